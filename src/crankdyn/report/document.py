"""Assemble the whole report from a run: sections in plan order, notes, conclusions."""

from __future__ import annotations

import dataclasses
import datetime
import functools
import hashlib
import html as html_lib
import pickle
import re
from dataclasses import dataclass, field

import jinja2
from markupsafe import Markup, escape

from ..engine.orchestrator import RunResult
from ..errors import SceneError
from ..physics.extrema import EXTREMUM_RTOL
from ..physics.indicator import RoundingParameters
from ..plugin.contracts import COUNTERWEIGHTS, FORCES, GAS_PRESSURE, KINEMATICS
from ..plugin.registry import Registry
from ..plugin.scene_inputs import engine_layout, rounding_parameters
from ..plugin.types import Digits
from ..version import __version__
from .assets import html_language, report_css
from .context import FigureFile, RenderContext, inline_figures, template_search_path
from .equation_legend import add_equation_legends, line_unit, symbol_meaning
from .frame import frame_html
from .i18n import translator
from .plausibility import format_params, report_key, scene_warnings, stage_warnings
from .typeset import (
    SYMBOLS,
    SymbolTable,
    italic_letters,
    symbol_html,
    symbol_table,
    symbol_unit,
    symbols_used,
    typeset_html,
    unbreakable_html,
)

_IDENTIFIER = re.compile(r"\b[a-z]+(?:[._][a-z]+)+\b")


def field_names(t, value):
    """Scene keys in a note's parameter (``crank_pin_diameter``) by their names in the catalog."""
    if not isinstance(value, str):
        return value
    return _IDENTIFIER.sub(
        lambda m: t(f"field.{m.group(0)}") if f"field.{m.group(0)}" in t.fallback else m.group(0),
        value,
    )


def report_units(t) -> list[str]:
    """The unit symbols of the report's language, kept on the line of their number."""
    units = {text for key, text in {**t.fallback, **t.texts}.items() if key.startswith("unit.")}
    return sorted(
        units | {"%", "°C", "K", "Н", "кН", "Вт", "кВт", "N", "kN", "W", "kW", "с", "s", "мс", "ms"}
    )


#: A numbered subsection's heading as :meth:`RenderContext.subsection` writes it.
_SUBSECTION = re.compile(r'<h3 class="subsection" id="sec-([^"]+)">(.*?)</h3>', re.S)


def lone_subsection_unnumbered(html: str) -> str:
    """A section's only subsection heading without its number and out of the contents: a section
    is divided into two subsections or more, or not at all (DSTU 3008:2015, 6.2), so a lone
    heading stays a plain heading within the section."""
    found = list(_SUBSECTION.finditer(html))
    if len(found) != 1:
        return html
    match = found[0]
    number = match[1]
    title = match[2].removeprefix(escape(number) + " ")
    return (
        html[: match.start()]
        + f'<h3 class="subsection-lone" id="sec-{number}">{title}</h3>'
        + html[match.end() :]
    )


@dataclass
class SectionView:
    number: int
    key: str
    title: str
    html: Markup
    conclusions: list[str] = field(default_factory=list)

    @property
    def subsections(self) -> list[tuple[str, str]]:
        """(number, heading) of each numbered subsection, for the table of contents."""
        return [
            (m[1], html_lib.unescape(re.sub(r"<[^>]+>", "", m[2])))
            for m in _SUBSECTION.finditer(self.html)
        ]


@dataclass
class RenderedReport:
    """A rendered report: the page referring to ``figures/NAME.svg``, and the figures once each."""

    linked_html: str
    figures: list[FigureFile]
    language: str
    missing_translations: set[str]
    worked: list = field(
        default_factory=list
    )  # the worked substitutions shown (report.worked.WorkedBlock)

    @functools.cached_property
    def html(self) -> str:
        """The self-contained page: every figure inlined as a data: URI (preview, ``--self-contained``)."""
        return inline_figures(self.linked_html, self.figures)


def _environment(registry: Registry, result: RunResult) -> jinja2.Environment:
    """The templates of the plan's stages."""
    extra = [
        s.presentation.template_dir
        for s in result.plan.order
        if s.presentation is not None and s.presentation.template_dir is not None
    ]
    return _cached_environment(tuple(str(p) for p in template_search_path(extra)))


@functools.lru_cache(maxsize=16)
def _cached_environment(search_path: tuple[str, ...]) -> jinja2.Environment:
    """One environment per template search path: its compiled templates are kept for the next
    report of the process (a batch's variants, the preview's saves; jinja2 checks the files'
    modification times, so an edited template is compiled again)."""
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(list(search_path)),
        undefined=jinja2.StrictUndefined,
        bytecode_cache=_bytecode_cache(),
        **TEMPLATE_OPTIONS,
    )


#: How the section templates are compiled (and so part of the key of their compiled code).
TEMPLATE_OPTIONS = {
    "autoescape": True,  # every value is escaped unless a helper marks it as markup
    "trim_blocks": True,
    "lstrip_blocks": True,
}


class _QuietBytecodeCache(jinja2.FileSystemBytecodeCache):
    """Jinja's file cache of compiled templates, for which a full or read-only disk is no error
    (the template is then compiled again next time, as without a cache), nor is one that cannot
    be read (compiled now, as without a cache)."""

    def load_bytecode(self, bucket) -> None:
        try:
            super().load_bytecode(bucket)
        except (
            OSError,
            EOFError,
            ValueError,
            TypeError,
            pickle.UnpicklingError,
        ):  # unreadable or damaged
            bucket.reset()

    def dump_bytecode(self, bucket) -> None:
        try:
            super().dump_bytecode(bucket)
        except OSError:
            pass


@functools.lru_cache(maxsize=1)
def _bytecode_cache() -> jinja2.BytecodeCache | None:
    """The compiled section templates, kept between runs: compiling them is about a tenth of a
    second of every report. Jinja's own file cache (a private folder in the temporary directory,
    checked to belong to this user); a template is found there by its path, used only while its
    source's checksum matches, and the file names carry this crankdyn version and the compile
    options. None (no cache) where that folder cannot be made."""
    options = hashlib.sha256(repr(sorted(TEMPLATE_OPTIONS.items())).encode()).hexdigest()[:8]
    try:
        return _QuietBytecodeCache(pattern=f"crankdyn-{__version__}-{options}-%s.cache")
    except (OSError, RuntimeError):  # RuntimeError: the folder is not this user's own
        return None


_SKIP_REASONS = (  # the stages' own (English) reasons, as results.json keeps them -> catalog keys
    (re.compile(r"no \[masses\]"), "skip.no_masses"),
    (re.compile(r"no \[flywheel\]"), "skip.no_flywheel"),
    (re.compile(r"no \[cycle\]"), "skip.no_cycle"),
    (re.compile(r"rod_moment_of_inertia"), "skip.no_rod_inertia"),
    (
        re.compile(
            r"mechanism is '[^']*', not|central crank-slider|mechanism has no|articulated rods"
        ),
        "skip.other_mechanism",
    ),
    (re.compile(r"covers|already|drawn by the"), "skip.covered"),
)


def _skip_key(reason: str) -> str:
    for pattern, key in _SKIP_REASONS:
        if pattern.search(reason):
            return key
    return "skip.not_applicable"


