"""``crankdyn serve SCENE``: a live HTML preview of the report on 127.0.0.1.

Three threads and one rule. A *watcher* (``watchfiles``) sees the scene file, or a
file it names (``cycle.trace_file`` and any other ``*_file`` key), being saved and
marks the preview dirty; a *builder* re-renders the report in memory; the *HTTP
server* (stdlib ``ThreadingHTTPServer``) serves whatever snapshot is current. The
rule: the snapshot is replaced in one assignment, and only by a complete result —
a full report, or for a scene that does not validate an error page listing its
problems — so a half-built report is never served.

The open browser tab follows the builds: every page carries a small inline script that asks
``/update?after=V`` — an answer the server holds back until the version is no longer V (a long
poll: the tab learns of a new build at once). The answer holds the HTML of the page's parts (its
top-level sections, :func:`page_parts`) that differ from version V's, and the script puts them in
place of the old ones by id: the tab keeps its scroll position and every other section, figures
included, as it is. A page whose frame changed (its head, its list of sections) or an error page
is loaded anew instead. ``/report.pdf`` renders the current report to PDF on request (cached per
version).

Fast saves: a build re-runs only the stages whose inputs changed
(:class:`crankdyn.engine.stage_cache.StageCache`)
and re-renders only their sections (:class:`crankdyn.report.section_cache.SectionCache`); the
new page is published as soon as its text is ready, and its figures follow: each is served at
``/figures/TOKEN/NAME`` once drawn (the request waits for it), and a figure kept from the last
build keeps its URL, so the browser shows it from its cache at once.
"""

from __future__ import annotations

import html
import json
import os
import re
import secrets
import signal
import sys
import threading
import time
import traceback
import webbrowser
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from urllib.parse import parse_qs, quote, urlsplit

from ..engine.orchestrator import is_study
from ..engine.stage_cache import StageCache
from ..engine.studies import StudyWorker
from ..errors import MISSING, CrankdynError, Problem, SceneError
from ..output.pipeline import run_for_preview
from ..plugin.registry import default_registry
from ..report.context import FIGURE_DIR, draw_figures, start_drawing
from ..report.i18n import available_languages
from ..report.pdf import html_to_pdf
from ..report.section_cache import SectionCache
from ..scene.inputcheck import MAX_DEPTH
from ..scene.model import load_scene, read_scene_data

HOST = "127.0.0.1"
DEFAULT_PORT = 8765
POLL_MS = 600  # how long an open tab waits before asking /update again after a failed request
LONG_POLL_S = 20.0  # the longest /version?after=V and /update?after=V hold their answers back
#: A save is built once no further change to the watched files came for this long (ms): an
#: editor's save (write, or a temporary file and a rename) comes as one burst of changes.
WATCH_STEP_MS = 20
#: The nice value added to the processes the builder forks to draw figures and to the study
#: worker: they work in the background of the page, which the open tab swaps in meanwhile on the
#: same cores.
DRAWING_NICE = 10
BUILDER_THREAD = "crankdyn-builder"
#: The versions whose parts are kept to answer /update: a tab shows one of the last few pages
#: (a tab further behind loads the page anew).
KEPT_PAGES = 8


@dataclass(frozen=True)
class Snapshot:
    """What the server shows: one complete rendering (or error page) and its version."""

    version: str
    page: bytes  # the HTML served at /, with the reload script
    state: str  # "report", "scene-error", "error" or "starting"
    report_html: str | None = (
        None  # the report without the script, as figures/NAME.svg links it: the PDF
    )
    problems: tuple[str, ...] = ()
    render_s: float = 0.0
    built_at: float = field(default_factory=time.time)
    figures: tuple = ()  # the report's FigureFiles, as report_html refers to them
    pending: tuple[
        str, ...
    ] = ()  # stages whose sections say they follow (the next snapshot has them)
    figures_s: float | None = None  # when every figure was drawn, seconds after the build started
    parts: PageParts | None = None  # the page's swappable parts (None: an error page)

    @property
    def figures_drawn(self) -> bool:
        return all(f.drawn for f in self.figures)


# --------------------------------------------------------------------------- pages


def reload_script(version: str, nonce: str) -> str:
    """The inline script that keeps the tab on the server's current version: it swaps in the
    parts that changed (``/update``), or reloads the page when the server says so. The version
    the tab shows is in ``data-version`` of the page's root element."""
    return (
        f'<script nonce="{nonce}">(function(){{var v={json.dumps(version)},'
        "d=document.documentElement;d.dataset.version=v;"
        # figures still being drawn wait behind a blank image: one request asks when they are
        # done (a browser holds only six connections to a host: six held image requests would
        # stall the next update)
        "function figures(){var w=Array.prototype.filter.call("
        "document.querySelectorAll('img[data-figure]'),function(i){"
        "return i.src.slice(0,5)==='data:';});"
        "if(w.length){fetch('/figures-ready?version='+encodeURIComponent(v),{cache:'no-store'})"
        ".then(function(){w.forEach(function(i){i.src=i.dataset.figure;});});}}"
        # every part named must be there before any is replaced: else the whole page anew
        "function swap(u){var ids=Object.keys(u.parts);"
        "if(!ids.every(function(k){return document.getElementById(k);})){return false;}"
        "ids.forEach(function(k){document.getElementById(k).outerHTML=u.parts[k];});"
        "v=u.version;d.dataset.version=v;figures();return true;}"
        "function poll(){fetch('/update?after='+encodeURIComponent(v),{cache:'no-store'})"
        ".then(function(r){return r.json();})"
        ".then(function(u){if(u.version===v){poll();}"
        "else if(u.parts&&swap(u)){poll();}else{location.reload();}})"
        f".catch(function(){{setTimeout(poll,{POLL_MS});}});}}"
        "figures();poll();})();</script>"
    )


