"""Batch robustness: a hung variant is stopped at its time limit, Ctrl-C still leaves an answer key,
row numbers count blank rows, formula-like text never reaches a spreadsheet live."""

from __future__ import annotations

import csv
import io
import time
from dataclasses import replace
from pathlib import Path

import pytest
from openpyxl import load_workbook

from crankdyn.batch.variants import neutralised, read_variants, run_batch
from crankdyn.cli import examples_dir
from crankdyn.plugin.registry import default_registry
from crankdyn.plugin.types import Stage, StageOutput, StagePresentation

BASE = examples_dir() / "kinematics-only.toml"
HANG_S = 60.0  # far beyond the test's time limit: finishing at all proves the variant was stopped
SLOW_RPM = 4444


MARKER_PREFIX = "finished-marker:"


def _maybe_hang(scene, inputs):
    if scene.engine.rpm == SLOW_RPM:
        time.sleep(HANG_S)
        # a variant that was stopped never gets here: a test may name a file that would tell
        if scene.report.subtitle.startswith(MARKER_PREFIX):
            Path(scene.report.subtitle[len(MARKER_PREFIX) :]).write_text(
                "finished", encoding="utf-8"
            )
    return StageOutput()


SLOW_STAGE = Stage(
    name="slow_for_test",
    requires=(),
    provides=(),
    applies=lambda scene: None,
    run=_maybe_hang,
    presentation=StagePresentation(title_key="kinematics.title", render=lambda output, ctx: None),
)


@pytest.fixture()
def slow_registry():
    registry = default_registry()
    return replace(registry, stages={**registry.stages, SLOW_STAGE.name: SLOW_STAGE})


def _csv(path, rpms, blank_after: int | None = None):
    lines = ["variant,engine.rpm,report.student"]
    for k, rpm in enumerate(rpms, start=1):
        lines.append(f"v{k},{rpm},Student {k}")
        if k == blank_after:
            lines += [
                "",
                ",,",
            ]  # an empty line and a row of empty cells: spreadsheet rows all the same
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.mark.slow  # waits out a 3 s time limit: in the slow tier, which CI runs
def test_a_hung_variant_is_stopped_and_listed_while_the_others_finish(tmp_path, slow_registry):
    variants = _csv(tmp_path / "v.csv", [3000, SLOW_RPM, 3500, 4000])
    out = tmp_path / "out"
    report = run_batch(
        variants, BASE, out, ["json"], jobs=2, progress=False, timeout=3.0, registry=slow_registry
    )
    assert report.seconds < HANG_S  # the hanging worker was killed, not waited for
    assert [(o.name, o.ok) for o in report.outcomes] == [
        ("v1", True),
        ("v2", False),
        ("v3", True),
        ("v4", True),
    ]
    assert "stopped after 3 s" in report.failures[0].error
    for name in ("v1", "v3", "v4"):
        assert (out / name / "results.json").is_file()
    key = list(csv.DictReader(io.StringIO((out / "answer_key.csv").read_text(encoding="utf-8"))))
    assert [r["variant"] for r in key] == ["v1", "v3", "v4"]
    failures = list(csv.DictReader(io.StringIO((out / "failures.csv").read_text(encoding="utf-8"))))
    assert [(f["variant"], f["row"]) for f in failures] == [("v2", "2")]


def test_ctrl_c_ends_cleanly_with_an_answer_key_for_what_finished(tmp_path, slow_registry):
    variants = _csv(tmp_path / "v.csv", [3000, SLOW_RPM, SLOW_RPM])

    def interrupt_after_first(outcome):
        raise KeyboardInterrupt  # what Ctrl-C does in the parent while it waits

    out = tmp_path / "out"
    report = run_batch(
        variants,
        BASE,
        out,
        ["json"],
        jobs=1,
        progress=False,
        timeout=HANG_S,
        on_outcome=interrupt_after_first,
        registry=slow_registry,  # forked workers inherit the run's registry
    )
    assert report.interrupted and report.seconds < HANG_S
    assert [(o.name, o.ok) for o in report.outcomes] == [("v1", True), ("v2", False), ("v3", False)]
    assert all("interrupted" in o.error for o in report.failures)
    assert (out / "answer_key.csv").is_file() and (out / "failures.csv").is_file()


def test_row_numbers_count_blank_rows_as_a_spreadsheet_does(tmp_path):
    _, variants = read_variants(_csv(tmp_path / "v.csv", [3000, 3100, 3200], blank_after=1))
    # data rows 1, (2 and 3 blank), 4, 5: the numbers a teacher sees beside the spreadsheet's rows
    assert [(v.name, v.row) for v in variants] == [("v1", 1), ("v2", 4), ("v3", 5)]


@pytest.mark.parametrize(
    "text, expected",
    [
        ('=HYPERLINK("http://x","y")', '\'=HYPERLINK("http://x","y")'),
        ("+1", "'+1"),
        ("-A1", "'-A1"),
        ("@SUM(A1)", "'@SUM(A1)"),
        ("\tx", "'\tx"),
        ("\rx", "'\rx"),
        ("Ivanenko", "Ivanenko"),
        (-5.0, -5.0),
    ],
)
def test_formula_like_text_is_neutralised(text, expected):
    assert neutralised(text) == expected


def test_answer_key_never_holds_a_live_formula(tmp_path):
    path = tmp_path / "v.csv"
    path.write_text(
        'variant,engine.rpm,report.student\nv1,3000,"=HYPERLINK(""http://evil"",""click"")"\n'
        "v2,3500,@SUM(A1)\n",
        encoding="utf-8",
    )
    out = tmp_path / "out"
    run_batch(path, BASE, out, ["json"], jobs=1, progress=False)
    text = (out / "answer_key.csv").read_text(encoding="utf-8")
    assert "'=HYPERLINK" in text and "\n=" not in text and ",=" not in text
    workbook = load_workbook(out / "answer_key.xlsx")
    cells = [c.value for sheet in workbook for row in sheet.iter_rows() for c in row]
    assert '\'=HYPERLINK("http://evil","click")' in cells
    assert not any(isinstance(c, str) and c.startswith(("=", "@", "+", "-")) for c in cells)
    assert "'@SUM(A1)" in cells


def test_a_hostile_cell_fails_its_row_only(tmp_path):
    path = tmp_path / "v.csv"
    path.write_text(
        "variant,engine.bore,report.student\n"
        f"deep,{'[' * 3000}{']' * 3000},x\nexpr,9**9**9 mm,y\nok,81 mm,z\n",
        encoding="utf-8",
    )
    report = run_batch(path, BASE, tmp_path / "out", ["json"], jobs=1, progress=False, timeout=60)
    assert [(o.name, o.ok) for o in report.outcomes] == [
        ("deep", False),
        ("expr", False),
        ("ok", True),
    ]
    assert all("engine.bore" in o.error and "internal" not in o.error for o in report.failures)
