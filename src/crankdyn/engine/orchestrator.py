"""Choose, order and run the stages a scene needs; record what was left out and why."""

from __future__ import annotations

import difflib
import functools
import heapq
import inspect
import time
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

from ..errors import MISSING, PluginError, Problem, SceneError
from ..parallel.fork import aside
from ..physics import lazy
from ..plugin.registry import Registry, broken_note
from ..plugin.types import (
    SERVICE_ASIDE,
    SERVICE_ERROR_PROBES,
    SERVICE_RUNNER,
    SERVICES,
    Stage,
    StageOutput,
    declared,
)
from ..scene.model import ROD_CHOICE, Scene, options


@dataclass
class Plan:
    order: list[Stage]
    skipped: dict[str, str]  # stage name -> reason
    registry: Registry | None = field(
        default=None, repr=False, compare=False
    )  # for stages' services


def is_study(stage: Stage) -> bool:
    """Whether ``stage`` is a study of the others: it comes ``last`` and provides nothing (the error
    against run time), so no stage can wait for it and it may be computed aside or later."""
    return stage.last and not stage.provides


@dataclass
class RunResult:
    scene: Scene
    plan: Plan
    outputs: dict[str, StageOutput]
    timing_s: dict[str, float] = field(default_factory=dict)
    #: studies left for later (``run_plan(defer_studies=True)``): stage name -> its inputs
    deferred: dict[str, dict[str, Any]] = field(default_factory=dict, repr=False)
    #: where the deferred studies are being computed meanwhile (``crankdyn.engine.studies``), if
    #: anywhere
    background: Any = field(default=None, repr=False, compare=False)

    def study_output(self, name: str) -> StageOutput | None:
        """The output of stage ``name``: a deferred study's is taken from the background (or, if
        that failed, computed here, so any error is the stage's own); None for a stage left out
        of this result (the live preview's pending studies)."""
        if name in self.outputs or name not in self.deferred:
            return self.outputs.get(name)
        stage = next(s for s in self.plan.order if s.name == name)
        taken = self.background.take(name) if self.background is not None else None
        output, elapsed = (
            taken if taken is not None else run_stage(stage, self.scene, self.deferred[name])
        )
        del self.deferred[name]
        self.outputs[name] = output
        self.timing_s[name] = elapsed
        return output

    def complete(self) -> None:
        """Every deferred study computed (or received), in plan order; the background closed."""
        for stage in self.plan.order:
            if stage.name in self.deferred:
                self.study_output(stage.name)
        self.close_background()

    def close_background(self) -> None:
        """Stop the background computation, if any (nothing is left running behind this result)."""
        if self.background is not None:
            self.background.close()
            self.background = None

    @property
    def stages_run(self) -> list[str]:
        return [s.name for s in self.plan.order]

    @property
    def pending(self) -> list[str]:
        """Stages of the plan not run yet (the live preview shows the others first)."""
        return [s.name for s in self.plan.order if s.name not in self.outputs]


def check_scene(scene: Scene, registry: Registry, languages: Iterable[str] = ()) -> None:
    """Checks that need the plugins: mechanism name, its own checks, language, stage names."""
    # a plugin that failed to load may be the one that would have known the name
    broken = broken_note(registry)
    scene = scene.with_plugin_defaults(registry)
    problems = _mechanism_problems(scene, registry, broken)
    claimed = {s.options_table: s for s in registry.stages.values() if s.options_table}
    for table in scene.plugin_tables():
        stage = claimed.get(table)
        if stage is None:
            known = [
                "report",
                "engine",
                "masses",
                "cycle",
                "analysis",
                "mechanism",
                *sorted(claimed),
            ]
            close = difflib.get_close_matches(table, known, n=1)
            hint = f"did you mean [{close[0]}]? " if close else ""
            problems.append(
                Problem(
                    table,
                    "[" + table + "]",
                    f"unknown table; {hint}known tables: " + ", ".join(known) + broken,
                )
            )
        elif stage.options_model is not None:
            try:
                options(scene, table, stage.options_model)
            except SceneError as exc:
                problems += exc.problems
    languages = sorted(set(languages))
    if languages and scene.report.language not in languages:
        problems.append(
            Problem(
                "report.language",
                scene.report.language,
                "allowed: " + ", ".join(languages) + broken,
            )
        )
    for name in scene.analysis.stages or ():
        if name not in registry.stages:
            problems.append(
                Problem(
                    "analysis.stages",
                    name,
                    "unknown stage; installed: " + ", ".join(sorted(registry.stages)) + broken,
                )
            )
    if problems:
        raise SceneError(problems)


