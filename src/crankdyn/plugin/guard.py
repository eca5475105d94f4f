"""Plugins held to their contract: every failure named, no stage running without end.

:func:`crankdyn.plugin.registry.collect` wraps what each plugin registers. A third-party plugin's
stage
whose ``applies``, ``run``, ``render``, ``input_rows`` or ``taken_rows`` raises, or returns what
:mod:`crankdyn.plugin.types` does not allow (a reason that is not a str, an output whose data
keys differ from ``provides``, a ``kinematics`` that is not a ``PistonMotion`` or holds NaN,
results that JSON cannot hold, a section that is not a str), raises
:class:`crankdyn.errors.PluginFailure` naming the plugin and the stage. A
:class:`crankdyn.errors.SceneError` a stage raises is the scene's fault and passes as it is.
The built-in plugins are the program's own: their errors stay internal errors.

Within :func:`stage_time_limit` (``crankdyn report --timeout``) every stage call of every plugin
(and each plugin's hooks) may take that many seconds; then it is stopped with
:class:`crankdyn.errors.StageTimeLimit`. The limit needs ``SIGALRM``, so it holds in a process's
main thread on POSIX systems; elsewhere the stages run without it.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import math
import numbers
import os
import signal
import threading
import time
import tomllib
from collections.abc import Callable, Iterator, Mapping
from typing import Any

import numpy as np

from ..errors import CrankdynError, PluginFailure, Problem, SceneError, StageTimeLimit, shorten
from . import contracts
from .types import (
    Catalog,
    ErrorProbe,
    Mechanism,
    MechanismGeometry,
    ProbePoint,
    Stage,
    StageOutput,
    StagePresentation,
    declared,
)

#: seconds one stage may take in ``crankdyn report`` unless ``--timeout`` says otherwise
DEFAULT_STAGE_TIMEOUT_S = 120.0
#: the largest ``--timeout``: an hour, far beyond any stage of a course project
MAX_STAGE_TIMEOUT_S = 3600.0
#: after the limit, the alarm repeats this often: a stage that catches the first cannot go on
_REPEAT_S = 0.5
#: the longest exception text quoted in a message
_QUOTED_CHARS = 300
#: the largest catalog file a plugin may bring
_MAX_CATALOG_BYTES = 8 * 2**20
#: how deep results may nest (a list holding itself would recurse without end)
_MAX_DEPTH = 32

#: the data a stage provides under a key of :mod:`crankdyn.plugin.contracts`, by type
CONTRACT_TYPES: dict[str, type] = {
    contracts.KINEMATICS: contracts.PistonMotion,
    contracts.GAS_PRESSURE: contracts.GasPressure,
    contracts.FORCES: contracts.CrankForces,
    contracts.ENGINE_TORQUE: contracts.EngineTorque,
    contracts.BAY_LOADS: contracts.BayLoads,
    contracts.CRANK_LOADS: contracts.CrankLoads,
    contracts.COUNTERWEIGHTS: contracts.Counterweights,
    contracts.FLYWHEEL: contracts.FlywheelDesign,
}


# ----------------------------------------------------------------------------- the time limit
class _Deadline(BaseException):
    """Raised by the alarm; not an ``Exception``, so a stage's ``except Exception`` lets it pass.
    Carries (plugin, where, step) of the innermost stage call running when it came."""


_limit_s: float | None = None
_deadline: float | None = None  # time.monotonic() when the running stage call must have ended
_armed_pid: int | None = None  # the process whose timer is set (a forked child has none)
_running: list[tuple[str, str, str]] = []  # (plugin, where, step) of the stage calls under way


def _on_alarm(signum, frame) -> None:
    if _deadline is not None and _armed_pid == os.getpid() and _running:
        raise _Deadline(_running[-1])


def _can_limit() -> bool:
    return (
        _limit_s is not None
        and threading.current_thread() is threading.main_thread()
        and signal.getsignal(signal.SIGALRM) is _on_alarm
    )


@contextlib.contextmanager
def stage_time_limit(seconds: float | None) -> Iterator[None]:
    """Within this block a stage's ``applies``, ``run`` or ``render`` (and a plugin's hook) that
    takes more than ``seconds`` raises :class:`crankdyn.errors.StageTimeLimit`; None: no limit.
    Holds in the main thread where ``SIGALRM`` is free (not in another thread, nor where the
    program has its own ``SIGALRM`` handler)."""
    global _limit_s
    if seconds is not None and not 0 < seconds <= MAX_STAGE_TIMEOUT_S:
        raise ValueError(
            f"a stage time limit is > 0 and at most {MAX_STAGE_TIMEOUT_S:g} s, not {seconds!r}"
        )
    usable = (
        seconds is not None
        and hasattr(signal, "setitimer")
        and threading.current_thread() is threading.main_thread()
        and signal.getsignal(signal.SIGALRM) in (signal.SIG_DFL, None, _on_alarm)
    )
    if not usable:
        yield
        return
    previous_handler, previous_limit = signal.signal(signal.SIGALRM, _on_alarm), _limit_s
    _limit_s = seconds
    try:
        yield
    finally:
        _limit_s = previous_limit
        if previous_limit is None:
            _disarm()
            signal.signal(signal.SIGALRM, previous_handler)


def _disarm() -> None:
    global _deadline
    signal.setitimer(signal.ITIMER_REAL, 0)
    _deadline = None


def call_limited(label: tuple[str, str, str], fn: Callable[..., Any], *args: Any) -> Any:
    """``fn(*args)`` as the stage call ``label`` = (plugin, where, step), within the time limit:
    the outermost stage call sets the alarm, one it makes (a stage re-running the pipeline)
    shares its time; the limit is then named by the innermost call running."""
    if not _can_limit():
        return fn(*args)
    depth = len(_running)
    if _deadline is not None and _armed_pid == os.getpid():  # inside another stage's call
        _running.append(label)
        try:
            return fn(*args)
        finally:
            del _running[depth:]
    try:
        return _armed(label, fn, args)
    except _Deadline as exc:
        _disarm()
        del _running[depth:]
        plugin, where, step = exc.args[0] if exc.args else label
        what = (
            f"{step} did not finish within the limit of {_limit_s:g} s a stage may take "
            "(crankdyn report --timeout SECONDS)"
        )
        raise StageTimeLimit(plugin, where, what) from None


def _armed(label, fn, args):
    global _deadline, _armed_pid
    now = time.monotonic()
    # a child forked within a stage call keeps what was left of the call's time
    remaining = _limit_s if _deadline is None else max(_deadline - now, 0.001)
    _deadline, _armed_pid = now + remaining, os.getpid()
    _running.append(label)
    signal.setitimer(signal.ITIMER_REAL, remaining, _REPEAT_S)
    try:
        return fn(*args)
    finally:
        _disarm()
        _running.pop()


# ----------------------------------------------------------------------------- naming failures
def describe(exc: BaseException) -> str:
    """``Type: message`` of an exception, on one line and cut to a readable length."""
    text = " ".join(str(exc).split())
    if len(text) > _QUOTED_CHARS:
        text = text[: _QUOTED_CHARS - 3] + "..."
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def call(
    plugin: str, where: str, step: str, foreign: bool, fn: Callable[..., Any], *args: Any
) -> Any:
    """``fn(*args)`` for ``plugin``'s ``where`` within the time limit; a third-party (``foreign``)
    plugin's error raised as a :class:`PluginFailure` that names it."""
    try:
        return call_limited((plugin, where, step), fn, *args)
    except (SceneError, PluginFailure):
        raise
    except Exception as exc:
        if not foreign:
            raise
        if isinstance(exc, CrankdynError):
            raise PluginFailure(plugin, where, f"{step}: {exc}") from exc
        raise PluginFailure(plugin, where, f"{step} raised {describe(exc)}") from exc


