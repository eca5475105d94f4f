"""Planetary crank mechanism: Cardan's straight line, the source's epicycloids, derivatives by
finite differences, the statics of the planet by virtual work, rejections and the report."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from conftest import modified, write_scene

from crankdyn.cli import examples_dir, main
from crankdyn.engine.orchestrator import run_scene
from crankdyn.errors import SceneError
from crankdyn.physics import kinematics as central
from crankdyn.physics import planetary as pl
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.scene.model import scene_from_dict
from crankdyn_builtin.planetary.compute import tdc_snapshot_m

REGISTRY = default_registry()
L = 0.15


def _geometry(gear="external", fixed=0.03, planet=0.01, pin=0.01, phase_deg=0.0, rod=L):
    return pl.PlanetaryGeometry(gear, fixed, planet, pin, math.radians(phase_deg), rod)


# ----------------------------------------------------------------------------- Cardan's circles


@pytest.mark.parametrize("phase_deg", [0.0, 37.0, -120.0])
def test_ring_gear_two_to_one_with_pin_on_the_pitch_circle_draws_a_straight_line(phase_deg):
    r_p = 0.02
    g = _geometry("internal", 2 * r_p, r_p, r_p, phase_deg)
    phi = np.linspace(0.0, 2.0 * np.pi, 3601)
    x, z, *_ = pl.big_end_path(phi, g)
    half = math.radians(phase_deg) / 2
    # distance of every point from the line through the shaft axis at psi0/2 from the cylinder axis
    assert np.max(np.abs(x * math.cos(half) - z * math.sin(half))) <= 1e-12
    assert np.max(np.hypot(x, z)) == pytest.approx(2 * r_p, rel=1e-12)  # a diameter of the ring


def test_two_to_one_hypocycloid_gives_pure_harmonic_piston_motion():
    r_p, omega = 0.02, 300.0
    g = _geometry("internal", 2 * r_p, r_p, r_p, 0.0)
    alpha = np.linspace(0.0, 2.0 * np.pi, 721)
    slider = pl.slider_motion(alpha, g)
    dc = pl.dead_centres(g)
    s = dc.tdc_height_m - slider.pin_z_m
    amplitude = 2 * r_p
    np.testing.assert_allclose(s, amplitude * (1 - np.cos(alpha)), atol=1e-12 * amplitude)
    np.testing.assert_allclose(
        -omega * slider.pin_z_d1_m, amplitude * omega * np.sin(alpha), atol=1e-12
    )
    np.testing.assert_allclose(
        -(omega**2) * slider.pin_z_d2_m,
        amplitude * omega**2 * np.cos(alpha),
        atol=1e-12 * amplitude * omega**2,
    )
    assert np.max(np.abs(slider.rod_angle_rad)) <= 1e-12  # the rod stays on the cylinder axis
    assert dc.stroke_m == pytest.approx(2 * amplitude, rel=1e-12)


def test_straight_line_through_the_stage():
    r_p = 0.02
    data = modified(
        "planetary-kinematics",
        {
            "engine": {"stroke": f"{4 * r_p * 1e3:g} mm"},
            "mechanism": {
                "gear": "internal",
                "fixed_gear_teeth": 40,
                "planet_teeth": 20,
                "module": "2 mm",
                "pin_radius": "20 mm",
                "pin_phase_deg": 0,
            },
        },
    )
    result = run_scene(scene_from_dict(data, base_dir=examples_dir()), REGISTRY)
    r = result.outputs["planetary"].results
    assert r["straight_line_deviation_m"] <= 1e-12
    assert r["planet_speed_ratio"] == -1.0
    assert r["torque_arm_tdc_m"] == pytest.approx(0.0, abs=1e-15)


# ----------------------------------------------------------------------------- the source's epicycloids


@pytest.mark.parametrize("d1, cusps, revolutions", [(20.0, 3, 1), (30.0, 2, 1), (40.0, 3, 2)])
def test_source_epicycloids_d2_60(d1, cusps, revolutions):
    """Fig. 2 of the source: planet d1 rolling on a fixed d2 = 60, pin on the planet's pitch circle."""
    r_f, r_p = 0.030, d1 / 2000.0
    g = _geometry("external", r_f, r_p, r_p)
    assert pl.motion_period_revolutions(60.0 / d1) == revolutions
    phi = np.linspace(0.0, 2.0 * np.pi * revolutions, 20000 * revolutions, endpoint=False)
    x, z, dx, dz, *_ = pl.big_end_path(phi, g)
    radius = np.hypot(x, z)
    # An epicycloid touches the fixed circle at its cusps (speed zero there) and reaches r_f + 2 r_p.
    assert radius.min() == pytest.approx(r_f, abs=1e-9) and radius.max() == pytest.approx(
        r_f + 2 * r_p, rel=1e-12
    )
    speed = np.hypot(dx, dz)
    touching = np.flatnonzero((radius[1:-1] < radius[:-2]) & (radius[1:-1] < radius[2:])) + 1
    assert len(touching) == cusps
    assert np.all(speed[touching] < 1e-3 * speed.max())
    # Epicycloid equation: rolling circle r_p on fixed r_f, parameter = planet's position angle.
    k = 1 + r_f / r_p
    np.testing.assert_allclose(x, (r_f + r_p) * np.sin(phi) + r_p * np.sin(k * phi), atol=1e-15)


