"""Incremental re-runs for the live preview: a stage runs again only when what it read changed.

Each stage's result is cached under

* the digests of exactly the scene fields it read on its last run (top-level tables:
  ``engine``, ``masses``, ``cycle``, ...; recorded while it ran, through a read-tracking copy
  of the scene, so nothing has to be declared by hand and a plugin stage is covered too), and
* the digests of the upstream data it was given (its ``requires``), by content.

A data file the stage opened through ``scene.resolve`` (a pressure trace) is a read too, keyed by
the file's path and digested by its contents: a changed trace under the same name re-runs the
stages that read it, and only those.

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
from pathlib import Path
from typing import Any

from pydantic import BaseModel

from ..physics import lazy
from ..plugin.types import Stage, StageOutput
from ..scene.model import Scene
from .orchestrator import Plan, RunResult, check_output, is_study, stage_inputs

#: Read of the scene as a whole (``dict(scene)``, ``model_dump``, ``__dict__``): depends on every field.
EVERYTHING = "*"
_ALL = frozenset({EVERYTHING})
#: The plugin tables (``[flywheel]``, ``[torsion]``, ...), kept as pydantic extras.
EXTRA = "__extra__"
_WHOLE = {
    "__dict__",
    "model_dump",
    "model_dump_json",
    "model_copy",
    "__getstate__",
    "__reduce_ex__",
}
_EXTRA_NAMES = {"__pydantic_extra__", "model_extra"}
#: A read of a data file: this prefix, the file's digest when read, ":" and its resolved path
#: (``Scene.resolve``); :func:`_file_read` makes one, :func:`_file_parts` takes it apart.
FILE = "file:"

#: The slot of a tracked copy that holds its :class:`_Recording` (None: not recording any more).
_RECORDING = "_crankdyn_recording"


@dataclass
class _Recording:
    """What a tracked copy records into: the read set (shared by a scene copy and its tables), the
    prefix of its reads ("" or "masses.") and, on a scene copy, its tracked tables, made once."""

    reads: set[str]
    prefix: str
    tables: dict[str, Any]


def _recording(tracked) -> _Recording | None:
    try:
        return object.__getattribute__(tracked, _RECORDING)
    except AttributeError:  # the slot was never set
        return None


@functools.cache
def _tracking_class(cls: type) -> type:
    """``cls`` with reads recorded: a field of the scene is recorded as its name, except that
    a table (a pydantic sub-model: ``masses``, ``engine``...) comes back as a tracked copy of
    itself, whose own reads are recorded as ``masses.rod``: a stage reading only
    ``masses.rod_cm_fraction`` does not depend on ``masses.rod``. Each copy keeps its recording
    in a slot of its own (made once per class: a pydantic class is costly to build)."""
    fields = frozenset(cls.model_fields)

    def __getattribute__(self, name):  # noqa: N807 - the hook itself
        value = super(tracked, self).__getattribute__(name)
        record = _recording(self)
        if record is None:
            return value
        reads, prefix = record.reads, record.prefix
        if name == "resolve" and not prefix:  # a data file: its contents are what the stage read
            return functools.partial(_resolve_recorded, value, reads)
        if name in fields:
            if not prefix and isinstance(value, BaseModel):  # one level deep: tables of the scene
                return _tracked_table(value, record, name)
            reads.add(prefix + name)
        elif name in _EXTRA_NAMES:
            reads.add(prefix + EXTRA if prefix else EXTRA)
        elif name in _WHOLE:
            reads.add(prefix.rstrip(".") if prefix else EVERYTHING)
        return value

    tracked = type(
        f"Tracked{cls.__name__}",
        (cls,),
        {"__getattribute__": __getattribute__, "__slots__": (_RECORDING,), "__module__": __name__},
    )
    return tracked


def _resolve_recorded(resolve, reads: set[str], name: str):
    """``resolve(name)``, recorded with the file's digest as the stage opens it: a file saved again
    while the stage runs then differs from what its output was computed from."""
    path = resolve(name)
    reads.add(_file_read(path))
    return path


def _file_read(path) -> str:
    """The read of data file ``path`` as it is now."""
    return f"{FILE}{_file_digest(path)}:{path}"


def _file_parts(read: str) -> tuple[str, str]:
    """(digest when read, path) of a :data:`FILE` read."""
    digest, path = read[len(FILE) :].split(":", 1)
    return digest, path


def _file_digest(path) -> str:
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError as exc:  # a missing or unreadable file: that is what the stage met
        return f"unreadable-{exc.__class__.__name__}"


def _construct(cls: type, model: BaseModel):
    values = {name: model.__dict__[name] for name in type(model).model_fields}
    return cls.model_construct(
        _fields_set=set(model.model_fields_set), **values, **(model.model_extra or {})
    )


def _tracked_table(table: BaseModel, scene_record: _Recording, name: str):
    """The scene copy's tracked copy of its table ``name``, recording its reads as ``name.field``
    into the scene copy's read set (made once per scene copy)."""
    copy = scene_record.tables.get(name)
    if copy is None:
        copy = _construct(_tracking_class(type(table)), table)
        object.__setattr__(copy, _RECORDING, _Recording(scene_record.reads, name + ".", {}))
        scene_record.tables[name] = copy
    return copy


