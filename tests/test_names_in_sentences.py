"""The assignment's engine name inside the note's sentences."""

from __future__ import annotations

import re

import pytest

from crankdyn.report.names import inside_sentence


@pytest.mark.parametrize(
    "name, language, printed",
    [
        ("Трициліндровий рядний двигун", "uk", "трициліндровий рядний двигун"),
        (
            "Рядный пятицилиндровый двигатель 5Ч 8,3/9,0",
            "ru",
            "рядный пятицилиндровый двигатель 5Ч 8,3/9,0",
        ),
        ("Дизель 8Ч 12/12 типа КамАЗ-740", "ru", "дизель 8Ч 12/12 типа КамАЗ-740"),
        ("Поршневий повітряний компресор", "uk", "поршневий повітряний компресор"),
        ("КамАЗ-740", "ru", "КамАЗ-740"),  # a proper name
        ("ЯМЗ-236 дизель", "ru", "ЯМЗ-236 дизель"),  # an abbreviation
        ("Урал", "ru", "Урал"),  # a proper name with no adjective's ending
        ("V8 90° з плоским валом", "uk", "V8 90° з плоским валом"),
        ("Mercedes-Benz OM 617", "ru", "Mercedes-Benz OM 617"),
        ("In-line four-cylinder petrol engine", "en", "In-line four-cylinder petrol engine"),
        ("одноциліндровий двигун", "uk", "одноциліндровий двигун"),
    ],
)
def test_a_common_first_word_is_lowered_a_proper_name_kept(name, language, printed):
    assert inside_sentence(name, language) == printed


def test_the_assignment_and_the_abstract_print_the_name_inside_their_sentences():
    from conftest import shared_html

    changes = {"engine": {"name": "Одноциліндровий бензиновий двигун 8,2/7,8"}}
    page = shared_html("petrol-1cyl-uk", changes, "uk", ("kinematics",)).linked_html
    text = " ".join(re.sub(r"<[^>]+>", "", page).split()).replace("\u2060", "")
    assert "Об’єкт розрахунку: одноциліндровий бензиновий двигун 8,2/7,8." in text
    assert "Об’єкт розрахунку – одноциліндровий бензиновий двигун 8,2/7,8." in text
