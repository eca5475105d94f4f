"""Many scenes from one: the batch of variants (:mod:`crankdyn.batch.variants`), the sweep over
a grid (:mod:`crankdyn.batch.sweep`, :mod:`crankdyn.batch.grid_run`,
:mod:`crankdyn.batch.sweep_plot`) and the answer key read from the results
(:mod:`crankdyn.batch.answer_key`).

``crankdyn.batch`` exports what the variants module exports (``run_batch``, ``MAX_VARIANTS``,
…), imported when first asked for, so that importing the answer key alone stays light.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from .variants import *  # noqa: F403


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    return getattr(importlib.import_module(".variants", __name__), name)
