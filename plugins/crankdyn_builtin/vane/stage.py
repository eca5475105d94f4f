"""Vane engine with a crank-rocker parallelogram mechanism: mechanism and kinematics stage.

Source: Klementev (2023). The vane engine is not a piston engine: its working volumes
follow the vane angle, so its scenes are kinematics-only and this stage provides no
``PistonMotion`` (the indicator, force and torque stages do not apply).

Scene mapping: ``engine.stroke`` = 2r (the slider's travel along the rocker's slot),
``engine.rod_length`` = l (the core's tail) or ``engine.rod_ratio`` = lambda = r/l.
"""

from __future__ import annotations

from functools import partial
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict

from crankdyn.errors import Problem
from crankdyn.physics import vane as vn
from crankdyn.physics.extrema import central_derivative, periodic_extreme
from crankdyn.physics.scalar_search import brentq
from crankdyn.plugin_types import Mechanism, Stage, StageOutput, Symbol
from crankdyn.report.context import sample_rows
from crankdyn.report.figures import crank_angle_axis, new_figure
from crankdyn.scene import number, options, quantity
from crankdyn.scene_inputs import single_mechanism_problems
from crankdyn_builtin.vane.worked import worked_vane

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"
#: Plugin tables that only a multi-cylinder engine reads (the articulated rods).
MULTI_CYLINDER_TABLES = ("articulated",)

MECHANISM = "vane_crank_rocker"
WORKING_CYCLE_DEG = (90.0, 810.0)  # one side of the vane: alpha = 90...450...810 (source)


