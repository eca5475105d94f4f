"""Balancing: free forces and moments, counterweights, balance shafts, firing-order explorer (Poda 2007 §6).

The physics is in :mod:`crankdyn.physics.balancing` (vector models, time-domain sums, sizing of
the balancing means) and :mod:`crankdyn.physics.firing_explorer`; this module reads the scene,
assembles the results and renders the section.
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import partial
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from markupsafe import Markup
from pydantic import AfterValidator, BaseModel, ConfigDict

from crankdyn.contracts import (
    COUNTERWEIGHTS,
    ENGINE_TORQUE,
    KINEMATICS,
    ArticulatedOptions,
    Counterweights,
)
from crankdyn.errors import Problem, SceneError
from crankdyn.physics import balancing as bal
from crankdyn.physics import firing_explorer as fe
from crankdyn.physics import forces as phys
from crankdyn.plugin_types import Stage, StageOutput, Symbol
from crankdyn.report.figures import hide_axes, new_figure
from crankdyn.scene import options
from crankdyn.scene import quantity as _quantity
from crankdyn.scene_inputs import engine_layout, rotating_mass_per_crank_kg
from crankdyn_builtin.balancing.worked import worked_balancing

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

ALLOWED_ORDERS = (1, 2, 4, 6, 8, 10, 12)
CHECK_SAMPLES = 720  # shaft angles per revolution in the time-domain check
CHECK_TOLERANCE = 1e-9  # relative agreement required between the vector method and the time-domain sum
NEGLIGIBLE = 1e-9  # a coefficient below this counts as balanced

#: The scene table of the articulated rods, read for the mass rotating with a crank pin.
ARTICULATED = "articulated"


def _orders(values: list[int]) -> list[int]:
    bad = [v for v in values if v not in ALLOWED_ORDERS]
    if bad:
        raise ValueError(f"orders {bad} are not allowed: the exact piston acceleration has the first order and the "
                         f"even orders only; allowed: {', '.join(map(str, ALLOWED_ORDERS))}")
    if len(set(values)) != len(values):
        raise ValueError("each order once")
    return sorted(values)


def _include(values: list[int]) -> list[int]:
    values = _orders(values)
    if 1 not in values or 2 not in values:
        raise ValueError("must include the first and second orders (1, 2)")
    return values


def _top(value: int) -> int:
    if not 1 <= value <= 200:
        raise ValueError("must be a whole number from 1 to 200")
    return value


class BalancingOptions(BaseModel):
    """The [balancing] table."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    counterweight_radius: _quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    balance_shaft_radius: _quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    balance_shaft_spacing: _quantity("length", gt=0, le=20.0, unit="mm", scale=1e-3) | None = None
    include_orders: Annotated[list[int], AfterValidator(_include)] = [1, 2, 4, 6]
    # None: the first order for one cylinder (a counterweight and one shaft, as single-cylinder
    # engines are built; the second order's two Lanchester shafts are rarely worth it there), the
    # first and second for more (:func:`balance_orders_for`)
    balance_orders: Annotated[list[int], AfterValidator(_orders)] | None = None
    counterweights: Literal["ends", "every_crank"] = "ends"
    first_order_forward: Literal["crankshaft", "shaft"] = "crankshaft"
    explore: bool = False
    explore_top: Annotated[int, AfterValidator(_top)] = 10


def balance_orders_for(scene, opts: BalancingOptions) -> list[int]:
    """The orders to balance: the scene's ``[balancing] balance_orders``, else [1] for a
    single-cylinder engine and [1, 2] for more cylinders."""
    if opts.balance_orders is not None:
        return list(opts.balance_orders)
    return [1] if scene.engine.cylinders == 1 else [1, 2]


#: The orders an offset crank-slider's tables show unless the scene names them.
OFFSET_ORDERS = [1, 2, 3, 4, 6]

#: The mechanisms whose piston motion is a crank-slider's (``extra``: ``rod_ratio``, with an
#: offset ``offset_m`` and ``crank_angle_at_tdc_rad``): the vector models take their exact
#: acceleration's Fourier series.
CRANK_SLIDERS = ("crank_slider", "offset_crank_slider")


def applies(scene) -> str | None:
    if scene.masses is None:
        return "the scene has no [masses]"
    if scene.engine.mechanism not in CRANK_SLIDERS:
        return "the vector models of balancing are built for crank-slider mechanisms (central or offset)"
    if scene.engine.mechanism != "crank_slider" and scene.engine.rod_type == "articulated":
        return "articulated rods are built on a central crank-slider's master rod"
    return None


ROUND_OFF = 1e-12  # relative size below which a computed value is round-off and shown as 0


def _c(value, scale: float = 1.0) -> complex:
    """A complex amplitude with round-off (below ROUND_OFF * scale) set to zero, part by part."""
    value = complex(value)
    limit = ROUND_OFF * scale
    return complex(0.0 if abs(value.real) < limit else value.real, 0.0 if abs(value.imag) < limit else value.imag)


def _r(value: float, scale: float = 1.0) -> float:
    value = float(value)
    return 0.0 if abs(value) < ROUND_OFF * scale else value


def _deg(value: complex) -> float:
    return math.degrees(math.atan2(value.imag, value.real)) % 360.0


def _vector(value: complex, scale: float) -> dict:
    """A planar vector as JSON: magnitude (times ``scale``), direction from the vertical, x, y."""
    return {"magnitude": abs(value) * scale, "angle_deg": _deg(value) if abs(value) > 1e-12 else 0.0,
            "x": value.imag * scale, "y": value.real * scale}


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
        model = bal.OrderModel(model.order, _c(model.force_forward, z), _c(model.force_backward, z),
                               _c(model.moment_forward, z), _c(model.moment_backward, z))
        force_coef, moment_coef = _r(model.force_max, z), _r(model.moment_max, z)
        coefficients["sum_" + name] = force_coef
        coefficients["M_" + name] = moment_coef
        absolute["sum_" + name + "_N"] = force_coef * amplitude
        absolute["M_" + name + "_Nm"] = moment_coef * amplitude * a if a is not None else None
        s = C if n == 0 else harmonics[n] * C_I
        # a complex harmonic (an offset crank-slider) turns its counter-rotating part back
        s_back = np.conj(s)
        hf = bal.hodograph(_c(model.force_forward) * s, _c(model.force_backward) * s_back, model.speed,
                           tolerance=NEGLIGIBLE * amplitude * g.cylinders)
        hm = bal.hodograph(_c(model.moment_forward) * s, _c(model.moment_backward) * s_back, model.speed,
                           tolerance=NEGLIGIBLE * amplitude * g.cylinders)
        unit_m = a if a is not None else 1.0
        orders.append({
            "order": n, "name": name, "speed": model.speed, "amplitude_N": amplitude,
            "force_coefficient": force_coef, "moment_coefficient": moment_coef,
            "force_max_N": force_coef * amplitude,
            "moment_max_Nm": moment_coef * amplitude * a if a is not None else None,
            "force_forward": _vector(_c(model.force_forward) * s, 1.0),
            "force_backward": _vector(_c(model.force_backward) * s_back, 1.0),
            "moment_forward": _vector(_c(model.moment_forward) * s, unit_m),
            "moment_backward": _vector(_c(model.moment_backward) * s_back, unit_m),
            "force_hodograph": _hodograph_json(hf, 1.0),
            "moment_hodograph": _hodograph_json(hm, unit_m),
        })
    return coefficients, absolute, orders


