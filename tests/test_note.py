"""The explanatory note a student hands in (DSTU 3008 layout, typography and language).

One PDF per language (uk, ru, en) is rendered once per test and every acceptance check runs on
it: typography (no ``^``, ``_``, ``e-03``; decimal comma), the abstract's counts against the
document, references to captions before the captions, citations, continued tables. The HTML
checks (no English words in uk/ru, worked substitutions equal to their table rows) need no PDF.
"""

from __future__ import annotations

import html as html_lib
import math
import re
import shutil
import subprocess
import types

import markupsafe
import pytest
from conftest import ARTIFACTS, as_read, modified, shared_html, write_scene
from page_layout import layout_problems, page_texts
from test_worked import check_worked

from crankdyn.cli import examples_dir, main
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.report.i18n import translator
from crankdyn.scene.model import load_scene, scene_from_dict

REGISTRY = default_registry()

needs_poppler = pytest.mark.skipif(
    shutil.which("pdftotext") is None or shutil.which("pdftoppm") is None,
    reason="poppler-utils not installed (bash .ci/setup.sh installs it)",
)

#: Per language: scene, extra CLI arguments, caption words, the words a reference to them uses,
#: the continuation label, the abstract and conclusions headings (as printed, upper case).
LANGUAGES = {
    "uk": (
        "petrol-1cyl-uk",
        [],
        "Таблиця",
        "Рисунок",
        "табл.",
        "рис.",
        "Продовження таблиці",
        "РЕФЕРАТ",
        "ВИСНОВКИ",
        "ПЕРЕЛІК ДЖЕРЕЛ ПОСИЛАННЯ",
    ),
    "ru": (
        "petrol-1cyl-ru",
        [],
        "Таблица",
        "Рисунок",
        "табл.",
        "рис.",
        "Продолжение таблицы",
        "РЕФЕРАТ",
        "ЗАКЛЮЧЕНИЕ",
        "СПИСОК ИСПОЛЬЗОВАННЫХ ИСТОЧНИКОВ",
    ),
    # --lang overrides the scene's language, as a student would do it on the command line
    "en": (
        "petrol-1cyl-ru",
        ["--lang", "en"],
        "Table",
        "Figure",
        "table",
        "figure",
        "Table",
        "ABSTRACT",
        "CONCLUSIONS",
        "REFERENCES",
    ),
}

#: Words each note must show (headings, captions, the input table), besides those above.
WORDS = {
    "uk": (
        "ПОЯСНЮВАЛЬНА ЗАПИСКА",
        "ЗМІСТ",
        "ВСТУП",
        "Вихідні дані",
        "Таблиця 4.1 –",
        "Рисунок 2.1 –",
        "Кінематика",
        "(2.1)",
        "Міністерство освіти і науки України",
        "Варіант 7",
        "Іваненко О. П.",
        "ПЕРЕЛІК УМОВНИХ ПОЗНАЧЕНЬ І СКОРОЧЕНЬ",
    ),
    "ru": (
        "ПОЯСНИТЕЛЬНАЯ ЗАПИСКА",
        "СОДЕРЖАНИЕ",
        "ВВЕДЕНИЕ",
        "Исходные данные",
        "Таблица 4.1 –",
        "Рисунок 2.1 –",
        "Частота вращения коленчатого вала",
        "(2.1)",
        "Вариант 12",
        "Иванов А. П.",
        "ПЕРЕЧЕНЬ УСЛОВНЫХ ОБОЗНАЧЕНИЙ И СОКРАЩЕНИЙ",
    ),
    "en": (
        "EXPLANATORY NOTE",
        "CONTENTS",
        "INTRODUCTION",
        "Table 4.1 —",
        "Figure 2.1 —",
        "(2.1)",
        "Variant 12",
        "LIST OF SYMBOLS AND ABBREVIATIONS",
    ),
}

#: Latin words a Ukrainian or Russian report may contain: function names, solver names, proper names.
ALLOWED_LATIN = {
    "cos",
    "sin",
    "tg",
    "arccos",
    "arcsin",
    "max",
    "min",
    "crankdyn",
    "Radau",
    "RK",
    "BDF",
    "LSODA",
    "IIA",
    "rtol",
    "CSV",
    "Diesel",
    "ind",
    "scipy",
    "SciPy",
    "LU",
    "mod",
    "ds",
    "dV",
    "dJ",
    "diag",
    "MN",
}  # MN: a segment between the points M and N of the source's drawing


