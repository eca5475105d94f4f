"""A stage is what it computes (``Stage``) and what it shows (``Stage.presentation``, a
``StagePresentation``): a stage without a presentation runs and gives its results but has no
section; the flat form (the presentation's fields given to ``Stage`` itself) is folded into a
``StagePresentation`` with a DeprecationWarning and still read back as ``stage.title_key``."""

from __future__ import annotations

import dataclasses
import re

import pytest
from conftest import example_data

from crankdyn.orchestrator import run_scene
from crankdyn.plugin_types import Stage, StageOutput, StagePresentation
from crankdyn.plugins import Registry, default_registry
from crankdyn.report.document import render_html
from crankdyn.scene import scene_from_dict

REGISTRY = default_registry()


def _run(scene, inputs):
    return StageOutput(results={"stroke_m": 2.0 * scene.engine.crank_radius_m})


def _render(output, ctx):
    return "<p>quiet section</p>"


def _stage(**fields) -> Stage:
    return Stage(
        name="quiet", requires=(), provides=(), applies=lambda scene: None, run=_run, **fields
    )


def _titles(html: str) -> list[str]:
    return re.findall(r"<h2[^>]*>(.*?)</h2>", html, flags=re.S)


def test_a_stage_without_presentation_gives_its_results_and_no_section():
    scene = scene_from_dict(example_data("kinematics-only"))
    plain = Registry(
        mechanisms=REGISTRY.mechanisms,
        catalogs=REGISTRY.catalogs,
        stages={"kinematics": REGISTRY.stages["kinematics"]},
    )
    quiet = dataclasses.replace(plain, stages={**plain.stages, "quiet": _stage()})
    result = run_scene(scene, quiet)
    assert "quiet" in [s.name for s in result.plan.order]
    # the stroke S = 2R, from the scene's own crank radius
    assert result.outputs["quiet"].results["stroke_m"] == pytest.approx(
        2.0 * scene.engine.crank_radius_m
    )
    report = render_html(result, quiet)
    assert "quiet section" not in report.linked_html
    assert _titles(report.linked_html) == _titles(
        render_html(run_scene(scene, plain), plain).linked_html
    )


def test_the_flat_form_is_folded_into_a_presentation_with_a_warning():
    with pytest.warns(DeprecationWarning, match="presentation=StagePresentation"):
        flat = _stage(title_key="quiet.title", render=_render, figures=["a"], appendix=True)
    assert flat.presentation == StagePresentation(
        title_key="quiet.title", render=_render, figures=["a"], appendix=True
    )
    new = _stage(presentation=StagePresentation(title_key="quiet.title", render=_render))
    assert new.presentation.figures == () and new.presentation.legend
    with pytest.warns(DeprecationWarning, match="Stage.title_key"):
        assert flat.title_key == "quiet.title"
    with pytest.warns(DeprecationWarning):
        assert flat.appendix is True and _stage().render is None and _stage().symbols == {}
    # dataclasses.replace with a flat field changes that field of the presentation only
    with pytest.warns(DeprecationWarning):
        other = dataclasses.replace(new, title_key="other.title")
    assert other.presentation.title_key == "other.title" and other.presentation.render is _render
    assert other.name == "quiet" and other.run is _run


def test_the_flat_form_names_what_it_misses_and_refuses_unknown_fields():
    with pytest.warns(DeprecationWarning), pytest.raises(TypeError, match="'quiet'.*render"):
        _stage(title_key="quiet.title")
    with pytest.raises(TypeError, match="'colour'"):
        _stage(colour="red")