def test_source_family_is_drawn_in_the_report():
    result = run_scene(
        scene_from_dict(modified("planetary-kinematics", {}), base_dir=examples_dir()), REGISTRY
    )
    family = result.outputs["planetary"].tables["family"]
    # the d1 = 20, 30, 40 (d2 = 60) paths of the source for this scene's 60 mm sun gear: the pin on
    # the planet's pitch circle reaches r_f + 2 r_p = 50, 60, 70 mm from the shaft axis
    for ratio, reach in (("3", 0.050), ("2", 0.060), ("1.5", 0.070)):
        radius = np.hypot(family[f"ratio_{ratio}_x_m"], family[f"ratio_{ratio}_z_m"])
        assert radius.max() == pytest.approx(reach, rel=1e-12) and radius.min() == pytest.approx(
            0.030, abs=1e-9
        )
    # one language is enough here: tests/test_report.py checks that every catalog has every key
    rendered = render_html(result, REGISTRY, "uk")
    assert not rendered.missing_translations, rendered.missing_translations
    assert (
        'data-stage="planetary"' in rendered.linked_html
        and 'data-stage="rod_dynamics"' in rendered.linked_html
    )
    names = [f.name for f in rendered.figures]
    for figure in (
        "planetary_path",
        "planetary_family",
        "planetary_motion",
        "planetary_arms",
        "rod_torque",
    ):
        assert any(n.endswith(f"_{figure}.svg") for n in names), figure
    assert "Епіциклоїди для передатних відношень d_f/d_p = 3, 2 і 1,5" in rendered.linked_html


# ----------------------------------------------------------------------------- derivatives and statics

CASES = [
    ("external", 0.03, 0.01, 0.01, 30.0),
    ("external", 0.03, 0.02, 0.006, 0.0),
    ("internal", 0.045, 0.015, 0.012, 65.0),
    ("internal", 0.04, 0.02, 0.005, 10.0),
]


@pytest.mark.parametrize("gear, fixed, planet, pin, phase", CASES)
def test_derivatives_match_finite_differences(gear, fixed, planet, pin, phase):
    g = _geometry(gear, fixed, planet, pin, phase)
    phi = np.linspace(0.0, 4.0 * np.pi, 97)
    h = 1e-5
    path, ahead, behind = (pl.big_end_path(p, g) for p in (phi, phi + h, phi - h))
    for i in range(2):  # x and z: first derivatives, then second
        np.testing.assert_allclose(path[2 + i], (ahead[i] - behind[i]) / (2 * h), atol=1e-10)
        np.testing.assert_allclose(path[4 + i], (ahead[2 + i] - behind[2 + i]) / (2 * h), atol=1e-9)
    m, mp, mm = (pl.slider_motion(p, g) for p in (phi, phi + h, phi - h))
    np.testing.assert_allclose(m.pin_z_d1_m, (mp.pin_z_m - mm.pin_z_m) / (2 * h), atol=1e-10)
    np.testing.assert_allclose(m.pin_z_d2_m, (mp.pin_z_d1_m - mm.pin_z_d1_m) / (2 * h), atol=1e-9)
    np.testing.assert_allclose(
        m.rod_angle_d1, (mp.rod_angle_rad - mm.rod_angle_rad) / (2 * h), atol=1e-9
    )
    np.testing.assert_allclose(
        m.rod_angle_d2, (mp.rod_angle_d1 - mm.rod_angle_d1) / (2 * h), atol=1e-8
    )
    # the loop closure itself: |A - B| = L with A on the axis
    x, z, *_ = path
    np.testing.assert_allclose(np.hypot(x, m.pin_z_m - z), g.rod_length_m, rtol=1e-14)


