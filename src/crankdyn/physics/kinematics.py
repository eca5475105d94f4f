"""Kinematics of the central (non-offset) crank-slider mechanism.

Conventions used throughout the module
--------------------------------------
* ``crank_angle_rad`` (alpha) is measured from top dead centre (TDC) in the
  direction of crankshaft rotation.
* Piston displacement ``s`` is measured from TDC towards the crankshaft, so
  ``s(0) = 0`` and ``s(pi) = 2 R``.  Velocity and acceleration are the first
  and second time derivatives of ``s`` at constant angular velocity, hence the
  acceleration is positive at TDC: ``j(0) = R w^2 (1 + lambda)``.
* ``rod_ratio`` (lambda) is crank radius over connecting-rod length, ``R / L``,
  and must satisfy ``0 <= lambda < 1``.
* The rod angle ``beta = arcsin(lambda sin alpha)`` is positive when the rod
  leans in the direction of rotation.
* Plane coordinates for points of the rod: origin on the crankshaft axis,
  ``z`` along the cylinder axis pointing towards TDC, ``x`` lateral and
  positive in the direction in which the crank pin moves at TDC.  Then the
  crank pin is ``B = (R sin alpha, R cos alpha)`` and the piston pin is
  ``A = (0, R cos alpha + L cos beta)``.

All quantities are SI.  Every function accepts scalars or numpy arrays
(broadcast against each other) and returns numpy arrays or numpy scalars.

References
----------
Poda, V. B. (2007). Dynamic calculation and balancing of piston internal
combustion engines (in Ukrainian). Kharkiv: KhAI.  Section 2, eqs. (9)-(11)
and (26).

Tristen, A. V., & Semenov, I. N. (n.d.). Kinematics of the crank-slider
mechanism (in Russian; student paper, Brest State Technical University):
eq. (3) approximate peak piston speed, eq. (4) mean piston speed, eq. (6)
maximum acceleration, eq. (7) minimum acceleration cases, eqs. (8)-(10)
motion of a point on the rod.
"""

from __future__ import annotations

import numpy as np

from .extrema import first_argmin
from .scalar_search import brentq

__all__ = [
    "rod_angle_rad",
    "piston_displacement_exact_m",
    "piston_displacement_approx_m",
    "piston_velocity_exact_m_s",
    "piston_velocity_approx_m_s",
    "piston_acceleration_exact_m_s2",
    "piston_acceleration_approx_m_s2",
    "piston_jerk_exact_m_s3",
    "rod_angular_velocity_rad_s",
    "rod_angular_acceleration_rad_s2",
    "rod_point_position_m",
    "rod_point_velocity_m_s",
    "rod_point_acceleration_m_s2",
    "mean_piston_speed_m_s",
    "max_piston_velocity_approx_m_s",
    "max_piston_velocity_exact",
    "max_piston_acceleration_m_s2",
    "min_piston_acceleration_approx",
    "min_piston_acceleration_exact",
]


def _as_float_array(value):
    return np.asarray(value, dtype=float)


def _checked_rod_ratio(rod_ratio):
    if type(rod_ratio) is float:  # the usual case, checked without numpy's reductions (same test)
        if rod_ratio < 0.0 or rod_ratio >= 1.0:
            raise ValueError("rod_ratio must satisfy 0 <= rod_ratio < 1")
        return rod_ratio
    rod_ratio = _as_float_array(rod_ratio)
    # lambda >= 1 would let the crank pin swing past the piston-pin circle,
    # so beta = arcsin(lambda sin alpha) stops being defined for some alpha.
    if np.any(rod_ratio < 0.0) or np.any(rod_ratio >= 1.0):
        raise ValueError("rod_ratio must satisfy 0 <= rod_ratio < 1")
    return rod_ratio


