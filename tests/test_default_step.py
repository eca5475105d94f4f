"""The angle step from a tolerance.

A scene without ``analysis.angle_step_deg`` gets the largest step that divides the cycle and every
firing delay and bank angle and is not above 1 deg (the bound for [numerics] tolerance = 0.1 %). The
expected step is found here by brute force — the first m = ceil(cycle/1 deg), m + 1, ... for which
cycle/m divides every delay and bank angle — independently of the rational-gcd grid of the code.
The numerics study runs on each engine with its steps moved onto the grid, and measures the peaks
within the tolerance. A refused step names steps that work.
"""

from __future__ import annotations

import math
import re
import types

import numpy as np
import pytest
from conftest import modified
from test_extreme import even_firing_order

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import check_scene, run_scene
from crankdyn.errors import PluginFailure, SceneError
from crankdyn.plugin.registry import default_registry
from crankdyn.plugin.scene_inputs import engine_layout
from crankdyn.report.context import sample_rows
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
CHEAP = {
    "numerics": {"steps_deg": [10], "repeats": 1, "kinematics_forms": False},
    "analysis": {"angle_step_deg": None, "table_step_deg": None, "stages": ["numerics"]},
}


def inline(n):
    return modified(
        "inline4-petrol",
        {
            "flywheel": None,
            **CHEAP,
            "engine": {"cylinders": n, "firing_order": even_firing_order("inline", n, 4)},
        },
    )


def radial(n):
    return modified("radial9-aircraft", {"engine": {"cylinders": n}, **CHEAP})


ENGINES = {
    "inline-7": inline(7),
    "inline-11": inline(11),
    "inline-23": inline(23),
    "radial-5": radial(5),
    "radial-7": radial(7),
    "radial-9": radial(9),
}


def divides(step, angle):
    q = angle / step
    return abs(q - round(q)) < 1e-7


def brute_force_step(scene, limit_deg=1.0):
    layout = engine_layout(scene)
    angles = [c.firing_delay_deg for c in layout.cylinders] + [c.axis_deg for c in layout.cylinders]
    angles.append(scene.analysis.table_step_deg)  # the tables' rows are whole crank angles
    m = math.ceil(layout.cycle_deg / limit_deg - 1e-9)
    while True:
        step = layout.cycle_deg / m
        if all(divides(step, a) for a in angles):
            return step
        m += 1


@pytest.mark.parametrize("name", list(ENGINES))
def test_default_step_and_the_numerics_study(name):
    scene = scene_from_dict(ENGINES[name], base_dir=examples_dir())
    step = scene.analysis.angle_step_deg
    assert scene.angle_step_defaulted
    assert step == pytest.approx(brute_force_step(scene), rel=1e-12)
    assert scene.analysis.table_step_deg == 10 and divides(step, 10)
    result = run_scene(scene, REGISTRY)
    numerics = result.outputs["numerics"].results
    assert not numerics["steps_refused"], numerics["steps_refused"]
    studied = [row["angle_step_deg"] for row in numerics["steps"]]
    assert len(studied) == 2 and studied[1] == step
    layout = engine_layout(scene)
    assert studied[0] <= 10 and all(
        divides(studied[0], c.firing_delay_deg) for c in layout.cylinders
    )
    at = numerics["at_scene_step"]
    assert (
        at["peaks_within_tolerance"] and at["peaks_error_relative"] <= 1e-3 and at["step_defaulted"]
    )
    assert any(
        key.startswith("numerics.note_default_step") for key, _ in result.outputs["numerics"].notes
    )


@pytest.mark.parametrize("step", [1.0, 0.7])
def test_refusal_names_steps_that_work(step):
    data = modified(
        "inline4-petrol",
        {
            "flywheel": None,
            "analysis": {"angle_step_deg": step},
            "engine": {"cylinders": 7, "firing_order": even_firing_order("inline", 7, 4)},
        },
    )
    with pytest.raises(SceneError) as info:
        run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY)
    message = str(info.value)
    suggested = [
        float(x)
        for x in re.search(r"nearest steps that work: ([0-9., ]+)", message)
        .group(1)
        .strip(" .,")
        .split(", ")
    ]
    assert len(suggested) == 2 and suggested[1] < step < suggested[0]
    for s in suggested:  # the scene accepts each suggestion as printed
        accepted = modified(
            "inline4-petrol",
            {
                "flywheel": None,
                "analysis": {"angle_step_deg": s, "table_step_deg": None},
                "engine": {"cylinders": 7, "firing_order": even_firing_order("inline", 7, 4)},
            },
        )
        check_scene(scene_from_dict(accepted, base_dir=examples_dir()), REGISTRY)
    for s in (
        suggested
    ):  # each works: 720 deg and every firing delay k*720/7 are whole multiples (to 12 digits)
        assert all(abs(k * 720 / 7 / s - round(k * 720 / 7 / s)) < 1e-8 for k in range(8))


@pytest.mark.parametrize("name", list(ENGINES))
def test_thirty_degree_tables_print_whole_crank_angles(name):
    data = {**ENGINES[name], "analysis": {"table_step_deg": 30}}
    scene = scene_from_dict(data, base_dir=examples_dir())
    step = scene.analysis.angle_step_deg
    assert (
        step <= 1
        and divides(step, 30)
        and all(divides(step, c.firing_delay_deg) for c in engine_layout(scene).cylinders)
    )
    angle = np.arange(round(scene.engine.cycle_deg / step)) * step
    _, labels = sample_rows(angle, scene.analysis.table_step_deg)
    assert np.allclose(labels, np.arange(0, scene.engine.cycle_deg + 1, 30.0), atol=1e-9)


