"""The ``drawing`` plugin: the hooks the ``crankdyn`` entry point names (see pyproject.toml).

Laid out like any third-party plugin: ``compute.py`` (run: the positions drawn), ``section.py``
(render), ``templates/sections/`` (its section template) and ``i18n/`` (its catalogs) in this one
folder; here the two Stages are assembled from them.
"""

from __future__ import annotations

from pathlib import Path

from crankdyn.plugin.contracts import KINEMATICS
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.types import SERVICE_RUNNER, Catalog, Stage, StagePresentation

from .compute import applies, applies_linkage, run
from .section import render

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"


#: The two stages' one section, drawn from what their one ``run`` computed.
_PRESENTATION = StagePresentation(
    title_key="drawing.title",
    render=render,
    template_dir=TEMPLATES,
    references=("poda2007",),
    figures=("scheme", "positions", "positions_*"),
)

DRAWING_STAGE = Stage(
    name="drawing",
    requires=(KINEMATICS,),
    provides=(),
    applies=applies,
    run=run,
    services=(SERVICE_RUNNER,),
    presentation=_PRESENTATION,
)
# After the mechanism's own section (nothing orders it: it requires no data).
LINKAGE_DRAWING_STAGE = Stage(
    name="drawing_linkage",
    requires=(),
    provides=(),
    applies=applies_linkage,
    run=run,
    services=(SERVICE_RUNNER,),
    last=True,
    presentation=_PRESENTATION,
)

HERE = Path(__file__).resolve().parent


@hookimpl
def crankdyn_stages():
    return [DRAWING_STAGE, LINKAGE_DRAWING_STAGE]


@hookimpl
def crankdyn_catalogs():
    return [
        Catalog(language=p.stem.rsplit(".", 1)[-1], path=p)
        for p in sorted((HERE / "i18n").glob("*.toml"))
    ]
