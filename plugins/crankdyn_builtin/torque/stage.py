"""Crankshaft loads and the engine's output torque (Poda 2007 §4.3-4.4, tables B.3 and B.4)."""

from __future__ import annotations

from functools import partial
from pathlib import Path

import numpy as np

from crankdyn.contracts import BAY_LOADS, CRANK_LOADS, ENGINE_TORQUE, CrankLoads, EngineTorque
from crankdyn.physics import crankshaft as cs
from crankdyn.physics import layout as lay
from crankdyn.physics.extrema import first_argmax, first_argmin
from crankdyn.plausibility import mechanical_efficiency
from crankdyn.plugin_types import AnswerColumn, Stage, StageOutput
from crankdyn.report.context import add_extreme_rows, sample_rows
from crankdyn.report.figures import crank_angle_axis, curve_with_mean_figure, new_figure
from crankdyn.report.typeset import journal_name
from crankdyn_builtin.torque.worked import worked_torque

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"


def applies(scene) -> str | None:
    if scene.masses is None:
        return "the scene has no [masses]"
    return None


def run(scene, inputs, *, period_deg: float | None = None) -> StageOutput:
    """The loads and torque of ``scene``; ``period_deg`` is its torque's sampled period when
    ``run_many`` has measured it for many scenes at once."""
    bays = inputs[BAY_LOADS]
    e = scene.engine
    layout = bays.layout
    angle = bays.crank_angle_deg
    R, area = bays.crank_radius_m, bays.piston_area_m2
    pin, journal = cs.running_torques(bays.tangential_Pa)
    q = cs.resultant_Pa(bays.tangential_Pa, bays.radial_Pa, bays.centrifugal_Pa)
    torque = journal[-1] * R * area
    work_all = bays.indicated_work_J
    revolutions = e.strokes / 2
    mean = float(np.mean(torque))
    from_work = work_all / (2 * np.pi * revolutions)
    from_power = cs.torque_from_power_Nm(work_all / e.cylinders, e.cylinders, e.strokes, e.rpm)
    i_max, i_min = first_argmax(torque), first_argmin(torque)
    combos = cs.dangerous_combinations(bays.radial_Pa, bays.tangential_Pa, q, journal)
    results = {
        "mean_Nm": mean,
        "mean_from_work_Nm": from_work,
        "mean_deviation_percent": 100 * (mean - from_work) / from_work if from_work else None,
        "mean_from_power_Nm": from_power,
        "mean_vs_power_deviation_percent": 100 * (mean - from_power) / from_power if from_power else None,
        "max_Nm": float(torque[i_max]),
        "max_crank_angle_deg": float(angle[i_max]),
        "min_Nm": float(torque[i_min]),
        "min_crank_angle_deg": float(angle[i_min]),
        # measured on the torque itself: cycle/cylinders for even firing of identical cylinders, longer
        # when the firing is uneven or the cylinders differ (articulated slave rods)
        "period_deg": (lay.sampled_period_deg(torque, scene.analysis.angle_step_deg,
                                              layout.cycle_deg)
                       if period_deg is None else period_deg),
        "period_even_firing_deg": layout.torque_period_deg,
        "non_uniformity": cs.torque_non_uniformity(torque),
        # each cylinder's cycle delay: its own crank angle alpha_i = alpha - delay (mod the cycle)
        "cylinder_cycle_delays_deg": [{k: p[k] for k in ("cylinder", "crank", "cycle_delay_deg")}
                                      for p in lay.cylinder_phases(layout)],
        "indicated_power_W": 1e3 * cs.indicated_power_kW(work_all / e.cylinders, e.cylinders, e.strokes, e.rpm),
        "journals": [_journal_range(lay.journal_label(k + 1), journal[k] * R * area)  # as the bearings' journals
                     for k in range(layout.cranks)],
        "dangerous": [{"crank": k + 1, **{kind: {"shaft_angle_deg": float(angle[i]),
                                                 "z_Pa": float(bays.radial_Pa[k, i]),
                                                 "t_Pa": float(bays.tangential_Pa[k, i]),
                                                 "q_Pa": float(q[k, i]),
                                                 "journal_t_Pa": float(journal[k, i])}
                                          for kind, i in combo.items()}}
                      for k, combo in enumerate(combos)],
    }
    if e.effective_power is not None:
        results.update(cs.effective_output(results["indicated_power_W"], e.effective_power, e.angular_velocity_rad_s))
    columns = {"crank_angle_deg": angle}
    for k in range(layout.cranks):
        columns[f"crank{k + 1}_radial_Pa"] = bays.radial_Pa[k]
        columns[f"crank{k + 1}_tangential_Pa"] = bays.tangential_Pa[k]
        columns[f"crank{k + 1}_resultant_Pa"] = q[k]
        columns[f"crank{k + 1}_pin_torque_Pa"] = pin[k]
        columns[f"journal{k + 1}_torque_Pa"] = journal[k]
    columns["output_torque_Nm"] = torque
    data = {
        ENGINE_TORQUE: EngineTorque(crank_angle_deg=angle, torque_Nm=torque, cylinders=e.cylinders, strokes=e.strokes,
                                    indicated_work_J=work_all, angular_velocity_rad_s=e.angular_velocity_rad_s),
        CRANK_LOADS: CrankLoads(crank_angle_deg=angle, tangential_Pa=bays.tangential_Pa, radial_Pa=bays.radial_Pa,
                                resultant_Pa=q, pin_torque_Pa=pin, journal_torque_Pa=journal,
                                centrifugal_Pa=bays.centrifugal_Pa, piston_area_m2=area, crank_radius_m=R),
    }
    return StageOutput(data=data, results=results, tables={"torque": columns})