def with_reload(page: str, version: str, nonce: str) -> str:
    script = reload_script(version, nonce)
    at = page.rfind("</body>")
    return page + script if at < 0 else page[:at] + script + page[at:]


#: Where a part of the page starts: a top-level section (or the contents' nav), at the start of a
#: line, as the report's template writes each.
_PART_START = re.compile(r"(?m)^<(section|nav)\b([^>]*)>")
_ID = re.compile(r'\sid="([^"]*)"')
_CLASS = re.compile(r'\sclass="([^"]*)"')


@dataclass(frozen=True)
class PageParts:
    """A page as the parts the tab can swap one by one: ``frame[0] + parts[0] + frame[1] + …
    + parts[-1] + frame[-1]`` is the page. Each part is one top-level element with an ``id``
    (its own, or ``preview-`` and its class where it has none)."""

    frame: tuple[str, ...]
    ids: tuple[str, ...]
    parts: tuple[str, ...]
    #: each part as the tab shows it once its figures are drawn (a blank image's place taken by
    #: the figure's URL): a part that differs from the last page's only there is not sent again
    drawn: tuple[str, ...] = ()

    @property
    def html(self) -> str:
        pieces = [self.frame[0]]
        for part, between in zip(self.parts, self.frame[1:], strict=True):
            pieces += [part, between]
        return "".join(pieces)

    def changed_since(self, old: PageParts) -> dict[str, str] | None:
        """The parts that differ from ``old``'s, by id; None when the frame differs (the page is
        to be loaded anew)."""
        if old.frame != self.frame or old.ids != self.ids:
            return None
        return {
            key: part
            for key, part, now, before in zip(
                self.ids, self.parts, self.drawn, old.drawn, strict=True
            )
            if now != before
        }


def _closed(part: str, tag: str) -> bool:
    """Whether ``part`` is one ``tag`` element, closed at its end, with its own sections nested."""
    opened = len(re.findall(rf"<{tag}\b", part))
    return part.endswith(f"</{tag}>") and opened == part.count(f"</{tag}>")


def page_parts(page: str) -> PageParts | None:
    """The page's top-level sections as :class:`PageParts`; None when it cannot be parted (no
    section, or one that is not a single closed element: the page is then loaded anew)."""
    starts = list(_PART_START.finditer(page))
    body_end = page.rfind("</body>")
    if not starts or body_end < starts[-1].start():
        return None
    ends = [m.start() for m in starts[1:]] + [body_end]
    frame, ids, parts, taken = [page[: starts[0].start()]], [], [], set()
    for match, end in zip(starts, ends, strict=True):
        text = page[match.start() : end]
        # the element ends at its tag's last close; what follows it (space, the colophon after
        # the last section) is the frame's
        part = text[: text.rfind(f"</{match[1]}>") + len(match[1]) + 3]
        if not _closed(part, match[1]):
            return None
        frame.append(text[len(part) :])
        found = _ID.search(match[2])
        if found is not None:
            key = found[1]
        else:
            found_class = _CLASS.search(match[2])
            name = (found_class[1] if found_class is not None else str(match[1])).split()
            key = base = f"preview-{name[0] if name else match[1]}"
            number = 1
            while key in taken:
                number += 1
                key = f"{base}-{number}"
            part = f'<{match[1]} id="{key}"{match[2]}>' + part[match.end() - match.start() :]
        if key in taken or not key:
            return None
        taken.add(key)
        ids.append(key)
        parts.append(part)
    frame[-1] += page[body_end:]
    drawn = tuple(_BLANK_IMAGE.sub(r'src="\1"', part) for part in parts)
    return PageParts(tuple(frame), tuple(ids), tuple(parts), drawn)


_ERROR_CSS = (
    "body{font-family:'Liberation Serif','DejaVu Serif',serif;max-width:54em;margin:2em auto;"
    "padding:0 1em;color:#111}h1{color:#8a1010;font-size:1.4em}table{border-collapse:collapse;width:100%}"
    "th,td{border:1px solid #bbb;padding:.3em .5em;text-align:left;vertical-align:top}"
    "td.field,td.value{font-family:'DejaVu Sans Mono',monospace;white-space:pre-wrap}"
    "pre{background:#f4f4f4;padding:.6em;overflow:auto}.hint{color:#555}"
)


