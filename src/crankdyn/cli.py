"""The ``crankdyn`` command line.

Bad input ends with one message on stderr and exit code 2; nothing is written.
"""

from __future__ import annotations

import argparse
import dataclasses
import gc
import json
import os
import signal
import sys
import time
import tomllib
import warnings
from importlib import resources
from pathlib import Path

from .engine.frozen_heap import collector_paused, frozen_heap
from .errors import CrankdynError, Problem, SceneError, UsageError
from .version import __version__

EXIT_BAD_INPUT = 2
EXIT_INTERNAL = 1

# A command's imports create a few hundred thousand long-lived objects. With the default young
# generation of 700 allocations the collector traces them again and again while they are made, and
# the interpreter's exit traces them all once more: about 0.1 s of a 0.8 s JSON report
# (benchmarks/acceptance.py). The command's own process therefore collects less often and
# freezes what is left before it exits; :func:`main`, called in-process by the API's users and the
# tests, leaves the collector alone.
YOUNG_GENERATION_THRESHOLD = 10_000
#: OpenBLAS's threads, which the command limits to one unless the user chose: the stages' arrays
#: are small (a cycle's angles, a few cylinders), so the BLAS threads only spin after each call,
#: on the cores a report's stage child and figure drawers need (0.2 s of CPU in an HTML report).
#: Read when numpy is first imported, which the command does after :func:`run` starts.
BLAS_THREADS_ENV = "OPENBLAS_NUM_THREADS"
#: pydantic's plugins, which the command leaves out unless the user chose (an empty value lets
#: them in): looking for them reads every installed package's entry points when the first scene
#: model is built, 0.02 s of the command's start-up on one core; crankdyn's models need none.
PYDANTIC_PLUGINS_ENV = "PYDANTIC_DISABLE_PLUGINS"
#: matplotlib's artists documented briefly in the command's process (crankdyn.report.figures,
#: where this name is read: that module is not imported before a report is rendered).
ARTIST_DOCSTRINGS_ENV = "CRANKDYN_MATPLOTLIB_DOCSTRINGS"


#: The formats ``--format`` accepts: crankdyn.output.writers.FORMATS, named here without importing
#: that
#: module (numpy), so that ``--help`` answers at once.
REPORT_FORMATS = ("html", "pdf", "json", "csv", "xlsx", "docx")
#: What users type for a report language, with the code they mean.
LANGUAGE_ALIASES = {
    "ua": "uk",
    "ukr": "uk",
    "ukrainian": "uk",
    "українська": "uk",
    "укр": "uk",
    "rus": "ru",
    "russian": "ru",
    "русский": "ru",
    "рус": "ru",
    "eng": "en",
    "english": "en",
    "gb": "en",
    "us": "en",
}


def report_languages() -> list[str]:
    """The report languages of the core catalogs (crankdyn.report.i18n.available_languages, read
    without importing it: that module imports numpy)."""
    catalogs = Path(str(resources.files("crankdyn.templates"))) / "i18n"
    return sorted(p.stem for p in catalogs.glob("*.toml"))


def report_language(text: str) -> str:
    """``--lang`` as a language code: any case (``UK`` is ``uk``); a name or code users often type
    for another (``ua``, ``eng``, ``uk-UA``) is refused with the code it most likely means."""
    import difflib  # lazy: heavy optional import (only a refused --lang is matched)

    languages = report_languages()
    code = text.strip().lower()
    if code in languages:
        return code
    meant = LANGUAGE_ALIASES.get(code) or next(
        (part for part in code.replace("_", "-").split("-") if part in languages), None
    )
    if meant is None:
        close = difflib.get_close_matches(code, languages, n=1, cutoff=0.6)  # "enn", not "de"
        meant = close[0] if close else None
    hint = f"; did you mean {meant!r}?" if meant else ""
    raise UsageError(
        f"--lang {text!r}: not a report language{hint} (available: {', '.join(languages)})"
    )


def _command(sub, name: str, help_text: str, epilog: str) -> argparse.ArgumentParser:
    """A subcommand whose ``--help`` ends with its examples, laid out as written."""
    description = help_text[:1].upper() + help_text[1:] + "."
    return sub.add_parser(
        name,
        help=help_text,
        description=description,
        epilog="examples:\n" + epilog,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )


def _lang_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--lang",
        metavar="CODE",
        help="report language, any case: "
        + ", ".join(report_languages())
        + " (default: the scene's report.language)",
    )


MAIN_EPILOG = """\
first report:
  crankdyn example petrol-1cyl -o my-engine.toml
  crankdyn check my-engine.toml
  crankdyn report my-engine.toml -o report

'crankdyn COMMAND --help' shows a command's options and examples."""

REPORT_EPILOG = """\
  crankdyn report engine.toml                       # into report/: html, pdf, json, csv
  crankdyn report engine.toml -o out --format html,docx --lang uk
  crankdyn report engine.toml --format json --stages forces -v   # and the stages left out
  crankdyn report engine.toml --data-dir ../traces  # a data file from another folder"""

