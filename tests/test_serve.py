"""``crankdyn serve``: the live preview re-renders on save, shows errors as a page, reloads the open tab.

The browser test drives Debian's headless Chromium through the DevTools protocol over a
pipe (``--remote-debugging-pipe``: JSON messages on file descriptors 3 and 4, no extra
library): it opens the preview in a tab, marks the tab's JavaScript state, edits the scene
and waits until the *same tab* shows the new value with the mark gone — so the tab reloaded
itself. Everything runs on 127.0.0.1 with bounded waits; processes are ended in ``finally``.
"""

from __future__ import annotations

import base64
import fcntl
import json
import os
import queue
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest
from conftest import ARTIFACTS, modified, write_scene

from crankdyn.cli import examples_dir
from crankdyn.errors import Problem, SceneError
from crankdyn.preview.server import (
    Preview,
    PreviewServer,
    error_page,
    referenced_files,
    with_reload,
)
from crankdyn.report import figure_memo

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
BASH = shutil.which("bash")


def _get(url: str, host: str | None = None, timeout: float = 30.0) -> tuple[int, dict, bytes]:
    request = urllib.request.Request(url, headers={"Host": host} if host else {})
    try:
        with urllib.request.urlopen(request, timeout=timeout) as response:
            return response.status, dict(response.headers), response.read()
    except urllib.error.HTTPError as exc:
        return exc.code, dict(exc.headers), exc.read()


def _status(base: str) -> dict:
    return json.loads(_get(base + "status")[2])


def _wait(condition, timeout: float, what: str, interval: float = 0.1):
    end = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > end:
            raise AssertionError(f"timed out after {timeout:g} s waiting for {what}")
        time.sleep(interval)


def _edit(path: Path, **changes: str) -> None:
    """Rewrite ``key = value`` lines in place, the way an editor saves (new file, atomic rename)."""
    text = path.read_text(encoding="utf-8")
    for key, value in changes.items():
        text, n = re.subn(rf"(?m)^{key} = .*$", f"{key} = {value}", text)
        assert n == 1, key
    tmp = path.with_suffix(".saving")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def _trace_scene(tmp_path: Path) -> Path:
    """The Diesel-RK trace example and its data file, copied to edit."""
    from crankdyn.cli import main

    target = tmp_path / "scene.toml"
    assert main(["example", "diesel-rk-trace", "-o", str(target)]) == 0
    return target


# --------------------------------------------------------------------------- pieces


def test_error_page_escapes_scene_text_and_lists_every_problem(tmp_path):
    exc = SceneError(
        [
            Problem("report.title", "<script>alert(1)</script>", "a title"),
            Problem("engine.bore", "-82 mm", "must be > 0 mm & <= 2000 mm"),
        ]
    )
    state, page, problems = error_page(exc, tmp_path / "a<b>.toml")
    assert state == "scene-error" and len(problems) == 2
    assert "<script>alert" not in page and "&lt;script&gt;alert(1)&lt;/script&gt;" in page
    assert (
        "engine.bore" in page
        and "&gt; 0 mm &amp; &lt;= 2000 mm" in page
        and "a&lt;b&gt;.toml" in page
    )
    state, page, _ = error_page(ZeroDivisionError("<x>"), tmp_path / "s.toml")
    assert (
        state == "error" and "internal error" in page and "&lt;x&gt;" in page and "<x>" not in page
    )


def test_reload_script_goes_before_body_end():
    page = with_reload("<html><body><p>x</p></body></html>", "abc-3", "NONCE")
    assert page.endswith("</script></body></html>")
    assert '<script nonce="NONCE">' in page and '"abc-3"' in page and "/update?after=" in page
    assert "location.reload()" in page and ".outerHTML=" in page


def test_referenced_files_include_the_trace(tmp_path):
    scene = _trace_scene(tmp_path)
    assert referenced_files(scene) == {tmp_path / "diesel6-1600rpm.ind"}
    scene.write_text("not [valid toml", encoding="utf-8")
    assert referenced_files(scene) == set()


# --------------------------------------------------------------------------- the server over HTTP


@pytest.fixture
def preview_server(tmp_path):
    """An in-process preview of the trace example (kinematics and indicator only, to stay quick)."""
    scene = _trace_scene(tmp_path)
    preview = Preview(scene, stages=["kinematics", "indicator"], debounce_ms=100)
    server = PreviewServer(preview, port=0)
    thread = threading.Thread(
        target=server.serve_forever, kwargs={"poll_interval": 0.1}, daemon=True
    )
    preview.start()
    thread.start()
    try:
        yield scene, server.url, preview
    finally:
        server.shutdown()
        server.server_close()
        preview.stop()
        thread.join(10)


