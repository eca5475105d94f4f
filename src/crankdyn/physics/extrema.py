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
