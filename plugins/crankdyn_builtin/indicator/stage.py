"""Indicator diagram: theoretical p-V diagram, its rounding, or a measured pressure trace (Poda 2007 §3.1)."""

from __future__ import annotations

import functools
from functools import partial
from pathlib import Path

import numpy as np

from crankdyn.contracts import GAS_PRESSURE, KINEMATICS, GasPressure
from crankdyn.errors import Problem, SceneError
from crankdyn.physics import indicator as ind
from crankdyn.physics import pressure_trace as trace
from crankdyn.physics.extrema import first_argmax
from crankdyn.physics.forces import piston_area_m2
from crankdyn.plausibility import MAX_PEAK_PRESSURE_PA, peak_pressure
from crankdyn.plugin_types import AnswerColumn, PlausibilityRule, Stage, StageOutput, Symbol
from crankdyn.report.context import add_extreme_rows, sample_rows
from crankdyn.report.figures import crank_angle_axis, new_figure
from crankdyn.scene_inputs import cycle_parameters, rounding_parameters
from crankdyn_builtin.indicator.worked import worked_indicator

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"


def applies(scene) -> str | None:
    if scene.cycle is None:
        return "the scene has no [cycle] data (indicator-diagram parameters or a pressure trace)"
    return None


def run(scene, inputs, *, junction_deg: float | None = None,
        volumes: dict | None = None) -> StageOutput:
    """The diagram of ``scene``; ``junction_deg`` is its rounding's junction J and ``volumes`` the
    cylinder volume (m³) at the angles the rounding reads it off (deg: m³) when ``run_many`` has
    computed them for many scenes at once."""
    motion = inputs[KINEMATICS]
    engine = scene.engine
    area = piston_area_m2(engine.bore)
    swept = area * engine.stroke
    angle = motion.crank_angle_deg
    results: dict = {"source": scene.cycle.source, "swept_volume_m3": swept}
    table: dict = {"crank_angle_deg": angle}
    notes: list = []

    if scene.cycle.source == "trace":
        pressure, volume = _trace_pressure(scene, motion, area, swept)
        table.update({"cylinder_volume_m3": volume, "pressure_Pa": pressure})
        notes.append(("indicator.note_trace", {"file": scene.cycle.trace_file}))
        # a measured trace has no end of compression to read off (combustion starts before TDC):
        # the result is stated as not given, so the answer key leaves its cell empty knowingly
        results["compression_end_pressure_Pa"] = None
    else:
        params = cycle_parameters(scene)
        rounding = rounding_parameters(scene)
        clearance = ind.clearance_volume_m3(swept, params.compression_ratio)
        volume = ind.cylinder_volume_m3(motion.piston_displacement_m, area, clearance)
        theoretical = ind.theoretical_pressure_Pa(angle, volume, clearance, params)
        try:
            pressure = ind.rounded_pressure_Pa(angle, volume, clearance, params, rounding,
                                               volume_function=_volume_function(motion, area, clearance,
                                                                                volumes),
                                               junction_deg=junction_deg, theoretical_Pa=theoretical)
        except ValueError as exc:
            raise SceneError(Problem("cycle.rounding", "(see message)", str(exc))) from None
        work_theoretical = ind.indicated_work_J(theoretical, volume)
        p_i_closed = ind.theoretical_mean_indicated_pressure_Pa(params)
        table.update({"cylinder_volume_m3": volume, "pressure_theoretical_Pa": theoretical, "pressure_Pa": pressure})
        results.update({
            "clearance_volume_m3": clearance,
            "compression_end_pressure_Pa": ind.compression_end_pressure_Pa(params),
            "expansion_end_pressure_Pa": ind.expansion_end_pressure_Pa(params),
            "theoretical_mean_indicated_pressure_Pa": p_i_closed,
            "theoretical_diagram_mean_pressure_Pa": ind.mean_indicated_pressure_Pa(work_theoretical, swept),
            "ignition_advance_deg": rounding.ignition_advance_deg,
            "combustion_delay_deg": rounding.combustion_delay_deg,
            "peak_pressure_rounded_Pa": rounding.peak_pressure_fraction * params.max_pressure_Pa,
        })
        note_key = "indicator.note_rounding_diesel" if scene.cycle.ignition == "diesel" else "indicator.note_rounding"
        notes.append((note_key, {"advance": rounding.ignition_advance_deg, "delay": rounding.combustion_delay_deg,
                                 "fraction": rounding.peak_pressure_fraction,
                                 "angle": rounding.peak_angle_after_tdc_deg}))

    work = ind.indicated_work_J(pressure, volume)
    p_i = ind.mean_indicated_pressure_Pa(work, swept)
    # the thermal calculation's p_i leaves the gas exchange out (physics.indicator.pumping_work_J)
    pumping = ind.pumping_work_J(pressure, volume, angle, engine.strokes)
    p_i_gross = ind.mean_indicated_pressure_Pa(work - pumping, swept)
    peak = first_argmax(pressure)
    results.update({
        "indicated_work_J": work,
        "pumping_work_J": pumping,
        "gross_mean_indicated_pressure_Pa": p_i_gross,
        "mean_indicated_pressure_Pa": p_i,
        "max_pressure_Pa": float(pressure[peak]),
        "max_pressure_crank_angle_deg": float(angle[peak]),
        "indicated_power_W": work * engine.rpm / 60.0 / (engine.strokes / 2),
    })
    if scene.cycle.mean_indicated_pressure is not None:
        target = scene.cycle.mean_indicated_pressure
        results["thermal_mean_indicated_pressure_Pa"] = target
        results["mean_indicated_pressure_deviation_percent"] = 100.0 * (p_i_gross - target) / target
    elif scene.cycle.source == "theoretical":  # both without the pumping strokes (p_i′: eq. 4.4)
        results["diagram_fullness"] = p_i_gross / results["theoretical_mean_indicated_pressure_Pa"]

    gas = GasPressure(crank_angle_deg=angle, pressure_Pa=pressure, volume_m3=volume, source=scene.cycle.source,
                      indicated_work_J=work, swept_volume_m3=swept)
    return StageOutput(data={GAS_PRESSURE: gas}, results=results, tables={"indicator": table},
                       notes=notes)


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


