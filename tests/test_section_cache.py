"""The live preview's section cache: a save re-renders only the sections whose stage output or
scene reads changed, and the page it gives is the page a fresh rendering of the saved scene gives."""

from __future__ import annotations

import re

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.engine.stage_cache import StageCache
from crankdyn.plugin.registry import default_registry
from crankdyn.report.context import draw_figures
from crankdyn.report.document import render_html
from crankdyn.report.section_cache import SectionCache
from crankdyn.scene.model import load_scene

REGISTRY = default_registry()
STAGES = [
    "forces"
]  # kinematics, indicator, forces; no timed section, so two renderings can be equal


def _without_run_times(html: str) -> str:
    """The page with the stages' run times (a table of measured milliseconds) blanked."""
    return re.sub(
        r'(<td class="text" style="text-align:left">[^<]*</td><td>)[^<]*(</td>)', r"\1…\2", html
    )


def _scene(**overrides):
    return load_scene(examples_dir() / "petrol-1cyl.toml", overrides or None)


def _build(scene, stages: StageCache, sections: SectionCache):
    result = run_scene(scene, REGISTRY, STAGES, cache=stages)
    rendered = render_html(result, REGISTRY, sections_cache=sections)
    draw_figures(rendered.figures, workers=1)
    return rendered


def test_a_mass_edit_re_renders_only_the_sections_it_changes_and_gives_the_fresh_page():
    stages, sections = StageCache(), SectionCache()
    first = _build(_scene(), stages, sections)
    assert sections.renders == {"kinematics": 1, "indicator": 1, "forces": 1}
    edited_scene = _scene(masses={"rod": "0.7 kg"})
    edited = _build(edited_scene, stages, sections)
    assert sections.renders == {"kinematics": 1, "indicator": 1, "forces": 2}
    kept = {f.name: f for f in first.figures}
    for figure in edited.figures:  # the kept sections' figures are the drawn objects themselves
        if figure.name.startswith(("fig_2_", "fig_3_")):
            assert figure is kept[figure.name]
        else:
            assert figure is not kept.get(figure.name)
    fresh = render_html(run_scene(edited_scene, REGISTRY, STAGES), REGISTRY)
    draw_figures(fresh.figures, workers=1)
    assert _without_run_times(edited.linked_html) == _without_run_times(fresh.linked_html)
    assert [(f.name, f.svg) for f in edited.figures] == [(f.name, f.svg) for f in fresh.figures]


def test_a_change_a_section_reads_in_rendering_only_re_renders_it():
    # report.worked_angle_deg: no stage's run reads it, the sections with worked substitutions do
    stages, sections = StageCache(), SectionCache()
    _build(_scene(), stages, sections)
    edited_scene = _scene(report={"worked_angle_deg": 60.0})
    edited = _build(edited_scene, stages, sections)
    assert stages.runs == {"kinematics": 1, "indicator": 1, "forces": 1}
    assert sections.renders["kinematics"] == 2
    fresh = render_html(run_scene(edited_scene, REGISTRY, STAGES), REGISTRY)
    assert _without_run_times(edited.linked_html) == _without_run_times(fresh.linked_html)


def test_another_language_renders_every_section_again():
    stages, sections = StageCache(), SectionCache()
    _build(_scene(), stages, sections)
    _build(_scene(report={"language": "uk"}), stages, sections)
    assert sections.renders == {"kinematics": 2, "indicator": 2, "forces": 2}


def test_the_preview_builds_each_sections_figures_as_the_section_is_rendered(examples):
    """The page's placeholders need each figure's size: the preview builds the figures given as
    builders while it renders (and the worker computes the study of the last section), not after."""
    from crankdyn.engine.stage_cache import StageCache
    from crankdyn.output.pipeline import run_for_preview
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.i18n import available_languages
    from crankdyn.report.section_cache import SectionCache
    from crankdyn.scene.model import load_scene

    registry = default_registry()
    _, rendered, _ = run_for_preview(
        load_scene(examples / "kinematics-only.toml"),
        registry,
        None,
        available_languages(),
        StageCache(),
        SectionCache(),
    )
    assert rendered.figures and all(f._figure is not None for f in rendered.figures)
    assert not any(f.drawn for f in rendered.figures)  # built, not drawn: the page is shown first


def test_a_section_that_reads_a_later_stages_data_is_rendered_again_when_it_changes():
    """The drawing section shows the counterweights the balancing stage fits: the cache keeps the
    section while the run's counterweights are the same objects and renders it again when the
    balancing stage gives new ones (an edit that changes them)."""
    from dataclasses import replace as _replace

    from crankdyn.plugin.contracts import COUNTERWEIGHTS
    from crankdyn.report.document import _render_context

    result = run_scene(_scene(), REGISTRY)
    drawing = REGISTRY.stages["drawing"]
    sections = SectionCache()
    ctx = _render_context(result, REGISTRY, "en")
    fitted = ctx.run_data[COUNTERWEIGHTS]
    assert len(fitted.crank) == 1  # a single cylinder: one counterweight, drawn on its crank
    output = result.outputs["drawing"]
    first = sections.render(drawing, output, ctx)
    assert "counterweight" in first
    sections.render(drawing, output, ctx)
    assert sections.renders["drawing"] == 1
    ctx.run_data[COUNTERWEIGHTS] = _replace(
        fitted,
        crank=fitted.crank[:0],
        centrifugal_N=fitted.centrifugal_N[:0],
        angle_from_crank_rad=fitted.angle_from_crank_rad[:0],
    )
    again = sections.render(drawing, output, ctx)
    assert sections.renders["drawing"] == 2 and "counterweight" not in again
