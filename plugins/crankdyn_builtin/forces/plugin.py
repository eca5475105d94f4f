"""The ``forces`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml) and the
stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``compute.py`` (applies and run), ``section.py`` (render),
``figures.py`` (its figures), ``worked.py``, ``templates/sections/`` (its section template) and
``i18n/`` (its catalogs) in this one folder.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import FORCES, GAS_PRESSURE, KINEMATICS
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import AnswerColumn, Catalog, Stage, StagePresentation
from crankdyn.report.plausibility import mechanical_efficiency

from .compute import applies, run, run_many
from .section import render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

FORCES_STAGE = Stage(
    name="forces",
    requires=(KINEMATICS, GAS_PRESSURE),
    provides=(FORCES,),
    applies=applies,
    run=run,
    run_many=run_many,
    tables=("forces",),
    plausibility=(mechanical_efficiency("mechanical_efficiency"),),
    answer_columns=(
        AnswerColumn(
            "p_j_tdc_MPa",
            "inertia_tdc_Pa",
            "MPa",
            factor=1e-06,
            label_key="forces.answer.p_j_tdc_MPa",
        ),
        AnswerColumn(
            "c_MPa", "centrifugal_Pa", "MPa", factor=1e-06, label_key="forces.answer.c_MPa"
        ),
        AnswerColumn(
            "t_max_MPa",
            "tangential_max_Pa",
            "MPa",
            factor=1e-06,
            label_key="forces.answer.t_max_MPa",
        ),
        AnswerColumn(
            "z_min_MPa", "radial_min_Pa", "MPa", factor=1e-06, label_key="forces.answer.z_min_MPa"
        ),
        AnswerColumn(
            "q_max_MPa",
            "resultant_max_Pa",
            "MPa",
            factor=1e-06,
            label_key="forces.answer.q_max_MPa",
        ),
        AnswerColumn(
            "M_cylinder_mean_Nm",
            "mean_torque_Nm",
            "N·m",
            label_key="forces.answer.M_cylinder_mean_Nm",
        ),
        AnswerColumn(
            "M_cylinder_max_Nm", "torque_max_Nm", "N·m", label_key="forces.answer.M_cylinder_max_Nm"
        ),
    ),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        # the core's letters that hold with their meaning in this section only
        section_symbols=(
            "radial_specific",
            "centrifugal_force",
            "rod_specific",
            "side_specific",
            "indicated_torque",
        ),
        title_key="forces.title",
        render=render,
        figures=("forces", "torque"),
        references=("poda2007", "popyk1970", "kolchin2002"),
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [FORCES_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
