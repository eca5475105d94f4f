"""Figures drawn by forked processes (crankdyn.report.figures.draw_jobs): the same bytes as
drawn one by one, in the same order, and never a lost figure or a child left behind."""

from __future__ import annotations

import io
import os
import time

import pytest

from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.report import figure_memo
from crankdyn.report.context import draw_figures, start_drawing
from crankdyn.report.document import render_html
from crankdyn.report.figures import draw_jobs
from crankdyn.scene.model import load_scene

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="no fork() on this platform")


def _no_children_left() -> bool:
    try:
        os.waitpid(-1, os.WNOHANG)
    except ChildProcessError:
        return True
    return False


def _wait_for(condition, what: str, deadline_s: float = 60.0) -> None:
    """Poll ``condition`` until it holds; a generous deadline only turns a hang into a failure."""
    end = time.monotonic() + deadline_s
    while not condition():
        assert time.monotonic() < end, f"waited {deadline_s:g} s for {what}"
        time.sleep(0.01)


def test_jobs_are_shared_between_processes_and_come_back_in_order(tmp_path):
    parent = os.getpid()
    arrivals = tmp_path / "pids"

    def job(i):
        # each job waits until all three processes have taken one: the figures are shared, not
        # drawn by whichever process happens to start first
        with open(arrivals, "a", encoding="utf-8") as file:
            file.write(f"{os.getpid()}\n")
        _wait_for(
            lambda: len(set(arrivals.read_text(encoding="utf-8").split())) >= 3, "three processes"
        )
        return f"{i}:{os.getpid()}".encode()

    results = draw_jobs([lambda i=i: job(i) for i in range(9)], workers=3, allow_threads=True)
    assert [r.split(b":")[0] for r in results] == [str(i).encode() for i in range(9)]
    pids = {int(r.split(b":")[1]) for r in results}
    assert parent in pids and len(pids) >= 2  # this process and the children took figures
    assert _no_children_left()


def test_a_free_process_takes_the_next_job_while_another_draws_a_long_one(tmp_path):
    """Taken one by one, not in fixed shares: whoever draws the long first figure draws nothing
    else, the other process draws the rest meanwhile (a fixed half each made one wait for the other)."""

    done = tmp_path / "done"

    def job(i):
        if i == 0:  # the long figure: drawn until every other one is done
            _wait_for(
                lambda: done.exists() and len(done.read_bytes()) == 7, "the other seven figures"
            )
        else:
            with open(done, "ab") as file:
                file.write(b"x")
        return str(os.getpid()).encode()

    results = draw_jobs([lambda i=i: job(i) for i in range(8)], workers=2, allow_threads=True)
    assert results[0] not in results[1:] and len(set(results[1:])) == 1
    assert _no_children_left()


def test_a_child_that_fails_leaves_its_figures_to_this_process():
    parent = os.getpid()

    def job(i=0):
        if os.getpid() != parent:
            raise RuntimeError("a child's figure failed")
        return str(i).encode()

    results = draw_jobs([lambda i=i: job(i) for i in range(8)], workers=2, allow_threads=True)
    assert results == [str(i).encode() for i in range(8)]
    assert _no_children_left()


def test_a_failure_here_is_raised_and_no_child_is_left():
    def job():
        raise ValueError("broken figure")

    with pytest.raises(ValueError, match="broken figure"):
        draw_jobs([job] * 6, workers=2, allow_threads=True)
    assert _no_children_left()


def test_serial_when_told_or_when_too_few():
    parent = os.getpid()
    assert (
        draw_jobs([lambda: str(os.getpid()).encode()] * 6, workers=1) == [str(parent).encode()] * 6
    )
    assert (
        draw_jobs([lambda: str(os.getpid()).encode()] * 3, workers=4, allow_threads=True)
        == [str(parent).encode()] * 3
    )


def test_report_figures_drawn_in_parallel_are_the_serial_bytes(examples):
    registry = default_registry()
    result = run_scene(load_scene(examples / "kinematics-only.toml"), registry, None, ())
    serial = render_html(result, registry).figures
    parallel = render_html(result, registry).figures
    assert len(serial) >= 4 and not any(f.drawn for f in parallel)  # drawn only when asked for
    draw_figures(serial, workers=1)
    draw_figures(parallel, workers=2, allow_threads=True)
    assert [f.name for f in parallel] == [f.name for f in serial]
    assert [f.svg for f in parallel] == [f.svg for f in serial]
    assert all(b"<svg" in f.svg for f in serial)