def _cos_rod_angle(crank_angle_rad, rod_ratio):
    # sqrt(1 - lambda^2 sin^2 alpha) is exact and avoids cos(arcsin(.))
    # round-off; it stays strictly positive because lambda < 1.
    sin_beta = rod_ratio * np.sin(crank_angle_rad)
    return np.sqrt(1.0 - sin_beta * sin_beta)


def rod_angle_rad(crank_angle_rad, rod_ratio):
    r"""Angle between the connecting rod and the cylinder axis.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha measured from TDC in the direction of rotation [rad].
    rod_ratio : float or array_like
        Crank radius over rod length, lambda = R / L [-], 0 <= lambda < 1.

    Returns
    -------
    numpy.ndarray or float
        Rod angle beta [rad], positive when the rod leans in the direction of
        rotation.

    Notes
    -----
    Poda (2007) eq. (26): :math:`\beta = \arcsin(\lambda \sin\alpha)`.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    return np.arcsin(rod_ratio * np.sin(crank_angle_rad))


def piston_displacement_exact_m(crank_angle_rad, crank_radius_m, rod_ratio):
    r"""Exact piston displacement from TDC of a central crank-slider.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].

    Returns
    -------
    numpy.ndarray or float
        Piston displacement s [m], measured from TDC towards the crankshaft.

    Notes
    -----
    Derived from the geometry (exact form):
    :math:`s = R[(1-\cos\alpha) + (1-\cos\beta)/\lambda]`.  It is evaluated
    as :math:`R[2\sin^2(\alpha/2) + \lambda\sin^2\alpha/(1+\cos\beta)]`,
    which is algebraically identical but has no 0/0 as lambda -> 0 and no
    cancellation near TDC.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    crank_radius_m = _as_float_array(crank_radius_m)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    half_sin = np.sin(0.5 * crank_angle_rad)
    sin_alpha = np.sin(crank_angle_rad)
    cos_beta = _cos_rod_angle(crank_angle_rad, rod_ratio)
    crank_part = 2.0 * half_sin * half_sin
    rod_part = rod_ratio * sin_alpha * sin_alpha / (1.0 + cos_beta)
    return crank_radius_m * (crank_part + rod_part)


def piston_displacement_approx_m(crank_angle_rad, crank_radius_m, rod_ratio):
    r"""Two-term (second-order in lambda) piston displacement from TDC.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].

    Returns
    -------
    numpy.ndarray or float
        Approximate piston displacement s [m]; the truncation error relative
        to the exact form is O(R lambda^3).

    Notes
    -----
    Poda (2007) eq. (9):
    :math:`s = R[(1+\lambda/4) - (\cos\alpha + (\lambda/4)\cos 2\alpha)]`.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    crank_radius_m = _as_float_array(crank_radius_m)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    quarter = 0.25 * rod_ratio
    return crank_radius_m * (
        (1.0 + quarter) - (np.cos(crank_angle_rad) + quarter * np.cos(2.0 * crank_angle_rad))
    )


def piston_velocity_exact_m_s(crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s):
    r"""Exact piston velocity of a central crank-slider.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Constant crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        Piston velocity v = ds/dt [m/s], positive while the piston moves away
        from TDC.

    Notes
    -----
    Derived: exact form, d/dt of the exact displacement,
    :math:`v = R\omega\,\sin(\alpha+\beta)/\cos\beta`.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    sin_alpha = np.sin(crank_angle_rad)
    cos_alpha = np.cos(crank_angle_rad)
    cos_beta = _cos_rod_angle(crank_angle_rad, rod_ratio)
    # sin(a+b)/cos b = sin a + cos a tan b, with tan b = lambda sin a / cos b
    ratio = sin_alpha * (1.0 + rod_ratio * cos_alpha / cos_beta)
    return _as_float_array(crank_radius_m) * _as_float_array(angular_velocity_rad_s) * ratio


