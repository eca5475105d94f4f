"""Benchmark of ``crankdyn batch``: 30 student variants (two of them broken) on two cores.

Run: python3 benchmarks/batch.py [--rows 30] [--jobs 2] [--format html] [--keep DIR]

Builds a variants CSV over the bundled petrol-1cyl example (speed, piston mass and peak
pressure vary per row; rows 7 and 19 carry a bad value), runs the batch exactly as the
command line does, prints the wall time and appends a record to
benchmarks/results/batch.jsonl. Not part of the test suite.
"""

from __future__ import annotations

import argparse
import csv
import datetime
import json
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

from crankdyn import __version__
from crankdyn.batch import run_batch
from crankdyn.cli import examples_dir

BROKEN = {7: ("engine.bore", "-82 mm"), 19: ("cycle.max_pressure", "1.0 MPa")}


def write_variants(path: Path, rows: int) -> Path:
    header = ["variant", "report.student", "engine.rpm", "engine.bore", "masses.piston_group", "cycle.max_pressure"]
    with open(path, "w", encoding="utf-8", newline="") as fh:
        writer = csv.DictWriter(fh, header)
        writer.writeheader()
        for k in range(1, rows + 1):
            row = {"variant": f"v{k:02d}", "report.student": f"Student {k}", "engine.rpm": 4000 + 100 * k,
                   "engine.bore": "", "masses.piston_group": f"{0.40 + 0.01 * k:.2f} kg",
                   "cycle.max_pressure": f"{5.0 + 0.1 * k:.1f} MPa"}
            if k in BROKEN:
                row[BROKEN[k][0]] = BROKEN[k][1]
            writer.writerow(row)
    return path


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rows", type=int, default=30)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--format", default="html", help="formats of each report (default html; try html,pdf)")
    parser.add_argument("--keep", type=Path, help="write the batch here and keep it (default: a temporary folder)")
    args = parser.parse_args()
    formats = [f.strip() for f in args.format.split(",") if f.strip()]

    with tempfile.TemporaryDirectory() as tmp:
        out = args.keep or Path(tmp) / "out"
        variants = write_variants(Path(tmp) / "variants.csv", args.rows)
        start = time.perf_counter()
        report = run_batch(variants, examples_dir() / "petrol-1cyl.toml", out, formats, jobs=args.jobs,
                           progress=sys.stderr.isatty())
        wall = time.perf_counter() - start
    ok = len(report.outcomes) - len(report.failures)
    per_row = sorted(o.seconds for o in report.outcomes if o.ok)
    record = {
        "date": datetime.datetime.now().isoformat(timespec="seconds"),
        "crankdyn_version": __version__,
        "rows": args.rows, "ok": ok, "failed": len(report.failures), "jobs": args.jobs, "formats": formats,
        "wall_s": round(wall, 2), "per_variant_median_s": round(per_row[len(per_row) // 2], 3) if per_row else None,
        "cpu_count": os.cpu_count(), "python": platform.python_version(), "machine": platform.machine(),
    }
    print(f"crankdyn batch benchmark: {args.rows} variants ({len(report.failures)} broken) as "
          f"{','.join(formats)} on {args.jobs} worker processes: {wall:.1f} s wall time, "
          f"{record['per_variant_median_s']} s median per variant")
    results = Path(__file__).resolve().parent / "results"
    results.mkdir(exist_ok=True)
    with open(results / "batch.jsonl", "a", encoding="utf-8") as fh:
        fh.write(json.dumps(record) + "\n")
    print(f"recorded in {results / 'batch.jsonl'}")


if __name__ == "__main__":
    main()
