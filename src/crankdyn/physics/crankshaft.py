"""Loads on the crankshaft of a multi-crank engine (Poda 2007 §4.3-4.4, tables B.3-B.4)."""

from __future__ import annotations

import math

import numpy as np

from .extrema import first_argmax, first_argmin


def running_torques(tangential_by_crank):
    """Running (accumulated) torques, as specific tangential forces, eq. (44)-(45).

    Parameters
    ----------
    tangential_by_crank : array, shape (cranks, N)
        t_i of every crank, cranks ordered from the free end, Pa.

    Returns
    -------
    pin : array (cranks, N)
        t_w,i = t_k,(i-1) + 0.5 t_i, twisting crank pin i, Pa (t_k,0 = 0 at the free end).
    journal : array (cranks, N)
        t_k,i = t_k,(i-1) + t_i, twisting the main journal after crank i, Pa; the last row
        is the engine's output torque divided by R*F_p (eq. 46).
    """
    t = np.asarray(tangential_by_crank, dtype=float)
    journal = np.cumsum(t, axis=0)
    pin = journal - 0.5 * t
    return pin, journal


def resultant_Pa(tangential_Pa, radial_Pa, centrifugal_Pa):
    """q = sqrt((z + c)^2 + t^2), eq. (36), Pa."""
    return np.hypot(np.asarray(radial_Pa) + centrifugal_Pa, tangential_Pa)


def torque_non_uniformity(torque_Nm) -> float:
    """(M_max - M_min) / |M_mean| of the output torque (dimensionless; the mean's magnitude: a
    driven machine's mean torque is negative, its swing as large); inf if the mean is 0."""
    torque = np.asarray(torque_Nm, dtype=float)
    mean = abs(float(np.mean(torque)))
    return float((torque.max() - torque.min()) / mean) if mean != 0 else float("inf")


def indicated_power_kW(indicated_work_J: float, cylinders: int, strokes: int, rpm: float) -> float:
    """N_i = W_i i n / (60 tau/2) / 1000 [kW]: the indicated work per cylinder and cycle [J] of
    ``cylinders`` cylinders, a cycle every ``strokes``/2 revolutions at ``rpm``."""
    return indicated_work_J * cylinders * rpm / 60.0 / (strokes / 2) / 1000.0


def torque_from_power_Nm(
    indicated_work_J: float, cylinders: int, strokes: int, rpm: float
) -> float:
    """M_i = N_i/ω = 3·10⁴ N_i / (π n) [N·m] with N_i in kW and n in rpm (Poda 2007 eq. (47)
    rounds the constant 30000/π = 9549.3 up to 9555, 0.06 % more)."""
    return 30000.0 / math.pi * indicated_power_kW(indicated_work_J, cylinders, strokes, rpm) / rpm


def effective_output(
    indicated_power_W: float,
    effective_power_W: float,
    angular_velocity_rad_s: float,
    pumping_power_W: float = 0.0,
) -> dict:
    """The rated effective power N_e [W] (the thermal calculation's) against the indicated power
    N_i [W] the indicator diagram gives.

    Parameters
    ----------
    indicated_power_W : float
        N_i of the diagram's whole indicated work, its pumping strokes included, W.
    effective_power_W : float
        N_e, W.
    angular_velocity_rad_s : float
        ω, rad/s.
    pumping_power_W : float, default 0
        N_p, the part of N_i the gas-exchange strokes make, W (negative where they take work:
        a naturally aspirated four-stroke; zero for a two-stroke).

    Returns
    -------
    dict
        ``mechanical_efficiency``: η_m = N_e/(N_i − N_p), the mechanical efficiency as the
        thermal calculation defines it, whose indicated power leaves the pumping strokes out and
        whose mechanical losses take them in (Kolchin & Demidov; Heywood 1988, §2.4, the "gross"
        indicated work); None for N_i − N_p ≤ 0 (a motored trace).
        ``mean_effective_torque_Nm``: M_e = N_e/ω, N·m. ``pumping_power_W``: N_p as given.
    """
    gross = indicated_power_W - pumping_power_W
    return {
        "effective_power_W": effective_power_W,
        "indicated_power_W": indicated_power_W,
        "pumping_power_W": pumping_power_W,
        "mechanical_efficiency": effective_power_W / gross if gross > 0 else None,
        "mean_effective_torque_Nm": effective_power_W / angular_velocity_rad_s,
    }


def dangerous_combinations(radial_Pa, tangential_Pa, resultant, journal_torque_Pa):
    """Table B.4: for each crank, the grid index where z, t, q and the journal torque t_k peak.

    Returns a list per crank of dicts {"Z": i, "Zmin": i, "T": i, "Tmin": i, "Q": i, "M": i}
    (indices on the grid). The largest positive z (towards the shaft: gas load) and t, the largest
    q and the largest |t_k| are the textbook's criteria; the least z (the inertia forces pulling
    the crank outwards) and t (the most negative) complete the cycle of stress that the crank's
    fatigue check takes (Kolchin and Demidov 2002, the crank pin's and web's stress ranges). The journal torque of an even-firing engine repeats within
    the cycle, so |t_k| peaks alike at several angles: of those, the one where the crank's own
    load q is largest (the combination the crank's strength is checked for).
    """
    out = []
    for k in range(np.shape(radial_Pa)[0]):
        torque = np.abs(np.asarray(journal_torque_Pa[k], dtype=float))
        # peaks equal but for rounding: relative 1e-9 of the largest
        alike = np.flatnonzero(torque >= torque.max() * (1.0 - 1e-9))
        loads = np.asarray(resultant[k], dtype=float)[alike]
        out.append(
            {
                "Z": first_argmax(radial_Pa[k]),
                "Zmin": first_argmin(radial_Pa[k]),
                "T": first_argmax(tangential_Pa[k]),
                "Tmin": first_argmin(tangential_Pa[k]),
                "Q": first_argmax(resultant[k]),
                "M": int(alike[first_argmax(loads)]),
            }
        )
    return out
