"""The Python API for scripts and notebooks (re-exported at the package top level).

>>> import crankdyn
>>> scene = crankdyn.load("examples/petrol-1cyl.toml", {"engine.rpm": 3000})   # doctest: +SKIP
>>> result = crankdyn.run(scene)                                               # doctest: +SKIP
>>> result.values["kinematics.v_max_m_s"]                                      # doctest: +SKIP

* :func:`load` reads a scene file (or a dict of the same tables) and lays overrides over it,
  named with the dotted paths of the batch CSV columns (``engine.rpm``, ``cycle.max_pressure``);
  every problem raises :class:`~crankdyn.errors.SceneError` at once, nothing is printed.
* :func:`run` computes a scene and returns a :class:`Result`: ``tables`` (pandas DataFrames,
  units in the column names), ``values`` (scalar results, units in the names), ``figures``
  (matplotlib Figures, rendered on first access), :meth:`Result.write` (the files of
  ``crankdyn report``), :meth:`Result.section` (one report section as HTML) and a compact
  summary when a notebook displays the result.
* :func:`sweep` runs a grid of overrides and returns the batch command's answer-key columns.

See docs/api.md for a worked example.
"""

from __future__ import annotations

import html
import itertools
import re
import weakref
from collections.abc import Iterable, Mapping
from functools import cached_property, lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from markupsafe import Markup

from .batch import answer_key
from .batch.grid_run import CHUNK_POINTS, evaluate, number, study_once
from .batch.variants import MAX_FIELDS, MAX_VARIANTS, _nest, answers
from .engine.orchestrator import RunResult, check_scene, run_scene
from .errors import Problem, SceneError
from .output.manifest import write_outputs
from .output.pipeline import render_files
from .output.writers import FORMATS, _named_tables, results_document
from .plugin.registry import default_registry
from .report.context import RenderContext
from .report.figures import STYLE, tight_layout
from .report.i18n import available_languages, translator
from .scene.inputcheck import structure_problems
from .scene.model import Scene, merge, read_scene_data, scene_from_dict

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

__all__ = ["load", "run", "sweep", "Result", "SceneError"]

#: Stage names one run may ask for (far more than are installed; an endless iterator stops here).
MAX_STAGE_NAMES = 1000

# The input each scene was loaded from (raw TOML-level data, base folder), so that a loaded
# scene can be loaded again with other overrides (sweep). Keyed by id, dropped with the scene.
_SOURCES: dict[int, tuple[weakref.ref, dict, str]] = {}


@lru_cache(maxsize=1)
def _registry():
    return default_registry()


def _languages() -> list[str]:
    return available_languages()


# --------------------------------------------------------------------------- loading


def _source_data(source: Any) -> tuple[dict, str, str]:
    """(raw data, base folder, name for messages) of a path, a dict or a scene from :func:`load`."""
    if isinstance(source, Scene):
        entry = _SOURCES.get(id(source))
        if entry is None or entry[0]() is not source:
            raise TypeError(
                "pass a scene made by crankdyn.load (or a path or dict) to lay overrides over it"
            )
        return entry[1], entry[2], "scene"
    if isinstance(source, Mapping):
        return dict(source), str(Path.cwd()), "scene"
    if isinstance(source, (str, Path)):
        path = Path(source)
        return read_scene_data(path), str(path.parent.resolve()), str(path)
    raise TypeError(
        f"expected a scene file path, a dict or a scene from crankdyn.load, not {type(source).__name__}"
    )


def _checked(data: Any, source: str) -> None:
    """Refuse nesting, sizes and text a scene may not hold before anything walks ``data``
    recursively (a dict nested thousands deep, or holding itself, would exhaust the stack)."""
    problems = structure_problems(data)
    if problems:
        raise SceneError(problems, source)


def _nested_overrides(overrides: Mapping[str, Any]) -> dict:
    """Dotted names (``engine.rpm``, or ``engine__rpm`` as a keyword) as the nested dict batch lays over a scene.

    The names follow the batch CSV header rules; a bad name is a problem like a bad value.
    """
    problems: list[Problem] = []
    names = {str(k).replace("__", "."): v for k, v in overrides.items()}
    for name in names:
        if any(not part for part in name.split(".")) or not re.fullmatch(r"[A-Za-z_][\w.]*", name):
            problems.append(
                Problem(
                    name,
                    names[name],
                    "not a dotted scene path such as engine.bore or "
                    "cycle.rounding.ignition_advance_deg",
                )
            )
        for other in names:
            if other.startswith(name + "."):
                problems.append(
                    Problem(
                        other,
                        names[other],
                        f"conflicts with override {name}: give one or the other",
                    )
                )
    if problems:
        raise SceneError(problems, "overrides")
    nested: dict = {}
    for name, value in names.items():
        nested = merge(nested, _nest(name, value))
    return nested