CHECK_EPILOG = """\
  crankdyn check engine.toml            # valid? the stages run and left out, the defaults
  crankdyn check engine.toml --lang uk  # checked as a Ukrainian report"""

EXAMPLE_EPILOG = """\
  crankdyn example --list
  crankdyn example petrol-1cyl -o my-engine.toml
  crankdyn example diesel-rk-trace -o diesel.toml   # also writes the pressure trace it refers to"""

PLUGINS_EPILOG = """\
  crankdyn plugins"""

EXPLORE_EPILOG = """\
  crankdyn explore --cylinders 4
  crankdyn explore --cylinders 8 --layout V --bank-angle 90 --top 5
  crankdyn explore --cylinders 6 --strokes 2 --all --json"""

SERVE_EPILOG = """\
  crankdyn serve engine.toml --open     # edit engine.toml; the page re-renders on save
  crankdyn serve engine.toml --port 0 --lang ru"""

BATCH_EPILOG = """\
  crankdyn batch variants.csv --base engine.toml -o batch
  crankdyn batch variants.csv --base engine.toml --format pdf --lang uk -j 2
  crankdyn batch variants.csv --base engine.toml --scheduler tcp://10.0.0.5:8786

variants.csv: a header of dotted scene fields, one row per student, e.g.
  variant,engine.bore,engine.rpm
  1,82 mm,5600"""

SWEEP_EPILOG = """\
  crankdyn sweep engine.toml --set engine.bore=76mm:88mm:4 --set engine.rod_ratio=0.26,0.3
  crankdyn sweep engine.toml --set engine.rpm=2000:6000:step=500 --plot j_max_m_s2 -o sweep
  crankdyn sweep engine.toml --grid study.toml --key csv,parquet"""


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="crankdyn",
        description="Dynamic calculation of crank mechanisms and "
        "piston engines,\nwritten up as a course-project report.",
        epilog=MAIN_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"crankdyn {__version__}")
    parser.add_argument("--debug", action="store_true", help="show a traceback on internal errors")
    sub = parser.add_subparsers(dest="command", required=True)
    _report_parser(sub)
    _other_parsers(sub)
    _batch_parser(sub)
    _sweep_parser(sub)
    return parser


def _report_parser(sub) -> None:
    report = _command(sub, "report", "compute a scene and write the report and data", REPORT_EPILOG)
    report.add_argument("scene", type=Path, help="the scene file (TOML)")
    report.add_argument(
        "-o", "--output", type=Path, default=Path("report"), help="output folder (default: report)"
    )
    report.add_argument(
        "--format",
        default="html,pdf,json,csv",
        help="comma-separated subset of "
        + ",".join(REPORT_FORMATS)
        + " (default: html,pdf,json,csv; docx needs pandoc)",
    )
    _lang_option(report)
    report.add_argument(
        "--stages", help="comma-separated stages to run (their prerequisites are added)"
    )
    report.add_argument(
        "--self-contained",
        action="store_true",
        help="inline the figures in report.html instead of referring to figures/*.svg",
    )
    report.add_argument(
        "--force",
        action="store_true",
        help="replace files in the output folder that crankdyn did not write or that were "
        "edited since (otherwise the run is refused and nothing is written)",
    )
    report.add_argument(
        "-q", "--quiet", action="store_true", help="no summary line (warnings still shown)"
    )
    report.add_argument(
        "-v",
        "--verbose",
        action="store_true",
        help="also list the stages left out and why ('check' always lists them)",
    )
    _stage_timeout_option(report)
    _data_dir_option(report)


