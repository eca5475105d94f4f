"""The ``bearings`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml) and
the stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``options.py`` (the scene table's options model),
``compute.py`` (applies and run), ``section.py`` (render), ``figures.py`` (the polar and wear
diagrams), ``labels.py`` (where the polar diagrams' labels go), ``worked.py``,
``templates/sections/`` (its section template) and ``i18n/`` (its catalogs) in this one folder.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import BAY_LOADS, COUNTERWEIGHTS, CRANK_LOADS, FORCES, KINEMATICS
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import Catalog, PlausibilityRule, Stage, StagePresentation

from .compute import _journals_fit, _main_pressure, _pin_pressure, applies, run
from .options import BearingOptions
from .section import SYMBOLS, input_rows, render, taken_rows

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

BEARINGS_STAGE = Stage(
    name="bearings",
    requires=(CRANK_LOADS, BAY_LOADS, KINEMATICS, FORCES),
    uses=(COUNTERWEIGHTS,),
    provides=(),
    applies=applies,
    run=run,
    tables=("bearings", "wear"),
    plausibility=(
        PlausibilityRule("pin_pressure", _pin_pressure),
        PlausibilityRule("journals_fit", _journals_fit),
        PlausibilityRule("main_pressure", _main_pressure),
    ),
    options_table="bearings",
    options_model=BearingOptions,
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        # the core's letters that hold with their meaning in this section only
        section_symbols=(
            "crank_tangential_total",
            "crank_radial_total",
            "radial_specific",
            "centrifugal_force",
            "journal_diameter",
            "bearing_width",
            "pin_load_max",
            "pin_load_mean",
            "bearing_pressure_max",
            "bearing_pressure_mean",
            "journal_load_max",
            "journal_load_mean",
        ),
        title_key="bearings.title",
        render=render,
        input_rows=input_rows,
        taken_rows=taken_rows,
        figures=("pin*", "rod_bearing*", "journal*", "main_bearing*", "wear_pin*", "unrolled"),
        references=("poda2007", "orlin1984", "kolchin2002"),
        symbols=SYMBOLS,
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [BEARINGS_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
