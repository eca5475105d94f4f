"""Benchmarks: compute-only, HTML and PDF time for a bundled example, against the goals.

Run: python3 benchmarks/run.py [EXAMPLE] [--repeat N]
Prints a table; writes nothing. Not part of the test suite (timings belong here, not in asserts).
"""

from __future__ import annotations

import argparse
import statistics
import time

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import plan, run_plan
from crankdyn.plugin.registry import default_registry
from crankdyn.report.document import render_html
from crankdyn.report.pdf import html_to_pdf
from crankdyn.scene.model import load_scene

GOALS_S = {"compute": 0.050, "html": 2.0}


def best_of(fn, repeat: int) -> tuple[float, float, object]:
    times, value = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return min(times), statistics.median(times), value


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("example", nargs="?", default="petrol-1cyl")
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args()

    registry = default_registry()
    scene = load_scene(examples_dir() / f"{args.example}.toml")
    the_plan = plan(scene, registry)
    run_plan(scene, the_plan)  # warm caches and imports

    rows = []
    best, median, result = best_of(lambda: run_plan(scene, the_plan), args.repeat)
    rows.append(("compute (all stages)", best, median, GOALS_S["compute"]))
    for name, seconds in result.timing_s.items():
        rows.append((f"  stage {name}", seconds, seconds, None))
    best, median, rendered = best_of(
        lambda: render_html(result, registry), max(args.repeat // 4, 3)
    )
    rows.append(("HTML (with figures)", best, median, GOALS_S["html"]))
    best, median, _ = best_of(lambda: html_to_pdf(rendered.html), 3)
    rows.append(("PDF (WeasyPrint)", best, median, None))

    print(
        f"crankdyn benchmark: {args.example}, angle step {scene.analysis.angle_step_deg:g} deg, "
        f"{len(scene.crank_angles_deg)} grid points"
    )
    print(f"{'what':28s} {'best, ms':>10s} {'median, ms':>11s} {'goal, ms':>9s}  verdict")
    for what, best, median, goal in rows:
        verdict = "" if goal is None else ("ok" if best < goal else "SLOWER THAN GOAL")
        goal_text = "" if goal is None else f"{goal * 1e3:.0f}"
        print(f"{what:28s} {best * 1e3:10.2f} {median * 1e3:11.2f} {goal_text:>9s}  {verdict}")


if __name__ == "__main__":
    main()
