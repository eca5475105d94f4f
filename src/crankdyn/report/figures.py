"""matplotlib figures as SVG bytes, in the report's house style.

Text stays text (``svg.fonttype = none``: searchable, selectable, in the report's fonts); each
figure is laid out and drawn by one SVG renderer, its styles written as presentation attributes;
figures are drawn by forked children while the report goes on (:class:`IncrementalDrawing`).
"""

from __future__ import annotations

import contextlib
import copy
import functools
import io
import os
import pickle
import re
import select
import struct
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..engine.frozen_heap import freeze_more
from ..parallel.fork import can_fork as _no_other_thread
from ..parallel.fork import fork_with_pipe
from . import figure_shortcuts, mathtext_store

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.typing import RcKeyType

# matplotlib is imported only when a figure is drawn (lazy: heavy optional import), and never
# through pyplot: each figure is a plain ``Figure`` on its own Agg canvas, so a JSON-only run
# pays nothing for plotting and no global figure state builds up between reports.


STYLE: dict[RcKeyType, Any] = {
    "svg.fonttype": "none",  # text stays text: searchable in the PDF (fonts: the report's, below)
    "pdf.fonttype": 3,  # a figure PDF's text in fonts matplotlib subsets itself (no fontTools: fast)
    "font.family": "DejaVu Sans",
    "font.size": 9,
    "axes.grid": True,
    "grid.alpha": 0.35,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.linewidth": 1.4,
    # each colour with its own dash: the curves of one axes stay apart in black-and-white print
    # (two solid lines, blue and orange, read as one on a grey copy)
    # (matplotlib reads the cycle from this text as from its matplotlibrc)
    "axes.prop_cycle": "cycler(color=['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2',"
    " '#7f7f7f']) + cycler(linestyle=['-', '--', '-.', ':', (0, (6, 2, 1, 2, 1, 2)), (0, (8, 3)),"
    " (0, (1, 3)), (0, (4, 1, 1, 1))])",
    # 72 = the SVG's own resolution: the layout pass (Agg) and the SVG pass then share
    # matplotlib's mathtext cache (keyed by dpi) instead of typesetting every label twice
    "figure.dpi": 72,
    "svg.hashsalt": "crankdyn",  # stable ids: the same scene gives the same bytes
}


@functools.cache
def _validated_style() -> dict:
    """:data:`STYLE` as matplotlib's validators store it (the cycler parsed), validated once."""
    import matplotlib  # lazy: heavy optional import

    validated = matplotlib.RcParams(STYLE)
    return {key: validated._get(key) for key in STYLE}


@contextlib.contextmanager
def house_style() -> Iterator[None]:
    """``matplotlib.rc_context(STYLE)`` for the figures' own code, which sets no other rcParams:
    only the keys of :data:`STYLE` are set and given back. ``rc_context`` copies and restores
    all three hundred rcParams and validates the style again (the colour cycle parsed from its
    text) each time: 0.6 ms, some 80 times a report."""
    import matplotlib  # lazy: heavy optional import

    params = matplotlib.rcParams
    style = _validated_style()
    before = {key: params._get(key) for key in style}
    params._update_raw(style)
    try:
        yield
    finally:
        params._update_raw(before)


#: Typeset mathtext strings kept per process. matplotlib keeps 50 per parser, and each renderer
#: has a parser of its own (every figure's SVG renderer makes a new one): a label would be
#: typeset again for every figure, and for every report of a batch or save of the preview
#: (pyparsing: ~5 ms a label).
MATHTEXT_CACHE = 4096


def _keep_more_mathtext() -> None:
    """One mathtext cache per process, shared by all parsers of an output type (a parser holds no
    state but that type: its grammar is shared by the class), holding :data:`MATHTEXT_CACHE`."""
    from matplotlib.mathtext import MathTextParser  # lazy: heavy optional import

    parse = MathTextParser._parse_cached  # type: ignore[attr-defined]  # matplotlib's private cache
    if getattr(parse, "crankdyn_shared", False) or not hasattr(parse, "__wrapped__"):
        return
    typeset = parse.__wrapped__
    parsers: dict = {}  # output type -> the first parser of that type (any would do)

    @functools.lru_cache(MATHTEXT_CACHE)
    def shared(output_type, s, dpi, prop, antialiased, load_glyph_flags):
        if output_type != "vector":  # a raster (the Word export's PNG) is not stored
            return typeset(parsers[output_type], s, dpi, prop, antialiased, load_glyph_flags)
        try:
            stored = mathtext_store.store()
            key = stored.key(s, dpi, prop, load_glyph_flags)
            parse = stored.get(key)
        except Exception:  # noqa: BLE001 - the store is an aid: without it the label is typeset
            stored = parse = None
        if parse is None:
            parse = typeset(parsers[output_type], s, dpi, prop, antialiased, load_glyph_flags)
            if stored is not None:
                try:
                    stored.put(key, parse)
                except Exception:  # noqa: BLE001 - not kept; the next run typesets it again
                    pass
        return parse

    def _parse_cached(self, s, dpi, prop, antialiased, load_glyph_flags):
        parsers.setdefault(self._output_type, self)
        return shared(self._output_type, s, dpi, prop, antialiased, load_glyph_flags)

    _parse_cached.crankdyn_shared = True  # type: ignore[attr-defined]  # marks the replacement
    _parse_cached.cache_info = shared.cache_info  # type: ignore[attr-defined]  # as lru_cache's
    MathTextParser._parse_cached = _parse_cached  # type: ignore[attr-defined]  # matplotlib's private cache


#: The font tables :meth:`matplotlib.text.Text._get_layout` reads for a text's line height,
#: in order (its own list: the first table the font has gives ascent, descent and line gap).
_HEIGHT_TABLES = (
    ("OS/2", "sTypoLineGap", "sTypoAscender", "sTypoDescender"),
    ("hhea", "lineGap", "ascent", "descent"),
)


@functools.lru_cache(maxsize=256)
def _font_height_metrics(font_files: tuple[str, ...], size_pt: float, dpi: float) -> tuple:
    """(ascent, descent, line gap) in pixels of the first of ``font_files`` at ``size_pt``, as
    ``Text._get_layout`` works them out from the font's tables for every text it lays out."""
    from matplotlib.font_manager import get_font  # lazy: heavy optional import

    font = get_font(list(font_files))
    for table_name, gap_key, ascent_key, descent_key in _HEIGHT_TABLES:
        table = font.get_sfnt_table(table_name)  # type: ignore[call-overload]  # a name it knows
        if table is not None:
            scale = 1 / font.get_sfnt_table("head")["unitsPerEm"] * size_pt * dpi / 72  # type: ignore[index]  # a font has a head
            return table[ascent_key] * scale, -table[descent_key] * scale, table[gap_key] * scale
    return None, None, None  # no table: matplotlib measures the text "lp" instead


