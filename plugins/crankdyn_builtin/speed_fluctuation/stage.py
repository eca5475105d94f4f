"""Crankshaft speed fluctuation as an initial-value problem; torsional multi-mass model."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from markupsafe import Markup
from pydantic import BaseModel, BeforeValidator, ConfigDict, model_validator

from crankdyn.contracts import BAY_LOADS, CRANK_LOADS, ENGINE_TORQUE, FLYWHEEL
from crankdyn.errors import Problem, SceneError
from crankdyn.physics import irregularity as irr
from crankdyn.physics import speed_fluctuation as sf
from crankdyn.physics import torsion as tor
from crankdyn.plugin_types import Stage, StageOutput, Symbol
from crankdyn.report.figures import crank_angle_axis, new_figure
from crankdyn.report.i18n import superscript
from crankdyn.scene import number as _number
from crankdyn.scene import options
from crankdyn.scene import quantity as _quantity
from crankdyn.scene_inputs import crank_train
from crankdyn.units import parse_quantity
from crankdyn_builtin.speed_fluctuation.worked import worked_speed_fluctuation

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

METHODS = ("RK45", "Radau", "BDF", "LSODA")
#: Tolerances of the single-mass comparison (the exact reference makes every error a true error).
SINGLE_MASS_RTOLS = (1e-3, 1e-5, 1e-7)
#: rtol of the single-mass run shown in the report.
SINGLE_MASS_RTOL = 1e-8
#: Smallest speed, as a fraction of the mean, for which the model is accepted.
MIN_SPEED_FRACTION = 0.5
#: Highest harmonic order listed in the torsional section (more when the significant order is higher).
MAX_ORDER = 12.0
#: Critical speeds within this fraction of the operating speed are flagged (resonance band).
CRITICAL_BAND = 0.10
#: Harmonics from this fraction of the largest amplitude count for the critical speeds and the Campbell diagram.
MAIN_ORDER_FRACTION = 0.01


def critical_near(harmonic_rows, mode_rows, rpm: float) -> list[dict]:
    """Critical speeds n_c = 60 f_s / nu (mode s, order nu) of the significant harmonics (amplitude at
    least MAIN_ORDER_FRACTION of the largest) within CRITICAL_BAND of the operating speed, nearest first."""
    if not harmonic_rows:
        return []
    largest = max(h["amplitude_Nm"] for h in harmonic_rows)
    near = []
    for h in harmonic_rows:
        if h["amplitude_Nm"] < MAIN_ORDER_FRACTION * largest:
            continue
        for k, mode in enumerate(mode_rows):
            deviation = h["critical_rpm"][k] / rpm - 1.0
            if abs(deviation) <= CRITICAL_BAND:
                near.append({"mode": mode["mode"], "order": h["order"], "critical_rpm": h["critical_rpm"][k],
                             "deviation_percent": 100.0 * deviation, "amplitude_Nm": h["amplitude_Nm"],
                             "vector_sum": h["vector_sum"][k]})
    return sorted(near, key=lambda c: abs(c["deviation_percent"]))


def _stiffness(kind_max: float = 1e12):
    return _quantity("torsional_stiffness", gt=0, le=kind_max, unit="N*m/rad")


def _stiffness_list(value):
    """One stiffness for every span, or a list with one per span."""
    items = value if isinstance(value, list) else [value]
    if not items:
        raise ValueError("give a stiffness such as '3e5 N*m/rad', or a list with one per span")
    out = []
    for item in items:
        stiffness = parse_quantity(item, "torsional_stiffness")
        if not 0 < stiffness <= 1e12:
            raise ValueError(f"{item!r}: must be > 0 and <= 1e12 N*m/rad")
        out.append(stiffness)
    return out if isinstance(value, list) else out[0]


class TorsionOptions(BaseModel):
    """The [torsion] table: the torsional multi-mass model of the crankshaft."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    span_stiffness: Annotated[float | list[float], BeforeValidator(_stiffness_list)]
    flywheel_stiffness: _stiffness() | None = None
    free_end_inertia: _quantity("moment_of_inertia", gt=0, le=1e6, unit="kg*m^2") | None = None
    free_end_stiffness: _stiffness() | None = None
    load_inertia: _quantity("moment_of_inertia", gt=0, le=1e6, unit="kg*m^2") | None = None
    coupling_stiffness: _stiffness() | None = None
    damping_ratio: _number(ge=0, lt=1) = 0.02
    solver: Literal["auto", "RK45", "Radau", "BDF", "LSODA"] = "auto"
    rtol: _number(ge=1e-10, le=1e-2) = 1e-4
    steady_tolerance: _number(gt=0, le=0.1) = 1e-3
    max_cycles: _number(ge=1, le=200) = 30
    compare_solvers: bool = True
    compare_rtols: list[_number(ge=1e-10, le=1e-2)] = [1e-3, 1e-4]
    reference_rtol: _number(ge=1e-12, le=1e-4) = 1e-6
    compare_fraction: _number(gt=0, le=1) = 0.25
    explicit_budget: _number(ge=100, le=1e7) = 20000

    @model_validator(mode="after")
    def _consistent(self) -> TorsionOptions:
        if (self.free_end_inertia is None) != (self.free_end_stiffness is None):
            raise ValueError("give free_end_inertia and free_end_stiffness together (a disc ahead of crank 1: "
                             "timing gear, pulley or damper, and the stiffness of the crank nose), or neither")
        if (self.load_inertia is None) != (self.coupling_stiffness is None):
            raise ValueError("give load_inertia and coupling_stiffness together (the load disc and the coupling "
                             "between the flywheel and it), or neither (the load torque then acts on the flywheel)")
        if self.reference_rtol >= min(self.compare_rtols, default=1.0):
            raise ValueError("reference_rtol must be smaller than every compare_rtols value")
        return self


def applies(scene) -> str | None:
    if "flywheel" not in scene.plugin_tables():
        return "the scene has no [flywheel] table"
    if scene.masses is None:
        return "the scene has no [masses]"
    return None


# --------------------------------------------------------------------------- single mass

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
        raise SceneError(Problem("flywheel.inertia", f"{design.flywheel_inertia_kg_m2:.4g} kg*m^2",
                                 "too small: with the variable inertia of the crank mechanisms the crankshaft would "
                                 "slow to less than half its mean speed once per cycle (or stop); give a larger "
                                 "flywheel or a smaller required_irregularity"))
    return inertia, gas, gas_series, exact


