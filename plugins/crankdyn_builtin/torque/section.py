"""The torque stage's section: its text, the journals' table and the output torque's rows."""

from __future__ import annotations

from dataclasses import replace
from functools import partial

from markupsafe import Markup

from crankdyn.plugin.contracts import COUNTERWEIGHTS
from crankdyn.plugin.scene_inputs import power_take_off
from crankdyn.plugin.types import StageOutput, Symbol
from crankdyn.report.context import add_extreme_rows, exact_decimals, sample_rows
from crankdyn.report.typeset import journal_name
from crankdyn_builtin.torque.worked import worked_torque

from .figures import _journals_figure, _output_figure

#: Decimals of a torque in N·m in the tables, and of the torques the conclusions take from them:
#: one rounding of a quantity wherever it is printed.
TORQUE_DECIMALS = 1


#: The catalog suffix of the power take-off end (:func:`power_take_off`).
OUTPUT_ENDS = {"propeller": "_propeller", "drive": "_power", "flywheel": ""}


def output_end(scene) -> str:
    """The catalog suffix of the power take-off end: the propeller's, a boat's drive's or the
    flywheel's."""
    return OUTPUT_ENDS[power_take_off(scene)]


def _journals_table(ctx, journals) -> str:
    """The running torques' range on each main journal (after the figure of them)."""
    t = ctx.t
    return ctx.table(
        [
            (t("torque.journal"), [journal_name(j["journal"]) for j in journals], None),
            (
                t("torque.journal_max") + ", " + t("unit.Nm"),
                [j["max_Nm"] for j in journals],
                TORQUE_DECIMALS,
            ),
            (
                t("torque.journal_min") + ", " + t("unit.Nm"),
                [j["min_Nm"] for j in journals],
                TORQUE_DECIMALS,
            ),
            (
                t("torque.journal_amplitude") + ", " + t("unit.Nm"),
                [j["amplitude_Nm"] for j in journals],
                TORQUE_DECIMALS,
            ),  # words: M_max is the engine's
        ],
        caption=t("torque.journals_table_caption"),
        see="torque.see_journals_table",
    )


