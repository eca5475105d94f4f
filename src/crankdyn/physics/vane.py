"""Crank-rocker parallelogram mechanism of the vane engine (Klementev 2023).

Two equal cranks of radius r (1, 2) turn in phase and carry the rocker (3, "кулиса")
as the coupler of a parallelogram, so the rocker translates without turning. The core (5)
with the vane turns about its fixed axis O3; its tail of length l ends in the slider (4),
which slides in the rocker's slot. The vane, not a piston, does the work: the working
volumes are set by the vane angle.

Conventions (those of the source)
---------------------------------
* alpha: crank angle from the upper (initial, symmetric) position, clockwise (the
  direction of omega); omega constant.
* lambda = r/l, chi = sqrt(1 - lambda^2 sin^2 alpha).
* beta: tail (core) angle, positive to the left; the vane, on the other side of the core
  axis, then turns to the right. beta = 0 at alpha = 0.
* Rocker coordinates from its initial position: x to the right, y downwards.
* Slider: x to the right; y measured from the core axis O3, downwards (y_p = l chi), or
  upwards from B', the tail end with the tail hanging vertically (alpha = 0):
  B'P = l - y_p (:func:`slider_vertical_travel_m`).
* Slider relative to the rocker: along the slot, upwards (towards the upper crank), zero at
  alpha = 0.

References
----------
Klementev, V. V. (2023). Kinematics of the crank-rocker parallelogram converting mechanism
of a vane internal combustion engine (in Russian). Vestnik UGATU 27(2), 24-41. Eqs. (1)-(5)
and the unnumbered relations for omega_c, epsilon_c, the rocker, the slider and its
relative motion. Every relation was re-derived for crankdyn; the OCR of eq. (3) lost its
minus sign and of y_max its structure: the derived forms are
gamma = arcsin(lambda) - arcsin(lambda sin alpha) and y_max = (r/lambda)(1 - sqrt(1 - lambda^2)).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "chi",
    "core_angle_rad",
    "core_angle_max_rad",
    "vane_angle_rad",
    "vane_angle_max_rad",
    "rod_ratio_from_vane_angle",
    "core_angular_velocity_rad_s",
    "core_angular_acceleration_rad_s2",
    "core_angular_acceleration_source_form_rad_s2",
    "rocker_position_m",
    "rocker_velocity_m_s",
    "rocker_acceleration_m_s2",
    "slider_height_below_core_m",
    "slider_vertical_travel_m",
    "slider_vertical_travel_max_m",
    "slider_vertical_velocity_m_s",
    "slider_vertical_acceleration_m_s2",
    "slider_vertical_acceleration_zeros_rad",
    "slider_relative_position_m",
    "slider_relative_velocity_m_s",
    "slider_relative_acceleration_m_s2",
]


def _as_float_array(value):
    return np.asarray(value, dtype=float)


def _checked(rod_ratio):
    rod_ratio = float(rod_ratio)
    if not 0.0 < rod_ratio < 1.0:
        raise ValueError(
            "lambda = r/l must satisfy 0 < lambda < 1 (r > l makes the mechanism inoperable)"
        )
    return rod_ratio


def chi(crank_angle_rad, rod_ratio):
    r""":math:`\chi = \sqrt{1 - \lambda^2\sin^2\alpha}` = cos(beta), always positive for lambda < 1."""
    lam = _checked(rod_ratio)
    s = lam * np.sin(_as_float_array(crank_angle_rad))
    return np.sqrt((1.0 - s) * (1.0 + s))


def core_angle_rad(crank_angle_rad, rod_ratio):
    r"""Tail (core) angle beta [rad], eq. (1): :math:`\beta = -\arcsin(\lambda\sin\alpha)`.

    Notes
    -----
    Derived: the slider shares the rocker's lateral motion r sin alpha, and the tail end
    is l sin(-beta) off the vertical through O3 (beta counted to the left).
    """
    return -np.arcsin(_checked(rod_ratio) * np.sin(_as_float_array(crank_angle_rad)))


def core_angle_max_rad(rod_ratio):
    r""":math:`|\beta_{max}| = \arcsin\lambda` (eq. 2), reached at alpha = 90 and 270 degrees."""
    return float(np.arcsin(_checked(rod_ratio)))


def vane_angle_rad(crank_angle_rad, rod_ratio):
    r"""Vane angle gamma from its extreme left position [rad] (eq. 3, corrected).

    Returns
    -------
    numpy.ndarray
        :math:`\gamma = \arcsin\lambda - \arcsin(\lambda\sin\alpha)`, from 0 at alpha = 90
        deg (extreme left) to 2 arcsin(lambda) at alpha = 270 deg (extreme right).

    Notes
    -----
    Derived: gamma = beta - beta_min with beta_min = -arcsin(lambda). The source's OCR
    prints eq. (3) without the minus sign between the two arcsines.
    """
    lam = _checked(rod_ratio)
    return np.arcsin(lam) - np.arcsin(lam * np.sin(_as_float_array(crank_angle_rad)))


def vane_angle_max_rad(rod_ratio):
    r""":math:`\gamma_{max} = 2\arcsin\lambda` [rad]."""
    return 2.0 * core_angle_max_rad(rod_ratio)


def rod_ratio_from_vane_angle(vane_angle_max_rad_):
    r""":math:`\lambda = \sin(\gamma_{max}/2)` (the source, after eq. 3): the swing sets lambda."""
    return float(np.sin(0.5 * float(vane_angle_max_rad_)))


def core_angular_velocity_rad_s(crank_angle_rad, rod_ratio, angular_velocity_rad_s):
    r"""Core angular velocity :math:`\omega_c = -\lambda\omega\cos\alpha/\chi` [rad/s] (source, §3).

    Notes
    -----
    Derived: d/dt of eq. (1). Positive clockwise (the vane's positive direction).
    """
    lam = _checked(rod_ratio)
    alpha = _as_float_array(crank_angle_rad)
    return -lam * float(angular_velocity_rad_s) * np.cos(alpha) / chi(alpha, lam)


def core_angular_acceleration_rad_s2(crank_angle_rad, rod_ratio, angular_velocity_rad_s):
    r"""Core angular acceleration at constant omega [rad/s^2].

    Returns
    -------
    numpy.ndarray
        :math:`\varepsilon_c = \lambda(1-\lambda^2)\,\omega^2\sin\alpha/\chi^3`.

    Notes
    -----
    Derived: d/dt of :func:`core_angular_velocity_rad_s`. The source's form
    :math:`-(\lambda\omega^2/\chi^2)\sin\alpha\,(\lambda^2\cos^2\alpha/\chi - \chi)`
    (:func:`core_angular_acceleration_source_form_rad_s2`) is the same function, because
    :math:`\lambda^2\cos^2\alpha - \chi^2 = \lambda^2 - 1`.
    """
    lam = _checked(rod_ratio)
    alpha = _as_float_array(crank_angle_rad)
    omega = float(angular_velocity_rad_s)
    return lam * (1.0 - lam * lam) * omega * omega * np.sin(alpha) / chi(alpha, lam) ** 3


def core_angular_acceleration_source_form_rad_s2(
    crank_angle_rad, rod_ratio, angular_velocity_rad_s
):
    r"""The source's expression for epsilon_c, kept to check it against the simplified one."""
    lam = _checked(rod_ratio)
    alpha = _as_float_array(crank_angle_rad)
    c = chi(alpha, lam)
    omega = float(angular_velocity_rad_s)
    return -(lam * omega * omega / c**2) * np.sin(alpha) * (lam * lam * np.cos(alpha) ** 2 / c - c)


def rocker_position_m(crank_angle_rad, crank_radius_m):
    r"""Rocker displacement from its initial position: :math:`x_k = r\sin\alpha`, :math:`y_k = r(1-\cos\alpha)`.

    Notes
    -----
    The rocker is the coupler of the parallelogram, so every point of it moves like the
    crank pin (x to the right, y downwards).
    """
    alpha = _as_float_array(crank_angle_rad)
    r = float(crank_radius_m)
    return r * np.sin(alpha), r * (1.0 - np.cos(alpha))


def rocker_velocity_m_s(crank_angle_rad, crank_radius_m, angular_velocity_rad_s):
    r""":math:`v_{xk} = r\omega\cos\alpha`, :math:`v_{yk} = r\omega\sin\alpha` [m/s]."""
    alpha = _as_float_array(crank_angle_rad)
    rw = float(crank_radius_m) * float(angular_velocity_rad_s)
    return rw * np.cos(alpha), rw * np.sin(alpha)


def rocker_acceleration_m_s2(crank_angle_rad, crank_radius_m, angular_velocity_rad_s):
    r""":math:`j_{xk} = -r\omega^2\sin\alpha`, :math:`j_{yk} = r\omega^2\cos\alpha` [m/s^2]."""
    alpha = _as_float_array(crank_angle_rad)
    rw2 = float(crank_radius_m) * float(angular_velocity_rad_s) ** 2
    return -rw2 * np.sin(alpha), rw2 * np.cos(alpha)


def slider_height_below_core_m(crank_angle_rad, crank_radius_m, rod_ratio):
    r"""Slider's distance below the core axis, :math:`y_p = O_3P = l\chi = (r/\lambda)\chi` [m].

    Its lateral coordinate equals the rocker's, :math:`x_p = l\sin(-\beta) = r\sin\alpha`.
    """
    lam = _checked(rod_ratio)
    return float(crank_radius_m) / lam * chi(crank_angle_rad, lam)


def slider_vertical_travel_m(crank_angle_rad, crank_radius_m, rod_ratio):
    r"""Slider's rise above B', the tail end in its lowest position: :math:`(r/\lambda)(1-\chi)` [m].

    Notes
    -----
    Zero at alpha = 0 and 180 deg, largest at 90 and 270 deg
    (:func:`slider_vertical_travel_max_m`).
    """
    lam = _checked(rod_ratio)
    return float(crank_radius_m) / lam * (1.0 - chi(crank_angle_rad, lam))


def slider_vertical_travel_max_m(crank_radius_m, rod_ratio):
    r"""Largest vertical travel of the slider, :math:`y_{max} = (r/\lambda)(1 - \sqrt{1-\lambda^2})` [m].

    Notes
    -----
    Derived: :func:`slider_vertical_travel_m` at sin^2 alpha = 1. With l = r/lambda this
    is l(1 - sqrt(1 - lambda^2)), 0.4 l for lambda = 0.8 (the source's value). Evaluated
    as :math:`r\lambda/(1+\sqrt{1-\lambda^2})`, without cancellation for small lambda.
    """
    lam = _checked(rod_ratio)
    return float(crank_radius_m) * lam / (1.0 + np.sqrt((1.0 - lam) * (1.0 + lam)))


def slider_vertical_velocity_m_s(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s
):
    r""":math:`v_{yp} = d(l\chi)/dt = -\omega r\lambda\sin\alpha\cos\alpha/\chi` [m/s] (source).

    Positive downwards (the y_p axis from O3).
    """
    lam = _checked(rod_ratio)
    alpha = _as_float_array(crank_angle_rad)
    return (
        -float(angular_velocity_rad_s)
        * float(crank_radius_m)
        * lam
        * np.sin(alpha)
        * np.cos(alpha)
        / chi(alpha, lam)
    )


def slider_vertical_acceleration_m_s2(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s
):
    r"""Vertical slider acceleration, eq. (4) [m/s^2].

    Returns
    -------
    numpy.ndarray
        :math:`j_{yp} = -(r\lambda\omega^2/\chi^2)(\chi\cos 2\alpha + \lambda^2\sin^2 2\alpha/(4\chi))`.

    Notes
    -----
    Derived: d/dt of :func:`slider_vertical_velocity_m_s`; agrees with eq. (4).
    """
    lam = _checked(rod_ratio)
    alpha = _as_float_array(crank_angle_rad)
    c = chi(alpha, lam)
    omega = float(angular_velocity_rad_s)
    return -(float(crank_radius_m) * lam * omega * omega / c**2) * (
        c * np.cos(2.0 * alpha) + lam * lam * np.sin(2.0 * alpha) ** 2 / (4.0 * c)
    )


def slider_vertical_acceleration_zeros_rad(rod_ratio):
    r"""Crank angles in [0, 2 pi) where the vertical slider acceleration vanishes.

    Returns
    -------
    numpy.ndarray
        :math:`\alpha_0, \pi-\alpha_0, \pi+\alpha_0, 2\pi-\alpha_0` with
        :math:`\sin^2\alpha_0 = (1-\sqrt{1-\lambda^2})/\lambda^2 = 1/(1+\sqrt{1-\lambda^2})`.

    Notes
    -----
    Derived: with u = sin^2 alpha the bracket of eq. (4) vanishes when
    :math:`4\chi^2\cos 2\alpha + \lambda^2\sin^2 2\alpha = 0`, which reduces to eq. (5),
    :math:`\lambda^2u^2 - 2u + 1 = 0`. Of its roots :math:`(1\pm\sqrt{1-\lambda^2})/\lambda^2`
    only the smaller is at most 1. For lambda = 0.8: sin alpha_0 = 0.7906, alpha_0 =
    52.239 deg, the source's check value (the source's "±52.239° ± πN").
    These are also the extremes of the vertical slider velocity.
    """
    lam = _checked(rod_ratio)
    alpha0 = float(np.arcsin(np.sqrt(1.0 / (1.0 + np.sqrt((1.0 - lam) * (1.0 + lam))))))
    return np.array([alpha0, np.pi - alpha0, np.pi + alpha0, 2.0 * np.pi - alpha0])


def slider_relative_position_m(crank_angle_rad, crank_radius_m, rod_ratio):
    r"""Slider position along the rocker's slot, relative to the rocker (upwards) [m].

    Returns
    -------
    numpy.ndarray
        :math:`y_{po} = r[(1-\cos\alpha) + (1-\chi)/\lambda]`, from 0 to 2r.

    Notes
    -----
    Derived: the rocker's downward displacement r(1 - cos alpha) plus the slider's rise
    l - l chi. It is the piston displacement of a central crank-slider with the same r and
    lambda (:func:`crankdyn.physics.kinematics.piston_displacement_exact_m`).
    """
    lam = _checked(rod_ratio)
    alpha = _as_float_array(crank_angle_rad)
    r = float(crank_radius_m)
    return r * ((1.0 - np.cos(alpha)) + (1.0 - chi(alpha, lam)) / lam)


def slider_relative_velocity_m_s(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s
):
    r""":math:`v_{po} = \omega r\sin\alpha\,(1 + \lambda\cos\alpha/\chi)` [m/s] (source)."""
    lam = _checked(rod_ratio)
    alpha = _as_float_array(crank_angle_rad)
    return (
        float(angular_velocity_rad_s)
        * float(crank_radius_m)
        * np.sin(alpha)
        * (1.0 + lam * np.cos(alpha) / chi(alpha, lam))
    )


def slider_relative_acceleration_m_s2(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s
):
    r"""Relative slider acceleration along the slot [m/s^2].

    Returns
    -------
    numpy.ndarray
        :math:`j_{po} = r\omega^2[(1+\mu)\cos\alpha - (\lambda/\chi)(1-\mu^2)\sin^2\alpha]`,
        :math:`\mu = \lambda\cos\alpha/\chi` (source).

    Notes
    -----
    Derived: d/dt of :func:`slider_relative_velocity_m_s`; equal to
    :math:`r\omega^2[\cos\alpha + \lambda\cos 2\alpha/\chi + \lambda^3\sin^2\alpha\cos^2\alpha/\chi^3]`.
    """
    lam = _checked(rod_ratio)
    alpha = _as_float_array(crank_angle_rad)
    c = chi(alpha, lam)
    mu = lam * np.cos(alpha) / c
    return (
        float(crank_radius_m)
        * float(angular_velocity_rad_s) ** 2
        * ((1.0 + mu) * np.cos(alpha) - (lam / c) * (1.0 - mu * mu) * np.sin(alpha) ** 2)
    )
