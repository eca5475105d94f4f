"""The ``rod_dynamics`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml)
and the stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``compute.py`` (applies and run), ``section.py`` (render),
``figures.py`` (its figures), ``worked.py``, ``templates/sections/`` (its section template) and
``i18n/`` (its catalogs) in this one folder.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.contracts import KINEMATICS, RodDynamicsOptions
from crankdyn.hookspecs import hookimpl
from crankdyn.plugin_types import Catalog, Stage

from .compute import applies, run
from .section import SYMBOLS, render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

ROD_DYNAMICS_STAGE = Stage(
    template_dir=TEMPLATES,
    name="rod_dynamics",
    title_key="rod_dynamics.title",
    requires=(KINEMATICS,),
    provides=(),
    applies=applies,
    run=run,
    render=render,
    figures=("rod_motion", "rod_torque"),
    tables=("rod_dynamics",),
    references=("poda2007",),
    options_table="rod_dynamics",
    options_model=RodDynamicsOptions,
    symbols=SYMBOLS,
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [ROD_DYNAMICS_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [Catalog(language=p.stem.rsplit(".", 1)[-1], path=p) for p in sorted((HERE / "i18n").glob("*.toml"))]
