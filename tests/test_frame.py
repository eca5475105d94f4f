"""The ESKD sheet frame and title blocks of the printed note (``[report] frame = "eskd"``).

The default (``frame = "none"``) report is the one of before, byte for byte; the frame only adds
its stylesheet and its running blocks. One framed PDF (the in-line four in Ukrainian, whose torque
section has landscape pages) is read as a supervisor checks it: no frame on the title page and the
assignment, form 2 with the total on the first sheet, the designation and the sheet's own number
on every other one (turned on the landscape pages), nothing running into a block.
"""

from __future__ import annotations

import dataclasses
import html as html_lib
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from conftest import ARTIFACTS, modified, shared_run, write_scene
from page_layout import crop_texts, first_sheets, landscape_pages, layout_problems, page_texts

from crankdyn.cli import examples_dir, main
from crankdyn.plugin.registry import default_registry
from crankdyn.report.assets import report_css
from crankdyn.report.document import render_html
from crankdyn.report.docx import pandoc_html
from crankdyn.report.frame import fitting_size, text_width_em
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
TEMPLATES = Path(__file__).resolve().parents[1] / "templates"
DESIGNATION = "КП.ДВЗ.041.00.000 ПЗ"
#: names as a student may type them: markup characters are text, printed as typed
FRAMED = {
    "frame": "eskd",
    "designation": DESIGNATION,
    "student": "Іваненко <О.> & П.",
    "supervisor": "доц. Петренко В. М.",
    "group": "241",
    "university": "НАУ «ХАІ»",
    "department": "Кафедра 203",
    "title": "Динамічний розрахунок рядного чотирициліндрового двигуна",
    "standards_controller": "ст. викл. Коваль І. І.",
    "approver": "проф. Мельник С. О.",
    "letter": "У",
}

needs_poppler = pytest.mark.skipif(
    shutil.which("pdftotext") is None or shutil.which("pdfinfo") is None,
    reason="poppler-utils not installed (bash .ci/setup.sh installs it)",
)


def _rendered(example: str, report: dict, language: str | None = None) -> str:
    """The report of ``example``'s shared run with the ``[report]`` table changed: the same
    computed results (and run times), so that two renderings differ only by what the table changes."""
    run = shared_run(example)
    scene = scene_from_dict(modified(example, {"report": report}), base_dir=examples_dir())
    return render_html(dataclasses.replace(run, scene=scene), REGISTRY, language).linked_html


def _without_frame(html: str) -> str:
    """The framed report with its stylesheet and its blocks taken out."""
    html = html.replace("\n" + (TEMPLATES / "frame-eskd.css").read_text(encoding="utf-8"), "", 1)
    start = html.index("<body>") + len("<body>")
    return html[:start] + html[html.index('\n<section class="title-page"') :]


def test_the_default_report_is_the_one_of_before():
    """``frame`` absent and ``frame = "none"`` give the same page, byte for byte, with nothing of the
    frame in it: the stylesheet is report.css and the language's, as before."""
    html = _rendered("petrol-1cyl", {})
    assert _rendered("petrol-1cyl", {"frame": "none", "designation": DESIGNATION}) == html
    assert (
        "eskd" not in html
        and DESIGNATION not in html
        and "Розроб." not in _rendered("petrol-1cyl", {}, "uk")
    )
    css = re.search(r"<style>(.*?)</style>", html, flags=re.S).group(1)
    assert css == (TEMPLATES / "report.css").read_text(encoding="utf-8") == report_css("en")
    ru = re.search(r"<style>(.*?)</style>", _rendered("petrol-1cyl", {}, "ru"), flags=re.S).group(1)
    assert ru == "\n".join(
        (TEMPLATES / n).read_text(encoding="utf-8") for n in ("report.css", "report.ru.css")
    )


