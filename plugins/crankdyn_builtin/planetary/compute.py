"""Planetary crank mechanism: mechanism and kinematics stage (Ismailov, figs. 1-3).

The carrier is the crank; a planet gear rolls outside a fixed sun gear (the big end runs on
an epicycloid) or inside a fixed ring gear (hypocycloid). This stage gives the big-end
trajectory, the piston motion, the rod motion, the torque arm at TDC and how a piston force
reaches the carrier. Scenes with this mechanism are kinematics-only: the textbook's force
stage puts the rod's rotating mass on the crank circle, which the big end here leaves.

The computation: ``applies``, ``run`` and their pure helpers.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from crankdyn.errors import Problem
from crankdyn.physics import forces as phys
from crankdyn.physics import kinematics as central
from crankdyn.physics import planetary as pl
from crankdyn.physics.extrema import first_argmax, first_argmin
from crankdyn.physics.scalar_search import minimize_bounded
from crankdyn.plugin.contracts import KINEMATICS, PistonMotion
from crankdyn.plugin.scene_inputs import single_mechanism_problems
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

from .options import PlanetaryParams

#: Plugin tables that only a multi-cylinder engine reads (the articulated rods).
MULTI_CYLINDER_TABLES = ("articulated",)

MECHANISM = "planetary"

MAX_ROD_ANGLE_DEG = 80.0  # beyond this the linkage is locked or about to lock

STROKE_TOLERANCE = (
    5e-4  # relative agreement required between engine.stroke and the linkage's stroke
)

FAMILY_RATIOS = (
    3.0,
    2.0,
    1.5,
)  # fixed/planet pitch diameters of the source's fig. 2: d1 = 20, 30, 40 with d2 = 60


def geometry_of(scene) -> tuple[PlanetaryParams, pl.PlanetaryGeometry]:
    params = options(scene, "mechanism", PlanetaryParams)
    r_f, r_p = params.radii_m()
    geometry = pl.PlanetaryGeometry(
        params.gear,
        r_f,
        r_p,
        params.pin_radius,
        math.radians(params.pin_phase_deg),
        scene.engine.rod_length_m,
    )
    return params, geometry


def check(scene) -> list[Problem]:
    problems = single_mechanism_problems(scene, "planetary crank mechanism", MULTI_CYLINDER_TABLES)
    if scene.cycle is not None:
        problems.append(
            Problem(
                "cycle",
                "[cycle]",
                "the planetary mechanism is computed for its kinematics and the "
                "force transmission per unit piston force; the gas- and inertia-force stages put the "
                "rod's rotating mass on the crank circle, which the big end here leaves, so remove "
                "[cycle]",
            )
        )
    params, geometry = geometry_of(scene)
    revolutions = pl.motion_period_revolutions(params.ratio())
    cycle_revolutions = scene.engine.strokes // 2
    if revolutions is None or cycle_revolutions % revolutions:
        ratio = float(params.ratio())
        repeat = (
            "never repeats exactly"
            if revolutions is None
            else f"repeats every {revolutions} carrier revolutions"
        )
        problems.append(
            Problem(
                "mechanism",
                f"gear ratio {ratio:g}",
                f"with this gear ratio the motion {repeat}, but the scene's cycle is "
                f"{cycle_revolutions} revolution(s) (strokes = {scene.engine.strokes}); use a ratio "
                "fixed/planet that is a whole number (or a half for strokes = 4), e.g. tooth counts "
                "60/20 or 60/40",
            )
        )
        return problems
    reach = pl.lateral_reach_m(geometry, revolutions)
    L = geometry.rod_length_m
    if reach >= L:
        problems.append(
            Problem(
                "engine.rod_length",
                f"{L * 1e3:g} mm",
                f"the rod cannot reach: the big end swings up to {reach * 1e3:.4g} mm off the "
                f"cylinder axis; the rod must be longer than that (a + e = "
                f"{(geometry.carrier_radius_m + geometry.pin_radius_m) * 1e3:.4g} mm always suffices)",
            )
        )
        return problems
    beta_max = math.degrees(math.asin(reach / L))
    if beta_max >= MAX_ROD_ANGLE_DEG:
        problems.append(
            Problem(
                "engine.rod_length",
                f"{L * 1e3:g} mm",
                f"the linkage locks: the rod swings up to {beta_max:.3g} deg from the cylinder axis "
                f"(the piston side force would reach {math.tan(math.radians(beta_max)):.3g} times the "
                f"axial force); keep it below {MAX_ROD_ANGLE_DEG:g} deg with a longer rod "
                f"(> {reach / math.sin(math.radians(MAX_ROD_ANGLE_DEG)) * 1e3:.4g} mm)",
            )
        )
        return problems
    stroke = pl.dead_centres(geometry, revolutions).stroke_m
    if abs(scene.engine.stroke - stroke) > STROKE_TOLERANCE * stroke:
        problems.append(
            Problem(
                "engine.stroke",
                f"{scene.engine.stroke * 1e3:g} mm",
                f"the planetary linkage gives a piston stroke of {stroke * 1e3:.6g} mm; write "
                f'stroke = "{stroke * 1e3:.6g} mm" (the stroke is a result of the gear sizes, the '
                "pin radius and the rod length, and sets the displayed R = S/2 and lambda)",
            )
        )
    return problems


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
        case = pl.PlanetaryGeometry(
            geometry.gear, geometry.fixed_pitch_radius_m, r_p, r_p, 0.0, geometry.rod_length_m
        )
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
        return float(
            -omega * omega * pl.slider_motion(a + dc.tdc_carrier_angle_rad, geometry).pin_z_d2_m
        )

    def extreme(fn, values, sign):
        i = first_argmax(sign * values)
        step = alpha[1] - alpha[0]
        res = minimize_bounded(
            lambda a: -sign * fn(a), alpha[i] - step, alpha[i] + step, xatol=1e-12
        )
        best = float(res.x) if -res.fun >= sign * values[i] else float(alpha[i])
        return fn(best), float(np.degrees(best) % (360.0 * revolutions))

    out = {}
    for name, fn, values, sign in (
        ("v_max", speed, v, +1.0),
        ("v_min", speed, v, -1.0),
        ("j_max", accel, j, +1.0),
        ("j_min", accel, j, -1.0),
    ):
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


def _table_at(angle_deg, geometry, params, dc, omega, R_eq, lam_eq) -> dict:
    """The stage's table columns at the crank angles ``angle_deg`` (the grid, or any angles)."""
    angle_deg = np.asarray(angle_deg, dtype=float)
    alpha = np.radians(angle_deg)
    phi = alpha + dc.tdc_carrier_angle_rad
    x, z, *_ = pl.big_end_path(phi, geometry)
    slider = pl.slider_motion(phi, geometry)
    transmission = pl.force_transmission(phi, geometry, math.radians(params.pressure_angle_deg))
    return _kinematics_table(
        angle_deg,
        phi,
        x,
        z,
        dc.tdc_height_m - slider.pin_z_m,
        -omega * slider.pin_z_d1_m,
        -omega * omega * slider.pin_z_d2_m,
        slider.rod_angle_rad,
        omega,
        slider,
        transmission,
        central.piston_velocity_exact_m_s(alpha, R_eq, lam_eq, 1.0),
        alpha,
        R_eq,
        lam_eq,
    )


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
    # A conventional central crank-slider with the same stroke and rod, for comparison (source, fig. 3a).
    R_eq = 0.5 * dc.stroke_m
    lam_eq = R_eq / geometry.rod_length_m
    table = _table_at(angle_deg, geometry, params, dc, omega, R_eq, lam_eq)
    s = table["piston_displacement_m"]
    v = table["piston_velocity_m_s"]
    j = table["piston_acceleration_m_s2"]
    beta = slider.rod_angle_rad
    transmission = pl.force_transmission(phi, geometry, math.radians(params.pressure_angle_deg))
    conventional_arm = table["conventional_torque_arm_m"]
    extremes = piston_extremes(alpha, v, j, omega, geometry, dc, revolutions)
    reversals = _reversal_results(geometry, dc, revolutions)
    reversal_angles = [item["crank_angle_deg"] for item in reversals["reversals"]]
    reversal_table = _table_at(reversal_angles, geometry, params, dc, omega, R_eq, lam_eq)
    results = {
        **_gear_results(params, geometry),
        **_mechanism_results(params, geometry, dc, revolutions, omega),
        **reversals,
        **_motion_extreme_results(beta, extremes),
        **_speed_results(dc, reversals, engine.rpm, revolutions),
        **_tdc_acceleration_results(geometry, dc, omega, R_eq, lam_eq),
        **_torque_arm_results(params, geometry, dc, transmission, conventional_arm),
        **_tooth_flank_results(params, geometry, dc, revolutions),
        **_straight_line_deviation(params, geometry, x, z),
    }
    motion = _piston_motion(angle_deg, s, v, j, beta, geometry, omega, slider, dc, revolutions)
    motion.extra["dead_centres_extra_deg"] = extra_dead_centres(
        reversals["reversals"], reversals["secondary_strokes"], dc.stroke_m
    )
    if scene.masses is not None:
        results.update(_piston_inertia(scene, j, angle_deg, table))
        reversal_table["inertia_force_N"] = -results["reciprocating_mass_kg"] * np.asarray(
            reversal_table["piston_acceleration_m_s2"]
        )
    notes = [
        ("planetary.note_derived", {}),
        ("planetary.note_torque_arm", {"arm_mm": results["torque_arm_tdc_m"] * 1e3}),
        ("planetary.note_family_" + params.gear, {}),
    ]
    return StageOutput(
        data={KINEMATICS: motion},
        results=results,
        tables={"planetary": table, "family": _family(geometry), "reversals": reversal_table},
        notes=notes,
    )


