"""crankdyn: the dynamic calculation of crank mechanisms and piston engines.

The public Python API (see docs/api.md): :func:`crankdyn.load`, :func:`crankdyn.run`
(returning a :class:`crankdyn.Result`) and :func:`crankdyn.sweep`, defined in
:mod:`crankdyn.api`; and the ``crankdyn`` command line. The lower-level entry points are
:func:`crankdyn.scene.load_scene` and :func:`crankdyn.orchestrator.run_scene`.
Mechanisms and analysis stages are pluggy plugins; see :mod:`crankdyn.hookspecs`.
"""

from .version import __version__

__all__ = ["load", "run", "sweep", "Result", "SceneError", "__version__"]

_API = {"load", "run", "sweep", "Result", "SceneError"}


def __getattr__(name: str):
    # Imported on first use, so that ``import crankdyn`` (and the command line) stays light.
    if name in _API:
        from . import api  # lazy: heavy optional import (numpy, scipy: import crankdyn stays light)

        return getattr(api, name)
    raise AttributeError(f"module 'crankdyn' has no attribute {name!r}")