def _mechanism_problems(scene: Scene, registry: Registry, broken: str) -> list[Problem]:
    """The scene's mechanism: named or the registry's default, installed, its ``[mechanism]``
    table, its rod (``Mechanism.needs_rod``) and, when these hold, its own ``check``."""
    installed = ", ".join(sorted(registry.mechanisms)) + broken
    name = scene.engine.mechanism
    if name is None:
        reason = "required: no installed mechanism is the default; installed: " + installed
        return [Problem("engine.mechanism", MISSING, reason)]
    mechanism = registry.mechanisms.get(name)
    if mechanism is None:
        return [Problem("engine.mechanism", name, "unknown mechanism; installed: " + installed)]
    problems: list[Problem] = []
    if mechanism.params_model is not None:
        try:
            options(scene, "mechanism", mechanism.params_model)
        except SceneError as exc:
            problems += exc.problems
    elif scene.mechanism:
        problems.append(
            Problem(
                "mechanism",
                scene.mechanism,
                f"the {mechanism.name!r} mechanism takes no [mechanism] table",
            )
        )
    if mechanism.needs_rod and not scene.engine.has_rod:
        problems.append(
            Problem(
                "engine.rod_length",
                MISSING,
                f"{ROD_CHOICE}: the {mechanism.name!r} mechanism has a connecting rod",
            )
        )
    return problems or list(mechanism.check(scene))


def plan(scene: Scene, registry: Registry, requested: Iterable[str] | None = None) -> Plan:
    """Order the stages to run for ``scene``.

    ``requested`` (or ``scene.analysis.stages``) names the stages wanted; by default
    every stage that applies and is marked default. Prerequisites are added from
    ``requires``/``provides``; a stage whose requirement nobody applicable provides is
    left out with the reason. A requirement no registered stage provides at all is a
    :class:`PluginError` (a mistake in the plugin, whatever the scene).
    """
    scene = scene.with_plugin_defaults(registry)
    requested = list(requested) if requested is not None else scene.analysis.stages
    if requested is not None:
        _check_requested(requested, registry)
    _check_requirements(registry)
    skipped: dict[str, str] = {}
    applicable = _applicable_stages(scene, registry, skipped)
    providers = _providers(applicable)
    wanted = _wanted_stages(applicable, requested, skipped)
    chosen = _choose_stages(wanted, applicable, providers, skipped, registry)
    return Plan(
        order=_topological(chosen), skipped=dict(sorted(skipped.items())), registry=registry
    )


def _check_requested(requested: list[str], registry: Registry) -> None:
    """Every requested stage is registered."""
    unknown = [n for n in requested if n not in registry.stages]
    if unknown:
        installed = ", ".join(sorted(registry.stages)) + broken_note(registry)
        raise SceneError(
            [Problem("stages", n, "unknown stage; installed: " + installed) for n in unknown]
        )


def _applicable_stages(scene: Scene, registry: Registry, skipped: dict[str, str]) -> dict:
    """The stages that apply to ``scene``; the others go to ``skipped`` with the reason."""
    applicable: dict[str, Stage] = {}
    for name, stage in sorted(registry.stages.items()):
        reason = stage_applies(stage, scene, registry)
        if reason is None:
            applicable[name] = stage
        else:
            skipped[name] = reason
    return applicable


