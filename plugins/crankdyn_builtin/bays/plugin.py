"""The ``bays`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml).

Laid out like any third-party plugin: ``compute.py`` (run), ``section.py`` and ``figures.py``
(render), ``templates/sections/`` (its section template) and ``i18n/`` (its catalogs) in this one
folder; here the Stage is assembled from them. Its scene table, ``[articulated]``, is the core's
:class:`crankdyn.plugin.contracts.ArticulatedOptions`.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import (
    BAY_LOADS,
    FORCES,
    GAS_PRESSURE,
    KINEMATICS,
    ArticulatedOptions,
)
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import Catalog, Stage, StagePresentation

from .compute import ARTICULATED, applies, run
from .section import SYMBOLS, input_rows, render, taken_rows

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"


BAYS_STAGE = Stage(
    name="bays",
    requires=(KINEMATICS, GAS_PRESSURE, FORCES),
    provides=(BAY_LOADS,),
    applies=applies,
    run=run,
    tables=("bay", "slave_*"),
    options_table=ARTICULATED,
    options_model=ArticulatedOptions,
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        # the core's letters that hold with their meaning in this section only
        section_symbols=(
            "radial_specific",
            "centrifugal_force",
            "rod_specific",
            "side_specific",
            # the sums over the crank's cylinders, one meaning with the torque section's
            "crank_tangential_total",
            "crank_radial_total",
        ),
        title_key="bays.title",
        render=render,
        input_rows=input_rows,
        taken_rows=taken_rows,
        figures=("plan", "bay"),
        references=("poda2007", "kolchin2002"),
        symbols=SYMBOLS,
    ),
)

HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [BAYS_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
