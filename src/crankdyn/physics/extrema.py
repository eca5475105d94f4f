"""Where a sampled curve peaks: one definition of "the angle of the maximum/minimum".

Periodic quantities of a multi-cylinder engine have several equal peaks per cycle (an in-line 4's
speed has four, one per firing interval). Equal to rounding, those peaks differ in the last bits,
and a raw ``argmax`` then picks whichever peak the last bit of the installed numpy/scipy favours.
crankdyn therefore reports **the first sample (in crank angle order) whose value lies within a
relative tolerance of the extreme value**, the tolerance relative to the curve's range
(peak-to-peak), so the answer depends on physics, never on rounding.
"""

from __future__ import annotations

import numpy as np

from .scalar_search import brentq

#: Relative tolerance (of the curve's peak-to-peak range) within which two peaks count as equal.
EXTREMUM_RTOL = 1e-9


def extremum_indices(values, kind: str = "max", rtol: float = EXTREMUM_RTOL) -> np.ndarray:
    """Indices of every sample within ``rtol`` x range of the maximum (``kind="max"``) or minimum.

    Parameters
    ----------
    values : array_like, 1-D
        Sampled curve (any unit); NaN samples are ignored.
    kind : {"max", "min"}
    rtol : float
        Tolerance relative to ``max - min`` of the finite samples; a constant curve has every
        sample tied.

    Returns
    -------
    numpy.ndarray of int, ascending.
    """
    if kind not in ("max", "min"):
        raise ValueError(f"kind must be 'max' or 'min', not {kind!r}")
    v = np.ascontiguousarray(values, dtype=float)
    if v.ndim != 1 or v.size == 0:
        raise ValueError("values must be a non-empty 1-D array")
    finite = np.isfinite(v)
    if not finite.any():
        raise ValueError("values has no finite sample")
    low, high = float(np.min(v[finite])), float(np.max(v[finite]))
    band = rtol * (high - low)
    if kind == "max":
        hit = finite & (v >= high - band)
    else:
        hit = finite & (v <= low + band)
    return np.flatnonzero(hit)


def first_extremum_index(values, kind: str = "max", rtol: float = EXTREMUM_RTOL) -> int:
    """Index of the first sample within ``rtol`` x range of the maximum or minimum.

    This is the definition behind every reported "crank angle of the maximum/minimum"; see the
    module docstring. Contiguous and strided inputs give the same answer.
    """
    return int(extremum_indices(values, kind, rtol)[0])


def first_argmax(values, rtol: float = EXTREMUM_RTOL) -> int:
    """:func:`first_extremum_index` of the maximum."""
    return first_extremum_index(values, "max", rtol)


def first_argmin(values, rtol: float = EXTREMUM_RTOL) -> int:
    """:func:`first_extremum_index` of the minimum."""
    return first_extremum_index(values, "min", rtol)


def central_derivative(fn, step: float = 1e-3):
    """d fn/dx by the five-point central difference (error step^4 f^(5)/30): for an extreme's root search
    where no closed-form derivative exists. ``fn`` takes and returns floats or arrays."""
    h = float(step)
    return lambda x: (-fn(x + 2 * h) + 8 * fn(x + h) - 8 * fn(x - h) + fn(x - 2 * h)) / (12 * h)


def periodic_extreme(
    fn,
    derivative,
    period: float,
    kind: str = "max",
    samples: int = 720,
    rtol: float = EXTREMUM_RTOL,
) -> tuple[float, float]:
    """The extreme of a smooth periodic function by root finding: (argument, value).

    ``fn`` is sampled at ``samples`` points of one period; every sampled local extreme within 1e-3 of
    the range of the sampled extreme is refined by Brent's method on ``derivative`` between its two
    neighbours (where the derivative changes sign), so the argument is exact to ~1e-15 of the period
    rather than to half a grid step. Of peaks equal within ``rtol`` x range the first in [0, period)
    is returned, the convention of :func:`first_extremum_index`.
    """
    sign = 1.0 if kind == "max" else -1.0
    x = np.arange(samples) * (period / samples)
    h = period / samples
    v = sign * np.asarray(fn(x), dtype=float)
    span = float(np.ptp(v)) or 1.0
    best = float(np.max(v))
    found = []
    for i in np.flatnonzero(v >= best - 1e-3 * span):
        if v[i] < v[i - 1] or v[i] < v[(i + 1) % samples]:
            continue
        lo, hi = x[i] - h, x[i] + h
        d_lo, d_hi = sign * float(derivative(lo)), sign * float(derivative(hi))
        if d_lo == 0.0 or d_hi == 0.0 or d_lo * d_hi > 0:
            root = lo if d_lo == 0.0 else (hi if d_hi == 0.0 else float(x[i]))
        else:
            root = brentq(
                lambda a: float(derivative(a)),
                lo,
                hi,
                xtol=1e-15 * period,
                rtol=4 * np.finfo(float).eps,
                maxiter=200,
            )
        root = root % period
        if period - root < 1e-12 * period:  # a root just below 0, e.g. -1e-17: it is angle 0
            root = 0.0
        found.append((root, sign * float(fn(root))))
    top = max(sign * value for _, value in found)
    first = min(root for root, value in found if sign * value >= top - rtol * span)
    return first, float(fn(first))
