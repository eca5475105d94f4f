"""The flywheel by the energy method: excess work, cyclic irregularity, inertia, rim."""

from __future__ import annotations

import math

import numpy as np

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import flywheel as fw
from crankdyn.physics import layout as lay
from crankdyn.physics import speed_fluctuation as sf
from crankdyn.plugin.contracts import (
    BAY_LOADS,
    COUNTERWEIGHTS,
    ENGINE_TORQUE,
    FLYWHEEL,
    FlywheelDesign,
    RodDynamicsOptions,
)
from crankdyn.plugin.scene_inputs import crank_train
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

from .options import FlywheelOptions

#: Above this irregularity the energy method (a first-order expansion in delta) is refused.
MAX_ENERGY_METHOD_IRREGULARITY = 0.5


#: The irregularity suggested when a chosen flywheel is refused as too small.
SUGGESTED_IRREGULARITY = 0.2

#: The significant digits a course note prints the exact δ with (its speed-fluctuation
#: section): an exact δ above [δ] by less than these digits show is taken as meeting [δ] (the
#: printed δ equals it); one that shows above it raises the flywheel.
PRINTED_DELTA_DIGITS = 4


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
        raise SceneError(
            Problem(
                "flywheel.rim_mean_diameter",
                f"{opts.rim_mean_diameter * 1e3:g} mm",
                f"too small for the flywheel: {exc}; choose a larger mean diameter",
            )
        ) from None
    speed = omega_rad_s * rim.outer_diameter_m / 2
    rim_results = {
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
        **_strength(opts.rim_density, fw.rim_hoop_stress_Pa(opts.rim_density, speed)),
        "max_speed_m_s": opts.max_rim_speed,
        "speed_ok": None if opts.max_rim_speed is None else bool(speed <= opts.max_rim_speed),
        "passing": None,
    }
    if rim_results["speed_ok"] is False:
        rim_results["passing"] = _passing_rim(opts, rim_inertia, omega_rad_s)
    return rim_results


def _passing_rim(opts, rim_inertia_kg_m2: float, omega_rad_s: float) -> dict | None:
    """The rim of the largest mean diameter, in whole millimetres, whose outer edge keeps to the
    allowed peripheral speed (:func:`fw.largest_rim_mean_diameter_m`), as the rim's keys give
    it; None when no rim of this material and width does."""
    largest = fw.largest_rim_mean_diameter_m(
        rim_inertia_kg_m2, opts.rim_density, 2.0 * opts.max_rim_speed / omega_rad_s, opts.rim_width
    )
    if largest is None or largest < 2e-3:
        return None
    whole_mm = math.floor(largest * 1e3 * (1.0 - 1e-9)) / 1e3  # within the limit after rounding
    rim = fw.rim_design(rim_inertia_kg_m2, whole_mm, opts.rim_density, opts.rim_width)
    return {
        "mean_diameter_m": rim.mean_diameter_m,
        "outer_diameter_m": rim.outer_diameter_m,
        "width_m": rim.width_m,
        "thickness_m": rim.thickness_m,
        "mass_kg": rim.mass_kg,
        "speed_m_s": omega_rad_s * rim.outer_diameter_m / 2,
    }


#: The material a rim density stands for and its tensile strength, Pa, from its standard: grey
#: cast iron СЧ 20 (ГОСТ 1412-85: at least 200 MPa) for 7000-7400 kg/m³, steel 45 (ГОСТ 1050:
#: 600 MPa) for 7700-7900 kg/m³; a rim of another density is not judged.
RIM_STRENGTHS = (
    ("cast_iron", 7000.0, 7400.0, 200e6, "gost1412"),
    ("steel", 7700.0, 7900.0, 600e6, "gost1050"),
)


def _strength(density_kg_m3: float, hoop_stress_Pa: float) -> dict:
    """The rim's material grade, its tensile strength and the margin strength/stress (the
    factor of safety of a thin rotating ring), or {} for a density of no listed material."""
    for material, low, high, strength_Pa, source in RIM_STRENGTHS:
        if low <= density_kg_m3 <= high:
            return {
                "strength_material": material,
                "tensile_strength_Pa": strength_Pa,
                "strength_margin": strength_Pa / hoop_stress_Pa if hoop_stress_Pa > 0 else None,
                "strength_source": source,
            }
    return {}


def is_propeller(scene) -> bool:
    """An aircraft engine: its propeller takes the flywheel's part, and has no rim to size."""
    return scene.engine.application == "aircraft"


def propeller_rim(scene, results=None) -> list[tuple[str, dict]]:
    """Rim fields given for an aircraft engine, whose propeller has no rim: left out, said on
    the console."""
    if not is_propeller(scene) or applies(scene) is not None:
        return []
    opts = options(scene, "flywheel", FlywheelOptions)
    if opts.rim_mean_diameter is None:
        return []
    return [("flywheel.plausibility_propeller_rim", {"diameter": opts.rim_mean_diameter * 1e3})]


