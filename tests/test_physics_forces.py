"""Independent checks of crankdyn.physics.forces.

Reference values come from statics (force decomposition invariants, virtual
work), energy balance over a cycle and a separately computed p dV integral.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from crankdyn.physics import forces as frc
from crankdyn.physics import kinematics as kin

BORE_M = 0.092
CRANK_RADIUS_M = 0.043
ROD_RATIO = 0.28
ANGULAR_VELOCITY_RAD_S = 2.0 * math.pi * 5400.0 / 60.0
RECIPROCATING_MASS_KG = 0.62


def periodic_grid(period_rad, points):
    """Uniform grid over one period without the duplicated end point."""
    return np.arange(points) * (period_rad / points)


# --------------------------------------------------------------------------
# masses and areas
# --------------------------------------------------------------------------


def test_piston_area():
    assert frc.piston_area_m2(0.1) == pytest.approx(7.853981633974483e-3, rel=1e-15)
    np.testing.assert_allclose(
        frc.piston_area_m2([0.08, 0.1]), [5.026548245743669e-3, 7.853981633974483e-3]
    )


def test_rod_mass_split_eq17():
    rod_mass_kg, rod_length_m = 1.2, 0.16
    centre = 0.25 * rod_length_m
    reciprocating, rotating = frc.rod_mass_split_kg(rod_mass_kg, rod_length_m, centre)
    assert reciprocating == pytest.approx(0.3, rel=1e-15)
    assert rotating == pytest.approx(0.9, rel=1e-15)
    assert reciprocating + rotating == pytest.approx(rod_mass_kg, rel=1e-15)
    # Static equivalence: the two point masses keep the centre of mass.
    assert reciprocating * rod_length_m == pytest.approx(rod_mass_kg * centre, rel=1e-15)
    # A centre of mass at the big end puts everything on the crank pin.
    assert frc.rod_mass_split_kg(rod_mass_kg, rod_length_m, 0.0) == (
        0.0,
        pytest.approx(rod_mass_kg),
    )
    with pytest.raises(ValueError):
        frc.rod_mass_split_kg(rod_mass_kg, rod_length_m, 0.2)


@settings(max_examples=100, deadline=None)
@given(
    rod_mass_kg=st.floats(min_value=0.05, max_value=50.0),
    rod_length_m=st.floats(min_value=0.05, max_value=2.0),
    fraction=st.floats(min_value=0.0, max_value=1.0),
)
def test_property_rod_mass_split_sums_to_rod_mass(rod_mass_kg, rod_length_m, fraction):
    reciprocating, rotating = frc.rod_mass_split_kg(
        rod_mass_kg, rod_length_m, fraction * rod_length_m
    )
    assert reciprocating + rotating == pytest.approx(rod_mass_kg, rel=1e-14)
    assert reciprocating >= 0.0 and rotating >= 0.0


# --------------------------------------------------------------------------
# inertia forces
# --------------------------------------------------------------------------


def test_inertia_pressure_signs_at_dead_centres():
    area = frc.piston_area_m2(BORE_M)
    r, lam, w, m = CRANK_RADIUS_M, ROD_RATIO, ANGULAR_VELOCITY_RAD_S, RECIPROCATING_MASS_KG
    j_tdc = kin.piston_acceleration_exact_m_s2(0.0, r, lam, w)
    j_bdc = kin.piston_acceleration_exact_m_s2(np.pi, r, lam, w)
    p_tdc = frc.inertia_pressure_Pa(m, j_tdc, area)
    p_bdc = frc.inertia_pressure_Pa(m, j_bdc, area)
    # Poda: negative (away from the shaft) at TDC, positive at BDC.
    assert p_tdc == pytest.approx(-m * r * w**2 * (1 + lam) / area, rel=1e-14)
    assert p_bdc == pytest.approx(m * r * w**2 * (1 - lam) / area, rel=1e-14)
    assert p_tdc < 0 < p_bdc


def test_first_plus_second_order_equals_two_term_inertia():
    area = frc.piston_area_m2(BORE_M)
    r, lam, w, m = CRANK_RADIUS_M, ROD_RATIO, ANGULAR_VELOCITY_RAD_S, RECIPROCATING_MASS_KG
    alpha = np.linspace(0.0, 4.0 * np.pi, 721)
    first = frc.inertia_pressure_first_order_Pa(m, alpha, r, w, area)
    second = frc.inertia_pressure_second_order_Pa(m, alpha, r, lam, w, area)
    total = frc.inertia_pressure_Pa(m, kin.piston_acceleration_approx_m_s2(alpha, r, lam, w), area)
    amplitude = m * r * w**2 / area
    np.testing.assert_allclose(first + second, total, rtol=0, atol=1e-13 * amplitude)
    # First order alone is the harmonic (lambda = 0) acceleration.
    np.testing.assert_allclose(
        first,
        frc.inertia_pressure_Pa(m, kin.piston_acceleration_approx_m_s2(alpha, r, 0.0, w), area),
        rtol=0,
        atol=1e-13 * amplitude,
    )
    # Second order has twice the crank frequency: equal at alpha and alpha + pi.
    np.testing.assert_allclose(
        frc.inertia_pressure_second_order_Pa(m, alpha + np.pi, r, lam, w, area),
        second,
        atol=1e-9 * amplitude,
    )


# --------------------------------------------------------------------------
# decomposition through the rod
# --------------------------------------------------------------------------


def test_rod_forces_at_dead_centres():
    p1 = 3.7e6
    tdc = frc.rod_force_components(p1, 0.0, kin.rod_angle_rad(0.0, ROD_RATIO))
    assert isinstance(tdc, frc.RodForces)
    assert tdc.tangential_Pa == pytest.approx(0.0, abs=1e-9)
    assert tdc.radial_Pa == pytest.approx(p1, rel=1e-15)
    assert tdc.side_Pa == pytest.approx(0.0, abs=1e-9)
    assert tdc.rod_Pa == pytest.approx(p1, rel=1e-15)
    bdc = frc.rod_force_components(p1, np.pi, kin.rod_angle_rad(np.pi, ROD_RATIO))
    assert bdc.tangential_Pa == pytest.approx(0.0, abs=1e-9 * p1)
    assert bdc.radial_Pa == pytest.approx(-p1, rel=1e-15)
    assert bdc.rod_Pa == pytest.approx(p1, rel=1e-15)


def test_rod_forces_at_quarter_turn_by_hand():
    # alpha = 90 deg, lambda = 0.25: sin b = 0.25, cos b = sqrt(15)/4,
    # tan b = 1/sqrt(15); t = p1 cos b / cos b = p1, z = -p1 sin b / cos b.
    p1 = 1.0e6
    beta = kin.rod_angle_rad(np.pi / 2, 0.25)
    forces = frc.rod_force_components(p1, np.pi / 2, beta)
    assert forces.tangential_Pa == pytest.approx(p1, rel=1e-15)
    assert forces.radial_Pa == pytest.approx(-p1 / math.sqrt(15.0), rel=1e-14)
    assert forces.side_Pa == pytest.approx(p1 / math.sqrt(15.0), rel=1e-14)
    assert forces.rod_Pa == pytest.approx(4.0 * p1 / math.sqrt(15.0), rel=1e-14)


@settings(max_examples=300, deadline=None)
@given(
    rod_ratio=st.floats(min_value=0.05, max_value=0.6),
    crank_angle_rad=st.floats(min_value=-20.0, max_value=20.0),
    total_pressure_Pa=st.floats(min_value=-2e7, max_value=2e7),
)
def test_property_decomposition_invariants(rod_ratio, crank_angle_rad, total_pressure_Pa):
    beta = kin.rod_angle_rad(crank_angle_rad, rod_ratio)
    forces = frc.rod_force_components(total_pressure_Pa, crank_angle_rad, beta)
    scale = abs(total_pressure_Pa) + 1.0
    assert forces.tangential_Pa**2 + forces.radial_Pa**2 == pytest.approx(
        forces.rod_Pa**2, rel=1e-12, abs=1e-12 * scale**2
    )
    assert forces.side_Pa == pytest.approx(
        forces.rod_Pa * np.sin(beta), rel=1e-12, abs=1e-12 * scale
    )
    # The axial component of the rod force gives back p1.
    assert forces.rod_Pa * np.cos(beta) == pytest.approx(
        total_pressure_Pa, rel=1e-12, abs=1e-12 * scale
    )
    # Virtual work: t * R * d(alpha) = p1 * ds, so t = p1 v / (R omega).
    r, w = 0.05, 300.0
    v = kin.piston_velocity_exact_m_s(crank_angle_rad, r, rod_ratio, w)
    assert forces.tangential_Pa == pytest.approx(
        total_pressure_Pa * v / (r * w), rel=1e-11, abs=1e-11 * scale
    )


# --------------------------------------------------------------------------
# centrifugal force, resultant and torque
# --------------------------------------------------------------------------


def test_centrifugal_pressure_is_negative():
    area = frc.piston_area_m2(BORE_M)
    c = frc.centrifugal_pressure_Pa(1.4, CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S, area)
    assert c < 0
    assert c == pytest.approx(-1.4 * CRANK_RADIUS_M * ANGULAR_VELOCITY_RAD_S**2 / area, rel=1e-15)


def test_resultant_crank_pin_pressure():
    assert frc.resultant_crank_pin_pressure_Pa(4.0, 1.0, -4.0) == pytest.approx(5.0, rel=1e-15)
    assert frc.resultant_crank_pin_pressure_Pa(-4.0, 5.0, -2.0) == pytest.approx(5.0, rel=1e-15)
    assert frc.resultant_crank_pin_pressure_Pa(0.0, 2.0e6, -2.0e6) == 0.0


def test_crank_torque():
    area = frc.piston_area_m2(0.1)
    assert frc.crank_torque_Nm(1.0e6, 0.05, area) == pytest.approx(1.0e6 * 0.05 * area, rel=1e-15)


# --------------------------------------------------------------------------
# work over a cycle
# --------------------------------------------------------------------------


def _torque_from_total_pressure(total_pressure_Pa, alpha, r, lam, area):
    beta = kin.rod_angle_rad(alpha, lam)
    t = frc.rod_force_components(total_pressure_Pa, alpha, beta).tangential_Pa
    return frc.crank_torque_Nm(t, r, area)


@pytest.mark.parametrize("rod_ratio", [0.0, 0.25, 0.33, 0.5])
def test_inertia_forces_do_no_net_work(rod_ratio):
    area = frc.piston_area_m2(BORE_M)
    r, w, m = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S, RECIPROCATING_MASS_KG
    alpha = periodic_grid(2.0 * np.pi, 360)
    p_j = frc.inertia_pressure_Pa(
        m, kin.piston_acceleration_exact_m_s2(alpha, r, rod_ratio, w), area
    )
    torque = _torque_from_total_pressure(p_j, alpha, r, rod_ratio, area)
    amplitude = np.max(np.abs(torque)) * 2.0 * np.pi
    assert amplitude > 0
    assert abs(frc.indicated_work_from_torque_J(alpha, torque)) < 1e-13 * amplitude
    assert abs(frc.cycle_mean(torque)) < 1e-13 * np.max(np.abs(torque))


def test_constant_gas_pressure_gives_zero_mean_torque():
    area = frc.piston_area_m2(BORE_M)
    alpha = periodic_grid(4.0 * np.pi, 720)
    torque = _torque_from_total_pressure(
        np.full_like(alpha, 2.0e6), alpha, CRANK_RADIUS_M, ROD_RATIO, area
    )
    assert abs(frc.cycle_mean(torque)) < 1e-13 * np.max(np.abs(torque))


def _gas_pressure_Pa(alpha):
    # Smooth 4 pi-periodic pulse peaking 15 deg after the firing TDC at
    # 360 deg, on top of a constant level: positive net work.
    peak_rad = 2.0 * np.pi + np.deg2rad(15.0)
    return 0.1e6 + 6.0e6 * np.exp(40.0 * (np.cos(0.5 * (alpha - peak_rad)) - 1.0))


def test_work_from_torque_equals_closed_cycle_p_dv():
    area = frc.piston_area_m2(BORE_M)
    r, lam = CRANK_RADIUS_M, ROD_RATIO
    alpha = periodic_grid(4.0 * np.pi, 720)
    torque = _torque_from_total_pressure(_gas_pressure_Pa(alpha), alpha, r, lam, area)
    work_J = frc.indicated_work_from_torque_J(alpha, torque)

    # Reference computed without any velocity or force formula: a Stieltjes
    # trapezoid sum of p dV with V = F s on a fine closed grid.
    fine = np.linspace(0.0, 4.0 * np.pi, 800001)
    volume_m3 = area * kin.piston_displacement_exact_m(fine, r, lam)
    pressure = _gas_pressure_Pa(fine)
    reference_J = np.sum(0.5 * (pressure[1:] + pressure[:-1]) * np.diff(volume_m3))

    assert reference_J > 100.0  # a meaningful positive cycle work
    assert work_J == pytest.approx(reference_J, rel=1e-8)
    # Mean torque over the 4 pi cycle is the work divided by 4 pi.
    assert frc.cycle_mean(torque) == pytest.approx(work_J / (4.0 * np.pi), rel=1e-12)


def test_periodic_rule_is_spectrally_accurate():
    # Refining the periodic grid changes the result only at round-off level,
    # far below the O(h^2) drift of a non-periodic trapezoid rule.
    area = frc.piston_area_m2(BORE_M)
    results = []
    for points in (180, 720, 1440):
        alpha = periodic_grid(4.0 * np.pi, points)
        torque = _torque_from_total_pressure(
            _gas_pressure_Pa(alpha), alpha, CRANK_RADIUS_M, ROD_RATIO, area
        )
        results.append(frc.indicated_work_from_torque_J(alpha, torque))
    assert results[1] == pytest.approx(results[2], rel=1e-12)
    assert results[0] == pytest.approx(results[2], rel=1e-12)


def test_work_rejects_bad_grids():
    alpha = periodic_grid(4.0 * np.pi, 10)
    with pytest.raises(ValueError):
        frc.indicated_work_from_torque_J(alpha**1.1, np.ones(10))
    with pytest.raises(ValueError):
        frc.indicated_work_from_torque_J(alpha, np.ones(9))
    with pytest.raises(ValueError):
        frc.indicated_work_from_torque_J(alpha[::-1], np.ones(10))
    # Constant torque: work is torque times the covered period.
    assert frc.indicated_work_from_torque_J(alpha, np.full(10, 3.0)) == pytest.approx(
        3.0 * 4.0 * np.pi
    )


def test_a_positive_side_force_presses_the_wall_the_crank_pin_leaves_after_tdc():
    """The note's sign rule for N: positive when it presses the piston against the wall the crank
    pin moves away from after TDC. At α = 30° the pin stands to that wall's far side
    (x = R sin α > 0, the cylinder axis at x = 0); the rod, compressed by p₁ > 0, pushes the
    piston along itself from the pin, so towards −x, onto that wall: and n = p₁ tan β > 0."""
    import math

    from crankdyn.physics.forces import rod_force_components
    from crankdyn.physics.kinematics import rod_angle_rad

    radius, rod_ratio, alpha = 0.05, 0.25, math.radians(30.0)
    pin_x, pin_y = radius * math.sin(alpha), radius * math.cos(alpha)
    piston_y = pin_y + math.sqrt((radius / rod_ratio) ** 2 - pin_x**2)
    push_x = 0.0 - pin_x  # from the pin towards the piston pin, along the compressed rod
    assert push_x < 0 and piston_y > pin_y
    beta = rod_angle_rad(alpha, rod_ratio)
    side = rod_force_components(2.0e6, alpha, beta).side_Pa
    assert side > 0
    assert side == pytest.approx(2.0e6 * abs(push_x) / (piston_y - pin_y), rel=1e-12)


def test_an_offset_mechanisms_side_force_is_set_beside_the_central_ones():
    """The forces section of an offset crank-slider gives the power stroke's side force against
    the central mechanism's at the same axial force p₁: recomputed here from the forces table's
    p₁ and both rod angles (the offset's from its own geometry: sin β = (R sin φ − e)/L)."""
    import math
    import re

    import numpy as np
    from conftest import shared_html, shared_run

    run = shared_run("offset-crank-engine")
    r = run.outputs["forces"].results
    f = run.outputs["forces"].tables.arrays("forces")
    motion = run.outputs["offset_crank"].data["kinematics"]
    lam, tdc = motion.extra["rod_ratio"], motion.extra["crank_angle_at_tdc_rad"]
    e_over_l = motion.extra["offset_m"] / (motion.crank_radius_m / lam)
    alpha = np.radians(f["crank_angle_deg"])
    offset_beta = np.arcsin(lam * np.sin(alpha + tdc) - e_over_l)
    central_beta = np.arcsin(lam * np.sin(alpha))
    p1 = f["total_Pa"]
    assert np.allclose(f["side_Pa"], p1 * np.tan(offset_beta), atol=1e-6 * np.abs(p1).max())
    bdc = motion.extra["bdc_crank_angle_deg"]
    firing = 360.0 if run.scene.engine.strokes == 4 else 0.0
    power = (f["crank_angle_deg"] >= firing) & (f["crank_angle_deg"] <= firing + bdc)
    expected = (p1 * np.tan(central_beta))[power].max()
    assert r["side_power_stroke_central_max_Pa"] == pytest.approx(expected, rel=1e-9)
    assert r["side_power_stroke_max_Pa"] == pytest.approx(f["side_Pa"][power].max(), rel=1e-9)
    assert not math.isclose(r["side_power_stroke_max_Pa"], expected, rel_tol=1e-3)
    text = " ".join(
        re.sub(r"<[^>]+>", " ", shared_html("offset-crank-engine", None, "en").linked_html).split()
    )
    mpa = f"{r['side_power_stroke_max_Pa'] / 1e6:.3f}"
    assert f"With the offset the side force of the power stroke reaches {mpa} MPa" in text
    assert "The offset changes the largest side force of the power stroke to" in text
