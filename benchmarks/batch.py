"""Benchmark of ``crankdyn batch``: 30 student variants (two of them broken) on two cores.

Run: python3 benchmarks/batch.py [--rows 30] [--jobs 2] [--format html,json] [--repeat 1] [--keep DIR]

Builds a variants CSV over the bundled petrol-1cyl example (speed, piston mass and peak
pressure vary per row; rows 7 and 19 carry a bad value) and, each in a fresh process, runs the
batch exactly as the command line does, twice per repeat, interleaved:

* ``warm``: as crankdyn does (the parent loads matplotlib with a first figure, the report
  language's translator and, for PDFs, WeasyPrint once; the forked workers inherit them);
* ``cold``: the parent loads only the plugins and the report code (no warm-up),
  so every variant's worker imports and initialises the rest itself.

It also times the work of one variant in one warm process (compute + render + write, the
median of three), which gives the batch-level overhead as a ratio: wall time / (ok variants x
work per variant / jobs). Prints the batch goal (30 variants HTML + JSON in <= 30 s on two
cores) as a ratio and appends a record to benchmarks/results/batch.jsonl. Not part of the tests.
"""

from __future__ import annotations

import argparse
import csv
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BROKEN = {7: ("engine.bore", "-82 mm"), 19: ("cycle.max_pressure", "1.0 MPa")}
GOAL_S = 30.0  # 30 variants, HTML + JSON, two cores


def write_variants(path: Path, rows: int) -> Path:
    header = [
        "variant",
        "report.student",
        "engine.rpm",
        "engine.bore",
        "masses.piston_group",
        "cycle.max_pressure",
    ]
    with open(path, "w", encoding="utf-8", newline="") as fh:
        writer = csv.DictWriter(fh, header)
        writer.writeheader()
        for k in range(1, rows + 1):
            row = {
                "variant": f"v{k:02d}",
                "report.student": f"Student {k}",
                "engine.rpm": 4000 + 100 * k,
                "engine.bore": "",
                "masses.piston_group": f"{0.40 + 0.01 * k:.2f} kg",
                "cycle.max_pressure": f"{5.0 + 0.1 * k:.1f} MPa",
            }
            if k in BROKEN:
                row[BROKEN[k][0]] = BROKEN[k][1]
            writer.writerow(row)
    return path


def _cold_warm(formats, languages=()) -> None:
    """A batch parent without the warm-up: the plugins and the report code only."""
    import crankdyn.batch.variants as batch
    from crankdyn.output import pipeline  # noqa: F401
    from crankdyn.output import writers as outputs  # noqa: F401
    from crankdyn.report import i18n  # noqa: F401

    batch._registry()
    if {"html", "pdf", "docx"} & set(formats):
        from crankdyn.report import document  # noqa: F401