#: A table or figure number: chapter (or appendix letter) and position, "2.1", "А.1".
NUMBER = r"[0-9A-ZА-Я]+\.\d+"


def _decimal_points(text: str) -> list[str]:
    """Numbers written with a decimal point, other than the numbering of sections, tables,
    figures and equations ("табл. 2.1", "(2.3)", "Рисунок 4.1", "підрозд. 6.1–6.2") and the version."""
    found = []
    for m in re.finditer(r"(\S*\s?\S*\s?)(?<![\d.,])(\d+\.\d+)(?![\d.])", text):
        before = m.group(1)
        line = text[text.rfind("\n", 0, m.start(2)) + 1 : m.start(2)]
        if (
            not line.strip()
            and re.match(r" [^\W\d_]", text[m.end(2) :])
            and text[m.end(2) + 1].isupper()
        ):
            continue  # a numbered subsection's heading ("2.1 Передавання сили на водило"), in the contents too
        if re.search(
            r"(табл|рис|Таблиц|Рисун|таблиц|розд|подразд|підрозд|додат|прилож|Продовження|Продолжение|"
            r"ГОСТ|ДСТУ|"
            r"crankdyn)[^\s]*\s*[А-ЯA-Z]?\.?\s*$|\($|[–-]$",
            before,
        ):
            continue
        found.append(before + m.group(2))
    return found


def _latin_words(document: str, scene_texts=()) -> list[str]:
    """Latin-letter words outside the allowed set; the scene's own texts (title-page fields,
    engine name: the student's data, in whatever language the student wrote them) left out."""
    body = as_read(
        document.split("<body", 1)[1]
    )  # the word joiner after "8.2/", the no-break space before initials
    for value in sorted(scene_texts, key=len, reverse=True):
        if len(value) > 3:  # not the language code
            for shown in (
                html_lib.escape(value, quote=False),
                str(markupsafe.escape(value)),
            ):  # "'" as &#39;
                body = body.replace(shown, " ")
    body = re.sub(
        r'<ol class="references">.*?</ol>', " ", body, flags=re.S
    )  # the sources keep their language
    body = re.sub(r"<img[^>]*>", " ", body)
    # code and drawing markup a reader never sees as text: scripts, styles, inline SVG
    body = re.sub(r"<(script|style|svg)\b.*?</\1>", " ", body, flags=re.S)
    body = re.sub(r"<(i|sub|sup|b)>[^<]{1,4}</\1>", " ", body)  # symbols and their indices
    body = re.sub(r"<sub>[^<\s]{1,10}</sub>", " ", body)  # a longer index: m_{rR.гол}
    text = html_lib.unescape(re.sub(r"<[^>]+>", " ", body))
    text = re.sub(r"\[[a-z_.]+\]", " ", text)  # the scene's table names, e.g. [bearings]
    words = re.findall(r"(?<![\w])[A-Za-z]{2,}(?![\w])", text)
    # an order's Roman numeral (a table's row "II") is a number, not a Latin word
    return [w for w in words if w not in ALLOWED_LATIN and not re.fullmatch(r"[IVX]+", w)]


def _check_hyphenation(text: str, title_page: str, language: str) -> None:
    """None made by the machine in Ukrainian (pyphen's uk_UA patterns break between any two
    consonants: "та-нгенціальна"), and no name parted on the title page and the assignment in any
    language (not "доц. Пет-/ров" on the assignment)."""
    hyphenated = [
        ln.strip()[-20:] for ln in text.splitlines() if re.search(r"[а-яіїєґё][-\u2010]\s*$", ln)
    ]
    if language == "uk":
        assert all(ln.endswith(("кривошипно-", "зворотно-", "будь-")) for ln in hyphenated), (
            hyphenated
        )  # a compound's own hyphen
    parted = [
        ln
        for ln in title_page.splitlines()
        if re.search(r"[-\u2010]\s*$", ln)
        and not ln.rstrip().endswith(("кривошипно-", "зворотно-"))
    ]  # a compound's own hyphen may end a line
    assert not parted, parted


