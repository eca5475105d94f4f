"""Root and minimum of a scalar function on a bracket, without importing scipy.

The stages look for a few roots and extremes per report (the crank angle of the largest piston
velocity, an extreme between two table rows); ``scipy.optimize`` takes 0.15–0.25 s to import,
more than all of a single-cylinder report's stages compute. These are the same two methods
scipy uses, step for step, so that they give the same floating-point result (tested against
``scipy.optimize.brentq`` and ``minimize_scalar(method="bounded")``):

* :func:`brentq`: Brent's root finder with inverse quadratic extrapolation (R. P. Brent,
  *Algorithms for Minimization without Derivatives*, 1973, ch. 4), as C. Harris wrote it for scipy;
* :func:`minimize_bounded`: Brent's minimisation by golden section and parabolic interpolation
  (ibid., ch. 5; G. E. Forsythe, M. A. Malcolm, C. B. Moler, *Computer Methods for Mathematical
  Computations*, 1977, ``fmin``), as scipy's ``fminbound``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

#: scipy's defaults for brentq: absolute and relative tolerance (4 machine epsilons), iterations.
XTOL = 2e-12
RTOL = 4 * 2.220446049250313e-16
MAXITER = 100


def _value(f: Callable[[float], float], x: float) -> float:
    value = float(f(x))
    if math.isnan(value):
        raise ValueError(f"the function is NaN at {x!r}")
    return value


def _negative(value: float) -> bool:
    """The sign bit (C's signbit): −0.0 counts as negative."""
    return math.copysign(1.0, value) < 0


def brentq(
    f: Callable[[float], float],
    a: float,
    b: float,
    xtol: float = XTOL,
    rtol: float = RTOL,
    maxiter: int = MAXITER,
) -> float:
    """A root of ``f`` in [a, b], where f(a) and f(b) differ in sign, to within
    ``xtol + rtol·|x|``. Raises ValueError (no sign change, a NaN, a bad tolerance) or
    RuntimeError (not converged in ``maxiter`` steps), as scipy's ``brentq`` does."""
    if xtol <= 0 or rtol < RTOL or maxiter < 0:
        raise ValueError(f"xtol must be > 0 and rtol >= {RTOL!r} (got {xtol!r}, {rtol!r})")
    previous, current = float(a), float(b)
    f_previous, f_current = _value(f, previous), _value(f, current)
    if f_previous == 0:
        return previous
    if f_current == 0:
        return current
    # signs compared by their sign bits, not by a product (1e-170² underflows to zero)
    if _negative(f_previous) == _negative(f_current):
        raise ValueError("f(a) and f(b) must have different signs")
    block, f_block, step_before, step = 0.0, 0.0, 0.0, 0.0
    for _ in range(maxiter):
        if f_previous != 0 and f_current != 0 and _negative(f_previous) != _negative(f_current):
            # the root lies between previous and current: block it there
            block, f_block = previous, f_previous
            step_before = step = current - previous
        if abs(f_block) < abs(f_current):  # current is the best estimate, block the other end
            previous, current, block = current, block, current
            f_previous, f_current, f_block = f_current, f_block, f_current
        delta = (xtol + rtol * abs(current)) / 2  # the tolerance is 2·delta
        bisection = (block - current) / 2
        if f_current == 0 or abs(bisection) < delta:
            return current
        step_before, step = _next_steps(
            previous,
            current,
            block,
            f_previous,
            f_current,
            f_block,
            step_before,
            step,
            bisection,
            delta,
        )
        previous, f_previous = current, f_current
        current += step if abs(step) > delta else (delta if bisection > 0 else -delta)
        f_current = _value(f, current)
    raise RuntimeError(
        f"no root to the tolerance within {maxiter} iterations (last estimate {current!r})"
    )


def _next_steps(
    previous, current, block, f_previous, f_current, f_block, step_before, step, bisection, delta
):
    """(the step before, the step): an interpolated step when it is short enough, else bisection."""
    if abs(step_before) > delta and abs(f_current) < abs(f_previous):
        if previous == block:  # linear interpolation (secant)
            trial = -f_current * (current - previous) / (f_current - f_previous)
        else:  # inverse quadratic extrapolation through the three points
            slope_previous = (f_previous - f_current) / (previous - current)
            slope_block = (f_block - f_current) / (block - current)
            trial = (
                -f_current
                * (f_block * slope_block - f_previous * slope_previous)
                / (slope_block * slope_previous * (f_block - f_previous))
            )
        if 2 * abs(trial) < min(abs(step_before), 3 * abs(bisection) - delta):
            return step, trial
    return bisection, bisection


class BoundedMinimum(NamedTuple):
    """Where a function is least on a bracket (``x``) and its value there (``fun``)."""

    x: float
    fun: float


_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))
_SQRT_EPS = math.sqrt(2.2e-16)  # scipy's fminbound uses this rounded epsilon


def minimize_bounded(
    f: Callable[[float], float], low: float, high: float, xatol: float = 1e-5, maxiter: int = 500
) -> BoundedMinimum:
    """The least value of ``f`` on [low, high], to within ``xatol`` in x (Brent's method: golden
    sections and parabolic steps; stops after ``maxiter`` evaluations, as scipy does)."""
    if not (math.isfinite(low) and math.isfinite(high)) or low > high:
        raise ValueError(f"the bounds must be finite with low <= high (got {low!r}, {high!r})")
    a, b = float(low), float(high)
    # best, second best, third best point (x, w, v in Brent's notation) and their values
    v = w = x = a + _GOLDEN * (b - a)
    fv = fw = fx = float(f(x))
    calls, e, rat = 1, 0.0, 0.0
    middle, tol1 = 0.5 * (a + b), _SQRT_EPS * abs(x) + xatol / 3.0
    while abs(x - middle) > 2.0 * tol1 - 0.5 * (b - a):
        e, rat = _bounded_step(a, b, x, w, v, fx, fw, fv, e, rat, middle, tol1)
        u = x + (1.0 if rat == 0 else math.copysign(1.0, rat)) * max(abs(rat), tol1)
        fu = float(f(u))
        calls += 1
        if fu <= fx:
            a, b = (x, b) if u >= x else (a, x)
            v, fv, w, fw, x, fx = w, fw, x, fx, u, fu
        else:
            a, b = (u, b) if u < x else (a, u)
            if fu <= fw or w == x:
                v, fv, w, fw = w, fw, u, fu
            elif fu <= fv or v == x or v == w:
                v, fv = u, fu
        middle, tol1 = 0.5 * (a + b), _SQRT_EPS * abs(x) + xatol / 3.0
        if calls >= maxiter:
            break
    return BoundedMinimum(x, fx)


def _bounded_step(a, b, x, w, v, fx, fw, fv, e, rat, middle, tol1) -> tuple[float, float]:
    """(e, rat): the parabola's step through x, w, v where it is acceptable, else a golden section."""
    tol2 = 2.0 * tol1
    if abs(e) > tol1:
        r = (x - w) * (fx - fv)
        q = (x - v) * (fx - fw)
        p = (x - v) * q - (x - w) * r
        q = 2.0 * (q - r)
        if q > 0.0:
            p = -p
        q = abs(q)
        e_before, e = e, rat
        if abs(p) < abs(0.5 * q * e_before) and q * (a - x) < p < q * (b - x):
            rat = (p + 0.0) / q
            u = x + rat
            if (u - a) < tol2 or (b - u) < tol2:
                rat = tol1 * (1.0 if middle == x else math.copysign(1.0, middle - x))
            return e, rat
    e = (a - x) if x >= middle else (b - x)
    return e, _GOLDEN * e
