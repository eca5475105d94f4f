"""A sweep's answer key at array speed: many points computed together, nothing rendered.

A point of a sweep that writes no files of its own needs only the numbers of the answer key.
Its points therefore run in chunks (one worker call, or one Dask task, per chunk), and within a
chunk:

* only the stages that fill answer-key columns run (:func:`key_plan`), with what they require and
  use; the studies of the other stages (the error against run time) run once, for the base scene
  (:func:`study_once`), not per point;
* the stages run one after the other over all the chunk's points: a stage that declares
  ``Stage.run_many`` computes them at once (arrays over points × angles), any other stage point by
  point with its ``run``;
* the answers are read from each stage's results directly, without building a results document.

Points that fail (a bad combination of values, a stage's error) become failure rows, as in a
batch. No stage is named here: what runs, and how, comes from the stages' declarations.
"""

from __future__ import annotations

import gc
import math
import signal
import time
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..engine.orchestrator import (
    Plan,
    check_output,
    check_scene,
    is_study,
    plan,
    run_plan,
    run_stage,
    stage_applies,
    stage_inputs,
)
from ..errors import PluginError
from ..parallel.allocator import chunk_arrays_reused
from ..parallel.pool import DEFAULT_TIMEOUT_S, OutOfTime, run_all, run_all_dask, stop_signals
from ..plugin.registry import Registry
from ..plugin.types import Stage, StageOutput
from ..scene.inputcheck import MAX_ARRAY_LENGTH, structure_problems
from ..scene.model import Scene, merge
from . import answer_key
from .variants import (
    VARIANT_COLUMN,
    Outcome,
    Progress,
    RunOptions,
    Variant,
    VariantRun,
    _client,
    _registry_or_default,
    _variant_scene,
    error_text,
    worker_count,
)

#: Points per chunk: one call of a local worker computes them together. A few hundred
#: amortise a call's cost (a fork, a pickled answer, a Dask task's round trip) and keep a
#: chunk's arrays (points × angles per quantity) to a few megabytes.
CHUNK_POINTS = 250
#: Points per Dask task: a task runs in its worker's own process (no fork), so what it costs
#: beyond its points is a round trip through the scheduler; a few hundred points amortise it
#: and leave enough tasks for the workers to finish together.
DASK_CHUNK_POINTS = 250


def key_plan(the_plan: Plan, registry: Registry) -> Plan:
    """``the_plan`` cut to the stages whose answer-key columns a sweep fills: each stage that
    declares ``answer_columns``, the stages providing what it requires or uses, and so on; no
    study (:func:`~crankdyn.orchestrator.is_study`). The order is the plan's."""
    by_key = {key: s.name for s in the_plan.order for key in s.provides}
    by_name = {s.name: s for s in the_plan.order}
    wanted = [s.name for s in the_plan.order if s.answer_columns and not is_study(s)]
    kept: set[str] = set()
    while wanted:
        name = wanted.pop()
        if name in kept:
            continue
        kept.add(name)
        stage = by_name[name]
        wanted += [by_key[k] for k in (*stage.requires, *stage.uses) if k in by_key]
    order = [s for s in the_plan.order if s.name in kept and not is_study(s)]
    return Plan(order=order, skipped=dict(the_plan.skipped), registry=registry)


def number(value: Any) -> Any:
    """A result as results.json holds it: numpy numbers as Python numbers, a non-finite one None."""
    if isinstance(value, (np.floating, float)):
        value = float(value)
        return value if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


@dataclass
class _Point:
    """One point while its chunk runs: its scene, the data its stages provided, their results."""

    index: int
    scene: Scene
    data: dict[str, Any] = field(default_factory=dict)
    results: dict[str, dict] = field(default_factory=dict)
    error: str = ""


def _check_time(deadline: float | None) -> None:
    if deadline is not None and time.monotonic() >= deadline:
        raise OutOfTime


