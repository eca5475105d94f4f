"""Live preview, measured with the browser: save -> the open tab shows the new page, and -> all its figures.

Run from the repository root (needs Debian's chromium, as the tests do; about a minute):

    python3 benchmarks/preview.py              # 10 edits of masses.rod in the single-cylinder example
    python3 benchmarks/preview.py --edits 20 --scene examples/inline4-petrol.toml

``crankdyn serve`` runs on a copy of the scene; a headless Chromium (DevTools over a pipe, as in
tests/test_serve.py) keeps the preview open. Each edit changes the rod's mass by 1 % and saves;
the clock runs from just before the write until (a) the tab shows the page of the new build
(the changed sections swapped in, or the page loaded anew; the version the tab shows is in its
root element's data-version; a study that has to run again, the error against run time, says
there that it follows), (b) the tab shows the whole page, that study too, and (c) every figure
of it has loaded. Medians and the worst of the edits are printed, with where (a)'s time goes (the
server's moments from /status: when its watcher saw the save, when the page went out), and (a)'s
median as a ratio to its goal. Not part of the test suite.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import statistics
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from test_serve import CHROMIUM, DevTools, _start_serve, _wait  # noqa: E402 - the tests' own browser driver

# the text is on screen once the tab shows a build after the save (the version its script keeps in
# the root element's data-version, set when a page is parsed or parts of it are swapped in): the
# first one (its study to follow) or, when the whole page was ready before the tab asked, the second
PAGE_IS = "{markers}.indexOf(document.documentElement.dataset.version) >= 0"
# the whole page: no section waits for its study (p.pending), and not the page before the save
COMPLETE = (
    "!!document.documentElement.dataset.version && "
    "document.documentElement.dataset.version !== {old} && !document.querySelector('p.pending')"
)
FIGURES_LOADED = (
    "document.readyState === 'complete' && !document.querySelector('p.pending') && "
    "Array.from(document.images).every(i => i.complete && i.naturalWidth > 0 && "
    "!(i.dataset.figure && i.src.startsWith('data:')))"
)


def _status(base: str) -> dict:
    with urllib.request.urlopen(base + "status", timeout=30) as answer:
        return json.loads(answer.read())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default=str(ROOT / "examples" / "petrol-1cyl.toml"))
    parser.add_argument("--edits", type=int, default=10)
    parser.add_argument("--each", action="store_true", help="print every edit's times too")
    args = parser.parse_args()
    if CHROMIUM is None:
        raise SystemExit("Debian's chromium is not installed (.ci/setup.sh installs it)")
    with tempfile.TemporaryDirectory(prefix="crankdyn-preview-") as tmp:
        tmp = Path(tmp)
        source = Path(args.scene)
        scene = tmp / source.name
        shutil.copy(source, scene)
        for data in source.parent.glob("*.ind"):
            shutil.copy(data, tmp)
        server, base = _start_serve(scene)
        browser = None
        page_s, complete_s, figures_s, server_s = [], [], [], []
        watch_s, render_s, tab_s = [], [], []  # where the first of these goes
        try:
            _wait(lambda: _status(base)["state"] == "report", 120, "the first rendering")
            browser = DevTools(base, tmp / "profile")
            browser.attach(base)
            _wait(
                lambda: browser.evaluate(FIGURES_LOADED, tolerant=True),
                60,
                "the first page and its figures",
            )
            text = scene.read_text(encoding="utf-8")
            for _ in range(args.edits):
                version = _status(base)["version"]
                boot, count = version.rsplit("-", 1)
                expected = [f"{boot}-{int(count) + k}" for k in (1, 2)]  # this save's two builds
                old = json.dumps(version)
                new = re.sub(
                    r'(?m)^(rod\s*=\s*")([0-9.]+)',
                    lambda m: f"{m[1]}{float(m[2]) * 1.01:.5f}",
                    text,
                    count=1,
                )
                assert new != text, "the scene has no masses.rod to edit"
                text = new
                start, saved = time.monotonic(), time.time()
                scene.write_text(text, encoding="utf-8")
                markers = json.dumps(expected)
                _wait(
                    lambda: browser.evaluate(PAGE_IS.format(markers=markers), tolerant=True),  # noqa: B023 - called within this iteration
                    60,
                    "the tab to show the new build",
                    interval=0.01,
                )
                page_s.append(time.monotonic() - start)
                shown = time.time()
                _wait(
                    lambda: browser.evaluate(COMPLETE.format(old=old), tolerant=True),  # noqa: B023 - called within this iteration
                    60,
                    "the whole page",
                    interval=0.01,
                )
                complete_s.append(time.monotonic() - start)
                _wait(
                    lambda: browser.evaluate(FIGURES_LOADED, tolerant=True),
                    60,
                    "the figures",
                    interval=0.01,
                )
                figures_s.append(time.monotonic() - start)
                _wait(lambda: not _status(base)["building"], 60, "the build to end", interval=0.05)
                status = _status(base)
                server_s.append(status["render_s"])
                times = status["times"]
                watch_s.append(times["seen"] - saved)
                render_s.append(times["page"] - times["started"])
                tab_s.append(shown - times["page"])
                if args.each:
                    print(
                        f"edit {len(page_s):3d}: page {page_s[-1]:.2f}  whole {complete_s[-1]:.2f}  "
                        f"figures {figures_s[-1]:.2f}  server {server_s[-1]:.2f}",
                        flush=True,
                    )
                time.sleep(0.3)
        finally:
            if browser is not None:
                browser.close()
            server.terminate()
            server.wait(10)
    print(f"live preview of {source.name}, {args.edits} edits of masses.rod (s)")
    print(f"{'':38s} {'median':>8s} {'worst':>8s}")
    for what, values in (
        ("save -> the tab shows the new page", page_s),
        ("save -> ... with the error study too", complete_s),
        ("save -> all its figures loaded", figures_s),
        ("server: build until the whole page out", server_s),
        ("  of the first: save -> the watcher", watch_s),
        ("  ... -> the page out (the build)", render_s),
        ("  ... -> the tab shows it (update)", tab_s),
    ):
        print(f"{what:38s} {statistics.median(values):8.2f} {max(values):8.2f}")
    goal_s = 0.3
    measured = statistics.median(page_s)
    ratio = measured / goal_s
    print(
        f"{'figure':62s} {'measured':>10s} {'goal':>10s} {'ratio':>7s}\n"
        f"{'preview: save -> the tab shows the new page, median (s)':62s} {measured:10.3f} "
        f"{goal_s:10.3f} {ratio:7.2f}  {'ok' if ratio <= 1 else 'NOT MET'}"
    )
    print(
        f"({os.cpu_count()} cores; load {', '.join(f'{x:.2f}' for x in os.getloadavg())} "
        "over 1, 5, 15 min at the end)"
    )


if __name__ == "__main__":
    main()
