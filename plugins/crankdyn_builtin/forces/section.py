"""The ``forces`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

from functools import partial

import numpy as np

from crankdyn.physics.extrema import first_argmax
from crankdyn.physics.layout import cylinder_labels
from crankdyn.plugin.contracts import COUNTERWEIGHTS
from crankdyn.plugin.scene_inputs import engine_layout
from crankdyn.plugin.types import StageOutput
from crankdyn.report.context import add_extreme_rows, sample_rows
from crankdyn.report.typeset import symbol_html
from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    column_decimals,
    printed,
    printed_fixed,
    worked_markup,
    worked_row,
)
from crankdyn_builtin.forces.worked import worked_crank_torque

from .figures import _forces_figure, _torque_figure


def _whose_torque(scene) -> str:
    """The catalog keys' suffix for whose torque the section gives: one crank's where each crank
    carries one cylinder (an in-line engine, a boxer), one cylinder's where a crank carries
    several (V, W, X, a radial's one crank), the engine's where it has one cylinder."""
    if scene is None:
        return ""
    if scene.engine.cylinders <= 1:
        return "_engine"
    try:
        places = cylinder_labels(scene.engine.layout, scene.engine.cylinders)
    except ValueError:  # a layout the physics does not know: say the cylinder's, never wrong
        return "_cylinder"
    cranks = len({bay for _, _, bay in places})
    return "_cylinder" if cranks < len(places) else ""


def render(output: StageOutput, ctx) -> str:
    t = ctx.t
    f = output.tables.arrays("forces")
    r = output.results
    angle = f["crank_angle_deg"]
    mpa = {k: f[k] / 1e6 for k in f.columns if k.endswith("_Pa")}

    whose = _whose_torque(ctx.scene)
    grid = sample_rows(angle, ctx.table_step_deg)
    # every extreme the conclusions name gets its row, even one a hair above a table row's value
    t_extremes = [
        (f["tangential_Pa"], "max", t("forces.extreme_t_max")),
        (f["tangential_Pa"], "min", t("forces.extreme_t_min")),
    ]
    table_b1, worked = _table_b1(ctx, f, mpa, r, grid, t_extremes)
    table_q = _table_q(ctx, f, mpa, r, grid, t_extremes, whose)
    figure_forces = ctx.figure(
        partial(_forces_figure, t, ctx.cycle_deg, angle, mpa),
        t("forces.figure_caption"),
        "forces",
        see="forces.see_figure",
    )
    figure_torque = ctx.figure(
        partial(
            _torque_figure, t, ctx.cycle_deg, angle, f["torque_Nm"], r["mean_torque_Nm"], whose
        ),
        t("forces.torque_caption" + whose),
        "torque",
        see="forces.see_torque" + whose,
    )
    _conclude(ctx, f, r, whose)
    return ctx.render_template(
        "sections/forces.html.j2",
        r=r,
        side_offset=side_offset_params(ctx, r) if "side_power_stroke_max_Pa" in r else {},
        table_b1=table_b1,
        table_q=table_q,
        figure_forces=figure_forces,
        figure_torque=figure_torque,
        worked=worked,
        # the cylinders on one crank where there are several, else 0
        cylinders_per_crank=_per_crank(ctx.scene) if whose == "_cylinder" else 0,
    )


def _table_b1(ctx, f, mpa: dict, r, grid, t_extremes) -> tuple[str, str]:
    """(table B.1 of the piston's motion and the specific forces at the table's angles and their
    extremes, the worked substitutions of its inertia and total force)."""
    t = ctx.t
    angle = f["crank_angle_deg"]
    rows, labels, extremes = add_extreme_rows(
        angle,
        *grid,
        [
            (f["gas_Pa"], "max", t("forces.extreme_gas_max")),
            (np.abs(f["side_Pa"]), "max", t("forces.extreme_n_max")),
            *t_extremes,
        ],
        resolution=0.0,
    )
    table_b1 = ctx.table(
        [
            ("<i>α</i>, °", ctx.angle_labels(labels), None),
            (
                "<i>s</i><sub>p</sub>, " + t("unit.mm"),
                f["piston_displacement_m"][rows] * 1e3,
                2,
            ),  # mm, as table 2.1
            ("<i>v</i><sub>p</sub>, " + t("unit.m_s"), f["piston_velocity_m_s"][rows], 2),
            (
                "<i>j</i><sub>p</sub>, " + t("unit.m_s2"),
                f["piston_acceleration_m_s2"][rows],
                column_decimals(f["piston_acceleration_m_s2"][rows], 0),
            ),
            ("<i>p</i><sub>g</sub>", mpa["gas_Pa"][rows], 3),
            ("<i>p</i><sub>j</sub>", mpa["inertia_Pa"][rows], 3),
            ("<i>p</i><sub>jI</sub>", mpa["inertia_first_order_Pa"][rows], 3),
            ("<i>p</i><sub>jII</sub>", mpa["inertia_second_order_Pa"][rows], 3),
            ("<i>p</i><sub>1</sub>", mpa["total_Pa"][rows], 3),
            ("<i>N</i>", mpa["side_Pa"][rows], 3),
            ("<i>k</i>", mpa["rod_Pa"][rows], 3),
            ("<i>z</i>", mpa["radial_Pa"][rows], 3),
            ("<i>t</i>", mpa["tangential_Pa"][rows], 3),
        ],
        caption=t(
            "forces.table_b1_caption"
            + (
                "_master"
                if ctx.scene is not None and ctx.scene.engine.rod_type == "articulated"
                else ""
            )
        ),
        css_class="data wide",
        extremes=extremes,
        see="forces.see_table_b1",
    )
    return table_b1, _worked(ctx, f.take(rows), labels, r)


def _table_q(ctx, f, mpa: dict, r, grid, t_extremes, whose: str) -> str:
    """The crank pin's loads and the crank's torque at the table's angles and their extremes,
    with the worked substitution of the torque."""
    t = ctx.t
    rows, labels, extremes = add_extreme_rows(
        f["crank_angle_deg"],
        *grid,
        [(f["resultant_Pa"], "max", t("forces.extreme_q_max")), *t_extremes],
        resolution=0.0,
    )
    return ctx.table(
        [
            ("<i>α</i>, °", ctx.angle_labels(labels), None),
            (
                "<i>z</i> + <i>c</i>, " + t("unit.MPa"),
                mpa["radial_Pa"][rows] + r["centrifugal_Pa"] / 1e6,
                3,
            ),
            ("<i>t</i>, " + t("unit.MPa"), mpa["tangential_Pa"][rows], 3),
            ("<i>q</i>, " + t("unit.MPa"), mpa["resultant_Pa"][rows], 3),
            ("<i>M</i><sub>k</sub>, " + t("unit.Nm"), f["torque_Nm"][rows], 1),
        ],
        caption=t("forces.table_q_caption" + whose),
        extremes=extremes,
        see="forces.see_table_q" + whose,
    ) + worked_crank_torque(ctx, f.take(rows), labels, r)


def _conclude(ctx, f, r, whose: str) -> None:
    """The finding (one cylinder's engine) and the conclusions: the mean torque against the
    indicated work's, the effective torque when given, the largest loads."""
    t = ctx.t
    if (
        ctx.scene is not None and ctx.scene.engine.cylinders == 1
    ):  # else the engine's torque: torque stage
        ctx.find(t("forces.finding", mean=ctx.num(r["mean_torque_Nm"])))
    # a driven machine (a compressor: negative mean torque) is loaded most by its least torque
    peak = "max" if r["mean_torque_Nm"] >= 0 or r["torque_max_Nm"] >= -r["torque_min_Nm"] else "min"
    ctx.conclude(
        t(
            "forces.conclusion_torque" + whose + ("" if peak == "max" else "_driven"),
            mean=ctx.num(r["mean_torque_Nm"]),
            from_work=ctx.num(r["mean_torque_from_work_Nm"]),
            deviation=ctx.num(r["mean_torque_deviation_percent"] or 0.0, 2),
            t_max=ctx.num(r[f"torque_{peak}_Nm"]),
            t_angle=ctx.angle_text(r[f"torque_{peak}_crank_angle_deg"]),
        )
    )
    if r.get("mechanical_efficiency") is not None:  # a single cylinder given its N_e
        ctx.conclude(
            t(
                # a four-stroke's η_m leaves the pumping strokes out of N_i, as the section says
                "forces.conclusion_effective"
                + ("" if ctx.scene is not None and ctx.scene.engine.strokes == 2 else "_pumping"),
                me=ctx.num(r["mean_effective_torque_Nm"]),
                eta=ctx.num(r["mechanical_efficiency"], 3),
            )
        )
    if whose == "_cylinder" and ctx.scene.engine.rod_type == "articulated":
        return  # the master cylinder's side force with the slave rods: the bays section says it
    fitted = ctx.data(COUNTERWEIGHTS)
    # q is the crank's own load, before the counterweights the balancing fits
    counterweights = whose != "_cylinder" and fitted is not None and fitted.fitted
    ctx.conclude(
        t(
            "forces.conclusion_loads" + whose + ("_counterweights" if counterweights else ""),
            q_max=ctx.num(r["resultant_max_Pa"] / 1e6),
            q_angle=ctx.angle_text(r["resultant_max_crank_angle_deg"]),
            # signed and with the digits the section's text and table print it with
            n_max=ctx.num(float(f["side_Pa"][first_argmax(np.abs(f["side_Pa"]))]) / 1e6, 3),
            n_angle=ctx.angle_text(float(f["crank_angle_deg"][first_argmax(np.abs(f["side_Pa"]))])),
        )
    )
    if "side_power_stroke_max_Pa" in r:  # an offset crank-slider: what its offset is for
        ctx.conclude(t("forces.conclusion_side_offset", **side_offset_params(ctx, r)))


def side_offset_params(ctx, r) -> dict:
    """An offset crank-slider's side forces against the central mechanism's, MPa, as printed."""
    return {
        key: ctx.num(r[f"side_{name}_Pa"] / 1e6, 3)
        for key, name in (
            ("power", "power_stroke_max"),
            ("power_central", "power_stroke_central_max"),
            ("other", "other_strokes_max_abs"),
            ("other_central", "other_strokes_central_max_abs"),
        )
    }


def _worked(ctx, rows, labels, r):
    """Inertia and total specific force with the numbers of one row of table B.1."""
    t, lang = ctx.t, ctx.t.language
    i = worked_row(labels, ctx.worked_angle_deg)
    alpha, row = float(labels[i]), rows.row(i)
    m_txt, m_s = printed(t, r["reciprocating_mass_kg"])
    f_txt, area = printed(t, r["piston_area_m2"])
    # as table B.1 prints it
    j_txt, j = printed_fixed(
        t,
        float(row["piston_acceleration_m_s2"]),
        column_decimals(rows["piston_acceleration_m_s2"], 0),
    )
    p_j = float(row["inertia_Pa"]) / 1e6
    g_txt, p_g = printed_fixed(t, float(row["gas_Pa"]) / 1e6, 3)
    pj_txt, p_j_printed = printed_fixed(t, p_j, 3)
    inputs = {"m_s": m_s, "F_p": area, "j": j, "p_g": p_g, "p_j": p_j_printed, "alpha_deg": alpha}
    lhs_j, lhs_1 = "<i>p</i><sub>j</sub>", "<i>p</i><sub>1</sub>"
    steps = [
        WorkedStep(
            "inertia_pressure",
            lhs_j,
            "−<i>m</i><sub>s</sub> "
            + symbol_html("piston_acceleration", lang)
            + "/<i>F</i><sub>p</sub>",
            f"(−{m_txt}·({j_txt})/{f_txt})·10<sup>−6</sup>",
            p_j,
            3,
            t("unit.MPa"),
            inputs,
        ),
        WorkedStep(
            "total_pressure",
            lhs_1,
            symbol_html("gas_pressure", lang) + " + " + lhs_j,
            f"{g_txt} + ({pj_txt})",
            float(row["total_Pa"]) / 1e6,
            3,
            t("unit.MPa"),
            inputs,
        ),
    ]
    return worked_markup(ctx, WorkedBlock("forces", ctx.last_table_number, alpha, steps))


def _per_crank(scene) -> int:
    """The cylinders on one crank of the engine (all its cranks carry as many)."""
    return engine_layout(scene).cylinders_per_bay
