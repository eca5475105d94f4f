"""Figure SVGs with presentation attributes instead of style attributes
(crankdyn.report.figures.presentation_attributes): what changes in the text, and that a
renderer draws the same pixels."""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest

from crankdyn.report.figures import new_figure, presentation_attributes, to_svg


def _matplotlib_svg() -> str:
    """A figure with what the report's figures use: grid lines (square caps), a dashed curve,
    a legend, mathtext and Cyrillic labels."""
    import matplotlib

    fig, axes = new_figure(8, 5)
    axes.plot([0, 90, 180], [0.0, 1.0, 0.2], label="a")
    axes.plot([0, 90, 180], [0.5, 0.1, 0.9], ls="--", lw=2.5, label="b")
    axes.set_xlabel(r"$p_{\mathrm{г}}$, МПа")
    axes.legend()
    axes.grid(True)
    buffer = __import__("io").StringIO()
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "t"}):
        fig.savefig(buffer, format="svg", metadata={"Date": None})
    return buffer.getvalue()


def test_styles_become_attributes_and_the_stylesheet_the_root_defaults():
    raw = _matplotlib_svg()
    assert ' style="' in raw and "<style" in raw  # what matplotlib writes
    lean = presentation_attributes(raw)
    assert "<style" not in lean and ' style="' not in lean
    assert re.search(r'<svg [^>]*stroke-linejoin="round" stroke-linecap="butt"', lean)
    assert 'stroke-linecap="square"' in lean  # the grid's own cap outranks the root's
    assert 'stroke-dasharray="' in lean and 'font-family="' in lean
    assert len(re.findall(r"<(?:path|use|text|tspan)\b", lean)) == len(
        re.findall(r"<(?:path|use|text|tspan)\b", raw)
    )


def test_other_properties_stay_in_style_and_other_stylesheets_are_left_alone():
    sheet = '<style type="text/css">*{stroke-linejoin: round; stroke-linecap: butt}</style>'
    svg = f'<svg width="1pt"><defs>{sheet}</defs><text style="white-space: pre; fill: #000">a b</text></svg>'
    assert presentation_attributes(svg) == (
        '<svg stroke-linejoin="round" stroke-linecap="butt" width="1pt"><defs>'
        '</defs><text fill="#000" style="white-space: pre">a b</text></svg>'
    )
    other = svg.replace("</defs>", "<style>path{fill: red}</style></defs>")
    assert presentation_attributes(other) == other


def test_the_report_figures_are_written_with_attributes():
    fig, axes = new_figure(6, 4)
    axes.plot([0.0, 1.0], [0.0, 1.0])
    svg = to_svg(fig).decode("utf-8")
    assert "<style" not in svg and ' style="' not in svg


@pytest.mark.skipif(
    shutil.which("pdftoppm") is None,
    reason="poppler-utils not installed (bash .ci/setup.sh installs it)",
)
def test_the_same_pixels_before_and_after(tmp_path):
    from PIL import Image

    from crankdyn.report.pdf import html_to_pdf

    raw = _matplotlib_svg()
    pixels = []
    for name, svg in (("raw", raw), ("lean", presentation_attributes(raw))):
        html = f'<img src="data:image/svg+xml;base64,{__import__("base64").b64encode(svg.encode()).decode()}">'
        (tmp_path / f"{name}.pdf").write_bytes(html_to_pdf(html))
        subprocess.run(
            [
                "pdftoppm",
                "-r",
                "150",
                "-gray",
                "-png",
                "-singlefile",
                str(tmp_path / f"{name}.pdf"),
                str(tmp_path / name),
            ],
            check=True,
        )
        pixels.append(np.asarray(Image.open(tmp_path / f"{name}.png"), dtype=int))
    assert pixels[0].shape == pixels[1].shape and pixels[0].min() < 128  # something was drawn
    assert np.array_equal(pixels[0], pixels[1])


def _pixels(svg: str, tmp_path, name: str):
    """``svg`` drawn by the report's PDF renderer and rasterised (grey, 150 dpi)."""
    import base64

    from PIL import Image

    from crankdyn.report.pdf import html_to_pdf

    html = f'<img src="data:image/svg+xml;base64,{base64.b64encode(svg.encode()).decode()}">'
    (tmp_path / f"{name}.pdf").write_bytes(html_to_pdf(html))
    subprocess.run(
        ["pdftoppm", "-r", "150", "-gray", "-png", "-singlefile"]
        + [str(tmp_path / f"{name}.pdf"), str(tmp_path / name)],
        check=True,
    )
    return np.asarray(Image.open(tmp_path / f"{name}.png"), dtype=int)


def _labelled_figure():
    fig, axes = new_figure(8, 5)
    axes.plot([0, 90, 180], [0.0, 1.0, 0.2], label="a")
    axes.plot([0, 90, 180], [0.5, 0.1, 0.9], ls="--", gid="named-curve", label="b")
    axes.set_xlabel(r"$p_{\mathrm{г}}$, МПа")
    axes.text(90, 0.5, "rotated", rotation=30)
    axes.legend()
    axes.grid(True)
    return fig


def test_a_figure_svg_keeps_only_the_groups_a_drawing_named():
    svg = to_svg(_labelled_figure()).decode("utf-8")
    assert '<g id="named-curve"' in svg  # an artist's own gid keeps its group
    assert not re.search(r'<g id="(xtick|line2d|text|patch|axes|figure|legend)_\d+"', svg)
    assert "rotate(-0 " not in svg and "rotate(-30)" in svg  # only a real rotation is written


@pytest.mark.skipif(
    shutil.which("pdftoppm") is None,
    reason="poppler-utils not installed (bash .ci/setup.sh installs it)",
)
def test_a_lean_figure_draws_the_pixels_of_matplotlibs_own_svg(tmp_path):
    import io

    import matplotlib

    from crankdyn.report.figures import house_style

    fig = _labelled_figure()
    lean = to_svg(fig).decode("utf-8")  # laid out here; matplotlib's own writer draws that layout
    buffer = io.StringIO()
    with house_style(), matplotlib.rc_context({"svg.hashsalt": "crankdyn"}):
        fig.savefig(buffer, format="svg", dpi=72, metadata={"Date": None})
    full = presentation_attributes(buffer.getvalue())
    assert full.count("<g") > 2 * lean.count("<g")  # matplotlib's groups were left out
    before, after = _pixels(full, tmp_path, "full"), _pixels(lean, tmp_path, "lean")
    assert before.shape == after.shape and before.min() < 128  # something was drawn
    assert np.array_equal(before, after)
