"""Frame rate of the report's mechanism animation in headless Chromium (goal: >= 30 frames/s).

Run from the repository root (needs Debian's ``chromium``):

    python3 benchmarks/animation.py                    # the V8 example
    python3 benchmarks/animation.py --example radial9-aircraft --seconds 5

Renders the example's drawing section to a temporary HTML file, opens it in headless Chromium
(driven over the DevTools pipe as tests/test_serve.py does), presses play and counts the frames
the page draws. Prints the rate; writes nothing. Not part of the test suite (the test only checks
that the animation runs).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import run_scene
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.scene.model import load_scene

GOAL_FPS = 30.0


def drawing_html(example: str) -> str:
    registry = default_registry()
    scene = load_scene(examples_dir() / f"{example}.toml")
    result = run_scene(scene, registry)
    only = replace(
        result.plan, order=[s for s in result.plan.order if s.name.startswith("drawing")]
    )
    return render_html(replace(result, plan=only), registry).html


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--example", default="v8-petrol")
    parser.add_argument("--seconds", type=float, default=3.0)
    args = parser.parse_args()
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    from test_serve import DevTools  # the tests' DevTools client

    with tempfile.TemporaryDirectory() as tmp:
        page = Path(tmp) / "page.html"
        page.write_text(drawing_html(args.example), encoding="utf-8")
        browser = DevTools(page.as_uri(), Path(tmp) / "profile")
        try:
            browser.attach("file://")
            root = "document.querySelector('.mech-animation')"
            deadline = time.monotonic() + 60
            while not browser.evaluate(f"!!{root} && !!{root}.dataset.drawn", tolerant=True):
                if time.monotonic() > deadline:
                    raise SystemExit("the animation did not start")
                time.sleep(0.1)
            frames = browser.evaluate(f"{root}.querySelectorAll('svg.mech-anim g.moving *').length")
            browser.evaluate(f"{root}.querySelector('.mech-play').click()")
            start = browser.evaluate(f"[+{root}.dataset.drawn, performance.now()]")
            time.sleep(args.seconds)
            end = browser.evaluate(f"[+{root}.dataset.drawn, performance.now()]")
        finally:
            browser.close()
    fps = (end[0] - start[0]) / ((end[1] - start[1]) / 1000.0)
    verdict = "meets" if fps >= GOAL_FPS else "misses"
    print(
        f"{args.example}: {fps:.1f} frames per second ({frames} moving SVG elements); "
        f"{verdict} the goal of {GOAL_FPS:g}"
    )


if __name__ == "__main__":
    main()
