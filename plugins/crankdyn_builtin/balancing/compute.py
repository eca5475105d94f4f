"""Balancing: free forces and moments, counterweights, balance shafts, firing-order explorer (Poda
2007 §6).

The physics is in :mod:`crankdyn.physics.balancing` (vector models, time-domain sums, sizing of
the balancing means) and :mod:`crankdyn.physics.firing_explorer`; this module reads the scene and
assembles the results.
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import partial

import numpy as np

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import articulated as art
from crankdyn.physics import balancing as bal
from crankdyn.physics import bearings as brg
from crankdyn.physics import firing_explorer as fe
from crankdyn.physics import forces as phys
from crankdyn.plugin.contracts import (
    COUNTERWEIGHTS,
    ENGINE_TORQUE,
    KINEMATICS,
    ArticulatedOptions,
    PinSizeOptions,
)
from crankdyn.plugin.scene_inputs import (
    articulated_reciprocating_masses_kg,
    engine_layout,
    rod_offset_m,
    rotating_mass_per_crank_kg,
    slave_geometries,
)
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

from .means import add_shaft_loads, means_records, remedy_summary, residual_after_means
from .notation import plain_symbol
from .options import LEAVE_SHARE, BalancingOptions, balance_orders_for
from .vectors import (
    CHECK_SAMPLES,
    NEGLIGIBLE,
    _fitted,
    bay_model_of,
    first_star_repeats,
    order_vectors,
    time_domain_check,
)

#: The scene table of the articulated rods, read for the mass rotating with a crank pin.
ARTICULATED = "articulated"


#: The orders an offset crank-slider's tables show unless the scene names them.
OFFSET_ORDERS = [1, 2, 3, 4, 5, 6]


#: The distance between the planes of two rods side by side on one crank pin over the bore, taken
#: when the scene gives none: one big-end bearing's width of the typical proportions (the
#: bearings section's sizes when the scene gives none).


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


def _time_table(theta, f_td, m_td, residual_F, residual_M, a) -> dict:
    """The stage's table: forces (and moments, with a spacing) over one turn, before and after balancing."""
    table = {"shaft_angle_deg": np.degrees(theta), "force_x_N": f_td.imag, "force_y_N": f_td.real}
    if a is not None:
        table.update({"moment_x_Nm": m_td.imag, "moment_y_Nm": m_td.real})
    table.update({"residual_force_x_N": residual_F.imag, "residual_force_y_N": residual_F.real})
    if a is not None:
        table.update(
            {"residual_moment_x_Nm": residual_M.imag, "residual_moment_y_Nm": residual_M.real}
        )
    return table


def inertia_masses(scene, layout, offset_ratio: float = 0.0) -> tuple[bal.Masses, float | None]:
    """(masses, a slave cylinder's reciprocating mass in kg or None without articulated rods).
    Reciprocating mass m_s = piston group + the rod's share at the pin (kg; articulated rods: the
    master cylinder's, with the slave rods' shares at its piston pin; a slave cylinder's is its
    piston group and the slave rod's share) and rotating mass m_R per crank, kg (crank pin, webs
    and the rods' big-end shares: ``rotating_mass_per_crank_kg``); ``offset_ratio`` k = e/L of an
    offset crank-slider."""
    e = scene.engine
    R, lam, w = e.crank_radius_m, e.rod_ratio_value, e.angular_velocity_rad_s
    m_s, slave_kg = _plain_reciprocating_kg(scene), None
    articulated = (
        options(scene, ARTICULATED, ArticulatedOptions)
        if scene.engine.rod_type == "articulated"
        else None
    )
    if articulated is not None:
        m_s, slave_kg = articulated_reciprocating_masses_kg(scene, layout, articulated, ARTICULATED)
    m_R = rotating_mass_per_crank_kg(scene, layout, articulated, ARTICULATED)
    return bal.Masses(m_s, m_R, R, lam, w, offset_ratio), slave_kg


def _plain_reciprocating_kg(scene) -> float:
    """The piston group with the rod's share at its pin, kg (the forces section's m_s; an
    articulated master rod's without the slave rods' shares)."""
    e, m = scene.engine, scene.masses
    rod_rec, _ = phys.rod_mass_split_kg(m.rod, e.rod_length_m, scene.rod_cm_from_big_end_m)
    return m.piston_group + float(rod_rec)


