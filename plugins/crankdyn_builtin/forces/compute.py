"""Gas and inertia forces, forces in the crank mechanism and the torque of one crank (Poda 2007 §3.2-3.3).


The computation: ``applies``, ``run``, ``run_many`` and their pure helpers.
"""

from __future__ import annotations

import numpy as np

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import crankshaft as phys_crankshaft
from crankdyn.physics import forces as phys
from crankdyn.physics import kinematics as kin
from crankdyn.physics import rod_loads
from crankdyn.physics.extrema import EXTREMUM_RTOL, first_argmax, first_argmin
from crankdyn.plugin.contracts import (
    FORCES,
    GAS_PRESSURE,
    KINEMATICS,
    ArticulatedOptions,
    CrankForces,
    RodDynamicsOptions,
)
from crankdyn.plugin.scene_inputs import articulated_reciprocating_masses_kg, engine_layout
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options


def applies(scene) -> str | None:
    if scene.masses is None:
        return "the scene has no [masses]"
    return None


def _extremes_many(crank_angle_deg, many) -> list[dict]:
    """For each ``series`` of ``many`` (tuples of (name, unit, values)), ``<name>_max_<unit>``/
    ``_min_`` and their crank angles (°): the first sample of each extreme (physics.extrema), all
    the curves of all the series found together."""
    rows = np.stack([values for series in many for _, _, values in series])
    at_max, at_min = _first_extremes(rows)
    out, row = [], 0
    for series in many:
        found = {}
        for base, unit, values in series:
            for which, i in (("max", at_max[row]), ("min", at_min[row])):
                found[f"{base}_{which}_{unit}"] = float(values[i])
                found[f"{base}_{which}_crank_angle_deg"] = float(crank_angle_deg[i])
            row += 1
        out.append(found)
    return out


def _first_extremes(rows) -> tuple[np.ndarray, np.ndarray]:
    """(index of the first maximum, of the first minimum) of each row of ``rows`` (curves x
    angles): per row the first sample within ``EXTREMUM_RTOL`` x its range of the extreme, as
    ``physics.extrema.first_argmax``/``first_argmin`` find it for one curve."""
    v = np.asarray(rows, dtype=float)
    if not np.isfinite(v).all():  # NaN samples are ignored there: row by row
        return (np.array([first_argmax(r) for r in v]), np.array([first_argmin(r) for r in v]))
    low, high = np.min(v, axis=1, keepdims=True), np.max(v, axis=1, keepdims=True)
    band = EXTREMUM_RTOL * (high - low)
    return np.argmax(v >= high - band, axis=1), np.argmax(v <= low + band, axis=1)


def _forces_table(motion, pressures: dict, rod, resultant_Pa, torque_Nm) -> dict:
    """The forces table: the piston's motion, the pressures on the piston (Pa, per unit piston
    area), the rod's components, the resultant on the crank pin and the torque (N·m)."""
    return {
        "crank_angle_deg": motion.crank_angle_deg,
        "piston_displacement_m": motion.piston_displacement_m,
        "piston_velocity_m_s": motion.piston_velocity_m_s,
        "piston_acceleration_m_s2": motion.piston_acceleration_m_s2,
        **pressures,
        "side_Pa": rod.side_Pa,
        "rod_Pa": rod.rod_Pa,
        "radial_Pa": rod.radial_Pa,
        "tangential_Pa": rod.tangential_Pa,
        "resultant_Pa": resultant_Pa,
        "torque_Nm": torque_Nm,
    }


def _higher_orders_max_Pa(inertia_Pa, first_order_Pa, second_order_Pa) -> float:
    """Largest |p_j - (p_jI + p_jII)| over the cycle, Pa: p_j from the mechanism's own (exact)
    acceleration against the textbook's two terms (Poda 2007, eq. 19), i.e. the terms of order
    lambda^3 and up; zero for the approximate kinematics."""
    return float(np.max(np.abs(inertia_Pa - first_order_Pa - second_order_Pa)))


