"""The printed page's language, whose patterns hyphenate it: an English note with the US ones."""

from __future__ import annotations

import pyphen
from conftest import shared_html


def test_an_english_note_is_hyphenated_as_english_is_printed():
    """WeasyPrint hyphenates by the page's ``lang``; "en" takes the British patterns, which part
    "journ-als", "pos-it-ive" and "ap-plic-a-tion" (a supervisor marks them), "en-US" does not."""
    english = shared_html("petrol-1cyl", None, "en", ("kinematics",)).linked_html
    assert '<html lang="en-US">' in english
    assert pyphen.Pyphen(lang="en_US").inserted("journals") == "jour-nals"
    assert pyphen.Pyphen(lang="en_US").inserted("positive") == "pos-i-tive"
    ukrainian = shared_html("petrol-1cyl", None, "uk", ("kinematics",)).linked_html
    assert '<html lang="uk">' in ukrainian