def bay_model_of(layout, g) -> dict | None:
    """The textbook's bay models (V, W, Y, X, radial): F, P and K, Z of one bay; None for one cylinder a bay."""
    if layout.cylinders_per_bay <= 1:
        return None
    axes = g.cylinder_axis_rad[g.cylinder_bay == 0]
    f1, p1 = bal.bay_vectors(axes, 1)
    k2, z2 = bal.bay_vectors(axes, 2)
    hod1 = bal.hodograph(f1, p1, 1)  # R = F e^{i alpha} + P e^{-i alpha}, alpha from the bay's vertical
    hod2 = bal.hodograph(k2, z2, 2)
    nb = len(axes)
    return {"F": _signed(_c(f1, nb)), "P": _signed(_c(p1, nb)), "K": _signed(_c(k2, nb)),
            "Z": _signed(_c(z2, nb)), "A_I": _r(hod1.x_amplitude, nb), "B_I": _r(hod1.y_amplitude, nb),
            "A_II": _r(hod2.x_amplitude, nb), "B_II": _r(hod2.y_amplitude, nb),
            "bank_axes_deg": [round(math.degrees(x), 9) for x in axes]}


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
    check = {"orders": all_orders, "samples": CHECK_SAMPLES,
             "force_deviation_relative": float(np.max(np.abs(f_td - f_vec)) / scale_F),
             "moment_deviation_relative": float(np.max(np.abs(m_td - m_vec)) / scale_M),
             "force_scale_N": scale_F, "moment_scale_Nm": scale_M if a is not None else None}
    check["agrees"] = bool(max(check["force_deviation_relative"], check["moment_deviation_relative"]) < CHECK_TOLERANCE)
    return f_td, m_td, scale_F, scale_M, check


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
        counterweights.append({"crank": k + 1, "mass_radius_kg_m": cw.mass_radius_kg_m,
                               "mass_kg": cw.mass_radius_kg_m / r_cw, "mass_per_web_kg": 0.5 * cw.mass_radius_kg_m / r_cw,
                               "angle_deg": cw.phase_deg, "angle_from_crank_deg": (cw.phase_deg - crank_dir) % 360.0,
                               "position_m": position_m(cw.position)})
    shafts = []
    for speed, shaft_masses in sorted(means.shafts.items(), key=lambda kv: (abs(kv[0]), -kv[0])):
        shafts.append({"speed_ratio": speed, "order": abs(speed),
                       "spacing_m": (abs(shaft_masses[-1].position - shaft_masses[0].position) * a
                                     if a is not None and len(shaft_masses) > 1 else None),
                       "masses": [{"mass_radius_kg_m": sm.mass_radius_kg_m, "mass_kg": sm.mass_radius_kg_m / r_sh,
                                   "phase_deg": sm.phase_deg,
                                   "position_m": position_m(sm.position),
                                   "end": "free" if sm.position < -1e-12 else ("power" if sm.position > 1e-12 else "middle")}
                                  for sm in shaft_masses]})
    return counterweights, shafts


def residual_after_means(g, masses, harmonics, means, theta, w, spacing, f_td, m_td, all_orders, balance_orders,
                         scale_F, scale_M, a):
    """What is left with the balancing means fitted, against the orders left unbalanced.

    Returns (residual force N, residual moment N·m as complex arrays, the record); it "vanishes"
    when the residual equals the vector sum of the unbalanced orders within CHECK_TOLERANCE.
    """
    f_means, m_means = means.forces(theta, w, spacing)
    unbalanced_orders = [n for n in all_orders if n not in balance_orders]
    f_left, m_left = bal.vector_method_sum(g, masses, theta, unbalanced_orders, spacing, harmonics, rotating=False)
    residual_F, residual_M = f_td + f_means, m_td + m_means
    residual = {
        "balanced_orders": sorted(balance_orders),
        "force_max_N": float(np.max(np.abs(residual_F))),
        "moment_max_Nm": float(np.max(np.abs(residual_M))) if a is not None else None,
        "force_deviation_relative": float(np.max(np.abs(residual_F - f_left)) / scale_F),
        "moment_deviation_relative": float(np.max(np.abs(residual_M - m_left)) / scale_M),
    }
    residual["vanishes"] = bool(max(residual["force_deviation_relative"], residual["moment_deviation_relative"])
                                < CHECK_TOLERANCE)
    return residual_F, residual_M, residual


def remedy(order: int, balanced: bool, forward: bool, backward: bool, balance_orders, first_order_forward: str) -> str:
    """How an order's force or moment is dealt with: self, counterweights, shaft_forward/backward or none."""
    if balanced:
        return "self"
    if order == 0:
        return "counterweights"
    if order in balance_orders:
        parts = []
        if forward:
            parts.append("counterweights" if order == 1 and first_order_forward == "crankshaft" else "shaft_forward")
        if backward:
            parts.append("shaft_backward")
        return "+".join(parts)
    return "none"


def remedy_summary(orders, g, C, C_I, harmonics, opts) -> list[dict]:
    """One row per order and kind (force, moment): its coefficient, whether it is balanced, the remedy."""
    summary = []
    for entry in orders:
        n = entry["order"]
        limit = NEGLIGIBLE * _amplitude(n, C, C_I, harmonics) * g.cylinders
        for kind in ("force", "moment"):
            coef = entry[f"{kind}_coefficient"]
            balanced = coef < NEGLIGIBLE * g.cylinders
            forward = entry[f"{kind}_forward"]["magnitude"] > limit
            backward = entry[f"{kind}_backward"]["magnitude"] > limit
            summary.append({"quantity": ("sum_" if kind == "force" else "M_") + entry["name"], "order": n,
                            "coefficient": coef, "balanced": bool(balanced),
                            "remedy": remedy(n, balanced, forward, backward, opts.balance_orders,
                                             opts.first_order_forward)})
    return summary


def _time_table(theta, f_td, m_td, residual_F, residual_M, a) -> dict:
    """The stage's table: forces (and moments, with a spacing) over one turn, before and after balancing."""
    table = {"shaft_angle_deg": np.degrees(theta), "force_x_N": f_td.imag, "force_y_N": f_td.real}
    if a is not None:
        table.update({"moment_x_Nm": m_td.imag, "moment_y_Nm": m_td.real})
    table.update({"residual_force_x_N": residual_F.imag, "residual_force_y_N": residual_F.real})
    if a is not None:
        table.update({"residual_moment_x_Nm": residual_M.imag, "residual_moment_y_Nm": residual_M.real})
    return table


def inertia_masses(scene, layout, offset_ratio: float = 0.0) -> bal.Masses:
    """Reciprocating mass m_s = piston group + the rod's share at the pin (kg) and rotating mass
    m_R per crank, kg (crank pin, webs and the rods' big-end shares: ``rotating_mass_per_crank_kg``);
    ``offset_ratio`` k = e/L of an offset crank-slider."""
    e, m = scene.engine, scene.masses
    R, lam, w = e.crank_radius_m, e.rod_ratio_value, e.angular_velocity_rad_s
    rod_rec, _ = phys.rod_mass_split_kg(m.rod, e.rod_length_m, scene.rod_cm_from_big_end_m)
    m_s = m.piston_group + rod_rec
    articulated = (options(scene, ARTICULATED, ArticulatedOptions)
                   if scene.engine.rod_type == "articulated" else None)
    m_R = rotating_mass_per_crank_kg(scene, layout, articulated, ARTICULATED)
    return bal.Masses(m_s, m_R, R, lam, w, offset_ratio)


