"""Vector (polar) load diagrams of crank pins, main journals and their bearings (Poda 2007 §5).


The computation: ``applies``, ``run`` and their pure helpers.
"""

from __future__ import annotations

import math

import numpy as np

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import bearings as brg
from crankdyn.physics import layout as lay
from crankdyn.physics.balancing import vertical_axis_deg
from crankdyn.physics.extrema import first_argmax
from crankdyn.plugin.contracts import (
    BAY_LOADS,
    COUNTERWEIGHTS,
    CRANK_LOADS,
    FORCES,
    KINEMATICS,
    RodOffsetOptions,
)
from crankdyn.plugin.scene_inputs import rod_offset_m
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

from .options import BearingOptions

# Typical proportions (fractions of the bore / of the journal diameter) for car and tractor
# engines (Kolchin and Demidov), used when the scene gives no journal dimensions; the crank pin's
# are the shared library's (physics.bearings.crank_pin_size_m).
DEFAULT_MAIN_DIAMETER_PER_BORE = 0.70

DEFAULT_MAIN_WIDTH_PER_DIAMETER = 0.45

#: Allowable specific loads of crank-pin bearings, MPa: (mean, largest) for petrol engines and
#: for diesels (Kolchin and Demidov, the wear diagram of the crank pin: mean 4-12 MPa and largest
#: 7-20 MPa in petrol engines, mean 6-16 MPa and largest 20-42 MPa in diesels; the upper ends
#: are the limits). An engine of unknown ignition (a measured trace) is judged as a diesel.
ALLOWABLE_PIN_PRESSURE_MPA = {"spark": (12.0, 20.0), "diesel": (16.0, 42.0)}

#: Allowable specific loads of main bearings, MPa: (mean, largest) for petrol engines and for
#: diesels (Kolchin and Demidov, the main journals: mean 4-12 MPa and largest up to 20 MPa in
#: petrol engines, mean 6-16 MPa and largest 20-40 MPa in diesels; the upper ends are the
#: limits). An engine of unknown ignition (a measured trace) is judged as a diesel.
ALLOWABLE_MAIN_PRESSURE_MPA = {"spark": (12.0, 20.0), "diesel": (16.0, 40.0)}

ALLOWABLE_PRESSURE_SOURCE = "kolchin2002"


def _ignition_kind(scene) -> str:
    """ "spark" or "diesel" (an engine of unknown ignition, a measured trace, is judged as a
    diesel)."""
    ignition = getattr(scene.cycle, "ignition", None) if scene.cycle is not None else None
    return "spark" if ignition == "spark" else "diesel"


def pin_area_needed_m2(pins, kind: str) -> float:
    """The crank pin's projected area d·B at which the most loaded pin's mean and largest bearing
    pressures (p = Q/(d·B)) are the allowable ones of its kind of engine."""
    mean_limit, max_limit = ALLOWABLE_PIN_PRESSURE_MPA[kind]
    return max(
        max(pin["mean_N"] for pin in pins) / (mean_limit * 1e6),
        max(pin["max_N"] for pin in pins) / (max_limit * 1e6),
    )


