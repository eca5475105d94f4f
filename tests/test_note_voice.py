"""A note is the student's own text: it states what the calculation shows and never tells its
reader what to do ("перевірте N_e", "уменьшите диаметр"), and it speaks of the engine, not of the
program that computed it: no run time in milliseconds, no reference run, tolerance setting or
machine precision, no "if I_G is given the note will contain", no list of left-out modules."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CATALOGS = sorted(
    [*ROOT.glob("templates/i18n/*.toml"), *ROOT.glob("plugins/crankdyn_builtin/*/i18n/*.toml")]
)
#: second-person imperatives a supervisor strikes out of a note
IMPERATIVE = {
    "en": r"\b(?:check|choose|reduce|increase|take|give|set)\s+(?:the|a|N_e|another)\b",
    "uk": r"\b(?:перевірте|зменште|збільште|оберіть|візьміть|задайте|вкажіть)\b",
    "ru": r"\b(?:проверьте|уменьшите|увеличьте|выберите|возьмите|задайте|укажите)\b",
}
_SUPERSCRIPT_12_TO_19 = "10⁻¹[²³⁴⁵⁶⁷⁸⁹]"
#: Phrases of a program, not of an engineer, in a course note (tests/test_scene_corpus.py reads
#: every generated note for them): the run time in milliseconds, the reference run, the tolerance
#: as a setting, machine precision and a rounding bound or residue, what the note would contain
#: with other input, a choice of the program presented as the assignment's, a list of the
#: calculations left out with the reasons, a check style's "(as the assignment states)".
SOFTWARE_PHRASES = {
    "en": (
        r"\b(?:takes|took|would take) [\d.,]+ ms\b",
        r"\b(?:off|from) the (?:step-independent )?reference\b",
        r"√\(tolerance|\(tolerance [\d.]+ ?%\)|\bmore than the tolerance\b",
        r"\bmachine precision\b",
        _SUPERSCRIPT_12_TO_19,
        r"\bunless the assignment gives it\b",
        r"\bthe assignment asks for the approximate kinematics\b",
        r"\bwith I_?G the report\b|\bthe report (?:adds|will contain)\b",
        r"\bexplorer\b|\btop-ranked\b",
        r"\bassignment (?:gives|names) no (?:angle step|firing order)\b",
        r"\bleft out of this report, and why\b|“[^”]+”: the assignment gives no\b",
        r"\(as the assignment states\)",
    ),
    "uk": (
        r"\b(?:триває|тривав би|займає) [\d,]+ мс\b",
        r"\bеталон\w*",
        r"\bдопуск[ау]?\s*(?:/|\d)",
        r"\bмашинн\w* точн\w*",
        _SUPERSCRIPT_12_TO_19,
        r"\(якщо (?:її|його|їх) не задано\)",
        r"\b[ув] завданні обрано наближену кінематику\b",
        r"\bякщо задати\b|\bзаписка міститиме\b",
        r"\bдослідник\w* поряд\w*|\bза рейтингом\b",
        r"\bу завданні не вказано кроку\b|\bсцена не задає\b",
        r"\bрозрахунки, не включені до записки\b|«[^»]+»: у завданні (?:немає|не вказано)",
        r"\(як зазначено в завданні\)|\(зазначено в завданні\)",
    ),
    "ru": (
        r"\b(?:длится|длился бы|занимает) [\d,]+ мс\b",
        r"\bэталон\w*",
        r"\bдопуск[ау]?\s*(?:/|\d)",
        r"\bмашинн\w* точн\w*",
        _SUPERSCRIPT_12_TO_19,
        r"\(если (?:она|он|оно|они) не задан\w*\)",
        r"\bв задании выбрана приближённая кинематика\b",
        r"\bесли задать\b|\bзаписка будет содержать\b",
        r"\bисследовател\w* порядк\w*|\bпо рейтингу\b",
        r"\bв задании не указан шаг\b|\bсцена не задаёт\b",
        r"\bрасч[её]ты, не включ[её]нные в записку\b|«[^»]+»: в задании (?:нет|не указан)",
        r"\(как указано в задании\)|\(указано в задании\)",
    ),
}


def software_phrases(language: str) -> re.Pattern:
    return re.compile("|".join(SOFTWARE_PHRASES[language]), flags=re.IGNORECASE)


#: entries that are written into the note: a section's or the conclusions' sentence, and the
#: mechanism checks said in the sections themselves
NOTE_KEYS = re.compile(r"(?:_section|_conclusion|^rim_speed_high)$")


def _entries(path: Path):
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    for table in data.values():
        if isinstance(table, dict):
            for key, text in table.items():
                if isinstance(text, str):
                    yield key, text


@pytest.mark.parametrize("path", CATALOGS, ids=lambda p: str(p.relative_to(ROOT)))
def test_a_note_sentence_tells_its_reader_nothing_to_do(path):
    language = path.stem.rsplit(".", 1)[-1]
    pattern = re.compile(IMPERATIVE[language], flags=re.IGNORECASE)
    orders = [key for key, text in _entries(path) if NOTE_KEYS.search(key) and pattern.search(text)]
    assert not orders, orders


#: The phrases a supervisor returned course notes for, each caught by SOFTWARE_PHRASES.
RETURNED = {
    "ru": (
        "весь расчёт сил и моментов длится 0,076 мс; с шагом 30° он длился бы 0,024 мс",
        "отклоняются на 0,1053 % от эталона, не зависящего от шага",
        "не превышает 1°·√(допуск/0,1 %)",
        "больше допуска 0,1000 %",
        "коэффициенты вычислены с машинной точностью",
        "наибольшая относительная разность < 10⁻¹² для сил",
        "отнесённая к их наибольшему моменту: 1,462·10⁻¹⁷",
        "точно равнялась степени сжатия главного (если она не задана)",
        "если задать I_G, записка будет содержать момент сил инерции шатуна",
        "Сцена не задаёт порядок работы: взят лучший по рейтингу порядок исследователя порядков",
        "В задании не указан шаг по углу: выбран Δα = 1°",
        "Расчёты, не включённые в записку, и причины:",
        "«Маховик»: в задании нет данных о маховике",
        "Чередование вспышек неравномерное (как указано в задании).",
    ),
    "uk": (
        "увесь розрахунок сил і моментів триває 0,23 мс; із кроком 30° він тривав би 0,086 мс",
        "відхиляються на 0,02174 % від еталона",
        "(допуск 0,1 %)",
        "з машинною точністю",
        "< 10⁻¹² для сил і < 10⁻¹² для моментів",
        "Робота сил інерції … 1,846·10⁻¹⁷",
        "замінено точними в усіх випадках (також коли в завданні обрано наближену кінематику)",
        "якщо задати IG, записка міститиме момент сил інерції шатуна",
        "узято найкращий за рейтингом порядок дослідника порядків роботи",
        "У завданні не вказано кроку за кутом: вибрано Δα = 1°",
        "Розрахунки, не включені до записки, і причини:",
        "«Похибка та час обчислення»: у завданні немає даних про робочий цикл",
        "Чергування спалахів нерівномірне (як зазначено в завданні).",
    ),
    "en": (
        "the whole calculation of the forces and torques takes 0.076 ms",
        "a step of 30° would take 0.024 ms",
        "off the step-independent reference (tolerance 0.1 %)",
        "computed to machine precision",
        "the largest relative difference < 10⁻¹²",
        "relative to their peak torque: 1.462·10⁻¹⁷",
        "the master's compression ratio (unless the assignment gives it)",
        "also when the assignment asks for the approximate kinematics",
        "with I_G the report adds the rod's inertia couple",
        "the firing-order explorer's top-ranked one was taken",
        "The assignment gives no angle step: Δα = 1° was chosen",
        "Stages left out of this report, and why:",
        "“Flywheel”: the assignment gives no flywheel data",
        "The firing is uneven (as the assignment states).",
    ),
}
#: An engineer's words the phrases leave alone.
KEPT = {
    "ru": (
        "в пределах допуска пособия 2–3 % [1]",
        "задержка воспламенения τз = 1,5 мс",
        "При более грубом шаге Δα = 24° относительная погрешность M_ср возросла бы до 12 %",
        "Работа сил инерции за цикл равна нулю с точностью до округления",
        "Порядок работы цилиндров выбран в этом расчёте",
        "коэффициент 2,5·10⁻⁴",
    ),
    "uk": (
        "що в межах допуску посібника 2–3 % [1]",
        "За грубішого кроку Δα = 22,5° відносна похибка M_сер зросла б до 7,0 %",
        "відрізняються від точних значень на 0,022 %, у межах точності 0,1 %, прийнятої в цьому розрахунку",
        "найбільша відносна різниця практично нульова",
    ),
    "en": (
        "the reference list",
        "With a coarser step, Δα = 30°, the relative error of M_m would grow to 1.2 %",
        "differ from their exact values by 0.11 %, more than the 0.1 % this calculation aims at",
    ),
}


@pytest.mark.parametrize("language", sorted(RETURNED))
def test_the_software_phrases_catch_what_a_supervisor_returns_and_keep_an_engineers(language):
    pattern = software_phrases(language)
    assert [text for text in RETURNED[language] if not pattern.search(text)] == []
    assert [text for text in KEPT[language] if pattern.search(text)] == []


#: Entries of the full report's numerics chapter (``detail = "full"``): the study of the error
#: against run time, with its reference, timing and tolerance, which a course note leaves out.
FULL_REPORT_ONLY = {
    "numerics": re.compile(
        r"(?:steps_intro|reference_\w+|theoretical_note|steps_caption|timing_\w+|time_\w+"
        r"|axis_\w+|refused_\w+|forms_\w+|see_\w+|solver_\w+|sources|kinematics_printed_\w+)"
    ),
    "report": re.compile(r"skipped_intro|extremum_rule|timing_\w+"),
    # the solvers compared with the exact solution (a course note says exact_text_course)
    "speed_fluctuation": re.compile(r"exact_text|choice_\w+|torsion_solvers_intro"),
    "symbol": re.compile(r"reference_\w+"),  # the letters of the study's reference values
}
#: A catalog entry's parameters ("{tolerance}"), which are no words of the note.
_PARAMETER = re.compile(r"\{[^}]*\}")


def _sections(path: Path):
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    for section, table in data.items():
        if isinstance(table, dict):
            for key, text in table.items():
                if isinstance(text, str):
                    yield section, key, text


@pytest.mark.parametrize("path", CATALOGS, ids=lambda p: str(p.relative_to(ROOT)))
def test_a_course_notes_sentence_speaks_of_the_engine_not_of_the_program(path):
    """Every catalog entry a course note can print is free of the program's phrases; the full
    report's study of the error against run time keeps its reference, timing and tolerance."""
    language = path.stem.rsplit(".", 1)[-1]
    pattern = software_phrases(language)
    found = [
        f"{section}.{key}: {match.group(0)!r}"
        for section, key, text in _sections(path)
        if not (section in FULL_REPORT_ONLY and FULL_REPORT_ONLY[section].fullmatch(key))
        and (match := pattern.search(_PARAMETER.sub("", text)))
    ]
    assert not found, found


