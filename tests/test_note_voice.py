"""A note is the student's own text: it states what the calculation shows and never tells its
reader what to do ("перевірте N_e", "уменьшите диаметр")."""

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