def _offset_remainder(motion, curves: dict, reciprocating: float, area: float) -> dict:
    """An offset crank-slider's p_j - (p_jI + p_jII) in its two parts, Pa: the terms of order
    lambda^3 and up (the central crank-slider's of the same R and lambda) and the terms the
    offset adds (its p_j against that central one's), each its largest over the cycle, with the
    crank's angle from the cylinder axis at TDC (deg), the angle the rod force is resolved at."""
    offset = motion.extra.get("offset_m", 0.0)
    if not offset:
        return {}
    alpha, radius, omega = (
        motion.crank_angle_rad,
        motion.crank_radius_m,
        motion.angular_velocity_rad_s,
    )
    central_Pa = phys.inertia_pressure_Pa(
        reciprocating,
        kin.piston_acceleration_exact_m_s2(alpha, radius, motion.extra["rod_ratio"], omega),
        area,
    )
    return {
        "crank_angle_at_tdc_deg": float(
            np.degrees(motion.extra.get("crank_angle_at_tdc_rad", 0.0))
        ),
        "inertia_higher_orders_central_max_Pa": float(
            np.max(np.abs(central_Pa - curves["first_Pa"] - curves["second_Pa"]))
        ),
        "inertia_offset_terms_max_Pa": float(np.max(np.abs(curves["inertia_Pa"] - central_Pa))),
    }


def _offset_side_force(motion, curves: dict, strokes: int) -> dict:
    """An offset crank-slider's side force against the central one's with the same axial force
    p₁ (the central mechanism's rod angle, sin β = λ sin α, at the same angle from TDC), Pa:
    its largest on the power stroke (from the firing TDC to the BDC after it; positive, on the
    thrust side, as the sign rule has it) and its largest magnitude on the other strokes."""
    offset = motion.extra.get("offset_m", 0.0)
    if not offset or motion.rod_angle_rad is None:
        return {}
    alpha = np.asarray(motion.crank_angle_rad, dtype=float)
    total = np.asarray(curves["total_Pa"], dtype=float)
    side = total * np.tan(np.asarray(motion.rod_angle_rad, dtype=float))
    central = total * np.tan(kin.rod_angle_rad(alpha, motion.extra["rod_ratio"]))
    firing = 360.0 if strokes == 4 else 0.0  # the cycle starts at the intake TDC (four-stroke)
    bdc = float(motion.extra.get("bdc_crank_angle_deg", 180.0))
    angle = np.degrees(alpha)
    power = (angle >= firing) & (angle <= firing + bdc)
    return {
        "side_power_stroke_max_Pa": float(side[power].max()),
        "side_power_stroke_central_max_Pa": float(central[power].max()),
        "side_other_strokes_max_abs_Pa": float(np.abs(side[~power]).max()),
        "side_other_strokes_central_max_abs_Pa": float(np.abs(central[~power]).max()),
    }


def _effective(engine, gas) -> dict:
    """A single cylinder's N_e against its N_i (η_m, M_e), when the scene gives N_e; an engine of
    more cylinders has them in the torque section."""
    if engine.cylinders != 1 or engine.effective_power is None:
        return {}
    cycles_per_s = engine.rpm / 60.0 / (engine.strokes / 2)
    return phys_crankshaft.effective_output(
        gas.indicated_work_J * cycles_per_s,
        engine.effective_power,
        engine.angular_velocity_rad_s,
        pumping_power_W=gas.pumping_work_J * cycles_per_s,
    )


def run(scene, inputs) -> StageOutput:
    series, finish = _forces(scene, inputs)
    return finish(_extremes_many(inputs[KINEMATICS].crank_angle_deg, [series])[0])


def run_many(scenes, inputs) -> list[StageOutput]:
    """``run`` over many scenes at once (a sweep's points): the forces over points x angles, the
    extremes of every point's seven curves over (points x curves) x angles; the same data and
    results as ``run``. Scenes on other angle grids: ``run`` one by one."""
    angle = inputs[0][KINEMATICS].crank_angle_deg
    if not all(np.array_equal(given[KINEMATICS].crank_angle_deg, angle) for given in inputs):
        return [run(scene, given) for scene, given in zip(scenes, inputs, strict=False)]
    curves = _curves_many(scenes, inputs)
    parts = [
        _forces(scene, given, c) for scene, given, c in zip(scenes, inputs, curves, strict=False)
    ]
    extremes = _extremes_many(angle, [series for series, _ in parts])
    return [finish(found) for (_, finish), found in zip(parts, extremes, strict=False)]