def _refuse_a_stalling_flywheel(irregularity, flywheel, own, excess_work_J, omega) -> None:
    """A flywheel so light that the speed would swing by more than the energy method holds for
    (the crankshaft nearly stops) is refused, with the flywheel that would do."""
    if irregularity <= MAX_ENERGY_METHOD_IRREGULARITY:
        return
    needed = max(
        fw.required_inertia_kg_m2(excess_work_J, SUGGESTED_IRREGULARITY, omega) - own,
        0.0,
    )
    raise SceneError(
        Problem(
            "flywheel.inertia",
            f"{flywheel:.4g} kg*m^2",
            f"too small: with the engine's own {own:.4g} kg*m^2 the speed would swing by "
            f"delta = {irregularity:.3g} of its mean every cycle (the crankshaft nearly stops), "
            f"where neither the energy method nor the torque diagram computed at constant speed "
            f"holds; a flywheel of at least {needed:.3g} kg*m^2 gives delta = "
            f"{SUGGESTED_IRREGULARITY:g}",
        )
    )


def torque_period_deg(torque) -> float:
    """The period (deg) the output torque repeats with: the firing interval for even firing of
    identical cylinders, else up to the whole cycle."""
    angle = torque.crank_angle_deg
    return lay.sampled_period_deg(
        torque.torque_Nm, float(angle[1] - angle[0]), 180.0 * torque.strokes
    )


def _excess_results(excess, torque) -> dict:
    """The mean torque, the excess work ΔL, where the work is largest and least (the first
    such angles in the cycle: W repeats with the torque), and ΔL per cycle's work (done or, by a
    driven machine, taken in; None when the mean torque is zero)."""
    period = torque_period_deg(torque)
    return {
        "mean_torque_Nm": excess.mean_torque_Nm,
        "excess_work_J": excess.excess_work_J,
        "torque_period_deg": period,
        "excess_work_max_crank_angle_deg": float(torque.crank_angle_deg[excess.max_index]) % period,
        "excess_work_min_crank_angle_deg": float(torque.crank_angle_deg[excess.min_index]) % period,
        # against the work per cycle done (an engine) or taken in (a driven compressor, M_m < 0)
        "excess_work_relative": excess.excess_work_J
        / (abs(excess.mean_torque_Nm) * 2 * math.pi * torque.strokes / 2)
        if excess.mean_torque_Nm != 0
        else None,
    }


#: The speeds, as fractions of the scene's, at which the note gives δ with the same J and
#: cylinder pressures.
LOWER_SPEED_FRACTIONS = (0.75, 0.5, 0.25)


def _gas_results(scene, torque, train, total_inertia_kg_m2: float, required, irregularity):
    """ΔL of the gas forces' torque alone (``excess_work_gas_J``, None without it) and
    :func:`lower_speeds`, from the one gas torque of :func:`gas_torque_Nm`."""
    gas = gas_torque_Nm(scene, torque, train)
    alpha = np.radians(torque.crank_angle_deg)
    own = None if gas is None else float(fw.excess_work(alpha, gas).excess_work_J)
    return {
        "excess_work_gas_J": own,
        **lower_speeds(scene, torque, gas, total_inertia_kg_m2, required, irregularity),
    }


def lower_speeds(scene, torque, gas, total_inertia_kg_m2: float, required, irregularity) -> dict:
    """ΔL and δ with the same cylinder pressures (the gas torque ``gas``, :func:`gas_torque_Nm`)
    and the same J at :data:`LOWER_SPEED_FRACTIONS` of the scene's speed
    (:func:`fw.excess_work_at_speed_J`), and the highest speed below the scene's at which δ
    reaches the ``required`` one (scanned down in steps of 1 % of the speed to a tenth of it,
    interpolated between the two steps about [δ], to three significant digits; None if it does
    not, if δ at the given speed, ``irregularity``, meets [δ] only just, or none is required);
    both None without a gas torque."""
    if gas is None:
        return {"lower_speeds": None, "required_irregularity_reached_rpm": None}
    omega = torque.angular_velocity_rad_s
    alpha = np.radians(torque.crank_angle_deg)
    inertia = np.asarray(torque.torque_Nm) - gas

    # the rows' speeds and every 1 % of the speed from 99 % down to 10 %, at once
    fractions = np.concatenate([LOWER_SPEED_FRACTIONS, np.arange(99, 9, -1) / 100])
    excess = fw.excess_work_at_speed_J(alpha, gas, inertia, fractions)
    deltas = fw.cyclic_irregularity(excess, total_inertia_kg_m2, fractions * omega)
    count = len(LOWER_SPEED_FRACTIONS)
    rows = [
        {
            "speed_fraction": k,
            "rpm": k * scene.engine.rpm,
            "excess_work_J": float(excess[i]),
            "irregularity": float(deltas[i]),
        }
        for i, k in enumerate(LOWER_SPEED_FRACTIONS)
    ]
    reached = None
    # where δ at the given speed is clearly below [δ] (the engine's own inertia or a given
    # flywheel; a designed one meets [δ] there, and any lower speed exceeds it)
    if required is not None and irregularity < 0.99 * required:
        scan = np.flatnonzero(deltas[count:] >= required)
        if scan.size:
            # between the scan's last speed below [δ] (or the given one) and its first above,
            # δ varies smoothly: interpolated linearly, to three significant digits
            hit = count + scan[0]
            upper, above = (
                (1.0, irregularity) if scan[0] == 0 else (fractions[hit - 1], deltas[hit - 1])
            )
            lower, below = fractions[hit], deltas[hit]
            fraction = upper + (required - above) * (lower - upper) / (below - above)
            reached = float(f"{fraction * scene.engine.rpm:.3g}")
    return {"lower_speeds": rows, "required_irregularity_reached_rpm": reached}


