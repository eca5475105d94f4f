"""Every symbol a displayed equation shows is in the one symbol table (so the list of symbols has it
and a "where" line explains it under its first equation), and no letter has two meanings within
one section (not θ, f_n, ξ_i, q_ш.ш, R_j, l′_i … with only a "Здесь …" paragraph; not i as
the imaginary unit and the summation index of one formula, A/B as the hodograph's semi-axes beside
A_n and the bearing width B, z as the radial force and the position along the shaft)."""

from __future__ import annotations

import re
from collections import defaultdict

import pytest
from conftest import shared_html

from crankdyn.plugin.registry import default_registry
from crankdyn.report import equation_legend, typeset
from crankdyn.report.equation_legend import _SECTION_OR_EQUATION
from crankdyn.report.i18n import translator

#: The table a report of the installed plugins reads: the core's symbols and the stages' own.
SYMBOLS = typeset.symbol_table(default_registry().stages.values())


def symbols_in(formula: str, language: str, stage: str) -> list[str]:
    return equation_legend.symbols_in(formula, language, stage, SYMBOLS)


def symbol_html(key: str, language: str) -> str:
    return typeset.symbol_html(key, language, SYMBOLS)


EXAMPLES = ("inline4-petrol", "v8-petrol", "petrol-1cyl-uk")
#: The stages whose letters are their own (Stage.symbols): the rod dynamics (offset crank), the
#: articulated rods (radial), the torsional model, the offset crank, the kinematics study, the vane
#: engine and the planetary mechanism (the only examples of these two stages); read in the textbook's
#: Cyrillic subscripts and in the Latin ones (ru writes its subscripts as uk does).
STAGE_EXAMPLES = (
    "offset-crank-engine",
    "radial9-aircraft",
    "inline4-torsion",
    "kinematics-only",
    "vane-engine-kinematics",
    "planetary-kinematics",
)
LANGUAGES = ("uk", "ru", "en")

#: A symbol as an equation writes it: an italic (or bold) letter, its primes and subscript; an
#: upright bold letter (the rotation matrix Π, the unit vectors e).
_TOKEN = re.compile(
    r"(?:<b>)?Δ?<i>[^<]+</i>(?:</b>)?[′″]?(?:<sub>(?:[^<]|<i>[^<]*</i>)*</sub>)?[′″]?"
    r"|<b>[^<]+</b>(?:<sub>(?:[^<]|<i>[^<]*</i>)*</sub>)?"
)
_RUN = re.compile(r"<i>([^<]{2,})</i>")
_SCRIPT = re.compile(r"<(sub|sup)>(?:[^<]|<i>[^<]*</i>|<sub>[^<]*</sub>)*?</\1>")
#: an instance of an indexed symbol (A_2 of A_n, H_1 of H_k)
_NUMBERED = re.compile(r"^<i>(\w)</i><sub>\d+</sub>$")


def _equations(html: str):
    """(stage, formula) of each displayed equation of a report."""
    stage = ""
    for m in _SECTION_OR_EQUATION.finditer(html):
        if m.group("stage") is not None:
            stage = m.group("stage")
        else:
            yield stage, m.group("formula")


def _tokens(formula: str) -> list[str]:
    """The symbols ``formula`` shows, a product in one italic run read letter by letter; a bare
    letter inside a sub- or superscript is an index or exponent, not a symbol."""
    formula = _RUN.sub(
        lambda m: "".join(f"<i>{c}</i>" for c in re.findall(r"\S[\u0300-\u036f]*", m.group(1))),
        formula,
    )
    scripts = [m.span() for m in _SCRIPT.finditer(formula)]
    return [
        t.group(0)
        for t in _TOKEN.finditer(formula)
        if "<sub>" in t.group(0) or not any(a < t.start() < b for a, b in scripts)
    ]


def _indexed_symbol(token: str, language: str, stage: str) -> bool:
    m = _NUMBERED.match(token)
    if not m:
        return False
    return any(
        symbols_in(symbol_html(key, language), language, stage) == [key]
        for key, symbol in SYMBOLS.items()
        if symbol.base == m.group(1)
        and re.search(r"<sub><i>\w</i></sub>$", symbol_html(key, language))
    )