def piston_velocity_approx_m_s(crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s):
    r"""Two-term piston velocity.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Constant crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        Approximate piston velocity [m/s] (exact time derivative of the
        two-term displacement).

    Notes
    -----
    Poda (2007) eq. (10):
    :math:`v = R\omega(\sin\alpha + (\lambda/2)\sin 2\alpha)`.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    shape = np.sin(crank_angle_rad) + 0.5 * rod_ratio * np.sin(2.0 * crank_angle_rad)
    return _as_float_array(crank_radius_m) * _as_float_array(angular_velocity_rad_s) * shape


def piston_acceleration_exact_m_s2(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s
):
    r"""Exact piston acceleration of a central crank-slider.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Constant crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        Piston acceleration j = d^2 s / dt^2 [m/s^2]; positive at TDC.

    Notes
    -----
    Derived: exact form, d/dt of the exact velocity at constant omega,
    using d(beta)/dt = omega lambda cos(alpha) / cos(beta):

    .. math::
        j = R\omega^2\left[\frac{\cos(\alpha+\beta)}{\cos\beta}
            + \frac{\lambda\cos^2\alpha}{\cos^3\beta}\right].
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    sin_alpha = np.sin(crank_angle_rad)
    cos_alpha = np.cos(crank_angle_rad)
    cos_beta = _cos_rod_angle(crank_angle_rad, rod_ratio)
    # cos(a+b)/cos b = cos a - sin a tan b
    tan_beta = rod_ratio * sin_alpha / cos_beta
    shape = cos_alpha - sin_alpha * tan_beta + rod_ratio * cos_alpha**2 / cos_beta**3
    omega = _as_float_array(angular_velocity_rad_s)
    return _as_float_array(crank_radius_m) * omega * omega * shape


def piston_acceleration_approx_m_s2(
    crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s
):
    r"""Two-term piston acceleration.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Constant crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        Approximate piston acceleration [m/s^2].

    Notes
    -----
    Poda (2007) eq. (11):
    :math:`j = R\omega^2(\cos\alpha + \lambda\cos 2\alpha)`.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    shape = np.cos(crank_angle_rad) + rod_ratio * np.cos(2.0 * crank_angle_rad)
    omega = _as_float_array(angular_velocity_rad_s)
    return _as_float_array(crank_radius_m) * omega * omega * shape


def piston_jerk_exact_m_s3(crank_angle_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s):
    r"""Exact piston jerk (time derivative of acceleration).

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Constant crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        Piston jerk d^3 s / dt^3 [m/s^3].

    Notes
    -----
    Derived: exact form, d/dt of :func:`piston_acceleration_exact_m_s2`:

    .. math::
        \dot j = -R\omega^3\sin\alpha\left[1 + \frac{\lambda\cos\alpha}{\cos\beta}
            + \frac{3\lambda\cos\alpha}{\cos^3\beta}
            - \frac{3\lambda^3\cos^3\alpha}{\cos^5\beta}\right].

    The bracket is strictly positive for ``cos(alpha) >= 0``, so the
    acceleration can only have an interior minimum in ``(pi/2, pi)``.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    omega = _as_float_array(angular_velocity_rad_s)
    bracket = _jerk_bracket(crank_angle_rad, rod_ratio)
    return -_as_float_array(crank_radius_m) * omega**3 * np.sin(crank_angle_rad) * bracket


def _jerk_bracket(crank_angle_rad, rod_ratio):
    cos_alpha = np.cos(crank_angle_rad)
    cos_beta = _cos_rod_angle(crank_angle_rad, rod_ratio)
    return (
        1.0
        + rod_ratio * cos_alpha / cos_beta
        + 3.0 * rod_ratio * cos_alpha / cos_beta**3
        - 3.0 * rod_ratio**3 * cos_alpha**3 / cos_beta**5
    )