def _providers(applicable: dict[str, Stage]) -> dict[str, Stage]:
    """The applicable stage that provides each result key (two providers of a key: PluginError)."""
    providers: dict[str, Stage] = {}
    for stage in applicable.values():
        for key in stage.provides:
            if key in providers:
                raise PluginError(
                    f"both {providers[key].name!r} and {stage.name!r} provide {key!r} for this scene"
                )
            providers[key] = stage
    return providers


def _wanted_stages(applicable: dict, requested: list[str] | None, skipped: dict) -> list[str]:
    """The applicable stages asked for (the default ones when none are requested); the others go
    to ``skipped``."""
    if requested is None:
        wanted = [n for n, s in applicable.items() if s.default]
        for n, s in applicable.items():
            if not s.default:
                skipped[n] = "optional stage, not requested"
    else:
        wanted = [n for n in requested if n in applicable]
        for n in applicable:
            if n not in requested:
                skipped[n] = "not requested"
    return wanted


def _choose_stages(wanted, applicable, providers, skipped: dict, registry) -> dict[str, Stage]:
    """The wanted stages and their prerequisites that can run; the others go to ``skipped``."""
    chosen: dict[str, Stage] = {}

    def add(name: str, chain: tuple[str, ...]) -> str | None:
        """Add ``name`` and its prerequisites; return a reason if it cannot run."""
        if name in chosen:
            return None
        if name in chain:
            raise PluginError(
                "stages require each other in a cycle: " + " -> ".join(chain + (name,))
            )
        stage = applicable[name]
        for key in stage.requires:
            provider = providers.get(key)
            if provider is None:
                why = [
                    f"{s.name}: {skipped[s.name]}"
                    for s in registry.stages.values()
                    if key in s.provides and s.name in skipped
                ]
                return f"needs {key!r}, which no applicable stage provides" + (
                    f" ({'; '.join(why)})" if why else ""
                )
            reason = add(provider.name, chain + (name,))
            if reason is not None:
                return f"needs {key!r} from {provider.name!r}, which cannot run: {reason}"
        chosen[name] = stage
        skipped.pop(name, None)
        return None

    for name in wanted:
        reason = add(name, ())
        if reason is not None:
            skipped[name] = reason
    return chosen


def _check_requirements(registry: Registry) -> None:
    """Every key a registered stage ``requires`` is provided by some registered stage.

    A key nobody provides is a mistake in the plugin (a typo such as "force" for "forces"), not a
    property of the scene: left out as "not applicable" it would pass unnoticed with exit 0. A key
    provided by a stage that does not apply to this scene is fine (``plan`` leaves the stage out)."""
    known = sorted({key for stage in registry.stages.values() for key in stage.provides})
    problems = []
    for name, stage in sorted(registry.stages.items()):
        for key in stage.requires:
            if key in known:
                continue
            if key in SERVICES:  # the orchestrator hands services in, no stage provides them
                hint = "; a service is named in Stage.services, not Stage.requires"
            else:
                close = difflib.get_close_matches(key, known, n=1)
                hint = f"; did you mean {close[0]!r}?" if close else ""
            problems.append(
                f"stage {name!r} requires {key!r}, which no registered stage provides{hint}"
            )
    if problems:
        raise PluginError(
            "; ".join(problems)
            + ". Known keys (provided by the registered stages): "
            + (", ".join(known) or "none")
        )


