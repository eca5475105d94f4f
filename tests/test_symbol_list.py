"""The list of symbols says where a letter with several meanings holds (document.symbol_list_html):
the sections and appendices of the stages the meaning belongs to, as numbered in this report."""

from __future__ import annotations

import re

import pytest
from conftest import symbol_rows

from crankdyn.plugin.registry import default_registry
from crankdyn.report import document
from crankdyn.report.document import _places
from crankdyn.report.i18n import translator
from crankdyn.report.typeset import symbol_table

#: The table a report of the installed plugins reads (the stages bind the sectioned letters).
SYMBOLS = symbol_table(default_registry().stages.values())


def symbol_list_html(keys, t, language, abbreviations=True, places=None, single=False):
    forms = ("single",) if single else ()
    return document.symbol_list_html(keys, t, language, abbreviations, places, forms, SYMBOLS)


def _rows(html: str) -> list[str]:
    return symbol_rows(html)


def test_a_letter_with_several_meanings_names_the_sections_of_each_sectioned_meaning():
    t = translator("uk")
    shows = "<i>n</i> <i>δ</i> <i>k</i>"  # each section shows the letters
    places = {
        "forces": [("section", "5", shows)],
        "bays": [("section", "9", shows)],
        "balancing": [("section", "6", shows)],
        "flywheel": [("section", "8", shows)],
    }
    places["numerics"] = [("appendix", "Б", shows)]
    rows = _rows(
        symbol_list_html(
            ["crank_speed", "rod_specific", "series_term", "irregularity"],
            t,
            "uk",
            places=places,
        )
    )
    assert rows[0] == "n – частота обертання колінчастого вала, хв⁻¹"  # holds throughout: no place
    assert rows[1] == (
        "k – питома сила, що діє вздовж шатуна (у розділах 5 і 9), МПа (у формулах – Па)"
    )
    assert rows[2] == "k – номер члена ряду (у додатку Б)"
    assert (
        rows[3] == "δ – коефіцієнт нерівномірності обертання"
    )  # the only δ of this list: no place


def test_the_crank_speed_side_force_and_order_of_a_harmonic_are_three_letters():
    """n is the crank speed throughout a note: the side force is N (Kolchin's), the order of a
    harmonic ν (as the torsion section writes it), so the list gives n one meaning."""
    letters = {key: SYMBOLS[key].base for key in ("crank_speed", "side_specific", "harmonic_order")}
    assert letters == {"crank_speed": "n", "side_specific": "N", "harmonic_order": "ν"}
    t = translator("ru")
    rows = _rows(symbol_list_html(["side_specific", "crank_speed", "harmonic_order"], t, "ru"))
    assert rows == [
        "N – удельная боковая сила, прижимающая поршень к стенке цилиндра, МПа (в формулах – Па)",
        "n – частота вращения коленчатого вала, мин⁻¹",
        "ν – порядок гармоники силы или момента",
    ]


def test_a_meaning_of_the_appendices_and_a_stage_absent_from_the_report():
    t = translator("en")
    places = {
        "numerics": [("appendix", "A", "<i>k</i><sub>2</sub>"), ("appendix", "B", "<i>k</i> = 1")]
    }
    rows = _rows(
        symbol_list_html(
            ["series_term", "side_specific", "rod_specific", "shaft_angle"], t, "en", places=places
        )
    )
    assert (
        rows[0] == "k – number of a term of a series (in appendix B)"
    )  # appendix A shows k₂, not k
    assert rows[1].startswith(
        "N – specific side force pressing the piston against the cylinder wall, "
    )
    # forces and bays are not in this report: nothing to point to, only the unit of the equations
    assert rows[2] == "k – specific force along the connecting rod, MPa (in the equations, Pa)"


def test_the_places_are_read_from_the_report_headings():
    html = (
        '<section class="chapter" id="sec-forces" data-stage="forces">\n  <h2 id="x">5 Сили</h2>'
        '<section class="chapter appendix" id="sec-numerics" data-stage="numerics">\n'
        '  <h2 class="unnumbered">Додаток А<br><span>(довідковий)</span><br>Похибка</h2>'
    )
    places = _places(html)
    assert {stage: [where[:2] for where in found] for stage, found in places.items()} == {
        "forces": [("section", "5")],
        "numerics": [("appendix", "А")],
    }
    assert places["forces"][0][2].endswith("5 Сили</h2>") and "Похибка" in places["numerics"][0][2]


