"""Indicator diagram: theoretical p-V diagram, its rounding, or a measured pressure trace (Poda 2007 §3.1).


The computation: ``applies``, ``run``, ``run_many`` and their pure helpers.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import indicator as ind
from crankdyn.physics import pressure_trace as trace
from crankdyn.physics.extrema import first_argmax
from crankdyn.physics.forces import piston_area_m2
from crankdyn.plugin.contracts import GAS_PRESSURE, KINEMATICS, GasPressure
from crankdyn.plugin.scene_inputs import cycle_parameters, rounding_parameters
from crankdyn.plugin.types import StageOutput
from crankdyn.report.plausibility import MAX_PEAK_PRESSURE_PA


def applies(scene) -> str | None:
    if scene.cycle is None:
        return "the scene has no [cycle] data (indicator-diagram parameters or a pressure trace)"
    return None


def piston_stroke_m(scene, motion) -> float:
    """The piston's stroke between its dead centres, m: the mechanism's own when its kinematics
    give one (an offset crank-slider's exceeds 2R), else the scene's stroke."""
    return float(motion.extra.get("stroke_m", scene.engine.stroke))


def bdc_crank_angle_deg(motion) -> float:
    """The crank angle of BDC after TDC, deg: the mechanism's own when its kinematics give one,
    else 180."""
    return float(motion.extra.get("bdc_crank_angle_deg", 180.0))


#: The mechanism whose exact displacement has a closed form (:func:`ind.lost_stroke_fraction`).
CENTRAL_CRANK_SLIDER = "crank_slider"


def diagram_parameters(scene, motion):
    """The scene's cycle parameters with the mechanism's BDC (points a and b) and, for a
    two-stroke, the lost stroke fraction of its exhaust ports."""
    bdc = bdc_crank_angle_deg(motion)
    params = dataclasses.replace(cycle_parameters(scene), bdc_deg=bdc)
    if scene.engine.strokes != 2 or scene.cycle.source != "theoretical":
        return params
    psi = lost_stroke_fraction(scene, motion)
    try:
        return dataclasses.replace(params, lost_stroke_fraction=psi)
    except ValueError as exc:
        raise SceneError(
            Problem(
                "cycle.rounding.exhaust_opens_before_bdc_deg",
                scene.cycle.rounding.exhaust_opens_before_bdc_deg,
                str(exc),
            )
        ) from None


def lost_stroke_fraction(scene, motion) -> float:
    """ψ = 1 − s_b/S of a two-stroke's exhaust ports: s_b the piston's travel from TDC when the
    ports open, ``exhaust_opens_before_bdc_deg`` before BDC. The ports' edge is where the piston
    stands, so the central crank-slider's is its exact displacement (also when the analysis takes
    the two-term kinematics); another mechanism's is its own displacement (an offset
    crank-slider's)."""
    opening = scene.cycle.rounding.exhaust_opens_before_bdc_deg
    if opening <= 0.0:
        return 0.0
    if scene.engine.mechanism in (None, CENTRAL_CRANK_SLIDER) or motion.displacement_at is None:
        return ind.lost_stroke_fraction(opening, scene.engine.rod_ratio_value)
    at = np.asarray([bdc_crank_angle_deg(motion) - opening])
    travel = float(np.ravel(motion.displacement_at(at))[0])
    return min(max(1.0 - travel / piston_stroke_m(scene, motion), 0.0), 1.0 - 1e-12)