def _text(html: str) -> str:
    text = re.sub(r"<[^>]+>", "", html).replace("\u2060", "")
    return re.sub(r"[\u00a0\u2009\u202f]", " ", text)  # the spaces kept on one line


def test_an_uneven_firing_is_explained_by_the_cranks_in_ordinary_text():
    """A four-stroke twin with cranks at 0 and 180°: each cylinder fires once in 720°, so the
    firings come 180° and 720 − 180 = 540° apart instead of 360°; said as text of the section
    (no check style), without "as the assignment states"."""
    from conftest import shared_html

    twin = {
        "flywheel": None,
        "engine": {
            "cylinders": 2,
            "crank_angles_deg": [0, 180],
            "firing_order": [1, 2],
            "uneven_firing": True,
        },
    }
    html = shared_html("inline4-petrol", twin, language="uk", stages=["bays"]).linked_html
    sentence = re.search(r"<p[^>]*>Чергування спалахів нерівномірне:.*?</p>", html).group(0)
    assert sentence.startswith("<p>"), sentence  # no check-bad (red bold) paragraph
    assert (
        "раз за цикл (720° повороту колінчастого вала), і за схеми колін 0; 180° інтервали між "
        "спалахами становлять 180° і 540° замість рівних 360°."
    ) in _text(sentence)
    assert "зазначено в завданні" not in html


