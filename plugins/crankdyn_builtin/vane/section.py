"""The ``vane`` stage's section: ``render``, the tables and the conclusions of its text."""

from __future__ import annotations

from functools import partial

from crankdyn.plugin.types import StageOutput, Symbol
from crankdyn.report.context import sample_rows
from crankdyn_builtin.vane.worked import worked_vane

from .figures import _lambda_figure, _plot_compared, _rocker_figure, _three_panels, _two_panels


def _vane_table(f, r, ctx) -> str:
    """The sampled table of the core, vane, rocker and slider motion, with its worked substitutions."""
    t = ctx.t
    mm = 1e3
    rows, labels = sample_rows(f["crank_angle_deg"], ctx.table_step_deg)
    g = f.take(rows)
    table = ctx.table(
        [
            ("<i>α</i>, °", labels, 0),
            ("<i>β</i>, °", g["core_angle_deg"], 2),
            ("<i>γ</i>, °", g["vane_angle_deg"], 2),
            ("<i>ω</i><sub>c</sub>, " + t("unit.rad_s"), g["core_angular_velocity_rad_s"], 2),
            ("<i>ε</i><sub>c</sub>, " + t("unit.rad_s2"), g["core_angular_acceleration_rad_s2"], 0),
            (
                "<i>x</i><sub>k</sub> = <i>x</i><sub>p</sub>, " + t("unit.mm"),
                g["rocker_x_m"] * mm,
                2,
            ),
            ("<i>y</i><sub>k</sub>, " + t("unit.mm"), g["rocker_y_m"] * mm, 2),
            ("<i>y</i><sub>p</sub>, " + t("unit.mm"), g["slider_y_below_core_m"] * mm, 2),
            ("<i>v</i><sub>yp</sub>, " + t("unit.m_s"), g["slider_vy_below_core_m_s"], 3),
            ("<i>j</i><sub>yp</sub>, " + t("unit.m_s2"), g["slider_jy_below_core_m_s2"], 0),
            ("<i>y</i><sub>po</sub>, " + t("unit.mm"), g["slider_relative_m"] * mm, 2),
        ],
        caption=t("vane.table_caption"),
        css_class="data wide",
        see="vane.see_table",
    )
    return table + worked_vane(ctx, g, labels, r)


def render(output: StageOutput, ctx) -> str:
    """The section: the sampled table, the angle, core, rocker, slider and relative-slider figures,
    the rod-ratio study and the conclusion."""
    f = output.tables.arrays("vane")
    r = output.results
    lam = r["rod_ratio"]
    plot = partial(
        _plot_compared,
        f,
        (output.tables.arrays("compare") if "compare" in output.tables else None),
        lam,
        r["compare_rod_ratios"],
        ctx.t,
    )

    table = _vane_table(f, r, ctx)
    figures = _motion_figures(plot, f, r, ctx)
    figure_lambda = _lambda_figure(output.tables.arrays("by_lambda"), lam, ctx)
    _conclude(r, ctx)
    return ctx.render_template(
        "sections/vane.html.j2",
        r=r,
        zeros=r["slider_vertical_acceleration_zeros_deg"],
        table=table,
        **figures,
        figure_lambda=figure_lambda,
    )


def _motion_figures(plot, f, r, ctx) -> dict:
    """The figures of the angles, the core's rates, the rocker, the slider and the slider
    relative to the rocker, in that order, by their template names."""
    figures = {}
    figures["figure_angles"] = _two_panels(
        plot,
        ctx,
        ("core_angle_deg", "vane_angle_deg"),
        ("vane.axis_beta", "vane.axis_gamma"),
        "vane.angles_caption",
        "vane_angles",
        "vane.see_angles",
    )
    figures["figure_core"] = _two_panels(
        plot,
        ctx,
        ("core_angular_velocity_rad_s", "core_angular_acceleration_rad_s2"),
        ("vane.axis_omega_c", "vane.axis_epsilon_c"),
        "vane.core_caption",
        "vane_core",
        "vane.see_core",
    )
    figures["figure_rocker"] = _rocker_figure(f, ctx)
    figures["figure_slider"] = _three_panels(
        plot,
        ctx,
        ("slider_y_below_core_m", "slider_vy_below_core_m_s", "slider_jy_below_core_m_s2"),
        ("vane.axis_slider_y", "vane.axis_slider_v", "vane.axis_slider_j"),
        "upper right",
        "vane.slider_caption",
        "vane_slider",
        "vane.see_slider",
        r["slider_vertical_acceleration_zeros_deg"],
    )
    figures["figure_relative"] = _three_panels(
        plot,
        ctx,
        ("slider_relative_m", "slider_relative_velocity_m_s", "slider_relative_acceleration_m_s2"),
        ("vane.axis_relative_y", "vane.axis_relative_v", "vane.axis_relative_j"),
        "upper left",
        "vane.relative_caption",
        "vane_relative",
        "vane.see_relative",
    )
    return figures