def _garbage(plugin: str, where: str, step: str, value: object, expected: str) -> PluginFailure:
    return PluginFailure(plugin, where, f"{step} returned {shorten(value)}; expected {expected}")


# ----------------------------------------------------------------------------- registrations
_NAME_TUPLES = ("requires", "provides", "uses", "services", "tables")
_PRESENTATION_NAME_TUPLES = ("references", "references_full", "figures")


def _name_tuples(
    owner: object, names: tuple[str, ...], plugin: str, where: str, stage: str
) -> dict[str, Any]:
    """The fields ``names`` of ``owner`` given as lists, as tuples; a value that is not a tuple of
    str is a :class:`PluginFailure`."""
    fixed: dict[str, Any] = {}
    for name in names:
        value = getattr(owner, name)
        if isinstance(value, list):
            value = fixed[name] = tuple(value)
        if not isinstance(value, tuple) or not all(isinstance(v, str) for v in value):
            raise PluginFailure(
                plugin,
                where,
                f"stage {stage!r}: {name} = {shorten(value)}; expected a tuple of str",
            )
    return fixed


def _checked_presentation(
    look: object, plugin: str, where: str, stage: str
) -> StagePresentation | None:
    """A stage's presentation checked field by field as :func:`checked_stage` checks the stage."""
    if look is None:
        return None
    if not isinstance(look, StagePresentation):
        raise PluginFailure(
            plugin,
            where,
            f"stage {stage!r}: presentation = {shorten(look)}; "
            "expected a StagePresentation or None",
        )
    fixed = _name_tuples(look, _PRESENTATION_NAME_TUPLES, plugin, where, stage)
    if not callable(look.render):
        raise PluginFailure(
            plugin, where, f"stage {stage!r}: render = {shorten(look.render)}; expected a function"
        )
    for hook in ("input_rows", "taken_rows"):
        rows = getattr(look, hook)
        if rows is not None and not callable(rows):
            raise PluginFailure(
                plugin,
                where,
                f"stage {stage!r}: {hook} = {shorten(rows)}; expected a function or None",
            )
    if not isinstance(look.title_key, str):
        raise PluginFailure(plugin, where, f"stage {stage!r}: title_key and options_table are str")
    return dataclasses.replace(look, **fixed) if fixed else look