def _remember_font_heights() -> None:
    """Let the SVG renderer answer a text's font height from :func:`_font_height_metrics`.

    matplotlib reads two font tables for every text it lays out (each tick label, again when
    the tight layout measures it and when it is drawn): ≈ 3500 reads a report, 4 % of drawing its
    figures. ``Text._get_layout`` asks the renderer first (``_get_font_height_metrics``, a hook
    matplotlib gives its PDF and PS backends); an SVG is always drawn at 72 dpi (``print_svg``
    and :func:`to_svg`), so the answer depends on the font files and the size only. The same
    numbers, so the same SVG bytes (tests/test_figures.py)."""
    from matplotlib.backends.backend_svg import RendererSVG  # lazy: heavy optional import
    from matplotlib.font_manager import fontManager  # lazy: heavy optional import

    if hasattr(RendererSVG, "_get_font_height_metrics") or not hasattr(
        fontManager, "_find_fonts_by_props"
    ):
        return  # matplotlib's own, or ours already; or a matplotlib that finds fonts otherwise

    def _get_font_height_metrics(self, prop):
        return _font_height_metrics(
            tuple(fontManager._find_fonts_by_props(prop)), prop.get_size_in_points(), 72.0
        )

    RendererSVG._get_font_height_metrics = _get_font_height_metrics  # type: ignore[attr-defined]  # private


#: A tick's artists, each a copy of the first tick's in :func:`_tick_like`.
_TICK_PARTS = ("tick1line", "tick2line", "gridline", "label1", "label2")


def _fresh_artist_state(artist) -> None:
    """What a copied artist must not share with its original: its callbacks, sticky edges and
    (a text) font properties, which matplotlib changes in place."""
    from matplotlib import cbook  # lazy: heavy optional import

    artist._callbacks = cbook.CallbackRegistry(signals=["pchanged"])
    if artist._sticky_edges is not None:
        artist._sticky_edges = type(artist._sticky_edges)(
            list(artist._sticky_edges.x), list(artist._sticky_edges.y)
        )
    if hasattr(artist, "_fontproperties"):
        artist._fontproperties = artist._fontproperties.copy()
    artist._stale = True


def _tick_like(first):
    """A new tick with the properties of ``first``: what ``Axis._get_tick`` followed by
    ``Axis._copy_tick_props(first, tick)`` makes, copied instead of built (five artists of a
    tick built from the rcParams, and the first tick's properties copied on to them: 1 ms a tick,
    a fifth of drawing a report's figures). Labels start empty, as a new tick's do; every tick
    is moved to its place and given its label before it is measured or drawn."""
    tick = copy.copy(first)
    _fresh_artist_state(tick)
    for name in _TICK_PARTS:
        part = copy.copy(getattr(first, name))
        _fresh_artist_state(part)
        setattr(tick, name, part)
    tick.label1._text = tick.label2._text = ""
    return tick


def _copyable_tick(tick) -> bool:
    """Whether :func:`_tick_like` makes what matplotlib would: a plain x or y tick (a polar
    tick moves its labels by transforms of its own) whose labels have no box."""
    from matplotlib.axis import XTick, YTick  # lazy: heavy optional import

    return type(tick) in (XTick, YTick) and all(
        getattr(tick, name)._bbox_patch is None for name in ("label1", "label2")
    )


def _more_ticks(axis, numticks: int, major: bool) -> list:
    """The axis's major or minor ticks grown to ``numticks``, as matplotlib's
    ``Axis.get_major_ticks`` grows them (the list read again each time: a tick of a projection
    of its own may reset it)."""
    name = "majorTicks" if major else "minorTicks"
    while len(getattr(axis, name)) < numticks:
        first = getattr(axis, name)[0]
        if _copyable_tick(first):
            getattr(axis, name).append(_tick_like(first))
        else:
            tick = axis._get_tick(major=major)
            getattr(axis, name).append(tick)
            axis._copy_tick_props(getattr(axis, name)[0], tick)
    return getattr(axis, name)[:numticks]


def _copy_new_ticks() -> None:
    """Let an axis make the ticks beyond its first as copies of it (:func:`_tick_like`)."""
    from matplotlib.axis import Axis  # lazy: heavy optional import

    if getattr(Axis.get_major_ticks, "crankdyn_copies", False):
        return

    def get_major_ticks(self, numticks=None):
        if numticks is None:
            numticks = len(self.get_majorticklocs())
        return _more_ticks(self, numticks, major=True)

    def get_minor_ticks(self, numticks=None):
        if numticks is None:
            numticks = len(self.get_minorticklocs())
        return _more_ticks(self, numticks, major=False)

    get_major_ticks.__doc__ = Axis.get_major_ticks.__doc__
    get_minor_ticks.__doc__ = Axis.get_minor_ticks.__doc__
    get_major_ticks.crankdyn_copies = True  # type: ignore[attr-defined]  # marks the replacement
    get_major_ticks.__wrapped__ = Axis.get_major_ticks  # type: ignore[attr-defined]  # matplotlib's
    get_minor_ticks.__wrapped__ = Axis.get_minor_ticks  # type: ignore[attr-defined]  # matplotlib's
    Axis.get_major_ticks = get_major_ticks  # type: ignore[method-assign]  # ticks copied
    Axis.get_minor_ticks = get_minor_ticks  # type: ignore[method-assign]  # ticks copied


#: The label :func:`prepare` typesets (upright and italic letters, a subscript: the fonts labels use).
WARM_UP_LABEL = r"$\alpha_{\rm x}$"


#: ``brief``: the artist classes matplotlib defines when :func:`import_matplotlib` imports it get
#: a one-line ``set()`` docstring instead of the list of every settable property, which matplotlib
#: builds for each class at import (≈ 0.1 s of the 0.35 s the import takes). The ``crankdyn``
#: command sets it unless the user did (no one reads a docstring there); a program or a notebook
#: using crankdyn keeps matplotlib's full ``help()``.
ARTIST_DOCSTRINGS_ENV = "CRANKDYN_MATPLOTLIB_DOCSTRINGS"


def _brief_kwdoc(artist) -> str:
    return "(not listed: matplotlib imported by the crankdyn command; see matplotlib.artist.kwdoc)"


def import_matplotlib() -> None:
    """Import the parts of matplotlib the figures use (the figure, the Agg and SVG backends)."""
    if os.environ.get(ARTIST_DOCSTRINGS_ENV) == "brief" and "matplotlib.figure" not in sys.modules:
        import matplotlib.artist  # lazy: heavy optional import

        full, matplotlib.artist.kwdoc = matplotlib.artist.kwdoc, _brief_kwdoc
        try:
            _import_figure_and_backends()
        finally:
            # classes defined later (a plugin's artists) are documented as matplotlib does
            matplotlib.artist.kwdoc = full
    else:
        _import_figure_and_backends()