def _flywheel_for(delta_required, design, gas_series, train, omega_n):
    """Flywheel inertia for which the exact periodic solution has the required irregularity."""
    own = design.engine_inertia_kg_m2
    total_mechanism = train.series(0.0).mean_kg_m2

    def delta(flywheel):
        return sf.periodic_speed(gas_series, train.series(flywheel + own), omega_n).irregularity

    flywheel = design.required_flywheel_inertia_kg_m2
    for _ in range(8):  # delta ~ 1/J: a fixed-point iteration on J_total converges in a few steps
        total = flywheel + own + total_mechanism
        new = max(total * delta(flywheel) / delta_required - own - total_mechanism, 0.0)
        if abs(new - flywheel) <= 1e-12 * max(total, 1e-30):
            flywheel = new
            break
        flywheel = new
    return flywheel


def _energy_curve(torque, design, omega_n):
    """omega(alpha) of the energy method: omega_m + (W - W_mid) / (J omega_m), constant J."""
    alpha = np.radians(torque.crank_angle_deg)
    step = alpha[1] - alpha[0]
    excess = torque.torque_Nm - np.mean(torque.torque_Nm)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (excess[:-1] + excess[1:]) * step)])
    total = design.flywheel_inertia_kg_m2 + design.engine_inertia_kg_m2 + design.mechanism_inertia_mean_kg_m2
    return omega_n + (work - 0.5 * (work.max() + work.min())) / (total * omega_n)


def _run_record(run, error, extra=None):
    """One solver run as reported. A run is a success only with every figure present: a run that
    finished but whose error cannot be measured (no steps, or non-finite values) is a failure with
    its reason, never ``success`` beside a missing number."""
    extra = dict(extra or {})
    values = [error] + [extra[k] for k in ("error_twist_relative",) if k in extra]
    complete = all(v is not None and math.isfinite(v) for v in values)
    success = bool(run.success and complete)
    message = str(run.message)
    if run.success and not complete:
        message = "finished, but its error could not be measured (no steps or non-finite values)"
        extra = {k: (None if k == "error_twist_relative" else v) for k, v in extra.items()}
    # a run stopped by the evaluation budget is not a failure of the method: named as such
    outcome = "finished" if success else ("budget" if message.startswith("stopped after") else "failed")
    if outcome == "budget":
        message = f"stopped by the evaluation budget, not a failure: {message}"
    record = {"method": run.method, "rtol": run.rtol, "success": success, "outcome": outcome, "message": message,
              "steps": run.steps,
              "steps_needed": run.steps_needed if math.isfinite(run.steps_needed) else None,
              "nfev": run.nfev, "njev": run.njev, "nlu": run.nlu, "time_s": run.time_s,
              "progress": run.progress, "error_relative": error if success else None}
    record.update(extra)
    return record


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
    chosen = sf.run_solver(rhs, span, y0, choice.method, SINGLE_MASS_RTOL, atol(SINGLE_MASS_RTOL), dense_output=True)
    times = np.linspace(0.0, exact.cycle_time_s, 4097)
    dense = chosen.sol(times)
    omega_solver = dense[1]
    w_max, w_min = float(omega_solver.max()), float(omega_solver.min())
    summary = _choice_record(choice, "single")
    chosen_error = sf.phase_error(chosen, exact)
    # the run the section quotes is in the table and the figure too, after its method's other runs
    last_of_method = max(i for i, r in enumerate(records) if r["method"] == choice.method)
    records.insert(last_of_method + 1, {**_run_record(chosen, chosen_error), "used": True})
    summary.update({"rtol": SINGLE_MASS_RTOL, "steps": chosen.steps, "nfev": chosen.nfev, "time_s": chosen.time_s,
                    "error_relative": chosen_error if math.isfinite(chosen_error) else None,
                    "irregularity": (w_max - w_min) / (0.5 * (w_max + w_min)),
                    "periodicity_error": float(abs(chosen.y[1, -1] - y0[1]) / omega_n),
                    "end_angle_error_rad": float(chosen.y[0, -1] - gas_series.period_rad)})
    return summary, records, (dense[0], omega_solver)


def _choice_record(choice: sf.SolverChoice, kind: str, forced: str | None = None) -> dict:
    method = forced or choice.method
    if forced:
        reason = f"{forced} as the scene asks (solver = \"{forced}\")"
    elif kind == "single":
        reason = (f"{choice.method}: one degree of freedom whose only eigenvalue, |J' omega / J| <= "
                  f"{choice.fastest_rad_s:.3g} 1/s, lets RK45 take {choice.stability_steps:.3g} steps per cycle "
                  f"for stability while following the torque needs about {choice.resolution_steps:.3g}: not stiff, "
                  f"the explicit solver is the cheapest")
    elif choice.stiff:
        reason = (f"Radau: stiff - the fastest shaft mode (|lambda| = {choice.fastest_rad_s:.3g} 1/s) limits RK45 to "
                  f"steps below {choice.stable_step_s:.3g} s, {choice.stability_steps:.3g} steps per cycle, while the "
                  f"solution only needs about {choice.resolution_steps:.3g} to follow the torque harmonics up to "
                  f"{choice.resolved_frequency_rad_s:.3g} rad/s (ratio {choice.ratio:.3g} > "
                  f"{sf.STIFFNESS_THRESHOLD:g}); Radau IIA is A- and L-stable, BDF of order 3-5 is not A-stable for "
                  f"lightly damped modes")
    else:
        reason = (f"RK45: not stiff - RK45 needs {choice.stability_steps:.3g} steps per cycle for stability and about "
                  f"{choice.resolution_steps:.3g} to follow the solution (ratio {choice.ratio:.3g} <= "
                  f"{sf.STIFFNESS_THRESHOLD:g}), and an explicit step is cheaper than an implicit one")
    return {"method": method, "automatic": forced is None, "stiff": choice.stiff, "reason": reason,
            "fastest_eigenvalue_rad_s": choice.fastest_rad_s,
            "stable_step_s": choice.stable_step_s if math.isfinite(choice.stable_step_s) else None,
            "stability_steps_per_cycle": choice.stability_steps,
            "resolved_frequency_rad_s": choice.resolved_frequency_rad_s,
            "resolution_steps_per_cycle": choice.resolution_steps, "stiffness_ratio": choice.ratio}


# --------------------------------------------------------------------------- torsion

def _spans(opts: TorsionOptions, cranks: int, has_flywheel: bool = True) -> list[float]:
    given = opts.span_stiffness
    if isinstance(given, list):
        if len(given) != cranks - 1 and not (cranks == 1 and len(given) == 0):
            raise SceneError(Problem("torsion.span_stiffness", f"{len(given)} values",
                                     f"needs one stiffness per span between adjacent cranks ({cranks - 1}), "
                                     "or one value for all"))
        spans = list(given)
    else:
        spans = [given] * (cranks - 1)
    first = spans[-1] if spans else (given if not isinstance(given, list) else None)
    fly = opts.flywheel_stiffness if opts.flywheel_stiffness is not None else first
    if has_flywheel:
        if fly is None:
            raise SceneError(Problem("torsion.flywheel_stiffness", "(missing)",
                                     "a one-crank engine needs the stiffness between its crank and the flywheel"))
        spans.append(fly)
    if opts.load_inertia is not None:
        spans.append(opts.coupling_stiffness)
    return spans


