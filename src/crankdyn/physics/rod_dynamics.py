"""A connecting rod driven at its big end, its small end guided along the cylinder axis.

This module is the common part of every rod-based mechanism: the big end B may run on
the crank circle (central or offset crank-slider) or on an epicycloid or hypocycloid
(planetary crank mechanism); the small end A (piston pin) slides on the cylinder axis.
Given the path of B and its derivatives with respect to the crank angle, it gives the
piston-pin motion, the rod angle and its derivatives, the motion of the rod's centre of
mass, and the rod's inertia loads in three models: the textbook's two-mass split, the
dynamically equivalent three-mass model and the two-mass model plus a correction couple.

Frame and conventions
---------------------
Origin on the crankshaft axis; ``z`` along the cylinder axis towards TDC; ``x`` lateral,
positive in the direction in which the crank pin moves at TDC (the frame of
:mod:`crankdyn.physics.kinematics`). The cylinder axis is the line ``x = axis_x``.
The rod angle ``beta`` (sin beta = (x_B - x_A)/L) is positive when the rod leans in the
direction of rotation. Derivatives written with a prime are taken with respect to the
crank angle (per radian); time derivatives at constant crank speed omega follow as
``d/dt = omega d/d(alpha)``. Torques are positive in the direction of rotation.

References
----------
Poda, V. B. (2007). Dynamic calculation and balancing of piston internal combustion
engines (in Ukrainian). Kharkiv: KhAI. Eq. (17): the two-mass split of the rod.

All relations here were derived for crankdyn (loop closure of the rod and rigid-body
kinematics); the tests check them against root finding and finite differences.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = [
    "SliderMotion",
    "slider_from_big_end",
    "rod_point_acceleration_m_s2",
    "rod_point_velocity_m_s",
    "two_mass_moment_of_inertia_kg_m2",
    "three_mass_split_kg",
    "correction_couple_Nm",
    "rod_inertia_torque_Nm",
    "point_masses_inertia_torque_Nm",
    "periodic_derivative",
]


def _as_float_array(value):
    return np.asarray(value, dtype=float)


class SliderMotion(NamedTuple):
    """Piston pin and rod angle as functions of the crank angle (per-radian derivatives).

    Attributes
    ----------
    pin_z_m, pin_z_d1_m, pin_z_d2_m : numpy.ndarray
        Height z_A of the piston pin on the cylinder axis [m] and its first and second
        derivatives with respect to the crank angle [m/rad, m/rad^2].
    rod_angle_rad, rod_angle_d1, rod_angle_d2 : numpy.ndarray
        Rod angle beta [rad] and its derivatives [rad/rad, rad/rad^2].
    """

    pin_z_m: np.ndarray
    pin_z_d1_m: np.ndarray
    pin_z_d2_m: np.ndarray
    rod_angle_rad: np.ndarray
    rod_angle_d1: np.ndarray
    rod_angle_d2: np.ndarray


def slider_from_big_end(
    big_end_x_m,
    big_end_z_m,
    big_end_x_d1,
    big_end_z_d1,
    big_end_x_d2,
    big_end_z_d2,
    rod_length_m,
    axis_x_m=0.0,
):
    r"""Piston-pin motion and rod angle for a rod whose big end follows a given path.

    Parameters
    ----------
    big_end_x_m, big_end_z_m : array_like
        Big-end (rod pin) position B [m] in the frame of this module.
    big_end_x_d1, big_end_z_d1 : array_like
        dB/d(alpha) [m/rad].
    big_end_x_d2, big_end_z_d2 : array_like
        d^2B/d(alpha)^2 [m/rad^2].
    rod_length_m : float
        Centre-to-centre rod length L [m].
    axis_x_m : float, optional
        Lateral position of the cylinder axis [m] (the pin offset of a desaxial engine).

    Returns
    -------
    SliderMotion

    Raises
    ------
    ValueError
        If the big end comes L or more off the cylinder axis: the rod cannot reach it.

    Notes
    -----
    Derived from the loop closure A = B + L(-sin beta, cos beta) with A on the axis.
    With u = x_B - x_axis and w = sqrt(L^2 - u^2) = L cos beta:

    .. math::
        z_A = z_B + w,\quad
        w' = -u u'/w,\quad
        w'' = -(u'^2 + u u'')/w - u^2 u'^2/w^3,

        \sin\beta = u/L,\quad \beta' = u'/w,\quad \beta'' = u''/w + u u'^2/w^3.
    """
    u = _as_float_array(big_end_x_m) - float(axis_x_m)
    du = _as_float_array(big_end_x_d1)
    ddu = _as_float_array(big_end_x_d2)
    length = float(rod_length_m)
    if np.any(np.abs(u) >= length):
        raise ValueError(
            "the big end comes a rod length or more off the cylinder axis: the rod cannot reach"
        )
    w = np.sqrt((length - u) * (length + u))  # L cos(beta), without cancellation near |u| = L
    dw = -u * du / w
    ddw = -(du * du + u * ddu) / w - u * u * du * du / w**3
    return SliderMotion(
        pin_z_m=_as_float_array(big_end_z_m) + w,
        pin_z_d1_m=_as_float_array(big_end_z_d1) + dw,
        pin_z_d2_m=_as_float_array(big_end_z_d2) + ddw,
        rod_angle_rad=np.arcsin(u / length),
        rod_angle_d1=du / w,
        rod_angle_d2=ddu / w + u * du * du / w**3,
    )


def rod_point_velocity_m_s(
    pin_velocity_z_m_s, rod_angle_rad, rod_angular_velocity_rad_s, distance_from_pin_m
):
    r"""Velocity of a point of the rod axis.

    Parameters
    ----------
    pin_velocity_z_m_s : array_like
        dz_A/dt of the piston pin A along the cylinder axis [m/s] (= -v_p, since the piston
        displacement is counted from TDC towards the shaft).
    rod_angle_rad, rod_angular_velocity_rad_s : array_like
        beta [rad] and d(beta)/dt [rad/s].
    distance_from_pin_m : float
        Distance d of the point from the piston pin towards the big end [m]
        (d = L - l for a point l from the big end).

    Returns
    -------
    vx_m_s, vz_m_s : numpy.ndarray

    Notes
    -----
    Derived: the point is A + d(sin beta, -cos beta), so
    :math:`\dot x = d\dot\beta\cos\beta`, :math:`\dot z = \dot z_A + d\dot\beta\sin\beta`.
    """
    beta = _as_float_array(rod_angle_rad)
    rate = _as_float_array(rod_angular_velocity_rad_s)
    d = float(distance_from_pin_m)
    return d * rate * np.cos(beta), _as_float_array(pin_velocity_z_m_s) + d * rate * np.sin(beta)


def rod_point_acceleration_m_s2(
    pin_acceleration_z_m_s2,
    rod_angle_rad,
    rod_angular_velocity_rad_s,
    rod_angular_acceleration_rad_s2,
    distance_from_pin_m,
):
    r"""Acceleration of a point of the rod axis.

    Parameters
    ----------
    pin_acceleration_z_m_s2 : array_like
        d^2 z_A/dt^2 of the piston pin [m/s^2] (= -j_p).
    rod_angle_rad, rod_angular_velocity_rad_s, rod_angular_acceleration_rad_s2 : array_like
        beta, d(beta)/dt, d^2(beta)/dt^2.
    distance_from_pin_m : float
        Distance d of the point from the piston pin towards the big end [m].

    Returns
    -------
    ax_m_s2, az_m_s2 : numpy.ndarray

    Notes
    -----
    Derived: d/dt of :func:`rod_point_velocity_m_s`,
    :math:`\ddot x = d(\ddot\beta\cos\beta - \dot\beta^2\sin\beta)`,
    :math:`\ddot z = \ddot z_A + d(\ddot\beta\sin\beta + \dot\beta^2\cos\beta)`.
    """
    beta = _as_float_array(rod_angle_rad)
    rate = _as_float_array(rod_angular_velocity_rad_s)
    accel = _as_float_array(rod_angular_acceleration_rad_s2)
    d = float(distance_from_pin_m)
    cos_b, sin_b = np.cos(beta), np.sin(beta)
    ax = d * (accel * cos_b - rate * rate * sin_b)
    az = _as_float_array(pin_acceleration_z_m_s2) + d * (accel * sin_b + rate * rate * cos_b)
    return ax, az


def two_mass_moment_of_inertia_kg_m2(rod_mass_kg, rod_length_m, cm_from_big_end_m):
    r"""Moment of inertia about the centre of mass implied by the two-mass split.

    Parameters
    ----------
    rod_mass_kg, rod_length_m, cm_from_big_end_m : float
        m, L and l_R (centre of mass from the big-end centre).

    Returns
    -------
    float
        :math:`I_2 = m l_R (L - l_R)` [kg m^2].

    Notes
    -----
    Derived: m l_R/L at the small end (L - l_R from G) and m (L - l_R)/L at the big end
    (l_R from G) give :math:`m l_R (L-l_R)^2/L + m (L-l_R) l_R^2/L = m l_R (L - l_R)`.
    The textbook split (Poda eq. 17) keeps the mass and the centre of mass but not the
    moment of inertia; the real rod's I_G is usually smaller.
    """
    return (
        float(rod_mass_kg)
        * float(cm_from_big_end_m)
        * (float(rod_length_m) - float(cm_from_big_end_m))
    )


def three_mass_split_kg(rod_mass_kg, rod_length_m, cm_from_big_end_m, moment_of_inertia_kg_m2):
    r"""Dynamically equivalent three-mass model of the rod: masses at the small end, big end and G.

    Parameters
    ----------
    rod_mass_kg : float
        Rod mass m [kg].
    rod_length_m : float
        L [m].
    cm_from_big_end_m : float
        l_R, distance of the centre of mass G from the big-end centre [m].
    moment_of_inertia_kg_m2 : float
        I_G, moment of inertia about the axis through G normal to the plane of motion.

    Returns
    -------
    small_end_kg, big_end_kg, centre_kg : float
        :math:`m_A = I_G/(L(L-l_R))`, :math:`m_B = I_G/(L l_R)`,
        :math:`m_G = m - I_G/(l_R(L-l_R))`.

    Notes
    -----
    Derived from the three conditions of dynamic equivalence: the same mass, the same
    centre of mass (m_A (L - l_R) = m_B l_R) and the same moment of inertia about G
    (m_A (L - l_R)^2 + m_B l_R^2 = I_G). m_G is negative when I_G exceeds the two-mass
    value m l_R (L - l_R); the model stays exact, but the mass at G loses its physical
    meaning.
    """
    m, length, l_r, inertia = (
        float(rod_mass_kg),
        float(rod_length_m),
        float(cm_from_big_end_m),
        float(moment_of_inertia_kg_m2),
    )
    small_end = inertia / (length * (length - l_r))
    big_end = inertia / (length * l_r)
    return small_end, big_end, m - small_end - big_end


def correction_couple_Nm(
    rod_angular_acceleration_rad_s2,
    rod_mass_kg,
    rod_length_m,
    cm_from_big_end_m,
    moment_of_inertia_kg_m2,
):
    r"""Couple to add to the two-mass model so that it becomes dynamically exact.

    Parameters
    ----------
    rod_angular_acceleration_rad_s2 : array_like
        d^2(beta)/dt^2 [rad/s^2].
    rod_mass_kg, rod_length_m, cm_from_big_end_m, moment_of_inertia_kg_m2 : float
        m, L, l_R, I_G.

    Returns
    -------
    numpy.ndarray
        :math:`\Delta M = -(I_G - m l_R (L - l_R))\,\ddot\beta` [N m], positive in the
        sense of increasing beta.

    Notes
    -----
    Derived: the inertia forces of the two masses have the right resultant (-m a_G,
    because G divides AB in the same ratio as the masses) but the moment
    :math:`-I_2\ddot\beta` about G; the real rod's is :math:`-I_G\ddot\beta`.
    """
    delta = float(moment_of_inertia_kg_m2) - two_mass_moment_of_inertia_kg_m2(
        rod_mass_kg, rod_length_m, cm_from_big_end_m
    )
    return -delta * _as_float_array(rod_angular_acceleration_rad_s2)


def rod_inertia_torque_Nm(
    rod_mass_kg,
    moment_of_inertia_kg_m2,
    cm_velocity,
    cm_acceleration,
    rod_angular_velocity_rad_s,
    rod_angular_acceleration_rad_s2,
    angular_velocity_rad_s,
):
    r"""Torque that the inertia of a rigid rod puts on the crankshaft.

    Parameters
    ----------
    rod_mass_kg : float
        m [kg].
    moment_of_inertia_kg_m2 : float
        Moment of inertia about G used by the model [kg m^2].
    cm_velocity, cm_acceleration : tuple of array_like
        (x, z) velocity [m/s] and acceleration [m/s^2] of the centre of mass.
    rod_angular_velocity_rad_s, rod_angular_acceleration_rad_s2 : array_like
        d(beta)/dt, d^2(beta)/dt^2.
    angular_velocity_rad_s : float
        Crankshaft speed omega [rad/s].

    Returns
    -------
    numpy.ndarray
        :math:`M = -(m\,\mathbf a_G\cdot\mathbf v_G + I\dot\beta\ddot\beta)/\omega` [N m],
        positive in the direction of rotation; its cycle mean is zero.

    Notes
    -----
    Derived by virtual work for a frictionless mechanism: the power of the rod's
    inertia forces, minus the rate of change of its kinetic energy
    :math:`\tfrac12 m v_G^2 + \tfrac12 I\dot\beta^2` (König), is delivered to the shaft.
    """
    vx, vz = cm_velocity
    ax, az = cm_acceleration
    power = float(rod_mass_kg) * (_as_float_array(ax) * vx + _as_float_array(az) * vz) + float(
        moment_of_inertia_kg_m2
    ) * _as_float_array(rod_angular_velocity_rad_s) * _as_float_array(
        rod_angular_acceleration_rad_s2
    )
    return -power / float(angular_velocity_rad_s)


def point_masses_inertia_torque_Nm(masses_kg, velocities, accelerations, angular_velocity_rad_s):
    r"""Torque on the crankshaft from the inertia of point masses.

    Parameters
    ----------
    masses_kg : sequence of float
        The point masses [kg].
    velocities, accelerations : sequence of (x, z) pairs of array_like
        Velocity [m/s] and acceleration [m/s^2] of each mass.
    angular_velocity_rad_s : float
        omega [rad/s].

    Returns
    -------
    numpy.ndarray
        :math:`M = -\sum_i m_i\,\mathbf a_i\cdot\mathbf v_i/\omega` [N m].

    Notes
    -----
    Virtual work, as :func:`rod_inertia_torque_Nm`; used to evaluate a mass model
    directly, independently of the rigid-body form.
    """
    power = 0.0
    for m, (vx, vz), (ax, az) in zip(masses_kg, velocities, accelerations, strict=True):
        power = power + float(m) * (_as_float_array(ax) * vx + _as_float_array(az) * vz)
    return -_as_float_array(power) / float(angular_velocity_rad_s)


def periodic_derivative(values, period):
    r"""Derivative of a smooth periodic function sampled on a uniform periodic grid.

    Parameters
    ----------
    values : array_like, shape (N,)
        Samples f(x_k), x_k = x_0 + k period/N, k = 0..N-1 (no duplicated end point).
    period : float
        Length of the sampled interval; the function must be periodic over it.

    Returns
    -------
    numpy.ndarray
        df/dx at the samples.

    Notes
    -----
    Spectral (Fourier) differentiation: exact for trigonometric polynomials of degree
    below N/2 and exponentially accurate for analytic periodic functions. The Nyquist
    mode of an even N is dropped, as its derivative is not defined on the grid.
    """
    values = _as_float_array(values)
    n = values.size
    coefficients = np.fft.rfft(values)
    wavenumbers = 2.0 * np.pi * np.arange(coefficients.size) / float(period)
    derivative = 1j * wavenumbers * coefficients
    if n % 2 == 0:
        derivative[-1] = 0.0
    return np.fft.irfft(derivative, n)