def _reversal_results(geometry, dc, revolutions: int) -> dict:
    """Every place the piston stops and reverses
    (:func:`crankdyn.physics.planetary.piston_reversals`) as crank angles from TDC, with the
    displacement there and whether it is a global dead centre, and the piston's path over the
    period (the sum of the travels between reversals)."""
    period = 360.0 * revolutions
    tie = 1e-9 * dc.stroke_m
    items = []
    for reversal in pl.piston_reversals(geometry, revolutions):
        angle = math.degrees(reversal.carrier_angle_rad - dc.tdc_carrier_angle_rad) % period
        angle = 0.0 if min(angle, period - angle) < 1e-7 else angle
        displacement = dc.tdc_height_m - reversal.height_m
        extreme = dc.stroke_m if reversal.kind == "bdc" else 0.0
        items.append(
            {
                "crank_angle_deg": angle,
                "displacement_m": 0.0 if abs(displacement) < tie else displacement,
                "kind": reversal.kind,
                "main": abs(displacement - extreme) <= tie,
            }
        )
    items.sort(key=lambda item: item["crank_angle_deg"])
    travels = [
        abs(items[(i + 1) % len(items)]["displacement_m"] - items[i]["displacement_m"])
        for i in range(len(items))
    ]
    strokes = secondary_strokes(items)
    return {
        "reversals": items,
        "reversal_count": len(items),
        "secondary_strokes": strokes,
        "bdc_crank_angles_deg": [
            i["crank_angle_deg"] for i in items if i["kind"] == "bdc" and i["main"]
        ],
        "piston_path_m": float(sum(travels)),
        # a conventional crank-slider over the same carrier angle: two strokes a revolution
        "conventional_path_m": 2.0 * dc.stroke_m * revolutions,
        "conventional_reversals": 2 * revolutions,
        "secondary_stroke_max_m": max((s["depth_m"] for s in strokes), default=0.0),
    }


