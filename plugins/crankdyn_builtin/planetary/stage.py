"""Planetary crank mechanism: mechanism and kinematics stage (Ismailov, figs. 1-3).

The carrier is the crank; a planet gear rolls outside a fixed sun gear (the big end runs on
an epicycloid) or inside a fixed ring gear (hypocycloid). This stage gives the big-end
trajectory, the piston motion, the rod motion, the torque arm at TDC and how a piston force
reaches the carrier. Scenes with this mechanism are kinematics-only: the textbook's force
stage puts the rod's rotating mass on the crank circle, which the big end here leaves.
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import AfterValidator, BaseModel, ConfigDict, model_validator

from crankdyn.contracts import KINEMATICS, PistonMotion
from crankdyn.errors import Problem
from crankdyn.physics import forces as phys
from crankdyn.physics import kinematics as central
from crankdyn.physics import planetary as pl
from crankdyn.physics.extrema import first_argmax, first_argmin
from crankdyn.physics.scalar_search import minimize_bounded
from crankdyn.plugin_types import Mechanism, Stage, StageOutput, Symbol
from crankdyn.report.context import sample_rows
from crankdyn.report.figures import crank_angle_axis, new_figure
from crankdyn.scene import number, options, quantity
from crankdyn.scene_inputs import single_mechanism_problems
from crankdyn_builtin.planetary.worked import worked_planetary

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"
#: Plugin tables that only a multi-cylinder engine reads (the articulated rods).
MULTI_CYLINDER_TABLES = ("articulated",)

MECHANISM = "planetary"
MAX_ROD_ANGLE_DEG = 80.0  # beyond this the linkage is locked or about to lock
STROKE_TOLERANCE = 5e-4  # relative agreement required between engine.stroke and the linkage's stroke
FAMILY_RATIOS = (3.0, 2.0, 1.5)  # fixed/planet pitch diameters of the source's fig. 2: d1 = 20, 30, 40 with d2 = 60


def _teeth(value: int) -> int:
    if value < 3:
        raise ValueError("must be a whole number of teeth, at least 3")
    return value


Teeth = Annotated[int, AfterValidator(_teeth)]


class PlanetaryParams(BaseModel):
    """The [mechanism] table of a planetary crank mechanism."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    gear: Literal["external", "internal"]
    fixed_gear_teeth: Teeth | None = None
    planet_teeth: Teeth | None = None
    module: quantity("length", gt=0, le=0.1, unit="mm", scale=1e-3) | None = None
    fixed_gear_pitch_diameter: quantity("length", gt=0, le=4.0, unit="mm", scale=1e-3) | None = None
    planet_pitch_diameter: quantity("length", gt=0, le=4.0, unit="mm", scale=1e-3) | None = None
    pin_radius: quantity("length", ge=0, le=2.0, unit="mm", scale=1e-3)
    pin_phase_deg: number(ge=-360, le=360) = 0.0
    pressure_angle_deg: number(ge=0, lt=45) = 20.0

    @model_validator(mode="after")
    def _sizes(self) -> PlanetaryParams:
        teeth = (self.fixed_gear_teeth, self.planet_teeth, self.module)
        diameters = (self.fixed_gear_pitch_diameter, self.planet_pitch_diameter)
        by_teeth = all(v is not None for v in teeth)
        by_diameters = all(v is not None for v in diameters)
        if by_teeth == by_diameters or (by_teeth and any(v is not None for v in diameters)) or (
                by_diameters and any(v is not None for v in teeth)):
            raise ValueError("give either fixed_gear_teeth, planet_teeth and module, or fixed_gear_pitch_diameter "
                             "and planet_pitch_diameter (the fixed gear is the sun for gear = 'external', the "
                             "ring for gear = 'internal')")
        if self.gear == "internal":
            planet, fixed = ((self.planet_teeth, self.fixed_gear_teeth) if by_teeth
                             else (self.planet_pitch_diameter, self.fixed_gear_pitch_diameter))
            if planet >= fixed:
                raise ValueError("a planet inside a ring gear must be smaller than the ring "
                                 f"(planet {planet:g} >= ring {fixed:g})")
        return self

    def radii_m(self) -> tuple[float, float]:
        if self.module is not None:
            return 0.5 * self.module * self.fixed_gear_teeth, 0.5 * self.module * self.planet_teeth
        return 0.5 * self.fixed_gear_pitch_diameter, 0.5 * self.planet_pitch_diameter

    def ratio(self) -> Fraction | float:
        if self.module is not None:
            return Fraction(self.fixed_gear_teeth, self.planet_teeth)
        return self.fixed_gear_pitch_diameter / self.planet_pitch_diameter