def test_stage_velocity_and_acceleration_match_finite_differences_of_its_displacement():
    result = run_scene(
        scene_from_dict(
            modified("planetary-kinematics", {"analysis": {"angle_step_deg": 0.25}}),
            base_dir=examples_dir(),
        ),
        REGISTRY,
    )
    motion = result.outputs["planetary"].data["kinematics"]
    h = np.radians(1e-3)
    alpha_deg = motion.crank_angle_deg[::40]
    ds = (motion.displacement_at(alpha_deg + 1e-3) - motion.displacement_at(alpha_deg - 1e-3)) / (
        2 * h
    )
    omega = motion.angular_velocity_rad_s
    np.testing.assert_allclose(motion.piston_velocity_m_s[::40], ds * omega, atol=1e-7 * omega)
    # second differences of the tabulated displacement (grid step 0.25 deg)
    s = motion.piston_displacement_m
    step = np.radians(0.25)
    d2 = (np.roll(s, -1) - 2 * s + np.roll(s, 1)) / step**2
    j = motion.piston_acceleration_m_s2
    assert np.max(np.abs(d2 * omega**2 - j)) < 2e-4 * np.max(np.abs(j))


@pytest.mark.parametrize("gear, fixed, planet, pin, phase", CASES)
def test_carrier_torque_from_the_planet_statics_equals_virtual_work(
    gear, fixed, planet, pin, phase
):
    g = _geometry(gear, fixed, planet, pin, phase)
    phi = np.linspace(0.0, 4.0 * np.pi, 181)
    ft = pl.force_transmission(phi, g)
    np.testing.assert_allclose(
        ft.carrier_torque_arm_m, -pl.slider_motion(phi, g).pin_z_d1_m, atol=1e-15
    )
    # The carrier torque is the rod force's moment about the shaft axis (the source's arm) plus the
    # moment of the fixed gear's tangential tooth force at the pitch point K = r_f u.
    np.testing.assert_allclose(
        ft.carrier_torque_arm_m,
        ft.rod_line_arm_m * ft.rod_force + fixed * ft.tooth_tangential,
        atol=1e-15,
    )
    assert np.all(ft.rod_force >= 1.0)


def test_tdc_rod_line_passes_through_the_pitch_point_and_the_effective_arm_vanishes():
    g = _geometry("external", 0.03, 0.01, 0.01, 30.0)
    dc = pl.dead_centres(g)
    ft = pl.force_transmission(dc.tdc_carrier_angle_rad, g)
    assert abs(float(ft.carrier_torque_arm_m)) < 1e-15
    assert abs(float(ft.rod_line_arm_m)) > 1e-3  # the source's arm MN exists ...
    kx, kz = 0.03 * math.sin(dc.tdc_carrier_angle_rad), 0.03 * math.cos(dc.tdc_carrier_angle_rad)
    x, z, *_ = pl.big_end_path(dc.tdc_carrier_angle_rad, g)
    beta = pl.slider_motion(dc.tdc_carrier_angle_rad, g).rod_angle_rad
    # ... because at a dead centre the rod's line passes the planet's instantaneous centre K
    assert abs(float(pl.rod_line_distance_m(kx, kz, x, z, beta))) < 1e-15
    # and TDC is the global maximum of the piston-pin height
    phi = np.linspace(0.0, 2 * np.pi, 7201)
    assert pl.slider_motion(phi, g).pin_z_m.max() <= dc.tdc_height_m + 1e-15
    # with the pin on the carrier line TDC is at phi = 0 and the arm vanishes as for a crank
    g0 = _geometry("external", 0.03, 0.01, 0.01, 0.0)
    assert pl.dead_centres(g0).tdc_carrier_angle_rad == 0.0
    assert float(pl.force_transmission(0.0, g0).rod_line_arm_m) == pytest.approx(0.0, abs=1e-15)


