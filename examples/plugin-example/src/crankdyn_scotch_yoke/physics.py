"""Kinematics of the Scotch yoke: pure numpy functions, SI units.

Crank angle alpha from TDC in the direction of rotation; piston displacement s from TDC
towards the crankshaft; constant crank speed omega.
"""

from __future__ import annotations

import numpy as np


def piston_displacement_m(crank_angle_rad, crank_radius_m):
    r"""Piston displacement from TDC, :math:`s = R(1 - \cos\alpha)` [m].

    Parameters
    ----------
    crank_angle_rad : array_like
        alpha [rad].
    crank_radius_m : float
        R [m].

    Notes
    -----
    The slot is perpendicular to the cylinder axis, so the yoke follows the projection of
    the crank pin on the axis: the central crank-slider's displacement with lambda -> 0.
    """
    return float(crank_radius_m) * (1.0 - np.cos(np.asarray(crank_angle_rad, dtype=float)))


def piston_velocity_m_s(crank_angle_rad, crank_radius_m, angular_velocity_rad_s):
    r""":math:`v = R\omega\sin\alpha` [m/s] (d/dt of the displacement)."""
    return (
        float(crank_radius_m)
        * float(angular_velocity_rad_s)
        * np.sin(np.asarray(crank_angle_rad, dtype=float))
    )


def piston_acceleration_m_s2(crank_angle_rad, crank_radius_m, angular_velocity_rad_s):
    r""":math:`j = R\omega^2\cos\alpha` [m/s^2] (d/dt of the velocity at constant omega)."""
    omega = float(angular_velocity_rad_s)
    return float(crank_radius_m) * omega * omega * np.cos(np.asarray(crank_angle_rad, dtype=float))