def skipped_reason(t, reason: str) -> str:
    """A left-out stage's reason in the report's language."""
    return t(_skip_key(reason))


#: Reasons a report does not list (results.json keeps every one): a stage for another mechanism
#: (the planetary or vane engine in a crank-slider's report) or one whose content another section
#: already gives is not part of this assignment, and naming it reads as a contradiction (the
#: "kinematic scheme" left out next to the section that draws it).
UNLISTED_SKIPS = ("skip.other_mechanism", "skip.covered")


def _in_sentence(title: str) -> str:
    """A section's title inside a sentence: its first letter small, unless it opens an
    abbreviation ("ВМТ")."""
    if len(title) > 1 and title[1].isupper():
        return title
    return title[:1].lower() + title[1:]


#: The reasons a course note's sentence on what it leaves out gives: data the assignment lacks. A
#: calculation that does not apply to the task is no part of it and goes unsaid.
_DATA_SKIPS = ("skip.no_masses", "skip.no_flywheel", "skip.no_cycle", "skip.no_rod_inertia")


def skipped_sentence(t, registry, result) -> str:
    """A course note's one sentence on the calculations it leaves out for want of data, or ""
    where it says nothing: a mechanism studied for its kinematics (no working cycle) is not an
    engine whose flywheel or forces the assignment left out, and a list of sections with reasons
    reads as a program's modules, not as the student's text."""
    if result.scene.cycle is None:
        return ""
    # an aircraft engine has no flywheel at all: its propeller takes the flywheel's part
    aircraft = getattr(result.scene.engine, "application", None) == "aircraft"
    skipped = [
        (
            _skipped_title(t, registry, name),
            t(
                _skip_key(reason)
                + ("_aircraft" if aircraft and "flywheel" in _skip_key(reason) else "")
            ),
        )
        for name, reason in result.plan.skipped.items()
        if _skip_key(reason) in _DATA_SKIPS
    ]
    if not skipped:
        return ""
    titles = [title for title, _ in skipped]
    titles = [titles[0], *map(_in_sentence, titles[1:])]
    # "A and B"; "A, B and C" where the last title has its own "and" ("… і крутильні коливання")
    conjunction = t("report.skipped_what_and", first="", last="").strip()
    if len(titles) > 1 and f" {conjunction} " not in titles[-1]:
        titles[-2:] = [t("report.skipped_what_and", first=titles[-2], last=titles[-1])]
    what = ", ".join(titles)
    why = "; ".join(dict.fromkeys(reason for _, reason in skipped))
    # a title joining two things ("… і крутильні коливання") is a plural subject by itself
    count = len(skipped) + sum(f" {conjunction} " in title for title, _ in skipped)
    return t("report.skipped_course", what=what, what_in=_in_sentence(what), why=why, count=count)


def _skipped_title(t, registry, name: str) -> str:
    """A left-out stage's title as the object of the sentence saying it is not calculated: the
    catalog's ``<title key>_accusative`` where the language declines it (Ukrainian «не
    розраховано» takes the accusative: «динаміку шатуна»), else the title."""
    stage = registry.stages.get(name)
    look = stage.presentation if stage is not None else None
    if look is not None and look.title_key and t.has(look.title_key + "_accusative"):
        return t(look.title_key + "_accusative")
    return _stage_title(t, registry, name)


def cite(numbers) -> str:
    """``[1, 2]``, ``[5–7]``: sources cited by their numbers in the list of references, three or
    more consecutive numbers as a range (ДСТУ 8302:2015 practice, as "[5–7]" for "[5, 6, 7]")."""
    ordered = sorted(set(numbers))
    runs: list[list[int]] = []
    for n in ordered:
        if runs and n == runs[-1][-1] + 1:
            runs[-1].append(n)
        else:
            runs.append([n])
    return (
        "["
        + ", ".join(
            f"{run[0]}–{run[-1]}" if len(run) >= 3 else ", ".join(map(str, run)) for run in runs
        )
        + "]"
    )


#: A source cited in a catalog's text by its key, "[@ismailov, fig. 3b]": the number the source
#: has in the report's list of references takes its place ("[2, fig. 3b]").
_CITED_KEY = re.compile(r"\[@([A-Za-z0-9_]+)")
#: Several sources cited together, "[@kolchin2002; @blair1996]": one bracket of their numbers
#: ("[6, 10]"), as the standard cites them.
_CITED_KEYS = re.compile(r"\[@([A-Za-z0-9_]+(?:;\s*@[A-Za-z0-9_]+)+)\]")


def cite_sources(text: str, references: list[str]) -> str:
    """``text`` with each "[@key" of a source replaced by "[n" of its number, and each
    "[@key; @other]" by one bracket of their numbers; a source cited here first is added to
    ``references`` (the list holds the sources the note cites, in the order of their first
    citation)."""

    def numbered(key: str) -> int:
        if key not in references:
            references.append(key)
        return references.index(key) + 1

    def several(match: re.Match) -> str:
        return cite([numbered(k.strip().lstrip("@")) for k in match.group(1).split(";")])

    text = _CITED_KEYS.sub(several, text)
    return _CITED_KEY.sub(lambda match: f"[{numbered(match.group(1))}", text)


def plausibility_text(t, found, references: list[str], said: set) -> tuple[Markup, list[str]]:
    """The section's paragraphs and the conclusions' sentences of the warnings ``found``
    (:func:`crankdyn.report.plausibility.report_key`) not ``said`` before (two stages may judge one
    value); a warning's ``source`` parameter (a catalog key of the reference its limits come
    from) is cited by its number, added to ``references``."""
    paragraphs, conclusions = [], []
    for key, params in found:
        if (key, repr(sorted(params.items()))) in said:
            continue
        said.add((key, repr(sorted(params.items()))))
        shown = format_params(params, t.decimal_separator)
        if "source" in params:
            if params["source"] not in references:
                references.append(params["source"])
            shown["source"] = cite([references.index(params["source"]) + 1])
        # an empty text: a warning the section's own check words (said on the console only)
        sentence = t(report_key(t, key, "section"), **shown)
        if sentence:
            paragraphs.append(f'<p class="plausibility">{escape(sentence)}</p>')
        conclusion = t(report_key(t, key, "conclusion"), **shown)
        if conclusion:
            conclusions.append(conclusion)
    # markup: joined to a section's markup as it is, not escaped again
    return Markup("".join(paragraphs)), conclusions


def appendix_letter(t, index: int) -> str:
    letters = t("doc.appendix_letters")
    return letters[index] if index < len(letters) else str(index + 1)


#: The source of the whole project's method: cited as [1] in the introduction.
PROJECT_METHOD = "poda2007"


def _inputs_used(result) -> dict[str, bool]:
    """Which of the assignment's masses and pressures the run uses: the crank's masses enter the
    forces on the crank pin and the balancing, the crankcase pressure the piston force; a report
    that computes neither does not list them (a kinematics-only mechanism's)."""
    provided = {key for stage in result.plan.order for key in stage.provides}
    return {
        "uses_crank_masses": bool(provided & {FORCES, COUNTERWEIGHTS}),
        "uses_crankcase_pressure": FORCES in provided,
    }


