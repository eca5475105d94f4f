"""The shortcuts crankdyn.report.figures takes through matplotlib's drawing (further ticks copied
from the first, text layouts and tick updates remembered, the house style set key by key, new
axes loaded from a template) give the SVG and PDF bytes matplotlib's own way gives."""

import subprocess
import sys

import matplotlib
import numpy as np
import pytest
from matplotlib import _text_helpers
from matplotlib.axis import Axis
from matplotlib.backends import backend_pdf
from matplotlib.text import Text
from matplotlib.transforms import BboxBase

from crankdyn.report import figure_shortcuts, figures


def _drawn(to=figures.to_svg) -> bytes:
    """A figure that exercises ticks: shared and twin axes, a log axis with minor ticks, tick
    parameters changed after the first tick was made, rotated labels, mathtext, a legend."""
    fig, (top, bottom) = figures.new_figure(12, 10, nrows=2, sharex=True)
    angle = np.linspace(0.0, 720.0, 73)
    top.plot(angle, np.sin(np.radians(angle)) * 3e4, label=r"$p_{\rm g}$")
    top.plot(angle, np.cos(np.radians(angle)) * 2e4, label="second")
    top.tick_params(axis="y", labelsize=7, length=5, colors="0.3")
    top.legend(loc="upper right")
    twin = figures.twin_axes(top)
    twin.plot(angle, angle / 10.0, color="C2")
    bottom.semilogy(angle, 1.0 + angle**2)
    bottom.minorticks_on()
    figures.crank_angle_axis(bottom, 720.0, "α, °")
    for label in bottom.get_xticklabels():
        label.set_rotation(30)
    bottom.set_ylabel(r"$\omega^2$, с⁻²")
    # narrow: the tight layout narrows the axes so much that the x axis has fewer ticks after it
    narrow, ax = figures.new_figure(7, 5)
    ax.plot([0.0, 1.0], [0.0, 123456.0])
    ax.set_ylabel("a long label\nof two lines")
    ax.text(0.2, 5e4, "alike", rotation=45)  # laid out apart from the same text upright
    ax.text(0.6, 5e4, "alike")
    # axes of other kinds: polar, rows of unequal heights
    polar, round_ax = figures.new_figure(9, 9, subplot_kw={"projection": "polar"})
    round_ax.plot(np.radians(angle), 1.0 + np.sin(np.radians(angle)))
    ratios, (high, low) = figures.new_figure(
        16, 13, nrows=2, sharex=True, gridspec_kw={"height_ratios": [2, 1]}
    )
    high.plot(angle, angle)
    low.plot(angle, -angle)
    return to(fig) + to(narrow) + to(polar) + to(ratios)


@pytest.mark.parametrize("to", [figures.to_svg, figures.to_pdf], ids=["svg", "pdf"])
def test_the_shortcuts_draw_the_bytes_matplotlib_draws(monkeypatch, to):
    figures._copy_new_ticks()
    figures._remember_text_layouts()
    figures._remember_tick_updates()
    figures._text_layouts.clear()
    _drawn(figures.to_svg)  # an SVG's layouts remembered first: a PDF measures its own
    shortcut = _drawn(to)
    assert figures._text_layouts, "layouts were remembered"
    assert _drawn(to) == shortcut  # and drawn again from what was remembered
    for owner, name in (
        (Axis, "get_major_ticks"),
        (Axis, "get_minor_ticks"),
        (Axis, "_update_ticks"),
        (Text, "_get_layout"),
    ):
        monkeypatch.setattr(owner, name, getattr(owner, name).__wrapped__)
    _unwrap_figure_shortcuts(monkeypatch)
    for installer in ("_copy_new_ticks", "_remember_text_layouts", "_remember_tick_updates"):
        monkeypatch.setattr(figures, installer, lambda: None)  # to_svg would put them back
    monkeypatch.setattr(figures, "house_style", lambda: matplotlib.rc_context(figures.STYLE))
    monkeypatch.setattr(figures, "AXES_TEMPLATES", figures.AxesTemplates(kept=0))  # made afresh
    assert not hasattr(Axis.get_major_ticks, "__wrapped__")
    assert _drawn(to) == shortcut


def _unwrap_figure_shortcuts(monkeypatch) -> None:
    """matplotlib's own functions back in the places figure_shortcuts took."""
    figure_shortcuts.install()
    figure_shortcuts.install_pdf()
    assert BboxBase.union.crankdyn_shortcut
    monkeypatch.setattr(BboxBase, "union", staticmethod(BboxBase.union.__wrapped__))
    monkeypatch.setattr(Axis, "_get_ticklabel_bboxes", Axis._get_ticklabel_bboxes.__wrapped__)
    monkeypatch.setattr(backend_pdf, "_text_helpers", _text_helpers)
    monkeypatch.setattr(
        backend_pdf.RendererPdf, "_get_font_ttf", backend_pdf.RendererPdf._get_font_ttf.__wrapped__
    )
    monkeypatch.setattr(
        backend_pdf, "_get_pdf_charprocs", backend_pdf._get_pdf_charprocs.__wrapped__
    )
    for installer in ("install", "install_pdf"):  # to_svg and to_pdf would put them back
        monkeypatch.setattr(figure_shortcuts, installer, lambda: None)


