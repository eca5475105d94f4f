"""The "where …" lines under a displayed equation (ДСТУ 3008: the symbols of a formula are
explained right below it, in the order in which they stand in it, each on its own line; the first
line starts with "де" at the paragraph indent, without a colon).

A symbol is explained under the first equation of the report that shows it; later equations
rely on that (and on the list of symbols in front of the introduction). The symbols, their
meanings and units come from the report's symbol table (a
:class:`crankdyn.report.typeset.SymbolTable`, the core's symbols by default), so the lines say what
the list of symbols says. A letter with a second meaning in some sections
(``Symbol.sections``) is read with that meaning inside those sections only, and a symbol marked
by a prime (``p_i′``) is another quantity, not explained as the unprimed one.

Works on the typeset report (symbols written in the report's language); nothing here computes.
"""

from __future__ import annotations

import functools
import re

from markupsafe import escape

from .typeset import (
    SYMBOLS,
    SymbolFinder,
    SymbolTable,
    italic_letters,
    sections_taking_over,
    symbol_finder,
    symbol_html,
    unit_text,
    unshifted_indices,
)

_SECTION_OR_EQUATION = re.compile(
    r'<section\b[^>]*\bdata-stage="(?P<stage>[^"]*)"'
    r'|<div class="equation"[^>]*><span class="formula">(?P<formula>.*?)</span>'
    r'<span class="eqno">[^<]*</span></div>',
    re.S,
)

_SECTIONS_NOTE = re.compile(r"\s*\([^()]*\)\s*$")


@functools.lru_cache(maxsize=8)
def _patterns(
    language: str, symbols: SymbolTable
) -> tuple[tuple[str, str, bool, tuple[str, ...], tuple[str, ...]], ...]:
    """(key, markup, bare, only in sections, not in sections) per symbol; where a formula shows
    it is :func:`_finder`'s (:class:`~crankdyn.report.typeset.SymbolFinder`: a primed symbol,
    p_i′, is another quantity, and here a bold one too, a vector or a matrix: R_j, q_ш.ш);
    ``bare``: no subscript of its own. A symbol without sections is not read in the sections where another of the same markup
    takes over. Kept per table (a table is hashed by its contents)."""
    taken_over = sections_taking_over(symbols, language)
    out = []
    for key, symbol in symbols.items():
        markup = symbol_html(key, language, symbols)
        out.append(
            (
                key,
                markup,
                "<sub>" not in markup and not symbol.in_scripts,
                symbol.sections,
                () if symbol.sections else tuple(sorted(taken_over.get(markup, ()))),
            )
        )
    return tuple(out)


@functools.lru_cache(maxsize=4096)
def _finder(key: str, language: str, symbols: SymbolTable) -> SymbolFinder:
    # an upright letter (the imaginary unit j) is not the italic one (the acceleration j_p)
    upright = "<i>" not in symbol_html(key, language, symbols)
    not_after = ("<b>", "<i>") if upright else ("<b>",)
    return symbol_finder(key, language, not_after=not_after, symbols=symbols)


_SCRIPT = re.compile(r"<(sub|sup)>.*?</\1>", re.S)
_ITALIC_RUN = re.compile(r"<i>([^<]{2,})</i>")
#: A letter with the combining marks on it (z̈, β̇: a derivative, another quantity than z or β).
_LETTER = re.compile(r"\S[\u0300-\u036f]*")


def symbols_in(
    formula_html: str, language: str, stage: str, symbols: SymbolTable = SYMBOLS
) -> list[str]:
    """The keys of the symbols ``formula_html`` shows in section ``stage``, in order of appearance.
    A bare letter inside a sub- or superscript is an index or an exponent (sin^{2k}, C_n, e_{t,i}),
    not the quantity; a symbol with its own subscript there is one (the exponent n_1), and so is one
    marked ``in_scripts`` (θ of e^{jnθ}). A shifted index is the index (l″_{i+1} is l″_i)."""
    formula_html = unshifted_indices(formula_html)
    # a product set in one italic run (<i>Rω</i>, <i>t R</i>) is read letter by letter, a letter
    # keeping its dots (<i>z̈</i> is not z)
    formula_html = _ITALIC_RUN.sub(
        lambda m: _LETTER.sub(lambda c: f"<i>{c.group(0)}</i>", m.group(1)), formula_html
    )
    scripts = [m.span() for m in _SCRIPT.finditer(formula_html)]
    found = []
    for key, markup, bare, only_in, not_in in _patterns(language, symbols):
        if (only_in and stage not in only_in) or stage in not_in or markup not in formula_html:
            continue
        for position in _finder(key, language, symbols).positions(formula_html):
            if not (bare and any(start < position < end for start, end in scripts)):
                found.append((position, key))
                break
    return [key for _, key in sorted(found)]


#: The tables' units and the SI units a formula is evaluated in (M_к = t R F_п holds in Pa, m and m²,
#: not in MPa, mm and cm²; a litre is a cubic metre, a kilonewton a newton there).
_SI_UNITS = {
    "unit.mm": "unit.m",
    "unit.cm2": "unit.m2",
    "unit.l": "unit.m3",
    "unit.MPa": "unit.Pa",
    "unit.kN": "unit.N",
    "unit.kW": "unit.W",
}


