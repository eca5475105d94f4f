"""The ``offset_crank`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml)
and the stage assembled from what computes and what presents.

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
from crankdyn.report.plausibility import ROD_CENTRE_OF_MASS, ROD_RATIO

from .compute import MECHANISM, applies, check, run
from .geometry import offset_geometry
from .options import OffsetParams
from .section import MECHANISM_INPUT_ROWS, SYMBOLS, input_rows, render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

OFFSET_CRANK_MECHANISM = Mechanism(
    name=MECHANISM,
    summary="offset (desaxial) crank-slider mechanism: the cylinder axis passes the crankshaft axis at a "
    "distance e (the pin offset)",
    check=check,
    params_model=OffsetParams,
    input_rows=MECHANISM_INPUT_ROWS,
    # λ = R/L and the rod's centre of mass hold as for the central crank-slider
    plausibility=(ROD_RATIO, ROD_CENTRE_OF_MASS),
)

OFFSET_CRANK_STAGE = Stage(
    name="offset_crank",
    requires=(),
    provides=(KINEMATICS,),
    applies=applies,
    run=run,
    tables=("offset_crank",),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        title_key="offset_crank.title",
        render=render,
        input_rows=input_rows,
        figures=("offset_piston", "offset_rod"),
        references=("poda2007",),
        symbols=SYMBOLS,
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [OFFSET_CRANK_STAGE]


@hookimpl
def crankdyn_mechanisms():
    # The drawing stage draws the mechanism from its geometry (see .geometry).
    return [replace(OFFSET_CRANK_MECHANISM, geometry=offset_geometry)]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