def _pin_pressure(scene, results=None) -> list[tuple[str, dict]]:
    """The most loaded crank pin's (with several big-end bearings side by side on it, the most
    loaded of these bearings') mean and largest pressure against the allowable ones of its kind
    of engine (:data:`ALLOWABLE_PIN_PRESSURE_MPA`)."""
    pins = (results or {}).get("crank_pins")
    if not pins:
        return []
    per_pin = results.get("rod_bearings_per_pin", 1)
    loaded = pins if per_pin == 1 else results["rod_bearings"]
    kind = _ignition_kind(scene)
    mean_limit, max_limit = ALLOWABLE_PIN_PRESSURE_MPA[kind]
    p_mean = max(x["mean_MPa"] for x in loaded)
    p_max = max(x["max_MPa"] for x in loaded)
    if p_mean <= mean_limit and p_max <= max_limit:
        return []
    sizes = results.get("dimensions") or {}
    diameter_m, width_m = sizes.get("crank_pin_diameter_m"), sizes.get("crank_pin_width_m")
    if per_pin == 1:
        area_needed_m2 = sizes.get("crank_pin_area_needed_m2") or pin_area_needed_m2(pins, kind)
    else:  # one bearing's d·B and width, as the section gives them
        area_needed_m2 = sizes.get("rod_bearing_area_needed_m2") or pin_area_needed_m2(loaded, kind)
        width_m = loaded[0].get("width_m")
    params = {
        "p_mean": float(p_mean),
        "p_max": float(p_max),
        "mean_limit": mean_limit,
        "max_limit": max_limit,
        "source": ALLOWABLE_PRESSURE_SOURCE,
        "area_needed": area_needed_m2 * 1e6,
    }
    if diameter_m and width_m:
        params.update(
            diameter=diameter_m * 1e3,
            width=width_m * 1e3,
            width_needed=area_needed_m2 / diameter_m * 1e3,
        )
    # rods side by side: B is each big-end bearing's, and the pin carries them all
    side_by_side = per_pin > 1 and "width_needed" in params
    if side_by_side:
        length_m = sizes.get("crank_pin_length_needed_m") or per_pin * area_needed_m2 / diameter_m
        params.update(n=per_pin, pin_width_needed=length_m * 1e3)
    # sizes assumed from typical ratios: the verdict is said to rest on them
    assumed = bool({"crank_pin_diameter", "crank_pin_width"} & set(sizes.get("defaulted", ())))
    key = (
        "bearings.plausibility_pin_pressure_"
        + ("side_by_side_" if side_by_side else "")
        + kind
        + ("_assumed" if assumed else "")
    )
    return [(key, params)]


def _journals_fit(scene, results=None) -> list[tuple[str, dict]]:
    """A shaft with a main journal between every two cranks needs the crank pin's width and the
    main journal's in one crank pitch, the cylinder spacing a, with room for the two webs: where
    the two widths alone exceed a, the journals of the section do not fit the shaft (widths
    assumed from typical ratios of the bore, or given); nothing for one crank or no a."""
    sizes = (results or {}).get("dimensions") or {}
    pins = (results or {}).get("crank_pins") or []
    spacing_m = scene.engine.cylinder_spacing
    pin_m, main_m = sizes.get("crank_pin_width_m"), sizes.get("main_journal_width_m")
    if len(pins) < 2 or spacing_m is None or not pin_m or not main_m:
        return []
    if pin_m + main_m <= spacing_m:
        return []
    # both widths assumed from the bore: the note says so (one given: neither is claimed)
    assumed = {"crank_pin_width", "main_journal_width"} <= set(sizes.get("defaulted", ()))
    params = {
        "pin": pin_m * 1e3,
        "main": main_m * 1e3,
        "total": (pin_m + main_m) * 1e3,
        "spacing": spacing_m * 1e3,
    }
    return [("bearings.plausibility_journals_fit" + ("_assumed" if assumed else ""), params)]


def _main_pressure(scene, results=None) -> list[tuple[str, dict]]:
    """The most loaded main bearing's mean and largest pressure against the allowable ones of
    the engine's kind, on the console (``crankdyn check``, ``report``) as the crank pin's are;
    the section and the conclusions word the verdict themselves (:func:`main_pressure_verdict`)."""
    verdict = main_pressure_verdict(scene, results or {})
    if verdict is None or not verdict["exceeded"]:
        return []
    sizes = (results or {}).get("dimensions") or {}
    assumed = bool(
        {"main_journal_diameter", "main_journal_width"} & set(sizes.get("defaulted", ()))
    )
    params = {
        "journal": verdict["mean_journal"]["journal"],
        "p_mean": float(verdict["p_mean"]),
        "p_max": float(verdict["p_max"]),
        "mean_limit": verdict["mean_limit"],
        "max_limit": verdict["max_limit"],
        "area_needed": verdict["area_needed_m2"] * 1e6,
    }
    key = "bearings.plausibility_main_pressure_" + verdict["kind"] + ("_assumed" if assumed else "")
    return [(key, params)]


def pin_pressure_within_limits(scene, results) -> dict | None:
    """The most loaded big-end bearing's mean and largest pressure, MPa, with the allowable ones
    of its kind of engine (``kind``: spark or diesel), where both are within them; None where
    they are not (the plausibility rule says so) or there are no crank pins."""
    pins = results.get("crank_pins")
    if not pins:
        return None
    loaded = pins if results.get("rod_bearings_per_pin", 1) == 1 else results["rod_bearings"]
    kind = _ignition_kind(scene)
    mean_limit, max_limit = ALLOWABLE_PIN_PRESSURE_MPA[kind]
    p_mean = max(x["mean_MPa"] for x in loaded)
    p_max = max(x["max_MPa"] for x in loaded)
    if p_mean > mean_limit or p_max > max_limit:
        return None
    return {
        "kind": kind,
        "p_mean": p_mean,
        "p_max": p_max,
        "mean_limit": mean_limit,
        "max_limit": max_limit,
    }


