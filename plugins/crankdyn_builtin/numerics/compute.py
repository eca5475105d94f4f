"""Error against run time, measured on the scene itself.

Three studies, all measured when the report is made:

* **angle step** — the scene's own pipeline re-run at angle steps from 30° to 0.1°
  (:mod:`.steps`): at each step the run time and the errors of the mean torque, the indicated
  work, the extremes of the tangential force t and the largest resultant crank-pin force q against
  references that do not use the method under test (:mod:`.reference`). A theoretical diagram's
  work is also checked against its closed form.
* **piston kinematics** — the textbook two-term form, the Maclaurin series in λ with 3, 4 and 5
  terms (power and harmonic forms) and the exact form: largest error of s and j against an
  extended-precision evaluation of the exact form, and time per evaluation.
* **solvers** — other plugins add error-against-time rows with the ``crankdyn_error_probes`` hook
  (e.g. a flywheel speed solver at a range of tolerances).

A process that reports on several scenes of one mechanism (a batch worker, the live preview)
measures the run times of the steps and of the kinematics forms for the first of them only:
they depend on the mechanism and the number of angles, not on the speed, masses or pressures.
The errors are each scene's own.
"""

from __future__ import annotations

import functools
import json
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from crankdyn.errors import CrankdynError, Problem, SceneError
from crankdyn.physics.layout import step_on_grid_deg
from crankdyn.plugin.contracts import GAS_PRESSURE
from crankdyn.plugin.types import (
    SERVICE_ASIDE,
    SERVICE_ERROR_PROBES,
    SERVICE_RUNNER,
    StageOutput,
)
from crankdyn.scene import (
    Scene,
    options,
)

from .options import NumericsOptions, default_angle_step_deg
from .reference import (
    FALLBACK_REFERENCE_STEP_DEG,
    PointwiseModel,
    Reference,
    kinematics_forms,
    reference_values,
)
from .steps import (
    MIN_REPEAT_S,
    StepRun,
    Timing,
    _motion,
    best_times,
    drawn_rounding,
    needed_stages,
    run_at_step,
    scene_with_step,
)

# A whole re-run through the stages (a mechanism without a pointwise model) costs the study itself
# once per repeat: best of a few is enough there, since its fixed overhead is part of what it times.
_RERUN_REPEATS = 3


# The steps' timing stops before ``repeats`` once this many rounds in a row lowered no step's best
# time by more than this fraction (the minima have settled; a loaded machine gets more rounds).
_SETTLED_ROUNDS = 3


QUANTITIES = ("mean_torque", "indicated_work", "tangential_max", "tangential_min", "resultant_max")


QUANTITY_UNITS = {
    "mean_torque": "Nm",
    "indicated_work": "J",
    "tangential_max": "Pa",
    "tangential_min": "Pa",
    "resultant_max": "Pa",
}


def _step_formulas(model: PointwiseModel, run: StepRun) -> Callable[[], tuple]:
    """The formulas of a step on its N angles: piston acceleration, rod angle, forces, torque, and the
    judged values (mean torque, t_max, t_min, q_max), from the step's pressure curve."""
    gas = next(o.data[GAS_PRESSURE] for o in run.outputs.values() if GAS_PRESSURE in o.data)
    angles, pressure = (
        np.asarray(gas.crank_angle_deg, dtype=float),
        np.asarray(gas.pressure_Pa, dtype=float),
    )

    def formulas():
        tangential, resultant, torque = model.forces(angles, pressure)
        return (
            np.mean(torque),
            np.max(tangential),
            np.min(tangential),
            None if resultant is None else np.max(resultant),
        )

    return formulas


