"""The worked substitution of the rod-dynamics stage at one table row: the lateral acceleration of the
rod's centre of mass, a_Gx = (L − l_R)(ε_r cos β − ω_r² sin β), from the row's own β, ω_r and ε_r,
and, with the rod's moment of inertia, its inertia couple M_G = −I_G ε_r."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    bracketed,
    column_decimals,
    printed,
    printed_fixed,
    worked_markup,
    worked_row,
)


def rod_table_decimals(g) -> tuple[int, int, int, int]:
    """The decimals the table prints ω_r, ε_r, a_Gx and a_Gz with (its worked line substitutes them
    so): 1, 0, 0, 0, more for a slow engine's small values (:func:`column_decimals`)."""
    return (
        column_decimals(g["rod_angular_velocity_rad_s"], 1),
        column_decimals(g["rod_angular_acceleration_rad_s2"], 0),
        column_decimals(g["cm_acceleration_x_m_s2"], 0),
        column_decimals(g["cm_acceleration_z_m_s2"], 0),
    )


def worked_rod_dynamics(ctx, g, labels, r) -> Markup:
    """``g``: the table's rows (as printed), ``labels`` their crank angles."""
    t = ctx.t
    i = worked_row(labels, ctx.worked_angle_deg)
    alpha, row = float(labels[i]), g.row(i)
    beta, rate, accel = (
        float(row[k])
        for k in ("rod_angle_deg", "rod_angular_velocity_rad_s", "rod_angular_acceleration_rad_s2")
    )
    arm_mm = (r["rod_length_m"] - r["rod_cm_from_big_end_m"]) * 1e3
    omega_dec, eps_dec, ax_dec, _ = rod_table_decimals(g)
    b_txt, b = printed_fixed(t, beta, 2)  # β, ω_r and ε_r as the table prints them
    w_txt, w = printed_fixed(t, rate, omega_dec)
    e_txt, e = printed_fixed(t, accel, eps_dec)
    d_txt, d = printed(t, arm_mm, 5)
    inputs = {"arm_mm": d, "beta_deg": b, "omega_r": w, "epsilon_r": e, "alpha_deg": alpha}
    exact = {
        "arm_mm": arm_mm,
        "beta_deg": beta,
        "omega_r": rate,
        "epsilon_r": accel,
        "alpha_deg": alpha,
    }
    steps = [
        WorkedStep(
            "rod_cm_acceleration_x",
            "<i>a</i><sub>Gx</sub>",
            "(<i>L</i> − <i>l</i><sub>R</sub>)(<i>ε</i><sub>r</sub> cos <i>β</i> − <i>ω</i><sub>r</sub><sup>2</sup> sin <i>β</i>)",
            f"{d_txt}·10<sup>−3</sup>·[{bracketed(e_txt, e)}·cos {bracketed(b_txt, b)}° − {bracketed(w_txt, w)}<sup>2</sup>·sin "
            f"{bracketed(b_txt, b)}°]",
            float(row["cm_acceleration_x_m_s2"]),
            ax_dec,
            t("unit.m_s2"),
            inputs,
            exact=exact,
        )
    ]
    if "inertia_couple_Nm" in g:
        i_txt, inertia = printed(t, r["rod_moment_of_inertia_kg_m2"])
        steps.append(
            WorkedStep(
                "rod_inertia_couple",
                "<i>M</i><sub>G</sub>",
                "−<i>I</i><sub>G</sub><i>ε</i><sub>r</sub>",
                f"−{i_txt}·{bracketed(e_txt, e)}",
                float(row["inertia_couple_Nm"]),
                2,
                t("unit.Nm"),
                {**inputs, "I_G": inertia},
                exact={**exact, "I_G": r["rod_moment_of_inertia_kg_m2"]},
            )
        )
    return worked_markup(ctx, WorkedBlock("rod_dynamics", ctx.last_table_number, alpha, steps))
