"""HTML to print-ready PDF through WeasyPrint, with no network and no arbitrary files.

The URL fetcher is the security boundary: scene text ends up in the HTML, so the
PDF step must not become a way to read files or reach hosts. Only ``data:`` URIs, the
report's own rendered figures (``figures/NAME.svg``, served from memory by exact URL) and
files inside the package's own templates folder load.
"""

from __future__ import annotations

import contextlib
import gc
import logging
import re
from importlib import resources
from pathlib import Path
from typing import Any
from urllib.parse import unquote, urlparse

from . import figure_forms, pdf_parts
from .assets import FIGURE_DIR
from .weasy import load_weasyprint


class BlockedResource(ValueError):
    pass


def _asset_root() -> Path:
    return Path(str(resources.files("crankdyn.templates"))).resolve()


def is_allowed(url: str) -> bool:
    """True for data: URIs and file: URLs inside the package's templates folder."""
    parsed = urlparse(url)
    if parsed.scheme == "data":
        return True
    if parsed.scheme == "file":
        path = Path(unquote(parsed.path)).resolve()
        root = _asset_root()
        return path == root or root in path.parents
    return False


def figure_urls(figures, base: str) -> dict:
    """URL -> the report's own figure (its ``svg``), as the page refers to it (``figures/NAME``).

    The SVG is read when WeasyPrint asks for it: figures still being drawn by forked children
    are waited for one by one, while the text before them is already being laid out."""

    return {f"{base}{FIGURE_DIR}/{f.name}": f for f in figures}


def _fetcher(in_memory: dict | None = None, forms: dict | None = None):
    """The safe fetcher; ``in_memory`` maps the exact URLs of the rendered figures to their
    FigureFile (served from memory, never from a file; any other URL follows :func:`is_allowed`).
    With ``forms`` (URL -> figure PDF, filled here), a figure that has a PDF page is served as an
    empty SVG of its size and its page kept there, to be stamped after the layout
    (:mod:`crankdyn.report.figure_forms`); any other figure is served as its SVG."""
    weasyprint = load_weasyprint()
    in_memory = dict(in_memory or {})

    def image(url: str) -> bytes:
        figure = in_memory[url]
        pdf = figure_forms.figure_page(figure) if forms is not None else None
        if pdf is None:
            return figure.svg
        forms[url] = pdf  # type: ignore[index]  # forms is not None here
        return figure_forms.placeholder_svg(pdf)

    if hasattr(weasyprint, "URLFetcher"):  # WeasyPrint >= 66: fetchers are objects

        class SafeURLFetcher(weasyprint.URLFetcher):  # type: ignore[name-defined]  # loaded at run time
            def fetch(self, url, headers=None):
                if unquote(url) in in_memory:
                    return weasyprint.urls.URLFetcherResponse(
                        url, image(unquote(url)), headers={"Content-Type": "image/svg+xml"}
                    )
                if not is_allowed(url):
                    raise BlockedResource(f"crankdyn does not load {url!r} into a report")
                return super().fetch(url, headers)

        return SafeURLFetcher(allowed_protocols=("data", "file"), allow_redirects=False)

    def safe_url_fetcher(url, *args, **kwargs):  # older WeasyPrint: a plain function
        if unquote(url) in in_memory:
            return {
                "string": image(unquote(url)),
                "mime_type": "image/svg+xml",
                "redirected_url": url,
            }
        if not is_allowed(url):
            raise BlockedResource(f"crankdyn does not load {url!r} into a report")
        return weasyprint.default_url_fetcher(url, *args, **kwargs)

    return safe_url_fetcher


#: A word space before an italic or bold symbol in running text ("за посібником <i>C</i><sub>II</sub>").
_SPACE_BEFORE_INLINE = re.compile(r"(?<=\S) ((?:<b>)?<i>|<b>)")


def spaces_into_inline(html: str) -> str:
    """``html`` with the word space before an italic or bold element moved into it (" <i>C</i>" →
    "<i> C</i>"): the same text, for WeasyPrint (70), which cannot break a line just before an
    inline element there and breaks it at the line's first space instead (a paragraph's first
    line would hold only "Амплітуду", the rest of it on the next). A space at a line's start is
    dropped as anywhere else."""
    return _SPACE_BEFORE_INLINE.sub(r"\1 ", html)


#: WeasyPrint makes millions of short-lived objects laying out a report, and Python's default
#: thresholds (a collection every 700 allocations) run the cyclic collector thousands of times
#: over them, a fifth of the layout's time. While a PDF is made the collector runs every 50 000
#: allocations, which leaves the peak memory as it was (its garbage is hardly ever cyclic).
LAYOUT_GC_THRESHOLDS = (50_000, 20, 10)


@contextlib.contextmanager
def fewer_collections():
    """The cyclic collector at :data:`LAYOUT_GC_THRESHOLDS` inside, as it was afterwards."""
    before = gc.get_threshold()
    gc.set_threshold(*LAYOUT_GC_THRESHOLDS)
    try:
        yield
    finally:
        gc.set_threshold(*before)


