"""crankdyn: the dynamic calculation of crank mechanisms and piston engines.

The public Python API (see docs/api.md): :func:`crankdyn.load`, :func:`crankdyn.run`
(returning a :class:`crankdyn.Result`) and :func:`crankdyn.sweep`, defined in
:mod:`crankdyn.api`; :func:`crankdyn.example_path`, the path of a bundled example scene; and the
``crankdyn`` command line. The lower-level entry points are
:func:`crankdyn.scene.load_scene` and :func:`crankdyn.engine.orchestrator.run_scene`.
Mechanisms and analysis stages are pluggy plugins; see :mod:`crankdyn.plugin.hooks`.
"""

from .bundled import example_path
from .version import __version__

__all__ = ["load", "run", "sweep", "Result", "SceneError", "example_path", "__version__"]

_API = {"load", "run", "sweep", "Result", "SceneError"}


def __getattr__(name: str):
    # Imported on first use, so that ``import crankdyn`` (and the command line) stays light.
    if name in _API:
        from . import api  # lazy: heavy optional import (numpy, scipy: import crankdyn stays light)

        return getattr(api, name)
    raise AttributeError(f"module 'crankdyn' has no attribute {name!r}")


def __dir__() -> list[str]:
    # The lazy names are not in the module's namespace until first used; dir() lists them anyway.
    return sorted(set(globals()) | set(__all__))
