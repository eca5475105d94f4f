"""A PDF printer process started before the report is computed: WeasyPrint loads meanwhile.

``crankdyn report`` with a PDF spends its first second importing numpy, scipy and crankdyn and
computing the stages, on one core. WeasyPrint's own import (0.4 s) needs none of that: a process
forked at the very start (:func:`prestart`) imports it on the other core, then waits for the
page. When the report's HTML is ready, :func:`print_pdf` hands it over and serves the figures the
layout asks for (``figures/NAME.svg``, drawn by this process or its drawing children, or the
figure's PDF page to stamp, :mod:`crankdyn.report.figure_forms`); the printer sends the PDF back
and exits. Once the scene is read, :func:`warm_up` tells the printer the report's language, and
it lays out a page of the report's markup in it while it waits.

Whatever goes wrong on the printer's side (it died, WeasyPrint raised, the pipe broke) the PDF is
made in this process instead, as without a printer: the same bytes, or the same exception. A
printer that was not used (the scene was refused, no PDF was asked for after all) is stopped by
:func:`discard`. Used by the command line only: a batch worker or the preview has WeasyPrint
loaded already.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import pickle
import select
import socket
import sys
import threading
from collections.abc import Sequence

from ..parallel.fork import stop_child
from . import figure_forms
from .assets import html_language, report_css
from .weasy import load_weasyprint

#: The printer of this process: (its pid, its socket, the pid that started it) or None.
_printer: tuple[int, socket.socket, int] | None = None


def prestart() -> bool:
    """Fork the printer if the process may (POSIX, no other thread, none started yet, WeasyPrint
    not imported here already). Returns whether a printer runs."""
    global _printer
    if (
        _printer is not None
        or not hasattr(os, "fork")
        or threading.active_count() != 1
        or "weasyprint" in sys.modules
    ):
        return _printer is not None
    ours, theirs = socket.socketpair()
    pid = os.fork()
    if pid == 0:  # the printer
        ours.close()
        code = 1
        try:
            code = _serve(theirs)
        finally:
            os._exit(code)
    theirs.close()
    _printer = (pid, ours, os.getpid())
    return True


class _RemoteFigure:
    """A figure of the report as the printer sees it: its SVG asked for when the layout needs it.

    ``lock`` (shared with a forked child laying out chapters too) keeps each question and its
    answer together on the one channel."""

    def __init__(self, name: str, channel, lock):
        self.name = name
        self._channel = channel
        self._lock = lock

    def _ask(self, question: str, answer: str):
        reader, writer = self._channel
        with self._lock:
            _send(writer, (question, self.name))
            kind, value = pickle.load(reader)
        if kind != answer:
            raise RuntimeError(f"the report did not send figure {self.name!r}")
        return value

    @property
    def svg(self) -> bytes:
        return self._ask("figure", "svg")

    @property
    def pdf(self) -> bytes | None:
        """The figure's PDF page, or None when the report has only its SVG."""
        return self._ask("form", "pdf")


def _send(writer, message) -> None:
    pickle.dump(message, writer, protocol=pickle.HIGHEST_PROTOCOL)
    writer.flush()


def _serve(sock: socket.socket) -> int:
    """The printer's life: load WeasyPrint, wait for the page, print it, send it back."""
    reader, writer = sock.makefile("rb"), sock.makefile("wb")
    try:
        load_weasyprint()  # the point of this process
        from .pdf import html_to_pdf  # lazy: heavy optional import (weasyprint, pikepdf)

        if not select.select([sock], [], [], 0)[0]:
            # nothing told yet: fontconfig and a first page's set-up meanwhile, as a batch warms
            # up (the report's language, when it is already waiting, sets up the same and more)
            html_to_pdf("<p>crankdyn</p>")
        message = pickle.load(reader)
        if message[0] == "language":  # the report's language and frame, known before its page
            _warm_up(*message[1:])
            message = pickle.load(reader)
        html, names = message
    except BaseException:  # noqa: BLE001 - no page will come (EOF) or WeasyPrint cannot load: the report prints
        return 0
    try:
        lock = multiprocessing.Lock()
        remote = [_RemoteFigure(name, (reader, writer), lock) for name in names]
        pdf = html_to_pdf(html, remote, parallel=True)
    except BaseException as exc:  # noqa: BLE001 - said to the report, which prints the PDF itself
        _send(writer, ("failed", f"{exc.__class__.__name__}: {exc}"))
        return 0
    _send(writer, ("pdf", pdf))
    return 0