class ParsedStylesheets:
    """A page's stylesheet (its head's ``<style>``) parsed once in a process and given to each
    layout of it as parsed: WeasyPrint parses a page's styles at every layout (25 ms for the
    report's), and a printed report is laid out four times (its two parts, its front matter
    twice), after a warm-up of the same styles. The stylesheet is given as the user's, with the
    same font and counter-style configuration each time. The page then has no author
    stylesheet in its head, which lays it out the same unless the sheet has a rule that
    ``!important`` or an id selector would weigh differently against the page's ``style``
    attributes (an author's): such a stylesheet stays in the page, as does one that loads
    anything (``url(``, ``@import``, ``@font-face``)."""

    _HEAD_STYLE = re.compile(r"<style>(.*?)</style>", re.S)

    def __init__(self) -> None:
        self._parsed: dict[tuple[str, str], Any] = {}
        self._configuration: tuple[Any, Any] | None = None

    def taken_from(self, html: str, base: str) -> tuple[str, dict]:
        """``html`` without its head's stylesheet, and the keyword arguments of WeasyPrint's
        ``HTML.render`` that give it back parsed (``html`` as it is and none, if it has none
        that can be kept)."""
        body = html.find("<body")
        found = self._HEAD_STYLE.search(html, 0, body if body >= 0 else len(html))
        if found is None or not self._keeps_its_weight(found.group(1)):
            return html, {}
        weasyprint = load_weasyprint()
        if self._configuration is None:
            from weasyprint.css.counters import CounterStyle  # lazy: heavy optional import
            from weasyprint.text.fonts import FontConfiguration  # lazy: heavy optional import

            self._configuration = (FontConfiguration(), CounterStyle())
        fonts, counters = self._configuration
        key = (found.group(1), base)
        sheet = self._parsed.get(key)
        if sheet is None:
            if len(self._parsed) >= 8:  # a batch's languages and frames
                self._parsed.clear()
            sheet = weasyprint.CSS(
                string=found.group(1), base_url=base, font_config=fonts, counter_style=counters
            )
            self._parsed[key] = sheet
        kept = {"stylesheets": [sheet], "font_config": fonts, "counter_style": counters}
        return html[: found.start()] + html[found.end() :], kept

    _DECLARATIONS = re.compile(r"\{[^{}]*\}")

    @classmethod
    def _keeps_its_weight(cls, css: str) -> bool:
        """Whether ``css`` lays a page out the same as the user's stylesheet (see the class)."""
        if any(word in css for word in ("url(", "@import", "@font-face", "!important")):
            return False
        selectors = cls._DECLARATIONS.sub("", cls._DECLARATIONS.sub("{}", css))
        return "#" not in selectors


#: This process's parsed stylesheets (:class:`ParsedStylesheets`).
STYLESHEETS = ParsedStylesheets()


def html_to_pdf(html: str, figures=(), *, parallel: bool = False) -> bytes:
    """PDF of ``html``; ``figures`` (FigureFile) are the files its ``figures/NAME.svg`` refer to.

    ``parallel``: the chapters may be laid out in a forked child at the same time
    (:mod:`crankdyn.report.pdf_parts`); only for a caller whose figures a child may ask for too
    (the printer's, served by the report's process one request at a time)."""
    with fewer_collections():
        return _html_to_pdf(html, figures, parallel)


def _html_to_pdf(html: str, figures, parallel: bool) -> bytes:
    # figures drawn as PDF pages are stamped into the laid-out pages (crankdyn.report.figure_forms)
    if figure_forms.available():
        try:
            return _laid_out(html, figures, parallel, forms={})
        except figure_forms.NotPlaced:
            logging.getLogger(__name__).debug("a figure's place was not found", exc_info=True)
    return _laid_out(html, figures, parallel, forms=None)


def _laid_out(html: str, figures, parallel: bool, forms: dict[str, bytes] | None) -> bytes:
    HTML = load_weasyprint().HTML
    html = spaces_into_inline(html)

    # A blocked resource is logged by WeasyPrint as a warning and left out; keep the
    # console quiet (the tests check the blocking itself).
    logging.getLogger("weasyprint").setLevel(logging.ERROR)
    base = _asset_root().as_uri() + "/"
    fetcher = _fetcher(figure_urls(figures, base), forms)

    def render(page_html: str):
        page_html, kept = STYLESHEETS.taken_from(page_html, base)
        document = HTML(string=page_html, base_url=base, url_fetcher=fetcher).render(**kept)
        if forms is None:
            return document
        return figure_forms.StampedDocument(document, forms, base, page_html)

    if parallel:
        parts = pdf_parts.split(html)
        if parts is not None and pdf_parts.can_split_processes():
            try:
                return pdf_parts.parallel_pdf(parts, render)
            except (pdf_parts.PartAbandoned, figure_forms.NotPlaced):
                raise  # the figures' channel may be out of step: the report makes the PDF
            except Exception:  # noqa: BLE001 - the same pages from one layout instead
                logging.getLogger(__name__).debug("laying out in parts failed", exc_info=True)
    return render(html).write_pdf()