@dataclass
class _Shaft:
    """The torsional multi-mass model of one scene: its discs, spans, matrices and equations of motion."""

    names: list[str]
    spans: list[float]
    mean_inertias: np.ndarray
    crank_nodes: np.ndarray
    reference: int  # the disc whose absolute angle the model keeps (the flywheel, else the last crank)
    K: np.ndarray
    C: np.ndarray
    modes: tor.Modes
    eigen: np.ndarray
    load: float
    model: tor.ShaftModel
    total_torque: np.ndarray  # (cranks, N): each crank's torque (gas + inertia) at the nominal speed

    @property
    def n(self) -> int:
        return int(self.mean_inertias.size)


def _shaft(torque, crank_loads, design, train, opts: TorsionOptions) -> _Shaft:
    """The discs (free end, cranks, flywheel, load) and the spans between them; the shaft's stiffness and
    modal damping matrices, natural modes and the equations of motion driven by each crank's torque."""
    omega_n = torque.angular_velocity_rad_s
    cranks = train.cranks
    has_flywheel = design.flywheel_inertia_kg_m2 > 0  # none when the engine's own inertia suffices
    alpha = np.radians(torque.crank_angle_deg)
    period = math.pi * torque.strokes
    shaft_share = design.engine_inertia_kg_m2 / cranks
    crank_series = [train.series(shaft_share, crank=k) for k in range(cranks)]
    total_torque = crank_loads.tangential_Pa * crank_loads.crank_radius_m * crank_loads.piston_area_m2  # (cranks, N)
    gas = np.array([sf.gas_torque_Nm(total_torque[k], crank_series[k](alpha)[1], omega_n) for k in range(cranks)])
    gas_series = sf.PeriodicSeries.from_samples(gas.T, period)
    front = 1 if opts.free_end_inertia is not None else 0
    spans = ([opts.free_end_stiffness] if front else []) + _spans(opts, cranks, has_flywheel)
    names = (["free end"] if front else []) + [f"crank {k + 1}" for k in range(cranks)] \
        + (["flywheel"] if has_flywheel else []) + (["load"] if opts.load_inertia else [])
    mean_inertias = np.array(([opts.free_end_inertia] if front else []) + [s.mean_kg_m2 for s in crank_series]
                             + ([design.flywheel_inertia_kg_m2] if has_flywheel else [])
                             + ([opts.load_inertia] if opts.load_inertia else []))
    crank_nodes = np.arange(front, front + cranks)
    if mean_inertias.size < 2:
        raise SceneError(Problem("torsion", "[torsion]", "a torsional model needs at least two discs: this engine has "
                                 "one crank and needs no flywheel; give flywheel.inertia or a load disc"))
    reference = front + cranks if has_flywheel else front + cranks - 1  # keeps the absolute angle
    K = tor.stiffness_matrix(spans)
    modes = tor.natural_modes(mean_inertias, spans)
    C = tor.modal_damping_matrix(mean_inertias, spans, opts.damping_ratio)
    eigen = tor.modal_eigenvalues(modes.omega_rad_s, opts.damping_ratio)
    load = float(gas_series.mean.sum())
    model = tor.ShaftModel(gas_series, crank_series, crank_nodes, mean_inertias, K, C, load, reference)
    return _Shaft(names, spans, mean_inertias, crank_nodes, reference, K, C, modes, eigen, load, model, total_torque)


def _periodic_state(shaft: _Shaft, torque, exact, opts: TorsionOptions, method: str):
    """The shaft's periodic steady state, integrated cycle after cycle until one repeats the one before.

    It starts from the linear frequency-domain solution (constant mean inertias, torques at constant
    speed): close to the periodic state, so few cycles remain to converge. Returns the steady state,
    its last cycle's run, the absolute tolerances as a function of rtol and the twist scale.
    """
    omega_n = torque.angular_velocity_rad_s
    alpha = np.radians(torque.crank_angle_deg)
    period = math.pi * torque.strokes
    n, reference, total_torque = shaft.n, shaft.reference, shaft.total_torque
    node_torque = np.zeros((alpha.size, n))
    node_torque[:, shaft.crank_nodes] = total_torque.T
    node_torque[:, -1] -= total_torque.sum(axis=0).mean()
    linear = tor.forced_response(shaft.mean_inertias, shaft.K, shaft.C,
                                 sf.PeriodicSeries.from_samples(node_torque, period), omega_n, reference)
    x0 = linear(0.0)
    v0 = omega_n * (1.0 + linear.derivative()(0.0))
    v0 += float(exact.omega_at(0.0)) - v0[reference]
    z0 = shaft.model.state(x0 - x0[reference], v0)
    twist_scale = max(float(np.max(np.abs(total_torque))) / min(shaft.spans), 1e-12)
    speed_scale = max(exact.omega_max_rad_s - exact.omega_min_rad_s, 1e-9 * omega_n)

    def atol(rtol):
        return np.concatenate([[rtol * 1e-3], np.full(n - 1, rtol * 1e-3 * twist_scale), np.full(n, rtol * 1e-3 * omega_n)])

    steady = tor.periodic_steady_state(shaft.model, z0, period, period / omega_n, method, opts.rtol, atol(opts.rtol),
                                       twist_scale, speed_scale, opts.steady_tolerance, int(opts.max_cycles))
    final = steady.runs[-1]
    if not final.success or final.sol is None:
        raise SceneError(Problem("torsion.solver", method, f"the solver failed on the torsional model ({final.message}); "
                                 "try solver = \"auto\" or \"Radau\""))
    return steady, final, atol, twist_scale


def _mode_rows(modes: tor.Modes, n: int) -> list[dict]:
    """The elastic modes (the rigid-body mode 0 left out): natural frequency and shape."""
    return [{"mode": s, "natural_frequency_rad_s": float(modes.omega_rad_s[s]),
             "natural_frequency_Hz": float(modes.omega_rad_s[s] / (2 * math.pi)),
             "shape": [float(a) for a in modes.shapes[:, s]]} for s in range(1, n)]