@pytest.mark.long
@needs_poppler
# the Russian note in the default run, the Ukrainian (framed: its frame is also
# tests/test_frame.py's) and the English ones under -m slow, which CI runs too: the suite's time
@pytest.mark.parametrize(
    "language",
    [pytest.param(lang, marks=pytest.mark.slow) if lang != "ru" else lang for lang in LANGUAGES],
)
def test_explanatory_note_pdf(tmp_path, language):
    (
        example,
        extra,
        table_word,
        figure_word,
        table_ref,
        figure_ref,
        continued,
        abstract,
        conclusions,
        sources,
    ) = LANGUAGES[language]
    out = tmp_path / language
    # the example at a 15° table step: its long tables (gas pressure, forces, torque) continue on a second page
    scene_file = write_scene(
        tmp_path / f"{example}.toml", modified(example, {"analysis": {"table_step_deg": 15}})
    )
    assert (
        main(["report", str(scene_file), "-o", str(out), "--format", "html,pdf", "-q", *extra]) == 0
    )
    assert not list(out.rglob("*.tmp"))
    html = (out / "report.html").read_text(encoding="utf-8")
    pages = page_texts(
        out / "report.pdf", html
    )  # (uk: the example's ESKD frame; what is inside it)
    text = "\f".join(pages)
    if (
        language != "en"
    ):  # F_p and M_k take the textbook's Cyrillic subscripts in text and equations alike
        assert not re.findall(r".{30}[FM]</i><sub>[pk]</sub>", html)

    _check_hyphenation(text, pages[0] + "\n" + pages[1], language)
    # Typography: nothing a reader sees is written the programmer's way.
    assert "^" not in text and "_" not in text, [
        ln for ln in text.splitlines() if "^" in ln or "_" in ln
    ][:5]
    assert not re.search(r"\de[-+−]?0\d", text), re.findall(r".{20}\de[-+−]?0\d.{5}", text)[:5]
    assert "�" not in text  # every glyph came through
    for words in WORDS[language]:
        assert words in text, words
    if language != "en":
        assert not _decimal_points(text), _decimal_points(text)[:10]
        assert not _latin_words(html), sorted(set(_latin_words(html)))

    # The abstract counts what the document holds.
    body_end = text.index(f"\n{sources}") if f"\n{sources}" in text else len(text)
    tables = set(re.findall(rf"{table_word}\s+({NUMBER})\s+[–—]", text))
    figures = set(re.findall(rf"{figure_word}\s+({NUMBER})\s+[–—]", text))
    references = re.findall(r'<ol class="references">(.*?)</ol>', html, flags=re.S)[0].count("<li>")
    abstract_page = next(p for p in pages if abstract in p)
    # pages, figures, tables, appendices (the numerics appendix and the error study's), sources
    numbers = [int(n) for n in re.findall(r"(\d+)\s", abstract_page.split(":", 1)[1])[:5]]
    appendices = html.count('<section class="chapter appendix"')
    assert appendices == 1  # a course note's one appendix: the numerics and the error study
    assert numbers == [len(pages), len(figures), len(tables), appendices, references], (
        numbers,
        abstract_page[:300],
    )

    # Every table and figure is referred to in the text before its caption.
    for word, ref, found in ((table_word, table_ref, tables), (figure_word, figure_ref, figures)):
        for number in found:
            caption = re.search(rf"{word}\s+{re.escape(number)}\s+[–—]", text).start()
            mention = re.search(rf"{re.escape(ref)}\s+{re.escape(number)}(?!\d)", text)
            assert mention and mention.start() < caption, (word, number)

    # Sources: every [n] exists, every source is cited.
    cited = set()
    for group in re.findall(r"\[(\d+(?:[,–]\s*\d+)*)\]", text[:body_end]):
        for part in group.split(","):  # "[1, 5–7]": a range of three or more
            first, _, last = part.strip().partition("–")
            cited |= set(range(int(first), int(last or first) + 1))
    assert cited == set(range(1, references + 1)), (cited, references)

    # Long tables continue on the next page under the label and the repeated header.
    continued_pages = [
        p
        for p in pages
        if re.search(rf"^\s*{continued} \d+\.\d+", p, flags=re.M)
        and not re.search(rf"{continued} \d+\.\d+ [–—]", p)
    ]
    assert continued_pages, "the tables at a 15° step span two pages"
    for page in continued_pages:
        first = next(line for line in page.splitlines() if line.strip())
        assert first.strip().startswith(continued), first

    # Pages as a supervisor leafs through them: none short but a chapter's last, every
    # continued table under its label and header, no caption apart from its table or figure.
    t = translator(language, REGISTRY.catalogs)
    problems = layout_problems(
        out / "report.pdf",
        pages,
        html,
        tmp_path / "pages",
        table_word=table_word,
        figure_word=figure_word,
        continued=lambda number: t("doc.continued", number=number),
    )
    assert not problems, problems

    # Contents with page numbers, and the fonts: Times metrics with Cyrillic, embedded.
    contents = next(p for p in pages if re.search(r"\.{5,}\s*\d+\s*$", p, flags=re.M))
    assert len(re.findall(r"^\s*\d+ .*?\.{3,}\s*(\d+)\s*$", contents, flags=re.M)) >= 4, contents
    fonts = subprocess.run(
        ["pdffonts", str(out / "report.pdf")], capture_output=True, text=True, check=True
    ).stdout
    assert any("Liberation-Serif" in line for line in fonts.splitlines()[2:]), fonts
    assert all(line.split()[-5] == "yes" for line in fonts.splitlines()[2:] if line.strip()), fonts

    # Five pages for a person to look at: title, abstract, a continued table, a figure, conclusions.
    ARTIFACTS.mkdir(exist_ok=True)
    chosen = {
        "1-title": 1,
        "2-abstract": pages.index(abstract_page) + 1,
        "3-continued-table": pages.index(continued_pages[0]) + 1,
        "4-figure": next(
            i for i, p in enumerate(pages, 1) if re.search(rf"{figure_word} \d+\.\d+ [–—]", p)
        ),
        "5-conclusions": max(
            i for i, p in enumerate(pages, 1) if re.search(rf"^\s*{conclusions}\s*$", p, flags=re.M)
        ),
    }
    for name, page in chosen.items():
        subprocess.run(
            [
                "pdftoppm",
                "-r",
                "60",
                "-png",
                "-singlefile",
                "-f",
                str(page),
                "-l",
                str(page),
                str(out / "report.pdf"),
                str(ARTIFACTS / f"note-{language}-{name}"),
            ],
            check=True,
        )
        assert (ARTIFACTS / f"note-{language}-{name}.png").is_file()