def geometry_of(scene) -> tuple[PlanetaryParams, pl.PlanetaryGeometry]:
    params = options(scene, "mechanism", PlanetaryParams)
    r_f, r_p = params.radii_m()
    geometry = pl.PlanetaryGeometry(params.gear, r_f, r_p, params.pin_radius, math.radians(params.pin_phase_deg),
                                    scene.engine.rod_length_m)
    return params, geometry


def check(scene) -> list[Problem]:
    problems = single_mechanism_problems(scene, "planetary crank mechanism", MULTI_CYLINDER_TABLES)
    if scene.cycle is not None:
        problems.append(Problem("cycle", "[cycle]", "the planetary mechanism is computed for its kinematics and the "
                                "force transmission per unit piston force; the gas- and inertia-force stages put the "
                                "rod's rotating mass on the crank circle, which the big end here leaves, so remove "
                                "[cycle]"))
    params, geometry = geometry_of(scene)
    revolutions = pl.motion_period_revolutions(params.ratio())
    cycle_revolutions = scene.engine.strokes // 2
    if revolutions is None or cycle_revolutions % revolutions:
        ratio = float(params.ratio())
        repeat = "never repeats exactly" if revolutions is None else f"repeats every {revolutions} carrier revolutions"
        problems.append(Problem("mechanism", f"gear ratio {ratio:g}",
                                f"with this gear ratio the motion {repeat}, but the scene's cycle is "
                                f"{cycle_revolutions} revolution(s) (strokes = {scene.engine.strokes}); use a ratio "
                                "fixed/planet that is a whole number (or a half for strokes = 4), e.g. tooth counts "
                                "60/20 or 60/40"))
        return problems
    reach = pl.lateral_reach_m(geometry, revolutions)
    L = geometry.rod_length_m
    if reach >= L:
        problems.append(Problem("engine.rod_length", f"{L * 1e3:g} mm",
                                f"the rod cannot reach: the big end swings up to {reach * 1e3:.4g} mm off the "
                                f"cylinder axis; the rod must be longer than that (a + e = "
                                f"{(geometry.carrier_radius_m + geometry.pin_radius_m) * 1e3:.4g} mm always suffices)"))
        return problems
    beta_max = math.degrees(math.asin(reach / L))
    if beta_max >= MAX_ROD_ANGLE_DEG:
        problems.append(Problem("engine.rod_length", f"{L * 1e3:g} mm",
                                f"the linkage locks: the rod swings up to {beta_max:.3g} deg from the cylinder axis "
                                f"(the piston side force would reach {math.tan(math.radians(beta_max)):.3g} times the "
                                f"axial force); keep it below {MAX_ROD_ANGLE_DEG:g} deg with a longer rod "
                                f"(> {reach / math.sin(math.radians(MAX_ROD_ANGLE_DEG)) * 1e3:.4g} mm)"))
        return problems
    stroke = pl.dead_centres(geometry, revolutions).stroke_m
    if abs(scene.engine.stroke - stroke) > STROKE_TOLERANCE * stroke:
        problems.append(Problem("engine.stroke", f"{scene.engine.stroke * 1e3:g} mm",
                                f"the planetary linkage gives a piston stroke of {stroke * 1e3:.6g} mm; write "
                                f"stroke = \"{stroke * 1e3:.6g} mm\" (the stroke is a result of the gear sizes, the "
                                "pin radius and the rod length, and sets the displayed R = S/2 and lambda)"))
    return problems


PLANETARY_MECHANISM = Mechanism(
    name=MECHANISM,
    summary="planetary crank mechanism: the carrier is the crank, the rod's big end is on a planet gear rolling "
            "on a fixed sun gear (epicycloid) or inside a fixed ring gear (hypocycloid)",
    check=check,
    params_model=PlanetaryParams,
    # the carrier is the crank: no R = S/2 nor λ = R/L (its radius a is in the section's data)
    input_rows={"crank_radius": None, "rod_ratio": None},
)


def applies(scene) -> str | None:
    if scene.engine.mechanism != MECHANISM:
        return f"the scene's mechanism is {scene.engine.mechanism!r}, not the planetary crank mechanism"
    return None


