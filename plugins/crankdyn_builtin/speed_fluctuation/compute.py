"""Crankshaft speed fluctuation as an initial-value problem; torsional multi-mass model.


The computation: ``applies``, ``run`` and their pure helpers.
"""

from __future__ import annotations

import math

import numpy as np

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import irregularity as irr
from crankdyn.physics import layout as lay
from crankdyn.physics import speed_fluctuation as sf
from crankdyn.plugin.contracts import BAY_LOADS, CRANK_LOADS, ENGINE_TORQUE, FLYWHEEL
from crankdyn.plugin.scene_inputs import crank_train
from crankdyn.plugin.types import StageOutput
from crankdyn.scene import options

from .options import TorsionOptions
from .solvers import METHODS, SINGLE_MASS_RTOL, SINGLE_MASS_RTOLS, _choice_record, _run_record
from .torsion import _torsion

#: Smallest speed, as a fraction of the mean, for which the model is accepted.
MIN_SPEED_FRACTION = 0.5


def applies(scene) -> str | None:
    if "flywheel" not in scene.plugin_tables():
        return "the scene has no [flywheel] table"
    if scene.masses is None:
        return "the scene has no [masses]"
    return None


def _single_mass(scene, torque, bays, design, train):
    omega_n = torque.angular_velocity_rad_s
    alpha = np.radians(torque.crank_angle_deg)
    period = math.pi * torque.strokes
    constant = design.flywheel_inertia_kg_m2 + design.engine_inertia_kg_m2
    inertia = train.series(constant)
    _, derivative = inertia(alpha)
    gas = sf.gas_torque_Nm(torque.torque_Nm, derivative, omega_n)
    gas_series = sf.PeriodicSeries.from_samples(gas, period)
    try:
        exact = sf.periodic_speed(gas_series, inertia, omega_n)
    except ValueError:
        exact = None
    if exact is None or exact.omega_min_rad_s < MIN_SPEED_FRACTION * exact.omega_mean_rad_s:
        raise SceneError(
            Problem(
                "flywheel.inertia",
                f"{design.flywheel_inertia_kg_m2:.4g} kg*m^2",
                "too small: with the variable inertia of the crank mechanisms the crankshaft would "
                "slow to less than half its mean speed once per cycle (or stop); give a larger "
                "flywheel or a smaller required_irregularity",
            )
        )
    return inertia, gas, gas_series, exact


def _flywheel_for(delta_required, design, gas_series, train, omega_n):
    """Flywheel inertia for which the exact periodic solution has the required irregularity (the
    flywheel stage's when it raised its flywheel to it: the same search on the same problem)."""
    if design.raised_by_exact_solution:
        return design.flywheel_inertia_kg_m2
    own = design.engine_inertia_kg_m2
    return sf.flywheel_for_irregularity(
        gas_series,
        lambda flywheel: train.series(flywheel + own),
        omega_n,
        delta_required,
        design.required_flywheel_inertia_kg_m2,
    )


def _energy_curve(torque, design, omega_n):
    """omega(alpha) of the energy method: omega_m + (W - W_mid) / (J omega_m), constant J."""
    alpha = np.radians(torque.crank_angle_deg)
    step = alpha[1] - alpha[0]
    excess = torque.torque_Nm - np.mean(torque.torque_Nm)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (excess[:-1] + excess[1:]) * step)])
    total = (
        design.flywheel_inertia_kg_m2
        + design.engine_inertia_kg_m2
        + design.mechanism_inertia_mean_kg_m2
    )
    return omega_n + (work - 0.5 * (work.max() + work.min())) / (total * omega_n)


