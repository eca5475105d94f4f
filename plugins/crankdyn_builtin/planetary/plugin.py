"""The ``planetary`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml).

Laid out like any third-party plugin: ``stage.py`` (run and render), ``templates/sections/``
(its section template) and ``i18n/`` (its catalogs) in this one folder.
"""

from dataclasses import replace
from pathlib import Path

from crankdyn.hookspecs import hookimpl
from crankdyn.plugin_types import Catalog

from .geometry import planetary_geometry
from .stage import PLANETARY_MECHANISM, PLANETARY_STAGE

HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [PLANETARY_STAGE]


@hookimpl
def crankdyn_mechanisms():
    # The drawing stage draws the mechanism from its geometry (see .geometry).
    return [replace(PLANETARY_MECHANISM, geometry=planetary_geometry)]


@hookimpl
def crankdyn_catalogs():
    return [Catalog(language=p.stem.rsplit(".", 1)[-1], path=p) for p in sorted((HERE / "i18n").glob("*.toml"))]