def _other_parsers(sub) -> None:
    check = _command(
        sub, "check", "validate a scene as 'report' does (computed, nothing written)", CHECK_EPILOG
    )
    check.add_argument("scene", type=Path, help="the scene file (TOML)")
    _lang_option(check)
    _stage_timeout_option(check)
    _data_dir_option(check)

    example = _command(sub, "example", "list or write the bundled example scenes", EXAMPLE_EPILOG)
    example.add_argument("name", nargs="?", help="the example to write (see --list)")
    example.add_argument("--list", action="store_true", help="list the bundled examples")
    example.add_argument("-o", "--output", type=Path, help="file to write the example scene to")
    example.add_argument("--force", action="store_true", help="overwrite an existing file")

    _command(
        sub,
        "plugins",
        "list installed plugins, mechanisms, stages and report languages",
        PLUGINS_EPILOG,
    )

    explore = _command(
        sub,
        "explore",
        "rank the even-firing crank arrangements and firing orders "
        "of an engine by balance and firing rules",
        EXPLORE_EPILOG,
    )
    explore.add_argument("--cylinders", type=int, required=True, help="number of cylinders (1-24)")
    explore.add_argument(
        "--layout",
        default="inline",
        choices=["inline", "V", "W", "Y", "X", "boxer", "radial"],
        help="cylinder layout (default inline)",
    )
    explore.add_argument(
        "--strokes", type=int, default=4, choices=[2, 4], help="strokes per cycle (default 4)"
    )
    explore.add_argument(
        "--bank-angle", type=float, help="angle between adjacent banks, deg (V, W, Y, X)"
    )
    explore.add_argument("--top", type=int, default=10, help="rows to show (default 10)")
    explore.add_argument("--all", action="store_true", help="rank and show every firing order")
    explore.add_argument("--json", action="store_true", help="print the ranking as JSON")

    serve = _command(
        sub,
        "serve",
        "live HTML preview on 127.0.0.1 that re-renders when the scene is saved",
        SERVE_EPILOG,
    )
    serve.add_argument("scene", type=Path, help="the scene file (TOML)")
    serve.add_argument(
        "--port",
        type=int,
        default=8765,
        help="port on 127.0.0.1 (default 8765; 0 picks a free one)",
    )
    _lang_option(serve)
    serve.add_argument(
        "--stages", help="comma-separated stages to run (their prerequisites are added)"
    )
    serve.add_argument(
        "--open", action="store_true", help="open the preview in the default browser"
    )
    serve.add_argument(
        "-q", "--quiet", action="store_true", help="no log lines on stderr, only the URL"
    )


def _batch_parser(sub) -> None:
    batch = _command(
        sub,
        "batch",
        "one report per row of a CSV of student variants, plus an answer key",
        BATCH_EPILOG,
    )
    batch.add_argument(
        "variants",
        type=Path,
        help="CSV: a header of dotted scene paths (engine.bore, ...) "
        "and an optional 'variant' column; one row per student",
    )
    batch.add_argument("--base", type=Path, required=True, help="the scene every row starts from")
    batch.add_argument(
        "-o", "--output", type=Path, default=Path("batch"), help="output folder (default: batch)"
    )
    batch.add_argument(
        "--format",
        default="html,pdf,json,csv",
        help="formats of each report, as for 'report' (default: html,pdf,json,csv)",
    )
    batch.add_argument(
        "-j", "--jobs", type=int, help="worker processes (default and most: the available cores)"
    )
    _lang_option(batch)
    batch.add_argument(
        "--stages", help="comma-separated stages to run (their prerequisites are added)"
    )
    batch.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    batch.add_argument(
        "--timeout",
        type=float,
        default=120.0,
        help="seconds one variant may take before it is stopped and listed as "
        "failed "
        "(default 120, at most 86400)",
    )
    _scheduler_options(batch)
    _data_dir_option(batch)


def _sweep_parser(sub) -> None:
    sweep = _command(
        sub,
        "sweep",
        "a design study: every combination of ranges of scene fields, "
        "the answer key as a table and a plot of one result over the grid",
        SWEEP_EPILOG,
    )
    sweep.add_argument("scene", type=Path, help="the scene every point starts from")
    sweep.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUES",
        help="a swept field: START:STOP:COUNT (2000:6000:5), START:STOP:step=STEP, A,B,C "
        "(0.26,0.28,0.3), with a unit where the field has one (76mm:88mm:4); one value sets the "
        "field for every point; repeat for more fields (the first varies slowest)",
    )
    sweep.add_argument(
        "--grid",
        type=Path,
        metavar="FILE",
        help="a sweep file (TOML: [sweep], [fixed], [plot]); "
        "--set adds to it or replaces its fields",
    )
    sweep.add_argument(
        "-o", "--output", type=Path, default=Path("sweep"), help="output folder (default: sweep)"
    )
    sweep.add_argument(
        "--key",
        default="csv,xlsx",
        help="answer-key formats: a subset of csv,xlsx,parquet "
        "(default csv,xlsx; parquet needs crankdyn[parquet])",
    )
    sweep.add_argument(
        "--plot",
        metavar="COLUMN",
        help="plot this answer-key column (e.g. j_max_m_s2) over the grid",
    )
    sweep.add_argument(
        "--plot-x", metavar="NAME", help="the swept field on the plot's x axis (default: the first)"
    )
    sweep.add_argument("--plot-format", default="svg", help="svg, png or svg,png (default svg)")
    sweep.add_argument(
        "--format",
        default="none",
        help="files of each point in DIR/<point>/, as for 'report' "
        "(default none: only the answer key and the plot)",
    )
    sweep.add_argument(
        "-j", "--jobs", type=int, help="worker processes (default and most: the available cores)"
    )
    _lang_option(sweep)
    sweep.add_argument(
        "--stages",
        help="comma-separated stages to run (their prerequisites are added); "
        "fewer stages, faster points",
    )
    sweep.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    sweep.add_argument(
        "--timeout",
        type=float,
        default=120.0,
        help="seconds one point may take before it is stopped and listed as failed "
        "(default 120, at most 86400)",
    )
    _scheduler_options(sweep)
    _data_dir_option(sweep)