def secondary_strokes(reversals: list[dict]) -> list[dict]:
    """The strokes besides the main one: each travel between two reversals against the direction
    of the half-stroke it lies in (back up on the way down to BDC, back down on the way up, away
    from a dead centre reached twice), with its depth (m), its crank angles (deg) and whether the
    piston rises or falls in it. A conventional mechanism has none."""
    n = len(reversals)
    strokes = []
    for i in range(n):
        first, second = reversals[i], reversals[(i + 1) % n]
        before = next(reversals[(i - k) % n] for k in range(n) if reversals[(i - k) % n]["main"])
        after = next(
            reversals[(i + 1 + k) % n] for k in range(n) if reversals[(i + 1 + k) % n]["main"]
        )
        travel = second["displacement_m"] - first["displacement_m"]  # s grows downwards
        if (before["kind"], after["kind"]) == ("tdc", "bdc"):
            back = travel < 0
        elif (before["kind"], after["kind"]) == ("bdc", "tdc"):
            back = travel > 0
        else:  # between two equal dead centres: the travel away from them
            back = travel < 0 if before["kind"] == "bdc" else travel > 0
        if back:
            strokes.append(
                {
                    "from_deg": first["crank_angle_deg"],
                    "to_deg": second["crank_angle_deg"],
                    "depth_m": abs(travel),
                    "direction": "rise" if travel < 0 else "fall",
                }
            )
    return strokes