def _input_notes(opts, g, spacing_m, rod_type: str, torque) -> list:
    """The notes on what the scene leaves out (no cylinder spacing, articulated rods, no cycle);
    a balance-shaft spacing without the cylinder spacing is refused."""
    notes = []
    if opts.balance_shaft_spacing is not None and spacing_m is None and g.cranks > 1:
        raise SceneError(Problem("balancing.balance_shaft_spacing", opts.balance_shaft_spacing,
                                 "needs engine.cylinder_spacing (the crank positions along the shaft)"))
    if spacing_m is None and g.cranks > 1:
        notes.append(("balancing.note_no_spacing", {}))
    if rod_type == "articulated":
        notes.append(("balancing.note_articulated", {}))
    if torque is None:
        notes.append(("balancing.note_no_torque", {}))
    return notes


def _offset_geometry(g, motion, rod_length_m: float):
    """The geometry and k = e/L of the piston motion's mechanism: an offset crank-slider's crank
    points phi_TDC past its cylinder axis at TDC (``extra``: ``offset_m``,
    ``crank_angle_at_tdc_rad``); a central one's along it (k = 0)."""
    k = motion.extra.get("offset_m", 0.0) / rod_length_m
    tdc = motion.extra.get("crank_angle_at_tdc_rad", 0.0)
    if tdc:
        g = replace(g, crank_direction_rad=g.crank_direction_rad + tdc)
    return g, k


def _offset_orders(opts, offset_ratio: float):
    """An offset crank-slider's force has odd orders too (the third is as large as the fourth): its
    tables show them unless the scene names the orders."""
    if offset_ratio and "include_orders" not in opts.model_fields_set:
        return opts.model_copy(update={"include_orders": OFFSET_ORDERS})
    return opts


def _harmonics_json(harmonics, orders) -> dict:
    """A_n of the piston acceleration by order name; an offset crank-slider's complex A_n as the
    amplitude |A_n| and the phase psi_n (a_n cos n alpha + b_n sin n alpha = |A_n| cos(n alpha + psi_n))."""
    if not np.iscomplexobj(harmonics):
        return {"acceleration_harmonics": {bal.roman(n): float(harmonics[n]) for n in orders}}
    return {"acceleration_harmonics": {bal.roman(n): float(abs(harmonics[n])) for n in orders},
            "acceleration_harmonic_phases_deg": {bal.roman(n): math.degrees(np.angle(harmonics[n]))
                                                 for n in orders}}


def run(scene, inputs) -> StageOutput:
    torque = inputs.get(ENGINE_TORQUE)  # only for the reaction-torque range; absent without a cycle
    opts = options(scene, "balancing", BalancingOptions)
    e = scene.engine
    layout = engine_layout(scene)
    g, k = _offset_geometry(bal.geometry_from_layout(layout), inputs[KINEMATICS], e.rod_length_m)
    opts = _offset_orders(opts, k).model_copy(update={"balance_orders": balance_orders_for(scene, opts)})
    R, lam, w = e.crank_radius_m, e.rod_ratio_value, e.angular_velocity_rad_s
    a = e.cylinder_spacing  # None: moments in units of a only
    masses = inertia_masses(scene, layout, k)
    m_s, m_R = masses.reciprocating_kg, masses.rotating_kg
    n_max = bal.orders_needed(lam, offset_ratio=k)
    harmonics = bal.harmonics_for(lam, n_max, k)
    C, C_I = masses.centrifugal_N, masses.first_order_N
    notes = _input_notes(opts, g, a, e.rod_type, torque)

    models = {0: bal.rotating_model(g)}
    for n in sorted(set(opts.include_orders) | set(opts.balance_orders)):
        models[n] = bal.reciprocating_model(g, n)
    coefficients, absolute, orders = order_vectors(g, models, opts.include_orders, C, C_I, harmonics, a)

    theta = 2 * np.pi * np.arange(CHECK_SAMPLES) / CHECK_SAMPLES
    spacing = a if a is not None else 1.0
    all_orders = bal.inertia_orders(n_max, k)
    f_td, m_td, scale_F, scale_M, check = time_domain_check(g, masses, harmonics, all_orders, theta, spacing, a)

    shaft_positions = None
    if opts.balance_shaft_spacing is not None and g.cranks > 1:
        half = 0.5 * opts.balance_shaft_spacing / a
        shaft_positions = (-half, half)
    means = bal.design_means(g, masses, harmonics, opts.balance_orders, opts.counterweights,
                             opts.first_order_forward, shaft_positions)
    r_cw = opts.counterweight_radius if opts.counterweight_radius is not None else R
    r_sh = opts.balance_shaft_radius if opts.balance_shaft_radius is not None else 0.5 * R
    counterweights, shafts = means_records(g, means, r_cw, r_sh, a)
    residual_F, residual_M, residual = residual_after_means(
        g, masses, harmonics, means, theta, w, spacing, f_td, m_td, all_orders, opts.balance_orders,
        scale_F, scale_M, a)

    torque_range = float(np.ptp(torque.torque_Nm)) if torque is not None else None
    results = {
        "reciprocating_mass_kg": m_s,
        "rotating_mass_kg": m_R,
        "centrifugal_N": C,
        "first_order_N": C_I,
        "second_order_N": masses.second_order_textbook_N,  # textbook C_II = lambda C_I (eq. 56)
        # exact: the second harmonic A_2 C_I of the exact inertia force (the P_II of ``orders``)
        "second_order_exact_N": float(abs(harmonics[2])) * C_I,
        "second_order_difference_relative": float(abs(harmonics[2])) * C_I / masses.second_order_textbook_N - 1.0,
        **_harmonics_json(harmonics, all_orders),
        "offset_ratio": k,
        "acceleration_series": {bal.roman(n): v for n, v in bal.acceleration_series(lam).items()},
        "cylinder_spacing_m": a,
        "vertical_axis_deg": g.vertical_deg,
        "coefficients": coefficients,
        "absolute": absolute,
        "orders": orders,
        "bay_model": bay_model_of(layout, g),
        "time_domain_check": check,
        "counterweight_radius_m": r_cw,
        "balance_shaft_radius_m": r_sh,
        "counterweights": counterweights,
        "balance_shafts": shafts,
        "residual": residual,
        "summary": remedy_summary(orders, g, C, C_I, harmonics, opts),
        "reaction_torque_range_Nm": torque_range,
        "first_order_forward": opts.first_order_forward,
        "crank_directions_deg": [math.degrees(x) % 360.0 for x in g.crank_direction_rad],
        "cylinder_axes_deg": [math.degrees(x) for x in g.cylinder_axis_rad],
        "cylinder_phases_deg": [math.degrees(x) % 360.0 for x in g.cylinder_phase_rad],
        "cylinder_labels": list(g.labels),
        "cylinder_bays": [int(b) for b in g.cylinder_bay],
    }
    if opts.explore:
        results["explorer"] = _explore(e, layout, opts.explore_top)
    notes.append(("balancing.note_check_single" if len(g.labels) == 1 else "balancing.note_check",
                  {"orders": n_max, "samples": CHECK_SAMPLES}))
    table = _time_table(theta, f_td, m_td, residual_F, residual_M, a)
    return StageOutput(data={COUNTERWEIGHTS: _fitted(counterweights, e.angular_velocity_rad_s)}, results=results,
                       tables={"balancing": table}, notes=notes)


def _fitted(counterweights: list[dict], omega_rad_s: float) -> Counterweights:
    """The counterweights of results.json as the bearings stage takes them (forces at the speed)."""
    return Counterweights(crank=np.array([cw["crank"] - 1 for cw in counterweights], dtype=int),
                          centrifugal_N=np.array([cw["mass_radius_kg_m"] * omega_rad_s ** 2 for cw in counterweights]),
                          angle_from_crank_rad=np.radians([cw["angle_from_crank_deg"] for cw in counterweights]))