def run(
    scene, inputs, *, junction_deg: float | None = None, volumes: dict | None = None
) -> StageOutput:
    """The diagram of ``scene``; ``junction_deg`` is its rounding's junction J and ``volumes`` the
    cylinder volume (m³) at the angles the rounding reads it off (deg: m³) when ``run_many`` has
    computed them for many scenes at once."""
    motion = inputs[KINEMATICS]
    engine = scene.engine
    area = piston_area_m2(engine.bore)
    swept = area * piston_stroke_m(scene, motion)
    angle = motion.crank_angle_deg
    results: dict = {
        "source": scene.cycle.source,
        "swept_volume_m3": swept,
        "bdc_crank_angle_deg": bdc_crank_angle_deg(motion),
    }
    table: dict = {"crank_angle_deg": angle}
    notes: list = []
    drawn = None  # a trace is not rounded

    if scene.cycle.source == "trace":
        pressure, volume = _trace_pressure(scene, motion, area, swept)
        table.update({"cylinder_volume_m3": volume, "pressure_Pa": pressure})
        notes.append(("indicator.note_trace", {}))
        # a measured trace has no end of compression to read off (combustion starts before TDC):
        # the result is stated as not given, so the answer key leaves its cell empty knowingly
        results["compression_end_pressure_Pa"] = None
    else:
        params, rounding, clearance, volume, theoretical, pressure, volume_function = (
            _rounded_diagram(scene, motion, area, swept, junction_deg, volumes)
        )
        table.update(
            {
                "cylinder_volume_m3": volume,
                "pressure_theoretical_Pa": theoretical,
                "pressure_Pa": pressure,
            }
        )
        rounding, lowered = _rounding_as_drawn(
            scene, angle, volume, clearance, params, rounding, volume_function
        )
        results.update(
            _theoretical_results(
                params, rounding, clearance, theoretical, volume, swept, volume_function
            )
        )
        results.update(peak_lowered=lowered, peak_on_isobar=_isobar_point(scene, params, clearance))
        results["pressure_rise_limited"] = _rise_limited(scene, params, rounding)
        drawn = rounding
        results["closed_form_check"] = _closed_form_check(scene, params, results)
        notes.append(_rounding_note(scene, rounding))
        if "lost_stroke_fraction" in results:  # the piston's travel s_b = (1 − ψ)S to the ports
            stroke = piston_stroke_m(scene, motion)
            results["piston_stroke_m"] = stroke
            results["port_opening_travel_m"] = (1.0 - results["lost_stroke_fraction"]) * stroke
    results.update(_work_results(pressure, volume, angle, engine, swept, motion))
    p_i_gross = results["gross_mean_indicated_pressure_Pa"]
    if scene.cycle.source == "theoretical":  # both without the pumping strokes (p_i′: eq. 4.4)
        results["diagram_fullness"] = p_i_gross / results["theoretical_mean_indicated_pressure_Pa"]
    if scene.cycle.mean_indicated_pressure is not None:
        target = scene.cycle.mean_indicated_pressure
        results["thermal_mean_indicated_pressure_Pa"] = target
        results["mean_indicated_pressure_deviation_percent"] = 100.0 * (p_i_gross - target) / target
    elif scene.cycle.source == "theoretical" and engine.strokes == 4:
        results["diagram_fullness_usual"] = list(USUAL_FULLNESS[scene.cycle.ignition])

    gas = GasPressure(
        crank_angle_deg=angle,
        pressure_Pa=pressure,
        volume_m3=volume,
        source=scene.cycle.source,
        indicated_work_J=results["indicated_work_J"],
        swept_volume_m3=swept,
        rounding=drawn,
        pumping_work_J=results["pumping_work_J"],
    )
    return StageOutput(
        data={GAS_PRESSURE: gas}, results=results, tables={"indicator": table}, notes=notes
    )


def _rounded_diagram(scene, motion, area: float, swept: float, junction_deg, volumes):
    """(cycle parameters, rounding parameters, clearance volume, cylinder volume, theoretical and
    rounded pressure) of the scene's indicator diagram; a rounding that does not fit raises
    SceneError."""
    angle = motion.crank_angle_deg
    params = diagram_parameters(scene, motion)
    clearance = ind.clearance_volume_m3(swept, params.compression_ratio)
    volume = ind.cylinder_volume_m3(motion.piston_displacement_m, area, clearance)
    theoretical = ind.theoretical_pressure_Pa(angle, volume, clearance, params)
    volume_function = _volume_function(motion, area, clearance, volumes)
    rounding = _rounding_taken(scene, motion, params, area, clearance)
    try:
        pressure = ind.rounded_pressure_Pa(
            angle,
            volume,
            clearance,
            params,
            rounding,
            volume_function=volume_function,
            junction_deg=junction_deg,
            theoretical_Pa=theoretical,
        )
    except ValueError as exc:
        raise SceneError(Problem("cycle.rounding", "(see message)", str(exc))) from None
    return params, rounding, clearance, volume, theoretical, pressure, volume_function