def test_a_firing_order_the_calculation_chose_is_no_given_datum():
    """An in-line four without a firing order: Table 1.1 (the task's data) has no firing-order
    row, the section says the order is this calculation's choice, and the appendix gives the
    order in the report's letters and the cranks with the reason, not a program's ranking."""
    from conftest import shared_html, shared_run

    changes = {
        "flywheel": None,
        "engine": {"firing_order": None, "crank_angles_deg": None},
    }
    result = shared_run("inline4-petrol", changes, stages=["bays"])
    assert result.scene.firing_order_chosen
    html = shared_html("inline4-petrol", changes, language="ru", stages=["bays"]).linked_html
    given = re.search(r'<table class="data values".*?</table>', html, flags=re.S).group(0)
    assert "Порядок работы цилиндров" not in given
    assert "Порядок работы цилиндров выбран в этом расчёте" in html
    order = "–".join(str(c) for c in result.scene.engine.firing_order)
    cranks = "; ".join(f"{x:g}" for x in result.outputs["bays"].results["crank_angles_deg"])
    assert (
        f"Порядок работы цилиндров {order} и схема колен {cranks}° выбраны в этом расчёте"
        in _text(html)
    )
    assert not software_phrases("ru").search(_text(html))


def test_a_step_that_misses_the_required_accuracy_says_so_and_names_the_step_that_meets_it():
    """Peaks of the forces required to 0,001 % at a given step of 1°: the note says the step misses
    it, by the error measured, and names the coarsest studied step that meets it with the
    decimal comma ("0,1°", never "0.1°")."""
    from conftest import shared_html, shared_run

    changes = {"flywheel": None, "numerics": {"tolerance": 1e-5, "time_budget_s": 3600}}
    r = shared_run("inline4-petrol", changes).outputs["numerics"].results
    at = r["at_scene_step"]
    assert at["peaks_error_relative"] > 1e-5 and not at["peaks_within_tolerance"]
    text = _text(shared_html("inline4-petrol", changes, language="uk").linked_html)

    def worst(row):
        return max(
            row[f"{q}_error_relative"]
            for q in ("tangential_max", "tangential_min", "resultant_max")
        )

    good = [s["angle_step_deg"] for s in r["steps"] if worst(s) <= 1e-5]
    if good:
        finer = f"{max(good):g}".replace(".", ",")
        expected = f"тобто більше за точність 0,001 %, прийняту в цьому розрахунку; цю точність дає крок Δα = {finer}°"
    else:
        expected = "тобто більше за точність 0,001 %, прийняту в цьому розрахунку; жоден із перевірених кроків"
    assert "З кроком Δα = 1° піки тангенціальної та сумарної сил відрізняються" in text
    assert expected in text, re.search(r"З кроком Δα = 1° піки[^.]*\.", text).group(0)
    assert not re.search(r"Δα = \d+\.\d", text)