def _signed(value: complex) -> float | dict:
    """The textbook's signed value when the vector lies on the vertical, else magnitude and angle."""
    if abs(value.imag) <= 1e-12 * max(abs(value), 1.0):
        return float(value.real)
    return {"magnitude": abs(value), "angle_deg": _deg(value)}


def _hodograph_json(h: bal.Hodograph, scale: float) -> dict:
    size = max(h.semi_major, 1e-300)
    return {"semi_major": h.semi_major * scale, "semi_minor": _r(h.semi_minor, size) * scale,
            "major_axis_deg": h.major_axis_deg, "x_amplitude": _r(h.x_amplitude, size) * scale,
            "y_amplitude": _r(h.y_amplitude, size) * scale, "sense": h.sense, "theta_at_max_deg": h.theta_at_max_deg}


def _explore(e, layout, top: int) -> dict:
    result = fe.explore(e.cylinders, e.layout, e.strokes, e.bank_angle_deg, top=top,
                        locate=(tuple(layout.crank_lag_deg), tuple(layout.firing_order)))
    return explorer_json(result)


def explorer_json(result: fe.Exploration) -> dict:
    """An explorer result as JSON (also used by ``crankdyn explore --json``)."""
    def row(c: fe.Candidate) -> dict:
        return {"rank": c.rank, "crank_angles_deg": list(c.crank_angles_deg), "firing_order": list(c.firing_order),
                "coefficients": c.coefficients, "neighbours": c.neighbours, "same_pin": c.same_pin,
                "same_half": c.same_half}

    return {"cylinders": result.cylinders, "layout": result.layout, "strokes": result.strokes,
            "bank_angle_deg": result.bank_angle_deg, "interval_deg": result.interval_deg,
            "arrangements": result.arrangements, "firing_orders": result.firing_orders,
            "scored_firing_orders": result.scored_firing_orders, "reason": result.reason,
            "rows": [row(c) for c in result.rows],
            "scene_rank": result.located_rank, "scene": row(result.located) if result.located else None}


# --------------------------------------------------------------------------- rendering

def _arrow(ax, x0, y0, x1, y1, **kw):
    ax.annotate("", xy=(x1, y1), xytext=(x0, y0), arrowprops=dict(arrowstyle="-|>", lw=kw.pop("lw", 1.2), **kw))


def _star_figure(ctx, r):
    """Crank diagrams seen from the free end: cranks (first order) and doubled angles (second order)."""
    single = len(r["cylinder_labels"]) == 1  # one crank and one cylinder: a vector of each order, not a "star"
    caption = ctx.t("balancing.star_caption_single") if single else ctx.t("balancing.star_caption")
    return ctx.figure(partial(_star_drawing, ctx.t, r), caption, "crank_diagrams",
                      see="balancing.see_star_single" if single else "balancing.see_star")


def _star_drawing(t, r):
    """The crank diagrams' figure (:func:`_star_figure`)."""
    from matplotlib.patches import Circle  # lazy: heavy optional import
    fig, axes = new_figure(16, 8.2, ncols=2)
    crank_dirs = np.radians(r["crank_directions_deg"])
    labels = r["cylinder_labels"]
    phases = np.radians(r["cylinder_phases_deg"])
    axes_rad = np.radians(r["cylinder_axes_deg"])
    for ax, order in zip(axes, (1, 2), strict=True):
        ax.set_aspect("equal")
        hide_axes(ax)
        ax.add_patch(Circle((0, 0), 1.0, fill=False, lw=0.5, ls=":", color="0.5"))
        for axis in sorted(set(np.round(axes_rad, 9))):
            ax.plot([0, 1.25 * math.sin(axis)], [0, 1.25 * math.cos(axis)], color="0.6", lw=0.8, ls="--")
        single = len(labels) == 1  # one crank: its vectors are named, not numbered
        if order == 1:  # cranks, numbered from the free end
            vectors = [(d, r"$C$, $C_{\mathrm{I}}$" if single else str(k + 1)) for k, d in enumerate(crank_dirs)]
            color, title = "C0", t("balancing.star_first")
        else:  # one C_II vector per cylinder, at twice the angle between its crank and its axis
            vectors = [(axes_rad[i] - 2 * phases[i], r"$C_{\mathrm{II}}$" if single else label) for i, label in enumerate(labels)]
            color, title = "C1", t("balancing.star_second")
        groups: dict[int, list[str]] = {}
        for d, label in vectors:
            groups.setdefault(int(round(math.degrees(d) * 100)) % 36000, []).append(label)
        for key, members in groups.items():
            d = math.radians(key / 100)
            _arrow(ax, 0, 0, math.sin(d), math.cos(d), color=color)
            # on a white ground: the dashed cylinder axis behind a label along it does not cut it
            ax.text(1.17 * math.sin(d), 1.17 * math.cos(d), ", ".join(members), ha="center", va="center", fontsize=7,
                    zorder=5, bbox={"facecolor": "white", "edgecolor": "none", "pad": 0.6})
        # the title inside the axes' limits: above them, an equal-aspect panel's title is cut
        ax.text(0, 1.62, title, ha="center", va="center", fontsize=8)
        ax.set_xlim(-1.4, 1.4)
        ax.set_ylim(-1.4, 1.75)
    return fig


def _models_shown(r) -> tuple[list, bool]:
    """The orders the vector models show, and whether a row of moments is drawn."""
    shown = [o for o in r["orders"] if o["order"] in (0, 1, 2)] + \
        [o for o in r["orders"] if o["order"] >= 4 and (o["force_coefficient"] > NEGLIGIBLE or o["moment_coefficient"] > NEGLIGIBLE)][:1]
    moments = r["cylinder_spacing_m"] is not None or any(o["moment_coefficient"] > NEGLIGIBLE for o in shown)
    return shown, moments


def _name_arrow(ax, name: str, start: complex, vector: complex, side: float) -> None:
    """``name`` in italics beside the middle of the arrow ``start`` → ``start + vector`` (complex
    numbers: imag along x, real along y, as the panels draw them), 5 pt off it on ``side`` (+1 left)."""
    length = abs(vector)
    normal = (-vector.real / length * side, vector.imag / length * side)  # the arrow turned by 90°
    middle = start + 0.5 * vector
    ax.annotate(name, (middle.imag, middle.real), xytext=(5 * normal[0], 5 * normal[1]), textcoords="offset points",
                fontsize=7, style="italic", ha="center", va="center")


def _models_figure(ctx, r):
    """Vector models and hodographs (textbook figs. 26-33): forces (top row) and moments (bottom row)."""
    moments = _models_shown(r)[1]
    return ctx.figure(partial(_models_drawing, ctx.t, r),
                      ctx.t("balancing.models_caption" if moments else "balancing.models_caption_forces"),
                      "vector_models", see="balancing.see_models")