def _unstepped(numerics: dict | None = None) -> dict:
    """A one-cylinder scene without steps: its grid is the 10 deg table step, so its default step
    is the largest 10/k deg not above the target."""
    changes = {"analysis": {"angle_step_deg": None, "table_step_deg": None}}
    return modified("kinematics-only", {**changes, "numerics": numerics})


def _largest_tenth_not_above(target_deg: float) -> float:
    return 10.0 / math.ceil(10.0 / target_deg - 1e-12)


@pytest.mark.parametrize("tolerance", [1e-2, 1e-3, 1e-4])
def test_the_numerics_plugin_declares_the_step_its_tolerance_asks(tolerance):
    """The step follows [numerics] tolerance as 1 deg x sqrt(tolerance / 0.1 %) through the
    numerics stage's ``default_angle_step``; read without a registry, the core's 1 deg target."""
    data = _unstepped({"tolerance": tolerance})
    expected = _largest_tenth_not_above(math.sqrt(tolerance / 1e-3))
    assert scene_from_dict(data).analysis.angle_step_deg == 1.0
    scene = scene_from_dict(data, registry=REGISTRY)
    assert scene.analysis.angle_step_deg == pytest.approx(expected, rel=1e-12)
    assert scene.angle_step_defaulted and scene.analysis.table_step_deg == 10
    assert scene.with_plugin_defaults(REGISTRY) is scene  # chosen once
    # planned without having been read with the registry: the same step
    result = run_scene(scene_from_dict(data), REGISTRY, ["kinematics"])
    assert result.scene.analysis.angle_step_deg == pytest.approx(expected, rel=1e-12)
    angles = result.outputs["kinematics"].data["kinematics"].crank_angle_deg
    assert len(angles) == round(720 / expected)


def test_a_given_step_is_kept_whatever_the_tolerance():
    data = modified("kinematics-only", {"numerics": {"tolerance": 1e-2}})
    given = scene_from_dict(data)
    assert not given.angle_step_defaulted
    assert scene_from_dict(data, registry=REGISTRY).analysis == given.analysis


def test_another_stage_may_ask_for_a_finer_step_and_the_finest_wins():
    from crankdyn.plugin.hooks import hookimpl
    from crankdyn.plugin.registry import collect, plugin_manager
    from crankdyn.plugin.types import Stage

    def plugin(name, wish):
        module = types.ModuleType(name)
        stage = Stage(
            name=name,
            requires=(),
            provides=(),
            applies=lambda scene: None,
            run=lambda scene, inputs: None,
            default=False,
            default_angle_step=wish,
        )
        module.crankdyn_stages = hookimpl(lambda: [stage])
        return module

    finer = collect(plugin_manager(extra_plugins=[plugin("fine_study", lambda scene: 0.4)]))
    assert scene_from_dict(_unstepped(), registry=finer).analysis.angle_step_deg == (
        _largest_tenth_not_above(0.4)
    )
    coarser = collect(plugin_manager(extra_plugins=[plugin("coarse_study", lambda scene: 5)]))
    assert scene_from_dict(_unstepped(), registry=coarser).analysis.angle_step_deg == 1.0
    broken = collect(plugin_manager(extra_plugins=[plugin("odd_study", lambda scene: "fast")]))
    with pytest.raises(PluginFailure, match="odd_study.*default_angle_step"):
        scene_from_dict(_unstepped(), registry=broken)


def test_a_short_firing_interval_gets_seventy_two_steps_and_its_excess_work_holds():
    """A two-stroke V16 fires every 22.5°: at 0.9375°, the step its grid allows next to 1°, the
    excess work loses about 1 % against a fine grid (24 steps an interval). The default step gives the mean
    firing interval 72 steps at least, and ΔL is then within 0.2 % of its value at a quarter of
    that step (the error falls as the step squared); engines with 90° and longer intervals keep
    1°."""
    engine = {
        "layout": "V",
        "bank_angle_deg": 45,
        "cylinders": 16,
        "strokes": 2,
        "rpm": 900,
        "firing_order": even_firing_order("V", 16, 2, 45),
        "cylinder_spacing": "400 mm",
    }
    cycle = {"exhaust_pressure": None, "rounding": {"exhaust_opens_before_bdc_deg": 60}}
    data = modified(
        "diesel-1cyl", {"engine": engine, "cycle": cycle, "flywheel": {"inertia": "10 kg*m^2"}}
    )
    data.get("analysis", {}).pop("angle_step_deg", None)
    scene = scene_from_dict(data, registry=REGISTRY)
    assert scene.analysis.angle_step_deg == pytest.approx(22.5 / 72)

    def excess(step):
        stepped = scene_from_dict({**data, "analysis": {"angle_step_deg": step}})
        return (
            run_scene(stepped, REGISTRY, ["flywheel"]).outputs["flywheel"].results["excess_work_J"]
        )

    fine = excess(22.5 / 288)
    assert excess(22.5 / 72) == pytest.approx(fine, rel=2e-3)
    assert abs(excess(22.5 / 24) / fine - 1) > 5e-3  # 24 steps an interval, for contrast
    for name in ("inline4-petrol", "v8-petrol", "radial9-aircraft"):
        plain = modified(name, {})
        plain.get("analysis", {}).pop("angle_step_deg", None)
        assert scene_from_dict(plain, registry=REGISTRY).analysis.angle_step_deg == 1.0