# a live preview server through edits: in the slow tier, which CI runs
@pytest.mark.slow
def test_preview_rerenders_on_save_and_shows_errors_as_a_page(preview_server):
    scene, base, _ = preview_server
    first = _wait(
        lambda: (s := _status(base))["state"] == "report" and s, 60, "the first rendering"
    )
    assert set(first["watched"]) == {str(scene), str(scene.parent / "diesel6-1600rpm.ind")}
    status, headers, page = _get(base)
    assert (
        status == 200
        and headers["Content-Type"].startswith("text/html")
        and headers["Cache-Control"] == "no-store"
    )
    nonce = re.search(r"script-src 'nonce-([^']+)'", headers["Content-Security-Policy"])[1]
    assert f'<script nonce="{nonce}">' in page.decode()
    assert _get(base + "version")[2].decode() == first["version"]

    # A save re-renders: a new version with the new value.
    _edit(scene, title='"Preview check <2>"')
    second = _wait(
        lambda: (s := _status(base))["version"] != first["version"] and s, 30, "a new version"
    )
    assert second["state"] == "report"
    assert "Preview check &lt;2&gt;" in _get(base)[2].decode()

    # An invalid save shows the problems instead of the old report; no PDF of a broken scene.
    _edit(scene, bore='"-83 mm"')
    broken = _wait(
        lambda: (s := _status(base))["state"] == "scene-error" and s, 30, "the error page"
    )
    assert any(p.startswith("engine.bore") for p in broken["problems"])
    page = _get(base)[2].decode()
    assert (
        'data-crankdyn="scene-error"' in page
        and "engine.bore" in page
        and "Preview check" not in page
    )
    assert _get(base + "report.pdf")[0] == 409

    # Fixed again; then a save of the pressure trace alone re-renders too.
    _edit(scene, bore='"83 mm"')
    fixed = _wait(lambda: (s := _status(base))["state"] == "report" and s, 30, "the report again")
    trace = scene.parent / "diesel6-1600rpm.ind"
    trace.write_bytes(trace.read_bytes())
    _wait(
        lambda: _status(base)["version"] != fixed["version"],
        30,
        "a re-rendering after the trace was saved",
    )

    status, headers, pdf = _get(base + "report.pdf", timeout=120)
    assert (
        status == 200 and headers["Content-Type"] == "application/pdf" and pdf.startswith(b"%PDF")
    )


def test_figures_are_served_by_url_and_a_kept_figure_keeps_its_url(preview_server):
    scene, base, preview = preview_server
    first = _wait(
        lambda: (s := _status(base))["state"] == "report" and not s["building"] and s,
        60,
        "the first rendering",
    )
    page = _get(base)[2].decode()
    # figures are linked, each drawn once; one not drawn when the page went out waits behind a
    # blank image and its URL, which the page's script swaps in once /figures-ready answers
    urls = re.findall(r'(?:src|data-figure)="(figures/[^"]+)"', page)
    assert urls and len(re.findall(r"<img ", page)) == len(urls)
    assert _get(base + "figures-ready?version=" + first["version"], timeout=60)[2] == b"ready\n"
    status, headers, svg = _get(base + urls[0])
    assert (
        status == 200
        and headers["Content-Type"] == "image/svg+xml"
        and svg.lstrip().startswith(b"<?xml")
    )
    assert "immutable" in headers["Cache-Control"]
    assert _get(base + "figures/nothing/fig_1.svg")[0] == 404
    # The long poll: answered at once for an old version, held back for the current one until a
    # new build is published (held back, it answers with the new version, not the one it was given).
    assert _get(base + "version?after=old")[2].decode() == first["version"]
    answered = []
    poll = threading.Thread(
        target=lambda: answered.append(preview.version_after(first["version"], timeout=120))
    )
    poll.start()

    # A change of the cycle re-renders the indicator section, not the kinematics one: the
    # kinematics figures keep their URLs (the browser shows them from its cache), the rest change.
    _edit(scene, compression_ratio="17.6")
    _wait(
        lambda: (s := _status(base))["version"] != first["version"] and not s["building"],
        60,
        "a new build",
    )
    poll.join(120)
    assert len(answered) == 1 and answered[0] != first["version"]
    new_page = _get(base)[2].decode()
    new_urls = re.findall(r'(?:src|data-figure)="(figures/[^"]+)"', new_page)
    assert all(
        f'src="{u}"' in new_page for u in urls if "/fig_2_" in u
    )  # kept: drawn, shown at once
    kinematics = [u for u in urls if "/fig_2_" in u]
    assert kinematics and all(u in new_urls for u in kinematics)
    assert all(u not in new_urls for u in urls if "/fig_2_" not in u)
    assert all(_get(base + u)[0] == 200 for u in new_urls)


