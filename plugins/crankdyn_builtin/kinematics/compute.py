"""Kinematics of the central crank-slider (Poda 2007 §2; Tristen et al. for the extremes).


The computation: ``applies``, ``run``, ``run_many`` and their pure helpers.
"""

from __future__ import annotations

import functools

import numpy as np

from crankdyn.physics import kinematics as kin
from crankdyn.plugin.contracts import KINEMATICS, PistonMotion
from crankdyn.plugin.types import StageOutput

#: Significant digits of the two-term formulas' largest differences, in the section's text and in
#: the appendix's note alike (kinematics.html.j2): one rounding of a quantity wherever it is printed.
TWO_TERM_DIGITS = 3


def _significant(value: float, digits: int = TWO_TERM_DIGITS) -> float:
    """``value`` rounded to ``digits`` significant digits (a note prints its number as given)."""
    return float(f"{value:.{digits - 1}e}")


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
    columns = {
        "rod_cm_x_m": x,
        "rod_cm_z_m": z,
        "rod_cm_velocity_x_m_s": vx,
        "rod_cm_velocity_z_m_s": vz,
        "rod_cm_acceleration_x_m_s2": ax,
        "rod_cm_acceleration_z_m_s2": az,
    }
    return columns, {
        "rod_cm_from_big_end_m": distance_m,
        "rod_cm_acceleration_max_m_s2": float(np.max(np.hypot(ax, az))),
    }


def _displacement_at_deg(displacement, radius_m: float, ratio: float, crank_angle_deg):
    """Piston displacement (m) at any crank angle (deg) by the stage's chosen formula; a
    module-level function (not a lambda), so that the output can be pickled to another process."""
    return displacement(np.radians(crank_angle_deg), radius_m, ratio)


def run(scene, inputs) -> StageOutput:
    engine = scene.engine
    angle_deg = scene.crank_angles_deg
    alpha = np.radians(angle_deg)
    radius, ratio, omega = (
        engine.crank_radius_m,
        engine.rod_ratio_value,
        engine.angular_velocity_rad_s,
    )

    exact, approx = _piston_both_ways(alpha, radius, ratio, omega)
    chosen = exact if scene.analysis.kinematics == "exact" else approx
    rod = (
        kin.rod_angle_rad(alpha, ratio),
        kin.rod_angular_velocity_rad_s(alpha, ratio, omega),
        kin.rod_angular_acceleration_rad_s2(alpha, ratio, omega),
    )
    table = _kinematics_table(angle_deg, chosen, exact, approx, rod)
    results = _kinematics_results(scene, exact, approx, rod)
    if scene.masses is not None:
        columns, rod_cm = _rod_centre_of_mass(
            alpha, radius, ratio, omega, scene.rod_cm_from_big_end_m
        )
        table.update(columns)
        results.update(rod_cm)
    notes = [
        ("kinematics.note_method_" + scene.analysis.kinematics, {}),
        (
            "kinematics.note_two_term_error",
            {
                "ds_mm": _significant(results["two_term_displacement_error_max_m"] * 1e3),
                "dj": _significant(results["two_term_acceleration_error_max_m_s2"]),
            },
        ),
    ]
    return StageOutput(
        data={KINEMATICS: _piston_motion(scene, angle_deg, chosen, rod)},
        results=results,
        tables={"kinematics": table},
        notes=notes,
    )


def _kinematics_table(angle_deg, chosen: dict, exact: dict, approx: dict, rod) -> dict:
    """The kinematics table: the chosen formula's piston motion, both formulas' displacement and
    acceleration, the rod's angle and rates (``rod``: angle, angular velocity, acceleration)."""
    beta, rod_omega, rod_epsilon = rod
    return {
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


def _kinematics_results(scene, exact: dict, approx: dict, rod) -> dict:
    """The kinematics results: the mechanism's sizes, the piston's extremes (exact and by the
    two-term formula), the rod's largest angle and rates, the two-term formula's errors."""
    engine = scene.engine
    radius, ratio, omega = (
        engine.crank_radius_m,
        engine.rod_ratio_value,
        engine.angular_velocity_rad_s,
    )
    _, rod_omega, rod_epsilon = rod
    v_max, v_max_angle = kin.max_piston_velocity_exact(radius, ratio, omega)
    j_min, j_min_angle = kin.min_piston_acceleration_exact(radius, ratio, omega)
    j_min_tb, j_min_tb_angle = kin.min_piston_acceleration_approx(radius, ratio, omega)
    return {
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


def _piston_motion(scene, angle_deg, chosen: dict, rod) -> PistonMotion:
    """The motion handed on to the later stages, by the chosen formula."""
    engine = scene.engine
    radius, ratio = engine.crank_radius_m, engine.rod_ratio_value
    beta, rod_omega, rod_epsilon = rod
    displacement = (
        kin.piston_displacement_exact_m
        if scene.analysis.kinematics == "exact"
        else kin.piston_displacement_approx_m
    )
    return PistonMotion(
        crank_angle_deg=angle_deg,
        piston_displacement_m=chosen["s"],
        piston_velocity_m_s=chosen["v"],
        piston_acceleration_m_s2=chosen["j"],
        rod_angle_rad=beta,
        crank_radius_m=radius,
        angular_velocity_rad_s=engine.angular_velocity_rad_s,
        method=scene.analysis.kinematics,
        # the rod's rates in closed form (rod_dynamics would otherwise differentiate the angle spectrally)
        extra={
            "rod_ratio": ratio,
            "rod_length_m": engine.rod_length_m,
            "rod_angular_velocity_rad_s": rod_omega,
            "rod_angular_acceleration_rad_s2": rod_epsilon,
        },
        displacement_at=functools.partial(_displacement_at_deg, displacement, radius, ratio),
    )


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
    return all(
        s.analysis.kinematics == first.analysis.kinematics
        and (s.masses is None) == (first.masses is None)
        and np.array_equal(s.crank_angles_deg, first.crank_angles_deg)
        for s in scenes
    )


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
    displacement = (
        kin.piston_displacement_exact_m if method == "exact" else kin.piston_displacement_approx_m
    )
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
            "crank_radius_m": r,
            "rod_length_m": engine.rod_length_m,
            "rod_ratio": lam,
            "angular_velocity_rad_s": w,
            "method": method,
            "mean_piston_speed_m_s": kin.mean_piston_speed_m_s(r, w),
            "v_max_m_s": float(v_max[k]),
            "v_max_crank_angle_deg": float(np.degrees(v_angle)),
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
            crank_angle_deg=angle_deg,
            piston_displacement_m=chosen["s"][k],
            piston_velocity_m_s=chosen["v"][k],
            piston_acceleration_m_s2=chosen["j"][k],
            rod_angle_rad=beta[k],
            crank_radius_m=r,
            angular_velocity_rad_s=w,
            method=method,
            extra={
                "rod_ratio": lam,
                "rod_length_m": engine.rod_length_m,
                "rod_angular_velocity_rad_s": rod_omega[k],
                "rod_angular_acceleration_rad_s2": rod_epsilon[k],
            },
            displacement_at=functools.partial(_displacement_at_deg, displacement, r, lam),
        )
        outputs.append(StageOutput(data={KINEMATICS: motion}, results=results))
    return outputs