def _import_figure_and_backends() -> None:
    import matplotlib.backends.backend_agg  # noqa: F401  # lazy: heavy optional import
    import matplotlib.backends.backend_svg  # noqa: F401  # lazy: heavy optional import
    import matplotlib.figure  # noqa: F401  # lazy: heavy optional import


def prepare(printed: bool = False) -> None:
    """Import what drawing needs and read the stored labels (:mod:`crankdyn.report.mathtext_store`)
    ahead of the first figure: a report does this while its stages are computed elsewhere.
    ``printed``: figures will be drawn as PDF pages too (:func:`to_pdf`); a small one is drawn
    now, so that the drawers forked later inherit matplotlib's PDF set-up (its fonts' Type 3
    outlines start there) instead of each making it again."""
    import_matplotlib()

    from matplotlib.font_manager import FontProperties  # lazy: heavy optional import
    from matplotlib.mathtext import MathTextParser  # lazy: heavy optional import

    _keep_more_mathtext()
    _copy_new_ticks()
    mathtext_store.store().preload()
    # One label typeset now: matplotlib builds its mathtext grammar and loads the fonts here, once,
    # for the drawers forked later to inherit, instead of in each of them (~40 ms a drawer)
    with house_style():
        MathTextParser("path").parse(WARM_UP_LABEL, 72, FontProperties(size=STYLE["font.size"]))
    if printed:
        fig, axes = new_figure(4, 3)
        axes.plot([0.0, 1.0], [0.0, 1.0])
        axes.set_xlabel(WARM_UP_LABEL)
        axes.set_ylabel("Кут α")
        to_pdf(fig)


def new_figure(width_cm: float = 16.0, height_cm: float = 8.5, **subplots):
    """(figure, axes) as ``pyplot.subplots`` returns them, on an Agg canvas, without pyplot."""
    import_matplotlib()
    _keep_more_mathtext()
    _copy_new_ticks()
    with house_style():
        size = (width_cm / 2.54, height_cm / 2.54)
        try:
            key = (_frozen(subplots), _rc_digest())
        except TypeError:  # an argument that is no plain value: made afresh
            key = None
        return AXES_TEMPLATES.subplots(key, size, subplots)


def _rc_digest() -> int:
    """A digest of every rcParam as stored (new axes take their looks from them)."""
    import matplotlib  # lazy: heavy optional import

    return hash(tuple((k, repr(v)) for k, v in dict.items(matplotlib.rcParams)))


def _frozen(value):
    """``value`` (keyword arguments: dicts, lists, tuples, strings, numbers) as a hashable key;
    TypeError for anything else."""
    if isinstance(value, dict):
        return ("dict", tuple(sorted((k, _frozen(v)) for k, v in value.items())))
    if isinstance(value, (list, tuple)):
        return (type(value).__name__, tuple(_frozen(v) for v in value))
    if value is None or isinstance(value, (str, int, float, bool)):
        return ("value", value)
    raise TypeError(f"no template for a {type(value).__name__} argument")