def _articulated_cylinders(scene, layout, g, masses, slave_kg: float, n_max: int):
    """The geometry and masses with every slave cylinder's own mass and own piston motion: its
    mass over the master's, its acceleration's harmonics over the master's (a slave piston's second
    harmonic is larger and out of phase) and its exact acceleration for the direct sum; the
    highest order raised to the one the slaves' harmonics still need. (geometry, masses, order)"""
    opts = options(scene, ARTICULATED, ArticulatedOptions)
    slaves = [geometry for _, geometry in slave_geometries(scene, layout, opts, ARTICULATED)]
    own = []  # each cylinder's slave geometry, by its place among its bay's slaves; None: master
    for c in layout.cylinders:
        bay_slaves = [x for x in layout.bay(c.bay) if not x.master]
        own.append(None if c.master else slaves[bay_slaves.index(c)])
    probe = [art.slave_acceleration_harmonics(x, 256, 2048) for x in slaves]
    needed = [n for n in range(2, 257) if any(abs(h[n]) > 1e-15 for h in probe)]
    n_max = max(n_max, max(needed, default=2))
    reference = bal.harmonics_for(masses.rod_ratio, n_max)
    ratio = np.ones((len(reference), len(own)), dtype=complex)
    for i, geometry in enumerate(own):
        if geometry is None:
            continue
        samples = 1024
        while samples <= 4 * len(reference):
            samples *= 2
        harmonics = art.slave_acceleration_harmonics(geometry, len(reference) - 1, samples)
        usable = np.abs(reference) > 0
        ratio[:, i] = np.where(usable, harmonics / np.where(usable, reference, 1.0), 0.0)
        ratio[0, i] = 1.0
    weights = np.array([1.0 if x is None else slave_kg / masses.reciprocating_kg for x in own])
    w = masses.angular_velocity_rad_s
    accelerations = tuple(
        None if x is None else partial(_slave_acceleration_m_s2, x, w) for x in own
    )
    g = replace(g, cylinder_weight=weights, cylinder_harmonic_ratio=ratio)
    return g, replace(masses, cylinder_accelerations=accelerations), n_max


def _rod_offset_couples(scene, opts, layout, g, masses, harmonics) -> dict | None:
    """Rods side by side on a crank pin (a V engine's central rods): the banks' cylinder axes lie
    one rod's width apart along the shaft, so their inertia forces give longitudinal couples
    though a crank's cylinders act on one pin; the tables take them in the crank's plane (as the
    textbook does). The couple this offset adds, of each order the tables show, summed over the
    cranks, N·m (amplitude, and its parts turning with and against the shaft), with bank 0
    nearest the free end; ``cranks`` the crank count. None for other rods (in one plane)."""
    offset, source = rod_offset_m(
        scene, layout, opts.rod_offset, options(scene, "bearings", PinSizeOptions)
    )
    if source == "none":
        return None
    banks = np.array([c.bank for c in layout.cylinders], dtype=float)
    planes = replace(g, cylinder_position=banks - 0.5 * (banks.max() + banks.min()))
    moments = []
    for n in sorted(set(opts.include_orders)):
        model = bal.scaled(bal.reciprocating_model(planes, n), harmonics[n] * masses.first_order_N)
        forward = abs(complex(model.moment_forward)) * offset
        backward = abs(complex(model.moment_backward)) * offset
        moments.append(
            {
                "order": n,
                "name": bal.roman(n),
                "moment_Nm": forward + backward,
                "forward_Nm": forward,
                "backward_Nm": backward,
            }
        )
    return {
        "offset_m": float(offset),
        "offset_given": source == "given",
        "offset_source": source,
        "moments": moments,
        "cranks": layout.cranks,
    }


def failed_check(scene, results=None) -> list[tuple[str, dict]]:
    """The direct sum of the real forces over the cycle left more than the orders the vector
    method analyses: the balance the note states holds for those orders only. Articulated rods
    whose knuckle pin lies off the bank angle give the slave pistons odd harmonics, which the
    orders of the central crank-slider leave out."""
    if not results or results["residual"]["vanishes"]:
        return []
    cause = "articulated" if _pins_off_axes(scene) else "orders"
    return [
        (
            "balancing.plausibility_check_failed_" + cause,
            {"force": results["residual"]["force_max_N"]},
        )
    ]


