"""Re-runs of the scene's own pipeline at another angle step, and the best-of-repeats timing of
the studies (``time.perf_counter``).

The pipeline is re-run through the orchestrator's runner (``SERVICE_RUNNER`` in ``inputs``), over
the registry the scene itself runs with; this stage never builds a registry of its own."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from pydantic import ValidationError

from crankdyn.errors import PluginError, SceneError
from crankdyn.physics import forces as phys
from crankdyn.plugin.contracts import ENGINE_TORQUE, FORCES, GAS_PRESSURE, KINEMATICS
from crankdyn.scene import (
    Analysis,
    Scene,
    _problems,  # one error format for every refusal
)

# timeit-style timing of a step's compute: calls per timed repeat grow (1, 2, 5, 10, 20, ...)
# until one repeat takes at least this long, then the best of ``repeats`` such repeats is kept.
# Short repeats, many of them, taken in turns over the steps: the minimum of many short windows
# is what an unloaded machine gives, even when other jobs share the cores.
MIN_REPEAT_S = 2.5e-4


_SETTLED_RELATIVE = 0.01


# ------------------------------------------------------------------ scene copies and re-runs
def scene_with_step(scene: Scene, step_deg: float) -> Scene:
    """A validated copy of ``scene`` at another angle step (tables at every point, all stages).

    The copy keeps every table, the plugin tables and ``base_dir``; the scene-level checks
    (the step divides the cycle) run again and raise SceneError when they fail.
    """
    analysis = Analysis.model_validate(
        {
            "angle_step_deg": step_deg,
            "table_step_deg": step_deg,
            "kinematics": scene.analysis.kinematics,
            "stages": None,
        }
    )
    try:
        return Scene.model_validate({**dict(scene), "analysis": analysis})
    except ValidationError as exc:
        raise SceneError(_problems(exc, {})) from None


def needed_stages(scene, runner) -> list[str]:
    return [
        s.name
        for s in runner.stages.values()
        if (FORCES in s.provides or ENGINE_TORQUE in s.provides)
        and runner.applies(s, scene) is None
    ]


@dataclass
class StepRun:
    step_deg: float
    points: int
    time_s: float  # wall time of the one re-run that gave ``values`` (overhead included)
    values: dict[str, float]
    outputs: dict[str, Any] = field(default_factory=dict)
    theoretical_work_J: float | None = None


def _values(data, cylinders: int) -> dict[str, float]:
    """The judged numbers: the engine's mean torque (the cylinder's times ``cylinders`` when no
    stage gives the engine torque), the cylinder's indicated work, t_max, t_min and q_max."""
    forces, gas = data[FORCES], data[GAS_PRESSURE]
    torque = (
        data[ENGINE_TORQUE].torque_Nm if ENGINE_TORQUE in data else cylinders * forces.torque_Nm
    )
    q = phys.resultant_crank_pin_pressure_Pa(
        forces.tangential_Pa, forces.radial_Pa, forces.centrifugal_Pa
    )
    return {
        "mean_torque": float(np.mean(torque)),
        "indicated_work": float(gas.indicated_work_J),
        "tangential_max": float(np.max(forces.tangential_Pa)),
        "tangential_min": float(np.min(forces.tangential_Pa)),
        "resultant_max": float(np.max(q)),
    }


def run_at_step(scene: Scene, step_deg: float, repeats: int = 1, *, runner) -> StepRun:
    """Re-run the stages that give forces and engine torque at ``step_deg`` once.

    ``runner``: the orchestrator's :class:`crankdyn.engine.orchestrator.Runner` (``SERVICE_RUNNER``).
    ``repeats`` is kept for callers of earlier versions: the run time of the study is measured
    separately (:func:`time_steps`), with repeats, so one run gives the values.
    """
    copy = scene_with_step(scene, step_deg)
    the_plan = runner.plan(copy, needed_stages(copy, runner))
    start = time.perf_counter()
    result = runner.run(copy, the_plan)
    elapsed = time.perf_counter() - start
    data = {}
    for output in result.outputs.values():
        data.update(output.data)
    if not {FORCES, GAS_PRESSURE} <= set(data):
        raise PluginError("the re-run pipeline gives no forces")
    indicator = result.outputs.get("indicator")
    theoretical = None
    if indicator is not None and "theoretical_diagram_mean_pressure_Pa" in indicator.results:
        theoretical = (
            indicator.results["theoretical_diagram_mean_pressure_Pa"]
            * indicator.results["swept_volume_m3"]
        )
    return StepRun(
        step_deg=step_deg,
        points=len(copy.crank_angles_deg),
        time_s=elapsed,
        values=_values(data, scene.engine.cylinders),
        outputs=result.outputs,
        theoretical_work_J=theoretical,
    )