class VaneParams(BaseModel):
    """The [mechanism] table of the vane engine (all optional)."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    core_offset: quantity("length", ge=0, le=2.0, unit="mm", scale=1e-3) = "0 mm"
    compare_rod_ratios: list[number(gt=0, lt=1)] = []


def check(scene) -> list[Problem]:
    problems = single_mechanism_problems(scene, "vane engine", MULTI_CYLINDER_TABLES)
    if scene.cycle is not None:
        problems.append(Problem("cycle", "[cycle]", "the vane engine is studied for its kinematics only: its "
                                "working volumes follow the vane angle, not a piston, so the indicator-diagram and "
                                "force stages do not apply; remove [cycle]"))
    if scene.masses is not None:
        problems.append(Problem("masses", "[masses]", "the vane engine is studied for its kinematics only (the "
                                "source gives no dynamics); remove [masses]"))
    options(scene, "mechanism", VaneParams)
    return problems


VANE_MECHANISM = Mechanism(
    name=MECHANISM,
    summary="vane engine with a crank-rocker parallelogram converting mechanism (kinematics only)",
    check=check,
    params_model=VaneParams,
    # the task's stroke is the slider's travel, its rod the core's tail (the section's own S, r, l, λ)
    input_rows={"stroke": ("vane.input_stroke", "<i>S</i>"), "crank_radius": ("vane.input_radius", "<i>r</i> = <i>S</i>/2"),
                "rod_length": ("vane.input_tail", "<i>l</i>"), "rod_ratio": ("vane.input_ratio", "<i>λ</i> = <i>r</i>/<i>l</i>")},
)


def applies(scene) -> str | None:
    if scene.engine.mechanism != MECHANISM:
        return f"the scene's mechanism is {scene.engine.mechanism!r}, not the vane engine"
    return None


def _curves(alpha, r, lam, omega, suffix=""):
    return {
        "core_angle_deg" + suffix: np.degrees(vn.core_angle_rad(alpha, lam)),
        "vane_angle_deg" + suffix: np.degrees(vn.vane_angle_rad(alpha, lam)),
        "core_angular_velocity_rad_s" + suffix: vn.core_angular_velocity_rad_s(alpha, lam, omega),
        "core_angular_acceleration_rad_s2" + suffix: vn.core_angular_acceleration_rad_s2(alpha, lam, omega),
        "slider_y_below_core_m" + suffix: vn.slider_height_below_core_m(alpha, r, lam),
        # one coordinate for the value and its derivatives: y_p = O3P, below the core axis (the source's)
        "slider_vy_below_core_m_s" + suffix: vn.slider_vertical_velocity_m_s(alpha, r, lam, omega),
        "slider_jy_below_core_m_s2" + suffix: vn.slider_vertical_acceleration_m_s2(alpha, r, lam, omega),
        # B'P = l - y_p, the rise above the lowest position (its derivatives are -v_yp, -j_yp)
        "slider_rise_above_lowest_m" + suffix: vn.slider_vertical_travel_m(alpha, r, lam),
        "slider_relative_m" + suffix: vn.slider_relative_position_m(alpha, r, lam),
        "slider_relative_velocity_m_s" + suffix: vn.slider_relative_velocity_m_s(alpha, r, lam, omega),
        "slider_relative_acceleration_m_s2" + suffix: vn.slider_relative_acceleration_m_s2(alpha, r, lam, omega),
    }


def _quantities(r, lam, omega) -> dict:
    """CSV column -> (value of alpha in rad, its derivative d/dalpha or None for a numerical one)."""
    return {
        "vane_angle_deg": (lambda a: np.degrees(vn.vane_angle_rad(a, lam)),
                           lambda a: np.degrees(vn.core_angular_velocity_rad_s(a, lam, omega)) / omega),
        "core_angular_velocity_rad_s": (lambda a: vn.core_angular_velocity_rad_s(a, lam, omega),
                                        lambda a: vn.core_angular_acceleration_rad_s2(a, lam, omega) / omega),
        "core_angular_acceleration_rad_s2": (lambda a: vn.core_angular_acceleration_rad_s2(a, lam, omega), None),
        "slider_y_below_core_m": (lambda a: vn.slider_height_below_core_m(a, r, lam),
                                  lambda a: vn.slider_vertical_velocity_m_s(a, r, lam, omega) / omega),
        "slider_vy_below_core_m_s": (lambda a: vn.slider_vertical_velocity_m_s(a, r, lam, omega),
                                     lambda a: vn.slider_vertical_acceleration_m_s2(a, r, lam, omega) / omega),
        "slider_jy_below_core_m_s2": (lambda a: vn.slider_vertical_acceleration_m_s2(a, r, lam, omega), None),
        "slider_relative_m": (lambda a: vn.slider_relative_position_m(a, r, lam),
                              lambda a: vn.slider_relative_velocity_m_s(a, r, lam, omega) / omega),
        "slider_relative_velocity_m_s": (lambda a: vn.slider_relative_velocity_m_s(a, r, lam, omega),
                                         lambda a: vn.slider_relative_acceleration_m_s2(a, r, lam, omega) / omega),
        "slider_relative_acceleration_m_s2": (lambda a: vn.slider_relative_acceleration_m_s2(a, r, lam, omega), None),
    }


def extremes(r, lam, omega) -> dict:
    """Largest and smallest value of each quantity over a revolution and the crank angles (deg) where
    they occur, by Brent's root search on the derivative (closed form, else a five-point difference),
    as the offset and planetary mechanisms find theirs; ties: the first angle."""
    out = {}
    for column, (fn, derivative) in _quantities(r, lam, omega).items():
        derivative = derivative or central_derivative(fn)
        entry = {}
        for kind in ("max", "min"):
            angle, value = periodic_extreme(fn, derivative, 2 * np.pi, kind)
            entry[kind], entry[f"{kind}_crank_angle_deg"] = value, float(np.degrees(angle))
        out[column] = entry
    return out


def _largest(entry: dict) -> float:
    return max(abs(entry["max"]), abs(entry["min"]))


def run(scene, inputs) -> StageOutput:
    engine = scene.engine
    params = options(scene, "mechanism", VaneParams)
    r, l_tail, omega = engine.crank_radius_m, engine.rod_length_m, engine.angular_velocity_rad_s
    lam = r / l_tail
    angle_deg = scene.crank_angles_deg
    angle_deg = angle_deg[angle_deg < 360.0]  # the motion repeats every revolution
    alpha = np.radians(angle_deg)

    xk, yk = vn.rocker_position_m(alpha, r)
    vxk, vyk = vn.rocker_velocity_m_s(alpha, r, omega)
    jxk, jyk = vn.rocker_acceleration_m_s2(alpha, r, omega)
    table = {"crank_angle_deg": angle_deg,
             "rocker_x_m": xk, "rocker_y_m": yk, "rocker_vx_m_s": vxk, "rocker_vy_m_s": vyk,
             "rocker_jx_m_s2": jxk, "rocker_jy_m_s2": jyk,
             "slider_x_m": xk, "slider_vx_m_s": vxk, "slider_jx_m_s2": jxk}
    table.update(_curves(alpha, r, lam, omega))
    table["slider_rotation_deg"] = -table["core_angle_deg"]  # relative to the tail: the mirror of beta
    compare = {"crank_angle_deg": angle_deg}
    for other in params.compare_rod_ratios:
        compare.update(_curves(alpha, r, other, omega, suffix=f"_lambda_{other:g}"))

    lam_grid = np.linspace(0.01, 0.99, 99)
    by_lambda = {
        "rod_ratio": lam_grid,
        "core_angle_max_deg": np.degrees(np.arcsin(lam_grid)),
        "slider_vertical_travel_max_over_tail": [vn.slider_vertical_travel_max_m(1.0, x) / (1.0 / x) for x in lam_grid],
        "slider_vertical_travel_max_over_crank": [vn.slider_vertical_travel_max_m(1.0, x) for x in lam_grid],
        "acceleration_zero_deg": [float(np.degrees(vn.slider_vertical_acceleration_zeros_rad(x)[0])) for x in lam_grid],
    }

    zeros = np.degrees(vn.slider_vertical_acceleration_zeros_rad(lam))
    # Independent check of the closed form: a root search on j_yp itself around each zero.
    found = [brentq(lambda a: float(vn.slider_vertical_acceleration_m_s2(a, r, lam, omega)),
                             np.radians(z) - 0.2, np.radians(z) + 0.2, xtol=1e-14) for z in zeros]
    zeros_check = float(np.max(np.abs(np.degrees(found) - zeros)))
    y_max = vn.slider_vertical_travel_max_m(r, lam)
    ext = extremes(r, lam, omega)
    results = {
        "crank_radius_m": r,
        "tail_length_m": l_tail,
        "rod_ratio": lam,
        "core_offset_m": params.core_offset,
        "angular_velocity_rad_s": omega,
        "core_angle_max_deg": float(np.degrees(vn.core_angle_max_rad(lam))),
        "vane_angle_max_deg": float(np.degrees(vn.vane_angle_max_rad(lam))),
        "rod_ratio_from_vane_angle": vn.rod_ratio_from_vane_angle(vn.vane_angle_max_rad(lam)),
        "slider_vertical_travel_max_m": y_max,
        "slider_vertical_travel_max_over_tail": y_max / l_tail,
        "slider_vertical_acceleration_zeros_deg": [float(z) for z in zeros],
        "slider_vertical_acceleration_zeros_check_deg": zeros_check,
        # extremes by root finding on the derivative (not grid maxima); y_p positive downwards
        "extremes": ext,
        "core_angular_velocity_max_rad_s": _largest(ext["core_angular_velocity_rad_s"]),
        "core_angular_acceleration_max_rad_s2": _largest(ext["core_angular_acceleration_rad_s2"]),
        "slider_vertical_velocity_max_m_s": _largest(ext["slider_vy_below_core_m_s"]),
        "slider_vertical_acceleration_max_m_s2": ext["slider_jy_below_core_m_s2"]["max"],
        "slider_vertical_acceleration_min_m_s2": ext["slider_jy_below_core_m_s2"]["min"],
        "slider_relative_travel_m": ext["slider_relative_m"]["max"] - ext["slider_relative_m"]["min"],
        "slider_relative_velocity_max_m_s": _largest(ext["slider_relative_velocity_m_s"]),
        "slider_relative_acceleration_max_m_s2": ext["slider_relative_acceleration_m_s2"]["max"],
        "slider_relative_acceleration_min_m_s2": ext["slider_relative_acceleration_m_s2"]["min"],
        "compare_rod_ratios": list(params.compare_rod_ratios),
        "working_cycle_deg": list(WORKING_CYCLE_DEG),
    }
    notes = [("vane.note_corrected", {}), ("vane.note_zeros", {"zero": float(zeros[0]), "check": zeros_check})]
    tables = {"vane": table, "by_lambda": by_lambda}
    if params.compare_rod_ratios:
        tables["compare"] = compare
    return StageOutput(data={}, results=results, tables=tables, notes=notes)


def _plot_compared(f, compare, lam, others, t, ax, key, scale=1.0, **style):
    """One column of the vane table over the crank angle, with the same column at each comparison
    rod ratio dashed beside it (``partial`` of the tables gives ``plot(ax, key, scale, **style)``)."""
    angle = f["crank_angle_deg"]
    ax.plot(angle, f[key] * scale, color="C0", label=f"λ = {t.number_g(lam, 4)}", **style)
    for i, other in enumerate(others):
        ax.plot(angle, compare[f"{key}_lambda_{other:g}"] * scale, color=f"C{i + 1}", ls="--", lw=1,
                label=f"λ = {t.number_g(other, 4)}")
    ax.axhline(0, color="0.3", lw=0.6)


def _vane_table(f, r, ctx) -> str:
    """The sampled table of the core, vane, rocker and slider motion, with its worked substitutions."""
    t = ctx.t
    mm = 1e3
    rows, labels = sample_rows(f["crank_angle_deg"], ctx.table_step_deg)
    g = f.take(rows)
    table = ctx.table([
        ("<i>α</i>, °", labels, 0),
        ("<i>β</i>, °", g["core_angle_deg"], 2),
        ("<i>γ</i>, °", g["vane_angle_deg"], 2),
        ("<i>ω</i><sub>c</sub>, " + t("unit.rad_s"), g["core_angular_velocity_rad_s"], 2),
        ("<i>ε</i><sub>c</sub>, " + t("unit.rad_s2"), g["core_angular_acceleration_rad_s2"], 0),
        ("<i>x</i><sub>k</sub> = <i>x</i><sub>p</sub>, " + t("unit.mm"), g["rocker_x_m"] * mm, 2),
        ("<i>y</i><sub>k</sub>, " + t("unit.mm"), g["rocker_y_m"] * mm, 2),
        ("<i>y</i><sub>p</sub>, " + t("unit.mm"), g["slider_y_below_core_m"] * mm, 2),
        ("<i>v</i><sub>yp</sub>, " + t("unit.m_s"), g["slider_vy_below_core_m_s"], 3),
        ("<i>j</i><sub>yp</sub>, " + t("unit.m_s2"), g["slider_jy_below_core_m_s2"], 0),
        ("<i>y</i><sub>po</sub>, " + t("unit.mm"), g["slider_relative_m"] * mm, 2),
    ], caption=t("vane.table_caption"), css_class="data wide", see="vane.see_table")
    return table + worked_vane(ctx, g, labels, r)


def _two_panels(plot, ctx, keys, axis_labels, caption_key, name, see) -> str:
    """An angle and its rate (or a rate and its derivative) over the crank angle, with the comparison rod ratios."""
    return ctx.figure(partial(_two_panels_plot, plot, keys, axis_labels, ctx.t), ctx.t(caption_key), name, see=see)


def _two_panels_plot(plot, keys, axis_labels, t):
    """Two columns of the vane table, one above the other, over the crank angle."""
    fig, axes = new_figure(16, 11, nrows=2, sharex=True)
    plot(axes[0], keys[0])
    axes[0].set_ylabel(t(axis_labels[0]))
    axes[0].legend(loc="upper right", fontsize=8)
    plot(axes[1], keys[1])
    axes[1].set_ylabel(t(axis_labels[1]))
    crank_angle_axis(axes[1], 360.0, t("axis.crank_angle"))
    return fig


def _rocker_figure(f, ctx) -> str:
    """The rocker joint's x and y position, velocity and acceleration over the crank angle."""
    return ctx.figure(partial(_rocker_plot, f, ctx.t), ctx.t("vane.rocker_caption"), "vane_rocker",
                      see="vane.see_rocker")


