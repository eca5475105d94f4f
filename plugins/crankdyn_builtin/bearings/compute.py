"""Vector (polar) load diagrams of crank pins, main journals and their bearings (Poda 2007 §5).


The computation: ``applies``, ``run`` and their pure helpers.
"""

from __future__ import annotations

import math

import numpy as np

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import bearings as brg
from crankdyn.physics import layout as lay
from crankdyn.physics.extrema import first_argmax
from crankdyn.plugin.contracts import BAY_LOADS, COUNTERWEIGHTS, CRANK_LOADS, KINEMATICS
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

from .options import BearingOptions

# Typical proportions (fractions of the bore / of the journal diameter) for car and tractor
# engines, used when the scene gives no journal dimensions.
DEFAULT_PIN_DIAMETER_PER_BORE = 0.63

DEFAULT_PIN_WIDTH_PER_DIAMETER = 0.60

DEFAULT_MAIN_DIAMETER_PER_BORE = 0.70

DEFAULT_MAIN_WIDTH_PER_DIAMETER = 0.45

#: Allowable specific loads of crank-pin bearings, MPa: (mean, largest) for petrol engines and
#: for diesels (Kolchin and Demidov, the wear diagram of the crank pin: mean 4-12 MPa and largest
#: 7-20 MPa in petrol engines, mean 6-16 MPa and largest 20-42 MPa in diesels; the upper ends
#: are the limits). An engine of unknown ignition (a measured trace) is judged as a diesel.
ALLOWABLE_PIN_PRESSURE_MPA = {"spark": (12.0, 20.0), "diesel": (16.0, 42.0)}

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
    """The most loaded crank pin's mean and largest bearing pressure against the allowable ones
    of its kind of engine (:data:`ALLOWABLE_PIN_PRESSURE_MPA`)."""
    pins = (results or {}).get("crank_pins")
    if not pins:
        return []
    kind = _ignition_kind(scene)
    mean_limit, max_limit = ALLOWABLE_PIN_PRESSURE_MPA[kind]
    p_mean = max(pin["mean_MPa"] for pin in pins)
    p_max = max(pin["max_MPa"] for pin in pins)
    if p_mean <= mean_limit and p_max <= max_limit:
        return []
    sizes = results.get("dimensions") or {}
    area_needed_m2 = sizes.get("crank_pin_area_needed_m2") or pin_area_needed_m2(pins, kind)
    diameter_m, width_m = sizes.get("crank_pin_diameter_m"), sizes.get("crank_pin_width_m")
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
    # sizes assumed from typical ratios: the verdict is said to rest on them
    assumed = bool({"crank_pin_diameter", "crank_pin_width"} & set(sizes.get("defaulted", ())))
    key = f"bearings.plausibility_pin_pressure_{kind}" + ("_assumed" if assumed else "")
    return [(key, params)]


def applies(scene) -> str | None:
    if scene.masses is None:
        return "the scene has no [masses]"
    return None


def _assumed_size_m(value_m: float) -> float:
    """A size taken from a typical ratio, as a drawing would give it: to 0.1 mm, a size under
    10 mm (a model engine's) to three significant digits."""
    return round(value_m * 1e4) / 1e4 if value_m >= 0.01 else float(f"{value_m:.3g}")


def _dimensions(scene, opts):
    bore = scene.engine.bore
    d_pin = opts.crank_pin_diameter or _assumed_size_m(DEFAULT_PIN_DIAMETER_PER_BORE * bore)
    w_pin = opts.crank_pin_width or _assumed_size_m(DEFAULT_PIN_WIDTH_PER_DIAMETER * d_pin)
    d_main = opts.main_journal_diameter or _assumed_size_m(DEFAULT_MAIN_DIAMETER_PER_BORE * bore)
    w_main = opts.main_journal_width or _assumed_size_m(DEFAULT_MAIN_WIDTH_PER_DIAMETER * d_main)
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


def _tables(angle, pin, rod, journal, bearing, wear_pins, wear_journals) -> dict:
    """The stage's tables: every pin, rod bearing, journal and main bearing load (t, z components
    in Pa, per crank angle), and the wear diagrams (N per surface angle)."""
    cranks = len(pin[0])
    table = {"crank_angle_deg": angle}
    for k in range(cranks):
        table.update(
            {
                f"pin{k + 1}_t_Pa": pin[0][k],
                f"pin{k + 1}_z_Pa": pin[1][k],
                f"rod_bearing{k + 1}_t_Pa": rod[0][k],
                f"rod_bearing{k + 1}_z_Pa": rod[1][k],
            }
        )
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