def render(output: StageOutput, ctx) -> str | None:
    r = output.results
    f = output.tables.arrays("torque")
    cranks = sum(1 for c in f.columns if c.startswith("journal"))
    if ctx.scene.engine.cylinders == 1:
        return None  # one cylinder: its crank torque is already in the forces section
    t = ctx.t
    angle = f["crank_angle_deg"]
    rows, labels = sample_rows(angle, ctx.table_step_deg)
    rows, labels, extremes = add_extreme_rows(
        angle,
        rows,
        labels,
        [
            (f["output_torque_Nm"], "max", t("torque.extreme_max")),
            (f["output_torque_Nm"], "min", t("torque.extreme_min")),
        ],
        # the conclusions give the torque's range to its printed 0.1 N·m with the angles of its
        # extremes: a row of the table shows each, not only one a hundredth of the range off
        resolution=TORQUE_ROW_RESOLUTION,
    )
    columns = _b3_columns(ctx, f, rows, labels, cranks)
    tables = _b3_tables(ctx, columns, cranks, extremes)
    delays = output.results["cylinder_cycle_delays_deg"]
    if cranks > 1 and len(delays) > cranks:  # a V's, W's or star's crank carries several cylinders
        tables[0] = (
            Markup("<p>{}</p>").format(t("torque.crank_sums", n=len(delays) // cranks)) + tables[0]
        )
    tables[-1] += worked_torque(ctx, f, rows, labels, cranks, delays)

    figure_output = ctx.figure(
        partial(_output_figure, angle, f["output_torque_Nm"], r["mean_Nm"], ctx.cycle_deg, t),
        t("torque.output_caption"),
        "output_torque",
        see="torque.see_output",
    )
    # one crank: its one journal behind it carries the output torque, shown above
    figure_journals = (
        None
        if cranks == 1
        else ctx.figure(
            partial(
                _journals_figure, f, cranks, ctx.cycle_deg, t, r["torque_per_specific_force_m3"]
            ),
            t("torque.journals_caption"),
            "journal_torques",
            see="torque.see_journals" + output_end(ctx.scene),
        )
    )
    journals_table = None if cranks == 1 else _journals_table(ctx, r["journals"])
    danger = _danger_table(ctx, r, cranks)
    danger_number = ctx.last_table_number
    _conclude(ctx, r)
    if len(delays) > cranks:  # the forces section gave one cylinder's part: the whole crank's
        _conclude_crank_load(ctx, r, danger_number)
    return ctx.render_template(
        "sections/torque.html.j2",
        r=r,
        tables=tables,
        figure_output=figure_output,
        figure_journals=figure_journals,
        journals_table=journals_table,
        danger=danger,
        output_end=output_end(ctx.scene),
        # a crank of several cylinders: its q holds the rods of all of them
        several_per_crank=len(delays) > cranks,
    )


def _b3_columns(ctx, f, rows, labels, cranks: int) -> list:
    """Table B.3's columns: each crank's loads and running torques (one crank's sums over its
    cylinders), then the output torque."""
    columns = [("<i>α</i>, °", ctx.angle_labels(labels), None)]
    if cranks == 1:  # one crank: the sums over its cylinders, no running torque between cranks
        columns += [
            ("<i>z</i><sub>Σ</sub>", f["crank1_radial_Pa"][rows] / 1e6, 3),
            ("<i>t</i><sub>Σ</sub>", f["crank1_tangential_Pa"][rows] / 1e6, 3),
        ]
    for k in range(1, cranks + 1 if cranks > 1 else 1):
        columns += [
            (f"<i>z</i><sub>{k}</sub>", f[f"crank{k}_radial_Pa"][rows] / 1e6, 3),
            (f"<i>t</i><sub>{k}</sub>", f[f"crank{k}_tangential_Pa"][rows] / 1e6, 3),
            (f"<i>t</i><sub>w{k}</sub>", f[f"crank{k}_pin_torque_Pa"][rows] / 1e6, 3),
            (f"<i>t</i><sub>k{k}</sub>", f[f"journal{k}_torque_Pa"][rows] / 1e6, 3),
        ]
    columns.append(
        ("<i>M</i><sub>d</sub>, " + ctx.t("unit.Nm"), f["output_torque_Nm"][rows], TORQUE_DECIMALS)
    )
    return columns


#: The share of the torque's range by which the table's rows may miss its largest and least
#: values before a row is added at them (the conclusions quote both to 0.1 N·m).
TORQUE_ROW_RESOLUTION = 1e-4


def _b3_tables(ctx, columns: list, cranks: int, extremes) -> list:
    """Table B.3 in chunks of four cranks, so that a wide engine's fits the page; the output
    torque in the last."""
    t = ctx.t
    tables = []
    per_table = 4
    # the torque's extremes are its own rows: a part without its column names the part with it
    section, before = ctx.last_table_number.split(".")
    torque_number = f"{section}.{int(before) + -(-cranks // per_table)}"
    elsewhere = [
        replace(e, what=t("torque.extreme_in_table", what=e.what, number=torque_number))
        for e in extremes
    ]
    for start in range(0, cranks, per_table):
        chunk = (
            [columns[0]] + columns[1 + 4 * start : 1 + 4 * min(start + per_table, cranks)]
            if cranks > 1
            else columns[:-1]
        )
        if start + per_table >= cranks:
            chunk.append(columns[-1])
        with_torque = chunk[-1] is columns[-1]
        caption = "torque.table_b3_caption_torque" if with_torque else "torque.table_b3_caption"
        if cranks == 1:  # one crank carries every cylinder: no running torques between cranks
            caption = "torque.table_b3_caption_single"
        elif (
            min(start + per_table, cranks) == start + 1
        ):  # a last table of one crank: "5", not "5–5"
            caption += "_one"
        see = (
            ("torque.see_table_b3_single" if cranks == 1 else "torque.see_table_b3_torque")
            if with_torque
            else "torque.see_table_b3"
        )
        tables.append(
            ctx.table(
                chunk,
                caption=t(caption, first=start + 1, last=min(start + per_table, cranks)),
                css_class="data wide",
                extremes=extremes if with_torque else elsewhere,
                see=see,
            )
        )
    return tables


def _danger_table(ctx, r, cranks: int) -> str:
    """Table B.4: each crank's dangerous combinations of loads."""
    t = ctx.t
    # one crank: its journal's running torque t_Σ is the crank's own t, so neither the row of
    # its largest |t_Σ| nor its column would add a number; there are no cranks to name
    single = "_single" if cranks == 1 else ""
    kinds = ("Z", "Zmin", "T", "Tmin", "Q") + (() if cranks == 1 else ("M",))
    danger_rows = [(d["crank"], kind, d[kind]) for d in r["dangerous"] for kind in kinds]
    return ctx.table(
        [
            # one crank: no column naming it
            *(
                []
                if cranks == 1
                else [(t("torque.crank"), [str(c) for c, _, _ in danger_rows], None)]
            ),
            (
                t("torque.criterion"),
                [
                    t("torque.criterion_" + kind + (single if kind == "M" else ""))
                    for _, kind, _ in danger_rows
                ],
                None,
            ),
            (
                "<i>α</i>, °",
                angles := [v["shaft_angle_deg"] for _, _, v in danger_rows],
                exact_decimals(angles, most=1),  # a grid step's angle to a tenth
            ),
            ("<i>z</i>, " + t("unit.MPa"), [v["z_Pa"] / 1e6 for _, _, v in danger_rows], 3),
            ("<i>t</i>, " + t("unit.MPa"), [v["t_Pa"] / 1e6 for _, _, v in danger_rows], 3),
            ("<i>q</i>, " + t("unit.MPa"), [v["q_Pa"] / 1e6 for _, _, v in danger_rows], 3),
            *(
                []
                if cranks == 1
                else [
                    (
                        "<i>t</i><sub>k<i>i</i></sub>, " + t("unit.MPa"),
                        [v["journal_t_Pa"] / 1e6 for _, _, v in danger_rows],
                        3,
                    )
                ]
            ),
        ],
        caption=_danger_caption(ctx, single),
        see="torque.see_table_b4_single" if cranks == 1 else "torque.see_table_b4",
    )


def _danger_caption(ctx, single: str) -> str:
    """Table B.4's caption; where the shaft carries counterweights, which the textbook's q
    leaves out (the bearings' loads take them), it says so."""
    fitted = ctx.data(COUNTERWEIGHTS)
    with_counterweights = fitted is not None and fitted.fitted
    return ctx.t(
        "torque.table_b4_caption" + single + ("_counterweights" if with_counterweights else "")
    )


def largest_running_torque(journals: list[dict]) -> dict | None:
    """The main journal of the largest running torque (the last of equal ones, as the section
    names it), where the shaft has several cranks; None for one crank (its journal carries the
    engine's torque, said already)."""
    if len(journals) < 2:
        return None
    return max(reversed(journals), key=lambda j: j["max_abs_Nm"])


def _conclude(ctx, r) -> None:
    """The finding and the conclusions: the mean output torque against the indicated work's, its
    range, period and non-uniformity, the effective torque when given."""
    t = ctx.t
    ctx.find(t("torque.finding", mean=ctx.num(r["mean_Nm"])))
    ctx.conclude(
        t(
            "torque.conclusion",
            mean=ctx.num(r["mean_Nm"]),
            from_work=ctx.num(r["mean_from_work_Nm"]),
            deviation=ctx.num(r["mean_deviation_percent"] or 0.0, 2),
            max=t.fixed(r["max_Nm"], TORQUE_DECIMALS),
            max_angle=ctx.angle_text(r["max_crank_angle_deg"]),
            min=t.fixed(r["min_Nm"], TORQUE_DECIMALS),
            period=ctx.angle_text(r["period_deg"]),
            mu=ctx.num(r["non_uniformity"], 3),
        )
    )
    engine = ctx.scene.engine
    even = engine.cycle_deg / engine.cylinders
    if engine.uneven_firing and r["period_deg"] > even * (1.0 + 1e-9):
        # what the uneven firing the scene gives does to the torque: a longer period
        ctx.conclusions[-1] += " " + t(
            "torque.conclusion_uneven_period",
            period=ctx.angle_text(r["period_deg"]),
            even=ctx.angle_text(even),
            cycle=ctx.angle_text(engine.cycle_deg),
            cylinders=engine.cylinders,
        )
    journal = largest_running_torque(r.get("journals") or [])
    if journal is not None:
        ctx.conclude(
            t(
                "torque.conclusion_journal_torque",
                label=journal_name(journal["journal"]),
                k=next(k for k, j in enumerate(r["journals"], 1) if j is journal),
                max=ctx.num(journal["max_abs_Nm"]),
            )
        )
    if r.get("mechanical_efficiency") is not None:
        ctx.conclude(
            t(
                # a four-stroke's η_m leaves the pumping strokes out of N_i, as the section says
                "torque.conclusion_effective"
                + ("" if ctx.scene is not None and ctx.scene.engine.strokes == 2 else "_pumping"),
                me=ctx.num(r["mean_effective_torque_Nm"]),
                eta=ctx.num(r["mechanical_efficiency"], 3),
            )
        )


def _conclude_crank_load(ctx, r, table_number) -> None:
    """The largest resultant load on a crank from all the cylinders it carries (table B.4)."""
    worst = max((d["Q"] for d in r["dangerous"]), key=lambda v: v["q_Pa"])
    fitted = ctx.data(COUNTERWEIGHTS)
    # the loads of the tables are the cranks' own, before the counterweights the balancing fits
    with_counterweights = fitted is not None and fitted.fitted
    ctx.conclude(
        ctx.t(
            "torque.conclusion_crank_load" + ("_counterweights" if with_counterweights else ""),
            q_max=ctx.num(worst["q_Pa"] / 1e6),
            q_angle=ctx.angle_text(worst["shaft_angle_deg"]),
            table=table_number,
        )
    )


#: The torque section's own letters (meanings: symbol.torque.<key> in i18n/).
SYMBOLS = {
    # a main journal's running torque as a specific tangential force (table B.4's criterion)
    "journal_running": Symbol("t", {"en": "k"}, "unit.MPa"),
    # the most dangerous combinations' criteria beside t_max, t_min and q_max (the core's)
    "radial_max": Symbol("z", {"en": "max"}, "unit.MPa"),
    "radial_min": Symbol("z", {"en": "min"}, "unit.MPa"),
}
