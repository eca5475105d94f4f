"""The ``planetary`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml) and
the stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``options.py`` (the scene table's options model),
``compute.py`` (applies and run), ``section.py`` (render), ``figures.py`` (its figures),
``geometry.py``, ``worked.py``, ``templates/sections/`` (its section template) and ``i18n/`` (its
catalogs) in this one folder.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from crankdyn.plugin.contracts import KINEMATICS
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import Catalog, Mechanism, Stage, StagePresentation

from .compute import MECHANISM, applies, check, run
from .geometry import planetary_geometry
from .options import PlanetaryParams
from .section import SYMBOLS, input_rows, render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

PLANETARY_MECHANISM = Mechanism(
    name=MECHANISM,
    summary="planetary crank mechanism: the carrier is the crank, the rod's big end is on a planet gear rolling "
    "on a fixed sun gear (an epicycloid or epitrochoid) or inside a fixed ring gear "
    "(a hypocycloid or hypotrochoid)",
    check=check,
    params_model=PlanetaryParams,
    # the carrier is the crank: no R = S/2 nor λ = R/L (its radius a is in the section's data)
    input_rows={"crank_radius": None, "rod_ratio": None},
)

PLANETARY_STAGE = Stage(
    name="planetary",
    requires=(),
    provides=(KINEMATICS,),
    applies=applies,
    run=run,
    tables=("planetary", "family", "reversals"),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        title_key="planetary.title",
        render=render,
        figures=("planetary_path", "planetary_family", "planetary_motion", "planetary_arms"),
        references=("artobolevsky1988", "kudryavtsev1977", "ismailov"),
        references_sentence="planetary.sources",
        input_rows=input_rows,
        symbols=SYMBOLS,
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [PLANETARY_STAGE]


@hookimpl
def crankdyn_mechanisms():
    # The drawing stage draws the mechanism from its geometry (see .geometry).
    return [replace(PLANETARY_MECHANISM, geometry=planetary_geometry)]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