def _without_none(data: dict) -> dict:
    """``data`` without the keys an override set to None (None removes a key, e.g. ``engine.rod_length``)."""
    return {
        k: _without_none(v) if isinstance(v, dict) else v for k, v in data.items() if v is not None
    }


def load(
    source: str | Path | Mapping | Scene, overrides: Mapping[str, Any] | None = None, /, **more: Any
) -> Scene:
    """Load and validate a scene; lay ``overrides`` over it first.

    ``source`` is a TOML scene file, a dict of the same tables, or a scene returned by
    :func:`load`. ``overrides`` map dotted scene paths to values, exactly as the columns of a
    batch CSV: ``{"engine.rpm": 3000, "engine.bore": "84 mm"}``; keywords work too, with
    ``__`` for the dot (``engine__rpm=3000``). Values are Python values as TOML would give them
    (``3000``, ``"84 mm"``, ``[1, 3, 4, 2]``); None removes the key (to give ``engine.rod_ratio``
    in place of a scene's ``engine.rod_length``, override both).
    Every problem (unknown key, value out of range, unknown mechanism or stage) raises one
    :class:`SceneError` listing them all; nothing is printed.
    """
    if overrides is not None and not isinstance(overrides, Mapping):
        raise TypeError(
            f"overrides must be a mapping of dotted scene paths to values, not "
            f"{type(overrides).__name__}"
        )
    data, base_dir, name = _source_data(source)
    _checked(data, name)
    changes = {**(overrides or {}), **more}
    if changes:
        _checked({str(k): v for k, v in changes.items()}, "overrides")
        data = _without_none(merge(data, _nested_overrides(changes)))
    registry = _registry()
    scene = scene_from_dict(data, base_dir=base_dir, source=name, registry=registry)
    try:
        check_scene(scene, registry, _languages())
    except SceneError as exc:
        raise SceneError(exc.problems, name) from None
    key = id(scene)
    _SOURCES[key] = (weakref.ref(scene, lambda _ref: _SOURCES.pop(key, None)), data, base_dir)
    return scene


def run(scene: Scene | str | Path | Mapping, stages: Iterable[str] | None = None) -> Result:
    """Compute ``scene`` (a scene, or anything :func:`load` takes) and return its :class:`Result`.

    ``stages`` names the stages wanted (their prerequisites are added), as ``--stages`` does;
    by default the scene's ``analysis.stages`` or every default stage that applies.
    """
    stages = _stage_names(stages)
    if not isinstance(scene, Scene):
        scene = load(scene)
    return Result(run_scene(scene, _registry(), stages, _languages()))


def _stage_names(stages: Iterable[str] | str | None) -> list[str] | None:
    """``stages`` as a list of names: a string is one name (never its letters); TypeError for
    anything that is not a name or an iterable of names."""
    if stages is None:
        return None
    if isinstance(stages, str):
        return [stages]
    if isinstance(stages, Mapping) or not isinstance(stages, Iterable):
        raise TypeError(
            f"stages must be a stage name or a list of stage names, not {type(stages).__name__}"
        )
    names = list(itertools.islice(stages, MAX_STAGE_NAMES + 1))
    if len(names) > MAX_STAGE_NAMES:
        raise SceneError(
            Problem(
                "stages",
                f"(more than {MAX_STAGE_NAMES} names)",
                f"at most {MAX_STAGE_NAMES} stage names",
            )
        )
    wrong = [n for n in names if not isinstance(n, str)]
    if wrong:
        raise TypeError(
            f"stages must be stage names (strings), not {type(wrong[0]).__name__}: {wrong[0]!r}"
        )
    return names