def rod_angular_velocity_rad_s(crank_angle_rad, rod_ratio, angular_velocity_rad_s):
    r"""Angular velocity of the connecting rod.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Constant crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        d(beta)/dt [rad/s], with the sign convention of :func:`rod_angle_rad`.

    Notes
    -----
    Derived: d/dt of :math:`\sin\beta = \lambda\sin\alpha`, giving
    :math:`\dot\beta = \omega\lambda\cos\alpha/\cos\beta`.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    cos_beta = _cos_rod_angle(crank_angle_rad, rod_ratio)
    return _as_float_array(angular_velocity_rad_s) * rod_ratio * np.cos(crank_angle_rad) / cos_beta


def rod_angular_acceleration_rad_s2(crank_angle_rad, rod_ratio, angular_velocity_rad_s):
    r"""Angular acceleration of the connecting rod at constant crank speed.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Constant crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        d^2(beta)/dt^2 [rad/s^2].

    Notes
    -----
    Derived: d/dt of :func:`rod_angular_velocity_rad_s`,
    :math:`\ddot\beta = -\omega^2\lambda(1-\lambda^2)\sin\alpha/\cos^3\beta`.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    omega = _as_float_array(angular_velocity_rad_s)
    cos_beta = _cos_rod_angle(crank_angle_rad, rod_ratio)
    return -omega * omega * rod_ratio * (1.0 - rod_ratio**2) * np.sin(crank_angle_rad) / cos_beta**3


def rod_point_position_m(crank_angle_rad, crank_radius_m, rod_ratio, distance_from_big_end_m):
    r"""Plane position of a point on the rod axis (e.g. its centre of mass).

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    distance_from_big_end_m : float or array_like
        Distance l of the point from the crank-pin (big-end) centre, measured
        along the rod towards the piston pin [m]; l = L is the piston pin.

    Returns
    -------
    x_m : numpy.ndarray or float
        Lateral coordinate [m], positive in the direction the crank pin moves
        at TDC.
    z_m : numpy.ndarray or float
        Coordinate along the cylinder axis from the crankshaft axis towards
        TDC [m].

    Notes
    -----
    Derived from the geometry; the same result as Tristen & Semenov,
    eq. (8):
    :math:`x = R\sin\alpha - l\sin\beta`, :math:`z = R\cos\alpha + l\cos\beta`.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    crank_radius_m = _as_float_array(crank_radius_m)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    distance = _as_float_array(distance_from_big_end_m)
    sin_alpha = np.sin(crank_angle_rad)
    sin_beta = rod_ratio * sin_alpha
    cos_beta = _cos_rod_angle(crank_angle_rad, rod_ratio)
    x_m = crank_radius_m * sin_alpha - distance * sin_beta
    z_m = crank_radius_m * np.cos(crank_angle_rad) + distance * cos_beta
    return x_m, z_m


def rod_point_velocity_m_s(
    crank_angle_rad, crank_radius_m, rod_ratio, distance_from_big_end_m, angular_velocity_rad_s
):
    r"""Velocity of a point on the rod axis at constant crank speed.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    distance_from_big_end_m : float or array_like
        Distance l of the point from the crank-pin centre along the rod [m].
    angular_velocity_rad_s : float or array_like
        Constant crankshaft angular velocity omega [rad/s].

    Returns
    -------
    vx_m_s : numpy.ndarray or float
        d x / dt [m/s] in the frame of :func:`rod_point_position_m`.
    vz_m_s : numpy.ndarray or float
        d z / dt [m/s].

    Notes
    -----
    Derived: d/dt of :func:`rod_point_position_m`,
    :math:`\dot x = R\omega\cos\alpha - l\dot\beta\cos\beta`,
    :math:`\dot z = -R\omega\sin\alpha - l\dot\beta\sin\beta`.
    Because :math:`l\dot\beta\cos\beta = l\lambda\omega\cos\alpha`, the
    lateral part reduces to :math:`R\omega\cos\alpha(1 - l/L)`.  (The
    Tristen & Semenov, eq. (9), print ``cos(beta)`` in place of
    ``cos(alpha)`` in the second term of the lateral velocity; their eq. (10)
    is consistent with the form used here.)
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    crank_radius_m = _as_float_array(crank_radius_m)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    distance = _as_float_array(distance_from_big_end_m)
    omega = _as_float_array(angular_velocity_rad_s)
    sin_alpha = np.sin(crank_angle_rad)
    cos_alpha = np.cos(crank_angle_rad)
    sin_beta = rod_ratio * sin_alpha
    cos_beta = _cos_rod_angle(crank_angle_rad, rod_ratio)
    beta_rate = omega * rod_ratio * cos_alpha / cos_beta
    vx_m_s = crank_radius_m * omega * cos_alpha - distance * beta_rate * cos_beta
    vz_m_s = -crank_radius_m * omega * sin_alpha - distance * beta_rate * sin_beta
    return vx_m_s, vz_m_s