def _rounding_used(result) -> RoundingParameters | None:
    """The indicator diagram's rounding as the run takes it (the defaults filled in, a diesel's
    advance past its delay; the peak's angle and a usual p_z′ as the gas-pressure stage drew
    them), for the given-data table; None without a rounded cycle."""
    cycle = getattr(result.scene, "cycle", None)
    if cycle is None or cycle.rounding is None or cycle.ignition is None:
        return None  # a measured trace is not rounded
    try:
        rounding = rounding_parameters(result.scene)
    except SceneError:
        return None
    drawn = [
        gas.rounding
        for stage in result.plan.order
        if GAS_PRESSURE in stage.provides and stage.name in result.outputs
        for gas in (result.outputs[stage.name].data.get(GAS_PRESSURE),)
        if getattr(gas, "rounding", None) is not None
    ]
    if not drawn:
        return rounding
    # a usual peak that would stand above the theoretical diagram is lowered by the stage, a
    # diesel's put on its isobar; a given fraction stays the task's datum (the section says
    # what was taken instead)
    fraction = (
        rounding.peak_pressure_fraction
        if cycle.rounding.peak_pressure_fraction is not None
        else drawn[0].peak_pressure_fraction
    )
    return dataclasses.replace(
        rounding,
        peak_pressure_fraction=fraction,
        peak_angle_after_tdc_deg=drawn[0].peak_angle_after_tdc_deg,
        pressure_rise_to_tdc_Pa=drawn[0].pressure_rise_to_tdc_Pa,
    )


def _peak_fraction_taken(result) -> tuple[float, str] | None:
    """The p_z′/p_z the gas-pressure stage drew where the scene gives another (a given peak
    that would stand above the theoretical diagram is lowered), with that stage's section mark:
    the given-data table names both; None otherwise."""
    cycle = getattr(result.scene, "cycle", None)
    given = getattr(getattr(cycle, "rounding", None), "peak_pressure_fraction", None)
    if given is None:
        return None
    for stage in result.plan.order:
        if GAS_PRESSURE in stage.provides and stage.name in result.outputs:
            drawn = getattr(result.outputs[stage.name].data.get(GAS_PRESSURE), "rounding", None)
            if drawn is not None and abs(drawn.peak_pressure_fraction - given) > 1e-9:
                return float(drawn.peak_pressure_fraction), f"{_COMPUTED_ROW_MARK}{stage.name}@@"
    return None


def _stage_input_rows(result, ctx, hook: str = "input_rows") -> list[tuple[str, str, str, str]]:
    """The given-data rows of the stages in the plan (``StagePresentation.input_rows``), in plan
    order; with ``hook="taken_rows"`` the values they take that the scene does not give."""
    shown = [stage.presentation for stage in result.plan.order if stage.presentation is not None]
    return [
        tuple(row)
        for look in shown
        if getattr(look, hook) is not None
        for row in getattr(look, hook)(result.scene, ctx)
    ]


#: A row of the given data that a section computes names that section ("computed in section N"):
#: the assignment, which lists the task's data only, leaves it out.
_COMPUTED_ROW_MARK = "@@SECTION:"


def _assignment_given(result, registry, ctx) -> dict:
    """What the assignment's list of the main data takes from the mechanism: the symbol of the
    scene's stroke (an offset crank-slider's is the crank throw 2R, not its piston's stroke) and
    the given data of the stage computing its kinematics ("e = 5 mm"), as markup (z<sub>f</sub>
    keeps its subscript)."""
    mechanism = registry.mechanisms.get(result.scene.engine.mechanism)
    own = (mechanism.input_rows if mechanism else {}).get("stroke")
    shown = [
        stage.presentation
        for stage in result.plan.order
        if stage.presentation is not None and KINEMATICS in stage.provides
    ]
    given = [
        Markup(f"{symbol} = ") + escape(value) + ("" if unit in ("°", "") else " ") + escape(unit)
        for look in shown
        if look.input_rows is not None
        for quantity, symbol, value, unit in look.input_rows(result.scene, ctx)
        if symbol and _COMPUTED_ROW_MARK not in quantity
    ]
    return {
        "assignment_stroke": Markup(own[1]).striptags() if own else "S",
        "assignment_given": given,
    }


def _section_body(stage, output, ctx, sections_cache, figure_sink) -> str | None:
    """``stage``'s section as rendered (or kept by the preview's cache); its figures go to
    ``figure_sink`` as soon as it is rendered."""
    figures_before = len(ctx.figures)
    if output is None:  # a study the preview computes after showing the rest (RunResult.pending)
        body = f'<p class="pending">{escape(ctx.t("doc.section_pending"))}</p>'
    elif sections_cache is None:
        body = stage.presentation.render(output, ctx)
    else:
        body = sections_cache.render(stage, output, ctx)
    if figure_sink is not None:
        figure_sink(ctx.figures[figures_before:])
    return body


def _input_view(result, registry, ctx) -> SectionView:
    """The given data's section (its plausibility sentences are added when the run is read)."""
    scene = result.scene
    ctx.start_section(1, "input")
    mechanism = registry.mechanisms.get(scene.engine.mechanism)
    return SectionView(
        1,
        "input",
        ctx.t("report.input_title"),
        Markup(
            ctx.render_template(
                "sections/input.html.j2",
                scene=scene,
                mechanism=mechanism,
                mechanism_key=mechanism_key,
                stage_rows=_stage_input_rows(result, ctx),
                stage_taken_rows=_stage_input_rows(result, ctx, "taken_rows"),
                rounding_used=_rounding_used(result),
                peak_fraction_taken=_peak_fraction_taken(result),
                shared_pins=_cylinders_share_pins(scene),
                **_inputs_used(result),
            )
        ),
    )


def _meaning_forms(scene) -> tuple[str, ...]:
    """The forms of the symbols' meanings that fit ``scene``'s engine, first to try first
    (:func:`crankdyn.report.equation_legend.symbol_meaning`): a one-cylinder engine's, cylinders
    sharing pins (a one bank's), a boxer's (a the offset of opposed cylinders along the shaft),
    a shaft of one crank ("without its crank's mass", not "its cranks' masses"), a W, Y or X
    engine's (its bank angle between adjacent banks), an aircraft engine's (its propeller's
    inertia where another engine has a flywheel's), an engine with banks (its frame along the
    banks' axis of symmetry; a boxer's, before it, normal to its cylinders); a crosshead engine's
    first (its side force on the guides); articulated rods' before a bank's (the master rod's
    bearing carries all the rods' forces)."""
    forms = []
    if getattr(scene.engine, "crosshead", False):
        forms.append("crosshead")  # the side force on the crosshead's guides, its moving parts
    if scene.engine.layout == "boxer":
        forms.append("flat")  # the engine's vertical is normal to its cylinders' axes
    if scene.engine.layout in ("V", "W", "Y", "X", "boxer"):
        forms.append("vertical")  # an engine frame along the banks' axis of symmetry
    one_crank = _cranks(scene) == 1
    if scene.engine.cylinders == 1:
        forms.append("single")
    elif one_crank:  # before a bank's: z_i of cylinders on one crank is each cylinder's own
        forms.append("one_crank")
    if getattr(scene.engine, "rod_type", "central") == "articulated":
        if _cranks(scene) == scene.engine.cylinders / 2:
            forms.append("one_slave")  # a V's pin: one slave rod beside the master (singular)
        forms.append("articulated")  # the master rod's bearing carries the slave rods' forces too
    if scene.engine.cylinders > 1 and _cylinders_share_pins(scene):
        forms.append("bank")
    elif scene.engine.cylinders > 1 and scene.engine.layout == "boxer":
        forms.append("boxer")
    if one_crank and "one_crank" not in forms:
        forms.append("one_crank")
    if scene.engine.layout in ("W", "Y", "X"):
        forms.append("banks")  # the bank angle lies between adjacent banks of three or four
    if getattr(scene.engine, "application", None) == "aircraft":
        forms.append("propeller")  # the propeller takes the flywheel's part
    return tuple(forms)


