"""``crankdyn batch``: one report per student variant, an answer key, failures listed and isolated."""

from __future__ import annotations

import csv
import io
import json
import math
import re

import pandas as pd
import pytest
from conftest import as_read, run_cli

from crankdyn.batch.variants import parse_cell, read_variants, run_batch
from crankdyn.cli import examples_dir
from crankdyn.errors import SceneError

BROKEN = {7: ("engine.bore", "-82 mm"), 19: ("cycle.max_pressure", "1.0 MPa")}


def _variants_csv(path, n=30):
    """n students: speed, piston mass and peak pressure vary; rows in BROKEN get a bad value."""
    header = [
        "variant",
        "report.student",
        "engine.rpm",
        "engine.bore",
        "masses.piston_group",
        "cycle.max_pressure",
    ]
    rows = []
    for k in range(1, n + 1):
        row = {
            "variant": f"v{k:02d}",
            "report.student": f"Студент {k}",
            "engine.rpm": str(4000 + 100 * k),
            "engine.bore": "",
            "masses.piston_group": f"{0.40 + 0.01 * k:.2f} kg",
            "cycle.max_pressure": f"{5.0 + 0.1 * k:.1f} MPa",
        }
        if k in BROKEN:
            field, value = BROKEN[k]
            row[field] = value
        rows.append(row)
    with open(path, "w", encoding="utf-8", newline="") as fh:
        writer = csv.DictWriter(fh, header)
        writer.writeheader()
        writer.writerows(rows)
    return path


# a batch of 30 variants: in the slow tier, which CI runs
@pytest.mark.slow
def test_batch_of_30_with_two_broken_rows(tmp_path):
    variants = _variants_csv(tmp_path / "variants.csv")
    out = tmp_path / "out"
    done = run_cli(
        "batch",
        str(variants),
        "--base",
        str(examples_dir() / "petrol-1cyl.toml"),
        "-o",
        str(out),
        "--format",
        "json,csv",
        "--jobs",
        "2",
        "--stages",
        "kinematics,indicator,forces,torque",
    )
    assert done.returncode == 2, done.stderr  # some rows failed
    assert "28 of 30 variants written" in done.stdout
    # Progress on stderr, then the failures, clearly, at the end.
    assert "30/30" in done.stderr
    tail = done.stderr[done.stderr.index("2 variant(s) failed") :]
    assert "row 7 (v07)" in tail and "engine.bore" in tail
    assert "row 19 (v19)" in tail and "cycle.max_pressure" in tail

    folders = sorted(p.name for p in out.iterdir() if p.is_dir())
    assert folders == [f"v{k:02d}" for k in range(1, 31) if k not in BROKEN]
    for name in folders:
        assert (out / name / "results.json").is_file() and (
            out / name / "tables" / "forces.csv"
        ).is_file()
        assert not (out / name / "report.html").exists()  # only the formats asked for
    assert not list(out.rglob("*.tmp"))

    failures = list(csv.DictReader(io.StringIO((out / "failures.csv").read_text(encoding="utf-8"))))
    assert [(f["variant"], f["row"]) for f in failures] == [("v07", "7"), ("v19", "19")]
    assert "engine.bore" in failures[0]["error"] and "cycle.max_pressure" in failures[1]["error"]

    key = pd.read_csv(out / "answer_key.csv")
    assert key["variant"].tolist() == folders
    assert key["report.student"].tolist()[:2] == ["Студент 1", "Студент 2"]
    for _, row in key.iterrows():
        results = json.loads((out / row["variant"] / "results.json").read_text(encoding="utf-8"))
        assert row["v_max_m_s"] == pytest.approx(results["kinematics"]["v_max_m_s"], rel=1e-5)
        assert row["p_max_MPa"] == pytest.approx(
            results["indicator"]["max_pressure_Pa"] / 1e6, rel=1e-5
        )
        assert row["M_cylinder_mean_Nm"] == pytest.approx(
            results["forces"]["mean_torque_Nm"], rel=1e-5
        )
        # Independent of the code: j_max = R*omega^2*(1 + lambda) for this variant's speed (R = 39 mm, lambda = 0.28).
        omega = math.pi * row["engine.rpm"] / 30
        assert row["j_max_m_s2"] == pytest.approx(0.039 * omega**2 * 1.28, rel=1e-5)
    # Each variant really got its own data: the peak pressure follows its p_z, the speed its rpm.
    assert key["engine.rpm"].tolist() == [4000 + 100 * int(v[1:]) for v in folders]
    assert key["j_max_m_s2"].is_monotonic_increasing
    # The workbook holds the same answer key (numbers as numbers) and the failures.
    # The answer-key sheet has the columns' labels above their names (row 2).
    assert pd.ExcelFile(out / "answer_key.xlsx").sheet_names == ["answer key", "failures"]
    book = pd.read_excel(out / "answer_key.xlsx", sheet_name="answer key", header=1)
    labels = pd.read_excel(out / "answer_key.xlsx", sheet_name="answer key", nrows=0).columns
    assert labels[list(book.columns).index("j_max_m_s2")] == "Maximum piston acceleration, m/s²"
    pd.testing.assert_series_equal(book["j_max_m_s2"], key["j_max_m_s2"], rtol=1e-5)
    failed = pd.read_excel(out / "answer_key.xlsx", sheet_name="failures")
    assert failed["variant"].tolist() == ["v07", "v19"]


