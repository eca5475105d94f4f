"""Shared fixtures: bundled examples, a scene builder and a CLI runner."""

from __future__ import annotations

import copy
import functools
import gc
import json
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from crankdyn import cli
from crankdyn.cli import examples_dir

ARTIFACTS = Path(__file__).resolve().parent / "artifacts"

# The test processes run as the ``crankdyn`` command does (crankdyn.cli.run), unless the user chose:
# - one OpenBLAS thread: set here, in the process that starts the xdist workers, before they import
#   numpy (this one has: pytest-randomly imports it), and so also in the interpreters the tests start;
#   the stages' arrays are small, and the BLAS threads spin after each call on the core the other
#   worker needs (about 5 % of the suite's CPU time);
# - the young generation collected less often: the workers keep every shared run and report
#   (_shared_run, _shared_html) for the tests after, a large heap that each collection of the older
#   generations walks (about 8 % of the CPU time of the report-rendering test files).
os.environ.setdefault(cli.BLAS_THREADS_ENV, "1")
gc.set_threshold(cli.YOUNG_GENERATION_THRESHOLD, *gc.get_threshold()[1:])

ROOT = Path(__file__).resolve().parent.parent


def pytest_configure(config):
    """Byte-compile crankdyn and its built-in plugins once, before the workers start, into their
    ``__pycache__`` folders (ignored by git), as Python does unless told not to: with
    ``PYTHONDONTWRITEBYTECODE`` set (a fresh clone on a CI machine) each of the hundred-odd
    ``crankdyn`` processes the tests start would compile some 400 modules again, 0.25 s each
    (about a tenth of the suite's time). Up-to-date byte code is left as it is."""
    if hasattr(config, "workerinput"):
        return
    import compileall

    for folder in (ROOT / "src", ROOT / "plugins"):
        compileall.compile_dir(str(folder), quiet=1, workers=0)


@pytest.fixture(scope="session", autouse=True)
def _shared_objects_frozen_at_the_end():
    """What the tests keep to the end (the shared runs and notes with their drawn figures) is
    frozen out of the garbage collector after the last test: pytest then collects garbage once
    more to report exceptions raised in finalizers, and walking those objects took seconds in
    every worker."""
    yield
    gc.freeze()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """Under CI (``CRANKDYN_CI=1``, set by .ci/run) a test skipped because a system tool "is not
    installed" fails instead: .ci/setup.sh installs every tool, so a skip there would hide a broken
    setup (pandoc, LibreOffice, poppler-utils, chromium)."""
    outcome = yield
    report = outcome.get_result()
    if os.environ.get("CRANKDYN_CI") and report.skipped and "not installed" in str(report.longrepr):
        report.outcome = "failed"
        report.longrepr = f"CRANKDYN_CI: a system tool is missing: {report.longrepr}"


@pytest.hookimpl(trylast=True)
def pytest_collection_modifyitems(config, items):
    """Tests marked ``long`` (a PDF, a browser, a fresh virtual environment: 3-10 s each) go first,
    after pytest-randomly's shuffle, and with them their files (xdist hands out whole files in the
    order of their first test): started last, one of them kept a core busy for 10 s while the
    other had nothing left to take."""
    items.sort(
        key=lambda item: item.get_closest_marker("long") is None
    )  # stable: the shuffle stays


@pytest.fixture(scope="session")
def examples() -> Path:
    return examples_dir()


def example_data(name: str) -> dict:
    return tomllib.loads((examples_dir() / f"{name}.toml").read_text(encoding="utf-8"))


def write_scene(path: Path, data: dict) -> Path:
    """Write ``data`` as TOML (a tiny writer: tables of scalars and one level of subtables)."""
    lines: list[str] = []

    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    def table(name, body):
        lines.append(f"[{name}]")
        subs = []
        for k, v in body.items():
            if isinstance(v, dict):
                subs.append((f"{name}.{k}", v))
            else:
                lines.append(f"{k} = {value(v)}")
        lines.append("")
        for sub_name, sub_body in subs:
            table(sub_name, sub_body)

    for k, v in data.items():
        if not isinstance(v, dict):
            lines.insert(0, f"{k} = {value(v)}")
    for k, v in data.items():
        if isinstance(v, dict):
            table(k, v)
    path.write_text("\n".join(lines), encoding="utf-8")
    return path


#: The in-line four as a boxer (flat four, a crank pin per cylinder) with the firing-order explorer
#: on: the explorer's and table 1.1's texts of an engine whose cylinders share no pin.
EXPLORED_BOXER = {
    "engine": {
        "layout": "boxer",
        "crank_angles_deg": [0, 180, 180, 0],
        "firing_order": [1, 3, 2, 4],
    },
    "balancing": {"explore": True, "explore_top": 6},
}

#: The V8 example made a flat four (a boxer: a crank pin per cylinder, cranks chosen by the
#: calculation, 100 mm between neighbouring cylinders), laid over it with :func:`modified`.
FLAT_FOUR_ENGINE = {
    "layout": "boxer",
    "bank_angle_deg": None,
    "cylinders": 4,
    "firing_order": None,
    "crank_angles_deg": None,
    "cylinder_spacing": "100 mm",
}


#: The V8 example made a 45° V-twin: two cylinders whose rods sit side by side on one crank pin,
#: firing 405°/315° apart, laid over it with :func:`modified`.
V_TWIN_ENGINE = {
    "cylinders": 2,
    "bank_angle_deg": 45,
    "crank_angles_deg": [0],
    "firing_order": ["1L", "1R"],
    "uneven_firing": True,
    "cylinder_spacing": None,
}

