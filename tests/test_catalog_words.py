"""The catalogs' sentences as written: no word doubled by an edit ("the power take-off end end")."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CATALOGS = sorted(ROOT.glob("plugins/*/*/i18n/*.toml")) + sorted(ROOT.glob("templates/i18n/*.toml"))
#: A word written twice in a row (a number may be: "1 1" is no typing slip in a formula).
DOUBLED = re.compile(r"\b([^\W\d_]{2,})\s+\1\b", re.IGNORECASE)


def _texts(table: dict, prefix: str = ""):
    for key, value in table.items():
        if isinstance(value, dict):
            yield from _texts(value, f"{prefix}{key}.")
        elif isinstance(value, str):
            yield prefix + key, value


def test_no_catalog_sentence_doubles_a_word():
    assert CATALOGS
    doubled = [
        f"{path.relative_to(ROOT)}: {key}: {found.group(0)!r}"
        for path in CATALOGS
        for key, text in _texts(tomllib.loads(path.read_text(encoding="utf-8")))
        for found in DOUBLED.finditer(re.sub(r"\{[^}]*\}", " ¤ ", text))
    ]
    assert not doubled, "\n".join(doubled)


def test_russian_references_part_their_areas_with_dashes():
    """A Russian list of sources parts the areas of each entry with " – " (ГОСТ Р 7.0.100: the
    edition, the place and publisher, the extent): every entry with a publisher does."""
    root = Path(__file__).resolve().parent.parent
    files = [root / "templates" / "i18n" / "ru.toml", *root.glob("plugins/*/*/i18n/*.ru.toml")]
    bare = [
        f"{path.name}: {key}"
        for path in files
        for key, entry in tomllib.loads(path.read_text(encoding="utf-8")).get("ref", {}).items()
        if " : " in entry and " – " not in entry[: entry.rindex(" : ")]
    ]
    assert not bare


def test_ukrainian_words_take_the_typographic_apostrophe():
    """A Ukrainian word's apostrophe is the typographic one (розв’язок), as in the rest of the
    note, not the typewriter's (розв'язок)."""
    files = [ROOT / "templates" / "i18n" / "uk.toml", *ROOT.glob("plugins/*/*/i18n/*.uk.toml")]
    straight = [
        f"{path.relative_to(ROOT)}: {key}: {found.group(0)!r}"
        for path in files
        for key, text in _texts(tomllib.loads(path.read_text(encoding="utf-8")))
        for found in re.finditer(r"[а-щьюяєіїґА-ЩЬЮЯЄІЇҐ]'[а-щьюяєіїґА-ЩЬЮЯЄІЇҐ]", text)
    ]
    assert (ROOT / "templates" / "i18n" / "uk.toml").exists()
    assert not straight, "\n".join(straight)


def test_ukrainian_moments_pulse_in_a_plane_with_the_euphonic_preposition():
    """ "ΣM_I і ΣM_II пульсують у вертикальній площині": between two consonants Ukrainian writes
    "у", after a vowel "в" ("ΣM_II пульсує в …")."""
    import re

    from conftest import shared_html

    text = " ".join(
        re.sub(
            r"<[^>]+>",
            "",
            shared_html(
                "inline4-petrol",
                {"engine": {"cylinders": 5, "firing_order": None}},
                "uk",
                ("balancing",),
            ).linked_html,
        ).split()
    )
    assert "пульсують у " in text and "пульсують в " not in text


def test_ukrainian_texts_write_privid_not_the_russian_privod():
    """The noun "привід" (a drive) in Ukrainian; "привод" is the Russian word (its other forms,
    "приводів", "приводного", are Ukrainian too)."""
    files = [ROOT / "templates" / "i18n" / "uk.toml", *ROOT.glob("plugins/*/*/i18n/*.uk.toml")]
    russian = [
        f"{path.relative_to(ROOT)}: {key}"
        for path in files
        for key, text in _texts(tomllib.loads(path.read_text(encoding="utf-8")))
        if re.search(r"\bпривод\b", text)
    ]
    assert not russian, "\n".join(russian)
