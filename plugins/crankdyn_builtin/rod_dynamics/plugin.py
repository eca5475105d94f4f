"""The ``rod_dynamics`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml)
and the stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``compute.py`` (applies and run), ``section.py`` (render),
``figures.py`` (its figures), ``worked.py``, ``templates/sections/`` (its section template) and
``i18n/`` (its catalogs) in this one folder.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import KINEMATICS, RodDynamicsOptions
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import Catalog, Stage, StagePresentation

from .compute import applies, run
from .section import SYMBOLS, input_rows, render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

ROD_DYNAMICS_STAGE = Stage(
    name="rod_dynamics",
    requires=(KINEMATICS,),
    provides=(),
    applies=applies,
    run=run,
    tables=("rod_dynamics",),
    options_table="rod_dynamics",
    options_model=RodDynamicsOptions,
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        title_key="rod_dynamics.title",
        render=render,
        figures=("rod_motion", "rod_torque"),
        references=("poda2007",),
        symbols=SYMBOLS,
        input_rows=input_rows,
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [ROD_DYNAMICS_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