def test_pin_at_the_planet_centre_is_a_central_crank_of_the_carrier_radius():
    g = _geometry("external", 0.03, 0.01, 0.0)
    alpha = np.linspace(0.0, 2 * np.pi, 121)
    slider = pl.slider_motion(alpha, g)
    a = g.carrier_radius_m
    np.testing.assert_allclose(
        pl.dead_centres(g).tdc_height_m - slider.pin_z_m,
        central.piston_displacement_exact_m(alpha, a, a / L),
        atol=1e-15,
    )


def test_gear_speed_ratios_and_periods():
    assert pl.planet_speed_ratio("external", 0.03, 0.01) == 4.0
    assert pl.planet_speed_ratio("internal", 0.04, 0.02) == -1.0
    assert pl.carrier_radius_m("internal", 0.045, 0.015) == pytest.approx(0.03)
    assert (
        pl.motion_period_revolutions(1.5) == 2
        and pl.motion_period_revolutions(math.sqrt(2)) is None
    )
    with pytest.raises(ValueError):
        pl.carrier_radius_m("internal", 0.02, 0.02)


# ----------------------------------------------------------------------------- the stage and bad scenes


def test_planetary_example_results(tmp_path):
    out = tmp_path / "out"
    assert (
        main(
            [
                "report",
                str(examples_dir() / "planetary-kinematics.toml"),
                "-o",
                str(out),
                "--format",
                "json,csv",
                "-q",
            ]
        )
        == 0
    )
    import json

    doc = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert doc["stages_run"] == ["planetary", "drawing", "rod_dynamics"]
    r = doc["planetary"]
    assert (
        r["gear_ratio"] == 3.0
        and r["planet_speed_ratio"] == 4.0
        and r["carrier_radius_m"] == pytest.approx(0.04)
    )
    assert abs(r["torque_arm_tdc_m"]) > 1e-3 and abs(r["effective_torque_arm_tdc_m"]) < 1e-15
    assert "no [cycle]" in doc["stages_skipped"]["indicator"]
    assert (out / "tables" / "planetary_family.csv").is_file()


@pytest.mark.parametrize(
    "changes, field, text",
    [
        ({"engine": {"rod_length": "48 mm"}}, "engine.rod_length", "cannot reach"),
        ({"engine": {"rod_length": "49.5 mm"}}, "engine.rod_length", "locks"),
        ({"engine": {"stroke": "90 mm"}}, "engine.stroke", "93.9267 mm"),
        (
            {"engine": {"strokes": 2}, "mechanism": {"planet_teeth": 40}},
            "mechanism",
            "repeats every 2",
        ),
        (
            {
                "mechanism": {
                    "module": None,
                    "fixed_gear_pitch_diameter": "60 mm",
                    "planet_pitch_diameter": "20 mm",
                }
            },
            "mechanism",
            "give either",
        ),
        (
            {"mechanism": {"gear": "internal", "planet_teeth": 60}},
            "mechanism",
            "smaller than the ring",
        ),
        ({"mechanism": {"gear": "sideways"}}, "mechanism.gear", "external"),
        ({"mechanism": {"planet_teeth": 2}}, "mechanism.planet_teeth", "at least 3"),
    ],
)
def test_bad_planetary_scenes_are_refused(tmp_path, capsys, changes, field, text):
    scene = write_scene(tmp_path / "scene.toml", modified("planetary-kinematics", changes))
    out = tmp_path / "out"
    assert main(["report", str(scene), "-o", str(out), "--format", "json"]) == 2
    err = capsys.readouterr().err
    assert field in err and text in err and "Traceback" not in err, err
    assert not out.exists()


def test_planetary_with_cycle_data_is_refused_with_the_reason():
    data = modified("planetary-kinematics", {})
    data["cycle"] = modified("petrol-1cyl", {})["cycle"]
    scene = scene_from_dict(data, base_dir=examples_dir())
    with pytest.raises(SceneError, match="remove \\[cycle\\]"):
        run_scene(scene, REGISTRY)