def test_a_figure_drawn_by_a_child_is_typeset_here_when_asked(examples):
    # The Word export draws the matplotlib figures again (as PNG) in this process: their labels
    # must be typeset here too, even when a forked process drew the SVG.
    from matplotlib.text import Text

    registry = default_registry()
    result = run_scene(load_scene(examples / "kinematics-only.toml"), registry, None, ())
    figures = render_html(result, registry).figures
    # fixed shares, every figure drawn by a child (draw_figures's shared queue may leave a
    # loaded machine's child none)
    start_drawing(figures, workers=2)()

    def raw_labels(fig):
        return [
            t.get_text()
            for t in fig.findobj(Text)
            if "_" in t.get_text() and "$" not in t.get_text()
        ]

    assert all(f.drawn for f in figures)
    assert any(raw_labels(f.figure) for f in figures)  # the children typeset their copies, not ours
    for figure in figures:
        assert raw_labels(figure.typeset()) == []


def test_log_axis_labels_are_powers_of_ten_in_unicode_superscripts():
    # 10⁻³ as the tables write it: a real superscript, and plain text in the SVG (no mathtext
    # to typeset for every label; ×10⁶ offsets likewise)
    from crankdyn.report.figures import new_figure, to_svg
    from crankdyn.report.i18n import translator
    from crankdyn.report.typeset import typeset_figure

    fig, (log_axes, big_axes) = new_figure(12, 6, ncols=2)
    log_axes.loglog([1e-4, 1e-1], [1e-6, 1.0])
    big_axes.plot([0.0, 1.0], [2.0e6, 3.5e6])
    typeset_figure(fig, translator("uk", default_registry().catalogs))
    svg = to_svg(fig).decode("utf-8")
    assert "10⁻³" in svg and "10⁻⁶" in svg and "×10⁶" in svg
    assert "$" not in svg and "e-0" not in svg and "^" not in svg


def test_a_log_axis_of_everyday_numbers_is_labelled_with_plain_numbers():
    # not "2·10⁰, 5·10⁰, 10¹" on the error study's step axis, where 2, 5 and 10 are meant;
    # within 0,01…10 000 the labels are plain numbers in the report's locale, beyond it powers of ten
    from crankdyn.report.figures import new_figure, to_svg
    from crankdyn.report.i18n import translator
    from crankdyn.report.typeset import typeset_figure

    fig, (plain, powers) = new_figure(12, 6, ncols=2)
    plain.loglog([0.5, 30.0], [0.05, 2.0])
    powers.loglog([1e-4, 1e-1], [1e-6, 1.0])
    typeset_figure(fig, translator("uk", default_registry().catalogs))
    fig.canvas.draw()
    shown = [
        label.get_text()
        for axis in (plain.xaxis, plain.yaxis)
        for label in axis.get_ticklabels(minor=False) + axis.get_ticklabels(minor=True)
        if label.get_text()
    ]
    assert {"1", "10", "0,1", "2", "5"} <= set(shown), shown
    assert not any("10⁰" in x or "10¹" in x or "·10" in x for x in shown), shown
    svg = to_svg(fig).decode("utf-8")
    assert "10⁻³" in svg and "10⁻⁶" in svg  # the wide axis keeps its powers of ten


def test_a_log_axis_over_many_decades_has_no_minor_ticks():
    # eight unlabelled marks a decade over nine decades are a comb (and ~100 tick objects to
    # make); up to five decades the minor ticks stay
    from crankdyn.report.figures import new_figure, to_svg
    from crankdyn.report.i18n import translator
    from crankdyn.report.typeset import typeset_figure

    fig, (wide, narrow) = new_figure(16, 10, ncols=2)  # tall enough for a major tick every decade
    wide.loglog([0.03, 0.7], [1.2e-7, 30.0])  # x: 1.4 decades, y: 8.4 (matplotlib: 80 minor ticks)
    narrow.semilogy([0.0, 1.0], [1e-3, 10.0])  # 4 decades
    typeset_figure(fig, translator("uk", default_registry().catalogs))
    to_svg(fig)
    assert len(wide.yaxis.get_minorticklocs()) == 0 and len(wide.yaxis.minorTicks) <= 1
    assert len(wide.xaxis.get_minorticklocs()) > 0
    assert len(narrow.yaxis.get_minorticklocs()) > 0


