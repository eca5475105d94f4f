"""The numerics' sections: the full study, the course note's appendix, the kinematics' forms."""

from __future__ import annotations

import functools
from html import escape

from crankdyn.plugin.types import (
    StageOutput,
)
from crankdyn.scene import (
    options,
)

from .compute import BUDGET_REASON, QUANTITIES
from .figures import _forms_figure, form_label, plain, steps_figure
from .options import NumericsOptions
from .reference import FALLBACK_REFERENCE_STEP_DEG, GAUSS_ORDER, PANEL_DEG, SEARCH_STEP_DEG


def _render_kinematics(r, ctx):
    t = ctx.t
    rows = r.get("kinematics_forms")
    if not rows:
        return None, None
    table = ctx.table(
        [
            (t("numerics.form"), [form_label(t, row) for row in rows], None),
            (
                "max |Δ<i>s</i>|, " + t("unit.m"),
                [ctx.num(row["displacement_error_max_m"], 2) for row in rows],
                None,
            ),
            (
                "max |Δ<i>j</i>|/<i>ω</i><sup>2</sup>, " + t("unit.m"),
                [ctx.num(row["acceleration_error_max_m_s2"], 2) for row in rows],
                None,
            ),
            (
                t("numerics.time_per_evaluation"),
                [ctx.num(row["time_per_evaluation_s"] * 1e6, 3) for row in rows],
                None,
            ),
        ],
        caption=t("numerics.forms_caption", points=rows[0]["points"]),
        see="numerics.see_forms_table",
    )
    figure = ctx.figure(
        functools.partial(_forms_figure, rows, t),
        t("numerics.forms_figure_caption"),
        "kinematics_forms",
        see="numerics.see_forms_figure",
    )
    return table, figure


def _render_probes(r, ctx):
    t = ctx.t
    out = []
    for study in (r.get("solvers") or {}).values():
        points = study["points"]
        if not points:
            out.append((study["title"], None, study.get("refused", "")))
            continue
        table = ctx.table(
            [
                (t("numerics.method"), [p["method"] for p in points], None),
                (t("numerics.setting"), [p["setting"] for p in points], None),
                (
                    t("numerics.error"),
                    [ctx.num(p["error"], 2) + " " + p["error_unit"] for p in points],
                    None,
                ),
                (t("numerics.time_ms"), [ctx.num(p["time_s"] * 1e3, 3) for p in points], None),
            ],
            caption=t("numerics.solver_caption", title=study["title"]),
            see="numerics.see_solver",
        )
        out.append((study["title"], table, ""))
    return out


