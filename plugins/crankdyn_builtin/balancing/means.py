"""The balancing means: counterweights and balance shafts sized for the free forces and moments,
what they leave, and the remedy for what is left."""

from __future__ import annotations

import math

import numpy as np

from crankdyn.physics import balancing as bal

from .vectors import CHECK_TOLERANCE, NEGLIGIBLE, _amplitude


def means_records(g, means, r_cw: float, r_sh: float, a):
    """Counterweights and balance shafts as results.json records (masses, kg; angles, deg; positions, m)."""
    centre = 0.5 * (g.cranks - 1)

    def position_m(z: float):
        """Position from crank 1 along the shaft (m); 0 for a one-crank engine even without a."""
        if g.cranks == 1:
            return 0.0
        return (z + centre) * a if a is not None else None

    counterweights = []
    for cw in means.counterweights:
        k = int(round(cw.position + centre))
        crank_dir = math.degrees(g.crank_direction_rad[k]) % 360.0
        counterweights.append(
            {
                "crank": k + 1,
                "mass_radius_kg_m": cw.mass_radius_kg_m,
                "mass_kg": cw.mass_radius_kg_m / r_cw,
                "mass_per_web_kg": 0.5 * cw.mass_radius_kg_m / r_cw,
                "angle_deg": cw.phase_deg,
                "angle_from_crank_deg": (cw.phase_deg - crank_dir) % 360.0,
                "position_m": position_m(cw.position),
            }
        )
    shafts = []
    for speed, shaft_masses in sorted(means.shafts.items(), key=lambda kv: (abs(kv[0]), -kv[0])):
        shafts.append(
            {
                "speed_ratio": speed,
                "order": abs(speed),
                "spacing_m": (
                    abs(shaft_masses[-1].position - shaft_masses[0].position) * a
                    if a is not None and len(shaft_masses) > 1
                    else None
                ),
                "masses": [
                    {
                        "mass_radius_kg_m": sm.mass_radius_kg_m,
                        "mass_kg": sm.mass_radius_kg_m / r_sh,
                        "phase_deg": sm.phase_deg,
                        "position_m": position_m(sm.position),
                        "end": "free"
                        if sm.position < -1e-12
                        else ("power" if sm.position > 1e-12 else "middle"),
                    }
                    for sm in shaft_masses
                ],
            }
        )
    return counterweights, shafts


def add_shaft_loads(shafts: list[dict], angular_velocity_rad_s: float) -> None:
    """Each balance shaft's own force (N) and moment about its middle (N·m): the rotating
    resultant of its masses' centrifugal forces m·r·(|n|ω)², which is the part of the engine's
    order n that the shaft cancels (what counterweights alone would leave of it)."""
    for shaft in shafts:
        speed = abs(shaft["speed_ratio"]) * angular_velocity_rad_s
        vectors = [
            m["mass_radius_kg_m"] * speed**2 * np.exp(1j * math.radians(m["phase_deg"]))
            for m in shaft["masses"]
        ]
        positions = [m["position_m"] for m in shaft["masses"]]
        shaft["force_N"] = float(abs(sum(vectors)))
        shaft["moment_Nm"] = None
        if None not in positions:
            middle = float(np.mean(positions))
            arms = [z - middle for z in positions]
            shaft["moment_Nm"] = float(abs(sum(v * z for v, z in zip(vectors, arms, strict=True))))