def _peak_on_isobar(scene, params) -> bool:
    """Whether a diesel's peak Z' is put on its isobar of heat addition: the scene gives no angle
    for it and the cycle has an isobar (ρ > 1)."""
    given = scene.cycle.rounding.model_fields_set
    return (
        scene.cycle.ignition == "diesel"
        and "peak_angle_after_tdc_deg" not in given
        and params.pre_expansion_ratio > 1.0
    )


def _rise_limited(scene, params, rounding) -> dict | None:
    """Where the usual rise to c″ would give p_c″ above (1 + the largest share) p_c and a quarter
    of p_c is taken instead: the ratio p_c″/p_c the usual rise would give; else None."""
    if "pressure_rise_to_tdc" in scene.cycle.rounding.model_fields_set:
        return None
    if rounding.pressure_rise_to_tdc_Pa >= ind.USUAL_PRESSURE_RISE_PA:
        return None
    p_c = rounding.pressure_rise_to_tdc_Pa / ind.LARGEST_PRESSURE_RISE_SHARE  # the cycle's own
    return {
        "usual_Pa": ind.USUAL_PRESSURE_RISE_PA,
        "usual_ratio": 1.0 + ind.USUAL_PRESSURE_RISE_PA / p_c,
        "share": ind.LARGEST_PRESSURE_RISE_SHARE,
    }


def _isobar_point(scene, params, clearance: float) -> dict | None:
    """Where :func:`_peak_on_isobar`: the share of the isobar z′ lies at and its volume, m³
    (:func:`ind.isobar_point_volume_m3`); else None."""
    if not _peak_on_isobar(scene, params):
        return None
    share = ind.DIESEL_PEAK_ISOBAR_SHARE
    return {"share": share, "volume_m3": ind.isobar_point_volume_m3(clearance, params, share)}


def _rounding_taken(scene, motion, params, area: float, clearance: float):
    """The scene's rounding (:func:`rounding_parameters`), a diesel's peak Z' on its isobar where :func:`_peak_on_isobar` (:func:`ind.isobar_peak_angle_deg`: there the
    theoretical pressure is p_z, so p_z′ = p_z keeps the actual diagram inside the theoretical
    one). The one-diagram and the many-diagram runs take it alike, from the mechanism's own
    volume function."""
    rounding = rounding_parameters(scene)
    if not _peak_on_isobar(scene, params):
        return rounding
    volume = ind.cylinder_volume_m3(motion.piston_displacement_m, area, clearance)
    on_isobar = ind.isobar_peak_angle_deg(
        motion.crank_angle_deg,
        volume,
        clearance,
        params,
        volume_function=_volume_function(motion, area, clearance, None),
    )
    if on_isobar is None:  # no isobar after all (ρ = 1): the scene's angle
        return rounding
    return dataclasses.replace(rounding, peak_angle_after_tdc_deg=on_isobar)


def _rounding_as_drawn(scene, angle, volume, clearance, params, rounding, volume_function):
    """(the rounding with its peak fraction as drawn, what was lowered or None): a p_z′ that would
    stand above the theoretical diagram at z′ is taken inside it (:func:`ind.peak_pressure_Pa`)."""
    peak = ind.peak_pressure_Pa(
        angle, volume, clearance, params, rounding, volume_function=volume_function
    )
    asked = rounding.peak_pressure_fraction
    if peak >= asked * params.max_pressure_Pa:
        return rounding, None
    lowered = {
        "requested_fraction": asked,
        "given": scene.cycle.rounding.peak_pressure_fraction is not None,
        "share_of_theoretical": ind.PEAK_BELOW_EXPANSION,
    }
    drawn = dataclasses.replace(rounding, peak_pressure_fraction=peak / params.max_pressure_Pa)
    return drawn, lowered


