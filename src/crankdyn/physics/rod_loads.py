r"""Loads of the central crank-slider with the connecting rod as a rigid body (Newton-Euler).

The textbook (Poda 2007 §3.2, eq. 30-35) splits the rod into two point masses, at the small end
(reciprocating) and at the big end (rotating). That split keeps the mass and the centre of mass but
not the moment of inertia I_G; with I_G known the loads follow exactly from the equations of motion
of the piston and of the rod (derived here; the rod_dynamics stage reports the same couple).

Frame: crank axis O at the origin, cylinder axis +y towards the piston, x to the side the crank pin
passes first (alpha from TDC in the direction of rotation). Crank pin B = R (sin a, cos a), piston pin
A = (0, R cos a + L cos b), sin b = lambda sin a; the rod vector A - B = L (-sin b, cos b), its angle
phi = pi/2 + b, so its angular acceleration is d^2 b/dt^2; centre of mass G = B + (l_R/L)(A - B).

Unknowns: the force F_A of the piston on the rod, F_B of the crank pin on the rod, the wall force N on
the piston (along x). Piston (mass m_p, gas force -F_g along y): m_p a_A = (0, -F_g) - F_A + (N, 0).
Rod: m a_G = F_A + F_B; about G: I_G phi'' = (A - G) x F_A + (B - G) x F_B, which with F_B = m a_G - F_A
becomes I_G phi'' = (A - B) x F_A + (B - G) x m a_G. Hence

    A_y = -F_g - m_p y_A'',   A_x = ((A-B)_x A_y + (B-G) x m a_G - I_G phi'') / (A-B)_y,   N = A_x.

The load on the crank pin is -F_B; its tangential part T (positive in the direction of rotation,
unit (cos a, -sin a)) and radial part Z (positive towards the shaft axis, unit -(sin a, cos a)) are
those of the textbook. For I_G = m l_R (L - l_R) and the rod's mass split as the textbook does, the
result is the textbook's: T = p1 sin(a+b)/cos b, Z = p1 cos(a+b)/cos b, N = p1 tan b, plus the
centrifugal force of the big-end mass in Z.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class RodLoads(NamedTuple):
    """Exact loads [N] over the crank angle (arrays)."""

    crank_pin_tangential_N: np.ndarray  # T of the rod's force on the crank pin, + with the rotation
    crank_pin_radial_N: (
        np.ndarray
    )  # Z of it, + towards the shaft axis (the rod's whole inertia included)
    wrist_pin_axial_N: (
        np.ndarray
    )  # force of the piston on the rod at the piston pin along the axis, + towards the crank
    wrist_pin_lateral_N: (
        np.ndarray
    )  # ... across the axis, + along x (equal to the wall force on the piston)
    side_N: (
        np.ndarray
    )  # N, the cylinder wall's force on the piston (+ along x: the sign of p1 tan b)
    rod_axial_N: (
        np.ndarray
    )  # K, the crank pin's force along the rod at the big end, + compressing the rod


def exact_rod_loads_N(
    crank_angle_rad,
    crank_radius_m,
    rod_length_m,
    rod_cm_from_big_end_m,
    rod_mass_kg,
    rod_moment_of_inertia_kg_m2,
    piston_mass_kg,
    angular_velocity_rad_s,
    gas_force_N,
    rod_angle_rad,
    rod_angular_acceleration_rad_s2,
    piston_acceleration_m_s2,
) -> RodLoads:
    """Loads of a central crank-slider with a rigid rod (mass m, centre l_R from the big end, I_G).

    Parameters are SI: crank angle a [rad] from TDC, R, L, l_R [m], masses [kg], I_G [kg m^2],
    omega [rad/s] (constant), F_g the gas force on the piston [N] (+ towards the crank), the rod
    angle b [rad] and its angular acceleration [rad/s^2] (b = arcsin(lambda sin a)), and the piston
    acceleration j = d^2 s/dt^2 [m/s^2] of the displacement s from TDC towards the crank.
    Equations: module docstring.
    """
    a = np.asarray(crank_angle_rad, dtype=float)
    b = np.asarray(rod_angle_rad, dtype=float)
    R, L, lr, w = (
        float(crank_radius_m),
        float(rod_length_m),
        float(rod_cm_from_big_end_m),
        float(angular_velocity_rad_s),
    )
    m, inertia, mp = float(rod_mass_kg), float(rod_moment_of_inertia_kg_m2), float(piston_mass_kg)
    bx, by = R * np.sin(a), R * np.cos(a)
    dx, dy = -L * np.sin(b), L * np.cos(b)  # A - B
    f = lr / L
    ya_dd = -np.asarray(piston_acceleration_m_s2, dtype=float)  # y_A = const - s
    abx, aby = -w * w * bx, -w * w * by  # a_B, constant omega
    agx, agy = abx + f * (0.0 - abx), aby + f * (ya_dd - aby)
    gbx, gby = -f * dx, -f * dy  # B - G
    a_y = -np.asarray(gas_force_N, dtype=float) - mp * ya_dd
    moment = gbx * m * agy - gby * m * agx  # (B - G) x m a_G
    a_x = (
        dx * a_y + moment - inertia * np.asarray(rod_angular_acceleration_rad_s2, dtype=float)
    ) / dy
    fbx, fby = m * agx - a_x, m * agy - a_y  # F_B on the rod; the crank pin carries -F_B
    tangential = -(fbx * np.cos(a) - fby * np.sin(a))
    radial = fbx * np.sin(a) + fby * np.cos(a)
    ux, uy = dx / L, dy / L
    return RodLoads(
        crank_pin_tangential_N=tangential,
        crank_pin_radial_N=radial,
        wrist_pin_axial_N=-a_y,
        wrist_pin_lateral_N=a_x,
        side_N=a_x,
        rod_axial_N=fbx * ux + fby * uy,
    )