#: An in-line six with a flywheel, whose cranks balance it: a course note in Russian or Ukrainian.
_SIX = {"engine": {"cylinders": 6, "firing_order": [1, 5, 3, 6, 2, 4]}, "torsion": None}


def _catalog_texts(language: str) -> str:
    return "\n".join(
        text
        for path in CATALOGS
        if path.stem.rsplit(".", 1)[-1] == language
        for _, _, text in _sections(path)
    )


def test_a_note_says_what_an_engineer_writes():
    """ "средств уравновешивания не требуют", not "Уравновешивать ничего не нужно"; results
    "сопоставлены", not "сравнены"; a check whose forces and moments agree to rounding says it once;
    the rounding of the indicator diagram in an engineer's words, with its source; the time of the
    calculation in one clause against a coarser step."""
    from conftest import shared_html

    ru_catalogs = _catalog_texts("ru")
    assert not re.search(r"\bсравнен[аоы]?\b", ru_catalogs)
    for language in ("ru", "uk", "en"):
        assert not re.search(
            r"эрмитов|ермітов|Hermite|ничего не нужно|нічого не потрібно", _catalog_texts(language)
        )
    ru_html = shared_html("inline4-petrol", _SIX, language="ru").linked_html
    ru = _text(ru_html)
    uk = _text(shared_html("inline4-petrol", _SIX, language="uk").linked_html)
    assert "Свободные силы и моменты двигателя средств уравновешивания не требуют:" in ru
    assert "Вільні сили й моменти двигуна засобів зрівноваження не потребують:" in uk
    assert "силы и моменты совпадают с точностью до погрешности округления." in ru
    assert "практически нулевая для сил" not in ru and "практично нульова для сил" not in uk
    rounding = re.search(
        r"у этих точек линии расчётной диаграммы сопряжены плавными дугами \[(\d+)\]", ru
    )
    sources = re.findall(r"<li>(.*?)</li>", ru_html[ru_html.index('<ol class="references">') :])
    assert rounding and _text(sources[int(rounding.group(1)) - 1]).startswith("Колчин А. И.")
    assert re.search(
        r"При более грубом шаге Δα = [\d,]+° относительная погрешность \S+ "
        r"возросла бы до [\d,]+ %",
        ru,
    )
    # a course note states the step and its errors, not a computer's run time
    assert "время расчёта" not in ru and "скоротив би час" not in uk
    assert "С этим шагом расчёт" not in ru and "З цим кроком розрахунок" not in uk