def sweep(
    scene: Scene | str | Path | Mapping,
    grid: Mapping[str, Iterable[Any]],
    stages: Iterable[str] | None = None,
) -> pd.DataFrame:
    """Run every combination of ``grid`` (dotted name -> values) and return the answer key.

    The combinations are computed as ``crankdyn sweep`` computes them: in chunks, only the stages
    whose answer-key columns they fill, a stage's ``run_many`` over many points at once; the
    studies (the error against run time) run once, for ``scene``, and
    ``frame.attrs["notes"]`` says so.

    One row per combination, in the order of :func:`itertools.product` over the grid (the
    first name varies slowest): the grid's own columns, then the answer-key columns of
    ``crankdyn batch`` (units in the names; columns no run has are left out, as there).
    The grid has at most :data:`~crankdyn.batch.MAX_FIELDS` names and
    :data:`~crankdyn.batch.MAX_VARIANTS` combinations, as ``crankdyn sweep``; a larger one raises
    :class:`SceneError` before anything runs.
    """
    import pandas as pd  # lazy: heavy optional import (pandas: only for a sweep's table)

    names, values = _grid_values(grid)
    stages = _stage_names(stages)
    key_columns = answer_key.answer_columns(_registry())  # the same columns as the batch answer key
    combinations = list(itertools.product(*values))
    rows = []
    for start in range(0, len(combinations), CHUNK_POINTS):  # the points at array speed, in chunks
        part = combinations[start : start + CHUNK_POINTS]
        scenes = [load(scene, dict(zip(names, combination, strict=True))) for combination in part]
        for combination, point, (run_names, results, error) in zip(
            part, scenes, evaluate(scenes, _registry(), stages, _languages()), strict=True
        ):
            if error:  # the point's own exception, as a run of it alone raises it
                run_scene(point, _registry(), stages, _languages())
                raise SceneError(Problem("sweep", str(combination), error), "sweep")
            document = {"stages_run": run_names, **results}
            answered = answer_key.answers(document, key_columns).values()
            rows.append([*combination, *(number(v) for v in answered)])
    answer_names = [c.name for c in key_columns]
    frame = pd.DataFrame(rows, columns=[*names, *answer_names])
    empty = [c for c in answer_names if frame[c].isna().all()]
    frame = frame.drop(columns=empty)
    frame.attrs["notes"] = _studies(scene, stages) if combinations else []
    return frame


def _studies(scene: Scene | str | Path | Mapping, stages: list[str] | None) -> list[str]:
    """The studies of the sweep's base ``scene`` run once: the notes saying so."""
    try:
        base = load(scene)
    except SceneError as exc:
        return [
            f"the studies (error against run time) did not run: the base scene alone is not "
            f"valid ({'; '.join(str(p) for p in exc.problems)})"
        ]
    return study_once(base, _registry(), stages)


def _grid_values(grid: Mapping[str, Iterable[Any]]) -> tuple[list[str], list[list[Any]]]:
    """The names of ``grid`` and the values of each, within the limits of ``crankdyn sweep``.

    The numbers of names and of combinations are checked from ``len()`` before any values are
    listed (``range(1, 10**9)`` is refused as it is); an iterator is read up to one value past the
    limit. A string or a mapping as a field's values is a TypeError, not a list of characters or
    keys.
    """
    if not isinstance(grid, Mapping):
        raise TypeError(
            f"grid must map dotted scene fields to lists of values, not {type(grid).__name__}"
        )
    if len(grid) > MAX_FIELDS:
        raise SceneError(
            Problem("grid", f"{len(grid)} fields", f"at most {MAX_FIELDS} fields"), "sweep"
        )
    names = list(grid)
    for name in names:
        given = grid[name]
        if isinstance(given, (str, bytes, Mapping)) or not isinstance(given, Iterable):
            raise TypeError(
                f"grid[{name!r}] must be a list of values, not {type(given).__name__} "
                f"(one value is a list of one: [{given!r}])"
            )
    _check_points({name: _size(grid[name]) for name in names})
    values = [list(itertools.islice(grid[name], MAX_VARIANTS + 1)) for name in names]
    _check_points(dict(zip(names, map(len, values), strict=True)))
    return names, values


def _size(values: Iterable[Any]) -> int | None:
    """``len(values)`` without listing them: None for an iterator, beyond the limit if too large."""
    try:
        return len(values)  # type: ignore[arg-type]
    except OverflowError:  # range(10**30): more than an index can count
        return MAX_VARIANTS + 1
    except TypeError:
        return None


def _check_points(sizes: dict[str, int | None]) -> None:
    """At most MAX_VARIANTS values per field and combinations in all (None: a size not known)."""
    problems = [
        Problem(name, f"{size} values", f"at most {MAX_VARIANTS} values")
        for name, size in sizes.items()
        if size is not None and size > MAX_VARIANTS
    ]
    if not problems:
        points = 1
        for size in sizes.values():
            points *= size if size is not None else 1
            if points > MAX_VARIANTS:
                problems.append(
                    Problem(
                        "grid",
                        f"more than {MAX_VARIANTS} combinations",
                        f"at most {MAX_VARIANTS} (the product of the numbers of values)",
                    )
                )
                break
    if problems:
        raise SceneError(problems, "sweep")