#: A secondary stroke shallower than this share of the stroke is described, not drawn.
DRAWN_SECONDARY_STROKE = 0.01


def extra_dead_centres(
    reversals: list[dict], strokes: list[dict], stroke_m: float
) -> dict[str, float]:
    """Crank angles (deg) of the dead centres the drawing shows besides the first TDC and BDC:
    a repeated one (``bdc_2`` ...) and a secondary one at the end of a secondary stroke at least
    :data:`DRAWN_SECONDARY_STROKE` of the stroke deep (``secondary_tdc_1`` ...)."""
    deep = set()
    for stroke in strokes:  # the secondary strokes (:func:`secondary_strokes`)
        if stroke["depth_m"] >= DRAWN_SECONDARY_STROKE * stroke_m:
            deep.update((stroke["from_deg"], stroke["to_deg"]))
    found: dict[str, float] = {}
    seen = {"tdc": 0, "bdc": 0}
    secondary = {"tdc": 0, "bdc": 0}
    for item in reversals:
        kind, angle = item["kind"], item["crank_angle_deg"]
        if item["main"]:
            seen[kind] += 1
            if seen[kind] > 1:
                found[f"{kind}_{seen[kind]}"] = angle
        elif angle in deep:
            secondary[kind] += 1
            found[f"secondary_{kind}_{secondary[kind]}"] = angle
    return found


def _speed_results(dc, reversals: dict, rpm: float, revolutions: int) -> dict:
    """The mean piston speed S·n/30 and, from the path over the period, the true one (m/s)."""
    return {
        "mean_piston_speed_m_s": dc.stroke_m * rpm / 30.0,
        "mean_piston_speed_path_m_s": reversals["piston_path_m"] * rpm / 60.0 / revolutions,
    }


def _tdc_acceleration_results(geometry, dc, omega, R_eq, lam_eq) -> dict:
    """The piston's acceleration at TDC against the central crank-slider's with the same stroke and
    rod, R ω² (1 + λ) with R = S/2, λ = R/L."""
    j_tdc = float(-omega * omega * pl.slider_motion(dc.tdc_carrier_angle_rad, geometry).pin_z_d2_m)
    conventional = R_eq * omega * omega * (1.0 + lam_eq)
    return {
        "j_tdc_m_s2": j_tdc,
        "conventional_j_tdc_m_s2": conventional,
        "j_tdc_excess": j_tdc / conventional - 1.0,
        "conventional_crank_radius_m": R_eq,
        "conventional_rod_ratio": lam_eq,
    }