def gas_torque_Nm(scene, torque, train):
    """The gas forces' torque alone, N·m: the output torque with the reciprocating masses'
    inertia torque −½J′(α)ω² taken out (:func:`sf.gas_torque_Nm`), which shows how much of ΔL
    the inertia forces make at the scene's speed; None where the loads take the rod as a rigid
    body (``[rod_dynamics] apply_to_loads``), whose inertia torque the two-mass J(α) does not
    hold."""
    if options(scene, "rod_dynamics", RodDynamicsOptions).apply_to_loads:
        return None
    _, derivative = train.series()(np.radians(torque.crank_angle_deg))
    return sf.gas_torque_Nm(torque.torque_Nm, derivative, torque.angular_velocity_rad_s)


def exact_design(torque, train, engine_inertia, required_irregularity, energy_flywheel):
    """The exact periodic solution's check of the energy method's flywheel: (the exact δ with it,
    the flywheel for which that solution gives ``required_irregularity``, or None when the exact δ
    meets it as printed); (None, None) when there is no periodic solution (the speed-fluctuation
    stage says why)."""
    omega = torque.angular_velocity_rad_s
    alpha = np.radians(torque.crank_angle_deg)

    def inertia_with(flywheel):
        return train.series(flywheel + engine_inertia)

    _, derivative = inertia_with(energy_flywheel)(alpha)
    gas = sf.PeriodicSeries.from_samples(
        sf.gas_torque_Nm(torque.torque_Nm, derivative, omega), math.pi * torque.strokes
    )
    try:
        exact = sf.periodic_speed(gas, inertia_with(energy_flywheel), omega).irregularity
        if float(f"{exact:.{PRINTED_DELTA_DIGITS}g}") <= required_irregularity:
            return exact, None
        design = sf.flywheel_for_irregularity(
            gas, inertia_with, omega, required_irregularity, energy_flywheel
        )
    except (ValueError, RuntimeError):  # no periodic solution with a positive speed
        return None, None
    return exact, design


def _raise_results(exact_energy, raised, energy_flywheel) -> dict:
    """The exact periodic solution's δ with the energy method's flywheel, and whether (and by how
    many percent) the flywheel is raised to the one for which that solution gives [δ]."""
    return {
        "energy_flywheel_exact_irregularity": exact_energy,
        "flywheel_raised": raised is not None,
        "flywheel_raise_percent": (
            100.0 * (raised / energy_flywheel - 1.0)
            if raised is not None and energy_flywheel
            else None
        ),
    }


def _balancing_inertia(inputs) -> tuple[float, float, int]:
    """(Σ m ρ² of the counterweights the balancing fits, which turn with the shaft; Σ m ρ² n² of
    its balance shafts' masses, reduced to the crankshaft, kg m² (0 without them); how many
    balance shafts there are)."""
    fitted = inputs.get(COUNTERWEIGHTS)
    if fitted is None:
        return 0.0, 0.0, 0
    return (
        fitted.moment_of_inertia_kg_m2,
        fitted.balance_shaft_inertia_kg_m2,
        fitted.balance_shafts,
    )


def _required(opts, excess_work_J: float, omega: float, own: float):
    """(J_0 for [δ], the flywheel J_0 − own, at least 0), kg m²; (None, None) without [δ]."""
    if opts.required_irregularity is None:
        return None, None
    total = fw.required_inertia_kg_m2(excess_work_J, opts.required_irregularity, omega)
    return total, max(total - own, 0.0)