# --------------------------------------------------------------------------- the result

# Unit suffixes of result names (longest first), for display.
_UNITS = (
    ("_kg_m2", "kg·m²"),
    ("_m_s2", "m/s²"),
    ("_rad_s2", "rad/s²"),
    ("_rad_s", "rad/s"),
    ("_m_s", "m/s"),
    ("_Nm", "N·m"),
    ("_MPa", "MPa"),
    ("_kPa", "kPa"),
    ("_Pa", "Pa"),
    ("_kW", "kW"),
    ("_W", "W"),
    ("_kN", "kN"),
    ("_N", "N"),
    ("_J", "J"),
    ("_deg", "°"),
    ("_rad", "rad"),
    ("_kg", "kg"),
    ("_mm", "mm"),
    ("_m2", "m²"),
    ("_m3", "m³"),
    ("_m", "m"),
    ("_ms", "ms"),
    ("_s", "s"),
    ("_Hz", "Hz"),
    ("_rpm", "rpm"),
    ("_percent", "%"),
)


def unit_of(name: str) -> str:
    """The unit a result name states in its suffix (``v_max_m_s`` -> ``m/s``); "" if none."""
    for suffix, unit in _UNITS:
        if name.endswith(suffix):
            return unit
    return ""


def _release(fig) -> None:
    """Lay a report figure out as the report does and drop it from pyplot's list (the object stays usable)."""
    import matplotlib.pyplot as plt  # lazy: heavy optional import (matplotlib: only when figures are released)

    with plt.rc_context(STYLE):
        tight_layout(fig)
    plt.close(fig)


class _LazyFigures(Mapping):
    """``result.figures``: matplotlib Figures by name, rendered on first access."""

    def __init__(self, result: Result):
        self._result = result
        self._figures: dict | None = None

    def _load(self) -> dict:
        if self._figures is None:
            self._figures = self._result._render(figures_only=True)[1]
        return self._figures

    def __getitem__(self, name: str):
        return self._load()[name]

    def __iter__(self):
        return iter(self._load())

    def __len__(self) -> int:
        return len(self._load())


class SectionHTML(str):
    """One rendered report section; shows as HTML in a notebook."""

    def _repr_html_(self) -> str:
        return str(self)