def _family(geometry: pl.PlanetaryGeometry) -> dict:
    """Big-end paths of the source's fig. 2: planets of 1/3, 1/2, 2/3 of the fixed gear, pin on the pitch circle."""
    phi = np.radians(np.arange(0.0, 720.0 + 0.25, 0.5))
    columns = {"carrier_angle_deg": np.degrees(phi)}
    for ratio in FAMILY_RATIOS:
        r_p = geometry.fixed_pitch_radius_m / ratio
        case = pl.PlanetaryGeometry(geometry.gear, geometry.fixed_pitch_radius_m, r_p, r_p, 0.0, geometry.rod_length_m)
        x, z, *_ = pl.big_end_path(phi, case)
        columns[f"ratio_{ratio:g}_x_m"] = x
        columns[f"ratio_{ratio:g}_z_m"] = z
    return columns


def piston_extremes(alpha, v, j, omega, geometry, dc, revolutions) -> dict:
    """Largest and smallest piston speed (m/s) and acceleration (m/s²) and their crank angles (deg).

    The grid's best point is refined by a bounded scalar search within one step on each side
    (the exact slider motion at any angle), kept only when it beats the grid value.
    """
    def speed(a):
        return float(-omega * pl.slider_motion(a + dc.tdc_carrier_angle_rad, geometry).pin_z_d1_m)

    def accel(a):
        return float(-omega * omega * pl.slider_motion(a + dc.tdc_carrier_angle_rad, geometry).pin_z_d2_m)

    def extreme(fn, values, sign):
        i = first_argmax(sign * values)
        step = alpha[1] - alpha[0]
        res = minimize_bounded(lambda a: -sign * fn(a), alpha[i] - step, alpha[i] + step, xatol=1e-12)
        best = float(res.x) if -res.fun >= sign * values[i] else float(alpha[i])
        return fn(best), float(np.degrees(best) % (360.0 * revolutions))

    out = {}
    for name, fn, values, sign in (("v_max", speed, v, +1.0), ("v_min", speed, v, -1.0),
                                   ("j_max", accel, j, +1.0), ("j_min", accel, j, -1.0)):
        out[name] = extreme(fn, values, sign)
    return out


def tdc_snapshot_m(geometry, dc) -> dict:
    """Where the parts are at TDC, m (x across, z along the cylinder axis; shaft axis at the origin).

    ``arm_foot`` is the foot of the perpendicular from the shaft axis on the rod's line at TDC
    (the source's N of MN): its distance from the axis is the rod line's torque arm.
    """
    c, s = math.cos(dc.tdc_carrier_angle_rad), math.sin(dc.tdc_carrier_angle_rad)
    snapshot = {
        "planet_centre": [float(v_) for v_ in geometry.carrier_radius_m * np.array([s, c])],
        "pin": [float(v_) for v_ in pl.big_end_path(dc.tdc_carrier_angle_rad, geometry)[:2]],
        "piston_pin": [0.0, dc.tdc_height_m],
        "pitch_point": [float(v_) for v_ in geometry.fixed_pitch_radius_m * np.array([s, c])],
    }
    pin_tdc = np.array(snapshot["pin"])
    direction = np.array([0.0, dc.tdc_height_m]) - pin_tdc
    direction /= np.hypot(*direction)
    snapshot["arm_foot"] = [float(v_) for v_ in pin_tdc - np.dot(pin_tdc, direction) * direction]
    return snapshot