def test_preview_refuses_foreign_host_names_and_unknown_paths(preview_server):
    _, base, _ = preview_server
    assert _get(base + "version", host="attacker.example:80")[0] == 403
    assert _get(base + "version", host=base.split("/")[2])[0] == 200
    assert _get(base + "etc/passwd")[0] == 404


# --------------------------------------------------------------------------- the browser


class DevTools:
    """Chromium's DevTools protocol over ``--remote-debugging-pipe`` (fd 3 in, fd 4 out)."""

    def __init__(self, url: str, profile: Path):
        to_chromium_r, to_chromium_w = os.pipe()
        from_chromium_r, from_chromium_w = os.pipe()
        # Chromium wants the pipe on fds 3 and 4: bash's "exec" puts it there (no preexec_fn, which
        # is unsafe in a process with threads).
        # Their child ends first go above fd 10, so that neither can be 3 or 4 itself.
        child_r = fcntl.fcntl(to_chromium_r, fcntl.F_DUPFD, 10)
        child_w = fcntl.fcntl(from_chromium_w, fcntl.F_DUPFD, 10)
        os.close(to_chromium_r)
        os.close(from_chromium_w)
        self.proc = subprocess.Popen(
            [
                BASH,
                "-c",
                f'exec "$0" "$@" 3<&{child_r} 4>&{child_w} {child_r}<&- {child_w}>&-',
                CHROMIUM,
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-dev-shm-usage",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--hide-scrollbars",
                f"--user-data-dir={profile}",
                "--window-size=1200,1600",
                "--remote-debugging-pipe",
                url,
            ],
            pass_fds=(child_r, child_w),
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        os.close(child_r)
        os.close(child_w)
        self._out, self._in = to_chromium_w, from_chromium_r
        self._messages: queue.Queue = queue.Queue()
        self._next = 0
        threading.Thread(target=self._reader, daemon=True).start()
        # the DevTools protocol's id of the channel to the attached page (its "sessionId")
        self.page_channel = None

    def _reader(self) -> None:
        buffer = b""
        while True:
            try:
                chunk = os.read(self._in, 1 << 16)
            except OSError:
                chunk = b""
            if not chunk:
                self._messages.put(None)
                return
            buffer += chunk
            while b"\0" in buffer:
                message, buffer = buffer.split(b"\0", 1)
                self._messages.put(json.loads(message))

    def call(
        self, method: str, params: dict | None = None, timeout: float = 30.0, page: bool = True
    ) -> dict:
        self._next += 1
        message = {"id": self._next, "method": method, "params": params or {}}
        if page and self.page_channel:
            message["sessionId"] = self.page_channel
        os.write(self._out, json.dumps(message).encode() + b"\0")
        end = time.monotonic() + timeout
        while True:
            reply = self._messages.get(timeout=max(0.01, end - time.monotonic()))
            if reply is None:
                raise AssertionError("chromium closed the DevTools pipe")
            if reply.get("id") == self._next:
                if "error" in reply:
                    raise AssertionError(f"{method}: {reply['error']}")
                return reply["result"]

    def attach(self, url_prefix: str) -> None:
        def page_target():
            infos = self.call("Target.getTargets", page=False)["targetInfos"]
            return next(
                (t for t in infos if t["type"] == "page" and t["url"].startswith(url_prefix)), None
            )

        target = _wait(page_target, 30, "the preview tab", interval=0.2)
        self.page_channel = self.call(
            "Target.attachToTarget", {"targetId": target["targetId"], "flatten": True}, page=False
        )["sessionId"]

    def evaluate(self, expression: str, tolerant: bool = False):
        """``expression``'s value in the tab; with ``tolerant``, None while the tab is between pages."""
        try:
            result = self.call(
                "Runtime.evaluate", {"expression": expression, "returnByValue": True}
            )
        except AssertionError:
            if tolerant:  # "Execution context was destroyed" and the like, mid-reload
                return None
            raise
        return result["result"].get("value")

    def screenshot(self, path: Path) -> None:
        self.call(
            "Emulation.setDeviceMetricsOverride",
            {"width": 1200, "height": 1600, "deviceScaleFactor": 1, "mobile": False},
        )
        data = self.call("Page.captureScreenshot", {"format": "png"})["data"]
        path.write_bytes(base64.b64decode(data))

    def close(self) -> None:
        try:
            self.call("Browser.close", page=False, timeout=5)
        except Exception:  # noqa: BLE001, S110 - it may be gone already; the wait below ends it anyway
            pass
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait(10)
        for fd in (self._out, self._in):
            try:
                os.close(fd)
            except OSError:
                pass


def _start_serve(scene: Path, *extra: str) -> tuple[subprocess.Popen, str]:
    proc = subprocess.Popen(
        [sys.executable, "-m", "crankdyn", "serve", str(scene), "--port", "0", *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONWARNINGS": "ignore"},
    )
    lines: queue.Queue = queue.Queue()
    threading.Thread(target=lambda: [lines.put(line) for line in proc.stdout], daemon=True).start()
    try:
        first = lines.get(timeout=60)
    except queue.Empty:
        proc.kill()
        raise AssertionError("crankdyn serve printed no URL within 60 s") from None
    match = re.search(r"http://127\.0\.0\.1:\d+/", first)
    assert match, first
    return proc, match[0]


@pytest.mark.slow  # drives Chromium: in the slow tier, which CI runs
@pytest.mark.skipif(
    CHROMIUM is None or BASH is None,
    reason="Debian's chromium package is not installed (.ci/setup.sh installs it)",
)
@pytest.mark.long
def test_open_tab_reloads_itself_after_a_save_and_shows_the_error_page(tmp_path):
    scene = write_scene(
        tmp_path / "engine.toml", modified("petrol-1cyl", {"report": {"title": "Preview one"}})
    )
    server, base = _start_serve(scene, "--stages", "kinematics,indicator")
    browser = None
    try:
        _wait(lambda: _status(base)["state"] == "report", 60, "the first rendering")
        browser = DevTools(base, tmp_path / "profile")
        browser.attach(base)
        _wait(
            lambda: (
                browser.evaluate(
                    "document.readyState === 'complete' && document.title", tolerant=True
                )
                == "Preview one"
            ),
            30,
            "the report in the tab",
        )
        # Mark this page's JavaScript state: a reload wipes it, a DOM patch or a cached page would not.
        browser.evaluate("window.__crankdyn_mark = 1")
        assert "\t5600\t" in browser.evaluate(
            "document.body.innerText"
        )  # n in the input table (the name says 5600 too)

        start = time.monotonic()
        _edit(scene, title='"Preview two"', rpm="6000")
        _wait(
            lambda: (
                browser.evaluate(
                    "document.readyState === 'complete' && document.title", tolerant=True
                )
                == "Preview two"
            ),
            30,
            "the open tab to show the edited scene",
        )
        latency = time.monotonic() - start
        assert browser.evaluate("window.__crankdyn_mark === undefined"), (
            "the tab did not reload itself"
        )
        text = browser.evaluate("document.body.innerText")
        assert "\t6000\t" in text and "\t5600\t" not in text
        ARTIFACTS.mkdir(exist_ok=True)
        browser.screenshot(ARTIFACTS / "serve-preview.png")
        assert (ARTIFACTS / "serve-preview.png").read_bytes().startswith(b"\x89PNG")
        print(f"the open tab showed the edit {latency:.1f} s after the save")

        # An invalid edit: the same tab turns into the error page, naming the field.
        browser.evaluate("window.__crankdyn_mark = 2")
        _edit(scene, bore='"-82 mm"')
        _wait(
            lambda: (
                browser.evaluate("document.body && document.body.dataset.crankdyn", tolerant=True)
                == "scene-error"
            ),
            30,
            "the error page in the open tab",
        )
        assert browser.evaluate("window.__crankdyn_mark === undefined")
        assert "engine.bore" in browser.evaluate("document.body.innerText")
        browser.screenshot(ARTIFACTS / "serve-error.png")

        # A fresh page load (what a new tab gets) shows the same error page.
        with tempfile.TemporaryDirectory() as profile:
            dom = subprocess.run(
                [
                    CHROMIUM,
                    "--headless",
                    "--no-sandbox",
                    "--disable-gpu",
                    "--disable-dev-shm-usage",
                    "--disable-quic",
                    "--no-first-run",
                    "--disable-background-networking",
                    "--disable-component-update",
                    "--disable-sync",
                    f"--user-data-dir={profile}",
                    "--dump-dom",
                    base,
                ],
                capture_output=True,
                text=True,
                timeout=60,
                check=False,
            ).stdout
        assert 'data-crankdyn="scene-error"' in dom and "engine.bore" in dom

        # Fixed: the tab comes back to the report by itself.
        _edit(scene, bore='"82 mm"')
        _wait(
            lambda: (
                browser.evaluate(
                    "document.readyState === 'complete' && document.title", tolerant=True
                )
                == "Preview two"
            ),
            30,
            "the report again",
        )
    finally:
        if browser is not None:
            browser.close()
        server.send_signal(signal.SIGTERM)
        try:
            code = server.wait(15)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait(10)
            code = None
    assert code == 0, "crankdyn serve did not stop cleanly on SIGTERM"
    assert "preview stopped" in server.stderr.read()


def test_a_study_that_must_run_again_follows_the_page(tmp_path):
    """The error study (last, providing nothing) runs after the page is out: the first snapshot
    says its section follows, the next one has it; the figures are drawn meanwhile."""
    scene = tmp_path / "kinematics.toml"
    scene.write_text(
        (examples_dir() / "kinematics-only.toml").read_text(encoding="utf-8"), encoding="utf-8"
    )
    preview = Preview(scene)
    published = []
    publish = preview._publish
    preview._publish = lambda *args: published.append(publish(*args)) or published[-1]
    final = preview.build()
    assert [s.state for s in published] == ["report", "report"]
    assert published[0].pending and published[1].pending == () and final is published[1]
    assert b'class="pending"' in published[0].page and b'class="pending"' not in published[1].page
    assert final.figures and all(f.drawn for f in final.figures)
    assert set(published[0].figures) <= set(
        final.figures
    )  # the first page's figures, kept and drawn


def test_the_server_process_draws_each_figure_once_while_idle(tmp_path, monkeypatch):
    # the figures are drawn by forked children, whose matplotlib caches (typeset labels, fonts)
    # die with them: the server draws each figure once itself while nothing is to be built, so
    # that the children of the next saves start warm; a save meanwhile stops the warming
    # (a fresh server: no figure of the geometry alone kept by an earlier report of this process)
    monkeypatch.setattr(figure_memo, "_svgs", {})
    preview = Preview(_trace_scene(tmp_path), stages=["kinematics", "indicator"])
    snapshot = preview.build()
    assert (
        snapshot.state == "report" and snapshot.figures and all(f.drawn for f in snapshot.figures)
    )
    preview._dirty.set()  # a save came: nothing drawn
    preview._warm(snapshot)
    assert preview._warmed == set()
    preview._dirty.clear()
    shown = [f.svg for f in snapshot.figures]
    preview._warm(snapshot)
    assert preview._warmed == {f.name for f in snapshot.figures}
    assert all(f._typeset_in == os.getpid() for f in snapshot.figures)  # drawn in this process
    assert [f.svg for f in snapshot.figures] == shown  # the page's SVGs are the children's, kept
    drawn_again = []
    for figure in snapshot.figures:
        figure.draw = lambda figure=figure: drawn_again.append(figure.name)
    preview._warm(snapshot)  # once: the next save's figures of the same names are not drawn again
    assert drawn_again == []


def test_a_changed_data_file_is_computed_again(tmp_path):
    # the trace's file name stays the same when its data changes: the stage cache keys the stage
    # that opened it by the file's contents too, and re-runs that stage only
    scene = _trace_scene(tmp_path)
    preview = Preview(scene, stages=["kinematics", "indicator"])
    first = preview.build()
    assert first.state == "report"
    peak = preview.stage_cache._entries["indicator"].output.results
    trace = tmp_path / "diesel6-1600rpm.ind"
    lines = trace.read_text(encoding="utf-8").splitlines(keepends=True)
    # every pressure (second column) 10 % higher
    scaled = [
        line
        if not line.strip() or not line.split()[0].replace(".", "", 1).isdigit()
        else line.replace(line.split()[1], f"{float(line.split()[1]) * 1.1:.2f}", 1)
        for line in lines
    ]
    trace.write_text("".join(scaled), encoding="utf-8")
    preview.build()
    again = preview.stage_cache._entries["indicator"].output.results
    assert again != peak and preview.stage_cache.runs["indicator"] == 2
    assert preview.stage_cache.runs["kinematics"] == 1  # it read no data file: kept
    runs = dict(preview.stage_cache.runs)
    preview.build()  # nothing changed since: kept
    assert dict(preview.stage_cache.runs) == runs