def _closed_form_check(scene, params, results) -> dict | None:
    """The sharp-cornered diagram's mean pressure integrated on the grid against its closed form
    p_i′ with the pumping strokes' p_a − p_r (a four-stroke's), Pa and relative; None where the
    closed form does not hold exactly (a linkage other than the central crank-slider, exhaust
    ports whose lost stroke it takes as the factor 1 − ψ)."""
    if scene.engine.mechanism != "crank_slider" or params.lost_stroke_fraction > 0.0:
        return None
    closed = ind.theoretical_diagram_mean_pressure_Pa(params)
    pumping = closed - results["theoretical_mean_indicated_pressure_Pa"]
    numeric = results["theoretical_diagram_mean_pressure_Pa"]
    return {
        "closed_Pa": closed,
        "pumping_Pa": pumping,
        "numeric_Pa": numeric,
        "deviation_relative": numeric / closed - 1.0,
    }


def _theoretical_results(
    params, rounding, clearance, theoretical, volume, swept, volume_function=None
) -> dict:
    """The theoretical diagram's results: its points, mean pressures and the rounding's data."""
    work_theoretical = ind.indicated_work_J(theoretical, volume)
    p_i_closed = ind.theoretical_mean_indicated_pressure_Pa(params)
    ports = (
        _port_results(params, rounding, clearance, volume_function)
        if params.lost_stroke_fraction > 0.0
        else {}
    )
    return {
        **ports,
        "clearance_volume_m3": clearance,
        "compression_end_pressure_Pa": ind.compression_end_pressure_Pa(params),
        "expansion_end_pressure_Pa": ind.expansion_end_pressure_Pa(params),
        "theoretical_mean_indicated_pressure_Pa": p_i_closed,
        "theoretical_diagram_mean_pressure_Pa": ind.mean_indicated_pressure_Pa(
            work_theoretical, swept
        ),
        "ignition_advance_deg": rounding.ignition_advance_deg,
        "combustion_delay_deg": rounding.combustion_delay_deg,
        "peak_pressure_rounded_Pa": rounding.peak_pressure_fraction * params.max_pressure_Pa,
        # point c″: the compression line's end raised by the rounding's rise (Poda 2007 §3.1)
        "pressure_rise_to_tdc_Pa": rounding.pressure_rise_to_tdc_Pa,
        "tdc_pressure_rounded_Pa": ind.compression_end_pressure_Pa(params)
        + rounding.pressure_rise_to_tdc_Pa,
        "peak_pressure_fraction": rounding.peak_pressure_fraction,
        "peak_angle_after_tdc_deg": rounding.peak_angle_after_tdc_deg,
    }


def _port_results(params, rounding, clearance: float, volume_function) -> dict:
    """A port-scavenged two-stroke's lost stroke fraction ψ, actual compression ratio ε_д, the
    volume V_a′ at the port closing a′ (and opening b) and the crank angles of b and a′ (deg after
    firing TDC; a′ symmetric to b about BDC without the mechanism's displacement)."""
    opening = params.bdc_deg - rounding.exhaust_opens_before_bdc_deg
    if volume_function is None:
        closing = params.bdc_deg + rounding.exhaust_opens_before_bdc_deg
    else:
        closing = ind.port_closing_deg(lambda a: (volume_function(a), None), clearance, params)
    return {
        "exhaust_ports_open_deg": float(opening),
        "exhaust_ports_close_deg": float(closing),
        # the rounding's blowdown after b and its compression rounding after a′, deg
        "blowdown_deg": ind.BLOWDOWN_FRACTION * rounding.exhaust_opens_before_bdc_deg,
        "port_closing_rounding_deg": (
            ind.PORT_CLOSING_ROUNDING_FRACTION * rounding.exhaust_opens_before_bdc_deg
        ),
        "lost_stroke_fraction": params.lost_stroke_fraction,
        "actual_compression_ratio": float(ind.actual_compression_ratio(params)),
        "port_closing_volume_m3": float(ind.port_closing_volume_m3(clearance, params)),
    }