def _rocker_plot(f, t):
    """The rocker joint's x and y position, velocity and acceleration, one panel each."""
    mm = 1e3
    angle = f["crank_angle_deg"]
    fig, axes = new_figure(16, 15, nrows=3, sharex=True)
    for ax, (kx, ky), label in ((axes[0], ("rocker_x_m", "rocker_y_m"), "vane.axis_rocker_s"),
                                (axes[1], ("rocker_vx_m_s", "rocker_vy_m_s"), "vane.axis_rocker_v"),
                                (axes[2], ("rocker_jx_m_s2", "rocker_jy_m_s2"), "vane.axis_rocker_j")):
        scale = mm if kx.endswith("_m") else 1.0
        ax.plot(angle, f[kx] * scale, color="C0", label="x")
        ax.plot(angle, f[ky] * scale, color="C1", ls="--", label="y")
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_ylabel(t(label))
    axes[0].legend(loc="upper right", fontsize=8)
    crank_angle_axis(axes[2], 360.0, t("axis.crank_angle"))
    return fig


def _three_panels(plot, ctx, keys, axis_labels, legend_loc, caption_key, name, see, zeros=()) -> str:
    """Value, velocity and acceleration of one coordinate over the crank angle, with the
    comparison rod ratios; vertical marks at ``zeros`` on the two derivatives."""
    return ctx.figure(partial(_three_panels_plot, plot, keys, axis_labels, legend_loc, zeros, ctx.t),
                      ctx.t(caption_key), name, see=see)