def checked_stage(stage: object, plugin: str, hook: str, foreign: bool = True) -> Stage:
    """``stage`` as a hook returned it, checked field by field (a str where a tuple of names
    belongs would be read as its letters); a list of names becomes a tuple."""
    where = f"hook {hook}"
    if not isinstance(stage, Stage):
        raise _garbage(plugin, where, "the hook", stage, "Stage objects")
    if not isinstance(stage.name, str) or not stage.name.strip():
        raise PluginFailure(
            plugin, where, f"a Stage's name is {shorten(stage.name)}; expected a non-empty str"
        )
    fixed: dict[str, Any] = dict(_name_tuples(stage, _NAME_TUPLES, plugin, where, stage.name))
    for name in ("applies", "run", "default_angle_step"):
        if name == "default_angle_step" and stage.default_angle_step is None:
            continue
        if not callable(getattr(stage, name)):
            raise PluginFailure(
                plugin,
                where,
                f"stage {stage.name!r}: {name} = "
                f"{shorten(getattr(stage, name))}; expected a function",
            )
    look = _checked_presentation(stage.presentation, plugin, where, stage.name)
    if look is not stage.presentation:
        fixed["presentation"] = look
    if stage.options_table is not None and not isinstance(stage.options_table, str):
        raise PluginFailure(
            plugin, where, f"stage {stage.name!r}: title_key and options_table are str"
        )
    if not _is_model(stage.options_model):
        raise PluginFailure(
            plugin,
            where,
            f"stage {stage.name!r}: options_model = "
            f"{shorten(stage.options_model)}; expected a pydantic model or None",
        )
    return dataclasses.replace(stage, **fixed) if fixed else stage


def checked_mechanism(mechanism: object, plugin: str, hook: str, foreign: bool = True) -> Mechanism:
    where = f"hook {hook}"
    if not isinstance(mechanism, Mechanism):
        raise _garbage(plugin, where, "the hook", mechanism, "Mechanism objects")
    if not isinstance(mechanism.name, str) or not mechanism.name.strip():
        raise PluginFailure(
            plugin,
            where,
            f"a Mechanism's name is {shorten(mechanism.name)}; expected a non-empty str",
        )
    geometry = mechanism.geometry
    if not callable(mechanism.check) or not (geometry is None or callable(geometry)):
        raise PluginFailure(
            plugin,
            where,
            f"mechanism {mechanism.name!r}: check (and geometry, if given) must be functions",
        )
    if not _is_model(mechanism.params_model):
        raise PluginFailure(
            plugin,
            where,
            f"mechanism {mechanism.name!r}: params_model = "
            f"{shorten(mechanism.params_model)}; expected a pydantic model or None",
        )
    for flag in ("needs_rod", "default"):
        value = getattr(mechanism, flag)
        if not isinstance(value, bool):
            raise PluginFailure(
                plugin,
                where,
                f"mechanism {mechanism.name!r}: {flag} = {shorten(value)}; expected True or False",
            )
    return mechanism