def _render_steps(r, ctx):
    """Table, figure, the printed-error statement and the reference text of the step study."""
    t = ctx.t
    steps = r["steps"]
    labels = {
        "mean_torque": t("numerics.q_mean_torque"),
        "indicated_work": t("numerics.q_indicated_work"),
        "tangential_max": t("numerics.q_tangential_max"),
        "tangential_min": t("numerics.q_tangential_min"),
        "resultant_max": t("numerics.q_resultant_max"),
    }
    has_theory = any("theoretical_work_error_relative" in s for s in steps)
    columns = [
        ("Δ<i>α</i>, °", [plain(ctx, s["angle_step_deg"]) for s in steps], None),
        (
            t("numerics.angles_count"),
            [str(s["points"]) for s in steps],
            None,
        ),  # N is the series' terms
        (t("numerics.time_ms"), [ctx.num(s["time_s"] * 1e3, 3) for s in steps], None),
    ]
    for q in QUANTITIES:
        columns.append(
            (labels[q] + ", %", [ctx.num(100 * s[f"{q}_error_relative"], 2) for s in steps], None)
        )
    if has_theory:
        columns.append(
            (
                t("numerics.q_theoretical_work") + ", %",
                [
                    ctx.num(100 * s["theoretical_work_error_relative"], 2)
                    if "theoretical_work_error_relative" in s
                    else "—"
                    for s in steps
                ],
                None,
            )
        )
    table = ctx.table(
        columns,
        caption=t("numerics.steps_caption"),
        css_class="data wide",
        see="numerics.see_steps_table",
    )

    figure = ctx.figure(
        functools.partial(steps_figure, steps, labels, has_theory, t),
        t("numerics.steps_figure_caption"),
        "error_vs_time",
        see="numerics.see_steps_figure",
    )

    a = r["at_scene_step"]
    statement = t(
        "numerics.printed_errors",
        step=plain(ctx, a["angle_step_deg"]),
        torque=ctx.num(100 * a["mean_torque_error_relative"], 2),
        work=ctx.num(100 * a["indicated_work_error_relative"], 2),
        t_max=ctx.num(a["tangential_max_error_Pa"] / 1e6, 2),
        t_min=ctx.num(a["tangential_min_error_Pa"] / 1e6, 2),
        q_max=ctx.num(a["resultant_max_error_Pa"] / 1e6, 2),
    )
    if r["reference_method"] in ("quadrature", "mixed"):
        uncertainty = max(r["reference_uncertainty_relative"].values(), default=0.0)
        reference_text = t(
            "numerics.reference_quadrature",
            panel=plain(ctx, PANEL_DEG),
            order=GAUSS_ORDER,
            search=plain(ctx, SEARCH_STEP_DEG),
            uncertainty=ctx.num(100 * uncertainty, 2),
            ms=ctx.num(r["reference_time_s"] * 1e3, 3),
        )
        if r["reference_method"] == "mixed":
            reference_text += " " + t(
                "numerics.reference_mixed", step=plain(ctx, FALLBACK_REFERENCE_STEP_DEG)
            )
    else:
        reference_text = t("numerics.reference_fine_step", step=plain(ctx, r["reference_step_deg"]))
    return table, figure, statement, reference_text + " " + _timing_text(r, ctx)


def _timing_text(r, ctx) -> str:
    """How the step times were measured and the fixed per-call overhead they leave out."""
    common = {
        "repeats": r["steps_timing_repeats"],
        "min_ms": ctx.num(r["steps_timing_min_repeat_s"] * 1e3, 2),
    }
    if r["steps_timed"] == "formulas":
        return ctx.t(
            "numerics.timing_formulas",
            overhead=ctx.num(r["per_call_overhead_s"] * 1e3, 2),
            **common,
        )
    return ctx.t("numerics.timing_rerun", **common)


def _course_note(ctx) -> bool:
    """A course note (``[report] detail = "course"``) states the error against time in a few
    sentences; the study's tables, figures and methods belong to the full report."""
    return ctx.scene is not None and ctx.scene.report.detail == "course"


def render_course(r, ctx) -> str | None:
    """The course note's statement: the step and the errors of the main results at it, against
    the coarsest step studied (what a coarser step would cost)."""
    if "steps" not in r:
        return None
    t = ctx.t
    a = r["at_scene_step"]
    statement = t(
        "numerics.printed_errors_course",
        step=plain(ctx, a["angle_step_deg"]),
        torque=_error_words(ctx, 100 * a["mean_torque_error_relative"]),
        work=_error_words(ctx, 100 * a["indicated_work_error_relative"]),
        t_max=_error_words(ctx, a["tangential_max_error_Pa"] / 1e6),
        t_min=_error_words(ctx, a["tangential_min_error_Pa"] / 1e6),
        q_max=_error_words(ctx, a["resultant_max_error_Pa"] / 1e6),
    )
    ctx.conclude(statement)
    own = min(r["steps"], key=lambda s: abs(s["angle_step_deg"] - a["angle_step_deg"]))
    coarse = max(r["steps"], key=lambda s: s["angle_step_deg"])
    text = [statement]
    if coarse is not own:
        text.append(_course_coarse(coarse, ctx))
    return "".join(f'<p class="printed-errors">{escape(p)}</p>' for p in text)


