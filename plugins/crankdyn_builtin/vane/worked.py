"""The worked substitution of the vane mechanism at one table row: the core's angle and angular
velocity and the slider's height and velocity in closed form, χ = √(1 − λ² sin² α) written out."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    printed,
    printed_g,
    worked_markup,
    worked_row,
)


def worked_vane(ctx, g, labels, r) -> Markup:
    """``g``: the table's rows, ``labels`` their crank angles α."""
    t = ctx.t
    i = worked_row(labels, ctx.worked_angle_deg)
    alpha, row = float(labels[i]), g.row(i)
    a = ctx.angle_text(alpha)
    lam_txt, lam = printed_g(t, r["rod_ratio"])
    w_txt, w = printed(t, r["angular_velocity_rad_s"], 5)
    r_txt, r_mm = printed_g(t, r["crank_radius_m"] * 1e3)
    l_txt, l_mm = printed_g(t, r["tail_length_m"] * 1e3)
    inputs = {"lambda": lam, "omega": w, "r_mm": r_mm, "l_mm": l_mm, "alpha_deg": alpha}
    exact = {
        "lambda": r["rod_ratio"],
        "omega": r["angular_velocity_rad_s"],
        "r_mm": r["crank_radius_m"] * 1e3,
        "l_mm": r["tail_length_m"] * 1e3,
        "alpha_deg": alpha,
    }
    chi_html = "√(1 − <i>λ</i><sup>2</sup> sin<sup>2</sup><i>α</i>)"
    chi = f"√(1 − {lam_txt}<sup>2</sup>·sin<sup>2</sup> {a}°)"
    steps = [
        WorkedStep(
            "vane_core_angle",
            "<i>β</i>",
            "−arcsin(<i>λ</i> sin <i>α</i>)",
            f"−arcsin({lam_txt}·sin {a}°)",
            float(row["core_angle_deg"]),
            2,
            "°",
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "vane_core_angular_velocity",
            "<i>ω</i><sub>c</sub>",
            f"−<i>λω</i> cos <i>α</i>/{chi_html}",
            f"−{lam_txt}·{w_txt}·cos {a}°/{chi}",
            float(row["core_angular_velocity_rad_s"]),
            2,
            t("unit.rad_s"),
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "vane_slider_height",
            "<i>y</i><sub>p</sub>",
            f"<i>l</i>{chi_html}",
            f"{l_txt}·{chi}",
            float(row["slider_y_below_core_m"]) * 1e3,
            2,
            t("unit.mm"),
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "vane_slider_velocity",
            "<i>v</i><sub>yp</sub>",
            f"−<i>ωrλ</i> sin <i>α</i> cos <i>α</i>/{chi_html}",
            f"−{w_txt}·{r_txt}·10<sup>−3</sup>·{lam_txt}·sin {a}°·cos {a}°/{chi}",
            float(row["slider_vy_below_core_m_s"]),
            3,
            t("unit.m_s"),
            inputs,
            exact=exact,
        ),
    ]
    return worked_markup(ctx, WorkedBlock("vane", ctx.last_table_number, alpha, steps))