@pytest.mark.parametrize("language", ["uk", "ru", "en"])
def test_the_frame_only_adds_its_blocks_and_stylesheet(language):
    """The framed page is the unframed one plus the stylesheet and the blocks at the body's start:
    the typesetting, the list of symbols and every section are untouched by them; the labels are
    the catalog's (no English in uk/ru); the names are escaped."""
    plain, framed = (
        _rendered("petrol-1cyl", FRAMED | {"frame": "none"}, language),
        _rendered("petrol-1cyl", FRAMED, language),
    )
    assert _without_frame(framed) == plain
    blocks = framed[framed.index("<body>") : framed.index('<section class="title-page"')]
    assert blocks.count('class="eskd-block') == 3  # form 2, form 2а, form 2а turned
    assert "Іваненко &lt;О.&gt; &amp;" in blocks and "<О.>" not in blocks
    assert blocks.count(DESIGNATION) == 3 and blocks.count('class="eskd-page"') == 3
    assert blocks.count('class="eskd-pages"') == 1
    # Н. контр. and Затв. with their names (surname and initials), Літ. a character a cell
    assert re.search(r"(Н\.\sконтр|N\.\scontr)\.</td><td[^>]*>Коваль\sІ\.\sІ\.</td>", blocks)
    assert re.search(r"(Затв|Утв|Approved)\.?</td><td[^>]*>Мельник\sС\.\sО\.</td>", blocks)
    assert re.findall(r'<td class="lit"[^>]*>([^<]*)</td>', blocks) == ["У", "", ""]
    labels = {
        "uk": (
            "Зм.",
            "Арк.",
            "№ докум.",
            "Підпис",
            "Дата",
            "Розроб.",
            "Перевір.",
            "Н. контр.",
            "Затв.",
            "Літ.",
            "Аркушів",
            "Пояснювальна записка",
            "гр. 241",
        ),
        "ru": (
            "Изм.",
            "Лист",
            "№ докум.",
            "Подп.",
            "Дата",
            "Разраб.",
            "Пров.",
            "Н. контр.",
            "Утв.",
            "Лит.",
            "Листов",
            "Пояснительная записка",
            "гр. 241",
        ),
        "en": (
            "Rev.",
            "Sheet",
            "Doc. No.",
            "Sign.",
            "Date",
            "Drawn",
            "Checked",
            "N. contr.",
            "Approved",
            "Lit.",
            "Sheets",
            "Explanatory note",
            "group 241",
        ),
    }[language]
    text = html_lib.unescape(re.sub(r"<[^>]+>", " ", blocks)).replace("\u00a0", " ")
    for label in labels:
        assert label in text, label
    if language != "en":
        assert not re.findall(r"[A-Za-z]{2,}", text), text


def test_the_word_export_leaves_the_frame_out():
    framed = _rendered("petrol-1cyl", FRAMED, "uk")
    converted = pandoc_html(framed, {})
    assert "eskd" not in converted and DESIGNATION not in converted and "Розроб." not in converted
    assert "ПОЯСНЮВАЛЬНА ЗАПИСКА".lower() in converted.lower()


def test_a_cell_text_is_set_in_the_largest_size_that_fits():
    assert fitting_size("Іваненко О. П.", 21, 4.5, 8.0, lines=1) == 8.0
    assert (
        fitting_size("доц. Петренко В. М.", 21, 4.5, 8.0, lines=1) == 6.5
    )  # 8,7 em of Times: 21,4 mm at 7 pt
    assert fitting_size("Костянтинопольська-Вишневецька О. П.", 21, 4.5, 8.0, lines=1) < 5.6
    assert fitting_size(DESIGNATION, 106, 13) == 14.0
    long = "Національний аерокосмічний університет ім. М. Є. Жуковського «Харківський авіаційний інститут»"
    assert (
        fitting_size(long, 48, 13.5, 9.0)
        < fitting_size("ХАІ, каф. 203, гр. 241", 48, 13.5, 9.0)
        == 9.0
    )
    assert (
        abs(text_width_em("доц. Петренко В. М.") - 8.67) < 0.4
    )  # the font's own advances: 8,67 em


def test_the_block_names_surname_and_initials_in_one_size():
    """ "доц. Петренко В. М." is not set smaller than "Іваненко О. П." above it; the block
    writes the surname and initials (the title page keeps the academic title), both in one size."""
    from crankdyn.report.frame import person_in_block, title_block
    from crankdyn.report.i18n import translator
    from crankdyn.scene.model import scene_from_dict

    assert person_in_block("доц. Петренко В. М.") == "Петренко В. М."
    assert person_in_block("ст. викл. Коваль І. І.") == "Коваль І. І."
    assert (
        person_in_block("Іваненко О. П.") == "Іваненко О. П."
        and person_in_block("Prof. A. Supervisor") == "Prof. A. Supervisor"
    )
    # a name given in full: the surname and the initials, as the block's narrow cell takes them
    assert person_in_block("Коваленко Марія Андріївна") == "Коваленко М. А."
    assert person_in_block("Смирнова Анна-Марія") == "Смирнова А.-М."
    assert person_in_block("проф. Дем'яненко Дем'ян Ілліч") == "Дем'яненко Д. І."
    assert person_in_block("Коваленко") == "Коваленко"
    meta = scene_from_dict(
        modified(
            "petrol-1cyl-uk",
            {
                "report": {
                    "student": "Костянтинопольська О. П.",
                    "supervisor": "доц. Петренко В. М.",
                }
            },
        )
    ).report
    block = title_block(translator("uk"), meta, "Назва")
    assert (
        block["supervisor"].text == "Петренко В. М."
        and block["student"].size == block["supervisor"].size < 8.0
    )


