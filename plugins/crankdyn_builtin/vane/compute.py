"""Vane engine with a crank-rocker parallelogram mechanism: mechanism and kinematics stage.

Source: Klementev (2023). The vane engine is not a piston engine: its working volumes
follow the vane angle, so its scenes are kinematics-only and this stage provides no
``PistonMotion`` (the indicator, force and torque stages do not apply).

Scene mapping: ``engine.stroke`` = 2r (the slider's travel along the rocker's slot),
``engine.rod_length`` = l (the core's tail) or ``engine.rod_ratio`` = lambda = r/l.

The computation: ``applies``, ``run`` and their pure helpers.
"""

from __future__ import annotations

import numpy as np

from crankdyn.errors import Problem
from crankdyn.physics import vane as vn
from crankdyn.physics.extrema import central_derivative, periodic_extreme
from crankdyn.physics.scalar_search import brentq
from crankdyn.plugin.scene_inputs import single_mechanism_problems
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

from .options import VaneParams

#: Plugin tables that only a multi-cylinder engine reads (the articulated rods).
MULTI_CYLINDER_TABLES = ("articulated",)

MECHANISM = "vane_crank_rocker"

WORKING_CYCLE_DEG = (90.0, 810.0)  # one side of the vane: alpha = 90...450...810 (source)


def check(scene) -> list[Problem]:
    problems = single_mechanism_problems(scene, "vane engine", MULTI_CYLINDER_TABLES)
    if scene.cycle is not None:
        problems.append(
            Problem(
                "cycle",
                "[cycle]",
                "the vane engine is studied for its kinematics only: its "
                "working volumes follow the vane angle, not a piston, so the indicator-diagram and "
                "force stages do not apply; remove [cycle]",
            )
        )
    if scene.masses is not None:
        problems.append(
            Problem(
                "masses",
                "[masses]",
                "the vane engine is studied for its kinematics only (the "
                "source gives no dynamics); remove [masses]",
            )
        )
    options(scene, "mechanism", VaneParams)
    return problems


def applies(scene) -> str | None:
    if scene.engine.mechanism != MECHANISM:
        return f"the scene's mechanism is {scene.engine.mechanism!r}, not the vane engine"
    return None


def _curves(alpha, r, lam, omega, suffix=""):
    return {
        "core_angle_deg" + suffix: np.degrees(vn.core_angle_rad(alpha, lam)),
        "vane_angle_deg" + suffix: np.degrees(vn.vane_angle_rad(alpha, lam)),
        "core_angular_velocity_rad_s" + suffix: vn.core_angular_velocity_rad_s(alpha, lam, omega),
        "core_angular_acceleration_rad_s2" + suffix: vn.core_angular_acceleration_rad_s2(
            alpha, lam, omega
        ),
        "slider_y_below_core_m" + suffix: vn.slider_height_below_core_m(alpha, r, lam),
        # one coordinate for the value and its derivatives: y_p = O3P, below the core axis (the source's)
        "slider_vy_below_core_m_s" + suffix: vn.slider_vertical_velocity_m_s(alpha, r, lam, omega),
        "slider_jy_below_core_m_s2" + suffix: vn.slider_vertical_acceleration_m_s2(
            alpha, r, lam, omega
        ),
        # B'P = l - y_p, the rise above the lowest position (its derivatives are -v_yp, -j_yp)
        "slider_rise_above_lowest_m" + suffix: vn.slider_vertical_travel_m(alpha, r, lam),
        "slider_relative_m" + suffix: vn.slider_relative_position_m(alpha, r, lam),
        "slider_relative_velocity_m_s" + suffix: vn.slider_relative_velocity_m_s(
            alpha, r, lam, omega
        ),
        "slider_relative_acceleration_m_s2" + suffix: vn.slider_relative_acceleration_m_s2(
            alpha, r, lam, omega
        ),
    }