def _master_reduced_mass(scene) -> dict:
    """Articulated rods: the master cylinder's reciprocating mass with the slave rods' shares at
    its piston pin (the reduced master rod, Poda 2007 fig. 9), kg, which the bays and the
    balancing take; this section's table keeps the master rod's own split. {} for other rods."""
    if scene.engine.rod_type != "articulated":
        return {}
    layout = engine_layout(scene)
    opts = options(scene, "articulated", ArticulatedOptions)
    master, _ = articulated_reciprocating_masses_kg(scene, layout, opts, "articulated")
    return {"master_reduced_reciprocating_mass_kg": master}


def _masses(scene) -> tuple[float, float, float, float]:
    """(reciprocating, rotating, the rod's reciprocating, the rod's rotating) mass of ``scene``,
    kg."""
    engine, masses = scene.engine, scene.masses
    rod_reciprocating, rod_rotating = phys.rod_mass_split_kg(
        masses.rod, engine.rod_length_m, scene.rod_cm_from_big_end_m
    )
    reciprocating = masses.piston_group + rod_reciprocating
    rotating = rod_rotating + masses.crank_pin + 2.0 * masses.crank_web
    return reciprocating, rotating, rod_reciprocating, rod_rotating


def _curves(
    alpha,
    crank_from_axis,
    beta,
    pressure_Pa,
    acceleration_m_s2,
    crankcase_Pa,
    radius,
    omega,
    ratio,
    area,
    reciprocating,
    rotating,
    rod_rotating,
) -> dict:
    """The specific forces (Pa) over the crank angles ``alpha`` (rad): one mechanism's numbers as
    scalars and its curves as 1-D arrays, or many mechanisms' numbers as columns (points, 1) and
    their curves as rows (points x angles); ``rod`` holds the rod's components."""
    gas_Pa = pressure_Pa - crankcase_Pa
    inertia_Pa = phys.inertia_pressure_Pa(reciprocating, acceleration_m_s2, area)
    total_Pa = gas_Pa + inertia_Pa
    rod = phys.rod_force_components(total_Pa, crank_from_axis, beta)
    centrifugal_Pa = phys.centrifugal_pressure_Pa(rotating, radius, omega, area)
    return {
        "gas_Pa": gas_Pa,
        "inertia_Pa": inertia_Pa,
        "total_Pa": total_Pa,
        "rod": rod,
        "first_Pa": phys.inertia_pressure_first_order_Pa(reciprocating, alpha, radius, omega, area),
        "second_Pa": phys.inertia_pressure_second_order_Pa(
            reciprocating, alpha, radius, ratio, omega, area
        ),
        "centrifugal_Pa": centrifugal_Pa,
        "centrifugal_rod_Pa": phys.centrifugal_pressure_Pa(rod_rotating, radius, omega, area),
        "resultant_Pa": phys.resultant_crank_pin_pressure_Pa(
            rod.tangential_Pa, rod.radial_Pa, centrifugal_Pa
        ),
        "torque_Nm": phys.crank_torque_Nm(rod.tangential_Pa, radius, area),
        # the inertia force's own torque: its cycle integral is the inertia work, zero for a
        # consistent kinematic model (a check of the kinematics the report prints)
        "inertia_torque_Nm": phys.crank_torque_Nm(
            phys.rod_force_components(inertia_Pa, crank_from_axis, beta).tangential_Pa, radius, area
        ),
    }


def _beta(motion, alpha):
    # The rod resolves p1 at the crank's angle from the cylinder axis: alpha, unless the
    # mechanism counts alpha from a TDC off the axis (offset crank). A mechanism without a
    # rod (rod_angle_rad None, e.g. a Scotch yoke) passes the force along the axis (beta = 0).
    crank_from_axis = alpha + motion.extra.get("crank_angle_at_tdc_rad", 0.0)
    beta = motion.rod_angle_rad if motion.rod_angle_rad is not None else np.zeros_like(alpha)
    return crank_from_axis, beta