def better_firing(scene, results=None) -> list[tuple[str, dict]]:
    """A given firing order that leaves a force or moment another even-firing order of the same
    engine does not (:func:`better_firing_order`): most often an order written in another
    numbering of the cylinders than the calculation's."""
    better = (results or {}).get("better_firing")
    if not better:
        return []
    layout = engine_layout(scene)
    return [
        (
            "balancing.plausibility_better_firing",
            {
                "order": "–".join(layout.firing_order),
                "cranks": "; ".join(f"{x:g}" for x in layout.crank_lag_deg),
                "better": "–".join(better["firing_order"]),
                "better_cranks": "; ".join(f"{x:g}" for x in better["crank_angles_deg"]),
                # the explorer's keys are the summary's quantities: named as table 6.3 names them
                "freed": ", ".join(plain_symbol({"quantity": k}) for k in better["freed"]),
            },
        )
    ]


def _pins_off_axes(scene) -> bool:
    """Articulated rods with a knuckle pin off its slave cylinder's axis angle (γ₁ ≠ γ)."""
    if scene.engine.rod_type != "articulated":
        return False
    layout = engine_layout(scene)
    opts = options(scene, ARTICULATED, ArticulatedOptions)
    return any(
        abs(g.pin_angle_rad - g.bank_angle_rad) > 1e-9
        for _, g in slave_geometries(scene, layout, opts, ARTICULATED)
    )


def rod_offset_against_pin(scene, results=None) -> list[tuple[str, dict]]:
    """A given rod offset that a given crank-pin width contradicts: rods side by side on the pin
    each take its width over their number, so their planes lie that far apart (a tenth either
    way is let pass, for the bearings' chamfers and thrust faces)."""
    if scene.engine.rod_type != "central" or scene.engine.cylinders < 2:
        return []
    try:
        layout = engine_layout(scene)
    except SceneError:  # a layout the stages refuse, with their own message
        return []
    given = options(scene, "balancing", BalancingOptions).rod_offset
    sizes = options(scene, "bearings", PinSizeOptions)
    offset, source = rod_offset_m(scene, layout, given, sizes)
    pin = sizes.crank_pin_width
    if source != "given" or pin is None:
        return []
    width = brg.big_end_bearing_width_m(
        float(pin), brg.big_end_bearings_on_pin("central", layout.cylinders_per_bay)
    )
    if abs(offset - width) <= 0.1 * width:
        return []
    return [
        (
            "balancing.plausibility_rod_offset_pin",
            {
                "offset": offset * 1e3,
                "pin": float(pin) * 1e3,
                "rods": layout.cylinders_per_bay,
                "width": width * 1e3,
            },
        )
    ]


def _slave_results(
    g, masses, harmonics, slave_kg, left, dropped, spacing_m, opts, scene, layout
) -> dict:
    """Articulated rods: a slave cylinder's reciprocating mass, what the slave rods' shares add to
    the master's, the largest |A_2| of a cylinder's piston, what only the slave cylinders leave
    unbalanced (parts and whole orders) and the parts only they give which the means balance."""
    balanced = _slave_parts_balanced(g, opts, harmonics, left)
    plain_kg = _plain_reciprocating_kg(scene)
    return {
        "slave_reciprocating_mass_kg": slave_kg,
        "slave_pins_master_share_kg": (
            None if slave_kg is None else masses.reciprocating_kg - plain_kg
        ),
        "slave_second_harmonic_max": _slave_second_harmonic_max(
            g, harmonics, [c.master for c in layout.cylinders]
        ),
        "parts_left": _parts_left_results(g, masses, harmonics, left, spacing_m),
        "orders_left_for_masses": dropped,
        "slave_parts_balanced": _parts_left_results(g, masses, harmonics, balanced, spacing_m),
    }


def _slave_second_harmonic_max(g, harmonics, masters: list[bool]) -> float | None:
    """The largest |A_2| of a slave piston's acceleration (a radial's slaves exceed the master's,
    a V engine's slave on a pin at the bank angle falls short of it); None where every cylinder
    moves as the reference does."""
    slaves = [i for i, master in enumerate(masters) if not master]
    if g.cylinder_harmonic_ratio is None or not slaves:
        return None
    ratios = np.abs(np.asarray(g.cylinder_harmonic_ratio[2])[slaves])
    return float(np.max(ratios)) * abs(float(harmonics[2]))


def _slave_acceleration_m_s2(geometry, angular_velocity_rad_s: float, alpha_rad):
    """A slave piston's acceleration, m/s^2, positive towards the shaft at its nominal TDC, at its
    crank angle ``alpha_rad`` from its own axis."""
    motion = art.slave_motion(
        np.asarray(alpha_rad) + geometry.bank_angle_rad, geometry, angular_velocity_rad_s
    )
    return -motion.piston_acceleration_m_s2