#: The in-line three example made a twin with a 270° crank: firing 270°/450° apart, off the
#: even-firing grid of a twin (360°), laid over its [engine] with :func:`modified`.
TWIN_270_ENGINE = {
    "cylinders": 2,
    "firing_order": [1, 2],
    "crank_angles_deg": [0, 270],
    "uneven_firing": True,
}


def modified(name: str, changes: dict) -> dict:
    """Example ``name`` with ``changes`` laid over it; a value of None deletes the key."""
    data = copy.deepcopy(example_data(name))

    def apply(target, patch):
        for k, v in patch.items():
            if v is None:
                target.pop(k, None)
            elif isinstance(v, dict) and isinstance(target.get(k), dict):
                apply(target[k], v)
            else:
                target[k] = v

    apply(data, changes)
    return data


@functools.cache
def _shared_run(name: str, changes_json: str, stages: tuple[str, ...] | None):
    from crankdyn.engine.orchestrator import (
        run_scene,  # lazy: the heavy imports only for the tests that compute
    )
    from crankdyn.plugin.registry import default_registry
    from crankdyn.scene.model import scene_from_dict

    scene = scene_from_dict(modified(name, json.loads(changes_json)), base_dir=examples_dir())
    return run_scene(scene, default_registry(), None if stages is None else list(stages))


def shared_run(name: str, changes: dict | None = None, stages=None):
    """The run of example ``name`` (``changes`` laid over it, as :func:`modified`; ``stages`` as
    ``run_scene``'s ``requested``), computed once per test process and shared by every test file
    that asks for the same: READ ONLY (a test that changes what it got must copy it first)."""
    return _shared_run(
        name, json.dumps(changes or {}, sort_keys=True), None if stages is None else tuple(stages)
    )


@functools.cache
def _shared_html(
    name: str, changes_json: str, language: str | None, stages: tuple[str, ...] | None
):
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.document import render_html

    return render_html(_shared_run(name, changes_json, stages), default_registry(), language)


def shared_html(name: str, changes: dict | None = None, language: str | None = None, stages=None):
    """``render_html`` of :func:`shared_run` in ``language``, rendered once per test process: READ ONLY."""
    return _shared_html(
        name,
        json.dumps(changes or {}, sort_keys=True),
        language,
        None if stages is None else tuple(stages),
    )


def drawing_positions(scene):
    """The drawing stage's mechanism positions of ``scene``, computing only the stages they need
    (the drawing and what provides the kinematics)."""
    from crankdyn.engine.orchestrator import plan, run_scene  # lazy: only the drawing tests
    from crankdyn.plugin.registry import default_registry

    registry = default_registry()
    wanted = [
        s.name
        for s in plan(scene, registry).order
        if s.name == "drawing" or "kinematics" in s.provides
    ]
    return run_scene(scene, registry, wanted).outputs["drawing"].artifacts["positions"]


_REPORTS: dict = {}


@pytest.fixture(scope="session")
def shared_report(tmp_path_factory):
    """``report(example, language=None)``: the folder of ``crankdyn report EXAMPLE.toml --format html -q``
    (with ``--lang LANGUAGE`` if given) of a bundled example, written once per test process and shared
    by the test files that read it: READ ONLY."""
    from crankdyn.cli import main

    def report(example: str, language: str | None = None) -> Path:
        if (example, language) not in _REPORTS:
            out = tmp_path_factory.mktemp("shared_report") / example
            args = [
                "report",
                str(examples_dir() / f"{example}.toml"),
                "-o",
                str(out),
                "--format",
                "html",
                "-q",
            ]
            assert main(args + (["--lang", language] if language else [])) == 0
            _REPORTS[(example, language)] = out
        return _REPORTS[(example, language)]

    return report


def run_cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    return subprocess.run(
        [sys.executable, "-m", "crankdyn", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=300,
    )


#: One part of a broken formula (crankdyn.report.formula_lines): its text, tags other than spans,
#: and spans without further spans inside (a bracketed group, a carried sign).
_EQ_PART = r'<span class="eq-part">((?:[^<]+|<(?!/?span\b)[^>]*>|<span\b[^>]*>(?:[^<]+|<(?!/?span\b)[^>]*>)*</span>)*)</span>'


def formula_as_read(html: str) -> str:
    """``html`` with each formula's line markup undone: the carried-over signs dropped, the parts
    unwrapped, a forced line break read as a space (the formula as one line of text)."""
    import re

    html = re.sub(r'<span class="eq-carry">[^<]*</span>', "", html)
    html = html.replace('<br class="eq-break">', " ")
    return re.sub(_EQ_PART, lambda m: m.group(1), html)


def symbol_rows(html: str) -> list[str]:
    """The list of symbols' rows of a report, as read ("e<sub>z</sub> – …" → "ez – …")."""
    return [
        re.sub(r"<[^>]+>", "", row) for row in re.findall(r'<p class="symbol-row">(.*?)</p>', html)
    ]


def as_read(html: str) -> str:
    """The report's HTML as a reader's eye takes it: the line-break binders undone (the no-break
    spaces around an "=" before a number, the word joiner after a slash, the no-break space before
    an initial: ``unbreakable_html``). For tests that look for words."""
    import re

    html = html.replace("\u00a0=\u00a0", " = ").replace("\u2060", "")
    html = formula_as_read(html)
    html = re.sub(
        "(?<=[.\\w])\u00a0(?=[0-9]|[A-ZА-ЯІЇЄҐЁ]\\.[0-9])", " ", html
    )  # "рис.\u00a07.1": the number bound
    return re.sub(
        "\u00a0(?=[A-ZА-ЯІЇЄҐЁ]\\.)|(?<=[A-ZА-ЯІЇЄҐЁ]\\.)\u00a0(?=[A-ZА-ЯІЇЄҐЁ][a-zа-яіїєґё'’])",
        " ",
        html,
    )
