"""The flywheel by the energy method: excess work, cyclic irregularity, inertia, rim."""

from __future__ import annotations

import math
from functools import partial
from pathlib import Path

import numpy as np
from markupsafe import Markup
from pydantic import BaseModel, ConfigDict, model_validator

from crankdyn.contracts import BAY_LOADS, ENGINE_TORQUE, FLYWHEEL, FlywheelDesign
from crankdyn.errors import Problem, SceneError
from crankdyn.physics import flywheel as fw
from crankdyn.physics.extrema import first_argmax, first_argmin
from crankdyn.plugin_types import Stage, StageOutput
from crankdyn.report.figures import crank_angle_axis, new_figure
from crankdyn.scene import number as _number
from crankdyn.scene import options
from crankdyn.scene import quantity as _quantity
from crankdyn.scene_inputs import crank_train
from crankdyn_builtin.flywheel.worked import irregularity_is_a_result, worked_flywheel

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

#: Above this irregularity the energy method (a first-order expansion in delta) is refused.
MAX_ENERGY_METHOD_IRREGULARITY = 0.5
#: The irregularity suggested when a chosen flywheel is refused as too small.
SUGGESTED_IRREGULARITY = 0.2


class FlywheelOptions(BaseModel):
    """The [flywheel] table."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    required_irregularity: _number(gt=0, le=0.2) | None = None
    inertia: _quantity("moment_of_inertia", gt=0, le=1e5, unit="kg*m^2") | None = None
    engine_inertia: _quantity("moment_of_inertia", ge=0, le=1e5, unit="kg*m^2") = "0 kg*m^2"
    rim_mean_diameter: _quantity("length", gt=0, le=10.0, unit="mm", scale=1e-3) | None = None
    rim_width: _quantity("length", gt=0, le=5.0, unit="mm", scale=1e-3) | None = None
    rim_density: _quantity("density", gt=0, le=25000, unit="kg/m^3") = "7200 kg/m^3"
    rim_fraction: _number(gt=0, le=1) = 1.0
    max_rim_speed: _quantity("velocity", gt=0, le=1000, unit="m/s") | None = None

    @model_validator(mode="after")
    def _something_to_do(self) -> FlywheelOptions:
        if self.required_irregularity is None and self.inertia is None:
            raise ValueError("give required_irregularity (delta, e.g. 0.01, to design the flywheel) "
                             "and/or inertia (a chosen flywheel, e.g. '0.12 kg*m^2')")
        if self.rim_width is not None and self.rim_mean_diameter is None:
            raise ValueError("rim_width needs rim_mean_diameter")
        return self


def applies(scene) -> str | None:
    if "flywheel" not in scene.plugin_tables():
        return "the scene has no [flywheel] table"
    if scene.masses is None:
        return "the scene has no [masses]"
    return None


def _rim(opts, flywheel_inertia_kg_m2: float, omega_rad_s: float) -> dict:
    """The flywheel's rim (its ``rim_fraction`` of the flywheel's inertia) at the scene's mean
    diameter: dimensions, mass, rim speed and hoop stress (SI units, keys name them)."""
    rim_inertia = flywheel_inertia_kg_m2 * opts.rim_fraction
    try:
        rim = fw.rim_design(rim_inertia, opts.rim_mean_diameter, opts.rim_density, opts.rim_width)
    except ValueError as exc:
        raise SceneError(Problem("flywheel.rim_mean_diameter", f"{opts.rim_mean_diameter * 1e3:g} mm",
                                 f"too small for the flywheel: {exc}; choose a larger mean diameter")) from None
    speed = omega_rad_s * rim.outer_diameter_m / 2
    return {
        "inertia_kg_m2": rim.inertia_kg_m2,
        "fraction": opts.rim_fraction,
        "mean_diameter_m": rim.mean_diameter_m,
        "outer_diameter_m": rim.outer_diameter_m,
        "inner_diameter_m": rim.inner_diameter_m,
        "width_m": rim.width_m,
        "thickness_m": rim.thickness_m,
        "square_section": opts.rim_width is None,
        "mass_kg": rim.mass_kg,
        "thin_rim_mass_kg": rim.thin_rim_mass_kg,
        "density_kg_m3": opts.rim_density,
        "speed_m_s": speed,
        "hoop_stress_Pa": fw.rim_hoop_stress_Pa(opts.rim_density, speed),
        "max_speed_m_s": opts.max_rim_speed,
        "speed_ok": None if opts.max_rim_speed is None else bool(speed <= opts.max_rim_speed),
    }


def run(scene, inputs) -> StageOutput:
    torque, bays = inputs[ENGINE_TORQUE], inputs[BAY_LOADS]
    opts = options(scene, "flywheel", FlywheelOptions)
    omega = torque.angular_velocity_rad_s
    alpha = np.radians(torque.crank_angle_deg)
    excess = fw.excess_work(alpha, torque.torque_Nm)
    train = crank_train(scene, bays)
    mechanism = train.series().mean_kg_m2
    own = mechanism + opts.engine_inertia

    required_total = required_flywheel = None
    if opts.required_irregularity is not None:
        required_total = fw.required_inertia_kg_m2(excess.excess_work_J, opts.required_irregularity, omega)
        required_flywheel = max(required_total - own, 0.0)
    flywheel = opts.inertia if opts.inertia is not None else required_flywheel
    total = own + flywheel
    irregularity = fw.cyclic_irregularity(excess.excess_work_J, total, omega)
    if irregularity > MAX_ENERGY_METHOD_IRREGULARITY:
        needed = max(fw.required_inertia_kg_m2(excess.excess_work_J, SUGGESTED_IRREGULARITY, omega) - own, 0.0)
        raise SceneError(Problem("flywheel.inertia", f"{flywheel:.4g} kg*m^2",
                                 f"too small: with the engine's own {own:.4g} kg*m^2 the speed would swing by "
                                 f"delta = {irregularity:.3g} of its mean every cycle (the crankshaft nearly stops), "
                                 f"where neither the energy method nor the torque diagram computed at constant speed "
                                 f"holds; a flywheel of at least {needed:.3g} kg*m^2 gives delta = "
                                 f"{SUGGESTED_IRREGULARITY:g}"))

    results: dict = {
        "angular_velocity_rad_s": omega,
        "mean_torque_Nm": excess.mean_torque_Nm,
        "excess_work_J": excess.excess_work_J,
        "excess_work_max_crank_angle_deg": float(torque.crank_angle_deg[excess.max_index]),
        "excess_work_min_crank_angle_deg": float(torque.crank_angle_deg[excess.min_index]),
        "excess_work_relative": excess.excess_work_J / (excess.mean_torque_Nm * 2 * math.pi * torque.strokes / 2)
        if excess.mean_torque_Nm > 0 else None,
        "mechanism_inertia_mean_kg_m2": mechanism,
        "engine_inertia_kg_m2": opts.engine_inertia,
        "own_inertia_kg_m2": own,
        "required_irregularity": opts.required_irregularity,
        "required_total_inertia_kg_m2": required_total,
        "required_flywheel_inertia_kg_m2": required_flywheel,
        "flywheel_given": opts.inertia is not None,
        "flywheel_inertia_kg_m2": flywheel,
        "total_inertia_kg_m2": total,
        "irregularity": irregularity,
        "flywheel_share": flywheel / total,
        "rim": None,
    }
    notes = []
    if required_flywheel == 0.0 and opts.inertia is None:
        notes.append(("flywheel.note_no_flywheel", {"own": own}))
    if train.articulated:
        notes.append(("flywheel.note_articulated", {}))

    if opts.rim_mean_diameter is not None and flywheel > 0:
        results["rim"] = _rim(opts, flywheel, omega)

    frame = {"crank_angle_deg": torque.crank_angle_deg, "torque_Nm": torque.torque_Nm,
                          "excess_work_J": excess.cumulative_J}
    design = FlywheelDesign(flywheel_inertia_kg_m2=flywheel, engine_inertia_kg_m2=opts.engine_inertia,
                            mechanism_inertia_mean_kg_m2=mechanism, excess_work_J=excess.excess_work_J,
                            irregularity=irregularity, required_irregularity=opts.required_irregularity,
                            required_flywheel_inertia_kg_m2=required_flywheel)
    return StageOutput(data={FLYWHEEL: design}, results=results, tables={"flywheel": frame}, notes=notes)


def render(output: StageOutput, ctx) -> str:
    t = ctx.t
    r = output.results
    f = output.tables.arrays("flywheel")
    figure_work = ctx.figure(partial(_work_figure, f, r["mean_torque_Nm"], ctx.cycle_deg, t),
                             t("flywheel.work_caption"), "excess_work", see="flywheel.see_work")

    rows = [(t("flywheel.row_excess_work"), "Δ<i>L</i>", r["excess_work_J"], t("unit.J")),
            (t("flywheel.row_mechanism"), "<i>J</i><sub>m</sub>", r["mechanism_inertia_mean_kg_m2"],
             t("flywheel.unit_kg_m2")),
            (t("flywheel.row_engine"), "<i>J</i><sub>e</sub>", r["engine_inertia_kg_m2"], t("flywheel.unit_kg_m2"))]
    if r["required_irregularity"] is not None:
        # a given value, as the task's data table prints it (0,01, not 0,01000)
        rows += [(t("flywheel.row_required_delta"), "[<i>δ</i>]", t.number_g(r["required_irregularity"], 6), "—"),
                 (t("flywheel.row_required_total"), "<i>J</i><sub>0</sub>", r["required_total_inertia_kg_m2"],
                  t("flywheel.unit_kg_m2")),
                 (t("flywheel.row_required_flywheel"), "<i>J</i><sub>f</sub>", r["required_flywheel_inertia_kg_m2"],
                  t("flywheel.unit_kg_m2"))]
    if r["flywheel_given"]:
        rows.append((t("flywheel.row_given_flywheel"), "<i>J</i><sub>f</sub>", r["flywheel_inertia_kg_m2"],
                     t("flywheel.unit_kg_m2")))
    if irregularity_is_a_result(r):
        rows.append((t("flywheel.row_delta"), "<i>δ</i>", r["irregularity"], "—"))
    rim = r["rim"]
    if rim is not None:
        rows += [(t("flywheel.row_rim_mean_diameter"), "<i>D</i><sub>m</sub>", rim["mean_diameter_m"] * 1e3,
                  t("unit.mm")),
                 (t("flywheel.row_rim_thin_mass"), "<i>m</i><sub>rim</sub> = 4<i>J</i><sub>rim</sub>/<i>D</i><sub>m</sub><sup>2</sup>",
                  rim["thin_rim_mass_kg"], t("unit.kg")),
                 (t("flywheel.row_rim_thickness"), "<i>h</i>", rim["thickness_m"] * 1e3, t("unit.mm")),
                 (t("flywheel.row_rim_width"), "<i>b</i>", rim["width_m"] * 1e3, t("unit.mm")),
                 (t("flywheel.row_rim_outer"), "<i>D</i><sub>o</sub>", rim["outer_diameter_m"] * 1e3, t("unit.mm")),
                 (t("flywheel.row_rim_mass"), "<i>m</i>", rim["mass_kg"], t("unit.kg")),
                 (t("flywheel.row_rim_speed"), "<i>v</i><sub>o</sub>", rim["speed_m_s"], t("unit.m_s")),
                 (t("flywheel.row_rim_stress"), "<i>σ</i> = <i>ρ</i><sub>mat</sub> <i>v</i><sub>o</sub><sup>2</sup>", rim["hoop_stress_Pa"] / 1e6,
                  t("unit.MPa"))]
    table = ctx.table([(t("input.quantity"), [x[0] for x in rows], None),
                       (t("input.symbol"), [Markup(x[1]) for x in rows], None),
                       (t("input.value"), [x[2] if isinstance(x[2], str) else ctx.num(x[2]) for x in rows], None),
                       (t("input.unit"), [x[3] for x in rows], None)],
                      caption=t("flywheel.table_caption"), see="flywheel.see_table") + worked_flywheel(ctx, r)
    ctx.find(t("flywheel.finding", flywheel=ctx.num(r["flywheel_inertia_kg_m2"]), delta=ctx.num(r["irregularity"], 3)))
    ctx.conclude(t("flywheel.conclusion", excess=ctx.num(r["excess_work_J"]), flywheel=ctx.num(r["flywheel_inertia_kg_m2"]),
                   delta=ctx.num(r["irregularity"], 3), own=ctx.num(r["own_inertia_kg_m2"]),
                   mechanism=ctx.num(r["mechanism_inertia_mean_kg_m2"]), shaft=ctx.num(r["engine_inertia_kg_m2"])))
    return ctx.render_template("sections/flywheel.html.j2", r=r, rim=rim, figure_work=figure_work, table=table)


def _work_figure(f, mean_torque_Nm, cycle_deg, t):
    """The engine torque against its mean, and the cumulative excess work with its swing ΔL."""
    angle = f["crank_angle_deg"]
    work = f["excess_work_J"]
    i_max, i_min = first_argmax(work), first_argmin(work)
    fig, axes = new_figure(16, 13, nrows=2, sharex=True)
    axes[0].plot(angle, f["torque_Nm"], color="C0", label=t("flywheel.torque"))
    axes[0].axhline(mean_torque_Nm, color="C3", ls="--", lw=1, label=t("flywheel.mean_torque"))
    axes[0].fill_between(angle, f["torque_Nm"], mean_torque_Nm, color="C0", alpha=0.15, lw=0)
    axes[0].set_ylabel(t("flywheel.axis_torque"))
    axes[0].legend(loc="upper right", fontsize=8, ncol=2)
    axes[1].plot(angle, work, color="C2", label=t("flywheel.cumulative_work"))
    axes[1].plot([angle[i_max]], [work[i_max]], "o", color="C3")
    axes[1].plot([angle[i_min]], [work[i_min]], "o", color="C3")
    axes[1].annotate("", xy=(angle[i_max], work[i_max]), xytext=(angle[i_max], work[i_min]),
                     arrowprops={"arrowstyle": "<->", "color": "C3"})
    axes[1].axhline(work[i_min], color="C3", lw=0.6, ls=":")
    axes[1].text(angle[i_max], 0.5 * (work[i_max] + work[i_min]), "  ΔL", color="C3", va="center")
    axes[1].set_ylabel(t("flywheel.axis_work"))
    for ax in axes:
        ax.axhline(0, color="0.3", lw=0.6)
    crank_angle_axis(axes[1], cycle_deg, t("axis.crank_angle"))
    return fig


def input_rows(scene, ctx) -> list[tuple[str, str, str, str]]:
    """The [flywheel] table's given data for the report's table of the task's data."""
    opts = options(scene, "flywheel", FlywheelOptions)
    t, num = ctx.t, ctx.t.number_g
    inertia = t("unit.kg_m2")
    rows = []
    if opts.required_irregularity is not None:
        rows.append((t("flywheel.input_irregularity"), "[<i>δ</i>]", num(opts.required_irregularity, 6), ""))
    if opts.inertia is not None:
        rows.append((t("flywheel.input_inertia"), "<i>J</i><sub>f</sub>", num(opts.inertia, 4), inertia))
    if opts.engine_inertia:
        rows.append((t("flywheel.input_engine_inertia"), "<i>J</i><sub>e</sub>", num(opts.engine_inertia, 4), inertia))
    if opts.rim_mean_diameter is not None:
        rows.append((t("flywheel.input_rim_diameter"), "<i>D</i><sub>m</sub>", num(opts.rim_mean_diameter * 1e3, 4),
                     t("unit.mm")))
    if opts.rim_width is not None:
        rows.append((t("flywheel.input_rim_width"), "<i>b</i>", num(opts.rim_width * 1e3, 4), t("unit.mm")))
    rows.append((t("flywheel.input_rim_density"), "<i>ρ</i><sub>mat</sub>", num(opts.rim_density, 4), t("unit.kg_m3")))
    if opts.max_rim_speed is not None:
        rows.append((t("flywheel.input_rim_speed"), "[<i>v</i><sub>o</sub>]", num(opts.max_rim_speed, 4), t("unit.m_s")))
    return rows


FLYWHEEL_STAGE = Stage(
    template_dir=TEMPLATES,
    name="flywheel",
    # the core's letters that hold with their meaning in this section only
    section_symbols=("irregularity", "rim_mass", "rim_width", "rim_height"),
    title_key="flywheel.title",
    requires=(ENGINE_TORQUE, BAY_LOADS),
    provides=(FLYWHEEL,),
    applies=applies,
    run=run,
    render=render,
    figures=("excess_work",),
    tables=("flywheel",),
    references=("poda2007", "artobolevsky1988", "khurmi2005", "timoshenko1956"),
    options_table="flywheel",
    input_rows=input_rows,
    options_model=FlywheelOptions,
)
