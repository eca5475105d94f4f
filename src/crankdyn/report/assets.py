"""The report's fixed files: the package's templates folder (the page frame, its stylesheets, the
section templates) and the folder a report's figures are written to, by name.

Nothing heavy is imported here (no numpy, no Jinja, no plugin types): the PDF printer, a
process of its own that loads WeasyPrint while the report is computed, reads the stylesheets
and the figures' folder from here and nothing more of the report's code.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

#: Folder of the figure files next to report.html, as the page refers to them.
FIGURE_DIR = "figures"


def templates_dir() -> Path:
    """The package's templates folder (report.html.j2, the stylesheets, the sections)."""
    return Path(str(resources.files("crankdyn.templates")))


#: The page's ``lang`` by report language, where it is not the code itself: an English note is
#: hyphenated with the US patterns (the British ones part "journ-als", "pos-it-ive").
HTML_LANGUAGES = {"en": "en-US"}


def html_language(language: str) -> str:
    """The report's ``<html lang>``: the language whose hyphenation the printed page uses."""
    return HTML_LANGUAGES.get(language, language)


def report_css(language: str, frame: str = "none") -> str:
    """The page frame (report.css), a language's own print rules where its standard differs
    (report.ru.css) and, with ``[report] frame = "eskd"``, the sheet frame (frame-eskd.css)."""
    names = (
        "report.css",
        f"report.{language}.css",
        *(("frame-eskd.css",) if frame == "eskd" else ()),
    )
    folder = templates_dir()
    return "\n".join(
        (folder / name).read_text(encoding="utf-8") for name in names if (folder / name).is_file()
    )
