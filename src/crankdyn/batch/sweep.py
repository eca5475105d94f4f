"""``crankdyn sweep SCENE --set engine.bore=76mm:88mm:4 --set engine.rod_ratio=0.25,0.3``: a design study.

Every combination of the swept fields' values (the Cartesian product, the first field varying
slowest) is one variant of the batch pipeline (:func:`crankdyn.batch.execute`: local worker
processes or a Dask cluster, the same time limit and failure rows). The result is the batch's
answer key (CSV, XLSX, Parquet) with one numeric column per swept field, and optionally a plot of
one result column over the grid.

Fields are the dotted scene paths of the batch CSV header and of :func:`crankdyn.api.sweep`
(``engine.rpm``, ``cycle.max_pressure``), checked by the same rules. Values, on the command line
or in a sweep file (TOML, see :func:`read_sweep_file`):

* ``START:STOP:COUNT`` — COUNT evenly spaced values, both ends included (``2000:6000:5``);
* ``START:STOP:step=STEP`` — from START by STEP while not past STOP (``0.25:0.31:step=0.02``);
* ``A,B,C`` — these values (``0.26,0.28,0.3``); one value alone sets the field for every point.

A quantity carries its unit on either end or both (``76:88:4 mm``, ``"76 mm:88 mm:4"``); the
values are then that unit's numbers, and the key column names it (``engine.bore [mm]``).
"""

from __future__ import annotations

import collections
import importlib.util
import itertools
import math
import re
import time
import tomllib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..api import _nested_overrides
from ..errors import Problem, SceneError, UsageError
from ..output.manifest import check_outputs, write_outputs
from ..plugin.registry import Registry
from ..scene.model import merge, scene_from_dict
from .answer_key import answer_columns
from .grid_run import KeyRun, execute_key, study_once
from .sweep_plot import plot_files
from .variants import (
    MAX_FIELDS,
    MAX_VARIANTS,
    VARIANT_COLUMN,
    BatchReport,
    RunOptions,
    Variant,
    _nest,
    _registry_or_default,
    _variant_scene,
    batch_language,
    check_options,
    execute,
    key_files,
    key_warnings,
    load_base,
    parse_cell,
)

#: Points of a sweep's grid, and values of one swept field: :data:`crankdyn.batch.MAX_VARIANTS`.
#: A range's count is checked before its values are made, the grid's size before its points are.
MAX_POINTS = MAX_VARIANTS
MAX_PLOT_LINES = 12
KEY_FORMATS = ("csv", "xlsx", "parquet")
PLOT_FORMATS = ("svg", "png")
# Fields of which a scene gives exactly one: sweeping one leaves the base scene's other out.
ALTERNATIVES = {"engine.rod_ratio": "engine.rod_length", "engine.rod_length": "engine.rod_ratio"}

_NUMBER = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"
_QUANTITY = re.compile(rf"^\s*({_NUMBER})\s*(.*?)\s*$")


@dataclass
class Axis:
    """One swept field: its values as the scene gets them, and as numbers in ``unit`` for the key."""

    name: str
    values: list[Any]
    numbers: Sequence[float | None]
    unit: str = ""

    @property
    def column(self) -> str:
        """The answer-key column: the field, with its unit when it has one (``engine.bore [mm]``)."""
        return f"{self.name} [{self.unit}]" if self.unit else self.name

    def cell(self, index: int) -> str:
        number = self.numbers[index]
        return _number_text(number) if number is not None else str(self.values[index])


@dataclass
class Sweep:
    """What to sweep: the axes (in product order), the fields set for every point, the plot wanted."""

    axes: list[Axis]
    fixed: dict[str, Any] = field(default_factory=dict)
    plot_y: str | None = None
    plot_x: str | None = None

    @property
    def points(self) -> int:
        """The grid's points; any number above :data:`MAX_POINTS` stands for "too many"."""
        return grid_points(len(a.values) for a in self.axes)


# --------------------------------------------------------------------------- reading ranges


def _number_text(value: float) -> str:
    return str(int(value)) if float(value).is_integer() and abs(value) < 1e15 else f"{value:.12g}"