@pytest.mark.parametrize(
    "example, language",
    [(e, lang) for e in EXAMPLES for lang in LANGUAGES]
    + [(e, lang) for e in STAGE_EXAMPLES for lang in ("uk", "en")],
)
def test_every_symbol_of_an_equation_is_in_the_symbol_table(example, language):
    missing = set()
    for stage, formula in _equations(shared_html(example, language=language).linked_html):
        for token in _tokens(formula):
            if not symbols_in(token, language, stage) and not _indexed_symbol(
                token, language, stage
            ):
                missing.add((stage, token))
    assert not missing, sorted(missing)


def test_a_markup_has_one_meaning_in_each_section():
    """Two symbols of one markup (p: the cylinder pressure, and the bearing pressure in the bearings
    section) never both apply in one section."""
    by_markup = defaultdict(list)
    for key, symbol in SYMBOLS.items():
        for language in LANGUAGES:
            by_markup[(language, symbol_html(key, language))].append(symbol.sections)
    for (_, markup), sections in by_markup.items():
        assert sum(1 for s in sections if not s) <= 1, markup
        scoped = [stage for s in sections for stage in s]
        assert len(scoped) == len(set(scoped)), markup


@pytest.mark.parametrize("language", LANGUAGES)
def test_no_letter_has_two_meanings_within_a_section(language):
    """Within one section a letter is not both a quantity and the imaginary unit or an index of the
    same formula, and a bare letter is not beside the same letter with another meaning's
    subscript: the hodograph's semi-axes are a_e, b_e (A_n, B: other quantities), the position
    along the shaft x_i (z_i: the radial force), the imaginary unit an upright j (i numbers the
    cylinders)."""
    html = shared_html("inline4-petrol", language=language).linked_html
    balancing = [f for stage, f in _equations(html) if stage == "balancing"]
    assert balancing and not any(re.search(r"e<sup>−?i", f) for f in balancing)
    assert any("e<sup>j" in f for f in balancing)
    assert not any(re.search(r"<i>[AB]</i>(?!<sub>)", f) for f in balancing)
    assert not any("<i>z</i><sub>" in f for f in balancing)
    keys_by_stage = defaultdict(set)
    for stage, formula in _equations(html):
        keys_by_stage[stage].update(symbols_in(formula, language, stage))
    for stage, keys in keys_by_stage.items():
        markups = [symbol_html(key, language) for key in keys]
        assert len(markups) == len(set(markups)), (stage, sorted(keys))


def test_the_new_symbols_are_explained_under_their_first_equation():
    ru = translator("ru", default_registry().catalogs)
    # the full report: the error study's relative error ε_X is a symbol of its numerics chapter
    html = shared_html("inline4-petrol", {"report": {"detail": "full"}}, language="ru").linked_html
    for key in (
        "shaft_angle",
        "crank_lag",
        "cylinder_axis_angle",
        "cylinder_position",
        "pin_load_vector",
        "rod_bearing_load_vector",
        "rotation_matrix",
        "journal_load_vector",
        "span_after",
        "rim_width",
        "relative_error",
        "hodograph_semi_axis_x",
    ):
        line = f'<span class="where-line">{symbol_html(key, "ru")} – '
        assert line in html, key
        assert ru(f"symbol.{key}").split(" (")[0] in re.sub(
            r"</?i>", "", html
        )  # (its letters in italics)


def test_the_symbols_paragraphs_say_no_meaning_twice():
    """The "Здесь …" paragraphs under the balancing and bearings equations keep the conventions
    only: what a symbol means is said by its "where" line."""
    html = shared_html("inline4-petrol", language="ru").linked_html
    plain = re.sub(r"<[^>]+>", "", html)
    assert "Здесь θ – угол поворота" not in plain
    assert "Здесь q – удельная нагрузка" not in plain
    assert "A и B – горизонтальная" not in plain
    assert "l′i + l″i = li" in plain  # a convention the lines do not say