def _models_drawing(t, r):
    """The vector models' figure (:func:`_models_figure`)."""
    from matplotlib.patches import Circle  # lazy: heavy optional import
    shown, moments = _models_shown(r)
    rows = 2 if moments else 1
    fig, axes = new_figure(16, rows * (16.0 / len(shown) + 0.9), nrows=rows, ncols=len(shown), squeeze=False)
    for col, o in enumerate(shown):
        for row, kind in enumerate(("force", "moment")[: 2 if moments else 1]):
            ax = axes[row][col]
            ax.set_aspect("equal")
            ax.set_xticks([])
            ax.set_yticks([])
            for side in ("left", "bottom"):
                ax.spines[side].set_visible(False)
            # the dotted circle is one amplitude C_n (one C_n * a for moments): the scale of the panel
            ax.add_patch(Circle((0, 0), 1.0, fill=False, lw=0.5, ls=":", color="0.55"))
            norm = o["amplitude_N"] * ((r["cylinder_spacing_m"] or 1.0) if kind == "moment" else 1.0)
            fwd, bwd = o[f"{kind}_forward"], o[f"{kind}_backward"]
            f = complex(fwd["y"], fwd["x"]) / norm if norm else 0j
            b = complex(bwd["y"], bwd["x"]) / norm if norm else 0j
            th = np.linspace(0, 2 * np.pi / o["speed"], 241)
            wv = f * np.exp(1j * o["speed"] * th) + b * np.exp(-1j * o["speed"] * th)
            ax.plot(wv.imag, wv.real, color="C2", lw=1.8, zorder=3, solid_capstyle="round")
            # the vectors named beside their middles (a black-and-white print still tells them apart),
            # f on the left of its arrow, b on the right, 5 pt off the line (not on the arrows)
            if abs(f) > 1e-9:
                _arrow(ax, 0, 0, f.imag, f.real, color="C0")
                _name_arrow(ax, "f", 0j, f, side=1.0)
            if abs(b) > 1e-9:
                _arrow(ax, f.imag, f.real, f.imag + b.imag, f.real + b.real, color="C3")
                _name_arrow(ax, "b", f, b, side=-1.0)
            lim = max(abs(f) + abs(b), 1.0) * 1.25
            ax.set_xlim(-lim, lim)
            ax.set_ylim(-lim, lim)
            ax.axhline(0, color="0.75", lw=0.5, zorder=1)
            ax.axvline(0, color="0.75", lw=0.5, zorder=1)
            if o[f"{kind}_coefficient"] <= NEGLIGIBLE * len(r["cylinder_labels"]):
                # under the panel, clear of its dotted circle (over it the label is unreadable)
                ax.text(0.5, 0.0, t("balancing.balanced_label"), ha="center", va="top", fontsize=7, color="C2",
                        transform=ax.transAxes)
            # the order's Roman numeral upright, as in the text and tables (P_II, not P_{II} in italics)
            sub = "C" if o["order"] == 0 else f"\\mathrm{{{o['name'][1:]}}}"
            amp = "C" if o["order"] == 0 else f"C_{{{sub}}}"
            # one cylinder's own force, without the sum sign, as its tables and text write it
            sigma = "" if len(r["cylinder_labels"]) == 1 else "\\Sigma "
            title = (f"${sigma}P_{{{sub}}}/{amp}$" if o["order"] else f"${sigma}C/C$") if kind == "force" \
                else f"${sigma}M_{{{sub}}}/({amp}a)$"
            ax.set_title(title, fontsize=8)
    return fig


#: The orders whose |A_n| and psi_n the table of an offset crank-slider's masses gives.
OFFSET_TABLE_ORDERS = ("I", "II", "III", "IV")


def _offset_masses_table(ctx, r):
    """An offset crank-slider's masses, force amplitudes and the acceleration's harmonics as
    amplitude |A_n| and phase psi_n (its series has sine terms and odd orders)."""
    t = ctx.t
    unit_n = " " + t("balancing.unit_N")
    orders = [n for n in OFFSET_TABLE_ORDERS if n in r["acceleration_harmonics"]]
    names = [t("balancing.m_s"), t("balancing.m_R")] + [Markup(x) for x in (
        "<i>C</i> = <i>m</i><sub>R</sub><i>Rω</i><sup>2</sup>",
        "<i>C</i><sub>I</sub> = <i>m</i><sub>s</sub><i>Rω</i><sup>2</sup>",
        "<i>C</i><sub>II</sub> = <i>λC</i><sub>I</sub>")]
    names += [Markup(f"|<i>A</i><sub>{bal_order(n)}</sub>|") for n in orders]
    values = [ctx.num(r["reciprocating_mass_kg"]) + " " + t("unit.kg"), ctx.num(r["rotating_mass_kg"]) + " " + t("unit.kg"),
              ctx.num(r["centrifugal_N"]) + unit_n, ctx.num(r["first_order_N"]) + unit_n,
              ctx.num(r["second_order_N"]) + unit_n]
    values += [ctx.num(r["acceleration_harmonics"][n], 6) for n in orders]
    phases = [""] * 5 + [t.fixed(r["acceleration_harmonic_phases_deg"][n], 2) for n in orders]
    table = ctx.table([(t("balancing.quantity"), names, None), (t("balancing.value"), values, None),
                       (Markup(t("balancing.phase") + ", <i>ψ</i><sub><i>n</i></sub>, °"), phases, None)],
                      caption=t("balancing.masses_caption"), see="balancing.see_masses")
    return table + worked_balancing(ctx, r)


def bal_order(name: str) -> int:
    """The order a Roman numeral of :func:`crankdyn.physics.balancing.roman` names."""
    return {v: k for k, v in bal.ROMAN.items()}.get(name) or int(name)


def _masses_table(ctx, r):
    """Masses, inertia-force amplitudes and acceleration harmonics."""
    if r.get("offset_ratio"):
        return _offset_masses_table(ctx, r)
    t = ctx.t
    masses_table = ctx.table([
        (t("balancing.quantity"), [t("balancing.m_s"), t("balancing.m_R")] + [Markup(x) for x in (
            "<i>C</i> = <i>m</i><sub>R</sub><i>Rω</i><sup>2</sup>", "<i>C</i><sub>I</sub> = <i>m</i><sub>s</sub><i>Rω</i><sup>2</sup>",
            "<i>C</i><sub>II</sub> = <i>λC</i><sub>I</sub>", "<i>A</i><sub>2</sub>", "<i>A</i><sub>4</sub>",
            "<i>A</i><sub>6</sub>")], None),
        (t("balancing.value"), [ctx.num(r["reciprocating_mass_kg"]) + " " + t("unit.kg"),
                                ctx.num(r["rotating_mass_kg"]) + " " + t("unit.kg"),
                                ctx.num(r["centrifugal_N"]) + " " + t("balancing.unit_N"),
                                ctx.num(r["first_order_N"]) + " " + t("balancing.unit_N"),
                                ctx.num(r["second_order_N"]) + " " + t("balancing.unit_N"),
                                ctx.num(r["acceleration_harmonics"]["II"], 6),
                                ctx.num(r["acceleration_harmonics"]["IV"], 4),
                                ctx.num(r["acceleration_harmonics"]["VI"], 4)], None),
        (t("balancing.series"), ["", "", "", "", "", ctx.num(r["acceleration_series"]["II"], 6),
                                 ctx.num(r["acceleration_series"]["IV"], 4), ctx.num(r["acceleration_series"]["VI"], 4)], None),
    ], caption=t("balancing.masses_caption"), see="balancing.see_masses")
    return masses_table + worked_balancing(ctx, r)