def _split_quantity(name: str, text: Any, what: str) -> tuple[float, str]:
    """(number, unit text) of one range end such as ``76 mm``, ``0.28`` or ``-5``."""
    if isinstance(text, bool) or not isinstance(text, (int, float, str)):
        raise SceneError(
            Problem(name, text, f"{what} must be a number, with a unit where the field has one")
        )
    if isinstance(text, (int, float)):
        return float(text), ""
    match = _QUANTITY.match(
        text.replace(",", ".", 1) if re.fullmatch(r"\s*[-+]?\d+,\d+.*", text) else text
    )
    if not match:
        raise SceneError(
            Problem(
                name,
                text,
                f"{what} must be a number, with a unit where the field has one (e.g. 76 mm)",
            )
        )
    return float(match[1]), match[2]


def _range_axis(
    name: str, start: Any, stop: Any, count: Any = None, step: Any = None, unit: str = ""
) -> Axis:
    """The values from ``start`` to ``stop``: ``count`` of them evenly spaced, or every ``step``."""
    a, unit_a = _split_quantity(name, start, "the range's start")
    b, unit_b = _split_quantity(name, stop, "the range's stop")
    units = {u for u in (unit_a, unit_b, unit) if u}
    if len(units) > 1:
        raise SceneError(
            Problem(
                name,
                f"{start}:{stop}",
                f"the range's ends must be in one unit, not {' and '.join(sorted(units))}",
            )
        )
    unit = units.pop() if units else ""
    if not (math.isfinite(a) and math.isfinite(b)):
        raise SceneError(
            Problem(name, f"{start}:{stop}", "the range's ends must be finite numbers")
        )
    if step is None:
        if isinstance(count, bool) or not isinstance(count, int) or count < 2:
            raise SceneError(
                Problem(
                    name,
                    count,
                    "the number of values must be a whole number >= 2 "
                    "(START:STOP:COUNT; for one value give it alone)",
                )
            )
        if count > MAX_POINTS:
            raise SceneError(
                Problem(name, count, f"the number of values must be at most {MAX_POINTS}")
            )
        numbers = [a + (b - a) * k / (count - 1) for k in range(count)]
    else:
        s, unit_s = _split_quantity(name, step, "the step")
        if unit_s and unit_s != unit:
            raise SceneError(
                Problem(name, step, f"the step must be in the range's unit ({unit or 'none'})")
            )
        if not (math.isfinite(s) and s != 0 and (b - a) * s >= 0):
            raise SceneError(
                Problem(name, step, f"the step must be non-zero and lead from {start} to {stop}")
            )
        steps = (b - a) / s * (1 + 1e-12) + 1e-9
        if not steps < MAX_POINTS:  # infinite too, for a step far smaller than the range
            raise SceneError(
                Problem(name, step, f"gives more than {MAX_POINTS} values; at most {MAX_POINTS}")
            )
        count = int(math.floor(steps)) + 1
        numbers = [a + s * k for k in range(count)]
    if a == b:
        raise SceneError(
            Problem(
                name,
                f"{start}:{stop}",
                "the range's start and stop are equal; give one value alone",
            )
        )
    numbers = [float(f"{x:.12g}") for x in numbers]  # 0.30000000000000004 -> 0.3
    whole = (
        all(float(x).is_integer() for x in numbers)
        and not unit
        and all(
            isinstance(v, int) or (isinstance(v, str) and re.fullmatch(r"\s*[-+]?\d+\s*", v))
            for v in (start, stop)
        )
    )
    values = [int(x) if whole else (f"{_number_text(x)} {unit}" if unit else x) for x in numbers]
    return Axis(name, values, numbers, unit)


def _list_axis(name: str, values: list[Any]) -> Axis:
    """Values listed one by one; numbers in the key when they are all numbers of one unit."""
    if not values:
        raise SceneError(Problem(name, values, "give at least one value"))
    if len(values) > MAX_POINTS:
        raise SceneError(Problem(name, f"{len(values)} values", f"at most {MAX_POINTS}"))
    if len({repr(v) for v in values}) < len(values):
        raise SceneError(Problem(name, values, "a value is listed twice"))
    parsed: list[tuple[float, str] | None] = []
    for value in values:
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            parsed.append((float(value), ""))
            continue
        match = _QUANTITY.match(value) if isinstance(value, str) else None
        parsed.append((float(match[1]), match[2]) if match else None)
    units = {p[1] for p in parsed if p is not None}
    if all(p is not None for p in parsed) and len(units) == 1:
        return Axis(name, list(values), [p[0] for p in parsed if p is not None], units.pop())
    return Axis(name, list(values), [None] * len(values))