def _rounding_note(scene, rounding) -> tuple[str, dict]:
    """The note on the rounding's points (a diesel's or a spark-ignition engine's)."""
    note_key = (
        "indicator.note_rounding_diesel"
        if scene.cycle.ignition == "diesel"
        else "indicator.note_rounding"
    )
    if note_key.endswith("diesel") and rounding.peak_pressure_fraction == 1.0:
        note_key += "_full"  # p_z′ = p_z, not "1·p_z"
    return (
        note_key,
        {
            "advance": rounding.ignition_advance_deg,
            "delay": rounding.combustion_delay_deg,
            "fraction": rounding.peak_pressure_fraction,
            "angle": round(rounding.peak_angle_after_tdc_deg, 1),  # a diesel's on its isobar
        },
    )


def _work_results(pressure, volume, angle, engine, swept: float, motion) -> dict:
    """The diagram's indicated and pumping work, mean indicated pressures, peak and power."""
    work = ind.indicated_work_J(pressure, volume)
    p_i = ind.mean_indicated_pressure_Pa(work, swept)
    # the thermal calculation's p_i leaves the gas exchange out (physics.indicator.pumping_work_J)
    pumping = ind.pumping_work_J(
        pressure, volume, angle, engine.strokes, bdc_deg=bdc_crank_angle_deg(motion)
    )
    p_i_gross = ind.mean_indicated_pressure_Pa(work - pumping, swept)
    peak = first_argmax(pressure)
    return {
        "indicated_work_J": work,
        "pumping_work_J": pumping,
        "gross_mean_indicated_pressure_Pa": p_i_gross,
        "mean_indicated_pressure_Pa": p_i,
        "max_pressure_Pa": float(pressure[peak]),
        "max_pressure_crank_angle_deg": float(angle[peak]),
        "indicated_power_W": work * engine.rpm / 60.0 / (engine.strokes / 2),
    }


def _volume_function(motion, area: float, clearance: float, volumes: dict | None):
    """The cylinder volume (m³) at any crank angle (deg) from the mechanism's displacement, taking
    the ``volumes`` already computed for a chunk of points; None without a displacement function."""
    if motion.displacement_at is None:
        return None

    def volume_at(a_deg):
        known = _known_volume(volumes, a_deg)
        if known is not None:
            return known
        return ind.cylinder_volume_m3(motion.displacement_at(a_deg), area, clearance)

    return volume_at


def _known_volume(volumes: dict | None, angle_deg):
    """The volume ``run_many`` computed at the one angle ``angle_deg``, as an array of its shape;
    None for another angle."""
    if volumes is None or np.size(angle_deg) != 1:
        return None
    known = volumes.get(float(np.ravel(angle_deg)[0]))
    return None if known is None else np.full(np.shape(angle_deg), known)


def _rounding_volumes(scenes, params, rounding, junctions, clearances, volume_at) -> list[dict]:
    """For each scene, the cylinder volume (m³) at the angles of its rounding's points C', J and
    b' and 1e-4° either side (the central difference of the lines' slopes), computed over points
    x angles: {angle in deg: volume}. The angles are the numbers ``physics.indicator`` asks for.
    A volume below the clearance (a negative displacement) is left out: ``run`` computes it and
    refuses it as it would alone."""
    step = 1e-4  # deg: the rounding's central difference
    cycle = np.array([720.0 if s.engine.strokes == 4 else 360.0 for s in scenes])[:, None]
    tdc = np.array([360.0 if s.engine.strokes == 4 else 0.0 for s in scenes])[:, None]
    psi = np.array(
        [
            [
                -(r.ignition_advance_deg - r.combustion_delay_deg),
                j,
                p.bdc_deg - r.exhaust_opens_before_bdc_deg,
            ]
            for r, j, p in zip(rounding, junctions, params, strict=False)
        ]
    )
    at = np.mod(tdc + psi, cycle)
    angles = np.concatenate([at, at + step, at - step], axis=1)
    rows = np.arange(len(scenes))
    found = np.isfinite(angles)
    values = volume_at(np.where(found, angles, 0.0), rows)
    found &= values >= np.asarray(clearances, dtype=float)[:, None]
    return [
        {float(a): float(v) for a, v, ok in zip(angles[k], values[k], found[k], strict=False) if ok}
        for k in rows
    ]