def _three_panels_plot(plot, keys, axis_labels, legend_loc, zeros, t):
    """Three columns of the vane table (the first in mm), one above the other, marks at ``zeros`` below the first."""
    fig, axes = new_figure(16, 15, nrows=3, sharex=True)
    for i, (ax, key, label) in enumerate(zip(axes, keys, axis_labels, strict=True)):
        plot(ax, key, 1e3 if i == 0 else 1.0)
        ax.set_ylabel(t(label))
        if i == 0:
            ax.legend(loc=legend_loc, fontsize=8)
    for zero in zeros:
        for ax in axes[1:]:
            ax.axvline(zero, color="C3", lw=0.7, ls=":")
    crank_angle_axis(axes[2], 360.0, t("axis.crank_angle"))
    return fig


def _lambda_figure(by_lambda, lam, ctx) -> str:
    """How the rod ratio λ sets the largest core angle, the slider's largest travel and the angle where
    its acceleration vanishes; the scene's λ marked."""
    return ctx.figure(partial(_lambda_plot, by_lambda, lam, ctx.t), ctx.t("vane.lambda_caption"), "vane_lambda",
                      see="vane.see_lambda")


def _lambda_plot(by_lambda, lam, t):
    """The rod-ratio study's three curves side by side, the scene's λ marked."""
    fig, axes = new_figure(16, 6.5, ncols=3)
    x = by_lambda["rod_ratio"]
    axes[0].plot(x, by_lambda["core_angle_max_deg"], color="C0")
    axes[0].set_ylabel(t("vane.axis_beta_max"))
    axes[1].plot(x, by_lambda["slider_vertical_travel_max_over_tail"], color="C0", label="l = 1")
    axes[1].plot(x, by_lambda["slider_vertical_travel_max_over_crank"], color="C1", ls="--", label="r = 1")
    axes[1].set_ylabel(t("vane.axis_y_max"))
    axes[1].legend(loc="upper left", fontsize=8)
    axes[2].plot(x, by_lambda["acceleration_zero_deg"], color="C0")
    axes[2].set_ylabel(t("vane.axis_alpha_zero"))
    for ax in axes:
        ax.axvline(lam, color="C3", lw=0.7, ls=":")
        ax.set_xlabel("λ")
        ax.tick_params(labelsize=7)
    return fig


