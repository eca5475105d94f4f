"""The batch answer key's columns, collected from what the stages declare.

No stage's result key is named here: every stage lists its columns in
``Stage.answer_columns`` (:class:`crankdyn.plugin.types.AnswerColumn`), and the key
shows them stage by stage in requires/provides order (ties by stage name), each
stage's columns in the order it gives.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..errors import PluginError
from ..plugin.registry import Registry
from ..plugin.types import AnswerColumn, Stage


@dataclass(frozen=True)
class KeyColumn:
    """One answer-key column: the stage that provides it and its declaration."""

    stage: str
    declared: AnswerColumn

    @property
    def name(self) -> str:
        return self.declared.column


def dependency_order(stages: dict[str, Stage]) -> list[str]:
    """Stage names so that every provider of a key comes before the stages requiring it.

    Ties (and stages in a requires cycle, which the orchestrator refuses anyway) go by name.
    """
    providers: dict[str, set[str]] = {}
    for stage in stages.values():
        for key in stage.provides:
            providers.setdefault(key, set()).add(stage.name)
    before = {
        name: {p for key in stage.requires for p in providers.get(key, ()) if p != name}
        for name, stage in stages.items()
    }
    order: list[str] = []
    placed: set[str] = set()
    while len(order) < len(stages):
        ready = sorted(n for n in stages if n not in placed and before[n] <= placed)
        if not ready:  # a cycle: place the rest by name
            ready = sorted(n for n in stages if n not in placed)
        order.append(ready[0])
        placed.add(ready[0])
    return order


def answer_columns(registry: Registry) -> list[KeyColumn]:
    """Every answer-key column the installed stages declare, in key order."""
    columns = [
        KeyColumn(name, column)
        for name in dependency_order(registry.stages)
        for column in registry.stages[name].answer_columns
    ]
    seen: dict[str, str] = {}
    for column in columns:
        if column.name in seen:
            raise PluginError(
                f"answer-key column {column.name!r} declared by both {seen[column.name]!r} "
                f"and {column.stage!r}"
            )
        seen[column.name] = column.stage
    return columns


_ABSENT = object()


def _lookup(results: Any, path: str, default: Any = None) -> Any:
    for part in path.split("."):
        if not isinstance(results, dict) or part not in results:
            return default
        results = results[part]
    return results


def absent(document: dict, columns: list[KeyColumn]) -> list[str]:
    """The columns whose stage ran in this results.json document but whose key is not in its
    results (a typo in ``AnswerColumn.key``, or a result renamed): their cells stay empty, and the
    batch warns (:func:`unanswered`) rather than leave the column out without a word."""
    ran = set(document.get("stages_run") or ())
    return [
        c.name
        for c in columns
        if c.stage in ran and _lookup(document.get(c.stage), c.declared.key, _ABSENT) is _ABSENT
    ]


def unanswered(columns: list[KeyColumn], outcomes: list[tuple[list[str], list[str]]]) -> list[str]:
    """One warning per column whose key was absent from its stage's results in every variant that
    ran the stage; ``outcomes``: (stages run, :func:`absent` columns) of each successful variant."""
    warnings = []
    for column in columns:
        ran = [missing for stages, missing in outcomes if column.stage in stages]
        if ran and all(column.name in missing for missing in ran):
            # a stage states a result its scene does not give as None (not absent), so absent in
            # every variant is most likely a typo; a third-party stage may not, so both are named
            warnings.append(
                f"answer-key column {column.name!r} left out: no variant's {column.stage!r} results "
                f"hold {column.declared.key!r} (a typo in AnswerColumn.key, or a result these "
                f"scenes do not give)"
            )
    return warnings


def answers(document: dict, columns: list[KeyColumn]) -> dict[str, Any]:
    """The answer-key values of one results.json document (a stage that did not run gives None)."""
    out: dict[str, Any] = {}
    for column in columns:
        value = _lookup(document.get(column.stage) or {}, column.declared.key)
        number = isinstance(value, (int, float)) and not isinstance(value, bool)
        out[column.name] = value * column.declared.factor if number else None
    return out
