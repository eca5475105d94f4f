"""The degree of cyclic irregularity delta, by both definitions in use (Poda 2007 §4.5).

delta = (omega_max - omega_min) / omega_m. The textbook takes omega_m = (omega_max + omega_min)/2
(the mid-range speed); the engine's mean speed is the time mean Phi/T, T = closed integral of
d(phi)/omega. Both are reported; for omega = w0 (1 + e cos phi) they are w0 and w0 sqrt(1 - e^2),
so the two deltas differ by O(e^2) relative.
"""

from __future__ import annotations

import numpy as np


def time_mean_speed_rad_s(omega_rad_s) -> float:
    r"""Time mean of a speed sampled at equal angle steps over one period (rad/s).

    :math:`\bar\omega = \Phi / T`, :math:`T = \oint d\varphi/\omega`; the periodic trapezoidal rule
    (the mean of 1/omega over the samples) is spectrally accurate for a smooth periodic omega.
    """
    omega = np.asarray(omega_rad_s, dtype=float)
    return float(1.0 / np.mean(1.0 / omega))


def irregularity_midrange(omega_max_rad_s: float, omega_min_rad_s: float) -> float:
    """delta = (w_max - w_min) / ((w_max + w_min)/2), the textbook's definition (dimensionless)."""
    return (omega_max_rad_s - omega_min_rad_s) / (0.5 * (omega_max_rad_s + omega_min_rad_s))


def irregularity_time_mean(
    omega_max_rad_s: float, omega_min_rad_s: float, omega_mean_rad_s: float
) -> float:
    """delta = (w_max - w_min) / w_mean with the time-mean speed w_mean = Phi/T (dimensionless)."""
    return (omega_max_rad_s - omega_min_rad_s) / omega_mean_rad_s