def main_pressure_verdict(scene, results) -> dict | None:
    """The main bearings' largest mean and largest peak pressure, MPa (each with its journal,
    the first of equal ones to the printed 0.01 MPa: its record), against the allowable ones of the engine's
    kind (:data:`ALLOWABLE_MAIN_PRESSURE_MPA`): ``exceeded`` is "", "mean", "max" or "both";
    ``area_needed_m2`` the journal's d·B at which both are allowable. None without journals."""
    journals = results.get("main_journals")
    if not journals:
        return None
    kind = _ignition_kind(scene)
    mean_limit, max_limit = ALLOWABLE_MAIN_PRESSURE_MPA[kind]
    by_mean = _first_largest(journals, "mean_MPa")
    by_max = _first_largest(journals, "max_MPa")
    over_mean = by_mean["mean_MPa"] > mean_limit
    over_max = by_max["max_MPa"] > max_limit
    exceeded = {(False, False): "", (True, False): "mean", (False, True): "max"}.get(
        (over_mean, over_max), "both"
    )
    return {
        "kind": kind,
        "p_mean": by_mean["mean_MPa"],
        "mean_journal": by_mean,
        "p_max": by_max["max_MPa"],
        "max_journal": by_max,
        "mean_limit": mean_limit,
        "max_limit": max_limit,
        "exceeded": exceeded,
        "area_needed_m2": max(
            max(j["mean_N"] for j in journals) / (mean_limit * 1e6),
            max(j["max_N"] for j in journals) / (max_limit * 1e6),
        ),
    }


def _allowable_results(scene, results) -> dict:
    """The allowable pressures the engine's kind has (MPa, :data:`ALLOWABLE_PIN_PRESSURE_MPA`,
    :data:`ALLOWABLE_MAIN_PRESSURE_MPA`), what the main bearings exceed and the journal's d·B
    they need (m²), as the section and the conclusions state them."""
    kind = _ignition_kind(scene)
    verdict = main_pressure_verdict(scene, results)
    return {
        "kind": kind,
        "crank_pin_MPa": list(ALLOWABLE_PIN_PRESSURE_MPA[kind]),
        "main_journal_MPa": list(ALLOWABLE_MAIN_PRESSURE_MPA[kind]),
        "main_exceeded": verdict["exceeded"] if verdict else "",
        "main_area_needed_m2": verdict["area_needed_m2"] if verdict else None,
    }


def _first_largest(records: list[dict], key: str) -> dict:
    """The record of the largest ``key`` value, the first of those equal to the printed 0.01."""
    top = max(round(x[key], 2) for x in records)
    return next(x for x in records if round(x[key], 2) == top)


def applies(scene) -> str | None:
    if scene.masses is None:
        return "the scene has no [masses]"
    return None


def _dimensions(scene, opts, rods_per_pin: int = 1):
    """(d_pin, w_pin, d_main, w_main, the names of those assumed): the scene's sizes, or the
    typical proportions; a pin of ``rods_per_pin`` rods side by side gives each its own width."""
    bore = scene.engine.bore
    d_pin, w_pin = brg.crank_pin_size_m(
        bore, rods_per_pin, opts.crank_pin_diameter, opts.crank_pin_width
    )
    d_main = opts.main_journal_diameter or brg.drawn_size_m(DEFAULT_MAIN_DIAMETER_PER_BORE * bore)
    w_main = opts.main_journal_width or brg.drawn_size_m(DEFAULT_MAIN_WIDTH_PER_DIAMETER * d_main)
    defaulted = [
        name
        for name in (
            "crank_pin_diameter",
            "crank_pin_width",
            "main_journal_diameter",
            "main_journal_width",
        )
        if getattr(opts, name) is None
    ]
    return d_pin, w_pin, d_main, w_main, defaulted


def rod_bearing_name(crank: int, place: int | None) -> str:
    """The tables' name of a big-end bearing: "rod_bearing2" of crank pin 2's one bearing,
    "rod_bearing2_1" of the first of several side by side on it (``place`` from 1)."""
    return f"rod_bearing{crank}" + ("" if place is None else f"_{place}")