def _coefficients_table(ctx, r):
    """Force and moment coefficients of every order with their hodographs."""
    t = ctx.t
    def order_name(o):
        return Markup("<i>C</i>" if o["order"] == 0 else "<i>P</i><sub>" + o["name"][1:] + "</sub>")

    def zero(o, kind):
        return o[f"{kind}_coefficient"] <= NEGLIGIBLE * len(r["cylinder_labels"])

    orders = r["orders"]
    single = len(r["cylinder_labels"]) == 1  # one cylinder: no moments, no sums
    columns = [
        (t("balancing.order"), [order_name(o) for o in orders], None),
        # in words: P and M alone name other quantities in this section (the bay model's P)
        (t("balancing.head_force_max_ratio" if single else "balancing.head_resultant_force_ratio", scale=_C_N),
         [o["force_coefficient"] for o in orders], 4),
        (t("balancing.head_force_max" if single else "balancing.head_resultant_force") + ", " + t("balancing.unit_N"),
         [newtons(ctx.t, o["force_max_N"]) for o in orders], None),
        (t("balancing.hodograph_axes", scale=_C_N), ["—" if zero(o, "force") else
                                         f"{ctx.t.fixed(o['force_hodograph']['semi_major'] / o['amplitude_N'], 3)} / "
                                         f"{ctx.t.fixed(o['force_hodograph']['semi_minor'] / o['amplitude_N'], 3)}"
                                         for o in orders], None),
        (t("balancing.major_axis"), ["—" if zero(o, "force") or _circular(o["force_hodograph"])
                                     else ctx.t.fixed(o["force_hodograph"]["major_axis_deg"], 1) for o in orders], None),
        (t("balancing.sense"), ["—" if zero(o, "force") else t("balancing.sense_" + o["force_hodograph"]["sense"])
                                for o in orders], None),
    ]
    if not single:
        columns += [
            (t("balancing.head_resultant_moment_ratio", scale=f"({_C_N}<i>a</i>)"),
             [o["moment_coefficient"] for o in orders], 4),
            (t("balancing.head_resultant_moment") + ", " + t("unit.Nm"),
             ["—" if o["moment_max_Nm"] is None else ctx.t.fixed(o["moment_max_Nm"], 1)
                                          for o in orders], None),
            (t("balancing.moment_plane"), ["—" if zero(o, "moment") else
                                           ctx.t.fixed(o["moment_hodograph"]["major_axis_deg"], 1) for o in orders], None),
        ]
    return ctx.table(columns, caption=t("balancing.coefficients_caption_single" if single else "balancing.coefficients_caption"),
                     css_class="data wide",
                     see="balancing.see_coefficients_single" if single else "balancing.see_coefficients")


def _bay_table(ctx, r):
    """The bay model (F, P, A, B, K, Z) of a V/W/Y/X/radial bay; None for one cylinder a bay."""
    t = ctx.t
    bay_table = None
    if r["bay_model"] is not None:
        bm = r["bay_model"]

        def show(v):
            return ctx.num(v, 4) if not isinstance(v, dict) else f"{ctx.num(v['magnitude'], 4)} ∠{ctx.t.fixed(v['angle_deg'], 1)}°"

        heads = ("<i>F</i>/<i>C</i><sub>I</sub>", "<i>P</i>/<i>C</i><sub>I</sub>", "<i>a</i><sub>e,I</sub>/<i>C</i><sub>I</sub>",
                 "<i>b</i><sub>e,I</sub>/<i>C</i><sub>I</sub>", "<i>K</i>/<i>C</i><sub>II</sub>", "<i>Z</i>/<i>C</i><sub>II</sub>",
                 "<i>a</i><sub>e,II</sub>/<i>C</i><sub>II</sub>", "<i>b</i><sub>e,II</sub>/<i>C</i><sub>II</sub>")
        keys = ("F", "P", "A_I", "B_I", "K", "Z", "A_II", "B_II")
        bay_table = ctx.table([(h, [show(bm[k])], None) for h, k in zip(heads, keys, strict=True)],
                              caption=t("balancing.bay_caption"), see="balancing.see_bay")

    return bay_table


def _summary_table(ctx, r):
    """What is balanced by itself and what each balancing means takes."""
    t = ctx.t
    rows = r["summary"]
    single = len(r["cylinder_labels"]) == 1
    if single:  # one cylinder's forces act in the plane of its crank: no moments (nor in the caption)
        rows = [s for s in rows if not s["quantity"].startswith("M_")]
    summary_table = ctx.table([
        (t("balancing.quantity"), [_summary_symbol(s, "" if single else "Σ") for s in rows], None),
        (t("balancing.coefficient"), [s["coefficient"] for s in rows], 4),
        (t("balancing.state"), [t("balancing.balanced") if s["balanced"] else t("balancing.unbalanced")
                                for s in rows], None),
        (t("balancing.remedy"), [_remedy_text(t, s["remedy"]) for s in rows], None),
    ], caption=t("balancing.summary_caption_forces" if single else "balancing.summary_caption"),
        see="balancing.see_summary")

    return summary_table


def _remedy_text(t, remedy: str) -> str:
    """The means of one order in words: a Lanchester pair named as such, several means joined by "і"."""
    if remedy == "shaft_forward+shaft_backward":
        return t("balancing.remedy_shaft_pair")
    return t("balancing.means_and").join(t("balancing.remedy_" + part) for part in remedy.split("+"))


def _means_table(ctx, r):
    """Counterweights and balance-shaft masses; None when there are none."""
    t = ctx.t
    single = len(r["cylinder_labels"]) == 1  # one crank: no crank numbers, ends or positions along the shaft
    means_rows = []
    for cw in r["counterweights"]:
        label = t("balancing.counterweight_single") if single else t("balancing.counterweight", crank=cw["crank"])
        means_rows.append((label, "+1", ctx.num(cw["mass_radius_kg_m"] * 1e3, 4),
                           ctx.num(cw["mass_kg"], 4) + f" ({ctx.num(cw['mass_per_web_kg'], 4)}\u00a0×\u00a02)",  # one unit in a narrow cell
                           ctx.t.fixed(cw["angle_from_crank_deg"], 1) + "° " + t("balancing.from_crank"),
                           ctx.num(cw["position_m"] * 1e3, 4) if cw["position_m"] is not None else "—"))
    for shaft in r["balance_shafts"]:
        for sm in shaft["masses"]:
            sense = t("balancing.shaft_" + ("forward" if shaft["speed_ratio"] > 0 else "backward"))
            means_rows.append((t("balancing.shaft_single", order=shaft["order"], sense=sense) if single else
                               t("balancing.shaft", order=shaft["order"], sense=sense, end=t("balancing.end_" + sm["end"])),
                               f"{shaft['speed_ratio']:+d}".replace("-", "\u2212"), ctx.num(sm["mass_radius_kg_m"] * 1e3, 4),
                               ctx.num(sm["mass_kg"], 4), ctx.t.fixed(sm["phase_deg"], 1) + "° " + t("balancing.from_vertical"),
                               ctx.num(sm["position_m"] * 1e3, 4) if sm["position_m"] is not None else "—"))
    if not means_rows:
        return None
    columns = [
        (t("balancing.means"), [x[0] for x in means_rows], None),
        (t("balancing.speed_ratio"), [x[1] for x in means_rows], None),
        (t("balancing.static_moment") + ", " + t("balancing.unit_kg_mm"), [x[2] for x in means_rows], None),
        (t("balancing.head_mass") + ", " + t("unit.kg"), [x[3] for x in means_rows], None),
        (t("balancing.angle"), [x[4] for x in means_rows], None),
    ] + ([] if single else [(t("balancing.head_distance_from_crank_1") + ", " + t("unit.mm"),
                             [x[5] for x in means_rows], None)])
    radii = {"r_cw": ctx.num(r["counterweight_radius_m"] * 1e3), "r_sh": ctx.num(r["balance_shaft_radius_m"] * 1e3)}
    if not r["balance_shafts"]:
        caption = t("balancing.means_caption_counterweights", **radii)
        see = "balancing.see_means_counterweight" if len(r["counterweights"]) == 1 \
            else "balancing.see_means_counterweights"
    elif not r["counterweights"]:
        caption = t("balancing.means_caption_shafts", **radii)
        see = "balancing.see_means_shaft" if len(r["balance_shafts"]) == 1 else "balancing.see_means_shafts"
    elif single:
        caption = t("balancing.means_caption_single", shafts=len(r["balance_shafts"]), **radii)
        see = "balancing.see_means_single"  # one counterweight and one or more shafts
    else:
        caption = t("balancing.means_caption", **radii)
        see = "balancing.see_means"
    return ctx.table(columns, caption=caption, css_class="data wide", see=see)