def rod_point_acceleration_m_s2(
    crank_angle_rad, crank_radius_m, rod_ratio, distance_from_big_end_m, angular_velocity_rad_s
):
    r"""Acceleration of a point on the rod axis at constant crank speed.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    distance_from_big_end_m : float or array_like
        Distance l of the point from the crank-pin centre along the rod [m].
    angular_velocity_rad_s : float or array_like
        Constant crankshaft angular velocity omega [rad/s].

    Returns
    -------
    ax_m_s2 : numpy.ndarray or float
        d^2 x / dt^2 [m/s^2] in the frame of :func:`rod_point_position_m`.
    az_m_s2 : numpy.ndarray or float
        d^2 z / dt^2 [m/s^2].

    Notes
    -----
    Derived: d/dt of :func:`rod_point_velocity_m_s`,

    .. math::
        \ddot x = -R\omega^2\sin\alpha
                  - l(\ddot\beta\cos\beta - \dot\beta^2\sin\beta),\qquad
        \ddot z = -R\omega^2\cos\alpha
                  - l(\ddot\beta\sin\beta + \dot\beta^2\cos\beta),

    which agrees with Tristen & Semenov, eq. (10).  The lateral part
    simplifies to :math:`-R\omega^2\sin\alpha(1 - l/L)`.
    """
    crank_angle_rad = _as_float_array(crank_angle_rad)
    crank_radius_m = _as_float_array(crank_radius_m)
    rod_ratio = _checked_rod_ratio(rod_ratio)
    distance = _as_float_array(distance_from_big_end_m)
    omega = _as_float_array(angular_velocity_rad_s)
    sin_alpha = np.sin(crank_angle_rad)
    cos_alpha = np.cos(crank_angle_rad)
    sin_beta = rod_ratio * sin_alpha
    cos_beta = _cos_rod_angle(crank_angle_rad, rod_ratio)
    beta_rate = omega * rod_ratio * cos_alpha / cos_beta
    beta_accel = -omega * omega * rod_ratio * (1.0 - rod_ratio**2) * sin_alpha / cos_beta**3
    centripetal = crank_radius_m * omega * omega
    ax_m_s2 = -centripetal * sin_alpha - distance * (
        beta_accel * cos_beta - beta_rate**2 * sin_beta
    )
    az_m_s2 = -centripetal * cos_alpha - distance * (
        beta_accel * sin_beta + beta_rate**2 * cos_beta
    )
    return ax_m_s2, az_m_s2


def mean_piston_speed_m_s(crank_radius_m, angular_velocity_rad_s):
    r"""Mean piston speed.

    Parameters
    ----------
    crank_radius_m : float or array_like
        Crank radius R [m].
    angular_velocity_rad_s : float or array_like
        Crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        Mean piston speed [m/s]: stroke 2R travelled twice per revolution.

    Notes
    -----
    Tristen & Semenov eq. (4): :math:`c_m = 2R\omega/\pi`, identical to the
    usual :math:`S n / 30` with S = 2R in m and n in rpm.
    """
    return 2.0 * _as_float_array(crank_radius_m) * _as_float_array(angular_velocity_rad_s) / np.pi