def _rod_columns(rods, per_pin: int) -> dict:
    """The big-end bearings' t and z columns (Pa), by :func:`rod_bearing_name`."""
    columns = {}
    for i, (k, _, t, z) in enumerate(rods):
        name = rod_bearing_name(k + 1, None if per_pin == 1 else i % per_pin + 1)
        columns.update({f"{name}_t_Pa": t, f"{name}_z_Pa": z})
    return columns


def _tables(angle, pin, rod_columns, journal, bearing, wear_pins, wear_journals) -> dict:
    """The stage's tables: every pin, rod bearing, journal and main bearing load (t, z components
    in Pa, per crank angle), and the wear diagrams (N per surface angle)."""
    cranks = len(pin[0])
    table = {"crank_angle_deg": angle}
    for k in range(cranks):
        table.update({f"pin{k + 1}_t_Pa": pin[0][k], f"pin{k + 1}_z_Pa": pin[1][k]})
    table.update(rod_columns)
    for j in range(cranks + 1):
        table.update(
            {
                f"journal{j}_t_Pa": journal[0][j],
                f"journal{j}_z_Pa": journal[1][j],
                f"main_bearing{j}_t_Pa": bearing[0][j],
                f"main_bearing{j}_z_Pa": bearing[1][j],
            }
        )
    wear = {"surface_angle_deg": wear_pins[0][0]}
    for k in range(cranks):
        wear[f"pin{k + 1}_wear_N"] = wear_pins[k][1]
    for j in range(cranks + 1):
        wear[f"journal{j}_wear_N"] = wear_journals[j][1]
    return {"bearings": table, "wear": wear}


def _counterweight_loads_Pa(fitted, cranks: int, area_m2: float) -> tuple[np.ndarray, np.ndarray]:
    """Per-crank (t, z) of the fitted counterweights (:class:`crankdyn.plugin.contracts.Counterweights`)
    per piston area [Pa]; zeros without counterweights (none fitted, or no balancing in the plan)."""
    if fitted is None:
        return np.zeros(cranks), np.zeros(cranks)
    return brg.counterweight_crank_load_Pa(
        fitted.crank,
        np.asarray(fitted.centrifugal_N) / area_m2,
        fitted.angle_from_crank_rad,
        cranks,
    )


def _rod_angle(motion, local_rad, revolution: int):
    """beta at the crank's angles ``local_rad`` from the cylinder axis (0 without a rod: a Scotch
    yoke's pin bears on the slider, along the cylinder axis)."""
    if motion.rod_angle_rad is None:
        return 0.0
    return np.interp(
        np.degrees(local_rad),
        motion.crank_angle_deg[:revolution],
        motion.rod_angle_rad[:revolution],
        period=360.0,
    )


def _pin_loads(loads, bays):
    """(pin t, pin z), each (cranks, N): the rods' load on each crank pin in crank axes."""
    return brg.crank_pin_load(loads.tangential_Pa, loads.radial_Pa, bays.centrifugal_rod_Pa)


def _master_rod_bearings(pin_t, pin_z, angle, motion, layout) -> list[tuple]:
    """(crank, cylinder, t, z) of the one big-end bearing of each crank pin (a single rod, a fork
    rod or a master rod), carrying the whole pin load, in its rod's axes."""
    master = layout.bay(0)[0]
    revolution = int(round(360 / (angle[1] - angle[0])))
    # the crank's angle from the cylinder axis is alpha + this (an offset crank-slider's phi_TDC)
    tdc = motion.extra.get("crank_angle_at_tdc_rad", 0.0)
    out = []
    for k in range(layout.cranks):
        # Each bay's master rod sees its crank at its own cycle angle.
        delay = layout.bay(k)[0].firing_delay_deg - master.firing_delay_deg
        local = np.radians((angle - delay) % 360.0)
        beta = _rod_angle(motion, local, revolution)
        rod_t, rod_z = brg.rod_bearing_load(pin_t[k], pin_z[k], local + tdc, beta)
        out.append((k, layout.bay(k)[0].label, rod_t, rod_z))
    return out


