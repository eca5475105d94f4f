"""The ``kinematics`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

from functools import partial

from crankdyn.plugin.types import StageOutput
from crankdyn.report import figure_memo
from crankdyn.report.context import sample_rows
from crankdyn.report.typeset import symbol_html
from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    column_decimals,
    printed,
    snapped,
    worked_markup,
    worked_row,
)

from .compute import TWO_TERM_DIGITS
from .figures import _piston_figure, _rod_cm_figure, _rod_figure


def _table(ctx, f, labels):
    """The piston's and the rod's motion at the table's angles (table 2.1)."""
    t = ctx.t
    return ctx.table(
        [
            ("<i>α</i>, °", labels, 0),
            ("<i>s</i><sub>p</sub>, " + t("unit.mm"), f["piston_displacement_m"] * 1e3, 2),
            ("<i>v</i><sub>p</sub>, " + t("unit.m_s"), f["piston_velocity_m_s"], 2),
            (
                "<i>j</i><sub>p</sub>, " + t("unit.m_s2"),
                f["piston_acceleration_m_s2"],
                column_decimals(f["piston_acceleration_m_s2"], 0),
            ),
            ("<i>β</i>, °", f["rod_angle_deg"], 2),
            (
                "<i>ω</i><sub>r</sub>, " + t("unit.rad_s"),
                f["rod_angular_velocity_rad_s"],
                column_decimals(f["rod_angular_velocity_rad_s"], 1),
            ),
            (
                "<i>ε</i><sub>r</sub>, " + t("unit.rad_s2"),
                f["rod_angular_acceleration_rad_s2"],
                column_decimals(f["rod_angular_acceleration_rad_s2"], 0),
            ),
        ],
        caption=t("kinematics.table_caption" + _master_suffix(ctx)),
        see="kinematics.see_table",
    )


def render(output: StageOutput, ctx) -> str:
    frame = output.tables.arrays("kinematics")
    r = output.results
    t = ctx.t
    # The motion repeats every revolution, so one revolution is tabulated.
    rows, labels = sample_rows(frame["crank_angle_deg"], ctx.table_step_deg, span_deg=360.0)
    f = frame.take(rows)
    table = _table(ctx, f, labels)
    worked = _worked(ctx, f, labels, r) if r["method"] == "exact" else None

    figure_main = ctx.figure(
        partial(_piston_figure, frame, t),
        t("kinematics.figure_caption"),
        "piston",
        see="kinematics.see_figure",
    )
    figure_rod = ctx.figure(
        partial(_rod_figure, frame, t),
        t("kinematics.rod_figure_caption"),
        "rod",
        see="kinematics.see_rod_figure",
    )
    figure_cm = None
    if "rod_cm_x_m" in frame:
        figure_cm = ctx.figure(
            figure_memo.MemoFigure(
                _rod_cm_figure,
                frame["rod_cm_x_m"],
                frame["rod_cm_z_m"],
                t("kinematics.axis_cm_x"),
                t("kinematics.axis_cm_z"),
            ),
            t("kinematics.cm_figure_caption"),
            "rod_cm",
            see="kinematics.see_cm",
        )

    ctx.conclude(
        t(
            "kinematics.conclusion",
            v_max=ctx.num(r["v_max_m_s"]),
            v_angle=ctx.angle_text(r["v_max_crank_angle_deg"]),
            v_mean=ctx.num(r["mean_piston_speed_m_s"]),
            j_max=ctx.num(r["j_max_m_s2"]),
            j_min=ctx.num(r["j_min_m_s2"]),
            j_angle=ctx.angle_text(r["j_min_crank_angle_deg"]),
        )
    )
    return ctx.render_template(
        "sections/kinematics.html.j2",
        r=r,
        table=table,
        figure_main=figure_main,
        figure_rod=figure_rod,
        figure_cm=figure_cm,
        worked=worked,
        two_term_digits=TWO_TERM_DIGITS,
    )


def _worked(ctx, rows, labels, r):
    """Displacement, velocity and acceleration of the piston with the numbers of one table row."""
    t, lang = ctx.t, ctx.t.language
    i = worked_row(labels, ctx.worked_angle_deg)
    alpha, row = float(labels[i]), rows.row(i)
    a = ctx.angle_text(alpha)
    r_txt, r_m = printed(t, r["crank_radius_m"])
    l_txt, lam = printed(t, r["rod_ratio"])
    w_txt, omega = printed(t, r["angular_velocity_rad_s"], 5)
    b_txt, beta = printed(t, snapped(float(row["rod_angle_deg"]), 90.0))
    inputs = {"R_m": r_m, "lambda": lam, "omega": omega, "alpha_deg": alpha, "beta_deg": beta}
    steps = [
        WorkedStep(
            "piston_displacement",
            symbol_html("piston_displacement", lang),
            "<i>R</i>[(1 − cos <i>α</i>) + (1 − cos <i>β</i>)/<i>λ</i>]",
            f"{r_txt}·[(1 − cos {a}°) + (1 − cos {b_txt}°)/{l_txt}]·10³",
            float(row["piston_displacement_m"]) * 1e3,
            2,
            t("unit.mm"),
            inputs,
        ),
        WorkedStep(
            "piston_velocity",
            symbol_html("piston_velocity", lang),
            "<i>Rω</i> sin(<i>α</i> + <i>β</i>)/cos <i>β</i>",
            f"{r_txt}·{w_txt}·sin({a}° + {b_txt}°)/cos {b_txt}°",
            float(row["piston_velocity_m_s"]),
            2,
            t("unit.m_s"),
            inputs,
        ),
        WorkedStep(
            "piston_acceleration",
            symbol_html("piston_acceleration", lang),
            "<i>Rω</i><sup>2</sup>[cos(<i>α</i> + <i>β</i>)/cos <i>β</i> + <i>λ</i> cos<sup>2</sup><i>α</i>/cos<sup>3</sup><i>β</i>]",
            f"{r_txt}·{w_txt}<sup>2</sup>·[cos({a}° + {b_txt}°)/cos {b_txt}° + {l_txt}·cos<sup>2</sup> {a}°/cos<sup>3</sup> {b_txt}°]",
            float(row["piston_acceleration_m_s2"]),
            column_decimals(rows["piston_acceleration_m_s2"], 0),  # as the table prints it
            t("unit.m_s2"),
            inputs,
        ),
    ]
    return worked_markup(ctx, WorkedBlock("kinematics", ctx.last_table_number, alpha, steps))


def _master_suffix(ctx) -> str:
    """ "_master" where the slave rods ride on a master rod (a radial): the section's table and
    figures are the master cylinder's, whose piston and rod the slaves' differ from."""
    scene = ctx.scene
    return "_master" if scene is not None and scene.engine.rod_type == "articulated" else ""
