"""The Ukrainian report of a single-cylinder engine as a supervisor checks it: the balancing
section speaks of one cylinder, not of sums over cylinders and moments;
the figure of vector models is captioned for what it shows; the forces figure's legend writes
p_г as the text does; a log axis shorter than a decade still carries numbers."""

from __future__ import annotations

import re
from functools import cache

import pytest
from conftest import as_read, shared_html, shared_run

#: The reports' folders by example, as the tests last asked for them.
_FOLDERS: dict = {}
#: The examples whose figures (files) a test here reads.
_WITH_FIGURE_FILES = ("petrol-1cyl-uk", "inline4-petrol")


@cache
def _html(folder) -> str:
    with open(f"{folder}/report.html", encoding="utf-8") as fh:
        return fh.read()


@pytest.fixture(scope="module")
def reports(shared_report):
    """The Ukrainian HTML report of an example (conftest.shared_report, shared with other test files:
    read only); ``--lang uk`` for the examples written in another language. The examples whose
    figure files a test reads are written by the command; the others' text is rendered without
    drawing their figures (conftest.shared_html)."""

    def html(example):
        language = None if example.endswith("-uk") else "uk"
        if example not in _WITH_FIGURE_FILES:
            return shared_html(example, language=language).linked_html
        folder = shared_report(example, language)
        _FOLDERS[example] = folder
        return _html(folder)

    return html


def test_the_balancing_section_of_one_cylinder_speaks_of_one_cylinder(reports):
    one, four = reports("petrol-1cyl-uk"), reports("inline4-petrol")
    for phrase in (
        "поздовжніх моментів немає",
        "Моментів в одноциліндровому двигуні немає",
        "реальна сила інерції",
        "Векторні моделі і годографи сил",
    ):
        assert phrase in one, phrase
        assert phrase not in four, phrase
    for phrase in (
        "однакових у всіх циліндрах",
        "сума реальних сил усіх циліндрів",
        "відстань між циліндрами",
        "моменти внизу",
    ):
        assert phrase not in one, phrase
        assert phrase in four, phrase


def test_the_resultants_motion_is_said_in_words(reports):
    one = reports("petrol-1cyl-uk")
    assert "Рух рівнодійної" in one and "пульсує вздовж прямої" in one
    assert "уздовж прямої</td>" not in one.replace("пульсує вздовж прямої", "")
    assert "Півосі годографа, велика / мала" in one


def test_the_forces_legend_writes_the_gas_pressure_as_the_text_does(reports):
    reports("petrol-1cyl-uk")  # written below the module's folder
    from crankdyn.report.typeset import symbol_mathtext

    assert symbol_mathtext("gas_pressure", "uk") == "$p_{\\mathrm{г}}$"
    svg = next(_FOLDERS["petrol-1cyl-uk"].glob("figures/*_forces.svg")).read_text(encoding="utf-8")
    legend = svg[svg.index("<!-- $p_{\\mathrm{") :][:800]
    assert "<!-- $p_{\\mathrm{г}}$ -->" in svg and re.search(r">г</tspan>", legend)


def test_a_log_axis_shorter_than_a_decade_labels_its_minor_ticks():
    from crankdyn.report.i18n import translator
    from crankdyn.report.typeset import _log_minor_label

    t = translator("uk")
    assert _log_minor_label(2.0, (1.5, 8.0), t) == "2"
    assert _log_minor_label(0.3, (0.15, 0.8), t) == "0,3"
    assert _log_minor_label(4.0, (1.5, 8.0), t) == ""  # 2, 3 and 5 only: room for the numbers
    assert _log_minor_label(2.0, (1.0, 1000.0), t) == ""  # the powers of ten are labelled there


def test_schemes_and_diagrams_are_announced_as_what_they_are(reports):
    one, four = as_read(reports("petrol-1cyl-uk")), as_read(reports("inline4-petrol"))
    for sentence in (
        "Кінематичну схему механізму наведено на рис. 3.1.",
        "Механізм у характерних положеннях (у мертвих точках і за кутів повороту кривошипа, за яких"
        " швидкість і прискорення поршня досягають екстремумів; кути з результатів кінематики)"
        " показано на рис. 3.2.",
        "Схему коліна наведено на рис.",
        "Векторні моделі і годографи наведено на рис.",
        "Полярну діаграму навантаження на шатунну шийку наведено на рис. 7.1.",
        "Полярну діаграму навантаження на шатунний підшипник наведено на рис. 7.2.",
        "Діаграму зношування шатунної шийки наведено на рис.",
    ):
        assert sentence in one, sentence
    # each diagram of a pair side by side says whose load it shows (not two "the vector diagram
    # is given in fig. 9.x" next to each other); several cranks: with their numbers
    for sentence in (
        "Полярну діаграму навантаження на шатунну шийку 1 наведено на рис. 9.1.",
        "Полярну діаграму навантаження на корінну шийку 2–3 наведено на рис. 9.3.",
        "Полярну діаграму навантаження на корінний підшипник 2–3 наведено на рис. 9.4.",
    ):
        assert sentence in four, sentence
    assert "Схеми колін наведено на рис." in four and "Схему коліна наведено" not in four
    # every figure and table says what it holds, none is announced as just "the curves" or "the results"
    assert "Графіки показано на рис." not in one
    four_text = as_read(four)
    for generic in ("Графіки показано на рис.", "Результати розрахунку наведено в табл."):
        assert generic not in as_read(one) and generic not in four_text, generic
    # a course note times no stage (the full report's numerics chapter does)
    assert "Час обчислення кожного етапу розрахунку наведено в табл." not in four_text
    assert (
        "Залежності переміщення, швидкості та прискорення поршня від кута повороту кривошипа "
        "показано на рис. 2.1."
    ) in one
    assert (
        "Кінематичні параметри поршня і питомі сили, що діють у механізмі одного циліндра, наведено в табл."
        in one
    )


def test_the_main_journal_diagram_says_whose_force_it_shows(reports):
    """The journal diagram is the bearing's force on the journal (the reaction), with the
    counterweights the balancing section fits (the in-line four fits none): said in the text, so
    that its sign and size are not mistaken."""
    one, four = reports("petrol-1cyl-uk"), reports("inline4-petrol")
    assert "сила, з якою на неї діє підшипник" in one
    assert "обчислено з противагами, які визначено в розділі 6" in one
    assert "обчислено для колінчастого вала без противаг" in four


def test_a_single_crank_is_not_described_as_one_of_many(reports):
    """One crank: no neighbouring cranks adding on a journal, no choice of the most loaded crank
    pin, one crank pin in the table's caption; journals are named as in the tables (0-1)."""
    one, four = reports("petrol-1cyl-uk"), reports("inline4-petrol")
    assert "розподіляється між двома корінними шийками" in one and "обох сусідніх колін" not in one
    assert (
        "Навантаження на шатунну шийку:" in one
        and "обидві корінні шийки навантажені однаково" in one
    )
    assert "діаграми побудовано для шийки 0–1" in one
    assert "обох сусідніх колін" in four and "Навантаження на шатунні шийки:" in four
    assert re.search(r"найбільш навантаженої корінної шийки \(\d–\d\)", four)


def test_table_cells_of_words_are_text_and_empty_cells_get_a_dash(reports):
    """Table 6.3's 'what balances it' column is words: centred as text, not flush right as numbers;
    an empty cell of table 6.1 (no series term for a mass) shows a dash."""
    one = reports("petrol-1cyl-uk")
    table = one[one.index('data-number="6.3"') :]
    table = table[: table.index("</table>")]
    assert '<td class="text">противаги на колінчастому валу</td>' in table
    forces = one[one.index('data-number="6.2"') :]
    forces = forces[: forces.index("</table>")]
    assert re.search(r"<td>\d[\d\u202f ]*</td>", forces)  # the forces stay numbers
    masses = one[one.index('data-number="6.1"') :]
    masses = masses[: masses.index("</table>")]
    assert "<td>—</td>" in masses and "<td></td>" not in masses


def test_the_abstract_names_the_main_results_and_counts_the_appendices(reports):
    """ДСТУ 3008: the abstract gives the results and the counts of appendices, and cites nothing;
    the appendices' status reads "(довідковий)"; the introduction refers to every appendix."""
    one = reports("petrol-1cyl-uk")
    abstract = one[one.index('<section class="abstract"') :]
    abstract = abstract[: abstract.index("</section>")]
    assert "[1]" not in abstract and "1 дод." in abstract  # a course note's one appendix
    assert (
        "Основні результати: найбільший абсолютний тиск газів у циліндрі" in abstract
        and "навантаження на шатунну шийку" in abstract
    )
    assert '<span class="appendix-kind">(довідковий)</span>' in one
    intro = one[one.index('id="sec-introduction"') :]
    intro = as_read(intro[: intro.index("</section>")])
    assert "в додатку А" in intro and "додатку Б" not in intro