def _own_rod_pin_forces(forces, bays, motion, layout, step_deg: float) -> list[tuple]:
    """(crank, cylinder, t, z + c_r, local crank angle, rod angle) of every central rod side by
    side on a shared pin: its own cylinder's forces (shifted to its cycle delay, as the bays sum
    them) and its own rod's centrifugal force, on the pin in the crank's axes."""
    angle = motion.crank_angle_deg
    revolution = int(round(360 / (angle[1] - angle[0])))
    tdc = motion.extra.get("crank_angle_at_tdc_rad", 0.0)
    c_one_rod = bays.centrifugal_rod_Pa / layout.cylinders_per_bay
    out = []
    for k in range(layout.cranks):
        for c in layout.bay(k):
            shift = lay.grid_shift(c.firing_delay_deg, step_deg)
            local = np.radians((angle - c.firing_delay_deg) % 360.0)
            pin_t, pin_z = brg.crank_pin_load(
                np.roll(forces.tangential_Pa, shift), np.roll(forces.radial_Pa, shift), c_one_rod
            )
            beta = _rod_angle(motion, local, revolution)
            out.append((k, c.label, pin_t, pin_z, local + tdc, beta))
    return out


def _own_rod_bearings(pin_forces: list[tuple]) -> list[tuple]:
    """(crank, cylinder, t, z) of every big-end bearing of central rods side by side on shared
    pins (:func:`_own_rod_pin_forces`), in its own rod's axes."""
    return [
        (k, label, *brg.rod_bearing_load(t, z, crank_angle, beta))
        for k, label, t, z, crank_angle, beta in pin_forces
    ]


def _rod_bearings(scene, inputs, pin_t, pin_z) -> tuple[list[tuple], int, list[tuple]]:
    """(the big-end bearings' (crank, cylinder, t, z), the number of bearings on one pin, each
    rod's (crank, cylinder, t, z) on the pin in crank axes where several share it, else [])."""
    bays, motion = inputs[BAY_LOADS], inputs[KINEMATICS]
    layout = bays.layout
    per_pin = brg.big_end_bearings_on_pin(scene.engine.rod_type, layout.cylinders_per_bay)
    if per_pin == 1:
        return _master_rod_bearings(pin_t, pin_z, motion.crank_angle_deg, motion, layout), 1, []
    step = scene.analysis.angle_step_deg
    pin_forces = _own_rod_pin_forces(inputs[FORCES], bays, motion, layout, step)
    on_pin = [(k, label, t, z) for k, label, t, z, _, _ in pin_forces]
    return _own_rod_bearings(pin_forces), per_pin, on_pin


def _rod_bearing_results(rods, per_pin: int, area, d_pin, w_pin, angle) -> list[dict]:
    """Each big-end bearing's summary: one per crank pin; with several side by side, one per rod
    (its cylinder, its width B/n), with the angles of its largest and smallest loads."""
    if per_pin == 1:
        return [
            {"crank": k + 1, **brg.polar_summary(t, z, area, d_pin, w_pin)} for k, _, t, z in rods
        ]
    width = brg.big_end_bearing_width_m(w_pin, per_pin)
    return [
        {
            "crank": k + 1,
            "cylinder": label,
            "width_m": width,
            **brg.polar_summary(t, z, area, d_pin, width, angle),
        }
        for k, label, t, z in rods
    ]