def run(scene, inputs) -> StageOutput:
    engine = scene.engine
    params, geometry = geometry_of(scene)
    omega = engine.angular_velocity_rad_s
    revolutions = pl.motion_period_revolutions(params.ratio())
    dc = pl.dead_centres(geometry, revolutions)
    angle_deg = scene.crank_angles_deg
    alpha = np.radians(angle_deg)
    phi = alpha + dc.tdc_carrier_angle_rad
    x, z, *_ = pl.big_end_path(phi, geometry)
    slider = pl.slider_motion(phi, geometry)
    s = dc.tdc_height_m - slider.pin_z_m
    v = -omega * slider.pin_z_d1_m
    j = -omega * omega * slider.pin_z_d2_m
    beta = slider.rod_angle_rad
    transmission = pl.force_transmission(phi, geometry, math.radians(params.pressure_angle_deg))
    at_tdc = pl.force_transmission(dc.tdc_carrier_angle_rad, geometry, math.radians(params.pressure_angle_deg))
    L = geometry.rod_length_m

    # A conventional central crank-slider with the same stroke and rod, for comparison (source, fig. 3a).
    R_eq = 0.5 * dc.stroke_m
    lam_eq = R_eq / L
    conventional_arm = central.piston_velocity_exact_m_s(alpha, R_eq, lam_eq, 1.0)

    results = {
        "gear": params.gear,
        "fixed_pitch_diameter_m": 2.0 * geometry.fixed_pitch_radius_m,
        "planet_pitch_diameter_m": 2.0 * geometry.planet_pitch_radius_m,
    }
    if params.module is not None:
        results.update({"fixed_gear_teeth": params.fixed_gear_teeth, "planet_teeth": params.planet_teeth,
                        "module_m": params.module})
    extremes = piston_extremes(alpha, v, j, omega, geometry, dc, revolutions)
    results.update({
        "gear_ratio": float(params.ratio()),
        "planet_speed_ratio": geometry.planet_speed_ratio,
        "carrier_radius_m": geometry.carrier_radius_m,
        "pin_radius_m": geometry.pin_radius_m,
        "pin_phase_deg": params.pin_phase_deg,
        "pressure_angle_deg": params.pressure_angle_deg,
        "rod_length_m": L,
        "angular_velocity_rad_s": omega,
        "period_revolutions": revolutions,
        "tdc_carrier_angle_deg": math.degrees(dc.tdc_carrier_angle_rad),
        "bdc_crank_angle_deg": math.degrees(dc.bdc_carrier_angle_rad - dc.tdc_carrier_angle_rad) % (360.0 * revolutions),
        "stroke_m": dc.stroke_m,
        "path_lateral_max_m": pl.lateral_reach_m(geometry, revolutions),
        "rod_angle_max_deg": float(np.degrees(np.max(np.abs(beta)))),
        "v_max_m_s": extremes["v_max"][0], "v_max_crank_angle_deg": extremes["v_max"][1],
        "v_min_m_s": extremes["v_min"][0], "v_min_crank_angle_deg": extremes["v_min"][1],
        "j_max_m_s2": extremes["j_max"][0], "j_max_crank_angle_deg": extremes["j_max"][1],
        "j_min_m_s2": extremes["j_min"][0], "j_min_crank_angle_deg": extremes["j_min"][1],
        "torque_arm_tdc_m": float(at_tdc.rod_line_arm_m),
        "effective_torque_arm_tdc_m": float(at_tdc.carrier_torque_arm_m),
        "tooth_force_tdc": float(at_tdc.tooth_tangential),
        "carrier_torque_arm_max_m": float(np.max(transmission.carrier_torque_arm_m)),
        "conventional_torque_arm_max_m": float(np.max(conventional_arm)),
        "tdc_snapshot_m": tdc_snapshot_m(geometry, dc),
    })
    if params.gear == "internal" and float(params.ratio()) == 2.0 and geometry.pin_radius_m == geometry.planet_pitch_radius_m:
        # Cardan's circles: the path is the diameter at psi0/2 from the cylinder axis.
        half = 0.5 * geometry.pin_phase_rad
        results["straight_line_deviation_m"] = float(np.max(np.abs(x * math.cos(half) - z * math.sin(half))))

    table = _kinematics_table(angle_deg, phi, x, z, s, v, j, beta, omega, slider, transmission,
                              conventional_arm, alpha, R_eq, lam_eq)
    motion = _piston_motion(angle_deg, s, v, j, beta, geometry, omega, slider, dc, revolutions)
    if scene.masses is not None:
        results.update(_piston_inertia(scene, j, angle_deg, table))
    notes = [("planetary.note_derived", {}),
             ("planetary.note_torque_arm", {"arm_mm": results["torque_arm_tdc_m"] * 1e3}),
             ("planetary.note_family", {})]
    return StageOutput(data={KINEMATICS: motion}, results=results,
                       tables={"planetary": table, "family": _family(geometry)}, notes=notes)


def _kinematics_table(angle_deg, phi, x, z, s, v, j, beta, omega, slider, transmission, conventional_arm,
                      alpha, R_eq, lam_eq) -> dict:
    """The stage's table: the linkage's motion and force ratios, and the equivalent crank-slider's."""
    return {
        "crank_angle_deg": angle_deg,
        "carrier_angle_deg": np.degrees(phi),
        "big_end_x_m": x,
        "big_end_z_m": z,
        "piston_displacement_m": s,
        "piston_velocity_m_s": v,
        "piston_acceleration_m_s2": j,
        "rod_angle_deg": np.degrees(beta),
        "rod_angular_velocity_rad_s": omega * slider.rod_angle_d1,
        "rod_angular_acceleration_rad_s2": omega * omega * slider.rod_angle_d2,
        "carrier_torque_arm_m": transmission.carrier_torque_arm_m,
        "rod_line_arm_m": transmission.rod_line_arm_m,
        "rod_force_per_piston_force": transmission.rod_force,
        "tooth_tangential_per_piston_force": transmission.tooth_tangential,
        "tooth_radial_per_piston_force": transmission.tooth_radial,
        "carrier_tangential_per_piston_force": transmission.carrier_tangential,
        "carrier_radial_per_piston_force": transmission.carrier_radial,
        "conventional_torque_arm_m": conventional_arm,
        "conventional_piston_displacement_m": central.piston_displacement_exact_m(alpha, R_eq, lam_eq),
        "conventional_piston_velocity_m_s": central.piston_velocity_exact_m_s(alpha, R_eq, lam_eq, omega),
        "conventional_piston_acceleration_m_s2": central.piston_acceleration_exact_m_s2(alpha, R_eq, lam_eq, omega),
    }