def sampled_periods_deg(values, cycle_deg: float, rtol: float = 1e-9) -> np.ndarray:
    """``physics.layout.sampled_period_deg`` of each row of ``values`` (points x angles over
    ``cycle_deg``), the rows tested together: per row the smallest cycle/k (a whole number of
    steps) by which the samples repeat within ``rtol`` x their range, deg."""
    v = np.asarray(values, dtype=float)
    count, n = v.shape
    tol = rtol * np.maximum(np.maximum(np.ptp(v, axis=1), np.max(np.abs(v), axis=1)), 1e-300)
    period = np.full(count, float(cycle_deg))
    open_rows = np.arange(count)
    for k in range(n, 1, -1):
        if n % k or not open_rows.size:
            continue
        shift = n // k
        # the first sample rejects most shifts: only the rows it passes are compared in full
        rows = open_rows[np.abs(v[open_rows, -shift] - v[open_rows, 0]) <= tol[open_rows]]
        if rows.size:
            repeats = np.max(np.abs(np.roll(v[rows], shift, axis=1) - v[rows]), axis=1) <= tol[rows]
            period[rows[repeats]] = cycle_deg / k
            open_rows = np.setdiff1d(open_rows, rows[repeats])
    return period


def _output_torque_Nm(bays):
    """The engine's output torque over the cycle, N·m (eq. 46)."""
    return cs.running_torques(bays.tangential_Pa)[1][-1] * bays.crank_radius_m * bays.piston_area_m2


def run_many(scenes, inputs) -> list[StageOutput]:
    """``run`` over many scenes at once (a sweep's points): the torques' periods, the search over
    the cycle's divisors that dominates a point, measured over points x angles; each scene's loads
    then as ``run`` gives them. Scenes on other grids or cycles: ``run`` one by one."""
    bays = [given[BAY_LOADS] for given in inputs]
    first = bays[0]
    if not all(b.layout.cycle_deg == first.layout.cycle_deg
               and np.array_equal(b.crank_angle_deg, first.crank_angle_deg) for b in bays):
        return [run(scene, given) for scene, given in zip(scenes, inputs, strict=False)]
    torques = np.stack([_output_torque_Nm(b) for b in bays])
    periods = sampled_periods_deg(torques, first.layout.cycle_deg)
    return [run(scene, given, period_deg=float(period))
            for scene, given, period in zip(scenes, inputs, periods, strict=False)]


def _journal_range(name: str, torque_Nm) -> dict:
    """A main journal's running torque over the cycle: its largest magnitude, its largest and
    smallest values and the amplitude (M_max − M_min)/2 a fatigue check of the journal takes."""
    high, low = float(np.max(torque_Nm)), float(np.min(torque_Nm))
    return {"journal": name, "max_abs_Nm": float(np.max(np.abs(torque_Nm))), "max_Nm": high, "min_Nm": low,
            "amplitude_Nm": (high - low) / 2}