def parse_values(name: str, text: str) -> Axis:
    """The values of ``--set NAME=TEXT``: ``START:STOP:COUNT``, ``START:STOP:step=STEP`` or ``A,B,C``."""
    text = text.strip()
    if not text:
        raise SceneError(
            Problem(name, text, "give values: START:STOP:COUNT, START:STOP:step=STEP or A,B,C")
        )
    if ":" in text and not text.startswith(("[", '"', "'")):
        parts = [p.strip() for p in text.split(":")]
        if len(parts) != 3 or not all(parts):
            raise SceneError(
                Problem(
                    name,
                    text,
                    "a range is START:STOP:COUNT or START:STOP:step=STEP "
                    "(e.g. 2000:6000:5, 76 mm:88 mm:4, 0.25:0.31:step=0.02)",
                )
            )
        start, stop, last = parts
        unit = ""
        match = re.fullmatch(rf"(step\s*=\s*)?({_NUMBER})\s*(.*)", last)
        if not match:
            raise SceneError(
                Problem(name, text, "the third part is a COUNT or step=STEP (e.g. 5 or step=500)")
            )
        if match[1]:
            return _range_axis(name, start, stop, step=f"{match[2]} {match[3]}".strip())
        count_text, unit = (
            match[2],
            match[3],
        )  # "76:88:4 mm": the unit after the count applies to both ends
        if not re.fullmatch(r"\d+", count_text):
            raise SceneError(
                Problem(name, count_text, "the number of values must be a whole number >= 2")
            )
        if len(count_text.lstrip("0")) > len(str(MAX_POINTS)):  # not read as a number at all
            raise SceneError(
                Problem(name, count_text, f"the number of values must be at most {MAX_POINTS}")
            )
        return _range_axis(name, start, stop, count=int(count_text), unit=unit)
    return _list_axis(name, [parse_cell(v) for v in _split_list(text)])


def _split_list(text: str) -> list[str]:
    """``A,B,C`` split at commas outside brackets and quotes (a value may be a TOML list)."""
    parts, depth, quote, current = [], 0, "", ""
    for char in text:
        if quote:
            quote = "" if char == quote else quote
        elif char in "\"'":
            quote = char
        elif char in "[{":
            depth += 1
        elif char in "]}":
            depth -= 1
        elif char == "," and depth == 0:
            parts.append(current)
            current = ""
            continue
        current += char
    return [p.strip() for p in [*parts, current]]


def axis_from_toml(name: str, value: Any) -> Axis:
    """One entry of a sweep file's ``[sweep]`` table: a list, a range table or a "START:STOP:COUNT" string."""
    if isinstance(value, list):
        return _list_axis(name, value)
    if isinstance(value, dict):
        unknown = sorted(set(value) - {"from", "to", "count", "step"})
        if (
            unknown
            or "from" not in value
            or "to" not in value
            or ("count" in value) == ("step" in value)
        ):
            raise SceneError(
                Problem(
                    name,
                    value,
                    "a range table is { from = ..., to = ..., count = N } or "
                    "{ from = ..., to = ..., step = ... }",
                )
            )
        return _range_axis(name, value["from"], value["to"], value.get("count"), value.get("step"))
    if isinstance(value, str):
        return parse_values(name, value)
    return _list_axis(name, [value])


def _flatten(table: dict, prefix: str = "") -> dict[str, Any]:
    """``{"engine": {"bore": ...}}`` and ``{"engine.bore": ...}`` alike as dotted names -> leaf values."""
    out: dict[str, Any] = {}
    for key, value in table.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict) and not ({"from", "to"} & set(value)):
            out.update(_flatten(value, name + "."))
        else:
            out[name] = value
    return out


def read_sweep_file(path: Path) -> Sweep:
    """A sweep file: ``[sweep]`` (fields -> values), optional ``[fixed]`` (fields set for every point)
    and ``[plot]`` (``y`` = a result column, ``x`` = a swept field)."""
    source = str(path)
    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8-sig"))
    except FileNotFoundError:
        raise SceneError(Problem("--grid", source, "file not found"), source) from None
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError, RecursionError) as exc:
        raise SceneError(
            Problem("--grid", source, f"not a readable TOML sweep file: {exc}"), source
        ) from None
    problems = [
        Problem(key, "", "unknown table; a sweep file has [sweep], [fixed] and [plot]")
        for key in data
        if key not in ("sweep", "fixed", "plot")
    ]
    plot = data.get("plot", {})
    if not isinstance(plot, dict) or set(plot) - {"x", "y"}:
        problems.append(
            Problem("plot", plot, 'a table with y = "<result column>" and optionally x = "<field>"')
        )
        plot = {}
    for table in ("sweep", "fixed"):
        if not isinstance(data.get(table, {}), dict):
            problems.append(Problem(table, data[table], "a table of dotted scene fields"))
    if problems:
        raise SceneError(problems, source)
    swept, fixed = _flatten(data.get("sweep", {})), _flatten(data.get("fixed", {}))
    check_field_count(len(swept) + len(fixed), source)
    try:
        axes = [axis_from_toml(name, value) for name, value in swept.items()]
    except SceneError as exc:
        raise SceneError(exc.problems, source) from None
    return Sweep(axes, fixed, plot.get("y"), plot.get("x"))


