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
    exact = {
        "phi_deg": phi,
        "beta_deg": beta,
        "R_mm": r["crank_radius_m"] * 1e3,
        "L_mm": r["rod_length_m"] * 1e3,
        "e_mm": r["offset_m"] * 1e3,
        "lambda": r["rod_ratio"],
        "k": r["offset_ratio"],
        "omega": r["angular_velocity_rad_s"],
        "alpha_deg": alpha,
    }
    texts, inputs = _printed_inputs(t, exact)
    steps = _offset_steps(t, row, texts, inputs, exact)
    note = t("offset_crank.worked_phi", alpha=ctx.angle_text(alpha), phi=texts["phi_deg"])
    return worked_markup(
        ctx, WorkedBlock("offset_crank", ctx.last_table_number, alpha, steps, note=note)
    )


#: The digits each input is printed with in the substitutions (None: significant digits).
_PRINTED_DIGITS = {
    "phi_deg": 5,
    "beta_deg": 5,
    "R_mm": None,
    "L_mm": None,
    "e_mm": None,
    "lambda": 5,
    "k": 4,
    "omega": 5,
}


def _printed_inputs(t, exact: dict) -> tuple[dict, dict]:
    """(each input as printed, each input's printed value) of the substitutions; α as it is."""
    texts, inputs = {}, {}
    for name, digits in _PRINTED_DIGITS.items():
        texts[name], inputs[name] = (
            printed_g(t, exact[name]) if digits is None else printed(t, exact[name], digits)
        )
    inputs["alpha_deg"] = exact["alpha_deg"]
    return texts, inputs


def _offset_steps(t, row, texts: dict, inputs: dict, exact: dict) -> list[WorkedStep]:
    """The substituted formulas: the rod angle, the piston's displacement and velocity and the
    rod's angular velocity, each with the row's value."""
    f_txt, r_txt, l_txt, lam_txt, w_txt = (
        texts[name] for name in ("phi_deg", "R_mm", "L_mm", "lambda", "omega")
    )
    b_s = f"{bracketed(texts['beta_deg'], inputs['beta_deg'])}°"
    e_b = bracketed(texts["e_mm"], inputs["e_mm"])
    return [
        WorkedStep(
            "offset_rod_angle",
            "<i>β</i>",
            "arcsin(<i>λ</i> sin <i>φ</i> − <i>k</i>)",
            f"arcsin({lam_txt}·sin {f_txt}° − {bracketed(texts['k'], inputs['k'])})",
            exact["beta_deg"],
            2,
            "°",
            inputs,
            exact=exact,
        ),
        WorkedStep(
            "offset_piston_displacement",
            "<i>s</i><sub>p</sub>",
            "√((<i>L</i> + <i>R</i>)<sup>2</sup> − <i>e</i><sup>2</sup>) "
            "− <i>R</i> cos <i>φ</i> − <i>L</i> cos <i>β</i>",
            f"√(({l_txt} + {r_txt})<sup>2</sup> − {e_b}<sup>2</sup>) "
            f"− {r_txt}·cos {f_txt}° − {l_txt}·cos {b_s}",
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