def _tooth_flank_results(params, geometry, dc, revolutions: int) -> dict:
    """The crank angles (deg) where the tangential tooth force changes sign: the planet's teeth
    then bear on their other flanks and the backlash closes with an impact."""
    period = 2.0 * math.pi * revolutions
    pressure = math.radians(params.pressure_angle_deg)

    def tooth(p):
        return pl.force_transmission(p, geometry, pressure).tooth_tangential

    angles = [
        math.degrees(root - dc.tdc_carrier_angle_rad) % (360.0 * revolutions)
        for root in pl.sign_changes(tooth, period, 4096 * revolutions)
    ]
    return {"tooth_force_sign_changes_deg": sorted(angles)}


def _gear_results(params, geometry) -> dict:
    """The gears: their kind, pitch diameters and, with a module, tooth counts and module."""
    results = {
        "gear": params.gear,
        "fixed_pitch_diameter_m": 2.0 * geometry.fixed_pitch_radius_m,
        "planet_pitch_diameter_m": 2.0 * geometry.planet_pitch_radius_m,
    }
    if params.module is not None:
        results.update(
            {
                "fixed_gear_teeth": params.fixed_gear_teeth,
                "planet_teeth": params.planet_teeth,
                "module_m": params.module,
            }
        )
    return results


def _mechanism_results(params, geometry, dc, revolutions: int, omega: float) -> dict:
    """The mechanism's sizes, its period, dead centres, stroke and the path's lateral reach."""
    return {
        "gear_ratio": float(params.ratio()),
        "planet_speed_ratio": geometry.planet_speed_ratio,
        "carrier_radius_m": geometry.carrier_radius_m,
        "pin_radius_m": geometry.pin_radius_m,
        "pin_phase_deg": params.pin_phase_deg,
        "pressure_angle_deg": params.pressure_angle_deg,
        "rod_length_m": geometry.rod_length_m,
        "angular_velocity_rad_s": omega,
        "period_revolutions": revolutions,
        "tdc_carrier_angle_deg": math.degrees(dc.tdc_carrier_angle_rad),
        "bdc_crank_angle_deg": math.degrees(dc.bdc_carrier_angle_rad - dc.tdc_carrier_angle_rad)
        % (360.0 * revolutions),
        "stroke_m": dc.stroke_m,
        "curve": curve_name(geometry),
        "path_lateral_max_m": pl.lateral_reach_m(geometry, revolutions),
    }


def curve_name(geometry) -> str:
    """The big end's path: a hypocycloid (ring gear) or an epicycloid (sun gear) with the pin on the
    planet's pitch circle; a curtate (pin inside it) or prolate (outside) hypo- or epitrochoid."""
    family = "hypo" if geometry.gear == "internal" else "epi"
    e, r_p = geometry.pin_radius_m, geometry.planet_pitch_radius_m
    if abs(e - r_p) <= 1e-12 * r_p:
        return family + "cycloid"
    return family + ("trochoid_curtate" if e < r_p else "trochoid_prolate")


def _motion_extreme_results(beta, extremes: dict) -> dict:
    """The rod's largest angle and the piston's extreme velocities and accelerations with their
    crank angles (:func:`piston_extremes`)."""
    return {
        "rod_angle_max_deg": float(np.degrees(np.max(np.abs(beta)))),
        "v_max_m_s": extremes["v_max"][0],
        "v_max_crank_angle_deg": extremes["v_max"][1],
        "v_min_m_s": extremes["v_min"][0],
        "v_min_crank_angle_deg": extremes["v_min"][1],
        "j_max_m_s2": extremes["j_max"][0],
        "j_max_crank_angle_deg": extremes["j_max"][1],
        "j_min_m_s2": extremes["j_min"][0],
        "j_min_crank_angle_deg": extremes["j_min"][1],
    }