def printed_table_units(formula_html: str, t) -> frozenset[str]:
    """The tables' units (``unit.mm``…) in which ``formula_html`` prints a value itself
    ("R = S/2 = 90 мм"): its where-lines name those units beside the SI ones."""
    text = re.sub(r"<[^>]+>", "", formula_html).replace("\u00a0", " ").replace("\u202f", " ")
    return frozenset(
        key
        for key in _SI_UNITS
        if re.search(rf"\d\s*{re.escape(unit_text(key, t))}(?![\w²³])", text)
    )


def line_unit(
    key: str, t, symbols: SymbolTable = SYMBOLS, printed: frozenset[str] = frozenset()
) -> str:
    """The unit a "where" line gives symbol ``key`` in, in the report's language ("" for a ratio):
    the SI unit the formulas are evaluated in and the worked substitutions put the numbers in
    (R = 0,03900 м, F_п = 0,005281 м², p in Pa, with ·10⁻⁶ to the table's МПа), where the tables,
    the figures and the equations' own results show convenient units (мм, МПа, см², л). Where
    the equation prints the quantity's value in such a unit (``printed``: "R = S/2 = 39 мм"), the
    line names both, as the list of symbols does: "мм (у формулах – м)". Lines in the tables'
    units alone would make the formulas wrong as read (M_к = t R F_п with t in МПа, R in мм, F_п
    in см² is ten times too small; p_j = −m_s j_п/F_п with F_п in см² ten thousand times), lines
    in SI alone beside "R = 39 мм" read as a second unit of the same value."""
    unit = symbols[key].unit
    si = _SI_UNITS.get(unit, unit)
    if unit in printed and si != unit:
        return t("doc.symbols_unit_in_formulas", unit=unit_text(unit, t), si=unit_text(si, t))
    return unit_text(si, t)


def symbol_meaning(t, key: str, forms: tuple[str, ...] = ()) -> str:
    """A symbol's meaning from the catalogs: the first of the engine's ``forms`` the catalog gives
    (``symbol.KEY_FORM``: a one-cylinder engine's "single", θ "від ВМТ циліндра", not "першого
    циліндра"; a boxer's "boxer", a the offset of opposed cylinders along the shaft), else its
    general meaning."""
    for form in forms:
        if t.has(f"symbol.{key}_{form}"):
            return t(f"symbol.{key}_{form}")
    return t(f"symbol.{key}")


def legend_html(
    keys: list[str],
    t,
    language: str,
    forms: tuple[str, ...] = (),
    symbols: SymbolTable = SYMBOLS,
    printed: frozenset[str] = frozenset(),
) -> str:
    """The "where" paragraph for ``keys``: "де α – meaning, unit;" one symbol per line, a full
    stop after the last; the unit as :func:`line_unit` says (``printed``: the tables' units the
    equation shows values in)."""
    lines = []
    for k, key in enumerate(keys):
        unit = line_unit(key, t, symbols, printed)
        meaning = symbol_meaning(t, key, forms)
        # "(in the flywheel sections)" of a core symbol is said by where the line stands; a stage's
        # own symbol (StagePresentation.symbols, "stage.key") carries no such note, its parentheses stay
        if symbols[key].sections and "." not in key:
            meaning = _SECTIONS_NOTE.sub("", meaning)
        meaning = italic_letters(str(escape(meaning)), language) + (
            f", {escape(unit)}" if unit else ""
        )
        end = "." if k == len(keys) - 1 else ";"
        lines.append(
            f'<span class="where-line">{symbol_html(key, language, symbols)} – {meaning}{end}</span>'
        )
    # the word in a box of its own: the lines after the first stand under the first symbol
    return (
        f'<p class="where"><span class="where-word">{escape(t("doc.equation_where"))} </span>'
        f'<span class="where-lines">{"<br>".join(lines)}</span></p>'
    )


def add_equation_legends(
    html: str,
    t,
    language: str,
    skip_stages: frozenset[str] = frozenset(),
    forms: tuple[str, ...] = (),
    symbols: SymbolTable = SYMBOLS,
) -> str:
    """``html`` with a "where" paragraph after each equation that shows symbols not explained before;
    none in the sections of ``skip_stages`` (``StagePresentation.legend`` False); ``forms``: the
    engine's forms of the meanings (:func:`symbol_meaning`)."""
    explained: set[str] = set()
    stage = ""
    parts = []
    position = 0
    for match in _SECTION_OR_EQUATION.finditer(html):
        if match.group("stage") is not None:
            stage = match.group("stage")
            continue
        if stage in skip_stages:
            continue
        new = [
            key
            for key in symbols_in(match.group("formula"), language, stage, symbols)
            if key not in explained
        ]
        if not new:
            continue
        explained.update(new)
        printed = printed_table_units(match.group("formula"), t)
        parts += [
            html[position : match.end()],
            legend_html(new, t, language, forms, symbols, printed),
        ]
        position = match.end()
    parts.append(html[position:])
    return "".join(parts)
