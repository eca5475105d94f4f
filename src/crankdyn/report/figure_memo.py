"""SVGs of figures that depend on nothing but their inputs, kept per process for the next report.

A batch's variants often share figures: variants that differ in speed, masses or pressure but
not in the mechanism's dimensions have the same kinematic scheme and the same characteristic
positions. A figure built by a :class:`MemoFigure` (a function and the arguments it draws from,
and nothing else) is drawn once per process for its inputs, report language and symbol table;
a later report of the same process whose figure has equal inputs takes the SVG drawn then (a
batch worker, the live preview). Equal inputs are those whose pickles are equal: the digest of
the pickled function name and arguments is the key.
"""

from __future__ import annotations

import hashlib
import pickle
from collections.abc import Callable
from typing import Any

#: SVGs kept per process (emptied when full): a few reports' worth of shared figures.
MEMO_SIZE = 64

_svgs: dict[tuple, bytes] = {}
_values: dict[bytes, Any] = {}
#: id of a translator -> (the translator, the digest of its texts): each report builds its own,
#: and the last few are kept (with their catalogs) so that their ids are not reused meanwhile
_translators: dict[int, tuple[Any, bytes]] = {}
TRANSLATORS_KEPT = 8


def inputs_digest(function: Callable, *args: Any) -> bytes | None:
    """The digest of ``function`` (by its module and name) and its ``args``; None when the
    arguments cannot be pickled (such a figure is drawn every time)."""
    try:
        data = pickle.dumps(
            (function.__module__, function.__qualname__, args),
            protocol=pickle.HIGHEST_PROTOCOL,
        )
    except Exception:  # noqa: BLE001 - not picklable: not kept
        return None
    return hashlib.blake2b(data, digest_size=32).digest()


class MemoFigure:
    """The builder of a figure that ``function(*args)`` makes from its arguments alone (module
    constants aside): called with no arguments it builds the matplotlib figure, as any figure
    builder given to ``RenderContext.figure``; ``digest`` keys its SVG. ``built``: the figure,
    when the caller has built it already (it is then returned instead of built again)."""

    def __init__(self, function: Callable, *args: Any, built: Any = None):
        self.function, self.args = function, args
        self.digest = inputs_digest(function, *args)
        self.built = built

    def __call__(self):
        return self.built if self.built is not None else self.function(*self.args)


def _texts_digest(t: Any) -> bytes | None:
    """What typesetting reads of translator ``t`` (its language and texts: the number format),
    as a digest computed once per translator."""
    if t is None:
        return None
    kept = _translators.get(id(t))
    if kept is not None and kept[0] is t:
        return kept[1]
    contents = pickle.dumps((t.language, t.texts, t.fallback), protocol=pickle.HIGHEST_PROTOCOL)
    digest = hashlib.blake2b(contents, digest_size=32).digest()
    if len(_translators) >= TRANSLATORS_KEPT:
        _translators.clear()
    _translators[id(t)] = (t, digest)  # the translator kept: its id is not reused meanwhile
    return digest


def svg(digest: bytes | None, t: Any, symbols: Any) -> bytes | None:
    """The SVG kept for ``digest`` typeset by translator ``t`` with ``symbols``, or None."""
    if digest is None:
        return None
    return _svgs.get((digest, _texts_digest(t), symbols))


def keep(digest: bytes | None, t: Any, symbols: Any, drawn: bytes) -> None:
    """Keep ``drawn`` as the SVG of ``digest`` typeset by ``t`` with ``symbols``."""
    if digest is None:
        return
    if len(_svgs) >= MEMO_SIZE:
        _svgs.clear()
    _svgs[(digest, _texts_digest(t), symbols)] = drawn


def value(digest: bytes | None) -> Any:
    """A value kept beside the figure of ``digest`` (the scale a scheme was drawn at), or None."""
    return None if digest is None else _values.get(digest)


def keep_value(digest: bytes | None, kept: Any) -> None:
    """Keep ``kept`` beside the figure of ``digest`` (:func:`value`)."""
    if digest is None:
        return
    if len(_values) >= MEMO_SIZE:
        _values.clear()
    _values[digest] = kept
