"""The free forces and moments as rotating vectors per order, and their check in the time domain
(:mod:`crankdyn.physics.balancing`)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from crankdyn.physics import balancing as bal
from crankdyn.plugin.contracts import (
    Counterweights,
)

CHECK_SAMPLES = 720  # shaft angles per revolution in the time-domain check


CHECK_TOLERANCE = (
    1e-9  # relative agreement required between the vector method and the time-domain sum
)


NEGLIGIBLE = 1e-9  # a coefficient below this counts as balanced


ROUND_OFF = 1e-12  # relative size below which a computed value is round-off and shown as 0


def first_star_repeats(phases_deg: Sequence[float], orders: Sequence[int]) -> dict[int, int]:
    """{order ν: +1 or −1} of the orders whose star of cylinder phases repeats the first order's
    (νξ_i ≡ ξ_i, mod 360°, at every cylinder) or mirrors it (νξ_i ≡ −ξ_i): with the cylinders in
    one plane and the same arms, such an order's moment coefficient is the first order's (an
    in-line five's orders IV and VI, an in-line three's II)."""
    first = np.exp(1j * np.radians(np.asarray(phases_deg, dtype=float)))
    repeats = {}
    for order in orders:
        star = first**order
        for sign in (1, -1):
            if np.allclose(star, first if sign > 0 else np.conj(first), rtol=0, atol=1e-9):
                repeats[int(order)] = sign
                break
    return repeats


def _c(value, scale: float = 1.0) -> complex:
    """A complex amplitude with round-off (below ROUND_OFF * scale) set to zero, part by part."""
    value = complex(value)
    limit = ROUND_OFF * scale
    return complex(
        0.0 if abs(value.real) < limit else value.real,
        0.0 if abs(value.imag) < limit else value.imag,
    )


def _r(value: float, scale: float = 1.0) -> float:
    value = float(value)
    return 0.0 if abs(value) < ROUND_OFF * scale else value


def _deg(value: complex) -> float:
    return math.degrees(math.atan2(value.imag, value.real)) % 360.0


def _vector(value: complex, scale: float) -> dict:
    """A planar vector as JSON: magnitude (times ``scale``), direction from the vertical, x, y."""
    return {
        "magnitude": abs(value) * scale,
        "angle_deg": _deg(value) if abs(value) > 1e-12 else 0.0,
        "x": value.imag * scale,
        "y": value.real * scale,
    }


def _amplitude(n: int, C: float, C_I: float, harmonics) -> float:
    """The force amplitude of order n, N: C for the rotating masses (n = 0), |a_n| C_I otherwise."""
    return C if n == 0 else abs(harmonics[n]) * C_I


def order_vectors(g, models: dict, include_orders, C: float, C_I: float, harmonics, a):
    """The vector method, order by order: (coefficients, absolute values, per-order entries).

    For each order n (0 = rotating masses) the forward and backward rotating parts of the
    resultant force and moment, their largest values as coefficients of the order's amplitude
    (moments in units of the cylinder spacing ``a``, m, or of ``a`` itself when it is None) and
    in N / N·m, and the hodographs.
    """
    coefficients, absolute, orders = {}, {}, []
    for n, model in models.items():
        if n not in include_orders and n != 0:
            continue
        amplitude = _amplitude(n, C, C_I, harmonics)
        name = "C" if n == 0 else "P" + bal.roman(n)
        z = g.cylinders
        model = bal.OrderModel(
            model.order,
            _c(model.force_forward, z),
            _c(model.force_backward, z),
            _c(model.moment_forward, z),
            _c(model.moment_backward, z),
        )
        force_coef, moment_coef = _r(model.force_max, z), _r(model.moment_max, z)
        coefficients["sum_" + name] = force_coef
        coefficients["M_" + name] = moment_coef
        absolute["sum_" + name + "_N"] = force_coef * amplitude
        absolute["M_" + name + "_Nm"] = moment_coef * amplitude * a if a is not None else None
        s = C if n == 0 else harmonics[n] * C_I
        # a complex harmonic (an offset crank-slider) turns its counter-rotating part back
        s_back = np.conj(s)
        hf = bal.hodograph(
            _c(model.force_forward) * s,
            _c(model.force_backward) * s_back,
            model.speed,
            tolerance=NEGLIGIBLE * amplitude * g.cylinders,
        )
        hm = bal.hodograph(
            _c(model.moment_forward) * s,
            _c(model.moment_backward) * s_back,
            model.speed,
            tolerance=NEGLIGIBLE * amplitude * g.cylinders,
        )
        unit_m = a if a is not None else 1.0
        orders.append(
            {
                "order": n,
                "name": name,
                "speed": model.speed,
                "amplitude_N": amplitude,
                "force_coefficient": force_coef,
                "moment_coefficient": moment_coef,
                "force_max_N": force_coef * amplitude,
                "moment_max_Nm": moment_coef * amplitude * a if a is not None else None,
                "force_forward": _vector(_c(model.force_forward) * s, 1.0),
                "force_backward": _vector(_c(model.force_backward) * s_back, 1.0),
                "moment_forward": _vector(_c(model.moment_forward) * s, unit_m),
                "moment_backward": _vector(_c(model.moment_backward) * s_back, unit_m),
                "force_hodograph": _hodograph_json(hf, 1.0),
                "moment_hodograph": _hodograph_json(hm, unit_m),
            }
        )
    return coefficients, absolute, orders


def bay_model_of(layout, g) -> dict | None:
    """The textbook's bay models (V, W, Y, X, radial): F, P and K, Z of one bay; None for one cylinder a bay."""
    if layout.cylinders_per_bay <= 1:
        return None
    bay = g.cylinder_bay == 0
    axes = g.cylinder_axis_rad[bay]
    # each cylinder's own force (a slave cylinder's lighter mass and other harmonics), if unlike
    f1, p1 = bal.bay_vectors(axes, 1, g.weights_for(1)[bay])
    k2, z2 = bal.bay_vectors(axes, 2, g.weights_for(2)[bay])
    hod1 = bal.hodograph(
        f1, p1, 1
    )  # R = F e^{i alpha} + P e^{-i alpha}, alpha from the bay's vertical
    hod2 = bal.hodograph(k2, z2, 2)
    nb = len(axes)
    return {
        "F": _signed(_c(f1, nb)),
        "P": _signed(_c(p1, nb)),
        "K": _signed(_c(k2, nb)),
        "Z": _signed(_c(z2, nb)),
        "A_I": _r(hod1.x_amplitude, nb),
        "B_I": _r(hod1.y_amplitude, nb),
        "A_II": _r(hod2.x_amplitude, nb),
        "B_II": _r(hod2.y_amplitude, nb),
        "bank_axes_deg": [round(math.degrees(x), 9) for x in axes],
    }