def max_piston_velocity_approx_m_s(crank_radius_m, rod_ratio, angular_velocity_rad_s):
    r"""Approximate peak piston speed.

    Parameters
    ----------
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        Approximate maximum piston velocity [m/s].

    Notes
    -----
    Tristen & Semenov eq. (3): :math:`v_{max} \approx R\omega\sqrt{1+\lambda^2}`.
    It matches the exact peak (:func:`max_piston_velocity_exact`) far better
    than its derivation suggests: the shortfall is about
    :math:`R\omega\lambda^6/2` for small lambda (checked numerically, about
    3e-5 R omega at lambda = 0.2).
    """
    rod_ratio = _checked_rod_ratio(rod_ratio)
    return (
        _as_float_array(crank_radius_m)
        * _as_float_array(angular_velocity_rad_s)
        * np.sqrt(1.0 + rod_ratio**2)
    )


def max_piston_velocity_exact(crank_radius_m, rod_ratio, angular_velocity_rad_s):
    r"""Exact peak piston speed and the crank angle at which it occurs.

    Parameters
    ----------
    crank_radius_m : float
        Crank radius R [m].
    rod_ratio : float
        lambda = R / L [-].
    angular_velocity_rad_s : float
        Crankshaft angular velocity omega [rad/s], positive.

    Returns
    -------
    v_max_m_s : float
        Maximum piston velocity over the outward stroke [m/s].
    crank_angle_at_max_rad : float
        Crank angle in (0, pi/2] at which it is reached [rad].

    Notes
    -----
    Derived: the velocity peaks where the exact acceleration
    (:func:`piston_acceleration_exact_m_s2`) vanishes.  That root is unique in
    (0, pi/2] because the acceleration is positive at TDC, equals
    :math:`-R\omega^2\tan\beta \le 0` at 90 degrees and decreases in between
    (see :func:`piston_jerk_exact_m_s3`).  It is found with Brent's method to
    a few ulp.
    """
    rod_ratio = float(_checked_rod_ratio(rod_ratio))
    crank_radius_m = float(crank_radius_m)
    angular_velocity_rad_s = float(angular_velocity_rad_s)
    quarter_turn = 0.5 * np.pi
    if rod_ratio == 0.0:
        # Pure harmonic motion: cos(pi/2) is not exactly zero in floating
        # point, so the bracket would not change sign.
        crank_angle_at_max_rad = quarter_turn
    else:
        crank_angle_at_max_rad = brentq(
            lambda angle: float(piston_acceleration_exact_m_s2(angle, 1.0, rod_ratio, 1.0)),
            0.0,
            quarter_turn,
            xtol=1e-300,
            rtol=4.0 * np.finfo(float).eps,
            maxiter=200,
        )
    v_max_m_s = float(
        piston_velocity_exact_m_s(
            crank_angle_at_max_rad, crank_radius_m, rod_ratio, angular_velocity_rad_s
        )
    )
    return v_max_m_s, float(crank_angle_at_max_rad)


def max_piston_acceleration_m_s2(crank_radius_m, rod_ratio, angular_velocity_rad_s):
    r"""Maximum piston acceleration (reached at TDC).

    Parameters
    ----------
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Crankshaft angular velocity omega [rad/s].

    Returns
    -------
    numpy.ndarray or float
        :math:`R\omega^2(1+\lambda)` [m/s^2].

    Notes
    -----
    Tristen & Semenov eq. (6); Poda (2007) eq. (11) at alpha = 0.  The exact
    and the two-term accelerations coincide at TDC, and the exact form has
    its global maximum there (it decreases monotonically on [0, pi/2]).
    """
    rod_ratio = _checked_rod_ratio(rod_ratio)
    omega = _as_float_array(angular_velocity_rad_s)
    return _as_float_array(crank_radius_m) * omega * omega * (1.0 + rod_ratio)