def _pin_and_rod_loads(loads, bays, motion, layout):
    """(pin t, pin z, rod-bearing t, rod-bearing z), each (cranks, N): the rods' load on each crank
    pin in crank axes, and the rod bearing of each bay's master rod in rod axes."""
    angle = loads.crank_angle_deg
    pin_t, pin_z = brg.crank_pin_load(loads.tangential_Pa, loads.radial_Pa, bays.centrifugal_rod_Pa)
    master = layout.bay(0)[0]
    rod_t, rod_z = np.zeros_like(pin_t), np.zeros_like(pin_z)
    revolution = int(round(360 / (angle[1] - angle[0])))
    # the crank's angle from the cylinder axis is alpha + this (an offset crank-slider's phi_TDC)
    tdc = motion.extra.get("crank_angle_at_tdc_rad", 0.0)
    for k in range(layout.cranks):
        # Each bay's master rod sees its crank at its own cycle angle.
        delay = layout.bay(k)[0].firing_delay_deg - master.firing_delay_deg
        local = np.radians((angle - delay) % 360.0)
        # without a rod (a Scotch yoke) the pin's bearing is the slider's, along the cylinder axis
        beta = (
            0.0
            if motion.rod_angle_rad is None
            else np.interp(
                np.degrees(local),
                motion.crank_angle_deg[:revolution],
                motion.rod_angle_rad[:revolution],
                period=360.0,
            )
        )
        rod_t[k], rod_z[k] = brg.rod_bearing_load(pin_t[k], pin_z[k], local + tdc, beta)
    return pin_t, pin_z, rod_t, rod_z


def run(scene, inputs) -> StageOutput:
    loads, bays, motion = inputs[CRANK_LOADS], inputs[BAY_LOADS], inputs[KINEMATICS]
    opts = options(scene, "bearings", BearingOptions)
    layout = bays.layout
    cranks = layout.cranks
    angle = loads.crank_angle_deg
    area = loads.piston_area_m2
    d_pin, w_pin, d_main, w_main, defaulted = _dimensions(scene, opts)
    _check_drawn_numbers(opts, cranks)
    pin_t, pin_z, rod_t, rod_z = _pin_and_rod_loads(loads, bays, motion, layout)
    # with the counterweights the balancing section fits (their centrifugal force on the webs)
    cw_t, cw_z = _counterweight_loads_Pa(inputs.get(COUNTERWEIGHTS), cranks, area)
    journal, bearing, centrifugal = _main_journal_loads(
        loads, motion, layout, (cw_t, cw_z), opts.span_ratio
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
    area_needed = pin_area_needed_m2(pins, _ignition_kind(scene))
    results = {
        # an offset crank-slider's crank is this far past the cylinder axis at TDC (0: central)
        "crank_angle_at_tdc_deg": math.degrees(motion.extra.get("crank_angle_at_tdc_rad", 0.0)),
        "dimensions": _dimension_results((d_pin, w_pin, d_main, w_main), defaulted, area_needed),
        "crank_pins": [{"crank": k + 1, **pins[k]} for k in range(cranks)],
        "with_counterweights": bool(np.any(cw_t) or np.any(cw_z)),
        "main_journals": [
            {
                "journal": lay.journal_label(j),
                **journals[j],
                "centrifugal_N": float(centrifugal[j] * area),
            }
            for j in range(cranks + 1)
        ],
        "crank_centrifugal_N": abs(loads.centrifugal_Pa) * area,
        "rod_bearings": [
            {"crank": k + 1, **brg.polar_summary(rod_t[k], rod_z[k], area, d_pin, w_pin)}
            for k in range(cranks)
        ],
        "main_bearings": [
            {
                "journal": lay.journal_label(j),
                **brg.polar_summary(bearing[0][j], bearing[1][j], area, d_main, w_main),
            }
            for j in range(cranks + 1)
        ],
        **_drawn_diagrams(opts, pins, journals),
        "centrifugal_rod_Pa": bays.centrifugal_rod_Pa,
        "centrifugal_Pa": bays.centrifugal_Pa,  # the crank's, in the main journals' loads
    }
    tables = _tables(
        angle, (pin_t, pin_z), (rod_t, rod_z), journal, bearing, wear_pins, wear_journals
    )
    return StageOutput(
        data={},
        results=results,
        tables=tables,
        notes=[("bearings.note_dimensions", {"names": ", ".join(defaulted)})] if defaulted else [],
    )


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


def _check_drawn_numbers(opts: BearingOptions, cranks: int) -> None:
    """The crank pins and main journals asked to be drawn exist on this crankshaft."""
    for key, values, limit in (
        ("bearings.pins", opts.pins, cranks),
        ("bearings.journals", opts.journals, cranks + 1),
    ):
        if values is not None and any(not 1 <= v <= limit for v in values):
            raise SceneError(Problem(key, values, f"numbers from 1 to {limit}"))


def _main_journal_loads(loads, motion, layout, counterweight_Pa, span_ratio: float):
    """((t, z) of the bearings' force on each main journal in the preceding crank's axes,
    (t, z) of the journals' force on each main bearing in the engine's axes, the mean magnitude
    of the part of each journal's load the cranks' centrifugal forces alone give), Pa."""
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
    # Journal diagram: force of the bearing on the journal (the reaction, -J) in the axes of the
    # preceding crank (crank 1 for the free-end journal); bearing diagram: J in engine axes.
    journal_t, journal_z = np.zeros_like(ja), np.zeros_like(ja)
    for j in range(cranks + 1):
        e_t, e_z = brg.crank_axes(positions[max(j - 1, 0)])
        journal_t[j], journal_z[j] = brg.to_frame(-ja[j], -jn[j], e_t, e_z)
    engine_t, engine_z = brg.crank_axes(np.zeros(1))
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