def test_figures_drawn_while_the_next_sections_render_are_the_serial_bytes(examples):
    from crankdyn.report.figures import IncrementalDrawing

    registry = default_registry()
    result = run_scene(load_scene(examples / "kinematics-only.toml"), registry, None, ())
    serial = render_html(result, registry).figures
    draw_figures(serial, workers=1)
    drawing = IncrementalDrawing(workers=2)
    handed = []
    rendered = render_html(
        result,
        registry,
        figure_sink=lambda figures: (handed.append(list(figures)), drawing.add(figures)),
    )
    drawing.finish()
    assert [
        f for batch in handed for f in batch
    ] == rendered.figures  # every figure, section by section
    assert all(f.drawn for f in rendered.figures)
    assert [(f.name, f.svg) for f in rendered.figures] == [(f.name, f.svg) for f in serial]
    assert _no_children_left()


def test_figures_handed_out_are_waited_for_one_by_one_and_are_the_serial_bytes(examples):
    """The PDF's path: every figure given to children at once (IncrementalDrawing.hand_out), then
    read in document order while the children may still draw: each read waits for the child that
    draws it (never drawn twice here) and gives the serial bytes."""
    from crankdyn.report.figures import IncrementalDrawing

    registry = default_registry()
    result = run_scene(load_scene(examples / "kinematics-only.toml"), registry, None, ())
    serial = render_html(result, registry).figures
    draw_figures(serial, workers=1)
    drawing = IncrementalDrawing(workers=2)
    rendered = render_html(result, registry, figure_sink=drawing.add)
    drawing.hand_out()
    assert rendered.figures and all(f.drawn or "svg" in f.awaiting for f in rendered.figures)
    drawn_here = []
    for figure in rendered.figures:  # a figure drawn here would mean a second drawing
        figure.draw = lambda figure=figure: drawn_here.append(figure.name) or b""
    assert [(f.name, f.svg) for f in rendered.figures] == [(f.name, f.svg) for f in serial]
    assert drawn_here == [] and not any(f.awaiting for f in rendered.figures)
    drawing.finish()
    assert _no_children_left()


def test_svg_and_pdf_pages_handed_out_together_are_each_waited_for_from_its_own_child(examples):
    """A report to HTML and PDF: the SVGs and the PDF pages drawn by children of two drawings at
    once; reading a figure's SVG waits for its SVG child and its PDF page for its PDF child, and
    neither is drawn here."""
    from crankdyn.report.figures import IncrementalDrawing

    registry = default_registry()
    result = run_scene(load_scene(examples / "kinematics-only.toml"), registry, None, ())
    serial = render_html(result, registry).figures
    draw_figures(serial, workers=1)
    pages = [figure.pdf for figure in serial]
    svgs = IncrementalDrawing(workers=2)
    rendered = render_html(result, registry, figure_sink=svgs.add)
    printed = IncrementalDrawing(workers=2, kind="pdf")
    printed.add(rendered.figures)
    svgs.hand_out()
    printed.hand_out()
    drawn_here = []
    for figure in rendered.figures:
        figure.draw = lambda figure=figure: drawn_here.append(("svg", figure.name)) or b""
        figure.draw_pdf = lambda figure=figure: drawn_here.append(("pdf", figure.name)) or b""
    assert [f.pdf for f in rendered.figures] == pages
    assert [f.svg for f in rendered.figures] == [f.svg for f in serial]
    assert drawn_here == [] and not any(f.awaiting for f in rendered.figures)
    svgs.finish()
    printed.finish()
    assert _no_children_left()


# a whole PDF report: in the slow tier, which CI runs
@pytest.mark.slow
def test_a_report_to_pdf_draws_each_figure_once_and_leaves_no_child(examples, tmp_path):
    from crankdyn.output.pipeline import render_files

    registry = default_registry()
    result = run_scene(load_scene(examples / "kinematics-only.toml"), registry, None, ())
    files = render_files(result, registry, ["pdf", "html"], figure_workers=2)
    assert files["report.pdf"].startswith(b"%PDF")
    serial = render_html(result, registry).figures
    draw_figures(serial, workers=1)
    assert {f.name: f.svg for f in serial} == {
        name.removeprefix("figures/"): data
        for name, data in files.items()
        if name.startswith("figures/")
    }
    assert _no_children_left()


