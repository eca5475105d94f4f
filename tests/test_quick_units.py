"""The pint-free reader of common unit strings agrees with pint bit for bit, and defers otherwise."""

from __future__ import annotations

import random

import pytest

from crankdyn.scene import units
from crankdyn.scene.units import FACTORS, quick_quantity

MAGNITUDES = (
    ["82", "0.085", "1e5", "1.2e5", "7850", "0.45", ".5", "0.006", "1E-3", "-3", "+2.5", "100"]
    + [repr(random.Random(7).uniform(0, 1000)) for _ in range(5)]
    + [str(n) for n in random.Random(8).sample(range(1, 10**6), 5)]
)


def _pint(text: str, kind: str) -> float:
    return float(units._registry().Quantity(text).to(units.SI_UNIT[kind]).magnitude)


@pytest.mark.parametrize("kind", sorted(FACTORS))
def test_every_tabled_unit_gives_pints_value_exactly(kind):
    for unit in FACTORS[kind]:
        for magnitude in MAGNITUDES:
            for text in (f"{magnitude} {unit}", f"{magnitude}{unit}", f"  {magnitude}  {unit} "):
                assert quick_quantity(text, kind) == _pint(text, kind), text


@pytest.mark.parametrize(
    "text, kind",
    [
        ("82 kg", "length"),
        ("82 inch", "length"),
        ("82", "length"),
        ("mm", "length"),
        ("82 mm mm", "length"),
        ("1.2.3 mm", "length"),
        ("82 MPA", "pressure"),
        ("0.45 lb", "mass"),
        ("1e999 mm", "length"),
    ],
)
def test_anything_else_is_left_to_pint(text, kind):
    assert quick_quantity(text, kind) is None


def test_parse_quantity_uses_the_table_and_still_words_errors():
    assert units.parse_quantity("82 mm", "length") == _pint("82 mm", "length")
    assert units.parse_quantity("3.25 inch", "length") == pytest.approx(0.08255)  # pint's path
    with pytest.raises(ValueError, match="not a length"):
        units.parse_quantity("82 kg", "length")