def _rounding_volumes(scenes, rounding, junctions, clearances, volume_at) -> list[dict]:
    """For each scene, the cylinder volume (m³) at the angles of its rounding's points C', J and
    b' and 1e-4° either side (the central difference of the lines' slopes), computed over points
    x angles: {angle in deg: volume}. The angles are the numbers ``physics.indicator`` asks for.
    A volume below the clearance (a negative displacement) is left out: ``run`` computes it and
    refuses it as it would alone."""
    step = 1e-4  # deg: the rounding's central difference
    cycle = np.array([720.0 if s.engine.strokes == 4 else 360.0 for s in scenes])[:, None]
    tdc = np.array([360.0 if s.engine.strokes == 4 else 0.0 for s in scenes])[:, None]
    psi = np.array([[-(r.ignition_advance_deg - r.combustion_delay_deg), j,
                     180.0 - r.exhaust_opens_before_bdc_deg] for r, j in zip(rounding, junctions, strict=False)])
    at = np.mod(tdc + psi, cycle)
    angles = np.concatenate([at, at + step, at - step], axis=1)
    rows = np.arange(len(scenes))
    found = np.isfinite(angles)
    values = volume_at(np.where(found, angles, 0.0), rows)
    found &= values >= np.asarray(clearances, dtype=float)[:, None]
    return [{float(a): float(v) for a, v, ok in zip(angles[k], values[k], found[k], strict=False) if ok}
            for k in rows]


def _stacked_displacement(motions):
    """The motions' ``displacement_at`` as one function ``(angle_deg, rows) -> m`` of angles
    (rows, M), when they are one function with other numbers (``functools.partial`` of the same
    function, each number a column); None otherwise."""
    first = motions[0].displacement_at
    partials = [m.displacement_at for m in motions]
    if not all(isinstance(d, functools.partial) and d.func is first.func and not d.keywords
               and len(d.args) == len(first.args) for d in partials):
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
    if (displacement is None or any(s.cycle.source != "theoretical" for s in scenes)
            or len({s.engine.strokes for s in scenes}) > 1):
        return [run(scene, given) for scene, given in zip(scenes, inputs, strict=False)]
    params = [cycle_parameters(scene) for scene in scenes]
    areas = np.asarray([piston_area_m2(scene.engine.bore) for scene in scenes], dtype=float)
    clearances = np.asarray([ind.clearance_volume_m3(area * s.engine.stroke, p.compression_ratio)
                             for area, s, p in zip(areas, scenes, params, strict=False)], dtype=float)
    area_column, clearance_column = areas[:, None], clearances[:, None]

    def volume_at(angle_deg, rows):
        return clearance_column[rows] + area_column[rows] * displacement(angle_deg, rows)

    rounding = [rounding_parameters(s) for s in scenes]
    junctions = ind.combustion_junctions_deg(params, rounding, clearances, volume_at)
    volumes = _rounding_volumes(scenes, rounding, junctions, clearances, volume_at)
    return [run(scene, given, junction_deg=float(j), volumes=v)
            for scene, given, j, v in zip(scenes, inputs, junctions, volumes, strict=False)]


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
        pressure = trace.to_cycle_grid(angle_file, pressure_file, scene.engine.cycle_deg, motion.crank_angle_deg,
                                       c.trace_firing_tdc_deg, target_tdc)
    except (trace.PressureTraceError, OSError) as exc:
        raise SceneError(Problem("cycle.trace_file", c.trace_file, str(exc))) from None
    clearance = ind.clearance_volume_m3(swept, c.compression_ratio)
    volume = ind.cylinder_volume_m3(motion.piston_displacement_m, area, clearance)
    return pressure, volume