def _curves_many(scenes, inputs) -> list[dict]:
    """:func:`_curves` of each scene, computed over points x angles (the scenes share the grid)."""
    motions = [given[KINEMATICS] for given in inputs]
    alpha = motions[0].crank_angle_rad
    angles = [_beta(m, alpha) for m in motions]

    def column(values):
        return np.asarray(values, dtype=float)[:, None]

    masses = [_masses(scene) for scene in scenes]
    many = _curves(
        alpha,
        np.stack([a for a, _ in angles]),
        np.stack([b for _, b in angles]),
        np.stack([given[GAS_PRESSURE].pressure_Pa for given in inputs]),
        np.stack([m.piston_acceleration_m_s2 for m in motions]),
        column([s.engine.crankcase_pressure for s in scenes]),
        column([m.crank_radius_m for m in motions]),
        column([m.angular_velocity_rad_s for m in motions]),
        column([s.engine.rod_ratio_value for s in scenes]),
        column([phys.piston_area_m2(s.engine.bore) for s in scenes]),
        *(column(values) for values in zip(*[m[:2] + m[3:] for m in masses], strict=False)),
    )
    out = []
    for k in range(len(scenes)):
        curves = {key: value[k] for key, value in many.items() if key != "rod"}
        curves["centrifugal_Pa"] = float(many["centrifugal_Pa"][k, 0])  # a column: one number
        curves["centrifugal_rod_Pa"] = float(many["centrifugal_rod_Pa"][k, 0])
        curves["rod"] = phys.RodForces(*(np.asarray(part)[k] for part in many["rod"]))
        out.append(curves)
    return out


def _forces(scene, inputs, curves: dict | None = None):
    """(the curves whose extremes the results give, ``finish(extremes) -> StageOutput``) of
    ``scene``: everything of ``run`` but the extremes, which ``_extremes_many`` finds; ``curves``
    its :func:`_curves` when ``run_many`` has computed them."""
    motion, gas = inputs[KINEMATICS], inputs[GAS_PRESSURE]
    engine = scene.engine
    radius = motion.crank_radius_m
    area = phys.piston_area_m2(engine.bore)
    masses = _masses(scene)
    if curves is None:
        curves = _scene_curves(scene, motion, gas, area, masses)
    rod, resultant_Pa, torque = curves["rod"], curves["resultant_Pa"], curves["torque_Nm"]
    exact = _exact_rod_loads(
        scene, motion, curves["gas_Pa"], area, rod, curves["centrifugal_rod_Pa"]
    )
    if exact is not None:
        rod = exact["rod"]
        resultant_Pa = phys.resultant_crank_pin_pressure_Pa(
            rod.tangential_Pa, rod.radial_Pa, curves["centrifugal_Pa"]
        )
        torque = phys.crank_torque_Nm(rod.tangential_Pa, radius, area)
    results = _forces_results(engine, motion, gas, curves, masses, area, torque)
    results.update(_master_reduced_mass(scene))
    series = (
        ("total", "Pa", curves["total_Pa"]),
        ("side", "Pa", rod.side_Pa),
        ("rod", "Pa", rod.rod_Pa),
        ("tangential", "Pa", rod.tangential_Pa),
        ("radial", "Pa", rod.radial_Pa),
        ("resultant", "Pa", resultant_Pa),
        ("torque", "Nm", torque),
    )

    def finish(extremes: dict) -> StageOutput:
        results.update(extremes)
        loads = (rod, resultant_Pa, torque)
        return _forces_output(results, scene, motion, curves, loads, exact, area)

    return series, finish


def _scene_curves(scene, motion, gas, area: float, masses) -> dict:
    """The force and torque curves of one scene (:func:`_curves`)."""
    engine = scene.engine
    reciprocating, rotating, _, rod_rotating = masses
    alpha = motion.crank_angle_rad
    crank_from_axis, beta = _beta(motion, alpha)
    return _curves(
        alpha,
        crank_from_axis,
        beta,
        gas.pressure_Pa,
        motion.piston_acceleration_m_s2,
        engine.crankcase_pressure,
        motion.crank_radius_m,
        motion.angular_velocity_rad_s,
        engine.rod_ratio_value,
        area,
        reciprocating,
        rotating,
        rod_rotating,
    )


