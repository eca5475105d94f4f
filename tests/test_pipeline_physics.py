"""Whole-pipeline physics against independent values and invariants."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import modified, shared_run

from crankdyn.engine.orchestrator import run_scene
from crankdyn.physics import kinematics as kin
from crankdyn.physics.pressure_trace import read_diesel_rk_ind_table
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()


def run(name: str, changes: dict | None = None, base_dir: Path | None = None):
    """The example's run; from the bundled examples' folder, computed once per test process and shared
    with the other tests and test files (read only)."""
    if base_dir is None:
        return shared_run(name, changes)
    data = modified(name, changes or {})
    from crankdyn.cli import examples_dir

    scene = scene_from_dict(data, base_dir=base_dir or examples_dir())
    return run_scene(scene, REGISTRY)


@pytest.mark.parametrize(
    "name", ["petrol-1cyl", "diesel-1cyl", "two-stroke-1cyl", "diesel-rk-trace"]
)
def test_mean_torque_equals_indicated_work_over_cycle_angle(name):
    """Mean crank torque = indicated work per cycle / (2*pi * strokes/2).

    The torque comes from t = p1 sin(a+b)/cos b (forces stage, rectangle rule over
    the crank angle); the work from the closed p-V loop (indicator stage, trapezoid
    rule in volume): two different integrals of the same physics.
    """
    result = run(name)
    forces = result.outputs["forces"].results
    work = result.outputs["indicator"].results["indicated_work_J"]
    strokes = result.scene.engine.strokes
    assert forces["mean_torque_from_work_Nm"] == pytest.approx(
        work / (2 * math.pi * strokes / 2), rel=1e-12
    )
    assert forces["mean_torque_Nm"] == pytest.approx(forces["mean_torque_from_work_Nm"], rel=2e-4)


@pytest.mark.parametrize("method", ["exact", "approximate"])
def test_inertia_forces_do_no_net_work(method):
    result = run("petrol-1cyl", {"analysis": {"kinematics": method}})
    assert abs(result.outputs["forces"].results["inertia_work_relative"]) < 1e-12


def test_dead_centre_values_through_the_pipeline():
    result = run("petrol-1cyl")
    f = result.outputs["forces"].tables["forces"]
    motion = result.outputs["kinematics"].data["kinematics"]
    R, w, lam = (
        motion.crank_radius_m,
        motion.angular_velocity_rad_s,
        result.scene.engine.rod_ratio_value,
    )
    for angle in (0, 180, 360, 540):
        row = f[f.crank_angle_deg == angle].iloc[0]
        assert row.piston_velocity_m_s == pytest.approx(0, abs=1e-9)
        assert row.tangential_Pa == pytest.approx(0, abs=1e-6 * abs(row.total_Pa) + 1e-6)
        sign = 1 if angle % 360 == 0 else -1
        assert row.radial_Pa == pytest.approx(sign * row.total_Pa, rel=1e-12)
        expected_j = R * w**2 * (1 + lam) if sign == 1 else -R * w**2 * (1 - lam)
        assert row.piston_acceleration_m_s2 == pytest.approx(expected_j, rel=1e-12)
    r = result.outputs["kinematics"].results
    assert r["j_max_m_s2"] == pytest.approx(R * w**2 * (1 + lam), rel=1e-12)
    assert r["mean_piston_speed_m_s"] == pytest.approx(
        result.scene.engine.stroke * result.scene.engine.rpm / 30
    )


def test_inertia_force_at_tdc_closed_form():
    result = run("petrol-1cyl")
    f = result.outputs["forces"].results
    s = result.scene
    area = math.pi * s.engine.bore**2 / 4
    m_s = s.masses.piston_group + s.masses.rod * s.masses.rod_cm_fraction
    expected = (
        -m_s
        * s.engine.crank_radius_m
        * s.engine.angular_velocity_rad_s**2
        * (1 + s.engine.rod_ratio_value)
        / area
    )
    assert f["inertia_tdc_Pa"] == pytest.approx(expected, rel=1e-12)
    c_expected = (
        -(
            s.masses.rod * (1 - s.masses.rod_cm_fraction)
            + s.masses.crank_pin
            + 2 * s.masses.crank_web
        )
        * s.engine.crank_radius_m
        * s.engine.angular_velocity_rad_s**2
        / area
    )
    assert f["centrifugal_Pa"] == pytest.approx(c_expected, rel=1e-12)


def test_published_example_khurmi_gupta_15_3():
    """Khurmi & Gupta, *Theory of Machines*, Example 15.3: crank 300 mm, rod 1 m, 200 rpm.

    Published answer (two-term velocity): maximum at theta = 75 deg from the inner dead
    centre, v_max = 6.54 m/s.
    """
    w = 200 * math.pi / 30
    v_75 = kin.piston_velocity_approx_m_s(math.radians(75), 0.3, 0.3, w)
    assert round(float(v_75), 2) == 6.54
    grid = np.radians(np.linspace(0, 180, 18001))
    assert (
        round(float(np.degrees(grid[np.argmax(kin.piston_velocity_approx_m_s(grid, 0.3, 0.3, w))])))
        == 75
    )
    v_exact, angle = kin.max_piston_velocity_exact(0.3, 0.3, w)
    assert v_exact == pytest.approx(6.54, abs=0.03)  # the exact peak lies within the two-term error


def test_diesel_rk_trace_matches_its_own_volume_column():
    """Peak pressure and indicated work of the bundled Diesel-RK trace against the file itself."""
    from crankdyn.cli import examples_dir

    table = read_diesel_rk_ind_table(examples_dir() / "diesel6-1600rpm.ind")
    names = list(table)
    angle, pressure_bar, volume = table[names[0]], table[names[1]], table[names[3]]
    p = pressure_bar * 1e5
    work_file = np.trapezoid(np.append(p[:-1], p[0]), np.append(volume[:-1], volume[0]))
    result = run("diesel-rk-trace")
    ind = result.outputs["indicator"].results
    assert ind["max_pressure_Pa"] == pytest.approx(pressure_bar.max() * 1e5)
    assert ind["max_pressure_crank_angle_deg"] == angle[np.argmax(pressure_bar)]
    # Our volume comes from the crank-slider kinematics with lambda = 0.3105 and eps = 17.7,
    # the file's from Diesel-RK: agreement checks the whole chain (angles, units, volume).
    assert ind["indicated_work_J"] == pytest.approx(work_file, rel=2e-3)


def test_rounded_diagram_does_not_depend_on_angle_step():
    fine = run("petrol-1cyl", {"analysis": {"angle_step_deg": 0.5, "table_step_deg": 30}})
    coarse = run("petrol-1cyl", {"analysis": {"angle_step_deg": 2, "table_step_deg": 30}})
    p_fine = (
        fine.outputs["indicator"].tables["indicator"].set_index("crank_angle_deg")["pressure_Pa"]
    )
    p_coarse = (
        coarse.outputs["indicator"].tables["indicator"].set_index("crank_angle_deg")["pressure_Pa"]
    )
    common = p_coarse.index
    np.testing.assert_allclose(p_coarse.to_numpy(), p_fine.loc[common].to_numpy(), rtol=1e-12)
    # Work integrals converge with the step (trapezoid rule in V: second order).
    w_fine = fine.outputs["indicator"].results["indicated_work_J"]
    w_coarse = coarse.outputs["indicator"].results["indicated_work_J"]
    assert w_coarse == pytest.approx(w_fine, rel=2e-3)


def test_kinematics_only_scene_skips_with_reasons(tmp_path):
    result = run("kinematics-only")
    assert result.stages_run == ["kinematics", "drawing", "numerics_kinematics"]
    assert "no [cycle]" in result.plan.skipped["indicator"]
    assert "[masses]" in result.plan.skipped["forces"]


def test_exact_vs_two_term_difference_is_third_order():
    """The pipeline's reported two-term error scales as lambda^3 (ratio ~8 when lambda halves)."""
    errors = []
    for lam in (0.3, 0.15):
        result = run("kinematics-only", {"engine": {"rod_length": None, "rod_ratio": lam}})
        errors.append(result.outputs["kinematics"].results["two_term_displacement_error_max_m"])
    assert 7.0 < errors[0] / errors[1] < 9.0


