"""Checks of a scene's raw TOML data before the model sees it.

Nesting depth (a scene of deeply nested arrays must be refused, not crash the
validator), control characters in text (they would reach the HTML raw), the sizes a
value may have (text length, array length, integers within TOML's 64 bits, no subnormal
floats) and misspelt names of the core tables ("did you mean [engine]?").
"""

from __future__ import annotations

import difflib
import re
import sys
from typing import Any

from ..errors import Problem

MAX_DEPTH = 16
#: Characters in one text value (a title, a name, a file name): a title page holds far less, and
#: a text of megabytes would make the page layout run for minutes.
MAX_TEXT_LENGTH = 1000
#: A nonzero number below the smallest normal float (2.2e-308) is subnormal: its square is 0.
TOO_CLOSE_TO_ZERO = (
    f"is too close to zero to compute with (below {sys.float_info.min:.3g}); "
    "give 0 or a value of a physical size"
)
#: Characters in one key (the longest name of the scene's tables has 30).
MAX_KEY_LENGTH = 100
#: Items in one array (firing orders, crank angles, lists of steps hold a few dozen), and keys
#: in one table.
MAX_ARRAY_LENGTH = 10_000
#: TOML integers are 64-bit signed; a longer one cannot be computed with as a float either.
MIN_INTEGER, MAX_INTEGER = -(2**63), 2**63 - 1
# C0 controls except none, DEL and the C1 controls: nothing a scene's text needs.
_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")
CORE_TABLES = ("report", "engine", "masses", "cycle", "analysis", "mechanism")


class UnderflowedFloat(float):
    """A TOML float whose text is not zero but whose value underflows to 0.0 (``1e-400``)."""

    text: str

    def __new__(cls, text: str):
        value = super().__new__(cls, 0.0)
        value.text = text
        return value


def toml_float(text: str) -> float:
    """``parse_float`` of :func:`tomllib.loads`: a float, marked when a nonzero text underflows
    to 0."""
    value = float(text)
    if value == 0.0 and re.search(r"[1-9]", text.lower().split("e")[0]):
        return UnderflowedFloat(text)
    return value


def structure_problems(data: Any) -> list[Problem]:
    """Too-deep nesting, control characters and oversized values anywhere in ``data``, each
    naming its dotted path."""
    problems: list[Problem] = []
    stack: list[tuple[str, Any, int]] = [("", data, 0)]
    while stack:  # iterative, so no depth can exhaust the interpreter's stack
        path, value, depth = stack.pop()
        if depth > MAX_DEPTH:
            problems.append(
                Problem(
                    path or "scene",
                    "(nested too deeply)",
                    f"tables and arrays may be nested at most {MAX_DEPTH} levels deep",
                )
            )
            continue
        if isinstance(value, dict):
            if len(value) > MAX_ARRAY_LENGTH:
                problems.append(
                    Problem(
                        path or "scene",
                        f"(a table of {len(value)} keys)",
                        f"a table may hold at most {MAX_ARRAY_LENGTH} keys",
                    )
                )
                continue
            for key, item in value.items():
                if len(str(key)) > MAX_KEY_LENGTH:
                    cut = str(key)[: MAX_KEY_LENGTH // 2] + "..."
                    allowed = f"a key may be at most {MAX_KEY_LENGTH} characters long"
                    problems.append(
                        Problem(
                            f"{path}.{cut}" if path else cut,
                            f"(a key of {len(str(key))} characters)",
                            allowed,
                        )
                    )
                    continue
                child = f"{path}.{key}" if path else str(key)
                if _CONTROL.search(str(key)):
                    problems.append(
                        Problem(child, str(key), "a key may not contain control characters")
                    )
                stack.append((child, item, depth + 1))
        elif isinstance(value, (list, tuple, set, frozenset)):  # the API may be given any of them
            if len(value) > MAX_ARRAY_LENGTH:
                problems.append(
                    Problem(
                        path or "scene",
                        f"(an array of {len(value)} items)",
                        f"an array may hold at most {MAX_ARRAY_LENGTH} items",
                    )
                )
                continue
            stack.extend((f"{path}.{k}", item, depth + 1) for k, item in enumerate(value))
        else:
            problem = value_problem(path or "scene", value)
            if problem is not None:
                problems.append(problem)
    return sorted(problems, key=lambda p: p.field)


def value_problem(path: str, value: Any) -> Problem | None:
    """Why one plain value (text, integer, float) may not stand in a scene, or None."""
    if isinstance(value, (bytes, bytearray)) and len(value) > MAX_TEXT_LENGTH:  # read as text
        return Problem(
            path,
            value,
            f"text may be at most {MAX_TEXT_LENGTH} characters long (it has {len(value)})",
        )
    if isinstance(value, str):
        if len(value) > MAX_TEXT_LENGTH:
            return Problem(
                path,
                value,
                f"text may be at most {MAX_TEXT_LENGTH} characters long (it has {len(value)})",
            )
        if _CONTROL.search(value):
            return Problem(
                path,
                value,
                "text may not contain control characters (tabs, line "
                "breaks, escape codes); write it on one line",
            )
    elif isinstance(value, int) and not isinstance(value, bool):
        if not MIN_INTEGER <= value <= MAX_INTEGER:
            return Problem(
                path,
                _LongInteger(value),
                f"an integer must lie between {MIN_INTEGER} "
                f"and {MAX_INTEGER} (64 bits, as TOML defines integers)",
            )
    elif isinstance(value, UnderflowedFloat):
        return Problem(path, value.text, TOO_CLOSE_TO_ZERO)
    elif isinstance(value, float) and value != 0.0 and abs(value) < sys.float_info.min:
        return Problem(path, value, TOO_CLOSE_TO_ZERO)
    return None


class _LongInteger:
    """A huge integer shown in a message by its leading digits and its length (Python refuses to
    turn an integer of more than 4300 digits into text)."""

    def __init__(self, value: int):
        digits = max(1, int(value.bit_length() * 0.30102999566398120))
        if 10**digits <= abs(value):
            digits += 1
        self.digits = digits
        self.leading = abs(value) // 10 ** max(0, digits - 20)
        self.sign = "-" if value < 0 else ""

    def __repr__(self) -> str:
        if self.digits <= 20:
            return f"{self.sign}{self.leading}"
        return f"{self.sign}{self.leading}... ({self.digits} digits)"


def table_problems(
    data: dict, plugin_tables: set[str] | frozenset[str] = frozenset()
) -> list[Problem]:
    """Top-level tables whose name is close to a missing core table: "did you mean [engine]?"."""
    problems = []
    for name in data:
        if name in CORE_TABLES or name in plugin_tables or not isinstance(data[name], dict):
            continue
        missing = [t for t in CORE_TABLES if t not in data]
        close = difflib.get_close_matches(name, missing, n=1, cutoff=0.75)
        if close:
            problems.append(
                Problem(
                    name,
                    f"[{name}]",
                    f"unknown table; did you mean [{close[0]}]? "
                    "core tables: " + ", ".join(CORE_TABLES),
                )
            )
    return problems