def test_the_list_of_symbols_defines_the_masses_forces_and_journal_sizes_the_text_uses(reports):
    """m_cp, m_w, C, C_I, c, V_a, d, B are used, so listed; m_cp would read as the Cyrillic
    'ср' (mean): in uk the crank pin's mass is m_ш.ш and a web's m_щ. Without a flywheel the note
    has no δ: the indicator section writes ε/ρ for the further-expansion ratio."""
    one = reports("petrol-1cyl-uk")
    symbols = one[one.index('class="symbol-list"') :]
    symbols = symbols[: symbols.index("</div>")]
    for markup in (
        "<i>m</i><sub>ш.ш</sub>",
        "<i>m</i><sub>щ</sub>",
        "<i>C</i><sub>I</sub>",
        "<i>c</i><sub>r</sub>",
        "<i>V</i><sub>a</sub>",
        "<i>d</i>",
        "<i>B</i>",
        "<i>l</i><sub>R</sub>",
    ):
        assert markup in symbols, markup
    assert "<sub>cp</sub>" not in one and "<i>m</i><sub>w</sub>" not in one
    assert "<i>δ</i>" not in symbols


def test_a_single_cylinder_balancing_section_speaks_of_one_crank_and_no_moments(reports):
    """No bay's axis of symmetry, no crank lag or bank angle, no sum over cylinders, no moment
    columns in the table of orders for one cylinder; an in-line four keeps them."""
    one, four = reports("petrol-1cyl-uk"), reports("inline4-petrol")
    for words in ("ВМТ першого циліндра до ВМТ", "до суми сил усіх циліндрів", "Момент, Н·м"):
        assert words not in one and words in four, words
    assert "Відцентрова сила і сили інерції кожного порядку" in one


def test_an_inline_engine_has_no_bays_and_no_bank_angle(reports):
    """The in-line four's note has none of a V engine's text: "the axis of symmetry of a bay",
    "the cylinder's phase taking in the crank lag and the axis angle", rods "side by side" on a common crank pin."""
    four, v8 = reports("inline4-petrol"), reports("v8-petrol")
    for words in (
        "вісь симетрії відсіку",
        "містить і відставання коліна циліндра",
        "розташовані поруч",
        "спільну шатунну шийку",
    ):
        assert words not in four and words in v8, words
    assert "Кожен циліндр діє на власну шатунну шийку" in four
    assert "Схема двигуна і порядок роботи циліндрів" in four
    # the cycle delays of 1-3-4-2, in firing order
    table = four[four.index("Коліна циліндрів і зсуви їхніх робочих циклів") :]
    cells = [c for c in table[: table.index("</table>")].split("<td")[1:]]
    values = [c.split(">", 1)[1].split("<", 1)[0] for c in cells]
    assert values == [
        "1",
        "1",
        "0",
        "0",
        "3",
        "3",
        "180",
        "180",
        "4",
        "4",
        "0",
        "360",
        "2",
        "2",
        "180",
        "540",
    ]


def test_the_task_sheet_lists_the_main_data_and_a_petrol_table_has_no_rho(reports):
    """The task sheet gives the main data itself (a supervisor's form has them), and the table of
    a spark-ignition engine leaves out ρ = 1, which is no datum of its task (a diesel's keeps it)."""
    one = as_read(reports("petrol-1cyl-uk"))
    assignment = one[one.index('<section class="assignment"') :]
    assignment = re.sub(
        r"</?i>", "", assignment[: assignment.index("</section>")]
    )  # the letters in italics
    assert "D = 82" in assignment and "S = 78" in assignment and "n = 5600" in assignment
    assert "Ступінь попереднього розширення" not in one


def test_the_wear_diagram_is_laid_inwards_from_the_journal_circle_with_its_scale(reports):
    """As the textbook draws it, and the caption says the scale: the largest summed load to 0.6 of
    the radius, a relative measure ("6938 kN" would read as an impossible force; the sum
    over the grid's angles depends on the angle step)."""
    one = reports("petrol-1cyl-uk")
    assert re.search(
        r"сумарні навантаження секторів відкладено всередину кола шийки \(умовна міра зношування, а не "
        r"сила\), найбільше – на 0,6 радіуса",
        one,
    )
    assert "Діаграма зношування шатунної шийки:" in one  # one crank pin: no number


def test_a_check_that_agrees_to_rounding_says_so_instead_of_printing_the_rounding(reports):
    """3,9·10⁻¹⁶ reads as a result, and a bound "< 10⁻¹²" as a program's precision; "practically
    zero" says that the two calculations agree."""
    one = reports("petrol-1cyl-uk")
    assert "відносна різниця практично нульова" in one
    assert not re.search(r"різниця (?:&lt;|<)? ?\d?,?\d?·?10⁻1[2-9]", one)


def test_a_single_cylinder_conclusion_gives_its_unbalanced_forces_in_newtons(reports):
    """Coefficients are all 1 for one cylinder; the conclusion says the forces: C = m_R R ω² of the
    example (17 235 N, as equation 6.1 prints it) and P_I, P_II."""
    one = reports("petrol-1cyl-uk")
    text = re.sub(r"<[^>]+>", "", as_read(one)).replace("\u202f", " ")
    # without the balancing means ("unbalanced" beside "balanced with its means" reads as a contradiction)
    assert (
        "Без засобів зрівноваження незрівноважені сили (амплітуди): C = 17 235 Н, PI = 8248 Н, PII = 2357 Н"
        in text
    )
    # one cylinder: no moments; the negligible forces named by their orders
    assert re.search(r"Крім них, незрівноважені сили [^(]*порядк(у|ів) \(", text)
    assert "сили й моменти" not in text and "сили і моменти" not in text


def test_the_torque_check_gives_each_cylinders_own_angle_and_the_units_of_its_table(reports):
    """t_k4 = t_1 + … + t_4 at α = 30° could not be traced without the cylinders' own angles:
    α_i = α − Δα_0i with the delays 0, 540, 180, 360° of 1-3-4-2 (cylinders 1, 2, 3, 4)."""
    four = re.sub(r"<[^>]+>", "", as_read(reports("inline4-petrol"))).replace("\u202f", " ")
    assert "α1 = 30°, α2 = 210°, α3 = 570°, α4 = 390°" in four
    assert re.search(
        r"Таблиця 7\.\d – Сили і набіжні моменти на колінах 1–4 \[1, табл\. Б\.3\], МПа \(Mд – у Н·м\)",
        four,
    )
    assert "набігаюч" not in four and "Набігаюч" not in four
    power = shared_run("inline4-petrol").outputs["torque"].results["indicated_power_W"]
    assert f"Ni = {power / 1e3:.2f} кВт".replace(".", ",") in four
    assert "кВт: Mсер = Ni/" in four and "9555" not in four


def test_a_displayed_equation_breaks_only_between_its_formulas():
    """The PDF broke (10.2) inside a fraction, "ΔL/ | (J ω²)", and (11.4) between "M_c =" and its
    value: each formula is kept whole, a long one broken only after an equals sign."""
    from crankdyn.report.formula_lines import unbroken_parts

    html = unbroken_parts(
        "<i>a</i> = 1, &nbsp; <i>δ</i> = Δ<i>L</i>/(<i>J</i> <i>ω</i><sup>2</sup>)"
    )
    assert html == (
        '<span class="eq-part"><i>a</i> = 1</span>, &nbsp; '
        '<span class="eq-part"><i>δ</i> = Δ<i>L</i>/(<i>J</i> <i>ω</i><sup>2</sup>)</span>'
    )
    long = (
        "<i>M</i> = " + " + ".join(f"<i>t</i><sub>{k}</sub>" for k in range(1, 20)) + " = 108,3 Н·м"
    )
    pieces = unbroken_parts(long).split('<span class="eq-part">')[1:]
    assert (
        pieces[-1].startswith("+ <i>t</i><sub>19</sub> = 108,3 Н·м") and len(pieces) == 19
    )  # the result kept
    assert pieces[0].startswith("<i>M</i> = <i>t</i><sub>1</sub>")  # "M =" not alone on a line
    assert all(p.startswith("+ ") for p in pieces[1:-1])  # the sign opens the next line


def test_a_long_formula_breaks_before_a_sign_outside_parentheses_only():
    """(4.4) of the ru report stood on three lines: "p′ᵢ =" alone, the whole bracket, the value."""
    from crankdyn.report.formula_lines import unbroken_parts

    formula = (
        "<i>p</i><sub>i</sub>′ = <i>p</i><sub>c</sub>/⁠(<i>ε</i> − 1) · [<i>λ</i>(<i>ρ</i> − 1) + "
        "<i>λρ</i>/⁠(<i>n</i><sub>2</sub> − 1) · (1 − 1/<i>δ</i><sup>n−1</sup>) − 1/⁠(<i>n</i><sub>1</sub> − 1)"
        " · (1 − 1/<i>ε</i><sup>n−1</sup>)] = 0,8814 МПа"
    )
    pieces = [
        p.split("</span>")[0] for p in unbroken_parts(formula).split('<span class="eq-part">')[1:]
    ]
    assert pieces[0].startswith("<i>p</i><sub>i</sub>′ = <i>p</i><sub>c</sub>")
    assert [p[:2] for p in pieces[1:3]] == ["+ ", "− "] and pieces[-1].endswith("] = 0,8814 МПа")
    for piece in pieces:  # no cut inside a pair of parentheses
        text = re.sub(r"<[^>]+>", "", piece)
        assert text.count("(") == text.count(")"), piece
    # nor inside an element ("<sup>n − 1</sup>" is not cut into two spans)
    long_sup = "<i>q</i> = " + " + ".join("<i>a</i><sup>n − 1 + k</sup>" for _ in range(8)) + " = 1"
    for piece in unbroken_parts(long_sup).split('<span class="eq-part">')[1:]:
        body = piece.rsplit("</span>", 1)[0]
        assert body.count("<sup>") == body.count("</sup>"), body


