"""The worked substitution of the torque stage: the sum over the cranks and the engine torque at one
table row (the last part of table B.3, which holds the last journal and M_d)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from markupsafe import Markup

from crankdyn.physics.forces import piston_area_m2
from crankdyn.plugin.contracts import BAY_LOADS
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
        cylinders = _cylinder_sum(ctx, alpha, journal, delays, total_html)
        steps = ([cylinders] if cylinders else []) + steps[1:]
    # articulated rods: a crank's t comes from the master rod's statics (the bays section), the
    # slave cylinders moving otherwise than the one cylinder of the forces section
    articulated = engine.rod_type == "articulated"
    key = "torque.worked_own_angles" + ("_articulated" if articulated else "")
    key += "_one" if articulated and cranks == 1 else ""
    # an angle between the forces table's rows (a V16 two-stroke's 7.5°, 52.5°): computed as
    # that table's rows are, not read off it
    step = ctx.table_step_deg
    between = any(
        abs(a / step - round(a / step)) > 1e-9
        for a in ((alpha - d["cycle_delay_deg"]) % ctx.cycle_deg for d in delays)
    )
    key += "_between" if between and not articulated else ""
    note = t(key, angles=own, step=t.number_g(step, 4)) if own else ""
    return worked_markup(ctx, WorkedBlock("torque", ctx.last_table_number, alpha, steps, note=note))


def _cylinder_sum(ctx, alpha: float, total: float, delays, total_html: str) -> WorkedStep | None:
    """``t_Σ = t_1 + t_3 + …``: each cylinder's part of the one crank's t at the worked row (the
    master rod's statics with that cylinder's force alone), MPa, in the order of the cylinders'
    own angles; None where the bays give no such parts (rods side by side)."""
    loads = ctx.data(BAY_LOADS)
    parts = None if loads is None else loads.cylinder_tangential_Pa
    if not parts:
        return None
    grid = np.asarray(loads.crank_angle_deg, dtype=float)
    row = int(np.argmin(np.abs(grid - alpha)))
    if abs(grid[row] - alpha) > 1e-6:
        return None
    t = ctx.t
    order = [
        d["cylinder"] for d in sorted(delays, key=lambda d: (d["crank"], d["cycle_delay_deg"]))
    ]
    exact = {label: float(parts[label][row]) / 1e6 for label in order if label in parts}
    if len(exact) != len(order):
        return None
    terms = [printed_fixed(t, exact[label], 4) for label in order]
    names = [f"<i>t</i><sub>{t.cylinder(label)}</sub>" for label in order]
    return WorkedStep(
        "journal_torque_sum",
        total_html,
        " + ".join(names),
        " + ".join(bracketed(text, value) for text, value in terms),
        total,
        3,
        t("unit.MPa"),
        {f"t{k}": v for k, (_, v) in enumerate(terms, start=1)},
        exact={f"t{k}": exact[label] for k, label in enumerate(order, start=1)},
    )