def time_steps(
    scene: Scene,
    runs: list[StepRun],
    repeats: int,
    runner,
    *,
    clock: Callable[[], float] = time.perf_counter,
) -> tuple[str, list[Timing], float | None]:
    """(what was timed, a :class:`Timing` per run, the fixed per-call overhead in s or None).

    ``formulas``: each step's formulas (:func:`_step_formulas`) on its own angles; the re-run
    through the stages costs a fixed amount more per call (argument checks, the rounding's junction
    points, results and tables) — the overhead, the smallest difference over the steps between the
    whole re-run and its formulas. ``rerun``: without a pointwise model of the mechanism the whole
    re-run is timed, overhead included (None).
    """
    motion = _motion(runs[0])
    try:
        model = PointwiseModel(scene, motion, drawn_rounding(runs[0]))
    except ValueError:
        model = None
    if model is None:
        plans = []
        for r in runs:
            copy = scene_with_step(scene, r.step_deg)
            plans.append(
                functools.partial(runner.run, copy, runner.plan(copy, needed_stages(copy, runner)))
            )
        return (
            "rerun",
            best_times(plans, min(repeats, _RERUN_REPEATS), min_time_s=MIN_REPEAT_S, clock=clock),
            None,
        )
    timings = best_times(
        [_step_formulas(model, r) for r in runs],
        repeats,
        min_time_s=MIN_REPEAT_S,
        clock=clock,
        settled_rounds=_SETTLED_ROUNDS,
    )
    return "formulas", timings, _overhead(runs, timings)


def _overhead(runs: list[StepRun], timings: list[Timing]) -> float:
    """The re-run's fixed cost per call beyond the formulas: the smallest difference over the steps."""
    return max(0.0, min(r.time_s - t.best_s for r, t in zip(runs, timings, strict=True)))


@functools.lru_cache(maxsize=8)
def _kept_timings(key: str) -> list:
    """The timings measured in this process for the steps of ``key`` (:func:`_timing_key`): empty
    until the first measurement is put in."""
    return []


def _timing_key(scene: Scene, runs: list[StepRun], repeats: int) -> str:
    """What the steps' run times depend on: the mechanism (the engine but its speed), the
    analysis settings and each step's angles; not the speed, masses or pressures, whose values
    the same formulas compute as fast."""
    return json.dumps(
        [
            scene.engine.model_dump(mode="json", exclude={"rpm"}),
            scene.analysis.model_dump(mode="json"),
            [(r.step_deg, r.points) for r in runs],
            repeats,
        ],
        sort_keys=True,
        default=str,
    )


def _steps_timed(
    scene: Scene, runs: list[StepRun], repeats: int, runner
) -> tuple[str, list[Timing], float | None]:
    """:func:`time_steps`, the timings measured once per process for a mechanism and its steps:
    a batch's variants of one mechanism (a worker's next report) and the preview's next save
    take the timings measured for the first, as they take the kinematics forms'. The per-call
    overhead is each run's own."""
    kept = _kept_timings(_timing_key(scene, runs, repeats))
    if not kept:
        timed, timings, _ = time_steps(scene, runs, repeats, runner)
        kept.append((timed, timings))
    timed, timings = kept[0]
    return timed, timings, None if timed == "rerun" else _overhead(runs, timings)


# ------------------------------------------------------------------ the stage
def applies(scene) -> str | None:
    if scene.cycle is None or scene.masses is None:
        missing = " and ".join(
            t for t, v in (("[cycle]", scene.cycle), ("[masses]", scene.masses)) if v is None
        )
        return (
            f"the scene has no {missing}: there is no cycle to integrate "
            "(the kinematics part is in numerics_kinematics)"
        )
    return None


def applies_kinematics(scene) -> str | None:
    if scene.cycle is not None and scene.masses is not None:
        return "the scene has cycle data: the numerics stage covers its kinematics too"
    if scene.engine.mechanism != "crank_slider":
        return "the series forms concern the central crank-slider only"
    return None


@functools.lru_cache(maxsize=8)
def _kinematics_forms_measured(radius: float, ratio: float, repeats: int) -> tuple:
    return tuple(kinematics_forms(radius, ratio, repeats=repeats))


def _kinematics_forms(radius: float, ratio: float, repeats: int) -> list[dict]:
    """:func:`kinematics_forms`, measured once per process for a crank radius and rod ratio: the
    forms' errors depend on nothing else, and a batch's variants of one mechanism (a worker's
    next report) take the rows, timings included, measured for the first."""
    return [dict(row) for row in _kinematics_forms_measured(radius, ratio, repeats)]


def _relative(value, reference):
    if reference == 0:
        return abs(value - reference)
    return abs(value - reference) / abs(reference)


