"""A name the assignment gives (the engine's) as the note's sentences print it."""

from __future__ import annotations

import re

#: Endings of an adjective's nominative (Russian, Ukrainian): a name starting with one starts
#: with a common word ("Рядный пятицилиндровый двигатель …"), not with a proper name.
_ADJECTIVE_ENDINGS = {
    "ru": ("ый", "ий", "ой", "ая", "яя", "ое", "ее", "ые", "ие"),
    "uk": ("ий", "ій", "а", "е", "і"),
}
#: Common nouns a name may start with ("Дизель 8Ч 12/12 …").
_COMMON_NOUNS = {
    "ru": frozenset({"двигатель", "дизель", "мотор", "компрессор", "механизм"}),
    "uk": frozenset({"двигун", "дизель", "мотор", "компресор", "механізм"}),
}
_FIRST_WORD = re.compile(r"[^\s,;:()]+")


def inside_sentence(name: str, language: str) -> str:
    """``name`` as the middle of a Russian or Ukrainian sentence prints it: a first word that is
    a capitalised adjective or common noun ("Трициліндровий рядний двигун …") in lower case, as
    after a colon or a dash; a proper name or an abbreviation ("КамАЗ-740", "ЯМЗ", "V8") as
    given, and any name in another language as given (English keeps its capital after a colon).
    """
    if language not in _COMMON_NOUNS or not name:
        return name
    found = _FIRST_WORD.match(name)
    if found is None:
        return name
    word = found.group(0)
    letters = [c for c in word if c.isalpha()]
    if len(letters) < 2 or not letters[0].isupper() or any(c.isupper() for c in letters[1:]):
        return name
    lowered = word.lower()
    if lowered in _COMMON_NOUNS[language] or (
        "-" not in lowered and lowered.endswith(_ADJECTIVE_ENDINGS[language])
    ):
        return name[0].lower() + name[1:]
    return name
