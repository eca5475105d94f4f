"""Kinematics of the offset (desaxial) crank-slider mechanism.

The cylinder axis is displaced by the pin offset ``e`` from the crankshaft axis. With
``e = 0`` every function here reduces to the central crank-slider of
:mod:`crankdyn.physics.kinematics`.

Conventions
-----------
* Frame of :mod:`crankdyn.physics.kinematics`: origin on the crankshaft axis, ``z`` along
  the cylinder direction towards the head, ``x`` lateral and positive in the direction in
  which the crank pin moves at the top. The cylinder axis is the line ``x = e``; a positive
  offset puts it on the side the crank pin passes during the outward (expansion) stroke,
  the usual choice that lowers the side force while the gas pressure is high.
* ``phi`` is the crank angle measured from the direction of the cylinder axis (the
  crank pin is B = R (sin phi, cos phi)); ``alpha = phi - phi_TDC`` is the crank angle
  measured from TDC, the angle of the tables and of the other stages.
* ``lambda = R/L``, ``k = e/L``; the rod angle satisfies ``sin beta = lambda sin phi - k``
  and is positive when the rod leans in the direction of rotation.
* Piston displacement s is measured from TDC towards the crankshaft.

References
----------
Derived for crankdyn from the loop closure of the linkage; the textbook (Poda 2007, §2,
eqs. 9-11 and 26) treats the central mechanism only, and these relations reduce to its
exact forms for e = 0. The tests compare them with a numerical solution of the linkage
(root finding for the position, finite differences for the derivatives).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = [
    "OffsetGeometry",
    "check_offset",
    "dead_centres",
    "rod_angle_rad",
    "piston_pin_height_m",
    "piston_displacement_m",
    "piston_velocity_m_s",
    "piston_acceleration_m_s2",
    "rod_angular_velocity_rad_s",
    "rod_angular_acceleration_rad_s2",
]


def _as_float_array(value):
    return np.asarray(value, dtype=float)


def check_offset(crank_radius_m, rod_length_m, offset_m):
    r"""Raise ValueError unless the crank can turn a full revolution.

    Notes
    -----
    The crank pin comes up to R + |e| off the cylinder axis (at phi = -/+ 90 deg), so the
    rod reaches it at every angle only if R + |e| < L, i.e. |e| < L - R. At |e| = L - R
    the linkage locks at BDC (crank and rod folded at right angles to the axis).
    """
    if not (0.0 < crank_radius_m < rod_length_m):
        raise ValueError("need 0 < R < L")
    if abs(offset_m) >= rod_length_m - crank_radius_m:
        raise ValueError(
            f"|e| must be < L - R = {(rod_length_m - crank_radius_m) * 1e3:g} mm "
            "for the crank to turn a full revolution"
        )


class OffsetGeometry(NamedTuple):
    """Dead centres and stroke of an offset crank-slider (all SI, angles in rad).

    Attributes
    ----------
    tdc_angle_rad : float
        phi_TDC = arcsin(e / (L + R)): crank angle from the cylinder axis at TDC.
    bdc_angle_rad : float
        phi_BDC = pi + arcsin(e / (L - R)).
    bdc_after_tdc_rad : float
        Crank angle from TDC to BDC, phi_BDC - phi_TDC (> pi for e > 0).
    tdc_height_m, bdc_height_m : float
        Piston-pin heights sqrt((L + R)^2 - e^2) and sqrt((L - R)^2 - e^2).
    stroke_m : float
        Piston stroke S = difference of the two heights (> 2R for e != 0).
    stroke_time_ratio : float
        Quick-return ratio: crank angle of the TDC->BDC stroke over that of the BDC->TDC stroke.
    """

    tdc_angle_rad: float
    bdc_angle_rad: float
    bdc_after_tdc_rad: float
    tdc_height_m: float
    bdc_height_m: float
    stroke_m: float
    stroke_time_ratio: float


def dead_centres(crank_radius_m, rod_length_m, offset_m) -> OffsetGeometry:
    r"""Dead-centre angles, piston-pin heights, stroke and quick-return ratio.

    Parameters
    ----------
    crank_radius_m : float
        Crank radius R [m].
    rod_length_m : float
        Rod length L [m].
    offset_m : float
        Pin offset e [m] (signed, see the module conventions); |e| < L - R.

    Returns
    -------
    OffsetGeometry

    Notes
    -----
    Derived: the piston is at a dead centre when crank and rod are in line, extended
    (TDC, |OA| = L + R) or folded (BDC, |OA| = L - R). A lies on x = e, so
    :math:`z_{TDC} = \sqrt{(L+R)^2-e^2}`, :math:`z_{BDC} = \sqrt{(L-R)^2-e^2}`; the crank
    points along OA at TDC (sin phi = e/(L+R)) and against it at BDC
    (sin phi = -e/(L-R), cos phi < 0). Because z_TDC - z_BDC grows with e^2, the stroke
    exceeds 2R for any offset.
    """
    R, L, e = float(crank_radius_m), float(rod_length_m), float(offset_m)
    check_offset(R, L, e)
    tdc = float(np.arcsin(e / (L + R)))
    bdc = float(np.pi + np.arcsin(e / (L - R)))
    z_tdc = float(np.sqrt((L + R - e) * (L + R + e)))
    z_bdc = float(np.sqrt((L - R - e) * (L - R + e)))
    out = bdc - tdc
    return OffsetGeometry(tdc, bdc, out, z_tdc, z_bdc, z_tdc - z_bdc, out / (2.0 * np.pi - out))


def _sin_cos_beta(phi, ratio, offset_ratio):
    sin_beta = ratio * np.sin(phi) - offset_ratio
    cos_beta = np.sqrt((1.0 - sin_beta) * (1.0 + sin_beta))
    return sin_beta, cos_beta


def rod_angle_rad(crank_angle_from_axis_rad, rod_ratio, offset_ratio):
    r"""Rod angle beta.

    Parameters
    ----------
    crank_angle_from_axis_rad : array_like
        phi, crank angle from the direction of the cylinder axis [rad].
    rod_ratio : float
        lambda = R/L.
    offset_ratio : float
        k = e/L.

    Returns
    -------
    numpy.ndarray
        beta [rad] from :math:`\sin\beta = \lambda\sin\varphi - k`.

    Notes
    -----
    Derived: the lateral distance between crank pin and piston pin is
    R sin phi - e = L sin beta. With k = 0 this is Poda eq. (26).
    """
    return np.arcsin(
        float(rod_ratio) * np.sin(_as_float_array(crank_angle_from_axis_rad)) - float(offset_ratio)
    )


def piston_pin_height_m(crank_angle_from_axis_rad, crank_radius_m, rod_ratio, offset_ratio):
    r"""Height z_A of the piston pin above the crankshaft axis.

    Notes
    -----
    :math:`z_A = R\cos\varphi + L\cos\beta` (loop closure).
    """
    phi = _as_float_array(crank_angle_from_axis_rad)
    R = float(crank_radius_m)
    _, cos_beta = _sin_cos_beta(phi, float(rod_ratio), float(offset_ratio))
    return R * np.cos(phi) + (R / float(rod_ratio)) * cos_beta


def piston_displacement_m(crank_angle_rad, crank_radius_m, rod_ratio, offset_ratio):
    r"""Exact piston displacement from TDC.

    Parameters
    ----------
    crank_angle_rad : array_like
        alpha, crank angle from TDC [rad].
    crank_radius_m : float
        R [m].
    rod_ratio : float
        lambda = R/L (0 < lambda < 1).
    offset_ratio : float
        k = e/L, |k| < 1 - lambda.

    Returns
    -------
    numpy.ndarray
        :math:`s = z_{TDC} - R\cos\varphi - L\cos\beta`, phi = alpha + phi_TDC [m].

    Notes
    -----
    Derived. For k = 0, phi = alpha and z_TDC = L + R, so s = R[(1 - cos alpha) +
    (1 - cos beta)/lambda], the textbook's exact form.
    """
    R, lam, k = float(crank_radius_m), float(rod_ratio), float(offset_ratio)
    geometry = dead_centres(R, R / lam, k * R / lam)
    phi = _as_float_array(crank_angle_rad) + geometry.tdc_angle_rad
    # TDC is the highest point, so s >= 0; near TDC the difference of two nearly equal heights
    # can come out as -1e-17 m by round-off (seen at |e| close to L - R), which later checks reject.
    return np.maximum(geometry.tdc_height_m - piston_pin_height_m(phi, R, lam, k), 0.0)


def piston_velocity_m_s(
    crank_angle_rad, crank_radius_m, rod_ratio, offset_ratio, angular_velocity_rad_s
):
    r"""Exact piston velocity (positive away from TDC).

    Returns
    -------
    numpy.ndarray
        :math:`v = R\omega\,\sin(\varphi+\beta)/\cos\beta` [m/s], phi = alpha + phi_TDC.

    Notes
    -----
    Derived: d/dt of the displacement with
    :math:`\dot\beta = \omega\lambda\cos\varphi/\cos\beta` (from sin beta = lambda sin phi - k,
    whose derivative does not contain k). The textbook's central form
    (Poda eq. 10 before truncation) holds with the angle from the cylinder axis.
    """
    R, lam, k = float(crank_radius_m), float(rod_ratio), float(offset_ratio)
    phi = _as_float_array(crank_angle_rad) + dead_centres(R, R / lam, k * R / lam).tdc_angle_rad
    sin_beta, cos_beta = _sin_cos_beta(phi, lam, k)
    # sin(phi + beta)/cos(beta) = sin(phi) + cos(phi) tan(beta)
    return R * float(angular_velocity_rad_s) * (np.sin(phi) + np.cos(phi) * sin_beta / cos_beta)


def piston_acceleration_m_s2(
    crank_angle_rad, crank_radius_m, rod_ratio, offset_ratio, angular_velocity_rad_s
):
    r"""Exact piston acceleration at constant crank speed (positive towards the shaft).

    Returns
    -------
    numpy.ndarray
        :math:`j = R\omega^2[\cos(\varphi+\beta)/\cos\beta + \lambda\cos^2\varphi/\cos^3\beta]`
        [m/s^2].

    Notes
    -----
    Derived: d/dt of :func:`piston_velocity_m_s`; the form is that of the central
    mechanism with alpha replaced by phi, and beta from the offset relation.
    """
    R, lam, k = float(crank_radius_m), float(rod_ratio), float(offset_ratio)
    phi = _as_float_array(crank_angle_rad) + dead_centres(R, R / lam, k * R / lam).tdc_angle_rad
    sin_beta, cos_beta = _sin_cos_beta(phi, lam, k)
    omega = float(angular_velocity_rad_s)
    cos_phi = np.cos(phi)
    shape = cos_phi - np.sin(phi) * sin_beta / cos_beta + lam * cos_phi**2 / cos_beta**3
    return R * omega * omega * shape


def rod_angular_velocity_rad_s(
    crank_angle_rad, crank_radius_m, rod_ratio, offset_ratio, angular_velocity_rad_s
):
    r"""Rod angular velocity :math:`\dot\beta = \omega\lambda\cos\varphi/\cos\beta` [rad/s]."""
    R, lam, k = float(crank_radius_m), float(rod_ratio), float(offset_ratio)
    phi = _as_float_array(crank_angle_rad) + dead_centres(R, R / lam, k * R / lam).tdc_angle_rad
    _, cos_beta = _sin_cos_beta(phi, lam, k)
    return float(angular_velocity_rad_s) * lam * np.cos(phi) / cos_beta


def rod_angular_acceleration_rad_s2(
    crank_angle_rad, crank_radius_m, rod_ratio, offset_ratio, angular_velocity_rad_s
):
    r"""Rod angular acceleration at constant crank speed [rad/s^2].

    Notes
    -----
    Derived: d/dt of :func:`rod_angular_velocity_rad_s`,

    .. math::
        \ddot\beta = \omega^2\lambda\,\frac{\lambda\cos^2\varphi\sin\beta - \sin\varphi\cos^2\beta}
                     {\cos^3\beta},

    which for k = 0 (sin beta = lambda sin phi) is the central
    :math:`-\omega^2\lambda(1-\lambda^2)\sin\varphi/\cos^3\beta`.
    """
    R, lam, k = float(crank_radius_m), float(rod_ratio), float(offset_ratio)
    phi = _as_float_array(crank_angle_rad) + dead_centres(R, R / lam, k * R / lam).tdc_angle_rad
    sin_beta, cos_beta = _sin_cos_beta(phi, lam, k)
    omega = float(angular_velocity_rad_s)
    return (
        omega
        * omega
        * lam
        * (lam * np.cos(phi) ** 2 * sin_beta - np.sin(phi) * cos_beta**2)
        / cos_beta**3
    )