def _single_mass_solvers(gas_series, inertia, exact, omega_n):
    rhs = sf.single_mass_rhs(gas_series, exact.load_torque_Nm, inertia)
    y0 = np.array([0.0, float(exact.omega_at(0.0))])
    span = (0.0, exact.cycle_time_s)
    # One degree of freedom: the linearisation d(omega_dot)/d(omega) = -J' omega / J is the only
    # eigenvalue (the angle does not feed back stiffly), so its largest value over the cycle decides.
    j, dj = inertia(exact.angle_rad)
    rate = float(np.max(np.abs(dj * exact.omega_rad_s / j)))
    # Wavenumbers of the series per radian of shaft angle are the orders per revolution.
    resolved = sf.significant_order(gas_series.wavenumbers, gas_series.coefficients[:, 0]) * omega_n
    choice = sf.choose_solver([-rate], exact.cycle_time_s, resolved)

    def atol(rtol):
        return [rtol * 1e-3, rtol * 1e-3 * omega_n]

    records = []
    for method in METHODS:
        for rtol in SINGLE_MASS_RTOLS:
            run = sf.run_solver(rhs, span, y0, method, rtol, atol(rtol))
            records.append(_run_record(run, sf.phase_error(run, exact)))
    chosen = sf.run_solver(
        rhs, span, y0, choice.method, SINGLE_MASS_RTOL, atol(SINGLE_MASS_RTOL), dense_output=True
    )
    times = np.linspace(0.0, exact.cycle_time_s, 4097)
    dense = chosen.sol(times)
    omega_solver = dense[1]
    w_max, w_min = float(omega_solver.max()), float(omega_solver.min())
    summary = _choice_record(choice, "single")
    chosen_error = sf.phase_error(chosen, exact)
    # the run the section quotes is in the table and the figure too, after its method's other runs
    last_of_method = max(i for i, r in enumerate(records) if r["method"] == choice.method)
    records.insert(last_of_method + 1, {**_run_record(chosen, chosen_error), "used": True})
    summary.update(
        {
            "rtol": SINGLE_MASS_RTOL,
            "steps": chosen.steps,
            "nfev": chosen.nfev,
            "time_s": chosen.time_s,
            "error_relative": chosen_error if math.isfinite(chosen_error) else None,
            "irregularity": (w_max - w_min) / (0.5 * (w_max + w_min)),
            "periodicity_error": float(abs(chosen.y[1, -1] - y0[1]) / omega_n),
            "end_angle_error_rad": float(chosen.y[0, -1] - gas_series.period_rad),
        }
    )
    return summary, records, (dense[0], omega_solver)


def speed_period_deg(torque, inertia_kg_m2) -> float:
    """The period (deg) the speed repeats with: that of the torque and of the reduced inertia
    together (the firing interval for even firing of identical cylinders), else the cycle."""
    angle = torque.crank_angle_deg
    step, cycle = float(angle[1] - angle[0]), 180.0 * torque.strokes
    periods = sorted(
        lay.sampled_period_deg(values, step, cycle) for values in (torque.torque_Nm, inertia_kg_m2)
    )
    ratio = periods[1] / periods[0]
    return periods[1] if abs(ratio - round(ratio)) < 1e-9 else cycle


def _speed_results(inertia, exact, design, summary: dict, records: list, period: float) -> dict:
    """The results of the exact periodic speed against the energy method's irregularity and
    flywheel, with the solvers' runs; the flywheel by the ODE and the torsion left to fill. The
    angles of the extreme speeds are the first in the cycle (the speed repeats every ``period``
    degrees)."""
    energy_delta = design.irregularity
    return {
        "speed_period_deg": period,
        "reference": "quadrature",
        "inertia_mean_kg_m2": inertia.mean_kg_m2,
        "counterweight_inertia_kg_m2": design.counterweight_inertia_kg_m2,
        "balance_shaft_inertia_kg_m2": design.balance_shaft_inertia_kg_m2,
        "inertia_min_kg_m2": float(np.min(exact.inertia_kg_m2)),
        "inertia_max_kg_m2": float(np.max(exact.inertia_kg_m2)),
        "load_torque_Nm": exact.load_torque_Nm,
        "omega_mean_rad_s": exact.omega_mean_rad_s,
        "omega_max_rad_s": exact.omega_max_rad_s,
        "omega_min_rad_s": exact.omega_min_rad_s,
        "omega_max_crank_angle_deg": math.degrees(exact.omega_max_angle_rad) % period,
        "omega_min_crank_angle_deg": math.degrees(exact.omega_min_angle_rad) % period,
        "cycle_time_s": exact.cycle_time_s,
        "irregularity": exact.irregularity,
        "irregularity_definition": "(omega_max - omega_min) / ((omega_max + omega_min) / 2)",
        "irregularity_time_mean": irr.irregularity_time_mean(
            exact.omega_max_rad_s, exact.omega_min_rad_s, exact.omega_mean_rad_s
        ),
        "irregularity_energy": energy_delta,
        "irregularity_deviation_percent": 100.0
        * (exact.irregularity - energy_delta)
        / energy_delta,
        "required_irregularity": design.required_irregularity,
        "flywheel_inertia_kg_m2": design.flywheel_inertia_kg_m2,
        "flywheel_inertia_energy_kg_m2": design.required_flywheel_inertia_kg_m2,
        "flywheel_raised": design.raised_by_exact_solution,
        "energy_flywheel_exact_irregularity": design.energy_flywheel_exact_irregularity,
        "flywheel_inertia_ode_kg_m2": None,
        "flywheel_inertia_deviation_percent": None,
        "solver": summary,
        "solvers": records,
        "torsion": None,
    }


