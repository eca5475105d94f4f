"""The ``torque`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml) and the
stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``compute.py`` (applies and run), ``section.py`` (render),
``figures.py`` (its figures), ``worked.py``, ``templates/sections/`` (its section template) and
``i18n/`` (its catalogs) in this one folder.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import BAY_LOADS, CRANK_LOADS, ENGINE_TORQUE, GAS_PRESSURE
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import AnswerColumn, Catalog, Stage, StagePresentation
from crankdyn.report.plausibility import mechanical_efficiency

from .compute import applies, run, run_many
from .section import SYMBOLS, render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

TORQUE_STAGE = Stage(
    name="torque",
    requires=(BAY_LOADS,),
    # one cylinder's indicated work: the slave cylinders' differs from it (articulated rods)
    uses=(GAS_PRESSURE,),
    provides=(ENGINE_TORQUE, CRANK_LOADS),
    applies=applies,
    run=run,
    run_many=run_many,
    tables=("torque",),
    plausibility=(mechanical_efficiency("mechanical_efficiency"),),
    answer_columns=(
        AnswerColumn("M_mean_Nm", "mean_Nm", "N·m", label_key="torque.answer.M_mean_Nm"),
        AnswerColumn("M_max_Nm", "max_Nm", "N·m", label_key="torque.answer.M_max_Nm"),
        AnswerColumn("M_min_Nm", "min_Nm", "N·m", label_key="torque.answer.M_min_Nm"),
        AnswerColumn(
            "torque_non_uniformity",
            "non_uniformity",
            "",
            label_key="torque.answer.torque_non_uniformity",
        ),
        AnswerColumn(
            "N_i_engine_kW",
            "indicated_power_W",
            "kW",
            factor=0.001,
            label_key="torque.answer.N_i_engine_kW",
        ),
    ),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        # the core's letters that hold with their meaning in this section only
        section_symbols=(
            "radial_specific",
            "indicated_torque",
            "crank_tangential_total",
            "crank_radial_total",
        ),
        title_key="torque.title",
        render=render,
        figures=("output_torque", "journal_torques"),
        references=("poda2007", "lukanin1995"),
        symbols=SYMBOLS,
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [TORQUE_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
