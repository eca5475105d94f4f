"""Offset (desaxial) crank-slider: closed forms against a numerical solution of the linkage,
the e = 0 limit, the force stage's resolution of the rod force, bad input and the report."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import modified, write_scene
from scipy import optimize

from crankdyn.cli import examples_dir, main
from crankdyn.engine.orchestrator import run_scene
from crankdyn.physics import forces as phys_forces
from crankdyn.physics import kinematics as central
from crankdyn.physics import offset_crank as oc
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
R, L, E = 0.039, 0.14, 0.008
LAM, K = R / L, E / L


# ----------------------------------------------------------------------------- a numerical linkage


def _pin_height(phi, e=E):
    """Piston-pin height by root finding on the loop closure |A - B| = L, A = (e, z)."""
    bx, bz = R * np.sin(phi), R * np.cos(phi)
    return optimize.brentq(
        lambda z: (e - bx) ** 2 + (z - bz) ** 2 - L * L, bz, bz + L + R, xtol=1e-16, rtol=1e-15
    )


def _numerical_dead_centres(e=E):
    top = optimize.minimize_scalar(
        lambda p: -_pin_height(p, e), bounds=(-0.5, 0.5), method="bounded", options={"xatol": 1e-12}
    )
    bottom = optimize.minimize_scalar(
        lambda p: _pin_height(p, e),
        bounds=(np.pi - 0.5, np.pi + 0.5),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return top.x, bottom.x, -top.fun, bottom.fun


def test_dead_centres_and_stroke_match_the_numerical_linkage():
    g = oc.dead_centres(R, L, E)
    tdc, bdc, z_top, z_bottom = _numerical_dead_centres()
    assert g.tdc_angle_rad == pytest.approx(
        tdc, abs=2e-6
    )  # flat maximum: the angle is found to ~sqrt(eps)
    assert g.bdc_angle_rad == pytest.approx(bdc, abs=2e-6)
    assert g.tdc_height_m == pytest.approx(z_top, abs=1e-12)
    assert g.stroke_m == pytest.approx(z_top - z_bottom, abs=1e-9)
    assert g.stroke_m > 2 * R
    assert g.bdc_after_tdc_rad > np.pi and g.stroke_time_ratio > 1.0


def test_displacement_matches_root_finding_to_a_nanometre():
    g = oc.dead_centres(R, L, E)
    alpha = np.linspace(0.0, 2.0 * np.pi, 73)
    numerical = np.array([g.tdc_height_m - _pin_height(a + g.tdc_angle_rad) for a in alpha])
    np.testing.assert_allclose(
        oc.piston_displacement_m(alpha, R, LAM, K), numerical, atol=1e-9, rtol=0
    )
    assert oc.piston_displacement_m(g.bdc_after_tdc_rad, R, LAM, K) == pytest.approx(
        g.stroke_m, abs=1e-12
    )


def test_velocity_and_acceleration_match_differentiation_of_the_root_found_position():
    g = oc.dead_centres(R, L, E)
    omega = 586.0
    alpha = np.linspace(0.05, 2.0 * np.pi, 37)

    def s(a):
        return g.tdc_height_m - _pin_height(a + g.tdc_angle_rad)

    h1, h2 = 1e-5, 1e-3
    ds = np.array([(s(a + h1) - s(a - h1)) / (2 * h1) for a in alpha])
    # Fourth-order stencil for the second derivative: truncation ~h^4, round-off ~eps z/h^2.
    d2s = np.array(
        [
            (-s(a + 2 * h2) + 16 * s(a + h2) - 30 * s(a) + 16 * s(a - h2) - s(a - 2 * h2))
            / (12 * h2 * h2)
            for a in alpha
        ]
    )
    np.testing.assert_allclose(
        oc.piston_velocity_m_s(alpha, R, LAM, K, omega), ds * omega, atol=1e-9 * omega
    )
    np.testing.assert_allclose(
        oc.piston_acceleration_m_s2(alpha, R, LAM, K, omega), d2s * omega**2, atol=1e-7 * omega**2
    )


def test_rod_angular_motion_matches_finite_differences():
    g = oc.dead_centres(R, L, E)
    omega, h = 300.0, 1e-5
    alpha = np.linspace(0.0, 2.0 * np.pi, 49)

    def beta(a):
        return oc.rod_angle_rad(a + g.tdc_angle_rad, LAM, K)

    rate = (beta(alpha + h) - beta(alpha - h)) / (2 * h) * omega
    np.testing.assert_allclose(
        oc.rod_angular_velocity_rad_s(alpha, R, LAM, K, omega), rate, rtol=1e-7, atol=1e-6
    )
    accel = (beta(alpha + h) - 2 * beta(alpha) + beta(alpha - h)) / h**2 * omega**2
    np.testing.assert_allclose(
        oc.rod_angular_acceleration_rad_s2(alpha, R, LAM, K, omega),
        accel,
        rtol=1e-4,
        atol=1e-3 * omega**2,
    )
    # sin(beta) is the lateral distance of the pins over L
    phi = alpha + g.tdc_angle_rad
    np.testing.assert_allclose(np.sin(beta(alpha)) * L, R * np.sin(phi) - E, atol=1e-15)


def test_zero_offset_is_the_central_crank_slider():
    alpha = np.linspace(0.0, 4.0 * np.pi, 181)
    omega = 400.0
    g = oc.dead_centres(R, L, 0.0)
    assert (g.tdc_angle_rad, g.bdc_angle_rad, g.stroke_m, g.stroke_time_ratio) == pytest.approx(
        (0, np.pi, 2 * R, 1)
    )
    np.testing.assert_allclose(
        oc.piston_displacement_m(alpha, R, LAM, 0.0),
        central.piston_displacement_exact_m(alpha, R, LAM),
        atol=1e-15,
    )
    np.testing.assert_allclose(
        oc.piston_velocity_m_s(alpha, R, LAM, 0.0, omega),
        central.piston_velocity_exact_m_s(alpha, R, LAM, omega),
        rtol=1e-13,
        atol=1e-12,
    )
    np.testing.assert_allclose(
        oc.piston_acceleration_m_s2(alpha, R, LAM, 0.0, omega),
        central.piston_acceleration_exact_m_s2(alpha, R, LAM, omega),
        rtol=1e-13,
        atol=1e-8,
    )
    np.testing.assert_allclose(
        oc.rod_angle_rad(alpha, LAM, 0.0), central.rod_angle_rad(alpha, LAM), atol=1e-15
    )
    np.testing.assert_allclose(
        oc.rod_angular_acceleration_rad_s2(alpha, R, LAM, 0.0, omega),
        central.rod_angular_acceleration_rad_s2(alpha, LAM, omega),
        rtol=1e-12,
        atol=1e-8,
    )


def test_negative_offset_mirrors_the_quick_return():
    plus, minus = oc.dead_centres(R, L, E), oc.dead_centres(R, L, -E)
    assert minus.stroke_m == pytest.approx(plus.stroke_m, rel=1e-14)
    assert minus.stroke_time_ratio == pytest.approx(1.0 / plus.stroke_time_ratio, rel=1e-13)
    assert minus.bdc_after_tdc_rad == pytest.approx(2 * np.pi - plus.bdc_after_tdc_rad, rel=1e-14)


def test_offset_beyond_l_minus_r_is_refused_by_the_physics():
    with pytest.raises(ValueError, match="L - R"):
        oc.dead_centres(R, L, L - R)


# ----------------------------------------------------------------------------- through the stages


def _run(name="offset-crank-engine", changes=None):
    scene = scene_from_dict(modified(name, changes or {}), base_dir=examples_dir())
    return run_scene(scene, REGISTRY)


@pytest.fixture(scope="module")
def offset_run():
    return _run()


def test_offset_example_runs_the_force_stages(offset_run):
    assert offset_run.stages_run[:4] == ["offset_crank", "drawing", "indicator", "forces"]
    assert "rod_dynamics" in offset_run.stages_run
    assert "not the central crank-slider" in offset_run.plan.skipped["kinematics"]
    r = offset_run.outputs["offset_crank"].results
    g = oc.dead_centres(R, L, E)
    assert r["stroke_m"] == pytest.approx(g.stroke_m, rel=1e-14)
    assert r["tdc_crank_angle_from_axis_deg"] == pytest.approx(np.degrees(np.arcsin(E / (L + R))))
    # The exact extremes do not depend on the grid
    v = offset_run.outputs["offset_crank"].tables["offset_crank"]["piston_velocity_m_s"].to_numpy()
    assert r["v_max_m_s"] >= v.max() - 1e-12 and r["v_max_m_s"] == pytest.approx(v.max(), rel=1e-4)
    assert r["v_min_m_s"] <= v.min() + 1e-12


def test_force_stage_resolves_the_rod_force_at_the_angle_from_the_axis(offset_run):
    motion = offset_run.outputs["offset_crank"].data["kinematics"]
    f = offset_run.outputs["forces"].tables["forces"]
    total = f["total_Pa"].to_numpy()
    # Virtual work: t R = p1 ds/dalpha at every angle (would fail with sin(alpha + beta)).
    np.testing.assert_allclose(
        f["tangential_Pa"].to_numpy() * R,
        total * motion.torque_arm_m,
        atol=1e-9 * np.max(np.abs(total)) * R,
    )
    # t^2 + z^2 = k^2 and n = p1 tan(beta)
    np.testing.assert_allclose(
        np.hypot(f["tangential_Pa"], f["radial_Pa"]), np.abs(f["rod_Pa"]), rtol=1e-12
    )
    np.testing.assert_allclose(
        f["side_Pa"], total * np.tan(motion.rod_angle_rad), rtol=1e-12, atol=1e-6
    )
    forces = offset_run.outputs["forces"].results
    assert abs(forces["inertia_work_relative"]) < 1e-12
    assert abs(forces["mean_torque_deviation_percent"]) < 0.05


def test_central_crank_forces_are_unchanged_by_the_angle_shift():
    result = _run("petrol-1cyl")
    motion = result.outputs["kinematics"].data["kinematics"]
    f = result.outputs["forces"].tables["forces"]
    textbook = phys_forces.rod_force_components(
        f["total_Pa"].to_numpy(), motion.crank_angle_rad, motion.rod_angle_rad
    )
    np.testing.assert_array_equal(f["tangential_Pa"].to_numpy(), textbook.tangential_Pa)
    np.testing.assert_array_equal(f["radial_Pa"].to_numpy(), textbook.radial_Pa)


def test_zero_offset_scene_reproduces_the_central_crank_slider():
    offset = _run(
        changes={
            "mechanism": {"offset": "0 mm"},
            "rod_dynamics": None,
            "masses": {"rod_moment_of_inertia": None},
        }
    )
    central_run = _run(
        changes={
            "engine": {"mechanism": "crank_slider"},
            "mechanism": None,
            "rod_dynamics": None,
            "masses": {"rod_moment_of_inertia": None},
        }
    )
    a, b = offset.outputs["forces"].tables["forces"], central_run.outputs["forces"].tables["forces"]
    for column in (
        "piston_displacement_m",
        "piston_acceleration_m_s2",
        "total_Pa",
        "tangential_Pa",
        "radial_Pa",
        "torque_Nm",
    ):
        np.testing.assert_allclose(
            a[column], b[column], rtol=1e-10, atol=1e-9 * np.max(np.abs(b[column]))
        )


def test_approximate_kinematics_request_is_noted_and_exact_is_used():
    result = _run(changes={"analysis": {"kinematics": "approximate"}})
    out = result.outputs["offset_crank"]
    assert out.results["method"] == "exact"
    assert ("offset_crank.note_exact_only", {}) in out.notes


@pytest.mark.parametrize(
    "changes, field, text",
    [
        ({"mechanism": {"offset": "101 mm"}}, "mechanism.offset", "L - R"),
        ({"mechanism": {"offset": "-101.5 mm"}}, "mechanism.offset", "full revolution"),
        ({"mechanism": None}, "mechanism.offset", "missing"),
        ({"mechanism": {"offset": 8}}, "mechanism.offset", "unit"),
        ({"mechanism": {"offset": "8 mm", "ofset": "1 mm"}}, "mechanism.ofset", "unknown key"),
        (
            {"engine": {"cylinders": 5, "layout": "radial", "rod_type": "articulated"}},
            "engine.rod_type",
            "articulated rods need the central crank-slider",
        ),
    ],
)
def test_bad_offset_scenes_are_refused(tmp_path, capsys, changes, field, text):
    scene = write_scene(tmp_path / "scene.toml", modified("offset-crank-engine", changes))
    out = tmp_path / "out"
    assert main(["report", str(scene), "-o", str(out), "--format", "json"]) == 2
    err = capsys.readouterr().err
    assert field in err and text in err and "Traceback" not in err
    assert not out.exists()


def test_offset_report_renders(offset_run):
    # one language is enough here: tests/test_report.py checks that every catalog has every key
    rendered = render_html(offset_run, REGISTRY, "ru")
    assert not rendered.missing_translations, rendered.missing_translations
    html = rendered.linked_html
    for stage in ("offset_crank", "indicator", "forces", "rod_dynamics"):
        assert f'data-stage="{stage}"' in html
    assert "φ" in html and "(2.1)" in html


def test_offset_example_through_the_cli(tmp_path):
    out = tmp_path / "out"
    assert (
        main(
            [
                "report",
                str(examples_dir() / "offset-crank-engine.toml"),
                "-o",
                str(out),
                "--format",
                "json,csv",
                "-q",
            ]
        )
        == 0
    )
    doc = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert doc["mechanism"] == "offset_crank_slider"
    assert doc["offset_crank"]["stroke_m"] > 0.078
    assert (out / "tables" / "offset_crank.csv").is_file()


def test_kinematics_only_offset_scene_leaves_the_cycle_stages_out_with_reasons():
    result = _run(changes={"cycle": None, "masses": None, "rod_dynamics": None})
    assert result.stages_run == ["offset_crank", "drawing"]
    assert "no [cycle]" in result.plan.skipped["indicator"]
    assert (
        "[masses]" in result.plan.skipped["forces"]
        and "[masses]" in result.plan.skipped["rod_dynamics"]
    )
    assert not any(
        key == "offset_crank.note_indicator" for key, _ in result.outputs["offset_crank"].notes
    )


# ------------------------------------------------------- the diagram's dead centres off 180°


def _cycle(bdc_deg=180.0):
    from crankdyn.physics import indicator as ind

    return ind.CycleParameters(
        strokes=4,
        ignition="spark",
        compression_ratio=9.5,
        intake_pressure_Pa=0.085e6,
        compression_index=1.37,
        max_pressure_Pa=6.0e6,
        pre_expansion_ratio=1.0,
        expansion_index=1.25,
        exhaust_pressure_Pa=0.118e6,
        bdc_deg=bdc_deg,
    )


def test_the_theoretical_diagram_turns_at_the_given_bdc():
    """With BDC at 190° (an offset crank-slider's, say) intake runs at p_a to 190°, compression
    starts there from V_a, expansion ends at 550° and the exhaust runs at p_r from there; the
    pumping work is taken over 550…720° and 0…190°: (p_a − p_r) V_h for the theoretical cycle."""
    from crankdyn.physics import indicator as ind

    bdc = 190.0
    params = _cycle(bdc)
    angle = np.arange(0.0, 720.0, 0.5)
    # a piston at BDC at 190° and 550°: V = V_c + V_h (1 − cos(π a/bdc))/2 on the outward stroke
    clearance, swept = 1e-4 / 8.5, 1e-4
    a = np.mod(angle, 360.0)
    phase = np.where(a <= bdc, np.pi * a / bdc, np.pi + np.pi * (a - bdc) / (360.0 - bdc))
    volume = clearance + swept * (1 - np.cos(phase)) / 2
    p = ind.theoretical_pressure_Pa(angle, volume, clearance, params)
    v_a = 9.5 * clearance
    assert np.all(p[(angle > 0) & (angle <= bdc)] == 0.085e6)
    after = (angle > bdc) & (angle < 360.0)
    np.testing.assert_allclose(p[after], 0.085e6 * (v_a / volume[after]) ** 1.37, rtol=1e-12)
    assert np.all(p[angle > 360.0 + bdc] == 0.118e6)
    assert p[angle == 360.0 + bdc][0] == pytest.approx(6.0e6 / 9.5**1.25, rel=1e-12)  # p_b at V_a
    # the trapezoid across the step p_r -> p_a at TDC costs ~2e-4; BDC taken at 180° costs 6 %
    pumping = ind.pumping_work_J(p, volume, angle, 4, bdc_deg=bdc)
    assert pumping == pytest.approx((0.085e6 - 0.118e6) * swept, rel=1e-3)
    assert ind.pumping_work_J(p, volume, angle, 4) != pytest.approx(pumping, rel=1e-2)


def test_a_bdc_outside_the_turn_is_refused():
    from crankdyn.physics import indicator as ind

    for bdc in (0.0, 360.0, float("nan")):
        with pytest.raises(ValueError, match="bdc_deg"):
            _cycle(bdc)
    assert ind.CycleParameters.__dataclass_fields__["bdc_deg"].default == 180.0