def _flywheel_by_ode(design, gas_series, train, omega_n: float) -> dict:
    """The flywheel that gives the required irregularity by the equation of motion, and its
    deviation from the energy method's."""
    ode = _flywheel_for(design.required_irregularity, design, gas_series, train, omega_n)
    return {
        "flywheel_inertia_ode_kg_m2": ode,
        "flywheel_inertia_deviation_percent": (
            100.0
            * (ode - design.required_flywheel_inertia_kg_m2)
            / design.required_flywheel_inertia_kg_m2
        ),
    }


def run(scene, inputs) -> StageOutput:
    torque, bays, crank_loads, design = (
        inputs[ENGINE_TORQUE],
        inputs[BAY_LOADS],
        inputs[CRANK_LOADS],
        inputs[FLYWHEEL],
    )
    torsion_opts = (
        options(scene, "torsion", TorsionOptions) if "torsion" in scene.plugin_tables() else None
    )
    omega_n = torque.angular_velocity_rad_s
    train = crank_train(scene, bays)
    inertia, gas, gas_series, exact = _single_mass(scene, torque, bays, design, train)
    alpha = np.radians(torque.crank_angle_deg)
    j_grid, dj_grid = inertia(alpha)
    summary, records, (solver_alpha, solver_omega) = _single_mass_solvers(
        gas_series, inertia, exact, omega_n
    )

    period = speed_period_deg(torque, j_grid)
    results = _speed_results(inertia, exact, design, summary, records, period)
    if design.required_irregularity is not None and design.required_flywheel_inertia_kg_m2:
        results.update(_flywheel_by_ode(design, gas_series, train, omega_n))
    tables = {
        "speed_fluctuation": {
            "crank_angle_deg": torque.crank_angle_deg,
            "inertia_kg_m2": j_grid,
            "inertia_derivative_kg_m2": dj_grid,
            "gas_torque_Nm": gas,
            "omega_rad_s": exact.omega_at(alpha),
            "omega_energy_method_rad_s": _energy_curve(torque, design, omega_n),
            "omega_solver_rad_s": np.interp(alpha, solver_alpha, solver_omega),
        }
    }
    # the solvers' check against the exact solution is a full report's (``detail = "full"``)
    full = scene.report.detail == "full"
    notes = [("speed_fluctuation.note_reference", {})] if full else []
    notes += [
        (
            "speed_fluctuation.note_irregularity",
            {
                "midrange": results["irregularity"],
                "time_mean": results["irregularity_time_mean"],
                "omega_mid": 0.5 * (exact.omega_max_rad_s + exact.omega_min_rad_s),
                "omega_mean": exact.omega_mean_rad_s,
            },
        )
    ]
    if torsion_opts is not None:
        torsion, torsion_tables = _torsion(
            scene, torque, crank_loads, design, train, exact, torsion_opts
        )
        results["torsion"] = torsion
        tables.update(torsion_tables)
        if full and not torsion["steady_state"]["converged"]:  # a course note's section says it
            notes.append(
                (
                    "speed_fluctuation.note_not_converged",
                    {"cycles": torsion["steady_state"]["cycles"]},
                )
            )
    return StageOutput(data={}, results=results, tables=tables, notes=notes)