def _shown(value) -> str:
    return "(missing)" if value is MISSING else repr(value)


def error_page(exc: BaseException, scene_path: Path) -> tuple[str, str, tuple[str, ...]]:
    """(state, HTML, problem lines) for a build that failed; every value is escaped."""
    e = html.escape
    if isinstance(exc, SceneError):
        state = "scene-error"
        problems = tuple(str(p) for p in exc.problems)
        rows = "".join(
            f'<tr><td class="field">{e(p.field)}</td><td class="value">{e(_shown(p.value))}</td>'
            f"<td>{e(p.allowed)}</td></tr>"
            for p in exc.problems
        )
        head = f"The scene has {len(exc.problems)} problem{'s' if len(exc.problems) != 1 else ''}"
        body = (
            f"<table><thead><tr><th>field</th><th>value</th><th>allowed</th></tr></thead>"
            f"<tbody>{rows}</tbody></table>"
        )
    elif isinstance(exc, CrankdynError):
        state, problems = "error", (str(exc),)
        head = "crankdyn cannot build this report"
        body = f"<pre>{e(str(exc))}</pre>"
    else:
        state, problems = "error", (f"internal error: {exc.__class__.__name__}: {exc}",)
        head = "crankdyn failed while building the report (internal error)"
        trace = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
        body = (
            f'<p>{e(problems[0])}</p><pre>{e(trace)}</pre><p class="hint">Please report this.</p>'
        )
    page = (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>crankdyn: {e(head)}</title>'
        f'<style>{_ERROR_CSS}</style></head><body data-crankdyn="{state}"><h1>{e(head)}</h1>'
        f'<p class="hint">{e(str(scene_path))}</p>{body}'
        '<p class="hint">The preview updates by itself when you save the file.</p></body></html>'
    )
    return state, page, problems


def _starting_page() -> str:
    return (
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>crankdyn: rendering…</title>'
        f'<style>{_ERROR_CSS}</style></head><body data-crankdyn="starting"><p>Rendering the report…</p>'
        "</body></html>"
    )


def _url(figure) -> str:
    """A figure's URL below figures/: the token of its drawing, then its file name."""
    return f"{figure.preview_token}/{figure.name}"


def _placeholder(url: str, size_pt: tuple[float, float]) -> str:
    """``src`` and ``data-figure`` of a figure not drawn yet: a blank image of its size."""
    width, height = size_pt
    blank = (
        f"<svg xmlns='http://www.w3.org/2000/svg' width='{width:.0f}pt' height='{height:.0f}pt' "
        f"viewBox='0 0 {width:.0f} {height:.0f}'/>"
    )
    return f'src="data:image/svg+xml,{quote(blank)}" data-figure="{FIGURE_DIR}/{url}"'


#: A figure's blank image and its URL (:func:`_placeholder`), as a part of the page holds it.
_BLANK_IMAGE = re.compile(r'src="data:image/svg\+xml,[^"]*" data-figure="([^"]*)"')
_SVG_SIZE = re.compile(rb'<svg\b[^>]*?\swidth="([0-9.]+)pt"\s+height="([0-9.]+)pt"')


def svg_size(svg: bytes) -> tuple[float, float] | None:
    """(width, height) in pt of a figure as drawn (matplotlib writes them on its ``svg``)."""
    found = _SVG_SIZE.search(svg, 0, 4096)
    return None if found is None else (float(found[1]), float(found[2]))


def figure_size(figure) -> tuple[float, float]:
    """(width, height) in pt of a figure's matplotlib figure (built now if it is not yet)."""
    width_in, height_in = figure.figure.get_size_inches()
    return width_in * 72, height_in * 72


# --------------------------------------------------------------------------- files


def referenced_files(scene_path: Path) -> set[Path]:
    """Files a scene names: every string under a key ending in ``_file`` (e.g. cycle.trace_file).

    Read from the raw TOML so that a scene that does not validate still has its data
    file watched; relative names are resolved against the scene's folder.
    """
    try:
        data = read_scene_data(scene_path)
    except SceneError:
        return set()
    found: set[Path] = set()
    tables = [(data, 0)]
    while tables:  # iterative: dotted keys may nest a table thousands deep
        table, depth = tables.pop()
        for key, value in table.items():
            if isinstance(value, dict) and depth < MAX_DEPTH:
                tables.append((value, depth + 1))
            elif isinstance(value, str) and key.endswith("_file") and value.strip():
                found.add(scene_path.parent / value)
    return found


def _watch_names(paths: Iterable[Path]) -> set[Path]:
    """The names change events arrive with: the file in its resolved folder, and its target if a link."""
    names = set()
    for p in paths:
        p = Path(os.path.abspath(p))
        names.add(p.parent.resolve() / p.name)
        names.add(p.resolve())
    return names


# --------------------------------------------------------------------------- the preview