def _slave_only_parts(g, orders, harmonics) -> list[tuple[int, float]]:
    """(signed speed, size in C_I) of each rotating part of ``orders`` that only the slave
    cylinders give (+n the co-rotating part of order n, -n the counter-rotating one): nil where
    the cylinders are alike, not nil as they are; none without articulated rods."""
    if g.cylinder_weight is None:
        return []
    scale = 1e-9 * g.cylinders
    alike = replace(g, cylinder_weight=None, cylinder_harmonic_ratio=None)
    parts = []
    for n in orders:
        equal, real = bal.reciprocating_model(alike, n), bal.reciprocating_model(g, n)
        for speed, part in ((n, "forward"), (-n, "backward")):
            if _part_negligible(equal, part, scale) and not _part_negligible(real, part, scale):
                size = abs(complex(getattr(real, f"force_{part}"))) * abs(harmonics[n])
                parts.append((speed, size))
    return parts


def _parts_left(g, opts, means_given: bool, harmonics) -> tuple[int, ...]:
    """The rotating parts of the balanced orders that are left unbalanced (signed speeds, as
    :func:`_slave_only_parts`): those only the slave cylinders give, under :data:`LEAVE_SHARE`
    of C_I, unless the scene chose the balancing means."""
    if means_given:
        return ()
    parts = _slave_only_parts(g, opts.balance_orders, harmonics)
    return tuple(speed for speed, size in parts if size < LEAVE_SHARE)


def _slave_parts_balanced(g, opts, harmonics, left) -> tuple[int, ...]:
    """The rotating parts of the balanced orders that only the slave cylinders give, as the
    parts left are, but which the means balance: too large to leave (:data:`LEAVE_SHARE`), or
    balanced as the scene chose."""
    parts = _slave_only_parts(g, opts.balance_orders, harmonics)
    return tuple(speed for speed, _ in parts if speed not in left)


def _orders_left(g, opts, means_given: bool, harmonics):
    """(the options with the orders to balance, the rotating parts left, the orders left whole):
    an order whose every part only the slave cylinders give is left whole, as an order not
    balanced; a part of an order whose other part the means take is left on its own."""
    left = _parts_left(g, opts, means_given, harmonics)
    dropped = [n for n in opts.balance_orders if n in left and -n in left]
    if dropped:
        kept = [n for n in opts.balance_orders if n not in dropped]
        opts = opts.model_copy(update={"balance_orders": kept})
        left = tuple(speed for speed in left if abs(speed) not in dropped)
    return opts, left, dropped


def _parts_left_chosen(opts, left) -> tuple[int, ...]:
    """The rotating parts the scene chose to leave unbalanced (signed speeds, as
    :func:`_parts_left`): the first order's counter-rotating part with ``first_order_backward =
    "left"`` where the first order is balanced (its co-rotating part then goes to the
    counterweights or a shaft alone)."""
    if opts.first_order_backward == "left" and 1 in opts.balance_orders and -1 not in left:
        return (-1,)
    return ()


def _part_negligible(model, part: str, scale: float) -> bool:
    """Whether the co- (``part`` "forward") or counter-rotating part of an order's force and moment
    is nil to round-off ``scale`` (in units of the order's amplitude)."""
    force, moment = getattr(model, f"force_{part}"), getattr(model, f"moment_{part}")
    return abs(complex(force)) <= scale and abs(complex(moment)) <= scale


def _input_notes(opts, g, spacing_m, torque) -> list:
    """The notes on what the scene leaves out (no cylinder spacing, no cycle);
    a balance-shaft spacing without the cylinder spacing is refused."""
    notes: list[tuple[str, dict]] = []
    if opts.balance_shaft_spacing is not None and spacing_m is None and g.cranks > 1:
        raise SceneError(
            Problem(
                "balancing.balance_shaft_spacing",
                opts.balance_shaft_spacing,
                "needs engine.cylinder_spacing (the crank positions along the shaft)",
            )
        )
    if spacing_m is None and g.cranks > 1:
        notes.append(("balancing.note_no_spacing", {}))
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
    return {
        "acceleration_harmonics": {bal.roman(n): float(abs(harmonics[n])) for n in orders},
        "acceleration_harmonic_phases_deg": {
            bal.roman(n): math.degrees(np.angle(harmonics[n])) for n in orders
        },
    }