def _harmonic_rows(orders, coefficients, significant: float, shaft: _Shaft, train) -> list[dict]:
    """One crank's torque harmonics up to the last significant order (at least MAX_ORDER), each with its
    relative vector sum and critical speed for every elastic mode."""
    n, modes = shaft.n, shaft.modes
    rows = []
    for order, c in zip(orders, coefficients, strict=True):
        if order > max(MAX_ORDER, significant) + 1e-9:
            break
        rows.append({
            "order": float(order), "amplitude_Nm": float(abs(c)),
            "vector_sum": [tor.relative_vector_sum(modes.shapes[shaft.crank_nodes[train.crank_of_cylinder], s],
                                                   train.phase_rad, order) for s in range(1, n)],
            "critical_rpm": [float(tor.critical_speed_rpm(modes.omega_rad_s[s], order)) for s in range(1, n)]})
    return rows


def _torsion(scene, torque, crank_loads, design, train, exact, opts: TorsionOptions):
    """The torsional section's results and table: the shaft model, its modes and the harmonics of the
    crank torque, the solver chosen by stiffness, the periodic state and its twists and span torques."""
    omega_n = torque.angular_velocity_rad_s
    alpha = np.radians(torque.crank_angle_deg)
    shaft = _shaft(torque, crank_loads, design, train, opts)
    n, reference, spans = shaft.n, shaft.reference, shaft.spans

    # Harmonic orders of one crank's torque (gas + inertia at the nominal speed).
    orders, coefficients = sf.harmonic_amplitudes(shaft.total_torque[0], torque.strokes / 2, 1e9)
    significant = sf.significant_order(orders, np.abs(coefficients))
    choice = sf.choose_solver(shaft.eigen, math.pi * torque.strokes / omega_n, significant * omega_n)
    forced = None if opts.solver == "auto" else opts.solver
    steady, final, atol, twist_scale = _periodic_state(shaft, torque, exact, opts, forced or choice.method)

    z = final.sol(np.linspace(0.0, steady.cycle_time_s, alpha.size + 1)[:-1])
    theta = shaft.model.P @ z[:n]
    speeds = z[n:]
    flywheel_angle = np.degrees(theta[reference] - theta[reference][0])
    twist = theta[1:] - theta[:-1]  # span j: disc j+1 minus disc j
    span_torque = np.asarray(spans)[:, None] * twist
    # The rigid-shaft (single-mass) flywheel speed at the same flywheel angles, for comparison.
    rigid = exact.omega_at(np.radians(flywheel_angle))
    fly_speed = speeds[reference]
    f_max, f_min = float(fly_speed.max()), float(fly_speed.min())
    mode_rows = _mode_rows(shaft.modes, n)
    harmonic_rows = _harmonic_rows(orders, coefficients, significant, shaft, train)

    results = {
        "nodes": [{"name": name, "inertia_mean_kg_m2": float(j)} for name, j in zip(shaft.names, shaft.mean_inertias, strict=True)],
        "reference_node": int(reference),
        "span_stiffness_N_m_rad": [float(k) for k in spans],
        "damping_ratio": opts.damping_ratio,
        "modes": mode_rows,
        "harmonics": harmonic_rows,
        "significant_order": significant,
        "critical_speeds_near_operating": critical_near(harmonic_rows, mode_rows, scene.engine.rpm),
        "critical_band_relative": CRITICAL_BAND,
        "operating_rpm": scene.engine.rpm,
        "solver": {**_choice_record(choice, "torsion", forced), "rtol": opts.rtol},
        "steady_state": {"cycles": steady.cycles, "converged": steady.converged,
                         "change": steady.change if math.isfinite(steady.change) else None,
                         "tolerance": opts.steady_tolerance, "load_torque_Nm": steady.load_torque_Nm,
                         "damping_loss_W": (shaft.load - steady.load_torque_Nm) * omega_n,
                         "steps_per_cycle": final.steps, "nfev_per_cycle": final.nfev,
                         "time_s": sum(r.time_s for r in steady.runs)},
        "twist_max_rad": [float(np.max(np.abs(t))) for t in twist],
        "span_torque_max_Nm": [float(np.max(np.abs(t))) for t in span_torque],
        "flywheel_irregularity": (f_max - f_min) / (0.5 * (f_max + f_min)),
        "flywheel_speed_deviation_from_rigid_relative": float(np.max(np.abs(fly_speed - rigid)) / omega_n),
        "compare_fraction": opts.compare_fraction,
        "reference_rtol": opts.reference_rtol,
        "solvers": [],
    }
    if opts.compare_solvers:
        results["solvers"] = _torsion_solvers(shaft.model, steady, atol, opts, n, twist_scale, omega_n)
    tables = {"torsion": {"shaft_angle_deg": flywheel_angle,
                          **{f"twist_{j + 1}_rad": twist[j] for j in range(n - 1)},
                          **{f"span_torque_{j + 1}_Nm": span_torque[j] for j in range(n - 1)},
                          **{f"speed_{name.replace(' ', '')}_rad_s": speeds[i] for i, name in
                             enumerate(shaft.names)},
                          "rigid_speed_rad_s": rigid}}
    return results, tables


def _torsion_solvers(model, steady, atol, opts, n, twist_scale, omega_n):
    """Every solver over a window of the periodic state (a quarter cycle by default), against a
    Radau run at a much tighter tolerance. RK45 gets at most ``explicit_budget`` evaluations,
    and no more than 10 times what the costliest implicit solver used at the same rtol."""
    span = (0.0, steady.cycle_time_s * opts.compare_fraction)
    z = steady.state
    reference = sf.run_solver(model, span, z, "Radau", opts.reference_rtol, atol(opts.reference_rtol),
                              jac=model.jacobian, dense_output=True)
    records = [_run_record(reference, 0.0, {"reference": True, "error_twist_relative": 0.0})]
    if not reference.success:
        return records
    for rtol in opts.compare_rtols:
        implicit = []
        for method in ("Radau", "BDF", "LSODA", "RK45"):
            budget = None
            if method == "RK45":
                budget = int(min(opts.explicit_budget, 10 * max(implicit + [100])))
            run = sf.run_solver(model, span, z, method, rtol, atol(rtol), jac=model.jacobian, max_nfev=budget)
            if run.success and run.steps > 0:
                exact = reference.sol(run.t)
                with np.errstate(all="ignore"):
                    error = float(np.max(np.abs(run.y[n:] - exact[n:]))) / omega_n
                    error_twist = float(np.max(np.abs(run.y[1:n] - exact[1:n]))) / twist_scale
            else:
                error = error_twist = None
            if method != "RK45":
                implicit.append(run.nfev)
            records.append(_run_record(run, error, {"reference": False, "error_twist_relative": error_twist}))
    return records


# --------------------------------------------------------------------------- stage