def test_tick_labels_are_measured_once_while_their_axis_stays(monkeypatch):
    figure_shortcuts.install()
    fig = _one_axes()
    renderer = fig.canvas.get_renderer()
    axis = fig.axes[0].xaxis
    measured = []
    measure = Text.get_window_extent

    def counted(self, *args, **kwargs):
        measured.append(self)
        return measure(self, *args, **kwargs)

    monkeypatch.setattr(Text, "get_window_extent", counted)
    monkeypatch.setattr(figure_shortcuts.tick_label_boxes, "boxes", {}, raising=False)
    first = axis._get_ticklabel_bboxes(axis._update_ticks(), renderer)
    count = len(measured)
    assert count > 0
    again = axis._get_ticklabel_bboxes(axis._update_ticks(), renderer)
    assert len(measured) == count  # not measured again
    assert [box.bounds for box in again[0]] == [box.bounds for box in first[0]]
    assert again[0][0] is not first[0][0]  # boxes of its own, as matplotlib gives
    fig.axes[0].set_position([0.3, 0.3, 0.4, 0.4])  # the axes moved: measured anew
    moved = axis._get_ticklabel_bboxes(axis._update_ticks(), renderer)
    assert len(measured) > count
    assert moved[0][0].bounds != first[0][0].bounds
    figure_shortcuts.tick_label_boxes.boxes = None  # outside a drawing: measured every time
    axis._get_ticklabel_bboxes(axis._update_ticks(), renderer)
    assert len(measured) > count + len(moved[0])


def test_a_pdf_shapes_each_text_once_per_font_and_size():
    figure_shortcuts._text_runs.clear()
    first = figures.to_pdf(_one_axes())
    runs = dict(figure_shortcuts._text_runs)
    assert runs, "the PDF's texts were shaped through the memo"
    assert figures.to_pdf(_one_axes()) == first
    assert figure_shortcuts._text_runs.keys() == runs.keys()  # nothing shaped anew


def _one_axes():
    fig, ax = figures.new_figure(8, 6)
    ax.plot([0.0, 360.0], [-1.5e5, 2.5e5])
    ax.set_xlabel("φ, °")
    ax.set_ylabel("F, Н")
    return fig


def test_new_axes_come_from_a_template_made_with_the_same_rc_params(monkeypatch):
    templates = figures.AxesTemplates(kept=16)
    monkeypatch.setattr(figures, "AXES_TEMPLATES", templates)
    figures.new_figure(16, 9, nrows=3, sharex=True)
    figures.new_figure(12, 9, nrows=3, sharex=True)  # made twice: kept as a template
    assert templates.loaded == 0
    _, axes = figures.new_figure(10, 20, nrows=3, sharex=True)  # another size, the same kind
    assert templates.loaded == 1
    assert axes[0].get_shared_x_axes().joined(axes[0], axes[2])
    assert axes[0].figure is axes[2].figure and axes[0].figure.get_size_inches()[1] == 20 / 2.54
    with matplotlib.rc_context({"axes.edgecolor": "red", "xtick.major.size": 9.0}):
        for _ in range(3):
            _, red = figures.new_figure(10, 20, nrows=3, sharex=True)
    assert templates.loaded == 2  # another template for other rcParams
    assert red[0].spines["left"].get_edgecolor() == (1.0, 0.0, 0.0, 1.0)
    assert red[0].xaxis.get_major_ticks()[0].tick1line.get_markersize() == 9.0
    _, black = figures.new_figure(10, 20, nrows=3, sharex=True)
    assert templates.loaded == 3
    assert black[0].spines["left"].get_edgecolor() != (1.0, 0.0, 0.0, 1.0)
    figures.new_figure(10, 20, ncols=2)  # a kind made once is no template
    assert templates.loaded == 3


def test_a_copied_tick_shares_no_state_matplotlib_changes_in_place():
    figures._copy_new_ticks()
    fig, ax = figures.new_figure(8, 6)
    first, second = ax.xaxis.get_major_ticks(2)
    for name in ("label1", "label2", "tick1line", "gridline"):
        ours, theirs = getattr(first, name), getattr(second, name)
        assert ours is not theirs and ours._callbacks is not theirs._callbacks
    second.label1.set_fontsize(20)
    assert first.label1.get_fontsize() != 20
    assert second.label1.get_text() == ""  # a new tick's label is empty until it is placed


def test_the_house_style_sets_what_rc_context_sets_and_gives_back_what_was_there():
    params = matplotlib.rcParams
    before = dict(params)
    with matplotlib.rc_context(figures.STYLE):
        expected = {key: params[key] for key in figures.STYLE}
    with figures.house_style():
        assert {key: params[key] for key in figures.STYLE} == expected
        assert params["font.size"] == figures.STYLE["font.size"]
    assert dict(params) == before


def test_an_svg_drawing_leaves_the_pdf_backend_unimported():
    code = (
        "import sys\n"
        "from crankdyn.report import figures\n"
        "fig, ax = figures.new_figure(8, 6)\n"
        "ax.plot([0, 1], [0, 1])\n"
        "figures.to_svg(fig)\n"
        "assert 'matplotlib.backends.backend_pdf' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
