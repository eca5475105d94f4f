"""MkDocs hook: the scene reference and the results.json reference, generated from the code.

A page that holds the line ``<!-- generated: scene-reference -->`` gets, in its place, one table per
scene table: every field of the pydantic models (:mod:`crankdyn.scene.model`, the stages' option models,
the mechanisms' parameter models) with its type, unit, range and default read from the model, and
its meaning from ``docs/reference/scene-fields.toml``. ``<!-- generated: results-reference -->``
gets, per stage of the registry, its declarations (``Stage``: requires, provides, options table,
tables, figures, answer-key columns) and the meaning of its results.json keys from
``docs/reference/results-keys.toml``.

A field of the code without a meaning, or a meaning for a name the code does not have, fails the
build: the references cannot drift from the code.
"""

from __future__ import annotations

import inspect
import tomllib
import types
import typing
from pathlib import Path
from typing import Any

from mkdocs.exceptions import PluginError

DOCS = Path(__file__).resolve().parent.parent
SCENE_MARK = "<!-- generated: scene-reference -->"
RESULTS_MARK = "<!-- generated: results-reference -->"
# Fields of the Scene model that the loader sets, not the scene file.
LOADER_FIELDS = {"base_dir", "data_dirs"}


def on_page_markdown(markdown: str, page, config, files) -> str:
    if SCENE_MARK in markdown:
        markdown = markdown.replace(SCENE_MARK, scene_reference())
    if RESULTS_MARK in markdown:
        markdown = markdown.replace(RESULTS_MARK, results_reference())
    return markdown


def _descriptions(name: str) -> dict[str, dict[str, str]]:
    with open(DOCS / "reference" / name, "rb") as file:
        return tomllib.load(file)


def _cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


# --- scene reference ------------------------------------------------------------------------------


def _closure(function) -> dict[str, Any]:
    try:
        return dict(inspect.getclosurevars(function).nonlocals)
    except (TypeError, ValueError):
        return {}


def _bounds(values: dict[str, Any], shown=lambda x: f"{x:g}") -> list[str]:
    symbols = {"gt": ">", "ge": "≥", "lt": "<", "le": "≤"}
    return [f"{symbols[k]} {shown(values[k])}" for k in symbols if values.get(k) is not None]


def _describe_annotated(metadata: list) -> tuple[str, list[str]]:
    """(kind, range) of a field built by ``crankdyn.scene.model.quantity``/``number`` or ``Field``."""
    kind, bounds = "", []
    for item in metadata:
        function = getattr(item, "func", None)
        values = _closure(function) if function else {}
        if "kind" in values:  # the quantity's parser: the physical dimension
            kind = f"quantity ({values['kind'].replace('_', ' ')})"
        elif "unit" in values and "scale" in values:  # the quantity's range, in its unit
            unit, scale = values["unit"], values["scale"]
            bounds += _bounds(values, lambda x: f"{x / scale:g} {unit}".strip())  # noqa: B023 - called within this iteration
            if unit:
                kind = f"{kind or 'quantity'}, e.g. in {unit}"
        elif {"gt", "ge", "lt", "le"} & set(values):  # a plain number's range
            kind = kind or "number"
            bounds += _bounds(values)
        for attribute, symbol in (
            ("gt", ">"),
            ("ge", "≥"),
            ("lt", "<"),
            ("le", "≤"),
            ("max_length", "length ≤"),
        ):
            value = getattr(item, attribute, None)
            if value is not None and not callable(value):
                bounds.append(
                    f"{symbol} {value:g}"
                    if isinstance(value, (int, float))
                    else f"{symbol} {value}"
                )
    return kind, bounds