def text_variant(scene) -> tuple[str, ...]:
    """The variants of the catalogs' texts for ``scene``'s engine (:class:`Translator`): a
    crosshead engine's side force acts on the crosshead's guides (``"crosshead"``); an
    aircraft engine's propeller takes the flywheel's part (``"propeller"``); an outboard motor's
    flywheel is the magneto's rotor with the starter's ring gear (``"outboard"``); a V, W, Y, X,
    boxer or radial engine, whose cylinders lie in more than one plane, is balanced by the
    arrangement of its cylinders and cranks, not of its cranks alone (``"banked"``)."""
    variants = []
    if getattr(scene.engine, "crosshead", False):
        variants.append("crosshead")  # the side force on the crosshead's guides, its pin A
    if getattr(scene.engine, "application", None) == "aircraft":
        variants.append("propeller")
    if getattr(scene.engine, "application", None) == "outboard":
        variants.append("outboard")
    engine = scene.engine
    if getattr(engine, "layout", "inline") != "inline" and getattr(engine, "cylinders", 1) > 1:
        variants.append("banked")
    return tuple(variants)


def _cranks(scene) -> int | None:
    """The number of the engine's cranks, or None for a layout the stages refuse too."""
    if scene.engine.cylinders == 1:
        return 1
    try:
        return engine_layout(scene).cranks
    except SceneError:  # said where the stages refuse it
        return None


def _cylinders_share_pins(scene) -> bool:
    """Whether cylinders share crank pins (a V's or W's banks): the spacing a along the shaft is
    then that of one bank's cylinders, not of neighbouring cylinders (a boxer's alternate banks
    on pins of their own)."""
    if scene.engine.cylinders < 2:
        return False
    try:
        return engine_layout(scene).cylinders_per_bay > 1
    except SceneError:  # a layout the stages refuse too: said there
        return False


def _cited_sources(t, stage, course: bool, references: list[str]) -> str:
    """The sentence citing the sources of ``stage``'s method (added to ``references``); none for
    a section of the project's own method alone, cited in the introduction. A course note cites
    no source of a full report's study (``StagePresentation.references_full``)."""
    look = stage.presentation
    cited = look.references + (() if course else look.references_full)
    for ref in cited:
        if ref not in references:
            references.append(ref)
    if not cited or set(cited) == {PROJECT_METHOD}:
        return ""
    numbers = [references.index(r) + 1 for r in cited]
    return f"<p>{escape(t(look.references_sentence, refs=cite(numbers)))}</p>"


def _unshown_warnings(result, registry, shown_stages) -> list:
    """The warnings of the stages without a section in the note (left out, or run for their data
    only): said with the given data."""
    return [
        w
        for name, stage in registry.stages.items()
        if name not in shown_stages
        for w in stage_warnings(
            stage, result.scene, result.outputs[name].results if name in result.outputs else None
        )
    ]


@dataclass
class _NoteParts:
    """The parts of the note gathered while its stages' sections are rendered."""

    sections: list[SectionView]
    references: list[str]
    appendices: list[SectionView] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    said: set = field(default_factory=set)  # the warnings the note has said
    shown_stages: set[str] = field(default_factory=set)


def _render_context(result, registry, language: str) -> RenderContext:
    """The rendering state of the report of ``result`` in ``language``."""
    scene = result.scene
    return RenderContext(
        t=translator(language, registry.catalogs, text_variant(scene)),
        env=_environment(registry, result),
        table_step_deg=scene.analysis.table_step_deg,
        cycle_deg=scene.engine.cycle_deg,
        scene=scene,
        symbols=symbol_table(registry.stages.values()),  # the core's letters and the stages' own
        run_data={
            contract: value
            for output in result.outputs.values()
            if output is not None
            for contract, value in output.data.items()
        },
    )


def _first_references(t) -> list[str]:
    """The sources cited before any section: the method of the whole project (cited in the
    introduction) and the standards the document follows."""
    references: list[str] = [PROJECT_METHOD]
    references += [key for key in t("doc.standards").split() if key not in references]
    return references


def _stage_section(stage, result, ctx, parts: _NoteParts, sections_cache, figure_sink) -> None:
    """Render one stage's section (in the appendix for a course note's study) and its notes."""
    t, scene = ctx.t, result.scene
    course = scene.report.detail == "course"
    # a study of the numerics (StagePresentation.appendix)
    to_appendix = course and stage.presentation.appendix
    # a course note has one appendix: the studies' short statements go into the core's
    number = appendix_letter(t, 0) if to_appendix else len(parts.sections) + 1
    ctx.start_section(number, stage.name, stage.presentation.figures)
    ctx.conclusions = []
    output = result.study_output(stage.name)  # a deferred study's: received or computed now
    body = _section_body(stage, output, ctx, sections_cache, figure_sink)
    if body is None:  # the stage ran for its data but has nothing to show for this scene
        return
    body = _cited_sources(t, stage, course, parts.references) + landscape_tables_later(body)
    parts.shown_stages.add(stage.name)
    results = output.results if output is not None else None
    found, concluded = plausibility_text(
        t, stage_warnings(stage, scene, results), parts.references, parts.said
    )
    view = SectionView(
        number,
        stage.name,
        ctx.title or t(stage.presentation.title_key),
        Markup(
            lone_subsection_unnumbered(cite_sources(_with_warnings(body, found), parts.references))
        ),
        list(ctx.conclusions) + concluded,
    )
    (parts.appendices if to_appendix else parts.sections).append(view)
    parts.notes += _stage_notes(output, ctx, parts.references)


#: Where a section puts its plausibility sentences, when they judge one of its tables (a bearing
#: pressure beside the table of that bearing); without it they close the section.
PLAUSIBILITY_MARK = "<!-- plausibility -->"


def _with_warnings(body: str, found: str) -> str:
    """The section's ``body`` with its plausibility sentences ``found`` at its mark or at its end."""
    found = str(found)  # the section's body is its rendered markup, taken as it is
    if PLAUSIBILITY_MARK in body:
        return body.replace(PLAUSIBILITY_MARK, found, 1)
    return body + found