def test_a_meaning_is_not_said_to_hold_in_a_section_that_does_not_show_its_letter():
    """Not "k – питома сила, що діє вздовж шатуна (у розділах 5 і 6)" in the in-line four,
    where section 6 (the bays) shows no k."""
    t = translator("uk")
    places = {
        "forces": [("section", "5", "<i>k</i> = <i>p</i><sub>1</sub>/cos <i>β</i>")],
        "bays": [("section", "6", "<i>k</i><sub>2</sub> <i>N</i><sub>i</sub>")],
    }
    rows = _rows(symbol_list_html(["rod_specific", "series_term"], t, "uk", places=places))
    assert rows[0] == "k – питома сила, що діє вздовж шатуна (у розділі 5), МПа (у формулах – Па)"


def test_sources_are_cited_with_three_or_more_consecutive_numbers_as_a_range():
    """ "[5, 6, 7]" is written "[5–7]"."""
    from crankdyn.report.document import cite

    assert cite([1]) == "[1]" and cite([2, 1, 2]) == "[1, 2]"
    assert cite([7, 5, 6]) == "[5–7]"
    assert cite([1, 3, 4, 5, 6, 9, 10]) == "[1, 3–6, 9, 10]"


def test_a_lone_latin_letter_of_cyrillic_prose_is_set_in_italics_as_in_the_equations():
    """ "координату x", "вектори F і P", "n-го порядку" in italics in the text, as the formulas
    set the same letters. Not an initial, a Roman numeral, the imaginary unit
    j, Euler's e, a letter of a formula's markup or of an English title quoted in the note."""
    from crankdyn.report.typeset import typeset_html

    def typeset(text: str, language: str = "uk") -> str:
        return typeset_html(f"<p>{text}</p>", language, [])[3:-4]

    assert typeset("координату x кожного циліндра") == "координату <i>x</i> кожного циліндра"
    assert (
        typeset("вектори F і P посібника, осей t–z, як")
        == "вектори <i>F</i> і <i>P</i> посібника, осей <i>t</i>–<i>z</i>, як"
    )
    assert typeset("сила n-го порядку") == "сила <i>n</i>-го порядку"
    assert (
        typeset("площі d·B; плече s.") == "площі <i>d</i>·<i>B</i>; плече <i>s</i>."
    )  # (a capital before "." is an initial)
    # an index subscript in italics as the equations set it, a numeral or a word's one upright
    assert typeset("сила P_I і l′_i, C_ν, Δα_{0i}, p_i тут") == (
        "сила <i>P</i><sub>I</sub> і <i>l</i>′<sub><i>i</i></sub>, "
        "<i>C</i><sub><i>ν</i></sub>, Δ<i>α</i><sub>0<i>i</i></sub>, "
        "<i>p</i><sub>i</sub> тут"
    )
    # left upright
    assert "<i>" not in typeset("Khurmi R. S. і порядок I.")
    # V and X are the volume and a studied value, at a sentence's end too; an initial follows a name
    assert (
        typeset("координатах p–V, величини X. Тут")
        == "координатах <i>p</i>–<i>V</i>, величини <i>X</i>. Тут"
    )
    assert (
        typeset("маса, зведена до радіуса R, а в частках Rω², M = 9555 N/n тут")
        == "маса, зведена до радіуса <i>R</i>, а в частках <i>R</i>ω², <i>M</i> = 9555 <i>N</i>/<i>n</i> тут"
    )
    assert "<i>j</i>" not in typeset("де j – уявна одиниця, cos α + j sin α")
    assert "<i>j</i>" not in typeset("где j – мнимая единица; j is the imaginary unit")
    # a letter naming a shape is part of a word ("V-подібного двигуна", "V-образного")
    assert typeset("розрахунок V-подібного та W-образного, n-го порядку") == (
        "розрахунок V-подібного та W-образного, <i>n</i>-го порядку"
    )
    assert "<i>e</i>" not in typeset("вектор e^{jα} тут")
    assert (
        typeset("тема: «Dynamic calculation of a four-cylinder engine»")
        == "тема: «Dynamic calculation of a four-cylinder engine»"
    )
    assert (
        typeset("d<i>V</i> і <i>p</i>") == "d<i>V</i> і <i>p</i>"
    )  # a formula's letters keep their markup
    assert typeset("координату x", "en") == "координату x"  # English prose: "a" and "I" are words


