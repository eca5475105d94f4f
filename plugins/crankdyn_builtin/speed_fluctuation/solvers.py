"""The ODE methods the speed-fluctuation stage compares and the records it keeps of each run and
of the method it chose (results.json ``solver``)."""

from __future__ import annotations

import math

from crankdyn.physics import speed_fluctuation as sf

METHODS = ("RK45", "Radau", "BDF", "LSODA")

#: Tolerances of the single-mass comparison (the exact reference makes every error a true error).
SINGLE_MASS_RTOLS = (1e-3, 1e-5, 1e-7)

#: rtol of the single-mass run shown in the report.
SINGLE_MASS_RTOL = 1e-8


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
    outcome = (
        "finished" if success else ("budget" if message.startswith("stopped after") else "failed")
    )
    if outcome == "budget":
        message = f"stopped by the evaluation budget, not a failure: {message}"
    record = {
        "method": run.method,
        "rtol": run.rtol,
        "success": success,
        "outcome": outcome,
        "message": message,
        "steps": run.steps,
        "steps_needed": run.steps_needed if math.isfinite(run.steps_needed) else None,
        "nfev": run.nfev,
        "njev": run.njev,
        "nlu": run.nlu,
        "time_s": run.time_s,
        "progress": run.progress,
        "error_relative": error if success else None,
    }
    record.update(extra)
    return record


def _choice_record(choice: sf.SolverChoice, kind: str, forced: str | None = None) -> dict:
    method = forced or choice.method
    if forced:
        reason = f'{forced} as the scene asks (solver = "{forced}")'
    elif kind == "single":
        reason = (
            f"{choice.method}: one degree of freedom whose only eigenvalue, |J' omega / J| <= "
            f"{choice.fastest_rad_s:.3g} 1/s, lets RK45 take {choice.stability_steps:.3g} steps per cycle "
            f"for stability while following the torque needs about {choice.resolution_steps:.3g}: not stiff, "
            f"the explicit solver is the cheapest"
        )
    elif choice.stiff:
        reason = (
            f"Radau: stiff - the fastest shaft mode (|lambda| = {choice.fastest_rad_s:.3g} 1/s) limits RK45 to "
            f"steps below {choice.stable_step_s:.3g} s, {choice.stability_steps:.3g} steps per cycle, while the "
            f"solution only needs about {choice.resolution_steps:.3g} to follow the torque harmonics up to "
            f"{choice.resolved_frequency_rad_s:.3g} rad/s (ratio {choice.ratio:.3g} > "
            f"{sf.STIFFNESS_THRESHOLD:g}); Radau IIA is A- and L-stable, BDF of order 3-5 is not A-stable for "
            f"lightly damped modes"
        )
    else:
        reason = (
            f"RK45: not stiff - RK45 needs {choice.stability_steps:.3g} steps per cycle for stability and about "
            f"{choice.resolution_steps:.3g} to follow the solution (ratio {choice.ratio:.3g} <= "
            f"{sf.STIFFNESS_THRESHOLD:g}), and an explicit step is cheaper than an implicit one"
        )
    return {
        "method": method,
        "automatic": forced is None,
        "stiff": choice.stiff,
        "reason": reason,
        "fastest_eigenvalue_rad_s": choice.fastest_rad_s,
        "stable_step_s": choice.stable_step_s if math.isfinite(choice.stable_step_s) else None,
        "stability_steps_per_cycle": choice.stability_steps,
        "resolved_frequency_rad_s": choice.resolved_frequency_rad_s,
        "resolution_steps_per_cycle": choice.resolution_steps,
        "stiffness_ratio": choice.ratio,
    }