def _conclude(r, ctx) -> None:
    """The section's conclusion: the mechanism's largest angles, the acceleration's zero and the
    slider's travel."""
    zeros = r["slider_vertical_acceleration_zeros_deg"]
    ctx.conclude(
        ctx.t(
            "vane.conclusion",
            lam=ctx.num(r["rod_ratio"], 4),
            beta_max=ctx.t.number_g(r["core_angle_max_deg"], 4),
            gamma_max=ctx.t.number_g(r["vane_angle_max_deg"], 4),
            zero=ctx.num(zeros[0], 5),
            y_max=ctx.num(r["slider_vertical_travel_max_m"] * 1e3, 5),
            y_rel=ctx.num(r["slider_vertical_travel_max_over_tail"], 4),
        )
    )


#: The letters of the section's equations (meanings: symbol.vane.<key> in i18n/). The crank angle,
#: the speed, the stroke, λ, β and μ mean the vane mechanism's own members here, not a crank-slider's,
#: so they take over from the core's in this section. The subscripts are the source's (c: the core,
#: k: the rocker, p: the slider, po: the slider relative to the rocker), Latin in every language.
#: O₃, P and B′ in the equations are points (upright, not quantities), explained in the prose.
#: the input table names the task's data as this section does (VANE_MECHANISM.input_rows)
_WITH_INPUT = ("vane", "input")

SYMBOLS = {
    "crank_angle": Symbol("α", {}, "°"),
    "angular_velocity": Symbol("ω", {}, "unit.rad_s", sections=_WITH_INPUT),
    "crank_radius": Symbol("r", {}, "unit.mm", sections=_WITH_INPUT),
    "tail_length": Symbol("l", {}, "unit.mm", sections=_WITH_INPUT),
    "stroke": Symbol("S", {}, "unit.mm", sections=_WITH_INPUT),
    "rod_ratio": Symbol("λ", {}, "", sections=_WITH_INPUT),
    "chi": Symbol("χ", {}, ""),
    "tail_angle": Symbol("β", {}, "°"),
    "tail_angle_max": Symbol("β", {"en": "max"}, "°"),
    "vane_angle": Symbol("γ", {}, "°"),
    "vane_angle_max": Symbol("γ", {"en": "max"}, "°"),
    "core_angular_velocity": Symbol("ω", {"en": "c"}, "unit.rad_s"),
    "core_angular_acceleration": Symbol("ε", {"en": "c"}, "unit.rad_s2"),
    "rocker_x": Symbol("x", {"en": "k"}, "unit.mm"),
    "rocker_y": Symbol("y", {"en": "k"}, "unit.mm"),
    "rocker_vx": Symbol("v", {"en": "xk"}, "unit.m_s"),
    "rocker_vy": Symbol("v", {"en": "yk"}, "unit.m_s"),
    "rocker_jx": Symbol("j", {"en": "xk"}, "unit.m_s2"),
    "rocker_jy": Symbol("j", {"en": "yk"}, "unit.m_s2"),
    "slider_x": Symbol("x", {"en": "p"}, "unit.mm"),
    "slider_y": Symbol("y", {"en": "p"}, "unit.mm"),
    "slider_rise_max": Symbol("y", {"en": "max"}, "unit.mm"),
    "slider_vy": Symbol("v", {"en": "yp"}, "unit.m_s"),
    "slider_jy": Symbol("j", {"en": "yp"}, "unit.m_s2"),
    "acceleration_zero": Symbol("α", {"en": "0"}, "°"),
    "integer": Symbol("N", {}, ""),
    "relative_y": Symbol("y", {"en": "po"}, "unit.mm"),
    "relative_v": Symbol("v", {"en": "po"}, "unit.m_s"),
    "relative_j": Symbol("j", {"en": "po"}, "unit.m_s2"),
    "mu": Symbol("μ", {}, ""),
}
