"""scipy's subpackages imported on first use, not when a physics module is imported.

``scipy.optimize`` and ``scipy.integrate`` take about 0.25 s to import. A report's process
validates the scene and renders the sections with the physics modules imported, while the
stages that call scipy may run in another process (:mod:`crankdyn.pipeline`); a module-level
``from scipy import optimize`` made every process pay for the import all the same.
"""

from __future__ import annotations

import importlib
from types import ModuleType


class LazyModule:
    """Stands for the module ``name``: the first attribute asked for imports it."""

    def __init__(self, name: str) -> None:
        self._name = name
        self._module: ModuleType | None = None

    def __getattr__(self, attribute: str):
        return getattr(self.load(), attribute)

    def load(self) -> ModuleType:
        """The module, imported now if it was not yet."""
        if self._module is None:
            self._module = importlib.import_module(self._name)
        return self._module

    def __repr__(self) -> str:
        return f"LazyModule({self._name!r}, imported={self._module is not None})"


optimize = LazyModule("scipy.optimize")
integrate = LazyModule("scipy.integrate")
linalg = LazyModule("scipy.linalg")


def import_all() -> None:
    """Import every module above now: before a stage's clock starts, so that the stage that calls
    scipy first is not timed with scipy's import (the report's table of run times)."""
    for module in (optimize, integrate, linalg):
        module.load()
