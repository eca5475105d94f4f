"""Connecting-rod dynamics for every rod-based mechanism.

Rod angle, angular velocity and acceleration, centre-of-mass acceleration and the rod's
inertia loads, in the textbook's two-mass split (default) and in the dynamically exact
models (three masses, or two masses plus a correction couple), with their difference.
Needs the rod's moment of inertia, ``masses.rod_moment_of_inertia``.

The computation: ``applies``, ``run`` and their pure helpers.
"""

from __future__ import annotations

import numpy as np

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import rod_dynamics as rd
from crankdyn.physics.forces import rod_mass_split_kg
from crankdyn.plugin.contracts import KINEMATICS, RodDynamicsOptions
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

ROD_MECHANISMS = ("crank_slider", "offset_crank_slider", "planetary")


def applies(scene) -> str | None:
    if scene.masses is None:
        return "the scene has no [masses]"
    if scene.engine.mechanism not in ROD_MECHANISMS:
        return (
            f"the {scene.engine.mechanism!r} mechanism has no connecting rod of the kind this stage treats "
            f"(a rod from a big end to a piston pin on the cylinder axis: {', '.join(ROD_MECHANISMS)})"
        )
    if scene.engine.rod_type == "articulated":
        return "articulated rods: the master rod also carries the slave rods, which this stage does not model"
    if scene.engine.mechanism == "crank_slider" and scene.masses.rod_moment_of_inertia is None:
        return (
            "the scene gives no masses.rod_moment_of_inertia; the kinematics section already shows the "
            "central rod's motion, and without I_G its inertia couple cannot be computed"
        )
    return None


def _rod_rates(motion) -> tuple[np.ndarray, np.ndarray, str]:
    """The rod's angular velocity (rad/s) and acceleration (rad/s²) and where they come from: the
    mechanism's closed forms ("analytic") or the rod angle differentiated spectrally over the cycle."""
    if "rod_angular_velocity_rad_s" in motion.extra:
        rate = np.asarray(motion.extra["rod_angular_velocity_rad_s"], dtype=float)
        accel = np.asarray(motion.extra["rod_angular_acceleration_rad_s2"], dtype=float)
        return rate, accel, "analytic"
    angle, omega = motion.crank_angle_deg, motion.angular_velocity_rad_s
    period_rad = np.radians(angle[1] - angle[0]) * len(angle)
    rate = omega * rd.periodic_derivative(motion.rod_angle_rad, period_rad)
    return rate, omega * rd.periodic_derivative(rate, period_rad), "spectral"


def _exact_models(
    model: str, m, L, l_r, inertia, rate, accel, omega, points: dict, torque_two, inertia_two
):
    """(results, table columns, notes) of the models that need the rod's moment of inertia: the
    three-mass model, the correction couple and the exact rigid-body torque, against two masses.
    ``points``: velocity and acceleration (x, z) of the small end "a", big end "b", centre "g"."""
    (v_a, a_a), (v_b, a_b), (v_g, a_g) = points["a"], points["b"], points["g"]
    two_max = float(np.max(np.abs(torque_two)))
    m3_small, m3_big, m3_centre = rd.three_mass_split_kg(m, L, l_r, inertia)
    couple = -inertia * accel
    correction = rd.correction_couple_Nm(accel, m, L, l_r, inertia)
    torque_three = rd.point_masses_inertia_torque_Nm(
        [m3_small, m3_big, m3_centre], [v_a, v_b, v_g], [a_a, a_b, a_g], omega
    )
    torque_couple = torque_two + correction * rate / omega
    torque_exact = rd.rod_inertia_torque_Nm(m, inertia, v_g, a_g, rate, accel, omega)
    chosen = {
        "two_mass": torque_two,
        "three_mass": torque_three,
        "correction_couple": torque_couple,
    }[model]
    difference = torque_exact - torque_two
    results = {
        "rod_moment_of_inertia_kg_m2": inertia,
        "moment_of_inertia_ratio": inertia / inertia_two,
        "three_mass_small_end_kg": m3_small,
        "three_mass_big_end_kg": m3_big,
        "three_mass_centre_kg": m3_centre,
        "inertia_couple_max_Nm": float(np.max(np.abs(couple))),
        "correction_couple_max_Nm": float(np.max(np.abs(correction))),
        "torque_max_abs_Nm": float(np.max(np.abs(chosen))),
        "torque_exact_max_abs_Nm": float(np.max(np.abs(torque_exact))),
        "torque_difference_max_abs_Nm": float(np.max(np.abs(difference))),
        "torque_difference_relative": float(np.max(np.abs(difference)) / two_max)
        if two_max > 0
        else 0.0,
        "torque_exact_mean_Nm": float(np.mean(torque_exact)),
    }
    columns = {
        "inertia_couple_Nm": couple,
        "correction_couple_Nm": correction,
        "torque_exact_Nm": torque_exact,
        "torque_difference_Nm": difference,
        "torque_model_Nm": chosen,
    }
    notes = [
        (
            "rod_dynamics.note_models",
            {
                "ratio": results["moment_of_inertia_ratio"],
                "difference": results["torque_difference_relative"] * 100.0,
            },
        )
    ]
    if m3_centre < 0:
        notes.append(("rod_dynamics.note_negative_mass", {"mass": m3_centre}))
    return results, columns, notes