def _first_order_shares(absolute: dict, first_order_N: float, spacing_m) -> dict:
    """Each resultant's amplitude as a share of one cylinder's C_I (a moment's: of C_I·a; none
    without a spacing), keyed as ``absolute`` without its unit: what "negligible" is measured by."""
    shares = {}
    for key, value in absolute.items():
        force = key.endswith("_N")
        scale = first_order_N * (1.0 if force else spacing_m or 0.0)
        if scale > 0:
            shares[key.rsplit("_", 1)[0]] = float(abs(value) / scale)
    return shares


#: the options by which a scene chooses its balancing means (else the stage chooses and says so)
MEANS_FIELDS = frozenset(
    {
        "balance_orders",
        "counterweight_radius",
        "balance_shaft_radius",
        "counterweights",
        "first_order_backward",
    }
)


def run(scene, inputs) -> StageOutput:
    torque = inputs.get(ENGINE_TORQUE)  # only for the reaction-torque range; absent without a cycle
    opts = options(scene, "balancing", BalancingOptions)
    means_given = bool(opts.model_fields_set & MEANS_FIELDS)
    e = scene.engine
    layout = engine_layout(scene)
    g, k = _offset_geometry(bal.geometry_from_layout(layout), inputs[KINEMATICS], e.rod_length_m)
    opts = _offset_orders(opts, k).model_copy(
        update={"balance_orders": balance_orders_for(scene, opts)}
    )
    a = e.cylinder_spacing  # None: moments in units of a only
    masses, slave_kg = inertia_masses(scene, layout, k)
    n_max = bal.orders_needed(e.rod_ratio_value, offset_ratio=k)
    if slave_kg is not None:
        g, masses, n_max = _articulated_cylinders(scene, layout, g, masses, slave_kg, n_max)
    harmonics = bal.harmonics_for(e.rod_ratio_value, n_max, k)
    opts, left, dropped = _orders_left(g, opts, means_given, harmonics)
    slave_left, chosen = left, _parts_left_chosen(opts, left)
    left = left + chosen
    C, C_I = masses.centrifugal_N, masses.first_order_N
    notes = _input_notes(opts, g, a, torque)
    coefficients, absolute, orders = _order_vectors(g, opts, C, C_I, harmonics, a)
    all_orders = bal.inertia_orders(n_max, k)
    means, r_cw, r_sh = _design_means(opts, g, masses, harmonics, e.crank_radius_m, a, left)
    counterweights, shafts = means_records(g, means, r_cw, r_sh, a)
    add_shaft_loads(shafts, e.angular_velocity_rad_s)
    theta, f_td, m_td, check, residual_F, residual_M, residual = _time_domain(
        g,
        masses,
        harmonics,
        all_orders,
        means,
        opts.balance_orders,
        e.angular_velocity_rad_s,
        a,
        left,
    )

    summary = remedy_summary(orders, g, C, C_I, harmonics, opts, left)
    results = {
        **_masses_results(masses, harmonics, all_orders, k, e.rod_ratio_value),
        "cylinder_spacing_m": a,
        "vertical_axis_deg": g.vertical_deg,
        "coefficients": coefficients,
        "absolute": absolute,
        "first_order_shares": _first_order_shares(absolute, C_I, a),
        "orders": orders,
        "bay_model": bay_model_of(layout, g),
        "time_domain_check": check,
        "counterweight_radius_m": r_cw,
        #: whether the scene chose the balancing means; otherwise the note says it chose them
        "means_given": means_given,
        "balance_shaft_radius_m": r_sh,
        "counterweights": counterweights,
        "balance_shafts": shafts,
        "residual": residual,
        "summary": summary,
        "reaction_torque_range_Nm": float(np.ptp(torque.torque_Nm)) if torque is not None else None,
        "first_order_forward": opts.first_order_forward,
        "first_order_backward": opts.first_order_backward,
        #: the rotating parts the scene chose to leave (records as ``parts_left``'s)
        "parts_left_chosen": _parts_left_results(g, masses, harmonics, chosen, a),
        **_geometry_results(g, orders),
        "rod_type": e.rod_type,
        "rod_offset_couples": _rod_offset_couples(scene, opts, layout, g, masses, harmonics),
        **_internal_moment(g, C, a, summary),
        **_shaft_beside_couple(shafts, C_I),
        **_slave_results(
            g, masses, harmonics, slave_kg, slave_left, dropped, a, opts, scene, layout
        ),
        **_firing_order_results(scene, layout, opts),
    }

    notes += _articulated_note(e.rod_type, results, harmonics) + [_check_note(g, all_orders)]
    table = _time_table(theta, f_td, m_td, residual_F, residual_M, a)
    fitted = _fitted(counterweights, e.angular_velocity_rad_s, r_cw, shafts, r_sh)
    return StageOutput(
        data={COUNTERWEIGHTS: fitted}, results=results, tables={"balancing": table}, notes=notes
    )


