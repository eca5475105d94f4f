"""Forces in the crank-slider mechanism of one cylinder.

Specific forces ("pressures") are forces divided by the piston area and are
expressed in Pa.  Sign conventions follow Poda (2007), fig. 4:

* forces along the cylinder axis (gas, inertia, total ``p1``) are positive
  when they push the piston towards the crankshaft;
* the tangential force ``t`` is positive in the direction of rotation;
* the radial force ``z`` is positive from the crank pin towards the
  crankshaft axis, so the centrifugal force ``c`` of the rotating masses is
  negative;
* the rod angle ``beta`` is positive when the rod leans in the direction of
  rotation (see :mod:`crankdyn.physics.kinematics`).

All functions are pure, accept scalars or numpy arrays and return numpy arrays
or numpy scalars.  SI units throughout.

References
----------
Poda, V. B. (2007). Dynamic calculation and balancing of piston internal
combustion engines (in Ukrainian). Kharkiv: KhAI.  Section 3, eqs.
(17)-(25) and (34)-(36).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = [
    "RodForces",
    "piston_area_m2",
    "rod_mass_split_kg",
    "inertia_pressure_Pa",
    "inertia_pressure_first_order_Pa",
    "inertia_pressure_second_order_Pa",
    "rod_force_components",
    "centrifugal_pressure_Pa",
    "resultant_crank_pin_pressure_Pa",
    "crank_torque_Nm",
    "indicated_work_from_torque_J",
    "cycle_mean",
]


def _as_float_array(value):
    return np.asarray(value, dtype=float)


class RodForces(NamedTuple):
    """Specific forces derived from the total axial force, all in Pa.

    Attributes
    ----------
    side_Pa : numpy.ndarray or float
        Side (normal) force of the piston on the cylinder wall, n, eq. (22).
    rod_Pa : numpy.ndarray or float
        Force along the rod axis, k, eq. (23); positive in compression.
    tangential_Pa : numpy.ndarray or float
        Tangential force on the crank pin, t, eq. (24); positive in the
        direction of rotation.
    radial_Pa : numpy.ndarray or float
        Radial force on the crank pin, z, eq. (25); positive towards the
        crankshaft axis.
    """

    side_Pa: np.ndarray | float
    rod_Pa: np.ndarray | float
    tangential_Pa: np.ndarray | float
    radial_Pa: np.ndarray | float


def piston_area_m2(bore_m):
    r"""Piston crown area projected on the cylinder cross-section.

    Parameters
    ----------
    bore_m : float or array_like
        Cylinder bore D [m].

    Returns
    -------
    numpy.ndarray or float
        Piston area F = pi D^2 / 4 [m^2].

    Notes
    -----
    Poda (2007), section 3 (the factor 4 / (pi D^2) of eqs. (18)-(20), (35)).
    """
    bore_m = _as_float_array(bore_m)
    return 0.25 * np.pi * bore_m * bore_m


def rod_mass_split_kg(rod_mass_kg, rod_length_m, centre_of_mass_from_big_end_m):
    r"""Two-mass static equivalent of the connecting rod.

    Parameters
    ----------
    rod_mass_kg : float or array_like
        Total rod mass m_rod including big-end bolts and nuts [kg].
    rod_length_m : float or array_like
        Centre-to-centre rod length L [m].
    centre_of_mass_from_big_end_m : float or array_like
        Distance l_R of the rod centre of mass from the big-end (crank-pin)
        centre [m]; Poda quotes l_R = (0.18...0.4) L.

    Returns
    -------
    reciprocating_kg : numpy.ndarray or float
        Mass placed at the piston pin, m_rod l_R / L [kg].
    rotating_kg : numpy.ndarray or float
        Mass placed at the crank pin, m_rod (L - l_R) / L [kg].

    Notes
    -----
    Poda (2007) eq. (17).  The split keeps the total mass and the position
    of the centre of mass (static equivalence); it does not preserve the
    rod's moment of inertia.
    """
    rod_mass_kg = _as_float_array(rod_mass_kg)
    rod_length_m = _as_float_array(rod_length_m)
    centre = _as_float_array(centre_of_mass_from_big_end_m)
    if np.any(centre < 0.0) or np.any(centre > rod_length_m):
        raise ValueError("centre_of_mass_from_big_end_m must lie between 0 and rod_length_m")
    reciprocating_kg = rod_mass_kg * centre / rod_length_m
    rotating_kg = rod_mass_kg * (rod_length_m - centre) / rod_length_m
    return reciprocating_kg, rotating_kg


def inertia_pressure_Pa(reciprocating_mass_kg, piston_acceleration_m_s2, piston_area_m2):
    r"""Specific inertia force of the reciprocating masses.

    Parameters
    ----------
    reciprocating_mass_kg : float or array_like
        Reciprocating mass m_s (piston set plus rod share) [kg].
    piston_acceleration_m_s2 : float or array_like
        Piston acceleration j [m/s^2], positive towards the crankshaft
        (exact or two-term, see :mod:`crankdyn.physics.kinematics`).
    piston_area_m2 : float or array_like
        Piston area F [m^2].

    Returns
    -------
    numpy.ndarray or float
        p_j = -m_s j / F [Pa]; negative (pulling the piston away from the
        shaft) around TDC.

    Notes
    -----
    Poda (2007) eq. (18).
    """
    return (
        -_as_float_array(reciprocating_mass_kg)
        * _as_float_array(piston_acceleration_m_s2)
        / _as_float_array(piston_area_m2)
    )


def inertia_pressure_first_order_Pa(
    reciprocating_mass_kg, crank_angle_rad, crank_radius_m, angular_velocity_rad_s, piston_area_m2
):
    r"""First-order (crank-frequency) part of the specific inertia force.

    Parameters
    ----------
    reciprocating_mass_kg : float or array_like
        Reciprocating mass m_s [kg].
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    angular_velocity_rad_s : float or array_like
        Crankshaft angular velocity omega [rad/s].
    piston_area_m2 : float or array_like
        Piston area F [m^2].

    Returns
    -------
    numpy.ndarray or float
        p_jI = -m_s R omega^2 cos(alpha) / F [Pa].

    Notes
    -----
    Poda (2007) eq. (19), with omega = pi n / 30.
    """
    omega = _as_float_array(angular_velocity_rad_s)
    amplitude = (
        _as_float_array(reciprocating_mass_kg)
        * _as_float_array(crank_radius_m)
        * omega
        * omega
        / _as_float_array(piston_area_m2)
    )
    return -amplitude * np.cos(_as_float_array(crank_angle_rad))


def inertia_pressure_second_order_Pa(
    reciprocating_mass_kg,
    crank_angle_rad,
    crank_radius_m,
    rod_ratio,
    angular_velocity_rad_s,
    piston_area_m2,
):
    r"""Second-order (twice crank frequency) part of the specific inertia force.

    Parameters
    ----------
    reciprocating_mass_kg : float or array_like
        Reciprocating mass m_s [kg].
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    crank_radius_m : float or array_like
        Crank radius R [m].
    rod_ratio : float or array_like
        lambda = R / L [-].
    angular_velocity_rad_s : float or array_like
        Crankshaft angular velocity omega [rad/s].
    piston_area_m2 : float or array_like
        Piston area F [m^2].

    Returns
    -------
    numpy.ndarray or float
        p_jII = -m_s R omega^2 lambda cos(2 alpha) / F [Pa].

    Notes
    -----
    Poda (2007) eq. (20).  The argument order mirrors
    :func:`inertia_pressure_first_order_Pa` with ``rod_ratio`` inserted after
    the crank radius, as in the kinematics functions.  The sum of the first
    and second orders equals eq. (18) evaluated with the two-term
    acceleration, eq. (11).
    """
    omega = _as_float_array(angular_velocity_rad_s)
    amplitude = (
        _as_float_array(reciprocating_mass_kg)
        * _as_float_array(crank_radius_m)
        * omega
        * omega
        * _as_float_array(rod_ratio)
        / _as_float_array(piston_area_m2)
    )
    return -amplitude * np.cos(2.0 * _as_float_array(crank_angle_rad))


def rod_force_components(total_pressure_Pa, crank_angle_rad, rod_angle_rad):
    r"""Resolve the total axial specific force through the connecting rod.

    Parameters
    ----------
    total_pressure_Pa : float or array_like
        Total specific force on the piston along the cylinder axis,
        p1 = p_gas + p_j [Pa], positive towards the crankshaft.
    crank_angle_rad : float or array_like
        Crank angle alpha from TDC [rad].
    rod_angle_rad : float or array_like
        Rod angle beta [rad] (e.g. from
        :func:`crankdyn.physics.kinematics.rod_angle_rad`).

    Returns
    -------
    RodForces
        Named tuple ``(side_Pa, rod_Pa, tangential_Pa, radial_Pa)``, all in Pa:
        n = p1 tan(beta), k = p1 / cos(beta),
        t = p1 sin(alpha + beta) / cos(beta),
        z = p1 cos(alpha + beta) / cos(beta).

    Notes
    -----
    Poda (2007) eqs. (22)-(25).  By construction t^2 + z^2 = k^2 and
    n = k sin(beta).
    """
    total = _as_float_array(total_pressure_Pa)
    crank_angle_rad = _as_float_array(crank_angle_rad)
    rod_angle_rad = _as_float_array(rod_angle_rad)
    rod_Pa = total / np.cos(rod_angle_rad)
    crank_rod_angle = crank_angle_rad + rod_angle_rad
    return RodForces(
        side_Pa=total * np.tan(rod_angle_rad),
        rod_Pa=rod_Pa,
        tangential_Pa=rod_Pa * np.sin(crank_rod_angle),
        radial_Pa=rod_Pa * np.cos(crank_rod_angle),
    )


def centrifugal_pressure_Pa(
    rotating_mass_kg, crank_radius_m, angular_velocity_rad_s, piston_area_m2
):
    r"""Specific centrifugal force of the masses rotating with the crank pin.

    Parameters
    ----------
    rotating_mass_kg : float or array_like
        Rotating mass reduced to the crank-pin radius [kg] (rod share plus
        crank pin plus the reduced masses of both webs, without
        counterweights).
    crank_radius_m : float or array_like
        Crank radius R [m].
    angular_velocity_rad_s : float or array_like
        Crankshaft angular velocity omega [rad/s].
    piston_area_m2 : float or array_like
        Piston area F [m^2].

    Returns
    -------
    numpy.ndarray or float
        c = -omega^2 R m_R / F [Pa]; negative because it points away from the
        shaft axis while ``z`` is counted towards it.

    Notes
    -----
    Poda (2007) eq. (35).
    """
    omega = _as_float_array(angular_velocity_rad_s)
    return (
        -omega
        * omega
        * _as_float_array(crank_radius_m)
        * _as_float_array(rotating_mass_kg)
        / _as_float_array(piston_area_m2)
    )


def resultant_crank_pin_pressure_Pa(tangential_Pa, radial_Pa, centrifugal_Pa):
    r"""Magnitude of the resultant specific force on the crank pin.

    Parameters
    ----------
    tangential_Pa : float or array_like
        Tangential specific force t [Pa].
    radial_Pa : float or array_like
        Radial specific force z [Pa], positive towards the shaft axis.
    centrifugal_Pa : float or array_like
        Centrifugal specific force c [Pa] in the same radial convention
        (normally negative).

    Returns
    -------
    numpy.ndarray or float
        q = sqrt((z + c)^2 + t^2) [Pa], non-negative.

    Notes
    -----
    Poda (2007) eq. (36).
    """
    radial_total = _as_float_array(radial_Pa) + _as_float_array(centrifugal_Pa)
    return np.hypot(radial_total, _as_float_array(tangential_Pa))


def crank_torque_Nm(tangential_Pa, crank_radius_m, piston_area_m2):
    r"""Torque produced on one crank throw by the tangential force.

    Parameters
    ----------
    tangential_Pa : float or array_like
        Tangential specific force t [Pa].
    crank_radius_m : float or array_like
        Crank radius R [m].
    piston_area_m2 : float or array_like
        Piston area F [m^2].

    Returns
    -------
    numpy.ndarray or float
        M = t R F [N m], positive when driving the shaft in its direction of
        rotation.

    Notes
    -----
    Poda (2007) eq. (34).
    """
    return (
        _as_float_array(tangential_Pa)
        * _as_float_array(crank_radius_m)
        * _as_float_array(piston_area_m2)
    )


def _periodic_step_rad(crank_angle_rad):
    crank_angle_rad = _as_float_array(crank_angle_rad)
    if crank_angle_rad.ndim != 1 or crank_angle_rad.size < 2:
        raise ValueError("crank_angle_rad must be a 1-D grid with at least two points")
    steps = np.diff(crank_angle_rad)
    step = float(np.mean(steps))
    # A non-uniform grid would silently turn the rectangle rule into a
    # first-order method, so reject it instead.
    if step <= 0.0 or not np.allclose(steps, step, rtol=1e-9, atol=0.0):
        raise ValueError("crank_angle_rad must be uniformly spaced and increasing")
    return step


def indicated_work_from_torque_J(crank_angle_rad, torque_Nm):
    r"""Work done by a periodic crank torque over one full cycle.

    Parameters
    ----------
    crank_angle_rad : array_like, shape (N,)
        Uniform, increasing crank-angle grid that covers exactly one cycle
        (4 pi for a four-stroke, 2 pi for a two-stroke engine) WITHOUT the
        duplicated end point, i.e. ``alpha_k = alpha_0 + k * period / N`` for
        ``k = 0 .. N-1`` [rad].
    torque_Nm : array_like, shape (N,) or (..., N)
        Torque sampled on that grid [N m]; the last axis is integrated.

    Returns
    -------
    numpy.ndarray or float
        Work per cycle, :math:`\oint M\,d\alpha` [J].  With ``M = t R F`` this
        equals the indicated cycle work :math:`\oint p\,dV` for the gas
        pressure part and zero for the inertia part.

    Notes
    -----
    Derived: rectangle rule on a periodic grid, which coincides with the
    periodic trapezoid rule and converges spectrally for smooth periodic
    integrands.  Including the end point (``alpha_N = alpha_0 + period``)
    would count that sample twice and bias the result.
    """
    step = _periodic_step_rad(crank_angle_rad)
    torque_Nm = _as_float_array(torque_Nm)
    if torque_Nm.shape[-1] != np.size(crank_angle_rad):
        raise ValueError("torque_Nm must have the grid length along its last axis")
    return np.sum(torque_Nm, axis=-1) * step


def cycle_mean(values):
    r"""Mean of a periodic quantity sampled on a uniform periodic grid.

    Parameters
    ----------
    values : array_like, shape (N,) or (..., N)
        Samples on a uniform grid covering one cycle without the duplicated
        end point (see :func:`indicated_work_from_torque_J`); any unit.

    Returns
    -------
    numpy.ndarray or float
        Cycle-averaged value in the unit of ``values``, taken along the last
        axis.

    Notes
    -----
    Derived: periodic trapezoid rule divided by the period, which reduces to
    the arithmetic mean of the samples.  For the crank torque this gives the
    mean indicated torque, ``indicated_work / period``.
    """
    return np.mean(_as_float_array(values), axis=-1)
