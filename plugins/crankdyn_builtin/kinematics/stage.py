"""Kinematics of the central crank-slider (Poda 2007 §2; Tristen et al. for the extremes)."""

from __future__ import annotations

import functools
from functools import partial
from pathlib import Path

import numpy as np

from crankdyn.contracts import KINEMATICS, PistonMotion
from crankdyn.physics import kinematics as kin
from crankdyn.plugin_types import AnswerColumn, Stage, StageOutput
from crankdyn.report.context import sample_rows
from crankdyn.report.figures import crank_angle_axis, new_figure, twin_axes
from crankdyn.report.typeset import symbol_html
from crankdyn.report.worked import WorkedBlock, WorkedStep, printed, worked_markup, worked_row

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"


def applies(scene) -> str | None:
    if scene.engine.mechanism != "crank_slider":
        return f"the scene's mechanism is {scene.engine.mechanism!r}, not the central crank-slider"
    return None


def _piston_both_ways(alpha, radius, ratio, omega) -> tuple[dict, dict]:
    """Piston displacement s (m), velocity v (m/s) and acceleration j (m/s²) at crank angles
    ``alpha`` (rad): exact, and by the two-term series (textbook eqs. for s, v, j)."""
    exact = {
        "s": kin.piston_displacement_exact_m(alpha, radius, ratio),
        "v": kin.piston_velocity_exact_m_s(alpha, radius, ratio, omega),
        "j": kin.piston_acceleration_exact_m_s2(alpha, radius, ratio, omega),
    }
    approx = {
        "s": kin.piston_displacement_approx_m(alpha, radius, ratio),
        "v": kin.piston_velocity_approx_m_s(alpha, radius, ratio, omega),
        "j": kin.piston_acceleration_approx_m_s2(alpha, radius, ratio, omega),
    }
    return exact, approx


def _rod_centre_of_mass(alpha, radius, ratio, omega, distance_m) -> tuple[dict, dict]:
    """(table columns, results) of the rod's centre of mass, ``distance_m`` from the big end:
    position (m), velocity (m/s) and acceleration (m/s²) in the cylinder's x, z axes."""
    x, z = kin.rod_point_position_m(alpha, radius, ratio, distance_m)
    vx, vz = kin.rod_point_velocity_m_s(alpha, radius, ratio, distance_m, omega)
    ax, az = kin.rod_point_acceleration_m_s2(alpha, radius, ratio, distance_m, omega)
    columns = {"rod_cm_x_m": x, "rod_cm_z_m": z, "rod_cm_velocity_x_m_s": vx, "rod_cm_velocity_z_m_s": vz,
               "rod_cm_acceleration_x_m_s2": ax, "rod_cm_acceleration_z_m_s2": az}
    return columns, {"rod_cm_from_big_end_m": distance_m,
                     "rod_cm_acceleration_max_m_s2": float(np.max(np.hypot(ax, az)))}


def _displacement_at_deg(displacement, radius_m: float, ratio: float, crank_angle_deg):
    """Piston displacement (m) at any crank angle (deg) by the stage's chosen formula; a
    module-level function (not a lambda), so that the output can be pickled to another process."""
    return displacement(np.radians(crank_angle_deg), radius_m, ratio)