def test_parse_cell_reads_toml_values():
    assert parse_cell("82") == 82 and isinstance(parse_cell("82"), int)
    assert parse_cell("0.28") == 0.28
    assert parse_cell("true") is True
    assert parse_cell("[1, 3, 4, 2]") == [1, 3, 4, 2]
    assert parse_cell('"82"') == "82"
    assert parse_cell("82 mm") == "82 mm"
    assert parse_cell(" Іваненко І. ") == "Іваненко І."


def test_read_variants_overrides_ids_and_decimal_comma(tmp_path):
    path = tmp_path / "v.csv"
    path.write_text(
        "variant;engine.rpm;engine.rod_ratio;report.student;cycle.rounding.ignition_advance_deg\n"
        "a/1;5600;0,3;Петренко, П.;\n"
        ";4800;;Шевчук;25\n"
        "a/1;5000;0,25;Дубль;\n",
        encoding="utf-8-sig",
    )
    fields, variants = read_variants(path)
    assert fields == [
        "engine.rpm",
        "engine.rod_ratio",
        "report.student",
        "cycle.rounding.ignition_advance_deg",
    ]
    first, second, third = variants
    assert first.name == "a_1" and first.error is None
    assert first.overrides == {
        "engine": {"rpm": 5600, "rod_ratio": 0.3},
        "report": {"student": "Петренко, П."},
    }
    assert second.name == "02"  # no id: the row number
    assert second.overrides == {
        "engine": {"rpm": 4800},
        "report": {"student": "Шевчук"},
        "cycle": {"rounding": {"ignition_advance_deg": 25}},
    }  # empty cells keep the base
    assert third.error and "unique" in third.error and third.name != first.name


@pytest.mark.parametrize(
    "text, message",
    [
        ("", "empty file"),
        ("variant,engine.rpm,engine.rpm\nx,1,2\n", "named twice"),
        ("variant,,engine.rpm\nx,1,2\n", "empty column name"),
        ("engine,engine.rpm\n1,2\n", "conflicts"),
        ("variant,engine..rpm\nx,1\n", "dotted scene path"),
        ("variant\nx\n", "no column"),
    ],
)
def test_malformed_variants_file_is_refused_as_a_whole(tmp_path, text, message):
    path = tmp_path / "v.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(SceneError) as info:
        read_variants(path)
    assert message in str(info.value)


def test_in_process_batch_isolates_a_failure_and_writes_nothing_for_it(tmp_path):
    path = tmp_path / "v.csv"
    path.write_text("variant,engine.rpm,engine.boer\nok,5000,\nbad,5000,82 mm\n", encoding="utf-8")
    out = tmp_path / "out"
    report = run_batch(
        path, examples_dir() / "kinematics-only.toml", out, ["json"], jobs=1, progress=False
    )
    assert [o.name for o in report.failures] == ["bad"]
    assert "did you mean 'bore'" in report.failures[0].error
    assert (out / "ok" / "results.json").is_file() and not (out / "bad").exists()
    key = list(csv.DictReader(io.StringIO((out / "answer_key.csv").read_text(encoding="utf-8"))))
    assert [r["variant"] for r in key] == ["ok"] and "p_max_MPa" not in key[
        0
    ]  # kinematics only: no pressure column
    # A later run without failures removes the stale failures.csv.
    path.write_text("variant,engine.rpm\nok,5000\n", encoding="utf-8")
    assert not run_batch(
        path, examples_dir() / "kinematics-only.toml", out, ["json"], jobs=1, progress=False
    ).failures
    assert not (out / "failures.csv").exists()


def test_batch_cli_refuses_a_missing_base_scene(tmp_path):
    path = tmp_path / "v.csv"
    path.write_text("engine.rpm\n5000\n", encoding="utf-8")
    done = run_cli(
        "batch", str(path), "--base", str(tmp_path / "nope.toml"), "-o", str(tmp_path / "o")
    )
    assert (
        done.returncode == 2 and "file not found" in done.stderr and "Traceback" not in done.stderr
    )
    assert not (tmp_path / "o").exists()


def test_each_variant_title_page_names_its_own_variant_and_student(tmp_path):
    """The batch writes each student's own title page (HTML only, no PDF)."""
    path = tmp_path / "v.csv"
    path.write_text(
        "variant,report.student,engine.rpm\n3,Шевченко Т. Г.,4000\n14,Коваленко І. А.,4500\n",
        encoding="utf-8",
    )
    out = tmp_path / "out"
    report = run_batch(
        path,
        examples_dir() / "petrol-1cyl-uk.toml",
        out,
        ["html"],
        jobs=1,
        language="uk",
        stages=["kinematics"],
        progress=False,
    )
    assert not report.failures
    students = {"3": "Шевченко Т. Г.", "14": "Коваленко І. А."}
    for variant, student in students.items():
        html = (out / variant / "report.html").read_text(encoding="utf-8")
        title = as_read(
            re.search(r'<section class="title-page">.*?</section>', html, flags=re.S).group(0)
        )
        assert f'<div class="variant">Варіант {variant}</div>' in title
        assert f'<td class="name">{student}</td>' in title
        other = next(s for v, s in students.items() if v != variant)
        assert other not in html and "Іваненко" not in title  # not the base scene's student
