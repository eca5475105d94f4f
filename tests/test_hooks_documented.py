"""Every hook is documented: a docstring in hookspecs.py and a section in docs/plugins.md."""

from __future__ import annotations

import inspect
from pathlib import Path

import pytest

from crankdyn.plugin import hooks as hookspecs

DOCS = Path(__file__).resolve().parent.parent / "docs" / "plugins.md"
HOOKS = [
    name
    for name, obj in inspect.getmembers(hookspecs, inspect.isfunction)
    if name.startswith("crankdyn_")
]


def test_there_are_hooks():
    assert {"crankdyn_mechanisms", "crankdyn_stages", "crankdyn_catalogs"} <= set(HOOKS)


@pytest.mark.parametrize("hook", HOOKS)
def test_hook_has_docstring(hook):
    doc = inspect.getdoc(getattr(hookspecs, hook))
    assert doc and len(doc) > 80, f"{hook} needs a real docstring"


@pytest.mark.parametrize("hook", HOOKS)
def test_hook_is_documented_in_guide(hook):
    text = DOCS.read_text(encoding="utf-8")
    assert f"### `{hook}`" in text, f"docs/plugins.md has no section '### `{hook}`'"