#: The textbook's characteristic points of a four-stroke diagram: (label, crank angle of cylinder 1 in
#: degrees or a rounding parameter's name, which curve, label offset in points). 0° is the TDC at
#: the start of intake; "advance" is the ignition (injection), "visible" the start of visible
#: combustion, "peak" the actual cycle's largest pressure, "exhaust" the exhaust valve's opening;
#: the curve is the theoretical or the actual (rounded) one, or p_c for the end of compression.
#: A vertical offset of 0 centres the label on its point's height: b″ stands between b and a at
#: BDC, and a label under it would read as a's.
_POINTS = (("r", 0.0, "actual", (4, 3)), ("a", 180.0, "actual", (-4, -3)),
           ("c", 360.0, "compression_end", (-4, 2)), ("c′", "advance", "actual", (4, -3)),
           ("f", "visible", "actual", (-5, 3)), ("c″", 360.0, "actual", (4, -2)),
           ("z", "theory_peak", "theory", (4, 2)), ("z′", "peak", "actual", (4, 2)),
           ("b′", "exhaust", "actual", (3, 3)), ("b", 540.0, "theory", (4, 3)), ("b″", 540.0, "actual", (5, 0)))


def _pumping_inset(ax, volume_l, theory_MPa, actual_MPa, t) -> None:
    """The exhaust and intake strokes enlarged in a corner of the p–V diagram: at the scale of the
    combustion peak the pumping loop (0,1 MPa against 5 MPa) is one line."""
    low = 0.45 * float(np.max(actual_MPa)) / 5.0 + 0.1  # about 0.55 MPa for a 5 MPa peak
    inset = ax.inset_axes([0.45, 0.32, 0.5, 0.42])
    inset.plot(volume_l, theory_MPa, color="0.45", lw=0.8, ls="--")
    inset.plot(volume_l, actual_MPa, color="C3", lw=1.0)
    inset.set_ylim(0.0, low)
    inset.set_xlim(float(np.min(volume_l)), float(np.max(volume_l)))
    inset.tick_params(labelsize=7)
    inset.set_xlabel(t("indicator.axis_volume"), fontsize=7, labelpad=1)
    inset.set_ylabel(t("indicator.axis_pressure"), fontsize=7, labelpad=1)
    inset.set_title(t("indicator.inset_title"), fontsize=7)


def _characteristic_points(ctx, frame, r) -> list[tuple[str, float, float, tuple[int, int]]]:
    """(label, volume in l, pressure in MPa, label offset) of each characteristic point of a
    four-stroke diagram computed from cycle data; none for other cycles."""
    if ctx.scene is None or ctx.scene.engine.strokes != 4 or getattr(ctx.scene, "cycle", None) is None:
        return []
    angle = frame["crank_angle_deg"]
    theory, actual = frame["pressure_theoretical_Pa"] / 1e6, frame["pressure_Pa"] / 1e6
    # the rounding's angles as run() used them (its results), the valve timing as the scene gives it
    where = {"advance": 360.0 - r["ignition_advance_deg"],
             "visible": 360.0 - r["ignition_advance_deg"] + r["combustion_delay_deg"],
             "peak": r["max_pressure_crank_angle_deg"], # the end of heat addition: at ρV_c in a diesel's theoretical cycle (the last point at p_z)
             "theory_peak": float(angle[int(np.flatnonzero(theory >= theory.max() * (1 - 1e-12))[-1])]),
             "exhaust": 540.0 - ctx.scene.cycle.rounding.exhaust_opens_before_bdc_deg}
    step = float(angle[1] - angle[0])
    points = []
    for label, at, curve, offset in _POINTS:
        i = int(round(where.get(at, at) / step)) % len(angle)  # a named event's angle, or the angle given
        # c: the end of the compression line, p_c; at TDC itself the theoretical spark-ignition cycle
        # is already at p_z (heat added at constant volume)
        p = (r["compression_end_pressure_Pa"] / 1e6 if curve == "compression_end"
             else theory[i] if curve == "theory" else actual[i])
        points.append((label, float(frame["cylinder_volume_m3"][i] * 1e3), float(p), offset))
    return points