def run(scene, inputs) -> StageOutput:
    loads, bays, motion = inputs[CRANK_LOADS], inputs[BAY_LOADS], inputs[KINEMATICS]
    opts = options(scene, "bearings", BearingOptions)
    layout = bays.layout
    cranks = layout.cranks
    angle = loads.crank_angle_deg
    area = loads.piston_area_m2
    rods_per_pin = brg.big_end_bearings_on_pin(scene.engine.rod_type, layout.cylinders_per_bay)
    d_pin, w_pin, d_main, w_main, defaulted = _dimensions(scene, opts, rods_per_pin)
    _check_drawn_numbers(opts, cranks)
    pin_t, pin_z = _pin_loads(loads, bays)
    rods, per_pin, on_pin = _rod_bearings(scene, inputs, pin_t, pin_z)
    planes_apart = _planes_apart_m(scene, layout, opts) if per_pin > 1 else 0.0
    spacing = scene.engine.cylinder_spacing
    rod_planes = _rod_planes(on_pin, per_pin, planes_apart, spacing, opts.span_ratio)
    # with the counterweights the balancing section fits (their centrifugal force on the webs)
    cw_t, cw_z = _counterweight_loads_Pa(inputs.get(COUNTERWEIGHTS), cranks, area)
    journal, bearing, centrifugal = _main_journal_loads(
        loads, motion, layout, (cw_t, cw_z), opts.span_ratio, rod_planes
    )
    pins, wear_pins = zip(
        *[
            _diagram_summary(pin_t[k], pin_z[k], d_pin, w_pin, area, angle, opts)
            for k in range(cranks)
        ],
        strict=True,
    )
    journals, wear_journals = zip(
        *[
            _diagram_summary(journal[0][j], journal[1][j], d_main, w_main, area, angle, opts)
            for j in range(cranks + 1)
        ],
        strict=True,
    )
    rod_results = _rod_bearing_results(rods, per_pin, area, d_pin, w_pin, angle)
    area_needed = pin_area_needed_m2(pins, _ignition_kind(scene))
    results = {
        # an offset crank-slider's crank is this far past the cylinder axis at TDC (0: central)
        "crank_angle_at_tdc_deg": math.degrees(motion.extra.get("crank_angle_at_tdc_rad", 0.0)),
        "dimensions": {
            **_dimension_results((d_pin, w_pin, d_main, w_main), defaulted, area_needed),
            **_rod_bearing_needed(rod_results, per_pin, d_pin, _ignition_kind(scene)),
        },
        #: the main bearings' y axis from cylinder 1's, deg (0: along it; a V's: half its bank angle)
        "main_bearing_frame_deg": main_bearing_frame_deg(layout),
        "crank_pins": [{"crank": k + 1, **pins[k]} for k in range(cranks)],
        "with_counterweights": bool(np.any(cw_t) or np.any(cw_z)),
        "counterweight_cranks": [k + 1 for k in range(cranks) if cw_t[k] or cw_z[k]],
        #: each crank's counterweights' specific centrifugal force (magnitude), Pa
        "counterweight_specific_force_Pa": [
            float(np.hypot(cw_t[k], cw_z[k])) for k in range(cranks)
        ],
        **_journal_results(journals, bearing, centrifugal * area, d_main, w_main, area),
        "crank_centrifugal_N": abs(loads.centrifugal_Pa) * area,
        "rod_bearings": rod_results,
        # big-end bearings side by side on one crank pin, each carrying its own rod only
        **({"rod_bearings_per_pin": per_pin} if per_pin > 1 else {}),
        **_rod_plane_shift(planes_apart, per_pin, spacing, opts.span_ratio),
        **_drawn_diagrams(opts, pins, journals),
        "centrifugal_rod_Pa": bays.centrifugal_rod_Pa,
        "centrifugal_Pa": bays.centrifugal_Pa,  # the crank's, in the main journals' loads
    }
    results["allowable"] = _allowable_results(scene, results)
    tables = _tables(
        angle,
        (pin_t, pin_z),
        _rod_columns(rods, per_pin),
        journal,
        bearing,
        wear_pins,
        wear_journals,
    )
    return StageOutput(
        data={},
        results=results,
        tables=tables,
        notes=[("bearings.note_dimensions", {"names": ", ".join(defaulted)})] if defaulted else [],
    )


def _journal_results(journals, bearing, centrifugal_N, d_main, w_main, area) -> dict:
    """Each main journal's load summary (with the part the cranks' centrifugal forces alone
    give, N) and each main bearing's, from the free end's journal 0-1 on."""
    return {
        "main_journals": [
            {"journal": lay.journal_label(j), **summary, "centrifugal_N": float(centrifugal_N[j])}
            for j, summary in enumerate(journals)
        ],
        "main_bearings": [
            {
                "journal": lay.journal_label(j),
                **brg.polar_summary(bearing[0][j], bearing[1][j], area, d_main, w_main),
            }
            for j in range(len(journals))
        ],
    }


def _dimension_results(sizes, defaulted: list[str], area_needed: float) -> dict:
    """The journals' sizes (``sizes``: pin diameter and width, main journal diameter and width,
    m), which of them were assumed, and the pin's area and width the allowable pressures need."""
    d_pin, w_pin, d_main, w_main = sizes
    return {
        "crank_pin_diameter_m": d_pin,
        "crank_pin_width_m": w_pin,
        "main_journal_diameter_m": d_main,
        "main_journal_width_m": w_main,
        "defaulted": defaulted,
        # the pin's d·B, and its width at its diameter, that the allowable
        # pressures need
        "crank_pin_area_needed_m2": area_needed,
        "crank_pin_width_needed_m": area_needed / d_pin,
    }


