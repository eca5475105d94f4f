"""The numerics' figures: the error against the angle step, and the kinematics' forms."""

from __future__ import annotations

from crankdyn.report.figures import new_figure

from .compute import QUANTITIES
from .reference import labelled_points

# Errors below this (relative) are shown as this on log axes.
_LOG_FLOOR = 1e-16


# ------------------------------------------------------------------ rendering
_FORM_MARKERS = {"two_term": "s", "series": "o", "harmonic": "^", "exact": "*"}


def plain(ctx, value: float) -> str:
    """A step such as 0.25 or 30 as typed (no padding zeros), with the language's separator."""
    return f"{value:g}".replace(".", ctx.t.decimal_separator)


def form_label(t, row) -> str:
    if row["form"] == "exact":
        return t("numerics.form_exact")
    if row["form"] == "two_term":
        return t("numerics.form_two_term")
    return t(f"numerics.form_{row['form']}", terms=row["terms"])


def _forms_figure(rows, t):
    """The largest displacement error of each form of the piston kinematics against its time per evaluation."""
    fig, ax = new_figure(16, 8.5)
    for row in rows:
        ax.loglog(
            [row["time_per_evaluation_s"] * 1e6],
            [max(row["displacement_error_max_m"], _LOG_FLOOR * 1e-3)],
            marker=_FORM_MARKERS[row["form"]],
            ls="none",
            ms=7,
            label=form_label(t, row),
        )
    ax.set_xlabel(t("numerics.axis_time_us"))
    ax.set_ylabel(t("numerics.axis_displacement_error"))
    ax.legend(loc="best", fontsize=8, ncol=2)
    return fig


def steps_figure(steps, labels, has_theory, t):
    """The errors of the step study's quantities against the run time, the points marked with their step."""
    fig, ax = new_figure(16, 10)
    times = [s["time_s"] * 1e3 for s in steps]
    highest = [100 * _LOG_FLOOR] * len(
        steps
    )  # each step's highest marker: its label goes above them all
    for i, q in enumerate(QUANTITIES):
        errors = [max(100 * s[f"{q}_error_relative"], 100 * _LOG_FLOOR) for s in steps]
        ax.loglog(times, errors, marker="os^vD"[i], label=labels[q])
        highest = [max(h, e) for h, e in zip(highest, errors, strict=True)]
    if has_theory:
        errors = [
            max(100 * s.get("theoretical_work_error_relative", 0.0), 100 * _LOG_FLOOR)
            for s in steps
        ]
        ax.loglog(
            times, errors, marker="x", ls="--", color="0.4", label=t("numerics.q_theoretical_work")
        )
        highest = [max(h, e) for h, e in zip(highest, errors, strict=True)]
    points = [
        (x, max(100 * s["mean_torque_error_relative"], 100 * _LOG_FLOOR))
        for s, x in zip(steps, times, strict=True)
    ]
    for k in labelled_points(points):  # (a supervisor: the labels printed over the markers)
        ax.annotate(
            f"{t.number_g(steps[k]['angle_step_deg'])}°",
            (times[k], highest[k]),
            textcoords="offset points",
            xytext=(0, 6),
            ha="center",
            va="bottom",
            fontsize=7,
        )
    ax.set_xlabel(t("numerics.axis_time_ms"))
    ax.set_ylabel(t("numerics.axis_error_percent"))
    ax.legend(loc="best", fontsize=8)
    return fig