def _displacement_at_deg(z_tdc_m: float, tdc_phi_rad: float, geometry, crank_angle_deg):
    """Slider displacement from TDC (m) at any crank angle (deg); module level, so the output pickles."""
    return z_tdc_m - pl.slider_motion(np.radians(crank_angle_deg) + tdc_phi_rad, geometry).pin_z_m


def _piston_motion(angle_deg, s, v, j, beta, geometry, omega, slider, dc, revolutions: int) -> PistonMotion:
    """The ``kinematics`` this stage provides (exact; displacement at any angle from the linkage)."""
    tdc_phi, z_tdc = dc.tdc_carrier_angle_rad, dc.tdc_height_m
    return PistonMotion(
        crank_angle_deg=angle_deg,
        piston_displacement_m=s,
        piston_velocity_m_s=v,
        piston_acceleration_m_s2=j,
        rod_angle_rad=beta,
        crank_radius_m=geometry.carrier_radius_m,
        angular_velocity_rad_s=omega,
        method="exact",
        extra={"rod_length_m": geometry.rod_length_m, "carrier_radius_m": geometry.carrier_radius_m,
               "rod_angular_velocity_rad_s": omega * slider.rod_angle_d1,
               "rod_angular_acceleration_rad_s2": omega * omega * slider.rod_angle_d2,
               "period_deg": 360.0 * revolutions},
        displacement_at=functools.partial(_displacement_at_deg, z_tdc, tdc_phi, geometry),
    )


def _piston_inertia(scene, j, angle_deg, table: dict) -> dict:
    """The inertia force of the reciprocating masses, P_j = −m_j j_p (N): the piston group and the
    rod's share at the piston pin (two-mass split), added to ``table``; its extremes (N, deg)."""
    rod_reciprocating, _ = phys.rod_mass_split_kg(scene.masses.rod, scene.engine.rod_length_m,
                                                  scene.rod_cm_from_big_end_m)
    mass = scene.masses.piston_group + rod_reciprocating
    force = -mass * j
    table["inertia_force_N"] = force
    low, high = first_argmin(force), first_argmax(force)
    return {"reciprocating_mass_kg": mass, "rod_reciprocating_mass_kg": rod_reciprocating,
            "inertia_force_max_N": float(force[high]), "inertia_force_max_crank_angle_deg": float(angle_deg[high]),
            "inertia_force_min_N": float(force[low]), "inertia_force_min_crank_angle_deg": float(angle_deg[low])}


def _circle(ax, centre, radius, **style):
    theta = np.linspace(0.0, 2.0 * np.pi, 361)
    ax.plot(centre[0] + radius * np.sin(theta), centre[1] + radius * np.cos(theta), **style)


def _sampled_table(f, r, span, ctx) -> str:
    """The sampled table of the linkage's motion and force ratios, with its worked substitutions."""
    t = ctx.t
    mm = 1e3
    angle = f["crank_angle_deg"]
    rows, labels = sample_rows(angle, ctx.table_step_deg, span_deg=span)
    g = f.take(rows)
    table = ctx.table([
        ("<i>α</i>, °", labels, 0),
        ("<i>x</i><sub>B</sub>, " + t("unit.mm"), g["big_end_x_m"] * mm, 3),
        ("<i>z</i><sub>B</sub>, " + t("unit.mm"), g["big_end_z_m"] * mm, 3),
        ("<i>s</i><sub>p</sub>, " + t("unit.mm"), g["piston_displacement_m"] * mm, 3),
        ("<i>v</i><sub>p</sub>, " + t("unit.m_s"), g["piston_velocity_m_s"], 2),
        ("<i>j</i><sub>p</sub>, " + t("unit.m_s2"), g["piston_acceleration_m_s2"], 0),
        ("<i>β</i>, °", g["rod_angle_deg"], 2),
        ("<i>h</i>, " + t("unit.mm"), g["carrier_torque_arm_m"] * mm, 3),
        ("<i>MN</i>, " + t("unit.mm"), g["rod_line_arm_m"] * mm, 3),
        ("<i>F</i><sub>t</sub>/<i>F</i>", g["tooth_tangential_per_piston_force"], 3),
    ] + ([("<i>P</i><sub>j</sub>, " + t("unit.kN"), g["inertia_force_N"] / 1e3, 3)] if "inertia_force_N" in g else []),
        caption=t("planetary.table_caption"), see="planetary.see_table")
    return table + worked_planetary(ctx, g, labels, r)