def _rod_bearing_needed(rod_results, per_pin: int, d_pin: float, kind: str) -> dict:
    """With big-end bearings side by side on the pins: the d·B of one bearing, its width at the
    pin's diameter, that the allowable pressures need for the most loaded one, and the pin's
    length for all its bearings of that width (m², m, m)."""
    if per_pin == 1:
        return {}
    area = pin_area_needed_m2(rod_results, kind)
    return {
        "rod_bearing_area_needed_m2": area,
        "rod_bearing_width_needed_m": area / d_pin,
        "crank_pin_length_needed_m": per_pin * area / d_pin,
    }


def _check_drawn_numbers(opts: BearingOptions, cranks: int) -> None:
    """The crank pins and main journals asked to be drawn exist on this crankshaft."""
    for key, values, limit in (
        ("bearings.pins", opts.pins, cranks),
        ("bearings.journals", opts.journals, cranks + 1),
    ):
        if values is not None and any(not 1 <= v <= limit for v in values):
            raise SceneError(Problem(key, values, f"numbers from 1 to {limit}"))


def _planes_apart_m(scene, layout, opts) -> float:
    """How far apart the planes of rods side by side on a pin lie, m, as the balancing takes it:
    its table's ``rod_offset``, else one big-end bearing's width (:func:`rod_offset_m`)."""
    given = options(scene, "balancing", RodOffsetOptions).rod_offset
    return rod_offset_m(scene, layout, given, opts)[0]


def _rod_plane_shift(planes_apart_m: float, per_pin: int, spacing_m, span_ratio: float) -> dict:
    """Rods side by side on a pin are loaded in its middle plane; the outermost rod's plane lies
    (n − 1)/2 of the rods' planes' distance ``planes_apart_m`` (the balancing's rod offset) off
    it, which shifts the share of its force each neighbouring main journal takes by that offset
    over the span (the crank spacing a): offset in m and share (None without a spacing: a single
    crank's span between its journals is not known from the assignment)."""
    if per_pin == 1 or span_ratio != 0.5 or not planes_apart_m:
        return {}
    offset = 0.5 * (per_pin - 1) * planes_apart_m
    share = offset / spacing_m if spacing_m else None
    return {"rod_plane_offset_m": offset, "rod_plane_share_shift": share}


def _rod_plane_transfer(rod_planes, positions):
    """Engine-frame (a, n) of what each crank's rods side by side move from the journal before
    the crank to the journal after it, Pa, arrays (cranks, N): Σ f_m x_m / l over the crank's
    rods, f_m a rod's force on the pin (its cylinder's t, z and its rod's centrifugal force,
    crank axes) and x_m its plane's distance from the pin's middle towards the journal after
    (textbook eq. 48-49 for each rod at its own l′)."""
    forces, offsets_over_span = rod_planes
    shift_t = np.einsum("kmn,km->kn", forces[0], offsets_over_span)
    shift_z = np.einsum("kmn,km->kn", forces[1], offsets_over_span)
    return brg.crank_force_engine_frame(shift_t, shift_z, 0.0, positions)


def _rod_planes(rods_in_crank_axes, per_pin: int, planes_apart_m: float, spacing_m, span_ratio):
    """(forces (t, z) of each crank's rods, arrays (cranks, rods, N); each rod plane's offset from
    the pin's middle over the span, (cranks, rods)) for the journal loads, the bay's first
    cylinder's rod (bank L's) nearest the free end; None where the rods share one plane or the
    span is not known (no crank spacing, a crank off the middle of its span)."""
    if per_pin == 1 or not planes_apart_m or not spacing_m or span_ratio != 0.5:
        return None
    by_crank: dict[int, list] = {}
    for k, _, t, z in rods_in_crank_axes:
        by_crank.setdefault(k, []).append((t, z))
    cranks = sorted(by_crank)
    t = np.array([[f[0] for f in by_crank[k]] for k in cranks])
    z = np.array([[f[1] for f in by_crank[k]] for k in cranks])
    offsets = (np.arange(per_pin) - 0.5 * (per_pin - 1)) * planes_apart_m / spacing_m
    return (t, z), np.tile(offsets, (len(cranks), 1))


def main_bearing_frame_deg(layout) -> float:
    """The angle of the main bearings' y axis from cylinder 1's, in the direction of rotation:
    the engine's vertical (:func:`crankdyn.physics.balancing.vertical_axis_deg`)."""
    return vertical_axis_deg(layout.layout, layout.bank_angle_deg)


