"""The indicator roundings' cubic Hermite pieces (crankdyn.physics.hermite) against independent values."""

import numpy as np
import pytest
from scipy.interpolate import CubicHermiteSpline

from crankdyn.physics.hermite import hermite_cubic


def test_a_cubic_is_reproduced_exactly():
    # a single cubic through its own values and slopes is the Hermite interpolant of itself,
    # on every piece and beyond the ends (continued end pieces)
    def p(x):
        return 0.5 * x**3 - 2.0 * x**2 + 3.0 * x - 7.0

    def dp(x):
        return 1.5 * x**2 - 4.0 * x + 3.0

    knots = np.array([-3.0, -0.5, 1.0, 4.5])
    curve = hermite_cubic(knots, p(knots), dp(knots))
    x = np.linspace(-5.0, 7.0, 1001)
    assert np.allclose(curve(x), p(x), rtol=0, atol=1e-12 * np.max(np.abs(p(x))))


def test_values_and_slopes_at_the_knots():
    knots, values, slopes = (
        [-10.0, 0.0, 12.0, 40.0],
        [1.0e6, 3.0e6, 5.5e6, 2.0e6],
        [1e5, 2.5e5, 0.0, -2e5],
    )
    curve = hermite_cubic(knots, values, slopes)
    assert np.allclose(curve(np.array(knots)), values, rtol=1e-14)
    h = 1e-6
    numeric = (curve(np.array(knots) + h) - curve(np.array(knots) - h)) / (2 * h)
    assert np.allclose(numeric, slopes, rtol=0, atol=1e-3 * max(abs(s) for s in slopes))


def test_same_curve_as_scipy():
    rng = np.random.default_rng(17)
    for _ in range(20):
        knots = np.cumsum(rng.uniform(0.1, 30.0, size=rng.integers(2, 6)))
        values, slopes = rng.normal(0, 1e6, knots.size), rng.normal(0, 1e5, knots.size)
        x = np.linspace(knots[0] - 20.0, knots[-1] + 20.0, 777)
        expected = CubicHermiteSpline(knots, values, slopes)(x)
        assert np.allclose(
            hermite_cubic(knots, values, slopes)(x), expected, rtol=1e-12, atol=1e-12 * 1e6
        )


@pytest.mark.parametrize(
    "knots, values, slopes",
    [
        ([0.0, 0.0, 1.0], [1, 2, 3], [0, 0, 0]),  # not strictly increasing
        ([0.0], [1.0], [0.0]),  # one point
        ([0.0, 1.0], [1.0, 2.0, 3.0], [0.0, 0.0]),  # lengths differ
    ],
)
def test_bad_knots_are_refused(knots, values, slopes):
    with pytest.raises(ValueError):
        hermite_cubic(knots, values, slopes)