def check_field_count(count: int, source: str = "sweep") -> None:
    """At most :data:`~crankdyn.batch.MAX_FIELDS` swept and fixed fields, counted before any is
    read."""
    if count > MAX_FIELDS:
        raise SceneError(
            Problem("sweep", f"{count} fields", f"at most {MAX_FIELDS} swept and fixed fields"),
            source,
        )


def grid_points(sizes: Iterable[int]) -> int:
    """The product of ``sizes``, stopped once it passes :data:`MAX_POINTS` (its value then is
    only known to be larger)."""
    points = 1
    for size in sizes:
        points *= size
        if points > MAX_POINTS:
            break
    return points


# --------------------------------------------------------------------------- the grid


def check_sweep(sweep: Sweep) -> None:
    """The field names by the batch/API rules, no field twice, something swept, a bounded grid."""
    check_field_count(len(sweep.axes) + len(sweep.fixed))
    names = [a.name for a in sweep.axes]
    counts = collections.Counter(names)
    problems = [
        Problem(n, "", "swept twice") for n in sorted(n for n, k in counts.items() if k > 1)
    ]
    problems += [
        Problem(n, sweep.fixed[n], "both swept and fixed: give one or the other")
        for n in names
        if n in sweep.fixed
    ]
    if not sweep.axes:
        problems.append(
            Problem(
                "--set",
                "",
                "nothing to sweep: give a field with several values, "
                "e.g. --set engine.rpm=2000:6000:5",
            )
        )
    if sweep.points > MAX_POINTS:
        problems.append(
            Problem(
                "sweep",
                f"more than {MAX_POINTS} points",
                f"at most {MAX_POINTS} points in the grid (the product of the "
                "numbers of values of the swept fields)",
            )
        )
    if problems:
        raise SceneError(problems, "sweep")
    _nested_overrides(
        {**{a.name: a.values[0] for a in sweep.axes}, **sweep.fixed}
    )  # the batch/API name rules


def variants(sweep: Sweep) -> tuple[list[str], list[Variant]]:
    """The key's input columns and one variant per grid point, in product order (first axis slowest)."""
    width = max(2, len(str(sweep.points)))
    fixed: dict = {}
    for name, value in sweep.fixed.items():
        fixed = merge(fixed, _nest(name, value))
    out = []
    indices = itertools.product(*(range(len(a.values)) for a in sweep.axes))
    for row, combination in enumerate(indices, start=1):
        overrides = fixed
        cells = {VARIANT_COLUMN: f"p{row:0{width}d}"}
        for axis, k in zip(sweep.axes, combination, strict=True):
            overrides = merge(overrides, _nest(axis.name, axis.values[k]))
            cells[axis.column] = axis.cell(k)
        out.append(Variant(row, cells[VARIANT_COLUMN], overrides, cells))
    return [a.column for a in sweep.axes], out


def base_for(base: dict, sweep: Sweep) -> tuple[dict, list[str]]:
    """The base scene without the alternative of a swept field (``rod_length`` when λ is swept), and notes."""
    set_here = {a.name for a in sweep.axes} | set(sweep.fixed)
    notes = []
    for name in sorted(set_here):
        other = ALTERNATIVES.get(name)
        if other and other not in set_here:
            table, key = other.split(".")
            if key in base.get(table, {}):
                base = {**base, table: {k: v for k, v in base[table].items() if k != key}}
                notes.append(f"{other} of the base scene is left out: the sweep sets {name}")
    return base, notes