@pytest.mark.parametrize("example, language", [("inline4-petrol", "uk")])  # ru: the PDF test above
def test_multicylinder_note_has_no_english_words(example, language):
    scene = load_scene(examples_dir() / f"{example}.toml")
    rendered = shared_html(
        example, language=language
    )  # the example's full run, shared with other files
    assert not rendered.missing_translations, rendered.missing_translations
    scene_texts = [v for v in scene.report.model_dump().values() if isinstance(v, str)] + [
        scene.engine.name
    ]
    words = _latin_words(
        rendered.linked_html, scene_texts
    )  # the text: its figures are not drawn here
    assert not words, sorted(set(words))
    text = html_lib.unescape(
        re.sub(
            r"<[^>]+>",
            " ",
            re.sub(
                r"<img[^>]*>|<(script|style|svg)\b.*?</\1>", " ", rendered.linked_html, flags=re.S
            ),
        )
    )
    assert "^" not in text and not re.search(r"[A-Za-zА-Яа-я]_", text)
    # a count below ten in words, the noun agreeing by the CLDR plural rules: "чотири циліндри" /
    # "четыре цилиндра", not "4 циліндрів"
    assert ("чотири циліндри" if language == "uk" else "четыре цилиндра") in text


def _evaluate(step) -> float:
    """The worked formula evaluated independently from the numbers substituted into it."""
    x = step.inputs
    a, b = math.radians(x.get("alpha_deg", 0.0)), math.radians(x.get("beta_deg", 0.0))
    if step.quantity == "piston_displacement":
        return x["R_m"] * ((1 - math.cos(a)) + (1 - math.cos(b)) / x["lambda"]) * 1e3
    if step.quantity == "piston_velocity":
        return x["R_m"] * x["omega"] * math.sin(a + b) / math.cos(b)
    if step.quantity == "piston_acceleration":
        return (
            x["R_m"]
            * x["omega"] ** 2
            * (math.cos(a + b) / math.cos(b) + x["lambda"] * math.cos(a) ** 2 / math.cos(b) ** 3)
        )
    if step.quantity == "inertia_pressure":
        return -x["m_s"] * x["j"] / x["F_p"] / 1e6
    if step.quantity == "total_pressure":
        return x["p_g"] + x["p_j"]
    raise AssertionError(step.quantity)


