"""The second worked substitution of the forces stage, after the table of crank-pin loads: the
torque of one crank, M_k = t R F_p, at the same row as the first (table B.1's)."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    bracketed,
    printed,
    worked_markup,
    worked_row,
)

#: mechanisms whose crank radius is the scene's R (the planetary linkage turns its carrier instead)
CRANK_MECHANISMS = ("crank_slider", "offset_crank_slider")


def worked_crank_torque(ctx, rows, labels, r) -> Markup:
    """``rows``: the printed rows of the forces table, ``labels`` their crank angles."""
    scene = ctx.scene
    if scene is None or scene.engine.mechanism not in CRANK_MECHANISMS:
        return Markup("")
    t = ctx.t
    i = worked_row(labels, ctx.worked_angle_deg)
    alpha, row = float(labels[i]), rows.row(i)
    tangential = float(row["tangential_Pa"]) / 1e6
    radius, area = scene.engine.crank_radius_m, r["piston_area_m2"]
    t_txt, t_mpa = printed(
        t, tangential
    )  # one digit more than the table where t is small: M_k to its 0,1 N·m
    r_txt, r_m = printed(t, radius)
    f_txt, f_m2 = printed(t, area)
    step = WorkedStep(
        "crank_torque",
        "<i>M</i><sub>k</sub>",
        "<i>t R</i> <i>F</i><sub>p</sub>",
        f"{bracketed(t_txt, t_mpa)}·10<sup>6</sup>·{r_txt}·{f_txt}",
        float(row["torque_Nm"]),
        1,
        t("unit.Nm"),
        {"t_k": t_mpa, "R": r_m, "F_p": f_m2, "alpha_deg": alpha},
        exact={"t_k": tangential, "R": radius, "F_p": area, "alpha_deg": alpha},
    )
    return worked_markup(ctx, WorkedBlock("forces_torque", ctx.last_table_number, alpha, [step]))