def _type_text(annotation, metadata: list) -> str:

    origin = typing.get_origin(annotation)
    if origin in (typing.Union, types.UnionType):
        members = [a for a in typing.get_args(annotation) if a is not type(None)]
        annotation = members[0] if len(members) == 1 else annotation
    if typing.get_origin(annotation) is typing.Annotated:
        base, *extra = typing.get_args(annotation)
        annotation, metadata = base, list(metadata) + list(extra)
    kind, bounds = _describe_annotated(metadata)
    origin = typing.get_origin(annotation)
    if origin is typing.Literal:
        text = "one of " + ", ".join(f"`{v}`" for v in typing.get_args(annotation))
    elif kind:
        text = kind
    elif origin is list:
        (item,) = typing.get_args(annotation) or (Any,)
        text = "list of " + _type_text(item, []).split(";")[0]
    elif origin in (typing.Union, types.UnionType):
        text = " or ".join(_type_text(a, []) for a in typing.get_args(annotation))
    elif annotation is bool:
        text = "`true` or `false`"
    elif annotation is int:
        text = "whole number"
    elif annotation is float:
        text = "number"
    elif annotation is str:
        text = "text"
    elif isinstance(annotation, type) and hasattr(annotation, "model_fields"):
        text = "table"
    else:
        text = getattr(annotation, "__name__", str(annotation))
    if bounds:
        text += "; " + ", ".join(bounds)
    return text


def _default_text(info, field: str = "") -> str:
    from pydantic_core import PydanticUndefined

    if field == "year":  # evaluated when the package is imported
        return "the current year"

    if info.default is PydanticUndefined and info.default_factory is None:
        return "required"
    default = info.default_factory() if info.default is PydanticUndefined else info.default
    if default is None:
        return "—"
    if isinstance(default, bool):
        return f"`{str(default).lower()}`"
    if isinstance(default, str):
        return f'`"{default}"`' if default else '`""`'
    if hasattr(default, "model_fields"):
        return "(table)"
    return f"`{default}`"


def _model_tables() -> list[tuple[str, type, str]]:
    """(table name, pydantic model, where it comes from) of every scene table the code knows."""
    from crankdyn.plugin.registry import default_registry
    from crankdyn.scene.model import Cycle, Scene

    tables = []
    for name, info in Scene.model_fields.items():
        model = info.annotation
        members = [a for a in typing.get_args(model) if a is not type(None)] or [model]
        model = members[0]
        if hasattr(model, "model_fields"):
            tables.append((name, model, "crankdyn.scene.model." + model.__name__))
            if model is Cycle:
                rounding = Cycle.model_fields["rounding"].annotation
                tables.append(
                    ("cycle.rounding", rounding, "crankdyn.scene.model." + rounding.__name__)
                )
    registry = default_registry()
    for stage in sorted(registry.stages.values(), key=lambda s: s.name):
        if stage.options_table and stage.options_model is not None:
            tables.append((stage.options_table, stage.options_model, f"stage `{stage.name}`"))
    for name, mechanism in sorted(registry.mechanisms.items()):
        if mechanism.params_model is not None:
            tables.append((f"mechanism.{name}", mechanism.params_model, f"mechanism `{name}`"))
    return tables


def scene_reference() -> str:
    descriptions = _descriptions("scene-fields.toml")
    problems, parts = [], []
    tables = _model_tables()
    known_tables = {name for name, _, _ in tables} | {"mechanism"}
    for table in descriptions:
        if table not in known_tables:
            problems.append(f"scene-fields.toml: [{table}] is no scene table of the code")
    mechanism = descriptions.get("mechanism", {})
    for name, model, source in tables:
        if name == "cycle.rounding":
            fields = {k: v for k, v in model.model_fields.items()}
        else:
            fields = {k: v for k, v in model.model_fields.items() if k not in LOADER_FIELDS}
        if name in ("cycle",):
            fields.pop("rounding", None)
        meanings = descriptions.get(name, {})
        covered: dict[str, str] = {}
        for group in meanings:
            if group.startswith("_"):
                continue
            for field in (f.strip() for f in group.split(",")):
                if field not in fields:
                    problems.append(
                        f"scene-fields.toml: [{name}] {field!r} is no field of {source}"
                    )
                covered[field] = group
        missing = [f for f in fields if f not in covered]
        problems += [
            f"scene-fields.toml: [{name}] has no meaning for the field {f!r} ({source})"
            for f in missing
        ]
        if name.startswith("mechanism."):
            title = f'`[mechanism]` of `engine.mechanism = "{name.split(".", 1)[1]}"`'
        else:
            title = f"`[{name}]`"
        lines = [f"### {title}", ""]
        if meanings.get("_about"):
            lines += [meanings["_about"], ""]
        lines += [
            f"From the code: {source}.",
            "",
            "| key | type, unit, range | default | meaning |",
            "|---|---|---|---|",
        ]
        seen = set()
        for field in fields:
            group = covered.get(field)
            if group is None or group in seen:
                continue
            seen.add(group)
            members = [f.strip() for f in group.split(",")]
            keys = "<br>".join(f"`{m}`" for m in members)
            kinds = "<br>".join(
                _cell(_type_text(fields[m].annotation, fields[m].metadata)) for m in members
            )
            defaults = "<br>".join(_default_text(fields[m], m) for m in members)
            lines.append(f"| {keys} | {kinds} | {defaults} | {_cell(meanings[group])} |")
        if meanings.get("_note"):
            lines += ["", meanings["_note"]]
        parts.append("\n".join(lines))
        if name == "analysis" and mechanism.get("_about"):
            parts.append("### `[mechanism]`\n\n" + mechanism["_about"])
    if problems:
        raise PluginError(
            "the scene reference does not match the code:\n  " + "\n  ".join(problems)
        )
    return "\n\n".join(parts) + "\n"


