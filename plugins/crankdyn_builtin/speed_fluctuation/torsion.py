"""The torsional model of the crankshaft (lumped discs on elastic spans): its natural modes, the
crank torque's harmonics, the critical speeds near the operating speed and the periodic steady
state, with each ODE method's study against a reference run."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from crankdyn.errors import Problem, SceneError
from crankdyn.physics import speed_fluctuation as sf
from crankdyn.physics import torsion as tor

from .options import TorsionOptions
from .solvers import _choice_record, _run_record

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
                near.append(
                    {
                        "mode": mode["mode"],
                        "order": h["order"],
                        "critical_rpm": h["critical_rpm"][k],
                        "deviation_percent": 100.0 * deviation,
                        "amplitude_Nm": h["amplitude_Nm"],
                        "vector_sum": h["vector_sum"][k],
                    }
                )
    return sorted(near, key=lambda c: abs(c["deviation_percent"]))


def _spans(opts: TorsionOptions, cranks: int, has_flywheel: bool = True) -> list[float]:
    given = opts.span_stiffness
    if isinstance(given, list):
        if len(given) != cranks - 1 and not (cranks == 1 and len(given) == 0):
            raise SceneError(
                Problem(
                    "torsion.span_stiffness",
                    f"{len(given)} values",
                    f"needs one stiffness per span between adjacent cranks ({cranks - 1}), "
                    "or one value for all",
                )
            )
        spans = list(given)
    else:
        spans = [given] * (cranks - 1)
    first = spans[-1] if spans else (given if not isinstance(given, list) else None)
    fly = opts.flywheel_stiffness if opts.flywheel_stiffness is not None else first
    if has_flywheel:
        if fly is None:
            raise SceneError(
                Problem(
                    "torsion.flywheel_stiffness",
                    "(missing)",
                    "a one-crank engine needs the stiffness between its crank and the flywheel",
                )
            )
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
    reference: (
        int  # the disc whose absolute angle the model keeps (the flywheel, else the last crank)
    )
    K: np.ndarray
    C: np.ndarray
    modes: tor.Modes
    eigen: np.ndarray
    load: float
    model: tor.ShaftModel
    total_torque: (
        np.ndarray
    )  # (cranks, N): each crank's torque (gas + inertia) at the nominal speed

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
    total_torque = (
        crank_loads.tangential_Pa * crank_loads.crank_radius_m * crank_loads.piston_area_m2
    )  # (cranks, N)
    gas = np.array(
        [
            sf.gas_torque_Nm(total_torque[k], crank_series[k](alpha)[1], omega_n)
            for k in range(cranks)
        ]
    )
    gas_series = sf.PeriodicSeries.from_samples(gas.T, period)
    front = 1 if opts.free_end_inertia is not None else 0
    spans = ([opts.free_end_stiffness] if front else []) + _spans(opts, cranks, has_flywheel)
    names = (
        (["free end"] if front else [])
        + [f"crank {k + 1}" for k in range(cranks)]
        + (["flywheel"] if has_flywheel else [])
        + (["load"] if opts.load_inertia else [])
    )
    mean_inertias = np.array(
        ([opts.free_end_inertia] if front else [])
        + [s.mean_kg_m2 for s in crank_series]
        + ([design.flywheel_inertia_kg_m2] if has_flywheel else [])
        + ([opts.load_inertia] if opts.load_inertia else [])
    )
    crank_nodes = np.arange(front, front + cranks)
    if mean_inertias.size < 2:
        raise SceneError(
            Problem(
                "torsion",
                "[torsion]",
                "a torsional model needs at least two discs: this engine has "
                "one crank and needs no flywheel; give flywheel.inertia or a load disc",
            )
        )
    reference = front + cranks if has_flywheel else front + cranks - 1  # keeps the absolute angle
    K = tor.stiffness_matrix(spans)
    modes = tor.natural_modes(mean_inertias, spans)
    C = tor.modal_damping_matrix(mean_inertias, spans, opts.damping_ratio)
    eigen = tor.modal_eigenvalues(modes.omega_rad_s, opts.damping_ratio)
    load = float(gas_series.mean.sum())
    model = tor.ShaftModel(
        gas_series, crank_series, crank_nodes, mean_inertias, K, C, load, reference
    )
    return _Shaft(
        names,
        spans,
        mean_inertias,
        crank_nodes,
        reference,
        K,
        C,
        modes,
        eigen,
        load,
        model,
        total_torque,
    )


#: The tightest rtol the steady state's search tightens a default one to, and the cycles the
#: default rtol is given first (light damping settles in more: the tighter runs get them all).
TIGHTEST_RTOL = 1e-8
FIRST_TRY_CYCLES = 10


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
    linear = tor.forced_response(
        shaft.mean_inertias,
        shaft.K,
        shaft.C,
        sf.PeriodicSeries.from_samples(node_torque, period),
        omega_n,
        reference,
    )
    x0 = linear(0.0)
    v0 = omega_n * (1.0 + linear.derivative()(0.0))
    v0 += float(exact.omega_at(0.0)) - v0[reference]
    z0 = shaft.model.state(x0 - x0[reference], v0)
    twist_scale = max(float(np.max(np.abs(total_torque))) / min(shaft.spans), 1e-12)
    speed_scale = max(exact.omega_max_rad_s - exact.omega_min_rad_s, 1e-9 * omega_n)

    def atol(rtol):
        return np.concatenate(
            [
                [rtol * 1e-3],
                np.full(n - 1, rtol * 1e-3 * twist_scale),
                np.full(n, rtol * 1e-3 * omega_n),
            ]
        )

    def settle(rtol: float, cycles: int):
        return tor.periodic_steady_state(
            shaft.model,
            z0,
            period,
            period / omega_n,
            method,
            rtol,
            atol(rtol),
            twist_scale,
            speed_scale,
            opts.steady_tolerance,
            cycles,
        )

    # A solver error above the steady tolerance keeps the cycles from repeating one another (a
    # stiff shaft's small twist scale): a default rtol is tried for a few cycles, then tightened.
    tighten = "rtol" not in opts.model_fields_set
    rtol, cycles = opts.rtol, int(opts.max_cycles)
    steady = settle(rtol, min(cycles, FIRST_TRY_CYCLES) if tighten else cycles)
    while not steady.converged and tighten and rtol > TIGHTEST_RTOL:
        rtol = max(rtol / 100.0, TIGHTEST_RTOL)
        steady = settle(rtol, cycles)
    final = steady.runs[-1]
    if not final.success or final.sol is None:
        raise SceneError(
            Problem(
                "torsion.solver",
                method,
                f"the solver failed on the torsional model ({final.message}); "
                'try solver = "auto" or "Radau"',
            )
        )
    return steady, final, atol, twist_scale


def _mode_rows(modes: tor.Modes, n: int) -> list[dict]:
    """The elastic modes (the rigid-body mode 0 left out): natural frequency and shape."""
    return [
        {
            "mode": s,
            "natural_frequency_rad_s": float(modes.omega_rad_s[s]),
            "natural_frequency_Hz": float(modes.omega_rad_s[s] / (2 * math.pi)),
            "shape": [float(a) for a in modes.shapes[:, s]],
        }
        for s in range(1, n)
    ]


def _harmonic_rows(orders, coefficients, significant: float, shaft: _Shaft) -> list[dict]:
    """One crank's torque harmonics up to the last significant order (at least MAX_ORDER), each with its
    relative vector sum over the cranks (each crank's own harmonic: :func:`tor.crank_vector_sum`)
    and critical speed for every elastic mode; ``coefficients`` has one row per crank."""
    n, modes = shaft.n, shaft.modes
    rows = []
    for j, order in enumerate(orders):
        if order > max(MAX_ORDER, significant) + 1e-9:
            break
        rows.append(
            {
                "order": float(order),
                "amplitude_Nm": float(abs(coefficients[0][j])),
                "vector_sum": [
                    tor.crank_vector_sum(
                        modes.shapes[shaft.crank_nodes, s], [c[j] for c in coefficients]
                    )
                    for s in range(1, n)
                ],
                "critical_rpm": [
                    float(tor.critical_speed_rpm(modes.omega_rad_s[s], order)) for s in range(1, n)
                ],
            }
        )
    return rows


def _torsion(scene, torque, crank_loads, design, train, exact, opts: TorsionOptions):
    """The torsional section's results and table: the shaft model, its modes and the harmonics of the
    crank torque, the solver chosen by stiffness, the periodic state and its twists and span torques."""
    omega_n = torque.angular_velocity_rad_s
    shaft = _shaft(torque, crank_loads, design, train, opts)
    n, reference, spans = shaft.n, shaft.reference, shaft.spans

    # Harmonic orders of each crank's torque (gas + inertia at the nominal speed); the first's
    # amplitudes are the table's
    spectra = [sf.harmonic_amplitudes(m, torque.strokes / 2, 1e9) for m in shaft.total_torque]
    orders, coefficients = spectra[0][0], [c for _, c in spectra]
    significant = sf.significant_order(orders, np.abs(coefficients[0]))
    choice = sf.choose_solver(
        shaft.eigen, math.pi * torque.strokes / omega_n, significant * omega_n
    )
    forced = None if opts.solver == "auto" else opts.solver
    steady, final, atol, twist_scale = _periodic_state(
        shaft, torque, exact, opts, forced or choice.method
    )
    curves = _periodic_curves(shaft, steady, final, torque, exact)
    twist, span_torque, fly_speed = curves["twist"], curves["span_torque"], curves["fly_speed"]
    f_max, f_min = float(fly_speed.max()), float(fly_speed.min())
    mode_rows = _mode_rows(shaft.modes, n)
    harmonic_rows = _harmonic_rows(orders, coefficients, significant, shaft)

    results = {
        "nodes": [
            {"name": name, "inertia_mean_kg_m2": float(j)}
            for name, j in zip(shaft.names, shaft.mean_inertias, strict=True)
        ],
        "reference_node": int(reference),
        "span_stiffness_N_m_rad": [float(k) for k in spans],
        "damping_ratio": opts.damping_ratio,
        "modes": mode_rows,
        "harmonics": harmonic_rows,
        "significant_order": significant,
        "critical_speeds_near_operating": critical_near(harmonic_rows, mode_rows, scene.engine.rpm),
        "critical_band_relative": CRITICAL_BAND,
        "operating_rpm": scene.engine.rpm,
        "solver": {**_choice_record(choice, "torsion", forced), "rtol": final.rtol},
        "steady_state": _steady_state_record(steady, final, shaft, opts, omega_n),
        "twist_max_rad": [float(np.max(np.abs(t))) for t in twist],
        "span_torque_max_Nm": [float(np.max(np.abs(t))) for t in span_torque],
        "flywheel_irregularity": (f_max - f_min) / (0.5 * (f_max + f_min)),
        "flywheel_speed_deviation_from_rigid_relative": float(
            np.max(np.abs(fly_speed - curves["rigid"])) / omega_n
        ),
        "compare_fraction": opts.compare_fraction,
        "reference_rtol": opts.reference_rtol,
        "solvers": [],
    }
    if opts.compare_solvers:
        results["solvers"] = _torsion_solvers(
            shaft.model, steady, atol, opts, n, twist_scale, omega_n
        )
    return results, {"torsion": _torsion_table(shaft, curves)}


def _periodic_curves(shaft, steady, final, torque, exact) -> dict:
    """Over one cycle of the periodic state, at the table's steps: the flywheel's angle, each
    span's twist and torque, each disc's speed and the rigid shaft's flywheel speed."""
    n, reference = shaft.n, shaft.reference
    alpha = np.radians(torque.crank_angle_deg)
    z = final.sol(np.linspace(0.0, steady.cycle_time_s, alpha.size + 1)[:-1])
    theta = shaft.model.P @ z[:n]
    speeds = z[n:]
    flywheel_angle = np.degrees(theta[reference] - theta[reference][0])
    twist = theta[1:] - theta[:-1]  # span j: disc j+1 minus disc j
    return {
        "flywheel_angle": flywheel_angle,
        "twist": twist,
        "span_torque": np.asarray(shaft.spans)[:, None] * twist,
        "speeds": speeds,
        "fly_speed": speeds[reference],
        # The rigid-shaft (single-mass) flywheel speed at the same flywheel angles, for comparison.
        "rigid": exact.omega_at(np.radians(flywheel_angle)),
    }


def _steady_state_record(steady, final, shaft, opts: TorsionOptions, omega_n: float) -> dict:
    """How the periodic state was reached: cycles, convergence, load, damping loss and cost."""
    return {
        "cycles": steady.cycles,
        "converged": steady.converged,
        "change": steady.change if math.isfinite(steady.change) else None,
        "tolerance": opts.steady_tolerance,
        "load_torque_Nm": steady.load_torque_Nm,
        "damping_loss_W": (shaft.load - steady.load_torque_Nm) * omega_n,
        "steps_per_cycle": final.steps,
        "nfev_per_cycle": final.nfev,
        "time_s": sum(r.time_s for r in steady.runs),
    }


def _torsion_table(shaft, curves: dict) -> dict:
    """The torsion table: the flywheel's angle, each span's twist and torque, each disc's speed
    and the rigid shaft's."""
    n, twist, span_torque, speeds = (
        shaft.n,
        curves["twist"],
        curves["span_torque"],
        curves["speeds"],
    )
    return {
        "shaft_angle_deg": curves["flywheel_angle"],
        **{f"twist_{j + 1}_rad": twist[j] for j in range(n - 1)},
        **{f"span_torque_{j + 1}_Nm": span_torque[j] for j in range(n - 1)},
        **{f"speed_{name.replace(' ', '')}_rad_s": speeds[i] for i, name in enumerate(shaft.names)},
        "rigid_speed_rad_s": curves["rigid"],
    }


def _torsion_solvers(model, steady, atol, opts, n, twist_scale, omega_n):
    """Every solver over a window of the periodic state (a quarter cycle by default), against a
    Radau run at a much tighter tolerance. RK45 gets at most ``explicit_budget`` evaluations,
    and no more than 10 times what the costliest implicit solver used at the same rtol."""
    span = (0.0, steady.cycle_time_s * opts.compare_fraction)
    z = steady.state
    reference = sf.run_solver(
        model,
        span,
        z,
        "Radau",
        opts.reference_rtol,
        atol(opts.reference_rtol),
        jac=model.jacobian,
        dense_output=True,
    )
    records = [_run_record(reference, 0.0, {"reference": True, "error_twist_relative": 0.0})]
    if not reference.success:
        return records
    for rtol in opts.compare_rtols:
        implicit = []
        for method in ("Radau", "BDF", "LSODA", "RK45"):
            budget = None
            if method == "RK45":
                budget = int(min(opts.explicit_budget, 10 * max(implicit + [100])))
            run = sf.run_solver(
                model, span, z, method, rtol, atol(rtol), jac=model.jacobian, max_nfev=budget
            )
            if run.success and run.steps > 0:
                exact = reference.sol(run.t)
                with np.errstate(all="ignore"):
                    error = float(np.max(np.abs(run.y[n:] - exact[n:]))) / omega_n
                    error_twist = float(np.max(np.abs(run.y[1:n] - exact[1:n]))) / twist_scale
            else:
                error = error_twist = None
            if method != "RK45":
                implicit.append(run.nfev)
            records.append(
                _run_record(run, error, {"reference": False, "error_twist_relative": error_twist})
            )
    return records