def _explorer_table(ctx, r):
    """The firing-order explorer's best rows; None when not asked for."""
    t = ctx.t
    explorer_table = None
    if "explorer" in r and r["explorer"]["rows"]:
        x = r["explorer"]
        rows = x["rows"]
        explorer_table = ctx.table([
            ("№", [str(c["rank"]) for c in rows], None),
            (t("balancing.cranks"), ["; ".join(ctx.angle_text(v) for v in c["crank_angles_deg"])
                                     for c in rows], None),
            (t("balancing.firing_order"), ["–".join(c["firing_order"]) for c in rows], None),
            ("Σ<i>C</i>", [c["coefficients"]["sum_C"] for c in rows], 3),
            ("Σ<i>M</i><sub>C</sub>", [c["coefficients"]["M_C"] for c in rows], 3),
            ("Σ<i>P</i><sub>I</sub>", [c["coefficients"]["sum_PI"] for c in rows], 3),
            ("Σ<i>M</i><sub>I</sub>", [c["coefficients"]["M_PI"] for c in rows], 3),
            ("Σ<i>P</i><sub>II</sub>", [c["coefficients"]["sum_PII"] for c in rows], 3),
            ("Σ<i>M</i><sub>II</sub>", [c["coefficients"]["M_PII"] for c in rows], 3),
            (t("balancing.rule_neighbours"), [str(c["neighbours"]) for c in rows], None),
            (t("balancing.rule_same_pin"), [str(c["same_pin"]) for c in rows], None),
            (t("balancing.rule_same_half"), [str(c["same_half"]) for c in rows], None),
        ], caption=t("balancing.explorer_caption", n=len(rows), total=x["firing_orders"]), css_class="data wide",
            see="balancing.see_explorer")

    return explorer_table


def _conclude(ctx, r) -> None:
    """The section's conclusions: what stays unbalanced, which means are fitted."""
    t = ctx.t
    unbalanced = [s for s in r["summary"] if not s["balanced"]]
    single = len(r["cylinder_labels"]) == 1
    # for the abstract: which resultants stay unbalanced (with the fitted means, if any), by their
    # symbols ("ΣP_II, ΣP_IV"), or none
    left = [s for s in _left_unbalanced(r, unbalanced) if not _negligible(r, s)]
    means = bool(r["counterweights"] or r["balance_shafts"])
    ctx.find(t("balancing.finding_unbalanced_means" if means else "balancing.finding_unbalanced",
               count=len(left), items=", ".join(_plain_symbol(s, "" if single else "Σ") for s in left))
             if left else t("balancing.finding_balanced_means" if means else "balancing.finding_balanced"))
    negligible = [s for s in unbalanced if _negligible(r, s)]
    significant = [s for s in unbalanced if s not in negligible]
    if significant and single:  # one cylinder: coefficients are all 1; say the forces
        amplitudes = {o["name"]: o["force_max_N"] for o in r["orders"]}
        ctx.conclude(t("balancing.conclusion_unbalanced_single", items=", ".join(
            f"{_plain_symbol(s, '')} = {newtons(t, amplitudes[s['quantity'].split('_', 1)[1]])} {t('balancing.unit_N')}"
            for s in significant if s["quantity"].startswith("sum_"))))
    elif significant:
        # the amplitude, and the textbook's coefficient times the scale it divides by (C_n = |A_n|·C_I,
        # table 8.2): "ΣP_II = 9426 Н (4,000·|A_2|C_I)" multiplies out, where "ΣP_II/C_II = 4,000" beside
        # the textbook's C_II = λC_I did not
        ctx.conclude(t("balancing.conclusion_unbalanced", items=", ".join(_unbalanced_item(ctx, r, s)
                                                                         for s in significant)))
    elif not negligible:
        ctx.conclude(t("balancing.conclusion_balanced"))
    if negligible:
        _conclude_negligible(ctx, r, negligible, single, alone=not significant)
    if r["counterweights"] or r["balance_shafts"]:
        ctx.conclude(_means_sentence(t, r))


#: An unbalanced resultant under this share of one cylinder's first-order inertia force C_I
#: (a moment: of C_I·a, a the cylinder spacing) is said to be negligible, not listed among the
#: unbalanced ones ("ΣP_VI = 4,4 Н" beside ΣP_II = 9426 Н is no finding).
NEGLIGIBLE_SHARE = 0.01


def _summary_amplitude(r, item) -> tuple[float | None, bool]:
    """(amplitude of an item of the summary: N for a force, N·m for a moment, None where the
    results have none; whether it is a force)."""
    force = item["quantity"].startswith("sum_")
    return r["absolute"].get(item["quantity"] + ("_N" if force else "_Nm")), force


def _negligible(r, item) -> bool:
    """Whether ``item``'s amplitude is under :data:`NEGLIGIBLE_SHARE` of C_I (a moment: of C_I·a)."""
    value, force = _summary_amplitude(r, item)
    scale = r["first_order_N"] * (1.0 if force else r["cylinder_spacing_m"] or 0.0)
    return value is not None and scale > 0 and abs(value) < NEGLIGIBLE_SHARE * scale


def _conclude_negligible(ctx, r, negligible, single: bool, alone: bool) -> None:
    """"ΣP_VI = 4,4 Н is under 1 % of C_I, negligible": after the unbalanced ones, or alone."""
    t = ctx.t
    items = []
    for item in negligible:
        value, force = _summary_amplitude(r, item)
        amplitude = newtons(t, value) if force else t.number_g(value, 2)
        items.append(f"{_plain_symbol(item, '' if single else 'Σ')} = {amplitude} "
                     f"{t('balancing.unit_N') if force else t('unit.Nm')}")
    moments = any(not item["quantity"].startswith("sum_") for item in negligible)
    reference = t("balancing.negligible_reference") + (" " + t("balancing.negligible_reference_moment") if moments else "")
    what = t("balancing.negligible_forces_moments" if moments else "balancing.negligible_forces")
    ctx.conclude(t("balancing.conclusion_only_negligible" if alone else "balancing.conclusion_negligible",
                   items=", ".join(items), percent=t.number_g(100 * NEGLIGIBLE_SHARE, 2), reference=reference,
                   what=what))


def _circular(hodograph: dict) -> bool:
    """Whether a hodograph is a circle to the table's three decimals: it has no major axis (an
    angle "0,0°" beside the semi-axes 1,000 / 1,000 would mean nothing)."""
    return round(hodograph["semi_major"], 9) == 0 or \
        abs(hodograph["semi_major"] - hodograph["semi_minor"]) <= 5e-4 * hodograph["semi_major"]


def _left_unbalanced(r, unbalanced) -> list:
    """The unbalanced resultants the fitted means leave: those of an order no balance shaft or
    counterweight balances (``residual.balanced_orders``; the centrifugal forces, order 0, by
    counterweights)."""
    balanced = set((r.get("residual") or {}).get("balanced_orders") or ())
    if r["counterweights"]:
        balanced.add(0)
    return [s for s in unbalanced if s["order"] not in balanced]


