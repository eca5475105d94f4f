"""The list of symbols says where a letter with several meanings holds (document.symbol_list_html):
the sections and appendices of the stages the meaning belongs to, as numbered in this report."""

from __future__ import annotations

import re

from crankdyn.report.document import _places, symbol_list_html
from crankdyn.report.i18n import translator


def _rows(html: str) -> list[str]:
    return [re.sub(r"<[^>]+>", "", row) for row in re.findall(r'<p class="symbol-row">(.*?)</p>', html)]


def test_a_letter_with_several_meanings_names_the_sections_of_each_sectioned_meaning():
    t = translator("uk")
    places = {"forces": [("section", "5")], "bays": [("section", "9")], "balancing": [("section", "6")],
              "flywheel": [("section", "8")]}
    rows = _rows(symbol_list_html(["crank_speed", "side_specific", "harmonic_order", "irregularity"], t, "uk",
                                  places=places))
    assert rows[0] == "n – частота обертання колінчастого вала, хв⁻¹"  # holds throughout: no place
    assert rows[1] == "n – питома бокова сила, що притискає поршень до стінки циліндра (у розділах 5 і 9), МПа"
    assert rows[2] == "n – порядок гармоніки сили чи моменту (у розділі 6)"
    assert rows[3] == "δ – коефіцієнт нерівномірності обертання"  # the only δ of this list: no place


def test_a_meaning_of_the_appendices_and_a_stage_absent_from_the_report():
    t = translator("en")
    places = {"numerics": [("appendix", "A"), ("appendix", "B")]}
    rows = _rows(symbol_list_html(["series_term", "side_specific", "rod_specific", "shaft_angle"], t, "en",
                                  places=places))
    assert rows[0] == "k – number of a term of a series (in appendices A and B)"
    assert rows[1].startswith("n – specific side force pressing the piston against the cylinder wall, ")
    assert "(" not in rows[2]  # forces and bays are not in this report: nothing to point to


def test_the_places_are_read_from_the_report_headings():
    html = ('<section class="chapter" id="sec-forces" data-stage="forces">\n  <h2 id="x">5 Сили</h2>'
            '<section class="chapter appendix" id="sec-numerics" data-stage="numerics">\n'
            '  <h2 class="unnumbered">Додаток А<br><span>(довідковий)</span><br>Похибка</h2>')
    assert _places(html) == {"forces": [("section", "5")], "numerics": [("appendix", "А")]}