def render(output: StageOutput, ctx) -> str:
    """The section: the sampled table, the angle, core, rocker, slider and relative-slider figures,
    the rod-ratio study and the conclusion."""
    t = ctx.t
    f = output.tables.arrays("vane")
    r = output.results
    lam = r["rod_ratio"]
    mm = 1e3
    plot = partial(_plot_compared, f, (output.tables.arrays("compare") if "compare" in output.tables else None), lam,
                   r["compare_rod_ratios"], t)

    table = _vane_table(f, r, ctx)
    figure_angles = _two_panels(plot, ctx, ("core_angle_deg", "vane_angle_deg"), ("vane.axis_beta", "vane.axis_gamma"),
                                "vane.angles_caption", "vane_angles", "vane.see_angles")
    figure_core = _two_panels(plot, ctx, ("core_angular_velocity_rad_s", "core_angular_acceleration_rad_s2"),
                              ("vane.axis_omega_c", "vane.axis_epsilon_c"), "vane.core_caption", "vane_core",
                              "vane.see_core")
    figure_rocker = _rocker_figure(f, ctx)
    figure_slider = _three_panels(
        plot, ctx, ("slider_y_below_core_m", "slider_vy_below_core_m_s", "slider_jy_below_core_m_s2"),
        ("vane.axis_slider_y", "vane.axis_slider_v", "vane.axis_slider_j"), "upper right", "vane.slider_caption",
        "vane_slider", "vane.see_slider", r["slider_vertical_acceleration_zeros_deg"])
    figure_relative = _three_panels(
        plot, ctx, ("slider_relative_m", "slider_relative_velocity_m_s", "slider_relative_acceleration_m_s2"),
        ("vane.axis_relative_y", "vane.axis_relative_v", "vane.axis_relative_j"), "upper left",
        "vane.relative_caption", "vane_relative", "vane.see_relative")
    figure_lambda = _lambda_figure(output.tables.arrays("by_lambda"), lam, ctx)

    zeros = r["slider_vertical_acceleration_zeros_deg"]
    ctx.conclude(t("vane.conclusion", lam=ctx.num(lam, 4), beta_max=ctx.t.number_g(r["core_angle_max_deg"], 4),
                   gamma_max=ctx.t.number_g(r["vane_angle_max_deg"], 4), zero=ctx.num(zeros[0], 5),
                   y_max=ctx.num(r["slider_vertical_travel_max_m"] * mm, 5),
                   y_rel=ctx.num(r["slider_vertical_travel_max_over_tail"], 4)))
    return ctx.render_template("sections/vane.html.j2", r=r, zeros=zeros, table=table, figure_angles=figure_angles,
                               figure_core=figure_core, figure_rocker=figure_rocker, figure_slider=figure_slider,
                               figure_relative=figure_relative, figure_lambda=figure_lambda)


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


VANE_STAGE = Stage(
    template_dir=TEMPLATES,
    name="vane",
    title_key="vane.title",
    requires=(),
    provides=(),
    applies=applies,
    run=run,
    render=render,
    figures=("vane_angles", "vane_core", "vane_rocker", "vane_slider", "vane_relative", "vane_lambda"),
    tables=("vane", "compare", "by_lambda"),
    references=("klementev2023",),
    symbols=SYMBOLS,
)
