"""Checks of a scene's raw TOML data before the model sees it.

Nesting depth (a scene of deeply nested arrays must be refused, not crash the
validator), control characters in text (they would reach the HTML raw) and
misspelt names of the core tables ("did you mean [engine]?").
"""

from __future__ import annotations

import difflib
import re
from typing import Any

from .errors import Problem

MAX_DEPTH = 16
# C0 controls except none, DEL and the C1 controls: nothing a scene's text needs.
_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")
CORE_TABLES = ("report", "engine", "masses", "cycle", "analysis", "mechanism")


def structure_problems(data: Any) -> list[Problem]:
    """Too-deep nesting and control characters anywhere in ``data``, each naming its dotted path."""
    problems: list[Problem] = []
    stack: list[tuple[str, Any, int]] = [("", data, 0)]
    while stack:  # iterative, so no depth can exhaust the interpreter's stack
        path, value, depth = stack.pop()
        if depth > MAX_DEPTH:
            problems.append(Problem(path or "scene", "(nested too deeply)",
                                    f"tables and arrays may be nested at most {MAX_DEPTH} levels deep"))
            continue
        if isinstance(value, dict):
            for key, item in value.items():
                child = f"{path}.{key}" if path else str(key)
                if _CONTROL.search(str(key)):
                    problems.append(Problem(child, str(key), "a key may not contain control characters"))
                stack.append((child, item, depth + 1))
        elif isinstance(value, list):
            stack.extend((f"{path}.{k}", item, depth + 1) for k, item in enumerate(value))
        elif isinstance(value, str) and _CONTROL.search(value):
            problems.append(Problem(path, value, "text may not contain control characters (tabs, line breaks, "
                                    "escape codes); write it on one line"))
    return sorted(problems, key=lambda p: p.field)


def table_problems(data: dict, plugin_tables: set[str] = frozenset()) -> list[Problem]:
    """Top-level tables whose name is close to a missing core table: "did you mean [engine]?"."""
    problems = []
    for name in data:
        if name in CORE_TABLES or name in plugin_tables or not isinstance(data[name], dict):
            continue
        missing = [t for t in CORE_TABLES if t not in data]
        close = difflib.get_close_matches(name, missing, n=1, cutoff=0.75)
        if close:
            problems.append(Problem(name, f"[{name}]", f"unknown table; did you mean [{close[0]}]? "
                                    "core tables: " + ", ".join(CORE_TABLES)))
    return problems
