"""The printed note leaves no page more than half empty before a figure or a table that a little
less room would have fitted there: a short table is not glued to the figure after it, and a figure
a fifth lower at most fits at the foot of the page before (templates/report.css,
crankdyn.report.page_fit)."""

from __future__ import annotations

import subprocess

import pytest

from crankdyn.report import page_fit
from crankdyn.report.context import FigureFile
from crankdyn.report.document import report_css
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


@pytest.mark.parametrize(
    "filler_mm, figure_mm, name, same_page",
    [
        # page 1 half empty; the figure block ~25 mm more than its image: 15 % lower, it fits
        (120.0, 125.0, "fig_1_2_curves.svg", True),
        # the same figure drawn to scale keeps its size
        (120.0, 125.0, "fig_3_1_scheme.svg", False),
        # it would have to be a third lower: it goes over
        (120.0, 170.0, "fig_1_2_curves.svg", False),
        # page 1 more than half full: a page's foot is not worth a smaller figure
        (140.0, 100.0, "fig_1_2_curves.svg", False),
    ],
)
def test_a_figure_a_little_lower_rather_than_a_half_empty_page(
    tmp_path, filler_mm, figure_mm, name, same_page
):
    figures = [FigureFile("filler.svg", _svg(filler_mm)), FigureFile(name, _svg(figure_mm))]
    pages = _pages(_figure(name), figures, tmp_path)
    assert _page_of(pages, "CAPTIONMARK") == (0 if same_page else 1)
    # (the cases' premise: laid out as drawn, the figure does not fit after the filler)
    assert filler_mm + figure_mm + 20.0 > TEXT_HEIGHT_MM


def test_the_figures_made_lower_are_at_most_a_fifth_lower(tmp_path):
    """The greatest height given is the image's as laid out less at most AT_MOST of it, and only
    for a figure that begins a page after a page less than half full."""
    from crankdyn.report.pdf import _asset_root, _fetcher, figure_urls
    from crankdyn.report.weasy import load_weasyprint

    figures = [
        FigureFile("filler.svg", _svg(120.0)),
        FigureFile("fig_1_2_curves.svg", _svg(125.0)),
    ]
    html = (
        f"<html><head><style>{report_css('en')}</style></head><body>"
        f'<p><img alt="" src="figures/filler.svg"></p>{_figure("fig_1_2_curves.svg")}'
        "</body></html>"
    )
    base = _asset_root().as_uri() + "/"
    document = (
        load_weasyprint()
        .HTML(string=html, base_url=base, url_fetcher=_fetcher(figure_urls(figures, base)))
        .render()
    )
    heights = page_fit.smaller_figures(document)
    assert list(heights) == ["figures/fig_1_2_curves.svg"]
    laid_out_px = 125.0 * 96 / 25.4
    assert (1 - page_fit.AT_MOST) * laid_out_px <= heights["figures/fig_1_2_curves.svg"]
    assert heights["figures/fig_1_2_curves.svg"] < laid_out_px
    style = page_fit.fitting_style(heights)
    assert 'figure img[src="figures/fig_1_2_curves.svg"]' in style and "max-height" in style


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