def _check_note(g, all_orders) -> tuple[str, dict]:
    """The note on the time-domain check of the orders' sums."""
    key = "balancing.note_check_single" if len(g.labels) == 1 else "balancing.note_check"
    return key, {"orders": _orders_listed(all_orders), "samples": CHECK_SAMPLES}


def _internal_moment(g, C: float, spacing_m: float | None, summary: list[dict]) -> dict:
    """The largest internal moment of the centrifugal forces (:func:`bal.internal_moment_max`),
    N·m, and its coefficient of C·a, where the crank arrangement balances those forces and their
    moment (the ``summary``'s verdicts, which the tables print) and the engine has several cranks
    along a known spacing; None otherwise."""
    balanced = g.cranks > 1 and all(
        s["balanced"] for s in summary if s["quantity"] in ("sum_C", "M_C")
    )
    if not balanced or spacing_m is None:
        return {"internal_moment_coefficient": None, "internal_moment_Nm": None}
    coefficient = bal.internal_moment_max(g)
    return {
        "internal_moment_coefficient": coefficient,
        "internal_moment_Nm": coefficient * C * spacing_m,
    }


#: The distance between the shafts' axes a single cylinder's beside-shaft couple is given for, m
#: (the scene gives the balance shaft no place).
SHAFT_BESIDE_DISTANCE_M = 0.1


def _shaft_beside_couple(shafts: list[dict], C_I: float) -> dict:
    """A counter-rotating first-order shaft beside the crankshaft, with no co-rotating partner:
    its own force (:func:`add_shaft_loads`) and the backward part of P_I it cancels are equal and
    opposite but the shafts' distance apart, a couple of that force times the distance, N·m per
    :data:`SHAFT_BESIDE_DISTANCE_M` (``shaft_beside_couple_per_100mm_Nm``, with the shaft's force,
    ``shaft_beside_force_N``); both None otherwise, and where the shaft cancels a couple only
    (its force below :data:`NEGLIGIBLE` of C_I: a couple is moved freely)."""
    none = {"shaft_beside_force_N": None, "shaft_beside_couple_per_100mm_Nm": None}
    if any(s["order"] == 1 and s["speed_ratio"] > 0 for s in shafts):
        return none
    backward = [s for s in shafts if s["order"] == 1 and s["speed_ratio"] < 0]
    if not backward or backward[0]["force_N"] <= NEGLIGIBLE * C_I:
        return none
    force = backward[0]["force_N"]
    return {
        "shaft_beside_force_N": force,
        "shaft_beside_couple_per_100mm_Nm": force * SHAFT_BESIDE_DISTANCE_M,
    }


def _articulated_note(rod_type: str, results: dict, harmonics) -> list:
    """The method note of articulated rods: the slave pistons' second harmonic larger than the
    master's (a radial's) or smaller (a V engine's knuckle pin at the bank angle)."""
    if rod_type != "articulated":
        return []
    second = results["slave_second_harmonic_max"]
    smaller = second is not None and second < abs(float(harmonics[2]))
    return [("balancing.note_articulated" + ("_smaller" if smaller else ""), {})]


def _order_vectors(g, opts, C: float, C_I: float, harmonics, spacing_m):
    """(coefficients, absolute values, per-order records) of the vector models of the centrifugal
    forces and of every inertia order included or balanced."""
    models = {0: bal.rotating_model(g)}
    for n in sorted(set(opts.include_orders) | set(opts.balance_orders)):
        models[n] = bal.reciprocating_model(g, n)
    return order_vectors(g, models, opts.include_orders, C, C_I, harmonics, spacing_m)


def _orders_listed(orders) -> str:
    """The orders the vector method sums, as a note lists them: "1, 2, 4, … 18" (a central
    crank-slider's even series), "1, 2, 3, … 17" (an offset one's odd orders too)."""
    shown = [str(n) for n in orders]
    return ", ".join(shown) if len(shown) <= 4 else ", ".join(shown[:3]) + ", … " + shown[-1]