def test_a_label_is_typeset_once_per_process_not_once_per_figure():
    """Every figure's SVG renderer has a mathtext parser of its own; the shared cache
    (figures._keep_more_mathtext) typesets a label once for all of them, with the same result."""
    from matplotlib.mathtext import MathTextParser

    from crankdyn.report.figures import new_figure, to_svg

    def figure():
        fig, axes = new_figure(6, 4)
        axes.plot([0.0, 1.0], [0.0, 1.0])
        axes.set_xlabel(r"$q_{\mathrm{shared, once}}$, МПа")
        return to_svg(fig)

    first = figure()
    before = MathTextParser._parse_cached.cache_info()
    second = figure()
    after = MathTextParser._parse_cached.cache_info()
    assert after.misses == before.misses and after.hits > before.hits
    assert first == second


def test_the_locale_formatter_gives_the_same_labels_when_asked_again_for_the_same_ticks():
    from crankdyn.report.i18n import translator
    from crankdyn.report.typeset import locale_formatter, tick_labels

    t = translator("uk")
    formatter = locale_formatter(t)
    big, small = [0.0, 2e6, 4e6], [0.0, 0.5, 1.0]
    first = formatter.format_ticks(big)
    assert first == tick_labels(big, t)[0] and formatter.get_offset() == "×10⁶"
    first.append("changed by the caller")  # the remembered labels are not the caller's list
    assert formatter.format_ticks(small) == ["0,0", "0,5", "1,0"] and formatter.get_offset() == ""
    assert (
        formatter.format_ticks(big) == tick_labels(big, t)[0] and formatter.get_offset() == "×10⁶"
    )
    assert (
        formatter.format_ticks(big) == tick_labels(big, t)[0] and formatter.get_offset() == "×10⁶"
    )


def test_six_digit_ticks_are_written_in_full_not_with_an_offset():
    """A rod's angular acceleration of 60 000 rad/s² reads "60 000" on its axis, not "0,6" under a
    "×10⁵" at the axis end that a reader has to find."""
    from crankdyn.report.i18n import translator
    from crankdyn.report.typeset import tick_labels

    labels, scale = tick_labels([-100000.0, -50000.0, 0.0, 50000.0, 100000.0], translator("uk"))
    assert scale == 0 and labels[-1].replace("\u202f", " ").replace("\u00a0", " ") == "100 000"
    assert tick_labels([0.0, 1e6, 2e6], translator("uk"))[1] == 6


def test_an_outside_legend_takes_as_many_columns_as_fit_in_even_rows():
    """Four labels "main journal after crank 1" … in one row were wider than the 16 cm figure (the
    layout squeezed the plot into its right half): two rows of two; short labels keep one row."""
    from crankdyn.report.figures import new_figure
    from crankdyn.report.typeset import _legend_columns

    fig, ax = new_figure(16, 8)
    long = [f"корінна шийка за коліном {k}" for k in range(1, 5)]
    assert _legend_columns(ax, long, 8.0) == 2
    assert _legend_columns(ax, ["t", "z", "k", "n"], 8.0) == 4
    assert _legend_columns(ax, ["one label only"], 8.0) == 1


def test_a_figure_given_as_its_builder_is_built_once_where_it_is_drawn():
    from crankdyn.report.context import FigureFile
    from crankdyn.report.figures import new_figure, to_svg

    def build():
        calls.append(os.getpid())
        fig, ax = new_figure(8, 6)
        ax.plot([0, 1, 2], [1, 3, 2])
        return fig

    calls = []
    figure = FigureFile("fig_1_1_a.svg", build=build)
    assert calls == [] and not figure.drawn and figure.made_from(build)
    svg = figure.svg
    assert figure.svg == svg and calls == [os.getpid()]  # built once, for the first drawing
    assert figure.figure is figure.figure and len(calls) == 1
    assert svg == to_svg(build())  # the bytes of the same figure built and drawn at once


def test_the_report_process_renders_the_text_without_building_the_figures_given_as_builders(
    examples, monkeypatch
):
    """The built-in stages hand ctx.figure the function that builds each figure: rendering a
    report's text creates no axes in its process (they are created in the child that draws)."""
    monkeypatch.setattr(figure_memo, "_svgs", {})  # a process that drew no scheme before
    monkeypatch.setattr(figure_memo, "_values", {})
    registry = default_registry()
    result = run_scene(load_scene(examples / "petrol-1cyl.toml"), registry, None, ())
    figures = render_html(result, registry).figures
    # every figure but the scheme, whose scale (printed in its caption) is measured on the drawing
    assert [f.name for f in figures if f._figure is not None] == ["fig_3_1_scheme.svg"]
    assert len(figures) >= 16
    scheme = figures[[f.name for f in figures].index("fig_3_1_scheme.svg")]
    scheme.svg  # noqa: B018 - drawn here, in this process, for its side effect
    # a scheme this process drew already is taken with its scale: not built again
    again = render_html(result, registry).figures
    assert [f.name for f in again if f._figure is not None] == []
    assert again[[f.name for f in again].index("fig_3_1_scheme.svg")].svg == scheme.svg