def _sheet_numbers(pdf: Path, landscape: list[bool]) -> list[str]:
    """What each page shows in its "Арк." number cell: form 2а's bottom 8 mm of its last 10 mm (the
    turned one's on a landscape page: the bottom-left corner of the frame)."""
    portrait = crop_texts(pdf, 195.5, 284.5, 204.5, 291.5)
    turned = crop_texts(pdf, 5.5, 195.5, 12.5, 204.5)
    return [
        " ".join((t if wide else p).split())
        for p, t, wide in zip(portrait, turned, landscape, strict=True)
    ]


@pytest.mark.slow  # a 34-page PDF: with the framed Ukrainian note, in the slow tier CI runs
@needs_poppler
def test_the_framed_pdf_numbers_its_sheets_in_the_blocks(tmp_path):
    """The ESKD frame: the in-line four in Ukrainian, up to its torque section (34 pages, one of
    them landscape: the table of the forces on the cranks)."""
    # rows every 90°: fewer pages to lay out, the wide table of the forces on the cranks still landscape
    scene = write_scene(
        tmp_path / "framed.toml",
        modified(
            "inline4-petrol",
            {"report": FRAMED | {"language": "uk"}, "analysis": {"table_step_deg": 90}},
        ),
    )
    out = tmp_path / "out"
    assert (
        main(
            [
                "report",
                str(scene),
                "-o",
                str(out),
                "--format",
                "html,pdf",
                "-q",
                "--stages",
                "torque",
            ]
        )
        == 0
    )
    pdf, html = out / "report.pdf", (out / "report.html").read_text(encoding="utf-8")
    full = subprocess.run(
        ["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True, check=True
    ).stdout.split("\f")[:-1]
    total, landscape, first = len(full), landscape_pages(pdf), first_sheets(pdf)
    assert any(landscape) and len(landscape) == len(first) == total

    # the title page and the assignment: no frame, no block, no page number
    for page in full[:2]:
        assert (
            DESIGNATION not in page
            and "Арк." not in page
            and not re.search(r"^\s*\d+\s*$", page, flags=re.M)
        )
    # the first sheet (the abstract): form 2 with the names, its number 3 and the total
    assert first.index(True) == 2 and first.count(True) == 1 and "РЕФЕРАТ" in full[2]
    for word in (
        "Розроб.",
        "Іваненко <О.> & П.",
        "Перевір.",
        "Петренко В. М.",
        "Літ.",
        "Аркушів",
        "Пояснювальна записка",
        "НАУ «ХАІ»",
        "Кафедра 203",
        "гр. 241",
        DESIGNATION,
    ):
        assert word in full[2].replace("\u00a0", " "), word
    sheet, sheets = (
        " ".join(t.split())
        for t in (
            crop_texts(pdf, 170.5, 272.5, 184.5, 276.5)[2],
            crop_texts(pdf, 185.5, 272.5, 204.5, 276.5)[2],
        )
    )
    assert (sheet, sheets) == ("3", str(total))
    # every following sheet: form 2а with the designation, "Арк." and its own number
    numbers = _sheet_numbers(pdf, landscape)
    for i in range(3, total):
        assert DESIGNATION in full[i] and "Арк." in full[i] and "Зм." in full[i], i + 1
        assert numbers[i] == str(i + 1), (i + 1, numbers[i])
    assert "Аркушів" not in "".join(full[3:])

    # the pages as a supervisor leafs through them: the content inside the frame, off the blocks
    problems = layout_problems(
        pdf,
        page_texts(pdf, html),
        html,
        tmp_path / "pages",
        table_word="Таблиця",
        figure_word="Рисунок",
        continued=lambda number: f"Продовження таблиці {number}",
    )
    assert not problems, problems
    ARTIFACTS.mkdir(exist_ok=True)
    for name, page in (
        ("first-sheet", 3),
        ("sheet", 4),
        ("landscape", landscape.index(True) + 1),
        ("last", total),
    ):
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
                str(pdf),
                str(ARTIFACTS / f"frame-uk-{name}"),
            ],
            check=True,
        )