# --- results.json reference -----------------------------------------------------------------------


def _csv_name(stage: str, table: str) -> str:
    return (
        f"`tables/{stage}.csv`"
        if table == stage
        else f"`tables/{stage}_{table.replace('*', '<n>')}.csv`"
    )


def results_reference() -> str:
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.i18n import translator

    descriptions = _descriptions("results-keys.toml")
    registry = default_registry()
    english = translator("en", registry.catalogs)
    problems = [
        f"results-keys.toml: [{name}] is no stage of the registry"
        for name in descriptions
        if name != "_top"
        and name not in registry.stages
        and not any(name == s.name for s in registry.stages.values())
    ]
    # A stage may share its keys with another of the same results (drawing and drawing_linkage).
    aliases = {"drawing_linkage": "drawing"}
    parts = ["### The document's own keys", "", "| key | meaning |", "|---|---|"]
    parts += [
        f"| {_keys(k)} | {_cell(v)} |"
        for k, v in descriptions["_top"].items()
        if not k.startswith("_")
    ]
    for stage in sorted(registry.stages.values(), key=lambda s: s.name):
        meanings = descriptions.get(stage.name) or descriptions.get(aliases.get(stage.name, ""))
        if meanings is None:
            problems.append(f"results-keys.toml: stage {stage.name!r} has no section")
            continue
        look = stage.presentation
        title = english(look.title_key) if look is not None else stage.name
        lines = ["", f"### `{stage.name}` — {title}", ""]
        if meanings.get("_about"):
            lines += [meanings["_about"], ""]
        declared = [
            ("requires", ", ".join(f"`{k}`" for k in stage.requires) or "—"),
            ("provides", ", ".join(f"`{k}`" for k in stage.provides) or "—"),
        ]
        if stage.uses:
            declared.append(("uses when present", ", ".join(f"`{k}`" for k in stage.uses)))
        declared.append(
            (
                "runs",
                "by default, when the scene needs it"
                if stage.default
                else "only when named in `analysis.stages`",
            )
        )
        if stage.options_table:
            declared.append(("options", f"`[{stage.options_table}]`"))
        if stage.tables:
            declared.append(("tables", ", ".join(_csv_name(stage.name, t) for t in stage.tables)))
        if look is not None and look.figures:
            declared.append(("figures", ", ".join(f"`{f}`" for f in look.figures)))
        if stage.answer_columns:
            declared.append(
                ("answer-key columns", ", ".join(f"`{c.column}`" for c in stage.answer_columns))
            )
        lines += ["| declared | |", "|---|---|"] + [f"| {k} | {v} |" for k, v in declared]
        keys = [(k, v) for k, v in meanings.items() if not k.startswith("_")]
        if keys:
            lines += ["", "| key | meaning |", "|---|---|"] + [
                f"| {_keys(k)} | {_cell(v)} |" for k, v in keys
            ]
        parts.append("\n".join(lines))
    if problems:
        raise PluginError(
            "the results.json reference does not match the code:\n  " + "\n  ".join(problems)
        )
    return "\n".join(parts) + "\n"


def _keys(group: str) -> str:
    return ", ".join(f"`{k.strip()}`" for k in group.split(","))
