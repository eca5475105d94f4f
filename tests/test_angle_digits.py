"""Crank angles in the text carry no more decimals than the computation step resolves."""

from __future__ import annotations

import html
import math
import re

import pytest
from conftest import shared_html, shared_run

from crankdyn.report.i18n import translator

#: An in-line engine whose cylinder count divides no round angle: its cylinders' own crank
#: angles (720/7 deg apart) fall between whole degrees.
SEVEN = {"engine": {"cylinders": 7, "firing_order": None}, "analysis": {"angle_step_deg": None}}

#: "α = 30°", "α 2 = 544.3°" (the subscript's tag taken out), "α = 0,9°": the number after α
#: (not after Δα, the step itself).
ALPHA = re.compile(r"(?<!Δ)α(?: ?\d{1,2})? = [−-]?(\d[\d\u202f ]*)(?:[.,](\d+))? ?°")


def _text(page: str) -> str:
    page = re.sub(r"<(script|style)\b.*?</\1>", " ", page, flags=re.S)
    return re.sub(r"\s+", " ", html.unescape(re.sub(r"<[^>]+>", " ", page)))


def _allowed_decimals(step_deg: float) -> int:
    return max(1, math.ceil(-math.log10(step_deg) - 1e-9))


@pytest.mark.parametrize("language", ["en", "uk"])
def test_crank_angles_of_a_seven_cylinder_engine_carry_the_step_decimals(language):
    step = shared_run("inline4-petrol", SEVEN).scene.analysis.angle_step_deg
    text = _text(shared_html("inline4-petrol", SEVEN, language).linked_html)
    found = ALPHA.findall(text)
    assert len(found) >= 8  # the worked check's seven cylinder angles at least
    # the cylinders' own angles lie between whole degrees: the check is not empty
    assert any(decimals for _, decimals in found)
    too_fine = [
        f"{whole}.{decimals}"
        for whole, decimals in found
        if len(decimals) > _allowed_decimals(step)
    ]
    assert not too_fine, too_fine


@pytest.mark.parametrize(
    ("angle", "step", "text"),
    [
        (544.2857142857, 1.0, "544,3"),
        (0.857143, 0.5, "0,9"),
        (623.0769, 0.25, "623,1"),
        (623.0769, 0.05, "623,08"),
        (180.0, 0.989011, "180"),
        (372.04, 0.05, "372,04"),
        (359.99, 1.0, "360"),
    ],
)
def test_a_crank_angle_is_printed_to_the_step(angle, step, text):
    assert translator("uk", ()).angle(angle, step) == text


@pytest.mark.parametrize(
    "value, shown",
    [
        (0.0099996, "0,01000"),  # rounding carries into the next decade: four digits, not five
        (9.99996, "10,00"),
        (-0.00099996, "−0,001000"),
        (0.012345, "0,01235"),
        (123.456, "123,5"),
    ],
)
def test_a_number_rounded_into_the_next_decade_keeps_its_significant_digits(value, shown):
    t = translator("uk")
    assert t.number(value, 4) == shown
    digits = re.sub(r"\D", "", shown).lstrip("0")
    assert len(digits) == 4


@pytest.mark.parametrize(
    "value, significant, shown",
    [
        (3e6, 4, "3·10⁶"),  # a power of ten keeps no padding zeros either
        (1.6e6, 4, "1,6·10⁶"),
        (-2.5e-7, 6, "−2,5·10⁻⁷"),
        (7.5, 6, "7,5"),
        (180.0, 6, "180"),
    ],
)
def test_a_number_like_percent_g_drops_its_padding_zeros(value, significant, shown):
    assert translator("uk").number_g(value, significant) == shown
