"""Series forms of the crank-slider kinematics (crankdyn.physics.series) against independent values.

References: the textbook two-term formulas (Poda eq. 9-11, already tested elsewhere), the exact
displacement evaluated with 50-digit arithmetic (mpmath), the coefficients printed in the source
(Ismailov eq. 14), finite differences in time, and the sign and bounds of the truncation error.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from crankdyn.physics import kinematics as kin
from crankdyn.physics import series

R = 0.039
OMEGA = 586.4
ANGLES = np.linspace(0.0, 2.0 * np.pi, 1441)


def exact_mp(alpha: float, radius: float, ratio: float) -> float:
    """s = R[(1 - cos a) + (1 - sqrt(1 - lam^2 sin^2 a))/lam] with 50 significant digits."""
    with mpmath.workdps(50):
        a, lam = mpmath.mpf(alpha), mpmath.mpf(ratio)
        return float(
            radius
            * ((1 - mpmath.cos(a)) + (1 - mpmath.sqrt(1 - lam**2 * mpmath.sin(a) ** 2)) / lam)
        )


def test_coefficients_are_those_of_the_source():
    # Ismailov eq. (14): sqrt(1 - x) = 1 - x/2 - x^2/8 - x^3/16 - 5 x^4/128 - ...
    assert [series.series_coefficient(k) for k in (1, 2, 3, 4)] == [0.5, 0.125, 0.0625, 5 / 128]
    # and they are the Taylor coefficients of 1 - sqrt(1 - x) (independent: mpmath.taylor)
    taylor = mpmath.taylor(lambda x: 1 - mpmath.sqrt(1 - x), 0, 8)
    for k in range(1, 9):
        assert series.series_coefficient(k) == pytest.approx(float(taylor[k]), rel=1e-15)


@pytest.mark.parametrize("ratio", [0.0, 0.001, 0.28, 0.5, 0.99])
def test_two_terms_are_the_textbook_form(ratio):
    s2 = series.piston_displacement_series_m(ANGLES, R, ratio, 2)
    v2 = series.piston_velocity_series_m_s(ANGLES, R, ratio, OMEGA, 2)
    j2 = series.piston_acceleration_series_m_s2(ANGLES, R, ratio, OMEGA, 2)
    np.testing.assert_allclose(
        s2, kin.piston_displacement_approx_m(ANGLES, R, ratio), rtol=0, atol=1e-15 * R
    )
    np.testing.assert_allclose(
        v2, kin.piston_velocity_approx_m_s(ANGLES, R, ratio, OMEGA), rtol=0, atol=1e-13 * R * OMEGA
    )
    np.testing.assert_allclose(
        j2,
        kin.piston_acceleration_approx_m_s2(ANGLES, R, ratio, OMEGA),
        rtol=0,
        atol=1e-13 * R * OMEGA**2,
    )


@pytest.mark.parametrize("terms", [1, 2, 3, 4, 5, 8])
@pytest.mark.parametrize("ratio", [0.001, 0.28, 0.9])
def test_power_and_harmonic_forms_are_the_same_polynomial(terms, ratio):
    for power, harmonic, scale in (
        (
            series.piston_displacement_series_m(ANGLES, R, ratio, terms),
            series.piston_displacement_harmonic_m(ANGLES, R, ratio, terms),
            R,
        ),
        (
            series.piston_velocity_series_m_s(ANGLES, R, ratio, OMEGA, terms),
            series.piston_velocity_harmonic_m_s(ANGLES, R, ratio, OMEGA, terms),
            R * OMEGA,
        ),
        (
            series.piston_acceleration_series_m_s2(ANGLES, R, ratio, OMEGA, terms),
            series.piston_acceleration_harmonic_m_s2(ANGLES, R, ratio, OMEGA, terms),
            R * OMEGA**2,
        ),
    ):
        np.testing.assert_allclose(power, harmonic, rtol=0, atol=1e-12 * scale)


def test_first_harmonic_amplitude():
    # H_1 = lam/4 + lam^3/16 + 15 lam^5/512 + ... (classical Fourier series of the crank-slider)
    lam = 0.3
    h = series.harmonic_coefficients(lam, 4)
    assert h[0] == pytest.approx(lam / 4 + lam**3 / 16 + 15 * lam**5 / 512, rel=1e-14)
    assert h[1] == pytest.approx(-(lam**3 / 64 + 3 * lam**5 / 256), rel=1e-14)
    assert h[2] == pytest.approx(lam**5 / 512, rel=1e-14)


@pytest.mark.parametrize("ratio", [0.01, 0.28, 0.6, 0.99])
@pytest.mark.parametrize("terms", [1, 2, 3, 4, 5])
def test_truncation_error_sign_bounds_and_maximum(ratio, terms):
    exact = np.array([exact_mp(a, R, ratio) for a in ANGLES[::8]])
    truncated = series.piston_displacement_series_m(ANGLES[::8], R, ratio, terms)
    error = exact - truncated
    lower, upper = series.displacement_truncation_error_bounds_m(ANGLES[::8], R, ratio, terms)
    slack = 1e-15 * R  # round-off of the float64 evaluation
    assert np.all(error >= -slack)  # every omitted term is positive
    assert np.all(error >= lower - slack) and np.all(error <= upper + slack)
    # the largest error is at 90 deg and equals R/lam [1 - sqrt(1 - lam^2) - sum_{k<N} c_k lam^2k]
    with mpmath.workdps(50):
        lam = mpmath.mpf(ratio)
        closed = (
            (
                1
                - mpmath.sqrt(1 - lam**2)
                - sum(
                    mpmath.mpf(series.series_coefficient(k)) * lam ** (2 * k)
                    for k in range(1, terms)
                )
            )
            / lam
            * R
        )
    assert series.displacement_truncation_error_max_m(R, ratio, terms) == pytest.approx(
        float(closed), rel=1e-12
    )
    assert error.max() == pytest.approx(float(closed), rel=1e-9, abs=2 * slack)


@pytest.mark.parametrize("ratio", [0.28, 0.9, 0.99])
def test_error_falls_with_every_term_and_the_series_converges(ratio):
    errors = [series.displacement_truncation_error_max_m(R, ratio, n) for n in range(1, 8)]
    assert all(b < a for a, b in zip(errors, errors[1:], strict=False))
    # the tail after N terms is below c_N lam^(2N-1) R / (1 - lam^2): choose N for 1e-13 R
    if ratio > 0.95:
        return  # ~1500 terms would be needed; the bounds test covers lambda = 0.99
    many = next(
        n
        for n in range(2, 5000)
        if series.series_coefficient(n) * ratio ** (2 * n - 1) / (1 - ratio**2) < 1e-14
    )
    exact = kin.piston_displacement_exact_m(ANGLES, R, ratio)
    np.testing.assert_allclose(
        series.piston_displacement_series_m(ANGLES, R, ratio, many), exact, rtol=0, atol=1e-13 * R
    )


@pytest.mark.parametrize("terms", [2, 3, 5])
def test_velocity_and_acceleration_are_time_derivatives(terms):
    ratio, h = 0.35, 1e-3

    def s(a):
        return series.piston_displacement_series_m(a, R, ratio, terms)

    a = ANGLES
    ds = (-s(a + 2 * h) + 8 * s(a + h) - 8 * s(a - h) + s(a - 2 * h)) / (12 * h)
    d2s = (-s(a + 2 * h) + 16 * s(a + h) - 30 * s(a) + 16 * s(a - h) - s(a - 2 * h)) / (12 * h * h)
    np.testing.assert_allclose(
        series.piston_velocity_series_m_s(a, R, ratio, OMEGA, terms),
        OMEGA * ds,
        rtol=0,
        atol=1e-9 * R * OMEGA,
    )
    np.testing.assert_allclose(
        series.piston_acceleration_series_m_s2(a, R, ratio, OMEGA, terms),
        OMEGA**2 * d2s,
        rtol=0,
        atol=1e-7 * R * OMEGA**2,
    )


@settings(max_examples=40, deadline=None)
@given(ratio=st.floats(0.0, 0.99), terms=st.integers(1, 6), alpha=st.floats(0.0, 2 * math.pi))
def test_series_never_exceeds_the_exact_displacement(ratio, terms, alpha):
    exact = exact_mp(alpha, R, ratio) if ratio > 0 else R * (1 - math.cos(alpha))
    assert float(series.piston_displacement_series_m(alpha, R, ratio, terms)) <= exact + 1e-15 * R


@pytest.mark.parametrize(
    "terms, ratio",
    [(0, 0.3), (-1, 0.3), (2.5, 0.3), (True, 0.3), (3, 1.0), (3, -0.1), (3, float("nan"))],
)
def test_bad_arguments_are_refused(terms, ratio):
    with pytest.raises(ValueError, match="invalid; allowed"):
        series.piston_displacement_series_m(0.3, R, ratio, terms)