def _note_value(t, value):
    """A note's parameter as printed: a number to four digits in the report's locale (a
    :class:`crankdyn.plugin.types.Digits` to its own); a tuple of
    numbers as a list ("0; 120; 240", the decimal comma taken); a tuple of cylinder labels as a
    firing order in the report's letters ("1Л–6П"); a text with its scene keys named."""
    if isinstance(value, float):
        return t.number_g(value, 4)
    if isinstance(value, Digits):
        return t.number_g(value.value, value.significant)
    if isinstance(value, (list, tuple)):
        if all(isinstance(v, float) for v in value):
            return "; ".join(t.number_g(v, 4) for v in value)
        return t.cylinders(value)
    return field_names(t, value)


def _stage_notes(output, ctx, references: list[str]) -> list[str]:
    """The notes a stage's output asks for, their numbers in the report's locale to four
    digits without padding zeros (a given advance of 22° is not "22,00°")."""
    t = ctx.t
    return [
        cite_sources(
            t(
                key,
                **{k: _note_value(t, v) for k, v in params.items()},
            ),
            references,
        )
        for key, params in (output.notes if output is not None else ())
    ]


def _page_html(result, registry, ctx, parts: _NoteParts, language: str) -> str:
    """The report's page from its template, before the whole-document finishing."""
    t, env, scene = ctx.t, ctx.env, result.scene
    course = scene.report.detail == "course"
    skipped = [
        (_stage_title(t, registry, name), skipped_reason(t, reason))
        for name, reason in result.plan.skipped.items()
        if _skip_key(reason) not in UNLISTED_SKIPS
    ]
    sections, appendices, references = parts.sections, parts.appendices, parts.references
    # each stage under its section's title as printed (a stage may retitle its section for the scene)
    shown = {v.key: v.title for v in (*sections, *appendices)}
    title = _title(scene, t)
    mechanism = registry.mechanisms.get(scene.engine.mechanism)
    return env.get_template("report.html.j2").render(
        _=t,
        num=ctx.num,
        scene=scene,
        # λ = R/L only for a mechanism that has a crank radius (not a planetary carrier's a)
        rod_ratio_shown=scene.engine.has_rod
        and not (mechanism is not None and mechanism.input_rows.get("rod_ratio", ()) is None),
        meta=scene.report,
        title=title,
        sections=sections,
        notes=parts.notes,
        timing=_timing_rows(result, shown, t),
        skipped=skipped,
        skipped_sentence=skipped_sentence(t, registry, result) if course else "",
        appendices=appendices,
        course=course,
        numerics_number=(appendix_letter(t, 0) if course else "") or len(sections) + 1,
        references=references,
        css=Markup(report_css(language, scene.report.frame)),
        html_lang=html_language(language),
        standard_refs=[cite([references.index(key) + 1]) for key in t("doc.standards").split()],
        extremum_rtol=ctx.num(EXTREMUM_RTOL, 1),
        appendix_letter=lambda i: appendix_letter(t, i),
        version=__version__,
        generated=datetime.date.today().isoformat(),
        language=language,
        findings=ctx.findings,
        frame=frame_html(env, t, scene.report, title),
        **_abstract_parts(t, registry, scene, sections),
        **_assignment_given(result, registry, ctx),
    )


def render_html(
    result: RunResult,
    registry: Registry,
    language: str | None = None,
    sections_cache=None,
    figure_sink=None,
) -> RenderedReport:
    """The report of ``result``; with a :class:`crankdyn.report.section_cache.SectionCache`
    (the live preview's), sections whose stage output and scene reads did not change are reused.
    ``figure_sink(figures)``, if given, receives each section's figures as soon as the section is
    rendered (e.g. :class:`crankdyn.report.figures.IncrementalDrawing`, drawing them meanwhile)."""
    scene = result.scene
    language = language or scene.report.language
    ctx = _render_context(result, registry, language)
    t = ctx.t
    input_view = _input_view(result, registry, ctx)
    parts = _NoteParts(sections=[input_view], references=_first_references(t))
    given_warnings = plausibility_text(
        t, scene_warnings(scene, registry), parts.references, parts.said
    )
    for stage in result.plan.order:
        if stage.presentation is not None:  # a stage without a section: run for its data alone
            _stage_section(stage, result, ctx, parts, sections_cache, figure_sink)
    found, concluded = plausibility_text(
        t, _unshown_warnings(result, registry, parts.shown_stages), parts.references, parts.said
    )
    input_view.html = Markup(input_view.html + given_warnings[0] + found)
    input_view.conclusions += given_warnings[1] + concluded
    html = _finish(
        fill_section_numbers(
            _page_html(result, registry, ctx, parts, language),
            lambda stage: _stage_title(t, registry, stage),
            t,
            _same_data(registry),
        ),
        t,
        language,
        len(parts.references),
        frozenset(
            s.name for s in result.plan.order if s.presentation is None or not s.presentation.legend
        ),
        forms=_meaning_forms(scene),
        symbols=ctx.symbols,
        strokes=scene.engine.strokes,
    )
    return RenderedReport(
        linked_html=html,
        figures=ctx.figures,
        language=language,
        missing_translations=set(t.missing),
        worked=list(ctx.worked),
    )


def _timing_rows(result, shown: dict, t) -> list[tuple[str, float]]:
    """(title, seconds) of each stage that ran; one that ran without a section (one cylinder's
    engine scheme, its torque) says so (a timing row needs a section to refer to)."""
    return [
        (
            shown.get(s.name) or t("report.timing_no_section", title=_section_title(t, s)),
            result.timing_s[s.name],
        )
        for s in result.plan.order
        if s.name in result.timing_s
    ]


def _abstract_parts(t, registry, scene, sections) -> dict:
    """The abstract's key words and its aim: the note's sections after the input data, each title
    as it heads its section ("; " between them: a title may hold a comma); the introduction's aim
    from what the sections do (:func:`introduction_aim`)."""
    catalogs = [_catalog_section(registry, v.key) for v in sections]
    motion = "" if getattr(scene, "cycle", None) is not None else "_kinematics"
    return {
        "keywords": keywords(
            t,
            mechanism_key(scene.engine, t),
            catalogs,
            motion,
            _meaning_forms(scene),
            engine_keywords(scene, t),
        ),
        "aim": "; ".join(_lower_first(v.title) for v in sections[1:]),
        "introduction_aim": introduction_aim(t, catalogs, motion),
    }


def engine_keywords(scene, t) -> tuple[str, ...]:
    """The key words that name the kind of engine where the mechanism's do not: its layout (a V,
    a boxer, a radial: ``doc.keyword_layout_<layout>``) and an aircraft engine's use."""
    engine = scene.engine
    words = []
    if engine.cylinders > 1 and t.has(f"doc.keyword_layout_{engine.layout}"):
        words.append(t(f"doc.keyword_layout_{engine.layout}"))
    if getattr(engine, "application", None) == "aircraft":
        words.append(t("doc.keyword_aircraft"))
    return tuple(words)


def introduction_aim(t, stages: list[str], motion: str = "") -> str:
    """The introduction's aim: "… by the method of [1]: to determine …, assess … and size the
    flywheel", each section's ``<section>.aim`` (its plugin's catalog) once, in the note's order; a
    note whose sections have none says the aim without them (a kinematics note does not claim to
    determine forces and torques and the engine's balance). ``motion`` "_kinematics": a
    mechanism studied without a working cycle, whose aim is its kinematic analysis."""
    aims = list(dict.fromkeys(t(f"{stage}.aim") for stage in stages if t.has(f"{stage}.aim")))
    if not aims:
        return t(f"doc.introduction_aim{motion}_plain" if motion else "doc.introduction_aim_plain")
    listed = aims[0] if len(aims) == 1 else ", ".join(aims[:-1]) + t("doc.aim_last") + aims[-1]
    return t(f"doc.introduction_aim{motion}", aims=listed)