def _stacked_displacement(motions):
    """The motions' ``displacement_at`` as one function ``(angle_deg, rows) -> m`` of angles
    (rows, M), when they are one function with other numbers (``functools.partial`` of the same
    function, each number a column); None otherwise."""
    first = motions[0].displacement_at
    partials = [m.displacement_at for m in motions]
    if not all(
        isinstance(d, functools.partial)
        and d.func is first.func
        and not d.keywords
        and len(d.args) == len(first.args)
        for d in partials
    ):
        return None
    columns = []
    for position, shared in enumerate(first.args):
        values = [d.args[position] for d in partials]
        if all(v is shared for v in values):
            columns.append(None)
        elif all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            columns.append(np.asarray(values, dtype=float)[:, None])
        else:
            return None

    def displacement(angle_deg, rows):
        args = [a if c is None else c[rows] for a, c in zip(first.args, columns, strict=False)]
        return first.func(*args, angle_deg)

    return displacement


def run_many(scenes, inputs) -> list[StageOutput]:
    """``run`` over many scenes at once (a sweep's points): the junctions J of their diagrams'
    rounding, the search that dominates a point, found together over points x angles
    (``physics.indicator.combustion_junctions_deg``); each scene's diagram then as ``run`` gives
    it. Measured traces, mixed strokes or a displacement without a common formula: ``run`` one by
    one."""
    motions = [given[KINEMATICS] for given in inputs]
    displacement = _stacked_displacement(motions)
    if (
        displacement is None
        or any(s.cycle.source != "theoretical" for s in scenes)
        or len({s.engine.strokes for s in scenes}) > 1
    ):
        return [run(scene, given) for scene, given in zip(scenes, inputs, strict=False)]
    params = [
        diagram_parameters(scene, motion) for scene, motion in zip(scenes, motions, strict=False)
    ]
    areas = np.asarray([piston_area_m2(scene.engine.bore) for scene in scenes], dtype=float)
    clearances = np.asarray(
        [
            ind.clearance_volume_m3(area * piston_stroke_m(s, m), p.compression_ratio)
            for area, s, m, p in zip(areas, scenes, motions, params, strict=False)
        ],
        dtype=float,
    )
    area_column, clearance_column = areas[:, None], clearances[:, None]

    def volume_at(angle_deg, rows):
        return clearance_column[rows] + area_column[rows] * displacement(angle_deg, rows)

    rounding = [
        _rounding_taken(s, m, p, area, clearance)
        for s, m, p, area, clearance in zip(scenes, motions, params, areas, clearances, strict=True)
    ]
    junctions = ind.combustion_junctions_deg(params, rounding, clearances, volume_at)
    volumes = _rounding_volumes(scenes, params, rounding, junctions, clearances, volume_at)
    return [
        run(scene, given, junction_deg=float(j), volumes=v)
        for scene, given, j, v in zip(scenes, inputs, junctions, volumes, strict=False)
    ]


def _trace_pressure(scene, motion, area, swept):
    c = scene.cycle
    path = scene.resolve(c.trace_file)
    fmt = c.trace_format or ("diesel-rk" if path.suffix.lower() == ".ind" else "csv")
    try:
        if fmt == "diesel-rk":
            angle_file, pressure_file = trace.read_diesel_rk_ind(path)
        else:
            angle_file, pressure_file = trace.read_pressure_csv(path)
        target_tdc = 360.0 if scene.engine.strokes == 4 else 0.0
        pressure = trace.to_cycle_grid(
            angle_file,
            pressure_file,
            scene.engine.cycle_deg,
            motion.crank_angle_deg,
            c.trace_firing_tdc_deg,
            target_tdc,
        )
    except (trace.PressureTraceError, OSError) as exc:
        raise SceneError(Problem("cycle.trace_file", c.trace_file, str(exc))) from None
    clearance = ind.clearance_volume_m3(swept, c.compression_ratio)
    volume = ind.cylinder_volume_m3(motion.piston_displacement_m, area, clearance)
    return pressure, volume