def _path_figure(f, r, inside, ctx) -> str:
    """The big end's trajectory and the mechanism at TDC with the torque arm MN (source, figs. 1 and 3b)."""
    return ctx.figure(functools.partial(_path_plot, f, r, inside, ctx.t), ctx.t("planetary.path_caption"),
                      "planetary_path", see="planetary.see_path")


def _path_plot(f, r, inside, t):
    """The gears' pitch circles, the big end's path and the mechanism at TDC with its arm MN."""
    mm = 1e3
    snap = r["tdc_snapshot_m"]
    fig, ax = new_figure(16, 10)
    _circle(ax, (0.0, 0.0), r["fixed_pitch_diameter_m"] / 2 * mm, color="0.5", ls="--", lw=0.9,
            label=t("planetary.fixed_gear"))
    _circle(ax, (0.0, 0.0), r["carrier_radius_m"] * mm, color="0.7", ls=":", lw=0.9, label=t("planetary.carrier_path"))
    ax.plot(f["big_end_x_m"][inside] * mm, f["big_end_z_m"][inside] * mm, color="C0",
            label=t("planetary.big_end_path"))
    centre = np.array(snap["planet_centre"]) * mm
    _circle(ax, centre, r["planet_pitch_diameter_m"] / 2 * mm, color="C2", lw=0.9, label=t("planetary.planet_at_tdc"))
    pin, piston, pitch, foot = (np.array(snap[k]) * mm for k in ("pin", "piston_pin", "pitch_point", "arm_foot"))
    extent = (r["carrier_radius_m"] + r["pin_radius_m"]) * mm * 1.15
    ax.plot([0, centre[0]], [0, centre[1]], color="C2", lw=2)
    ax.plot([centre[0], pin[0]], [centre[1], pin[1]], color="C2", lw=1.2)
    # The rod towards the piston pin (clipped by the axes), its line extended through the pitch point,
    # and the source's arm MN from the shaft axis to that line.
    ax.plot([pin[0], piston[0]], [pin[1], piston[1]], color="C3", lw=1.6, label=t("planetary.rod_at_tdc"))
    ax.plot([pin[0], 2 * pin[0] - piston[0]], [pin[1], 2 * pin[1] - piston[1]], color="C3", lw=0.7, ls="--")
    ax.plot([0, foot[0]], [0, foot[1]], color="k", lw=1.0, label="MN")
    ax.plot([0], [0], "k+", ms=8)
    ax.plot([pitch[0]], [pitch[1]], "ko", ms=3)
    ax.axvline(0, color="0.3", lw=0.5)
    ax.set_xlim(-extent, extent)
    ax.set_ylim(-extent, extent)
    ax.set_aspect("equal")
    ax.set_xlabel(t("planetary.axis_x"))
    ax.set_ylabel(t("planetary.axis_z"))
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8)
    return fig


def _family_figure(family, r, ctx) -> str:
    """The big-end paths of the source's fig. 2 family of gear ratios."""
    return ctx.figure(functools.partial(_family_plot, family, r["fixed_pitch_diameter_m"], ctx.t),
                      ctx.t("planetary.family_caption_" + r["gear"]), "planetary_family",
                      see="planetary.see_family_" + r["gear"])


def _family_plot(family, fixed_pitch_diameter_m, t):
    """One big-end path per gear ratio of the family, side by side, in the fixed gear's pitch circle."""
    mm = 1e3
    fig, axes = new_figure(16, 6.5, ncols=3)
    for ax, ratio in zip(axes, FAMILY_RATIOS, strict=True):
        d_fixed = fixed_pitch_diameter_m * mm
        _circle(ax, (0.0, 0.0), d_fixed / 2, color="0.5", ls="--", lw=0.8)
        ax.plot(family[f"ratio_{ratio:g}_x_m"] * mm, family[f"ratio_{ratio:g}_z_m"] * mm, color="C0")
        ax.set_aspect("equal")
        ax.set_title(f"d₁ = {d_fixed / ratio:.4g}, d₂ = {d_fixed:.4g} " + t("unit.mm"), fontsize=8)
        ax.tick_params(labelsize=7)
    return fig