def run(scene, inputs) -> StageOutput:
    motion = inputs[KINEMATICS]
    opts = options(scene, "rod_dynamics", RodDynamicsOptions)
    masses = scene.masses
    m, inertia = masses.rod, masses.rod_moment_of_inertia
    L = motion.extra.get("rod_length_m", scene.engine.rod_length_m)
    l_r = scene.rod_cm_from_big_end_m
    omega = motion.angular_velocity_rad_s
    rate, accel, source = _rod_rates(motion)
    points = _rod_point_motions(motion, rate, accel, L, l_r)
    (v_a, a_a), (v_b, a_b), a_g = points["a"], points["b"], points["g"][1]
    m_small, m_big = (float(x) for x in rod_mass_split_kg(m, L, l_r))
    inertia_two = rd.two_mass_moment_of_inertia_kg_m2(m, L, l_r)
    torque_two = rd.point_masses_inertia_torque_Nm([m_small, m_big], [v_a, v_b], [a_a, a_b], omega)
    force_x, force_z = -m * a_g[0], -m * a_g[1]
    _check_model(opts.model, inertia)
    two_max = float(np.max(np.abs(torque_two)))
    results = {
        "model": opts.model,
        "derivatives": source,
        "rod_mass_kg": m,
        "rod_length_m": L,
        "rod_cm_from_big_end_m": l_r,
        "two_mass_moment_of_inertia_kg_m2": inertia_two,
        "two_mass_small_end_kg": m_small,
        "two_mass_big_end_kg": m_big,
        "rod_angular_velocity_max_rad_s": float(np.max(np.abs(rate))),
        "rod_angular_acceleration_max_rad_s2": float(np.max(np.abs(accel))),
        "cm_acceleration_max_m_s2": float(np.max(np.hypot(*a_g))),
        "inertia_force_max_N": float(np.max(np.hypot(force_x, force_z))),
        "torque_max_abs_Nm": two_max,
        "torque_two_mass_max_abs_Nm": two_max,
    }
    columns = _two_mass_columns(motion, rate, accel, a_g, (force_x, force_z), torque_two)
    results["period_deg"] = float(motion.extra.get("period_deg", 360.0))
    notes = []
    if inertia is None:
        notes.append(("rod_dynamics.note_no_inertia", {}))
    else:
        more, more_columns, more_notes = _exact_models(
            opts.model,
            m,
            L,
            l_r,
            inertia,
            rate,
            accel,
            omega,
            points,
            torque_two,
            inertia_two,
        )
        results.update(more)
        columns.update(more_columns)
        notes += more_notes
        # with the cycle the force stage computes the rod's loads: with the two-mass split unless
        # they take the rod as a rigid body (its own note says so)
        if scene.cycle is not None and not opts.apply_to_loads:
            notes.append(("rod_dynamics.note_forces_two_mass", {}))
    table = columns
    if source == "spectral":
        notes.append(("rod_dynamics.note_spectral", {}))
    if motion.method == "approximate":
        notes.append(
            ("rod_dynamics.note_approximate", {"mean": float(np.mean(columns["torque_model_Nm"]))})
        )
    return StageOutput(data={}, results=results, tables={"rod_dynamics": table}, notes=notes)


def _two_mass_columns(motion, rate, accel, a_g, force, torque_two) -> dict:
    """The table's columns of the rod's motion, its inertia force and the two-mass model's
    torque (the model's torque until an exact model replaces it)."""
    return {
        "crank_angle_deg": motion.crank_angle_deg,
        "rod_angle_deg": np.degrees(motion.rod_angle_rad),
        "rod_angular_velocity_rad_s": rate,
        "rod_angular_acceleration_rad_s2": accel,
        "cm_acceleration_x_m_s2": a_g[0],
        "cm_acceleration_z_m_s2": a_g[1],
        "inertia_force_x_N": force[0],
        "inertia_force_z_N": force[1],
        "torque_two_mass_Nm": torque_two,
        "torque_model_Nm": torque_two,
    }


def _rod_point_motions(motion, rate, accel, L: float, l_r: float) -> dict:
    """(velocity, acceleration) (x, z components, m/s and m/s²) of the rod's small end "a", big
    end "b" and centre of mass "g" (``l_r`` from the big end)."""
    beta = motion.rod_angle_rad
    pin_v, pin_a = -motion.piston_velocity_m_s, -motion.piston_acceleration_m_s2
    zero = np.zeros_like(pin_v)
    v_g = rd.rod_point_velocity_m_s(pin_v, beta, rate, L - l_r)
    a_g = rd.rod_point_acceleration_m_s2(pin_a, beta, rate, accel, L - l_r)
    v_b = rd.rod_point_velocity_m_s(pin_v, beta, rate, L)
    a_b = rd.rod_point_acceleration_m_s2(pin_a, beta, rate, accel, L)
    return {"a": ((zero, pin_v), (zero, pin_a)), "b": (v_b, a_b), "g": (v_g, a_g)}


def _check_model(model: str, inertia) -> None:
    """The exact models need the rod's moment of inertia."""
    if inertia is None and model != "two_mass":
        raise SceneError(
            Problem(
                "rod_dynamics.model",
                model,
                "the exact models need the rod's moment of inertia, masses.rod_moment_of_inertia; "
                "without it only two_mass is possible",
            )
        )
