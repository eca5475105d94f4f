"""A report's PDF laid out in two processes at once, its parts joined into one document.

WeasyPrint lays out a document on one core, page after page. A report's chapters each start on a
new page, so the chapters are split in two parts laid out at the same time: the first part
(with the front matter: title page, assignment, abstract, contents) in this process, the second
in a forked child. The pages come out the same as from one layout because nothing on a page
depends on another part but numbers:

- a page number in a margin box: each chapters part starts with a throw-away page (so that its
  first chapter page is not an ``@page :first``) and its margin boxes are made with the page
  counter moved on by the pages before it (:func:`_numbered_from`), once those are laid out;
- a contents line or the abstract's page count, ``target-counter(attr(href), page)`` to a
  chapter or the document's end: the front matter is laid out last, with those numbers written
  in (``data-crankdyn-page``), after a first layout that gives its own page count.

The parts' PDFs are joined with pikepdf: pages, the outline (bookmarks), the named destinations
and the contents' links. A document this cannot split (a framed note, whose blocks count all
sheets; links between chapters; fewer than two chapters), no pikepdf, one core or none to spare
(:func:`machine_busy`), or anything that goes wrong on the way: the PDF is made in one layout
instead, the same pages.
"""

from __future__ import annotations

import contextlib
import importlib
import io
import logging
import os
import pickle
import re
import socket
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..parallel.fork import stop_child
from ..parallel.messages import receive_message, send_message

#: The attribute that carries a resolved page number into the front matter's HTML.
PAGE_ATTRIBUTE = "data-crankdyn-page"
_TARGET_PAGE = "target-counter(attr(href), page)"
_CHAPTER = re.compile(r'<section class="chapter[ "]')
_BODY = re.compile(r"<body\b[^>]*>")
_INTERNAL_LINK = re.compile(r'<a\b[^>]*?\bhref="#([^"]+)"')
#: What a part would count in itself alone: the total of pages, other references' numbers.
_ACROSS_PARTS = ("counter(pages)", "target-counter", "target-text")
_MARKUP = re.compile(r"<script\b.*?</script>|<svg\b.*?</svg>|<[^>]+>", re.S)
#: A throw-away first page: a chapters part's first chapter page is no ``@page :first``.
_LEAD_PAGE = '<div class="crankdyn-part-lead"></div>'


@dataclass(frozen=True)
class Split:
    """A report's HTML cut at chapter starts: ``head`` up to the body's content, ``front`` the
    front matter, ``first`` and ``second`` the chapters of each part, ``tail`` the closing tags."""

    head: str
    front: str
    first: str
    second: str
    tail: str

    def front_html(self, pages: dict[str, int] | None) -> str:
        """The front matter alone, each page number it refers to written in (``pages``: anchor ->
        page number; None: a placeholder of two digits, for its own page count)."""

        def numbered(match: re.Match) -> str:
            number = "88" if pages is None else str(pages[match.group(1)])
            return f'{match.group(0)} {PAGE_ATTRIBUTE}="{number}"'

        head = self.head.replace(_TARGET_PAGE, f"attr({PAGE_ATTRIBUTE})")
        return head + _INTERNAL_LINK.sub(numbered, self.front) + self.tail

    def part_html(self, chapters: str) -> str:
        return self.head + _LEAD_PAGE + chapters + self.tail


def split(html: str) -> Split | None:
    """``html`` cut into the front matter and two parts of chapters of about equal work, or None
    when its pages cannot be laid out apart (see the module's docstring)."""
    body = _BODY.search(html)
    end = html.rfind("</body>")
    starts = [m.start() for m in _CHAPTER.finditer(html)]
    if body is None or end < 0 or len(starts) < 2 or 'class="eskd' in html:
        return None
    head, front = html[: body.end()], html[body.end() : starts[0]]
    if any(
        numbers in head.replace(_TARGET_PAGE, "") or numbers in html[body.end() :]
        for numbers in _ACROSS_PARTS
    ):
        return None
    chapters = [html[a:b] for a, b in zip(starts, [*starts[1:], end], strict=True)]
    anchors = set(re.findall(r'\bid="([^"]+)"', "".join(chapters)))
    if any(_INTERNAL_LINK.search(chapter) for chapter in chapters):
        return None  # a link from a chapter: the parts would have to resolve each other's
    if not set(_INTERNAL_LINK.findall(front)) <= anchors:
        return None
    weights = [_work(chapter) for chapter in chapters]
    front_work = 2 * _work(front)  # laid out twice, with the first part
    cut = min(
        range(1, len(chapters)),
        key=lambda k: max(front_work + sum(weights[:k]), sum(weights[k:])),
    )
    return Split(head, front, "".join(chapters[:cut]), "".join(chapters[cut:]), html[end:])