def run(scene, inputs) -> StageOutput:
    torque, bays, crank_loads, design = inputs[ENGINE_TORQUE], inputs[BAY_LOADS], inputs[CRANK_LOADS], inputs[FLYWHEEL]
    torsion_opts = options(scene, "torsion", TorsionOptions) if "torsion" in scene.plugin_tables() else None
    omega_n = torque.angular_velocity_rad_s
    train = crank_train(scene, bays)
    inertia, gas, gas_series, exact = _single_mass(scene, torque, bays, design, train)
    alpha = np.radians(torque.crank_angle_deg)
    j_grid, dj_grid = inertia(alpha)
    summary, records, (solver_alpha, solver_omega) = _single_mass_solvers(gas_series, inertia, exact, omega_n)

    energy_delta = design.irregularity
    results = {
        "reference": "quadrature",
        "inertia_mean_kg_m2": inertia.mean_kg_m2,
        "inertia_min_kg_m2": float(np.min(exact.inertia_kg_m2)),
        "inertia_max_kg_m2": float(np.max(exact.inertia_kg_m2)),
        "load_torque_Nm": exact.load_torque_Nm,
        "omega_mean_rad_s": exact.omega_mean_rad_s,
        "omega_max_rad_s": exact.omega_max_rad_s,
        "omega_min_rad_s": exact.omega_min_rad_s,
        "omega_max_crank_angle_deg": math.degrees(exact.omega_max_angle_rad),
        "omega_min_crank_angle_deg": math.degrees(exact.omega_min_angle_rad),
        "cycle_time_s": exact.cycle_time_s,
        "irregularity": exact.irregularity,
        "irregularity_definition": "(omega_max - omega_min) / ((omega_max + omega_min) / 2)",
        "irregularity_time_mean": irr.irregularity_time_mean(exact.omega_max_rad_s, exact.omega_min_rad_s,
                                                             exact.omega_mean_rad_s),
        "irregularity_energy": energy_delta,
        "irregularity_deviation_percent": 100.0 * (exact.irregularity - energy_delta) / energy_delta,
        "flywheel_inertia_energy_kg_m2": design.required_flywheel_inertia_kg_m2,
        "flywheel_inertia_ode_kg_m2": None,
        "flywheel_inertia_deviation_percent": None,
        "solver": summary,
        "solvers": records,
        "torsion": None,
    }
    if design.required_irregularity is not None and design.required_flywheel_inertia_kg_m2:
        ode = _flywheel_for(design.required_irregularity, design, gas_series, train, omega_n)
        results["flywheel_inertia_ode_kg_m2"] = ode
        results["flywheel_inertia_deviation_percent"] = 100.0 * (ode - design.required_flywheel_inertia_kg_m2) \
            / design.required_flywheel_inertia_kg_m2
    tables = {"speed_fluctuation": {
        "crank_angle_deg": torque.crank_angle_deg,
        "inertia_kg_m2": j_grid,
        "inertia_derivative_kg_m2": dj_grid,
        "gas_torque_Nm": gas,
        "omega_rad_s": exact.omega_at(alpha),
        "omega_energy_method_rad_s": _energy_curve(torque, design, omega_n),
        "omega_solver_rad_s": np.interp(alpha, solver_alpha, solver_omega),
    }}
    # the solvers' check against the exact solution is a full report's (``detail = "full"``)
    full = scene.report.detail == "full"
    notes = [("speed_fluctuation.note_reference", {})] if full else []
    notes += [("speed_fluctuation.note_irregularity", {
                 "midrange": results["irregularity"], "time_mean": results["irregularity_time_mean"],
                 "omega_mid": 0.5 * (exact.omega_max_rad_s + exact.omega_min_rad_s),
                 "omega_mean": exact.omega_mean_rad_s})]
    if torsion_opts is not None:
        torsion, torsion_tables = _torsion(scene, torque, crank_loads, design, train, exact, torsion_opts)
        results["torsion"] = torsion
        tables.update(torsion_tables)
        if full and not torsion["steady_state"]["converged"]:  # a course note's section says it
            notes.append(("speed_fluctuation.note_not_converged", {"cycles": torsion["steady_state"]["cycles"]}))
    return StageOutput(data={}, results=results, tables=tables, notes=notes)


# --------------------------------------------------------------------------- report

def _solver_table(ctx, records, caption, see, twist=False):
    t = ctx.t
    rows = [r for r in records if not r.get("reference")]
    columns = [
        (t("speed_fluctuation.col_method"), [r["method"] for r in rows], None),
        (t("speed_fluctuation.col_rtol"), [_sci(r["rtol"], t.decimal_separator).replace("1,0·", "").replace("1.0·", "") for r in rows], None),
        (t("speed_fluctuation.col_steps"), [_steps_text(ctx, r) for r in rows], None),
        (t("speed_fluctuation.col_nfev"), [str(r["nfev"]) for r in rows], None),
        (t("speed_fluctuation.col_njev"), [f"{r['njev']}/{r['nlu']}" for r in rows], None),
        (t("speed_fluctuation.col_time"), [r["time_s"] * 1e3 for r in rows], 1),
        (t("speed_fluctuation.col_error"), [_error_text(ctx, r["error_relative"]) for r in rows], None),
    ]
    if twist:
        columns.append((t("speed_fluctuation.col_error_twist"),
                        [_error_text(ctx, r.get("error_twist_relative")) for r in rows], None))
    return ctx.table(columns, caption=caption, see=see)


def _steps_text(ctx, r):
    if r["success"]:
        return str(r["steps"])
    if r["steps_needed"] is None:
        return "—"
    return ctx.t("speed_fluctuation.steps_stopped", steps=r["steps"], percent=ctx.num(100 * r["progress"], 2),
                 needed=ctx.num(r["steps_needed"], 2))


def _error_text(ctx, value):
    return _sci(value, ctx.t.decimal_separator)


def _sci(value, separator: str = ".") -> str:
    """1.2·10⁻⁵ style for errors and tolerances in the text (— when missing)."""
    if value is None or not math.isfinite(value):
        return "—"
    if value == 0:
        return "0"
    mantissa, exponent = f"{value:.1e}".split("e")
    return f"{mantissa.replace('.', separator)}·10{superscript(int(exponent))}".replace("-", "−")


def _power_of_ten(value: float, t) -> str:
    """A tolerance as a figure label: ``10⁻³`` (Unicode superscripts), never ``1e-03``."""
    exponent = math.log10(value) if value > 0 else float("nan")
    if math.isfinite(exponent) and abs(exponent - round(exponent)) < 1e-9:
        return f"10{superscript(int(round(exponent)))}"
    return t.number_g(value, 2)


def _error_figure(ctx, records, caption, name, see, key="error_relative"):
    return ctx.figure(partial(_error_plot, records, key, ctx.t), caption, name, see=see)


