"""Series forms of the central crank-slider kinematics: Maclaurin series in the rod ratio.

The exact piston displacement from TDC (Ismailov, eq. 13; Poda 2007 eq. 9 before
truncation) is

.. math::
    s = R\\left[(1-\\cos\\alpha) + \\frac{1}{\\lambda}\\left(1-\\sqrt{1-\\lambda^2\\sin^2\\alpha}\\right)\\right].

Expanding the root in its Maclaurin series (Ismailov, eq. 14)

.. math::
    \\sqrt{1-x} = 1 - \\sum_{k\\ge1} c_k x^k,\\qquad
    c_k = \\frac{\\binom{2k}{k}}{(2k-1)\\,4^k} = \\tfrac12,\\ \\tfrac18,\\ \\tfrac1{16},\\ \\tfrac5{128},\\ \\dots

with :math:`x = \\lambda^2\\sin^2\\alpha` gives the displacement as a series of *terms*

.. math::
    \\frac{s}{R} = (1-\\cos\\alpha) + \\sum_{k=1}^{N-1} c_k\\,\\lambda^{2k-1}\\sin^{2k}\\alpha .

``terms = N`` counts the crank term ``1 - cos(alpha)`` as the first term, so ``N = 2`` is
the textbook two-term form (Poda 2007 eq. 9, Ismailov eq. 16-17, since
:math:`\\tfrac12\\lambda\\sin^2\\alpha = \\tfrac\\lambda4(1-\\cos2\\alpha)`), and ``N = 3, 4, 5``
add the terms in :math:`\\lambda^3, \\lambda^5, \\lambda^7`.

The same truncated series can be written as a Fourier (harmonic) series, using
:math:`\\sin^{2k}\\alpha = 4^{-k}[\\binom{2k}{k} + 2\\sum_{j=1}^{k}(-1)^j\\binom{2k}{k-j}\\cos2j\\alpha]`
(derived):

.. math::
    \\frac{s}{R} = (1-\\cos\\alpha) + \\sum_{j=1}^{N-1} H_j\\,(1-\\cos2j\\alpha),\\qquad
    H_j = \\sum_{k=j}^{N-1} (-1)^{j+1}\\,\\frac{2\\,c_k}{4^k}\\binom{2k}{k-j}\\,\\lambda^{2k-1},

the classical form with harmonics of even order only (:math:`H_1 = \\lambda/4 + \\lambda^3/16 + \\dots`).
Both forms are the same polynomial in :math:`\\lambda`; they differ only in the work and
the round-off of an evaluation.

Truncation error (derived): every omitted term is positive, so the truncated series never
exceeds the exact displacement, and with :math:`x = \\lambda^2\\sin^2\\alpha`

.. math::
    c_N\\lambda^{2N-1}\\sin^{2N}\\alpha \\;\\le\\; \\frac{s - s_N}{R}
    \\;\\le\\; \\frac{c_N\\lambda^{2N-1}\\sin^{2N}\\alpha}{1-x},

because :math:`c_{k+1}/c_k = (2k-1)/(2k+2) < 1`. The largest error is at
:math:`\\alpha = 90°`, equal to :func:`displacement_truncation_error_max_m`.

Velocity and acceleration are the exact time derivatives of the truncated displacement at
constant angular velocity.

References
----------
Ismailov, O. R. Kinematics of crank-slider mechanisms of various schemes and their
evaluation (in Uzbek; Tashkent Kimyo International University), eqs. (13)-(19).
Poda, V. B. (2007). Dynamic calculation and balancing of piston ICEs. KhAI. Eqs. (9)-(11).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "series_coefficient",
    "harmonic_coefficients",
    "piston_displacement_series_m",
    "piston_velocity_series_m_s",
    "piston_acceleration_series_m_s2",
    "piston_displacement_harmonic_m",
    "piston_velocity_harmonic_m_s",
    "piston_acceleration_harmonic_m_s2",
    "displacement_truncation_error_max_m",
    "displacement_truncation_error_bounds_m",
]


def _check(terms, rod_ratio):
    if isinstance(terms, bool) or not isinstance(terms, (int, np.integer)) or terms < 1:
        raise ValueError(f"terms = {terms!r} is invalid; allowed: a whole number >= 1")
    lam = np.asarray(rod_ratio, dtype=float)
    if np.any(~np.isfinite(lam)) or np.any(lam < 0.0) or np.any(lam >= 1.0):
        raise ValueError(f"rod_ratio = {rod_ratio!r} is invalid; allowed: 0 <= rod_ratio < 1")
    return int(terms), lam


def series_coefficient(k: int) -> float:
    """Coefficient c_k of x^k in 1 - sqrt(1 - x).

    Parameters
    ----------
    k : int
        Power, >= 1.

    Returns
    -------
    float
        c_k = C(2k, k) / ((2k - 1) 4^k): 1/2, 1/8, 1/16, 5/128, 7/256, ...

    Notes
    -----
    Ismailov eq. (14) lists c_1..c_4; the closed form is the binomial series of
    (1 - x)^(1/2) (derived).
    """
    if k < 1:
        raise ValueError(f"k = {k!r} is invalid; allowed: >= 1")
    return math.comb(2 * k, k) / ((2 * k - 1) * 4**k)


def harmonic_coefficients(rod_ratio, terms: int) -> np.ndarray:
    """Amplitudes H_1..H_{N-1} of the harmonics (1 - cos 2j alpha) of the truncated series.

    Parameters
    ----------
    rod_ratio : float
        lambda = R / L [-], 0 <= lambda < 1.
    terms : int
        Number of terms N of the series (>= 1).

    Returns
    -------
    numpy.ndarray, shape (N - 1,)
        H_j [-] such that s/R = (1 - cos a) + sum_j H_j (1 - cos 2 j a).

    Notes
    -----
    Derived (see the module docstring); H_1 = lambda/4 for N = 2 (Poda eq. 9).
    """
    terms, lam = _check(terms, rod_ratio)
    lam = float(lam)
    out = np.zeros(max(terms - 1, 0))
    for j in range(1, terms):
        total = 0.0
        for k in range(j, terms):
            total += (
                (-1) ** (j + 1)
                * 2.0
                * series_coefficient(k)
                / 4**k
                * math.comb(2 * k, k - j)
                * lam ** (2 * k - 1)
            )
        out[j - 1] = total
    return out


def _power_sums(crank_angle_rad, rod_ratio, terms):
    """sum_k c_k lam^(2k-1) sin^(2k), and the two angle derivatives of that sum."""
    a = np.asarray(crank_angle_rad, dtype=float)
    sin_a, cos_a = np.sin(a), np.cos(a)
    s2 = sin_a * sin_a
    value = np.zeros(np.broadcast(a, rod_ratio).shape)
    first = np.zeros_like(value)
    second = np.zeros_like(value)
    power = np.ones_like(value)  # sin^(2k-2)
    for k in range(1, terms):
        coef = series_coefficient(k) * rod_ratio ** (2 * k - 1)
        # d/da sin^(2k) = 2k sin^(2k-1) cos;  d2/da2 = 2k[(2k-1) sin^(2k-2) cos^2 - sin^(2k)]
        value = value + coef * power * s2
        first = first + coef * 2 * k * power * sin_a * cos_a
        second = second + coef * 2 * k * ((2 * k - 1) * power * cos_a * cos_a - power * s2)
        power = power * s2
    return sin_a, cos_a, value, first, second


def piston_displacement_series_m(crank_angle_rad, crank_radius_m, rod_ratio, terms):
    r"""Piston displacement from TDC by the Maclaurin series in lambda with ``terms`` terms.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float
        Crank radius R [m].
    rod_ratio : float
        lambda = R / L [-], 0 <= lambda < 1.
    terms : int
        N >= 1; N = 2 is the textbook two-term form.

    Returns
    -------
    numpy.ndarray or float
        s_N [m], never above the exact displacement.

    Notes
    -----
    Ismailov eqs. (13)-(14): :math:`s/R = (1-\cos\alpha) + \sum_{k=1}^{N-1} c_k\lambda^{2k-1}\sin^{2k}\alpha`.
    The crank part is evaluated as :math:`2\sin^2(\alpha/2)` (no cancellation at TDC).
    """
    terms, lam = _check(terms, rod_ratio)
    a = np.asarray(crank_angle_rad, dtype=float)
    half = np.sin(0.5 * a)
    _, _, value, _, _ = _power_sums(a, lam, terms)
    return crank_radius_m * (2.0 * half * half + value)


def piston_velocity_series_m_s(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s, terms
):
    r"""Piston velocity: the time derivative of :func:`piston_displacement_series_m`.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha [rad].
    crank_radius_m : float
        R [m].
    rod_ratio : float
        lambda [-].
    angular_velocity_rad_s : float
        Constant omega [rad/s].
    terms : int
        N >= 1.

    Returns
    -------
    numpy.ndarray or float
        v_N [m/s].

    Notes
    -----
    Derived: :math:`v/(R\omega) = \sin\alpha + \sum_k 2k\,c_k\lambda^{2k-1}\sin^{2k-1}\alpha\cos\alpha`
    (Ismailov eq. 18 for N = 2).
    """
    terms, lam = _check(terms, rod_ratio)
    sin_a, _, _, first, _ = _power_sums(crank_angle_rad, lam, terms)
    return crank_radius_m * angular_velocity_rad_s * (sin_a + first)


def piston_acceleration_series_m_s2(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s, terms
):
    r"""Piston acceleration: the second time derivative of :func:`piston_displacement_series_m`.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha [rad].
    crank_radius_m : float
        R [m].
    rod_ratio : float
        lambda [-].
    angular_velocity_rad_s : float
        Constant omega [rad/s].
    terms : int
        N >= 1.

    Returns
    -------
    numpy.ndarray or float
        j_N [m/s^2].

    Notes
    -----
    Derived: :math:`j/(R\omega^2) = \cos\alpha + \sum_k 2k\,c_k\lambda^{2k-1}
    [(2k-1)\sin^{2k-2}\alpha\cos^2\alpha - \sin^{2k}\alpha]`; N = 2 gives Poda eq. (11),
    :math:`\cos\alpha + \lambda\cos2\alpha`.
    """
    terms, lam = _check(terms, rod_ratio)
    _, cos_a, _, _, second = _power_sums(crank_angle_rad, lam, terms)
    return crank_radius_m * angular_velocity_rad_s**2 * (cos_a + second)


def _harmonics(crank_angle_rad, rod_ratio, terms):
    h = harmonic_coefficients(rod_ratio, terms)
    a = np.asarray(crank_angle_rad, dtype=float)
    return a, h


def piston_displacement_harmonic_m(crank_angle_rad, crank_radius_m, rod_ratio, terms):
    r"""The truncated series of :func:`piston_displacement_series_m` in its harmonic form.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        alpha [rad].
    crank_radius_m : float
        R [m].
    rod_ratio : float
        lambda [-].
    terms : int
        N >= 1.

    Returns
    -------
    numpy.ndarray or float
        s_N [m] (the same polynomial in lambda as the power form).

    Notes
    -----
    Derived: :math:`s/R = 2\sin^2(\alpha/2) + \sum_{j=1}^{N-1} 2H_j\sin^2(j\alpha)`, i.e.
    :math:`H_j(1-\cos2j\alpha)` written without cancellation.
    """
    a, h = _harmonics(crank_angle_rad, rod_ratio, terms)
    half = np.sin(0.5 * a)
    total = 2.0 * half * half
    for j, amplitude in enumerate(h, start=1):
        sj = np.sin(j * a)
        total = total + 2.0 * amplitude * sj * sj
    return crank_radius_m * total


def piston_velocity_harmonic_m_s(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s, terms
):
    r"""Velocity of the harmonic form: :math:`R\omega[\sin\alpha + \sum_j 2jH_j\sin2j\alpha]`.

    Parameters
    ----------
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s, terms
        As :func:`piston_velocity_series_m_s`.

    Returns
    -------
    numpy.ndarray or float
        v_N [m/s].

    Notes
    -----
    Derived (term-by-term derivative; N = 2 gives Poda eq. 10).
    """
    a, h = _harmonics(crank_angle_rad, rod_ratio, terms)
    total = np.sin(a)
    for j, amplitude in enumerate(h, start=1):
        total = total + 2.0 * j * amplitude * np.sin(2.0 * j * a)
    return crank_radius_m * angular_velocity_rad_s * total


def piston_acceleration_harmonic_m_s2(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s, terms
):
    r"""Acceleration of the harmonic form: :math:`R\omega^2[\cos\alpha + \sum_j 4j^2H_j\cos2j\alpha]`.

    Parameters
    ----------
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s, terms
        As :func:`piston_acceleration_series_m_s2`.

    Returns
    -------
    numpy.ndarray or float
        j_N [m/s^2].

    Notes
    -----
    Derived (term-by-term derivative; N = 2 gives Poda eq. 11).
    """
    a, h = _harmonics(crank_angle_rad, rod_ratio, terms)
    total = np.cos(a)
    for j, amplitude in enumerate(h, start=1):
        total = total + 4.0 * j * j * amplitude * np.cos(2.0 * j * a)
    return crank_radius_m * angular_velocity_rad_s**2 * total


def displacement_truncation_error_max_m(crank_radius_m, rod_ratio, terms):
    r"""Largest displacement error of the N-term series over a revolution (at alpha = 90 deg).

    Parameters
    ----------
    crank_radius_m : float
        R [m].
    rod_ratio : float
        lambda [-], 0 <= lambda < 1.
    terms : int
        N >= 1.

    Returns
    -------
    float
        max (s - s_N) = R/lambda [1 - sqrt(1 - lambda^2) - sum_{k<N} c_k lambda^(2k)] [m];
        0 for lambda = 0.

    Notes
    -----
    Derived: the omitted terms are all positive and grow with sin^2(alpha), so the error
    peaks at 90 deg. Evaluated as the tail sum sum_{k>=N} c_k lambda^(2k-1), which has no
    cancellation (the tail terms decay at least as lambda^2 each).
    """
    terms, lam = _check(terms, rod_ratio)
    lam = float(lam)
    if lam == 0.0:
        return 0.0
    total, k = 0.0, terms
    while True:
        term = series_coefficient(k) * lam ** (2 * k - 1)
        total += term
        if term <= 1e-18 * total or k > terms + 20000:
            break
        k += 1
    return crank_radius_m * total


def displacement_truncation_error_bounds_m(crank_angle_rad, crank_radius_m, rod_ratio, terms):
    r"""Lower and upper bounds of s - s_N at each angle (derived, see the module docstring).

    Parameters
    ----------
    crank_angle_rad : float or array_like
        alpha [rad].
    crank_radius_m : float
        R [m].
    rod_ratio : float
        lambda [-].
    terms : int
        N >= 1.

    Returns
    -------
    lower_m, upper_m : numpy.ndarray
        c_N lambda^(2N-1) sin^(2N) R and the same divided by (1 - lambda^2 sin^2 alpha) [m].
    """
    terms, lam = _check(terms, rod_ratio)
    sin_a = np.sin(np.asarray(crank_angle_rad, dtype=float))
    first_omitted = (
        series_coefficient(terms) * lam ** (2 * terms - 1) * sin_a ** (2 * terms) * crank_radius_m
    )
    return first_omitted, first_omitted / (1.0 - (lam * sin_a) ** 2)
