"""The documentation's text as the site shows it: every page of docs/ and the scene and results.json
references the site generates from the code (docs/hooks/reference.py)."""

from __future__ import annotations

import functools
import importlib.util
from pathlib import Path

DOCS = Path(__file__).resolve().parent.parent / "docs"


@functools.cache
def documentation_text() -> str:
    spec = importlib.util.spec_from_file_location(
        "docs_reference_hook", DOCS / "hooks" / "reference.py"
    )
    hook = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hook)
    pages = [p.read_text(encoding="utf-8") for p in sorted(DOCS.glob("*.md"))]
    return "\n".join(pages + [hook.scene_reference(), hook.results_reference()])