def _parts_left_results(g, masses, harmonics, left, spacing_m) -> list[dict]:
    """The rotating parts left unbalanced (:func:`_parts_left`): order, sense, amplitude (N; a
    moment's N·m, none without a spacing) and share of one cylinder's C_I."""
    out = []
    for speed in left:
        n = abs(speed)
        model = bal.scaled(bal.reciprocating_model(g, n), harmonics[n] * masses.first_order_N)
        force, moment = (
            (model.force_forward, model.moment_forward)
            if speed > 0
            else (model.force_backward, model.moment_backward)
        )
        out.append(
            {
                "order": n,
                "name": bal.roman(n),
                "sense": "forward" if speed > 0 else "backward",
                "force_N": float(abs(complex(force))),
                "moment_Nm": (
                    float(abs(complex(moment))) * spacing_m if spacing_m is not None else None
                ),
                "share_of_first_order": float(abs(complex(force))) / masses.first_order_N,
            }
        )
    return out


def _time_domain(
    g, masses, harmonics, all_orders, means, balance_orders, omega, spacing_m, left=()
):
    """The checks at :data:`CHECK_SAMPLES` shaft angles a revolution: the real forces summed
    cylinder by cylinder against the vector method, and what the means leave of them. (angles,
    force and moment sums, the check, residual force and moment, the residual's record)"""
    theta = 2 * np.pi * np.arange(CHECK_SAMPLES) / CHECK_SAMPLES
    spacing = spacing_m if spacing_m is not None else 1.0
    f_td, m_td, scale_F, scale_M, check = time_domain_check(
        g, masses, harmonics, all_orders, theta, spacing, spacing_m
    )
    residual_F, residual_M, residual = residual_after_means(
        g,
        masses,
        harmonics,
        means,
        theta,
        omega,
        spacing,
        f_td,
        m_td,
        all_orders,
        balance_orders,
        scale_F,
        scale_M,
        spacing_m,
        left,
    )
    return theta, f_td, m_td, check, residual_F, residual_M, residual


def _design_means(opts, g, masses, harmonics, crank_radius_m: float, spacing_m, left=()):
    """(the balancing means the options ask for, counterweights' and balance shafts' radii, m):
    the shafts at ``balance_shaft_spacing`` apart about the middle of a shaft of several cranks;
    the radii default to R and R/2."""
    shaft_positions = None
    if opts.balance_shaft_spacing is not None and g.cranks > 1:
        half = 0.5 * opts.balance_shaft_spacing / spacing_m
        shaft_positions = (-half, half)
    means = bal.design_means(
        g,
        masses,
        harmonics,
        opts.balance_orders,
        opts.counterweights,
        opts.first_order_forward,
        shaft_positions,
        leave=left,
    )
    r_cw = opts.counterweight_radius if opts.counterweight_radius is not None else crank_radius_m
    r_sh = (
        opts.balance_shaft_radius if opts.balance_shaft_radius is not None else 0.5 * crank_radius_m
    )
    return means, r_cw, r_sh


def _masses_results(masses, harmonics, all_orders, offset_ratio: float, rod_ratio: float) -> dict:
    """The masses, the amplitudes C, C_I, C_II (textbook and exact) and the acceleration series."""
    C_I = masses.first_order_N
    exact_second = float(abs(harmonics[2])) * C_I
    return {
        "reciprocating_mass_kg": masses.reciprocating_kg,
        "rotating_mass_kg": masses.rotating_kg,
        "centrifugal_N": masses.centrifugal_N,
        "first_order_N": C_I,
        "second_order_N": masses.second_order_textbook_N,  # textbook C_II = lambda C_I (eq. 56)
        # exact: the second harmonic A_2 C_I of the exact inertia force (the P_II of ``orders``)
        "second_order_exact_N": exact_second,
        "second_order_difference_relative": exact_second / masses.second_order_textbook_N - 1.0,
        **_harmonics_json(harmonics, all_orders),
        "offset_ratio": offset_ratio,
        "acceleration_series": {
            bal.roman(n): v for n, v in bal.acceleration_series(rod_ratio).items()
        },
    }


