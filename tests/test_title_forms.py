"""The title page's "performed by" line takes the student's grammatical gender."""

from __future__ import annotations

import pytest
from conftest import modified

from crankdyn import api


@pytest.mark.parametrize(
    "language, gender, expected, absent",
    [
        ("uk", "female", ("Виконала: студентка групи МТ-31", "прийняла до виконання"), "Виконав:"),
        (
            "ru",
            "female",
            ("Выполнила: студентка группы МТ-31", "приняла к исполнению"),
            "Выполнил:",
        ),
        ("uk", "male", ("Виконав: студент групи МТ-31", "прийняв до виконання"), "Виконала:"),
        ("ru", "male", ("Выполнил: студент группы МТ-31", "принял к исполнению"), "Выполнила:"),
    ],
)
def test_performed_by_follows_the_students_gender(tmp_path, language, gender, expected, absent):
    data = modified(
        "kinematics-only",
        {"report": {"language": language, "group": "МТ-31", "student_gender": gender}},
    )
    api.run(data).write(tmp_path, formats=["html"])
    html = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert all(words in html for words in expected) and absent not in html


def test_the_english_title_page_says_prepared_by_a_student_of_the_group():
    """ "Performed by: student of group" is a calque of «Виконав: студент групи»."""
    import re

    from conftest import shared_html

    html = shared_html("petrol-1cyl", {"report": {"group": "ME-31"}}, "en", ("kinematics",))
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html.linked_html))
    assert "Prepared by: student, group ME-31" in text
    assert "Performed by" not in text