def _torque_arm_results(params, geometry, dc, transmission, conventional_arm) -> dict:
    """The torque arms at TDC and their largest values against the conventional mechanism's, and
    where the parts are at TDC."""
    at_tdc = pl.force_transmission(
        dc.tdc_carrier_angle_rad, geometry, math.radians(params.pressure_angle_deg)
    )
    return {
        "torque_arm_tdc_m": float(at_tdc.rod_line_arm_m),
        "effective_torque_arm_tdc_m": float(at_tdc.carrier_torque_arm_m),
        "tooth_force_tdc": float(at_tdc.tooth_tangential),
        "carrier_torque_arm_max_m": float(np.max(transmission.carrier_torque_arm_m)),
        "conventional_torque_arm_max_m": float(np.max(conventional_arm)),
        "tdc_snapshot_m": tdc_snapshot_m(geometry, dc),
    }


def _straight_line_deviation(params, geometry, x, z) -> dict:
    """Cardan's circles (an internal gear of ratio 2, the pin on the planet's pitch circle): how
    far the big end's path strays from its straight line; nothing for another mechanism."""
    if (
        params.gear == "internal"
        and float(params.ratio()) == 2.0
        and geometry.pin_radius_m == geometry.planet_pitch_radius_m
    ):
        # Cardan's circles: the path is the diameter at psi0/2 from the cylinder axis.
        half = 0.5 * geometry.pin_phase_rad
        return {
            "straight_line_deviation_m": float(
                np.max(np.abs(x * math.cos(half) - z * math.sin(half)))
            )
        }
    return {}


def _kinematics_table(
    angle_deg,
    phi,
    x,
    z,
    s,
    v,
    j,
    beta,
    omega,
    slider,
    transmission,
    conventional_arm,
    alpha,
    R_eq,
    lam_eq,
) -> dict:
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
        "conventional_piston_displacement_m": central.piston_displacement_exact_m(
            alpha, R_eq, lam_eq
        ),
        "conventional_piston_velocity_m_s": central.piston_velocity_exact_m_s(
            alpha, R_eq, lam_eq, omega
        ),
        "conventional_piston_acceleration_m_s2": central.piston_acceleration_exact_m_s2(
            alpha, R_eq, lam_eq, omega
        ),
    }


def _displacement_at_deg(z_tdc_m: float, tdc_phi_rad: float, geometry, crank_angle_deg):
    """Slider displacement from TDC (m) at any crank angle (deg); module level, so the output pickles."""
    return z_tdc_m - pl.slider_motion(np.radians(crank_angle_deg) + tdc_phi_rad, geometry).pin_z_m


def _piston_motion(
    angle_deg, s, v, j, beta, geometry, omega, slider, dc, revolutions: int
) -> PistonMotion:
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
        extra={
            "rod_length_m": geometry.rod_length_m,
            "carrier_radius_m": geometry.carrier_radius_m,
            "rod_angular_velocity_rad_s": omega * slider.rod_angle_d1,
            "rod_angular_acceleration_rad_s2": omega * omega * slider.rod_angle_d2,
            "period_deg": 360.0 * revolutions,
        },
        displacement_at=functools.partial(_displacement_at_deg, z_tdc, tdc_phi, geometry),
    )


def _piston_inertia(scene, j, angle_deg, table: dict) -> dict:
    """The inertia force of the reciprocating masses, P_j = −m_j j_p (N): the piston group and the
    rod's share at the piston pin (two-mass split), added to ``table``; its extremes (N, deg)."""
    rod_reciprocating, _ = phys.rod_mass_split_kg(
        scene.masses.rod, scene.engine.rod_length_m, scene.rod_cm_from_big_end_m
    )
    mass = scene.masses.piston_group + rod_reciprocating
    force = -mass * j
    table["inertia_force_N"] = force
    low, high = first_argmin(force), first_argmax(force)
    return {
        "reciprocating_mass_kg": mass,
        "rod_reciprocating_mass_kg": rod_reciprocating,
        "inertia_force_max_N": float(force[high]),
        "inertia_force_max_crank_angle_deg": float(angle_deg[high]),
        "inertia_force_min_N": float(force[low]),
        "inertia_force_min_crank_angle_deg": float(angle_deg[low]),
    }