@pytest.mark.parametrize("angle", [60.0])  # not the default 30°: the scene chooses
def test_worked_substitutions_equal_their_table_rows(angle):
    scene = scene_from_dict(
        modified("petrol-1cyl", {"report": {"worked_angle_deg": angle}}), base_dir=examples_dir()
    )
    result = run_scene(scene, REGISTRY, ["kinematics", "indicator", "forces"])
    rendered = render_html(result, REGISTRY, "en")
    t = translator("en", REGISTRY.catalogs)
    assert {b.stage for b in rendered.worked} >= {"kinematics", "forces"}
    assert check_worked(rendered.linked_html, rendered.worked, "en") == {
        "indicator",
        "forces_torque",
    }  # the other stages
    for block in (b for b in rendered.worked if b.stage in ("kinematics", "forces")):
        assert block.angle_deg == angle
        table = re.search(
            rf'<table class="[^"]*" data-number="{re.escape(block.table_number)}">(.*?)</div>',
            rendered.linked_html,
            flags=re.S,
        ).group(1)
        row = re.search(rf"<tr(?:\s[^>]*)?><td>{t.fixed(angle, 0)}</td>(.*?)</tr>", table).group(1)
        cells = re.findall(r"<td>([^<]*)</td>", row)
        for step in block.steps:
            assert t.fixed(step.value, step.decimals) in cells, (step.quantity, cells)
            # the substituted numbers give the result to the precision they are printed with
            assert _evaluate(step) == pytest.approx(
                step.value, rel=2e-3, abs=2 * 10**-step.decimals
            ), step.quantity


@pytest.mark.parametrize("language", ["uk", "ru"])
def test_numerics_refusals_in_the_report_language(language):
    """The numerics study's rare texts (steps left out for the time budget or as not allowed) come
    from the catalogs: no English sentence in a uk/ru note, the step written with a decimal comma."""
    scene = scene_from_dict(
        modified(
            "petrol-1cyl-uk", {"numerics": {"time_budget_s": 1e-9}, "report": {"detail": "full"}}
        ),
        base_dir=examples_dir(),
    )
    result = run_scene(scene, REGISTRY, ["kinematics", "indicator", "forces", "numerics"])
    rendered = render_html(result, REGISTRY, language)
    html = rendered.linked_html  # the text: the figures are not drawn here
    assert 'data-part="refused-steps"' in html
    scene_texts = [v for v in scene.report.model_dump().values() if isinstance(v, str)] + [
        scene.engine.name
    ]
    assert not _latin_words(html, scene_texts), sorted(set(_latin_words(html, scene_texts)))
    t = translator(language, REGISTRY.catalogs)
    # (the unit bound to its number by a narrow no-break space: "1,00·10⁻⁹ с" as one)
    assert t("numerics.refused_time_budget", budget=t.number_g(1e-9, 3)) in html_lib.unescape(
        html
    ).replace("\u202f", " ")

    from crankdyn_builtin.numerics.section import refused_steps

    # a step the scene's rules refuse: results.json keeps the rule, the note says so in its language
    ctx = types.SimpleNamespace(t=t, scene=scene)
    rows = refused_steps(
        {"steps_refused": {"0.5": "angle_step_deg: must divide the firing interval"}}, ctx
    )
    assert rows == [("0,5", t("numerics.refused_not_allowed"))]


def _symbol_list(html: str) -> str:
    return re.search(r'<section class="chapter symbols".*?</section>', html, flags=re.S).group(0)


