"""The torsional part of the speed-fluctuation section: the shaft's tables, the harmonics' table,
the Campbell diagram's text and the parts the section's template shows."""

from __future__ import annotations

from functools import partial

from markupsafe import Markup

from crankdyn.plugin.types import StageOutput

from .figures import (
    _campbell_plot,
    _error_figure,
    _modes_figure,
    _torsion_figure,
    no_flywheel,
)
from .solver_text import _solver_table
from .torsion import CRITICAL_BAND


def _shaft_tables(ctx, torsion, node_names, parts) -> None:
    """The discs and spans of the shaft model, and its natural modes (frequencies and shapes)."""
    t = ctx.t
    nodes, modes = torsion["nodes"], torsion["modes"]
    parts["table_nodes"] = ctx.table(
        [
            (
                t("speed_fluctuation.col_node"),
                [f"{i + 1}: {name}" for i, name in enumerate(node_names)],
                None,
            ),
            (
                "<i>J</i><sub><i>i</i></sub>, " + t("flywheel.unit_kg_m2"),
                [ctx.num(n["inertia_mean_kg_m2"]) for n in nodes],
                None,
            ),
            (
                "<i>c</i><sub><i>i</i></sub>, " + t("speed_fluctuation.unit_N_m_rad"),
                [ctx.num(k) for k in torsion["span_stiffness_N_m_rad"]] + ["—"],
                None,
            ),
            (
                t("speed_fluctuation.col_twist"),
                [ctx.num(x * 1e3) for x in torsion["twist_max_rad"]] + ["—"],
                None,
            ),
            (
                t("speed_fluctuation.col_span_torque"),
                [ctx.num(x) for x in torsion["span_torque_max_Nm"]] + ["—"],
                None,
            ),
        ],
        caption=t("speed_fluctuation.nodes_caption"),
        see="speed_fluctuation.see_nodes",
    )
    parts["table_modes"] = ctx.table(
        [
            (t("speed_fluctuation.col_mode"), [str(m["mode"]) for m in modes], None),
            (
                "<i>ω</i><sub><i>s</i></sub>, " + t("unit.rad_s"),
                [ctx.num(m["natural_frequency_rad_s"]) for m in modes],
                None,
            ),
            (
                "<i>f</i><sub><i>s</i></sub>, " + t("speed_fluctuation.unit_Hz"),
                [ctx.num(m["natural_frequency_Hz"]) for m in modes],
                None,
            ),
        ]
        + [
            (
                Markup("<i>a</i><sub>") + str(i + 1) + Markup("</sub>"),
                [m["shape"][i] for m in modes],
                3,
            )
            for i in range(len(nodes))
        ],
        caption=t("speed_fluctuation.modes_caption"),
        see="speed_fluctuation.see_modes_table",
    )


def _harmonics_table(ctx, torsion, parts) -> None:
    """The crank torque's harmonic orders with the critical speeds and vector sums of the first two modes."""
    t = ctx.t
    harmonics = torsion["harmonics"]
    shown = torsion["modes"][:2]
    parts["table_harmonics"] = ctx.table(
        [
            # orders are halves and wholes: "0,5", "1", "4,5", "10" (not "0,500", "10,0")
            (Markup("<i>ν</i>"), [ctx.t.number_g(h["order"], 4) for h in harmonics], None),
            (
                Markup("|<i>M</i><sub><i>ν</i></sub>|, ") + t("unit.Nm"),
                [h["amplitude_Nm"] for h in harmonics],
                1,
            ),
        ]
        + [
            (
                t("speed_fluctuation.col_critical", mode=m["mode"]),
                [h["critical_rpm"][k] for h in harmonics],
                0,
            )
            for k, m in enumerate(shown)
        ]
        + [
            (
                t("speed_fluctuation.col_vector_sum", mode=m["mode"]),
                [h["vector_sum"][k] for h in harmonics],
                2,
            )
            for k, m in enumerate(shown)
        ],
        caption=t("speed_fluctuation.harmonics_caption"),
        see="speed_fluctuation.see_harmonics",
    )


def _torsion_parts(ctx, output: StageOutput, torsion, course: bool = False) -> dict:
    """The torsional subsection's tables and figures, made in the order the template shows them
    (tables and figures are numbered as made), and its conclusions; a course note's without
    the solvers' comparison."""
    t = ctx.t
    parts = {}
    node_names = [_node_name(t, node["name"]) for node in torsion["nodes"]]
    modes = torsion["modes"]
    _shaft_tables(ctx, torsion, node_names, parts)
    _modes_figure(ctx, torsion, parts)
    _harmonics_table(ctx, torsion, parts)
    _campbell(ctx, torsion, parts)
    _torsion_figure(ctx, output.tables.arrays("torsion"), torsion, node_names, parts)
    if torsion["solvers"] and not course:
        parts["table_torsion_solvers"] = _solver_table(
            ctx,
            torsion["solvers"],
            t("speed_fluctuation.torsion_table_caption"),
            "speed_fluctuation.see_torsion_table",
            twist=True,
        )
        parts["figure_torsion_solvers"] = _error_figure(
            ctx,
            torsion["solvers"],
            t("speed_fluctuation.torsion_figure_caption"),
            "solvers_torsion",
            "speed_fluctuation.see_torsion_figure",
        )
    conclusion = "speed_fluctuation.conclusion_torsion" + ("_course" if course else "")
    if not torsion["steady_state"]["converged"]:  # the last cycle's values: estimates only
        conclusion = "speed_fluctuation.conclusion_torsion_last"
    ctx.conclude(
        t(
            conclusion + no_flywheel(torsion),
            f1=ctx.num(modes[0]["natural_frequency_Hz"]) if modes else "—",
            method=torsion["solver"]["method"],
            twist=ctx.num(max(torsion["twist_max_rad"]) * 1e3),
            torque=ctx.num(max(torsion["span_torque_max_Nm"])),
        )
    )
    return parts


def _campbell(ctx, torsion, parts) -> None:
    """Campbell diagram (natural frequencies against engine speed, with the significant orders) and the
    conclusion on the critical speeds near the operating speed."""
    t = ctx.t
    rpm = torsion["operating_rpm"]
    parts["figure_campbell"] = ctx.figure(
        partial(_campbell_plot, torsion, t),
        t("speed_fluctuation.campbell_caption", band=ctx.num(100 * CRITICAL_BAND, 2)),
        "campbell",
        see="speed_fluctuation.see_campbell",
    )
    near = torsion["critical_speeds_near_operating"]
    if near:
        items = "; ".join(
            t(
                "speed_fluctuation.critical_item",
                mode=c["mode"],
                order=ctx.t.number_g(c["order"], 4),
                rpm=ctx.num(c["critical_rpm"], 4),
                deviation=ctx.num(c["deviation_percent"], 2),
                vector=ctx.num(c["vector_sum"], 2),
            )
            for c in near
        )
        ctx.conclude(
            t(
                "speed_fluctuation.conclusion_critical",
                rpm=ctx.num(rpm, 4),
                band=ctx.num(100 * CRITICAL_BAND, 2),
                items=items,
                zeta=ctx.num(torsion["damping_ratio"], 3),
            )
        )
    else:
        ctx.conclude(
            t(
                "speed_fluctuation.conclusion_no_critical",
                rpm=ctx.num(rpm, 4),
                band=ctx.num(100 * CRITICAL_BAND, 2),
            )
        )


def _node_name(t, name: str) -> str:
    if name.startswith("crank "):
        return t("speed_fluctuation.node_crank", k=name.split()[1])
    return t("speed_fluctuation.node_" + name.replace(" ", "_"))
