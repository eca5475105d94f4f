"""An aircraft engine has no flywheel: its propeller takes the flywheel's part, and its note says
"propeller" wherever a car engine's says "flywheel", but for the one sentence that explains it."""

from __future__ import annotations

import html
import re

import pytest
from conftest import as_read, shared_html

#: The radial aircraft engine given its propeller's moment of inertia.
PROPELLER = {"flywheel": {"inertia": "8 kg m^2"}}

#: The flywheel as a word, in any language of the note.
FLYWHEEL = re.compile(r"flywheel|маховик", re.IGNORECASE)

#: Per language: the sentence that says the propeller takes the flywheel's part, the remark in
#: parentheses after the propeller's moment of inertia (the list of symbols, the task's data),
#: the introduction's aim, the section's table caption and its sentence on the given inertia.
TEXTS = {
    "en": {
        "explained": r"An aircraft engine has no flywheel: [^.]*\.",
        "remark": r"\((?:the propeller takes|taking) the flywheel's part\)",
        "aim": r"The aim of the work is [^.]*account for the propeller's moment of inertia",
        "caption": r"Table \d+\.\d+ [—–] Speed fluctuation with the propeller by the energy method",
        "given": r"The assignment gives the propeller's moment of inertia Jf = 8\.000 kg·m²",
    },
    "uk": {
        "explained": r"Авіаційний двигун маховика не має: [^.]*\.",
        "remark": r"\((?:гвинт )?виконує роль маховика\)",
        "aim": r"Мета роботи – [^.]*врахувати момент інерції повітряного гвинта",
        "caption": r"Таблиця \d+\.\d+ [—–] Нерівномірність обертання з повітряним гвинтом"
        r" за енергетичним методом",
        "given": r"У завданні вказано момент інерції повітряного гвинта Jмах = 8,000 кг·м²",
    },
    "ru": {
        "explained": r"Авиационный двигатель маховика не имеет: [^.]*\.",
        "remark": r"\((?:винт )?выполняет роль маховика\)",
        "aim": r"Цель работы – [^.]*учесть момент инерции воздушного винта",
        "caption": r"Таблица \d+\.\d+ [—–] Неравномерность вращения с воздушным винтом"
        r" по энергетическому методу",
        "given": r"В задании указан момент инерции воздушного винта Jмах = 8,000 кг·м²",
    },
}


def _text(page: str) -> str:
    body = page.split("<body", 1)[1]
    body = re.sub(r"<(script|style|svg)\b.*?</\1>", " ", body, flags=re.S)
    return " ".join(html.unescape(as_read(re.sub(r"<[^>]+>", "", body))).split())


@pytest.mark.parametrize("language", ["ru", "uk", "en"])
def test_an_aircraft_engines_note_calls_its_propeller_no_flywheel(language):
    """A radial aircraft engine given its propeller's moment of inertia: the introduction's aim,
    the speed fluctuation's table and its sentence on the given inertia name the propeller, and
    the flywheel is named only where the note says that the propeller takes its part."""
    page = shared_html("radial9-aircraft", PROPELLER, language, ("flywheel", "speed_fluctuation"))
    text = _text(page.linked_html)
    said = TEXTS[language]
    for part in ("aim", "caption", "given"):
        assert re.search(said[part], text), part
    assert len(re.findall(said["explained"], text)) == 1
    rest = re.sub(said["remark"], "", re.sub(said["explained"], "", text))
    left = [rest[max(0, m.start() - 80) : m.end() + 40] for m in FLYWHEEL.finditer(rest)]
    assert not left, left


def test_a_raised_propellers_inertia_is_not_called_a_flywheels():
    """An aircraft engine whose exact solution raises the propeller's inertia: the section says
    the propeller (not a flywheel) has to supply it and was raised, with no rim to size."""
    import re

    from conftest import shared_html, shared_run

    changes = {
        "engine": {"application": "aircraft"},
        "flywheel": {"required_irregularity": 0.005},
    }
    r = shared_run("inline4-petrol", changes, ("flywheel",)).outputs["flywheel"].results
    assert r["flywheel_raised"]
    html = shared_html("inline4-petrol", changes, "uk", ("flywheel",)).linked_html
    section = re.search(r'data-stage="flywheel">.*?</section>', html, re.S).group(0)
    text = " ".join(re.sub(r"<[^>]+>", "", section).split())
    assert "з якого повітряний гвинт за енергетичним методом має дати" in text
    assert "Тому момент інерції повітряного гвинта збільшено на" in text
    assert "з цим маховиком" not in text and "момент інерції маховика збільшено" not in text