def _forces_results(engine, motion, gas, curves: dict, masses, area: float, torque) -> dict:
    """The stage's results but the extremes: piston area, masses, centrifugal and inertia
    pressures, the mean torque against the indicated work's and the inertia torque's work."""
    reciprocating, rotating, rod_reciprocating, rod_rotating = masses
    centrifugal_Pa, inertia_torque = curves["centrifugal_Pa"], curves["inertia_torque_Nm"]
    revolutions_per_cycle = engine.strokes / 2
    mean_torque = float(np.mean(torque))
    mean_from_work = gas.indicated_work_J / (2 * np.pi * revolutions_per_cycle)
    cycle_rad = 2 * np.pi * revolutions_per_cycle
    results = {
        "piston_area_m2": area,
        "reciprocating_mass_kg": reciprocating,
        "rod_reciprocating_mass_kg": rod_reciprocating,
        "rod_rotating_mass_kg": rod_rotating,
        "rotating_mass_kg": rotating,
        "centrifugal_Pa": centrifugal_Pa,
        "centrifugal_rod_Pa": curves["centrifugal_rod_Pa"],
        "centrifugal_N": centrifugal_Pa * area,
        "inertia_tdc_Pa": float(
            phys.inertia_pressure_Pa(reciprocating, motion.piston_acceleration_m_s2[0], area)
        ),
        "inertia_higher_orders_max_Pa": _higher_orders_max_Pa(
            curves["inertia_Pa"], curves["first_Pa"], curves["second_Pa"]
        ),
        "mean_torque_Nm": mean_torque,
        "mean_torque_from_work_Nm": mean_from_work,
        "mean_torque_deviation_percent": 100.0 * (mean_torque - mean_from_work) / mean_from_work
        if mean_from_work != 0
        else None,
        "inertia_work_J": float(np.mean(inertia_torque) * cycle_rad),
        "inertia_work_relative": float(np.mean(inertia_torque) / np.max(np.abs(inertia_torque)))
        if np.max(np.abs(inertia_torque)) > 0
        else 0.0,
    }
    results.update(_effective(engine, gas))
    results.update(_offset_remainder(motion, curves, reciprocating, area))
    results.update(_offset_side_force(motion, curves, engine.strokes))
    return results


def _forces_output(results: dict, scene, motion, curves: dict, loads, exact, area: float):
    """The stage's output from its complete ``results``: the forces handed on, the forces table
    (the exact rod model's columns last) and the notes."""
    rod, resultant_Pa, torque = loads
    engine = scene.engine
    pressures = {
        "gas_Pa": curves["gas_Pa"],
        "inertia_Pa": curves["inertia_Pa"],
        "inertia_first_order_Pa": curves["first_Pa"],
        "inertia_second_order_Pa": curves["second_Pa"],
        "total_Pa": curves["total_Pa"],
    }
    frame = _forces_table(motion, pressures, rod, resultant_Pa, torque)
    notes = []
    if exact is not None:
        results["rod_model"] = "exact"
        results["exact_rod"] = exact["results"]
        frame = {**frame, **exact["columns"]}  # as DataFrame.assign: new columns last
        notes.append(
            (
                "forces.note_exact_rod",
                {k: v for k, v in exact["results"].items() if k in _NOTE_KEYS},
            )
        )
    data = CrankForces(
        crank_angle_deg=motion.crank_angle_deg,
        gas_Pa=curves["gas_Pa"],
        inertia_Pa=curves["inertia_Pa"],
        total_Pa=curves["total_Pa"],
        tangential_Pa=rod.tangential_Pa,
        radial_Pa=rod.radial_Pa,
        centrifugal_Pa=curves["centrifugal_Pa"],
        piston_area_m2=area,
        torque_Nm=torque,
        side_Pa=rod.side_Pa,
        rod_Pa=rod.rod_Pa,
    )
    # a spark-ignition two-stroke is scavenged by its crankcase; a diesel one by a blower or a
    # turbocharger, with a space of constant pressure under its piston
    crankcase_scavenged = (
        engine.strokes == 2 and scene.cycle is not None and scene.cycle.ignition == "spark"
    )
    notes = [
        (
            "forces.note_gauge" + ("_two_stroke" if crankcase_scavenged else ""),
            {"p0": engine.crankcase_pressure / 1e6},
        ),
        _inertia_work_note(results["inertia_work_relative"]),
    ] + notes
    return StageOutput(data={FORCES: data}, results=results, tables={"forces": frame}, notes=notes)


#: A relative work of the inertia forces below this is rounding: the note says it is zero.
ROUNDING_LEVEL = 1e-12


def _inertia_work_note(relative: float) -> tuple[str, dict]:
    """The note on the inertia forces' net work over the cycle, zero for a consistent kinematic
    model: "zero to rounding" where it is (a number such as 1,5·10⁻¹⁷ only says two sums agree),
    else the relative value."""
    if abs(relative) < ROUNDING_LEVEL:
        return ("forces.note_inertia_work_zero", {})
    return ("forces.note_inertia_work", {"relative": abs(relative)})