def _is_model(model: object) -> bool:
    """None, or a class that validates a table as a pydantic model does."""
    return model is None or (
        isinstance(model, type) and callable(getattr(model, "model_validate", None))
    )


def checked_probe(probe: object, plugin: str, hook: str, foreign: bool = True) -> ErrorProbe:
    where = f"hook {hook}"
    if not isinstance(probe, ErrorProbe):
        raise _garbage(plugin, where, "the hook", probe, "ErrorProbe objects")
    if not isinstance(probe.name, str) or not callable(probe.applies) or not callable(probe.run):
        raise PluginFailure(
            plugin,
            where,
            f"error probe {shorten(probe.name)}: a str name and the "
            "functions applies and run are required",
        )
    return probe


def checked_catalog(catalog: object, plugin: str, hook: str, foreign: bool = True) -> Catalog:
    """``catalog`` as a hook returned it; a third-party catalog's file is read: TOML of texts."""
    where = f"hook {hook}"
    if not isinstance(catalog, Catalog):
        raise _garbage(plugin, where, "the hook", catalog, "Catalog objects")
    if (
        not isinstance(catalog.language, str)
        or not isinstance(catalog.path, (str, os.PathLike))
        or not os.path.isfile(catalog.path)
    ):
        raise PluginFailure(
            plugin,
            where,
            f"catalog {shorten(catalog.language)}: path {shorten(str(catalog.path))} is not a file",
        )
    problem = _catalog_problem(catalog.path) if foreign else None
    if problem:
        raise PluginFailure(
            plugin, where, f"catalog {catalog.language!r} ({catalog.path}): {problem}"
        )
    return catalog


def _catalog_problem(path) -> str | None:
    if os.path.getsize(path) > _MAX_CATALOG_BYTES:
        return f"larger than {_MAX_CATALOG_BYTES // 2**20} MB"
    try:
        with open(path, "rb") as file:
            table = tomllib.load(file)
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        return f"not a readable TOML file ({describe(exc)})"
    return _texts_problem(table, "")


def _texts_problem(table: dict, prefix: str) -> str | None:
    """The first key of a catalog whose value is neither a text nor a table of texts."""
    for key, value in table.items():
        if isinstance(value, dict):
            problem = _texts_problem(value, f"{prefix}{key}.")
            if problem:
                return problem
        elif not isinstance(value, str):
            return f"{prefix}{key} = {shorten(value, 60)} is not a text"
    return None


# ----------------------------------------------------------------------------- guarded calls
def guarded_stage(stage: Stage, plugin: str, foreign: bool) -> Stage:
    """``stage`` whose calls are named and limited in time (see the module docstring)."""
    where = f"stage {stage.name!r}"

    @functools.wraps(stage.applies)
    def applies(scene, *services):  # services: as the orchestrator passes them (Stage.services)
        reason = call(plugin, where, "applies", foreign, stage.applies, scene, *services)
        if reason is not None and not isinstance(reason, str):
            raise _garbage(
                plugin,
                where,
                "applies",
                reason,
                "None (the stage applies) or a str (the reason it does not)",
            )
        return reason

    @functools.wraps(stage.run)
    def run(scene, inputs):
        output = call(plugin, where, "run", foreign, stage.run, scene, inputs)
        if foreign:
            check_stage_output(stage, output, plugin)
        return output

    if stage.default_angle_step is not None:
        stage = dataclasses.replace(
            stage,
            default_angle_step=_guarded_step(stage.default_angle_step, plugin, where, foreign),
        )
    look = stage.presentation
    if look is None:
        return dataclasses.replace(stage, applies=applies, run=run)

    @functools.wraps(look.render)
    def render(output, ctx):
        body = call(plugin, where, "render", foreign, look.render, output, ctx)
        if body is not None and not isinstance(body, str):
            raise _garbage(plugin, where, "render", body, "the section's HTML as a str, or None")
        return body

    def guarded_rows(hook: str):
        given = getattr(look, hook)
        if given is None:
            return None

        @functools.wraps(given)
        def rows_of(scene, ctx):
            rows = call(plugin, where, hook, foreign, given, scene, ctx)
            if foreign and not _is_rows(rows):
                raise _garbage(
                    plugin,
                    where,
                    hook,
                    rows,
                    "a list of (quantity, symbol, value, unit) tuples of str",
                )
            return rows

        return rows_of

    guarded = dataclasses.replace(
        look,
        render=render,
        input_rows=guarded_rows("input_rows"),
        taken_rows=guarded_rows("taken_rows"),
    )
    return dataclasses.replace(stage, applies=applies, run=run, presentation=guarded)


