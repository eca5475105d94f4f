"""The ``vane`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml) and the
stage assembled from what computes and what presents.

Laid out like any third-party plugin: ``options.py`` (the scene table's options model),
``compute.py`` (applies and run), ``section.py`` (render), ``figures.py`` (its figures),
``geometry.py``, ``worked.py``, ``templates/sections/`` (its section template) and ``i18n/`` (its
catalogs) in this one folder.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import Catalog, Mechanism, Stage, StagePresentation

from .compute import MECHANISM, applies, check, run
from .geometry import vane_geometry
from .options import VaneParams
from .section import SYMBOLS, render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

VANE_MECHANISM = Mechanism(
    name=MECHANISM,
    summary="vane engine with a crank-rocker parallelogram converting mechanism (kinematics only)",
    check=check,
    params_model=VaneParams,
    # the task's stroke is the slider's travel, its rod the core's tail (the section's own S, r, l, λ)
    input_rows={
        "stroke": ("vane.input_stroke", "<i>S</i>"),
        "crank_radius": ("vane.input_radius", "<i>r</i> = <i>S</i>/2"),
        "rod_length": ("vane.input_tail", "<i>l</i>"),
        "rod_ratio": ("vane.input_ratio", "<i>λ</i> = <i>r</i>/<i>l</i>"),
    },
)

VANE_STAGE = Stage(
    name="vane",
    requires=(),
    provides=(),
    applies=applies,
    run=run,
    tables=("vane", "compare", "by_lambda"),
    presentation=StagePresentation(
        template_dir=TEMPLATES,
        title_key="vane.title",
        render=render,
        figures=(
            "vane_angles",
            "vane_core",
            "vane_rocker",
            "vane_slider",
            "vane_relative",
            "vane_lambda",
        ),
        references=("klementev2023",),
        symbols=SYMBOLS,
    ),
)


HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [VANE_STAGE]


@hookimpl
def crankdyn_mechanisms():
    # The drawing stage draws the mechanism from its geometry (see .geometry).
    return [replace(VANE_MECHANISM, geometry=vane_geometry)]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