def test_a_sections_own_letters_keep_their_meaning_there():
    """The planetary note's list of symbols must not call a "the distance between adjacent
    cylinder axes" and θ "the crank angle from cylinder 1's TDC" (the carrier's arm and the
    planet's angle there), nor give the rod dynamics' torque M the error study's meaning. The
    balancing and error-study letters are read in their sections only."""
    import re

    from conftest import shared_html

    planetary = shared_html("planetary-kinematics", language="uk").linked_html
    assert "відстань між осями сусідніх циліндрів" not in planetary
    assert "кут повороту колінчастого вала від ВМТ першого циліндра" not in planetary
    offset = shared_html("offset-crank-engine", language="uk").linked_html
    rod = offset[offset.find('data-stage="rod_dynamics"') :]
    rod = rod[: rod.find("</section>")]
    assert not re.search(r"<i>M</i> – сумарний індикаторний крутний момент", rod)
    four = shared_html("inline4-petrol", language="uk").linked_html
    assert "відстань між осями сусідніх циліндрів" in four and "від ВМТ першого циліндра" in four


def test_the_error_tables_count_of_angles_is_not_the_series_n():
    """The uk check: "N" counted the angles in table Б.1 and the series' terms in (Б.2)."""
    from conftest import shared_html

    html = shared_html("petrol-1cyl", {"report": {"detail": "full"}}, language="uk").linked_html
    # (N heads the side force's column of the forces section: the letter of that quantity only)
    study = html[html.index('data-stage="numerics"') :]
    assert "<th>Кількість кутів</th>" in study and "<th><i>N</i></th>" not in study


def test_every_stage_symbol_has_a_meaning_in_every_language():
    """A stage's own letters (StagePresentation.symbols) are explained from its plugin's catalogs, as
    ``symbol.<stage>.<key>``, in each report language; a meaning is plain text (no "_" the list
    would print as it is)."""
    registry = default_registry()
    declared = [
        f"{stage.name}.{key}"
        for stage in registry.stages.values()
        if stage.presentation is not None
        for key in stage.presentation.symbols
    ]
    assert len(declared) >= 58 and all(key in SYMBOLS for key in declared)
    for language in LANGUAGES:
        t = translator(language, registry.catalogs)
        for key in declared:
            assert t.has(f"symbol.{key}"), (language, key)
            assert "_" not in t(f"symbol.{key}"), (language, key)


def test_a_stage_symbol_key_must_be_an_identifier():
    from crankdyn.errors import PluginError
    from crankdyn.plugin.types import Stage, StagePresentation, Symbol

    def stage(symbols):
        return Stage(
            name="odd",
            requires=(),
            provides=(),
            applies=lambda scene: None,
            run=lambda scene, inputs: None,
            presentation=StagePresentation(
                title_key="odd.title", render=lambda output, ctx: None, symbols=symbols
            ),
        )

    with pytest.raises(PluginError, match="'bad key'"):
        typeset.symbol_table([stage({"bad key": Symbol("x", {}, "")})])
    with pytest.raises(PluginError, match="'x'"):
        typeset.symbol_table([stage({"x": ("x", "mm")})])


@pytest.mark.parametrize("language, note", [("uk", "у розділі 2"), ("en", "in section 2")])
def test_a_stage_letter_listed_with_another_meaning_says_where_it_holds(language, note):
    """The offset crank's k = e/L beside the force along the rod k: the list of symbols says in
    which section the stage's own k holds."""
    html = shared_html("offset-crank-engine", language=language).linked_html
    listed = html[html.index('<div class="symbol-list">') :]
    listed = listed[: listed.index("</div>")]
    t = translator(language, default_registry().catalogs)
    rows = re.findall(
        r'<span class="symbol"><i>k</i></span> – <span class="meaning">([^<]*)</span>', listed
    )
    assert f"{t('symbol.offset_crank.offset_ratio')} ({note})" in rows and len(rows) == 2
    # a letter the list shows once keeps its meaning as it is
    assert f'<i>e</i></span> – <span class="meaning">{t("symbol.offset_crank.offset")},' in listed


def test_the_list_of_symbols_gives_a_taken_over_letter_only_the_meaning_it_has():
    """A core symbol whose letter a stage takes over in its section is listed only if the report
    shows it elsewhere (the vane engine's μ is no torque non-uniformity); a symbol of some sections
    only if it stands in one of them (the rod dynamics' M is not the error study's total torque).
    The vane's points (O₃, P, B′) are names, upright, not quantities."""
    vane = shared_html("vane-engine-kinematics", language="uk").linked_html
    listed = vane[vane.index('id="sec-symbols"') :]
    listed = listed[: listed.index("</section>")]
    assert "коефіцієнт нерівномірності крутного моменту" not in listed
    assert "відношення кутової швидкості осердя до кутової швидкості кривошипів" in listed
    assert "<i>y</i><sub>p</sub> = O<sub>3</sub>P = " in vane and "<i>O</i>" not in vane
    planetary = shared_html("planetary-kinematics", language="uk").linked_html
    listed = planetary[planetary.index('id="sec-symbols"') :]
    assert "сумарний індикаторний крутний момент" not in listed[: listed.index("</section>")]