def test_the_table_of_given_data_lists_everything_the_calculation_takes(reports):
    """The bearing and balancing tables cannot be checked without the firing order and the
    cylinder spacing, nor the rounding and the flywheel without their data: table 1.1
    lists the engine's layout, the cycle's rounding data and (through Stage.input_rows) the
    flywheel's given data."""
    four = as_read(reports("inline4-petrol"))
    table = four[four.index("Таблиця 1.1") :]
    rows = {}
    for row in table[: table.index("</table>")].split("<tr")[1:]:
        cells = [
            re.sub(r"<[^>]+>", "", c) for c in re.findall(r"<t[dh][^>]*>(.*?)</t[dh]>", row, re.S)
        ]
        rows[cells[0]] = cells[1:]
    assert rows["Порядок роботи циліндрів"][1] == "1–3–4–2"
    assert rows["Відстань між осями сусідніх циліндрів"][1:] == ["92", "мм"]
    assert rows["Тиск у картері"] == ["p0", "0,1", "МПа"]
    assert rows["Кут випередження запалювання (до ВМТ)"][1:] == ["22", "°"]
    assert rows["Закриття впускного клапана (після НМТ)"][1:] == ["50", "°"]
    assert rows["Допустимий коефіцієнт нерівномірності обертання"][:2] == ["[δ]", "0,01"]
    assert rows[
        "Момент інерції колінчастого вала без мас колін (корінні шийки, деталі на кінцях вала)"
    ] == [
        "Jв",
        "0,006",
        "кг·м²",
    ]
    assert rows["Густина матеріалу маховика"][1:] == ["7850", "кг/м³"]
    assert "ρ = 1" in four  # a spark-ignition cycle: stated where the formulas with ρ begin


def test_the_introduction_states_the_aim_and_the_tasks_and_sections_do_not_repeat_the_method(
    reports,
):
    """ДСТУ 3008: the introduction gives the aim and the tasks (one per section of the note); the
    project's method [1] is cited there once, not again at the head of every section."""
    four = reports("inline4-petrol")
    intro = four[four.index('id="sec-introduction"') :]
    intro = intro[: intro.index("</section>")]
    assert "Мета роботи – виконати динамічний розрахунок заданого двигуна за методикою [1]" in intro
    tasks = re.findall(r"<li>(.*?)</li>", intro[intro.index('class="tasks"') :])
    assert tasks[0] == "кінематика кривошипно-шатунного механізму;" and tasks[-1].endswith(".")
    assert "Розрахунок виконано за методикою [1]." not in four


def test_the_engine_layout_section_refers_to_the_scheme_with_the_crank_star(reports):
    """Section 6 needs a scheme of the cranks: it refers to Fig. 3.1, drawn
    with the crank star in section 3, by the number that figure got (ctx.figure_number)."""
    four = reports("inline4-petrol")
    assert "кінематичній схемі (рис. 3.1, зірка кривошипів)" in as_read(four)
    assert 'src="figures/fig_3_1_scheme.svg"' in four


def test_counts_of_balancing_means_are_written_in_words(reports):
    """ДСТУ 3008: a number without a unit up to nine in words: "дві противаги і один
    зрівноважувальний вал" (one on each web, as the means table gives m (m_web × 2)), "два
    зрівноважувальні вали", not "2 противаги і 1 …"."""
    one, four = reports("petrol-1cyl-uk"), reports("inline4-petrol")
    assert "Засоби зрівноваження: дві противаги і один зрівноважувальний вал (порядок 1)." in one
    assert "Засоби зрівноваження: два зрівноважувальні вали (порядок 2);" in four


def test_the_solver_run_the_speed_section_quotes_is_in_its_table_and_figure(reports):
    # "Методом RK45 з відносним допуском 1,0·10⁻⁸ (66 кроків) …": the table of the runs has
    # that run's row (method, 10⁻⁸, the steps), and the error figure rings it with a legend entry.
    # (the solvers' comparison is the full report's: ``detail = "full"``)
    rendered = shared_html("inline4-petrol", {"report": {"detail": "full"}}, language="uk")
    html = rendered.linked_html
    section = html[html.index('data-stage="speed_fluctuation"') :]
    quoted = re.search(r"Методом (\w+) з відносним допуском 1,0·10⁻⁸ \((\d+) крок", section)
    assert quoted, "the quoted run"
    row = rf'<td class="text">{quoted[1]}</td><td class="text">10⁻⁸</td><td>{quoted[2]}</td>'
    assert re.search(r"<tr[^>]*>" + re.escape(row), section)
    figure = next(f for f in rendered.figures if f.key == "solvers_single")
    assert f'src="figures/{figure.name}"' in section
    assert "розрахунок, використаний у цьому розділі" in figure.draw().decode("utf-8")
    course = reports("inline4-petrol")  # a course note: the results, no solver named
    course_section = course[course.index('data-stage="speed_fluctuation"') :]
    course_section = course_section[: course_section.index("</section>")]
    for word in ("RK45", "Radau", "BDF", "LSODA", "Якобі", "SciPy"):
        assert word not in course_section, word


def test_a_value_is_not_parted_from_its_quantity_nor_a_unit_at_its_slash(reports):
    """The PDF ended lines with "p_z =" (the value on the next line) and "156 м/" (с² on the next):
    no-break spaces around an "=" that a number follows, a word joiner after a slash inside a word
    or formula; a web address keeps its breaks, a tag its slash, a script its text."""
    from crankdyn.report.typeset import unbreakable_html

    html = unbreakable_html(
        "<p><i>p</i><sub>z</sub> = 6,0\u202fМПа, 156\u202fм/с² за α = −4°; a = b; "
        "<i>ΣM</i>/(<i>C</i>a); див. https://doi.org/10.1/x</p><script>x = 1; a/b</script>"
    )
    assert "</sub>\u00a0=\u00a06,0\u202fМПа" in html and "α\u00a0=\u00a0−4°" in html
    assert "a = b" in html  # no number follows: the line may break there
    assert "156\u202fм/\u2060с²" in html and "</i>/\u2060(" in html
    assert "https://doi.org/10.1/x" in html and "<script>x = 1; a/b</script>" in html
    # a surname and its initials stay on one line (the title page had "Петров В. | М.")
    named = unbreakable_html(
        "<p>доц. Петров В. М.; Khurmi R. S., Gupta J. K. Theory; табл. Б.1; рис. 2.1</p>"
    )
    assert (
        "доц. Петров\u00a0В.\u00a0М.;" in named
        and "Khurmi\u00a0R.\u00a0S., Gupta\u00a0J.\u00a0K.\u00a0Theory" in named
    )  # an initial before a capitalised word: bound too
    # an abbreviated reference keeps its number (not "(табл." at a line's end, "6.3)" on the next)
    assert "табл.\u00a0Б.1; рис.\u00a02.1" in named
    assert "75 с., 24 рис. Процес. 5" in unbreakable_html("<p>75 с., 24 рис. Процес. 5</p>")
    joined = unbreakable_html("<p>доц. Петров В.М.; В. М. Петров, Khurmi R.S.</p>")
    assert (
        "Петров\u00a0В.М.;" in joined
        and "В.\u00a0М.\u00a0Петров," in joined
        and "Khurmi\u00a0R.S." in joined
    )
    assert "</i>" in html and "</sub>" in html and unbreakable_html(html) == html  # once is enough
    # an absolute value's opening bar keeps its contents (the ru note ended a line with "C_n = |")
    bars = unbreakable_html(
        "<p><i>C</i><sub>n</sub> = |<i>A</i><sub>n</sub>|·<i>C</i><sub>I</sub>, (|<i>x</i>|), a | b</p>"
    )
    assert (
        "</sub>\u00a0=\u00a0|\u2060<i>A</i>" in bars
        and "(|\u2060<i>x</i>" in bars
        and "a | b" in bars
    )
    # after a product's dot too (not "(4,000·|" at a line's end, "A₄|C_I)" on the next)
    assert "4,000·|\u2060<i>A</i>" in unbreakable_html(
        "<p>(4,000·|<i>A</i><sub>4</sub>|<i>C</i><sub>I</sub>)</p>"
    )
    assert unbreakable_html(bars) == bars

    # the whole report: in running text every "X = <number>" is bound (a displayed equation
    # breaks after an "=" on purpose, between its parts), and no tag is broken
    four = reports("inline4-petrol")
    body = re.sub(
        r'<span class="eq-part">.*?</span>',
        "",
        re.sub(r"<script.*?</script>", "", four, flags=re.S),
    )
    assert not re.search(r"[^ \u00a0] = [−-]?\d", re.sub(r"<[^>]+>", "", body))
    assert "м/\u2060с" in four and not re.search(r"</\u2060|<\u2060", four)


#: Symbols of the in-line four's Ukrainian note that need an explanation,
#: as the typeset report writes them, with the number of the equation that first shows them.
_ONCE_UNEXPLAINED = {
    "7.2": [
        "<i>t</i><sub>w<i>i</i></sub>",
        "<i>t</i><sub><i>i</i></sub>",
        "<i>t</i><sub>k<i>i</i></sub>",
    ],
    "8.2": ["<i>j</i><sub>п</sub>", "<i>P</i><sub><i>ν</i></sub>"],
    "10.3": ["Φ", "<i>s</i>′"],
    "11.2": ["<i>J</i>′"],
    "11.3": ["<i>M</i><sub>j</sub>", "<i>s</i>″", "<i>ω</i><sub>n</sub>"],
    "11.4": ["<i>E</i><sub>0</sub>", "<i>W</i><sub>г</sub>"],
}