def run(scene, inputs) -> StageOutput:
    engine = scene.engine
    angle_deg = scene.crank_angles_deg
    alpha = np.radians(angle_deg)
    radius, ratio, omega = engine.crank_radius_m, engine.rod_ratio_value, engine.angular_velocity_rad_s

    exact, approx = _piston_both_ways(alpha, radius, ratio, omega)
    chosen = exact if scene.analysis.kinematics == "exact" else approx
    displacement = (kin.piston_displacement_exact_m if scene.analysis.kinematics == "exact"
                    else kin.piston_displacement_approx_m)
    beta = kin.rod_angle_rad(alpha, ratio)
    rod_omega = kin.rod_angular_velocity_rad_s(alpha, ratio, omega)
    rod_epsilon = kin.rod_angular_acceleration_rad_s2(alpha, ratio, omega)

    v_max, v_max_angle = kin.max_piston_velocity_exact(radius, ratio, omega)
    j_min, j_min_angle = kin.min_piston_acceleration_exact(radius, ratio, omega)
    j_min_tb, j_min_tb_angle = kin.min_piston_acceleration_approx(radius, ratio, omega)

    table = {
        "crank_angle_deg": angle_deg,
        "piston_displacement_m": chosen["s"],
        "piston_velocity_m_s": chosen["v"],
        "piston_acceleration_m_s2": chosen["j"],
        "piston_displacement_exact_m": exact["s"],
        "piston_displacement_two_term_m": approx["s"],
        "piston_acceleration_exact_m_s2": exact["j"],
        "piston_acceleration_two_term_m_s2": approx["j"],
        "rod_angle_deg": np.degrees(beta),
        "rod_angular_velocity_rad_s": rod_omega,
        "rod_angular_acceleration_rad_s2": rod_epsilon,
    }
    results = {
        "crank_radius_m": radius,
        "rod_length_m": engine.rod_length_m,
        "rod_ratio": ratio,
        "angular_velocity_rad_s": omega,
        "method": scene.analysis.kinematics,
        "mean_piston_speed_m_s": kin.mean_piston_speed_m_s(radius, omega),
        "v_max_m_s": v_max,
        "v_max_crank_angle_deg": float(np.degrees(v_max_angle)),
        "v_max_approx_m_s": kin.max_piston_velocity_approx_m_s(radius, ratio, omega),
        "j_max_m_s2": kin.max_piston_acceleration_m_s2(radius, ratio, omega),
        "j_min_m_s2": j_min,
        "j_min_crank_angle_deg": float(np.degrees(j_min_angle)),
        "j_min_textbook_m_s2": j_min_tb,
        "j_min_textbook_crank_angle_deg": float(np.degrees(j_min_tb_angle)),
        "rod_angle_max_deg": float(np.degrees(np.arcsin(ratio))),
        "rod_angular_velocity_max_rad_s": float(np.max(np.abs(rod_omega))),
        "rod_angular_acceleration_max_rad_s2": float(np.max(np.abs(rod_epsilon))),
        "two_term_displacement_error_max_m": float(np.max(np.abs(approx["s"] - exact["s"]))),
        "two_term_acceleration_error_max_m_s2": float(np.max(np.abs(approx["j"] - exact["j"]))),
    }
    if scene.masses is not None:
        columns, rod_cm = _rod_centre_of_mass(alpha, radius, ratio, omega, scene.rod_cm_from_big_end_m)
        table.update(columns)
        results.update(rod_cm)

    motion = PistonMotion(
        crank_angle_deg=angle_deg,
        piston_displacement_m=chosen["s"],
        piston_velocity_m_s=chosen["v"],
        piston_acceleration_m_s2=chosen["j"],
        rod_angle_rad=beta,
        crank_radius_m=radius,
        angular_velocity_rad_s=omega,
        method=scene.analysis.kinematics,
        # the rod's rates in closed form (rod_dynamics would otherwise differentiate the angle spectrally)
        extra={"rod_ratio": ratio, "rod_length_m": engine.rod_length_m,
               "rod_angular_velocity_rad_s": rod_omega, "rod_angular_acceleration_rad_s2": rod_epsilon},
        displacement_at=functools.partial(_displacement_at_deg, displacement, radius, ratio),
    )
    notes = [("kinematics.note_method_" + scene.analysis.kinematics, {}),
             ("kinematics.note_two_term_error", {"ds_mm": results["two_term_displacement_error_max_m"] * 1e3,
                                                  "dj": results["two_term_acceleration_error_max_m_s2"]})]
    return StageOutput(data={KINEMATICS: motion}, results=results, tables={"kinematics": table},
                       notes=notes)


@functools.lru_cache(maxsize=4096)
def _extreme_shapes(ratio: float) -> tuple[float, float, float]:
    """(crank angle of v_max, j_min / (R omega^2), crank angle of j_min) of the exact motion, in
    rad: they depend on lambda alone, so many points of a sweep share one root search."""
    _, v_angle = kin.max_piston_velocity_exact(1.0, ratio, 1.0)
    j_shape, j_angle = kin.min_piston_acceleration_exact(1.0, ratio, 1.0)
    return v_angle, j_shape, j_angle


def _uniform(scenes) -> bool:
    """Whether ``scenes`` share the angle grid, the kinematics form and having masses or not."""
    first = scenes[0]
    return all(s.analysis.kinematics == first.analysis.kinematics
               and (s.masses is None) == (first.masses is None)
               and np.array_equal(s.crank_angles_deg, first.crank_angles_deg) for s in scenes)


