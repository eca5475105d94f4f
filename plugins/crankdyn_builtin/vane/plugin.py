"""The ``vane`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml).

Laid out like any third-party plugin: ``stage.py`` (run and render), ``templates/sections/``
(its section template) and ``i18n/`` (its catalogs) in this one folder.
"""

from dataclasses import replace
from pathlib import Path

from crankdyn.hookspecs import hookimpl
from crankdyn.plugin_types import Catalog

from .geometry import vane_geometry
from .stage import VANE_MECHANISM, VANE_STAGE

HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [VANE_STAGE]


@hookimpl
def crankdyn_mechanisms():
    # The drawing stage draws the mechanism from its geometry (see .geometry).
    return [replace(VANE_MECHANISM, geometry=vane_geometry)]


@hookimpl
def crankdyn_catalogs():
    return [Catalog(language=p.stem.rsplit(".", 1)[-1], path=p) for p in sorted((HERE / "i18n").glob("*.toml"))]