def _where_lines(html: str, number: str) -> list[str]:
    """The symbols explained under equation ``number`` and under every equation before it."""
    before = html[: html.index(f'<span class="eqno">({number})</span>')]
    after = html[len(before) :]
    own = re.match(r'.*?</div>\s*(<p class="where">.*?</p>)?', after, flags=re.S).group(1) or ""
    lines = re.findall(r'<span class="where-line">(.*?) – ', before + own)
    return lines


def test_the_in_line_fours_symbols_are_explained_and_listed(reports):
    html = reports("inline4-petrol")
    listed = re.search(r'id="sec-symbols".*?</section>', html, flags=re.S).group(0)
    for number, symbols in _ONCE_UNEXPLAINED.items():
        explained = _where_lines(html, number)
        for symbol in symbols:
            assert symbol in explained, (number, symbol)
            assert f'<span class="symbol">{symbol}</span>' in listed, symbol
    # appendix B's cycle is the flywheel's Φ, no second letter for it
    assert "Θ" not in html
    # the mean over the cycle is said in words where it is first written
    assert "⟨s′²⟩ (кутові дужки тут і далі – середнє за цикл)" in as_read(html)


def test_a_given_value_is_printed_as_given_wherever_it_appears(reports):
    """[δ] = 0,01 from the scene: 0,01 in the data, the flywheel's table, its text and worked line
    (not 0,0100 in one place and 0,01000 in another)."""
    text = as_read(re.sub(r"<[^>]+>", "", reports("inline4-petrol")))
    shown = re.findall(r"\[δ\](?:\s*=)?\s*(?:—\s*)?(\d+,\d+)", text) + re.findall(
        r"ΔL/\(\[δ\][^=]*=\s*[\d\s,]+/\((\d+,\d+)·", text
    )
    assert shown and set(shown) == {"0,01"}, shown


def test_the_conclusions_name_the_most_loaded_main_journal_as_its_table_gives_it(reports):
    html = reports("inline4-petrol")
    table = re.search(
        r'<table class="data" data-number="(\d+\.\d+)"><caption>Таблиця \1 – Навантаження на корінні'
        r".*?<tbody>(.*?)</tbody>",
        html,
        flags=re.S,
    )
    rows = [
        re.findall(r"<td[^>]*>(.*?)</td>", row)
        for row in re.findall(r"<tr>(.*?)</tr>", table.group(2))
    ]
    label, r_max, _, _, p_mean, oil = max(rows, key=lambda row: float(row[1].replace(",", ".")))
    conclusions = as_read(
        re.sub(
            r"<[^>]+>",
            "",
            re.search(r'id="sec-conclusions".*?</section>', html, flags=re.S).group(0),
        )
    )
    conclusions = conclusions.replace("\u202f", " ").replace("\u00a0", " ")
    assert (
        f"За найбільшою за цикл силою найбільш навантажена корінна шийка {label}: до {r_max} кН за середнього тиску на "
        f"підшипник {p_mean} МПа; отвір для мастила в ній – під кутом {oil}° (відлік – як у табл. "
        f"{table.group(1)})."
    ) in conclusions


def test_the_worked_lines_keep_their_short_brackets_whole(reports):
    lines = re.findall(r'<p class="worked-line">(.*?)</p>', reports("inline4-petrol"))
    grouped = [line for line in lines if '<span class="group">(1 − cos\u00a030°)</span>' in line]
    assert grouped, "the piston displacement's worked line"


def test_the_error_appendix_cites_its_source_for_what_it_takes_from_it(reports):
    """Ismailov's paper gives the series of the piston kinematics, not the error study's method: the
    appendix says what it compares as in that source, not "calculated by the method of [n]"."""
    html = shared_html("inline4-petrol", {"report": {"detail": "full"}}, language="uk").linked_html
    appendix = "".join(
        re.findall(
            r'<section class="chapter"[^>]*data-stage="numerics".*?</section>', html, flags=re.S
        )
    )
    assert "за методикою" not in appendix
    number = re.search(r"порівняно з її рядами за степенями λ, як у \[(\d+)\]", appendix).group(1)
    references = re.findall(
        r"<li>(.*?)</li>",
        re.search(r'<ol class="references">(.*?)</ol>', html, flags=re.S).group(1),
    )
    assert references[int(number) - 1].startswith("Ismailov")


def test_a_single_cylinder_has_no_most_loaded_pin_and_its_equal_journals_are_said_to_be_equal(
    reports,
):
    """A single cylinder's note has no "the most loaded crank pin (1)" of one pin, no "the most
    loaded main journal 0-1" of two equally loaded ones, and one oil-hole angle in the table and
    the conclusions (not 192 and 192,5°)."""
    html = reports("petrol-1cyl-uk")
    text = as_read(re.sub(r"<[^>]+>", "", html)).replace("\u202f", " ").replace("\u00a0", " ")
    assert "найбільш навантаженої шатунної шийки" not in text
    assert "Найбільший тиск на підшипник шатунної шийки – найбільша сила" in text
    assert "(0–1; обидві корінні шийки навантажені однаково)" in text  # two: "both", not "all"
    assert "Найбільш навантажена корінна шийка" not in text
    journals = re.search(
        r"<caption>Таблиця (\d+\.\d+) – Навантаження на корінні.*?<tbody>(.*?)</tbody>",
        html,
        flags=re.S,
    )
    assert "Корінні шийки навантажені однаково: до " in text
    assert f"кути отворів для мастила наведено в табл. {journals.group(1)}." in text


def test_journals_tied_by_round_off_are_named_together_not_one_picked_by_its_last_digit():
    """In the six-cylinder trace engine four main journals carry 58 141,704 N to the last digit;
    the conclusion names them together, not one of them "the most loaded"."""
    from crankdyn_builtin.bearings.worked import loads_equal, most_loaded

    records = [
        {"journal": "0-1", "max_N": 1.0e4},
        {"journal": "1-2", "max_N": 58141.70445238453},
        {"journal": "2-3", "max_N": 58141.70445238454},
        {"journal": "3-4", "max_N": 4.0e4},
    ]
    assert [r["journal"] for r in most_loaded(records)] == ["1-2", "2-3"]
    assert not loads_equal(records) and loads_equal(records[1:3])


def test_the_balancing_conclusion_prints_the_forces_as_the_table_of_orders_does(reports):
    """ΣP_VI = 4,416 N in the conclusions against 4 N in the table (and 48,09 against 48 in the ru
    single cylinder): one value, one precision."""
    for example in ("inline4-petrol", "petrol-1cyl-uk"):
        html = reports(example)
        conclusions = re.sub(
            r"<[^>]+>",
            "",
            re.search(r'id="sec-conclusions".*?</section>', html, flags=re.S).group(0),
        )
        forces = re.findall(r"P[IVX]+\u00a0=\u00a0([\d\u202f]+(?:,\d+)?)\u202fН", conclusions)
        assert forces, example
        table = re.search(
            r"<th>(?:Сила|Найбільша сила), Н</th>.*?</table>", html, flags=re.S
        ).group(0)
        cells = set(re.findall(r"<td[^>]*>([^<]*)</td>", table))
        assert all(force in cells for force in forces), (example, forces)


def test_the_balancing_conclusion_multiplies_out(reports):
    """Not "ΣP_II/C_II = 4,000 (ΣP_II = 9426 Н)" beside C_II = λC_I = 2310 Н, while
    4·2310 = 9240. Each unbalanced force is printed with the coefficient and the one-cylinder
    amplitude it multiplies, |A_n|·C_I, which the section's table of amplitudes prints too: the
    product of the printed numbers gives the printed force to their precision."""
    html = reports("inline4-petrol")
    text = as_read(re.sub(r"<[^>]+>", "", html)).replace("\u202f", " ").replace("\u00a0", " ")
    conclusion = re.search(
        r"Зрівноваженість: без засобів зрівноваження незрівноважені (.*?) \(у дужках", text
    ).group(1)
    items = re.findall(r"ΣP([IVX]+) = (\d[\d ]*(?:,\d+)?) Н \(([\d,]+)·\|A(\d+)\|CI\)", conclusion)
    assert [i[0] for i in items] == ["II", "IV"], conclusion
    c_first = float(re.search(r"CI = msRω2 = ([\d ]+) Н", text).group(1).replace(" ", ""))
    for roman, force, coefficient, order in items:
        cell = re.search(rf"<td[^>]*><i>A</i><sub>{order}</sub></td><td>([^<]+)</td>", html).group(
            1
        )
        expected = (
            float(coefficient.replace(",", "."))
            * abs(float(cell.replace("−", "-").replace(",", ".")))
            * c_first
        )
        assert float(force.replace(" ", "").replace(",", ".")) == pytest.approx(
            expected, rel=2e-3, abs=0.06
        ), (roman, force, expected)
        assert expected >= 0.01 * c_first  # listed: not negligible


