"""Russian reports and the course-project conventions of the Cyrillic reports (uk, ru)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import modified

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.report.i18n import available_languages, core_catalog_dir, load_catalog_file
from crankdyn.scene.model import scene_from_dict

REGISTRY = default_registry()
UKRAINIAN_ONLY = set("іїєґІЇЄҐ")  # letters Russian does not have
RUSSIAN_ONLY = set("ыэъёЫЭЪЁ")  # letters Ukrainian does not have


@pytest.fixture(scope="module")
def petrol():
    scene = scene_from_dict(
        modified("petrol-1cyl", {"report": {"language": "ru"}}), base_dir=examples_dir()
    )
    return run_scene(scene, REGISTRY, languages=available_languages())


@pytest.fixture(scope="module")
def russian(petrol):
    return render_html(petrol, REGISTRY)


def test_russian_is_a_report_language():
    assert "ru" in available_languages()


def test_russian_html_captions_numbers_and_decimal_comma(russian):
    html = russian.linked_html
    assert not russian.missing_translations, russian.missing_translations
    assert '<html lang="ru">' in html
    for text in (
        "Содержание",
        "Исходные данные",
        "Кинематика кривошипно-шатунного механизма",
        "Таблица 2.1 – ",
        "Рисунок 2.1 – ",
        "Заключение",
        "Список использованных источников",
    ):
        assert text in html, text
    assert not re.search(r"(Table|Figure) \d+\.\d+", html)  # no English caption left
    assert "0,2800" in html and "0.2800" not in html  # lambda, with the decimal comma


def _chapters(html: str) -> dict[int, str]:
    parts = re.split(r'<section class="chapter" id="sec-(\w+)"', html)
    return {
        int(key): body for key, body in zip(parts[1::2], parts[2::2], strict=True) if key.isdigit()
    }


def test_tables_figures_equations_numbered_within_their_section(russian):
    # The numbering is language-independent (RenderContext); checked on the Russian report.
    language, table_word, figure_word = "ru", "Таблица", "Рисунок"
    html = russian.linked_html
    chapters = _chapters(html)
    assert len(chapters) >= 4
    counted = {"table": 0, "figure": 0, "equation": 0}
    for number, body in chapters.items():
        for kind, pattern in (
            ("table", rf"{table_word} (\d+)\.(\d+) – "),
            ("figure", rf"{figure_word} (\d+)\.(\d+) – "),
            ("equation", r'class="eqno">\((\d+)\.(\d+)\)'),
        ):
            found = [(int(a), int(b)) for a, b in re.findall(pattern, body)]
            counted[kind] += len(found)
            assert all(section == number for section, _ in found), (language, kind, number, found)
            # 1, 2, 3 ... within the section, in order
            assert [k for _, k in found] == list(range(1, len(found) + 1)), (
                language,
                kind,
                number,
                found,
            )
    assert counted["table"] >= 4 and counted["figure"] >= 4 and counted["equation"] >= 10, counted


def _catalogs(language: str) -> dict[str, str]:
    texts = dict(load_catalog_file(core_catalog_dir() / f"{language}.toml"))
    plugin_dir = Path(next(iter(REGISTRY.catalogs)).path).parent
    for path in sorted(plugin_dir.glob(f"*.{language}.toml")):
        texts.update(load_catalog_file(path))
    return texts


def test_russian_catalog_is_russian_not_ukrainian():
    texts = _catalogs("ru")
    assert len(texts) > 100
    # Sources are cited in the language they were published in; everything else must be Russian.
    leaks = {k: v for k, v in texts.items() if not k.startswith("ref.") and UKRAINIAN_ONLY & set(v)}
    assert not leaks, leaks
    uk = _catalogs("uk")
    english = _catalogs("en")
    untranslated = [
        k
        for k, v in texts.items()
        if v == english.get(k)
        and re.search(r"[A-Za-z]{4,}", v)
        and not k.startswith("ref.")
        and "{" not in v
    ]
    assert not untranslated, untranslated
    ukrainian_words = [k for k, v in texts.items() if v == uk.get(k) and (set(v) & UKRAINIAN_ONLY)]
    assert not ukrainian_words or all(k.startswith("ref.") for k in ukrainian_words)
    assert any(set(v) & RUSSIAN_ONLY for v in texts.values())


def test_caption_style_of_the_cyrillic_reports():
    # DSTU 3008:2015 and GOST 7.32-2017: "Таблиця 3.1 – Назва" above, "Рисунок 3.2 – Назва" below.
    uk, ru = _catalogs("uk"), _catalogs("ru")
    assert uk["report.table_caption"] == "Таблиця {number} – {caption}"
    assert uk["report.figure_caption"] == "Рисунок {number} – {caption}"
    assert ru["report.table_caption"] == "Таблица {number} – {caption}"
    assert ru["report.figure_caption"] == "Рисунок {number} – {caption}"
    assert uk["_meta.decimal_separator"] == ru["_meta.decimal_separator"] == ","


# The Russian PDF (Cyrillic text, captions, a Times-metric font): tests/test_note.py::test_explanatory_note_pdf[ru].


def test_a_russian_note_numbers_its_pages_at_the_bottom_centre():
    """ГОСТ 7.32-2017, 6.3.2 (a Ukrainian note: DSTU 3008, top right): report.ru.css is added to the
    page frame of a Russian report only."""
    registry = default_registry()
    from crankdyn.scene.model import load_scene

    result = run_scene(load_scene(examples_dir() / "petrol-1cyl-ru.toml"), registry, ["kinematics"])
    html = render_html(result, registry).linked_html
    assert "@bottom-center { content: counter(page)" in html
    uk = run_scene(load_scene(examples_dir() / "petrol-1cyl-uk.toml"), registry, ["kinematics"])
    # (the Ukrainian example is printed in the ESKD frame, whose block carries the sheet number)
    assert "@bottom-center { content: counter(page)" not in render_html(uk, registry).linked_html


def test_an_order_left_unbalanced_is_said_so_whatever_its_gender():
    """The balancing summary's means column: "P_II | оставлено неуравновешенным" agreed with
    neither the force (она) nor the moment (он), and "не уравновешивается" read as if it could
    not be; "средств не предусмотрено" fits both, as "засобів не передбачено" in Ukrainian."""
    import re

    from conftest import shared_html

    for language, words in (("ru", "средств не предусмотрено"), ("uk", "засобів не передбачено")):
        html = shared_html("inline4-petrol", None, language, ("balancing",)).linked_html
        cells = re.findall(r'<td class="text">([^<]*)</td>', html)
        assert any(c.startswith(words) for c in cells)
        assert not any(
            "оставлено неуравновешенным" in c or "залишено незрівноваженим" in c for c in cells
        )


def test_the_means_angles_are_counted_from_the_pistons_tdc():
    """A piston is at TDC, not a cylinder: "углы отсчитаны … когда поршень в ВМТ"."""
    import re

    from conftest import shared_html

    for language, said in (("ru", "вращения, когда поршень в ВМТ"), ("uk", "коли поршень у ВМТ")):
        text = " ".join(
            re.sub(r"<[^>]+>", "", shared_html("petrol-1cyl", None, language).linked_html).split()
        )
        assert said in text
        assert "положении цилиндра в ВМТ" not in text and "коли циліндр у ВМТ" not in text