def test_tdc_snapshot_foot_of_the_arm_is_the_rod_line_arm_away_from_the_shaft():
    """The stage's TDC drawing: the foot N of the perpendicular from the shaft on the rod's line
    lies on that line and |ON| is the rod-line arm that force_transmission computes independently."""
    g = _geometry("external", 0.03, 0.01, 0.01, 30.0)
    dc = pl.dead_centres(g)
    snap = tdc_snapshot_m(g, dc)
    foot, pin, piston = (np.array(snap[k]) for k in ("arm_foot", "pin", "piston_pin"))
    arm = abs(float(pl.force_transmission(dc.tdc_carrier_angle_rad, g).rod_line_arm_m))
    assert np.hypot(*foot) == pytest.approx(arm, rel=1e-12)
    along = piston - pin
    off = foot - pin
    assert abs(along[0] * off[1] - along[1] * off[0]) < 1e-15  # N on the rod's line
    assert snap["pitch_point"] == pytest.approx(
        [0.03 * math.sin(dc.tdc_carrier_angle_rad), 0.03 * math.cos(dc.tdc_carrier_angle_rad)],
        rel=1e-15,
    )


# ----------------------------------------------------------------------------- a kinematics-only note


@pytest.fixture(scope="module")
def planetary_run():
    scene = scene_from_dict(
        modified("planetary-kinematics", {"analysis": {"table_step_deg": 30}}),
        base_dir=examples_dir(),
    )
    return run_scene(scene, REGISTRY)


def test_piston_inertia_force_from_the_given_masses(planetary_run):
    """P_j = -(m_pg + m_r l_R/L) j_p, with j_p from a central difference of the displacement."""
    out = planetary_run.outputs["planetary"]
    motion = out.data["kinematics"]
    table = out.tables["planetary"]
    angle = table["crank_angle_deg"].to_numpy()
    h = 0.05  # deg
    d2s = (
        motion.displacement_at(angle + h)
        - 2 * motion.displacement_at(angle)
        + motion.displacement_at(angle - h)
    ) / np.radians(h) ** 2
    omega = math.pi * 3000 / 30
    mass = (
        0.45 + 0.60 * 0.275
    )  # piston group, the rod's share at the pin (examples' rod_cm_fraction)
    force = table["inertia_force_N"].to_numpy()
    np.testing.assert_allclose(force, -mass * omega**2 * d2s, atol=1e-5 * np.max(np.abs(force)))
    assert out.results["inertia_force_min_N"] == pytest.approx(force.min())


def test_kinematics_only_note_lists_what_it_uses_and_repeats_every_turn(planetary_run):
    html = render_html(planetary_run, REGISTRY, "uk").linked_html
    given = html.split("Таблиця 1.1", 1)[1].split("</table>", 1)[0]
    assert "<i>R</i> = <i>S</i>/2" not in given and "<i>λ</i> = <i>R</i>/<i>L</i>" not in given
    for absent in ("Маса шатунної шийки", "Тиск у картері"):
        assert absent not in given
    assert "Маса поршневої групи" in given
    # the rod dynamics' table runs over the motion's one turn, not the four-stroke cycle
    rod = planetary_run.outputs["rod_dynamics"].results
    assert rod["period_deg"] == 360.0
    assert ">720<" not in html and ">390<" not in html
    # the source cited by its number in the list of references; no phrase about a forces section
    number = re.search(r"\[(\d+), рис\.\s3б\]", html)
    assert number and "джерела;" not in html
    listed = re.findall(r"<li[^>]*>(.*?)</li>", html.split('class="references"')[-1], re.S)
    assert "Ismailov" in listed[int(number.group(1)) - 1]
    assert "Розділ про сили" not in html and "У розділі про сили" not in html


@pytest.mark.parametrize(
    ("language", "said"),
    [
        ("uk", "Для чотиритактного циклу вторинні ходи"),
        ("en", "For a four-stroke cycle the secondary"),
    ],
)
def test_the_secondary_strokes_are_judged_for_the_cycle_in_words(language, said):
    """ "Для 4-тактного циклу": the number of strokes is written as a word in the sentence."""
    import re

    from conftest import shared_html

    text = " ".join(
        re.sub(
            r"<[^>]+>", "", shared_html("planetary-kinematics", None, language).linked_html
        ).split()
    )
    assert said in text and not re.search(r"\d-(?:тактн|stroke)", text)