#: The smallest error a course note states as a number (in % of a result, or in MPa): a smaller
#: one is "below 0,001", as an engineer bounds an error, not 6,7·10⁻⁶ of a program's precision.
_ERROR_FLOOR = 1e-3


def _error_words(ctx, error: float) -> str:
    """An error of a printed result in a course note: "up to 0,0067" or "below 0,001"."""
    if abs(error) < _ERROR_FLOOR:
        return ctx.t("numerics.error_below", value=ctx.t.number_g(_ERROR_FLOOR, 1))
    return ctx.t("numerics.error_up_to", value=ctx.num(abs(error), 2))


def _course_coarse(coarse, ctx) -> str:
    """What the coarsest step studied would cost: the largest relative error of the main results
    and whose it is (a course note states the step and its errors; a computer's run time says
    nothing of the method)."""
    worst = max(QUANTITIES, key=lambda q: coarse[f"{q}_error_relative"])
    return ctx.t(
        "numerics.course_coarse",
        coarse=plain(ctx, coarse["angle_step_deg"]),
        quantity=ctx.t(f"numerics.q_{worst}"),
        coarse_error=ctx.num(100 * coarse[f"{worst}_error_relative"], 2),
    )


def render(output: StageOutput, ctx) -> str:
    r = output.results
    if _course_note(ctx):
        return render_course(r, ctx)
    step_table = step_figure = statement = reference_text = None
    if "steps" in r:
        step_table, step_figure, statement, reference_text = _render_steps(r, ctx)
        ctx.conclude(statement)
    forms_table, forms_figure = _render_kinematics(r, ctx)
    return ctx.render_template(
        "sections/numerics.html.j2",
        r=r,
        step_table=step_table,
        step_figure=step_figure,
        statement=statement,
        reference_text=reference_text,
        refused=refused_steps(r, ctx),
        unavailable=ctx.t("numerics.unavailable_pipeline") if r.get("steps_unavailable") else None,
        forms_table=forms_table,
        forms_figure=forms_figure,
        kinematics_statement=_kinematics_statement(r, ctx),
        probes=_render_probes(r, ctx),
    )


def refused_steps(r, ctx) -> list[tuple[str, str]]:
    """The steps left out of the study and why, in the report's language. results.json keeps
    the reasons as the code words them (the rule a step broke, in English); the report says
    which of the two cases it is."""
    t = ctx.t
    budget = (
        options(ctx.scene, "numerics", NumericsOptions).time_budget_s
        if ctx.scene is not None
        else None
    )
    out = []
    for step, reason in r.get("steps_refused", {}).items():
        if reason.startswith(BUDGET_REASON) and budget is not None:
            why = t("numerics.refused_time_budget", budget=t.number_g(budget, 3))
        else:
            why = t("numerics.refused_not_allowed")
        out.append((t.number_g(float(step), 4), why))
    return out


def _kinematics_statement(r, ctx) -> str | None:
    rows = r.get("kinematics_forms")
    if not rows:
        return None
    t = ctx.t
    chosen = next(
        row
        for row in rows
        if row["form"] == ("exact" if r["kinematics_method"] == "exact" else "two_term")
    )
    return t(
        "numerics.kinematics_printed_" + r["kinematics_method"],
        ds=ctx.num(chosen["displacement_error_max_m"] * 1e3, 2),
        dj=ctx.num(chosen["acceleration_error_max_m_s2"], 2),
    )


def render_kinematics(output: StageOutput, ctx) -> str | None:
    r = output.results
    if _course_note(ctx):  # the series of the kinematics are a study of the full report
        return None
    forms_table, forms_figure = _render_kinematics(r, ctx)
    if forms_table is None and not r.get("solvers"):
        return None
    return ctx.render_template(
        "sections/numerics.html.j2",
        r=r,
        step_table=None,
        step_figure=None,
        statement=None,
        reference_text=None,
        refused=[],
        unavailable=None,
        forms_table=forms_table,
        forms_figure=forms_figure,
        kinematics_statement=_kinematics_statement(r, ctx),
        probes=_render_probes(r, ctx),
    )