def run_many(scenes, inputs) -> list[StageOutput]:
    """``run`` over many scenes at once (a sweep's points): the curves as arrays over points x
    angles, the extremes' angles once per rod ratio; the same data and results as ``run``, no
    tables or notes (a sweep renders nothing)."""
    if not _uniform(scenes):
        return [run(scene, given) for scene, given in zip(scenes, inputs, strict=True)]
    first = scenes[0]
    angle_deg = first.crank_angles_deg
    alpha = np.radians(angle_deg)
    radii = [s.engine.crank_radius_m for s in scenes]
    ratios = [s.engine.rod_ratio_value for s in scenes]
    omegas = [s.engine.angular_velocity_rad_s for s in scenes]
    radius, ratio, omega = (np.asarray(v, dtype=float)[:, None] for v in (radii, ratios, omegas))
    exact, approx = _piston_both_ways(alpha, radius, ratio, omega)
    method = first.analysis.kinematics
    chosen = exact if method == "exact" else approx
    displacement = (kin.piston_displacement_exact_m if method == "exact"
                    else kin.piston_displacement_approx_m)
    beta = kin.rod_angle_rad(alpha, ratio)
    rod_omega = kin.rod_angular_velocity_rad_s(alpha, ratio, omega)
    rod_epsilon = kin.rod_angular_acceleration_rad_s2(alpha, ratio, omega)
    shapes = [_extreme_shapes(float(r)) for r in ratios]
    v_angles = np.asarray([v for v, _, _ in shapes])
    v_max = kin.piston_velocity_exact_m_s(v_angles, radius[:, 0], ratio[:, 0], omega[:, 0])
    rows = {
        "rod_angular_velocity_max_rad_s": np.max(np.abs(rod_omega), axis=1),
        "rod_angular_acceleration_max_rad_s2": np.max(np.abs(rod_epsilon), axis=1),
        "two_term_displacement_error_max_m": np.max(np.abs(approx["s"] - exact["s"]), axis=1),
        "two_term_acceleration_error_max_m_s2": np.max(np.abs(approx["j"] - exact["j"]), axis=1),
    }
    if first.masses is not None:
        distance = np.asarray([s.rod_cm_from_big_end_m for s in scenes], dtype=float)[:, None]
        ax, az = kin.rod_point_acceleration_m_s2(alpha, radius, ratio, distance, omega)
        rows["rod_cm_from_big_end_m"] = distance[:, 0]
        rows["rod_cm_acceleration_max_m_s2"] = np.max(np.hypot(ax, az), axis=1)
    outputs = []
    for k, scene in enumerate(scenes):
        engine, r, lam, w = scene.engine, radii[k], ratios[k], omegas[k]
        v_angle, j_shape, j_angle = shapes[k]
        j_min_tb, j_min_tb_angle = kin.min_piston_acceleration_approx(r, lam, w)
        results = {
            "crank_radius_m": r, "rod_length_m": engine.rod_length_m, "rod_ratio": lam,
            "angular_velocity_rad_s": w, "method": method,
            "mean_piston_speed_m_s": kin.mean_piston_speed_m_s(r, w),
            "v_max_m_s": float(v_max[k]), "v_max_crank_angle_deg": float(np.degrees(v_angle)),
            "v_max_approx_m_s": kin.max_piston_velocity_approx_m_s(r, lam, w),
            "j_max_m_s2": kin.max_piston_acceleration_m_s2(r, lam, w),
            "j_min_m_s2": float(r) * float(w) ** 2 * j_shape,
            "j_min_crank_angle_deg": float(np.degrees(j_angle)),
            "j_min_textbook_m_s2": j_min_tb,
            "j_min_textbook_crank_angle_deg": float(np.degrees(j_min_tb_angle)),
            "rod_angle_max_deg": float(np.degrees(np.arcsin(lam))),
            **{name: float(values[k]) for name, values in rows.items()},
        }
        motion = PistonMotion(
            crank_angle_deg=angle_deg, piston_displacement_m=chosen["s"][k],
            piston_velocity_m_s=chosen["v"][k], piston_acceleration_m_s2=chosen["j"][k],
            rod_angle_rad=beta[k], crank_radius_m=r,
            angular_velocity_rad_s=w, method=method,
            extra={"rod_ratio": lam, "rod_length_m": engine.rod_length_m,
                   "rod_angular_velocity_rad_s": rod_omega[k],
                   "rod_angular_acceleration_rad_s2": rod_epsilon[k]},
            displacement_at=functools.partial(_displacement_at_deg, displacement, r, lam),
        )
        outputs.append(StageOutput(data={KINEMATICS: motion}, results=results))
    return outputs