def residual_after_means(
    g,
    masses,
    harmonics,
    means,
    theta,
    w,
    spacing,
    f_td,
    m_td,
    all_orders,
    balance_orders,
    scale_F,
    scale_M,
    a,
    left=(),
):
    """What is left with the balancing means fitted, against the orders left unbalanced and the
    rotating parts ``left`` (signed speeds, as :func:`crankdyn.physics.balancing.design_means`).

    Returns (residual force N, residual moment N·m as complex arrays, the record); it "vanishes"
    when the residual equals the vector sum of the unbalanced orders within CHECK_TOLERANCE.
    """
    f_means, m_means = means.forces(theta, w, spacing)
    unbalanced_orders = [n for n in all_orders if n not in balance_orders]
    f_left, m_left = bal.vector_method_sum(
        g, masses, theta, unbalanced_orders, spacing, harmonics, rotating=False
    )
    for speed in left:
        model = bal.scaled(
            bal.reciprocating_model(g, abs(speed)), harmonics[abs(speed)] * masses.first_order_N
        )
        force, moment = (
            (model.force_forward, model.moment_forward)
            if speed > 0
            else (model.force_backward, model.moment_backward)
        )
        turn = np.exp(1j * speed * theta)
        f_left = f_left + force * turn
        m_left = m_left + moment * turn * spacing
    residual_F, residual_M = f_td + f_means, m_td + m_means
    residual = {
        "balanced_orders": sorted(balance_orders),
        "force_max_N": float(np.max(np.abs(residual_F))),
        "moment_max_Nm": float(np.max(np.abs(residual_M))) if a is not None else None,
        "force_deviation_relative": float(np.max(np.abs(residual_F - f_left)) / scale_F),
        "moment_deviation_relative": float(np.max(np.abs(residual_M - m_left)) / scale_M),
    }
    residual["vanishes"] = bool(
        max(residual["force_deviation_relative"], residual["moment_deviation_relative"])
        < CHECK_TOLERANCE
    )
    return residual_F, residual_M, residual


def remedy(
    order: int,
    balanced: bool,
    forward: bool,
    backward: bool,
    balance_orders,
    first_order_forward: str,
) -> str:
    """How an order's force or moment is dealt with: self, counterweights, shaft_forward/backward or none."""
    if balanced:
        return "self"
    if order == 0:
        return "counterweights"
    if order in balance_orders:
        parts = []
        if forward:
            parts.append(
                "counterweights"
                if order == 1 and first_order_forward == "crankshaft"
                else "shaft_forward"
            )
        if backward:
            parts.append("shaft_backward")
        return "+".join(parts) or "none"
    return "none"


def remedy_summary(orders, g, C, C_I, harmonics, opts, left=()) -> list[dict]:
    """One row per order and kind (force, moment): its coefficient, whether it is balanced, the
    remedy (a rotating part in ``left``, a signed speed, is left, not given a means)."""
    summary = []
    for entry in orders:
        n = entry["order"]
        limit = NEGLIGIBLE * _amplitude(n, C, C_I, harmonics) * g.cylinders
        for kind in ("force", "moment"):
            coef = entry[f"{kind}_coefficient"]
            balanced = coef < NEGLIGIBLE * g.cylinders
            forward_part = entry[f"{kind}_forward"]["magnitude"] > limit
            backward_part = entry[f"{kind}_backward"]["magnitude"] > limit
            forward, backward = forward_part and n not in left, backward_part and -n not in left
            summary.append(
                {
                    "quantity": ("sum_" if kind == "force" else "M_") + entry["name"],
                    "order": n,
                    "coefficient": coef,
                    "balanced": bool(balanced),
                    "remedy": _with_parts_left(
                        remedy(
                            n,
                            balanced,
                            forward,
                            backward,
                            opts.balance_orders,
                            opts.first_order_forward,
                        ),
                        forward_part and n in left,
                        backward_part and -n in left,
                    ),
                }
            )
    return summary


def _with_parts_left(remedy_text: str, forward_left: bool, backward_left: bool) -> str:
    """A remedy with the rotating parts its means leave named too ("counterweights+left_backward"):
    the row of an order whose other part the means take does not read as balanced whole."""
    if remedy_text == "none" or not (forward_left or backward_left):
        return remedy_text
    return "+".join(
        [remedy_text]
        + (["left_forward"] if forward_left else [])
        + (["left_backward"] if backward_left else [])
    )
