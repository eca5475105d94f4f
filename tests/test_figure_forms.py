"""The printed report's figures as matplotlib's own PDF pages stamped where the layout put an
empty image of their size (crankdyn.report.figure_forms): the same place and size as WeasyPrint
draws the figure's SVG, its text searchable, the layout the same."""

from __future__ import annotations

import io
import shutil
import subprocess

import numpy as np
import pytest

from crankdyn.report import figure_forms
from crankdyn.report import pdf as pdf_module
from crankdyn.report.context import FigureFile
from crankdyn.report.figures import new_figure, to_pdf
from crankdyn.report.pdf import html_to_pdf

pikepdf = pytest.importorskip("pikepdf")
pytestmark = pytest.mark.skipif(
    shutil.which("pdftoppm") is None or shutil.which("pdftotext") is None,
    reason="poppler-utils not installed (bash .ci/setup.sh installs it)",
)

PAGE = (
    "<style>@page { size: A5; margin: 20mm 15mm 25mm 30mm } img { width: 60% }</style>"
    "<p>Before the figure, a paragraph of text.</p>"
    '<figure><img src="figures/fig_1.svg"></figure><p>After the figure.</p>'
)


def _block_figure():
    """A figure that is one black block over its whole canvas, and a label."""
    fig, axes = new_figure(8, 5)
    fig.patch.set_facecolor("black")
    axes.set_axis_off()
    axes.text(0.5, 0.5, "Кут повороту", color="white", ha="center", transform=axes.transAxes)
    return fig


def _dark_box(pdf: bytes, tmp_path, name: str) -> tuple[int, int, int, int]:
    """The pixel box (left, top, right, bottom) of the black block on the PDF's first page, 100 dpi."""
    from PIL import Image

    (tmp_path / f"{name}.pdf").write_bytes(pdf)
    subprocess.run(
        ["pdftoppm", "-r", "100", "-gray", "-png", "-singlefile", "-f", "1", "-l", "1"]
        + [str(tmp_path / f"{name}.pdf"), str(tmp_path / name)],
        check=True,
    )
    dark = np.asarray(Image.open(tmp_path / f"{name}.png").convert("L")) < 40
    # the block, not the text: rows and columns with more dark pixels than a line of text has
    rows, columns = np.nonzero(dark.sum(axis=1) > 100)[0], np.nonzero(dark.sum(axis=0) > 60)[0]
    return columns.min(), rows.min(), columns.max(), rows.max()


def _matplotlib_fonts(pdf: bytes) -> int:
    """How many Type 3 fonts the PDF has: matplotlib's figure pages bring them, WeasyPrint's
    text has none."""
    with pikepdf.open(io.BytesIO(pdf)) as document:
        return sum(
            isinstance(item, pikepdf.Dictionary) and item.get("/Subtype") == "/Type3"
            for item in document.objects
        )


def test_a_stamped_figure_takes_the_place_and_size_weasyprint_draws_its_svg_in(
    tmp_path, monkeypatch
):
    stamped = html_to_pdf(PAGE, [FigureFile("fig_1.svg", build=_block_figure)])
    monkeypatch.setattr(figure_forms, "available", lambda: False)  # WeasyPrint draws the SVG
    drawn = html_to_pdf(PAGE, [FigureFile("fig_1.svg", build=_block_figure)])
    assert _matplotlib_fonts(stamped) and not _matplotlib_fonts(drawn)  # matplotlib's page
    box, expected = _dark_box(stamped, tmp_path, "stamped"), _dark_box(drawn, tmp_path, "drawn")
    assert np.allclose(box, expected, atol=1)  # the same place and size, to a pixel at 100 dpi


def test_the_text_of_a_stamped_figure_is_searchable(tmp_path):
    pdf = html_to_pdf(PAGE, [FigureFile("fig_1.svg", build=_block_figure)])
    (tmp_path / "page.pdf").write_bytes(pdf)
    text = subprocess.run(
        ["pdftotext", str(tmp_path / "page.pdf"), "-"], capture_output=True, text=True, check=True
    ).stdout
    assert "Кут повороту" in text and "After the figure." in text


def test_a_placeholder_has_the_size_of_the_figures_page():
    pdf = to_pdf(_block_figure())
    with pikepdf.open(io.BytesIO(pdf)) as document:
        box = [float(v) for v in document.pages[0].mediabox]
    assert figure_forms.page_size_pt(pdf) == pytest.approx((box[2], box[3]))
    assert box[2] == pytest.approx(8 / 2.54 * 72) and box[3] == pytest.approx(5 / 2.54 * 72)
    svg = figure_forms.placeholder_svg(pdf).decode()
    assert f'width="{box[2]}pt"' in svg and f'viewBox="0 0 {box[2]} {box[3]}"' in svg
    assert "<path" not in svg and "<text" not in svg  # it draws nothing


def test_a_figure_given_only_as_svg_is_drawn_by_weasyprint(monkeypatch):
    svg = (
        b'<svg xmlns="http://www.w3.org/2000/svg" width="100pt" height="50pt">'
        b'<text x="5" y="30">only an svg</text></svg>'
    )
    figure = FigureFile("fig_1.svg", svg=svg)
    assert figure.pdf is None
    stamped: list = []
    monkeypatch.setattr(
        figure_forms, "stamp", lambda pdf, where, forms: stamped.append(where) or pdf
    )
    pdf = pdf_module.html_to_pdf(PAGE, [figure])
    assert stamped == [[]] and pdf.startswith(b"%PDF")


def test_a_figure_whose_place_is_not_found_is_drawn_by_weasyprint_instead(tmp_path, monkeypatch):
    expected = _dark_box(
        html_to_pdf(PAGE, [FigureFile("fig_1.svg", build=_block_figure)]), tmp_path, "placed"
    )
    monkeypatch.setattr(figure_forms, "placements", lambda document, forms, base: [])
    pdf = html_to_pdf(PAGE, [FigureFile("fig_1.svg", build=_block_figure)])
    assert not _matplotlib_fonts(pdf)  # WeasyPrint drew the SVG
    assert np.allclose(_dark_box(pdf, tmp_path, "drawn"), expected, atol=1)  # the figure is there


def test_a_figure_that_cannot_be_drawn_as_a_pdf_page_is_printed_from_its_svg(tmp_path):
    class NoPage(FigureFile):
        def draw_pdf(self) -> bytes:
            raise RuntimeError("this artist has no PDF drawing")

    pdf = html_to_pdf(PAGE, [NoPage("fig_1.svg", build=_block_figure)])
    assert np.allclose(
        _dark_box(pdf, tmp_path, "svg"),
        _dark_box(html_to_pdf(PAGE, [FigureFile("fig_1.svg", build=_block_figure)]), tmp_path, "p"),
        atol=1,
    )


def test_a_figures_svg_is_the_same_whether_its_pdf_page_was_drawn_first():
    from crankdyn.report.figures import to_svg

    def figure():
        fig, axes = new_figure(8, 5, nrows=2, sharex=True)
        for ax, scale in zip(axes, (1.0, 12345.6), strict=True):
            ax.plot([0.0, 360.0], [0.0, scale])
            ax.set_ylabel(r"$p_{\mathrm{г}}$, МПа")
        return fig

    printed_first = figure()
    to_pdf(printed_first)
    assert to_svg(printed_first) == to_svg(figure())
