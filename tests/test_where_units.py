"""The units of the "де …" lines agree with what the reader sees around the equation (two
supervisors' readings: "s_п – переміщення поршня, м" beside a table in мм; "d, B" in m beside a
worked line in kN and mm): a symbol's line gives the unit its section's tables and worked lines
show it in, else the unit of the table of given data; SI only where an equation declares it."""

from __future__ import annotations

import html as html_lib
import re
from functools import lru_cache

import pytest

from crankdyn.report.typeset import SYMBOLS, symbol_html

#: One section's start, an equation (its ``data-si`` declaration and number), a where line, a
#: worked line, a table's header or body.
_PIECES = re.compile(
    r'<section\b[^>]*\bdata-stage="(?P<stage>[^"]*)"'
    r'|<div class="equation"[^>]*?(?: data-si="(?P<si>[^"]*)")?><span class="formula">.*?'
    r'<span class="eqno">(?P<number>[^<]*)</span></div>'
    r'|<span class="where-line">(?P<where>.*?)</span>(?=<br>|</span>)'
    r'|<p class="worked-line">(?P<worked>.*?)</p>'
    r'|<thead>(?P<head>.*?)</thead>'
    r'|<tbody>(?P<body>.*?)</tbody>', re.S)
_SI = {"м", "м²", "м³", "Па", "m", "m²", "m³", "Pa"}


def _markup(html: str) -> str:
    """Symbol markup as the where lines write it: no spans, breaks nor word joiners."""
    return re.sub(r"</?span[^>]*>|<br[^>]*>", "", html).replace("\u2060", "").strip()


def _text(html: str) -> str:
    return html_lib.unescape(re.sub(r"<[^>]+>", "", html)).replace("\u2060", "").strip()


def _worked_unit(line: str) -> tuple[str, str] | None:
    """(left-hand side, unit of the result) of a worked line ("s_п = … = 6,60 мм")."""
    line = _markup(line)
    result = _text(line.rsplit(" = ", 1)[-1])
    match = re.fullmatch(r"[−\-]?[\d\u202f\u00a0 ,]+(?:[\u202f\u00a0 ]?)(\D+)", result)
    return (line.split(" = ", 1)[0], match.group(1).strip()) if match else None


def _table_units(head: str | None, body: str | None) -> list[tuple[str, str]]:
    """(symbol, unit) of a table's header cells "s_п, мм", or of its rows "name | symbol | value | unit"."""
    if head is not None:
        cells = [_markup(c) for c in re.findall(r"<th[^>]*>(.*?)</th>", head, re.S)]
        return [tuple(_markup(part) for part in cell.rsplit(", ", 1)) for cell in cells if ", " in cell]
    out = []
    for row in re.findall(r"<tr[^>]*>(.*?)</tr>", body, re.S):
        cells = [_markup(c) for c in re.findall(r"<td[^>]*>(.*?)</td>", row, re.S)]
        if len(cells) == 4 and cells[1].startswith("<i>") and _text(cells[3]) not in ("", "—"):
            out.append((cells[1].split(" = ")[0], _text(cells[3])))
    return out


def _own_meaning(symbol: str, stage: str, language: str) -> bool:
    """Whether ``symbol`` has a meaning of its own in section ``stage`` (``Symbol.sections``: n, the
    forces' specific side force, is not the given data's crank speed)."""
    return any(s.sections and stage in s.sections and symbol_html(key, language) == symbol
               for key, s in SYMBOLS.items())


@lru_cache(maxsize=None)
def _read(folder) -> str:
    return (folder / "report.html").read_text(encoding="utf-8")


def where_units(html: str, language: str) -> list[tuple[str, str, str, str, set[str], str]]:
    """(section, equation, symbol, the line's unit, the units shown for it, the equation's SI keys) per
    where line; shown: in its section's tables and worked lines, else in the table of given data."""
    stage, number, si = "", "", ""
    shown: dict[str, dict[str, set[str]]] = {}
    lines = []
    for m in _PIECES.finditer(html):
        if m.group("stage") is not None:
            stage = m.group("stage")
        elif m.group("number") is not None:
            number, si = m.group("number"), m.group("si") or ""
        elif m.group("where") is not None:
            symbol, _, rest = _markup(m.group("where")).partition(" – ")
            unit = re.search(r", ([^,]+)[;.]$", _text(rest))
            lines.append((stage, number, symbol, unit.group(1) if unit else "", si))
        elif m.group("worked") is not None and _worked_unit(m.group("worked")):
            symbol, unit = _worked_unit(m.group("worked"))
            shown.setdefault(stage, {}).setdefault(symbol, set()).add(unit)
        elif m.group("head") is not None or m.group("body") is not None:
            for symbol, unit in _table_units(m.group("head"), m.group("body")):
                shown.setdefault(stage, {}).setdefault(symbol, set()).add(_text(unit))
    given = shown.get("input", {})
    return [(stage, number, symbol, unit, shown.get(stage, {}).get(symbol) or
             (set() if _own_meaning(symbol, stage, language) else given.get(symbol, set())), si)
            for stage, number, symbol, unit, si in lines]


@pytest.mark.parametrize("example, language", [
    ("petrol-1cyl", "uk"), ("inline4-petrol", "uk"), ("offset-crank-engine", "uk"),
    ("petrol-1cyl", "en"), ("petrol-1cyl-ru", None)])
def test_a_where_line_gives_the_unit_its_section_shows(shared_report, example, language):
    lines = where_units(_read(shared_report(example, language)), language or "ru")
    assert len(lines) > 40
    checked = 0
    for stage, number, symbol, unit, units, si in lines:
        if units:
            checked += 1
            assert unit in units, (stage, number, _text(symbol), unit, units)
        assert unit not in _SI or si, (stage, number, _text(symbol), unit, "SI, not declared")
    assert checked >= 20, checked


def test_the_lines_a_supervisor_read_as_contradictions_now_agree(shared_report):
    """The in-line four: s_п under (2.3) beside "s_п, мм"; d and B under (9.4) beside the worked
    "p_max = Q_max/(d B) = 16,37·10³/(51,66·31,00) = 10,22 МПа"; the gas pressures in МПа."""
    lines = {(number, _text(symbol)): unit for _, number, symbol, unit, _, _ in
             where_units(_read(shared_report("inline4-petrol", "uk")), "uk")}
    assert lines[("(2.3)", "sп")] == "мм"
    assert lines[("(9.4)", "d")] == lines[("(9.4)", "B")] == "мм"
    assert lines[("(9.4)", "p")] == lines[("(4.2)", "p")] == lines[("(5.2)", "pj")] == "МПа"
    assert lines[("(4.2)", "Va")] == "л"