def _scheduler_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run the variants on the Dask cluster whose scheduler is at ADDRESS (tcp://HOST:8786, "
        "started with 'dask scheduler'; needs crankdyn[dask]) instead of local worker processes",
    )
    parser.add_argument(
        "--connect-timeout",
        type=float,
        default=10.0,
        metavar="SECONDS",
        help="seconds to wait for the --scheduler (default 10, at most 86400)",
    )
    parser.add_argument(
        "--force",
        action="store_true",
        help="replace files in the output folder that crankdyn did not write or that were "
        "edited since (otherwise they are kept and the run is refused)",
    )


def _run_options(args, formats: list[str]):
    """The batch/sweep options of the command line, checked."""
    from .batch.variants import (  # lazy: heavy optional import (numpy, scipy: per command)
        RunOptions,
        available_cores,
    )
    from .parallel.pool import (
        check_seconds,  # lazy: heavy optional import (numpy, scipy: per command)
    )

    if args.jobs is not None and args.jobs < 1:
        raise SceneError(Problem("--jobs", args.jobs, "a whole number >= 1"))
    if args.jobs is not None and args.scheduler:
        raise UsageError(
            "--jobs applies to the local worker processes; on a Dask cluster the workers set how "
            "many variants run at once (dask worker --nthreads N): give one or the other"
        )
    check_seconds("--timeout", args.timeout)
    check_seconds("--connect-timeout", args.connect_timeout)
    jobs = args.jobs
    if jobs is not None and jobs > available_cores():
        jobs = available_cores()
        print(
            f"crankdyn {args.command}: --jobs {args.jobs}: capped at {jobs}, the cores available "
            "(more worker processes only share them)",
            file=sys.stderr,
        )
    return RunOptions(
        formats,
        jobs,
        args.lang,
        _stage_list(args.stages),
        not args.quiet,
        None,
        args.timeout,
        tuple(str(d) for d in args.data_dir),
        args.scheduler,
        args.connect_timeout,
        args.force,
    )


#: seconds one stage may take in 'report' and 'check' (crankdyn.plugin.guard's, without its import)
DEFAULT_STAGE_TIMEOUT_S = 120.0
MAX_STAGE_TIMEOUT_S = 3600.0


def _stage_timeout_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--timeout",
        type=float,
        default=DEFAULT_STAGE_TIMEOUT_S,
        metavar="SECONDS",
        help="seconds one stage may take before the command stops with its name "
        f"(default {DEFAULT_STAGE_TIMEOUT_S:g}, at most {MAX_STAGE_TIMEOUT_S:g})",
    )


def _stage_time_limit(seconds: float):
    """The time limit of each stage (``--timeout``), checked: > 0 and at most the maximum."""
    from .plugin.guard import stage_time_limit  # lazy: heavy optional import (numpy)

    if not 0 < seconds <= MAX_STAGE_TIMEOUT_S:
        raise UsageError(
            f"--timeout {seconds:g}: give the seconds one stage may take, a number > 0 "
            f"and at most {MAX_STAGE_TIMEOUT_S:g}"
        )
    return stage_time_limit(seconds)


def _data_dir_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--data-dir",
        action="append",
        type=Path,
        default=[],
        metavar="DIR",
        help="a folder data files (cycle.trace_file ...) may also be read from; by default only "
        "the scene's folder and below",
    )


def run() -> None:
    """The ``crankdyn`` command (and ``python -m crankdyn``): :func:`main` in a process of its own."""
    gc.set_threshold(YOUNG_GENERATION_THRESHOLD, *gc.get_threshold()[1:])
    os.environ.setdefault(BLAS_THREADS_ENV, "1")
    os.environ.setdefault(PYDANTIC_PLUGINS_ENV, "__all__")
    os.environ.setdefault(ARTIST_DOCSTRINGS_ENV, "brief")
    code = main()
    try:
        sys.stdout.flush()  # what is still buffered, while a closed pipe can be told from an error
    except BrokenPipeError:
        _quiet_stdout()
    # Nothing is left to collect that matters: outputs are closed; atexit handlers still run.
    gc.freeze()
    sys.exit(code)


