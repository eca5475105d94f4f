"""The ``flywheel`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml).

Laid out like any third-party plugin: ``options.py`` (its scene table), ``compute.py`` (run),
``section.py`` and ``figures.py`` (render), ``worked.py`` (the worked checks),
``templates/sections/`` (its section template) and ``i18n/`` (its catalogs) in this one folder;
here the Stage is assembled from them.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import BAY_LOADS, COUNTERWEIGHTS, ENGINE_TORQUE, FLYWHEEL
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import Catalog, PlausibilityRule, Stage, StagePresentation, Symbol

from .compute import applies, propeller_rim, run
from .options import FlywheelOptions
from .section import input_rows, render, taken_rows

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"


#: The counterweights' letters (meaning: symbol.flywheel.<key>), where the balancing fits them.
SYMBOLS = {
    # the speed-fluctuation section's J(α) names it too
    "counterweight_inertia": Symbol(
        "J",
        {"en": "cw", "uk": "пр", "ru": "пр"},
        "unit.kg_m2",
        sections=("flywheel", "speed_fluctuation"),
    ),
    "balance_shaft_inertia": Symbol(
        "J",
        {"en": "bs", "uk": "зв", "ru": "ув"},
        "unit.kg_m2",
        sections=("flywheel", "speed_fluctuation"),
    ),
    "balance_shaft_mass": Symbol("m", {"en": "bs", "uk": "зв", "ru": "ув"}, "unit.kg"),
    "balance_shaft_radius": Symbol("ρ", {"en": "bs", "uk": "зв", "ru": "ув"}, "unit.mm"),
    "counterweight_mass": Symbol("m", {"en": "cw", "uk": "пр", "ru": "пр"}, "unit.kg"),
    "counterweight_radius": Symbol("ρ", {"en": "cw", "uk": "пр", "ru": "пр"}, "unit.mm"),
    # articulated rods: each cylinder's own reciprocating mass in J_m and J(α)
    "cylinder_reciprocating_mass": Symbol(
        "m",
        {"en": "s"},
        "unit.kg",
        sections=("flywheel", "speed_fluctuation"),
        html="<i>m</i><sub>{sub}<i>i</i></sub>",
    ),
    # the energy method's flywheel where the exact solution raises it: J_f is the adopted one
    "energy_flywheel_inertia": Symbol(
        "J", {"en": "f", "uk": "мах", "ru": "мах"}, "unit.kg_m2", html="<i>J</i>′<sub>{sub}</sub>"
    ),
}


FLYWHEEL_STAGE = Stage(
    name="flywheel",
    requires=(ENGINE_TORQUE, BAY_LOADS),
    uses=(COUNTERWEIGHTS,),
    provides=(FLYWHEEL,),
    applies=applies,
    run=run,
    tables=("flywheel",),
    options_table="flywheel",
    options_model=FlywheelOptions,
    plausibility=(PlausibilityRule("propeller_rim", propeller_rim),),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        # the core's letters that hold with their meaning in this section only
        section_symbols=("irregularity", "rim_mass", "rim_width", "rim_height"),
        title_key="flywheel.title",
        render=render,
        figures=("excess_work",),
        # the rim's hoop stress cites its source where a rim is sized (timoshenko1956)
        references=("poda2007", "artobolevsky1988", "khurmi2005"),
        symbols=SYMBOLS,
        input_rows=input_rows,
        taken_rows=taken_rows,
    ),
)

HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [FLYWHEEL_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