#: A study that took less than this (s) on the last save is computed by the study worker on the
#: next, while the page is rendered and shown without it (its section follows, swapped in) ...
STUDY_INLINE_S = 0.5
#: ... if the stages the save ran again took less than this (s): the worker runs them a second
#: time (the in-line four's 0.4 s cost the figures' cores more than the worker saved).
WORKER_STAGES_S = 0.1
#: The longest the builder stays idle waiting for the worker's study before rendering the page
#: with it (s); it then waits in that rendering, when the study's section comes.
STUDY_WAIT_S = 30.0


class Preview:
    """Builds snapshots of one scene; watches its files; renders the PDF on request."""

    def __init__(
        self,
        scene_path: Path | str,
        language: str | None = None,
        stages: list[str] | None = None,
        registry=None,
        log: Callable[[str], None] | None = None,
        debounce_ms: int = 80,
    ):
        self.scene_path = Path(os.path.abspath(scene_path))
        self.language = language
        self.stages = stages
        self.nonce = secrets.token_urlsafe(12)
        self._boot = secrets.token_hex(3)
        self._count = 0
        self._registry = registry
        self._log = log or (lambda message: None)
        self._debounce_ms = debounce_ms
        self._dirty = threading.Event()
        self._stop = threading.Event()
        self._building = threading.Event()
        self._pdf_lock = threading.Lock()
        self._pdf_cache: tuple[str, bytes] | None = None

        self.stage_cache = StageCache()  # a save re-runs only the stages whose inputs changed
        self.sections_cache = SectionCache()  # ... and re-renders only their sections
        self._drawn = threading.Condition()  # notified after each figure the builder draws
        self._recent: tuple = ()  # the snapshots before the current one
        self._pages: dict[str, PageParts | None] = {}  # the last pages' parts, by version
        self._sizes: dict[str, tuple[float, float]] = {}  # the last drawing's size (pt), by name
        self._tokens = 0
        self._warmed: set[str] = set()  # the figures this process has drawn itself (_warm)
        self._worker: StudyWorker | None = (
            None  # computes the studies while the page is rendered (start)
        )
        self._studies = None  # the studies the shown page says follow, being computed there
        self._study_s: float | None = None  # how long the last save's study took
        self._stages_s: float | None = None  # ... and the stages it ran again before it
        self._threads: list[threading.Thread] = []
        self._seen_at: float | None = None  # when the watcher last saw a save (epoch s)
        #: the last build's moments (epoch s): the save seen, the build started, its page out
        self.times: dict[str, float | None] = {}
        version = f"{self._boot}-0"
        self._published = threading.Condition()  # notified when a new snapshot is shown
        self.snapshot = Snapshot(
            version, with_reload(_starting_page(), version, self.nonce).encode("utf-8"), "starting"
        )

    # ------------------------------------------------------------- building
    @property
    def building(self) -> bool:
        return self._building.is_set()

    def build(self) -> Snapshot:
        """Render the scene now (in this thread) and make the result the current snapshot: the
        page first — without a study that has to run again (the error against run time), whose
        section says it follows —, then the whole page, then its figures (see the module docstring)."""
        self._building.set()
        start = time.perf_counter()
        seen, started = self._seen_at, time.time()
        try:
            snapshot = self._publish(*self._render(defer_studies=True), start)
            self.times = {"seen": seen, "started": started, "page": time.time()}
            if (
                snapshot.pending
            ):  # the study, and nothing else, runs now (its figures drawn meanwhile)
                in_children = {id(f) for f in snapshot.figures if not f.drawn}
                finish = start_drawing(snapshot.figures)
                try:
                    self._await_worker()
                    snapshot = self._publish(*self._render(defer_studies=False), start)
                    if (
                        finish is not None
                    ):  # the study's figures: drawn here while the children draw
                        self._draw_here([f for f in snapshot.figures if id(f) not in in_children])
                finally:
                    if finish is not None:
                        finish()
                        with self._drawn:
                            self._drawn.notify_all()
            self._draw(snapshot, start)
        finally:
            self._building.clear()
        if snapshot.state == "report":
            self._log(
                f"rendered {self.scene_path.name} in {snapshot.render_s:.2f} s, figures by "
                f"{snapshot.figures_s:.2f} s (version {self._count})"
            )
        else:
            self._log(
                f"{self.scene_path.name}: {len(snapshot.problems)} problem(s); showing them instead of the "
                "report\n" + "\n".join(f"  - {p}" for p in snapshot.problems)
            )
        return snapshot

    def _await_worker(self) -> None:
        """Stay idle until the study worker has this save's study: the page just published is
        being taken by the tab meanwhile, and rendering the whole page cannot end sooner."""
        wait = getattr(getattr(self._studies, "background", None), "wait", None)
        if wait is not None:
            wait(STUDY_WAIT_S)

    def _publish(
        self,
        state: str,
        page: str,
        problems: tuple[str, ...],
        report_html: str | None,
        figures: list,
        pending: tuple[str, ...],
        start: float,
    ) -> Snapshot:
        self._count += 1
        version = f"{self._boot}-{self._count}"
        parts = page_parts(page) if state == "report" else None
        if parts is not None:
            page = parts.html  # with the ids the tab finds the parts by
        snapshot = Snapshot(
            version,
            with_reload(page, version, self.nonce).encode("utf-8"),
            state,
            report_html,
            problems,
            time.perf_counter() - start,
            figures=tuple(figures),
            pending=pending,
            parts=parts,
        )
        with self._drawn:
            self._recent = (self.snapshot, *self._recent)[:2]  # a tab may still show one of these
            self._pages[version] = parts
            while len(self._pages) > KEPT_PAGES:
                del self._pages[next(iter(self._pages))]
        self.snapshot = snapshot  # the one swap: readers see the old or the new snapshot, whole
        with self._published:
            self._published.notify_all()
        return snapshot

    def _render(
        self, defer_studies: bool = False
    ) -> tuple[str, str, tuple[str, ...], str | None, list, tuple]:
        try:
            if self._registry is None:
                self._registry = default_registry()
            overrides = {"report": {"language": self.language}} if self.language else None
            scene = load_scene(self.scene_path, overrides, registry=self._registry)
            studies, self._studies = self._studies, None
            runs = dict(self.stage_cache.runs)
            try:
                # the page never waits for a study: a quick one is computed by the worker
                # meanwhile; a slow one is computed here after the page (the worker would compute
                # the changed stages a second time, on the cores the figures need)
                quick = (
                    self._study_s is not None
                    and self._study_s < STUDY_INLINE_S
                    and self._stages_s is not None
                    and self._stages_s < WORKER_STAGES_S
                )
                result, rendered, self._studies = run_for_preview(
                    scene,
                    self._registry,
                    self.stages,
                    available_languages(),
                    self.stage_cache,
                    self.sections_cache,
                    defer_studies,
                    studies,
                    self._worker if quick else None,
                    figure_sink=self._build_unsized,
                )
                self._note_times(result, runs)
            finally:
                if studies is not None:  # taken from, or not wanted (the scene changed meanwhile)
                    studies.close_background()
        except Exception as exc:  # noqa: BLE001 - every failure becomes a page, the server lives on
            state, page, problems = error_page(exc, self.scene_path)
            return state, page, problems, None, [], ()
        page = rendered.linked_html
        for figure in rendered.figures:
            if getattr(figure, "preview_token", None) is None:  # a new figure: a new URL
                self._tokens += 1
                figure.preview_token = f"{self._boot}{self._tokens}"
            url = _url(figure)
            # a figure still to draw: a blank image of its size until the page's script swaps it in
            page = page.replace(
                f'src="{FIGURE_DIR}/{figure.name}"',
                f'src="{FIGURE_DIR}/{url}"'
                if figure.drawn
                else _placeholder(url, self._sizes.get(figure.name) or figure_size(figure)),
            )
        return (
            "report",
            page,
            (),
            rendered.linked_html,
            list(rendered.figures),
            tuple(result.pending),
        )

    def _note_times(self, result, runs: dict) -> None:
        """How long the studies this rendering ran took (the worker's or the server's run), and
        the other stages it ran again, for the next save's choice. A save's first pass runs the
        stages, its second the study; what did not run keeps its last time."""
        ran = [
            s
            for s in result.plan.order
            if s.name in result.timing_s and self.stage_cache.runs[s.name] > runs.get(s.name, 0)
        ]
        studies = [result.timing_s[s.name] for s in ran if is_study(s)]
        stages = [result.timing_s[s.name] for s in ran if not is_study(s)]
        if studies:
            self._study_s = max(studies)
        if stages:
            self._stages_s = sum(stages)

    def _build_unsized(self, figures) -> None:
        """Build, as its section is rendered, each new figure of a name not drawn before: the
        page's blank image needs its size. A figure drawn before under its name takes that
        drawing's size, and is built by the process that draws it (building the figures' axes
        of a mass's edit takes longer than rendering the page's text)."""
        for figure in figures:
            if not figure.drawn and figure.name not in self._sizes:
                figure.figure  # noqa: B018 - built for its size

    def _note_sizes(self, figures) -> None:
        for figure in figures:
            if figure.drawn and (size := svg_size(figure.svg)) is not None:
                self._sizes[figure.name] = size

    def _draw(self, snapshot: Snapshot, start: float) -> None:
        """Draw the snapshot's new figures, shared by forked processes, and wake the requests
        that wait for them. The server's other threads only wait or send bytes and the children
        only draw and exit, so forking beside them is safe here (``allow_threads``)."""
        pending = [f for f in snapshot.figures if not f.drawn]
        if pending:
            draw_figures(pending, allow_threads=True)
            with self._drawn:
                self._drawn.notify_all()
        self._note_sizes(snapshot.figures)
        object.__setattr__(snapshot, "figures_s", time.perf_counter() - start)

    def _draw_here(self, figures) -> None:
        """Draw, in this process, the figures no child is drawing (the study's, new with the whole
        page), while the children draw the others: this process would only wait for them, and
        it has the figures' labels typeset already (:meth:`_warm`)."""
        for figure in figures:
            if figure.drawn:
                continue
            figure.svg  # noqa: B018 - drawn and kept
            with self._drawn:
                self._drawn.notify_all()

    def figures_ready(self, version: str, timeout: float = 120.0) -> bool:
        """Wait until the figures of snapshot ``version`` are drawn (False if another snapshot came)."""
        deadline = time.monotonic() + timeout
        with self._drawn:
            while True:
                snapshot = self.snapshot
                if snapshot.version != version and not any(
                    s.version == version for s in self._recent
                ):
                    return False
                if all(f.drawn for f in self._figures_of(version)):
                    return True
                if time.monotonic() >= deadline:
                    return False
                self._drawn.wait(0.5)

    def _figures_of(self, version: str) -> tuple:
        return next((s.figures for s in (self.snapshot, *self._recent) if s.version == version), ())

    def changes_after(self, version: str, timeout: float = LONG_POLL_S) -> dict:
        """What a tab showing ``version`` needs, as soon as the version is not ``version`` (or
        after ``timeout`` seconds): ``{"version": V}`` alone when nothing changed, with
        ``"parts"`` (id: HTML) the parts that differ from ``version``'s page, or with
        ``"reload": true`` when the page is to be loaded anew."""
        if self.version_after(version, timeout) == version:
            return {"version": version}
        snapshot = self.snapshot  # the newest: a tab skips the versions built meanwhile
        with self._drawn:
            old = self._pages.get(version)
        changed = (
            None if old is None or snapshot.parts is None else snapshot.parts.changed_since(old)
        )
        if changed is None:
            return {"version": snapshot.version, "reload": True}
        return {"version": snapshot.version, "parts": changed}

    def version_after(self, version: str, timeout: float = LONG_POLL_S) -> str:
        """The current version, as soon as it is not ``version`` (or after ``timeout`` seconds)."""
        with self._published:
            self._published.wait_for(
                lambda: self.snapshot.version != version or self._stop.is_set(), timeout
            )
        return self.snapshot.version

    def figure(self, url: str, timeout: float = 120.0) -> bytes | None:
        """The SVG at ``figures/<url>``, waiting while the builder draws it; None if unknown."""
        deadline = time.monotonic() + timeout
        with self._drawn:
            while True:
                # this build's figures or a recent one's: a tab may still show an earlier page
                figure = next(
                    (
                        f
                        for snap in (self.snapshot, *self._recent)
                        for f in snap.figures
                        if _url(f) == url
                    ),
                    None,
                )
                if figure is None:
                    return None
                if figure.drawn:
                    return figure.svg
                if (
                    not self._drawn.wait(max(0.0, min(0.5, deadline - time.monotonic())))
                    and time.monotonic() >= deadline
                ):
                    return None

    def pdf(self, snapshot: Snapshot) -> bytes:
        """The PDF of ``snapshot``'s report, built on the first request for that version."""
        with self._pdf_lock:
            if self._pdf_cache is None or self._pdf_cache[0] != snapshot.version:
                if snapshot.report_html is None:
                    raise CrankdynError("the scene has no report to print")
                # drawn by the builder, never here (matplotlib is not thread-safe)
                if not self.figures_ready(snapshot.version):
                    raise CrankdynError("the report's figures were not drawn in time")
                self._pdf_cache = (
                    snapshot.version,
                    html_to_pdf(snapshot.report_html, snapshot.figures),
                )
            return self._pdf_cache[1]

    # ------------------------------------------------------------- threads
    def watched(self) -> set[Path]:
        return {self.scene_path} | {
            Path(os.path.abspath(p)) for p in referenced_files(self.scene_path)
        }

    def start(self) -> None:
        """Start the study worker, then the builder and watcher threads; the first build begins
        at once. The worker is forked first: forking beside running threads is not safe."""
        if self._worker is None:
            self._worker = StudyWorker.start(self._registry)
            if self._worker is not None:  # its study follows the page, as the figures do
                _lower_priority(self._worker.pid)
        self._dirty.set()
        for target, name in (
            (self._builder, BUILDER_THREAD),
            (self._watcher, "crankdyn-watcher"),
        ):
            thread = threading.Thread(target=target, name=name, daemon=True)
            thread.start()
            self._threads.append(thread)

    def stop(self, timeout: float = 10.0) -> None:
        self._stop.set()
        self._dirty.set()
        with self._published:  # answer the tabs' long polls now
            self._published.notify_all()
        for thread in self._threads:
            thread.join(timeout)
        if self._worker is not None:  # no worker left behind
            self._worker.stop()
            self._worker = None

    def _builder(self) -> None:
        while not self._stop.is_set():
            if not self._dirty.wait(0.5) or self._stop.is_set():
                continue
            self._dirty.clear()  # saves during the build mark it dirty again: one more build follows
            self._warm(self.build())

    def _warm(self, snapshot: Snapshot) -> None:
        """While nothing is to be built, draw here, once, each figure this process has not drawn
        before, and throw the SVG away: the figures are drawn by children forked from this
        process, and what matplotlib keeps per process (typeset mathtext labels, loaded fonts)
        died with each child, so every save had all labels typeset again (a third of the
        drawing time). A child forked after this finds them ready. A save meanwhile stops the
        warming between two figures (one figure, a few tens of ms, is the longest it waits)."""
        if snapshot.state != "report":
            return
        for figure in snapshot.figures:
            if self._dirty.is_set() or self._stop.is_set():
                return
            if figure.name in self._warmed or not figure.drawn:
                continue
            try:
                figure.draw()  # in this process; the SVG the page shows is the child's, kept
            except Exception:  # noqa: BLE001 - warming is an optimisation: the figure was drawn already
                pass
            self._warmed.add(figure.name)

    def _watcher(self) -> None:
        import watchfiles  # lazy: heavy optional import (watchfiles: only while the preview watches the scene)

        while not self._stop.is_set():
            files = self.watched()
            names = _watch_names(files)
            folders = sorted({p.parent for p in names if p.parent.is_dir()})
            if not folders:
                self._stop.wait(1.0)
                continue

            def relevant(change, path: str, names=names) -> bool:
                return Path(path) in names

            for changes in watchfiles.watch(
                *folders,
                watch_filter=relevant,
                debounce=self._debounce_ms,
                step=WATCH_STEP_MS,
                stop_event=self._stop,
                rust_timeout=1000,
                yield_on_timeout=True,
                recursive=False,
                raise_interrupt=False,
            ):
                if changes:
                    self._seen_at = time.time()
                    self._dirty.set()
                if self.watched() != files:  # the scene now names another data file: watch anew
                    break