def test_a_meaning_ending_with_its_letter_and_a_one_letter_table_cell_are_in_italics():
    """ "зведена до радіуса R, кг" sets R in italics (the unit is put after the meaning), and the
    criteria column's cells z, t, q are in italics as their headers are."""
    from crankdyn.report.typeset import italic_letters, typeset_html

    assert italic_letters("маса, зведена до радіуса R", "ru") == "маса, зведена до радіуса <i>R</i>"
    assert (
        typeset_html('<tr><td class="text">z</td><td>1,5</td></tr>', "uk", [])
        == '<tr><td class="text"><i>z</i></td><td>1,5</td></tr>'
    )
    assert (
        typeset_html('<tr><td class="text">z</td></tr>', "en", [])
        == '<tr><td class="text">z</td></tr>'
    )


def test_a_letter_of_the_prose_only_is_in_the_list_too():
    """T of "ω_m = Φ/T" (the time-mean speed, in the method notes) is defined too. Set in
    italics in the prose, the list finds and explains it."""
    from conftest import shared_html

    html = shared_html("inline4-petrol", language="uk").linked_html
    listed = html[html.index('<div class="symbol-list">') :]
    assert "Φ/<i>T</i>" in html
    assert (
        '<span class="symbol"><i>T</i></span> – <span class="meaning">тривалість одного циклу, с</span>'
        in listed
    )


def test_a_one_cylinder_note_gives_the_one_cylinder_meanings():
    """A single-cylinder note defines θ not 'від ВМТ першого циліндра' nor M as the 'сумарний'
    torque. A meaning may have a one-cylinder form (``symbol.<key>_single``), which the
    list and the "where" lines of a one-cylinder note use."""
    from conftest import shared_html

    t = translator("uk")
    assert _rows(symbol_list_html(["shaft_angle"], t, "uk", single=True)) == [
        "θ – кут повороту колінчастого вала від ВМТ циліндра, °"
    ]
    assert _rows(symbol_list_html(["shaft_angle"], t, "uk")) == [
        "θ – кут повороту колінчастого вала від ВМТ першого циліндра, °"
    ]
    one = shared_html("petrol-1cyl-uk", language="uk").linked_html
    four = shared_html("inline4-petrol", language="uk").linked_html
    assert "від ВМТ першого циліндра" not in one and "від ВМТ першого циліндра" in four
    # a one-cylinder engine's bay model: its cylinder's force, not its crank's cylinders'
    assert "вектор сили першого порядку циліндра, що обертається разом із коліном" in one
    assert "циліндрів коліна" not in one and "вектор сил першого порядку циліндрів коліна" in four


_ROW = re.compile(
    r'<p class="symbol-row"><span class="symbol">(.*?)</span> – <span class="meaning">(.*?)</span>'
)
#: where a meaning of a letter with several holds: "(у розділі 5)", "(в приложении Б)"
_PLACE = re.compile(r"\((?:у|в|in) (?:розділ|раздел|додат|приложени|section|appendix)")


def _listed(html: str) -> list[tuple[str, str]]:
    listed = html[html.index('<div class="symbol-list">') :]
    return _ROW.findall(listed[: listed.index("</div>")])


@pytest.mark.parametrize(
    "example, language",
    [("radial9-aircraft", "uk"), ("radial9-aircraft", "ru"), ("radial9-aircraft", "en")]
    + [("inline4-petrol", language) for language in ("uk", "ru", "en")],
)
def test_the_list_gives_a_letter_one_meaning(example, language):
    """A letter the list shows twice (a vector in bold and its magnitude in light type count as one
    letter) says where each meaning holds; a vector and its magnitude are one row. Not q_ш.ш twice,
    t_kN "за останнім, N-м коліном" beside the side force N, R_j beside the imaginary unit j, B the
    crank pin's axis beside the bearing width B, M_i beside M_сер, and not an imaginary unit, Δα,
    Δj_п that the list leaves out."""
    from conftest import shared_html

    html = shared_html(example, language=language).linked_html
    rows = _listed(html)
    seen: dict[str, list[str]] = {}
    for markup, meaning in rows:
        seen.setdefault(re.sub(r"</?b>", "", markup), []).append(meaning)
    for markup, meanings in seen.items():
        if len(meanings) > 1:
            assert all(_PLACE.search(m) for m in meanings), (markup, meanings)
    plain = re.sub(r"<[^>]+>", "", html)
    assert "<i>t</i><sub>k<i>N</i></sub>" not in html and "N-м" not in plain
    assert not re.search(r"<i>R</i></b><sub><i>j</i>", html)
    assert "<i>M</i><sub>i</sub>" not in html
    assert not re.search(r"\bB (–|the) (вісь|ось|axis|crank pin)", plain)
    symbols = [markup for markup, _ in rows]
    if "e<sup>j" in html:  # the balancing's complex amplitudes
        assert "j" in symbols
    body = html[html.index('<div class="symbol-list">') :]
    body = body[body.index("</div>") :]
    for shown in ("Δ<i>α</i>", "Δ<i>j</i><sub>", "<i>σ</i><sub>"):
        assert shown not in body or any(s.startswith(shown) for s in symbols), shown