def _work(html: str) -> float:
    """About how long WeasyPrint takes over ``html``, in characters of plain text: a table cell,
    an equation or a where-list and a part of its own each cost as much as that many characters
    (fitted to the layout and printing times of the bundled examples' chapters, alone). A figure
    costs next to nothing: its PDF page is stamped after the layout (:mod:`.figure_forms`), as
    whenever the parts can be joined (pikepdf)."""
    return (
        len(_MARKUP.sub("", html))
        + 22 * len(re.findall(r"<t[dh]\b", html))
        + 45 * (html.count('class="equation') + html.count('class="where'))
        + 900
    )


def can_split_processes() -> bool:
    """Two cores, one of them to spare (:func:`machine_busy`), fork, no other thread in this
    process, pikepdf to join the parts."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cores = os.cpu_count() or 1
    if cores < 2 or not hasattr(os, "fork") or threading.active_count() != 1:
        return False
    if machine_busy(cores):
        return False
    try:
        importlib.import_module("pikepdf")
    except ImportError:
        return False
    return True


def machine_busy(cores: int) -> bool:
    """Whether the machine's load average over the last minute reaches ``cores`` + 1. A report
    with a PDF keeps about two processes busy itself (the layout, the figures); beyond that the
    other core is taken by other work, and two parts would only share the one core with more
    work in all than one layout (the front matter twice, a second document)."""
    try:
        load = os.getloadavg()[0]
    except OSError:  # not to be had: taken as free
        return False
    return load >= cores + 1


@contextlib.contextmanager
def _numbered_from(first_number: Callable[[], int]):
    """While a chapters part is laid out: its margin boxes count pages from ``first_number()``
    (asked for once, when the part's pages are laid out and their margin boxes are to be made)
    for its first chapter page, the page after the throw-away first one."""
    layout: Any = importlib.import_module("weasyprint.layout")  # private, patched while laid out
    original = layout.make_margin_boxes
    start: list[int] = []

    def make_margin_boxes(context, page, state):
        if not start:
            start.append(first_number())
        counters = dict(state[1])
        counters["page"] = [start[0] + context.current_page - 2]
        return original(context, page, (state[0], counters, *state[2:]))

    layout.make_margin_boxes = make_margin_boxes
    try:
        yield
    finally:
        layout.make_margin_boxes = original


def _anchors(document, first_number: int) -> dict[str, tuple[int, float, float]]:
    """Anchor -> (page number, x, y in CSS px) of a chapters part (its first page thrown away)."""
    found: dict[str, tuple[int, float, float]] = {}
    for index, page in enumerate(document.pages[1:]):
        for name, (x, y, *_) in page.anchors.items():
            found.setdefault(name, (first_number + index, x, y))
    return found


def _send(sock: socket.socket, message) -> None:
    send_message(sock, pickle.dumps(message, protocol=pickle.HIGHEST_PROTOCOL))


def _receive(sock: socket.socket):
    return pickle.loads(receive_message(sock))


def _second_part(sock: socket.socket, render: Callable[[str], Any], html: str) -> None:
    """The child's work: lay out the second part, wait for its first page number, send its
    anchors and bookmarks, draw it, send the PDF."""
    number: list[int] = []

    def first_number() -> int:
        number.append(_receive(sock))
        return number[0]

    with _numbered_from(first_number):
        document = render(html)
    marks = [_Bookmarks(page.bookmarks, page.height) for page in document.pages[1:]]
    _send(sock, ("anchors", _anchors(document, number[0]), marks))
    _send(sock, ("pdf", document.write_pdf()))


@dataclass(frozen=True)
class _Bookmarks:
    """A page's bookmarks as WeasyPrint's outline is made from them (level, label, point,
    state), and the page's height (CSS px)."""

    bookmarks: list
    height: float


class PartAbandoned(RuntimeError):
    """The child laying out a part did not end when asked and was killed: a question it had put
    to the report (a figure) may be left unanswered, so this process must not ask again."""


#: How long a child that is no longer needed may take to end (it does at its next exchange).
CHILD_GRACE_S = 120.0


def parallel_pdf(parts: Split, render: Callable[[str], Any]) -> bytes:
    """The PDF of the split report; ``render(html)`` lays out one HTML document (a WeasyPrint
    Document). Raises on any failure: the caller then makes the PDF in one layout, unless it is
    :class:`PartAbandoned`."""
    ours, theirs = socket.socketpair()
    try:
        pid = os.fork()
    except OSError:  # no process to be had (EAGAIN, ENOMEM): one layout instead
        ours.close()
        theirs.close()
        raise
    if pid == 0:  # the child: the second part
        ours.close()
        code = 1
        try:
            _second_part(theirs, render, parts.part_html(parts.second))
            code = 0
        except BaseException:  # noqa: BLE001 - the parent sees the socket close and lays it out itself
            pass
        finally:
            os._exit(code)
    theirs.close()
    try:
        front_pages = len(render(parts.front_html(None)).pages)
        with _numbered_from(lambda: front_pages + 1):
            first = render(parts.part_html(parts.first))
        second_number = front_pages + len(first.pages)  # less its throw-away page, plus one
        _send(ours, second_number)
        first_pdf = first.write_pdf()
        kind, second_anchors, second_marks = _receive(ours)
        anchors = {**_anchors(first, front_pages + 1), **second_anchors}
        front = render(parts.front_html({name: at[0] for name, at in anchors.items()}))
        if len(front.pages) != front_pages:
            raise RuntimeError("the front matter's page count changed with its page numbers")
        front_pdf = _quietly(front.write_pdf)  # its links to the chapters are added in the join
        kind, second_pdf = _receive(ours)
        if kind != "pdf":
            raise RuntimeError("the second part sent no PDF")
    finally:
        _end_child(pid, ours)
    marks = [*front.pages, *first.pages[1:], *second_marks]
    return join(front, front_pdf, [first_pdf, second_pdf], anchors, _outline(marks))


def _end_child(pid: int, sock: socket.socket) -> None:
    """Wait for the child to end: done, or at its next exchange with this process, which says
    nothing more (a figure it is asking for meanwhile still gets its answer, so that the channel
    to the report stays in step). Killed after :data:`CHILD_GRACE_S`: :class:`PartAbandoned`."""
    ended = False
    try:
        sock.shutdown(socket.SHUT_WR)
        sock.settimeout(CHILD_GRACE_S)
        while sock.recv(1 << 16):  # what it still sends, until its end of the socket closes
            pass
        ended = True
    except OSError:  # the timeout too
        pass
    finally:
        sock.close()
    stop_child(pid)  # reaped; killed first if it did not end
    if not ended:
        raise PartAbandoned("the process laying out the report's second part did not end")


def _outline(pages) -> list:
    """WeasyPrint's outline of the joined document, from each page's bookmarks."""
    from weasyprint.document import Document  # lazy: heavy optional import (weasyprint)

    whole = type("Pages", (), {"pages": pages})()
    return Document.make_bookmark_tree(whole, scale=0.75, transform_pages=True)


def _quietly(write: Callable[[], bytes]) -> bytes:
    """``write()`` with WeasyPrint's error for a link to an anchor not in the document unsaid."""
    logger = logging.getLogger("weasyprint")
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        return write()
    finally:
        logger.setLevel(level)


def _front_links(front) -> list[tuple[int, str, tuple[float, float, float, float], float]]:
    """The front matter's links to anchors in the chapters: (page, anchor, rectangle in CSS px,
    the page's height in CSS px)."""
    own = {name for page in front.pages for name in page.anchors}
    return [
        (index, target, rectangle, page.height)
        for index, page in enumerate(front.pages)
        for kind, target, rectangle, _box in page.links
        if kind == "internal" and target not in own
    ]


def join(front, front_pdf: bytes, part_pdfs: list[bytes], anchors, outline_tree) -> bytes:
    """One PDF: the front matter's pages, then each chapters part's less its throw-away first
    page, with the parts' named destinations, the front matter's links to ``anchors``
    (name -> (page number, x, y)) and the outline ``outline_tree`` (WeasyPrint's bookmark tree:
    (label, (page index, x, y), children, state))."""
    import pikepdf  # lazy: heavy optional import (pikepdf: only a PDF laid out in parts)

    out = pikepdf.open(io.BytesIO(front_pdf))
    sources = [pikepdf.open(io.BytesIO(pdf)) for pdf in part_pdfs]
    page_maps = []  # per part: its page object's id -> the joined document's page
    for source in sources:
        mapping = {}
        for page in source.pages[1:]:
            out.pages.append(page)
            mapping[page.obj.objgen] = out.pages[len(out.pages) - 1].obj
        page_maps.append(mapping)
    names = pikepdf.NameTree.new(out) if "/Names" not in out.Root else None
    if names is None:
        root_names = out.Root.Names
        if "/Dests" not in root_names:
            root_names.Dests = pikepdf.NameTree.new(out).obj
        names = pikepdf.NameTree(root_names.Dests)
    else:
        out.Root.Names = pikepdf.Dictionary(Dests=names.obj)
    for source, mapping in zip(sources, page_maps, strict=True):
        if "/Names" in source.Root and "/Dests" in source.Root.Names:
            for name, destination in pikepdf.NameTree(source.Root.Names.Dests).items():
                moved = _moved_destination(destination, mapping)
                if moved is not None:
                    names[name] = moved
    with out.open_outline() as outline:
        outline.root.clear()
        outline.root.extend(_outline_items(out, outline_tree))
    for index, target, (x1, y1, x2, y2), height in _front_links(front):
        if target not in anchors:
            continue
        page = out.pages[index]
        rect = [x1 * 0.75, (height - y1) * 0.75, x2 * 0.75, (height - y2) * 0.75]
        link = out.make_indirect(
            pikepdf.Dictionary(
                Type=pikepdf.Name.Annot,
                Subtype=pikepdf.Name.Link,
                Rect=pikepdf.Array(rect),
                BS=pikepdf.Dictionary(W=0),
                Dest=pikepdf.String(target),
            )
        )
        if "/Annots" not in page.obj:
            page.obj.Annots = pikepdf.Array()
        page.obj.Annots.append(link)
    buffer = io.BytesIO()
    out.save(buffer, object_stream_mode=pikepdf.ObjectStreamMode.generate)
    return buffer.getvalue()


def _moved_destination(destination, mapping):
    import pikepdf  # lazy: heavy optional import (pikepdf: only a PDF laid out in parts)

    if isinstance(destination, pikepdf.Dictionary) and "/D" in destination:
        destination = destination.D
    if not isinstance(destination, pikepdf.Array) or len(destination) == 0:
        return None
    page = mapping.get(destination[0].objgen)
    if page is None:
        return None
    return pikepdf.Array([page, *list(destination)[1:]])


def _outline_items(out, tree) -> list:
    import pikepdf  # lazy: heavy optional import (pikepdf: only a PDF laid out in parts)

    items = []
    for label, (page, x, y), children, state in tree:
        destination = pikepdf.Array([out.pages[page].obj, pikepdf.Name.XYZ, x, y, 0])
        item = pikepdf.OutlineItem(label, destination)
        item.children.extend(_outline_items(out, children))
        item.is_closed = state == "closed"
        items.append(item)
    return items