def _guarded_step(wish: Callable, plugin: str, where: str, foreign: bool) -> Callable:
    """A stage's ``default_angle_step`` named and limited as its other calls; a value that is
    not None or a positive number of degrees is the plugin's error."""

    @functools.wraps(wish)
    def default_angle_step(scene):
        step = call(plugin, where, "default_angle_step", foreign, wish, scene)
        number = isinstance(step, numbers.Real) and not isinstance(step, bool)
        if step is not None and not (number and 0 < step < math.inf):
            raise _garbage(
                plugin, where, "default_angle_step", step, "None or a positive number of degrees"
            )
        return step

    return default_angle_step


def _is_rows(rows: object) -> bool:
    return isinstance(rows, (list, tuple)) and all(
        isinstance(row, (list, tuple)) and len(row) == 4 and all(isinstance(v, str) for v in row)
        for row in rows
    )


def guarded_mechanism(mechanism: Mechanism, plugin: str, foreign: bool) -> Mechanism:
    where = f"mechanism {mechanism.name!r}"

    @functools.wraps(mechanism.check)
    def check(scene):
        problems = call(plugin, where, "check", foreign, mechanism.check, scene)
        if foreign and not (
            isinstance(problems, (list, tuple)) and all(isinstance(p, Problem) for p in problems)
        ):
            raise _garbage(plugin, where, "check", problems, "a list of crankdyn.errors.Problem")
        return problems

    @functools.wraps(mechanism.geometry)
    def geometry(scene, crank_angle_rad):
        shape = call(plugin, where, "geometry", foreign, mechanism.geometry, scene, crank_angle_rad)
        if foreign and not isinstance(shape, MechanismGeometry):
            raise _garbage(plugin, where, "geometry", shape, "a MechanismGeometry")
        return shape

    return dataclasses.replace(
        mechanism, check=check, geometry=None if mechanism.geometry is None else geometry
    )


def guarded_probe(probe: ErrorProbe, plugin: str, foreign: bool) -> ErrorProbe:
    where = f"error probe {probe.name!r}"

    @functools.wraps(probe.applies)
    def applies(scene):
        return bool(call(plugin, where, "applies", foreign, probe.applies, scene))

    @functools.wraps(probe.run)
    def run(scene, runner):
        points = call(plugin, where, "run", foreign, probe.run, scene, runner)
        if foreign and not (
            isinstance(points, (list, tuple)) and all(isinstance(p, ProbePoint) for p in points)
        ):
            raise _garbage(plugin, where, "run", points, "a list of ProbePoint")
        return points

    return dataclasses.replace(probe, applies=applies, run=run)


# ----------------------------------------------------------------------------- a stage's output
def check_stage_output(stage: Stage, output: object, plugin: str) -> None:
    """What a third-party stage's ``run`` returned, against :class:`StageOutput`'s contract."""
    where = f"stage {stage.name!r}"
    if not isinstance(output, StageOutput):
        raise _garbage(plugin, where, "run", output, "a StageOutput")
    problem = _output_problem(stage, output)
    if problem:
        raise PluginFailure(plugin, where, f"run returned {problem}")


def _output_problem(stage: Stage, output: StageOutput) -> str | None:
    for name in ("data", "results", "tables", "artifacts"):
        if not isinstance(getattr(output, name), Mapping):
            return f"{name} = {shorten(getattr(output, name))}; expected a dict"
    if set(output.data) != set(stage.provides):
        return (
            f"data with the keys {sorted(map(str, output.data))}; the stage declares "
            f"provides={list(stage.provides)}"
        )
    for key in stage.provides:
        problem = _contract_problem(key, output.data[key])
        if problem:
            return f"data[{key!r}]: {problem}"
    problem = _json_problem(output.results, "results", 0)
    if problem:
        return problem
    for name in dict.keys(output.tables):
        problem = _table_problem(stage, name, dict.__getitem__(output.tables, name))
        if problem:
            return f"tables[{shorten(name)}]: {problem}"
    if not isinstance(output.notes, (list, tuple)) or not all(map(_is_note, output.notes)):
        return f"notes = {shorten(output.notes)}; expected a list of (catalog key, parameters dict)"
    return None