def _topological(stages: dict[str, Stage]) -> list[Stage]:
    provider_of = {key: s.name for s in stages.values() for key in s.provides}
    depends = {
        name: {provider_of[k] for k in s.requires}
        | {provider_of[k] for k in s.uses if k in provider_of}
        for name, s in stages.items()
    }
    # Ties are broken by name, so the order is reproducible; stages marked ``last`` (summaries
    # such as the error study) wait until nothing else is ready.
    ready = [(stages[n].last, n) for n, d in depends.items() if not d]
    heapq.heapify(ready)
    order: list[Stage] = []
    while ready:
        _, name = heapq.heappop(ready)
        order.append(stages[name])
        for other, deps in depends.items():
            if name in deps:
                deps.discard(name)
                if (
                    not deps
                    and other not in [s.name for s in order]
                    and (stages[other].last, other) not in ready
                ):
                    heapq.heappush(ready, (stages[other].last, other))
    if len(order) != len(stages):
        raise PluginError(
            "stages require each other in a cycle: "
            + ", ".join(sorted(set(stages) - {s.name for s in order}))
        )
    return order


@dataclass(frozen=True)
class Runner:
    """Re-plan and re-run the pipeline over one registry: the ``SERVICE_RUNNER`` a stage receives.

    ``stages``: the registered stages by name; ``plan(scene, names)`` checks ``scene`` against
    the plugins and orders ``names`` with their prerequisites; ``run(scene, plan)`` runs a plan.
    """

    registry: Registry

    @property
    def stages(self) -> dict[str, Stage]:
        return self.registry.stages

    def plan(self, scene: Scene, names: Iterable[str] | None = None) -> Plan:
        check_scene(scene, self.registry)
        return plan(scene, self.registry, names)

    def run(self, scene: Scene, the_plan: Plan) -> RunResult:
        return run_plan(scene, the_plan)

    def applies(self, stage: Stage, scene: Scene) -> str | None:
        """Why ``stage`` does not apply to ``scene`` in this registry, or None (as ``plan`` asks)."""
        return stage_applies(stage, scene, self.registry)


def stage_applies(stage: Stage, scene: Scene, registry: Registry | None) -> str | None:
    """``stage.applies`` for ``scene``: with the services the stage names as its second argument
    when its ``applies`` takes one (a stage whose applicability depends on the other plugins of the
    run, e.g. on the scene's mechanism), else with the scene alone."""
    if stage.services and _argument_count(stage.applies) >= 2:
        return stage.applies(scene, _services(stage, registry))
    return stage.applies(scene)


def _argument_count(function) -> int:
    """The parameters ``function`` takes, looked up once per function (a sweep asks this of
    every stage at every point); a callable that cannot be a cache's key is looked up each time."""
    try:
        return _cached_argument_count(function)
    except TypeError:
        return len(inspect.signature(function).parameters)


@functools.lru_cache(maxsize=512)
def _cached_argument_count(function) -> int:
    return len(inspect.signature(function).parameters)


def _services(stage: Stage, registry: Registry | None) -> dict[str, Any]:
    """The orchestrator's objects ``stage`` names in ``Stage.services``."""
    if not stage.services:
        return {}
    if registry is None:
        raise PluginError(
            f"stage {stage.name!r} needs {list(stage.services)}, but the plan has no registry"
        )
    known = {
        SERVICE_RUNNER: lambda: Runner(registry),
        SERVICE_ERROR_PROBES: lambda: list(registry.error_probes.values()),
        SERVICE_ASIDE: lambda: aside,
    }
    unknown = [s for s in stage.services if s not in known]
    if unknown:
        raise PluginError(
            f"stage {stage.name!r} asks for unknown services {unknown}; known: {sorted(known)}"
        )
    return {name: known[name]() for name in stage.services}


def stage_inputs(stage: Stage, data: dict[str, Any], registry: Registry | None) -> dict[str, Any]:
    """What ``stage.run`` receives: its required data, the ``uses`` data that was provided, and
    the services it names (every runner of a plan, cached or not, builds it here)."""
    inputs = {key: data[key] for key in stage.requires}
    inputs.update({key: data[key] for key in stage.uses if key in data})
    inputs.update(_services(stage, registry))
    return inputs