def test_unbalanced_resultants_under_one_percent_of_c_i_are_called_negligible(reports):
    """Not "ΣP_VI = 4,4 Н" listed as unbalanced beside ΣP_II = 9426 Н. A resultant under
    1 % of one cylinder's C_I (a moment: of C_I·a) is said to be negligible, after the others; an
    engine with only such is not called unbalanced."""
    text = (
        as_read(re.sub(r"<[^>]+>", "", reports("inline4-petrol")))
        .replace("\u202f", " ")
        .replace("\u00a0", " ")
    )
    c_first = float(re.search(r"CI = msRω2 = ([\d ]+) Н", text).group(1).replace(" ", ""))
    # forces only: what is left is ΣP_VI, no moment (no "сили й моменти" where there are none)
    found = re.search(
        r"Крім них, незрівноважена сила шостого порядку \((.*?)\) становить не більше ніж ([\d,]+) % "
        r"амплітуди сили "
        r"інерції першого порядку одного циліндра CI, тому нею можна знехтувати\.",
        text,
    )
    value = float(re.fullmatch(r"ΣPVI = ([\d,]+) Н", found.group(1)).group(1).replace(",", "."))
    assert 0 < value < 0.01 * c_first
    # the share itself, not the 1 % bound: ΣP_VI/C_I in per cent to two significant digits
    share = float(found.group(2).replace(",", "."))
    assert share == pytest.approx(100 * value / c_first, rel=0.06) and share < 1
    html = reports("inline4-petrol")
    abstract = re.sub(
        r"<[^>]+>", "", re.search(r'<section class="abstract".*?</section>', html, re.S).group(0)
    )
    # nor is it called unbalanced there: the abstract names it as small, as the table leaves it
    plain = " ".join(abstract.replace("\u202f", " ").replace("\u00a0", " ").split())
    # the abstract names it after ΣP_IV, with its value and share, as negligible
    assert "ΣPIV" in abstract
    assert (
        f"а також ΣPVI = {found.group(1).split(' = ')[1]} – нехтовно мала величина "
        f"({found.group(2)} % від CI)" in plain
    )
    assert abstract.count("ΣPVI") == 1
    from crankdyn_builtin.balancing.section import _negligible

    r = {
        "absolute": {"sum_PVI_N": 1.5, "M_PIV_Nm": 9.5},
        "first_order_N": 1000.0,
        "cylinder_spacing_m": 0.5,
    }
    assert _negligible(r, {"quantity": "sum_PVI"})  # 1.5 < 10 N
    assert not _negligible(r, {"quantity": "M_PIV"})  # 9.5 > 0.01 * 1000 * 0.5 = 5 N·m


def test_a_single_cylinder_has_no_total_torque_to_react_to(reports):
    one, four = (
        as_read(re.sub(r"<[^>]+>", "", reports(e))) for e in ("petrol-1cyl-uk", "inline4-petrol")
    )
    assert "реакції індикаторного крутного моменту" in one and "реакції сумарного" not in one
    assert "реакції сумарного індикаторного крутного моменту" in four


def test_a_defaulted_ignition_delay_says_where_it_comes_from(reports):
    """Not "начало видимого сгорания через 2,42°" with no source; a default is the
    textbook's 0,11 of the advance (spark) or 6nτ (diesel), and the note says so."""
    text = as_read(re.sub(r"<[^>]+>", "", reports("petrol-1cyl-uk")))
    assert "через 2,42°" in text
    assert (
        "Затримку займання взято за посібником [1, підрозд. 3.1]: 0,11 кута випередження запалювання"
        in text
    )


def test_a_small_unbalanced_force_is_not_printed_as_zero():
    """Whole newtons would print the two-stroke's sixth order (0,19 N) as "0 N"."""
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.i18n import translator
    from crankdyn_builtin.balancing.notation import newtons

    t = translator("uk", default_registry().catalogs)
    assert [newtons(t, f) for f in (17235.4, 192.4, 10.2, 4.416, 0.1904)] == [
        "17\u202f235",
        "192",
        "10",
        "4,4",
        "0,19",
    ]


def test_a_given_delta_of_more_digits_is_printed_alike_everywhere(tmp_path):
    """[δ] = 0.0066667 is printed with the same digits in the table, the text and the worked
    line (not 0,006667 against 0,0066667)."""
    from conftest import modified, write_scene

    from crankdyn.cli import main

    scene = write_scene(
        tmp_path / "d.toml",
        modified(
            "inline4-petrol",
            {"flywheel": {"required_irregularity": 0.0066667}, "report": {"language": "uk"}},
        ),
    )
    assert (
        main(
            [
                "report",
                str(scene),
                "-o",
                str(tmp_path / "out"),
                "--format",
                "html",
                "-q",
                "--stages",
                "flywheel",
            ]
        )
        == 0
    )
    text = as_read(
        re.sub(r"<[^>]+>", "", (tmp_path / "out" / "report.html").read_text(encoding="utf-8"))
    )
    shown = re.findall(r"\[δ\](?:\s*=)?\s*(?:—\s*)?(\d+,\d+)", text) + re.findall(
        r"ΔL/\(\[δ\][^=]*=\s*[\d\s,]+/\((\d+,\d+)·", text
    )
    assert len(shown) >= 3 and set(shown) == {"0,0066667"}, shown


def test_subsections_are_numbered_and_listed_in_the_contents(tmp_path, examples):
    """The vane, planetary, rod-dynamics and torsion sections had unnumbered <h3> headings (DSTU
    3008: subsections are numbered within their section and listed in the contents)."""
    from crankdyn.cli import main

    assert (
        main(
            [
                "report",
                str(examples / "vane-engine-kinematics.toml"),
                "-o",
                str(tmp_path),
                "--format",
                "html",
                "-q",
            ]
        )
        == 0
    )
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert "<h3>" not in page
    headings = re.findall(r'<h3 class="subsection" id="sec-(\d+)\.(\d+)">(\d+)\.(\d+) ', page)
    assert len(headings) >= 3
    assert all(a == c and b == d for a, b, c, d in headings)
    section = headings[0][0]
    assert [int(b) for a, b, _, _ in headings if a == section] == list(
        range(1, 1 + sum(1 for a, *_ in headings if a == section))
    )
    contents = page[page.index('<nav class="contents">') : page.index("</nav>")]
    for a, b, _, _ in headings:
        assert f'href="#sec-{a}.{b}"' in contents


def test_the_closing_row_of_the_theoretical_diagram_is_point_r():
    """Point r (end of exhaust, p_r) is not at α = 0°, where table 4.1 shows p_a (the intake
    line the periodic grid starts with). The text places r at 720°, and the
    theoretical column's 720° row ends the exhaust line at p_r; the 0° row keeps p_a."""
    from conftest import shared_html

    html = shared_html("petrol-1cyl-ru").linked_html
    assert "<i>r</i> – конец выпуска (ВМТ, α = 720°)" in as_read(
        html
    )  # the point's letter in italics
    table = html[html.index("Таблица 4.1") :]
    rows = re.findall(r"<tr[^>]*>(.*?)</tr>", table[: table.index("</table>")])
    cells = [
        [re.sub(r"<[^>]+>", "", c) for c in re.findall(r"<td[^>]*>(.*?)</td>", row)]
        for row in rows[1:]
    ]
    given = html[html.index("Давление остаточных газов") :][:400]
    p_r = re.search(r"<td[^>]*>(0,\d+)</td>", given)[1]  # as the data table gives it: 0,118
    assert cells[0][0] == "0" and cells[-1][0] == "720"
    assert float(cells[-1][2].replace(",", ".")) == pytest.approx(float(p_r.replace(",", ".")))
    assert cells[0][2] != cells[-1][2]  # 0°: p_a, the intake line
    assert cells[0][3] == cells[-1][3]  # the actual (rounded) diagram is continuous at TDC


def test_the_two_term_acceleration_is_shown_by_its_difference_from_the_exact_one():
    """Fig. 2.1: on the scale of j the dashed two-term curve could not be told from the exact one;
    a bottom panel shows their difference, whose largest size is the note's figure."""
    import numpy as np
    from conftest import shared_html, shared_run

    figure = next(f for f in shared_html("petrol-1cyl").figures if f.key == "piston").figure
    assert len(figure.axes) == 4
    difference = figure.axes[3].get_lines()[0].get_ydata()
    results = shared_run("petrol-1cyl").outputs["kinematics"].results
    assert float(np.max(np.abs(difference))) == pytest.approx(
        results["two_term_acceleration_error_max_m_s2"], rel=1e-12
    )


def test_the_mean_indicated_pressure_check_leaves_the_pumping_strokes_out():
    """The thermal calculation's p_i leaves the gas exchange to the mechanical losses, so ∮p dV,
    pumping loop included, is no check of it (0,73 % only by coincidence). The check takes
    (L_i − L_нас)/V_h."""
    from conftest import shared_html, shared_run

    r = shared_run("petrol-1cyl").outputs["indicator"].results
    swept = r["indicated_work_J"] / r["mean_indicated_pressure_Pa"]
    assert r["pumping_work_J"] < 0  # p_r > p_a: the piston works on the gas in exchange
    assert r["gross_mean_indicated_pressure_Pa"] == pytest.approx(
        (r["indicated_work_J"] - r["pumping_work_J"]) / swept
    )
    assert r["mean_indicated_pressure_deviation_percent"] == pytest.approx(
        100 * (r["gross_mean_indicated_pressure_Pa"] / r["thermal_mean_indicated_pressure_Pa"] - 1)
    )
    text = as_read(shared_html("petrol-1cyl-ru").linked_html)
    gross = f"{r['gross_mean_indicated_pressure_Pa'] / 1e6:.4f}".replace(".", ",")
    from crankdyn.report.i18n import translator

    deviation = translator("ru").number(r["mean_indicated_pressure_deviation_percent"], 2)
    assert (
        f"по диаграмме без насосных ходов – {gross}\u202fМПа; отклонение {deviation}\u202f%" in text
    )
    assert (
        "<i>L</i><sub>нас</sub> = ∫<sub>540°</sub><sup>720°</sup>" in text
    )  # the equation, with the Russian subscript


