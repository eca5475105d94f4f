"""The flywheel by the energy method: excess work, cyclic irregularity, inertia and rim size.

Conventions
-----------
* Torques are sampled on a uniform crank-angle grid covering one cycle without its end
  point (as everywhere in crankdyn); angles in rad, torques in N m, inertias in kg m^2.
* The *excess work* (textbook "надлишкова робота", Khurmi & Gupta's "maximum fluctuation
  of energy") is the largest swing of the cumulative work of the output torque above its
  mean: ``Delta L = max W - min W`` with ``W(alpha) = int_0^alpha (M - M_mean) d alpha``.
* The *cyclic irregularity* (coefficient of fluctuation of speed) is
  ``delta = (omega_max - omega_min) / omega_m`` with ``omega_m = (omega_max + omega_min) / 2``.

Derivation of the energy method
-------------------------------
With a constant moment of inertia J of everything that turns with the crankshaft, the
kinetic energy changes by the work of the unbalanced torque, so between the angles of the
largest and smallest speed ``1/2 J (omega_max^2 - omega_min^2) = Delta L``. Factoring,
``1/2 J (omega_max + omega_min)(omega_max - omega_min) = J omega_m^2 delta``; hence

    delta = Delta L / (J omega_m^2),      J_required = Delta L / (delta omega_m^2).

The torque diagram used is the output torque *including* the inertia torque of the
reciprocating masses at the mean speed; that is how the variable part of the reduced
inertia of the crank mechanisms enters (see :mod:`crankdyn.physics.speed_fluctuation`,
where the inertia torque at constant speed is shown to be ``-1/2 J'(alpha) omega^2``).
The constant part, the cycle mean of the reduced inertia ``J(alpha)``, is the engine's own
inertia and is subtracted from ``J_required`` to get the flywheel.

References
----------
Khurmi, R. S., & Gupta, J. K. (2005). *Theory of Machines*, ch. 16 "Turning moment diagrams
and flywheel", eqs. for the maximum fluctuation of energy ``Delta E = I omega^2 C_s``.
Timoshenko, S. (1956). *Strength of Materials*, part II (rotating rings): hoop stress ``sigma = rho v^2``
of a thin rotating ring.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .extrema import first_argmax, first_argmin
from .scalar_search import brentq

__all__ = [
    "ExcessWork",
    "excess_work",
    "cyclic_irregularity",
    "excess_work_at_speed_J",
    "required_inertia_kg_m2",
    "RimDesign",
    "thin_rim_mass_kg",
    "rim_design",
    "rim_hoop_stress_Pa",
    "largest_rim_mean_diameter_m",
]


class ExcessWork(NamedTuple):
    """Result of :func:`excess_work`."""

    cumulative_J: np.ndarray  # W(alpha_k) on the grid, W(alpha_0) = 0
    excess_work_J: float  # Delta L = max W - min W
    max_index: int  # grid index of max W (largest speed)
    min_index: int  # grid index of min W (smallest speed)
    mean_torque_Nm: float


def excess_work(crank_angle_rad, torque_Nm) -> ExcessWork:
    r"""Cumulative work of the torque above its mean, and the excess work.

    Parameters
    ----------
    crank_angle_rad : array_like, shape (N,)
        Uniform grid over one cycle, end point excluded [rad].
    torque_Nm : array_like, shape (N,)
        Output torque on that grid [N m].

    Returns
    -------
    ExcessWork
        ``cumulative_J`` is :math:`W(\alpha)=\int_0^\alpha (M-\bar M)\,d\alpha` by the
        trapezoidal rule (exactly periodic: the closing step back to the first point returns
        W to 0, because the cycle mean is the periodic trapezoid mean), ``excess_work_J`` is
        :math:`\Delta L=\max W-\min W` [J].

    Notes
    -----
    Khurmi & Gupta (2005), ch. 16 (maximum fluctuation of energy as the largest difference of
    the areas of the turning-moment diagram above the mean line); the cumulative-integral form
    is the same statement without graphical areas.
    """
    angle = np.asarray(crank_angle_rad, dtype=float)
    torque = np.asarray(torque_Nm, dtype=float)
    if angle.ndim != 1 or angle.shape != torque.shape or angle.size < 3:
        raise ValueError(
            "crank_angle_rad and torque_Nm must be 1-D arrays of the same length (>= 3)"
        )
    step = float(np.mean(np.diff(angle)))
    mean = float(np.mean(torque))
    excess = torque - mean
    increments = 0.5 * (excess[:-1] + excess[1:]) * step
    cumulative = np.concatenate([[0.0], np.cumsum(increments)])
    i_max, i_min = first_argmax(cumulative), first_argmin(cumulative)
    return ExcessWork(cumulative, float(cumulative[i_max] - cumulative[i_min]), i_max, i_min, mean)


def cyclic_irregularity(excess_work_J, inertia_kg_m2, angular_velocity_rad_s):
    r"""Cyclic irregularity :math:`\delta=\Delta L/(J\omega_m^2)` of a constant inertia.

    Parameters
    ----------
    excess_work_J : float
        :math:`\Delta L` [J].
    inertia_kg_m2 : float
        Total moment of inertia J reduced to the crankshaft [kg m^2]; must be > 0.
    angular_velocity_rad_s : float
        Mean angular velocity :math:`\omega_m` [rad/s].

    Returns
    -------
    float
        :math:`\delta` [-] (module docstring: derivation).
    """
    if inertia_kg_m2 <= 0:
        raise ValueError("inertia_kg_m2 must be positive")
    return excess_work_J / (inertia_kg_m2 * angular_velocity_rad_s**2)


#: Elements of one block of :func:`excess_work_at_speed_J` (8 MiB of floats).
_BLOCK_ELEMENTS = 1 << 20


def excess_work_at_speed_J(crank_angle_rad, gas_torque_Nm, inertia_torque_Nm, speed_fraction):
    r"""Excess work at other speeds with the same cylinder pressures.

    .. math:: M(\alpha) = M_g(\alpha) + k^2 M_j(\alpha), \qquad \Delta L = \max W - \min W

    The reciprocating masses' inertia torque :math:`M_j = -\tfrac12 J'(\alpha)\,\omega^2`
    scales with the square of the speed (:math:`k = \omega/\omega_n`), the gas torque
    :math:`M_g` stays as it is: the same cylinder pressures at the lower speed, which a real
    engine's change with its load and filling. W as :func:`excess_work` integrates it.

    Parameters
    ----------
    crank_angle_rad : array_like, shape (N,)
        Uniform crank-angle grid over one cycle [rad].
    gas_torque_Nm : array_like, shape (N,)
        Torque of the gas forces alone on that grid [N m].
    inertia_torque_Nm : array_like, shape (N,)
        Inertia torque of the reciprocating masses at the reference speed :math:`\omega_n` [N m].
    speed_fraction : float or array_like, shape (K,)
        :math:`k = \omega/\omega_n` [-].

    Returns
    -------
    float or numpy.ndarray, shape (K,)
        :math:`\Delta L` at each :math:`k\,\omega_n` [J].
    """
    k = np.asarray(speed_fraction, dtype=float)
    angle = np.asarray(crank_angle_rad, dtype=float)
    gas = np.asarray(gas_torque_Nm, dtype=float)
    inertia = np.asarray(inertia_torque_Nm, dtype=float)
    if k.ndim == 0:
        return excess_work(angle, gas + k**2 * inertia).excess_work_J
    # excess_work's trapezoid, row by row: one cumulative sum for a block of speeds, the blocks
    # bounded (a 0.01° grid has 72 000 angles)
    step = float(np.mean(np.diff(angle)))
    rows = max(1, _BLOCK_ELEMENTS // max(gas.size, 1))
    out = np.empty(k.shape)
    for start in range(0, k.size, rows):
        torque = gas + np.multiply.outer(k[start : start + rows] ** 2, inertia)
        excess = torque - torque.mean(axis=1, keepdims=True)
        cumulative = np.cumsum(0.5 * (excess[:, :-1] + excess[:, 1:]) * step, axis=1)
        # W starts at 0: the extremes with it
        top = np.maximum(cumulative.max(axis=1), 0.0)
        bottom = np.minimum(cumulative.min(axis=1), 0.0)
        out[start : start + rows] = top - bottom
    return out


def required_inertia_kg_m2(excess_work_J, irregularity, angular_velocity_rad_s):
    r"""Total inertia for a required irregularity: :math:`J=\Delta L/(\delta\omega_m^2)` [kg m^2]."""
    if irregularity <= 0:
        raise ValueError("irregularity must be positive")
    return excess_work_J / (irregularity * angular_velocity_rad_s**2)


class RimDesign(NamedTuple):
    """A rectangular flywheel rim (a hollow cylinder) of given mean diameter."""

    mean_diameter_m: float
    width_m: float  # axial width b
    thickness_m: float  # radial thickness h
    outer_diameter_m: float
    inner_diameter_m: float
    mass_kg: float
    thin_rim_mass_kg: float  # 4 J / D_m^2, the textbook's thin-rim estimate
    inertia_kg_m2: float


def thin_rim_mass_kg(inertia_kg_m2, mean_diameter_m):
    r"""Mass of a thin rim of mean diameter :math:`D_m` with inertia J: :math:`m = 4J/D_m^2` [kg].

    Notes
    -----
    A thin ring of radius :math:`D_m/2` has :math:`J = m D_m^2/4` (Khurmi & Gupta 2005,
    ch. 16: the rim carries the flywheel's inertia, hub and arms neglected).
    """
    return 4.0 * inertia_kg_m2 / mean_diameter_m**2


def rim_design(inertia_kg_m2, mean_diameter_m, density_kg_m3, width_m=None) -> RimDesign:
    r"""Dimensions of a rectangular rim that carries the inertia J exactly.

    Parameters
    ----------
    inertia_kg_m2 : float
        Inertia the rim must have [kg m^2], > 0.
    mean_diameter_m : float
        Chosen mean diameter :math:`D_m` [m].
    density_kg_m3 : float
        Rim material density :math:`\rho` [kg/m^3].
    width_m : float, optional
        Axial width b [m]; default: a square section, b = h.

    Returns
    -------
    RimDesign

    Notes
    -----
    Derived: a hollow cylinder with radii :math:`r_{o,i}=(D_m\pm h)/2` has
    :math:`J=\tfrac{\pi}{2}\rho b(r_o^4-r_i^4)` and, since :math:`r_o^2-r_i^2=D_m h` and
    :math:`r_o^2+r_i^2=(D_m^2+h^2)/2`,

    .. math:: J = \frac{m\,(D_m^2+h^2)}{4},\qquad m=\pi\rho\,b\,D_m h,

    which tends to the thin-rim :math:`m D_m^2/4` for :math:`h\ll D_m`. For given b (or
    b = h) J grows monotonically with h, so the root is unique; it is found by Brent's method.
    The thickness must stay below :math:`D_m` (the rim cannot fill its own bore).
    """
    if inertia_kg_m2 <= 0 or mean_diameter_m <= 0 or density_kg_m3 <= 0:
        raise ValueError("inertia, mean diameter and density must be positive")
    D, rho = float(mean_diameter_m), float(density_kg_m3)

    def inertia_of(h: float) -> float:
        b = h if width_m is None else float(width_m)
        return math.pi * rho * b * D * h * (D * D + h * h) / 4.0

    if inertia_of(D) < inertia_kg_m2:
        raise ValueError(
            f"no rim of mean diameter {D:g} m reaches {inertia_kg_m2:g} kg m^2 "
            f"(even a rim as thick as its mean diameter has {inertia_of(D):.3g} kg m^2)"
        )
    h = brentq(lambda x: inertia_of(x) - inertia_kg_m2, 0.0, D, xtol=1e-15, rtol=1e-13)
    b = h if width_m is None else float(width_m)
    mass = math.pi * rho * b * D * h
    return RimDesign(D, b, h, D + h, D - h, mass, thin_rim_mass_kg(inertia_kg_m2, D), inertia_of(h))


#: Mean diameters tried between the allowed outer diameter and a twentieth of it when the largest
#: rim that fits is looked for (a geometric grid: 1 % apart).
_RIM_SEARCH_POINTS = 300


def largest_rim_mean_diameter_m(
    inertia_kg_m2, density_kg_m3, outer_diameter_max_m, width_m=None
) -> float | None:
    r"""The largest mean diameter :math:`D_m` [m] of a rim that carries the inertia J
    (:func:`rim_design`) with its outer diameter :math:`D_m + h` at most ``outer_diameter_max_m``;
    None when no rim of this density does.

    Parameters
    ----------
    inertia_kg_m2 : float
        Inertia the rim must have [kg m^2], > 0.
    density_kg_m3 : float
        Rim material density [kg/m^3], > 0.
    outer_diameter_max_m : float
        The largest outer diameter allowed [m], e.g. :math:`2 v_{max}/\omega` for a peripheral
        speed :math:`v_{max}` at the angular velocity :math:`\omega`.
    width_m : float, optional
        Axial width b [m]; default: a square section, b = h.

    Notes
    -----
    A smaller mean diameter needs a thicker rim for the same J (:math:`h \propto D_m^{-3/2}`
    for a square thin rim), so the outer diameter :math:`D_m + h(D_m)` falls with :math:`D_m` only
    down to a minimum, below which the thickness outgrows the diameter saved. The largest root of
    :math:`D_m + h(D_m) = D_{max}` is bracketed on a geometric grid from :math:`D_{max}` down to
    :math:`D_{max}/20` and found by Brent's method; none on the grid means no rim fits.
    """
    if inertia_kg_m2 <= 0 or density_kg_m3 <= 0 or outer_diameter_max_m <= 0:
        raise ValueError("inertia, density and the largest outer diameter must be positive")
    top = float(outer_diameter_max_m)

    def excess_m(mean_diameter_m: float) -> float:
        """Outer diameter over the allowed one, m (positive where no rim of this D_m fits)."""
        try:
            rim = rim_design(inertia_kg_m2, mean_diameter_m, density_kg_m3, width_m)
        except ValueError:  # no rim of this mean diameter reaches J
            return top
        return rim.outer_diameter_m - top

    above = top  # D_m = D_max: its rim's outer diameter exceeds D_max by h > 0
    for mean in top * np.geomspace(1.0, 0.05, _RIM_SEARCH_POINTS)[1:]:
        if excess_m(float(mean)) <= 0.0:
            return brentq(excess_m, float(mean), above, xtol=1e-12, rtol=1e-12)
        above = float(mean)
    return None


def rim_hoop_stress_Pa(density_kg_m3, rim_speed_m_s):
    r"""Hoop stress of a thin rotating ring, :math:`\sigma=\rho v^2` [Pa].

    Notes
    -----
    Timoshenko (1956), part II, rotating rings; v is the peripheral speed of the ring (at the mean
    diameter for the mean stress, at the outer diameter for an upper bound).
    """
    return density_kg_m3 * rim_speed_m_s**2