def render(output: StageOutput, ctx) -> str:
    frame = output.tables.arrays("kinematics")
    r = output.results
    t = ctx.t
    # The motion repeats every revolution, so one revolution is tabulated.
    rows, labels = sample_rows(frame["crank_angle_deg"], ctx.table_step_deg, span_deg=360.0)
    f = frame.take(rows)
    table = ctx.table([
        ("<i>α</i>, °", labels, 0),
        ("<i>s</i><sub>p</sub>, " + t("unit.mm"), f["piston_displacement_m"] * 1e3, 2),
        ("<i>v</i><sub>p</sub>, " + t("unit.m_s"), f["piston_velocity_m_s"], 2),
        ("<i>j</i><sub>p</sub>, " + t("unit.m_s2"), f["piston_acceleration_m_s2"], 0),
        ("<i>β</i>, °", f["rod_angle_deg"], 2),
        ("<i>ω</i><sub>r</sub>, " + t("unit.rad_s"), f["rod_angular_velocity_rad_s"], 1),
        ("<i>ε</i><sub>r</sub>, " + t("unit.rad_s2"), f["rod_angular_acceleration_rad_s2"], 0),
    ], caption=t("kinematics.table_caption"), see="kinematics.see_table")
    worked = _worked(ctx, f, labels, r) if r["method"] == "exact" else None

    figure_main = ctx.figure(partial(_piston_figure, frame, t), t("kinematics.figure_caption"), "piston",
                             see="kinematics.see_figure")
    figure_rod = ctx.figure(partial(_rod_figure, frame, t), t("kinematics.rod_figure_caption"), "rod",
                            see="kinematics.see_rod_figure")
    figure_cm = None
    if "rod_cm_x_m" in frame:
        figure_cm = ctx.figure(partial(_rod_cm_figure, frame, t), t("kinematics.cm_figure_caption"), "rod_cm",
                               see="kinematics.see_cm")

    ctx.conclude(t("kinematics.conclusion", v_max=ctx.num(r["v_max_m_s"]), v_angle=ctx.angle_text(r["v_max_crank_angle_deg"]),
                   v_mean=ctx.num(r["mean_piston_speed_m_s"]), j_max=ctx.num(r["j_max_m_s2"]),
                   j_min=ctx.num(r["j_min_m_s2"]), j_angle=ctx.angle_text(r["j_min_crank_angle_deg"])))
    return ctx.render_template("sections/kinematics.html.j2", r=r, table=table, figure_main=figure_main,
                               figure_rod=figure_rod, figure_cm=figure_cm, worked=worked)


def _piston_figure(frame, t):
    """The piston's s, v, j over one revolution, and the two-term j's difference from the exact."""
    angle = frame["crank_angle_deg"]
    fig, axes = new_figure(16, 19, nrows=4, sharex=True, gridspec_kw={"height_ratios": [1, 1, 1, 0.6]})
    # one colour for the report's curves in every panel, the two-term acceleration dashed; one
    # legend above the top panel for all; the bottom panel shows the two-term acceleration's
    # difference from the exact one (on the scale of j itself the two curves cannot be told apart)
    axes[0].plot(angle, frame["piston_displacement_m"] * 1e3, color="C0")
    axes[0].set_ylabel(t("kinematics.axis_s"))
    axes[1].plot(angle, frame["piston_velocity_m_s"], color="C0")
    axes[1].set_ylabel(t("kinematics.axis_v"))
    exact = axes[2].plot(angle, frame["piston_acceleration_m_s2"], color="C0")[0]
    two_term = axes[2].plot(angle, frame["piston_acceleration_two_term_m_s2"], color="C3", ls="--", lw=1)[0]
    axes[2].set_ylabel(t("kinematics.axis_j"))
    axes[3].plot(angle, frame["piston_acceleration_two_term_m_s2"] - frame["piston_acceleration_m_s2"],
                 color="C3", ls="--", lw=1)
    axes[3].set_ylabel(t("kinematics.axis_dj"))
    axes[0].legend([exact, two_term], [t("kinematics.exact"), t("kinematics.two_term_j")], loc="lower right",
                   bbox_to_anchor=(1.0, 1.0), ncol=2, frameon=False, fontsize=8, borderaxespad=0.2)
    # The motion repeats every revolution; one revolution is the textbook's fig. 3.
    crank_angle_axis(axes[3], 360.0, t("axis.crank_angle"))
    for ax in axes:
        ax.axhline(0, color="0.3", lw=0.6)
    return fig


def _rod_figure(frame, t):
    """The rod's angle, angular velocity and angular acceleration over one revolution."""
    angle = frame["crank_angle_deg"]
    fig, axes = new_figure(16, 10, nrows=2, sharex=True)
    axes[0].plot(angle, frame["rod_angle_deg"], color="C4")
    axes[0].set_ylabel(t("kinematics.axis_beta"))
    axes[1].plot(angle, frame["rod_angular_velocity_rad_s"], color="C5", label="ω")
    ax2 = twin_axes(axes[1])
    ax2.plot(angle, frame["rod_angular_acceleration_rad_s2"], color="C6", ls="--", label="ε")
    axes[1].set_ylabel(t("kinematics.axis_rod_omega"))
    ax2.set_ylabel(t("kinematics.axis_rod_epsilon"))
    crank_angle_axis(axes[1], 360.0, t("axis.crank_angle"))
    return fig