def test_the_imaginary_unit_is_upright_and_said_to_be_one():
    """In (8.4) "Σ_i e^{i(φ_i − νξ_i)}" an italic i would be both the cylinder's index and the
    imaginary unit. The unit is upright (ISO 80000-2) and named in the text; and (an upright i
    beside the index i is still one letter for two things) it is j, as in
    the engineering textbooks, i numbering the cylinders."""
    from conftest import shared_html

    for name, language, words in (
        ("inline4-petrol", "uk", "уявна одиниця"),
        ("petrol-1cyl-ru", "ru", "мнимая единица"),
    ):
        html = shared_html(name, language=language).linked_html
        assert "e<sup><i>i" not in html and "e<sup>−<i>i" not in html and "e<sup>i" not in html
        assert "e<sup>j<i>νθ</i></sup>" in html and words in html


def test_a_formula_carried_over_repeats_the_sign_at_the_start_of_the_next_line():
    """DSTU 3008:2015: a formula is carried over after =, + or −, the sign repeated on the next
    line (not "(4.4) starts its second line with − and no sign ends the first"). The
    Word export's equation, which wraps by itself, has each sign once."""
    from crankdyn.report.docx import parse_html
    from crankdyn.report.docx_math import omml
    from crankdyn.report.formula_lines import _printed_length, unbroken_parts

    long = (
        "<i>M</i> = "
        + " + ".join(f"<i>t</i><sub>{k}</sub> · <i>R</i>" for k in range(1, 16))
        + " − <i>c</i> = 108,3 Н·м"
    )
    lines = unbroken_parts(long).split('<br class="eq-break">')
    assert len(lines) >= 3
    for before, after in zip(lines, lines[1:], strict=False):
        carried = re.search(r'<span class="eq-carry">\s*([=+−])\s*</span></span>$', before)
        opening = re.sub(r"<[^>]+>", "", after).lstrip()[:1]
        assert carried and carried.group(1) == opening, (before[-80:], after[:80])
    assert all(
        _printed_length(re.sub(r'<span class="eq-carry">[^<]*</span>', "", line)) <= 66
        for line in lines
    )
    math = omml(parse_html(f'<span class="formula">{unbroken_parts(long)}</span>').children[0], 28)
    signs = re.findall(r"<m:t[^>]*>\s*([=+−])\s*</m:t>", math)
    assert signs.count("+") == 14 and signs.count("=") == 2 and signs.count("−") == 1


def test_an_equals_sign_inside_a_group_or_bracket_is_no_break_point():
    """A long worked line split at every " = " would cut "(a = 1)" in its group span."""
    from crankdyn.report.formula_lines import unbroken_parts

    long = (
        '<i>x</i> = <span class="group">(<i>a</i> = 1)</span> + '
        + " + ".join(f"<i>b</i><sub>{k}</sub>" for k in range(30))
        + " = 5"
    )
    html = unbroken_parts(long, 84)
    assert '<span class="group">(<i>a</i> = 1)</span>' in html
    opened = re.findall(r"<(/?)(span|i|sub)\b", html)
    depth = 0
    for closing, _ in opened:
        depth += -1 if closing else 1
        assert depth >= 0
    assert depth == 0


def test_the_inertia_torque_of_several_cylinders_sums_over_them(reports):
    """Not (11.3) M_j = −m_s ω² s″s′ for a four-cylinder engine, without the sum over
    its cylinders (each at its own cycle angle α_i, as the reduced moment of inertia sums them)."""
    four = reports("inline4-petrol")
    equation = re.search(r"<i>M</i><sub>j</sub> = −.*?</div>", four, flags=re.S).group(0)
    assert (
        "Σ<sub><i>i</i></sub> <i>s</i>″(<i>α</i><sub><i>i</i></sub>)<i>s</i>′(<i>α</i><sub><i>i</i></sub>)"
        in equation
    )


def test_the_crank_radius_is_printed_without_padding_zeros(reports):
    """Not "R = S/2 = 39,000 мм" (false precision) for a stroke of 78 mm."""
    one = as_read(reports("petrol-1cyl-uk"))
    assert "<i>R</i> = <i>S</i>/2 = 39\u202fмм" in one
    assert "39,000" not in one


def test_orders_are_written_as_ordinal_words(reports):
    """Not "сили порядку 1" where a Ukrainian text writes "сили першого порядку"."""
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.i18n import translator
    from crankdyn_builtin.balancing.section import orders_in_words

    t = translator("uk", default_registry().catalogs)
    assert orders_in_words(t, [1]) == "першого"
    assert orders_in_words(t, [1, 2]) == "першого і другого"
    assert orders_in_words(t, [1, 2, 4]) == "першого, другого і четвертого"
    assert orders_in_words(t, [12]) == "12"
    four = as_read(re.sub(r"<[^>]+>", "", reports("inline4-petrol")))
    assert "сама зрівноважує відцентрові сили та їхній момент, сили інерції першого порядку" in four
    assert "моменти сил інерції першого, другого, четвертого і шостого порядків" in four
    assert "порядку 1" not in four and "порядків 1, 2" not in four


def test_the_journal_torque_has_one_subscript_alphabet(reports):
    """Not table 7.2's rows with "|tк|" (Cyrillic) under its own header "tk, МПа" and
    the list of symbols' Latin t_k: one symbol, one spelling."""
    html = reports("inline4-petrol")
    assert "<sub>k</sub>" in html or "<sub>k<i>" in html
    assert "<i>t</i><sub>к" not in html


def test_an_in_line_engine_is_not_said_to_have_central_rods(reports):
    """No "шатуны: центральные" in an in-line four, where "central rod" belongs to V
    and radial engines (rods side by side or a master rod on one pin): each rod has its own pin,
    which the layout says without a word on the rods."""
    text = as_read(re.sub(r"<[^>]+>", "", reports("inline4-petrol")))
    assert "Схема двигуна: однорядна, чотири циліндри на чотирьох колінах. Колінчастий" in text
    assert "шатуни: центральні" not in text and "шатуни: по одному" not in text


def test_the_introductions_aim_is_what_the_sections_do(reports):
    """The aim names the bearings and the flywheel the note computes, not only forces, torques
    and the balance; a note of the kinematics alone claims no forces and no balance.
    The aim lists each section's own aim, in the note's order."""
    four = as_read(re.sub(r"<[^>]+>", "", reports("inline4-petrol")))
    aim = re.search(
        r"Мета роботи – виконати динамічний розрахунок заданого двигуна за методикою \[1\]: (.*?)\.\n",
        four,
    )
    assert aim, "the aim"
    for part in (
        "визначити кінематичні параметри механізму",
        "побудувати індикаторну діаграму",
        "оцінити зрівноваженість двигуна",
        "визначити навантаження на шийки й підшипники колінчастого вала",
        "підібрати маховик",
    ):
        assert part in aim.group(1), part
    assert aim.group(1).index("побудувати індикаторну") < aim.group(1).index("підібрати маховик")
    kinematics = as_read(re.sub(r"<[^>]+>", "", reports("kinematics-only")))
    aim = re.search(r"Мета роботи – виконати[^\n]*", kinematics).group(0)
    assert (
        "визначити кінематичні параметри механізму" in aim
        and "сили" not in aim
        and "зрівноваж" not in aim
    )


def test_a_circular_hodograph_has_no_major_axis_in_the_table(reports):
    """The uk check: "Велика вісь від вертикалі 0,0" beside the semi-axes 1,000 / 1,000 of the
    centrifugal force's circle: a circle has no major axis, the cell says "—"."""
    from crankdyn_builtin.balancing.notation import circular

    assert circular({"semi_major": 1.0, "semi_minor": 1.0}) and circular(
        {"semi_major": 0.0, "semi_minor": 0.0}
    )
    assert not circular({"semi_major": 1.0, "semi_minor": 0.0}) and not circular(
        {"semi_major": 1.0, "semi_minor": 0.99}
    )
    html = reports("petrol-1cyl-uk")
    row = re.search(r"<tr><td[^>]*><i>C</i></td>(.*?)</tr>", html).group(1)
    # a single cylinder's table: the force, the semi-axes, the major axis (no ratio of 1)
    assert re.findall(r"<td[^>]*>([^<]*)</td>", row)[1:3] == ["1,000 / 1,000", "—"], row


def test_the_balancing_means_table_speaks_in_words_not_a_programmers_shorthand(reports):
    """Headers like "Швидкість, ×ω" and "m r, кг·мм" read as a program's output."""
    one = reports("petrol-1cyl-uk")
    table = one[one.index("Противаги (центр мас на радіусі") :]
    head = as_read(re.sub(r"<[^>]+>", "", table[: table.index("</thead>")]))
    assert (
        "Кутова швидкість у частках ω" in head
        and "Статичний момент, кг·мм" in head
        and "Маса, кг" in head
    )
    assert "×ω" not in head and "mr" not in head  # m and r named no symbol of the list