def test_a_mechanism_names_the_given_data_its_own_way():
    """The vane note's table of given data speaks of no piston stroke, crank radius R or
    connecting rod L, and its list of symbols gives S, λ, ω one meaning each. The mechanism
    names those rows (Mechanism.input_rows) as its section does, and its letters hold there too."""
    html = shared_html("vane-engine-kinematics", language="uk").linked_html
    given = html[html.index('data-stage="input"') :]
    given = given[: given.index("</table>")]
    for row in (
        "Хід повзуна вздовж паза куліси",
        "Радіус кривошипів",
        "Довжина хвостовика осердя",
        "<i>r</i> = <i>S</i>/",
    ):
        assert row in given, row
    assert "Довжина шатуна" not in given and "<i>R</i> = " not in given
    listed = html[html.index('<div class="symbol-list">') :]
    listed = listed[: listed.index("</div>")]
    for letter in ("S", "λ", "ω", "l", "r"):
        assert listed.count(f'<span class="symbol"><i>{letter}</i></span>') == 1, letter
    # a piston engine's list keeps the crank-slider's meanings (the vane's letters are not in its report)
    petrol = shared_html("petrol-1cyl", language="uk").linked_html
    assert "хід повзуна" not in petrol and "Хід поршня" in petrol


#: A numbered instance of a symbol indexed by i: t_w1 of t_wi, z_3 of z_i.
_NUMBERED_INSTANCE = re.compile(r"^<i>(\w)</i><sub>(\w*?)\d+</sub>$")
_SECTION_START = re.compile(r'<section class="chapter[^"]*" id="[^"]*" data-stage="([^"]+)">')


def _instance_of_an_indexed_symbol(token: str, language: str, stage: str) -> bool:
    m = _NUMBERED_INSTANCE.match(token)
    return bool(m) and bool(
        symbols_in(f"<i>{m.group(1)}</i><sub>{m.group(2)}<i>i</i></sub>", language, stage)
    )


@pytest.mark.parametrize("example, language", [(e, lang) for e in EXAMPLES for lang in LANGUAGES])
def test_every_symbol_of_a_table_header_or_caption_is_in_the_symbol_table(example, language):
    """p_теор, p_max, ΣP/C_n, mr, t_max … head table columns and must be defined.
    Every letter a table's header or caption shows is in the one symbol table (so in
    the list of symbols), with its meaning in that section; a crank's column (t_w1) is the
    numbered instance of its symbol (t_wi)."""
    html = shared_html(example, language=language).linked_html
    starts = [(m.start(), m.group(1)) for m in _SECTION_START.finditer(html)]
    missing = set()
    for m in re.finditer(r"<th[^>]*>(.*?)</th>|<caption[^>]*>(.*?)</caption>", html, flags=re.S):
        stage = next((name for start, name in reversed(starts) if start < m.start()), "")
        for token in _tokens(m.group(1) or m.group(2)):
            if not (
                symbols_in(token, language, stage)
                or _indexed_symbol(token, language, stage)
                or _instance_of_an_indexed_symbol(token, language, stage)
            ):
                missing.add((stage, token))
    assert not missing, sorted(missing)


#: An in-line six with a flywheel: the letters of every section of a course note in one report.
_SIX = {"engine": {"cylinders": 6, "firing_order": [1, 5, 3, 6, 2, 4]}, "torsion": None}
_ROW = re.compile(
    r'<p class="symbol-row"><span class="symbol">(.*?)</span> – <span class="meaning">(.*?)</span>'
)
_WHERE = re.compile(r'<span class="where-line">(.*?) – (.*?)[;.]</span>')
_UNIT_IN_FORMULAS = {"uk": " (у формулах – {})", "ru": " (в формулах – {})"}