#: The abstract's key words: DSTU 3008:2015 and GOST 7.32-2017 ask for five to fifteen.
KEYWORDS_MAX = 15


def _catalog_section(registry, stage: str) -> str:
    """The catalog section a stage's texts are in: its title key's (``drawing_linkage`` writes
    with ``drawing``'s catalog)."""
    found = registry.stages.get(stage)
    look = found.presentation if found is not None else None
    return look.title_key.split(".", 1)[0] if look is not None and look.title_key else stage


def mechanism_key(engine, t) -> str:
    """The catalog key (``mechanism.<key>``) of the engine's mechanism as the note describes it:
    with articulated rods, ``<mechanism>_articulated`` where a catalog describes it (a mechanism
    whose cylinder axes meet the shaft's holds that for its master rod only); with several
    cylinders, ``<mechanism>_cylinders`` where a catalog has it."""
    articulated = f"{engine.mechanism}_articulated"
    if getattr(engine, "rod_type", None) == "articulated" and t.has(f"mechanism.{articulated}"):
        return articulated
    several = f"{engine.mechanism}_cylinders"  # "the cylinders' axes pass through …"
    if (getattr(engine, "cylinders", 1) or 1) > 1 and t.has(f"mechanism.{several}"):
        return several
    return engine.mechanism


def keywords(
    t,
    mechanism: str,
    stages: list[str],
    motion: str = "",
    forms: tuple[str, ...] = (),
    engine: tuple[str, ...] = (),
) -> str:
    """The abstract's key words, upper case, for what this report holds: the calculation and the
    engine (``doc.keyword_general``, comma-separated), the mechanism (its description in the
    catalog, up to the colon) and each section's own words (``<section>.keywords`` in its
    plugin's catalog, comma-separated; a stage without them adds none). A report of the
    kinematics alone has five; a mechanism without a working cycle is named by its kinematic
    analysis (``motion`` "_kinematics"), not by an engine's dynamic calculation. A section's
    words for the engine's ``forms`` come first (``<section>.keywords_<form>``: an aircraft
    engine's propeller where another has a flywheel). ``engine``: the words that name the kind of
    engine, after the mechanism (:func:`engine_keywords`)."""
    words = [w.strip() for w in t(f"doc.keyword_general{motion}").split(",")]
    if t.has(f"mechanism.{mechanism}"):
        words.append(t(f"mechanism.{mechanism}").split(":", 1)[0])
    words += list(engine)
    for stage in stages:
        key = next(
            (f"{stage}.keywords_{form}" for form in forms if t.has(f"{stage}.keywords_{form}")),
            f"{stage}.keywords",
        )
        if t.has(key):
            words += [w.strip() for w in t(key).split(",") if w.strip()]
    unique = list(dict.fromkeys(w.upper() for w in words))
    return ", ".join(unique[:KEYWORDS_MAX])


def _lower_first(title: str) -> str:
    """A section's title inside a sentence: "кінематика …" for "Кінематика …", an abbreviation
    ("ВМТ …") kept."""
    return title[:1].lower() + title[1:] if len(title) > 1 and title[1].islower() else title


def _title(scene, t) -> str:
    """The scene's title; a scene without one gets the report language's (the model's default is English)."""
    return (
        scene.report.title if "title" in scene.report.model_fields_set else t("doc.default_title")
    )


def _finish(
    html: str,
    t,
    language: str,
    sources: int,
    without_legend: frozenset[str],
    forms: tuple[str, ...] = (),
    symbols: SymbolTable = SYMBOLS,
    strokes: int = 4,
) -> str:
    """What needs the whole document: the abstract's counts, the typesetting, the equations'
    "where" lines and the list of the symbols shown (``forms``: the engine's forms of the
    meanings, :func:`_meaning_forms`;
    ``strokes``: a two-stroke engine's meanings of the cycle, :func:`_cycle_meanings`)."""
    t = _cycle_meanings(t, strokes)
    html = _fill_counts(html, t, sources)
    html = by_sections(
        _typeset_part, html, language, tuple(report_units(t)), t.decimal_separator, symbols
    )
    html = add_equation_legends(html, t, language, without_legend, forms, symbols)
    return by_sections(_unbreakable_part, _fill_symbol_list(html, t, language, forms, symbols))


#: Where the document's sections start (each at the start of a line, in report.html.j2).
_SECTION_START = re.compile(r'(?m)^(?=<section class=")')
_SKIPPED_TAG = re.compile(r"<(/?)(?:script|style|title)\b", re.I)


def _balanced(part: str) -> bool:
    """Whether ``part`` closes every ``<script>``, ``<style>`` and ``<title>`` it opens."""
    depth = 0
    for m in _SKIPPED_TAG.finditer(part):
        depth += -1 if m.group(1) else 1
    return depth == 0


def by_sections(transform, html: str, *args) -> str:
    """``transform(html, *args)`` for a pass over text nodes, applied section by section.

    Each part is a pure function of its text, so a part met before (the live preview renders the
    report again after each save, mostly with the same sections) is taken from the transform's
    cache instead of being typeset again. Split only where no script, style or title is open
    (the passes skip their text), else the whole document is transformed at once.
    """
    parts = _SECTION_START.split(html)
    if len(parts) == 1 or not all(_balanced(p) for p in parts):
        return transform(html, *args)
    return "".join(transform(part, *args) for part in parts)


#: Sections kept typeset: a report's sections in a few languages (the preview's saves), not more
#: (a batch worker renders many variants' sections that never come again).
_TYPESET_PARTS = 128


@functools.lru_cache(maxsize=_TYPESET_PARTS)
def _typeset_part(
    part: str, language: str, units: tuple[str, ...], decimal: str, symbols: SymbolTable = SYMBOLS
) -> str:
    return typeset_html(part, language, list(units), decimal, symbols)


@functools.lru_cache(maxsize=_TYPESET_PARTS)
def _unbreakable_part(part: str) -> str:
    return unbreakable_html(part)


_LANDSCAPE_BLOCK = re.compile(r'<div class="table-block[^"]*\blandscape\b[^"]*">.*?</div>', re.S)
_TABLE_BLOCK = re.compile(r'<div class="table-block')
_TABLE_BLOCK_WHOLE = re.compile(r'<div class="table-block[^"]*">.*?</div>', re.S)
#: a worked check right after a table: it refers to the table's row, so it moves with the table
_WORKED_BLOCK_WHOLE = re.compile(r'<div class="worked">.*?</div>', re.S)
_DIV_TAG = re.compile(r"<(/?)div\b")


def _same_level(html: str) -> bool:
    """Whether ``html`` opens and closes its own ``div``s (never closes one it did not open)."""
    depth = 0
    for m in _DIV_TAG.finditer(html):
        depth += -1 if m.group(1) else 1
        if depth < 0:
            return False
    return depth == 0


