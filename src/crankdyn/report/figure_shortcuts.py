"""Shortcuts through matplotlib's layout and drawing that give the bytes its own way gives.

A report draws about twenty figures, a batch a few hundred, one process each drawing them one
after another. Each shortcut below replaces one matplotlib function, once per process
(:func:`install`; :func:`install_pdf` where a PDF is drawn), with one that computes the same
result with less work; the replacement keeps
matplotlib's function as ``__wrapped__`` and carries ``crankdyn_shortcut``.
``tests/test_figure_shortcuts.py`` draws figures both ways and compares the bytes.

- :func:`_union_at_once`: the box around boxes (``Bbox.union``) from one array, not four
  reductions of a Python list each (the tight layout and every axis label's place ask for it).
- :func:`_remember_tick_label_boxes`: the boxes of an axis's tick labels, measured once for as
  long as the axis's ticks stay as they are while a figure is drawn (its tight layout and its
  drawing ask for them four times an axis).
- :func:`_remember_pdf_text_runs` and :func:`_remember_pdf_glyph_procs`: a PDF page's texts are
  shaped once per text, font and size, and each glyph's outline is converted once per font.
"""

from __future__ import annotations

import functools
import threading
import types
from collections.abc import Callable
from typing import Any

#: Shaped texts :func:`_remember_pdf_text_runs` keeps per process (emptied when full).
TEXT_RUNS = 4096
_text_runs: dict = {}
#: The size each PDF renderer's font was last set to: font id -> (font, size in points); at
#: most FONT_SIZES fonts (matplotlib keeps 64 a thread).
FONT_SIZES = 256
_pdf_font_sizes: dict[int, tuple[Any, float]] = {}

#: While :func:`crankdyn.report.figures.to_svg` or ``to_pdf`` draws a figure in this thread:
#: ``boxes``, each axis's last measured tick labels by the axis's id (unset or None outside).
tick_label_boxes = threading.local()


def install() -> None:
    """Put the shortcuts of every drawing in place (once per process)."""
    _union_at_once()
    _remember_tick_label_boxes()


def install_pdf() -> None:
    """Put the shortcuts of a PDF drawing in place (once per process): only a process that draws
    a PDF imports matplotlib's PDF backend."""
    _remember_pdf_text_runs()
    _remember_pdf_glyph_procs()


def _marked(replacement: Callable, original: Callable) -> Callable:
    replacement.crankdyn_shortcut = True  # type: ignore[attr-defined]  # marks the replacement
    replacement.__wrapped__ = original  # type: ignore[attr-defined]  # matplotlib's
    return replacement


def _union_at_once() -> None:
    """``Bbox.union`` from one array of the boxes' corners.

    matplotlib's takes each box's ``xmin``, ``xmax``, ``ymin`` and ``ymax`` (each a reduction
    of the box's points) into four lists and reduces each again. Here each coordinate is reduced
    over each box's two corners and then over the boxes, in that order too, so the extremes
    (and the sign of a zero among them) are the same."""
    import numpy as np  # lazy: heavy optional import
    from matplotlib.transforms import Bbox, BboxBase  # lazy: heavy optional import

    union = BboxBase.union
    if getattr(union, "crankdyn_shortcut", False):
        return

    def union_at_once(bboxes):
        if not len(bboxes):
            raise ValueError("'bboxes' cannot be empty")
        points = np.array([bbox.get_points() for bbox in bboxes], dtype=float)
        x, y = points[:, :, 0], points[:, :, 1]
        return Bbox(
            [
                [x.min(axis=1).min(), y.min(axis=1).min()],
                [x.max(axis=1).max(), y.max(axis=1).max()],
            ]
        )

    BboxBase.union = staticmethod(_marked(union_at_once, union))  # type: ignore[method-assign]  # the same box, once