def _quiet_stdout() -> None:
    """Point stdout at devnull: its reader went away (`crankdyn plugins | head`), and the
    interpreter's final flush would report the closed pipe once more."""
    os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    handler = {
        "report": _report,
        "check": _check,
        "example": _example,
        "plugins": _plugins,
        "serve": _serve,
        "batch": _batch,
        "explore": _explore,
        "sweep": _sweep,
    }[args.command]
    try:
        if getattr(args, "lang", None) is not None:
            args.lang = report_language(args.lang)
        return _with_product_warnings(handler, args)
    except CrankdynError as exc:
        print(f"crankdyn: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt as exc:  # Ctrl-C, or SIGTERM where a batch handles it so
        return 128 + getattr(exc, "number", signal.SIGINT)
    except BrokenPipeError:  # the reader of the output went away: nothing more to say
        _quiet_stdout()
        return 0
    except Exception as exc:  # noqa: BLE001 - the last line of defence for the user
        if args.debug:
            raise
        print(
            f"crankdyn: internal error: {exc.__class__.__name__}: {exc}\n"
            f"(run again as 'crankdyn --debug {args.command} …' for the traceback, and please "
            "report it)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL


def _with_product_warnings(handler, args) -> int:
    """Run ``handler`` with crankdyn's own warnings (a kept output file ...) shown as one line each."""
    shown = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):
        if category.__module__.startswith("crankdyn"):
            print(f"crankdyn: warning: {message}", file=sys.stderr)
        else:
            shown(message, category, filename, lineno, file, line)

    with warnings.catch_warnings():
        warnings.showwarning = show
        return handler(args)


def _formats(text: str) -> list[str]:
    from .output.writers import FORMATS  # lazy: heavy optional import (numpy, scipy: per command)

    chosen = [f.strip() for f in text.split(",") if f.strip()]
    bad = [f for f in chosen if f not in FORMATS]
    if bad or not chosen:
        raise UsageError(
            f"unknown --format {', '.join(bad) or repr(text)}; allowed: a comma-separated subset of "
            + ",".join(FORMATS)
        )
    _require_tools(chosen)
    return chosen


def _require_tools(formats: list[str]) -> None:
    """The programs the chosen formats need, found before anything is computed (exit 2 with how
    to install a missing one): a Word file needs pandoc."""
    if "docx" in formats:
        from .report.docx import pandoc_path  # lazy: heavy optional import (only for a Word file)

        pandoc_path()


def _load(scene_path: Path, lang: str | None = None, data_dirs=(), registry=None):
    from .report.i18n import (
        available_languages,  # lazy: heavy optional import (numpy, scipy: per command)
    )
    from .scene.model import load_scene  # lazy: heavy optional import (numpy, scipy: per command)

    overrides = {"report": {"language": lang}} if lang else None
    scene = load_scene(scene_path, overrides, tuple(str(d) for d in data_dirs), registry)
    return scene, available_languages()


def _report(args) -> int:
    printer = None
    if "pdf" in (f.strip() for f in args.format.split(",")):
        from .report import printer  # lazy: heavy optional import (only a PDF has a printer)

        printer.prestart()  # WeasyPrint loads in a forked printer while the scene is computed
    try:
        # what the imports and the scene's reading make lives as long as the report: frozen
        # (crankdyn.engine.frozen_heap)
        with frozen_heap():
            with collector_paused():
                limit = _stage_time_limit(args.timeout)
            with limit:
                return _write_report(args)
    finally:
        if printer is not None:
            printer.discard()  # one not used (a refused scene, no PDF after all): stopped


def _write_report(args) -> int:
    with collector_paused():  # imports: nothing to collect (crankdyn.engine.frozen_heap)
        from .output.pipeline import (
            write_report,  # lazy: heavy optional import (numpy, scipy: per command)
        )
        from .plugin.registry import (
            default_registry,  # lazy: heavy optional import (numpy, scipy: per command)
        )

    formats = _formats(args.format)
    stages = [s.strip() for s in args.stages.split(",")] if args.stages else None
    start = time.perf_counter()
    with collector_paused():  # the plugins' imports and the scene's reading
        registry = default_registry()
        scene, languages = _load(args.scene, args.lang, args.data_dir, registry)
    if "pdf" in formats:
        from .report import printer  # lazy: heavy optional import (only a PDF has a printer)

        printer.warm_up(scene.report.language, scene.report.frame)
    _print_broken(registry)
    run = write_report(
        scene,
        registry,
        args.output,
        formats,
        stages,
        languages,
        self_contained=args.self_contained,
        force=args.force,
    )
    result, written = run.result, run.written
    _print_warnings(result, registry)
    if run.missing_translations:
        print(
            f"crankdyn: {missing_translations_line(result.scene.report.language, run.missing_translations)}",
            file=sys.stderr,
        )
    if not args.quiet:
        main_files = [p for p in written if p.parent == args.output]
        print(
            f"crankdyn: {len(written)} files in {args.output} ({time.perf_counter() - start:.2f} s): "
            + ", ".join(p.name for p in main_files)
        )
    if args.verbose and not args.quiet:
        _print_left_out(result.plan)
    return 0


def _print_left_out(plan) -> None:
    """The stages of the plan left out, each with its reason: a fact about the scene, not a
    warning."""
    for name, reason in plan.skipped.items():
        print(f"  stage {name} left out: {reason}")


def _print_unused_tables(plan, registry, scene) -> None:
    """The scene's tables whose stage is left out: they are read by nothing (a planetary
    mechanism's [balancing] table, which the report would otherwise pass over in silence)."""
    tables = scene.plugin_tables()
    for name in plan.skipped:
        table = getattr(registry.stages.get(name), "options_table", None)
        if table and table in tables:
            print(f"  table [{table}] is not used: stage {name} is left out")


def missing_translations_line(language: str, keys: set[str], shown: int = 10) -> str:
    """One warning line for the catalog keys a report has no text for in ``language`` (the first
    ``shown`` by name, then how many more): the report is written anyway, with the keys in it."""
    names = sorted(keys)
    more = f" and {len(names) - shown} more" if len(names) > shown else ""
    return (
        f"warning: the report in {language!r} has no translation for {len(names)} key(s): "
        + ", ".join(names[:shown])
        + more
    )


def _stage_list(text: str | None) -> list[str] | None:
    return [s.strip() for s in text.split(",")] if text else None


def _serve(args) -> int:
    from .preview.server import serve  # lazy: heavy optional import (numpy, scipy: per command)

    if not 0 <= args.port <= 65535:
        raise SceneError(
            Problem("--port", args.port, "a port number from 1 to 65535, or 0 for any free port")
        )
    return serve(
        args.scene,
        port=args.port,
        language=args.lang,
        stages=_stage_list(args.stages),
        open_browser=args.open,
        quiet=args.quiet,
    )


def _batch(args) -> int:
    from .batch.variants import run_batch  # lazy: heavy optional import (numpy, scipy: per command)

    o = _run_options(args, _formats(args.format))
    report = run_batch(
        args.variants,
        args.base,
        args.output,
        o.formats,
        jobs=o.jobs,
        language=o.language,
        stages=o.stages,
        progress=o.progress,
        timeout=o.timeout,
        data_dirs=o.data_dirs,
        scheduler=o.scheduler,
        connect_timeout=o.connect_timeout,
    )
    for warning in report.warnings:
        print(f"crankdyn batch: warning: {warning}", file=sys.stderr)
    done = len(report.outcomes) - len(report.failures)
    print(
        f"crankdyn batch: {done} of {len(report.outcomes)} variants written to {args.output} "
        f"in {report.seconds:.1f} s; answer key: {args.output / 'answer_key.csv'} (and .xlsx)"
    )
    if report.failures:
        lines = [
            f"crankdyn batch: {len(report.failures)} variant(s) failed "
            f"(listed in {args.output / 'failures.csv'}):"
        ]
        lines += _failure_lines(report.failures)
        print("\n".join(lines), file=sys.stderr)
    if report.interrupted:
        print(
            f"crankdyn batch: interrupted ({_stop_name(report.stop_signal)}); the answer key and "
            "failures.csv cover what finished",
            file=sys.stderr,
        )
        return 128 + report.stop_signal
    if report.failures:
        return EXIT_BAD_INPUT
    return 0


def _sweep(args) -> int:
    from .batch.sweep import (  # lazy: heavy optional import (numpy, scipy: per command)
        SweepRequest,
        run_sweep,
        sweep_from_args,
    )

    formats = [] if args.format.strip().lower() == "none" else _formats(args.format)
    request = SweepRequest(
        args.scene,
        sweep_from_args(args.set, args.grid, args.plot, args.plot_x),
        args.output,
        _run_options(args, formats),
        _csv_list(args.key),
        _csv_list(args.plot_format),
    )
    report, notes = run_sweep(request)
    for note in notes:
        print(f"crankdyn sweep: {note}", file=sys.stderr)
    for warning in report.warnings:
        print(f"crankdyn sweep: warning: {warning}", file=sys.stderr)
    done = len(report.outcomes) - len(report.failures)
    print(
        f"crankdyn sweep: {done} of {len(report.outcomes)} points computed in {report.seconds:.1f} s; "
        f"written to {args.output}: " + ", ".join(p.name for p in report.written)
    )
    if report.failures:
        lines = [
            f"crankdyn sweep: {len(report.failures)} point(s) failed (listed in {args.output / 'failures.csv'}):"
        ]
        lines += _failure_lines(report.failures)
        print("\n".join(lines), file=sys.stderr)
    if report.interrupted:
        print(
            f"crankdyn sweep: interrupted ({_stop_name(report.stop_signal)}); the answer key and "
            "failures.csv cover what finished",
            file=sys.stderr,
        )
        return 128 + report.stop_signal
    return EXIT_BAD_INPUT if report.failures or any(n.startswith("no point") for n in notes) else 0


#: Failed variants a batch or sweep names on stderr; failures.csv lists them all.
FAILURES_SHOWN = 20


def _failure_lines(failures: list, shown: int = FAILURES_SHOWN) -> list[str]:
    """One line per failed variant, the first ``shown`` of them, then how many more."""
    lines = [f"  row {o.row} ({o.name}): {o.error}" for o in failures[:shown]]
    return lines + ([f"  ... and {len(failures) - shown} more"] if len(failures) > shown else [])


def _stop_name(number: int) -> str:
    """How the user stopped a batch or sweep: Ctrl-C (SIGINT) or the signal's name."""
    return "Ctrl-C" if number == signal.SIGINT else signal.Signals(number).name


def _csv_list(text: str) -> list[str]:
    return [part.strip().lower() for part in text.split(",") if part.strip()]


def _explore(args) -> int:
    """The explore command: rank the firing orders asked for, print them as text or JSON."""
    _check_explore_args(args)
    start = time.perf_counter()
    result = _firing_ranking(args)
    seconds = time.perf_counter() - start
    if args.json:
        print(
            json.dumps(
                {**dataclasses.asdict(result), "seconds": seconds}, indent=1, ensure_ascii=False
            )
        )
        return 0
    _print_firing_ranking(args, result, seconds)
    return 0


def _check_explore_args(args) -> None:
    """The explore command's numbers are in range and the bank angle is given where it applies."""
    if not 1 <= args.cylinders <= 24:
        raise SceneError(Problem("--cylinders", args.cylinders, "a whole number from 1 to 24"))
    if args.top < 1:
        raise SceneError(Problem("--top", args.top, "a whole number >= 1"))
    needs_angle = args.layout in ("V", "W", "Y", "X")
    if needs_angle != (args.bank_angle is not None):
        raise SceneError(
            Problem(
                "--bank-angle",
                args.bank_angle,
                f"required for a {args.layout} engine"
                if needs_angle
                else f"does not apply to a {args.layout} engine",
            )
        )
    if args.bank_angle is not None and not (
        0 < args.bank_angle < 360 and args.bank_angle >= sys.float_info.min
    ):
        raise SceneError(
            Problem(
                "--bank-angle",
                args.bank_angle,
                "an angle in degrees, > 0 and < 360 (as engine.bank_angle_deg)",
            )
        )


def _firing_ranking(args):
    """The ranking of the firing orders the explore command asks for; a layout or a count it
    cannot rank raises SceneError naming the option."""
    from .physics import firing_explorer  # lazy: heavy optional import (numpy, scipy: per command)
    from .physics.layout import (
        LayoutError,  # lazy: heavy optional import (numpy, scipy: per command)
    )

    try:
        return firing_explorer.explore(
            args.cylinders,
            args.layout,
            args.strokes,
            args.bank_angle,
            top=None if args.all else args.top,
        )
    except LayoutError as exc:
        raise SceneError(
            Problem("--" + exc.field.split(".")[-1].replace("_", "-"), exc.value, str(exc))
        ) from None
    except firing_explorer.TooManyFiringOrders as exc:
        option = ("--all", "(every firing order)") if args.all else ("--top", args.top)
        raise SceneError(
            Problem(
                option[0],
                option[1],
                f"{exc}; list the best ones with --top N, N <= {firing_explorer.MAX_RANKED_ORDERS}",
            )
        ) from None


def _print_firing_ranking(args, result, seconds: float) -> None:
    """Print the explore command's ranking as a text table."""
    print(
        f"crankdyn explore: {args.cylinders}-cylinder {args.layout} {args.strokes}-stroke"
        + (f", bank angle {args.bank_angle:g} deg" if args.bank_angle is not None else "")
        + f": firing every {result.interval_deg:g} deg; {result.arrangements} crank arrangements, "
        f"{result.firing_orders} firing orders ({result.scored_firing_orders} scored in detail, {seconds:.3f} s)"
    )
    if result.reason:
        print(f"  no even-firing arrangement: {result.reason}")
        return
    print(
        "  ranked by: first-order parts needing balance shafts, second order, what counterweights cure, then "
        "consecutive firings of neighbours / on one pin / on one half of the shaft"
    )
    head = (
        f"{'#':>4}  {'crank angles, deg':<34} {'firing order':<30} {'sum_C':>6} {'M_C':>6} {'sum_PI':>6} "
        f"{'M_PI':>6} {'sum_PII':>7} {'M_PII':>6} {'nb':>3} {'pin':>3} {'half':>4}"
    )
    print(head)
    for row in result.rows:
        c = row.coefficients
        print(
            f"{row.rank:>4}  {','.join(f'{x:g}' for x in row.crank_angles_deg):<34} "
            f"{'-'.join(row.firing_order):<30} {c['sum_C']:6.3f} {c['M_C']:6.3f} {c['sum_PI']:6.3f} "
            f"{c['M_PI']:6.3f} {c['sum_PII']:7.3f} {c['M_PII']:6.3f} {row.neighbours:>3} {row.same_pin:>3} "
            f"{row.same_half:>4}"
        )


def _check(args) -> int:
    with _stage_time_limit(args.timeout):
        return _check_scene(args)


def _check_scene(args) -> int:
    from .engine.orchestrator import (
        run_scene,  # lazy: heavy optional import (numpy, scipy: per command)
    )
    from .plugin.registry import (
        default_registry,  # lazy: heavy optional import (numpy, scipy: per command)
    )

    registry = default_registry()
    scene, languages = _load(args.scene, args.lang, args.data_dir, registry)
    _print_broken(registry)
    # Exactly what 'report' does before rendering (data files read, every stage run), so a scene
    # 'check' passes is one 'report' accepts; nothing is written.
    result = run_scene(scene, registry, None, languages)
    the_plan = result.plan
    print(f"crankdyn: {args.scene} is valid; stages: {', '.join(s.name for s in the_plan.order)}")
    _print_left_out(the_plan)
    _print_unused_tables(the_plan, registry, scene)
    _print_warnings(result, registry)
    from .report.plausibility import (
        defaults_applied,  # lazy: heavy optional import (numpy, scipy: per command)
    )

    applied = defaults_applied(scene)
    if applied:
        print("defaults applied (not given in the scene):")
        for field, value in applied:
            print(f"  {field} = {value!r}")
    return 0


def _print_broken(registry) -> None:
    """A warning for each plugin left out because it failed to load (``crankdyn plugins`` lists
    them)."""
    for message in registry.broken.values():
        print(f"crankdyn: warning: {message}; the plugin is left out", file=sys.stderr)


def _print_warnings(result, registry) -> None:
    """Plausibility warnings (a valid scene with values no real engine has) on stderr."""
    from .report.plausibility import (  # lazy: heavy optional import (numpy, scipy: per command)
        console_lines,
        language_warnings,
        warnings,
    )

    for line in console_lines(
        warnings(result.scene, registry, result) + language_warnings(result.scene), registry
    ):
        print(f"crankdyn: {line}", file=sys.stderr)


def examples_dir() -> Path:
    return Path(str(resources.files("crankdyn.examples")))


def _example_names() -> dict[str, Path]:
    return {p.stem: p for p in sorted(examples_dir().glob("*.toml"))}


def _example(args) -> int:
    names = _example_names()
    if args.list or not args.name:
        for name, path in names.items():
            title = (
                tomllib.loads(path.read_text(encoding="utf-8")).get("report", {}).get("title", "")
            )
            print(f"{name:28s} {title}")
        return 0
    if args.name not in names:
        raise UsageError(f"unknown example {args.name!r}; available: " + ", ".join(names))
    source = names[args.name]
    text = source.read_bytes()
    target = args.output or Path(f"{args.name}.toml")
    from .output.writers import (
        write_atomically,  # lazy: heavy optional import (numpy, scipy: per command)
    )

    files = {target.name: text}
    # An example may refer to a data file next to it; bring it along so the copy runs.
    data = tomllib.loads(text.decode("utf-8")).get("cycle", {}).get("trace_file")
    if data:
        files[data] = (source.parent / data).read_bytes()
    folder = target.parent if str(target.parent) else Path(".")
    # A file already there with exactly these bytes (the data file two examples share) is reused.
    existing = [
        folder / name for name in files if (folder / name).exists() or (folder / name).is_symlink()
    ]
    existing = [
        path
        for path in existing
        if path.is_symlink() or not path.is_file() or path.read_bytes() != files[path.name]
    ]
    if existing and not args.force:
        raise UsageError(
            f"{existing[0]} exists; not overwritten (give --force to replace it, or another -o FILE)"
        )
    write_atomically(target.parent if str(target.parent) else Path("."), files)
    print(f"crankdyn: wrote {target}" + (f" and {target.parent / data}" if data else ""))
    return 0


def _plugins(args) -> int:
    from .plugin.registry import (
        default_registry,  # lazy: heavy optional import (numpy, scipy: per command)
    )

    with _stage_time_limit(DEFAULT_STAGE_TIMEOUT_S):  # a plugin whose import never ends is named
        registry = default_registry()
    print("mechanisms:")
    for name, mech in sorted(registry.mechanisms.items()):
        print(f"  {name:24s} [{registry.owner['mechanism:' + name]}] {mech.summary}")
    print("stages:")
    for name, stage in sorted(registry.stages.items()):
        print(
            f"  {name:24s} [{registry.owner['stage:' + name]}] requires={','.join(stage.requires) or '-'} "
            f"provides={','.join(stage.provides) or '-'}"
            f"{' uses=' + ','.join(stage.uses) if stage.uses else ''}{'' if stage.default else ' (optional)'}"
        )
    if registry.broken:
        print("broken (failed to load, left out):")
        for name, message in sorted(registry.broken.items()):
            print(f"  {name:24s} {message}")
    from .report.i18n import (
        available_languages,  # lazy: heavy optional import (numpy, scipy: per command)
    )

    print("languages: " + ", ".join(available_languages()))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