def _tracked_copy(scene: Scene) -> Scene:
    """The same scene (no validation re-run) whose field reads it records itself."""
    copy = _construct(_tracking_class(type(scene)), scene)
    object.__setattr__(copy, _RECORDING, _Recording(set(), "", {}))
    return copy


def tracked_copy(scene: Scene) -> Scene:
    """A copy of ``scene`` that records which top-level fields are read; :func:`reads_of` tells."""
    return _tracked_copy(scene)


def reads_of(tracked: Scene) -> frozenset[str]:
    """The fields read through ``tracked`` so far (and stop recording them)."""
    record = _recording(tracked)
    if record is None:
        return frozenset()
    for table in record.tables.values():
        object.__setattr__(table, _RECORDING, None)
    object.__setattr__(tracked, _RECORDING, None)
    return frozenset(record.reads)


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
        parts += [
            code.co_code.hex(),
            repr(code.co_consts),
            repr(code.co_names),
            _digest(value.__defaults__, depth + 1),
        ]
        parts += [_digest(cell.cell_contents, depth + 1) for cell in value.__closure__ or ()]
    elif isinstance(value, types.MethodType):
        parts += [_digest(value.__func__, depth + 1), _digest(value.__self__, depth + 1)]
    elif isinstance(value, functools.partial):
        parts += [
            _digest(value.func, depth + 1),
            _digest(value.args, depth + 1),
            _digest(value.keywords, depth + 1),
        ]
    elif isinstance(value, (tuple, list)):
        parts += [_digest(v, depth + 1) for v in value]
    elif isinstance(value, dict):
        parts += [_digest(k, depth + 1) + _digest(v, depth + 1) for k, v in value.items()]
    else:
        return uuid.uuid4().hex
    return hashlib.sha256("|".join(parts).encode()).hexdigest()


def _field_value(scene: Scene, name: str) -> Any:
    """The value a recorded read names: ``engine``, ``masses.rod``, ``__extra__``, ``mechanism.__extra__``,
    ``file:<digest>:/path`` (the file's digest now)."""
    if name.startswith(FILE):
        return _file_digest(_file_parts(name)[1])
    head, _, rest = name.partition(".")
    value = scene.model_extra if head == EXTRA else scene.__dict__.get(head)
    if not rest:
        return value
    if value is None:
        return None  # the table is gone (or came): a change like any other
    if rest == EXTRA:
        return getattr(value, "model_extra", None)
    return value.__dict__.get(rest)