def _error_plot(records, key, t):
    """The error of each solver's runs against their time, the tolerances marked, the run quoted ringed."""
    fig, ax = new_figure(16, 9)
    for i, method in enumerate(METHODS):
        rows = [r for r in records if r["method"] == method and not r.get("reference") and r[key] is not None
                and r[key] > 0]
        if rows:
            # milliseconds, as the table of the runs beside it
            ax.loglog([r["time_s"] * 1e3 for r in rows], [r[key] for r in rows], "o-", color=f"C{i}", label=method)
            for r in rows:
                ax.annotate(_power_of_ten(r["rtol"], t), (r["time_s"] * 1e3, r[key]), fontsize=7, xytext=(3, 3),
                            textcoords="offset points")
    used = [r for r in records if r.get("used") and r[key] is not None and r[key] > 0]
    if used:  # the run the section quotes, ringed (a shape, not a colour: black-and-white print)
        ax.loglog([r["time_s"] * 1e3 for r in used], [r[key] for r in used], "o", ms=11, mfc="none", mec="black",
                  mew=0.9, label=t("speed_fluctuation.used_run"))
    ax.set_xlabel(t("speed_fluctuation.axis_time"))
    ax.set_ylabel(t("speed_fluctuation.axis_error"))
    ax.legend(loc="best", fontsize=8)
    return fig


def _speed_figure(f, r, ctx) -> str:
    """The crankshaft speed over the cycle (exact, the solver's, the energy method's) above the variable inertia."""
    return ctx.figure(partial(_speed_plot, f, r["solver"]["method"], ctx.cycle_deg, ctx.t),
                      ctx.t("speed_fluctuation.speed_caption"), "speed", see="speed_fluctuation.see_speed")