def _remember_tick_label_boxes() -> None:
    """Let an axis measure its tick labels once for as long as its ticks stay as they are.

    ``Axis._get_ticklabel_bboxes`` measures every tick label each time the axis's label is
    placed or the axis is measured or drawn: four times an axis while a figure is laid out and
    drawn, where the labels move only once (the tight layout). While a figure is drawn
    (``tick_label_boxes.boxes`` set), an x or y axis measures again only when the axis's tick
    update key (``figures._tick_update_key``: its view, place, scale, locators, formatters and
    tick lists), the ticks asked about or the renderer changed since; the boxes are new objects
    each time, as matplotlib's are."""
    from matplotlib.axis import Axis, XAxis, YAxis  # lazy: heavy optional import

    measure = Axis._get_ticklabel_bboxes  # type: ignore[attr-defined]  # matplotlib's private measure
    if getattr(measure, "crankdyn_shortcut", False):
        return
    from .figures import (  # lazy: heavy optional import (matplotlib; figures installs these)
        _tick_update_key,
    )

    def _get_ticklabel_bboxes(self, ticks, renderer=None):
        boxes = getattr(tick_label_boxes, "boxes", None)
        if boxes is None or renderer is None or type(self) not in (XAxis, YAxis):
            return measure(self, ticks, renderer)
        key = (_tick_update_key(self), tuple(map(id, ticks)), id(renderer))
        last = boxes.get(id(self))
        if last is None or last[0] != key:
            last = boxes[id(self)] = (key, measure(self, ticks, renderer), list(ticks), renderer)
        first, second = last[1]
        return [box.frozen() for box in first], [box.frozen() for box in second]

    Axis._get_ticklabel_bboxes = _marked(_get_ticklabel_bboxes, measure)  # type: ignore[attr-defined]  # measured once


def _remember_pdf_text_runs() -> None:
    """Let the PDF renderer shape a text once per text, font, size, features and language.

    ``RendererPdf.draw_text`` shapes each text it draws (``_text_helpers.layout``: the glyphs
    and their places, by libraqm, each glyph loaded), the same tick labels in figure after
    figure. The run depends on the font object (its file and fallbacks), the size the renderer
    set it to (:data:`_pdf_font_sizes`, recorded by the renderer's ``_get_font_ttf``), the text,
    its features and language. ``draw_text`` reads the items only, not the glyph each left
    loaded in the font. A text shaped with a font whose size was set elsewhere is shaped as
    before."""
    from matplotlib.backends import backend_pdf  # lazy: heavy optional import

    helpers = backend_pdf._text_helpers
    if getattr(helpers, "crankdyn_shortcut", False):
        return
    layout = helpers.layout
    get_font_ttf = backend_pdf.RendererPdf._get_font_ttf

    def _get_font_ttf(self, prop):
        font = get_font_ttf(self, prop)
        if len(_pdf_font_sizes) >= FONT_SIZES:
            _pdf_font_sizes.clear()
        _pdf_font_sizes[id(font)] = (font, prop.get_size_in_points())
        return font

    def remembered_layout(string, font, *, features=None, language=None):
        sized = _pdf_font_sizes.get(id(font))
        if sized is None or sized[0] is not font:
            return layout(string, font, features=features, language=language)
        key = (
            string,
            id(font),
            sized[1],
            None if features is None else tuple(features),
            language if isinstance(language, (str, type(None))) else tuple(language),
        )
        known = _text_runs.get(key)
        if known is None:
            if len(_text_runs) >= TEXT_RUNS:
                _text_runs.clear()
            # the font is kept with its items, so that its id is not another font's meanwhile
            known = _text_runs[key] = (
                font,
                tuple(layout(string, font, features=features, language=language)),
            )
        return iter(known[1])

    # the PDF backend's own view of the helpers: other users of _text_helpers are left alone
    view = types.SimpleNamespace(**vars(helpers))
    view.layout = _marked(remembered_layout, layout)
    view.crankdyn_shortcut = True
    backend_pdf._text_helpers = view  # type: ignore[assignment]  # its texts shaped once
    backend_pdf.RendererPdf._get_font_ttf = _marked(_get_font_ttf, get_font_ttf)  # type: ignore[method-assign]  # sizes recorded


def _remember_pdf_glyph_procs() -> None:
    """Let a figure PDF convert each glyph's outline once per font file.

    A Type 3 font holds each glyph it draws as a little PDF program, converted from the font
    file's outline (``backend_pdf._get_pdf_charprocs``) anew in every figure that uses it.
    Each glyph's program depends on the font file and the glyph alone."""
    from matplotlib.backends import backend_pdf  # lazy: heavy optional import

    procs = backend_pdf._get_pdf_charprocs
    if getattr(procs, "crankdyn_shortcut", False):
        return

    @functools.lru_cache(maxsize=8192)
    def glyph_proc(font_path, glyph_index) -> tuple[str, bytes]:
        ((name, proc),) = procs(font_path, [glyph_index]).items()
        return name, proc

    def _get_pdf_charprocs(font_path, glyph_indices):
        return dict(glyph_proc(font_path, index) for index in glyph_indices)

    backend_pdf._get_pdf_charprocs = _marked(_get_pdf_charprocs, procs)  # each glyph once