def _geometry_results(g, orders) -> dict:
    """The geometry of the diagrams: crank directions, cylinder axes and phases, labels, bays;
    the orders whose moments repeat the first order's star (:func:`_first_star_repeats`)."""
    return {
        "first_star_repeats": _first_star_repeats(g, orders),
        "crank_directions_deg": [math.degrees(x) % 360.0 for x in g.crank_direction_rad],
        "cylinder_axes_deg": [math.degrees(x) for x in g.cylinder_axis_rad],
        "cylinder_phases_deg": [math.degrees(x) % 360.0 for x in g.cylinder_phase_rad],
        "cylinder_labels": list(g.labels),
        "cylinder_bays": [int(b) for b in g.cylinder_bay],
    }


def better_firing_order(scene, layout) -> dict:
    """``{"better_firing": ...}``: the best-balanced even-firing order of the engine, when the
    scene's own order leaves a force or moment that it does not
    (:func:`crankdyn.physics.firing_explorer.better_balanced`): its order and cranks and the
    quantities it frees the engine of. Empty for an order the calculation chose, uneven firing,
    a radial and searches too large to run with every report."""
    e = scene.engine
    if scene.firing_order_chosen or not layout.even_firing or e.layout == "radial":
        return {}
    if not fe.small_search(layout.cranks):
        return {}
    found = fe.better_balanced(
        e.cylinders,
        e.layout,
        e.strokes,
        e.bank_angle_deg,
        layout.crank_lag_deg,
        layout.firing_order,
    )
    if found is None:
        return {}
    best, freed = found
    return {
        "better_firing": {
            "firing_order": list(best.firing_order),
            "crank_angles_deg": list(best.crank_angles_deg),
            "freed": list(freed),
        }
    }


def _firing_order_results(scene, layout, opts) -> dict:
    """The explorer's ranking where the scene asks for it, and a better-balanced order than
    the scene's where one exists (:func:`better_firing_order`)."""
    out = better_firing_order(scene, layout)
    if opts.explore:
        out["explorer"] = _explore(scene.engine, layout, opts.explore_top)
    return out


def _first_star_repeats(g, orders) -> list[dict]:
    """[{order, sign}] of an in-line engine's orders (the second and higher) whose moment is not
    nil and whose star of phases repeats (+1) or mirrors (−1) the first order's, when the
    first order's moment is not nil either (:func:`.vectors.first_star_repeats`)."""
    by_order = {int(o["order"]): o for o in orders}
    cylinders = len(g.labels)
    first = by_order.get(1)
    if (
        cylinders < 3
        or np.any(np.abs(np.asarray(g.cylinder_axis_rad)) > 1e-12)
        or first is None
        or first["moment_coefficient"] <= NEGLIGIBLE * cylinders
    ):
        return []
    higher = [
        n
        for n, o in by_order.items()
        if n >= 2 and o["moment_coefficient"] > NEGLIGIBLE * cylinders
    ]
    repeats = first_star_repeats(np.degrees(np.asarray(g.cylinder_phase_rad)), higher)
    return [{"order": n, "sign": sign} for n, sign in sorted(repeats.items())]


def _explore(e, layout, top: int) -> dict:
    result = fe.explore(
        e.cylinders,
        e.layout,
        e.strokes,
        e.bank_angle_deg,
        top=top,
        locate=(tuple(layout.crank_lag_deg), tuple(layout.firing_order)),
    )
    return explorer_json(result)


def explorer_json(result: fe.Exploration) -> dict:
    """An explorer result as JSON (also used by ``crankdyn explore --json``)."""

    def row(c: fe.Candidate) -> dict:
        return {
            "rank": c.rank,
            "crank_angles_deg": list(c.crank_angles_deg),
            "firing_order": list(c.firing_order),
            "coefficients": c.coefficients,
            "neighbours": c.neighbours,
            "same_pin": c.same_pin,
            "same_half": c.same_half,
        }

    return {
        "cylinders": result.cylinders,
        "layout": result.layout,
        "strokes": result.strokes,
        "bank_angle_deg": result.bank_angle_deg,
        "interval_deg": result.interval_deg,
        "arrangements": result.arrangements,
        "firing_orders": result.firing_orders,
        "scored_firing_orders": result.scored_firing_orders,
        "reason": None if result.reason is None else str(result.reason),
        "reason_code": None if result.reason is None else result.reason.code,
        "reason_values": None if result.reason is None else result.reason.values,
        "rows": [row(c) for c in result.rows],
        "scene_rank": result.located_rank,
        "scene": row(result.located) if result.located else None,
    }
