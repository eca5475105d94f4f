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