def _kinematics_part(scene, opts, results, tables) -> None:
    if not opts.kinematics_forms or scene.engine.mechanism != "crank_slider":
        return
    e = scene.engine
    # the forms differ by factors, not by per cent as neighbouring steps do: fewer repeats suffice
    rows = _kinematics_forms(e.crank_radius_m, e.rod_ratio_value, max(3, opts.repeats // 3))
    results["kinematics_forms"] = rows
    results["kinematics_method"] = scene.analysis.kinematics
    # CSV: one text column names the form ("series-3"); no empty cells for the exact form's terms
    tables["kinematics_forms"] = [
        {
            "form": row["form"] + (f"-{row['terms']}" if row["terms"] else ""),
            **{k: v for k, v in row.items() if k not in ("form", "terms")},
        }
        for row in rows
    ]


def _step_rows(runs: list[StepRun], timings: list[Timing], reference: Reference) -> list[dict]:
    """One row per step: points, the timed formulas, the re-run's wall time, values and their errors."""
    ref = reference.values
    step_rows = []
    for r, timing in zip(runs, timings, strict=True):
        row = {
            "angle_step_deg": r.step_deg,
            "points": r.points,
            "time_s": timing.best_s,
            "timing_loops": timing.loops,
            "rerun_time_s": r.time_s,
        }
        for q in QUANTITIES:
            row[f"{q}_{QUANTITY_UNITS[q]}"] = r.values[q]
            row[f"{q}_error_relative"] = _relative(r.values[q], ref[q])
        if reference.theoretical_work_J is not None and r.theoretical_work_J is not None:
            row["theoretical_work_error_relative"] = _relative(
                r.theoretical_work_J, reference.theoretical_work_J
            )
        step_rows.append(row)
    return step_rows


def run(scene, inputs) -> StageOutput:
    runner, probes, aside = (
        inputs[SERVICE_RUNNER],
        inputs[SERVICE_ERROR_PROBES],
        inputs[SERVICE_ASIDE],
    )
    opts = options(scene, "numerics", NumericsOptions)
    results: dict[str, Any] = {}
    tables: dict[str, Any] = {}
    notes: list = []
    scene_step = scene.analysis.angle_step_deg

    # The scene's own step is always in the study (first): its values are the ones this report
    # prints. The other steps follow from coarse to fine while the time budget lasts.
    # Each study step is moved onto the engine's grid (the largest step grid/k not above it), so
    # that it divides the cycle and every firing interval for any number of cylinders.
    others = sorted(set(study_steps_deg(scene, opts.steps_deg)) - {scene_step}, reverse=True)
    refused: dict[str, str] = {}
    start = time.perf_counter()
    sample = _run_or_refuse(scene, scene_step, opts, runner, refused)
    if sample is None:
        # The pipeline cannot be re-run from the installed plugins (e.g. a mechanism registered
        # only in a custom registry): no step study, said so in results.json and the report.
        results["steps_unavailable"] = refused.get(
            f"{scene_step:g}", "the scene's pipeline cannot be re-run"
        )
        _merge(results, tables, _side_studies(scene, opts, None, runner, probes))
        return StageOutput(data={}, results=results, tables=tables, notes=notes)
    # the reference, the kinematics forms and the solvers need none of the other steps' re-runs:
    # computed beside them when the report's process has a core to spare (crankdyn.aside)
    with aside(_side_studies, scene, opts, sample, runner, probes) as side:
        runs = [sample] + _runs_within_budget(scene, others, opts, runner, refused, start)
        runs.sort(key=lambda r: -r.step_deg)
        timed, timings, overhead = _steps_timed(scene, runs, opts.repeats, runner)
        studies = side.result()
    reference = studies["reference"]
    ref = reference.values
    step_rows = _step_rows(runs, timings, reference)
    printed = sample.values  # the re-run at the scene's own step: the numbers this report prints

    at_scene = _at_scene_step(scene_step, printed, ref)

    _refuse_if_too_coarse(scene, opts, at_scene, step_rows)
    notes += _peaks_against_tolerance(scene, opts, at_scene, step_rows)

    results.update(_study_results(reference, step_rows, timed, timings, overhead, refused))
    results["at_scene_step"] = at_scene
    tables["steps"] = step_rows
    _merge(results, tables, studies)
    return StageOutput(data={}, results=results, tables=tables, notes=notes)


def _runs_within_budget(scene, steps, opts, runner, refused: dict[str, str], start: float) -> list:
    """The re-runs at ``steps`` (coarse to fine) while the time budget since ``start`` lasts; the
    steps left out, and why, in ``refused``."""
    runs = []
    for step in steps:
        if time.perf_counter() - start > opts.time_budget_s:
            refused[f"{step:g}"] = (
                f"{BUDGET_REASON} of {opts.time_budget_s:g} s was spent ([numerics] time_budget_s)"
            )
            continue
        run = _run_or_refuse(scene, step, opts, runner, refused)
        if run is not None:
            runs.append(run)
    return runs


def _at_scene_step(scene_step: float, printed, ref) -> dict:
    """The printed values at the scene's own step and their errors against the reference."""
    at_scene = {"angle_step_deg": scene_step}
    for q in QUANTITIES:
        at_scene[f"{q}_{QUANTITY_UNITS[q]}"] = printed[q]
        at_scene[f"{q}_error_{QUANTITY_UNITS[q]}"] = abs(printed[q] - ref[q])
        at_scene[f"{q}_error_relative"] = _relative(printed[q], ref[q])
    return at_scene


def _study_results(reference, step_rows, timed, timings, overhead, refused) -> dict:
    """The step study's results: the reference, the steps with their errors and timings."""
    return {
        "reference_method": reference.method,
        "reference_step_deg": FALLBACK_REFERENCE_STEP_DEG
        if reference.method != "quadrature"
        else None,
        "reference_time_s": reference.time_s,
        "reference": {f"{q}_{QUANTITY_UNITS[q]}": reference.values[q] for q in QUANTITIES},
        "reference_uncertainty_relative": reference.uncertainty,
        "theoretical_work_closed_form_J": reference.theoretical_work_J,
        "steps": step_rows,
        "steps_timed": timed,
        "steps_timing_repeats": timings[0].repeats,
        "steps_timing_min_repeat_s": MIN_REPEAT_S,
        "per_call_overhead_s": overhead,
        "steps_refused": refused,
    }


def _run_or_refuse(scene, step: float, opts, runner, refused: dict[str, str]) -> StepRun | None:
    """The re-run at ``step``, or None with the reason in ``refused``."""
    try:
        return run_at_step(scene, step, opts.repeats, runner=runner)
    except (CrankdynError, ValueError) as exc:
        refused[f"{step:g}"] = "; ".join(p.allowed for p in getattr(exc, "problems", [])) or str(
            exc
        )
        return None


def _side_studies(scene, opts, sample: StepRun | None, runner, probes) -> dict[str, Any]:
    """What the study computes beside the re-runs at the other steps: the reference (with a
    ``sample``, the re-run at the scene's step), the kinematics forms and the solver studies."""
    out: dict[str, Any] = {"results": {}, "tables": {}}
    if sample is not None:
        try:
            out["reference"] = reference_values(scene, sample, runner)
        except ValueError as exc:  # the pointwise model refused an angle: use a fine step, say why
            run = run_at_step(scene, FALLBACK_REFERENCE_STEP_DEG, repeats=1, runner=runner)
            out["reference"] = Reference("fine_step", run.values, {}, 0.0, note=str(exc))
    _kinematics_part(scene, opts, out["results"], out["tables"])
    _probes(scene, out["results"], probes, runner)
    return out


def _merge(results: dict, tables: dict, studies: dict[str, Any]) -> None:
    results.update(studies["results"])
    tables.update(studies["tables"])


def study_steps_deg(scene, steps_deg) -> list[float]:
    """The study's steps on the engine's grid: each the largest grid/k not above the one asked for."""
    grid = scene.engine_grid_deg
    return sorted({step_on_grid_deg(grid, float(s)) for s in steps_deg}, reverse=True)


PEAKS = ("tangential_max", "tangential_min", "resultant_max")


def _peaks_against_tolerance(scene, opts, at_scene, step_rows) -> list:
    """The largest relative error of the reported peaks at the scene's step against [numerics] tolerance.

    Records it in ``at_scene`` and returns the method notes: how a defaulted step was chosen and
    what its peaks measure against the accuracy required, or, when the peaks are off by more than
    the tolerance, that the step misses it and the coarsest measured step that keeps them.
    The notes print the error to two digits, as an engineer states an accuracy (three or more
    where two would read as the tolerance itself).
    """

    def worst(row):
        return max(row[f"{q}_error_relative"] for q in PEAKS)

    error = worst(at_scene)
    at_scene.update(
        {
            "peaks_error_relative": error,
            "tolerance_relative": opts.tolerance,
            "peaks_within_tolerance": bool(error <= opts.tolerance),
            "step_defaulted": scene.angle_step_defaulted,
            "grid_deg": scene.engine_grid_deg,
        }
    )
    notes = []
    if scene.angle_step_defaulted:
        # the step at its upper limit is no "largest step not above" itself: said plainly
        at_limit = scene.analysis.angle_step_deg == default_angle_step_deg(scene)
        notes.append(
            (
                "numerics.note_default_step"
                + ("_at_limit" if at_limit else "")
                + ("_articulated" if scene.engine.rod_type == "articulated" else ""),
                {
                    "step": scene.analysis.angle_step_deg,
                    "grid": scene.engine_grid_deg,
                    "limit": default_angle_step_deg(scene),
                    "tolerance": 100 * opts.tolerance,
                },
            )
        )
    if error <= opts.tolerance:
        if scene.angle_step_defaulted:
            notes.append(
                (
                    "numerics.note_peaks_within",
                    {"error": _stated(error, opts.tolerance), "tolerance": 100 * opts.tolerance},
                )
            )
        return notes
    good = [row["angle_step_deg"] for row in step_rows if worst(row) <= opts.tolerance]
    params = {
        "step": scene.analysis.angle_step_deg,
        "error": _stated(error, opts.tolerance),
        "tolerance": 100 * opts.tolerance,
    }
    if good:  # the step as a number, printed in the report's locale
        notes.append(("numerics.note_peaks_beyond", {**params, "finer": float(max(good))}))
    else:
        notes.append(("numerics.note_peaks_beyond_studied", params))
    return notes


def _stated(error: float, tolerance: float) -> float:
    """``error`` in percent to two significant digits, more where two equal ``tolerance``'s."""
    for digits in (2, 3, 4, 6):
        rounded = float(f"{100 * error:.{digits}g}")
        if rounded != float(f"{100 * tolerance:.6g}"):
            return rounded
    return 100 * error


def _refuse_if_too_coarse(scene, opts, at_scene, step_rows) -> None:
    """No silent wrong numbers: refuse a step whose measured integrals are off by more than allowed.

    A stiff scene (e.g. an offset crank close to locking, where the piston's acceleration spikes
    near BDC) can make the scene's step far too coarse; the error is measured against the
    step-independent reference, and the message names the coarsest measured step that is good enough.
    """
    limit = opts.max_error_percent / 100.0

    def worst(row):
        return max(row["mean_torque_error_relative"], row["indicated_work_error_relative"])

    if worst(at_scene) <= limit:
        return
    good = [row for row in step_rows if worst(row) <= limit]
    if good:
        row = max(good, key=lambda r: r["angle_step_deg"])
        hint = f"Δα = {row['angle_step_deg']:g}° keeps both within it ({100 * worst(row):.2g} %)"
    else:
        hint = "choose a finer step"
    raise SceneError(
        Problem(
            "analysis.angle_step_deg",
            scene.analysis.angle_step_deg,
            f"too coarse for this scene: at {scene.analysis.angle_step_deg:g}° the mean torque is "
            f"{100 * at_scene['mean_torque_error_relative']:.3g} % and the indicated work "
            f"{100 * at_scene['indicated_work_error_relative']:.3g} % off a reference that does not depend on the step "
            f"(at most {opts.max_error_percent:g} % allowed, [numerics] max_error_percent); {hint}",
        )
    )


def _probes(scene, results, probes, runner) -> None:
    studies = {}
    for probe in probes:
        try:
            if not probe.applies(scene):
                continue
            points = probe.run(scene, runner)
            studies[probe.name] = {"title": probe.title, "points": [p.__dict__ for p in points]}
        except CrankdynError as exc:
            studies[probe.name] = {"title": probe.title, "refused": str(exc), "points": []}
    if studies:
        results["solvers"] = studies


def run_kinematics(scene, inputs) -> StageOutput:
    runner, probes = inputs[SERVICE_RUNNER], inputs[SERVICE_ERROR_PROBES]
    opts = options(scene, "numerics", NumericsOptions)
    results: dict[str, Any] = {}
    tables: dict[str, Any] = {}
    _kinematics_part(scene, opts, results, tables)
    _probes(scene, results, probes, runner)
    return StageOutput(data={}, results=results, tables=tables)


#: How results.json words a step left out for the study's time budget (see ``run``).
BUDGET_REASON = "left out: the study's time budget"
