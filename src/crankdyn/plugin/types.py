"""The typed objects that plugins return from the hooks in :mod:`crankdyn.hookspecs`.

A stage is data plus callables: ``applies`` (does the scene need me, and if
not, why), ``run`` (physics: arrays in, arrays out) and, in its presentation
(:class:`StagePresentation`), ``render`` (text and figures from what ``run`` produced;
never physics). The orchestrator orders stages by ``requires``/``provides`` only.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import MISSING, dataclass, field, fields, replace
from fnmatch import fnmatchcase
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from ..scene.model import Scene


@dataclass(frozen=True)
class PlausibilityRule:
    """A check of a valid scene for values no real engine has: a warning, never an error.

    ``check(scene, results)`` returns the warnings (catalog key, parameters) it finds; ``results``
    is the declaring stage's ``StageOutput.results`` when the stage ran, else None (the check
    before a run, or a mechanism's rule). A mechanism declares its rules in
    ``Mechanism.plausibility`` (they hold for scenes naming it), a stage in
    ``Stage.plausibility``; the texts are catalog entries in the declaring plugin's catalogs
    (or the core's, for the rules :mod:`crankdyn.plausibility` offers).
    """

    name: str
    check: Callable[[Scene, Mapping[str, Any] | None], list[tuple[str, dict[str, Any]]]]


@dataclass(frozen=True)
class Mechanism:
    """A mechanism type a scene can name in ``engine.mechanism``.

    ``check`` returns the problems (``crankdyn.errors.Problem``) a scene has for
    this mechanism beyond the generic validation, e.g. a linkage that cannot assemble.

    ``geometry`` (optional) is ``geometry(scene, crank_angle_rad) -> MechanismGeometry``:
    the named joint positions of the linkage at the given crank angles (an array), built
    from the same physics functions as the mechanism's kinematics. With it the ``drawing``
    stage draws the kinematic scheme, the characteristic positions and the animation.

    ``input_rows`` (optional) renames rows of the report's table of given data for a mechanism
    whose members are not a crank-slider's: row -> (catalog key of the quantity, symbol markup),
    rows ``bore``, ``stroke``, ``crank_radius``, ``rod_length``, ``rod_ratio`` (a vane engine's
    ``rod_length`` is the tail of its core, l, not a connecting rod's L); None leaves out a row
    the mechanism has no quantity for (a planetary mechanism's R = S/2 and λ = R/L).

    ``plausibility``: the :class:`PlausibilityRule` s of this mechanism's scenes (a crank-slider's
    λ = R/L and its rod's centre of mass), besides the core's rules that hold for every engine.

    ``needs_rod``: whether the mechanism has a connecting rod (or a member sized as one, a vane
    engine's tail), so that its scenes give exactly one of ``engine.rod_length`` or
    ``engine.rod_ratio``; a mechanism without one (a Scotch yoke) declares False and its scenes
    give neither.

    ``default``: the mechanism of a scene that names none (``engine.mechanism`` left out); at
    most one mechanism of a registry declares it (two are a :class:`crankdyn.errors.PluginError`).
    The built-in central crank-slider does.
    """

    name: str
    summary: str
    check: Callable[[Scene], list] = lambda scene: []
    params_model: type | None = None  # pydantic model of the scene's [mechanism] table
    geometry: Callable[[Scene, Any], MechanismGeometry] | None = None
    # compare=False: a Mechanism stays hashable with a mapping here
    input_rows: Mapping[str, tuple[str, str] | None] = field(default_factory=dict, compare=False)
    plausibility: tuple[PlausibilityRule, ...] = ()
    needs_rod: bool = True
    default: bool = False


@dataclass
class Guide:
    """A straight guide a joint slides in: a cylinder liner (``bore_m`` > 0) or a slot.

    The guide's axis is the line through ``origin_m`` along the unit vector ``direction``;
    the joint ``joint`` slides on it between ``travel_m`` = (nearest, farthest) distances
    from ``origin_m`` along ``direction``. ``label`` names it in the drawing (cylinder 1, 2L ...).
    ``moving`` names two joints the guide is fixed to when it moves (a slotted rocker or
    yoke): then its axis runs from the first joint to the second.
    """

    joint: str
    origin_m: tuple[float, float] = (0.0, 0.0)
    direction: tuple[float, float] = (0.0, 1.0)
    travel_m: tuple[float, float] = (0.0, 0.0)
    bore_m: float = 0.0
    label: str = ""
    moving: tuple[str, str] | None = None


@dataclass
class MechanismGeometry:
    """Where the members of a mechanism are at a set of crank angles (SI, one plane).

    Frame: origin on the crankshaft (carrier, core) axis, ``x`` to the right, ``y`` up
    along the first cylinder's axis (towards its head); the crank turns clockwise, so at
    crank angle ``a`` from cylinder 1's TDC the crank points along (sin a, cos a).

    joints:     name -> array (n, 2) of positions [m] at the n crank angles. Names in use:
                ``crank_centre``, ``crank_pin`` (``crank_pin_<k>`` per crank), ``wrist_pin``
                (``wrist_pin_<cylinder>``), ``slave_pin_<cylinder>``, ``planet_centre``,
                ``pivot_<name>`` ...
    links:      (name, joint a, joint b): rigid members drawn as bars; their length is constant.
    fixed:      joints that are ground pivots (drawn with hatching).
    guides:     cylinders and slots (:class:`Guide`).
    circles:    (centre joint, radius m, kind): gear pitch circles ("fixed" or "moving").
    traces:     name -> array (m, 2): fixed curves drawn thin (e.g. the big end's path).
    dimensions: symbol -> value [m] for the scheme's dimension lines: ``R``, ``L``, ``e``, ``D``,
                ``S`` (the stroke, between the dead centres the scheme marks).
    travel_m:   the output member's displacement from its dead centre nearest the head
                (the piston displacement s), array (n,), used when no kinematics stage
                provides the motion.
    cranks:     (label, crank angle lag deg, cylinder labels) per crank: the crank star.
    firing_order: cylinder labels in firing order (multi-cylinder engines).
    counterweight_cranks: the 1-based cranks drawn with a counterweight; None: every crank of a
                piston engine (the drawing section narrows it to the ones the run fits).
    counterweight_angles: (1-based crank, angle rad from its crank pin in the direction of
                rotation) of the counterweights fitted elsewhere than opposite their pins;
                a crank not named has its counterweight opposite its pin (pi).
    """

    joints: dict[str, Any]
    links: list[tuple[str, str, str]] = field(default_factory=list)
    fixed: tuple[str, ...] = ("crank_centre",)
    guides: list[Guide] = field(default_factory=list)
    circles: list[tuple[str, float, str]] = field(default_factory=list)
    traces: dict[str, Any] = field(default_factory=dict)
    dimensions: dict[str, float] = field(default_factory=dict)
    travel_m: Any = None
    cranks: list[tuple[str, float, tuple[str, ...]]] = field(default_factory=list)
    firing_order: tuple[str, ...] = ()
    counterweight_cranks: tuple[int, ...] | None = None
    counterweight_angles: tuple[tuple[int, float], ...] = ()


class ColumnTable:
    """A table as named numpy columns, read without pandas: ``table["torque_Nm"]`` is an array.

    What a section's ``render`` reads (:meth:`Tables.arrays`): the report then needs no pandas,
    whose import (about 0.3 s) would come before the first figure of every report.
    """

    __slots__ = ("_columns",)

    def __init__(self, columns: Mapping[str, Any]):
        self._columns = {str(name): np.asarray(values) for name, values in columns.items()}

    def __getitem__(self, name: str) -> np.ndarray:
        return self._columns[name]

    def __contains__(self, name: object) -> bool:
        return name in self._columns

    def __len__(self) -> int:
        return len(next(iter(self._columns.values()))) if self._columns else 0

    @property
    def columns(self) -> list[str]:
        return list(self._columns)

    def take(self, rows) -> ColumnTable:
        """The rows at the integer positions ``rows`` (as ``DataFrame.iloc[rows]``)."""
        return ColumnTable({name: values[rows] for name, values in self._columns.items()})

    def row(self, i: int) -> dict[str, Any]:
        """Row ``i`` as column name -> value (as ``DataFrame.iloc[i]``)."""
        return {name: values[i] for name, values in self._columns.items()}


def _rows_to_columns(rows: list[Mapping[str, Any]]) -> dict[str, list]:
    names = list(dict.fromkeys(name for row in rows for name in row))
    return {name: [row.get(name, np.nan) for row in rows] for name in names}


class Tables(dict):
    """A stage's named tables: each read as a pandas DataFrame, or without pandas as a
    :class:`ColumnTable` (:meth:`arrays`).

    A stage may store a table as a DataFrame or as what ``pandas.DataFrame`` is built from (a dict
    of columns or a list of row dicts); the latter becomes a DataFrame when it is first read
    (``tables[name]``, ``get``, ``values``, ``items``), so a run that writes no table file
    (JSON, HTML, PDF) never imports pandas. Pickled (a study computed in a forked child,
    :mod:`crankdyn.background`) as stored, without making DataFrames.
    """

    def arrays(self, name: str) -> ColumnTable:
        """The table ``name`` as numpy columns, without pandas."""
        table = super().__getitem__(name)
        if isinstance(table, dict):
            return ColumnTable(table)
        if isinstance(table, list):
            return ColumnTable(_rows_to_columns(table))
        return ColumnTable({name: table[name].to_numpy() for name in table.columns})  # a DataFrame

    def __reduce__(self):
        return (
            Tables,
            ({name: super(Tables, self).__getitem__(name) for name in dict.keys(self)},),
        )

    def __getitem__(self, name: str) -> pd.DataFrame:
        table = super().__getitem__(name)
        if isinstance(table, (dict, list)):
            import pandas as pd  # lazy: heavy optional import (pandas: only when a table is read)

            table = pd.DataFrame(table)
            super().__setitem__(name, table)
        return table

    def get(self, name: str, default=None):
        return self[name] if name in self else default

    def values(self):
        return [self[name] for name in self]

    def items(self):
        return [(name, self[name]) for name in self]


@dataclass(frozen=True)
class Digits:
    """A note's number printed to ``significant`` digits instead of the notes' usual four (a
    length the section prints to the micrometre elsewhere: the same value reads the same)."""

    value: float
    significant: int


@dataclass(init=False)
class StageOutput:
    """What a stage's ``run`` returns.

    data:       objects for later stages, one entry per key in ``Stage.provides``.
    results:    JSON-ready key results (floats, strings, lists) for results.json.
    tables:     named tables (:class:`Tables`; given as any mapping of name -> table, e.g. a plain
                dict), written as tables/<stage>_<name>.csv; column names carry their unit, e.g.
                ``crank_angle_deg``.
    notes:      method notes as (catalog key, parameters) pairs, rendered by the report (a float
                to four significant digits, a :class:`Digits` to its own).
    artifacts:  objects only this stage's ``render`` uses (e.g. a computed geometry); not
                passed to other stages and not written to any output.
    """

    data: dict[str, Any]
    results: dict[str, Any]
    tables: Tables
    notes: list[tuple[str, dict]]
    artifacts: dict[str, Any]

    def __init__(
        self,
        data: dict[str, Any] | None = None,
        results: dict[str, Any] | None = None,
        tables: Mapping[str, Any] | None = None,
        notes: list[tuple[str, dict]] | None = None,
        artifacts: dict[str, Any] | None = None,
    ) -> None:
        self.data = {} if data is None else data
        self.results = {} if results is None else results
        # a Tables given stays the same object (a stage may fill it after returning it)
        self.tables = tables if isinstance(tables, Tables) else Tables(tables or {})
        self.notes = [] if notes is None else notes
        self.artifacts = {} if artifacts is None else artifacts


@dataclass
class Section:
    """A rendered report section: HTML body plus the conclusions it contributes."""

    key: str
    title: str
    html: str
    conclusions: list[str] = field(default_factory=list)
    references: tuple[str, ...] = ()


@dataclass(frozen=True)
class Symbol:
    """A quantity's symbol: base letter, subscript per language (none: ``{}``; English where a
    language has none), unit (a catalog key ``unit.…``, a literal such as ``°``, or ``""`` for a
    ratio) and the meaning's catalog key, ``symbol.<key>`` of the symbol's key in the table.

    The core's table (:data:`crankdyn.report.typeset.SYMBOLS`) holds the quantities many sections
    share (some bound to the sections of the stages that declare them in ``Stage.section_symbols``);
    a stage declares its own letters in ``Stage.symbols`` (key ``k`` of stage ``s`` is
    ``s.k`` in the table, its meaning the catalog key ``symbol.s.k`` in the plugin's catalogs,
    and it applies in the stage's own section unless ``sections`` says otherwise). In its
    sections a symbol with ``sections`` takes over from a core symbol of the same markup.
    """

    base: str
    sub: dict[str, str]
    unit: str
    meaning: str = ""
    #: a second meaning of a letter that one calculation gives it (δ: the expansion ratio, and the
    #: irregularity in the flywheel sections): listed only when one of these sections is present
    sections: tuple[str, ...] = ()
    #: the markup, where the symbol is more than a letter with a subscript (Δ<i>L</i>, p_i′, a vector
    #: <b><i>q</i></b><sub>{sub}</sub>: ``{sub}`` stands for the language's subscript)
    html: str = ""
    #: a bare letter that is the quantity inside an exponent too (θ of e^{jnθ}), not an index
    in_scripts: bool = False


@dataclass(frozen=True)
class AnswerColumn:
    """A column of the batch answer key (``answer_key.csv``/``.xlsx``) a stage declares.

    column:     the column header; carries its unit, e.g. ``p_max_MPa``.
    key:        where the value is in the stage's ``StageOutput.results``; dots walk into
                nested tables (``"peak.value_Pa"``).
    unit:       the column's unit as printed ("MPa", "m/s", "" for a plain number).
    factor:     column value = results value x factor (results are SI: Pa -> MPa is 1e-6).
    label_key:  optional catalog key of the column's human-readable label with its unit
                ("Maximum cycle pressure, MPa"), from the plugin's own catalogs: ``answer_key.xlsx``
                shows it in the batch's language above the column names (without one, the
                column's name); ``answer_key.csv`` keeps the names only.

    A variant whose stage did not run (or gave no number) leaves the cell empty.
    """

    column: str
    key: str
    unit: str = ""
    factor: float = 1.0
    label_key: str | None = None


@dataclass(frozen=True)
class StagePresentation:
    """What a stage shows in the report: its section, figures, sources and letters.

    title_key:  catalog key of the section title.
    render:     ``render(output, ctx) -> str | None``: the section's HTML (usually via
                ``ctx.render_template``), or None when the stage has nothing to show for
                this scene (it ran only for the data it provides).
    template_dir: a folder with this plugin's section templates, if it has its own.
    references: catalog keys of the sources the method comes from.
    references_full: catalog keys of the sources only the full report's study cites (its solver
                and series comparisons, ``[report] detail = "full"``): a course note lists
                only the sources it cites.
    references_sentence: catalog key of the sentence that opens the section citing them
                (``{refs}``: "[2, 8]"); default ``doc.method_from``, "the calculation follows [n]",
                which overclaims for a section that takes only a part from its sources.
    figures:    the names of the figures ``render`` may draw (the ``name`` of each
                ``ctx.figure(fig, caption, name)``; the file is figures/fig_<number>_<name>.svg).
                A ``*`` stands for any text, for a figure drawn once per cylinder or bearing
                (``"wear_pin*"``). Drawing a figure not declared is a
                :class:`crankdyn.errors.PluginError`.
    input_rows: ``input_rows(scene, ctx) -> [(quantity, symbol markup, value, unit), ...]``: the
                given data of this stage's own scene table that the report's first table (the
                task's data) lists after the engine's, translated by ``ctx.t``; None: none.
    taken_rows: ``taken_rows(scene, ctx)``, rows as ``input_rows``'s: the values of this stage's
                scene table that the scene leaves at their defaults and the calculation takes
                (a rim's material density): the report lists them in its table of the values
                taken, not among the task's data; None: none.
    legend:     whether the symbol table explains this section's equations (the "де …"
                lines, ``crankdyn.report.equation_legend``); False for a section that explains
                its letters in its own words.
    symbols:    key -> :class:`Symbol`: the letters this stage's equations use that the core's
                symbol table does not have (or has with another meaning), each with its meaning
                ``symbol.<stage>.<key>`` in the plugin's catalogs; they go to the list of symbols
                and the "де …" lines like the core's (a vane engine's β, the tail's angle, is not
                a connecting rod's angle: declared here, it takes over in the vane's section).
    section_symbols: keys of the core's section-bound symbols (``Symbol.sections`` =
                ``crankdyn.report.typeset.SECTION_BOUND``: the side force n, the irregularity δ)
                whose meaning holds in this stage's section; a letter the core gives another
                meaning elsewhere (n, the crank speed) is read so there.
    appendix:   whether the section is a study of the numerics rather than part of a course brief:
                with ``[report] detail = "course"`` (the default) it goes to an appendix.
    """

    title_key: str
    # ctx is a crankdyn.report.context.RenderContext; not imported here, even for type checking:
    # the report layer sits above the hook types (docs/architecture.md, [tool.importlinter]).
    render: Callable[[StageOutput, Any], str | None]
    template_dir: Path | None = None
    references: tuple[str, ...] = ()
    references_full: tuple[str, ...] = ()
    references_sentence: str = "doc.method_from"
    figures: tuple[str, ...] = ()
    input_rows: Callable[[Scene, Any], Sequence[tuple[str, str, str, str]]] | None = None
    taken_rows: Callable[[Scene, Any], Sequence[tuple[str, str, str, str]]] | None = None
    legend: bool = True
    # compare=False: a StagePresentation stays hashable (tuples elsewhere) with a mapping here
    symbols: Mapping[str, Symbol] = field(default_factory=dict, compare=False)
    section_symbols: tuple[str, ...] = ()
    appendix: bool = False


#: the fields of :class:`StagePresentation`, which ``Stage`` also takes as keywords (the flat form)
PRESENTATION_FIELDS = (
    "title_key",
    "render",
    "template_dir",
    "references",
    "references_full",
    "references_sentence",
    "figures",
    "input_rows",
    "legend",
    "symbols",
    "section_symbols",
    "appendix",
)


@dataclass(frozen=True)
class Stage:
    """An analysis stage: what it computes and when it runs; what it shows is ``presentation``.

    name:       unique; used in ``--stages`` and results.json.
    requires:   data keys this stage needs from earlier stages.
    provides:   data keys it makes (``StageOutput.data`` must hold exactly these).
    uses:       data keys it takes when a stage in the plan provides them (e.g. the engine
                torque for one extra result); they never pull a stage into the plan, and
                ``run`` finds them in ``inputs`` only when they were provided.
    applies:    ``applies(scene) -> None`` when the scene needs this stage, else the
                reason (one English sentence; it goes to results.json and the report).
                A stage that names ``services`` may take them as a second argument,
                ``applies(scene, services)`` (the mapping ``run`` finds in ``inputs``): a stage
                whose applicability depends on the run's other plugins asks the run's registry
                (``services[SERVICE_RUNNER].registry``), never a registry of its own.
    run:        ``run(scene, inputs) -> StageOutput``; ``inputs`` maps each required key
                to the object an earlier stage provided.
    run_many:   optional ``run_many(scenes, inputs) -> [StageOutput, ...]``: ``run`` over many
                scenes at once (a sweep's points: arrays over points × angles), ``inputs`` one
                mapping per scene as ``run`` gets it. Each output's ``data`` and ``results`` equal
                what ``run`` gives for its scene (``tables`` and ``notes`` may stay empty: a sweep
                renders nothing). When it raises, the sweep runs ``run`` point by point, so each
                point gets its own error; without it, the sweep always does.
    options_table: name of a top-level scene table this stage reads (e.g. "flywheel").
    options_model: pydantic model validating that table (see ``crankdyn.scene.options``).
    services:   objects the orchestrator passes in ``inputs`` (``SERVICE_RUNNER``,
                ``SERVICE_ERROR_PROBES``, ``SERVICE_ASIDE``, see below); a stage never builds
                its own registry, nor decides on its own to use another core.
    tables:     the names of the tables ``run`` may put in ``StageOutput.tables`` (written as
                tables/<stage>_<name>.csv, or tables/<stage>.csv for the name of the stage, and as
                sheets of tables.xlsx); ``*`` as in ``StagePresentation.figures``. Returning a
                table not declared is a :class:`crankdyn.errors.PluginError`. The numbered tables
                of the report's text (``ctx.table``) belong to the section and are not declared.
    default:    whether the stage runs when the scene does not list stages.
    last:       order hint: run (and appear in the report) after every stage that is
                ready at the same time, e.g. a summary of the others; ``requires`` still rules.
    answer_columns: the :class:`AnswerColumn` s this stage adds to the batch answer key
                (in the key they follow the stages' requires/provides order, then the
                order given here).
    plausibility: the :class:`PlausibilityRule` s checking this stage's scene values or results
                (the indicator's peak pressure).
    presentation: the stage's section (:class:`StagePresentation`); None: the stage shows
                nothing (it runs for the data it provides and its results).
    default_angle_step: optional ``default_angle_step(scene) -> float | None``: the crank-angle
                step [deg] the stage's accuracy asks for when the scene gives no
                ``analysis.angle_step_deg`` (the numerics stage: 1 deg x sqrt(tolerance / 0.1 %)
                from its ``[numerics] tolerance``); None: no wish. The smallest wish of the
                registered stages is the target the default step is chosen for, else 1 deg.

    The presentation's fields given to ``Stage`` itself (``Stage(name=..., title_key=...,
    render=..., figures=...)``, the flat form) are folded into a :class:`StagePresentation`
    with a ``DeprecationWarning``; read as ``stage.title_key`` they are still there, read-only.
    Both are kept for one release.
    """

    name: str
    requires: tuple[str, ...]
    provides: tuple[str, ...]
    applies: Callable[..., str | None]
    run: Callable[[Scene, Mapping[str, Any]], StageOutput]
    uses: tuple[str, ...] = ()
    run_many: (
        Callable[[Sequence[Scene], Sequence[Mapping[str, Any]]], Sequence[StageOutput]] | None
    ) = None
    options_table: str | None = None
    options_model: type | None = None
    services: tuple[str, ...] = ()
    tables: tuple[str, ...] = ()
    default: bool = True
    last: bool = False
    answer_columns: tuple[AnswerColumn, ...] = ()
    plausibility: tuple[PlausibilityRule, ...] = ()
    presentation: StagePresentation | None = None
    default_angle_step: Callable[[Scene], float | None] | None = None

    def __init__(
        self,
        *,
        name: str,
        requires: tuple[str, ...],
        provides: tuple[str, ...],
        applies: Callable[..., str | None],
        run: Callable[[Scene, Mapping[str, Any]], StageOutput],
        uses: tuple[str, ...] = (),
        run_many: (
            Callable[[Sequence[Scene], Sequence[Mapping[str, Any]]], Sequence[StageOutput]] | None
        ) = None,
        options_table: str | None = None,
        options_model: type | None = None,
        services: tuple[str, ...] = (),
        tables: tuple[str, ...] = (),
        default: bool = True,
        last: bool = False,
        answer_columns: tuple[AnswerColumn, ...] = (),
        plausibility: tuple[PlausibilityRule, ...] = (),
        presentation: StagePresentation | None = None,
        default_angle_step: Callable[[Scene], float | None] | None = None,
        **flat: Any,
    ) -> None:
        if flat:
            presentation = _folded_presentation(name, presentation, flat)
        given = dict(
            name=name,
            requires=requires,
            provides=provides,
            applies=applies,
            run=run,
            uses=uses,
            run_many=run_many,
            options_table=options_table,
            options_model=options_model,
            services=services,
            tables=tables,
            default=default,
            last=last,
            answer_columns=answer_columns,
            plausibility=plausibility,
            presentation=presentation,
            default_angle_step=default_angle_step,
        )
        for key, value in given.items():
            object.__setattr__(self, key, value)


def _folded_presentation(
    name: str, presentation: StagePresentation | None, flat: dict[str, Any]
) -> StagePresentation:
    """The flat form's presentation keywords as a :class:`StagePresentation` (over
    ``presentation`` when one is given too, as ``dataclasses.replace(stage, title_key=...)``)."""
    unknown = sorted(set(flat) - set(PRESENTATION_FIELDS))
    if unknown:
        raise TypeError(f"Stage() got an unexpected keyword argument {unknown[0]!r}")
    warnings.warn(
        f"stage {name!r}: give {', '.join(sorted(flat))} in "
        "Stage(presentation=StagePresentation(...)); the flat form "
        "Stage(title_key=..., render=...) is kept for one release",
        DeprecationWarning,
        stacklevel=3,
    )
    if presentation is not None:
        return replace(presentation, **flat)
    missing = [key for key in ("title_key", "render") if key not in flat]
    if missing:
        raise TypeError(
            f"stage {name!r}: the flat form needs {' and '.join(missing)} "
            "(or give presentation=StagePresentation(...))"
        )
    return StagePresentation(**flat)


def _presentation_property(key: str) -> property:
    default = {f.name: f.default for f in fields(StagePresentation)}.get(key)

    def read(stage: Stage) -> Any:
        warnings.warn(
            f"Stage.{key} is read as Stage.presentation.{key}; the flat attribute is "
            "kept for one release",
            DeprecationWarning,
            stacklevel=2,
        )
        if stage.presentation is None:
            return {} if key == "symbols" else (None if default is MISSING else default)
        return getattr(stage.presentation, key)

    return property(read, doc=f"``presentation.{key}`` (the flat form, kept for one release)")


for _key in PRESENTATION_FIELDS:
    setattr(Stage, _key, _presentation_property(_key))
del _key


def declared(name: str, declarations: tuple[str, ...]) -> bool:
    """Whether ``name`` is one of ``declarations`` (``StagePresentation.figures``,
    ``Stage.tables``), where a ``*`` in a declaration stands for any text."""
    return any(fnmatchcase(name, pattern) for pattern in declarations)


# Objects the orchestrator hands to a stage that names them in ``Stage.services``; they arrive
# in ``run``'s ``inputs`` under these keys (next to the data keys of ``requires``).
#: a :class:`crankdyn.orchestrator.Runner` over the registry the scene runs with: re-plan and
#: re-run (part of) the pipeline, e.g. at another angle step, without building a registry.
SERVICE_RUNNER = "crankdyn:runner"
#: the :class:`ErrorProbe` s every plugin registered with the ``crankdyn_error_probes`` hook.
SERVICE_ERROR_PROBES = "crankdyn:error_probes"
#: :func:`crankdyn.aside.aside`: ``aside(fn, *args)`` computes ``fn(*args)`` in a forked child when
#: the report's process has a core to spare (a report that renders nothing), else when asked.
SERVICE_ASIDE = "crankdyn:aside"
SERVICES = (SERVICE_RUNNER, SERVICE_ERROR_PROBES, SERVICE_ASIDE)


@dataclass(frozen=True)
class ProbePoint:
    """One point of an error-against-time study of a solver.

    method:   the solver ("RK45", "Newmark", ...); setting: what was varied ("rtol = 1e-6");
    error:    the error against the probe's reference, in ``error_unit``; time_s: its run time;
    reference: how the reference was obtained (independent of the method under test).
    """

    method: str
    setting: str
    error: float
    error_unit: str
    time_s: float
    reference: str


@dataclass(frozen=True)
class ErrorProbe:
    """An error-against-time study of a solver, shown by the numerics section and in results.json.

    Returned from the ``crankdyn_error_probes`` hook. ``applies(scene)`` says whether the probe
    concerns the scene; ``run(scene, runner)`` returns its points, or raises
    :class:`crankdyn.errors.SceneError` when the scene cannot be studied (the reason is
    reported). ``runner`` is the orchestrator's :class:`crankdyn.orchestrator.Runner`: a probe
    that needs e.g. the engine torque re-runs the pipeline with it, then times its own solver
    (e.g. at tolerances 1e-3 ... 1e-10) against a reference that does not use that solver.
    ``title`` is plain text shown above its table.
    """

    name: str
    title: str
    applies: Callable[[Scene], bool]
    run: Callable[[Scene, Any], list[ProbePoint]]


@dataclass(frozen=True)
class Catalog:
    """Translations a plugin adds: ``language`` code and a TOML file of key = text."""

    language: str
    path: Path
