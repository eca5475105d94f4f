"""The units of the "де …" lines are the SI units the formulas hold in and the worked substitutions
put the numbers in; beside an equation that prints a value in a handier unit ("R = S/2 = 39 мм")
the line names both, as the list of symbols does ("мм (у формулах – м)"); the tables, figures
and results show handier units (мм, МПа, см², л), as the list of symbols says first. "s_п, м" beside a table in мм is no contradiction: lines in the
tables' units would make the formulas wrong as read (M_к = t R F_п with t in МПа, R in мм and F_п
in см² is ten times too small)."""

from __future__ import annotations

import html as html_lib
import re

import pytest
from conftest import shared_html

#: Units of the tables that no formula holds in as printed.
_TABLE_ONLY = {"мм", "МПа", "см²", "л", "кН", "кВт", "mm", "MPa", "cm²", "l", "kN", "kW"}
_WHERE = re.compile(r'<span class="where-line">(.*?)</span>(?=<br>|</span>)', re.S)
_EQUATION_AND_WHERE = re.compile(
    r'<span class="formula">(.*?)</span><span class="eqno">[^<]*</span></div>'
    r'<p class="where">(.*?)</p>',
    re.S,
)
_WORKED = re.compile(r'<p class="worked-line">(.*?)</p>', re.S)


def _text(html: str) -> str:
    return html_lib.unescape(re.sub(r"<[^>]+>", "", html)).replace("\u2060", "").strip()


@pytest.mark.parametrize(
    "example, language",
    [
        ("petrol-1cyl", "uk"),
        ("inline4-petrol", "uk"),
        ("offset-crank-engine", "uk"),
        ("petrol-1cyl", "en"),
        ("petrol-1cyl-ru", None),
    ],
)
def test_a_where_line_gives_the_si_unit(example, language):
    html = shared_html(
        example, language=language
    ).linked_html  # the text without drawing its figures
    pairs = [
        (_text(m.group(1)), [_text(line) for line in _WHERE.findall(m.group(2))])
        for m in _EQUATION_AND_WHERE.finditer(html)
    ]
    lines = [line for _, where in pairs for line in where]
    assert len(lines) > 40
    units = [re.search(r", ([^,]+)[;.]$", line) for line in lines]
    # a table's unit only beside the SI one the formula holds in, where the equation itself prints
    # a value in it ("R = S/2 = 39 мм": "R – …, мм (у формулах – м)"); one list mixed "R, мм" with
    # "s_п, м" and "p_j, Па" with "F_п, см²" before
    alone = [
        line
        for line in lines
        if (unit := re.search(r", ([^,()]+)[;.]$", line)) and unit.group(1) in _TABLE_ONLY
    ]
    assert not alone, alone[:5]
    both = [
        (formula, line)
        for formula, where in pairs
        for line in where
        if (
            unit := re.search(
                r", (\S+) \((?:у формулах|в формулах|in the equations),? –? ?(\S+)\)[;.]$", line
            )
        )
    ]
    assert both, "R = S/2 = … мм: its where-line names мм beside м"
    for formula, line in both:
        unit = re.search(r", (\S+) \(", line).group(1)
        assert unit in _TABLE_ONLY and re.search(rf"\d\s*{re.escape(unit)}(?![\w²³])", formula), (
            line
        )
    assert (
        sum(1 for unit in units if unit and unit.group(1) in {"м", "Па", "м²", "m", "Pa", "m²"})
        >= 10
    )


def test_the_worked_lines_substitute_si_numbers_and_the_list_says_so():
    """The in-line four: R substituted in metres (0,03900), the bearing pressure from kN and mm
    converted to N and m (·10³, ·10⁻³) and the result from Pa to МПа (·10⁻⁶); the list of symbols
    tells the reader which units the formulas take."""
    html = shared_html("inline4-petrol", language="uk").linked_html
    worked = [_text(m.group(1)) for m in _WORKED.finditer(html)]
    assert any("0,03900" in w for w in worked)
    pressure = next(w for w in worked if w.startswith("pmax = Qmax/(d B)"))
    pressure = pressure.replace("\u00a0", " ").replace("\u202f", " ")
    assert re.search(r"·103/\([\d,]+·10−3·[\d,]+·10−3\)·10−6 = [\d,]+ МПа$", pressure), pressure
    assert "У формули величини підставляють в одиницях СІ (довжини – у метрах" in html
    where = {(_text(m.group(1)).split(" – ")[0]): _text(m.group(1)) for m in _WHERE.finditer(html)}
    assert (
        where["sп"].endswith(", м.")
        and where["d"].endswith(", м;")
        and where["Va"].endswith(", м³;")
    )