def landscape_tables_later(body: str) -> str:
    """Each landscape table (with any tables right after it) moved past the text and figures that
    follow it in its section, up to the next numbered table (the numbers stay in order) or the
    section's end; not when that next table is a landscape one too.

    A landscape page is a page of its own: the portrait page before it ends where the table
    starts and would be left short. Moved after the portrait material that follows it, the
    table (with the sentence that announces it) lets that material fill the page first."""
    position = 0
    while (m := _LANDSCAPE_BLOCK.search(body, position)) is not None:
        group_end = m.end()
        while True:  # the tables (numbers in order) and worked checks right after it go with it
            gap = len(body) - group_end - len(body[group_end:].lstrip())
            more = _TABLE_BLOCK_WHOLE.match(body, group_end + gap) or _WORKED_BLOCK_WHOLE.match(
                body, group_end + gap
            )
            if more is None:
                break
            group_end = more.end()
        group, rest = body[m.start() : group_end], body[group_end:]
        following = _TABLE_BLOCK.search(rest)
        between = rest[: following.start() if following else len(rest)]
        # before another landscape table it stays: the text between them shares their landscape pages
        next_landscape = (
            following is not None and _LANDSCAPE_BLOCK.match(rest, following.start()) is not None
        )
        if not between.strip() or not _same_level(between) or next_landscape:
            position = group_end
            continue
        split = _after_last_figure(between)
        if split is not None and between[split:].strip():
            # the text after the last figure (as a rule a few lines that would stand alone on a
            # portrait page: 15 % of page 31 of the en in-line four) leads the table onto its page
            moved = between[:split] + f'<div class="landscape-lead">{between[split:]}</div>' + group
        else:
            moved = between + group
        body = body[: m.start()] + moved + rest[len(between) :]
        position = m.start() + len(moved)
    return body


_FIGURE_CLOSE = re.compile(r"\s*</div>")


def _after_last_figure(html: str) -> int | None:
    """Where the material after the last figure block (or row of figures) of ``html`` starts;
    None without a figure at the level of ``html``."""
    end = html.rfind("</figure>")
    if end < 0:
        return None
    k = end + len("</figure>")
    while not _same_level(html[:k]):
        close = _FIGURE_CLOSE.match(html, k)
        if close is None:
            return None
        k = close.end()
    return k if _same_level(html[k:]) else None


def _stage_title(t, registry: Registry, name: str) -> str:
    stage = registry.stages.get(name)
    return _section_title(t, stage) if stage is not None else name


def _section_title(t, stage) -> str:
    """The title of ``stage``'s section, or its name for a stage without one."""
    look = stage.presentation
    return t(look.title_key) if look is not None and look.title_key else stage.name


def _fill_counts(html: str, t, sources: int) -> str:
    """The abstract's counts of figures, tables and sources, counted in the document itself."""
    figures = len(set(re.findall(r'<figure data-number="([^"]+)"', html)))
    tables = len(set(re.findall(r'<table class="[^"]*" data-number="([^"]+)"', html)))
    appendices = len(re.findall(r'<section class="chapter appendix"', html))
    counts = t(
        "doc.abstract_counts",
        pages='<span class="abstract-pages">'
        + t("doc.abstract_pages", pages='<a class="pagecount" href="#document-end"></a>')
        + "</span>",
        figures=figures,
        tables=tables,
        sources=sources,
        appendices=t("doc.abstract_appendices", count=appendices) if appendices else "",
    )
    return html.replace("@@ABSTRACT_COUNTS@@", counts)


#: The suffix of a symbol's meaning for a two-stroke engine ("symbol.cycle_angle_two_stroke"):
#: it takes the place of the plain meaning, which states the four-stroke cycle.
_TWO_STROKE_SUFFIX = "_two_stroke"


def _cycle_meanings(t, strokes: int):
    """``t`` with the symbols' meanings of the engine's own cycle: for a two-stroke engine each
    "symbol.<key>_two_stroke" in place of "symbol.<key>"; ``t`` itself for a four-stroke one."""
    if strokes != 2:
        return t

    def own(texts: dict) -> dict:
        return {
            **texts,
            **{
                key[: -len(_TWO_STROKE_SUFFIX)]: text
                for key, text in texts.items()
                if key.startswith("symbol.") and key.endswith(_TWO_STROKE_SUFFIX)
            },
        }

    return dataclasses.replace(t, texts=own(t.texts), fallback=own(t.fallback))


def symbol_list_html(
    keys,
    t,
    language: str,
    abbreviations: bool = True,
    places: dict | None = None,
    forms: tuple[str, ...] = (),
    symbols: SymbolTable = SYMBOLS,
) -> str:
    """The list of symbols: one line per symbol, "symbol – meaning, unit", then the abbreviations
    (paragraphs, not a table: the Word export gives every table a repeated header row). A letter
    whose markup the list shows with another meaning too, and which holds in some sections only (a
    stage's own letter, ``StagePresentation.symbols``, or a core symbol's ``Symbol.sections``), says where it
    holds, from ``places`` (stage -> [("section", "2", its HTML), ...]) where its section shows it:
    "k – відносний дезаксаж (у розділі 2)", "δ – коефіцієнт нерівномірності обертання (у розділах 8 і 9)"."""
    keys, markups = _distinct_meanings(keys, t, language, forms, symbols)
    magnitudes = _vector_magnitudes(markups, [symbols[key].unit for key in keys])
    rows = []
    for key, markup in zip(keys, markups, strict=True):
        if markup in magnitudes.values():
            continue  # said in its vector's row
        unit = list_unit(key, t, symbols)
        meaning = symbol_meaning(t, key, forms)
        where = (
            _where(_symbol_stages(key, symbols), places or {}, t, markup)
            if markups.count(markup) > 1
            else ""
        )
        if where:
            meaning += f" ({where})"
        meaning = italic_letters(str(escape(meaning)), language)
        if markup in magnitudes:
            meaning = (
                str(escape(t("doc.symbol_vector_magnitude", vector="@@V@@", plain="@@P@@")))
                .replace("@@V@@", meaning)
                .replace("@@P@@", magnitudes[markup])
            )
        meaning += f", {escape(unit)}" if unit else ""
        rows.append(
            f'<p class="symbol-row"><span class="symbol">{markup}</span> – '
            f'<span class="meaning">{meaning}</span></p>'
        )
    # the handier units the list itself uses (a kinematics note has no МПа, см² or л)
    handy = ("unit.mm", "unit.MPa", "unit.cm2", "unit.l")
    used = {symbols[key].unit for key in keys}
    units = ", ".join(t(unit) for unit in handy if unit in used) or t("unit.mm")
    intro = t("doc.symbols_intro", units=units)
    html = f'<p>{escape(intro)}</p><div class="symbol-list">{"".join(rows)}</div>'
    if abbreviations:
        html += f'<p class="abbreviations">{escape(t("doc.symbols_abbreviations"))}</p>'
    return html


