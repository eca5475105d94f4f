"""The "де …" lines under equations (ДСТУ 3008): which symbols, in what order, said how."""

from __future__ import annotations

import re

import pytest

from crankdyn.plugin.registry import default_registry
from crankdyn.report import equation_legend
from crankdyn.report.i18n import translator
from crankdyn.report.typeset import symbol_table

REGISTRY = default_registry()
#: The table a report of the registry reads: the core's symbols and the stages' own.
SYMBOLS = symbol_table(REGISTRY.stages.values())


def symbols_in(formula: str, language: str, stage: str, symbols=SYMBOLS) -> list[str]:
    return equation_legend.symbols_in(formula, language, stage, symbols)


def add_equation_legends(
    html: str, t, language: str, skip_stages=frozenset(), single=False, symbols=SYMBOLS
) -> str:
    forms = ("single",) if single else ()
    return equation_legend.add_equation_legends(html, t, language, skip_stages, forms, symbols)


def _equation(formula: str, number: str = "1.1") -> str:
    return (
        f'<div class="equation"><span class="formula">{formula}</span>'
        f'<span class="eqno">({number})</span></div>'
    )


def _section(stage: str, body: str) -> str:
    return f'<section class="chapter" data-stage="{stage}">{body}</section>'


@pytest.fixture(scope="module")
def uk():
    return translator("uk", REGISTRY.catalogs)


def _legends(html: str) -> list[str]:
    """Each "where" paragraph as plain text, its lines separated by " | "."""
    out = []
    for m in re.finditer(r'<p class="where">(.*?)</p>', html, re.S):
        text = re.sub(r"<br>", " | ", m.group(1))
        out.append(re.sub(r"<[^>]+>", "", text))
    return out


def test_symbols_are_listed_in_the_order_they_stand_in_the_formula():
    # R = S/2, λ = R/L: R first, then S, λ, L (each once)
    formula = "<i>R</i> = <i>S</i>/2, <i>λ</i> = <i>R</i>/<i>L</i>"
    assert symbols_in(formula, "uk", "kinematics") == [
        "crank_radius",
        "stroke",
        "rod_ratio",
        "rod_length",
    ]


def test_a_symbol_is_explained_under_its_first_equation_only(uk):
    html = _section(
        "kinematics",
        _equation("<i>R</i> = <i>S</i>/2")
        + "<p>text</p>"
        + _equation("<i>λ</i> = <i>R</i>/<i>L</i>", "1.2"),
    )
    legends = _legends(add_equation_legends(html, uk, "uk"))
    assert legends == [
        "де R – радіус кривошипа, м; | S – хід поршня, м.",
        "де λ – відношення радіуса кривошипа до довжини шатуна; | L – довжина шатуна, м.",
    ]
    # the paragraph follows its equation, before the text after it
    out = add_equation_legends(html, uk, "uk")
    assert out.index("(1.1)") < out.index("де ") < out.index("<p>text</p>")


def test_an_equation_of_known_symbols_gets_no_legend(uk):
    html = _section(
        "kinematics", _equation("<i>R</i> = <i>S</i>/2") + _equation("<i>S</i> = 2<i>R</i>", "1.2")
    )
    assert len(_legends(add_equation_legends(html, uk, "uk"))) == 1


def test_a_primed_symbol_is_another_quantity():
    # p_i′ (the theoretical diagram's pressure) is not p_i, the mean indicated pressure
    assert "mean_indicated_pressure" not in symbols_in(
        "<i>p</i><sub>i</sub>′ = 1", "uk", "indicator"
    )
    assert symbols_in("<i>p</i><sub>i</sub> = 1", "uk", "indicator") == ["mean_indicated_pressure"]