def _plain(html: str) -> str:
    return re.sub(r"<[^>]+>", "", html).replace("\u2060", "")


@pytest.mark.parametrize("language", ["uk", "ru"])
def test_a_note_gives_each_letter_one_meaning_and_its_where_lines_the_lists_units(language):
    """The list of symbols of a six-cylinder note with a flywheel names each symbol once (n the
    crank speed, N the side force, ν the order of a harmonic, δ the irregularity alone, p the gas
    pressure alone); every "where" line's unit is the list's unit of that symbol, or the unit of the
    equations the list gives beside it ("МПа (в формулах – Па)")."""
    html = shared_html("inline4-petrol", _SIX, language=language).linked_html
    listed = html[html.index('<div class="symbol-list">') :]
    listed = listed[: listed.index("</div>")]
    rows = _ROW.findall(listed)
    markups = [markup for markup, _ in rows]
    assert [m for m in set(markups) if markups.count(m) > 1] == []
    for key in ("crank_speed", "side_specific", "harmonic_order", "irregularity"):
        assert symbol_html(key, language) in markups, key
    assert "post_expansion_ratio" not in typeset.symbols_used(html, language, SYMBOLS)
    t = translator(language)
    units = {t(key) for key in ("unit.Pa", "unit.MPa", "unit.m", "unit.mm", "unit.m2", "unit.cm2")}
    meaning_of = dict(rows)
    lines = _WHERE.findall(html)
    checked = 0
    for markup, meaning in lines:
        unit = _plain(meaning).rsplit(", ", 1)[-1]
        if unit not in units:
            continue
        # the list's unit (an equation printing a value in it: "R = S/2 = 41 мм") or its SI unit
        row = _plain(meaning_of[markup])
        formulas = re.escape(_UNIT_IN_FORMULAS[language]).replace(r"\{\}", "([^()]+)")
        found = re.search(rf", ([^,()]+)(?:{formulas})?$", row)
        assert found and unit in found.groups(), (markup, unit, row)
        checked += 1
    assert checked >= 20
    pressure = _plain(meaning_of[symbol_html("cylinder_pressure", language)])
    assert pressure.endswith(
        f", {t('unit.MPa')}" + _UNIT_IN_FORMULAS[language].format(t("unit.Pa"))
    )


def test_the_sums_the_axes_and_the_allowed_irregularity_are_in_the_list():
    """ΣC, ΣM_C and the sums of one order (ΣP_I … ΣP_VI, listed as ΣP_ν), the bearing diagrams'
    axes z_ш, t_ш, x, y and [δ] are symbols a reader meets in the note: the list explains them."""
    html = shared_html("inline4-petrol", _SIX, language="ru").linked_html
    listed = html[html.index('<div class="symbol-list">') :]
    listed = _plain(listed[: listed.index("</div>")])
    for row in (
        "ΣC – равнодействующая центробежных сил вращающихся масс коленчатого вала, Н",
        "ΣMC – момент центробежных сил всех колен относительно середины вала, Н·м",
        "ΣPν – равнодействующая сил инерции ν-го порядка всех цилиндров",
        "zш – ось диаграммы шатунного подшипника вдоль оси шатуна",
        "tш – ось диаграммы шатунного подшипника, перпендикулярная к оси шатуна",
        "x – ось диаграммы коренного подшипника",
        "y – ось диаграммы коренного подшипника вдоль оси первого цилиндра",
        "[δ] – допускаемый коэффициент неравномерности вращения",
    ):
        assert row in listed, row
    # the orders in Roman numerals are instances of the order ν
    assert typeset.order_indices("Σ<i>P</i><sub>VI</sub> <i>C</i><sub>II</sub>") == (
        "Σ<i>P</i><sub><i>ν</i></sub> <i>C</i><sub>II</sub>"
    )


def test_a_single_cylinders_bearing_axis_is_its_cylinders_axis():
    """Several cylinders: the main bearing diagram's y lies along the first one's axis (a
    boxer's two cylinders point opposite ways); one cylinder: along its axis."""
    single = _plain(shared_html("petrol-1cyl", language="ru").linked_html)
    assert "y – ось диаграммы коренного подшипника вдоль оси цилиндра" in single
    assert "вдоль оси первого цилиндра" not in single