def _is_note(note: object) -> bool:
    return (
        isinstance(note, (list, tuple))
        and len(note) == 2
        and isinstance(note[0], str)
        and isinstance(note[1], Mapping)
    )


def _contract_problem(key: str, value: object) -> str | None:
    """What is wrong with ``value`` as the data of a :mod:`crankdyn.plugin.contracts` key: its type,
    an array field that is not a finite numeric array, a number field that is not finite."""
    expected = CONTRACT_TYPES.get(key)
    if expected is None:
        return None
    if not isinstance(value, expected):
        return f"{shorten(value)} is not a crankdyn.plugin.contracts.{expected.__name__}"
    for field in dataclasses.fields(value):
        kind = str(field.type)
        item = getattr(value, field.name)
        if item is None and "None" in kind:
            continue
        if kind.startswith("np.ndarray"):
            problem = _array_problem(item)
        elif kind.startswith("float"):
            problem = None if _finite_number(item) else "not a finite number"
        else:
            continue
        if problem:
            return f"{field.name} = {shorten(item, 60)}: {problem}"
    return None


def _array_problem(item: object) -> str | None:
    if not isinstance(item, np.ndarray):
        return "not a numpy array"
    if item.dtype.kind not in "biuf":
        return f"an array of {item.dtype}, not of numbers"
    if item.dtype.kind == "f" and not np.isfinite(item).all():
        return f"{int(np.count_nonzero(~np.isfinite(item)))} value(s) not finite (NaN or infinite)"
    return None


def _finite_number(item: object) -> bool:
    return isinstance(item, numbers.Real) and not isinstance(item, bool) and math.isfinite(item)


def _json_problem(value: object, path: str, depth: int) -> str | None:
    """Where ``value`` holds what results.json cannot hold (NaN is written as null)."""
    if depth > _MAX_DEPTH:
        return f"{path}: nested deeper than {_MAX_DEPTH} levels"
    if value is None or isinstance(value, (str, bool, numbers.Real, np.bool_)):
        return None
    if isinstance(value, np.ndarray):
        return (
            None
            if value.dtype.kind in "biuf" and value.size <= 10**7
            else f"{path}: an array of {value.dtype} (size {value.size}), not a JSON list of numbers"
        )
    if isinstance(value, Mapping):
        for key, item in value.items():
            if not isinstance(key, str):
                return f"{path}: the key {shorten(key)} is not a str"
            problem = _json_problem(item, f"{path}[{key!r}]", depth + 1)
            if problem:
                return problem
        return None
    if isinstance(value, (list, tuple)):
        for index, item in enumerate(value):
            problem = _json_problem(item, f"{path}[{index}]", depth + 1)
            if problem:
                return problem
        return None
    return (
        f"{path}: {shorten(value, 60)} ({type(value).__name__}) cannot be written to results.json"
    )


def _table_problem(stage: Stage, name: object, table: object) -> str | None:
    if not isinstance(name, str) or not declared(name, stage.tables):
        return f"not declared in Stage.tables (declared: {list(stage.tables)})"
    if type(table).__name__ == "DataFrame" and type(table).__module__.startswith("pandas"):
        return None
    if isinstance(table, Mapping):
        lengths = set()
        for column, values in table.items():
            if not isinstance(values, (list, tuple, np.ndarray)) or np.ndim(values) != 1:
                return (
                    f"column {shorten(column)} is {shorten(values, 60)}; "
                    "expected a list or 1-D array"
                )
            lengths.add(len(values))
        return None if len(lengths) <= 1 else f"columns of different lengths {sorted(lengths)}"
    if isinstance(table, list) and all(isinstance(row, Mapping) for row in table):
        return None
    return f"{shorten(table, 60)}; expected a DataFrame, a dict of columns or a list of row dicts"
