"""Independent checks of crankdyn.physics.kinematics.

The reference values come from closed forms at the dead centres, series
expansions in the rod ratio, finite differences in time, dense-grid searches
and a worked example computed by hand.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from crankdyn.physics import kinematics as kin

CRANK_RADIUS_M = 0.045
ANGULAR_VELOCITY_RAD_S = 2.0 * math.pi * 5600.0 / 60.0
ROD_RATIOS = [0.0, 0.18, 0.25, 0.3, 0.5]

# Fourth-order central stencils; with a step of 1e-3 rad of crank angle the
# truncation error is ~1e-12 and the round-off of the second derivative
# ~1e-10 of the amplitude, so 1e-8 leaves a wide but still sensitive margin.
STEP_RAD = 1e-3
FD_TOLERANCE = 1e-8


def first_derivative_in_time(func, crank_angle_rad, angular_velocity_rad_s, step_rad=STEP_RAD):
    """d/dt of func(alpha) at constant omega, 5-point central stencil."""
    h = step_rad
    a = np.asarray(crank_angle_rad, dtype=float)
    d_dalpha = (-func(a + 2 * h) + 8 * func(a + h) - 8 * func(a - h) + func(a - 2 * h)) / (12 * h)
    return angular_velocity_rad_s * d_dalpha


def second_derivative_in_time(func, crank_angle_rad, angular_velocity_rad_s, step_rad=STEP_RAD):
    """d2/dt2 of func(alpha) at constant omega, 5-point central stencil."""
    h = step_rad
    a = np.asarray(crank_angle_rad, dtype=float)
    d2 = (
        -func(a + 2 * h) + 16 * func(a + h) - 30 * func(a) + 16 * func(a - h) - func(a - 2 * h)
    ) / (12 * h * h)
    return angular_velocity_rad_s**2 * d2


ANGLES_RAD = np.linspace(0.0, 4.0 * np.pi, 721)


# --------------------------------------------------------------------------
# dead centres
# --------------------------------------------------------------------------


@pytest.mark.parametrize("rod_ratio", ROD_RATIOS)
@pytest.mark.parametrize("form", ["exact", "approx"])
def test_dead_centre_values(rod_ratio, form):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    displacement = getattr(kin, f"piston_displacement_{form}_m")
    velocity = getattr(kin, f"piston_velocity_{form}_m_s")
    acceleration = getattr(kin, f"piston_acceleration_{form}_m_s2")
    assert displacement(0.0, r, rod_ratio) == pytest.approx(0.0, abs=1e-15)
    assert displacement(np.pi, r, rod_ratio) == pytest.approx(2.0 * r, rel=1e-14)
    assert displacement(2.0 * np.pi, r, rod_ratio) == pytest.approx(0.0, abs=1e-15)
    assert velocity(0.0, r, rod_ratio, w) == pytest.approx(0.0, abs=1e-12 * r * w)
    assert velocity(np.pi, r, rod_ratio, w) == pytest.approx(0.0, abs=1e-12 * r * w)
    assert acceleration(0.0, r, rod_ratio, w) == pytest.approx(
        r * w**2 * (1 + rod_ratio), rel=1e-14
    )
    assert acceleration(np.pi, r, rod_ratio, w) == pytest.approx(
        -r * w**2 * (1 - rod_ratio), rel=1e-14
    )


@pytest.mark.parametrize("rod_ratio", ROD_RATIOS)
def test_velocity_at_quarter_turn_equals_crank_pin_speed(rod_ratio):
    # At 90 degrees the rod's instantaneous centre makes the piston move
    # exactly with the crank-pin speed R*omega, whatever lambda is.
    v = kin.piston_velocity_exact_m_s(np.pi / 2, CRANK_RADIUS_M, rod_ratio, ANGULAR_VELOCITY_RAD_S)
    assert v == pytest.approx(CRANK_RADIUS_M * ANGULAR_VELOCITY_RAD_S, rel=1e-14)


def test_displacement_at_quarter_turn_matches_geometry():
    # At 90 degrees: s = R + L - sqrt(L^2 - R^2), straight from Pythagoras.
    r, rod_length = 0.05, 0.17
    expected = r + rod_length - math.sqrt(rod_length**2 - r**2)
    assert kin.piston_displacement_exact_m(np.pi / 2, r, r / rod_length) == pytest.approx(
        expected, rel=1e-14
    )


def test_exact_displacement_matches_textbook_form_and_zero_rod_ratio_limit():
    r = CRANK_RADIUS_M
    for rod_ratio in [0.1, 0.3, 0.6]:
        beta = np.arcsin(rod_ratio * np.sin(ANGLES_RAD))
        textbook = r * ((1 - np.cos(ANGLES_RAD)) + (1 - np.cos(beta)) / rod_ratio)
        np.testing.assert_allclose(
            kin.piston_displacement_exact_m(ANGLES_RAD, r, rod_ratio), textbook, rtol=0, atol=1e-14
        )
    # lambda -> 0: pure harmonic motion, finite and without 0/0.
    for rod_ratio in [0.0, 1e-300, 1e-12]:
        s = kin.piston_displacement_exact_m(ANGLES_RAD, r, rod_ratio)
        assert np.all(np.isfinite(s))
        # first-order rod correction R lambda sin^2(alpha) / 2 (2e-14 m at 1e-12)
        harmonic_plus_rod = r * (1 - np.cos(ANGLES_RAD) + 0.5 * rod_ratio * np.sin(ANGLES_RAD) ** 2)
        np.testing.assert_allclose(s, harmonic_plus_rod, rtol=0, atol=1e-15)


def test_rod_angle_is_arcsin_and_sign_follows_rotation():
    beta = kin.rod_angle_rad(np.deg2rad([0.0, 90.0, 180.0, 270.0]), 0.3)
    np.testing.assert_allclose(beta, [0.0, math.asin(0.3), 0.0, -math.asin(0.3)], atol=1e-15)


@pytest.mark.parametrize("bad_rod_ratio", [-0.1, 1.0, 1.5])
def test_invalid_rod_ratio_rejected(bad_rod_ratio):
    with pytest.raises(ValueError):
        kin.piston_displacement_exact_m(0.3, CRANK_RADIUS_M, bad_rod_ratio)


# --------------------------------------------------------------------------
# exact versus two-term form
# --------------------------------------------------------------------------


def test_two_term_displacement_error_is_third_order_in_rod_ratio():
    r = CRANK_RADIUS_M
    angles = np.linspace(0.0, 2.0 * np.pi, 4001)
    rod_ratios = [0.2, 0.1, 0.05, 0.025]
    max_errors = []
    for rod_ratio in rod_ratios:
        diff = kin.piston_displacement_exact_m(
            angles, r, rod_ratio
        ) - kin.piston_displacement_approx_m(angles, r, rod_ratio)
        max_errors.append(np.max(np.abs(diff)))
    normalised = np.array(max_errors) / (r * np.array(rod_ratios) ** 3)
    # Series: (1 - cos b)/lambda = lambda sin^2/2 + lambda^3 sin^4/8 + ..., so
    # the leading neglected term peaks at R lambda^3 / 8.
    assert np.all(normalised < 0.2)
    assert normalised[-1] == pytest.approx(1.0 / 8.0, rel=0.01)
    ratios = np.array(max_errors[:-1]) / np.array(max_errors[1:])
    np.testing.assert_allclose(ratios, 8.0, rtol=0.07)


@pytest.mark.parametrize("rod_ratio", [0.05, 0.3])
def test_two_term_forms_are_first_terms_of_exact(rod_ratio):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    # Velocity and acceleration errors are O(lambda^3) as well.
    v_err = kin.piston_velocity_exact_m_s(
        ANGLES_RAD, r, rod_ratio, w
    ) - kin.piston_velocity_approx_m_s(ANGLES_RAD, r, rod_ratio, w)
    j_err = kin.piston_acceleration_exact_m_s2(
        ANGLES_RAD, r, rod_ratio, w
    ) - kin.piston_acceleration_approx_m_s2(ANGLES_RAD, r, rod_ratio, w)
    assert np.max(np.abs(v_err)) < 1.0 * r * w * rod_ratio**3
    assert np.max(np.abs(j_err)) < 3.0 * r * w**2 * rod_ratio**3


# --------------------------------------------------------------------------
# derivative consistency
# --------------------------------------------------------------------------


@pytest.mark.parametrize("rod_ratio", ROD_RATIOS)
@pytest.mark.parametrize("form", ["exact", "approx"])
def test_velocity_and_acceleration_are_time_derivatives_of_displacement(rod_ratio, form):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    displacement = getattr(kin, f"piston_displacement_{form}_m")
    velocity = getattr(kin, f"piston_velocity_{form}_m_s")
    acceleration = getattr(kin, f"piston_acceleration_{form}_m_s2")

    def s_of_alpha(a):
        return displacement(a, r, rod_ratio)

    def v_of_alpha(a):
        return velocity(a, r, rod_ratio, w)

    v_fd = first_derivative_in_time(s_of_alpha, ANGLES_RAD, w)
    j_fd = second_derivative_in_time(s_of_alpha, ANGLES_RAD, w)
    j_fd_from_v = first_derivative_in_time(v_of_alpha, ANGLES_RAD, w)
    np.testing.assert_allclose(v_of_alpha(ANGLES_RAD), v_fd, rtol=0, atol=FD_TOLERANCE * r * w)
    np.testing.assert_allclose(
        acceleration(ANGLES_RAD, r, rod_ratio, w), j_fd, rtol=0, atol=FD_TOLERANCE * r * w**2
    )
    np.testing.assert_allclose(
        acceleration(ANGLES_RAD, r, rod_ratio, w), j_fd_from_v, rtol=0, atol=FD_TOLERANCE * r * w**2
    )


@pytest.mark.parametrize("rod_ratio", ROD_RATIOS)
def test_jerk_is_time_derivative_of_acceleration(rod_ratio):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    jerk_fd = first_derivative_in_time(
        lambda a: kin.piston_acceleration_exact_m_s2(a, r, rod_ratio, w), ANGLES_RAD, w
    )
    np.testing.assert_allclose(
        kin.piston_jerk_exact_m_s3(ANGLES_RAD, r, rod_ratio, w),
        jerk_fd,
        rtol=0,
        atol=FD_TOLERANCE * r * w**3,
    )


@pytest.mark.parametrize("rod_ratio", ROD_RATIOS)
def test_rod_angular_rates_are_derivatives_of_rod_angle(rod_ratio):
    w = ANGULAR_VELOCITY_RAD_S

    def beta(a):
        return kin.rod_angle_rad(a, rod_ratio)

    np.testing.assert_allclose(
        kin.rod_angular_velocity_rad_s(ANGLES_RAD, rod_ratio, w),
        first_derivative_in_time(beta, ANGLES_RAD, w),
        rtol=0,
        atol=FD_TOLERANCE * w,
    )
    np.testing.assert_allclose(
        kin.rod_angular_acceleration_rad_s2(ANGLES_RAD, rod_ratio, w),
        second_derivative_in_time(beta, ANGLES_RAD, w),
        rtol=0,
        atol=FD_TOLERANCE * w**2,
    )


@settings(max_examples=200, deadline=None)
@given(
    rod_ratio=st.floats(min_value=0.05, max_value=0.6),
    crank_angle_rad=st.floats(min_value=-10.0, max_value=10.0),
)
def test_property_exact_kinematics_consistent(rod_ratio, crank_angle_rad):
    r, w = 0.07, 250.0
    s_fd_v = first_derivative_in_time(
        lambda a: kin.piston_displacement_exact_m(a, r, rod_ratio), crank_angle_rad, w
    )
    s_fd_j = second_derivative_in_time(
        lambda a: kin.piston_displacement_exact_m(a, r, rod_ratio), crank_angle_rad, w
    )
    assert kin.piston_velocity_exact_m_s(crank_angle_rad, r, rod_ratio, w) == pytest.approx(
        s_fd_v, abs=FD_TOLERANCE * r * w
    )
    assert kin.piston_acceleration_exact_m_s2(crank_angle_rad, r, rod_ratio, w) == pytest.approx(
        s_fd_j, abs=FD_TOLERANCE * r * w**2
    )
    # The piston pin lies on the cylinder axis at height R + L - s.
    rod_length = r / rod_ratio
    x_pin, z_pin = kin.rod_point_position_m(crank_angle_rad, r, rod_ratio, rod_length)
    assert x_pin == pytest.approx(0.0, abs=1e-14)
    assert z_pin == pytest.approx(
        r + rod_length - kin.piston_displacement_exact_m(crank_angle_rad, r, rod_ratio), abs=1e-13
    )


# --------------------------------------------------------------------------
# points on the rod
# --------------------------------------------------------------------------


@pytest.mark.parametrize("rod_ratio", [0.2, 0.3, 0.45])
def test_rod_point_end_positions(rod_ratio):
    r = CRANK_RADIUS_M
    rod_length = r / rod_ratio
    x_b, z_b = kin.rod_point_position_m(ANGLES_RAD, r, rod_ratio, 0.0)
    np.testing.assert_allclose(x_b, r * np.sin(ANGLES_RAD), atol=1e-15)
    np.testing.assert_allclose(z_b, r * np.cos(ANGLES_RAD), atol=1e-15)
    x_a, z_a = kin.rod_point_position_m(ANGLES_RAD, r, rod_ratio, rod_length)
    np.testing.assert_allclose(x_a, 0.0, atol=1e-15)
    np.testing.assert_allclose(
        z_a,
        r + rod_length - kin.piston_displacement_exact_m(ANGLES_RAD, r, rod_ratio),
        rtol=0,
        atol=1e-15,
    )
    # Any point stays at its fixed distance from the crank pin.
    x_c, z_c = kin.rod_point_position_m(ANGLES_RAD, r, rod_ratio, 0.3 * rod_length)
    np.testing.assert_allclose(np.hypot(x_c - x_b, z_c - z_b), 0.3 * rod_length, rtol=1e-14)


@pytest.mark.parametrize("rod_ratio", [0.0, 0.25, 0.4])
@pytest.mark.parametrize("fraction_from_big_end", [0.0, 0.27, 1.0])
def test_rod_point_velocity_and_acceleration_match_finite_differences(
    rod_ratio, fraction_from_big_end
):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    rod_length = 0.16 if rod_ratio == 0.0 else r / rod_ratio
    distance = fraction_from_big_end * rod_length
    vx, vz = kin.rod_point_velocity_m_s(ANGLES_RAD, r, rod_ratio, distance, w)
    ax, az = kin.rod_point_acceleration_m_s2(ANGLES_RAD, r, rod_ratio, distance, w)
    for component, velocity, acceleration in [(0, vx, ax), (1, vz, az)]:

        def coordinate(a, component=component):
            return kin.rod_point_position_m(a, r, rod_ratio, distance)[component]

        np.testing.assert_allclose(
            velocity,
            first_derivative_in_time(coordinate, ANGLES_RAD, w),
            rtol=0,
            atol=FD_TOLERANCE * r * w,
        )
        np.testing.assert_allclose(
            acceleration,
            second_derivative_in_time(coordinate, ANGLES_RAD, w),
            rtol=0,
            atol=FD_TOLERANCE * r * w**2,
        )


@pytest.mark.parametrize("rod_ratio", [0.25, 0.4])
def test_piston_pin_kinematics_equal_piston_kinematics(rod_ratio):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    rod_length = r / rod_ratio
    vx, vz = kin.rod_point_velocity_m_s(ANGLES_RAD, r, rod_ratio, rod_length, w)
    ax, az = kin.rod_point_acceleration_m_s2(ANGLES_RAD, r, rod_ratio, rod_length, w)
    # z points towards TDC whereas s points away from it.
    np.testing.assert_allclose(vx, 0.0, atol=1e-12 * r * w)
    np.testing.assert_allclose(ax, 0.0, atol=1e-12 * r * w**2)
    np.testing.assert_allclose(
        -vz, kin.piston_velocity_exact_m_s(ANGLES_RAD, r, rod_ratio, w), rtol=0, atol=1e-12 * r * w
    )
    np.testing.assert_allclose(
        -az,
        kin.piston_acceleration_exact_m_s2(ANGLES_RAD, r, rod_ratio, w),
        rtol=0,
        atol=1e-12 * r * w**2,
    )


# --------------------------------------------------------------------------
# extreme values
# --------------------------------------------------------------------------


def test_mean_piston_speed_equals_stroke_times_rpm_over_30():
    stroke_m, rpm = 0.086, 6000.0
    assert kin.mean_piston_speed_m_s(stroke_m / 2, rpm * math.pi / 30) == pytest.approx(
        stroke_m * rpm / 30, rel=1e-14
    )


@pytest.mark.parametrize("rod_ratio", [0.0, 0.1, 0.25, 0.33, 0.5, 0.7])
def test_exact_peak_velocity_is_maximum_of_dense_grid(rod_ratio):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    v_max, angle = kin.max_piston_velocity_exact(r, rod_ratio, w)
    grid = np.linspace(0.0, 2.0 * np.pi, 400001)
    v_grid = kin.piston_velocity_exact_m_s(grid, r, rod_ratio, w)
    assert np.max(v_grid) <= v_max * (1 + 1e-15)
    # grid spacing 1.6e-5 rad -> flat-top error < ~1e-10 relative
    assert np.max(v_grid) == pytest.approx(v_max, rel=1e-9)
    assert 0.0 < angle <= np.pi / 2
    assert angle == pytest.approx(grid[np.argmax(v_grid)], abs=2e-5)
    # The root is refined to round-off: acceleration there is ~0.
    assert abs(kin.piston_acceleration_exact_m_s2(angle, r, rod_ratio, w)) < 1e-13 * r * w**2
    # Symmetry: the return stroke peaks at 2 pi - angle with the opposite sign.
    assert kin.piston_velocity_exact_m_s(2 * np.pi - angle, r, rod_ratio, w) == pytest.approx(
        -v_max, rel=1e-14
    )


def test_textbook_peak_velocity_formula_close_to_exact():
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    for rod_ratio in [0.1, 0.2, 0.3, 0.4]:
        v_exact, _ = kin.max_piston_velocity_exact(r, rod_ratio, w)
        v_approx = kin.max_piston_velocity_approx_m_s(r, rod_ratio, w)
        shortfall = (v_exact - v_approx) / (r * w)
        # Numerically the formula is accurate to ~lambda^6 / 2.
        assert 0.0 < shortfall < 0.6 * rod_ratio**6


@pytest.mark.parametrize("rod_ratio", [0.0, 0.2, 0.3, 0.5])
def test_max_acceleration_is_at_tdc(rod_ratio):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    grid = np.linspace(0.0, 2.0 * np.pi, 20001)
    j_max = kin.max_piston_acceleration_m_s2(r, rod_ratio, w)
    assert j_max == pytest.approx(r * w**2 * (1 + rod_ratio), rel=1e-15)
    assert np.max(kin.piston_acceleration_exact_m_s2(grid, r, rod_ratio, w)) == pytest.approx(
        j_max, rel=1e-14
    )
    assert np.max(kin.piston_acceleration_approx_m_s2(grid, r, rod_ratio, w)) == pytest.approx(
        j_max, rel=1e-14
    )


@pytest.mark.parametrize("rod_ratio", [0.0, 0.15, 0.25, 0.26, 0.3, 0.4, 0.6])
def test_textbook_min_acceleration_cases_match_grid_of_two_term_form(rod_ratio):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    j_min, angle = kin.min_piston_acceleration_approx(r, rod_ratio, w)
    grid = np.linspace(0.0, np.pi, 200001)
    j_grid = kin.piston_acceleration_approx_m_s2(grid, r, rod_ratio, w)
    assert np.min(j_grid) >= j_min * (1 + 1e-14)
    assert np.min(j_grid) == pytest.approx(j_min, rel=1e-9)
    assert kin.piston_acceleration_approx_m_s2(angle, r, rod_ratio, w) == pytest.approx(
        j_min, rel=1e-13
    )
    if rod_ratio <= 0.25:
        assert angle == np.pi
        assert j_min == pytest.approx(-r * w**2 * (1 - rod_ratio), rel=1e-15)
    else:
        assert np.pi / 2 < angle < np.pi
        assert j_min < -r * w**2 * (1 - rod_ratio)


@pytest.mark.parametrize("rod_ratio", [0.0, 0.15, 0.25, 0.26, 0.2637, 0.27, 0.3, 0.4, 0.6])
def test_exact_min_acceleration_matches_dense_grid(rod_ratio):
    r, w = CRANK_RADIUS_M, ANGULAR_VELOCITY_RAD_S
    j_min, angle = kin.min_piston_acceleration_exact(r, rod_ratio, w)
    grid = np.linspace(0.0, 2.0 * np.pi, 400001)
    j_grid = kin.piston_acceleration_exact_m_s2(grid, r, rod_ratio, w)
    assert np.min(j_grid) >= j_min - 1e-14 * r * w**2
    assert np.min(j_grid) == pytest.approx(j_min, rel=1e-9)
    assert kin.piston_acceleration_exact_m_s2(angle, r, rod_ratio, w) == pytest.approx(
        j_min, rel=1e-14
    )
    assert np.pi / 2 <= angle <= np.pi


def test_exact_min_acceleration_threshold_differs_from_textbook_quarter():
    # Expanding the exact acceleration about BDC, j/(R w^2) = -(1 - lambda)
    # + eps^2 (1 - lambda)(1 - 3 lambda - 3 lambda^2) / 2 + O(eps^4), so BDC
    # stays the minimum up to lambda* = (sqrt(21) - 3) / 6 = 0.26376, not 0.25.
    r, w = 1.0, 1.0
    threshold = (math.sqrt(21.0) - 3.0) / 6.0
    below, above = threshold - 1e-4, threshold + 1e-4
    assert kin.min_piston_acceleration_exact(r, below, w)[1] == np.pi
    assert kin.min_piston_acceleration_exact(r, above, w)[1] < np.pi
    # At lambda = 0.26 the two-term form already has an interior minimum,
    # the exact one does not.
    assert kin.min_piston_acceleration_approx(r, 0.26, w)[1] < np.pi
    assert kin.min_piston_acceleration_exact(r, 0.26, w) == (pytest.approx(-0.74, rel=1e-15), np.pi)


# --------------------------------------------------------------------------
# worked example
# --------------------------------------------------------------------------


def test_worked_example_by_hand():
    r"""Hand calculation, R = 0.05 m, L = 0.2 m, n = 3000 rpm, alpha = 30 deg.

    lambda = R / L = 0.25; omega = pi n / 30 = 100 pi = 314.159265 rad/s;
    R omega = 15.7079633 m/s; R omega^2 = 4934.80220 m/s^2.

    sin(beta) = 0.25 * sin 30 deg = 0.125
    beta      = arcsin(0.125) = 0.125327831 rad = 7.18076 deg
    cos(beta) = sqrt(1 - 0.015625) = sqrt(0.984375) = 0.992156742

    s = R (1 - cos 30) + L (1 - cos beta)
      = 0.05 * 0.133974596 + 0.2 * 0.007843258
      = 0.00669872981 + 0.00156865167 = 0.00826738148 m
    two-term eq. (9): 0.05 * [1.0625 - (0.866025404 + 0.0625 * 0.5)]
      = 0.05 * 0.165224596 = 0.00826122981 m

    alpha + beta = 0.523598776 + 0.125327831 = 0.648926607 rad
    sin(alpha + beta) = 0.604331546, cos(alpha + beta) = 0.796732943
    v = R omega sin(a + b) / cos b = 15.7079633 * 0.609108945 = 9.56786094 m/s
    two-term eq. (10): 15.7079633 * (0.5 + 0.125 * 0.866025404)
      = 15.7079633 * 0.608253175 = 9.55441854 m/s

    cos^2(alpha) / cos^3(beta) = 0.75 / 0.976654293 = 0.767927818
    j = R omega^2 [cos(a + b)/cos b + lambda cos^2 a / cos^3 b]
      = 4934.80220 * (0.803031325 + 0.191981955)
      = 4934.80220 * 0.995013279 = 4910.19372 m/s^2
    two-term eq. (11): 4934.80220 * (0.866025404 + 0.25 * 0.5)
      = 4934.80220 * 0.991025404 = 4890.51434 m/s^2
    """
    r, rod_length, rpm = 0.05, 0.2, 3000.0
    rod_ratio = r / rod_length
    w = math.pi * rpm / 30.0
    alpha = math.radians(30.0)
    assert kin.rod_angle_rad(alpha, rod_ratio) == pytest.approx(0.125327831, rel=1e-8)
    assert kin.piston_displacement_exact_m(alpha, r, rod_ratio) == pytest.approx(
        0.00826738148, rel=1e-8
    )
    assert kin.piston_displacement_approx_m(alpha, r, rod_ratio) == pytest.approx(
        0.00826122981, rel=1e-8
    )
    assert kin.piston_velocity_exact_m_s(alpha, r, rod_ratio, w) == pytest.approx(
        9.56786094, rel=1e-8
    )
    assert kin.piston_velocity_approx_m_s(alpha, r, rod_ratio, w) == pytest.approx(
        9.55441854, rel=1e-8
    )
    assert kin.piston_acceleration_exact_m_s2(alpha, r, rod_ratio, w) == pytest.approx(
        4910.19372, rel=1e-8
    )
    assert kin.piston_acceleration_approx_m_s2(alpha, r, rod_ratio, w) == pytest.approx(
        4890.51434, rel=1e-8
    )


@pytest.mark.parametrize(("rod_ratio", "said"), [(0.255, True), (0.28, False), (0.24, False)])
def test_a_split_two_term_minimum_the_exact_acceleration_does_not_share_is_said(rod_ratio, said):
    """The two-term minimum of the piston acceleration splits once λ > 1/4 (cos α = −1/(4λ)); the
    exact one only at a larger λ (between 0.26 and 0.265: at λ = 0.255 it is still at 180°, at
    0.28 near 158°). Where the two disagree the note says why; elsewhere it says nothing."""
    from conftest import shared_html, shared_run

    changes = {"engine": {"rod_ratio": rod_ratio}}
    r = shared_run("petrol-1cyl", changes, ("kinematics",)).outputs["kinematics"].results
    assert (abs(r["j_min_crank_angle_deg"] - 180.0) < 1e-6) == (rod_ratio <= 0.26)
    if rod_ratio > 0.25:
        split = np.degrees(np.arccos(-1 / (4 * rod_ratio)))
        assert r["j_min_textbook_crank_angle_deg"] == pytest.approx(split, abs=1e-9)
    html = shared_html("petrol-1cyl", changes, "en", ("kinematics",)).linked_html
    assert ("the exact acceleration of this mechanism still has its single minimum" in html) == said