def _main_journal_loads(
    loads, motion, layout, counterweight_Pa, span_ratio: float, rod_planes=None
):
    """((t, z) of the bearings' force on each main journal in the preceding crank's axes,
    (t, z) of the journals' force on each main bearing in the engine's axes, the mean magnitude
    of the part of each journal's load the cranks' centrifugal forces alone give), Pa.
    ``rod_planes`` (:func:`_rod_planes`): rods side by side, each rod's force shared between the
    journals by its own plane; None: every force in the pin's middle plane."""
    # Main journals: each crank a beam on two supports; forces in the engine frame.
    # each crank's angle from the engine's vertical (the cylinder axis of a one-cylinder engine)
    cranks = layout.cranks
    theta = np.radians(loads.crank_angle_deg)
    tdc = motion.extra.get("crank_angle_at_tdc_rad", 0.0)
    positions = np.array([theta + tdc - np.radians(lag) for lag in layout.crank_lag_deg])
    cw_t, cw_z = counterweight_Pa
    fa, fn = brg.crank_force_engine_frame(
        loads.tangential_Pa + cw_t[:, None],
        loads.radial_Pa + cw_z[:, None],
        loads.centrifugal_Pa,
        positions,
    )
    share_after = np.full(cranks, span_ratio)
    ja, jn = brg.journal_loads(fa, fn, 1.0 - share_after, share_after)
    if rod_planes is not None:  # each rod's force shared by its own plane, not the pin's middle
        shift_a, shift_n = _rod_plane_transfer(rod_planes, positions)
        ja[1:] += shift_a
        jn[1:] += shift_n
        ja[:-1] -= shift_a
        jn[:-1] -= shift_n
    # Journal diagram: force of the bearing on the journal (the reaction, -J) in the axes of the
    # preceding crank (crank 1 for the free-end journal); bearing diagram: J in engine axes.
    journal_t, journal_z = np.zeros_like(ja), np.zeros_like(ja)
    for j in range(cranks + 1):
        e_t, e_z = brg.crank_axes(positions[max(j - 1, 0)])
        journal_t[j], journal_z[j] = brg.to_frame(-ja[j], -jn[j], e_t, e_z)
    # the main bearings' axes: the engine's vertical (a V's, W's or boxer's banks' axis of
    # symmetry, as the balancing takes it; cylinder 1's axis of an in-line or radial engine)
    engine_t, engine_z = brg.crank_axes(np.radians([main_bearing_frame_deg(layout)]))
    # the cranks' centrifugal forces alone (no counterweights): constant in magnitude, rotating
    none = np.zeros_like(loads.tangential_Pa)
    ca, cn = brg.crank_force_engine_frame(none, none, loads.centrifugal_Pa, positions)
    centrifugal = np.hypot(*brg.journal_loads(ca, cn, 1.0 - share_after, share_after)).mean(axis=1)
    return (journal_t, journal_z), brg.to_frame(ja, jn, engine_t, engine_z), centrifugal


def _diagram_summary(t, z, d, w, area, angle, opts: BearingOptions):
    """(summary of a polar load diagram with its oil hole and least loaded arc, its wear
    diagram (psi, wear))."""
    s = brg.polar_summary(t, z, area, d, w, angle)
    # Contact point on the rotating part: opposite to the force applied to it.
    psi, wear = brg.wear_diagram(-t, -z, np.hypot(t, z) * area, opts.wear_spread_deg)
    start, end, centre = brg.least_loaded_arc(psi, wear)
    s.update({"oil_hole_deg": centre, "least_loaded_arc_deg": [start, end]})
    return s, (psi, wear)


def _drawn_diagrams(opts: BearingOptions, pins, journals) -> dict:
    """The pins and journals whose diagrams are drawn (the most loaded ones unless chosen), the
    span ratio and whether the choice was the default."""
    most_loaded_pin = first_argmax([p["max_N"] for p in pins]) + 1
    most_loaded_journal = first_argmax([j["max_N"] for j in journals]) + 1
    return {
        "drawn_pins": opts.pins or [most_loaded_pin],
        "drawn_journals": opts.journals or [most_loaded_journal],
        "span_ratio": opts.span_ratio,  # l'/l of every crank
        "chosen_by_default": opts.pins is None and opts.journals is None,
    }