def _speed_plot(f, method, cycle_deg, t):
    """The speed over the cycle (exact, the solver's, the energy method's) above the variable inertia."""
    angle = f["crank_angle_deg"]
    fig, axes = new_figure(16, 13, nrows=2, sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    axes[0].plot(angle, f["omega_rad_s"], color="C0", label=t("speed_fluctuation.exact"))
    axes[0].plot(angle, f["omega_solver_rad_s"], color="C1", ls="--", lw=1,
                 label=t("speed_fluctuation.solver_curve", method=method))
    axes[0].plot(angle, f["omega_energy_method_rad_s"], color="C2", ls=":", label=t("speed_fluctuation.energy_curve"))
    axes[0].set_ylabel(t("speed_fluctuation.axis_omega"))
    axes[0].legend(loc="upper right", fontsize=8)
    axes[1].plot(angle, f["inertia_kg_m2"], color="C4")
    axes[1].set_ylabel(t("speed_fluctuation.axis_inertia"))
    crank_angle_axis(axes[1], cycle_deg, t("axis.crank_angle"))
    return fig


def _shaft_tables(ctx, torsion, node_names, parts) -> None:
    """The discs and spans of the shaft model, and its natural modes (frequencies and shapes)."""
    t = ctx.t
    nodes, modes = torsion["nodes"], torsion["modes"]
    parts["table_nodes"] = ctx.table(
        [(t("speed_fluctuation.col_node"), [f"{i + 1}: {name}" for i, name in enumerate(node_names)], None),
         ("<i>J</i><sub><i>i</i></sub>, " + t("flywheel.unit_kg_m2"), [ctx.num(n["inertia_mean_kg_m2"]) for n in nodes], None),
         ("<i>c</i><sub><i>i</i></sub>, " + t("speed_fluctuation.unit_N_m_rad"),
          [ctx.num(k) for k in torsion["span_stiffness_N_m_rad"]] + ["—"], None),
         (t("speed_fluctuation.col_twist"), [ctx.num(x * 1e3) for x in torsion["twist_max_rad"]] + ["—"], None),
         (t("speed_fluctuation.col_span_torque"), [ctx.num(x) for x in torsion["span_torque_max_Nm"]] + ["—"],
          None)],
        caption=t("speed_fluctuation.nodes_caption"), see="speed_fluctuation.see_nodes")
    parts["table_modes"] = ctx.table(
        [(t("speed_fluctuation.col_mode"), [str(m["mode"]) for m in modes], None),
         ("<i>ω</i><sub><i>s</i></sub>, " + t("unit.rad_s"), [ctx.num(m["natural_frequency_rad_s"]) for m in modes], None),
         ("<i>f</i><sub><i>s</i></sub>, " + t("speed_fluctuation.unit_Hz"), [ctx.num(m["natural_frequency_Hz"]) for m in modes], None)]
        + [(Markup("<i>a</i><sub>") + str(i + 1) + Markup("</sub>"), [m["shape"][i] for m in modes], 3)
           for i in range(len(nodes))],
        caption=t("speed_fluctuation.modes_caption"), see="speed_fluctuation.see_modes_table")


def _modes_figure(ctx, torsion, parts) -> None:
    """The shapes of the first (at most three) elastic modes along the shaft."""
    t = ctx.t
    modes = torsion["modes"]
    labels = [t("speed_fluctuation.mode_label", mode=m["mode"], f=ctx.num(m["natural_frequency_Hz"], 4))
              for m in modes[: min(3, len(modes))]]
    parts["figure_modes"] = ctx.figure(partial(_modes_plot, len(torsion["nodes"]), modes, labels, t),
                                       t("speed_fluctuation.modes_figure_caption"), "modes",
                                       see="speed_fluctuation.see_modes_figure")


def _modes_plot(node_count, modes, labels, t):
    """The shapes of the first modes (one curve per label) along the shaft's nodes."""
    fig, ax = new_figure(16, 7)
    for m, label in zip(modes, labels, strict=False):
        ax.plot(range(1, node_count + 1), m["shape"], "o-", label=label)
    ax.axhline(0, color="0.3", lw=0.6)
    ax.set_xticks(range(1, node_count + 1))
    ax.set_xlabel(t("speed_fluctuation.axis_node"))
    ax.set_ylabel(t("speed_fluctuation.axis_amplitude"))
    ax.legend(loc="best", fontsize=8)
    return fig


def _harmonics_table(ctx, torsion, parts) -> None:
    """The crank torque's harmonic orders with the critical speeds and vector sums of the first two modes."""
    t = ctx.t
    harmonics = torsion["harmonics"]
    shown = torsion["modes"][:2]
    parts["table_harmonics"] = ctx.table(
        [(Markup("<i>ν</i>"), [ctx.num(h["order"], 3) for h in harmonics], None),
         (Markup("|<i>M</i><sub><i>ν</i></sub>|, ") + t("unit.Nm"), [h["amplitude_Nm"] for h in harmonics], 1)]
        + [(t("speed_fluctuation.col_critical", mode=m["mode"]), [h["critical_rpm"][k] for h in harmonics], 0)
           for k, m in enumerate(shown)]
        + [(t("speed_fluctuation.col_vector_sum", mode=m["mode"]), [h["vector_sum"][k] for h in harmonics], 2)
           for k, m in enumerate(shown)],
        caption=t("speed_fluctuation.harmonics_caption"), see="speed_fluctuation.see_harmonics")


def _torsion_figure(ctx, tf, torsion, node_names, parts) -> None:
    """The periodic state: the flywheel's and the first crank's speed against the rigid shaft's, and the
    torque in every span, over the shaft angle."""
    parts["figure_torsion"] = ctx.figure(partial(_torsion_plot, tf, torsion, node_names, ctx.cycle_deg, ctx.t),
                                         ctx.t("speed_fluctuation.torsion_caption"), "torsion",
                                         see="speed_fluctuation.see_torsion")


def _torsion_plot(tf, torsion, node_names, cycle_deg, t):
    """The speeds of the reference node and the first crank against the rigid shaft's, and the span torques."""
    nodes = torsion["nodes"]
    fig, axes = new_figure(16, 13, nrows=2, sharex=True)
    shaft = tf["shaft_angle_deg"]
    speed_columns = [c for c in tf.columns if c.startswith("speed_")]
    reference = torsion["reference_node"]
    axes[0].plot(shaft, tf[speed_columns[reference]], color="C0", label=node_names[reference])
    axes[0].plot(shaft, tf["rigid_speed_rad_s"], color="C3", ls="--", lw=1, label=t("speed_fluctuation.rigid_speed"))
    first_crank = next(i for i, node in enumerate(nodes) if node["name"].startswith("crank "))
    axes[0].plot(shaft, tf[speed_columns[first_crank]], color="C1", lw=0.8, label=node_names[first_crank])
    axes[0].set_ylabel(t("speed_fluctuation.axis_omega"))
    axes[0].legend(loc="upper right", fontsize=8)
    spans = [c for c in tf.columns if c.startswith("span_torque_")]
    for j, column in enumerate(spans):
        axes[1].plot(shaft, tf[column], lw=0.9, label=t("speed_fluctuation.span_label", first=j + 1, second=j + 2))
    axes[1].set_ylabel(t("speed_fluctuation.axis_span_torque"))
    axes[1].legend(loc="upper right", fontsize=8, ncol=3)
    crank_angle_axis(axes[1], cycle_deg, t("speed_fluctuation.axis_shaft_angle"))
    return fig


def _torsion_parts(ctx, output: StageOutput, torsion, course: bool = False) -> dict:
    """The torsional subsection's tables and figures, made in the order the template shows them
    (tables and figures are numbered as made), and its conclusions; a course note's without
    the solvers' comparison."""
    t = ctx.t
    parts = {}
    node_names = [_node_name(t, node["name"]) for node in torsion["nodes"]]
    modes = torsion["modes"]
    _shaft_tables(ctx, torsion, node_names, parts)
    _modes_figure(ctx, torsion, parts)
    _harmonics_table(ctx, torsion, parts)
    _campbell(ctx, torsion, parts)
    _torsion_figure(ctx, output.tables.arrays("torsion"), torsion, node_names, parts)
    if torsion["solvers"] and not course:
        parts["table_torsion_solvers"] = _solver_table(ctx, torsion["solvers"],
                                                       t("speed_fluctuation.torsion_table_caption"),
                                                       "speed_fluctuation.see_torsion_table", twist=True)
        parts["figure_torsion_solvers"] = _error_figure(ctx, torsion["solvers"],
                                                        t("speed_fluctuation.torsion_figure_caption"),
                                                        "solvers_torsion", "speed_fluctuation.see_torsion_figure")
    conclusion = "speed_fluctuation.conclusion_torsion" + ("_course" if course else "")
    ctx.conclude(t(conclusion, f1=ctx.num(modes[0]["natural_frequency_Hz"]) if modes
                   else "—", method=torsion["solver"]["method"],
                   twist=ctx.num(max(torsion["twist_max_rad"]) * 1e3),
                   torque=ctx.num(max(torsion["span_torque_max_Nm"]))))
    return parts


def _digits_that_differ(relative: float, least: int = 4, most: int = 8) -> int:
    """Significant digits that show two values a relative difference apart as different: two
    beyond the first that differs ("δ = 0,0100014, the energy method 0,0100000 (0,014 %)"),
    where four digits printed 0,01000 twice beside a difference."""
    if not relative or not math.isfinite(relative):
        return least
    return int(min(most, max(least, math.ceil(-math.log10(abs(relative))) + 2)))


def render(output: StageOutput, ctx) -> str:
    """The section: the speed over the cycle and the single-mass solver study, then the torsional
    model when the scene has one, and the conclusions."""
    t = ctx.t
    r = output.results
    # a course note gives the results; the solvers' comparison is the full report's study
    course = ctx.scene is not None and ctx.scene.report.detail == "course"
    figure_speed = _speed_figure(output.tables.arrays("speed_fluctuation"), r, ctx)
    table_single = figure_single = None
    if not course:
        table_single = _solver_table(ctx, r["solvers"], t("speed_fluctuation.single_table_caption"),
                                     "speed_fluctuation.see_single_table")
        figure_single = _error_figure(ctx, r["solvers"],
                                      t("speed_fluctuation.single_figure_caption"),
                                      "solvers_single", "speed_fluctuation.see_single_figure")

    torsion = r["torsion"]
    if torsion is None:  # no torsional model in the scene: the title does not promise one
        ctx.title = t("speed_fluctuation.title_rigid")
    parts = _torsion_parts(ctx, output, torsion, course) if torsion is not None else {}
    digits = _digits_that_differ(r["irregularity_deviation_percent"] / 100)
    ctx.conclude(t("speed_fluctuation.conclusion" + ("_course" if course else ""),
                   delta=ctx.num(r["irregularity"], digits),
                   energy=ctx.num(r["irregularity_energy"], digits),
                   deviation=ctx.num(r["irregularity_deviation_percent"], 2), method=r["solver"]["method"]))
    return ctx.render_template("sections/speed_fluctuation.html.j2", r=r, torsion=torsion, delta_digits=digits,
                               cylinders=ctx.scene.engine.cylinders, course=course,
                               sci=lambda value: _sci(value, t.decimal_separator),
                               figure_speed=figure_speed, table_single=table_single, figure_single=figure_single,
                               worked=worked_speed_fluctuation(ctx, r), **parts)


def _campbell(ctx, torsion, parts) -> None:
    """Campbell diagram (natural frequencies against engine speed, with the significant orders) and the
    conclusion on the critical speeds near the operating speed."""
    t = ctx.t
    rpm = torsion["operating_rpm"]
    parts["figure_campbell"] = ctx.figure(partial(_campbell_plot, torsion, t),
                                          t("speed_fluctuation.campbell_caption", band=ctx.num(100 * CRITICAL_BAND, 2)),
                                          "campbell", see="speed_fluctuation.see_campbell")
    near = torsion["critical_speeds_near_operating"]
    if near:
        items = "; ".join(t("speed_fluctuation.critical_item", mode=c["mode"], order=ctx.num(c["order"], 3),
                            rpm=ctx.num(c["critical_rpm"], 4), deviation=ctx.num(c["deviation_percent"], 2),
                            vector=ctx.num(c["vector_sum"], 2)) for c in near)
        ctx.conclude(t("speed_fluctuation.conclusion_critical", rpm=ctx.num(rpm, 4),
                       band=ctx.num(100 * CRITICAL_BAND, 2), items=items, zeta=ctx.num(torsion["damping_ratio"], 3)))
    else:
        ctx.conclude(t("speed_fluctuation.conclusion_no_critical", rpm=ctx.num(rpm, 4),
                       band=ctx.num(100 * CRITICAL_BAND, 2)))


def _campbell_plot(torsion, t):
    """The natural frequencies and the significant orders against engine speed, the operating band shaded."""
    rpm = torsion["operating_rpm"]
    harmonics = torsion["harmonics"]
    largest = max((h["amplitude_Nm"] for h in harmonics), default=0.0)
    main = [h for h in harmonics if h["amplitude_Nm"] >= MAIN_ORDER_FRACTION * largest]
    speeds = np.linspace(0.0, 1.3 * rpm, 200)
    fig, ax = new_figure(16, 10)
    top = max(m["natural_frequency_Hz"] for m in torsion["modes"][:2]) * 1.25
    for h in main:
        ax.plot(speeds, h["order"] * speeds / 60.0, color="0.6", lw=0.6)
        end = min(1.3 * rpm, top * 60.0 / h["order"])
        ax.text(end, h["order"] * end / 60.0, t.number_g(h["order"]), fontsize=7, color="0.35")
    for m in torsion["modes"][:2]:
        ax.axhline(m["natural_frequency_Hz"], color="C0", lw=1.0)
    ax.axvspan((1 - CRITICAL_BAND) * rpm, (1 + CRITICAL_BAND) * rpm, color="C3", alpha=0.12, lw=0)
    ax.axvline(rpm, color="C3", lw=0.8, ls="--")
    for c in torsion["critical_speeds_near_operating"]:
        f = next(m["natural_frequency_Hz"] for m in torsion["modes"] if m["mode"] == c["mode"])
        ax.plot([c["critical_rpm"]], [f], "o", color="C3", ms=3)
    ax.set_xlim(0, 1.3 * rpm)
    ax.set_ylim(0, top)
    ax.set_xlabel(t("speed_fluctuation.axis_campbell_rpm"))
    ax.set_ylabel(t("speed_fluctuation.axis_campbell_hz"))
    return fig


def _node_name(t, name: str) -> str:
    if name.startswith("crank "):
        return t("speed_fluctuation.node_crank", k=name.split()[1])
    return t("speed_fluctuation.node_" + name.replace(" ", "_"))


#: The torsional model's letters (meanings: symbol.speed_fluctuation.<key> in i18n/): i numbers
#: the discs, s the modes.
_I = {"en": "i"}
SYMBOLS = {
    "disc_inertia": Symbol("J", _I, "unit.kg_m2", html="<i>J</i><sub><i>i</i></sub>"),
    "disc_inertia_derivative": Symbol("J", _I, "unit.kg_m2_rad", html="<i>J</i>′<sub><i>i</i></sub>"),
    "disc_angle": Symbol("θ", _I, "speed_fluctuation.unit_rad", html="<i>θ</i><sub><i>i</i></sub>"),
    "disc_speed": Symbol("θ\u0307", _I, "unit.rad_s", html="<i>θ\u0307</i><sub><i>i</i></sub>"),
    "disc_acceleration": Symbol("θ\u0308", _I, "unit.rad_s2", html="<i>θ\u0308</i><sub><i>i</i></sub>"),
    "disc_angles": Symbol("θ", {}, "speed_fluctuation.unit_rad", html="<b><i>θ</i></b>"),
    "disc_speeds": Symbol("θ\u0307", {}, "unit.rad_s", html="<b><i>θ\u0307</i></b>"),
    "disc_gas_torque": Symbol("M", {"en": "g", "uk": "г", "ru": "г"}, "unit.Nm", html="<i>M</i><sub>{sub},<i>i</i></sub>"),
    "stiffness_matrix": Symbol("K", {}, "speed_fluctuation.unit_N_m_rad", html="<b>K</b>"),
    "damping_matrix": Symbol("C", {}, "speed_fluctuation.unit_N_m_s_rad", html="<b>C</b>"),
    "inertia_matrix": Symbol("M", {}, "unit.kg_m2", html="<b>M</b>"),
    "mode_matrix": Symbol("Φ", {}, "", html="<b>Φ</b>"),
    "kronecker": Symbol("δ", {}, "", html="<i>δ</i><sub><i>i</i><i>N</i></sub>"),
    "mode_shape": Symbol("v", {"en": "s"}, "", html="<b><i>v</i></b><sub><i>s</i></sub>"),
    "span_stiffness": Symbol("c", _I, "speed_fluctuation.unit_N_m_rad", html="<i>c</i><sub><i>i</i></sub>"),
    "natural_frequency_Hz": Symbol("f", {"en": "s"}, "speed_fluctuation.unit_Hz", html="<i>f</i><sub><i>s</i></sub>"),
    "natural_frequency": Symbol("ω", {"en": "s"}, "unit.rad_s", html="<i>ω</i><sub><i>s</i></sub>"),
    "damping_ratio": Symbol("ζ", {}, ""),
}


SPEED_FLUCTUATION_STAGE = Stage(
    template_dir=TEMPLATES,
    name="speed_fluctuation",
    # the core's letters that hold with their meaning in this section only
    section_symbols=("irregularity", "cylinder_phase"),
    title_key="speed_fluctuation.title",
    requires=(ENGINE_TORQUE, BAY_LOADS, CRANK_LOADS, FLYWHEEL),
    provides=(),
    applies=applies,
    run=run,
    render=render,
    figures=("speed", "solvers_single", "modes", "campbell", "torsion", "solvers_torsion"),
    tables=("speed_fluctuation", "torsion"),
    references=("denhartog1956",),
    references_full=("hairer1996", "scipy2020"),
    options_table="torsion",
    options_model=TorsionOptions,
    symbols=SYMBOLS,
)