#: The usual diagram fullness φ_п = p_i/p_i′ of four-stroke spark-ignition engines and diesels
#: (Kolchin and Demidov): the actual cycle loses this much of the theoretical one's area.
USUAL_FULLNESS = {"spark": (0.94, 0.97), "diesel": (0.92, 0.95)}


#: The rounded diagram's peak p_z' of a diesel, MPa: below 5 MPa a diesel would not ignite its
#: fuel reliably (the end of compression alone reaches 3.5-5.5 MPa), above 20 MPa only the most
#: highly boosted engines run (up to 25 MPa, where the core's peak-pressure rule takes over).
DIESEL_PEAK_RANGE_MPA = (5.0, 20.0)


#: How far, percent, the diagram's mean indicated pressure may lie from the thermal calculation's
#: the scene gives (the textbook allows 2–3 %); beyond it the note says the check fails.
MEAN_PRESSURE_CHECK_PERCENT = 3.0


def _mean_pressure_check(scene, results=None) -> list[tuple[str, dict]]:
    """The given mean indicated pressure further than :data:`MEAN_PRESSURE_CHECK_PERCENT` from the
    rounded diagram's (without the pumping strokes): said on the console, where the student can
    still correct the data; the note's own check says it in the section and the conclusions."""
    deviation = (results or {}).get("mean_indicated_pressure_deviation_percent")
    if not isinstance(deviation, (int, float)) or abs(deviation) <= MEAN_PRESSURE_CHECK_PERCENT:
        return []
    return [
        (
            "indicator.plausibility_mean_pressure",
            {
                "given": results["thermal_mean_indicated_pressure_Pa"] / 1e6,
                "diagram": results["gross_mean_indicated_pressure_Pa"] / 1e6,
                "deviation": abs(deviation),
                "limit": MEAN_PRESSURE_CHECK_PERCENT,
            },
        )
    ]


def _peak_lowered(scene, results=None) -> list[tuple[str, dict]]:
    """A given p_z′/p_z that would put z′ above the theoretical diagram (and was lowered); or a
    diesel's default p_z′ lowered because no pre-expansion ratio was given (ρ = 1: the whole heat
    at constant volume, so the expansion line falls below p_z within a few degrees of TDC)."""
    lowered = (results or {}).get("peak_lowered")
    if lowered and not lowered["given"] and _diesel_without_pre_expansion(scene):
        return [
            (
                "indicator.plausibility_peak_lowered_isochoric",
                {
                    "peak": round(results["peak_pressure_rounded_Pa"] / 1e6, 2),
                    "given": round(scene.cycle.max_pressure / 1e6, 2),
                    "share": round(100 * (1 - results["peak_pressure_fraction"])),
                },
            )
        ]
    if not lowered or not lowered["given"]:
        return []
    return [
        (
            "indicator.plausibility_peak_lowered",
            {
                "given": lowered["requested_fraction"],
                "angle": round(results["peak_angle_after_tdc_deg"], 1),
                "taken": round(results["peak_pressure_fraction"], 3),
            },
        )
    ]


def _diesel_without_pre_expansion(scene) -> bool:
    """A diesel whose scene gives no pre-expansion ratio ρ (taken as 1)."""
    cycle = scene.cycle
    return (
        cycle is not None
        and cycle.ignition == "diesel"
        and "pre_expansion_ratio" not in cycle.model_fields_set
    )


def _diesel_peak(scene, results=None) -> list[tuple[str, dict]]:
    """A diesel's p_z' (the rounded diagram's peak) outside :data:`DIESEL_PEAK_RANGE_MPA`."""
    if scene.cycle is None or scene.cycle.ignition != "diesel":
        return []
    peak = (results or {}).get("peak_pressure_rounded_Pa")
    if not isinstance(peak, (int, float)) or peak > MAX_PEAK_PRESSURE_PA:
        return []
    low, high = DIESEL_PEAK_RANGE_MPA
    if low <= peak / 1e6 <= high:
        return []
    return [
        ("indicator.plausibility_diesel_peak", {"pressure": peak / 1e6, "low": low, "high": high})
    ]
