"""The worked substitution of the offset crank-slider at one table row: the rod angle, the piston's
displacement and velocity and the rod's angular velocity in closed form with the row's numbers."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    bracketed,
    printed,
    printed_g,
    worked_markup,
    worked_row,
)


def worked_offset_crank(ctx, g, labels, r) -> Markup:
    """``g``: the table's rows, ``labels`` their crank angles α (from TDC); φ = α + φ_TDC."""
    t = ctx.t
    i = worked_row(labels, ctx.worked_angle_deg)
    alpha, row = float(labels[i]), g.row(i)
    phi, beta = float(row["crank_angle_from_axis_deg"]) % 360.0, float(row["rod_angle_deg"])
    radius_mm, length_mm, offset_mm = (
        r["crank_radius_m"] * 1e3,
        r["rod_length_m"] * 1e3,
        r["offset_m"] * 1e3,
    )
    f_txt, f = printed(t, phi, 5)
    b_txt, b = printed(t, beta, 5)
    r_txt, r_mm = printed_g(t, radius_mm)
    l_txt, l_mm = printed_g(t, length_mm)
    e_txt, e_mm = printed_g(t, offset_mm)
    lam_txt, lam = printed(t, r["rod_ratio"], 5)
    k_txt, k = printed(t, r["offset_ratio"], 4)
    w_txt, w = printed(t, r["angular_velocity_rad_s"], 5)
    inputs = {
        "phi_deg": f,
        "beta_deg": b,
        "R_mm": r_mm,
        "L_mm": l_mm,
        "e_mm": e_mm,
        "lambda": lam,
        "k": k,
        "omega": w,
        "alpha_deg": alpha,
    }
    exact = {
        "phi_deg": phi,
        "beta_deg": beta,
        "R_mm": radius_mm,
        "L_mm": length_mm,
        "e_mm": offset_mm,
        "lambda": r["rod_ratio"],
        "k": r["offset_ratio"],
        "omega": r["angular_velocity_rad_s"],
        "alpha_deg": alpha,
    }
    b_s = f"{bracketed(b_txt, b)}°"
    steps = [
        WorkedStep(
            "offset_rod_angle",
            "<i>β</i>",
            "arcsin(<i>λ</i> sin <i>φ</i> − <i>k</i>)",
            f"arcsin({lam_txt}·sin {f_txt}° − {bracketed(k_txt, k)})",
            beta,
            2,
            "°",
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "offset_piston_displacement",
            "<i>s</i><sub>p</sub>",
            "√((<i>L</i> + <i>R</i>)<sup>2</sup> − <i>e</i><sup>2</sup>) − <i>R</i> cos <i>φ</i> − <i>L</i> cos <i>β</i>",
            f"√(({l_txt} + {r_txt})<sup>2</sup> − {bracketed(e_txt, e_mm)}<sup>2</sup>) − {r_txt}·cos {f_txt}° "
            f"− {l_txt}·cos {b_s}",
            float(row["piston_displacement_m"]) * 1e3,
            3,
            t("unit.mm"),
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "offset_piston_velocity",
            "<i>v</i><sub>p</sub>",
            "<i>Rω</i> sin(<i>φ</i> + <i>β</i>)/cos <i>β</i>",
            f"{r_txt}·10<sup>−3</sup>·{w_txt}·sin({f_txt}° + {b_s})/cos {b_s}",
            float(row["piston_velocity_m_s"]),
            2,
            t("unit.m_s"),
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "offset_rod_angular_velocity",
            "<i>ω</i><sub>r</sub>",
            "<i>ωλ</i> cos <i>φ</i>/cos <i>β</i>",
            f"{w_txt}·{lam_txt}·cos {f_txt}°/cos {b_s}",
            float(row["rod_angular_velocity_rad_s"]),
            1,
            t("unit.rad_s"),
            inputs,
            exact=exact,
        ),
    ]
    note = t("offset_crank.worked_phi", alpha=ctx.angle_text(alpha), phi=f_txt)
    return worked_markup(
        ctx, WorkedBlock("offset_crank", ctx.last_table_number, alpha, steps, note=note)
    )