def test_a_letter_with_a_second_meaning_is_read_by_its_section():
    # δ: the irregularity in the flywheel's section only; the indicator section writes ε/ρ, not the
    # textbook's further-expansion ratio δ, so that a note gives δ one meaning
    assert symbols_in("<i>δ</i> = 1", "uk", "indicator") == []
    assert symbols_in("<i>δ</i> = 1", "uk", "flywheel") == ["irregularity"]
    # B: the bearing width in the bearings section, not the ellipse's semi-axis in the balancing one
    assert symbols_in("<i>B</i> = 1", "uk", "bearings") == ["bearing_width"]
    assert symbols_in("<i>B</i> = 1", "uk", "balancing") == []
    # n: the crank speed everywhere; the specific side force is N (Kolchin's letter), in the
    # forces section, where n is still the crank speed
    assert symbols_in("<i>n</i> = 1", "uk", "kinematics") == ["crank_speed"]
    assert symbols_in("<i>n</i> = 1", "uk", "forces") == ["crank_speed"]
    assert symbols_in("<i>N</i> = <i>p</i><sub>1</sub> tg <i>β</i>", "uk", "forces") == [
        "side_specific",
        "total_pressure",
        "rod_angle",
    ]


def test_a_symbol_without_subscript_is_not_read_in_one_with_a_subscript():
    # ω_ш is the rod's angular velocity, not ω
    assert symbols_in("<i>ω</i><sub>ш</sub> = 1", "uk", "kinematics") == ["rod_angular_velocity"]


def test_the_section_note_of_a_second_meaning_is_not_repeated_in_its_section(uk):
    legends = _legends(
        add_equation_legends(_section("flywheel", _equation("<i>δ</i> = 1")), uk, "uk")
    )
    assert legends == ["де δ – коефіцієнт нерівномірності обертання."]


def test_every_report_language_has_its_word():
    for language, word in (("uk", "де"), ("ru", "где"), ("en", "where")):
        t = translator(language, REGISTRY.catalogs)
        html = add_equation_legends(_section("kinematics", _equation("<i>L</i> = 1")), t, language)
        assert _legends(html)[0].startswith(word + " L – ")


def test_a_delta_or_a_prime_makes_another_quantity():
    # ΔL (the excess work) is not L (the rod's length); p_i′ is not p_i; Δα_0i is not α
    assert symbols_in("Δ<i>L</i> = <i>W</i><sub>max</sub>", "uk", "flywheel") == [
        "excess_work",
        "accumulated_work_max",
    ]
    assert symbols_in("<i>p</i><sub>i</sub>′ = 1", "uk", "indicator") == [
        "theoretical_mean_indicated_pressure"
    ]
    assert symbols_in(
        "<i>α</i><sub><i>i</i></sub> = <i>α</i> − Δ<i>α</i><sub>0<i>i</i></sub>", "uk", "torque"
    ) == ["cylinder_crank_angle", "crank_angle", "cycle_delay"]
    # the bare p: the gas pressure in every section (the bearings section writes p_max, p_сер)
    assert symbols_in("<i>p</i> = 1", "uk", "indicator") == ["cylinder_pressure"]
    assert symbols_in("<i>p</i> = 1", "uk", "bearings") == ["cylinder_pressure"]
    assert symbols_in("<i>p</i><sub>max</sub> = 1", "uk", "bearings") == ["bearing_pressure_max"]
    # after Σ a sum, after [ an allowed value: not the quantity of the letter
    assert symbols_in("Σ<i>C</i> = <i>C</i>", "uk", "balancing") == [
        "sum_centrifugal",
        "centrifugal_force",
    ]
    assert symbols_in("Σ<i>P</i><sub><i>ν</i></sub>", "uk", "balancing") == ["sum_order_force"]
    assert symbols_in("[<i>δ</i>] = <i>δ</i>", "uk", "flywheel") == [
        "allowed_irregularity",
        "irregularity",
    ]
    # a bracket that holds more than the letter is no allowed value
    assert symbols_in("[<i>λ</i><sub>p</sub>(<i>ρ</i> − 1)]", "uk", "indicator") == [
        "pressure_rise_ratio",
        "pre_expansion_ratio",
    ]