# ------------------------------------------------------------------ timing (timeit-style)
@dataclass(frozen=True)
class Timing:
    """Best time per call of a function: ``loops`` calls per timed repeat, best of ``repeats``."""

    best_s: float
    loops: int
    repeats: int


def _autorange(
    fn: Callable[[], Any], min_time_s: float, clock: Callable[[], float]
) -> tuple[int, float]:
    """(loops, seconds per call): loops 1, 2, 5, 10, 20, 50, ... until one repeat takes ``min_time_s``
    (as :meth:`timeit.Timer.autorange`)."""
    base = 1
    while True:
        for loops in (base, 2 * base, 5 * base):
            start = clock()
            for _ in range(loops):
                fn()
            elapsed = clock() - start
            if elapsed >= min_time_s or loops >= 1 << 20:
                return loops, elapsed / loops
        base *= 10


def best_times(
    functions: list[Callable[[], Any]],
    repeats: int,
    *,
    min_time_s: float = MIN_REPEAT_S,
    clock: Callable[[], float] = time.perf_counter,
    settled_rounds: int = 0,
) -> list[Timing]:
    """timeit-style best time per call of each function, the repeats taken in turns.

    Each function's loop count is found as :meth:`timeit.Timer.autorange` does (that first
    measurement counts as its first repeat); then up to ``repeats - 1`` further repeats go round
    all the functions in turn (backwards and forwards), so a burst of load on the machine slows
    every function alike rather than one step of the study, each repeat after one untimed call
    (warm caches). The minimum is kept: load only ever adds time.

    With ``settled_rounds`` > 0 the repeats stop early, once that many rounds in a row have
    lowered no function's best time by more than ``_SETTLED_RELATIVE``: the minima have settled,
    and further rounds cost time without changing them. A loaded machine keeps lowering some
    minimum, so it gets more rounds, up to ``repeats``.
    """
    ranged = [_autorange(fn, min_time_s, clock) for fn in functions]
    best = [per_call for _, per_call in ranged]
    taken, quiet = 1, 0
    for round_ in range(max(1, repeats) - 1):
        if settled_rounds and quiet >= settled_rounds:
            break
        # every other round backwards: no function always follows the same one (cache state)
        order = range(len(functions)) if round_ % 2 else range(len(functions) - 1, -1, -1)
        lowered = False
        for k in order:
            fn, loops = functions[k], ranged[k][0]
            fn()  # untimed: the previous function left other data in the caches
            start = clock()
            for _ in range(loops):
                fn()
            per_call = (clock() - start) / loops
            lowered |= per_call < best[k] * (1 - _SETTLED_RELATIVE)
            best[k] = min(best[k], per_call)
        taken += 1
        quiet = 0 if lowered else quiet + 1
    return [Timing(b, loops, taken) for b, (loops, _) in zip(best, ranged, strict=True)]


def _motion(run: StepRun):
    return next((o.data[KINEMATICS] for o in run.outputs.values() if KINEMATICS in o.data), None)


def drawn_rounding(run: StepRun):
    """The rounding the run's indicator diagram was drawn with (a lowered peak, a diesel's peak
    on its isobar), which the pointwise model takes too; None for a trace or without one."""
    return next(
        (
            o.data[GAS_PRESSURE].rounding
            for o in run.outputs.values()
            if GAS_PRESSURE in o.data and getattr(o.data[GAS_PRESSURE], "rounding", None)
        ),
        None,
    )