def test_the_vector_and_its_magnitude_are_one_row():
    """q_ш.ш in bold (the vector) and in light type (its magnitude) are said in one row."""
    t = translator("uk")
    rows = _rows(symbol_list_html(["pin_load_vector", "bays.pin_load", "crank_speed"], t, "uk"))
    assert rows == [
        "qш.ш – вектор питомого навантаження на шатунну шийку в осях коліна (t, z); "
        "qш.ш (світлим шрифтом) – його модуль, МПа (у формулах – Па)",
        "n – частота обертання колінчастого вала, хв⁻¹",
    ]


def test_the_vector_models_are_divided_by_their_circles_radius():
    """Fig. "vector models": a second-order panel is divided by |A_2| C_I, the dotted circle's
    radius C_ν, not by C_II (the textbook's λC_I)."""
    from crankdyn_builtin.balancing.figures import _models_drawing

    panels = [
        (1, "PI", 1, [("force", 0.5 + 0j, 0.5 + 0j, 1.0), ("moment", 0j, 0j, 0.0)]),
        (2, "PII", 2, [("force", 0.4 + 0j, 0.1 + 0j, 0.5), ("moment", 0j, 0j, 0.0)]),
    ]
    fig = _models_drawing(panels, True, 4, "")
    titles = [ax.get_title() for ax in fig.axes]
    assert titles[:2] == [
        r"$\Sigma P_{\mathrm{I}}/C_{\mathrm{I}}$",
        r"$\Sigma P_{\mathrm{II}}/(|A_{2}|C_{\mathrm{I}})$",
    ]
    assert not any("C_{\\mathrm{II}}" in title for title in titles)


def test_a_three_bank_engines_bank_angle_is_between_adjacent_banks():
    """A W12's γ is the angle between adjacent banks (the outer ones lie 2γ apart), in the task's
    data and the list of symbols; a V's is its bank angle."""
    from conftest import shared_html

    w = {"engine": {"layout": "W", "cylinders": 12, "bank_angle_deg": 60}}
    w["engine"].update(crank_angles_deg=None, firing_order=None)
    text = re.sub(
        r"\s+", " ", re.sub(r"<[^>]+>", "", shared_html("v8-petrol", w, "en").linked_html)
    )
    assert "Angle between adjacent cylinder banks" in text and "Bank angle" not in text
    assert "γ – angle between the axes of adjacent cylinder banks" in text
    v = re.sub(r"<[^>]+>", "", shared_html("v8-petrol", None, "en", ("kinematics",)).linked_html)
    assert "Bank angle" in v and "adjacent cylinder banks" not in v


def test_a_letter_two_stages_declare_alike_is_listed_once_and_one_they_declare_apart_twice():
    """The offset crank-slider's φ, declared by its kinematics and by its bearings with the same
    meaning and unit, is one row that holds throughout; e_z, the crank's axis in the bearings and
    the cylinder's axis in the rod's dynamics, is two rows, each saying its section."""
    import re

    from conftest import shared_html

    html = shared_html("offset-crank-engine", None, "uk").linked_html
    rows = _rows(html)
    assert [r for r in rows if r.startswith("φ –")] == [
        "φ – кут повороту кривошипа від напрямку осі циліндра, °"
    ]
    axes = [r for r in rows if r.startswith("ez –")]
    assert len(axes) == 2 and all(re.search(r"\(у розділі \d+\)$", r) for r in axes)


def test_the_dangerous_combinations_criteria_are_all_in_the_list():
    """The table of the most dangerous load combinations names z_max and z_min beside t_max,
    t_min and q_max: the list of symbols gives them all."""

    from conftest import shared_html

    html = shared_html("inline4-petrol", None, "uk").linked_html
    rows = _rows(html)
    for start in (
        "zmax – найбільша за цикл питома радіальна сила",
        "zmin – найменша",
        "tmax – ",
        "qmax – ",
    ):
        assert any(row.startswith(start) for row in rows), start