@pytest.mark.parametrize("kinematics", ["exact", "approximate"])
def test_inertia_beyond_the_textbook_two_terms_is_of_order_lambda_cubed(kinematics):
    """p_j - (p_jI + p_jII): with the exact kinematics, the terms of order lambda^3 and up, whose
    largest value is (m_s R omega^2 / F_p) lambda^3 / 2 at alpha = 90 deg to within lambda^5
    (exact j / (R omega^2) = cos a + lambda cos 2a + (lambda^3/4)(cos 2a - cos 4a) + O(lambda^5));
    with the textbook's approximate kinematics p_j is exactly the two terms. The report explains
    the difference only when the table's three decimals show it."""
    result = run("petrol-1cyl", {"analysis": {"kinematics": kinematics, "angle_step_deg": 0.5}})
    forces, scene = result.outputs["forces"].results, result.scene
    radius, ratio = scene.engine.stroke / 2, scene.engine.rod_ratio_value
    omega = 2 * math.pi * scene.engine.rpm / 60
    scale = forces["reciprocating_mass_kg"] * radius * omega**2 / forces["piston_area_m2"]
    rest = forces["inertia_higher_orders_max_Pa"]
    table = result.outputs["forces"].tables["forces"]
    direct = np.max(
        np.abs(
            table["inertia_Pa"] - table["inertia_first_order_Pa"] - table["inertia_second_order_Pa"]
        )
    )
    assert rest == pytest.approx(direct, rel=1e-12, abs=1e-9)
    if kinematics == "exact":
        assert abs(rest / scale - ratio**3 / 2) <= ratio**5
    else:
        assert rest <= 1e-9 * scale