def _stage_outputs(
    stage: Stage, points: list[_Point], registry: Registry, deadline: float | None = None
) -> None:
    """Run ``stage`` for ``points``: all at once through ``run_many`` when the stage has one, else
    (or when that raised: every point then gets its own error) point by point, the time checked
    against ``deadline`` before each point."""
    inputs = [stage_inputs(stage, p.data, registry) for p in points]
    if stage.run_many is not None and len(points) > 1:
        try:
            outputs = list(stage.run_many([p.scene for p in points], inputs))
            if len(outputs) != len(points):
                raise PluginError(
                    f"stage {stage.name!r}: run_many returned {len(outputs)} outputs "
                    f"for {len(points)} scenes"
                )
            for point, output in zip(points, outputs, strict=True):
                check_output(stage, output)
                _take(stage, point, output)
            return
        except Exception:  # noqa: BLE001 - the points are run one by one: each gets its own error
            pass
    for point, given in zip(points, inputs, strict=True):
        _check_time(deadline)
        try:
            output, _ = run_stage(stage, point.scene, given)
        except Exception as exc:  # noqa: BLE001 - one bad point must not stop its chunk
            point.error = error_text(exc)
            continue
        _take(stage, point, output)


def _take(stage: Stage, point: _Point, output: StageOutput) -> None:
    point.data.update(output.data)
    point.results[stage.name] = output.results


def _planned(
    scenes: list[_Point], registry: Registry, stages: list[str] | None, languages: Iterable[str]
) -> dict[tuple[str, ...], tuple[Plan, list[_Point]]]:
    """The points grouped by their key plan (almost always one group: the grid's points differ in
    values, seldom in the stages that apply)."""
    groups: dict[tuple[str, ...], tuple[Plan, list[_Point]]] = {}
    plans: dict[tuple, Plan] = {}
    for point in scenes:
        try:
            check_scene(point.scene, registry, languages)
            # a plan follows from what each stage's applies says and the stages asked for alone
            said = (
                tuple(stage_applies(s, point.scene, registry) for s in registry.stages.values()),
                tuple(stages if stages is not None else point.scene.analysis.stages or ()),
                stages is None and point.scene.analysis.stages is None,
            )
            if said not in plans:
                plans[said] = key_plan(plan(point.scene, registry, stages), registry)
            the_plan = plans[said]
        except Exception as exc:  # noqa: BLE001 - one bad point must not stop its chunk
            point.error = error_text(exc)
            continue
        names = tuple(s.name for s in the_plan.order)
        groups.setdefault(names, (the_plan, []))[1].append(point)
    return groups


def evaluate(
    scenes: Sequence[Scene],
    registry: Registry,
    stages: list[str] | None = None,
    languages: Iterable[str] = (),
    deadline: float | None = None,
) -> list[tuple[list[str], dict[str, dict], str]]:
    """(stages run, stage -> its results, error text or "") of each scene, in order: the key
    plan's stages run over all the scenes together. Past ``deadline`` (``time.monotonic``) it
    raises :class:`~crankdyn.parallel.pool.OutOfTime` before the next stage."""
    points = [_Point(k, scene.with_plugin_defaults(registry)) for k, scene in enumerate(scenes)]
    out: list[tuple[list[str], dict[str, dict], str]] = [([], {}, "")] * len(points)
    for names, (the_plan, group) in _planned(points, registry, stages, languages).items():
        alive = group
        for stage in the_plan.order:
            _check_time(deadline)
            _stage_outputs(stage, alive, registry, deadline)
            alive = [p for p in alive if not p.error]
        for point in group:
            out[point.index] = (list(names), point.results, point.error)
    for point in points:
        if point.error and not out[point.index][2]:
            out[point.index] = ([], {}, point.error)
    return out