def _rod_cm_figure(frame, t):
    """The path of the rod's centre of mass."""
    fig, ax = new_figure(9, 9)
    ax.plot(frame["rod_cm_x_m"] * 1e3, frame["rod_cm_z_m"] * 1e3, color="C0")
    ax.set_aspect("equal")
    ax.set_xlabel(t("kinematics.axis_cm_x"))
    ax.set_ylabel(t("kinematics.axis_cm_z"))
    return fig


def _worked(ctx, rows, labels, r):
    """Displacement, velocity and acceleration of the piston with the numbers of one table row."""
    t, lang = ctx.t, ctx.t.language
    i = worked_row(labels, ctx.worked_angle_deg)
    alpha, row = float(labels[i]), rows.row(i)
    a = ctx.angle_text(alpha)
    r_txt, r_m = printed(t, r["crank_radius_m"])
    l_txt, lam = printed(t, r["rod_ratio"])
    w_txt, omega = printed(t, r["angular_velocity_rad_s"], 5)
    b_txt, beta = printed(t, float(row["rod_angle_deg"]))
    inputs = {"R_m": r_m, "lambda": lam, "omega": omega, "alpha_deg": alpha, "beta_deg": beta}
    steps = [
        WorkedStep("piston_displacement", symbol_html("piston_displacement", lang),
                   "<i>R</i>[(1 − cos <i>α</i>) + (1 − cos <i>β</i>)/<i>λ</i>]",
                   f"{r_txt}·[(1 − cos {a}°) + (1 − cos {b_txt}°)/{l_txt}]·10³",
                   float(row["piston_displacement_m"]) * 1e3, 2, t("unit.mm"), inputs),
        WorkedStep("piston_velocity", symbol_html("piston_velocity", lang),
                   "<i>Rω</i> sin(<i>α</i> + <i>β</i>)/cos <i>β</i>",
                   f"{r_txt}·{w_txt}·sin({a}° + {b_txt}°)/cos {b_txt}°",
                   float(row["piston_velocity_m_s"]), 2, t("unit.m_s"), inputs),
        WorkedStep("piston_acceleration", symbol_html("piston_acceleration", lang),
                   "<i>Rω</i><sup>2</sup>[cos(<i>α</i> + <i>β</i>)/cos <i>β</i> + <i>λ</i> cos<sup>2</sup><i>α</i>/cos<sup>3</sup><i>β</i>]",
                   f"{r_txt}·{w_txt}<sup>2</sup>·[cos({a}° + {b_txt}°)/cos {b_txt}° + {l_txt}·cos<sup>2</sup> {a}°/cos<sup>3</sup> {b_txt}°]",
                   float(row["piston_acceleration_m_s2"]), 0, t("unit.m_s2"), inputs),
    ]
    return worked_markup(ctx, WorkedBlock("kinematics", ctx.last_table_number, alpha, steps))


KINEMATICS_STAGE = Stage(
    template_dir=TEMPLATES,
    name="kinematics",
    title_key="kinematics.title",
    requires=(),
    provides=(KINEMATICS,),
    applies=applies,
    run=run,
    run_many=run_many,
    render=render,
    figures=("piston", "rod", "rod_cm"),
    tables=("kinematics",),
    references=("poda2007", "tristen", "artobolevsky1988", "kolchin2002"),
    answer_columns=(
        AnswerColumn("v_max_m_s", "v_max_m_s", "m/s", label_key="kinematics.answer.v_max_m_s"),
        AnswerColumn("v_max_crank_angle_deg", "v_max_crank_angle_deg", "°", label_key="kinematics.answer.v_max_crank_angle_deg"),
        AnswerColumn("v_mean_m_s", "mean_piston_speed_m_s", "m/s", label_key="kinematics.answer.v_mean_m_s"),
        AnswerColumn("j_max_m_s2", "j_max_m_s2", "m/s²", label_key="kinematics.answer.j_max_m_s2"),
        AnswerColumn("j_min_m_s2", "j_min_m_s2", "m/s²", label_key="kinematics.answer.j_min_m_s2"),
        AnswerColumn("j_min_crank_angle_deg", "j_min_crank_angle_deg", "°", label_key="kinematics.answer.j_min_crank_angle_deg"),
    ),
)