def field_digests(
    scene: Scene, names: frozenset[str], as_read: bool = False
) -> tuple[tuple[str, str], ...]:
    """Digests of the read fields of ``scene``, top-level (``engine``) or in a table (``masses.rod``);
    see :data:`EVERYTHING`, :data:`EXTRA`. A data file's digest is its contents' now, or with
    ``as_read`` (when an entry is made) the one it had when the stage opened it."""
    if EVERYTHING in names:
        names = (
            frozenset(type(scene).model_fields) | {EXTRA} | {n for n in names if n.startswith(FILE)}
        )

    def value(name: str):
        if as_read and name.startswith(FILE):
            return _file_parts(name)[0]
        return _field_value(scene, name)

    return tuple((name, _digest(value(name))) for name in sorted(names))


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
        # a deferred study: (stage, upstream digests, digests of every scene field and data file) when deferred
        self._deferred_keys: dict[str, tuple] = {}
        self._deferred_reads: dict[str, frozenset[str]] = {}
        self.runs: Counter[str] = Counter()  # real runs per stage (cache hits not counted)

    def _valid(self, entry: _Entry | None, stage: Stage, scene: Scene, upstream: tuple) -> bool:
        return (
            entry is not None
            and entry.stage is stage
            and entry.upstream == upstream
            and entry.fields == field_digests(scene, entry.reads)
        )

    def _everything(self) -> frozenset[str]:
        """What a study computed elsewhere counts as having read: every scene field, and every data
        file a stage of this cache has opened, as it is now (the worker's own reads do not come back)."""
        paths = {
            _file_parts(name)[1]
            for entry in self._entries.values()
            for name in entry.reads
            if name.startswith(FILE)
        }
        return _ALL | {_file_read(path) for path in paths}

    def deferred_study(self, name: str) -> bool:
        """Whether a :meth:`run_plan` deferred study ``name``."""
        return name in self._deferred_keys

    def adopt(self, name: str, output: StageOutput) -> None:
        """Keep the output of the deferred study ``name``, computed elsewhere (the preview's study
        worker) for the scene it was deferred with, as if it had run here; it counts as having
        read every field."""
        kept = self._entries.get(name)
        if kept is not None and kept.output is output:
            return  # kept already (it ran here, or was taken from the worker by run_plan)
        stage, upstream, fields = self._deferred_keys[name]
        self._entries[name] = _Entry(
            stage,
            self._deferred_reads[name],
            fields,
            upstream,
            output,
            {key: _digest(value) for key, value in output.data.items()},
        )
        self.runs[name] += 1

    @staticmethod
    def _run(
        stage: Stage, scene: Scene, inputs: dict[str, Any]
    ) -> tuple[StageOutput, frozenset[str]]:
        """(output, the scene fields it read) of ``stage`` run on a read-tracking copy of ``scene``."""
        tracked = _tracked_copy(scene)
        try:
            output = stage.run(tracked, inputs)
        finally:
            reads = reads_of(tracked)
        check_output(stage, output)
        return output, reads

    def run_plan(
        self,
        scene: Scene,
        the_plan: Plan,
        defer_studies: bool = False,
        deferred: RunResult | None = None,
    ) -> RunResult:
        """:func:`crankdyn.engine.orchestrator.run_plan`, re-running only stages whose inputs
        changed.

        With ``defer_studies``, a stage that would have to run again, comes ``last`` and provides
        nothing (a study of the others, such as the error against run time: no stage can wait
        for it) is not run: it is missing from the result's outputs (:attr:`RunResult.pending`),
        its inputs are kept in :attr:`RunResult.deferred` (so that it can be computed meanwhile,
        :mod:`crankdyn.engine.studies`), and a second call without ``defer_studies`` runs it (and
        only it). Given that first call's result as ``deferred``, the second call takes a study
        from it (:meth:`RunResult.study_output`: from its background child, or computed with the
        kept inputs) when the scene and the study's upstream data are still the ones it was
        deferred with; the study then counts as having read every field."""
        data: dict[str, Any] = {}
        digests: dict[str, str] = {}
        outputs: dict[str, StageOutput] = {}
        timing: dict[str, float] = {}
        kept: dict[str, dict[str, Any]] = {}
        for stage in the_plan.order:
            upstream = tuple(
                (key, digests[key]) for key in (*stage.requires, *stage.uses) if key in digests
            )
            entry = self._entries.get(stage.name)
            start, taken, imported = time.perf_counter(), None, lazy.import_seconds()
            if not self._valid(entry, stage, scene, upstream):
                study = everything = None
                if is_study(stage):
                    everything = self._everything()
                    study = (stage, upstream, field_digests(scene, everything, as_read=True))
                if defer_studies and study is not None:
                    kept[stage.name] = stage_inputs(stage, data, the_plan.registry)
                    self._deferred_keys[stage.name] = study
                    self._deferred_reads[stage.name] = everything
                    continue
                if (
                    study is not None
                    and deferred is not None
                    and stage.name in deferred.deferred
                    and self._deferred_keys.get(stage.name) == study
                ):
                    output, reads = deferred.study_output(stage.name), everything
                    taken = deferred.timing_s[
                        stage.name
                    ]  # its run (in the worker), not the wait for it
                else:
                    output, reads = self._run(
                        stage, scene, stage_inputs(stage, data, the_plan.registry)
                    )
                entry = _Entry(
                    stage,
                    reads,
                    field_digests(scene, reads, as_read=True),
                    upstream,
                    output,
                    {key: _digest(value) for key, value in output.data.items()},
                )
                self._entries[stage.name] = entry
                self.runs[stage.name] += 1
            # as orchestrator.run_stage times it: without scipy's import on the stage's first call
            timing[stage.name] = (
                max(0.0, time.perf_counter() - start - (lazy.import_seconds() - imported))
                if taken is None
                else taken
            )
            data.update(entry.output.data)
            digests.update(entry.data_digests)
            outputs[stage.name] = entry.output
        return RunResult(
            scene=scene, plan=the_plan, outputs=outputs, timing_s=timing, deferred=kept
        )