def check_output(stage: Stage, output: StageOutput) -> None:
    """What ``run`` returned matches the stage's declarations: ``data`` holds exactly the keys of
    ``provides``, and every table in ``tables`` is one of ``Stage.tables``."""
    if set(output.data) != set(stage.provides):
        raise PluginError(
            f"stage {stage.name!r} declared provides={list(stage.provides)} "
            f"but returned {sorted(output.data)}"
        )
    undeclared = [name for name in output.tables.keys() if not declared(name, stage.tables)]
    if undeclared:
        raise PluginError(
            f"stage {stage.name!r} returned the tables {undeclared}, which it does not declare "
            f"in Stage.tables (declared: {list(stage.tables)})"
        )


def run_stage(stage: Stage, scene: Scene, inputs: dict[str, Any]) -> tuple[StageOutput, float]:
    """(output, seconds) of ``stage.run``, its output checked against the stage's declarations."""
    start, imported = time.perf_counter(), lazy.import_seconds()
    output = stage.run(scene, inputs)
    # not scipy's import; never below zero (the count is the process's: another thread's import too)
    elapsed = max(0.0, time.perf_counter() - start - (lazy.import_seconds() - imported))
    check_output(stage, output)
    return output, elapsed


def run_plan(
    scene: Scene,
    the_plan: Plan,
    defer_studies: bool = False,
    computed: tuple[dict[str, StageOutput], dict[str, float]] | None = None,
) -> RunResult:
    """Run the stages of ``the_plan`` in order. With ``defer_studies`` the studies
    (:func:`is_study`) are not run: their inputs are kept in :attr:`RunResult.deferred`, and
    :meth:`RunResult.study_output` computes (or receives) each when it is wanted. ``computed``:
    (outputs, seconds) of the stages already run elsewhere (a forked child), taken instead of running them."""
    scene = scene.with_plugin_defaults(the_plan.registry)
    data: dict[str, Any] = {}
    outputs: dict[str, StageOutput] = {}
    timing: dict[str, float] = {}
    deferred: dict[str, dict[str, Any]] = {}
    for stage in the_plan.order:
        inputs = stage_inputs(stage, data, the_plan.registry)
        if defer_studies and is_study(stage):
            deferred[stage.name] = inputs
            continue
        if computed is not None:
            output, timing[stage.name] = computed[0][stage.name], computed[1][stage.name]
        else:
            output, timing[stage.name] = run_stage(stage, scene, inputs)
        data.update(output.data)
        outputs[stage.name] = output
    return RunResult(
        scene=scene, plan=the_plan, outputs=outputs, timing_s=timing, deferred=deferred
    )


def resume_plan(
    scene: Scene, the_plan: Plan, outputs: dict[str, StageOutput], timing_s: dict[str, float]
) -> RunResult:
    """The result ``run_plan(scene, the_plan, defer_studies=True)`` gives, from the outputs and
    timings of its stages computed elsewhere (a forked child): the studies' inputs are built here."""
    return run_plan(scene, the_plan, defer_studies=True, computed=(outputs, timing_s))


def run_scene(
    scene: Scene,
    registry: Registry,
    requested: Iterable[str] | None = None,
    languages: Iterable[str] = (),
    cache=None,
    defer_studies: bool = False,
) -> RunResult:
    """Validate against the plugins, plan and run: the whole computation of one scene.

    With ``cache`` (a :class:`crankdyn.engine.stage_cache.StageCache`) only stages whose inputs
    changed since
    the cache's last run are run again (the live preview). ``defer_studies``: see :func:`run_plan`
    (not with a cache). A scene naming no mechanism gets the registry's default one."""
    scene = scene.with_plugin_defaults(registry)
    check_scene(scene, registry, languages)
    the_plan = plan(scene, registry, requested)
    if cache is not None:
        return cache.run_plan(scene, the_plan)
    return run_plan(scene, the_plan, defer_studies)