#: What a report's first page sets up in WeasyPrint once (its fonts' faces, the language's
#: hyphenation patterns, the title page's, contents' and chapters' styles), in the report's markup.
_WARM_UP_BODY = (
    '<section class="title-page"><div class="university">Aa</div><div class="doc-kind">Bb</div>'
    '<div class="doc-title">Cc</div><table class="signatures"><tr><td class="name">Dd</td></tr>'
    '<tr><td class="line"><span class="blank wide"></span> <span class="hint">(e)</span></td>'
    '</tr></table><div class="city-year">2026</div></section>'
    '<section class="abstract"><h2 class="unnumbered">Ff</h2><p class="counts">'
    '<a class="pagecount" href="#end"></a></p></section>'
    '<nav class="contents"><ul><li><a href="#s1">1 Gg</a></li></ul></nav>'
    '<section class="chapter" id="s1"><h1>1 Aa</h1><h2>1.1 Bb</h2>'
    '<p style="hyphens: auto; width: 3em">характеристика acceleration</p>'
    "<p><i>x</i><sub>p</sub> <b>Bb</b> <b><i>c</i></b><sup>2</sup> − 0,5 °</p>"
    '<div class="equation"><span class="formula"><i>R</i> = 1</span><span class="eqno">(1.1)</span></div>'
    '<table class="data"><tr><th>a</th><td>1</td></tr></table></section><p id="end"></p>'
)


def _warm_up(language: str, frame: str) -> None:
    """Lay out and print a page of the report's markup in ``language`` and ``frame`` while the
    report is still computed: the first layout of the report's front matter took three times as
    long as the second, most of it loading the language's hyphenation patterns."""
    from .pdf import html_to_pdf  # lazy: heavy optional import (weasyprint)

    html_to_pdf(
        f'<html lang="{html_language(language)}"><head><style>{report_css(language, frame)}</style></head>'
        f"<body>{_WARM_UP_BODY}</body></html>"
    )


def warm_up(language: str, frame: str) -> None:
    """Tell this process's printer (if it started one) the report's language and frame, so that
    it sets them up before the page comes (:func:`_warm_up`). Nothing happens without a printer."""
    if _printer is None or _printer[2] != os.getpid():
        return
    with contextlib.suppress(OSError):  # a dead printer: print_pdf finds out and prints here
        writer = _printer[1].makefile("wb")
        _send(writer, ("language", language, frame))
        writer.close()


def _take() -> tuple[int, socket.socket] | None:
    """This process's printer, if it started one (a forked child's inherited one is not its own)."""
    global _printer
    printer, _printer = _printer, None
    if printer is None:
        return None
    pid, sock, owner = printer
    if owner != os.getpid():
        _printer = printer  # the owner's, left for it
        return None
    return pid, sock


def print_pdf(html: str, figures: Sequence) -> bytes | None:
    """The PDF of ``html`` made by the prestarted printer (``figures``: the FigureFile objects its
    ``figures/NAME.svg`` refer to, served from here), or None when there is no printer or it did
    not deliver (the caller then makes the PDF itself)."""
    printer = _take()
    if printer is None:
        return None
    pid, sock = printer
    by_name = {f.name: f for f in figures}
    reader, writer = sock.makefile("rb"), sock.makefile("wb")
    try:
        _send(writer, (html, list(by_name)))
        while True:
            kind, value = pickle.load(reader)
            if kind == "figure":
                # the figure's own exceptions are the report's: raised here, as without a printer
                _send(writer, ("svg", by_name[value].svg))
            elif kind == "form":
                _send(writer, ("pdf", figure_forms.figure_page(by_name[value])))
            elif kind == "pdf":
                return value
            else:  # "failed": made here again, which raises the same error where it is one
                return None
    except (EOFError, OSError, pickle.UnpicklingError):
        return None  # the printer died or the pipe broke
    finally:
        _stop(pid, sock)


def discard() -> None:
    """Stop a printer that was started and not used (nothing is left running)."""
    printer = _take()
    if printer is not None:
        _stop(*printer)


def _stop(pid: int, sock: socket.socket) -> None:
    sock.close()
    stop_child(pid)
