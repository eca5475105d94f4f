"""The worked substitution of the torque stage: the sum over the cranks and the engine torque at one
table row (the last part of table B.3, which holds the last journal and M_d)."""

from __future__ import annotations

from collections.abc import Sequence

from markupsafe import Markup

from crankdyn.physics.forces import piston_area_m2
from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    bracketed,
    printed,
    printed_fixed,
    worked_markup,
    worked_row,
)


def worked_torque(ctx, f, rows, labels, cranks: int, delays: Sequence[dict] = ()) -> Markup:
    """``t_kN = t_1 + … + t_N`` and ``M_d = t_kN R F_p`` with the numbers of one row of table B.3,
    after the sentence that gives each cylinder's own crank angle at that row (``delays``: the
    torque stage's ``cylinder_cycle_delays_deg``), so that every t_i can be found in its table."""
    t = ctx.t
    i = worked_row(labels, ctx.worked_angle_deg)
    alpha, row = float(labels[i]), f.row(rows[i])
    own = ", ".join(
        f"α_{{{t.cylinder(d['cylinder'])}}} = {ctx.angle_text((alpha - d['cycle_delay_deg']) % ctx.cycle_deg)}°"
        for d in sorted(delays, key=lambda d: (d["crank"], d["cycle_delay_deg"]))
    )
    engine = ctx.scene.engine
    radius, area = engine.crank_radius_m, piston_area_m2(engine.bore)
    terms = [
        printed_fixed(t, float(row[f"crank{k}_tangential_Pa"]) / 1e6, 3)
        for k in range(1, cranks + 1)
    ]
    journal = float(row[f"journal{cranks}_torque_Pa"]) / 1e6
    tk_txt, tk = printed(
        t, journal
    )  # four digits, not the table's three decimals: M_d to its 0,1 N·m
    r_txt, r_m = printed(t, radius)
    f_txt, f_m2 = printed(t, area)
    inputs = {f"t{k}": v for k, (_, v) in enumerate(terms, start=1)}
    exact = {f"t{k}": float(row[f"crank{k}_tangential_Pa"]) / 1e6 for k in range(1, cranks + 1)}
    total_html = f"<i>t</i><sub>k{cranks}</sub>" if cranks > 1 else "<i>t</i><sub>Σ</sub>"
    steps = [
        WorkedStep(
            "journal_torque_sum",
            total_html,
            " + ".join(f"<i>t</i><sub>{k}</sub>" for k in range(1, cranks + 1)),
            " + ".join(bracketed(text, value) for text, value in terms),
            journal,
            3,
            t("unit.MPa"),
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "output_torque",
            "<i>M</i><sub>d</sub>",
            total_html + " <i>R</i> <i>F</i><sub>p</sub>",
            f"{bracketed(tk_txt, tk)}·10<sup>6</sup>·{r_txt}·{f_txt}",
            float(row["output_torque_Nm"]),
            1,
            t("unit.Nm"),
            {"t_k": tk, "R": r_m, "F_p": f_m2, "alpha_deg": alpha},
            exact={"t_k": journal, "R": radius, "F_p": area, "alpha_deg": alpha},
        ),
    ]
    if cranks == 1:  # one crank: t_Σ is its table's own column, no sum over cranks to show
        steps = steps[1:]
    # articulated rods: a crank's t comes from the master rod's statics (the bays section), the
    # slave cylinders moving otherwise than the one cylinder of the forces section
    articulated = engine.rod_type == "articulated"
    key = "torque.worked_own_angles" + ("_articulated" if articulated else "")
    note = t(key, angles=own) if own else ""
    return worked_markup(ctx, WorkedBlock("torque", ctx.last_table_number, alpha, steps, note=note))
