"""The ``speed_fluctuation`` plugin: the hooks the ``crankdyn`` entry point names (see
pyproject.toml) and the stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``options.py`` (the ``[torsion]`` options model),
``compute.py`` (applies, run and the single-mass model), ``section.py`` (render), ``figures.py``
(its figures), ``torsion.py`` (the torsional shaft model), ``solvers.py`` (the records of the
solver studies), ``torsion_section.py`` (the torsion part of the section), ``solver_text.py`` (how
the solver studies are written), ``worked.py``, ``templates/sections/`` (its section template) and
``i18n/`` (its catalogs) in this one folder.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import BAY_LOADS, CRANK_LOADS, ENGINE_TORQUE, FLYWHEEL
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import Catalog, Stage, StagePresentation

from .compute import applies, run
from .options import TorsionOptions
from .section import SYMBOLS, input_rows, render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

SPEED_FLUCTUATION_STAGE = Stage(
    name="speed_fluctuation",
    requires=(ENGINE_TORQUE, BAY_LOADS, CRANK_LOADS, FLYWHEEL),
    provides=(),
    applies=applies,
    run=run,
    tables=("speed_fluctuation", "torsion"),
    options_table="torsion",
    options_model=TorsionOptions,
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        # the core's letters that hold with their meaning in this section only
        section_symbols=("irregularity",),
        title_key="speed_fluctuation.title",
        render=render,
        figures=("speed", "solvers_single", "modes", "campbell", "torsion", "solvers_torsion"),
        references=("denhartog1956",),
        references_full=("hairer1996", "scipy2020"),
        symbols=SYMBOLS,
        input_rows=input_rows,
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [SPEED_FLUCTUATION_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
