"""The worked substitution of the flywheel stage: the required moment of inertia and the cyclic
irregularity with the numbers put in, each equal to its row of the results table
(½J(ω_max² − ω_min²) = ΔL, so J = ΔL/(δω²); Poda 2007 §5, Khurmi 2005 ch. 16)."""

from __future__ import annotations

from markupsafe import Markup

from crankdyn.report.typeset import symbol_html
from crankdyn.report.worked import WorkedBlock, WorkedStep, printed, printed_g, worked_markup


def irregularity_is_a_result(r) -> bool:
    """Whether δ is a result to show: a flywheel sized for [δ] gives [δ] back; δ says something for a
    given flywheel, or where the engine's own inertia already keeps it below [δ]."""
    required = r["required_irregularity"]
    if r.get("flywheel_raised"):  # the exact solution, not ΔL/(Jω²), gives the design's δ = [δ]
        return False
    return (
        r["flywheel_given"]
        or required is None
        or abs(r["irregularity"] - required) > 1e-9 * required
    )


def worked_flywheel(ctx, r) -> Markup:
    """J_0 = ΔL/([δ]ω²), J_f = J_0 − J_m − J_e (when a δ is required) and δ = ΔL/(Jω²) (when δ is a result)."""
    t = ctx.t
    excess_txt, excess = printed(t, r["excess_work_J"])  # as the results table prints them
    w_txt, w = printed(t, r["angular_velocity_rad_s"], 5)
    jm_txt, j_m = printed(t, r["mechanism_inertia_mean_kg_m2"])
    je_txt, j_e = printed(t, r["engine_inertia_kg_m2"])
    jt_txt, j_total = printed(t, r["total_inertia_kg_m2"])
    j0_txt, j_0 = printed(t, r["required_total_inertia_kg_m2"] or 0.0)
    inputs = {"dL": excess, "omega": w, "J_m": j_m, "J_e": j_e, "J": j_total, "J_0": j_0}
    exact = {
        "dL": r["excess_work_J"],
        "omega": r["angular_velocity_rad_s"],
        "J_m": r["mechanism_inertia_mean_kg_m2"],
        "J_e": r["engine_inertia_kg_m2"],
        "J": r["total_inertia_kg_m2"],
        "J_0": r["required_total_inertia_kg_m2"] or 0.0,
    }
    unit, steps = t("flywheel.unit_kg_m2"), []
    if r["required_irregularity"] is not None:
        d_txt, delta = printed_g(t, r["required_irregularity"])  # given: as written
        inputs["delta_req"], exact["delta_req"] = delta, r["required_irregularity"]
        steps.append(
            WorkedStep(
                "required_total_inertia",
                "<i>J</i><sub>0</sub>",
                "Δ<i>L</i>/([<i>δ</i>] <i>ω</i><sub>m</sub><sup>2</sup>)",
                f"{excess_txt}/({d_txt}·{w_txt}<sup>2</sup>)",
                r["required_total_inertia_kg_m2"],
                0,
                unit,
                inputs,
                significant=4,
                exact=exact,
            )
        )
    if r[
        "required_flywheel_inertia_kg_m2"
    ]:  # zero when the engine's own inertia is enough: nothing to subtract
        steps.append(
            WorkedStep(
                "required_flywheel_inertia",
                # the adopted flywheel (J_f) is the exact solution's where it raises this one
                symbol_html("flywheel.energy_flywheel_inertia", t.language, ctx.symbols)
                if r.get("flywheel_raised")
                else "<i>J</i><sub>f</sub>",
                "<i>J</i><sub>0</sub> − <i>J</i><sub>m</sub> − <i>J</i><sub>e</sub>",
                f"{j0_txt} − {jm_txt} − {je_txt}",
                r["required_flywheel_inertia_kg_m2"],
                0,
                unit,
                inputs,
                significant=4,
                exact=exact,
            )
        )
    if irregularity_is_a_result(r):
        steps.append(
            WorkedStep(
                "irregularity",
                "<i>δ</i>",
                "Δ<i>L</i>/(<i>J</i> <i>ω</i><sub>m</sub><sup>2</sup>)",
                f"{excess_txt}/({jt_txt}·{w_txt}<sup>2</sup>)",
                r["irregularity"],
                0,
                "",
                inputs,
                significant=4,
                exact=exact,
            )
        )
    return worked_markup(
        ctx,
        WorkedBlock(
            "flywheel", ctx.last_table_number, None, steps, note=t("flywheel.worked_total")
        ),
    )