def _lower_priority(pid: int = 0) -> None:
    """Run process ``pid`` (0: this one) :data:`DRAWING_NICE` below the server."""
    try:
        os.setpriority(os.PRIO_PROCESS, pid, os.getpriority(os.PRIO_PROCESS, 0) + DRAWING_NICE)
    except OSError:  # not allowed here: it runs at the server's priority
        pass


def _lower_drawing_priority() -> None:
    """In a process forked by a preview's builder (a figure's drawer): run below the server."""
    if threading.current_thread().name == BUILDER_THREAD:
        _lower_priority()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_lower_drawing_priority)


# --------------------------------------------------------------------------- HTTP


class _Handler(BaseHTTPRequestHandler):
    server_version = "crankdyn-serve"
    protocol_version = "HTTP/1.1"

    @property
    def preview(self) -> Preview:
        return self.server.preview  # type: ignore[attr-defined]

    def do_GET(self) -> None:
        if not self._host_ok():
            self._send(HTTPStatus.FORBIDDEN, "text/plain; charset=utf-8", b"forbidden host\n")
            return
        path = urlsplit(self.path).path
        snapshot = self.preview.snapshot
        if path in ("/", "/index.html"):
            self._send(HTTPStatus.OK, "text/html; charset=utf-8", snapshot.page, csp=True)
        elif path == "/version":
            after = parse_qs(urlsplit(self.path).query).get("after")
            version = self.preview.version_after(after[0]) if after else snapshot.version
            self._send(HTTPStatus.OK, "text/plain; charset=utf-8", version.encode("ascii"))
        elif path == "/update":
            since = (parse_qs(urlsplit(self.path).query).get("after") or [""])[0]
            changes = self.preview.changes_after(since)
            self._send(
                HTTPStatus.OK,
                "application/json",
                json.dumps(changes, ensure_ascii=False).encode("utf-8"),
            )
        elif path == "/status":
            status = {
                "version": snapshot.version,
                "state": snapshot.state,
                "problems": list(snapshot.problems),
                "render_s": round(snapshot.render_s, 3),
                "building": self.preview.building,
                "pending": list(snapshot.pending),
                "times": self.preview.times,
                "scene": str(self.preview.scene_path),
                "watched": sorted(str(p) for p in self.preview.watched()),
            }
            self._send(
                HTTPStatus.OK,
                "application/json",
                json.dumps(status, ensure_ascii=False).encode("utf-8"),
            )
        elif path == "/report.pdf":
            if snapshot.state != "report":
                self._send(HTTPStatus.CONFLICT, "text/html; charset=utf-8", snapshot.page, csp=True)
                return
            try:
                pdf = self.preview.pdf(snapshot)
            except Exception as exc:  # noqa: BLE001
                _, page, _ = error_page(exc, self.preview.scene_path)
                self._send(
                    HTTPStatus.INTERNAL_SERVER_ERROR,
                    "text/html; charset=utf-8",
                    page.encode("utf-8"),
                    csp=True,
                )
                return
            self._send(
                HTTPStatus.OK,
                "application/pdf",
                pdf,
                extra={
                    "Content-Disposition": content_disposition(
                        self.preview.scene_path.stem + ".pdf"
                    )
                },
            )
        elif path == "/figures-ready":
            version = (parse_qs(urlsplit(self.path).query).get("version") or [""])[0]
            ready = self.preview.figures_ready(version)
            self._send(
                HTTPStatus.OK, "text/plain; charset=utf-8", b"ready\n" if ready else b"gone\n"
            )
        elif path.startswith(f"/{FIGURE_DIR}/"):
            svg = self.preview.figure(path[len(FIGURE_DIR) + 2 :])
            if svg is None:
                self._send(HTTPStatus.NOT_FOUND, "text/plain; charset=utf-8", b"not found\n")
            else:  # a figure's URL names one drawing: the browser may keep it
                self._send(
                    HTTPStatus.OK, "image/svg+xml", svg, cache="public, max-age=31536000, immutable"
                )
        elif path == "/favicon.ico":
            self._send(HTTPStatus.NO_CONTENT, "text/plain", b"")
        else:
            self._send(HTTPStatus.NOT_FOUND, "text/plain; charset=utf-8", b"not found\n")

    def do_HEAD(self) -> None:
        """As GET, headers only (Content-Length of the body GET would send)."""
        self._head_only = True
        try:
            self.do_GET()
        finally:
            self._head_only = False

    def _host_ok(self) -> bool:
        """Refuse other Host names (a DNS-rebinding page must not read the report)."""
        host = (self.headers.get("Host") or "").rsplit(":", 1)[0].strip("[]").lower()
        return host in ("127.0.0.1", "localhost", "")

    def _send(
        self,
        status: HTTPStatus,
        content_type: str,
        body: bytes,
        csp: bool = False,
        extra: dict[str, str] | None = None,
        cache: str = "no-store",
    ) -> None:
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", cache)
        self.send_header("X-Content-Type-Options", "nosniff")
        if csp:
            # Figures come from this server (or are data: images), the style is inline; the only
            # script is ours (nonce).
            self.send_header(
                "Content-Security-Policy",
                f"default-src 'none'; img-src 'self' data:; style-src 'unsafe-inline'; "
                f"script-src 'nonce-{self.preview.nonce}'; connect-src 'self'; base-uri 'none'; "
                "form-action 'none'",
            )
        for key, value in (extra or {}).items():
            self.send_header(key, value)
        self.end_headers()
        if not getattr(self, "_head_only", False):
            self.wfile.write(body)

    def log_message(self, format: str, *args) -> None:
        pass  # the polling would flood the console


