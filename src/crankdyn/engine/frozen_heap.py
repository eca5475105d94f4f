"""Fewer garbage-collector passes over what stays alive for a whole report.

CPython's cyclic collector walks every tracked object of its oldest generation on each full
pass. Once numpy, scipy, pandas, matplotlib, Jinja and the plugins are imported, that is some
hundreds of thousands of objects (modules, functions, classes, the figures of the report) that
never become garbage while the report is built, and matplotlib allocates enough to trigger
many full passes: measured on the single-cylinder example, they cost about a fifth of the HTML
run's CPU time.

:func:`frozen_heap` moves everything alive at its start into the collector's permanent
generation (``gc.freeze``, which the collector skips) and gives it back at the end, so the
objects of one report are collected as usual once it is done (a batch worker or the preview
server builds many). :func:`freeze_more` does the same, inside that scope, for what was
allocated since (lazy imports, the figures before a fork): a forked child then never touches
those pages for its collector either (no copy-on-write of the whole heap).

:func:`collector_paused` keeps the collector off while modules are imported (the command's
start-up, matplotlib before the first figure): an import makes objects that stay alive, and the
full passes it would trigger only walk them. Inside :func:`frozen_heap` they are frozen as the
block ends; otherwise the first pass after it walks them all once (0.03 s after matplotlib's
import, of the HTML report's 0.9 s).
"""

from __future__ import annotations

import gc
import threading
from collections.abc import Iterator
from contextlib import contextmanager

_lock = threading.Lock()
_depth = 0


@contextmanager
def frozen_heap() -> Iterator[None]:
    """Within the block the collector skips the objects alive at its start (see module docs)."""
    global _depth
    with _lock:
        gc.freeze()
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                gc.unfreeze()


@contextmanager
def collector_paused() -> Iterator[None]:
    """Within the block the cyclic collector is off; after it, as it was (see module docs).
    Inside :func:`frozen_heap`, what the block made joins the frozen objects as it ends: the
    first pass after an import would otherwise walk every object the import made."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        freeze_more()
        if enabled:
            gc.enable()


def freeze_more() -> None:
    """Inside :func:`frozen_heap`: let the collector skip what was allocated since, too
    (outside it nothing happens, so nothing stays frozen after a report)."""
    with _lock:
        if _depth:
            gc.freeze()
