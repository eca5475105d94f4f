"""The acceptance figures (start-up, rendering, memory, batch, preview), each as a ratio to its
goal measured in the same run (the sweep's figures: benchmarks/sweep.py).

Run from the repository root (takes a few minutes; writes only below a temporary folder):

    python3 benchmarks/acceptance.py               # every figure
    python3 benchmarks/acceptance.py --repeat 3    # fewer whole-process repeats
    python3 benchmarks/acceptance.py --only startup,timing   # some figures only

Whole processes are timed (``crankdyn`` started afresh each time, median of ``--repeat`` runs,
each figure in turns with its yardstick: benchmarks.acceptance.walls) with byte-code caching on (in a temporary ``PYTHONPYCACHEPREFIX``), as an installed package
runs, and with the typeset mathtext labels kept between runs in a store of the benchmark's own
(filled by the warm-up run, as a user's is by the first report; the HTML figure is also given with
no store at all). A ratio <= 1 meets the goal. Not part of the test suite.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def _env(cache: Path) -> dict:
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = str(cache)
    # the typeset labels a run keeps for the next (crankdyn.report.mathtext_store): a store of
    # this benchmark's own, filled by each figure's warm-up run, as a user's is after the first report
    env["CRANKDYN_MATHTEXT_CACHE"] = str(cache.parent / "mathtext.json")
    # the parsed catalogs (crankdyn.report.catalog_cache), likewise this benchmark's own
    env["CRANKDYN_CACHE_DIR"] = str(cache.parent / "crankdyn-cache")
    return env


def walls(runs: list[tuple[list[str], dict]], repeat: int, codes: tuple[int, ...] = (0,)) -> list:
    """Median wall time of each ``(command, environment)`` as a whole process, the commands run
    in turns (each once first, as a warm-up): a figure and its yardstick are measured over the
    same stretch of time, so that a drift of the machine's speed meanwhile moves both alike.
    A command that exits with a code outside ``codes`` stops the benchmark."""
    times: list[list[float]] = [[] for _ in runs]
    for round_ in range(repeat + 1):
        for k, (cmd, env) in enumerate(runs):
            start = time.perf_counter()
            done = subprocess.run(cmd, env=env, capture_output=True, text=True)
            if done.returncode not in codes:
                raise SystemExit(
                    f"{' '.join(cmd[2:4])} exited with {done.returncode}: {done.stderr[-500:]}"
                )
            if round_:
                times[k].append(time.perf_counter() - start)
    return [statistics.median(t) for t in times]


def _cpu_s(cmd: list[str], env: dict) -> tuple[subprocess.CompletedProcess, float]:
    """``cmd`` run once: its result and the CPU seconds of it and of the processes it waited for."""
    import resource

    def spent() -> float:
        used = resource.getrusage(resource.RUSAGE_CHILDREN)
        return used.ru_utime + used.ru_stime

    before = spent()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    return done, spent() - before


def crankdyn(*args: str) -> list[str]:
    return [sys.executable, "-m", "crankdyn", *args]


FIGURES = ("startup", "html", "pdf", "size", "memory", "batch", "timing", "preview")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument(
        "--skip-memory", action="store_true", help="leave out the 0.01 deg in-line 4 runs"
    )
    parser.add_argument(
        "--only", help="comma-separated subset of " + ",".join(FIGURES) + " (default: all)"
    )
    parser.add_argument(
        "--write-docs",
        action="store_true",
        help="also write the figures into docs/performance.md (between its acceptance marks)",
    )
    args = parser.parse_args()
    only = set(FIGURES) if not args.only else {f.strip() for f in args.only.split(",")}
    if only - set(FIGURES):
        parser.error(
            f"unknown --only {','.join(sorted(only - set(FIGURES)))}; allowed: {','.join(FIGURES)}"
        )
    rows, notes = [], []
    with tempfile.TemporaryDirectory(prefix="crankdyn-accept-") as tmp:
        tmp = Path(tmp)
        env = _env(tmp / "pycache")
        one = str(EXAMPLES / "petrol-1cyl.toml")

        if only & {"startup", "html"}:  # measured in turns with their yardstick
            yardstick = [sys.executable, "-c", "import numpy, scipy.integrate, scipy.optimize"]
            runs = [(yardstick, env)]
            if "startup" in only:
                runs.append(
                    (crankdyn("report", one, "-o", str(tmp / "j"), "--format", "json", "-q"), env)
                )
            if "html" in only:
                html = crankdyn("report", one, "-o", str(tmp / "h"), "--format", "html", "-q")
                # and the first report on a machine (or after matplotlib's settings changed):
                # every label typeset
                runs += [(html, env), (html, {**env, "CRANKDYN_MATHTEXT_CACHE": "off"})]
            imports, *measured = walls(runs, args.repeat)
            if "startup" in only:
                json_s, *measured = measured
                rows.append(
                    (
                        "report --format json (1 cyl) / 1.5 x import numpy+scipy",
                        json_s,
                        1.5 * imports,
                    )
                )
            if "html" in only:
                html_s, cold = measured
                rows.append(
                    (
                        "report --format html (1 cyl) / 2 x import numpy+scipy",
                        html_s,
                        2.0 * imports,
                    )
                )
                rows.append(
                    ("  the same, no stored labels (first run) / 2 x import", cold, 2.0 * imports)
                )
        if "pdf" in only:
            subprocess.run(
                crankdyn(
                    "report",
                    one,
                    "-o",
                    str(tmp / "sc"),
                    "--format",
                    "html",
                    "--self-contained",
                    "-q",
                ),
                env=env,
                check=True,
                capture_output=True,
            )
            weasyprint_alone = [
                sys.executable,
                "-c",
                "import sys, weasyprint; weasyprint.HTML(filename=sys.argv[1]).write_pdf(sys.argv[2])",
                str(tmp / "sc" / "report.html"),
                str(tmp / "w.pdf"),
            ]
            pdf_s, weasy = walls(
                [
                    (crankdyn("report", one, "-o", str(tmp / "p"), "--format", "pdf", "-q"), env),
                    (weasyprint_alone, env),
                ],
                args.repeat,
            )
            rows.append(
                ("report --format pdf / 0.6 x WeasyPrint alone on its HTML", pdf_s, 0.6 * weasy)
            )
        if "size" in only:
            subprocess.run(
                crankdyn(
                    "report",
                    str(EXAMPLES / "v8-petrol.toml"),
                    "-o",
                    str(tmp / "v8"),
                    "--format",
                    "html",
                    "-q",
                ),
                env=env,
                check=True,
                capture_output=True,
            )
            size = (tmp / "v8" / "report.html").stat().st_size + sum(
                p.stat().st_size for p in (tmp / "v8" / "figures").iterdir()
            )
            rows.append(("V8 report.html + figures/ (MB) / 1.0 MB", size / 1e6, 1.0))
        if "memory" in only and not args.skip_memory:
            sys.path.insert(0, str(Path(__file__).resolve().parent))
            import scaling

            # each stage's least time of five processes per step, the steps in turns
            # (scaling.best_points)
            coarse, fine = scaling.best_points("inline4-petrol", [0.02, 0.01], 5)
            rows.append(("in-line 4 at 0.01 deg: peak RSS (MB) / 600 MB", fine["maxrss_MB"], 600.0))
            worst = max(
                (fine["stages"][n]["s"] / max(coarse["stages"][n]["s"], 1e-9), n)
                for n in fine["stages"]
                if coarse["stages"][n]["s"] > 0.05
            )
            rows.append(
                (
                    f"halving 0.02 -> 0.01 deg: worst stage time ratio ({worst[1]}) / 2",
                    worst[0],
                    2.0,
                )
            )

        if "batch" in only:
            sys.path.insert(0, str(Path(__file__).resolve().parent))
            from batch import write_variants  # the 30 variants (two broken) of benchmarks/batch.py

            variants = write_variants(tmp / "variants.csv", 30)
            report = crankdyn("report", one, "-o", str(tmp / "r"), "--format", "html,json", "-q")
            cmd = crankdyn(
                "batch",
                str(variants),
                "--base",
                one,
                "-o",
                str(tmp / "b"),
                "--format",
                "html,json",
                "--jobs",
                "2",
                "-q",
            )
            single_cpu = _cpu_s(report, env)[1]
            done, batch_cpu = _cpu_s(cmd, env)
            if (
                done.returncode != 2 or not (tmp / "b" / "answer_key.csv").is_file()
            ):  # 2: rows 7, 19 fail on purpose
                raise SystemExit(
                    f"the benchmark batch did not run as expected: {done.stderr[-500:]}"
                )
            # in turns: the batch and the one report it is measured against
            batch_s, single = walls([(cmd, env), (report, env)], args.repeat, codes=(0, 2))
            rows.append(
                (
                    "batch: 30 variants html+json, 2 jobs / 8 x one report html+json",
                    batch_s,
                    8.0 * single,
                )
            )
            notes.append(
                f"batch CPU seconds (all its processes) {batch_cpu:.1f}, one report's "
                f"{single_cpu:.2f}: {batch_cpu / single_cpu:.1f}x (the wall-time ratio on "
                "a shared machine follows the other load)"
            )

        if "timing" in only:
            monotone = 0
            for _ in range(10):
                subprocess.run(
                    crankdyn("report", one, "-o", str(tmp / "n"), "--format", "json", "-q"),
                    env=env,
                    check=True,
                    capture_output=True,
                )
                steps = json.loads((tmp / "n" / "results.json").read_text())["numerics"]["steps"]
                steps.sort(key=lambda s: s["points"])
                falls = [
                    (a["points"], b["points"], a["time_s"], b["time_s"])
                    for a, b in zip(steps, steps[1:], strict=False)
                    if a["time_s"] > b["time_s"]
                ]
                monotone += not falls
                for (
                    n_a,
                    n_b,
                    t_a,
                    t_b,
                ) in falls:  # which neighbours, by how much: noise or a real fall
                    print(
                        f"  not monotone: {n_a} angles {t_a * 1e6:.2f} us > {n_b} angles {t_b * 1e6:.2f} us",
                        file=sys.stderr,
                    )
            rows.append(("error-against-run-time table monotone, runs of 10 / 10", monotone, 10))

        if (
            "preview" in only
        ):  # benchmarks/preview.py: crankdyn serve + headless Chromium, 10 edits of a mass
            done = subprocess.run(
                [
                    sys.executable,
                    str(Path(__file__).resolve().parent / "preview.py"),
                    "--edits",
                    "10",
                ],
                env=env,
                capture_output=True,
                text=True,
            )
            found = {
                m[1]: float(m[2])
                for m in re.finditer(r"(?m)^(save -> [^\n]*?)\s+([0-9.]+)\s+[0-9.]+$", done.stdout)
            }
            if done.returncode != 0 or len(found) != 3:
                raise SystemExit(f"the preview benchmark did not run: {done.stderr[-800:]}")
            page, figures = (
                found["save -> the tab shows the new page"],
                found["save -> all its figures loaded"],
            )
            rows.append(
                ("preview: save -> the tab shows the new page, median (s) / 0.3 s", page, 0.3)
            )
            rows.append(
                (
                    "preview: save -> ... with the error study too (s) / 1 s",
                    found["save -> ... with the error study too"],
                    1.0,
                )
            )
            rows.append(("preview: save -> its figures loaded too, median (s) / 1 s", figures, 1.0))

    heading = (
        f"acceptance ({os.cpu_count()} cores, median of {args.repeat} whole-process runs; load "
        f"{', '.join(f'{x:.2f}' for x in os.getloadavg())} over 1, 5, 15 min at the end)"
    )
    print(heading)
    print(f"{'figure':62s} {'measured':>10s} {'goal':>10s} {'ratio':>7s}")
    for what, measured, goal in rows:
        ratio = measured / goal
        print(f"{what:62s} {measured:10.3f} {goal:10.3f} {ratio:7.2f}  {_verdict(what, ratio)}")
    for note in notes:
        print(note)
    if args.write_docs:
        write_docs(ROOT / "docs" / "performance.md", heading, rows, notes)
    print(
        "not measured here: the Dask cluster's answer key equal to the local pool's is "
        "a test (tests/test_batch_dask.py); benchmarks/batch.py shows where the batch's time goes"
    )


def _verdict(what: str, ratio: float) -> str:
    """ "ok" when the figure meets its goal (a count of monotone runs: at least the goal)."""
    ok = ratio >= 1 if "monotone" in what else ratio <= 1
    return "ok" if ok else "NOT MET"


#: The marks in docs/performance.md between which ``--write-docs`` puts the figures.
DOCS_START, DOCS_END = "<!-- acceptance:start -->", "<!-- acceptance:end -->"


def docs_table(heading: str, rows, notes) -> str:
    """The figures as the docs' Markdown table: measured, goal, their ratio and the verdict."""
    lines = [
        f"Measured by `python3 benchmarks/acceptance.py --write-docs`: {heading}.",
        "",
        "| figure | measured | goal | ratio | |",
        "|---|---|---|---|---|",
    ]
    for what, measured, goal in rows:
        ratio = measured / goal
        lines.append(
            f"| {what} | {measured:.3f} | {goal:.3f} | {ratio:.2f} | {_verdict(what, ratio)} |"
        )
    lines += [""] + [f"- {note}" for note in notes]
    return "\n".join(lines).rstrip() + "\n"


def write_docs(path: Path, heading: str, rows, notes) -> None:
    """Replace the figures between the acceptance marks of ``path`` (the rest is kept)."""
    text = path.read_text(encoding="utf-8")
    start, end = text.find(DOCS_START), text.find(DOCS_END)
    if start < 0 or end < start:
        raise SystemExit(f"{path}: no {DOCS_START} … {DOCS_END} marks to write the figures between")
    body = docs_table(heading, rows, notes)
    path.write_text(text[: start + len(DOCS_START)] + "\n" + body + text[end:], encoding="utf-8")


if __name__ == "__main__":
    main()