def _motion_figure(f, angle, inside, span, ctx) -> str:
    """Piston displacement, velocity and acceleration against the equivalent crank-slider's (source, fig. 3a)."""
    return ctx.figure(functools.partial(_motion_plot, f, angle, inside, span, ctx.t), ctx.t("planetary.motion_caption"),
                      "planetary_motion", see="planetary.see_motion")


def _motion_plot(f, angle, inside, span, t):
    """The piston's s, v, j over the period, the equivalent crank-slider's dashed beside them."""
    mm = 1e3
    fig, axes = new_figure(16, 16, nrows=3, sharex=True)
    for ax, key, unit, scale, label in ((axes[0], "piston_displacement", "_m", mm, "planetary.axis_s"),
                                        (axes[1], "piston_velocity", "_m_s", 1.0, "planetary.axis_v"),
                                        (axes[2], "piston_acceleration", "_m_s2", 1.0, "planetary.axis_j")):
        ax.plot(angle[inside], f[key + unit][inside] * scale, color="C0", label=t("planetary.planetary"))
        ax.plot(angle[inside], f["conventional_" + key + unit][inside] * scale, color="0.45", ls="--",
                lw=1, label=t("planetary.conventional"))
        ax.axhline(0, color="0.3", lw=0.6)
        ax.set_ylabel(t(label))
    axes[0].legend(loc="upper right", fontsize=8)
    crank_angle_axis(axes[2], span, t("axis.crank_angle"))
    return fig


def _arms_figure(f, angle, inside, span, ctx) -> str:
    """How a piston force reaches the carrier: the torque arms and the tooth and carrier force ratios."""
    return ctx.figure(functools.partial(_arms_plot, f, angle, inside, span, ctx.t), ctx.t("planetary.arms_caption"),
                      "planetary_arms", see="planetary.see_arms")


def _arms_plot(f, angle, inside, span, t):
    """The torque arms above the tooth and carrier force ratios over the period."""
    mm = 1e3
    fig, axes = new_figure(16, 12, nrows=2, sharex=True)
    axes[0].plot(angle[inside], f["carrier_torque_arm_m"][inside] * mm, color="C0",
                 label=t("planetary.arm_effective"))
    axes[0].plot(angle[inside], f["rod_line_arm_m"][inside] * mm, color="C3", ls=":",
                 label=t("planetary.arm_rod_line"))
    axes[0].plot(angle[inside], f["conventional_torque_arm_m"][inside] * mm, color="0.45", ls="--", lw=1,
                 label=t("planetary.arm_conventional"))
    axes[0].set_ylabel(t("planetary.axis_arm"))
    axes[0].legend(loc="upper right", fontsize=8)
    axes[1].plot(angle[inside], f["tooth_tangential_per_piston_force"][inside], color="C2",
                 label=t("planetary.tooth_force"))
    axes[1].plot(angle[inside], f["carrier_radial_per_piston_force"][inside], color="C4", ls="--",
                 label=t("planetary.carrier_radial"))
    axes[1].set_ylabel(t("planetary.axis_force_ratio"))
    axes[1].legend(loc="upper right", fontsize=8)
    for ax in axes:
        ax.axhline(0, color="0.3", lw=0.6)
    crank_angle_axis(axes[1], span, t("axis.crank_angle"))
    return fig


def render(output: StageOutput, ctx) -> str:
    """The section: the sampled table, the four figures (path, family, motion, arms) and the conclusion."""
    t = ctx.t
    f = output.tables.arrays("planetary")
    r = output.results
    span = 360.0 * r["period_revolutions"]
    angle = f["crank_angle_deg"]
    inside = angle < span
    mm = 1e3

    table = _sampled_table(f, r, span, ctx)
    figure_path = _path_figure(f, r, inside, ctx)
    figure_family = _family_figure(output.tables.arrays("family"), r, ctx)
    figure_motion = _motion_figure(f, angle, inside, span, ctx)
    figure_arms = _arms_figure(f, angle, inside, span, ctx)

    ctx.conclude(t("planetary.conclusion", gear=t("planetary.gear_" + r["gear"]), ratio=ctx.num(r["gear_ratio"], 4),
                   stroke=ctx.num(r["stroke_m"] * mm, 5), arm=ctx.num(r["torque_arm_tdc_m"] * mm, 4),
                   arm_max=ctx.num(r["carrier_torque_arm_max_m"] * mm, 4),
                   conventional=ctx.num(r["conventional_torque_arm_max_m"] * mm, 4)))
    # The effective arm at TDC is zero; show round-off (~1e-17 m) as 0.
    effective_tdc = r["effective_torque_arm_tdc_m"] if abs(r["effective_torque_arm_tdc_m"]) > 1e-9 * r["stroke_m"] else 0.0
    return ctx.render_template("sections/planetary.html.j2", r=r, effective_tdc=effective_tdc, table=table,
                               figure_path=figure_path,
                               figure_family=figure_family, figure_motion=figure_motion, figure_arms=figure_arms)


