"""Stage planning: order from requires/provides, prerequisites, skip reasons, duplicates."""

from __future__ import annotations

import random

import pytest
from conftest import example_data

from crankdyn.engine.orchestrator import plan, run_plan, run_scene
from crankdyn.errors import PluginError, SceneError
from crankdyn.plugin.hooks import hookimpl
from crankdyn.plugin.registry import Registry, collect, default_registry, plugin_manager
from crankdyn.plugin.types import Stage, StageOutput, StagePresentation
from crankdyn.scene.model import scene_from_dict


def _stage(name, requires=(), provides=(), applies=None, default=True):
    return Stage(
        name=name,
        requires=tuple(requires),
        provides=tuple(provides),
        applies=applies or (lambda scene: None),
        run=lambda scene, inputs, p=tuple(provides): StageOutput(
            data={k: (name, dict(inputs)) for k in p}
        ),
        default=default,
        presentation=StagePresentation(title_key=name, render=lambda output, ctx: ""),
    )


@pytest.fixture
def scene():
    return scene_from_dict(example_data("petrol-1cyl"))


def _registry(stages):
    reg = Registry()
    for s in stages:
        reg.stages[s.name] = s
    return reg


def test_order_follows_requires_not_registration(scene):
    stages = [
        _stage("c", requires=["b_out"], provides=["c_out"]),
        _stage("a", provides=["a_out"]),
        _stage("b", requires=["a_out"], provides=["b_out"]),
        _stage("d", requires=["a_out", "c_out"]),
    ]
    for seed in range(5):
        random.Random(seed).shuffle(stages)
        order = [s.name for s in plan(scene, _registry(stages)).order]
        assert order == ["a", "b", "c", "d"]


def test_requested_stage_pulls_prerequisites_and_leaves_rest_out(scene):
    stages = [_stage("a", provides=["x"]), _stage("b", requires=["x"], provides=["y"]), _stage("z")]
    p = plan(scene, _registry(stages), requested=["b"])
    assert [s.name for s in p.order] == ["a", "b"]
    assert p.skipped == {"z": "not requested"}


def test_inapplicable_stage_and_its_dependants_are_left_out_with_reasons(scene):
    stages = [
        _stage("gas", provides=["p"], applies=lambda s: "no cycle data"),
        _stage("force", requires=["p"], provides=["f"]),
        _stage("kin", provides=["k"]),
    ]
    p = plan(scene, _registry(stages))
    assert [s.name for s in p.order] == ["kin"]
    assert p.skipped["gas"] == "no cycle data"
    assert "needs 'p'" in p.skipped["force"] and "no cycle data" in p.skipped["force"]


def test_optional_stage_runs_only_on_request(scene):
    stages = [_stage("base", provides=["b"]), _stage("extra", requires=["b"], default=False)]
    assert [s.name for s in plan(scene, _registry(stages)).order] == ["base"]
    assert [s.name for s in plan(scene, _registry(stages), requested=["extra"]).order] == [
        "base",
        "extra",
    ]


def test_two_providers_of_one_key_is_an_error(scene):
    stages = [_stage("a", provides=["x"]), _stage("b", provides=["x"])]
    with pytest.raises(PluginError, match="provide 'x'"):
        plan(scene, _registry(stages))


def test_cycle_is_an_error(scene):
    stages = [
        _stage("a", requires=["y"], provides=["x"]),
        _stage("b", requires=["x"], provides=["y"]),
    ]
    with pytest.raises(PluginError, match="cycle"):
        plan(scene, _registry(stages))


def test_unknown_requested_stage(scene):
    with pytest.raises(SceneError, match="unknown stage"):
        plan(scene, _registry([_stage("a")]), requested=["nope"])


def test_stage_must_return_what_it_provides(scene):
    bad = Stage(
        name="bad",
        requires=(),
        provides=("x",),
        applies=lambda s: None,
        run=lambda scene, inputs: StageOutput(data={}),
        presentation=StagePresentation(title_key="bad", render=lambda o, c: ""),
    )
    with pytest.raises(PluginError, match="declared provides"):
        run_plan(scene, plan(scene, _registry([bad])))


def test_data_flows_between_stages(scene):
    stages = [_stage("a", provides=["x"]), _stage("b", requires=["x"], provides=["y"])]
    result = run_plan(scene, plan(scene, _registry(stages)))
    assert result.outputs["b"].data["y"] == ("b", {"x": ("a", {})})
    assert set(result.timing_s) == {"a", "b"}


class _DuplicatePlugin:
    @hookimpl
    def crankdyn_stages(self):
        return [_stage("kinematics", provides=["kinematics"])]


def test_duplicate_stage_names_across_plugins_are_rejected():
    with pytest.raises(PluginError, match="duplicate stage name 'kinematics'"):
        collect(plugin_manager(extra_plugins=[_DuplicatePlugin()]))


class _WrongTypePlugin:
    @hookimpl
    def crankdyn_mechanisms(self):
        return ["not a mechanism"]


def test_hook_must_return_typed_objects():
    registry = collect(plugin_manager(extra_plugins=[_WrongTypePlugin()]))
    (message,) = registry.broken.values()  # left out and named, the other plugins kept
    assert (
        "(hook crankdyn_mechanisms): the hook returned 'not a mechanism'; expected Mechanism"
        in message
    )
    assert message.startswith("plugin 'test_orchestrator._WrongTypePlugin' ")
    assert "crank_slider" in registry.mechanisms


def test_builtins_register_through_entry_points():
    registry = default_registry()
    assert {"kinematics", "indicator", "forces"} <= set(registry.stages)
    assert "crank_slider" in registry.mechanisms
    # Registered by name from the entry-point group, the way a third-party plugin is.
    assert registry.owner["stage:kinematics"] == "builtin_kinematics"
    assert registry.owner["mechanism:crank_slider"] == "builtin_crank_slider"


def test_real_pipeline_orders_and_skips(scene):
    registry = default_registry()
    result = run_scene(scene, registry)
    assert result.stages_run == [
        "kinematics",
        "drawing",
        "indicator",
        "forces",
        "bays",
        "torque",
        "balancing",
        "bearings",
        "numerics",
    ]
    kin_only = scene_from_dict(example_data("kinematics-only"))
    result = run_scene(kin_only, registry)
    assert result.stages_run == ["kinematics", "drawing", "numerics_kinematics"]
    assert "no [cycle] data" in result.plan.skipped["indicator"]