def render(output: StageOutput, ctx) -> str:
    t = ctx.t
    frame = output.tables.arrays("indicator")
    r = output.results
    angle = frame["crank_angle_deg"]
    volume_l = frame["cylinder_volume_m3"] * 1e3
    pressure = frame["pressure_Pa"] / 1e6
    has_theory = "pressure_theoretical_Pa" in frame

    theory = frame["pressure_theoretical_Pa"] / 1e6 if has_theory else None
    points = _characteristic_points(ctx, frame, r) if has_theory else []
    figure_pv = ctx.figure(partial(_pv_figure, volume_l, pressure, theory, points, t),
                           t("indicator.pv_caption_points" if points else "indicator.pv_caption"), "pV",
                           see="indicator.see_pv")
    pv_number = ctx.last_figure_number
    figure_pa = ctx.figure(partial(_palpha_figure, angle, pressure, theory, ctx.cycle_deg, t),
                           t("indicator.palpha_caption"), "p_alpha", see="indicator.see_palpha")

    rows, labels = sample_rows(angle, ctx.table_step_deg)
    rows, labels, extremes = add_extreme_rows(angle, rows, labels,
                                              [(pressure, "max", t("indicator.extreme_p_max"))])
    columns = [("<i>α</i>, °", ctx.angle_labels(labels), None), ("<i>V</i>, " + t("unit.l"), volume_l[rows], 4)]
    if has_theory:
        columns.append(("<i>p</i><sub>theor</sub>, " + t("unit.MPa"), _closing_row_theory(theory, rows, labels,
                                                                                         ctx.cycle_deg), 4))
    columns.append(("<i>p</i>, " + t("unit.MPa"), pressure[rows], 4))
    table = ctx.table(columns, caption=t("indicator.table_caption"), extremes=extremes, see="indicator.see_table")
    table += worked_indicator(ctx, frame, rows, labels, r)

    ctx.find(t("indicator.finding", p_max=ctx.num(r["max_pressure_Pa"] / 1e6),
                angle=ctx.angle_text(r["max_pressure_crank_angle_deg"])))
    deviation = r.get("mean_indicated_pressure_deviation_percent")
    ctx.conclude(t("indicator.conclusion", p_max=ctx.num(r["max_pressure_Pa"] / 1e6),
                   angle=ctx.angle_text(r["max_pressure_crank_angle_deg"]),
                   p_i=ctx.num(r["mean_indicated_pressure_Pa"] / 1e6), work=ctx.num(r["indicated_work_J"])))
    if deviation is not None:
        key = "indicator.check_ok" if abs(deviation) <= 3.0 else "indicator.check_bad"
        ctx.conclude(t(key, deviation=ctx.num(deviation, 2)))
    diesel = getattr(getattr(ctx.scene, "cycle", None), "ignition", None) == "diesel"
    return ctx.render_template("sections/indicator.html.j2", r=r, figure_pv=figure_pv, figure_pa=figure_pa, diesel=diesel,
                               points=bool(points), pv_number=pv_number,
                               table=table, deviation=deviation, has_theory=has_theory)


def _pv_figure(volume_l, pressure, theory, points, t):
    """The p–V diagram: the actual (or measured) cycle, the theoretical one and its characteristic points."""
    fig, ax = new_figure(16, 9.5)
    if theory is not None:
        ax.plot(np.append(volume_l, volume_l[0]), np.append(theory, theory[0]), color="0.45", lw=1, ls="--",
                label=t("indicator.theoretical"))
    ax.plot(np.append(volume_l, volume_l[0]), np.append(pressure, pressure[0]), color="C3",
            label=t("indicator.actual") if theory is not None else t("indicator.trace"))
    if theory is not None:
        _pumping_inset(ax, np.append(volume_l, volume_l[0]), np.append(theory, theory[0]),
                       np.append(pressure, pressure[0]), t)
    for label, volume, p, (dx, dy) in points:
        ax.plot([volume], [p], "o", ms=3, color="k")
        ax.annotate(label, (volume, p), xytext=(dx, dy), textcoords="offset points", fontsize=8, style="italic",
                    ha="left" if dx >= 0 else "right", va="center" if dy == 0 else "bottom" if dy > 0 else "top")
    ax.set_xlabel(t("indicator.axis_volume"))
    ax.set_ylabel(t("indicator.axis_pressure"))
    ax.legend(loc="upper right", fontsize=8)
    return fig


