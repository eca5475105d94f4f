"""The worked substitution of the balancing stage: the amplitudes of the inertia forces (the
results of the masses table), C = m_R R ω², C_I = m_s R ω² and C_II = λ C_I (Poda 2007 eqs. 35, 55, 56)."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.worked import WorkedBlock, WorkedStep, printed, printed_g, worked_markup

from .notation import master_mass


def worked_balancing(ctx, r) -> Markup:
    """The three amplitudes with the numbers substituted, each equal to its row of the masses table."""
    t, engine = ctx.t, ctx.scene.engine
    radius, omega, ratio = (
        engine.crank_radius_m,
        engine.angular_velocity_rad_s,
        engine.rod_ratio_value,
    )
    # as the masses table prints them, to five digits: a mass rounded to four would move the
    # product C = m_R R ω² beyond its last printed digit
    m_r_txt, m_r = printed(t, r["rotating_mass_kg"], 5)
    m_s_txt, m_s = printed(t, r["reciprocating_mass_kg"], 5)
    # the crank radius and λ = R/L as the data give them (0,09; 0,28125), no padding or rounding:
    # λ rounded to 0,2812 would not give the C_II printed beside it
    r_txt, r_m = printed_g(t, radius)
    w_txt, w = printed(t, omega, 5)
    l_txt, lam = printed_g(t, ratio)
    c1_txt, c1 = printed(t, r["first_order_N"])
    inputs = {"m_R": m_r, "m_s": m_s, "R": r_m, "omega": w, "lambda": lam, "C_I": c1}
    exact = {
        "m_R": r["rotating_mass_kg"],
        "m_s": r["reciprocating_mass_kg"],
        "R": radius,
        "omega": omega,
        "lambda": ratio,
        "C_I": r["first_order_N"],
    }
    unit = t("balancing.unit_N")
    steps = [
        WorkedStep(
            "centrifugal_amplitude",
            "<i>C</i>",
            "<i>m</i><sub>R</sub><i>Rω</i><sup>2</sup>",
            f"{m_r_txt}·{r_txt}·{w_txt}<sup>2</sup>",
            r["centrifugal_N"],
            0,
            unit,
            inputs,
            significant=4,
            exact=exact,
        ),
        WorkedStep(
            "first_order_amplitude",
            "<i>C</i><sub>I</sub>",
            master_mass(t, r) + "<i>Rω</i><sup>2</sup>",
            f"{m_s_txt}·{r_txt}·{w_txt}<sup>2</sup>",
            r["first_order_N"],
            0,
            unit,
            inputs,
            significant=4,
            exact=exact,
        ),
        WorkedStep(
            "second_order_amplitude",
            "<i>C</i><sub>II</sub>",
            "<i>λC</i><sub>I</sub>",
            f"{l_txt}·{c1_txt}",
            r["second_order_N"],
            0,
            unit,
            inputs,
            significant=4,
            exact=exact,
        ),
    ]
    return worked_markup(ctx, WorkedBlock("balancing", ctx.last_table_number, None, steps))