def test_font_heights_remembered_by_the_svg_renderer_give_matplotlibs_own_bytes(monkeypatch):
    """The SVG renderer answers a text's line height from the font tables once per font and size
    (figures._remember_font_heights); a figure of one- and two-line texts, mathtext, two sizes
    and a Cyrillic label is byte for byte the one matplotlib lays out reading the tables itself."""
    from matplotlib.backends.backend_svg import RendererSVG

    from crankdyn.report import figures

    def drawn() -> bytes:
        fig, ax = figures.new_figure(8, 6)
        ax.plot([0, 1, 2], [0, 1e4, 3])
        ax.set_xlabel("Кут повороту колінчастого вала α, °")
        ax.set_ylabel(r"$p_{\rm г}$, МПа")
        ax.set_title("two\nlines", fontsize=12)
        ax.text(0.5, 0.5, "note", fontsize=7)
        return figures.to_svg(fig)

    figures._remember_font_heights()
    assert "_get_font_height_metrics" in RendererSVG.__dict__, "the hook is installed"
    remembered = drawn()
    monkeypatch.delattr(RendererSVG, "_get_font_height_metrics")
    monkeypatch.setattr(figures, "_remember_font_heights", lambda: None)  # to_svg would put it back
    assert not hasattr(RendererSVG, "_get_font_height_metrics")
    assert drawn() == remembered


def test_the_curves_of_one_axes_differ_by_dash_as_well_as_colour():
    """Two solid curves, blue and orange, read as one on a black-and-white copy. The
    figures' cycle gives each colour its own dash, so curves drawn without a style of their own differ
    in print too (the first stays solid)."""
    import matplotlib

    from crankdyn.report.figures import STYLE

    with matplotlib.rc_context(STYLE):
        cycle = list(matplotlib.rcParams["axes.prop_cycle"])
    dashes = [str(entry["linestyle"]) for entry in cycle]
    assert dashes[0] == "-" and len(set(dashes)) == len(dashes) >= 6
    assert len({entry["color"] for entry in cycle}) == len(cycle)


def test_a_mathtext_label_is_measured_by_the_typesetting_that_draws_it(monkeypatch):
    """figures._measure_math_as_drawn: the SVG renderer measures a mathtext label with the box of
    the typesetting it draws (matplotlib's own typesets it again at 100 pt for the measure). The
    box is that typesetting's, within a point of matplotlib's scaled measure (each typeset box is
    rounded up to whole points), and drawing a figure typesets no label at 100 pt."""
    import matplotlib
    from matplotlib.backends.backend_svg import RendererSVG
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextToPath

    from crankdyn.report import figures

    figures._measure_math_as_drawn()
    renderer = RendererSVG(100, 100, io.StringIO())
    label = r"$p_{\rm г} \cdot 10^{-3}$, МПа"
    with matplotlib.rc_context(figures.STYLE):
        for size_pt in (7.0, 9.0, 12.5):
            prop = FontProperties(size=size_pt)
            drawn = renderer._text2path.mathtext_parser.parse(label, 72, prop)
            measured = renderer.get_text_width_height_descent(label, prop, True)
            assert measured == (drawn.width, drawn.height, drawn.depth)
            scaled = TextToPath().get_text_width_height_descent(label, prop, True)
            assert all(
                0 <= ours - theirs <= 1.0 + 1e-9
                for ours, theirs in zip(measured, scaled, strict=True)
            ), (measured, scaled)
            plain = renderer.get_text_width_height_descent("МПа", prop, False)
            assert plain == TextToPath().get_text_width_height_descent(
                "МПа", prop, False
            )  # plain text: matplotlib's

    at_100_pt = []
    measure = TextToPath.get_text_width_height_descent
    monkeypatch.setattr(
        TextToPath,
        "get_text_width_height_descent",
        lambda self, s, prop, ismath: at_100_pt.append(s) or measure(self, s, prop, ismath),
    )
    fig, ax = figures.new_figure(8, 6)
    ax.set_ylabel(label)
    ax.set_title(r"$\omega_{\rm к}$ and plain text")
    figures.to_svg(fig)
    assert at_100_pt and not [s for s in at_100_pt if "$" in s]  # plain texts only
