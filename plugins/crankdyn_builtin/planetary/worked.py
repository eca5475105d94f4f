"""The worked substitution of the planetary linkage at one table row: the big end's coordinates
x_B = a sin φ + e sin θ, z_B = a cos φ + e cos θ (θ = ψ0 + kφ) and the rod angle sin β = x_B/L."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.worked import (
    WorkedBlock,
    WorkedStep,
    bracketed,
    printed_fixed,
    printed_g,
    worked_markup,
    worked_row,
)


def worked_planetary(ctx, g, labels, r) -> Markup:
    """``g``: the table's rows, ``labels`` their crank angles α; φ = α + φ_TDC is the carrier's angle."""
    t = ctx.t
    i = worked_row(labels, ctx.worked_angle_deg)
    alpha, row = float(labels[i]), g.row(i)
    phi = float(row["carrier_angle_deg"])
    a_mm, e_mm, length_mm = (
        r["carrier_radius_m"] * 1e3,
        r["pin_radius_m"] * 1e3,
        r["rod_length_m"] * 1e3,
    )
    f_txt, f = printed_g(t, phi)
    a_txt, a = printed_g(t, a_mm)
    e_txt, e = printed_g(t, e_mm)
    l_txt, l_mm = printed_g(t, length_mm)
    p_txt, psi = printed_g(t, r["pin_phase_deg"])
    k_txt, k = printed_g(t, r["planet_speed_ratio"])
    x_mm = float(row["big_end_x_m"]) * 1e3
    x_txt, x = printed_fixed(t, x_mm, 2)  # as the table prints it
    inputs = {
        "phi_deg": f,
        "a_mm": a,
        "e_mm": e,
        "L_mm": l_mm,
        "psi0_deg": psi,
        "k": k,
        "x_B": x,
        "alpha_deg": alpha,
    }
    exact = {
        "phi_deg": phi,
        "a_mm": a_mm,
        "e_mm": e_mm,
        "L_mm": length_mm,
        "psi0_deg": r["pin_phase_deg"],
        "k": r["planet_speed_ratio"],
        "x_B": x_mm,
        "alpha_deg": alpha,
    }
    theta = f"({p_txt}° + {bracketed(k_txt, k)}·{bracketed(f_txt, f)}°)"
    phi_s = f"{bracketed(f_txt, f)}°"
    steps = [
        WorkedStep(
            "planetary_big_end_x",
            "<i>x</i><sub>B</sub>",
            "<i>a</i> sin <i>φ</i> + <i>e</i> sin <i>θ</i>",
            f"{a_txt}·sin {phi_s} + {e_txt}·sin {theta}",
            x_mm,
            2,
            t("unit.mm"),
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "planetary_big_end_z",
            "<i>z</i><sub>B</sub>",
            "<i>a</i> cos <i>φ</i> + <i>e</i> cos <i>θ</i>",
            f"{a_txt}·cos {phi_s} + {e_txt}·cos {theta}",
            float(row["big_end_z_m"]) * 1e3,
            2,
            t("unit.mm"),
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "planetary_rod_angle",
            "<i>β</i>",
            "arcsin(<i>x</i><sub>B</sub>/<i>L</i>)",
            f"arcsin({bracketed(x_txt, x)}/{l_txt})",
            float(row["rod_angle_deg"]),
            2,
            "°",
            inputs,
            exact=exact,
        ),
    ]
    note = t("planetary.worked_phi", alpha=ctx.angle_text(alpha), phi=f_txt)
    return worked_markup(
        ctx, WorkedBlock("planetary", ctx.last_table_number, alpha, steps, note=note)
    )