@pytest.mark.parametrize(
    "language, present, absent",
    [
        ("uk", "з розділу 2.", "в розділі «Аналіз зрівноваженості двигуна»:"),
        ("ru", "(см. раздел 2)", "в разделе «Анализ уравновешенности двигателя»:"),
        ("en", "in section 2.", "in section “Balancing of the engine”:"),
    ],
)
def test_a_section_is_referred_to_by_its_number(language, present, absent):
    """ "(см. раздел кинематики)" names no section. A catalog text writes
    @@SECTION:stage@@ for the number that stage's section has in this report; a stage without a
    section there is named by its section's title in quotes."""
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.document import fill_section_numbers
    from crankdyn.report.i18n import translator

    t = translator(language, default_registry().catalogs)
    page = (
        '<section class="chapter" id="sec-1" data-stage="input">\n<h2 id="h-1">1 X</h2>'
        '<section class="chapter" id="sec-2" data-stage="kinematics">\n<h2 id="h-2">2 Y</h2>'
        '<section class="chapter appendix" id="sec-a" data-stage="numerics">\n<h2 id="h-a">Додаток<br>А</h2>'
    )
    words = {
        "uk": ("з розділу @@SECTION:kinematics@@.", "в розділі @@SECTION:balancing@@:"),
        "ru": ("(см. раздел @@SECTION:kinematics@@)", "в разделе @@SECTION:balancing@@:"),
        "en": ("in section @@SECTION:kinematics@@.", "in section @@SECTION:balancing@@:"),
    }[language]
    from crankdyn.report.document import _stage_title

    filled = fill_section_numbers(
        page + " ".join(words), lambda stage: _stage_title(t, default_registry(), stage), t
    )
    assert present in filled and absent in filled and "@@" not in filled
    # the bundled reports: every mark filled
    html = shared_html("petrol-1cyl-ru", language=language).linked_html
    assert "@@SECTION" not in html
    assert present.rstrip(".)") in html


#: An in-line six with a flywheel, as a course note in Russian or Ukrainian.
_SIX = {"engine": {"cylinders": 6, "firing_order": [1, 5, 3, 6, 2, 4]}, "torsion": None}


def _six_html(language: str) -> str:
    return shared_html("inline4-petrol", _SIX, language=language).linked_html


def _plain(html: str) -> str:
    text = re.sub(r"<[^>]+>", "", as_read(html)).replace("\u2060", "")
    return re.sub(r"[\u00a0\u202f]", " ", text)


def test_the_references_are_textbooks_and_the_standards_in_force():
    """No student paper without a year among the sources; a Russian note follows ГОСТ 2.105-2019
    and describes its sources after ГОСТ Р 7.0.100-2018, a Ukrainian one ДСТУ 3008:2015 and
    ДСТУ 8302:2015; each listed source is cited."""
    for language in ("ru", "uk"):
        html = _six_html(language)
        sources = re.findall(
            r"<li>(.*?)</li>", re.search(r'<ol class="references">(.*?)</ol>', html, re.S).group(1)
        )
        text = _plain(html[: html.index('<ol class="references">')])
        cited = {
            int(n) for group in re.findall(r"\[([\d, –]+)", text) for n in re.findall(r"\d+", group)
        }
        # a range "[5–7]" cites 6 too
        for a, b in re.findall(r"\[[^\]]*?(\d+)–(\d+)", text):
            cited |= set(range(int(a), int(b) + 1))
        assert len(sources) >= 10 and set(range(1, len(sources) + 1)) <= cited, (language, cited)
        for word in ("студ.", "[б. г.]", "Тристень"):
            assert not any(word in source for source in sources), word
        if language == "ru":
            assert (
                "оформлена в соответствии с ГОСТ 7.32-2017 [2] и ГОСТ 2.105-2019 [3], список "
                "использованных источников – по ГОСТ Р 7.0.100-2018 [4]."
            ) in text
            assert sources[2].startswith("ГОСТ 2.105-2019. Единая система конструкторской")
            assert sources[3].startswith("ГОСТ Р 7.0.100-2018. Система стандартов по информации")
        else:
            assert "оформлено відповідно до ДСТУ 3008:2015 [2]" in text
            assert "перелік джерел посилання – за ДСТУ 8302:2015 [4]" in text


def test_a_quantity_is_printed_with_one_rounding_wherever_the_note_states_it():
    """The two-term formulas' largest differences in the kinematics section and in the appendix,
    the output torque's range in the conclusions and in the journals' table: the same digits;
    the speeds of the fluctuation and the flywheel of the exact solution to 4 significant digits."""
    html = _six_html("ru")
    text = _plain(html)
    section = re.search(
        r"разность между двучленными и точными формулами: ([\d,]+) мм для перемещения и "
        r"([\d ,]+) м/с² для ускорения",
        text,
    )
    appendix = re.search(
        r"наибольшая разность перемещений ([\d,]+) мм, ускорений ([\d ,]+) м/с²", text
    )
    assert section and appendix and section.groups() == appendix.groups(), (section, appendix)
    low, high = re.search(r"момент изменяется от (−?[\d ,]+) до ([\d ,]+) Н·м", text).groups()
    journals = re.search(
        r"<table[^>]*>(?:(?!</table>).)*Наибольший момент, Н·м.*?</table>", html, re.S
    )
    last = re.findall(r"<td[^>]*>([^<]*)</td>", journals.group(0).rsplit("<tr>", 1)[-1])
    assert [_plain(cell) for cell in last[1:3]] == [high, low], (last, low, high)
    speeds = re.search(
        r"Угловая скорость изменяется от ([\d,]+) рад/с \(α = [\d,]+°\) до ([\d,]+) рад/с", text
    ).groups()
    inertia = re.search(
        r"составляет Jмах = ([\d,]+) кг·м²; по энергетическому методу – ([\d,]+)", text
    )
    for number in (*speeds, *inertia.groups()):
        assert len(number.replace(",", "").lstrip("0")) == 4, number


def test_what_stays_unbalanced_is_said_to_be_without_the_fitted_means(reports):
    """Counterweights or balance shafts fitted: the conclusion that lists the unbalanced forces and
    moments says it is without them, the next says what they balance (the two do not contradict
    each other); with none fitted, it lists what stays unbalanced."""
    text = as_read(re.sub(r"<[^>]+>", "", reports("inline4-petrol")))
    unbalanced = text.index("Зрівноваженість: без засобів зрівноваження незрівноважені ΣP")
    assert text.index("Засоби зрівноваження: два зрівноважувальні вали", unbalanced) > unbalanced
    assert "Зрівноваженість: незрівноважені" not in text


def test_a_v_engines_bank_angle_is_in_the_symbol_list_and_its_spacing_is_one_banks(reports):
    """Table 1.1 of a V engine gives the bank angle γ, which the list of symbols then explains,
    and the distance a between neighbouring cylinders of one bank (a V's neighbours along the
    shaft are not its neighbouring cylinders: the two of one crank stand a rod's width apart)."""
    text = as_read(re.sub(r"<[^>]+>", "", reports("v8-petrol")))
    assert "γ – кут розвалу циліндрів, між осями їхніх рядів, °" in text
    assert "Відстань між осями сусідніх циліндрів одного ряду" in text
    assert "a – відстань між осями сусідніх циліндрів одного ряду, мм" in text
    inline = as_read(re.sub(r"<[^>]+>", "", reports("inline4-petrol")))
    assert "Відстань між осями сусідніх циліндрів" in inline
    assert "одного ряду" not in inline and "кут розвалу" not in inline


def test_a_boxers_spacing_is_between_neighbouring_cylinders_of_opposite_banks():
    """A boxer's cylinders have crank pins of their own: the neighbours along the shaft are of
    opposite banks, a apart, as the balancing's moments take it (not one bank's, 2a apart); the
    given data call it the offset of their axes along the shaft."""
    from conftest import EXPLORED_BOXER, shared_html

    html = shared_html("inline4-petrol", EXPLORED_BOXER, "uk", ("balancing",)).linked_html
    text = as_read(re.sub(r"<[^>]+>", "", html))
    # opposed cylinders are not "neighbouring" across the engine: their axes are offset along the shaft
    assert "Зміщення осей сусідніх циліндрів уздовж колінчастого вала" in text
    assert "Відстань між осями сусідніх циліндрів" not in text
    # and the list of symbols says the same of a
    assert "a – зміщення осей сусідніх циліндрів уздовж колінчастого вала, мм" in text
    assert "відстань між осями сусідніх циліндрів" not in text


def test_the_counterweight_radius_is_listed_in_millimetres_as_its_table_gives_it():
    """The list of symbols gave ρ_пр in metres alone beside lengths in "мм (у формулах – м)",
    while the balancing table prints the radius in millimetres."""
    from conftest import shared_html

    page = shared_html("inline3-petrol", {"flywheel": {"required_irregularity": 0.02}}, "uk")
    assert "радіус центра мас противаги, мм (у формулах – м)" in page.linked_html


def test_a_radials_balancing_gives_the_reason_it_has_no_longitudinal_moments(reports):
    """A radial (or a V-twin on fork-and-blade rods) is not a "single-row engine": its cylinders
    share one crank in one plane across the shaft, which is why no longitudinal moment arises."""
    text = as_read(re.sub(r"<[^>]+>", "", reports("radial9-aircraft")))
    assert "однорядн" not in text
    assert "лежать в одній площині, перпендикулярній до осі вала" in text
    assert "тож поздовжніх моментів немає" in text