def one_batch(mode: str, variants: Path, out: Path, formats: list[str], jobs: int) -> dict:
    """One whole batch in this (fresh) process; ``mode`` is warm or cold."""
    import crankdyn.batch.variants as batch
    from crankdyn.cli import examples_dir

    if mode == "cold":
        batch.warm = _cold_warm
    start, cpu = time.perf_counter(), _cpu_s()
    report = batch.run_batch(
        variants, examples_dir() / "petrol-1cyl.toml", out, formats, jobs=jobs, progress=False
    )
    wall, cpu = time.perf_counter() - start, _cpu_s() - cpu
    seconds = sorted(o.seconds for o in report.outcomes if o.ok)
    return {
        "wall_s": wall,
        "cpu_s": cpu,
        "ok": len(seconds),
        "failed": len(report.failures),
        "variant_median_s": seconds[len(seconds) // 2] if seconds else None,
    }


def _cpu_s() -> float:
    """CPU seconds of this process and its finished children (the forked workers): what the batch costs,
    which other load on the machine changes far less than the wall time."""
    import resource

    own, children = (
        resource.getrusage(resource.RUSAGE_SELF),
        resource.getrusage(resource.RUSAGE_CHILDREN),
    )
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def work_per_variant(formats: list[str], out: Path) -> float:
    """Median seconds of one variant computed, rendered and written in a warm process (no fork)."""
    import tomllib

    import crankdyn.batch.variants as batch
    from crankdyn.cli import examples_dir

    base_path = examples_dir() / "petrol-1cyl.toml"
    base = tomllib.loads(base_path.read_text(encoding="utf-8"))
    batch.warm(formats, ("en",))
    times, cpu = [], []
    for k in range(4):
        variant = batch.Variant(k + 1, f"w{k}", {"engine": {"rpm": 4000 + 100 * k}}, {})
        before = time.process_time()
        outcome = batch.run_variant(
            base, str(base_path.parent), variant, str(out), formats, None, None
        )
        assert outcome.ok, outcome.error
        times.append(outcome.seconds)
        cpu.append(time.process_time() - before)
    return statistics.median(times[1:]), statistics.median(
        cpu[1:]
    )  # the first one still fills caches


def _in_fresh_process(*args: str) -> dict:
    done = subprocess.run(
        [sys.executable, __file__, *args], capture_output=True, text=True, check=True
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rows", type=int, default=30)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument(
        "--format", default="html,json", help="formats of each report (default html,json)"
    )
    parser.add_argument("--repeat", type=int, default=1, help="batches per mode (interleaved)")
    parser.add_argument("--keep", type=Path, help="write the batches below here and keep them")
    parser.add_argument("--one", choices=["warm", "cold", "work"], help=argparse.SUPPRESS)
    parser.add_argument("--variants", type=Path, help=argparse.SUPPRESS)
    parser.add_argument("--out", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args()
    formats = [f.strip() for f in args.format.split(",") if f.strip()]
    if args.one == "work":
        work, work_cpu = work_per_variant(formats, args.out)
        print(json.dumps({"work_s": work, "work_cpu_s": work_cpu}))
        return
    if args.one:
        print(json.dumps(one_batch(args.one, args.variants, args.out, formats, args.jobs)))
        return

    runs: dict[str, list[dict]] = {"warm": [], "cold": []}
    with tempfile.TemporaryDirectory() as tmp:
        root = args.keep or Path(tmp)
        variants = write_variants(Path(tmp) / "variants.csv", args.rows)
        common = ["--format", args.format, "--jobs", str(args.jobs), "--variants", str(variants)]
        for k in range(args.repeat):
            for mode in ("warm", "cold"):
                runs[mode].append(
                    _in_fresh_process("--one", mode, *common, "--out", str(root / f"{mode}{k}"))
                )
        work_run = _in_fresh_process("--one", "work", *common, "--out", str(root / "work"))
    work, work_cpu = work_run["work_s"], work_run["work_cpu_s"]
    warm = statistics.median(r["wall_s"] for r in runs["warm"])
    cold = statistics.median(r["wall_s"] for r in runs["cold"])
    warm_cpu = statistics.median(r["cpu_s"] for r in runs["warm"])
    cold_cpu = statistics.median(r["cpu_s"] for r in runs["cold"])
    ok = runs["warm"][0]["ok"]
    ideal = ok * work / args.jobs
    print(
        f"crankdyn batch benchmark: {args.rows} variants ({runs['warm'][0]['failed']} broken) as "
        f"{','.join(formats)} on {args.jobs} worker processes, {os.cpu_count()} cores, median of {args.repeat}"
    )
    print(
        f"  wall time, now (parent warmed once):          {warm:6.1f} s   "
        f"goal {GOAL_S:g} s: ratio {warm / GOAL_S:.2f} {'ok' if warm <= GOAL_S else 'NOT MET'}"
    )
    print(
        f"  wall time, workers loading matplotlib etc.:   {cold:6.1f} s   (before; now / before = {warm / cold:.2f})"
    )
    print(
        f"  one variant's work in a warm process:         {work:6.2f} s   "
        f"(x {ok} ok / {args.jobs} jobs = {ideal:.1f} s); CPU {work_cpu:.2f} s"
    )
    print(
        f"  batch overhead (wall / that):                 {warm / ideal:6.2f}    "
        f"median variant in its worker: {runs['warm'][0]['variant_median_s']:.2f} s now, "
        f"{runs['cold'][0]['variant_median_s']:.2f} s before"
    )
    print(
        f"  CPU seconds of the whole batch (all workers): {warm_cpu:6.1f} s now, {cold_cpu:.1f} s before "
        f"(now / before = {warm_cpu / cold_cpu:.2f}); per ok variant {warm_cpu / ok:.2f} s against "
        f"{work_cpu:.2f} s of work (overhead {warm_cpu / (ok * work_cpu):.2f})"
    )
    print(
        f"  so on an idle {args.jobs}-core machine about {warm_cpu / args.jobs:.1f} s "
        f"(goal {GOAL_S:g} s: ratio {warm_cpu / args.jobs / GOAL_S:.2f})"
    )
    record = {
        "date": datetime.datetime.now().isoformat(timespec="seconds"),
        "rows": args.rows,
        "ok": ok,
        "jobs": args.jobs,
        "formats": formats,
        "repeat": args.repeat,
        "wall_s": round(warm, 2),
        "wall_cold_s": round(cold, 2),
        "cpu_s": round(warm_cpu, 1),
        "cpu_cold_s": round(cold_cpu, 1),
        "work_cpu_per_variant_s": round(work_cpu, 3),
        "work_per_variant_s": round(work, 3),
        "overhead_ratio": round(warm / ideal, 3),
        "goal_ratio": round(warm / GOAL_S, 3),
        "cpu_count": os.cpu_count(),
        "python": platform.python_version(),
        "machine": platform.machine(),
    }
    results = Path(__file__).resolve().parent / "results"
    results.mkdir(exist_ok=True)
    with open(results / "batch.jsonl", "a", encoding="utf-8") as fh:
        fh.write(json.dumps(record) + "\n")
    print(f"recorded in {results / 'batch.jsonl'}")


if __name__ == "__main__":
    main()