def test_an_index_or_an_exponent_is_not_the_quantity_of_its_letter():
    # k in sin^{2k} and the ν of C_ν are indices (C_ν is the amplitude, not C nor the order ν);
    # t and z in e_{t,i} name axes (an italic bold e is no symbol); R_{i,i+1} and q_ш.ш in bold
    # are the vectors, not the crank radius nor q; but the exponent n_1 of a polytrope is the polytropic index
    assert symbols_in("sin<sup>2<i>k</i></sup> <i>α</i>", "uk", "forces") == ["crank_angle"]
    assert symbols_in("<i>C</i><sub><i>ν</i></sub>", "uk", "balancing") == ["order_amplitude"]
    assert symbols_in("<b><i>e</i></b><sub><i>t</i>,<i>i</i></sub>", "uk", "bearings") == []
    assert symbols_in(
        "<b><i>R</i></b><sub><i>i</i>,<i>i</i>+1</sub> = <b><i>q</i></b><sub>ш.ш</sub>",
        "uk",
        "bearings",
    ) == ["journal_load_vector", "pin_load_vector"]
    assert symbols_in(
        "<i>p</i><sub>a</sub>(<i>V</i><sub>a</sub>/<i>V</i>)<sup><i>n</i><sub>1</sub></sup>",
        "uk",
        "indicator",
    ) == ["intake_end_pressure", "total_volume", "cylinder_volume", "compression_polytrope"]


def test_a_section_that_explains_its_letters_in_its_own_words_gets_no_legend():
    # Stage.legend = False: no "where" lines in that section (here a made-up one)
    html = add_equation_legends(
        _section("vane", _equation("<i>β</i> = 1")),
        translator("uk", REGISTRY.catalogs),
        "uk",
        frozenset({"vane"}),
    )
    assert _legends(html) == []
    assert REGISTRY.stages["forces"].presentation.legend


def test_a_mechanism_of_its_own_letters_explains_them_with_its_own_meanings():
    # the vane engine's β is its core's tail angle, not a connecting rod's, and its α is counted from
    # the cranks' upper position, not from a TDC: its own symbols take over in its section
    assert REGISTRY.stages["vane"].presentation.legend
    assert REGISTRY.stages["planetary"].presentation.legend
    uk = translator("uk", REGISTRY.catalogs)
    line = _legends(
        add_equation_legends(
            _section("vane", _equation("<i>β</i> = −arcsin(<i>λ</i> sin <i>α</i>)")),
            uk,
            "uk",
            symbols=SYMBOLS,
        )
    )[0]
    assert "β – кут відхилення хвостовика осердя від вертикалі, °;" in line
    assert "λ – відношення радіуса кривошипа до довжини хвостовика;" in line
    assert "α – кут повороту кривошипів від їхнього верхнього положення, °." in line
    assert "шатуна" not in line and "ВМТ" not in line
    # the planetary carrier's torque is M_в in uk (the Latin c is the resistance torque's M_оп there)
    line = _legends(
        add_equation_legends(
            _section("planetary", _equation("<i>M</i><sub>в</sub> = <i>F h</i>")),
            uk,
            "uk",
            symbols=SYMBOLS,
        )
    )[0]
    assert "Mв – крутний момент на водилі, Н·м;" in line


def test_the_lines_give_the_si_units_the_formulas_hold_in(uk):
    """A line gives the SI unit the formula is evaluated in and the worked substitutions use, as
    the list of symbols says before it lists the tables' units: lines in the tables' units make
    the formulas wrong as read (M_к = t R F_п with t in МПа, R in мм,
    F_п in см² is ten times too small; p_max = Q_max/(d B) a thousand times)."""
    html = _section(
        "forces",
        _equation(
            "<i>M</i><sub>к</sub> = <i>t</i> <i>R</i> <i>F</i><sub>п</sub>, "
            "<i>V</i><sub>h</sub>, <i>m</i><sub>s</sub>, <i>s</i><sub>п</sub>"
        ),
    )
    line = _legends(add_equation_legends(html, uk, "uk"))[0]
    for part in (
        "Mк – крутний момент від сил одного циліндра, Н·м;",
        "t – питома тангенціальна сила, Па;",
        "R – радіус кривошипа, м;",
        "Fп – площа поршня, м²;",
        "Vh – робочий об’єм циліндра, м³;",
        "ms – маса частин, що рухаються зворотно-поступально, кг;",
        "sп – переміщення поршня, м.",
    ):
        assert part in line.replace("&#39;", "'"), part
    html = _section(
        "bearings",
        _equation("<i>p</i><sub>max</sub> = <i>Q</i><sub>max</sub> / (<i>d</i> <i>B</i>)"),
    )
    line = _legends(add_equation_legends(html, uk, "uk"))[0]
    assert (
        "за цикл тиск на підшипник, Па;" in line
        and "шатунну шийку, Н;" in line
        and "d – діаметр шийки, м;" in line
        and "B – ширина підшипника, м." in line
    ), line


