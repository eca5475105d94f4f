"""The ``crankdyn`` command line.

Bad input ends with one message on stderr and exit code 2; nothing is written.
"""

from __future__ import annotations

import argparse
import sys
import time
from importlib import resources
from pathlib import Path

from . import __version__
from .errors import CrankdynError, Problem, SceneError

EXIT_BAD_INPUT = 2
EXIT_INTERNAL = 1


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="crankdyn", description="Dynamic calculation of crank mechanisms and "
                                     "piston engines, written up as a course-project report.")
    parser.add_argument("--version", action="version", version=f"crankdyn {__version__}")
    parser.add_argument("--debug", action="store_true", help="show a traceback on internal errors")
    sub = parser.add_subparsers(dest="command", required=True)

    report = sub.add_parser("report", help="compute a scene and write the report and data")
    report.add_argument("scene", type=Path)
    report.add_argument("-o", "--output", type=Path, default=Path("report"), help="output folder (default: report)")
    report.add_argument("--format", default="html,pdf,json,csv",
                        help="comma-separated subset of html,pdf,json,csv (default: all)")
    report.add_argument("--lang", help="report language code (overrides report.language)")
    report.add_argument("--stages", help="comma-separated stages to run (their prerequisites are added)")
    report.add_argument("-q", "--quiet", action="store_true")

    check = sub.add_parser("check", help="validate a scene without computing it")
    check.add_argument("scene", type=Path)

    example = sub.add_parser("example", help="list or write the bundled example scenes")
    example.add_argument("name", nargs="?")
    example.add_argument("--list", action="store_true", help="list the bundled examples")
    example.add_argument("-o", "--output", type=Path, help="file to write the example scene to")

    sub.add_parser("plugins", help="list installed plugins, mechanisms and stages")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    handler = {"report": _report, "check": _check, "example": _example, "plugins": _plugins}[args.command]
    try:
        return handler(args)
    except CrankdynError as exc:
        print(f"crankdyn: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        return 130
    except Exception as exc:  # noqa: BLE001 - the last line of defence for the user
        if args.debug:
            raise
        print(f"crankdyn: internal error: {exc.__class__.__name__}: {exc}\n"
              "(run again with --debug for the traceback, and please report it)", file=sys.stderr)
        return EXIT_INTERNAL


def _formats(text: str) -> list[str]:
    from .outputs import FORMATS

    chosen = [f.strip() for f in text.split(",") if f.strip()]
    bad = [f for f in chosen if f not in FORMATS]
    if bad or not chosen:
        raise SceneError(Problem("--format", text, "a comma-separated subset of " + ",".join(FORMATS)))
    return chosen


def _load(scene_path: Path, lang: str | None = None):
    from .report.i18n import available_languages
    from .scene import load_scene

    overrides = {"report": {"language": lang}} if lang else None
    scene = load_scene(scene_path, overrides)
    return scene, available_languages()


def _report(args) -> int:
    from . import outputs
    from .orchestrator import run_scene
    from .plugins import default_registry

    formats = _formats(args.format)
    stages = [s.strip() for s in args.stages.split(",")] if args.stages else None
    start = time.perf_counter()
    scene, languages = _load(args.scene, args.lang)
    registry = default_registry()
    result = run_scene(scene, registry, stages, languages)

    files: dict[str, bytes] = {}
    if "json" in formats:
        files["results.json"] = outputs.json_bytes(outputs.results_document(result))
    if "csv" in formats:
        files.update(outputs.csv_tables(result))
    if "html" in formats or "pdf" in formats:
        from .report.document import render_html

        rendered = render_html(result, registry)
        if "html" in formats:
            files["report.html"] = rendered.html.encode("utf-8")
            files.update({f"figures/{f.name}": f.svg for f in rendered.figures})
        if "pdf" in formats:
            from .report.pdf import html_to_pdf

            files["report.pdf"] = html_to_pdf(rendered.html)
    written = outputs.write_atomically(args.output, files)
    if not args.quiet:
        main_files = [p for p in written if p.parent == args.output]
        print(f"crankdyn: {len(written)} files in {args.output} ({time.perf_counter() - start:.2f} s): "
              + ", ".join(p.name for p in main_files))
        for name, reason in result.plan.skipped.items():
            print(f"  stage {name} left out: {reason}")
    return 0


def _check(args) -> int:
    from .orchestrator import check_scene, plan
    from .plugins import default_registry

    scene, languages = _load(args.scene)
    registry = default_registry()
    check_scene(scene, registry, languages)
    the_plan = plan(scene, registry)
    print(f"crankdyn: {args.scene} is valid; stages: {', '.join(s.name for s in the_plan.order)}")
    for name, reason in the_plan.skipped.items():
        print(f"  stage {name} left out: {reason}")
    return 0


def examples_dir() -> Path:
    return Path(str(resources.files("crankdyn.examples")))


def _example_names() -> dict[str, Path]:
    return {p.stem: p for p in sorted(examples_dir().glob("*.toml"))}


def _example(args) -> int:
    import tomllib

    names = _example_names()
    if args.list or not args.name:
        for name, path in names.items():
            title = tomllib.loads(path.read_text(encoding="utf-8")).get("report", {}).get("title", "")
            print(f"{name:28s} {title}")
        return 0
    if args.name not in names:
        raise SceneError(Problem("example", args.name, "unknown example; available: " + ", ".join(names)))
    source = names[args.name]
    text = source.read_bytes()
    target = args.output or Path(f"{args.name}.toml")
    from .outputs import write_atomically

    files = {target.name: text}
    # An example may refer to a data file next to it; bring it along so the copy runs.
    data = tomllib.loads(text.decode("utf-8")).get("cycle", {}).get("trace_file")
    if data:
        files[data] = (source.parent / data).read_bytes()
    write_atomically(target.parent if str(target.parent) else Path("."), files)
    print(f"crankdyn: wrote {target}" + (f" and {target.parent / data}" if data else ""))
    return 0


def _plugins(args) -> int:
    from .plugins import default_registry

    registry = default_registry()
    print("mechanisms:")
    for name, mech in sorted(registry.mechanisms.items()):
        print(f"  {name:24s} [{registry.owner['mechanism:' + name]}] {mech.summary}")
    print("stages:")
    for name, stage in sorted(registry.stages.items()):
        print(f"  {name:24s} [{registry.owner['stage:' + name]}] requires={','.join(stage.requires) or '-'} "
              f"provides={','.join(stage.provides) or '-'}{'' if stage.default else ' (optional)'}")
    from .report.i18n import available_languages

    print("languages: " + ", ".join(available_languages()))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