def _journals_table(ctx, journals) -> str:
    """The running torques' range on each main journal (after the figure of them)."""
    t = ctx.t
    return ctx.table([
        (t("torque.journal"), [journal_name(j["journal"]) for j in journals], None),
        (t("torque.journal_max") + ", " + t("unit.Nm"), [j["max_Nm"] for j in journals], 1),
        (t("torque.journal_min") + ", " + t("unit.Nm"), [j["min_Nm"] for j in journals], 1),
        (t("torque.journal_amplitude") + ", " + t("unit.Nm"), [j["amplitude_Nm"] for j in journals], 1),  # words: M_max is the engine's
    ], caption=t("torque.journals_table_caption"), see="torque.see_journals_table")


def render(output: StageOutput, ctx) -> str | None:
    r = output.results
    f = output.tables.arrays("torque")
    cranks = sum(1 for c in f.columns if c.startswith("journal"))
    if ctx.scene.engine.cylinders == 1:
        return None  # one cylinder: its crank torque is already in the forces section
    t = ctx.t
    angle = f["crank_angle_deg"]
    rows, labels = sample_rows(angle, ctx.table_step_deg)
    rows, labels, extremes = add_extreme_rows(angle, rows, labels, [
        (f["output_torque_Nm"], "max", t("torque.extreme_max")),
        (f["output_torque_Nm"], "min", t("torque.extreme_min"))])
    columns = [("<i>α</i>, °", ctx.angle_labels(labels), None)]
    for k in range(1, cranks + 1):
        columns += [(f"<i>z</i><sub>{k}</sub>", f[f"crank{k}_radial_Pa"][rows] / 1e6, 3),
                    (f"<i>t</i><sub>{k}</sub>", f[f"crank{k}_tangential_Pa"][rows] / 1e6, 3),
                    (f"<i>t</i><sub>w{k}</sub>", f[f"crank{k}_pin_torque_Pa"][rows] / 1e6, 3),
                    (f"<i>t</i><sub>k{k}</sub>", f[f"journal{k}_torque_Pa"][rows] / 1e6, 3)]
    columns.append(("<i>M</i><sub>d</sub>, " + t("unit.Nm"), f["output_torque_Nm"][rows], 1))
    # Wide engines: split the B.3 table into chunks of cranks so it fits the page.
    tables = []
    per_table = 4
    for start in range(0, cranks, per_table):
        chunk = [columns[0]] + columns[1 + 4 * start: 1 + 4 * min(start + per_table, cranks)]
        if start + per_table >= cranks:
            chunk.append(columns[-1])
        with_torque = chunk[-1] is columns[-1]
        caption = "torque.table_b3_caption_torque" if with_torque else "torque.table_b3_caption"
        if cranks == 1:  # one crank carries every cylinder: no running torques between cranks
            caption = "torque.table_b3_caption_single"
        see = ("torque.see_table_b3_single" if cranks == 1 else "torque.see_table_b3_torque") if with_torque \
            else "torque.see_table_b3"
        tables.append(ctx.table(chunk, caption=t(caption, first=start + 1,
                                                   last=min(start + per_table, cranks)), css_class="data wide",
                                  extremes=extremes, see=see))
    tables[-1] += worked_torque(ctx, f, rows, labels, cranks, output.results["cylinder_cycle_delays_deg"])

    figure_output = ctx.figure(partial(_output_figure, angle, f["output_torque_Nm"], r["mean_Nm"], ctx.cycle_deg, t),
                               t("torque.output_caption"), "output_torque", see="torque.see_output")
    # one crank: its one journal behind it carries the output torque, shown above
    figure_journals = None if cranks == 1 else ctx.figure(
        partial(_journals_figure, f, cranks, ctx.cycle_deg, t), t("torque.journals_caption"),
        "journal_torques", see="torque.see_journals")
    journals_table = None if cranks == 1 else _journals_table(ctx, r["journals"])
    danger_rows = [(d["crank"], kind, d[kind]) for d in r["dangerous"] for kind in ("Z", "T", "Q", "M")]
    danger = ctx.table([
        (t("torque.crank"), [str(c) for c, _, _ in danger_rows], None),
        (t("torque.criterion"), [t("torque.criterion_" + kind) for _, kind, _ in danger_rows], None),
        ("<i>α</i>, °", [v["shaft_angle_deg"] for _, _, v in danger_rows], 0),
        ("<i>z</i>, " + t("unit.MPa"), [v["z_Pa"] / 1e6 for _, _, v in danger_rows], 3),
        ("<i>t</i>, " + t("unit.MPa"), [v["t_Pa"] / 1e6 for _, _, v in danger_rows], 3),
        ("<i>q</i>, " + t("unit.MPa"), [v["q_Pa"] / 1e6 for _, _, v in danger_rows], 3),
        ("<i>t</i><sub>k<i>i</i></sub>, " + t("unit.MPa"), [v["journal_t_Pa"] / 1e6 for _, _, v in danger_rows], 3),
    ], caption=t("torque.table_b4_caption"),
        see="torque.see_table_b4_single" if cranks == 1 else "torque.see_table_b4")

    ctx.find(t("torque.finding", mean=ctx.num(r["mean_Nm"])))
    ctx.conclude(t("torque.conclusion", mean=ctx.num(r["mean_Nm"]), from_work=ctx.num(r["mean_from_work_Nm"]),
                   deviation=ctx.num(r["mean_deviation_percent"] or 0.0, 2), max=ctx.num(r["max_Nm"]),
                   max_angle=ctx.angle_text(r["max_crank_angle_deg"]), min=ctx.num(r["min_Nm"]),
                   period=ctx.angle_text(r["period_deg"]), mu=ctx.num(r["non_uniformity"], 3)))
    if r.get("mechanical_efficiency") is not None:
        ctx.conclude(t("torque.conclusion_effective", me=ctx.num(r["mean_effective_torque_Nm"]),
                       eta=ctx.num(r["mechanical_efficiency"], 3)))
    return ctx.render_template("sections/torque.html.j2", r=r, tables=tables, figure_output=figure_output,
                               figure_journals=figure_journals, journals_table=journals_table, danger=danger)