def run_chunk(
    base: dict,
    base_dir: str,
    variants: list[Variant],
    language: str | None,
    stages: list[str] | None,
    data_dirs: tuple[str, ...] = (),
    limit_s: float | None = None,
    registry: Registry | None = None,
) -> list[Outcome]:
    """The outcomes of a chunk of a sweep's points (answers only, nothing rendered or written);
    an error is part of its point's outcome. With ``limit_s`` the chunk keeps its own time limit:
    past it, it raises :class:`~crankdyn.parallel.pool.OutOfTime` before its next stage or point
    (a chunk run in a Dask worker's own process, which no one else can stop). ``registry``: the
    run's plugins (by default the installed ones)."""
    start = time.perf_counter()
    deadline = None if limit_s is None else time.monotonic() + limit_s
    registry = _registry_or_default(registry)
    columns = answer_key.answer_columns(registry)
    scenes = _PointScenes(base, base_dir, language, data_dirs, registry)
    ready: list[tuple[Variant, Scene]] = []
    outcomes: dict[int, Outcome] = {}
    for variant in variants:
        if variant.error:
            outcomes[variant.row] = Outcome(variant.row, variant.name, False, 0.0, variant.error)
            continue
        try:
            ready.append((variant, scenes.scene(variant)))
        except Exception as exc:  # noqa: BLE001 - one bad point must not stop its chunk
            outcomes[variant.row] = Outcome(variant.row, variant.name, False, 0.0, error_text(exc))
    _check_time(deadline)
    with _collector_paused():
        evaluated = evaluate([scene for _, scene in ready], registry, stages, deadline=deadline)
    seconds = (time.perf_counter() - start) / max(1, len(variants))  # a chunk's time, shared out
    for (variant, _), (run, results, error) in zip(ready, evaluated, strict=True):
        if error:
            outcomes[variant.row] = Outcome(variant.row, variant.name, False, seconds, error)
            continue
        document = {"stages_run": run, **results}
        outcomes[variant.row] = Outcome(
            variant.row,
            variant.name,
            True,
            seconds,
            stages_run=run,
            answers={c: number(v) for c, v in answer_key.answers(document, columns).items()},
            absent=answer_key.absent(document, columns),
        )
    return [outcomes[v.row] for v in variants]


class _PointScenes:
    """The scenes of a chunk's points: the base scene with each point's values, built as
    :func:`crankdyn.batch._variant_scene` builds them, but with the base's data checked once.

    The sizes, nesting and text of the base's data are checked here once; for a point, only its
    own values and the tables they change (what a grid changes is a few numbers). Whatever does
    not validate, or anything out of the ordinary, goes through ``_variant_scene`` itself, so a
    bad point's error reads as a batch states it."""

    def __init__(
        self,
        base: dict,
        base_dir: str,
        language: str | None,
        data_dirs: tuple[str, ...],
        registry: Registry,
    ):
        self.base, self.base_dir, self.registry = base, base_dir, registry
        self.language, self.data_dirs = language, data_dirs
        self.fixed = {
            "base_dir": str(base_dir),
            "data_dirs": tuple(str(Path(d).resolve()) for d in data_dirs),
        }
        self.base_clean = (
            isinstance(base, dict)
            and not {"base_dir", "data_dirs"} & set(base)
            and not structure_problems(base)
        )

    def scene(self, variant: Variant) -> Scene:
        changes = [variant.overrides]  # laid over the base in _variant_scene's order
        if "variant" not in variant.overrides.get("report", {}):  # the title page names its own
            label = variant.cells.get(VARIANT_COLUMN) or variant.name
            changes.append({"report": {"variant": label}})
        if self.language:
            changes.append({"report": {"language": self.language}})
        data = self.base
        for change in changes:
            data = merge(data, change)
        if self.base_clean and all(_changes_clean(data, change) for change in changes):
            try:
                scene = Scene.model_validate({**data, **self.fixed})
                return scene.with_plugin_defaults(self.registry)
            except Exception:  # noqa: BLE001 - the full path states the error
                pass
        return _variant_scene(
            self.base, self.base_dir, variant, self.language, self.data_dirs, self.registry
        )