def test_the_assignment_gives_the_crank_angles_of_several_cranks_only():
    """A 270° twin's cranks define the engine: the assignment gives them ("кути колін … 0; 270°")
    and its firing order. A V-twin's one crank has no angle to give ("кути колін … 0°" said
    nothing)."""
    from conftest import TWIN_270_ENGINE, V_TWIN_ENGINE, shared_html

    def assignment(name, engine):
        html = shared_html(name, {"engine": engine}, "uk", ("kinematics",)).linked_html
        part = html.split('class="assignment"', 1)[1].split("</section>", 1)[0]
        return as_read(re.sub(r"<[^>]+>", "", part))

    twin = assignment("inline3-petrol", TWIN_270_ENGINE)
    assert "кути колін (відставання від першого) 0; 270°" in twin
    assert "порядок роботи циліндрів 1–2" in twin
    v_twin = assignment("v8-petrol", V_TWIN_ENGINE)
    assert "кути колін" not in v_twin
    assert "порядок роботи циліндрів 1Л–1П" in v_twin


def test_what_the_means_leave_points_to_the_slave_cylinders_parts(reports):
    """A radial's means leave only the negligible ΣP_IV and ΣP_VI, said so just before, and the
    parts only its slave cylinders make, said next: the means' conclusion does not list the
    negligible ones again as what remains, and the slaves' parts follow it."""
    text = as_read(re.sub(r"<[^>]+>", "", reports("radial9-aircraft")))
    conclusions = text[text.index("Крім них, незрівноважені сили четвертого і шостого порядків") :]
    means = conclusions[conclusions.index("Засоби зрівноваження:") :]
    sentence = means.split(".", 1)[0]
    assert "ΣPIV" not in sentence and "залишаються" not in sentence
    assert "їхнє розташування зрівноважило б складову сил першого порядку" in means[:600]


def test_a_radials_one_cylinder_tables_name_the_master_cylinder(reports):
    """A radial's kinematics and dynamics tables are its master cylinder's (the slaves' pistons
    move otherwise): "of one cylinder" read as any of them."""
    radial = as_read(re.sub(r"<[^>]+>", "", reports("radial9-aircraft")))
    assert "Кінематика поршня і шатуна головного циліндра" in radial
    assert "Динамічний розрахунок головного циліндра [1, табл. Б.1]" in radial
    single = as_read(re.sub(r"<[^>]+>", "", reports("petrol-1cyl")))
    assert "головного циліндра" not in single
    assert "Динамічний розрахунок одного циліндра [1, табл. Б.1]" in single


def test_a_radials_largest_tdc_shift_reads_the_same_in_text_note_and_table(reports):
    """The slaves' largest TDC shift was "до 4°" in the section, "до 3,952°" in the method note
    and 3,95 in the slaves' table: one value, to the hundredth, as the table gives it."""
    from conftest import shared_run

    slaves = shared_run("radial9-aircraft").outputs["bays"].results["slaves"]
    largest = max(abs(s["tdc_shift_deg"]) for s in slaves)
    printed = f"{largest:.2f}".replace(".", ",").rstrip("0").rstrip(",")
    text = as_read(re.sub(r"<[^>]+>", "", reports("radial9-aircraft")))
    shifts = re.findall(r"\(до ([\d,]+)°\)", text)
    assert len(shifts) >= 2 and set(shifts) == {printed}, shifts


def test_a_multicylinder_positions_figure_says_whose_piston_its_positions_are(reports):
    """The positions figure of a V8 marks the dead centres and extremes of cylinder 1Л's piston
    (the other pistons stand elsewhere at those crank angles): the sentence before it says so;
    a single cylinder's needs no name."""
    v8 = as_read(re.sub(r"<[^>]+>", "", reports("v8-petrol")))
    assert "Механізм у характерних положеннях поршня циліндра 1Л (у його мертвих точках" in v8
    single = as_read(re.sub(r"<[^>]+>", "", reports("petrol-1cyl")))
    assert "Механізм у характерних положеннях (у мертвих точках" in single


def test_a_given_indicator_diagram_is_named_by_what_it_is_not_by_its_file():
    """A course note names no file: the given data said "Файл індикаторної діаграми |
    diesel6-1600rpm.ind" and the method note "з файлу diesel6-1600rpm.ind"."""
    from conftest import shared_html

    html = shared_html("inline6-diesel-trace", language="uk").linked_html
    text = as_read(re.sub(r"<[^>]+>", " ", html))
    assert re.search(r"Індикаторна діаграма\s+задана розрахунком у програмі Diesel-RK", text)
    assert "diesel6-1600rpm" not in text and "Файл" not in text


def test_a_boosted_engines_pumping_work_is_called_a_gain():
    """With the intake (0,2 MPa) above the exhaust pressure (0,16 MPa) the pumping strokes' work
    is positive: the note called it the pumping losses counted among the mechanical ones."""
    from conftest import shared_html, shared_run

    boost = {
        "cycle": {
            "intake_pressure": "0.2 MPa",
            "exhaust_pressure": "0.16 MPa",
            "max_pressure": "14 MPa",
        }
    }
    stages = ("kinematics", "indicator")
    assert (
        shared_run("diesel-1cyl", boost, stages).outputs["indicator"].results["pumping_work_J"] > 0
    )
    text = as_read(
        re.sub(r"<[^>]+>", "", shared_html("diesel-1cyl", boost, "uk", stages).linked_html)
    )
    assert "тож ця робота додатна – виграш, а не втрата" in text
    assert "насосні втрати в ньому віднесено до механічних" not in text
    usual = as_read(
        re.sub(r"<[^>]+>", "", shared_html("diesel-1cyl", None, "uk", stages).linked_html)
    )
    assert "насосні втрати в ньому віднесено до механічних" in usual


def test_an_aircraft_engines_left_out_torsion_has_a_reason_that_covers_it(reports):
    """An aircraft engine without its propeller's inertia: the sections left out are named by
    their titles for a propeller, and the reason covers the torsion and the speed's fluctuation
    too, which that inertia would allow: the assignment gives none."""
    text = as_read(re.sub(r"<[^>]+>", "", reports("radial9-aircraft")))
    assert re.search(
        r"У записці не розраховано нерівномірність обертання з повітряним гвинтом за енергетичним "
        r"методом, [^:]*крутильні "
        r"коливання: авіаційний двигун не має маховика \(його роль виконує повітряний гвинт\), а "
        r"момент інерції гвинта в завданні не вказано\.",
        text,
    )


def test_the_fullness_remark_names_the_excess_work_only_with_a_flywheel_section():
    """A V8 note without a flywheel section said that "the excess work" comes out larger, a
    quantity it never computes; with a flywheel it is said."""
    from conftest import shared_html

    stages = ("kinematics", "indicator", "forces", "bays", "torque", "flywheel")
    plain = as_read(
        re.sub(r"<[^>]+>", "", shared_html("v8-petrol", None, "en", stages).linked_html)
    )
    assert "so the mean indicated pressure and the mean torque come out up to" in plain
    assert "excess work come out" not in plain
    flywheel = {"flywheel": {"required_irregularity": 0.01}}
    sized = as_read(
        re.sub(r"<[^>]+>", "", shared_html("v8-petrol", flywheel, "en", stages).linked_html)
    )
    assert "the mean torque and the excess work come out up to" in sized


def test_sources_cited_together_share_one_bracket():
    """ "[@kolchin2002; @blair1996]" in a catalog's text is "[6, 10]", as the standard cites
    several sources, not "[6], [10]"; three in a row are a range; a source cited first here is
    added to the list in the order cited; a single key keeps its page or figure."""
    from crankdyn.report.document import cite_sources

    references = ["a", "b"]
    text = cite_sources("x [@a; @c]. y [@b, fig. 3]. z [@c; @d; @a; @b]", references)
    assert text == "x [1, 3]. y [2, fig. 3]. z [1–4]"
    assert references == ["a", "b", "c", "d"]


def test_a_lone_letter_stays_with_the_word_its_hyphen_opens():
    """The title page broke "V-" | "образного": a capital Latin letter and a hyphen opening a
    word are bound to it by a word joiner; other hyphens ("1–2", "a-b", "AB-C", "X-5") keep
    their breaks."""
    from crankdyn.report.typeset import unbreakable_html

    html = unbreakable_html("<p>V-образного, W-подібного, V-twin; a-b, AB-C, X-5, 1-2</p>")
    assert "V-\u2060образного, W-\u2060подібного, V-\u2060twin;" in html
    assert "a-b, AB-C, X-5, 1-2" in html
    assert unbreakable_html(html) == html


def test_an_engines_designation_stays_on_one_line():
    """The assignment broke "6Ч | 8,4/8,96": the letters of a designation and its D/S are bound
    by a no-break space; a word that merely starts with the letter is not."""
    from crankdyn.report.typeset import unbreakable_html

    html = unbreakable_html("<p>6ЧН 8,4/8,96, 4Ch 8.2/7.8 і 1Ч 10,5/12; Чорний 5/6</p>")
    assert "6ЧН\u00a08,4/" in html and "4Ch\u00a08.2/" in html and "1Ч\u00a010,5/" in html
    assert "Чорний 5/" in html