class Result:
    """What :func:`run` returns: the computed scene, its tables, values, figures and report."""

    def __init__(self, run_result: RunResult):
        self.run_result = run_result
        self.scene = run_result.scene
        self.figures: Mapping[str, Any] = _LazyFigures(self)

    @property
    def stages_run(self) -> list[str]:
        return self.run_result.stages_run

    @property
    def skipped(self) -> dict[str, str]:
        """Stages left out, with the reason (as in results.json and the report)."""
        return dict(self.run_result.plan.skipped)

    @cached_property
    def document(self) -> dict[str, Any]:
        """The results.json document of this run."""
        return results_document(self.run_result)

    @cached_property
    def tables(self) -> dict[str, pd.DataFrame]:
        """Every table by the name of its CSV file (``kinematics``, ``forces_bays``...); units in the column names."""
        return {name: frame.copy() for name, frame in _named_tables(self.run_result)}

    @cached_property
    def values(self) -> dict[str, float]:
        """Scalar results as ``"<stage>.<name>"`` -> number; the unit is the name's suffix (see :func:`unit_of`)."""
        out: dict[str, float] = {}
        for stage in self.stages_run:
            for key, value in (self.document.get(stage) or {}).items():
                if isinstance(value, (int, float)) and not isinstance(value, bool):
                    out[f"{stage}.{key}"] = value
        return out

    @cached_property
    def answers(self) -> dict[str, Any]:
        """The main results, as the batch answer key has them (units in the names)."""
        return answers(self.document)

    def write(
        self,
        out_dir: str | Path,
        formats: Iterable[str] = ("html", "pdf", "json", "csv"),
        *,
        force: bool = False,
    ) -> list[Path]:
        """Write the files ``crankdyn report`` writes (same pipeline, nothing recomputed); return their paths.

        As the command line, it replaces only files crankdyn wrote there and left unchanged; a file in
        the way raises :class:`crankdyn.errors.OutputError` unless ``force`` is true."""
        formats = [formats] if isinstance(formats, str) else list(formats)  # a string is one format
        bad = [f for f in formats if f not in FORMATS]
        if bad or not formats:
            raise SceneError(
                Problem("formats", formats, "a non-empty subset of " + ", ".join(FORMATS))
            )
        return write_outputs(
            Path(out_dir), render_files(self.run_result, _registry(), formats), force=force
        )

    # ----------------------------------------------------------------- report sections
    def _render(
        self, figures_only: bool = False, language: str | None = None, only: str | None = None
    ) -> tuple[dict[str, SectionHTML], dict[str, Any]]:
        """Render the sections as the report numbers them; return their HTML and the Figures drawn."""
        from .report.document import (  # lazy: heavy optional import (jinja2: only when a section is rendered)
            _environment,
            text_variant,
        )

        registry = _registry()
        language = language or self.scene.report.language
        if language not in _languages():
            raise SceneError(Problem("language", language, "allowed: " + ", ".join(_languages())))
        figures: dict[str, Any] = {}

        class Capture(RenderContext):
            def figure(
                self,
                fig,
                caption: str,
                name: str,
                see: str | None = None,
                see_params: dict | None = None,
            ) -> Markup:
                self.check_figure_declared(name)  # also for the sections not shown
                key = name if name not in figures else f"{self.stage_name}.{name}"
                if callable(fig):  # given as the function that builds it: the API hands out Figures
                    fig = fig()
                figures[key] = fig
                if figures_only or (only is not None and self.stage_name != only):
                    self._figure += 1
                    _release(fig)
                    return Markup("")
                return super().figure(fig, caption, name, see, see_params)

        scene = self.scene
        t = translator(language, registry.catalogs, text_variant(scene))
        ctx = Capture(
            t=t,
            env=_environment(registry, self.run_result),
            table_step_deg=scene.analysis.table_step_deg,  # type: ignore[arg-type]  # the scene set it
            cycle_deg=scene.engine.cycle_deg,
            scene=scene,
        )
        sections: dict[str, SectionHTML] = {}
        number = 1  # section 1 is the input data
        for stage in self.run_result.plan.order:
            look = stage.presentation
            if look is None:  # a stage without a section takes no number
                continue
            ctx.start_section(number + 1, stage.name, look.figures)
            ctx.conclusions = []
            if only is not None and stage.name != only:
                # Still counted: a stage that shows nothing takes no number, as in the report.
                if look.render(self.run_result.outputs[stage.name], ctx) is not None:
                    number += 1
                continue
            body = look.render(self.run_result.outputs[stage.name], ctx)
            if body is None:
                continue
            number += 1
            title = html.escape(f"{number}. {t(look.title_key)}")
            sections[stage.name] = SectionHTML(
                f'<section class="crankdyn-section"><h2>{title}</h2>{body}</section>'
            )
        return sections, figures

    def section(self, name: str, language: str | None = None) -> SectionHTML:
        """Section ``name`` (a stage name) rendered with the report's own templates, in ``language``
        (default: the scene's ``report.language``), numbered as in the report."""
        if name not in self.stages_run:
            raise KeyError(
                f"no section {name!r}; sections of this run: {', '.join(self.stages_run)}"
            )
        sections, _ = self._render(language=language, only=name)
        if name not in sections:
            raise KeyError(
                f"stage {name!r} ran for its data only and has no section for this scene"
            )
        return sections[name]

    # ----------------------------------------------------------------- display
    def _repr_html_(self) -> str:
        t = translator(self.scene.report.language, _registry().catalogs)
        esc = html.escape
        rows = "".join(
            f"<tr><td>{esc(name)}</td><td style='text-align:right'>{value:.6g}</td>"
            f"<td>{esc(unit_of(name))}</td></tr>"
            for name, value in self.answers.items()
            if value is not None
        )
        parts = [
            f"<div class='crankdyn-result'><b>{esc(self.scene.report.title)}</b>",
            f"<p>{esc(str(self.scene.engine.mechanism))} · {esc(', '.join(self.stages_run))}</p>",
        ]
        if rows:
            parts.append(f"<table>{rows}</table>")
        if self.skipped:
            items = "".join(f"<li><b>{esc(n)}</b>: {esc(r)}</li>" for n, r in self.skipped.items())
            parts.append(f"<p>{esc(t('report.skipped_intro'))}</p><ul>{items}</ul>")
        parts.append("</div>")
        return "".join(parts)

    def __repr__(self) -> str:
        return f"<crankdyn Result {self.scene.report.title!r}: stages {', '.join(self.stages_run)}>"
