"""Start-up of a JSON-only report, this tree against an earlier commit, measured in turns in one run.

    python3 benchmarks/startup_ab.py [--before REV] [--repeat 9]

The earlier commit is unpacked (``git archive``) into a temporary folder and put first on
``PYTHONPATH``, so the same interpreter and packages run both; each repeat times, in turn, the
yardstick ``python3 -c "import numpy, scipy.integrate, scipy.optimize"``, the earlier tree and
this one (whole processes, byte-code caching on). Prints the medians, the ratios to the yardstick
(the goal: at most 1.5) and the numerics stage's own time from each results.json.
Not part of the test suite.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", default="HEAD~1", help="the earlier commit (default HEAD~1)")
    parser.add_argument("--repeat", type=int, default=9)
    parser.add_argument("--scene", default=str(ROOT / "examples" / "petrol-1cyl.toml"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="crankdyn-ab-") as tmp:
        tmp = Path(tmp)
        (tmp / "before").mkdir()
        archive = subprocess.run(
            ["git", "-C", str(ROOT), "archive", args.before], check=True, capture_output=True
        )
        subprocess.run(["tar", "-x", "-C", str(tmp / "before")], input=archive.stdout, check=True)
        env = dict(os.environ)
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = str(tmp / "pycache")
        before_env = dict(
            env,
            PYTHONPATH=os.pathsep.join(
                [str(tmp / "before" / "src"), str(tmp / "before" / "plugins")]
            ),
        )

        def report(name):
            return [
                sys.executable,
                "-m",
                "crankdyn",
                "report",
                args.scene,
                "-o",
                str(tmp / name),
                "--format",
                "json",
                "-q",
            ]

        runs = {
            "import": (
                [sys.executable, "-c", "import numpy, scipy.integrate, scipy.optimize"],
                env,
            ),
            "before": (report("before-out"), before_env),
            "after": (report("after-out"), env),
        }
        for cmd, run_env in runs.values():  # warm-up: byte-code caches
            subprocess.run(cmd, env=run_env, check=True, capture_output=True)
        times: dict[str, list[float]] = {k: [] for k in runs}
        numerics: dict[str, list[float]] = {"before": [], "after": []}
        for _ in range(args.repeat):
            for name, (cmd, run_env) in runs.items():
                start = time.perf_counter()
                subprocess.run(cmd, env=run_env, check=True, capture_output=True)
                times[name].append(time.perf_counter() - start)
                if name != "import":
                    document = json.loads((tmp / f"{name}-out" / "results.json").read_text())
                    numerics[name].append(document["timing_s"].get("numerics", float("nan")))
    median = {k: statistics.median(v) for k, v in times.items()}
    print(
        f"JSON-only report of {Path(args.scene).name}, medians of {args.repeat} whole processes taken in turns "
        f"(load average {os.getloadavg()[0]:.1f})"
    )
    print(f"  import numpy, scipy.integrate, scipy.optimize  {median['import']:.3f} s")
    for name in ("before", "after"):
        label = f"{args.before}" if name == "before" else "this tree"
        print(
            f"  {label:45s} {median[name]:.3f} s  = {median[name] / median['import']:.2f} x the import "
            f"(numerics stage {statistics.median(numerics[name]):.3f} s)"
        )


if __name__ == "__main__":
    main()
