"""The ``numerics`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml).

Laid out like any third-party plugin: ``options.py`` (its scene table), ``steps.py`` (the angle-step
study: re-runs and their timing), ``reference.py`` (the references the studies are measured
against), ``compute.py`` (applies and run), ``section.py`` and ``figures.py`` (render),
``templates/sections/`` (its section templates) and ``i18n/`` (its catalogs) in this one folder;
here the two Stages are assembled from them.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import FORCES, GAS_PRESSURE, KINEMATICS
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import (
    SERVICE_ASIDE,
    SERVICE_ERROR_PROBES,
    SERVICE_RUNNER,
    Catalog,
    Stage,
    StagePresentation,
)

from .compute import applies, applies_kinematics, run, run_kinematics
from .options import NumericsOptions, default_angle_step_deg
from .section import render, render_kinematics

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"


#: the core's letters that hold with their meaning in the numerics sections only (both stages)
SECTION_SYMBOLS = (
    "studied_value",
    "total_torque",
    "series_term",
    "tangential_max",
    "tangential_min",
    "crank_load_max",
    "displacement_difference",
    "acceleration_difference",
)


NUMERICS_STAGE = Stage(
    name="numerics",
    requires=(KINEMATICS, GAS_PRESSURE, FORCES),
    last=True,
    provides=(),
    applies=applies,
    run=run,
    tables=("steps", "kinematics_forms"),
    options_table="numerics",
    options_model=NumericsOptions,
    # the default angle step keeps the peaks within [numerics] tolerance
    default_angle_step=default_angle_step_deg,
    services=(SERVICE_RUNNER, SERVICE_ERROR_PROBES, SERVICE_ASIDE),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        appendix=True,
        section_symbols=SECTION_SYMBOLS,
        title_key="numerics.title",
        render=render,
        figures=("error_vs_time", "kinematics_forms"),
        references_full=("ismailov",),
        references_sentence="numerics.sources",
    ),
)


NUMERICS_KINEMATICS_STAGE = Stage(
    name="numerics_kinematics",
    requires=(KINEMATICS,),
    provides=(),
    applies=applies_kinematics,
    run=run_kinematics,
    tables=("kinematics_forms",),
    last=True,
    services=(SERVICE_RUNNER, SERVICE_ERROR_PROBES),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        appendix=True,
        section_symbols=SECTION_SYMBOLS,
        title_key="numerics.title",
        render=render_kinematics,
        figures=("kinematics_forms",),
        references_full=("ismailov",),
        references_sentence="numerics.sources",
    ),
)

HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [NUMERICS_STAGE, NUMERICS_KINEMATICS_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