def _notes(results: dict, articulated: bool) -> list:
    """The stage's notes: no flywheel needed (the engine's own inertia meets [δ]), articulated rods."""
    notes = [("flywheel.note_no_flywheel", {"own": results["own_inertia_kg_m2"]})]
    notes = notes if results["own_inertia_sufficient"] else []
    return notes + ([("flywheel.note_articulated", {})] if articulated else [])


def _reached_from(opts, raised, required_flywheel):
    """The [δ] whose speed :func:`lower_speeds` looks for: None for a flywheel designed for it
    (raised too), which meets [δ] at the given speed while any lower speed exceeds it."""
    designed = opts.inertia is None and (raised is not None or bool(required_flywheel))
    return None if designed else opts.required_irregularity


def run(scene, inputs) -> StageOutput:
    torque, bays = inputs[ENGINE_TORQUE], inputs[BAY_LOADS]
    opts = options(scene, "flywheel", FlywheelOptions)
    omega = torque.angular_velocity_rad_s
    alpha = np.radians(torque.crank_angle_deg)
    excess = fw.excess_work(alpha, torque.torque_Nm)
    train = crank_train(scene, bays)
    counterweights, balance_shafts, shaft_count = _balancing_inertia(inputs)
    fitted = counterweights + balance_shafts  # on the webs, geared to the shaft: constant, in J_m
    train_mean = train.series().mean_kg_m2
    mechanism = train_mean + fitted
    shaft = opts.engine_inertia + fitted  # the constant added to the crank train's J(α)
    own = mechanism + opts.engine_inertia
    required_total, required_flywheel = _required(opts, excess.excess_work_J, omega, own)
    flywheel = opts.inertia if opts.inertia is not None else required_flywheel
    exact_energy = raised = None
    # also when the energy method needs no flywheel: the engine's own inertia varies over the
    # cycle, and the exact solution may still exceed [δ] without one
    if opts.inertia is None and required_flywheel is not None:
        exact_energy, raised = exact_design(
            torque, train, shaft, opts.required_irregularity, required_flywheel
        )
    reached_from = _reached_from(opts, raised, required_flywheel)
    flywheel = raised if raised is not None else flywheel
    total = own + flywheel
    irregularity = fw.cyclic_irregularity(excess.excess_work_J, total, omega)
    _refuse_a_stalling_flywheel(irregularity, flywheel, own, excess.excess_work_J, omega)

    results: dict = {
        "angular_velocity_rad_s": omega,
        **_excess_results(excess, torque),
        "mechanism_inertia_mean_kg_m2": mechanism,
        "engine_inertia_kg_m2": opts.engine_inertia,
        "counterweight_inertia_kg_m2": counterweights,
        "balance_shaft_inertia_kg_m2": balance_shafts,
        "balance_shaft_count": shaft_count,
        "own_inertia_kg_m2": own,
        "required_irregularity": opts.required_irregularity,
        "required_total_inertia_kg_m2": required_total,
        "required_flywheel_inertia_kg_m2": required_flywheel,
        "flywheel_given": opts.inertia is not None,
        "flywheel_inertia_kg_m2": flywheel,
        **_raise_results(exact_energy, raised, required_flywheel),
        "total_inertia_kg_m2": total,
        "irregularity": irregularity,
        **_gas_results(scene, torque, train, total, reached_from, irregularity),
        "flywheel_share": flywheel / total,
        # J_0 - J_m - J_e as computed: negative when the engine's own inertia already meets [delta]
        "flywheel_inertia_difference_kg_m2": (
            required_total - own if required_total is not None else None
        ),
        "own_inertia_sufficient": required_flywheel == 0.0 and opts.inertia is None and not raised,
        "rim": None,
    }
    notes = _notes(results, train.articulated)
    if opts.rim_mean_diameter is not None and flywheel > 0 and not is_propeller(scene):
        results["rim"] = _rim(opts, flywheel, omega)

    frame = {"crank_angle_deg": torque.crank_angle_deg, "torque_Nm": torque.torque_Nm}
    frame["excess_work_J"] = excess.cumulative_J
    design = FlywheelDesign(
        flywheel_inertia_kg_m2=flywheel,
        engine_inertia_kg_m2=shaft,
        # the crank train's own mean: the counterweights and balance shafts are in the constant part
        mechanism_inertia_mean_kg_m2=train_mean,
        excess_work_J=excess.excess_work_J,
        irregularity=irregularity,
        required_irregularity=opts.required_irregularity,
        required_flywheel_inertia_kg_m2=required_flywheel,
        energy_flywheel_exact_irregularity=exact_energy if raised is not None else None,
        counterweight_inertia_kg_m2=counterweights,
        balance_shaft_inertia_kg_m2=balance_shafts,
    )
    return StageOutput(
        data={FLYWHEEL: design}, results=results, tables={"flywheel": frame}, notes=notes
    )