#: The letters of the section's equations (meanings: symbol.planetary.<key> in i18n/); the crank angle,
#: the crankshaft's speed, the rod's angle and length and the piston's motion are the core's. The
#: subscripts are Latin in every language (f: the fixed gear, p: the planet, B: the big end, A: the
#: piston pin), but the carrier torque's, whose Latin c is the resistance torque's M_оп in uk/ru.
#: P, C and K in the prose are points; in the equations they are the points' position vectors.
_CARRIER = {"en": "c", "uk": "в", "ru": "в"}
SYMBOLS = {
    "fixed_teeth": Symbol("z", {"en": "f"}, ""),
    "planet_teeth": Symbol("z", {"en": "p"}, ""),
    "module": Symbol("m", {}, "unit.mm"),
    "fixed_diameter": Symbol("d", {"en": "f"}, "unit.mm"),
    "planet_diameter": Symbol("d", {"en": "p"}, "unit.mm"),
    "gear_ratio": Symbol("i", {}, ""),
    "carrier_radius": Symbol("a", {}, "unit.mm"),
    "speed_ratio": Symbol("k", {}, ""),
    "planet_angular_velocity": Symbol("ω", {"en": "p"}, "unit.rad_s"),
    "big_end_x": Symbol("x", {"en": "B"}, "unit.mm"),
    "big_end_z": Symbol("z", {"en": "B"}, "unit.mm"),
    "carrier_angle": Symbol("φ", {}, "°"),
    "pin_radius": Symbol("e", {}, "unit.mm"),
    "pin_angle": Symbol("θ", {}, "°"),
    "pin_phase": Symbol("ψ", {"en": "0"}, "°"),
    "piston_pin_z": Symbol("z", {"en": "A"}, "unit.mm"),
    "piston_pin_z_tdc": Symbol("z", {"en": "A,TDC", "uk": "A,ВМТ", "ru": "A,ВМТ"}, "unit.mm"),
    "big_end_x_derivative": Symbol("x", {"en": "B"}, "unit.m_rad", html="<i>x</i>′<sub>{sub}</sub>"),
    "big_end_z_derivative": Symbol("z", {"en": "B"}, "unit.m_rad", html="<i>z</i>′<sub>{sub}</sub>"),
    "rod_force_vector": Symbol("F", {"en": "P"}, "unit.N", html="<b>F</b><sub>{sub}</sub>"),
    "piston_force": Symbol("F", {}, "unit.N"),
    "tooth_tangential": Symbol("F", {"en": "t"}, "unit.N"),
    "pin_vector": Symbol("P", {}, "unit.mm", html="<b>P</b>"),
    "planet_centre_vector": Symbol("C", {}, "unit.mm", html="<b>C</b>"),
    "mesh_sign": Symbol("s", {}, ""),
    "planet_radius": Symbol("r", {"en": "p"}, "unit.mm"),
    "tooth_radial": Symbol("F", {"en": "r"}, "unit.N"),
    "pressure_angle": Symbol("α", {"en": "w"}, "°"),
    "carrier_torque": Symbol("M", _CARRIER, "unit.Nm"),
    "tooth_force_vector": Symbol("F", {"en": "K"}, "unit.N", html="<b>F</b><sub>{sub}</sub>"),
    "rotation_direction": Symbol("t", {}, "", html="<b>t</b>"),
    "torque_arm": Symbol("h", {}, "unit.mm"),
    # the inertia force of the reciprocating masses, given the masses
    "inertia_force": Symbol("P", {"en": "j"}, "unit.N"),
    "reciprocating_mass": Symbol("m", {"en": "j"}, "unit.kg"),
    # the points of the rod line's arm MN (the table's column and the text at TDC)
    "shaft_axis_point": Symbol("M", {}, ""),
    "arm_foot_point": Symbol("N", {}, ""),
}


PLANETARY_STAGE = Stage(
    template_dir=TEMPLATES,
    name="planetary",
    title_key="planetary.title",
    requires=(),
    provides=(KINEMATICS,),
    applies=applies,
    run=run,
    render=render,
    figures=("planetary_path", "planetary_family", "planetary_motion", "planetary_arms"),
    tables=("planetary", "family"),
    references=("ismailov",),
    symbols=SYMBOLS,
)