def value_problems(
    base: dict, base_dir: str, sweep: Sweep, data_dirs: tuple[str, ...]
) -> list[Problem]:
    """Each value of each swept field tried against the base scene: a value the scene refuses whatever
    the other fields are is refused before anything runs.

    A value is tried with the other swept fields at their first values and, if that fails on the
    field itself, at their last values too (a rod length too short for the first stroke may suit
    the last); it is refused when both fail. Problems of the base scene itself are reported too.
    Combinations that are bad only together run, and fail as rows of failures.csv.
    """
    problems: dict[str, Problem] = {}
    first = {a.name: a.values[0] for a in sweep.axes}
    last = {a.name: a.values[-1] for a in sweep.axes}
    for axis in sweep.axes:
        for value in axis.values:
            found = _scene_problems(
                base, base_dir, {**sweep.fixed, **first, axis.name: value}, data_dirs
            )
            own = [p for p in found if p.field == axis.name]
            if own:
                again = _scene_problems(
                    base, base_dir, {**sweep.fixed, **last, axis.name: value}, data_dirs
                )
                own = [p for p in own if str(p) in {str(q) for q in again}]
            for problem in own + [p for p in found if p.field not in first]:
                problems.setdefault(str(problem), problem)
    return _merged(list(problems.values()))


class _Values(tuple):
    """Several values of one field with the same problem, shown as a list: ``76, 80, 84``."""

    def __repr__(self) -> str:
        return ", ".join(repr(value) for value in self)


def _merged(problems: list[Problem]) -> list[Problem]:
    """One problem per field and reason, naming every value that has it (a unit missing from a
    range is one mistake, however many values the range has)."""
    values: dict[tuple[str, str], list[Any]] = {}
    for problem in problems:
        values.setdefault((problem.field, problem.allowed), []).append(problem.value)
    return [
        Problem(name, found[0] if len(found) == 1 else _Values(found), allowed)
        for (name, allowed), found in values.items()
    ]


def _scene_problems(
    base: dict, base_dir: str, values: dict[str, Any], data_dirs: tuple[str, ...]
) -> list[Problem]:
    overrides: dict = {}
    for name, value in values.items():
        overrides = merge(overrides, _nest(name, value))
    try:
        scene_from_dict(
            merge(base, overrides), base_dir=base_dir, source="sweep", data_dirs=data_dirs
        )
    except SceneError as exc:
        return list(exc.problems)
    return []


# --------------------------------------------------------------------------- running it


@dataclass
class SweepRequest:
    """A sweep as the command line gives it."""

    scene: Path
    sweep: Sweep
    out_dir: Path
    options: RunOptions
    key_formats: list[str] = field(default_factory=lambda: ["csv", "xlsx"])
    plot_formats: list[str] = field(default_factory=lambda: ["svg"])


def check_request(request: SweepRequest, registry: Registry | None = None) -> None:
    """Everything about the request that can be wrong before a point runs (exit 2, nothing written);
    ``registry``: the run's plugins (by default the installed ones)."""
    sweep = request.sweep
    check_sweep(sweep)
    check_options(request.options)
    bad = [f for f in request.key_formats if f not in KEY_FORMATS]
    if bad or not request.key_formats:
        raise UsageError(
            f"unknown --key {','.join(bad) or '(none)'}; allowed: a subset of {','.join(KEY_FORMATS)}"
        )
    bad = [f for f in request.plot_formats if f not in PLOT_FORMATS]
    if bad or not request.plot_formats:
        raise UsageError(
            f"unknown --plot-format {','.join(bad)}; allowed: a subset of {','.join(PLOT_FORMATS)}"
        )
    if "parquet" in request.key_formats:
        if importlib.util.find_spec("pyarrow") is None:
            raise UsageError(
                "--key parquet needs pyarrow; install it with: pip install 'crankdyn[parquet]'"
            )
    if sweep.plot_y is not None:
        columns = [c.name for c in answer_columns(_registry_or_default(registry))]
        if sweep.plot_y not in columns:
            raise SceneError(
                Problem(
                    "--plot",
                    sweep.plot_y,
                    "a result column of the answer key: " + ", ".join(columns),
                )
            )
        names = [a.name for a in sweep.axes]
        if sweep.plot_x is not None and sweep.plot_x not in names:
            raise SceneError(
                Problem("--plot-x", sweep.plot_x, "a swept field: " + ", ".join(names))
            )
        lines = math.prod(len(a.values) for a in sweep.axes if a.name != (sweep.plot_x or names[0]))
        if lines > MAX_PLOT_LINES:
            raise SceneError(
                Problem(
                    "--plot",
                    sweep.plot_y,
                    f"would draw {lines} lines (one per combination of "
                    f"the other swept fields); at most {MAX_PLOT_LINES}: sweep fewer values, "
                    "or leave --plot out and plot the answer key yourself",
                )
            )


