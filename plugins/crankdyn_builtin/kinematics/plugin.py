"""The ``kinematics`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml) and
the stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``compute.py`` (applies and run), ``section.py`` (render),
``figures.py`` (its figures), ``templates/sections/`` (its section template) and ``i18n/`` (its
catalogs) in this one folder.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import KINEMATICS
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import AnswerColumn, Catalog, Stage, StagePresentation

from .compute import applies, run, run_many
from .section import render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

KINEMATICS_STAGE = Stage(
    name="kinematics",
    requires=(),
    provides=(KINEMATICS,),
    applies=applies,
    run=run,
    run_many=run_many,
    tables=("kinematics",),
    answer_columns=(
        AnswerColumn("v_max_m_s", "v_max_m_s", "m/s", label_key="kinematics.answer.v_max_m_s"),
        AnswerColumn(
            "v_max_crank_angle_deg",
            "v_max_crank_angle_deg",
            "°",
            label_key="kinematics.answer.v_max_crank_angle_deg",
        ),
        AnswerColumn(
            "v_mean_m_s", "mean_piston_speed_m_s", "m/s", label_key="kinematics.answer.v_mean_m_s"
        ),
        AnswerColumn("j_max_m_s2", "j_max_m_s2", "m/s²", label_key="kinematics.answer.j_max_m_s2"),
        AnswerColumn("j_min_m_s2", "j_min_m_s2", "m/s²", label_key="kinematics.answer.j_min_m_s2"),
        AnswerColumn(
            "j_min_crank_angle_deg",
            "j_min_crank_angle_deg",
            "°",
            label_key="kinematics.answer.j_min_crank_angle_deg",
        ),
    ),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        title_key="kinematics.title",
        render=render,
        figures=("piston", "rod", "rod_cm"),
        references=("poda2007", "artobolevsky1988", "kolchin2002"),
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [KINEMATICS_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