def newtons(t, force_N: float) -> str:
    """A force as the table of orders and the conclusions print it: whole newtons (C = 17 235 Н),
    two significant digits under 10 N, where whole newtons would print a small unbalanced force
    as 0 or 1 Н."""
    return t.fixed(force_N, 0) if abs(force_N) >= 10 else t.number_g(force_N, 2)


def _unbalanced_item(ctx, r, item) -> str:
    """"ΣP_II = 9426 Н (4,000·|A_2|C_I)", "ΣM_I = 12,5 Н·м (0,5000·C_I·a)": an unbalanced sum's
    amplitude with the coefficient and the one-cylinder amplitude it multiplies (as table 8.2
    divides); "ΣP_II/C_II = 4,000" without an amplitude to print."""
    value, force = _summary_amplitude(r, item)
    coefficient = ctx.num(item["coefficient"], 4)
    if value is None:
        return f"{_plain_symbol(item)}/{_scale_symbol(item)} = {coefficient}"
    unit = ctx.t("balancing.unit_N") if force else ctx.t("unit.Nm")
    amplitude = newtons(ctx.t, value) if force else ctx.t.fixed(value, 1)
    order = item["order"]  # 0: the centrifugal forces; A_1 = 1: the first order's amplitude is C_I itself
    # a word joiner after the bar: "(4,000·|A4|" is not parted from "CI)" at a line's end
    scale = "C" if order == 0 else "C_I" if order == 1 else f"|A_{order}|\u2060C_I"
    return f"{_plain_symbol(item)} = {amplitude} {unit} ({coefficient}·{scale if force else scale + '·a'})"



def _in_words(t, n: int) -> dict[str, str]:
    """``words_m``/``words_f``: a count of one to nine in words, as a text writes a number without a
    unit (ДСТУ 3008), in the masculine and the feminine; a larger count in digits."""
    if 1 <= n <= 9:
        return {f"words_{g}": t(f"balancing.numerals_{g}").split("|")[n - 1] for g in ("m", "f")}
    return {"words_m": str(n), "words_f": str(n)}


def _means_sentence(t, r) -> str:
    """What the fitted means are, and what is balanced with them: the shafts' own orders, and
    the crank arrangement's part where it balances an order (or the centrifugal forces) alone."""
    shaft_orders = sorted({shaft["order"] for shaft in r["balance_shafts"]})
    means = []
    if r["counterweights"]:
        means.append(t("balancing.means_counterweights", n=len(r["counterweights"]), **_in_words(t, len(r["counterweights"]))))
    if r["balance_shafts"]:
        means.append(t("balancing.means_shafts", n=len(r["balance_shafts"]), k=len(shaft_orders),
                       orders=", ".join(map(str, shaft_orders)), **_in_words(t, len(r["balance_shafts"]))))
    balanced = r["residual"]["balanced_orders"]
    by_means = set(shaft_orders) | ({1} if r["counterweights"] else set())
    with_scheme = not r["counterweights"] or any(order not in by_means for order in balanced)
    single = len(r["cylinder_labels"]) == 1
    return t("balancing.conclusion_means_single" if single else "balancing.conclusion_means", means=t("balancing.means_and").join(means),
             with_them=t("balancing.with_means_and_scheme" if with_scheme else "balancing.with_means"),
             orders=", ".join(map(str, balanced)), orders_words=orders_in_words(t, balanced), count=len(balanced))


def orders_in_words(t, orders) -> str:
    """"першого і другого": the orders as ordinal words (a text writes "сили першого порядку", not
    "сили порядку 1"), the last joined by "and"; an order above ten in digits."""
    words = t("balancing.ordinals").split("|")
    named = [words[n - 1] if 1 <= n <= len(words) else str(n) for n in orders]
    return named[0] if len(named) == 1 else ", ".join(named[:-1]) + t("balancing.ordinals_and") + named[-1]


def render(output: StageOutput, ctx) -> str | None:
    r = output.results
    star = _star_figure(ctx, r)
    masses_table = _masses_table(ctx, r)
    models_figure = _models_figure(ctx, r)
    bay_table = _bay_table(ctx, r)  # numbered as the section shows them: the bay's model first
    coef_table = _coefficients_table(ctx, r)
    summary_table = _summary_table(ctx, r)
    means_table = _means_table(ctx, r)
    explorer_table = _explorer_table(ctx, r)
    _conclude(ctx, r)
    return ctx.render_template("sections/balancing.html.j2", r=r, star=star, masses_table=masses_table,
                               models_figure=models_figure, coef_table=coef_table, bay_table=bay_table,
                               summary_table=summary_table, means_table=means_table, explorer_table=explorer_table,
                               spacing=r["cylinder_spacing_m"], orders_in_words=partial(orders_in_words, ctx.t))


#: The amplitude a table of orders divides by, as its headers print it (the catalogs' ``{scale}``).
_C_N = "<i>C</i><sub><i>n</i></sub>"


def _summary_symbol(s, sum_sign: str = "Σ") -> Markup:
    """ΣC, ΣP_II, ΣM_I as the summary table prints them; one cylinder's without the sum sign (C, P_II),
    as its table of orders and its text write them."""
    kind, base = s["quantity"].split("_", 1)
    if kind == "sum":
        return Markup(f"{sum_sign}<i>C</i>" if base == "C" else f"{sum_sign}<i>P</i><sub>" + base[1:] + "</sub>")
    return Markup(f"{sum_sign}<i>M</i><sub>" + ("C" if base == "C" else base[1:]) + "</sub>")


def _scale_symbol(s) -> str:
    """What table 6.3 divides a sum by: C_n (C for the centrifugal forces), and a moment also by a."""
    kind, base = s["quantity"].split("_", 1)
    order = base[1:] if base.startswith("P") else ""
    scale = f"C_{order}" if order else "C"
    return scale if kind == "sum" else f"({scale}·a)"


def _plain_symbol(s, sum_sign: str = "Σ") -> str:
    """``ΣP_I``, ``ΣM_II``, ``ΣC``: the symbol as table 6.3 prints it (typeset with its subscript);
    ``sum_sign=""`` for one cylinder's own force (``P_I``)."""
    kind, base = s["quantity"].split("_", 1)
    order = base[1:] if base.startswith("P") else ""
    if kind == "sum":
        return f"{sum_sign}P_{order}" if order else sum_sign + base
    return f"{sum_sign}M_{order or base}"


#: The offset crank-slider's phase of an acceleration harmonic (meaning: symbol.balancing.<key>).
SYMBOLS = {"harmonic_phase": Symbol("ψ", {"en": "n"}, "°", html="<i>ψ</i><sub><i>n</i></sub>")}


BALANCING_STAGE = Stage(
    template_dir=TEMPLATES,
    name="balancing",
    # the core's letters that hold with their meaning in this section only
    section_symbols=("harmonic_order", "shaft_angle", "crank_lag", "cylinder_axis_angle",
                     "cylinder_position", "bay_forward_first", "bay_backward_first",
                     "bay_forward_second", "bay_backward_second", "bay_semi_axis_x_first",
                     "bay_semi_axis_y_first", "bay_semi_axis_x_second", "bay_semi_axis_y_second",
                     "cylinder_spacing"),
    title_key="balancing.title",
    requires=(KINEMATICS,),
    uses=(ENGINE_TORQUE,),
    provides=(COUNTERWEIGHTS,),
    applies=applies,
    run=run,
    render=render,
    figures=("crank_diagrams", "vector_models"),
    symbols=SYMBOLS,
    tables=("balancing",),
    references=("poda2007", "lukanin1995", "taylor1985"),
    options_table="balancing",
    options_model=BalancingOptions,
)