def content_disposition(filename: str) -> str:
    """``inline`` with an ASCII ``filename`` and, for any other name, the RFC 5987 ``filename*``
    (a Cyrillic scene name cannot go into a latin-1 HTTP header as it is)."""
    ascii_name = "".join(c if 32 <= ord(c) < 127 and c not in '"\\' else "_" for c in filename)
    header = f'inline; filename="{ascii_name}"'
    if ascii_name != filename:
        header += f"; filename*=UTF-8''{quote(filename, safe='')}"
    return header


class PreviewServer(ThreadingHTTPServer):
    daemon_threads = True
    allow_reuse_address = True

    def handle_error(self, request, client_address) -> None:
        """A browser that closes the connection mid-answer is normal: no traceback for that."""
        if isinstance(sys.exc_info()[1], (ConnectionError, TimeoutError)):
            return
        super().handle_error(request, client_address)

    def __init__(self, preview: Preview, port: int = DEFAULT_PORT):
        self.preview = preview
        super().__init__((HOST, port), _Handler)

    @property
    def url(self) -> str:
        return f"http://{HOST}:{self.server_address[1]}/"


def serve(
    scene_path: Path,
    port: int = DEFAULT_PORT,
    language: str | None = None,
    stages: list[str] | None = None,
    open_browser: bool = False,
    quiet: bool = False,
) -> int:
    """Run the preview until Ctrl-C or SIGTERM; returns the exit code."""
    if not Path(scene_path).is_file():
        raise SceneError(Problem("scene", str(scene_path), "file not found"), str(scene_path))

    def log(message: str) -> None:
        if not quiet:
            print(f"crankdyn: {message}", file=sys.stderr, flush=True)

    preview = Preview(scene_path, language, stages, log=log)
    try:
        server = PreviewServer(preview, port)
    except OSError as exc:
        raise CrankdynError(
            f"cannot listen on {HOST}:{port} ({exc.strerror or exc}); "
            "choose another port with --port, or --port 0 for any free one"
        ) from None
    stop = threading.Event()
    previous = {}
    if threading.current_thread() is threading.main_thread():
        for signum in (signal.SIGINT, signal.SIGTERM):
            previous[signum] = signal.signal(signum, lambda *_: stop.set())
    server_thread = threading.Thread(
        target=server.serve_forever,
        kwargs={"poll_interval": 0.2},
        name="crankdyn-http",
        daemon=True,
    )
    try:
        preview.start()
        server_thread.start()
        print(
            f"crankdyn: live preview of {scene_path} at {server.url} (PDF: {server.url}report.pdf); "
            "Ctrl-C stops",
            flush=True,
        )
        if open_browser:
            webbrowser.open(server.url)
        while not stop.wait(0.25):
            pass
    finally:
        server.shutdown()
        server.server_close()
        preview.stop()
        for signum, handler in previous.items():
            signal.signal(signum, handler)
    log("preview stopped")
    return 0