def _distinct_meanings(keys, t, language: str, forms, symbols: SymbolTable):
    """(keys, their markups) without a key whose letter, meaning and unit an earlier one has:
    two plugins that declare the same quantity (φ of the offset crank-slider, in its kinematics
    and in its bearings) give it one row, which holds throughout."""
    kept, markups, seen = [], [], set()
    for key in keys:
        markup = symbol_html(key, language, symbols)
        said = (markup, symbol_meaning(t, key, forms), list_unit(key, t, symbols))
        if said not in seen:
            seen.add(said)
            kept.append(key)
            markups.append(markup)
    return kept, markups


def _vector_magnitudes(markups: list[str], units: list[str]) -> dict[str, str]:
    """A vector's bold markup -> its magnitude's, the same letters in light type and the same
    unit, where the list shows both: one row says both (q_ш.ш, the vector of the crank pin's load,
    and its magnitude), so that one letter is not listed twice. A light letter of another unit is
    another quantity (θ, the shaft angle in degrees, beside the torsion's vector of disc angles in
    radians) and keeps its own row, as does one beside a bold letter of no unit: a matrix (Φ of
    the mode shapes beside Φ, the cycle's angle) or a unit vector has no magnitude to list."""
    unit_of = dict(zip(markups, units, strict=True))
    found = {}
    for markup in markups:
        plain = markup.replace("<b>", "").replace("</b>", "")
        if plain != markup and unit_of[markup] and unit_of.get(plain) == unit_of[markup]:
            found[markup] = plain
    return found


def list_unit(key: str, t, symbols: SymbolTable) -> str:
    """A symbol's unit in the list of symbols: the tables' unit, and the SI unit the "where" lines
    give where the equations take the quantity in another ("МПа (в формулах – Па)"), so that the
    list and the lines under the equations never seem to disagree."""
    unit = symbol_unit(key, t, symbols)
    in_formulas = line_unit(key, t, symbols)
    if not unit or in_formulas == unit:
        return unit
    return t("doc.symbols_unit_in_formulas", unit=unit, si=in_formulas)


def _symbol_stages(key: str, symbols: SymbolTable) -> tuple[str, ...]:
    """The stages whose sections a symbol's meaning holds in: a stage's own symbol its stage, a
    core symbol those it declares (none: it holds throughout)."""
    if "." in key:
        return (key.split(".", 1)[0],)
    symbol = symbols.get(key)
    return tuple(symbol.sections) if symbol is not None else ()


def _where(stages, places: dict, t, markup: str) -> str:
    """ "у розділах 5 і 8, у додатку А": the sections and appendices of ``stages`` in this report
    that show ``markup`` (a meaning declared for a section that does not use the letter is not
    said to hold there)."""
    shown = re.compile(re.escape(markup) + r"(?!<sub>|<sup>[′″]|[′″])")
    found = [
        (kind, value)
        for stage in stages
        for kind, value, body in places.get(stage, ())
        if shown.search(body)
    ]
    numbers = sorted({value for kind, value in found if kind == "section"}, key=int)
    letters = sorted({value for kind, value in found if kind == "appendix"})
    parts = []
    if numbers:
        parts.append(
            t("doc.symbol_in_section", number=numbers[0])
            if len(numbers) == 1
            else t("doc.symbol_in_sections", numbers=t.join_and(numbers))
        )
    if letters:
        parts.append(
            t("doc.symbol_in_appendix", letter=letters[0])
            if len(letters) == 1
            else t("doc.symbol_in_appendices", letters=t.join_and(letters))
        )
    return ", ".join(parts)


#: A numbered chapter or an appendix of the document, with the stage it shows.
_CHAPTER = re.compile(
    r'<section class="chapter( appendix)?" id="sec-[^"]*" data-stage="([^"]+)">\s*'
    r"<h2[^>]*>(?:(\d+) |[^<]*?(\w+)<br>)"
)


#: ``@@SECTION:kinematics@@`` in a catalog text: the number of that stage's section in this report
#: ("див. розділ 2"; "см. раздел кинематики" names no section).
SECTION_MARK = re.compile(r"@@SECTION:(\w+)@@")
#: ``@@TABLE:torque:1@@``: ", табл. 7.1", that stage's k-th table in this report, or nothing when
#: the stage has no section here (the sentence then names the section alone)
TABLE_MARK = re.compile(r"@@TABLE:(\w+):(\d+)@@")


def _same_data(registry):
    """``providers(stage)``: the stages that provide what ``stage`` provides (an offset
    crank-slider's own stage gives the piston motion the kinematics stage gives a central one)."""

    def providers(stage: str) -> list[str]:
        found = registry.stages.get(stage)
        provides = set(found.provides) if found is not None else set()
        return [name for name, s in registry.stages.items() if provides & set(s.provides)]

    return providers


def fill_section_numbers(html: str, title, t, providers=None) -> str:
    """Each :data:`SECTION_MARK` replaced by its stage's section number, or, when that stage has
    no section here, the number of a section whose stage provides the same data
    (``providers(stage)``); else by the section's title (``title(stage)``) in quotes (the
    sentence then still reads)."""
    if "@@SECTION:" not in html and "@@TABLE:" not in html:
        return html
    numbers = {
        stage: number
        for appendix, stage, number, _ in _CHAPTER.findall(html)
        if number and not appendix
    }

    def number(m: re.Match) -> str:
        stage = m.group(1)
        if stage in numbers:
            return numbers[stage]
        for other in providers(stage) if providers is not None else ():
            if other in numbers:
                return numbers[other]
        return t("doc.quoted", text=title(stage))

    def table(m: re.Match) -> str:
        stage = m.group(1)
        if stage not in numbers:
            return ""
        return t("doc.table_reference", number=f"{numbers[stage]}.{m.group(2)}")

    return SECTION_MARK.sub(number, TABLE_MARK.sub(table, html))


def _places(html: str) -> dict[str, list[tuple[str, str, str]]]:
    """stage -> where its sections stand, with each section's HTML: ("section", "2", html) or
    ("appendix", "Б", html), the appendix's letter as its heading prints it."""
    found: dict[str, list[tuple[str, str, str]]] = {}
    chapters = list(_CHAPTER.finditer(html))
    for m, following in zip(chapters, [*chapters[1:], None], strict=True):
        appendix, stage, number, letter = m.groups()
        body = html[m.start() : following.start() if following else len(html)]
        if number and not appendix:
            found.setdefault(stage, []).append(("section", number, body))
        elif appendix and letter:
            found.setdefault(stage, []).append(("appendix", letter, body))
    return found


_ASSIGNMENT = re.compile(r'<section class="assignment">.*?</section>', re.S)


def _fill_symbol_list(
    html: str, t, language: str, forms: tuple[str, ...] = (), symbols: SymbolTable = SYMBOLS
) -> str:
    """The list of symbols with those the (typeset) report shows, from the one symbol table."""
    head, _, rest = html.partition("@@SYMBOL_LIST@@")
    # the assignment sheet repeats the given data with the core's letters (S = 100 мм); the given
    # data's section names them as the mechanism does (a vane engine's S is its slider's travel)
    body = _ASSIGNMENT.sub("", head.split("<body", 1)[-1]) + rest
    abbreviation = t("doc.symbols_abbreviations").split(",", 1)[0]
    return (
        head
        + symbol_list_html(
            symbols_used(body, language, symbols),
            t,
            language,
            abbreviation in body,
            _places(rest),
            forms,
            symbols,
        )
        + rest
    )