def _output_figure(angle, torque_Nm, mean_Nm, cycle_deg, t):
    """The engine's output torque over the cycle, with its mean."""
    return curve_with_mean_figure(angle, torque_Nm, mean_Nm, cycle_deg, t,
                                  (t("torque.output"), t("torque.mean"), t("torque.axis_torque")), height_cm=8.5)


def _journals_figure(f, cranks, cycle_deg, t):
    """The running torque on each main journal over the cycle."""
    angle = f["crank_angle_deg"]
    fig, ax = new_figure(16, 9)
    for k in range(1, cranks + 1):
        ax.plot(angle, f[f"journal{k}_torque_Pa"] / 1e6, lw=1, label=t("torque.journal_label", k=k))
    crank_angle_axis(ax, cycle_deg, t("axis.crank_angle"))
    ax.set_ylabel("t_k, " + t("unit.MPa"))  # the running torque as a specific tangential force (table B.3)
    ax.legend(loc="upper right", fontsize=8, ncol=3)
    return fig


TORQUE_STAGE = Stage(
    template_dir=TEMPLATES,
    name="torque",
    # the core's letters that hold with their meaning in this section only
    section_symbols=("indicated_torque",),
    title_key="torque.title",
    requires=(BAY_LOADS,),
    provides=(ENGINE_TORQUE, CRANK_LOADS),
    applies=applies,
    run=run,
    run_many=run_many,
    render=render,
    figures=("output_torque", "journal_torques"),
    tables=("torque",),
    references=("poda2007", "lukanin1995"),
    plausibility=(mechanical_efficiency("mechanical_efficiency"),),
    answer_columns=(
        AnswerColumn("M_mean_Nm", "mean_Nm", "N·m", label_key="torque.answer.M_mean_Nm"),
        AnswerColumn("M_max_Nm", "max_Nm", "N·m", label_key="torque.answer.M_max_Nm"),
        AnswerColumn("M_min_Nm", "min_Nm", "N·m", label_key="torque.answer.M_min_Nm"),
        AnswerColumn("torque_non_uniformity", "non_uniformity", "", label_key="torque.answer.torque_non_uniformity"),
        AnswerColumn("N_i_engine_kW", "indicated_power_W", "kW", factor=0.001, label_key="torque.answer.N_i_engine_kW"),
    ),
)