@pytest.mark.parametrize("language", ["uk", "ru", "en"])
def test_list_of_symbols_shows_the_symbols_the_report_uses(language):
    """The run's symbol table (report.typeset.symbol_table) printed before the introduction: each symbol the
    report shows, with its subscript in the report's language, its meaning and unit from the
    catalogs; none the report does not show."""
    from crankdyn.report.equation_legend import line_unit
    from crankdyn.report.typeset import symbol_html, symbol_table, symbol_unit, symbols_used

    table = symbol_table(REGISTRY.stages.values())

    t = translator(language, REGISTRY.catalogs)
    scenes = {"kinematics-only": None, "petrol-1cyl": ["kinematics", "indicator", "forces"]}
    shown = {}
    for name, stages in scenes.items():
        html = shared_html(
            name, language=language, stages=stages
        ).linked_html  # shared with other files (read only)
        listed = _symbol_list(html)
        rest = html.replace(listed, "")
        rows = re.findall(
            r'<span class="symbol">(.*?)</span> – <span class="meaning">(.*?)</span>', listed
        )
        keys = symbols_used(rest, language, table)
        assert [markup for markup, _ in rows] == [symbol_html(k, language, table) for k in keys]
        where = re.compile(
            " \\((?:{}) [^)]*\\)".format(
                "|".join(
                    t(f"doc.symbol_in_{kind}", number="", numbers="", letter="", letters="").strip()
                    for kind in ("section", "sections", "appendix", "appendices")
                )
            )
        )
        markups = [markup for markup, _ in rows]
        for (markup, meaning), key in zip(rows, keys, strict=True):
            unit = symbol_unit(key, t, table)
            text = as_read(
                html_lib.unescape(re.sub(r"</?i>", "", meaning))
            )  # its letters in italics
            # a letter with several meanings says where a sectioned one holds (tests/test_symbol_list.py)
            assert not where.search(text) or markups.count(markup) > 1
            # the tables' unit, and the equations' where they take the quantity in another
            si = line_unit(key, t, table)
            if unit and si != unit:
                unit = t("doc.symbols_unit_in_formulas", unit=unit, si=si)
            assert where.sub("", text) == t(f"symbol.{key}") + (f", {unit}" if unit else "")
        shown[name] = set(keys)
    # the kinematics alone shows no gas pressure; the full calculation does, with its own subscript
    assert "gas_pressure" not in shown["kinematics-only"] and "gas_pressure" in shown["petrol-1cyl"]
    assert {"crank_angle", "piston_displacement", "rod_ratio"} <= shown["kinematics-only"]
    assert shown["kinematics-only"] < set(table)
    subscript = {"uk": "п", "ru": "п", "en": "p"}[language]
    assert f"<i>s</i><sub>{subscript}</sub>" in _symbol_list(html)
    # listed in the contents, before the introduction
    contents = re.search(r'<nav class="contents">.*?</nav>', html, flags=re.S).group(0)
    assert contents.index("#sec-symbols") < contents.index("#sec-introduction")


EXAMPLES = sorted(p.stem for p in examples_dir().glob("*.toml"))


