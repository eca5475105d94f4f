"""Angles listed in a sentence (the firing intervals): each with its degree sign, joined as the
language lists things (CLDR), equal ones once, a repeating list as its pattern taken in turn."""

from __future__ import annotations

import pytest

from crankdyn.report.i18n import translator


@pytest.mark.parametrize(
    ("language", "values", "said"),
    [
        ("uk", [450, 270], "450° і 270°"),
        ("ru", [450, 270], "450° и 270°"),
        ("en", [405, 315], "405° and 315°"),
        ("uk", [180, 180, 180, 180], "180°"),  # even firing: one interval
        ("uk", [90, 150, 90, 150, 90, 150], "по черзі 90° і 150°"),  # odd-fire V6
        ("ru", [90, 150, 90, 150, 90, 150], "поочерёдно 90° и 150°"),
        ("en", [180, 540, 180, 540], "alternately 180° and 540°"),
        ("uk", [120, 150, 90, 120, 150, 90], "по черзі 120°, 150° і 90°"),
        ("uk", [100, 120, 140, 360], "100°, 120°, 140° і 360°"),  # no repetition
        ("uk", [80.25, 79.75], "80,25° і 79,75°"),
    ],
)
def test_angles_are_listed_as_the_language_lists_them(language, values, said):
    assert translator(language).degrees_and(values) == said


def test_no_angles_are_no_text():
    assert translator("uk").degrees_and([]) == ""
