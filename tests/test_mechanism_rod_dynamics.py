"""Connecting-rod dynamics: the generic rod kinematics against closed forms and finite
differences, the equivalence of the exact mass models, the two-mass error, the stage."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import modified

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import plan, run_scene
from crankdyn.errors import SceneError
from crankdyn.physics import kinematics as central
from crankdyn.physics import rod_dynamics as rd
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
M, L, LR, I_G = 0.6, 0.14, 0.0385, 0.0014


def test_slider_from_a_crank_circle_is_the_central_crank_slider():
    R, lam = 0.039, 0.039 / L
    alpha = np.linspace(0.0, 2 * np.pi, 181)
    s, c = np.sin(alpha), np.cos(alpha)
    m = rd.slider_from_big_end(R * s, R * c, R * c, -R * s, -R * s, -R * c, L)
    np.testing.assert_allclose(
        R + L - m.pin_z_m, central.piston_displacement_exact_m(alpha, R, lam), atol=1e-15
    )
    np.testing.assert_allclose(
        -m.pin_z_d1_m, central.piston_velocity_exact_m_s(alpha, R, lam, 1.0), atol=1e-15
    )
    np.testing.assert_allclose(
        -m.pin_z_d2_m, central.piston_acceleration_exact_m_s2(alpha, R, lam, 1.0), atol=1e-14
    )
    np.testing.assert_allclose(m.rod_angle_rad, central.rod_angle_rad(alpha, lam), atol=1e-15)
    np.testing.assert_allclose(
        m.rod_angle_d1, central.rod_angular_velocity_rad_s(alpha, lam, 1.0), atol=1e-15
    )
    np.testing.assert_allclose(
        m.rod_angle_d2, central.rod_angular_acceleration_rad_s2(alpha, lam, 1.0), atol=1e-14
    )


def test_slider_refuses_a_big_end_out_of_reach():
    with pytest.raises(ValueError, match="cannot reach"):
        rd.slider_from_big_end(np.array([0.2]), 0.0, 0.0, 0.0, 0.0, 0.0, 0.15)


def test_rod_point_motion_against_the_closed_form_and_finite_differences():
    R, lam, omega = 0.039, 0.039 / L, 500.0
    alpha = np.linspace(0.0, 2 * np.pi, 361)
    beta = central.rod_angle_rad(alpha, lam)
    rate = central.rod_angular_velocity_rad_s(alpha, lam, omega)
    accel = central.rod_angular_acceleration_rad_s2(alpha, lam, omega)
    v_pin = -central.piston_velocity_exact_m_s(alpha, R, lam, omega)
    a_pin = -central.piston_acceleration_exact_m_s2(alpha, R, lam, omega)
    ax, az = rd.rod_point_acceleration_m_s2(a_pin, beta, rate, accel, L - LR)
    cx, cz = central.rod_point_acceleration_m_s2(alpha, R, lam, LR, omega)
    np.testing.assert_allclose(ax, cx, atol=1e-9 * np.max(np.abs(cx)))
    np.testing.assert_allclose(az, cz, atol=1e-9 * np.max(np.abs(cz)))
    vx, vz = rd.rod_point_velocity_m_s(v_pin, beta, rate, L - LR)
    h = 1e-5
    px2, pz2 = central.rod_point_position_m(alpha + h, R, lam, LR)
    px1, pz1 = central.rod_point_position_m(alpha - h, R, lam, LR)
    np.testing.assert_allclose(vx, (px2 - px1) / (2 * h) * omega, atol=1e-7)
    np.testing.assert_allclose(vz, (pz2 - pz1) / (2 * h) * omega, atol=1e-7)


def test_three_mass_model_is_dynamically_equivalent():
    a, b, g = rd.three_mass_split_kg(M, L, LR, I_G)
    assert a + b + g == pytest.approx(M, rel=1e-15)
    assert a * (L - LR) == pytest.approx(b * LR, rel=1e-14)  # same centre of mass
    assert a * (L - LR) ** 2 + b * LR**2 == pytest.approx(
        I_G, rel=1e-14
    )  # same moment of inertia about G
    # the two-mass split keeps the mass and the centre of mass but not the inertia
    assert rd.two_mass_moment_of_inertia_kg_m2(M, L, LR) == pytest.approx(
        M * LR / L * (L - LR) ** 2 + M * (L - LR) / L * LR**2, rel=1e-14
    )
    assert rd.three_mass_split_kg(M, L, LR, rd.two_mass_moment_of_inertia_kg_m2(M, L, LR))[
        2
    ] == pytest.approx(0.0, abs=1e-15)


def test_periodic_derivative_is_spectrally_accurate():
    x = np.linspace(0.0, 4 * np.pi, 720, endpoint=False)
    f = np.exp(np.sin(x)) + 0.2 * np.cos(3 * x)
    np.testing.assert_allclose(
        rd.periodic_derivative(f, 4 * np.pi),
        np.cos(x) * np.exp(np.sin(x)) - 0.6 * np.sin(3 * x),
        atol=1e-11,
    )


# ----------------------------------------------------------------------------- the stage


def _run(name, changes=None):
    return run_scene(
        scene_from_dict(modified(name, changes or {}), base_dir=examples_dir()), REGISTRY
    )


@pytest.mark.parametrize(
    "name, changes",
    [
        ("offset-crank-engine", {}),
        ("planetary-kinematics", {}),
        ("petrol-1cyl", {"masses": {"rod_moment_of_inertia": "0.0015 kg m^2"}}),
    ],
)
def test_exact_models_agree_and_differ_from_two_masses_by_the_correction_couple(name, changes):
    result = _run(name, changes)
    out = result.outputs["rod_dynamics"]
    f, r = out.tables["rod_dynamics"], out.results
    exact, two = f["torque_exact_Nm"].to_numpy(), f["torque_two_mass_Nm"].to_numpy()
    scale = np.max(np.abs(exact))
    motion = result.outputs[result.stages_run[0]].data["kinematics"]
    omega = motion.angular_velocity_rad_s
    inertia_two = r["two_mass_moment_of_inertia_kg_m2"]
    rate, accel = (
        f["rod_angular_velocity_rad_s"].to_numpy(),
        f["rod_angular_acceleration_rad_s2"].to_numpy(),
    )
    # exact - two-mass = -(I_G - I_2) beta' beta'' / omega
    np.testing.assert_allclose(
        exact - two,
        -(r["rod_moment_of_inertia_kg_m2"] - inertia_two) * rate * accel / omega,
        atol=1e-9 * scale,
    )
    # the three-mass model and the correction couple are the same exact model
    for model in ("three_mass", "correction_couple"):
        chosen = _run(name, {**changes, "rod_dynamics": {"model": model}}).outputs["rod_dynamics"]
        np.testing.assert_allclose(
            chosen.tables["rod_dynamics"]["torque_model_Nm"], exact, atol=1e-9 * scale
        )
    # inertia loads do no net work over a cycle
    assert abs(np.mean(exact)) < 1e-9 * scale and abs(np.mean(two)) < 1e-9 * scale
    assert r["torque_difference_max_abs_Nm"] > 0.01 * r["torque_two_mass_max_abs_Nm"]


def test_two_mass_torque_of_the_crank_slider_is_the_textbook_one():
    result = _run("petrol-1cyl", {"masses": {"rod_moment_of_inertia": "0.0015 kg m^2"}})
    r = result.outputs["rod_dynamics"].results
    motion = result.outputs["kinematics"].data["kinematics"]
    # the big-end mass runs on the crank circle (no torque); the small-end mass reciprocates: -m_A j ds/dalpha
    textbook = -r["two_mass_small_end_kg"] * motion.piston_acceleration_m_s2 * motion.torque_arm_m
    np.testing.assert_allclose(
        result.outputs["rod_dynamics"].tables["rod_dynamics"]["torque_two_mass_Nm"],
        textbook,
        atol=1e-9 * np.max(np.abs(textbook)),
    )


def test_crank_slider_passes_its_closed_form_rod_rates():
    # the kinematics stage hands its closed-form rates on: no note on spectral differentiation
    result = _run("petrol-1cyl", {"masses": {"rod_moment_of_inertia": "0.0015 kg m^2"}})
    out = result.outputs["rod_dynamics"]
    assert out.results["derivatives"] == "analytic"
    assert "rod_dynamics.note_spectral" not in [key for key, _ in out.notes]
    f = out.tables["rod_dynamics"]
    motion = result.outputs["kinematics"].data["kinematics"]
    lam, omega = motion.extra["rod_ratio"], motion.angular_velocity_rad_s
    closed = central.rod_angular_acceleration_rad_s2(motion.crank_angle_rad, lam, omega)
    np.testing.assert_allclose(
        f["rod_angular_acceleration_rad_s2"], closed, atol=1e-8 * np.max(np.abs(closed))
    )
    # and the centre-of-mass acceleration is the kinematics stage's
    kin = result.outputs["kinematics"].tables["kinematics"]
    np.testing.assert_allclose(
        f["cm_acceleration_z_m_s2"],
        kin["rod_cm_acceleration_z_m_s2"],
        atol=1e-8 * np.max(np.abs(kin["rod_cm_acceleration_z_m_s2"])),
    )


@pytest.mark.parametrize(
    "name, changes, reason",
    [
        ("petrol-1cyl", {}, "rod_moment_of_inertia"),
        ("kinematics-only", {}, "[masses]"),
        ("radial9-aircraft", {"masses": {"rod_moment_of_inertia": "0.01 kg m^2"}}, "articulated"),
    ],
)
def test_rod_dynamics_is_left_out_with_a_reason(name, changes, reason):
    the_plan = plan(scene_from_dict(modified(name, changes), base_dir=examples_dir()), REGISTRY)
    assert "rod_dynamics" not in [s.name for s in the_plan.order]
    assert reason in the_plan.skipped["rod_dynamics"]


def test_bad_rod_dynamics_input():
    with pytest.raises(SceneError, match="rod_dynamics.model"):
        _run("offset-crank-engine", {"rod_dynamics": {"model": "four_mass"}})
    with pytest.raises(SceneError, match="masses.rod_moment_of_inertia"):
        scene_from_dict(
            modified("offset-crank-engine", {"masses": {"rod_moment_of_inertia": "0.0014 kg"}})
        )
    with pytest.raises(SceneError, match="masses.rod_moment_of_inertia"):
        scene_from_dict(
            modified("offset-crank-engine", {"masses": {"rod_moment_of_inertia": 0.0014}})
        )


def test_without_the_moment_of_inertia_the_two_mass_model_is_reported_alone():
    changes = {"masses": {"rod_moment_of_inertia": None}, "rod_dynamics": None}
    result = _run("offset-crank-engine", changes)
    out = result.outputs["rod_dynamics"]
    assert (
        "rod_moment_of_inertia_kg_m2" not in out.results
        and "torque_exact_Nm" not in out.tables["rod_dynamics"]
    )
    assert ("rod_dynamics.note_no_inertia", {}) in out.notes
    with_inertia = _run("offset-crank-engine", {"rod_dynamics": None}).outputs["rod_dynamics"]
    np.testing.assert_allclose(
        out.tables["rod_dynamics"]["torque_two_mass_Nm"],
        with_inertia.tables["rod_dynamics"]["torque_two_mass_Nm"],
        rtol=0,
        atol=0,
    )
    from crankdyn.report.document import render_html

    rendered = render_html(result, REGISTRY, "uk")
    assert not rendered.missing_translations, rendered.missing_translations
    assert 'data-stage="rod_dynamics"' in rendered.linked_html
    with pytest.raises(SceneError, match="rod_dynamics.model"):
        _run(
            "offset-crank-engine", {"masses": {"rod_moment_of_inertia": None}}
        )  # the example asks for three_mass


@pytest.mark.parametrize(
    ("name", "changes", "language", "expected", "forces"),
    [
        (
            "offset-crank-engine",
            {},
            "uk",
            "У розділі {n} цей момент обчислено за тримасовою моделлю. Сили і крутний момент "
            "обчислено за двомасовою моделлю посібника, тож цієї різниці вони не містять.",
            True,
        ),
        (
            "planetary-kinematics",
            {"rod_dynamics": {"model": "correction_couple"}},
            "ru",
            "В разделе {n} этот момент вычислен по двухмассовой модели с корректирующим моментом.",
            False,
        ),
    ],
)
def test_a_rod_model_of_the_section_alone_is_concluded_with_its_section(
    name, changes, language, expected, forces
):
    """A model other than the two-mass one is the rod dynamics section's own: the conclusion
    names that section by its number and the model in the sentence's case, and says that the
    forces and the torque keep the two-mass split only where the run computed them (a planetary
    mechanism without a cycle has none)."""
    import re

    from crankdyn.report.document import render_html

    html = render_html(_run(name, changes), REGISTRY, language).html
    number = re.search(r'data-stage="rod_dynamics"[^>]*>\s*<h2[^>]*>(\d+)', html)
    assert number, "the rod dynamics section has a number"
    conclusions = html[html.rindex('class="conclusions"') :]
    assert expected.format(n=number.group(1)) in re.sub(r"<[^>]+>", "", conclusions)
    assert ("двомасовою моделлю посібника" in conclusions) is forces
    assert "У цьому розділі" not in conclusions and "В этом разделе" not in conclusions
