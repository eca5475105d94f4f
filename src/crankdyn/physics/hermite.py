"""Piecewise cubic Hermite interpolation: the curve through given points with given slopes.

The indicator diagram's roundings are cubic Hermite pieces between a few junction points, each
with its value and slope (Poda, section 3.1: the combustion rounding c'-c''-z'-J and the exhaust
rounding b'-BDC-r). On the piece [x_k, x_k+1] of width h, with t = (x - x_k)/h, the standard
basis gives

    p(x) = h00(t) y_k + h10(t) h m_k + h01(t) y_k+1 + h11(t) h m_k+1,
    h00 = 2t^3 - 3t^2 + 1,  h10 = t^3 - 2t^2 + t,  h01 = -2t^3 + 3t^2,  h11 = t^3 - t^2

(de Boor, *A Practical Guide to Splines*, ch. IV; the same curve as scipy's
``CubicHermiteSpline``). Outside the knots the first or last piece's cubic is continued, as
scipy's ``extrapolate=True`` does: callers evaluate a whole grid and keep only the window.

Written here rather than taken from ``scipy.interpolate`` because that package costs about
25 ms of every run's start-up for a dozen arithmetic operations a point.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def hermite_cubic(knots, values, slopes) -> Callable[[np.ndarray], np.ndarray]:
    """The piecewise cubic with ``values`` and ``slopes`` (units of value per unit of knot) at the
    strictly increasing ``knots``; returns ``p(x)`` for an array of x in the knots' unit."""
    x = np.asarray(knots, dtype=float)
    y = np.asarray(values, dtype=float)
    m = np.asarray(slopes, dtype=float)
    if x.ndim != 1 or x.size < 2 or y.shape != x.shape or m.shape != x.shape:
        raise ValueError(
            f"knots, values and slopes: equal 1-D lengths >= 2, got {x.shape}, {y.shape}, {m.shape}"
        )
    if not np.all(np.diff(x) > 0):
        raise ValueError(f"knots must increase strictly, got {x.tolist()}")

    def curve(at) -> np.ndarray:
        at = np.asarray(at, dtype=float)
        k = np.clip(np.searchsorted(x, at, side="right") - 1, 0, x.size - 2)
        h = x[k + 1] - x[k]
        t = (at - x[k]) / h
        t2 = t * t
        t3 = t2 * t
        return (
            (2.0 * t3 - 3.0 * t2 + 1.0) * y[k]
            + (t3 - 2.0 * t2 + t) * h * m[k]
            + (3.0 * t2 - 2.0 * t3) * y[k + 1]
            + (t3 - t2) * h * m[k + 1]
        )

    return curve
