"""The ``balancing`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml).

Laid out like any third-party plugin: ``options.py`` (its scene table), ``vectors.py`` and
``means.py`` (the physics it assembles), ``compute.py`` (applies and run), ``tables.py``,
``section.py`` and ``figures.py`` (render), ``worked.py`` (the worked checks),
``templates/sections/`` (its section template) and ``i18n/`` (its catalogs) in this one folder;
here the Stage is assembled from them.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import (
    COUNTERWEIGHTS,
    ENGINE_TORQUE,
    KINEMATICS,
)
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import Catalog, PlausibilityRule, Stage, StagePresentation

from .compute import applies, better_firing, failed_check, rod_offset_against_pin, run
from .notation import SYMBOLS
from .options import BalancingOptions
from .section import input_rows, render, taken_rows

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"


BALANCING_STAGE = Stage(
    name="balancing",
    requires=(KINEMATICS,),
    uses=(ENGINE_TORQUE,),
    provides=(COUNTERWEIGHTS,),
    applies=applies,
    run=run,
    tables=("balancing",),
    options_table="balancing",
    options_model=BalancingOptions,
    plausibility=(
        PlausibilityRule("rod_offset_pin", rod_offset_against_pin),
        PlausibilityRule("check_failed", failed_check),
        PlausibilityRule("better_firing", better_firing),
    ),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        # the core's letters that hold with their meaning in this section only
        section_symbols=(
            "centrifugal_force",
            "harmonic_order",
            "shaft_angle",
            "crank_lag",
            "cylinder_axis_angle",
            "cylinder_position",
            "bay_forward_first",
            "bay_backward_first",
            "bay_forward_second",
            "bay_backward_second",
            "bay_semi_axis_x_first",
            "bay_semi_axis_y_first",
            "bay_semi_axis_x_second",
            "bay_semi_axis_y_second",
            "cylinder_spacing",
        ),
        title_key="balancing.title",
        render=render,
        input_rows=input_rows,
        taken_rows=taken_rows,
        figures=("crank_diagrams", "vector_models"),
        symbols=SYMBOLS,
        references=("poda2007", "lukanin1995", "taylor1985"),
    ),
)

HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [BALANCING_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
