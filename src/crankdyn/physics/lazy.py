"""scipy's subpackages imported on first use, not when a physics module is imported.

``scipy.optimize`` and ``scipy.integrate`` take about 0.25 s to import. A report's process
validates the scene and renders the sections with the physics modules imported, while the
stages that call scipy may run in another process (:mod:`crankdyn.output.pipeline`); a module-level
``from scipy import optimize`` would make every process pay for the import all the same. (Roots
and extremes of scalar functions need no scipy at all: :mod:`crankdyn.physics.scalar_search`.)
"""

from __future__ import annotations

import importlib
import time
from types import ModuleType

_import_seconds = 0.0  # time this process spent importing through a LazyModule


class LazyModule:
    """Stands for the module ``name``: the first attribute asked for imports it."""

    def __init__(self, name: str) -> None:
        self._name = name
        self._module: ModuleType | None = None

    def __getattr__(self, attribute: str):
        return getattr(self.load(), attribute)

    def load(self) -> ModuleType:
        """The module, imported now if it was not yet (the time it took counted in :func:`import_seconds`)."""
        global _import_seconds
        if self._module is None:
            start = time.perf_counter()
            self._module = importlib.import_module(self._name)
            _import_seconds += time.perf_counter() - start
        return self._module

    def __repr__(self) -> str:
        return f"LazyModule({self._name!r}, imported={self._module is not None})"


optimize = LazyModule("scipy.optimize")
integrate = LazyModule("scipy.integrate")
linalg = LazyModule("scipy.linalg")


def import_seconds() -> float:
    """Seconds this process has spent importing through the modules above: a stage's run time
    is given without the import its first call of scipy made (the report's table of run times)."""
    return _import_seconds
