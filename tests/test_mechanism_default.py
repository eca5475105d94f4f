"""The mechanism of a scene that names none is the one the plugins declare the default
(``Mechanism(default=True)``), read from the run's registry: the core's scene model names none."""

from __future__ import annotations

import types

import pytest
from conftest import modified

from crankdyn.engine.orchestrator import check_scene, run_scene
from crankdyn.errors import MISSING, PluginError, SceneError
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.registry import collect, default_registry, plugin_manager
from crankdyn.plugin.types import Mechanism
from crankdyn.scene.model import Engine, scene_from_dict

#: a kinematics-only scene naming no mechanism
UNNAMED = modified("kinematics-only", {"engine": {"mechanism": None}})


def _mechanisms_plugin(name: str, *mechanisms: Mechanism) -> types.ModuleType:
    module = types.ModuleType(name)
    module.crankdyn_mechanisms = hookimpl(lambda: list(mechanisms))
    return module


def test_the_scene_model_declares_no_default_mechanism():
    assert Engine.model_fields["mechanism"].default is None
    assert scene_from_dict(UNNAMED).engine.mechanism is None  # no registry: nothing to choose


def test_the_built_in_crank_slider_is_the_default_and_stays_not_given():
    registry = default_registry()
    assert registry.default_mechanism == "crank_slider"
    assert [m.name for m in registry.mechanisms.values() if m.default] == ["crank_slider"]
    scene = scene_from_dict(UNNAMED, registry=registry)
    assert scene.engine.mechanism == "crank_slider"
    assert "mechanism" not in scene.engine.model_fields_set
    named = scene_from_dict(
        modified("kinematics-only", {"engine": {"mechanism": "planetary"}}), registry=registry
    )
    assert named.engine.mechanism == "planetary"  # a named mechanism is kept


def test_the_orchestrator_chooses_it_when_the_scene_was_read_without_a_registry():
    result = run_scene(scene_from_dict(UNNAMED), default_registry(), ["kinematics"])
    assert result.scene.engine.mechanism == "crank_slider"
    assert result.stages_run == ["kinematics"]


def test_another_plugin_may_declare_the_default():
    """A registry of one third-party mechanism: its scenes that name none get it."""
    own = Mechanism("own_linkage", "a linkage of a plugin", default=True, needs_rod=False)
    registry = collect(
        plugin_manager(extra_plugins=[_mechanisms_plugin("own", own)], entry_points=False)
    )
    assert registry.default_mechanism == "own_linkage"
    data = modified(
        "kinematics-only", {"engine": {"mechanism": None, "rod_ratio": None, "rod_length": None}}
    )
    scene = scene_from_dict(data, registry=registry)
    assert scene.engine.mechanism == "own_linkage"
    check_scene(scene, registry)


def test_a_registry_without_a_default_asks_the_scene_for_its_mechanism():
    plain = Mechanism("plain_linkage", "a linkage that is nobody's default")
    registry = collect(
        plugin_manager(extra_plugins=[_mechanisms_plugin("plain", plain)], entry_points=False)
    )
    assert registry.default_mechanism is None
    with pytest.raises(SceneError) as refused:
        check_scene(scene_from_dict(UNNAMED, registry=registry), registry)
    (problem,) = refused.value.problems
    assert problem.field == "engine.mechanism" and problem.value is MISSING
    assert "no installed mechanism is the default; installed: plain_linkage" in problem.allowed


def test_two_defaults_are_a_plugin_error_naming_both():
    second = Mechanism("second_slider", "a second default", default=True)
    manager = plugin_manager(extra_plugins=[_mechanisms_plugin("second", second)])
    with pytest.raises(PluginError, match="more than one mechanism declares itself the default"):
        collect(manager)
    with pytest.raises(PluginError, match="'second_slider' \\('second'\\)"):
        collect(manager)