@pytest.mark.slow
@needs_poppler
@pytest.mark.parametrize("language", ["uk", "ru", "en"])
@pytest.mark.parametrize("example", EXAMPLES)
def test_every_bundled_example_pdf_reads_as_typeset(example, language, tmp_path):
    """Every bundled example in every language: pdftotext finds no
    ``^``, no ``_``, no ``e-03`` number; in uk/ru no decimal point inside a number and no Latin
    word outside the allowed set; and the pages pass the supervisor's layout check."""
    out = tmp_path / "out"
    assert (
        main(
            [
                "report",
                str(examples_dir() / f"{example}.toml"),
                "-o",
                str(out),
                "--format",
                "html,pdf",
                "-q",
                "--lang",
                language,
            ]
        )
        == 0
    )
    html = (out / "report.html").read_text(encoding="utf-8")
    pages = page_texts(out / "report.pdf", html)
    text = "\f".join(pages)
    assert "^" not in text and "_" not in text, [
        ln for ln in text.splitlines() if "^" in ln or "_" in ln
    ][:5]
    assert not re.search(r"\de[-+−]?0\d", text), re.findall(r".{20}\de[-+−]?0\d.{5}", text)[:5]
    if language != "en":
        scene = load_scene(examples_dir() / f"{example}.toml")
        scene_texts = [v for v in scene.report.model_dump().values() if isinstance(v, str)] + [
            scene.engine.name
        ]
        # the student's own texts (an engine named "75 × 84.8 mm" in English) are theirs to write, the
        # sources keep their own titles ("SciPy 1.0")
        sources = re.findall(r'<ol class="references">(.*?)</ol>', html, flags=re.S)
        own = (
            scene_texts + [html_lib.unescape(re.sub(r"<[^>]+>", " ", sources[0]))]
            if sources
            else scene_texts
        )
        points = [p for p in _decimal_points(text) if not any(p.split()[-1] in v for v in own)]
        assert not points, points[:10]
        words = _latin_words(html, scene_texts)
        assert not words, sorted(set(words))
    table_word, figure_word = LANGUAGES[language][2:4]
    t = translator(language, REGISTRY.catalogs)
    problems = layout_problems(
        out / "report.pdf",
        pages,
        html,
        tmp_path / "pages",
        table_word=table_word,
        figure_word=figure_word,
        continued=lambda number: t("doc.continued", number=number),
    )
    assert not problems, problems


def test_landscape_tables_go_after_the_portrait_material_that_follows_them():
    from crankdyn.report.document import landscape_tables_later

    wide = '<div class="table-block long landscape"><table data-number="7.1"></table></div>'
    narrow = '<div class="table-block"><table data-number="7.2"></table></div>'
    after = '<div class="table-block"><table data-number="7.3"></table></div>'
    figure = '<div class="figure-block"><figure data-number="7.1"></figure></div><p>text</p>'
    # the wide table and the one right after it move past the figure and the text, before table 7.3
    # (the text after the last figure leads them onto their landscape page, not alone on a portrait one)
    lead = '<div class="landscape-lead"><p>text</p></div>'
    assert (
        landscape_tables_later("<p>a</p>" + wide + "\n" + narrow + figure + after)
        == "<p>a</p>" + figure.replace("<p>text</p>", lead) + wide + "\n" + narrow + after
    )
    # a row of figures is closed before the lead; text alone (no figure) moves as before
    row = '<div class="figure-row">' + figure.replace("<p>text</p>", "") * 2 + "</div>"
    assert (
        landscape_tables_later(wide + row + "<p>t</p>" + after)
        == row + lead.replace("text", "t") + wide + after
    )
    assert landscape_tables_later(wide + "<p>t</p>" + after) == "<p>t</p>" + wide + after
    # another landscape table next: the text between shares their landscape pages, nothing moves
    second = wide.replace("7.1", "7.2")
    assert landscape_tables_later(wide + "<p>t</p>" + second) == wide + "<p>t</p>" + second
    # never out of the block that holds it
    nested = '<div class="x">' + wide + "</div><p>t</p>"
    assert landscape_tables_later(nested) == nested


def test_double_primed_symbols_are_typeset_as_the_primed_ones():
    """The bearings section's l′_i and l″_i (the crank's distances to its two main bearings)."""
    from crankdyn.report.typeset import typeset_text_html

    html = typeset_text_html("l′_i + l″_i = l_i", "uk", [])
    # the index in italics, as formula 7.3 sets it
    assert (
        html
        == "<i>l</i>′<sub><i>i</i></sub> + <i>l</i>″<sub><i>i</i></sub> = <i>l</i><sub><i>i</i></sub>"
    )


def test_a_number_with_a_power_of_ten_keeps_its_unit_on_its_line():
    """ "±4,3·10⁻⁵ МПа" is not parted at a line's end (the narrow no-break space follows a
    superscript digit too, not only a plain one)."""
    from crankdyn.report.typeset import typeset_text_html

    html = typeset_text_html("t_min ±4,3·10⁻⁵ МПа, 0,0067 %, 17 235 Н", "uk", ["МПа", "%", "Н"])
    assert "10⁻⁵\u202fМПа" in html and "0,0067\u202f%" in html and "235\u202fН" in html