def _changes_clean(data: dict, changes: dict) -> bool:
    """Whether ``data`` (a clean base with ``changes`` laid over it) has no structure problem:
    the changes have none of their own, name no key the loader sets, and every table they
    change stays within its size."""
    if {"base_dir", "data_dirs"} & set(changes) or structure_problems(changes):
        return False
    stack = [(data, changes)]
    while stack:
        table, changed = stack.pop()
        if len(table) > MAX_ARRAY_LENGTH:
            return False
        stack += [
            (table[key], value)
            for key, value in changed.items()
            if isinstance(value, dict) and isinstance(table.get(key), dict)
        ]
    return True


@contextmanager
def _collector_paused() -> Iterator[None]:
    """The cyclic garbage collector off while a chunk computes: its arrays and results are freed
    by reference counting, and a collection pass every few hundred allocations would walk
    everything the process has loaded (some 5 % of a point). A chunk's memory is bounded by its
    points; what it leaves in cycles is collected once the collector is on again."""
    if not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


def chunks(variants: list[Variant], workers: int, size: int = CHUNK_POINTS) -> list[list[Variant]]:
    """``variants`` in chunks of at most ``size`` points, and at least two chunks per worker when
    there are enough points (so that no worker waits for the last long one)."""
    size = max(1, min(size, len(variants) // max(1, 2 * workers)))
    return [variants[k : k + size] for k in range(0, len(variants), size)]


def study_once(scene: Scene, registry: Registry, stages: list[str] | None) -> list[str]:
    """Run the studies of ``scene``'s plan (the error against run time) once; the notes saying so,
    one per study: its name and, if it failed, why."""
    the_plan = plan(scene, registry, stages)
    studies = [s.name for s in the_plan.order if is_study(s)]
    if not studies:
        return []
    try:
        check_scene(scene, registry)
        run_plan(scene, the_plan)
    except Exception as exc:  # noqa: BLE001 - the points' answers do not depend on it
        return [
            f"the study {name!r} failed for the base scene: {error_text(exc)}" for name in studies
        ]
    return [
        f"the study {name!r} (error against run time) ran once, for the base scene, not per point"
        for name in studies
    ]


# --------------------------------------------------------------------------- running the chunks


class _Rerun(list):
    """A chunk that timed out or whose worker died: its points run again one by one, each with
    its own time limit, so that only the point at fault fails."""


class KeyRun(VariantRun):
    """A sweep's run of chunks of points for the answer key: :class:`VariantRun` whose
    :meth:`run_chunk` is what the workers run."""

    def run_chunk(
        self,
        base: dict,
        base_dir: str,
        variants: list[Variant],
        language: str | None,
        stages: list[str] | None,
        data_dirs: tuple[str, ...] = (),
        limit_s: float | None = None,
    ) -> list[Outcome]:
        """:func:`run_chunk` with the run's registry (in a Dask worker, with its arrays' memory
        reused: :mod:`crankdyn.parallel.allocator`)."""
        with chunk_arrays_reused():
            return run_chunk(
                base, base_dir, variants, language, stages, data_dirs, limit_s, self.registry
            )

    def prepare_dask_worker(self) -> None:
        """:func:`_prepare_dask_worker` for this run."""
        _prepare_dask_worker(self)


def execute_key(
    variants: list[Variant],
    base: dict,
    base_dir: str,
    options: RunOptions,
    run: KeyRun | None = None,
) -> tuple[list[Outcome], int]:
    """The answers of ``variants`` (a sweep's points, nothing rendered), in chunks: local worker
    processes, or the Dask cluster of ``options.scheduler``. Returns the outcomes in row order and
    the signal that interrupted the run (0 when it ran through), as :func:`crankdyn.batch.execute`.

    A chunk is given the time limits of its points together; a chunk that runs out of it (or
    whose worker dies) is run again point by point, each point with its own limit. A local
    chunk runs in a forked worker that is stopped at the limit; a Dask chunk runs in the worker's
    own process and stops itself at the limit, before its next stage or point (the points run
    again each in a child forked from the worker, stopped at its limit).
    """
    client = _client(options) if options.scheduler else None
    run = run if run is not None else KeyRun()
    bar = Progress(len(variants), enabled=options.progress)
    outcomes: list[Outcome] = []
    rerun: list[Variant] = []

    def finished(result: list[Outcome]) -> None:
        if isinstance(result, _Rerun):
            rerun.extend(result)
            return
        for outcome in result:
            outcomes.append(outcome)
            bar.update(outcome)
            if options.on_outcome:
                options.on_outcome(outcome)

    def failed(chunk: list[Variant], reason: str, seconds: float) -> list[Outcome]:
        if len(chunk) > 1:
            return _Rerun(chunk)
        return [Outcome(v.row, v.name, False, seconds, reason) for v in chunk]

    data_dirs = tuple(str(Path(d).resolve()) for d in options.data_dirs)
    timeout = DEFAULT_TIMEOUT_S if options.timeout is None else options.timeout
    tail = (options.language, options.stages, data_dirs)
    with stop_signals() as received:
        try:
            if client is None:
                run.warm()  # forked workers inherit the registry and the loaded libraries
                jobs = max(1, min(worker_count(options.jobs), max(len(variants), 1)))
                _run_local(
                    run, variants, base, base_dir, tail, jobs, timeout, finished, failed, rerun
                )
            else:
                try:
                    _run_dask(
                        run,
                        variants,
                        base,
                        base_dir,
                        tail,
                        client,
                        timeout,
                        finished,
                        failed,
                        rerun,
                    )
                finally:
                    client.close()
        except KeyboardInterrupt:  # outside the loop's own handling (loading, closing): kept too
            pass
    return _with_unfinished(variants, outcomes, received)


def _run_local(run, variants, base, base_dir, tail, jobs, timeout, finished, failed, rerun) -> None:
    def args_of(chunk):
        return (base, base_dir, chunk, *tail)

    items = chunks(variants, jobs)
    if run_all(
        items,
        run.run_chunk,
        args_of,
        jobs,
        timeout * len(items[0]) if items else timeout,
        finished,
        failed,
    ):
        return  # interrupted
    if rerun:
        single = [[v] for v in rerun]
        rerun.clear()
        run_all(single, run.run_chunk, args_of, jobs, timeout, finished, failed)


def _run_dask(
    run, variants, base, base_dir, tail, client, timeout, finished, failed, rerun
) -> None:
    def args_of(chunk):
        return (base, base_dir, chunk, *tail)

    workers = max(1, sum(client.nthreads().values()))
    items = chunks(variants, workers, DASK_CHUNK_POINTS)
    prepare = run.prepare_dask_worker
    limit = timeout * len(items[0]) if items else timeout

    def chunk_args(chunk):  # a chunk runs in the worker's own process and keeps its own limit
        return (*args_of(chunk), limit)

    if run_all_dask(
        items,
        run.run_chunk,
        chunk_args,
        client,
        limit,
        finished,
        failed,
        prepare=prepare,
        in_process=True,
    ):
        return
    if rerun:
        single = [[v] for v in rerun]
        rerun.clear()
        run_all_dask(
            single, run.run_chunk, args_of, client, timeout, finished, failed, prepare=prepare
        )


def _prepare_dask_worker(run: VariantRun) -> None:
    """Build the run's registry and load the libraries once per Dask worker
    (:meth:`crankdyn.batch.variants.VariantRun.warm`)."""
    run.warm((), ())


def _with_unfinished(
    variants: list[Variant], outcomes: list[Outcome], received: list[int]
) -> tuple[list[Outcome], int]:
    """The outcomes in row order, a failure row for each point without one (an interruption)."""
    done = {o.row for o in outcomes}
    unfinished = [v for v in variants if v.row not in done]
    stop_signal = received[0] if received else signal.SIGINT if unfinished else 0
    what = "SIGTERM" if stop_signal == signal.SIGTERM else "Ctrl-C"
    reason = f"not finished: the sweep was interrupted ({what})"
    outcomes += [Outcome(v.row, v.name, False, 0.0, reason) for v in unfinished]
    outcomes.sort(key=lambda o: o.row)
    return outcomes, int(stop_signal)
