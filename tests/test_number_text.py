"""Numbers in the report's languages: what Babel's CLDR formatting writes, with a narrow no-break
space between digit groups and "−" for minus."""

from __future__ import annotations

import random

import pytest
from babel import Locale
from babel.numbers import format_decimal, get_group_symbol

from crankdyn.report.i18n import MINUS, NARROW_NBSP, translator


def _babel(value: float, decimals: int, language: str) -> str:
    """Babel's own text of ``value`` to ``decimals`` decimals (the independent value)."""
    locale = Locale.parse(language)
    pattern = ("#,##0" if abs(value) >= 10000 else "0") + ("." + "0" * decimals if decimals else "")
    text = format_decimal(value, format=pattern, locale=locale)
    return text.replace(get_group_symbol(locale), NARROW_NBSP).replace("-", MINUS)


@pytest.mark.parametrize("language", ["en", "uk", "ru"])
def test_fixed_numbers_read_as_babel_writes_them(language):
    t = translator(language)
    generator = random.Random(7)
    values = [0.0, 9999.4, 9999.5, 10000.0, -10000.0, 123456789.125, -0.0004, 0.5, 2.5]
    values += [generator.choice((1, -1)) * 10 ** generator.uniform(-5, 9) for _ in range(3000)]
    for value in values:
        for decimals in (0, 1, 3, 5):
            rounded = float(f"{value:.{decimals}f}")
            expected = _babel(rounded if rounded else 0.0, decimals, language)
            assert t.fixed(value, decimals) == expected, (value, decimals)


def test_fixed_numbers_use_the_languages_symbols():
    assert translator("uk").fixed(-12345.678, 2) == f"{MINUS}12{NARROW_NBSP}345,68"
    assert translator("ru").fixed(1234.5, 1) == "1234,5"
    assert translator("en").fixed(12345.0, 0) == f"12{NARROW_NBSP}345"
    assert translator("en").fixed(-0.0001, 2) == "0.00"


@pytest.mark.parametrize("language", ["en", "uk", "ru"])
def test_grouped_numbers_split_four_digits_as_babel_does(language):
    """A table column that holds five-digit numbers splits its four-digit ones too (Babel's
    "#,##0" pattern for every number of a thousand and more); below a thousand nothing changes."""
    t = translator(language)
    generator = random.Random(11)
    values = [999.4, 999.5, 1000.0, -1234.5, 9999.5]
    values += [generator.choice((1, -1)) * 10 ** generator.uniform(-3, 6) for _ in range(2000)]
    for value in values:
        for decimals in (0, 2):
            rounded = float(f"{value:.{decimals}f}") or 0.0
            locale = Locale.parse(language)
            pattern = ("#,##0" if abs(rounded) >= 1000 else "0") + (".00" if decimals else "")
            expected = format_decimal(rounded, format=pattern, locale=locale)
            expected = expected.replace(get_group_symbol(locale), NARROW_NBSP).replace("-", MINUS)
            assert t.fixed(value, decimals, grouped=True) == expected, (value, decimals)


def test_a_table_column_with_five_digit_numbers_groups_its_four_digit_ones():
    from conftest import shared_run

    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.context import RenderContext
    from crankdyn.report.document import _environment

    registry = default_registry()
    t = translator("ru", registry.catalogs)
    ctx = RenderContext(
        t=t,
        env=_environment(registry, shared_run("petrol-1cyl")),
        table_step_deg=30.0,
        cycle_deg=720.0,
    )
    html = ctx.table(
        [("a", [25831.0, 7013.0, -6186.0, 412.0], 0), ("b", [7013.0, -6186.0, 412.0, 5.0], 0)],
        caption="x",
    )
    cells = [c.split("<")[0] for c in str(html).split("<td>")[1:]]
    assert cells[0::2] == [
        f"25{NARROW_NBSP}831",
        f"7{NARROW_NBSP}013",
        f"{MINUS}6{NARROW_NBSP}186",
        "412",
    ]
    assert cells[1::2] == ["7013", f"{MINUS}6186", "412", "5"]  # no five digits: as in the text
