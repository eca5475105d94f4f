"""The ``indicator`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml) and
the stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``compute.py`` (applies and run), ``section.py`` (render),
``figures.py`` (its figures), ``worked.py``, ``templates/sections/`` (its section template) and
``i18n/`` (its catalogs) in this one folder.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import GAS_PRESSURE, KINEMATICS
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import (
    AnswerColumn,
    Catalog,
    PlausibilityRule,
    Stage,
    StagePresentation,
)
from crankdyn.report.plausibility import peak_pressure

from .compute import _diesel_peak, _mean_pressure_check, _peak_lowered, applies, run, run_many
from .section import SYMBOLS, render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

INDICATOR_STAGE = Stage(
    plausibility=(
        peak_pressure("max_pressure_Pa"),
        PlausibilityRule("diesel_peak", _diesel_peak),
        PlausibilityRule("mean_pressure_check", _mean_pressure_check),
        PlausibilityRule("peak_lowered", _peak_lowered),
    ),
    name="indicator",
    requires=(KINEMATICS,),
    provides=(GAS_PRESSURE,),
    applies=applies,
    run=run,
    run_many=run_many,
    tables=("indicator",),
    answer_columns=(
        AnswerColumn(
            "p_c_MPa",
            "compression_end_pressure_Pa",
            "MPa",
            factor=1e-06,
            label_key="indicator.answer.p_c_MPa",
        ),
        AnswerColumn(
            "p_max_MPa",
            "max_pressure_Pa",
            "MPa",
            factor=1e-06,
            label_key="indicator.answer.p_max_MPa",
        ),
        AnswerColumn(
            "p_max_crank_angle_deg",
            "max_pressure_crank_angle_deg",
            "°",
            label_key="indicator.answer.p_max_crank_angle_deg",
        ),
        AnswerColumn(
            "p_i_MPa",
            "mean_indicated_pressure_Pa",
            "MPa",
            factor=1e-06,
            label_key="indicator.answer.p_i_MPa",
        ),
        AnswerColumn("L_i_J", "indicated_work_J", "J", label_key="indicator.answer.L_i_J"),
        AnswerColumn(
            "N_i_cylinder_kW",
            "indicated_power_W",
            "kW",
            factor=0.001,
            label_key="indicator.answer.N_i_cylinder_kW",
        ),
    ),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        title_key="indicator.title",
        render=render,
        figures=("pV", "p_alpha"),
        references=("poda2007", "orlin1983", "heywood1988", "kolchin2002"),
        symbols=SYMBOLS,
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [INDICATOR_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