def test_a_product_in_one_italic_run_is_read_letter_by_letter():
    # v = Rω sin(α + β): ω stands before α
    assert symbols_in(
        "<i>v</i><sub>п</sub> = <i>Rω</i> sin(<i>α</i> + <i>β</i>)", "uk", "kinematics"
    ) == ["piston_velocity", "crank_radius", "crank_angular_velocity", "crank_angle", "rod_angle"]
    assert symbols_in("<i>M</i><sub>к</sub> = <i>t R</i> <i>F</i><sub>п</sub>", "uk", "forces") == [
        "crank_torque",
        "tangential_specific",
        "crank_radius",
        "piston_area",
    ]


def test_the_flywheel_equations_explain_their_own_quantities(uk):
    # ½J(ω_max² − ω_min²) = ΔL: J, ω_max and ω_min are explained under it, in that order
    html = _section(
        "flywheel",
        _equation(
            "½<i>J</i>(<i>ω</i><sub>max</sub><sup>2</sup> − <i>ω</i><sub>min</sub>"
            "<sup>2</sup>) = Δ<i>L</i>"
        ),
    )
    line = _legends(add_equation_legends(html, uk, "uk"))[0]
    assert line.startswith("де J – зведений до колінчастого вала момент інерції")
    assert line.index("ωmax –") < line.index("ωmin –") < line.index("ΔL –")


def test_a_symbol_finder_finds_its_markup_only_where_it_means_that_symbol():
    """The markup, not after a Δ nor a given text, a bare symbol not followed by a subscript nor
    a prime, not in brackets of its own: the positions those conditions, written as a regular
    expression, find."""
    import re

    from crankdyn.report.typeset import symbol_finder, symbol_html

    bare = symbol_html("crank_angular_velocity", "uk")  # <i>ω</i>
    text = (
        f"{bare} = Δ{bare}; <b>{bare}</b>, {bare}<sub>ш</sub>, {bare}′ [{bare}] [{bare} + 1] {bare}"
    )
    finder = symbol_finder("crank_angular_velocity", "uk", not_after=("<b>",))
    expected = [
        m.start()
        for m in re.finditer(
            "(?<!Δ)(?<!<b>)(?<!Σ)"
            + re.escape(bare)
            + r"(?!<sub>)(?![′″])(?!(?<=\["
            + re.escape(bare)
            + r")\])",
            text,
        )
    ]
    assert list(finder.positions(text)) == expected
    assert expected == [0, text.index("[" + bare + " +") + 1, len(text) - len(bare)]
    assert finder.found_in(text) and not finder.found_in(f"Δ{bare}, [{bare}]")
    # a symbol with its own subscript may be followed by one of its formula (no bare-symbol rule)
    sub = symbol_finder("rod_angular_velocity", "uk")
    rod = symbol_html("rod_angular_velocity", "uk")
    assert list(sub.positions(f"{rod}<sub>x</sub> Σ{rod}")) == [0]


def test_a_dotted_letter_is_not_the_letter():
    """The planetary note has no "z – питома радіальна сила" under a_G = z̈_A e_z + …, whose z̈
    is the second derivative of a coordinate (the italic run "z̈" is not read letter by letter)."""
    # the rod dynamics' own letters (Stage.symbols): the vectors and the dotted z̈_A, none of them z
    assert symbols_in(
        "<b>a</b><sub>G</sub> = <i>z̈</i><sub>A</sub> <b>e</b><sub><i>z</i></sub>",
        "uk",
        "rod_dynamics",
    ) == [
        "rod_dynamics.acceleration_G",
        "rod_dynamics.small_end_acceleration",
        "rod_dynamics.cylinder_axis_vector",
    ]
    assert symbols_in("<i>β̈</i> (cos <i>β</i>)", "uk", "rod_dynamics") == ["rod_angle"]
    assert symbols_in("<i>z</i> = <i>β</i>", "uk", "forces")[1:] == [
        "rod_angle"
    ]  # z itself: the radial force
    assert symbols_in("<i>Rω</i>", "uk", "kinematics") == ["crank_radius", "crank_angular_velocity"]
