"""crankdyn.physics.scalar_search against scipy.optimize: the same methods step for step, so the
same floating-point results (an independent implementation of each, compared bit for bit)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize

from crankdyn.physics import kinematics as kin
from crankdyn.physics.scalar_search import brentq, minimize_bounded

ROOTS = [  # (function, bracket, keyword arguments)
    (lambda x: x**3 - 2 * x - 5, (2.0, 3.0), {}),
    (math.cos, (0.0, 3.0), {"xtol": 1e-15, "rtol": 4 * np.finfo(float).eps, "maxiter": 200}),
    (lambda x: math.exp(x) - 10.0, (-5.0, 10.0), {"xtol": 1e-13}),
    (lambda x: (x - 1e-3) ** 3, (-1.0, 2.0), {"maxiter": 200}),  # a flat root: many bisections
    (lambda x: math.atan(1e4 * (x - 0.3)), (-10.0, 10.0), {"xtol": 1e-14}),
    (
        lambda a: float(kin.piston_acceleration_exact_m_s2(a, 1.0, 0.28, 1.0)),
        (0.0, math.pi / 2),
        {},
    ),
    (lambda x: x, (0.0, 1.0), {}),  # a root at an end of the bracket
    (lambda x: 1e-170 * (x - 0.3), (0.0, 1.0), {}),  # values whose product underflows
]


@pytest.mark.parametrize("f, bracket, options", ROOTS)
def test_brentq_gives_scipys_root_bit_for_bit(f, bracket, options):
    ours = brentq(f, *bracket, **options)
    assert ours == optimize.brentq(f, *bracket, **options)
    assert abs(f(ours)) < 1e-9 or bracket[0] == ours


def test_brentq_refuses_what_scipy_refuses():
    with pytest.raises(ValueError, match="different signs"):
        brentq(lambda x: x * x + 1, -1.0, 1.0)
    with pytest.raises(ValueError, match="different signs"):
        brentq(lambda x: 1e-170 * (x * x + 1), 0.0, 1.0)
    with pytest.raises(ValueError, match="NaN"):
        brentq(lambda x: math.nan, -1.0, 1.0)
    with pytest.raises(ValueError, match="rtol"):
        brentq(math.sin, -1.0, 1.0, rtol=1e-17)
    for solve in (brentq, optimize.brentq):  # a flat root: not within 100 iterations, for either
        with pytest.raises(RuntimeError, match="100"):
            solve(lambda x: (x - 1e-3) ** 5, -1.0, 2.0)


MINIMA = [
    (lambda x: (x - 0.7) ** 2 + 3.0, (0.0, 2.0), {}),
    (lambda x: -math.sin(x), (0.0, 3.0), {"xatol": 1e-12}),
    (lambda x: math.cosh(x - 1e-3), (-2.0, 5.0), {"xatol": 1e-13}),
    (lambda x: abs(x - 0.25), (0.0, 1.0), {"xatol": 1e-9}),  # a kink: golden sections
    (lambda x: x, (0.0, 1.0), {"xatol": 1e-12}),  # the least value at the bound
    (
        lambda a: -float(kin.piston_velocity_exact_m_s(a, 0.04, 0.28, 600.0)),
        (1.2, 1.5),
        {"xatol": 1e-12},
    ),
    (lambda x: (x - 0.3) ** 4, (0.0, 1.0), {"xatol": 1e-14, "maxiter": 7}),  # stopped by maxiter
]


@pytest.mark.parametrize("f, bounds, options", MINIMA)
def test_minimize_bounded_gives_scipys_minimum_bit_for_bit(f, bounds, options):
    ours = minimize_bounded(f, *bounds, **options)
    theirs = optimize.minimize_scalar(f, bounds=bounds, method="bounded", options=options)
    assert (ours.x, ours.fun) == (float(theirs.x), float(theirs.fun))
    assert ours.fun == f(ours.x)


def test_minimize_bounded_refuses_bounds_that_are_not_a_bracket():
    with pytest.raises(ValueError, match="bounds"):
        minimize_bounded(math.sin, 1.0, 0.0)
    with pytest.raises(ValueError, match="bounds"):
        minimize_bounded(math.sin, 0.0, math.inf)