def time_domain_check(g, masses, harmonics, all_orders, theta, spacing, a):
    """The vector method against the direct sum of every cylinder's inertia forces over one turn.

    Returns (force N, moment N·m of the direct sum as complex y + i x, force scale, moment scale,
    the check's record); the deviations are relative to the scales.
    """
    C, C_I = masses.centrifugal_N, masses.first_order_N
    f_td, m_td = bal.time_domain_sum(g, masses, theta, spacing)
    f_vec, m_vec = bal.vector_method_sum(g, masses, theta, all_orders, spacing, harmonics)
    scale_F = g.cranks * C + g.cylinders * C_I * float(np.sum(np.abs(harmonics[all_orders])))
    scale_M = scale_F * spacing * max(float(np.max(np.abs(g.cylinder_position))), 0.5)
    check = {
        "orders": all_orders,
        "samples": CHECK_SAMPLES,
        "force_deviation_relative": float(np.max(np.abs(f_td - f_vec)) / scale_F),
        "moment_deviation_relative": float(np.max(np.abs(m_td - m_vec)) / scale_M),
        "force_scale_N": scale_F,
        "moment_scale_Nm": scale_M if a is not None else None,
    }
    check["agrees"] = bool(
        max(check["force_deviation_relative"], check["moment_deviation_relative"]) < CHECK_TOLERANCE
    )
    return f_td, m_td, scale_F, scale_M, check


def _fitted(
    counterweights: list[dict],
    omega_rad_s: float,
    radius_m: float,
    shafts: Sequence[dict] = (),
    shaft_radius_m: float = 0.0,
) -> Counterweights:
    """The counterweights of results.json as the bearings and flywheel stages take them (forces
    at the speed; the moment of inertia of masses m at the radius r, Σ m r·r), with the balance
    shafts' masses reduced to the crankshaft's speed (Σ m r·r·n², n the shaft's speed ratio)."""
    return Counterweights(
        crank=np.array([cw["crank"] - 1 for cw in counterweights], dtype=int),
        centrifugal_N=np.array([cw["mass_radius_kg_m"] * omega_rad_s**2 for cw in counterweights]),
        angle_from_crank_rad=np.radians([cw["angle_from_crank_deg"] for cw in counterweights]),
        moment_of_inertia_kg_m2=float(sum(cw["mass_radius_kg_m"] for cw in counterweights))
        * radius_m,
        balance_shaft_inertia_kg_m2=float(
            sum(
                mass["mass_radius_kg_m"] * shaft_radius_m * shaft["speed_ratio"] ** 2
                for shaft in shafts
                for mass in shaft["masses"]
            )
        ),
        balance_shafts=len(shafts),
    )


def _signed(value: complex) -> float | dict:
    """The textbook's signed value when the vector lies on the vertical, else magnitude and angle."""
    if abs(value.imag) <= 1e-12 * max(abs(value), 1.0):
        return float(value.real)
    return {"magnitude": abs(value), "angle_deg": _deg(value)}


def _hodograph_json(h: bal.Hodograph, scale: float) -> dict:
    size = max(h.semi_major, 1e-300)
    return {
        "semi_major": h.semi_major * scale,
        "semi_minor": _r(h.semi_minor, size) * scale,
        "major_axis_deg": h.major_axis_deg,
        "x_amplitude": _r(h.x_amplitude, size) * scale,
        "y_amplitude": _r(h.y_amplitude, size) * scale,
        "sense": h.sense,
        "theta_at_max_deg": h.theta_at_max_deg,
    }
