"""Property-based tests (hypothesis) over random valid scenes: invariants of the crank mechanism.

A scene is drawn from the petrol (four-stroke) or two-stroke example with random rod ratio
(0.001-0.99), speed (1-20000 rpm), masses (1e-6-1e3 kg, log-uniform), bore and stroke, kinematics
(exact or the textbook two-term form) and an in-line cylinder count (1-8 but 7, whose 102.86-deg
firing interval no step divides). Only the stages that
give forces and torques run (no report, no numerics study), so many scenes fit in a few seconds.
Tolerances are those of tests/test_extreme.py, where they are justified.
"""

from __future__ import annotations

import math

import numpy as np
from conftest import modified
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def log_uniform(low, high):
    return st.floats(math.log10(low), math.log10(high)).map(lambda x: 10.0**x)


@st.composite
def scenes(draw):
    two_stroke = draw(st.booleans())
    cylinders = draw(
        st.sampled_from([1, 2, 3, 4, 5, 6, 8])
    )  # the 1-deg step must divide the firing interval
    masses = {k: f"{draw(log_uniform(1e-6, 1e3)):.6g} kg" for k in ("piston_group", "rod")}
    masses.update(
        {
            k: f"{draw(st.one_of(st.just(0.0), log_uniform(1e-6, 1e3))):.6g} kg"
            for k in ("crank_pin", "crank_web")
        }
    )
    masses["rod_cm_fraction"] = draw(st.floats(0.05, 0.95))
    engine = {
        "rod_ratio": draw(st.floats(0.001, 0.99)),
        "rpm": draw(log_uniform(1.0, 20000.0)),
        "bore": f"{draw(st.floats(5.0, 500.0)):.4g} mm",
        "stroke": f"{draw(st.floats(5.0, 800.0)):.4g} mm",
        "cylinders": cylinders,
        "firing_order": list(range(1, cylinders + 1)) if cylinders > 1 else None,
    }
    kinematics = draw(st.sampled_from(["exact", "approximate"]))
    data = modified(
        "two-stroke-1cyl" if two_stroke else "petrol-1cyl",
        {
            "engine": engine,
            "masses": masses,
            "analysis": {"kinematics": kinematics, "stages": ["forces", "torque"]},
        },
    )
    return scene_from_dict(data, base_dir=examples_dir())


def expected_deviation_percent(scene, result) -> float:
    """The mean torque's deviation from the indicated work that the kinematics make, percent: none
    with the exact kinematics; with the two-term ones, the torque takes the piston's arm from the
    exact rod angle, ds/dα = R(sin α + λ sin α cos α / cos β), the work ∮p dV the volume of the
    two-term displacement, ds/dα = R(sin α + λ/2 sin 2α), so the mean torque exceeds the work's
    by F R ∮p Δ(ds/dα) dα (the crankcase pressure and the inertia forces do no work over a cycle
    with either arm)."""
    if scene.analysis.kinematics != "approximate":
        return 0.0
    table = result.outputs["indicator"].tables["indicator"]
    alpha = np.radians(table["crank_angle_deg"].to_numpy())
    pressure = table["pressure_Pa"].to_numpy()
    lam, radius = scene.engine.rod_ratio_value, scene.engine.stroke / 2
    exact = np.sin(alpha) + lam * np.sin(alpha) * np.cos(alpha) / np.sqrt(
        1.0 - (lam * np.sin(alpha)) ** 2
    )
    approximate = np.sin(alpha) + 0.5 * lam * np.sin(2.0 * alpha)
    area = math.pi * scene.engine.bore**2 / 4.0
    difference = area * radius * np.sum(pressure * (exact - approximate)) * (alpha[1] - alpha[0])
    return 100.0 * difference / result.outputs["indicator"].results["indicated_work_J"]


@SETTINGS
@given(scene=scenes())
def test_net_inertia_work_is_zero(scene):
    result = run_scene(scene, REGISTRY)
    r = result.outputs["forces"].results
    assert abs(r["inertia_work_relative"]) < 1e-9
    frame = result.outputs["forces"].tables["forces"]
    inertia = frame["inertia_Pa"].to_numpy()
    # direct sum of the inertia torque over the cycle, against its own scale
    alpha = np.radians(frame["crank_angle_deg"].to_numpy())
    arm = frame["piston_velocity_m_s"].to_numpy() / scene.engine.angular_velocity_rad_s
    torque = inertia * arm
    assert abs(torque.sum()) <= 1e-9 * np.abs(torque).sum() + 1e-300
    assert np.all(np.isfinite(alpha))


@SETTINGS
@given(scene=scenes())
def test_mean_torque_is_indicated_work_over_the_cycle_angle(scene):
    result = run_scene(scene, REGISTRY)
    forces, torque = result.outputs["forces"].results, result.outputs["torque"].results
    work = result.outputs["indicator"].results["indicated_work_J"]
    revolutions = scene.engine.strokes / 2
    assert forces["mean_torque_from_work_Nm"] == work / (2 * math.pi * revolutions)
    # 0.05 %: the rectangle sum of the torque against the trapezoid rule of the work, 1° step
    expected = expected_deviation_percent(scene, result)
    assert abs(forces["mean_torque_deviation_percent"] - expected) < 0.05
    assert abs(torque["mean_deviation_percent"] - expected) < 0.05
    # the engine's mean torque is the cylinders' sum (central rods, every cylinder alike)
    assert math.isclose(
        torque["mean_Nm"],
        scene.engine.cylinders * forces["mean_torque_Nm"],
        rel_tol=1e-9,
        abs_tol=1e-12 * abs(forces["torque_max_Nm"]),
    )


@SETTINGS
@given(scene=scenes())
def test_reciprocating_forces_are_symmetric(scene):
    result = run_scene(scene, REGISTRY)
    frame = result.outputs["forces"].tables["forces"]
    inertia = frame["inertia_Pa"].to_numpy()
    n = len(inertia)
    scale = np.max(np.abs(inertia))
    # p_j(alpha) = p_j(-alpha): the piston motion is symmetric about the dead centres
    np.testing.assert_allclose(inertia, inertia[(-np.arange(n)) % n], rtol=0, atol=1e-9 * scale)
    # and about BDC: p_j(180 + x) = p_j(180 - x)
    per_rev = int(round(360.0 / scene.analysis.angle_step_deg))
    half = per_rev // 2
    k = np.arange(per_rev)
    np.testing.assert_allclose(
        inertia[(half + k) % n], inertia[(half - k) % n], rtol=0, atol=1e-9 * scale
    )
    if scene.engine.strokes == 4:  # the motion repeats every revolution
        np.testing.assert_allclose(inertia, np.roll(inertia, per_rev), rtol=0, atol=1e-9 * scale)
    if scene.analysis.kinematics == "approximate":  # eq. (18) = (19) + (20) for the two-term form
        np.testing.assert_allclose(
            inertia,
            frame["inertia_first_order_Pa"] + frame["inertia_second_order_Pa"],
            rtol=0,
            atol=1e-9 * scale,
        )
    # at TDC p_j = -m_s R w^2 (1 + lambda) / F (both forms agree there)
    r = result.outputs["forces"].results
    e = scene.engine
    expected = (
        -r["reciprocating_mass_kg"]
        * e.crank_radius_m
        * e.angular_velocity_rad_s**2
        * (1 + e.rod_ratio_value)
        / r["piston_area_m2"]
    )
    assert math.isclose(inertia[0], expected, rel_tol=1e-12)