def _palpha_figure(angle, pressure, theory, cycle_deg, t):
    """The pressure against the crank angle over the cycle (with the theoretical one, if any)."""
    fig, ax = new_figure(16, 8)
    if theory is not None:
        ax.plot(angle, theory, color="0.45", lw=1, ls="--", label=t("indicator.theoretical"))
    ax.plot(angle, pressure, color="C3", label=t("indicator.actual") if theory is not None else t("indicator.trace"))
    crank_angle_axis(ax, cycle_deg, t("axis.crank_angle"))
    ax.set_ylabel(t("indicator.axis_pressure"))
    ax.legend(loc="upper right", fontsize=8)
    return fig


def _closing_row_theory(theory, rows, labels, cycle_deg: float):
    """The theoretical pressure at the table's rows, the closing row (720°) given the value the
    diagram ends the cycle with: where it ends on a flat line (the exhaust line at p_r, point r),
    that line's value, not the intake's p_a that the periodic grid has at 0° (the theoretical
    diagram steps from p_r to p_a at TDC; a table with p_a at 720° contradicts point r)."""
    shown = np.array(theory[rows], dtype=float)
    if len(labels) and abs(float(labels[-1]) - cycle_deg) < 1e-9 and len(theory) > 2 and theory[-1] == theory[-2]:
        shown[-1] = theory[-1]
    return shown


#: The indicator's own letters (Stage.symbols): the theoretical (unrounded) diagram's pressure of its table.
SYMBOLS = {
    "theoretical_pressure": Symbol("p", {"en": "theor", "uk": "теор", "ru": "теор"}, "unit.MPa"),
}



#: The rounded diagram's peak p_z' of a diesel, MPa: below 5 MPa a diesel would not ignite its
#: fuel reliably (the end of compression alone reaches 3.5-5.5 MPa), above 20 MPa only the most
#: highly boosted engines run (up to 25 MPa, where the core's peak-pressure rule takes over).
DIESEL_PEAK_RANGE_MPA = (5.0, 20.0)


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
    return [("indicator.plausibility_diesel_peak",
             {"pressure": peak / 1e6, "low": low, "high": high})]


INDICATOR_STAGE = Stage(
    plausibility=(peak_pressure("max_pressure_Pa"), PlausibilityRule("diesel_peak", _diesel_peak)),
    template_dir=TEMPLATES,
    name="indicator",
    # the core's letters that hold with their meaning in this section only
    section_symbols=("post_expansion_ratio",),
    title_key="indicator.title",
    requires=(KINEMATICS,),
    provides=(GAS_PRESSURE,),
    applies=applies,
    run=run,
    run_many=run_many,
    render=render,
    figures=("pV", "p_alpha"),
    tables=("indicator",),
    references=("poda2007", "orlin1983", "heywood1988"),
    symbols=SYMBOLS,
    answer_columns=(
        AnswerColumn("p_c_MPa", "compression_end_pressure_Pa", "MPa", factor=1e-06, label_key="indicator.answer.p_c_MPa"),
        AnswerColumn("p_max_MPa", "max_pressure_Pa", "MPa", factor=1e-06, label_key="indicator.answer.p_max_MPa"),
        AnswerColumn("p_max_crank_angle_deg", "max_pressure_crank_angle_deg", "°", label_key="indicator.answer.p_max_crank_angle_deg"),
        AnswerColumn("p_i_MPa", "mean_indicated_pressure_Pa", "MPa", factor=1e-06, label_key="indicator.answer.p_i_MPa"),
        AnswerColumn("L_i_J", "indicated_work_J", "J", label_key="indicator.answer.L_i_J"),
        AnswerColumn("N_i_cylinder_kW", "indicated_power_W", "kW", factor=0.001, label_key="indicator.answer.N_i_cylinder_kW"),
    ),
)