def _quantities(r, lam, omega) -> dict:
    """CSV column -> (value of alpha in rad, its derivative d/dalpha or None for a numerical one)."""
    return {
        "vane_angle_deg": (
            lambda a: np.degrees(vn.vane_angle_rad(a, lam)),
            lambda a: np.degrees(vn.core_angular_velocity_rad_s(a, lam, omega)) / omega,
        ),
        "core_angular_velocity_rad_s": (
            lambda a: vn.core_angular_velocity_rad_s(a, lam, omega),
            lambda a: vn.core_angular_acceleration_rad_s2(a, lam, omega) / omega,
        ),
        "core_angular_acceleration_rad_s2": (
            lambda a: vn.core_angular_acceleration_rad_s2(a, lam, omega),
            None,
        ),
        "slider_y_below_core_m": (
            lambda a: vn.slider_height_below_core_m(a, r, lam),
            lambda a: vn.slider_vertical_velocity_m_s(a, r, lam, omega) / omega,
        ),
        "slider_vy_below_core_m_s": (
            lambda a: vn.slider_vertical_velocity_m_s(a, r, lam, omega),
            lambda a: vn.slider_vertical_acceleration_m_s2(a, r, lam, omega) / omega,
        ),
        "slider_jy_below_core_m_s2": (
            lambda a: vn.slider_vertical_acceleration_m_s2(a, r, lam, omega),
            None,
        ),
        "slider_relative_m": (
            lambda a: vn.slider_relative_position_m(a, r, lam),
            lambda a: vn.slider_relative_velocity_m_s(a, r, lam, omega) / omega,
        ),
        "slider_relative_velocity_m_s": (
            lambda a: vn.slider_relative_velocity_m_s(a, r, lam, omega),
            lambda a: vn.slider_relative_acceleration_m_s2(a, r, lam, omega) / omega,
        ),
        "slider_relative_acceleration_m_s2": (
            lambda a: vn.slider_relative_acceleration_m_s2(a, r, lam, omega),
            None,
        ),
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
    table = _vane_table(angle_deg, alpha, r, lam, omega)
    compare = {"crank_angle_deg": angle_deg}
    for other in params.compare_rod_ratios:
        compare.update(_curves(alpha, r, other, omega, suffix=f"_lambda_{other:g}"))
    by_lambda = _by_lambda_table()
    zeros, zeros_check = _acceleration_zeros(r, lam, omega)
    results = _vane_results(params, r, l_tail, omega, zeros, zeros_check)
    notes = [
        ("vane.note_corrected", {}),
        _zeros_note(float(zeros[0]), zeros_check),
    ]
    tables = {"vane": table, "by_lambda": by_lambda}
    if params.compare_rod_ratios:
        tables["compare"] = compare
    return StageOutput(data={}, results=results, tables=tables, notes=notes)


#: A root search agreeing with the closed form below this [deg] agrees to rounding: the note says
#: so in words (5,7·10⁻¹⁴° only says that two calculations agree).
ROUNDING_DEG = 1e-9


def _zeros_note(zero_deg: float, check_deg: float) -> tuple[str, dict]:
    """The note on the zeros of the slider's vertical acceleration and their check."""
    if abs(check_deg) < ROUNDING_DEG:
        return ("vane.note_zeros_rounding", {"zero": zero_deg})
    return ("vane.note_zeros", {"zero": zero_deg, "check": check_deg})


def _vane_table(angle_deg, alpha, r: float, lam: float, omega: float) -> dict:
    """The motion table over one revolution: the rocker's (and the slider's horizontal) motion,
    the mechanism's curves (:func:`_curves`) and the slider's rotation relative to the tail."""
    xk, yk = vn.rocker_position_m(alpha, r)
    vxk, vyk = vn.rocker_velocity_m_s(alpha, r, omega)
    jxk, jyk = vn.rocker_acceleration_m_s2(alpha, r, omega)
    table = {
        "crank_angle_deg": angle_deg,
        "rocker_x_m": xk,
        "rocker_y_m": yk,
        "rocker_vx_m_s": vxk,
        "rocker_vy_m_s": vyk,
        "rocker_jx_m_s2": jxk,
        "rocker_jy_m_s2": jyk,
        "slider_x_m": xk,
        "slider_vx_m_s": vxk,
        "slider_jx_m_s2": jxk,
    }
    table.update(_curves(alpha, r, lam, omega))
    table["slider_rotation_deg"] = -table[
        "core_angle_deg"
    ]  # relative to the tail: the mirror of beta
    return table


def _by_lambda_table() -> dict:
    """The mechanism's largest angles and travels and the acceleration's first zero over the rod
    ratios 0.01-0.99."""
    lam_grid = np.linspace(0.01, 0.99, 99)
    return {
        "rod_ratio": lam_grid,
        "core_angle_max_deg": np.degrees(np.arcsin(lam_grid)),
        "slider_vertical_travel_max_over_tail": [
            vn.slider_vertical_travel_max_m(1.0, x) / (1.0 / x) for x in lam_grid
        ],
        "slider_vertical_travel_max_over_crank": [
            vn.slider_vertical_travel_max_m(1.0, x) for x in lam_grid
        ],
        "acceleration_zero_deg": [
            float(np.degrees(vn.slider_vertical_acceleration_zeros_rad(x)[0])) for x in lam_grid
        ],
    }


def _acceleration_zeros(r: float, lam: float, omega: float):
    """(the crank angles where the slider's vertical acceleration is zero, in closed form, deg;
    the largest difference from a root search on the acceleration itself, deg)."""
    zeros = np.degrees(vn.slider_vertical_acceleration_zeros_rad(lam))
    # Independent check of the closed form: a root search on j_yp itself around each zero.
    found = [
        brentq(
            lambda a: float(vn.slider_vertical_acceleration_m_s2(a, r, lam, omega)),
            np.radians(z) - 0.2,
            np.radians(z) + 0.2,
            xtol=1e-14,
        )
        for z in zeros
    ]
    return zeros, float(np.max(np.abs(np.degrees(found) - zeros)))


def _vane_results(params, r: float, l_tail: float, omega: float, zeros, zeros_check) -> dict:
    """The results: sizes, the largest angles and travel, the acceleration's zeros and the
    extremes of the motion found by root finding on the derivative."""
    lam = r / l_tail
    y_max = vn.slider_vertical_travel_max_m(r, lam)
    ext = extremes(r, lam, omega)
    return {
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
        "slider_relative_travel_m": ext["slider_relative_m"]["max"]
        - ext["slider_relative_m"]["min"],
        "slider_relative_velocity_max_m_s": _largest(ext["slider_relative_velocity_m_s"]),
        "slider_relative_acceleration_max_m_s2": ext["slider_relative_acceleration_m_s2"]["max"],
        "slider_relative_acceleration_min_m_s2": ext["slider_relative_acceleration_m_s2"]["min"],
        "compare_rod_ratios": list(params.compare_rod_ratios),
        "working_cycle_deg": list(WORKING_CYCLE_DEG),
    }
