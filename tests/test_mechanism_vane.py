"""Vane engine's crank-rocker parallelogram mechanism: every relation of Klementev (2023)
re-derived and checked (finite differences, geometry, the ±52.239° check value, y_max)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import modified, write_scene
from scipy import optimize

from crankdyn.cli import examples_dir, main
from crankdyn.engine.orchestrator import run_scene
from crankdyn.physics import kinematics as central
from crankdyn.physics import vane as vn
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
ALPHA = np.linspace(0.0, 2.0 * np.pi, 721)
H = 1e-5


def _d(fn, alpha=ALPHA):
    return (fn(alpha + H) - fn(alpha - H)) / (2 * H)


def test_check_value_zeros_of_the_slider_vertical_acceleration():
    zeros = np.degrees(vn.slider_vertical_acceleration_zeros_rad(0.8))
    # the source: alpha = ±52.239° ± pi N, i.e. 52.239, 180 - 52.239, 180 + 52.239, 360 - 52.239
    np.testing.assert_allclose(np.round(zeros, 3), [52.239, 127.761, 232.239, 307.761], atol=0)
    assert math.sin(math.radians(zeros[0])) == pytest.approx(0.791, abs=5e-4)  # "arcsin(±0.791)"
    # they are roots of eq. (4) itself, found by a root search, and the only ones
    j = vn.slider_vertical_acceleration_m_s2(ALPHA, 1.0, 0.8, 1.0)
    crossings = np.flatnonzero(np.signbit(j[:-1]) != np.signbit(j[1:]))
    assert len(crossings) == 4
    found = [
        optimize.brentq(
            lambda a: float(vn.slider_vertical_acceleration_m_s2(a, 1.0, 0.8, 1.0)),
            ALPHA[i],
            ALPHA[i + 1],
            xtol=1e-15,
        )
        for i in crossings
    ]
    np.testing.assert_allclose(np.degrees(found), zeros, atol=1e-9)


@pytest.mark.parametrize("lam", [0.3, 0.6, 0.8, 0.95])
def test_eq5_and_the_zeros_are_the_vertical_velocity_extremes(lam):
    u = math.sin(vn.slider_vertical_acceleration_zeros_rad(lam)[0]) ** 2
    assert lam**2 * u**2 - 2 * u + 1 == pytest.approx(0.0, abs=1e-14)  # eq. (5)
    assert u == pytest.approx((1 - math.sqrt(1 - lam**2)) / lam**2, rel=1e-14)  # the source's root
    other = (1 + math.sqrt(1 - lam**2)) / lam**2
    assert other > 1  # the second root of eq. (5) gives no real angle
    v = vn.slider_vertical_velocity_m_s(ALPHA, 1.0, lam, 1.0)
    extremes = (
        np.flatnonzero((np.abs(v[1:-1]) > np.abs(v[:-2])) & (np.abs(v[1:-1]) >= np.abs(v[2:]))) + 1
    )
    np.testing.assert_allclose(
        np.sort(np.degrees(ALPHA[extremes])),
        np.degrees(vn.slider_vertical_acceleration_zeros_rad(lam)),
        atol=0.5,
    )


@pytest.mark.parametrize("lam", [0.2, 0.6, 0.8])
def test_y_max(lam):
    r = 0.05
    expected = (r / lam) * (1 - math.sqrt(1 - lam**2))
    assert vn.slider_vertical_travel_max_m(r, lam) == pytest.approx(expected, rel=1e-14)
    travel = vn.slider_vertical_travel_m(np.linspace(0, 2 * np.pi, 3601), r, lam)
    assert travel.max() == pytest.approx(expected, rel=1e-12) and travel.min() == pytest.approx(
        0.0, abs=1e-16
    )
    if lam == 0.8:
        assert expected / (r / lam) == pytest.approx(0.4)  # "0.4 l" in the source
    # the vertical travel is l - y_p, the slider's rise above B'
    np.testing.assert_allclose(
        travel,
        r / lam - vn.slider_height_below_core_m(np.linspace(0, 2 * np.pi, 3601), r, lam),
        atol=1e-16,
    )


def test_y_max_for_small_lambda_has_no_cancellation():
    assert vn.slider_vertical_travel_max_m(1.0, 1e-6) == pytest.approx(0.5e-6, rel=1e-9)


@pytest.mark.parametrize("lam", [0.6, 0.8])
def test_core_and_vane_angles(lam):
    beta = vn.core_angle_rad(ALPHA, lam)
    gamma = vn.vane_angle_rad(ALPHA, lam)
    # eq. (1) from the geometry: the tail end follows the rocker sideways, l sin(-beta) = r sin(alpha)
    np.testing.assert_allclose(np.sin(-beta) / lam, np.sin(ALPHA), atol=1e-15)
    assert np.max(np.abs(beta)) == pytest.approx(math.asin(lam), rel=1e-9)  # eq. (2)
    # gamma from the extreme left position: 0 at 90°, max at 270°, = beta - beta_min
    np.testing.assert_allclose(gamma, beta + math.asin(lam), atol=1e-15)
    assert gamma.min() == pytest.approx(0.0, abs=1e-15) and gamma[
        ALPHA.searchsorted(np.pi / 2)
    ] == pytest.approx(0, abs=1e-12)
    assert gamma.max() == pytest.approx(vn.vane_angle_max_rad(lam), rel=1e-12)
    assert vn.rod_ratio_from_vane_angle(vn.vane_angle_max_rad(lam)) == pytest.approx(lam, rel=1e-14)


@pytest.mark.parametrize("lam", [0.3, 0.8])
def test_core_angular_velocity_and_acceleration(lam):
    omega = 2.5
    np.testing.assert_allclose(
        vn.core_angular_velocity_rad_s(ALPHA, lam, omega),
        omega * _d(lambda a: vn.core_angle_rad(a, lam)),
        atol=1e-8,
    )
    np.testing.assert_allclose(
        vn.core_angular_acceleration_rad_s2(ALPHA, lam, omega),
        omega * _d(lambda a: vn.core_angular_velocity_rad_s(a, lam, omega)),
        atol=1e-7,
    )
    # the source's form of epsilon_c is the same function
    np.testing.assert_allclose(
        vn.core_angular_acceleration_source_form_rad_s2(ALPHA, lam, omega),
        vn.core_angular_acceleration_rad_s2(ALPHA, lam, omega),
        atol=1e-12,
    )


def test_rocker_motion():
    r, omega = 0.05, 3.0
    x, y = vn.rocker_position_m(ALPHA, r)
    vx, vy = vn.rocker_velocity_m_s(ALPHA, r, omega)
    jx, jy = vn.rocker_acceleration_m_s2(ALPHA, r, omega)
    np.testing.assert_allclose(vx, omega * _d(lambda a: vn.rocker_position_m(a, r)[0]), atol=1e-10)
    np.testing.assert_allclose(vy, omega * _d(lambda a: vn.rocker_position_m(a, r)[1]), atol=1e-10)
    np.testing.assert_allclose(
        jx, omega * _d(lambda a: vn.rocker_velocity_m_s(a, r, omega)[0]), atol=1e-9
    )
    np.testing.assert_allclose(
        jy, omega * _d(lambda a: vn.rocker_velocity_m_s(a, r, omega)[1]), atol=1e-9
    )
    # the coupler of the parallelogram moves like the crank pin: a circle of radius r
    np.testing.assert_allclose(np.hypot(x, r - y), r, rtol=1e-14)


@pytest.mark.parametrize("lam", [0.6, 0.8])
def test_slider_vertical_motion(lam):
    r, omega = 0.05, 3.0
    np.testing.assert_allclose(
        vn.slider_vertical_velocity_m_s(ALPHA, r, lam, omega),
        omega * _d(lambda a: vn.slider_height_below_core_m(a, r, lam)),
        atol=1e-10,
    )
    np.testing.assert_allclose(
        vn.slider_vertical_acceleration_m_s2(ALPHA, r, lam, omega),
        omega * _d(lambda a: vn.slider_vertical_velocity_m_s(a, r, lam, omega)),
        atol=1e-9,
    )
    # y_p = l chi = l cos(beta): the tail end lies on a circle of radius l about O3
    beta = vn.core_angle_rad(ALPHA, lam)
    np.testing.assert_allclose(
        vn.slider_height_below_core_m(ALPHA, r, lam), (r / lam) * np.cos(beta), atol=1e-16
    )


@pytest.mark.parametrize("lam", [0.6, 0.8])
def test_slider_motion_relative_to_the_rocker(lam):
    r, omega = 0.05, 3.0
    y = vn.slider_relative_position_m(ALPHA, r, lam)
    # sum of the rocker's downward motion and the slider's rise, from 0 to 2r
    np.testing.assert_allclose(
        y,
        vn.rocker_position_m(ALPHA, r)[1] + vn.slider_vertical_travel_m(ALPHA, r, lam),
        atol=1e-16,
    )
    assert y.min() == pytest.approx(0.0, abs=1e-16) and y.max() == pytest.approx(2 * r, rel=1e-12)
    # ... which is the central crank-slider's piston displacement
    np.testing.assert_allclose(y, central.piston_displacement_exact_m(ALPHA, r, lam), atol=1e-15)
    np.testing.assert_allclose(
        vn.slider_relative_velocity_m_s(ALPHA, r, lam, omega),
        omega * _d(lambda a: vn.slider_relative_position_m(a, r, lam)),
        atol=1e-10,
    )
    np.testing.assert_allclose(
        vn.slider_relative_acceleration_m_s2(ALPHA, r, lam, omega),
        omega * _d(lambda a: vn.slider_relative_velocity_m_s(a, r, lam, omega)),
        atol=1e-9,
    )


def test_limits_of_lambda():
    assert vn.core_angle_max_rad(1e-9) == pytest.approx(0.0, abs=1e-8)
    assert math.degrees(vn.core_angle_max_rad(0.999999)) == pytest.approx(90.0, abs=0.2)
    with pytest.raises(ValueError, match="lambda"):
        vn.chi(0.0, 1.0)


# ----------------------------------------------------------------------------- the stage


@pytest.fixture(scope="module")
def vane_run():
    return run_scene(
        scene_from_dict(modified("vane-engine-kinematics", {}), base_dir=examples_dir()), REGISTRY
    )


def test_vane_example_is_kinematics_only_with_reasons(vane_run):
    assert vane_run.stages_run == ["vane", "drawing_linkage"]
    skipped = vane_run.plan.skipped
    assert "no [cycle]" in skipped["indicator"] and "[masses]" in skipped["forces"]
    r = vane_run.outputs["vane"].results
    assert r["rod_ratio"] == pytest.approx(0.8)
    np.testing.assert_allclose(
        np.round(r["slider_vertical_acceleration_zeros_deg"], 3),
        [52.239, 127.761, 232.239, 307.761],
    )
    assert r["slider_vertical_acceleration_zeros_check_deg"] < 1e-9
    assert r["slider_vertical_travel_max_m"] == pytest.approx(0.0625 * 0.4, rel=1e-12)
    assert r["core_angle_max_deg"] == pytest.approx(math.degrees(math.asin(0.8)))
    assert r["vane_angle_max_deg"] == pytest.approx(2 * math.degrees(math.asin(0.8)))
    assert r["slider_relative_travel_m"] == pytest.approx(0.1, rel=1e-9)


@pytest.mark.parametrize(
    "changes, field",
    [
        ({"masses": {"piston_group": "0.4 kg", "rod": "0.5 kg", "rod_cm_fraction": 0.3}}, "masses"),
        ({"engine": {"cylinders": 2}}, "engine.cylinders"),
        ({"mechanism": {"compare_rod_ratios": [1.2]}}, "mechanism.compare_rod_ratios"),
        ({"mechanism": {"core_ofset": "20 mm"}}, "mechanism.core_ofset"),
    ],
)
def test_bad_vane_scenes_are_refused(tmp_path, capsys, changes, field):
    scene = write_scene(tmp_path / "scene.toml", modified("vane-engine-kinematics", changes))
    out = tmp_path / "out"
    assert main(["report", str(scene), "-o", str(out), "--format", "json"]) == 2
    err = capsys.readouterr().err
    assert field in err and "Traceback" not in err, err
    assert not out.exists()


def test_vane_with_cycle_data_is_refused():
    data = modified("vane-engine-kinematics", {})
    petrol = modified("petrol-1cyl", {})
    data["cycle"], data["masses"] = petrol["cycle"], petrol["masses"]
    from crankdyn.errors import SceneError

    with pytest.raises(SceneError, match="kinematics only"):
        run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY)


def test_vane_report_has_the_source_plots(vane_run):
    rendered = render_html(vane_run, REGISTRY, "en")
    assert not rendered.missing_translations, rendered.missing_translations
    names = [f.name for f in rendered.figures]
    for plot in (
        "vane_angles",
        "vane_core",
        "vane_rocker",
        "vane_slider",
        "vane_relative",
        "vane_lambda",
    ):
        assert any(n.endswith(f"_{plot}.svg") for n in names), plot
    assert "52" in rendered.linked_html


def test_vane_example_through_the_cli(tmp_path):
    out = tmp_path / "out"
    assert (
        main(
            [
                "report",
                str(examples_dir() / "vane-engine-kinematics.toml"),
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
    assert doc["stages_run"] == ["vane", "drawing_linkage"]
    assert sorted(p.name for p in (out / "tables").iterdir()) == [
        "vane.csv",
        "vane_by_lambda.csv",
        "vane_compare.csv",
    ]


def test_lambda_to_one_limit_disagrees_with_the_source_conclusion():
    """The source: as lambda -> 1, j_yp becomes the rocker's single-period j_yk. The derivation:
    y_p -> r|cos alpha|, so j_yp -> -r omega^2 |cos alpha| (half the period) away from 90° and 270°."""
    alpha = np.radians([0.0, 30.0, 150.0, 180.0, 210.0, 330.0])
    lam = 1.0 - 1e-9
    np.testing.assert_allclose(
        vn.slider_vertical_acceleration_m_s2(alpha, 1.0, lam, 1.0),
        -np.abs(np.cos(alpha)),
        atol=1e-6,
    )
    jy_rocker = vn.rocker_acceleration_m_s2(alpha, 1.0, 1.0)[1]
    assert (
        jy_rocker[0] == pytest.approx(1.0)
        and vn.slider_vertical_acceleration_m_s2(0.0, 1.0, lam, 1.0) < 0
    )


def _root(fn, lo_deg, hi_deg):
    return optimize.brentq(fn, math.radians(lo_deg), math.radians(hi_deg), xtol=1e-15)


def test_extremes_by_root_finding_against_an_independent_solve():
    """Extremes exact to 1e-9 rad, one coordinate (y_p = O3P, downwards) for value and derivatives.

    The derivatives used here are written out by hand from the source's forms, independently of the code:
    v_yp = -w r lam sin a cos a / chi  =>  dv/da = 0  <=>  chi^2 cos 2a + lam^2 sin^2 a cos^2 a = 0
    (Klementev's check value a0 = 52.239 deg for lam = 0.8: v_yp is smallest there, largest at 180 - a0);
    eps_c = lam (1 - lam^2) w^2 sin a / chi^3 is largest at 90 deg: lam w^2 / sqrt(1 - lam^2);
    v_po = w r (sin a + lam sin a cos a / chi)  =>  cos a + lam (chi^2 cos 2a + lam^2 sin^2 a cos^2 a)/chi^3 = 0.
    """
    from crankdyn_builtin.vane.compute import extremes

    r, lam, w = 0.04, 0.8, 100.0

    def chi(a):
        return math.sqrt(1 - lam**2 * math.sin(a) ** 2)

    def bracket(a):
        return chi(a) ** 2 * math.cos(2 * a) + lam**2 * math.sin(a) ** 2 * math.cos(a) ** 2

    ext = extremes(r, lam, w)
    a0 = _root(bracket, 40, 60)
    assert math.degrees(a0) == pytest.approx(52.239, abs=5e-4)  # Klementev's check value
    v = ext["slider_vy_below_core_m_s"]
    assert abs(math.radians(v["min_crank_angle_deg"]) - a0) < 1e-9
    assert abs(math.radians(v["max_crank_angle_deg"]) - (math.pi - a0)) < 1e-9
    v_at = -w * r * lam * math.sin(a0) * math.cos(a0) / chi(a0)
    assert v["min"] == pytest.approx(v_at, rel=1e-13) and v["max"] == pytest.approx(
        -v_at, rel=1e-13
    )
    eps = ext["core_angular_acceleration_rad_s2"]
    assert abs(math.radians(eps["max_crank_angle_deg"]) - math.pi / 2) < 1e-9
    assert eps["max"] == pytest.approx(lam * w**2 / math.sqrt(1 - lam**2), rel=1e-13)
    a1 = _root(lambda a: math.cos(a) + lam * bracket(a) / chi(a) ** 3, 50, 80)
    rel = ext["slider_relative_velocity_m_s"]
    assert abs(math.radians(rel["max_crank_angle_deg"]) - a1) < 1e-9
    assert rel["max"] == pytest.approx(
        w * r * math.sin(a1) * (1 + lam * math.cos(a1) / chi(a1)), rel=1e-13
    )
    # y_p (below the core axis) is largest with the tail vertical (alpha = 0), smallest at 90 deg
    y = ext["slider_y_below_core_m"]
    assert y["max_crank_angle_deg"] == 0.0 and y["max"] == pytest.approx(r / lam, rel=1e-15)
    assert abs(y["min_crank_angle_deg"] - 90) < 1e-7 and y["min"] == pytest.approx(
        r / lam * math.sqrt(1 - lam**2)
    )
    j = ext["slider_jy_below_core_m_s2"]
    assert j["min_crank_angle_deg"] == 0.0  # of the equal minima at 0 and 180 deg, the first