def test_the_verb_of_the_left_out_calculations_agrees_with_their_number():
    """One calculation left out "не рассчитывается", several "не рассчитываются" (ru); the
    Ukrainian impersonal "не розраховано" holds for any number and takes its object in the
    accusative ("динаміку шатуна"), "У записці" opening the sentence."""
    from conftest import shared_html

    one = _text(shared_html("inline4-petrol", _SIX, language="ru").linked_html)
    several = _text(
        shared_html("inline4-petrol", {**_SIX, "flywheel": None}, language="ru").linked_html
    )
    assert "Динамика шатуна в записке не рассчитывается:" in one
    assert re.search(r"Маховик, динамика шатуна, [^:]* в записке не рассчитываются:", several)
    uk = _text(shared_html("inline4-petrol", {**_SIX, "flywheel": None}, language="uk").linked_html)
    assert re.search(r"У записці не розраховано маховик, динаміку шатуна, [^:]*:", uk)
    assert "динаміка шатуна" not in uk.lower()


def test_an_english_reference_names_its_sources_language_one_way():
    """A source in another language than the note's is marked the same way in every entry of the
    English list: "(in Russian)." after the entry's last full stop, as ГОСТ 7.1 and the English
    translations of the Russian and Ukrainian lists have it."""
    marked = {}
    for path in CATALOGS:
        if not path.name.endswith("en.toml"):
            continue
        for key, entry in tomllib.loads(path.read_text(encoding="utf-8")).get("ref", {}).items():
            if re.search(r"\(in [A-Z][a-z]+\)", entry):
                marked[f"{path.name}:{key}"] = entry
    assert len(marked) >= 15, sorted(marked)
    odd = {k: e[-40:] for k, e in marked.items() if not re.search(r"\. \(in [A-Z][a-z]+\)\.$", e)}
    assert not odd, odd