class AxesTemplates:
    """New axes of the kinds of subplots a process makes again and again (a batch worker's next
    variant), loaded from a pickle of the same subplots made with the same rcParams.

    New axes cost 3 ms each (every axis, spine and tick built from the rcParams); loading them
    from a pickle a third of that. A kind is kept the second time it is made (the pickle of
    that pristine figure), so a kind made once in a process (most figures of one report, drawn
    by several processes) costs nothing more. The figure's size is set after loading: the axes'
    places are fractions of it, and the layout is made when the figure is drawn. Up to ``kept``
    kinds are kept (none with 0)."""

    _CANNOT = b""  # a kind whose figure cannot be pickled (a projection of a plugin's)

    def __init__(self, kept: int):
        self.kept = kept
        self.loaded = 0  # figures loaded from a template (for the tests)
        self._seen: set = set()
        self._pickles: dict[Any, bytes] = {}

    def subplots(self, key, size: tuple[float, float], subplots: dict):
        """``(figure, axes)`` of ``fig.subplots(**subplots)`` on a figure of ``size`` inches, on an
        Agg canvas; ``key``: the subplots' kind and the rcParams' digest (None: made afresh)."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg  # lazy: heavy optional import
        from matplotlib.figure import Figure  # lazy: heavy optional import

        kept = self._pickles.get(key) if key is not None else None
        if kept:
            fig, axes = pickle.loads(kept)
            FigureCanvasAgg(fig)
            fig.set_size_inches(size, forward=False)
            self.loaded += 1
            return fig, axes
        fig = Figure(figsize=size)
        FigureCanvasAgg(fig)
        axes = fig.subplots(**subplots)
        if key is None or kept is not None or self.kept <= 0:
            return fig, axes
        if key in self._seen:  # made before: this pristine one is kept as the kind's template
            if len(self._pickles) >= self.kept:
                self._pickles.clear()
            try:
                self._pickles[key] = pickle.dumps((fig, axes), protocol=pickle.HIGHEST_PROTOCOL)
            except Exception:  # noqa: BLE001 - cannot be pickled: made afresh each time
                self._pickles[key] = self._CANNOT
        elif len(self._seen) < 4 * self.kept:
            self._seen.add(key)
        return fig, axes


#: This process's templates of new axes (:class:`AxesTemplates`; a report uses about six kinds).
AXES_TEMPLATES = AxesTemplates(kept=16)


#: Marks a figure laid out by its author (a drawing to scale): :func:`to_svg` leaves its axes where they are.
FIXED_LAYOUT = "_crankdyn_fixed_layout"
_MM_PER_INCH = 25.4


def new_drawing(width_mm: float, height_mm: float):
    """An empty figure of ``width_mm`` x ``height_mm`` on an Agg canvas whose axes are placed in
    millimetres (:func:`add_axes_mm`) and stay there: a drawing to scale."""
    import_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # lazy: heavy optional import
    from matplotlib.figure import Figure  # lazy: heavy optional import

    _keep_more_mathtext()
    _copy_new_ticks()
    with house_style():
        fig = Figure(figsize=(width_mm / _MM_PER_INCH, height_mm / _MM_PER_INCH))
        FigureCanvasAgg(fig)
    setattr(fig, FIXED_LAYOUT, True)
    return fig


def add_axes_mm(fig, left_mm: float, bottom_mm: float, width_mm: float, height_mm: float):
    """Axes at a place of the figure given in millimetres from its lower left corner."""

    w, h = (size * _MM_PER_INCH for size in fig.get_size_inches())
    with house_style():
        return fig.add_axes((left_mm / w, bottom_mm / h, width_mm / w, height_mm / h))


def drawn_box(axes, renderer):
    """The box (display units) of what the axes draw: their lines, patches, texts and titles,
    not their own rectangle (a drawing's limits keep room it may not use); None if nothing."""
    from matplotlib.collections import Collection  # lazy: heavy optional import
    from matplotlib.transforms import Bbox  # lazy: heavy optional import

    boxes = []
    for ax in axes:
        skip = {ax.patch, *ax.spines.values(), ax.xaxis, ax.yaxis}
        for artist in ax.get_children():
            if artist in skip or not artist.get_visible():
                continue
            if hasattr(artist, "get_text") and not artist.get_text():
                continue  # the axes' empty title slots
            box = (
                _collection_box(ax, artist)
                if isinstance(artist, Collection)
                else artist.get_tightbbox(renderer)
            )
            if (
                box is not None
                and box.width >= 0
                and box.height >= 0
                and np.isfinite(box.bounds).all()
            ):
                boxes.append(box)
    return Bbox.union(boxes) if boxes else None


def _collection_box(ax, collection):
    """A collection's box from its data limits: matplotlib gives the whole axes for its tight box."""
    from matplotlib.transforms import Bbox  # lazy: heavy optional import

    limits = collection.get_datalim(ax.transData)
    if not np.isfinite(limits.get_points()).all():
        return None
    return Bbox.intersection(Bbox(ax.transData.transform(limits.get_points())).padded(1.0), ax.bbox)


def fit_to_content(fig, margin_mm: float) -> None:
    """Grow or shrink the figure to what it draws (every text and arrow too) plus ``margin_mm``,
    keeping the size of each axes on paper, and so the scale of a drawing."""

    renderer = fig.canvas.get_renderer()
    with house_style():
        box = (drawn_box(fig.axes, renderer) or fig.bbox).transformed(
            fig.dpi_scale_trans.inverted()
        )  # inches
    margin = margin_mm / _MM_PER_INCH
    old_w, old_h = fig.get_size_inches()
    new_w, new_h = box.width + 2 * margin, box.height + 2 * margin
    dx, dy = margin - box.x0, margin - box.y0
    placed = [(ax, ax.get_position()) for ax in fig.axes]
    fig.set_size_inches(new_w, new_h)
    for ax, pos in placed:
        ax.set_position(
            (
                (pos.x0 * old_w + dx) / new_w,
                (pos.y0 * old_h + dy) / new_h,
                pos.width * old_w / new_w,
                pos.height * old_h / new_h,
            )
        )


def tight_layout(fig) -> None:
    """``fig.tight_layout()`` unless the figure was laid out by its author (:data:`FIXED_LAYOUT`:
    a drawing to scale, which a tight layout would resize)."""
    if not getattr(fig, FIXED_LAYOUT, False):
        fig.tight_layout()


def twin_axes(ax):
    """``ax.twinx()`` in the report's style: made outside it, the twin's tick labels came out in
    matplotlib's default 10 pt beside the 9 pt of the axes it shares a figure with."""

    with house_style():
        return ax.twinx()


def hide_axes(ax) -> None:
    """``ax.axis("off")`` for a drawing, with no ticks either: matplotlib still makes a tick per
    location for hidden axes, five artists each, when the figure's texts are gathered and laid
    out (the positions figure's six panels: about a third of its drawing time)."""
    ax.axis("off")
    ax.set_xticks([])
    ax.set_yticks([])


def crank_angle_axis(ax, cycle_deg: float, label: str) -> None:
    """An x axis of crank angle over the cycle; curves over the whole cycle's grid are closed."""
    ax.set_xlim(0, cycle_deg)
    step = 90 if cycle_deg > 360 else 45
    ax.set_xticks(range(0, int(cycle_deg) + 1, step))
    ax.set_xlabel(label)
    for axes in ax.get_shared_x_axes().get_siblings(ax):
        for line in axes.get_lines():
            close_cycle(line, cycle_deg)


def curve_with_mean_figure(
    angle_deg,
    values,
    mean,
    cycle_deg: float,
    t,
    labels: tuple[str, str, str],
    height_cm: float = 8.0,
):
    """A quantity over the cycle with its mean dashed (a torque and its mean torque): ``labels``
    are the curve's, the mean's and the vertical axis's."""
    fig, ax = new_figure(16, height_cm)
    ax.plot(angle_deg, values, color="C0", label=labels[0])
    ax.axhline(mean, color="C3", ls="--", lw=1, label=labels[1])
    ax.axhline(0, color="0.3", lw=0.6)
    crank_angle_axis(ax, cycle_deg, t("axis.crank_angle"))
    ax.set_ylabel(labels[2])
    ax.legend(loc="upper right", fontsize=8)
    return fig


def close_cycle(line, cycle_deg: float) -> None:
    """Draw a curve over a whole cycle's grid (0 .. cycle − step, the grid has no end point) on to
    the cycle's end with its first value, where a periodic quantity returns: a torque curve that
    stops at 719° short of the table's 720° row reads as a cycle that does not close."""
    x, y = line.get_xdata(), line.get_ydata()
    if (
        not (isinstance(x, np.ndarray) and isinstance(y, np.ndarray))
        or len(x) < 3
        or len(y) != len(x)
    ):
        return
    step = x[1] - x[0]
    if x[0] != 0.0 or step <= 0 or abs(x[-1] + step - cycle_deg) > 1e-9 * cycle_deg:
        return
    if not np.allclose(np.diff(x), step, rtol=1e-9, atol=1e-12 * cycle_deg):
        return
    line.set_data(np.append(x, cycle_deg), np.append(y, y[0]))


def _measure_math_as_drawn() -> None:
    """Let the SVG renderer measure a mathtext label with the typesetting that then draws it.

    matplotlib's SVG renderer measures a label by typesetting it at 100 pt and scaling the box
    down (``TextToPath.get_text_width_height_descent``), then draws it typeset at its own size:
    each label typeset twice, ≈ 5 ms each, the larger part of a first report's drawing time
    when no typeset labels are stored (``mathtext_store``). Measured with the drawing's own
    typesetting, the box is the one drawn (its width and height rounded up to whole points, as
    matplotlib rounds every typeset box), so the layout places what is drawn."""
    from matplotlib.backends.backend_svg import RendererSVG  # lazy: heavy optional import

    if getattr(RendererSVG.get_text_width_height_descent, "crankdyn_as_drawn", False):
        return
    measure = RendererSVG.get_text_width_height_descent

    def get_text_width_height_descent(self, s, prop, ismath):
        if (
            ismath is True or ismath == "mathtext"
        ):  # not "TeX", which the SVG renderer measures its way
            width, height, descent, *_ = self._text2path.mathtext_parser.parse(s, 72, prop)
            return width, height, descent
        return measure(self, s, prop, ismath)

    get_text_width_height_descent.crankdyn_as_drawn = True  # type: ignore[attr-defined]  # marks the replacement
    RendererSVG.get_text_width_height_descent = get_text_width_height_descent  # type: ignore[method-assign]  # measured as drawn


#: Text layouts :func:`_remember_text_layouts` keeps per process (emptied when full).
TEXT_LAYOUTS = 4096
_text_layouts: dict = {}


def _vector_renderer(renderer) -> type | None:
    """The class of an SVG or PDF renderer (inside a mixed-mode one), else None: those draw at
    72 dpi here (:func:`_draw_laid_out`) and measure texts by the font files alone."""
    from matplotlib.backends.backend_mixed import MixedModeRenderer  # lazy: heavy optional import
    from matplotlib.backends.backend_svg import RendererSVG  # lazy: heavy optional import

    if isinstance(renderer, MixedModeRenderer):
        renderer = renderer._renderer
    if isinstance(renderer, RendererSVG):
        return RendererSVG
    backend_pdf = sys.modules.get("matplotlib.backends.backend_pdf")
    if backend_pdf is not None and isinstance(renderer, backend_pdf.RendererPdf):
        return backend_pdf.RendererPdf
    return None


def _remember_text_layouts() -> None:
    """Let a text laid out for an SVG or a PDF keep its layout for every text laid out alike.

    ``Text._get_layout`` (the box and the lines' places of a text, relative to its anchor) runs
    for every text several times a figure (the tight layout, the axis labels' placing, the
    drawing) and for the same tick labels in figure after figure: a seventh of drawing a
    report's figures. For an SVG or a PDF (always drawn at 72 dpi, their texts measured by the
    font files alone: :func:`to_svg`, :func:`to_pdf`) the layout depends only on what the key
    holds: the renderer's kind (the two measure a little differently), the text, its font, dpi,
    rotation, alignments, line spacing and whether it is parsed as mathtext. A text that wraps
    (its lines depend on where it stands) or is set by TeX is laid out every time."""
    from matplotlib.text import Text  # lazy: heavy optional import

    layout = Text._get_layout  # type: ignore[attr-defined]  # matplotlib's private layout
    if getattr(layout, "crankdyn_remembered", False):
        return

    def _get_layout(self, renderer):
        kind = _vector_renderer(renderer)
        if self._wrap or self.get_usetex() or kind is None:
            return layout(self, renderer)
        key = (
            kind,
            self._text,
            self._fontproperties,
            self.get_figure(root=True).dpi,
            self.get_rotation(),
            self._rotation_mode,
            self._horizontalalignment,
            self._verticalalignment,
            self._multialignment,
            self._linespacing,
            self._parse_math,
        )
        known = _text_layouts.get(key)
        if known is None:
            known = layout(self, renderer)
            if len(_text_layouts) >= TEXT_LAYOUTS:
                _text_layouts.clear()
            # the key keeps a copy of the font, which matplotlib changes in place
            _text_layouts[(*key[:2], key[2].copy(), *key[3:])] = known
        box, lines, corner = known
        return box.frozen(), list(lines), corner  # a box of its own: a caller may move it

    _get_layout.crankdyn_remembered = True  # type: ignore[attr-defined]  # marks the replacement
    _get_layout.__wrapped__ = layout  # type: ignore[attr-defined]  # matplotlib's
    Text._get_layout = _get_layout  # type: ignore[attr-defined]  # layouts remembered


#: ``updates``: while :func:`to_svg` lays out and draws a figure in this thread, each axis's last
#: tick update by the axis's id (unset or None outside it; the preview may draw in two threads).
_tick_updates = threading.local()


def _tick_update_key(axis) -> tuple:
    """What ``Axis._update_ticks`` reads: the view, the axes' place, the scale, locators,
    formatters and tick lists (nothing else changes them while a figure is laid out and drawn)."""
    return (
        tuple(axis.get_view_interval()),
        axis.axes.bbox.bounds,
        axis.get_figure(root=True).dpi,
        axis.get_scale(),
        id(axis.major.locator),
        id(axis.major.formatter),
        id(axis.minor.locator),
        id(axis.minor.formatter),
        id(axis.majorTicks),
        len(axis.majorTicks),
        id(axis.minorTicks),
        len(axis.minorTicks),
    )


def _remember_tick_updates() -> None:
    """Let an axis update its ticks once for as long as nothing they depend on changes.

    matplotlib updates an axis's ticks (locator, formatter, each tick moved and labelled) each
    time it measures or draws the axis, its spines or a sibling's label: eight times an axis
    while :func:`to_svg` lays out and draws a figure, where the view and the axes' place change
    only once (the tight layout). Inside :func:`to_svg` an x or y axis updates its ticks again
    only when :func:`_tick_update_key` changed since its last update; its ticks are still as
    that update left them."""
    from matplotlib.axis import Axis, XAxis, YAxis  # lazy: heavy optional import

    update = Axis._update_ticks  # type: ignore[attr-defined]  # matplotlib's private update
    if getattr(update, "crankdyn_remembered", False):
        return

    def _update_ticks(self):
        updates = getattr(_tick_updates, "updates", None)
        if updates is None or type(self) not in (XAxis, YAxis):
            return update(self)
        key = _tick_update_key(self)
        last = updates.get(id(self))
        if last is not None and last[0] == key:
            return list(last[1])
        ticks = update(self)
        updates[id(self)] = (_tick_update_key(self), list(ticks))
        return ticks

    _update_ticks.crankdyn_remembered = True  # type: ignore[attr-defined]  # marks the replacement
    _update_ticks.__wrapped__ = update  # type: ignore[attr-defined]  # matplotlib's
    Axis._update_ticks = _update_ticks  # type: ignore[attr-defined]  # updates remembered


#: A text drawn upright: matplotlib still writes its rotation by zero (``rotate(-0 x y)``).
_UPRIGHT = re.compile(r' transform="rotate\(-0 [^")]*\)"')


@functools.cache
def _lean_svg_renderer() -> type:
    """``RendererSVG`` that writes no group for an artist without a ``gid`` of its own.

    matplotlib wraps every artist, tick and label in a ``<g id="xtick_1">`` (about four elements
    in ten of a figure's SVG) that nothing refers to; a renderer walks each of them (WeasyPrint
    cascades its style and transform) and draws the same. An artist given a ``gid`` keeps its
    group (the drawings name their parts so)."""
    from matplotlib.backends.backend_svg import RendererSVG  # lazy: heavy optional import

    class LeanRendererSVG(RendererSVG):
        def open_group(self, s, gid=None):
            self.__dict__.setdefault("_kept_groups", []).append(bool(gid))
            if gid:
                super().open_group(s, gid)

        def close_group(self, s):
            if self.__dict__["_kept_groups"].pop():
                super().close_group(s)

    return LeanRendererSVG


def to_svg(fig) -> bytes:
    """The figure as SVG bytes, laid out (tight layout) and drawn by one SVG renderer.

    ``savefig`` would measure every label twice: once for the layout, with the Agg canvas's
    renderer, and again, with the SVG renderer, to draw it; laid out with the renderer that then
    draws, each text is measured once (matplotlib caches text metrics per renderer). What
    follows is ``FigureCanvasSVG.print_svg`` with the ``TightLayoutEngine`` step before the draw.
    """
    buffer = io.StringIO()

    def renderer(width: float, height: float):
        return _lean_svg_renderer()(
            width * 72, height * 72, buffer, image_dpi=72, metadata={"Date": None}
        )

    _draw_laid_out(fig, renderer)
    return presentation_attributes(_UPRIGHT.sub("", buffer.getvalue())).encode("utf-8")


#: A figure PDF's document information: none (the same figure gives the same bytes).
_NO_PDF_METADATA = {"Creator": None, "Producer": None, "CreationDate": None}


def to_pdf(fig) -> bytes:
    """The figure as a one-page PDF (its page the figure's size in points), laid out and drawn
    as :func:`to_svg` does, for the printed report to place as it is
    (:mod:`crankdyn.report.figure_forms`). Text stays text, in Type 3 fonts matplotlib subsets
    itself, with their Unicode names (searchable, copied as written)."""
    from matplotlib.backends.backend_pdf import PdfFile, RendererPdf  # lazy: heavy optional import

    figure_shortcuts.install_pdf()
    buffer = io.BytesIO()
    file = PdfFile(buffer, metadata=_NO_PDF_METADATA)

    def renderer(width: float, height: float):
        file.newPage(width, height)
        return RendererPdf(file, 72, height, width)

    try:
        _draw_laid_out(fig, renderer)
        file.finalize()
    finally:
        file.close()
    return buffer.getvalue()


def _draw_laid_out(fig, renderer_for: Callable[[float, float], Any]) -> None:
    """Lay ``fig`` out (tight layout, unless it is a drawing to scale) and draw it with the
    renderer ``renderer_for(width_in, height_in)`` makes, at 72 dots an inch."""
    from matplotlib._tight_layout import (  # lazy: heavy optional import
        get_subplotspec_list,
        get_tight_layout_figure,
    )
    from matplotlib.backends.backend_mixed import MixedModeRenderer  # lazy: heavy optional import

    _keep_more_mathtext()
    _copy_new_ticks()
    _remember_font_heights()
    _measure_math_as_drawn()
    _remember_text_layouts()
    _remember_tick_updates()
    figure_shortcuts.install()
    dpi = fig.dpi
    outer_updates = getattr(_tick_updates, "updates", None)
    outer_boxes = getattr(figure_shortcuts.tick_label_boxes, "boxes", None)
    _tick_updates.updates = {}
    figure_shortcuts.tick_label_boxes.boxes = {}
    try:
        with house_style():
            fig.set_layout_engine(None)  # laid out here, once
            fig.dpi = 72  # the vector formats' own unit, as savefig sets it (and gives back after)
            width, height = fig.get_size_inches()
            renderer = MixedModeRenderer(fig, width, height, 72, renderer_for(width, height))
            if fig.axes and not getattr(fig, FIXED_LAYOUT, False):
                _from_first_layout(fig)
                with renderer._draw_disabled():
                    adjust = get_tight_layout_figure(
                        fig, fig.axes, get_subplotspec_list(fig.axes), renderer, pad=1.08
                    )
                if adjust:
                    fig.subplots_adjust(**adjust)
            fig.draw(renderer)
            renderer.finalize()
    finally:
        fig.dpi = dpi
        _tick_updates.updates = outer_updates
        figure_shortcuts.tick_label_boxes.boxes = outer_boxes
    pyplot = sys.modules.get("matplotlib.pyplot")
    if pyplot is not None and getattr(fig.canvas, "manager", None) is not None:
        pyplot.close(fig)  # a plugin drew it with pyplot: release pyplot's reference


#: Where a figure keeps the subplot parameters it had before it was first laid out.
_FIRST_LAYOUT = "_crankdyn_first_layout"
_SUBPLOT_PARAMETERS = ("left", "bottom", "right", "top", "wspace", "hspace")


def _from_first_layout(fig) -> None:
    """Put the figure's subplots back where they were before its first tight layout, so that
    each drawing (its SVG, its PDF page) is laid out from the same start and does not depend on
    which was drawn first (a PDF measures its texts a little differently)."""
    first = getattr(fig, _FIRST_LAYOUT, None)
    if first is None:
        setattr(fig, _FIRST_LAYOUT, {k: getattr(fig.subplotpars, k) for k in _SUBPLOT_PARAMETERS})
    else:
        fig.subplots_adjust(**first)


#: The one stylesheet matplotlib writes into an SVG (every element's line joins and caps).
_MATPLOTLIB_SHEET = '<style type="text/css">*{stroke-linejoin: round; stroke-linecap: butt}</style>'
_STYLE_ATTRIBUTE = re.compile(r' style="([^"]*)"')
#: SVG presentation attributes matplotlib puts into ``style`` (SVG 1.1, section 6.4; any other
#: property stays in a ``style`` attribute).
_PRESENTATION = frozenset(
    {
        "fill",
        "fill-opacity",
        "fill-rule",
        "stroke",
        "stroke-width",
        "stroke-opacity",
        "stroke-linecap",
        "stroke-linejoin",
        "stroke-dasharray",
        "stroke-dashoffset",
        "stroke-miterlimit",
        "opacity",
        "font-family",
        "font-size",
        "font-style",
        "font-weight",
        "text-anchor",
        "clip-rule",
    }
)


def presentation_attributes(svg: str) -> str:
    """matplotlib's SVG with each element's ``style="fill: none; stroke: #000"`` written as
    presentation attributes (``fill="none" stroke="#000"``), which a renderer reads without a CSS
    parser: WeasyPrint draws a report's figures about a tenth faster, the same pixels.

    matplotlib's stylesheet (``*{stroke-linejoin: round; stroke-linecap: butt}``) outranks
    presentation attributes but not an element's own ``style``; it becomes the same two
    attributes on the root ``<svg>``, inherited by every element that does not set its own.
    An SVG with any other stylesheet is returned unchanged.
    """
    if svg.count("<style") != 1 or _MATPLOTLIB_SHEET not in svg:
        return svg
    svg = svg.replace(_MATPLOTLIB_SHEET, "").replace(
        "<svg ", '<svg stroke-linejoin="round" stroke-linecap="butt" ', 1
    )

    def attributes(match: re.Match) -> str:
        declarations = [d.split(":", 1) for d in match.group(1).split(";") if ":" in d]
        plain = "".join(
            f' {name.strip()}="{value.strip()}"'
            for name, value in declarations
            if name.strip() in _PRESENTATION
        )
        rest = "; ".join(
            f"{name.strip()}: {value.strip()}"
            for name, value in declarations
            if name.strip() not in _PRESENTATION
        )
        return plain + (f' style="{rest}"' if rest else "")

    return _STYLE_ATTRIBUTE.sub(attributes, svg)


#: Environment variable that sets how many processes draw a report's figures (1: no fork).
WORKERS_ENV = "CRANKDYN_FIGURE_WORKERS"


def default_workers() -> int:
    """Processes for drawing figures: the CPUs this process may use (``CRANKDYN_FIGURE_WORKERS``
    overrides; a batch runs its variants in parallel instead and passes 1)."""
    value = os.environ.get(WORKERS_ENV, "")
    if value.strip().isdigit() and int(value) >= 1:
        return int(value)
    try:
        return max(1, min(len(os.sched_getaffinity(0)), 8))
    except AttributeError:  # no sched_getaffinity (macOS, Windows)
        return max(1, min(os.cpu_count() or 1, 8))


def can_fork(allow_threads: bool = False) -> bool:
    """Whether figures may be drawn in forked children: POSIX ``fork``, and (unless the caller
    knows better) no other thread that a child's copy of a held lock could stall."""
    return hasattr(os, "fork") if allow_threads else _no_other_thread()


def draw_jobs(
    jobs: Sequence[Callable[[], bytes]], workers: int = 1, allow_threads: bool = False
) -> list[bytes]:
    """``[job() for job in jobs]``, the work shared by ``workers`` processes.

    matplotlib draws in Python, one core per process; a report's figures are independent, so
    ``workers - 1`` forked children (which inherit the figures already built, nothing is pickled
    on the way in) and this process take the figures one by one (:class:`SharedDrawing`). A child
    that fails or dies leaves its figures to be drawn here, so the result (and any exception) is
    the serial one. Serial when ``workers`` is 1, there are fewer than 4 jobs or forking is unsafe.
    """
    jobs = list(jobs)
    workers = min(workers, len(jobs) // 2)
    if workers <= 1 or len(jobs) < 4 or len(jobs) > SHARED_JOBS_MAX or not can_fork(allow_threads):
        return [job() for job in jobs]
    drawing = SharedDrawing(jobs, children=workers - 1)
    try:
        drawing.draw_here()
    finally:  # even when a figure this process took failed: no child is left behind
        drawing.collect()
    return drawing.finish()


class ForkedDrawing:
    """Jobs drawn by forked children, one child per share of job indices, while this process
    goes on with other work; :meth:`finish` collects them and does here whatever a child did
    not deliver. Call :meth:`finish` (or :meth:`collect`) exactly once: it reaps the children."""

    def __init__(self, jobs: Sequence[Callable[[], bytes]], shares: Sequence[Sequence[int]]):
        self.jobs = list(jobs)
        self.results: list[bytes | None] = [None] * len(self.jobs)
        self._children = [self._fork(list(share)) for share in shares if share]

    def _fork(self, mine: list[int]):
        freeze_more()  # the child's collector leaves the inherited heap alone (engine.frozen_heap)
        forked = fork_with_pipe()
        if forked is None:  # no process to be had: these jobs are done here
            return None, None, mine
        pid, read_end, write_end = forked
        if pid == 0:  # the child: draw, send, leave without running the parent's exit handlers
            os.close(read_end)
            code = 1
            try:
                payload = pickle.dumps(
                    [self.jobs[i]() for i in mine], protocol=pickle.HIGHEST_PROTOCOL
                )
                with os.fdopen(write_end, "wb") as pipe:
                    pipe.write(payload)
                code = 0
                mathtext_store.save()  # the labels this child typeset, for the next run (after the answer)
            finally:
                os._exit(code)
        os.close(write_end)
        return pid, read_end, mine

    def done(self) -> bool:
        """Whether every child has finished drawing (its answer is waiting in its pipe)."""
        return all(
            read_end is None or select.select([read_end], [], [], 0)[0]
            for _, read_end, _ in self._children
        )

    def collect(self) -> None:
        """Wait for every child and keep what it drew."""
        children, self._children = self._children, []
        for pid, read_end, mine in children:
            if pid is None:  # never forked: its jobs are done here
                continue
            with os.fdopen(read_end, "rb") as pipe:
                payload = pipe.read()
            _, status = os.waitpid(pid, 0)
            if status == 0:
                try:
                    for i, svg in zip(mine, pickle.loads(payload), strict=True):
                        self.results[i] = svg
                except Exception:  # noqa: BLE001 - a truncated answer: those figures are drawn here
                    pass

    def finish(self) -> list[bytes]:
        """Every job's result: the children's, and here what they did not deliver."""
        self.collect()
        return [
            job() if result is None else result
            for job, result in zip(self.jobs, self.results, strict=True)
        ]


#: A job's number as written to :class:`SharedDrawing`'s pipe (two bytes: up to 65 535 jobs).
_TOKEN = struct.Struct(">H")
#: Jobs a :class:`SharedDrawing` takes: their numbers must fit in a pipe before anyone reads it
#: (Linux: 64 KiB, POSIX at least 512 bytes).
SHARED_JOBS_MAX = 256


class SharedDrawing:
    """Jobs taken one at a time, in order, by this process and ``children`` forked ones: whoever
    is free takes the next, so all finish within about one job of each other (a fixed half each
    left one process drawing the last long figure alone while the other waited).

    The jobs' numbers are written to a pipe before the fork; each process reads one number (a
    read of two bytes from a pipe is not split) until the pipe is empty. A child sends back
    ``(number, result)`` pairs; a job whose child failed or died is done here by :meth:`finish`,
    so the results (and any exception) are the serial ones. Call :meth:`collect` exactly once.
    """

    _claims: int | None  # the pipe's end the numbers are read from; None once closed

    def __init__(self, jobs: Sequence[Callable[[], bytes]], children: int):
        self.jobs = list(jobs)
        if len(self.jobs) > SHARED_JOBS_MAX:
            raise ValueError(
                f"{len(self.jobs)} jobs; a shared drawing takes at most {SHARED_JOBS_MAX}"
            )
        self.results: list[bytes | None] = [None] * len(self.jobs)
        self._claims, numbers = os.pipe()
        os.write(numbers, b"".join(_TOKEN.pack(i) for i in range(len(self.jobs))))
        os.close(numbers)  # the pipe ends once every number is taken
        self._children = []
        for _ in range(children):
            child = self._fork()
            if child is None:  # no more processes to be had: this one takes what is left
                break
            self._children.append(child)

    def _claim(self) -> int | None:
        assert self._claims is not None  # claims are read before collect() closes the pipe
        token = os.read(self._claims, _TOKEN.size)
        return _TOKEN.unpack(token)[0] if len(token) == _TOKEN.size else None

    def _fork(self):
        """(pid, the end its answer comes from), or None when no process could be forked."""
        freeze_more()  # the child's collector leaves the inherited heap alone (engine.frozen_heap)
        forked = fork_with_pipe()
        if forked is None:
            return None
        pid, read_end, write_end = forked
        if (
            pid == 0
        ):  # the child: take, draw, send, leave without running the parent's exit handlers
            os.close(read_end)
            code = 1
            try:
                drawn = []
                while (number := self._claim()) is not None:
                    drawn.append((number, self.jobs[number]()))
                with os.fdopen(write_end, "wb") as pipe:
                    pipe.write(pickle.dumps(drawn, protocol=pickle.HIGHEST_PROTOCOL))
                code = 0
                mathtext_store.save()  # the labels this child typeset, for the next run (after the answer)
            finally:
                os._exit(code)
        os.close(write_end)
        return pid, read_end

    def draw_here(self) -> None:
        """Take and draw jobs in this process until none is left."""
        while (number := self._claim()) is not None:
            self.results[number] = self.jobs[number]()

    def collect(self) -> None:
        """Wait for every child and keep what it drew (no job is taken after this)."""
        children, self._children = self._children, []
        for pid, read_end in children:
            with os.fdopen(read_end, "rb") as pipe:
                payload = pipe.read()
            _, status = os.waitpid(pid, 0)
            if status == 0:
                try:
                    for number, result in pickle.loads(payload):
                        self.results[number] = result
                except Exception:  # noqa: BLE001 - a truncated answer: those jobs are done here
                    pass
        if self._claims is not None:
            os.close(self._claims)
            self._claims = None

    def finish(self) -> list[bytes]:
        """Every job's result: the children's, and here what they did not deliver."""
        self.collect()
        return [
            job() if result is None else result
            for job, result in zip(self.jobs, self.results, strict=True)
        ]


class IncrementalDrawing:
    """Figures drawn by forked children while this process goes on rendering the report's next
    sections: :meth:`add` hands over a section's figures (a child is forked for what is waiting
    whenever fewer than ``workers - 1`` are busy), :meth:`finish` draws here what no child took,
    while the children finish, and collects their SVGs. Works on :class:`FigureFile` s.

    Instead of :meth:`finish`, :meth:`hand_out` gives every figure still waiting to children and
    returns at once: this process may go on (laying out the PDF) and a figure's ``svg`` then
    waits for the child drawing it; :meth:`finish` afterwards reaps what is left.

    ``kind``: what is drawn, the figures' ``"svg"`` (the page's files) or ``"pdf"`` (the pages
    a printed report places, :mod:`crankdyn.report.figure_forms`).
    """

    def __init__(self, workers: int, kind: str = "svg"):
        if kind not in ("svg", "pdf"):
            raise ValueError(f"kind {kind!r}; allowed: 'svg', 'pdf'")
        self.workers = max(workers, 1)
        self.children = max(workers - 1, 1)
        self.kind = kind
        self._running: list[tuple[ForkedDrawing, list]] = []
        self._waiting: list = []

    def _job(self, figure) -> Callable[[], bytes]:
        return figure.draw if self.kind == "svg" else figure.draw_pdf

    #: Figures a child takes at a time: small batches leave work for the end, where this process
    #: and the children share it (a child that took everything would leave this one idle).
    BATCH = 3

    def add(self, figures) -> None:
        self._waiting += [f for f in figures if not f.has(self.kind)]
        self._store(finished_only=True)
        if self._waiting and len(self._running) < self.children:
            batch, self._waiting = self._waiting[: self.BATCH], self._waiting[self.BATCH :]
            self._fork(batch)

    def _fork(self, batch: list) -> None:
        drawing = ForkedDrawing([self._job(f) for f in batch], [list(range(len(batch)))])
        self._running.append((drawing, batch))
        for figure in batch:
            figure.awaiting[self.kind] = self._await

    def _await(self, figure) -> None:
        """``figure.svg`` asked for while a child draws it: wait for that child (only)."""
        for entry in self._running:
            if any(f is figure for f in entry[1]):
                self._running.remove(entry)
                self._keep(*entry)
                return

    def _keep(self, drawing: ForkedDrawing, batch: list) -> None:
        for figure, drawn in zip(batch, drawing.finish(), strict=True):
            figure.keep(self.kind, drawn)

    def _store(self, finished_only: bool) -> None:
        keep = []
        for drawing, batch in self._running:
            if finished_only and not drawing.done():
                keep.append((drawing, batch))
                continue
            self._keep(drawing, batch)
        self._running = keep

    def hand_out(self) -> None:
        """Give every waiting figure to new children (one per CPU, in document order) and return."""
        self._store(finished_only=True)
        waiting, self._waiting = self._waiting, []
        if not waiting:
            return
        shares = min(self.workers, len(waiting))
        size = -(-len(waiting) // shares)
        # consecutive figures per child: the PDF asks for them in document order, so the first
        # ones are ready first
        for k in range(0, len(waiting), size):
            self._fork(waiting[k : k + size])

    def finish(self) -> None:
        self._store(finished_only=True)
        waiting, self._waiting = self._waiting, []
        if 2 <= len(waiting) <= SHARED_JOBS_MAX:
            # the rest taken figure by figure by this process and a new child (a busy one has at
            # most BATCH left)
            shared = SharedDrawing([self._job(f) for f in waiting], children=1)
            try:
                shared.draw_here()
            finally:
                shared.collect()
                self._store(finished_only=False)
            for figure, drawn in zip(waiting, shared.finish(), strict=True):
                figure.keep(self.kind, drawn)
            return
        try:
            for figure in waiting:
                getattr(figure, self.kind)  # drawn here for its side effect
        finally:
            self._store(finished_only=False)

    def abandon(self) -> None:
        """The report failed: reap the children, draw nothing more."""
        self._waiting = []
        for drawing, batch in self._running:
            drawing.collect()
            for figure in batch:
                figure.awaiting.pop(self.kind, None)
        self._running = []
