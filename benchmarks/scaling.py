"""How the stages scale with the angle step and the number of cylinders: time and peak memory per stage.

Run from the repository root:

    python3 benchmarks/scaling.py                       # steps 1 ... 0.01 deg (in-line 4), 1 ... 24 cylinders
    python3 benchmarks/scaling.py --steps 0.25,0.1 --cylinders ""   # a subset
    python3 benchmarks/scaling.py --no-memory           # time only (one run per point)

Every point runs in its own process, so the process's peak resident memory (``ru_maxrss``) is
that point's alone. Each stage is timed once without tracing (``time.perf_counter``), then run
again under ``tracemalloc`` for its own peak of allocated memory (numpy reports its arrays to
tracemalloc), so the time column is free of the tracing overhead. Writes nothing; not part of
the test suite (heavy points belong here, never in tests).

Goal: the in-line 4 example at a 0.01 deg step within 600 MB of peak memory,
and halving the step at most doubling every stage's time (the ``x prev`` column, within noise).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

STEPS_DEG = [1.0, 0.5, 0.25, 0.1, 0.05, 0.02, 0.01]
CYLINDERS = [1, 2, 4, 8, 12, 16, 24]
PEAK_GOAL_MB = 600.0


def _point(example: str, step: float, cylinders: int | None, memory: bool) -> dict:
    """Run one scene in this process; return per-stage seconds and traced peaks (MB) and ru_maxrss."""
    import resource
    import time
    import tracemalloc

    from crankdyn.cli import examples_dir
    from crankdyn.engine.orchestrator import plan, stage_inputs
    from crankdyn.plugin.registry import default_registry
    from crankdyn.scene.model import load_scene

    overrides = {
        "analysis": {
            "angle_step_deg": step,
            "table_step_deg": 30 if 30 / step == round(30 / step) else step,
        }
    }
    if cylinders is not None:
        # firing intervals equal, in firing order 1..n; a long shaft needs no other change
        overrides["engine"] = {
            "cylinders": cylinders,
            "firing_order": list(range(1, cylinders + 1)),
        }
    scene = load_scene(examples_dir() / f"{example}.toml", overrides)
    the_plan = plan(scene, default_registry())
    rows = {}
    data: dict = {}
    for stage in the_plan.order:
        # the orchestrator's own inputs: required and used data, and the services a stage names
        inputs = stage_inputs(stage, data, the_plan.registry)
        start = time.perf_counter()
        output = stage.run(scene, inputs)
        seconds = time.perf_counter() - start
        peak = None
        if memory:
            tracemalloc.start()
            tracemalloc.reset_peak()
            stage.run(scene, inputs)
            peak = tracemalloc.get_traced_memory()[1] / 2**20
            tracemalloc.stop()
        data.update(output.data)
        rows[stage.name] = {"s": seconds, "peak_MB": peak}
    maxrss_MB = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return {"points": len(scene.crank_angles_deg), "stages": rows, "maxrss_MB": maxrss_MB}


def run_point(example: str, step: float, cylinders: int | None, memory: bool) -> dict:
    """One point in a fresh process (its own peak resident memory)."""
    code = (
        f"import json, sys; sys.path.insert(0, {str(__file__.rsplit('/', 1)[0])!r}); import scaling; "
        f"print(json.dumps(scaling._point({example!r}, {step!r}, {cylinders!r}, {memory!r})))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    if done.returncode != 0:
        return {"error": (done.stderr.strip().splitlines() or ["failed"])[-1]}
    return json.loads(done.stdout.strip().splitlines()[-1])


def best_points(example: str, steps: list[float], repeat: int) -> list[dict]:
    """For each of ``steps``, ``repeat`` points in fresh processes, each stage's least time of them
    (a stage of a tenth of a second timed once varies by 5-10 % on a busy machine; the halving
    ratio compares two such) and the largest peak memory; the processes run in turns (one of each
    step, ``repeat`` times), so that a ratio of two steps' times compares the same stretch of
    time."""
    runs: list[list[dict]] = [[] for _ in steps]
    for _ in range(repeat):
        for k, step in enumerate(steps):
            runs[k].append(run_point(example, step, None, False))
    return [_best(points) for points in runs]


def _best(points: list[dict]) -> dict:
    points = [p for p in points if "error" not in p] or points[:1]
    if "error" in points[0]:
        return points[0]
    best = {
        name: {"s": min(p["stages"][name]["s"] for p in points), "peak_MB": None}
        for name in points[0]["stages"]
    }
    return {
        "points": points[0]["points"],
        "stages": best,
        "maxrss_MB": max(p["maxrss_MB"] for p in points),
    }


def report(title: str, label: str, points: list[tuple[str, dict]]) -> None:
    print(f"\n{title}")
    stages = []
    for _, p in points:
        for name in p.get("stages", {}):
            if name not in stages:
                stages.append(name)
    print(
        f"{label:>8s} {'angles':>7s} {'stage':22s} {'time, s':>9s} {'x prev':>7s} {'peak, MB':>9s}"
    )
    previous: dict = {}
    for key, p in points:
        if "error" in p:
            print(f"{key:>8s} {'':7s} FAILED: {p['error']}")
            continue
        for name in stages:
            row = p["stages"].get(name)
            if row is None:
                continue
            ratio = f"{row['s'] / previous[name]:.2f}" if previous.get(name) else ""
            peak = "" if row["peak_MB"] is None else f"{row['peak_MB']:.1f}"
            print(f"{key:>8s} {p['points']:7d} {name:22s} {row['s']:9.3f} {ratio:>7s} {peak:>9s}")
            previous[name] = row["s"]
        total = sum(r["s"] for r in p["stages"].values())
        verdict = "ok" if p["maxrss_MB"] <= PEAK_GOAL_MB else f"ABOVE {PEAK_GOAL_MB:.0f} MB"
        print(
            f"{key:>8s} {p['points']:7d} {'= all stages':22s} {total:9.3f} {'':>7s} "
            f"{p['maxrss_MB']:9.1f}  process peak RSS ({verdict})"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--example", default="inline4-petrol")
    parser.add_argument("--steps", default=",".join(f"{s:g}" for s in STEPS_DEG))
    parser.add_argument("--cylinders", default=",".join(str(c) for c in CYLINDERS))
    parser.add_argument(
        "--cylinder-step", type=float, default=1.0, help="angle step of the cylinder sweep"
    )
    parser.add_argument("--no-memory", action="store_true", help="time only, no tracemalloc pass")
    args = parser.parse_args()
    memory = not args.no_memory
    steps = [float(s) for s in args.steps.split(",") if s]
    cylinders = [int(c) for c in args.cylinders.split(",") if c]
    if steps:
        report(
            f"{args.example}: angle step (deg) -> time and peak memory per stage",
            "step",
            [(f"{s:g}", run_point(args.example, s, None, memory)) for s in steps],
        )
    if cylinders:
        report(
            f"{args.example}: number of cylinders at a {args.cylinder_step:g} deg step",
            "cyl",
            [(str(c), run_point(args.example, args.cylinder_step, c, memory)) for c in cylinders],
        )


if __name__ == "__main__":
    main()