_NOTE_KEYS = (
    "crank_pin_difference_max_N",
    "crank_pin_two_mass_max_N",
    "side_exact_max_N",
    "side_two_mass_max_N",
    "wrist_pin_difference_max_N",
)


def _exact_rod_loads(scene, motion, gas_Pa, area, rod, centrifugal_rod_Pa) -> dict | None:
    """With ``[rod_dynamics] apply_to_loads = true``: the rod as a rigid body (physics.rod_loads) in place
    of the two-mass split, as specific forces for the later stages, and the difference to the two-mass loads.

    The radial force handed on is Z_exact - c_rod, so that the stages adding the rods' centrifugal
    force c_rod (crank-pin load, bays) get the exact load.
    """
    if not options(scene, "rod_dynamics", RodDynamicsOptions).apply_to_loads:
        return None
    e, m = scene.engine, scene.masses
    if m.rod_moment_of_inertia is None:
        raise SceneError(
            Problem("rod_dynamics.apply_to_loads", True, "needs masses.rod_moment_of_inertia (I_G)")
        )
    if e.mechanism != "crank_slider" or e.rod_type == "articulated":
        raise SceneError(
            Problem(
                "rod_dynamics.apply_to_loads",
                True,
                "is built for the central crank-slider with central or fork rods",
            )
        )
    alpha, omega = motion.crank_angle_rad, motion.angular_velocity_rad_s
    accel = kin.rod_angular_acceleration_rad_s2(alpha, e.rod_ratio_value, omega)
    loads = rod_loads.exact_rod_loads_N(
        alpha,
        motion.crank_radius_m,
        e.rod_length_m,
        scene.rod_cm_from_big_end_m,
        m.rod,
        m.rod_moment_of_inertia,
        m.piston_group,
        omega,
        gas_Pa * area,
        motion.rod_angle_rad,
        accel,
        motion.piston_acceleration_m_s2,
    )
    c_rod = centrifugal_rod_Pa * area
    pin_two = np.hypot(rod.tangential_Pa * area, (rod.radial_Pa + centrifugal_rod_Pa) * area)
    pin_exact = np.hypot(loads.crank_pin_tangential_N, loads.crank_pin_radial_N)
    pin_diff = np.hypot(
        loads.crank_pin_tangential_N - rod.tangential_Pa * area,
        loads.crank_pin_radial_N - (rod.radial_Pa * area + c_rod),
    )
    side_two = rod.side_Pa * area
    # two-mass wrist pin: the piston's axial force (same in both models) and the side force p1 tan b
    wrist_diff = np.abs(loads.wrist_pin_lateral_N - side_two)
    exact_rod = phys.RodForces(
        side_Pa=loads.side_N / area,
        rod_Pa=loads.rod_axial_N / area,
        tangential_Pa=loads.crank_pin_tangential_N / area,
        radial_Pa=loads.crank_pin_radial_N / area - centrifugal_rod_Pa,
    )
    results = {
        "crank_pin_exact_max_N": float(np.max(pin_exact)),
        "crank_pin_two_mass_max_N": float(np.max(pin_two)),
        "crank_pin_difference_max_N": float(np.max(pin_diff)),
        "crank_pin_difference_max_crank_angle_deg": float(
            motion.crank_angle_deg[first_argmax(pin_diff)]
        ),
        "side_exact_max_N": float(np.max(np.abs(loads.side_N))),
        "side_two_mass_max_N": float(np.max(np.abs(side_two))),
        "wrist_pin_difference_max_N": float(np.max(wrist_diff)),
        "torque_difference_max_Nm": float(
            np.max(np.abs(loads.crank_pin_tangential_N - rod.tangential_Pa * area))
            * motion.crank_radius_m
        ),
    }
    columns = {
        "crank_pin_tangential_N": loads.crank_pin_tangential_N,
        "crank_pin_radial_N": loads.crank_pin_radial_N,
        "crank_pin_tangential_two_mass_N": rod.tangential_Pa * area,
        "crank_pin_radial_two_mass_N": rod.radial_Pa * area + c_rod,
        "wrist_pin_axial_N": loads.wrist_pin_axial_N,
        "wrist_pin_lateral_N": loads.wrist_pin_lateral_N,
        "side_N": loads.side_N,
        "side_two_mass_N": side_two,
    }
    return {"rod": exact_rod, "results": results, "columns": columns}