def run_sweep(
    request: SweepRequest, registry: Registry | None = None
) -> tuple[BatchReport, list[str]]:
    """Run the grid; write the answer key, the failures and the plot into ``out_dir``. Returns the
    batch report and notes for the user (a field left out of the base, a plot with no values).
    ``registry``: the plugins the points are computed with (by default the installed ones)."""
    start = time.perf_counter()
    run = KeyRun(registry)
    check_request(request, run.registry)
    base, base_dir = load_base(request.scene)
    base, notes = base_for(base, request.sweep)
    data_dirs = tuple(str(Path(d).resolve()) for d in request.options.data_dirs)
    problems = value_problems(base, base_dir, request.sweep, data_dirs)
    if problems:
        raise SceneError(problems, "sweep")
    fields, points = variants(request.sweep)
    key_names = [f"answer_key.{f}" for f in request.key_formats] + ["failures.csv"]
    check_outputs(Path(request.out_dir), key_names, force=request.options.force)  # before computing
    if request.options.formats:  # files of each point: each point runs the whole report
        outcomes, stop_signal = execute(
            points, base, base_dir, request.out_dir, request.options, run
        )
    else:  # the answer key only: chunks of points, the studies once (crankdyn.grid_run)
        notes += base_studies(base, base_dir, request.options, run.registry)
        outcomes, stop_signal = execute_key(points, base, base_dir, request.options, run)
    language = batch_language(base, request.options)
    files = key_files(fields, outcomes, points, request.key_formats, language, notes, run.registry)
    if request.sweep.plot_y is not None:
        plotted, note = plot_files(request.sweep, outcomes, request.plot_formats, run.registry)
        files.update(plotted)
        notes += [note] if note else []
    written = write_outputs(Path(request.out_dir), files, force=request.options.force)
    seconds = time.perf_counter() - start
    return (
        BatchReport(
            Path(request.out_dir),
            outcomes,
            seconds,
            written,
            bool(stop_signal),
            key_warnings(outcomes, run.registry),
            stop_signal,
        ),
        notes,
    )


def base_studies(
    base: dict, base_dir: str, options: RunOptions, registry: Registry | None = None
) -> list[str]:
    """The studies of the base scene's plan (the error against run time), run once for the sweep
    rather than per point; the notes saying so. A base scene that is not valid alone (the sweep
    supplies a field it lacks) has its studies left out, with a note."""
    variant = Variant(0, "base", {}, {VARIANT_COLUMN: "base"})
    data_dirs = tuple(str(Path(d).resolve()) for d in options.data_dirs)
    try:
        registry = _registry_or_default(registry)
        scene = _variant_scene(base, base_dir, variant, options.language, data_dirs, registry)
    except SceneError as exc:
        return [
            f"the studies (error against run time) did not run: the base scene alone is not "
            f"valid ({'; '.join(str(p) for p in exc.problems)})"
        ]
    return study_once(scene, registry, options.stages)


def sweep_from_args(
    sets: Iterable[str], grid: Path | None, plot_y: str | None, plot_x: str | None
) -> Sweep:
    """The sweep of ``--grid FILE`` with ``--set NAME=VALUES`` laid over it (a --set replaces the file's field)."""
    sweep = read_sweep_file(grid) if grid else Sweep([])
    sets = list(sets)
    names = {text.partition("=")[0].strip() for text in sets}
    names |= {a.name for a in sweep.axes} | set(sweep.fixed)
    check_field_count(len(names))  # before any --set's values are read
    for text in sets:
        name, equals, values = text.partition("=")
        name = name.strip()
        if not equals or not name:
            raise SceneError(
                Problem(
                    "--set",
                    text,
                    "NAME=VALUES, e.g. engine.rpm=2000:6000:5 or engine.rod_ratio=0.26,0.28,0.3",
                )
            )
        axis = parse_values(name, values)
        sweep.axes = [a for a in sweep.axes if a.name != name]
        sweep.fixed.pop(name, None)
        if len(axis.values) == 1:
            sweep.fixed[name] = axis.values[0]
        else:
            sweep.axes.append(axis)
    sweep.plot_y = plot_y or sweep.plot_y
    sweep.plot_x = plot_x or sweep.plot_x
    return sweep
