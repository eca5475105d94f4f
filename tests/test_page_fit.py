"""The printed note leaves no page more than half empty before a short table: its last row does not
glue it to the figure after it (templates/report.css)."""

from __future__ import annotations

import subprocess

from crankdyn.report.assets import report_css
from crankdyn.report.context import FigureFile
from crankdyn.report.pdf import html_to_pdf

#: The text height of an A4 page in templates/report.css (297 mm less margins of 20 and 20 mm).
TEXT_HEIGHT_MM = 257.0


def _svg(height_mm: float, width_mm: float = 160.0) -> bytes:
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width_mm}mm" height="{height_mm}mm" '
        f'viewBox="0 0 {width_mm} {height_mm}"><rect width="{width_mm}" height="{height_mm}" '
        'fill="none" stroke="black"/></svg>'
    ).encode()


def _figure(name: str) -> str:
    return (
        '<div class="figure-block"><p class="see">The curves are shown in figure 1.2.</p>'
        f'<figure data-number="1.2"><img alt="" src="figures/{name}">'
        "<figcaption>Figure 1.2 – CAPTIONMARK</figcaption></figure></div>"
    )


def _table() -> str:
    return (
        '<div class="table-block"><p class="see">The values are given in table 1.1.</p>'
        '<table class="data" data-number="1.1"><caption>Table 1.1 – Values</caption>'
        "<thead><tr><th>a</th><th>b</th></tr></thead>"
        "<tbody><tr><td>TABLEMARK</td><td>1</td></tr></tbody></table></div>"
    )


def _pages(body: str, figures: list[FigureFile], tmp_path) -> list[str]:
    """The text of each page of the PDF of ``body`` printed with the note's style."""
    html = (
        f"<html><head><style>{report_css('en')}</style></head><body>"
        f'<p><img alt="" src="figures/filler.svg"></p>{body}</body></html>'
    )
    pdf = tmp_path / "note.pdf"
    pdf.write_bytes(html_to_pdf(html, figures))
    text = subprocess.run(
        ["pdftotext", str(pdf), "-"], capture_output=True, text=True, check=True
    ).stdout
    return text.split("\f")[:-1]


def _page_of(pages: list[str], mark: str) -> int:
    return next(k for k, page in enumerate(pages) if mark in page)


def test_a_short_table_stays_on_its_page_when_the_figure_after_it_goes_over(tmp_path):
    """The rule keeping a table's first rows together never applies to its last row: carried to
    the table's end it would glue a one-row table to the figure after it, and both would leave
    half a page empty."""
    figures = [
        FigureFile("filler.svg", _svg(80.0)),
        FigureFile("fig_1_2_curves.svg", _svg(170.0)),
    ]
    pages = _pages(_table() + _figure("fig_1_2_curves.svg"), figures, tmp_path)
    assert _page_of(pages, "TABLEMARK") == 0
    assert _page_of(pages, "CAPTIONMARK") == 1