def min_piston_acceleration_approx(crank_radius_m, rod_ratio, angular_velocity_rad_s):
    r"""Minimum of the two-term piston acceleration and its crank angle.

    Parameters
    ----------
    crank_radius_m : float
        Crank radius R [m].
    rod_ratio : float
        lambda = R / L [-].
    angular_velocity_rad_s : float
        Crankshaft angular velocity omega [rad/s].

    Returns
    -------
    j_min_m_s2 : float
        Most negative value of eq. (11) [m/s^2].
    crank_angle_rad : float
        Crank angle in [0, pi] where it occurs [rad].

    Notes
    -----
    Tristen & Semenov eq. (7), derived from Poda (2007) eq. (11):

    * lambda <= 1/4: :math:`j_{min} = -R\omega^2(1-\lambda)` at alpha = pi;
    * lambda > 1/4: :math:`j_{min} = -R\omega^2(\lambda + 1/(8\lambda))` at
      :math:`\alpha = \arccos(-1/(4\lambda))`.

    The second angle mirrors to 2 pi - alpha on the return stroke.
    """
    rod_ratio = float(_checked_rod_ratio(rod_ratio))
    scale = float(crank_radius_m) * float(angular_velocity_rad_s) ** 2
    if rod_ratio <= 0.25:
        return -scale * (1.0 - rod_ratio), float(np.pi)
    return (
        -scale * (rod_ratio + 1.0 / (8.0 * rod_ratio)),
        float(np.arccos(-1.0 / (4.0 * rod_ratio))),
    )


def min_piston_acceleration_exact(crank_radius_m, rod_ratio, angular_velocity_rad_s):
    r"""Minimum of the exact piston acceleration and its crank angle.

    Parameters
    ----------
    crank_radius_m : float
        Crank radius R [m].
    rod_ratio : float
        lambda = R / L [-].
    angular_velocity_rad_s : float
        Crankshaft angular velocity omega [rad/s].

    Returns
    -------
    j_min_m_s2 : float
        Minimum of :func:`piston_acceleration_exact_m_s2` over [0, pi]
        [m/s^2].
    crank_angle_rad : float
        Crank angle in [pi/2, pi] where it occurs [rad].

    Notes
    -----
    Derived: candidates are BDC and the roots of the exact jerk
    (:func:`piston_jerk_exact_m_s3`) in (pi/2, pi), bracketed on a uniform
    grid and refined with Brent's method.  No root exists on [0, pi/2]
    because the jerk bracket is positive there.  Expanding the exact
    acceleration about BDC shows that BDC stops being a local minimum when
    :math:`3\lambda^2 + 3\lambda - 1 > 0`, i.e. for
    :math:`\lambda > (\sqrt{21}-3)/6 \approx 0.2638`, slightly above the 1/4
    threshold of the two-term form.
    """
    rod_ratio = float(_checked_rod_ratio(rod_ratio))
    scale = float(crank_radius_m) * float(angular_velocity_rad_s) ** 2
    grid_rad = np.linspace(0.5 * np.pi, np.pi, 2049)
    bracket_values = _jerk_bracket(grid_rad, rod_ratio)
    candidates = [float(np.pi)]
    sign_change = np.nonzero(np.signbit(bracket_values[:-1]) != np.signbit(bracket_values[1:]))[0]
    for index in sign_change:
        left, right = grid_rad[index], grid_rad[index + 1]
        if bracket_values[index + 1] == 0.0:
            candidates.append(float(right))
            continue
        root = brentq(
            lambda angle: float(_jerk_bracket(angle, rod_ratio)),
            left,
            right,
            xtol=1e-300,
            rtol=4.0 * np.finfo(float).eps,
            maxiter=200,
        )
        candidates.append(float(root))
    candidate_angles = np.asarray(candidates)
    shape_values = piston_acceleration_exact_m_s2(candidate_angles, 1.0, rod_ratio, 1.0)
    best = first_argmin(shape_values)
    return scale * float(shape_values[best]), float(candidate_angles[best])
