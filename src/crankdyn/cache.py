"""Incremental re-runs for the live preview: a stage runs again only when what it read changed.

Each stage's result is cached under

* the digests of exactly the scene fields it read on its last run (top-level tables:
  ``engine``, ``masses``, ``cycle``, ...; recorded while it ran, through a read-tracking copy
  of the scene, so nothing has to be declared by hand and a plugin stage is covered too), and
* the digests of the upstream data it was given (its ``requires``), by content.

A save that changes ``masses.rod`` therefore re-runs the stages that read ``[masses]`` (and
those whose upstream data changed as a result), but not the indicator diagram, which reads
only ``[engine]`` and ``[cycle]``. A stage whose reads cannot be told apart (it iterated or
dumped the whole scene) depends on every field. :attr:`StageCache.runs` counts the real runs.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import pickle
import time
import types
import uuid
from collections import Counter
from dataclasses import dataclass
from typing import Any

from .orchestrator import Plan, RunResult, check_output
from .plugin_types import Stage, StageOutput
from .scene import Scene

#: Read of the scene as a whole (``dict(scene)``, ``model_dump``, ``__dict__``): depends on every field.
EVERYTHING = "*"
#: The plugin tables (``[flywheel]``, ``[torsion]``, ...), kept as pydantic extras.
EXTRA = "__extra__"
_WHOLE = {"__dict__", "model_dump", "model_dump_json", "model_copy", "__getstate__", "__reduce_ex__"}
_EXTRA_NAMES = {"__pydantic_extra__", "model_extra"}

_reads: dict[int, set[str]] = {}
_classes: dict[type, type] = {}


def _tracking_class(cls: type) -> type:
    if cls not in _classes:
        fields = frozenset(cls.model_fields)

        def __getattribute__(self, name):  # noqa: N807 - the hook itself
            reads = _reads.get(id(self))
            if reads is not None:
                if name in fields:
                    reads.add(name)
                elif name in _EXTRA_NAMES:
                    reads.add(EXTRA)
                elif name in _WHOLE:
                    reads.add(EVERYTHING)
            return super(tracked, self).__getattribute__(name)

        tracked = type(f"Tracked{cls.__name__}", (cls,), {"__getattribute__": __getattribute__,
                                                           "__module__": __name__})
        _classes[cls] = tracked
    return _classes[cls]


def _tracked_copy(scene: Scene) -> Scene:
    """The same scene (no validation re-run) whose field reads are recorded in ``_reads``."""
    cls = _tracking_class(type(scene))
    values = {name: scene.__dict__[name] for name in type(scene).model_fields}
    copy = cls.model_construct(_fields_set=set(scene.model_fields_set), **values, **(scene.model_extra or {}))
    _reads[id(copy)] = set()
    return copy


def _digest(value: Any, depth: int = 0) -> str:
    """Content digest. What pickle refuses is taken apart: a dataclass field by field, a
    function by its code, defaults and captured values, a bound method by function and owner.
    Anything else gets a fresh token (never equal to another: its consumers re-run)."""
    try:
        return hashlib.sha256(pickle.dumps(value, protocol=5)).hexdigest()
    except Exception:  # noqa: BLE001 - unpicklable: fall through to the parts below
        pass
    if depth > 8:
        return uuid.uuid4().hex
    parts: list[str] = [type(value).__qualname__]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        parts += [_digest(getattr(value, f.name), depth + 1) for f in dataclasses.fields(value)]
    elif isinstance(value, types.FunctionType):
        code = value.__code__
        parts += [code.co_code.hex(), repr(code.co_consts), repr(code.co_names), _digest(value.__defaults__, depth + 1)]
        parts += [_digest(cell.cell_contents, depth + 1) for cell in value.__closure__ or ()]
    elif isinstance(value, types.MethodType):
        parts += [_digest(value.__func__, depth + 1), _digest(value.__self__, depth + 1)]
    elif isinstance(value, functools.partial):
        parts += [_digest(value.func, depth + 1), _digest(value.args, depth + 1), _digest(value.keywords, depth + 1)]
    elif isinstance(value, (tuple, list)):
        parts += [_digest(v, depth + 1) for v in value]
    elif isinstance(value, dict):
        parts += [_digest(k, depth + 1) + _digest(v, depth + 1) for k, v in value.items()]
    else:
        return uuid.uuid4().hex
    return hashlib.sha256("|".join(parts).encode()).hexdigest()


def field_digests(scene: Scene, names: frozenset[str]) -> tuple[tuple[str, str], ...]:
    """Digests of the named top-level fields of ``scene`` (see :data:`EVERYTHING`, :data:`EXTRA`)."""
    if EVERYTHING in names:
        names = frozenset(type(scene).model_fields) | {EXTRA}
    out = []
    for name in sorted(names):
        value = scene.model_extra if name == EXTRA else scene.__dict__[name]
        out.append((name, _digest(value)))
    return tuple(out)


@dataclass
class _Entry:
    stage: Stage
    reads: frozenset[str]
    fields: tuple
    upstream: tuple
    output: StageOutput
    data_digests: dict[str, str]


class StageCache:
    """Stage results kept between runs of (versions of) one scene; see the module docstring."""

    def __init__(self) -> None:
        self._entries: dict[str, _Entry] = {}
        self.runs: Counter[str] = Counter()  # real runs per stage (cache hits not counted)

    def _valid(self, entry: _Entry | None, stage: Stage, scene: Scene, upstream: tuple) -> bool:
        return (entry is not None and entry.stage is stage and entry.upstream == upstream
                and entry.fields == field_digests(scene, entry.reads))

    def run_plan(self, scene: Scene, the_plan: Plan) -> RunResult:
        """:func:`crankdyn.orchestrator.run_plan`, re-running only stages whose inputs changed."""
        data: dict[str, Any] = {}
        digests: dict[str, str] = {}
        outputs: dict[str, StageOutput] = {}
        timing: dict[str, float] = {}
        for stage in the_plan.order:
            upstream = tuple((key, digests[key]) for key in stage.requires)
            entry = self._entries.get(stage.name)
            start = time.perf_counter()
            if not self._valid(entry, stage, scene, upstream):
                tracked = _tracked_copy(scene)
                try:
                    output = stage.run(tracked, {key: data[key] for key in stage.requires})
                finally:
                    reads = frozenset(_reads.pop(id(tracked)))
                check_output(stage, output)
                entry = _Entry(stage, reads, field_digests(scene, reads), upstream, output,
                               {key: _digest(value) for key, value in output.data.items()})
                self._entries[stage.name] = entry
                self.runs[stage.name] += 1
            timing[stage.name] = time.perf_counter() - start
            data.update(entry.output.data)
            digests.update(entry.data_digests)
            outputs[stage.name] = entry.output
        return RunResult(scene=scene, plan=the_plan, outputs=outputs, timing_s=timing)
