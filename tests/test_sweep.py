"""``crankdyn sweep``: ranges of scene fields -> the Cartesian product through the batch pipeline,
the answer key as CSV/XLSX/Parquet and a plot of one result column over the grid."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pandas as pd
import pytest
from conftest import run_cli

from crankdyn.batch.sweep import (
    SweepRequest,
    parse_values,
    read_sweep_file,
    run_sweep,
    sweep_from_args,
)
from crankdyn.batch.variants import RunOptions
from crankdyn.cli import examples_dir, main
from crankdyn.errors import SceneError

KINEMATICS = examples_dir() / "kinematics-only.toml"  # R = 50 mm, S = 100 mm, rod_length = 200 mm
SWEEP_FILE = Path(__file__).resolve().parent.parent / "examples" / "sweeps" / "bore-rod-ratio.toml"


@pytest.mark.parametrize(
    "text, values, numbers, unit",
    [
        ("2000:6000:5", [2000, 3000, 4000, 5000, 6000], [2000, 3000, 4000, 5000, 6000], ""),
        ("0.25:0.31:step=0.02", [0.25, 0.27, 0.29, 0.31], [0.25, 0.27, 0.29, 0.31], ""),
        ("76 mm:88 mm:4", ["76 mm", "80 mm", "84 mm", "88 mm"], [76, 80, 84, 88], "mm"),
        ("76:88:4 mm", ["76 mm", "80 mm", "84 mm", "88 mm"], [76, 80, 84, 88], "mm"),
        ("76mm:80mm:step=2", ["76 mm", "78 mm", "80 mm"], [76, 78, 80], "mm"),
        ("6000:2000:3", [6000, 4000, 2000], [6000, 4000, 2000], ""),
        ("0.26,0.28,0.3", [0.26, 0.28, 0.3], [0.26, 0.28, 0.3], ""),
        ("5.5 MPa,6 MPa", ["5.5 MPa", "6 MPa"], [5.5, 6.0], "MPa"),
        (
            "1000:2000:4",
            [1000, 1333.33333333, 1666.66666667, 2000],
            [1000, 1333.33333333, 1666.66666667, 2000],
            "",
        ),
    ],
)
def test_ranges_and_lists(text, values, numbers, unit):
    axis = parse_values("f.x", text)
    assert axis.values == pytest.approx(values) if not unit else axis.values == values
    assert axis.numbers == pytest.approx(numbers) and axis.unit == unit
    assert axis.column == (f"f.x [{unit}]" if unit else "f.x")


@pytest.mark.parametrize(
    "text, message",
    [
        ("2000:6000:1", "whole number >= 2"),
        ("2000:6000:2.5", "whole number >= 2"),
        ("2000:6000", "START:STOP:COUNT"),
        ("76 mm:0.088 m:3", "one unit"),
        ("2000:2000:3", "equal"),
        ("2000:6000:step=-500", "lead from"),
        ("2000:6000:step=0", "non-zero"),
        ("fast:slow:3", "must be a number"),
        ("0.26,0.26", "listed twice"),
        ("", "give values"),
    ],
)
def test_bad_ranges_name_the_field(text, message):
    with pytest.raises(SceneError) as info:
        parse_values("engine.rpm", text)
    assert "engine.rpm" in str(info.value) and message in str(info.value)


def _request(
    tmp_path, sets, plot=None, key=("csv", "xlsx", "parquet"), plot_formats=("svg",), **options
):
    sweep = sweep_from_args(sets, None, plot, None)
    options = RunOptions(["json"], jobs=2, progress=False, stages=["kinematics"], **options)
    return SweepRequest(KINEMATICS, sweep, tmp_path / "out", options, list(key), list(plot_formats))


def test_the_cartesian_product_in_order_with_closed_form_results(tmp_path):
    rpms, ratios = [2000, 3000, 4000], [0.25, 0.3]
    request = _request(
        tmp_path,
        ["engine.rpm=2000:4000:3", "engine.rod_ratio=0.25,0.3", "report.student=Anna"],
        plot="j_max_m_s2",
    )
    report, notes = run_sweep(request)
    assert not report.failures and len(report.outcomes) == 6
    assert notes == [
        "engine.rod_length of the base scene is left out: the sweep sets engine.rod_ratio"
    ]
    key = pd.read_csv(tmp_path / "out" / "answer_key.csv")
    assert key["variant"].tolist() == [f"p{k:02d}" for k in range(1, 7)] and key[
        "row"
    ].tolist() == list(range(1, 7))
    # the first field varies slowest; every combination exactly once
    assert list(zip(key["engine.rpm"], key["engine.rod_ratio"], strict=True)) == [
        (n, r) for n in rpms for r in ratios
    ]
    assert "report.student" not in key  # a field set for every point is not a key column
    for _, row in key.iterrows():
        omega = math.pi * row["engine.rpm"] / 30
        # central crank-slider, R = 50 mm: j_max = R*omega^2*(1 + lambda) at TDC; v_mean = S*n/30
        assert row["j_max_m_s2"] == pytest.approx(
            0.05 * omega**2 * (1 + row["engine.rod_ratio"]), rel=1e-5
        )
        assert row["v_mean_m_s"] == pytest.approx(0.1 * row["engine.rpm"] / 30, rel=1e-5)
    # the per-point results really came from each point's own scene (JSON was asked for)
    assert (tmp_path / "out" / "p04" / "results.json").is_file()
    book = pd.read_excel(
        tmp_path / "out" / "answer_key.xlsx", header=1
    )  # row 1: the columns' labels
    parquet = pd.read_parquet(tmp_path / "out" / "answer_key.parquet")
    pd.testing.assert_series_equal(book["j_max_m_s2"], key["j_max_m_s2"], rtol=1e-5)
    pd.testing.assert_series_equal(parquet["j_max_m_s2"], key["j_max_m_s2"], rtol=1e-5)
    assert parquet["engine.rpm"].dtype.kind == "i" and parquet["engine.rod_ratio"].dtype.kind == "f"

    svg = (tmp_path / "out" / "sweep-j_max_m_s2.svg").read_text(encoding="utf-8")
    texts = set(re.findall(r"<text[^>]*>([^<]*)</text>", svg))  # text stays text, not glyph paths
    assert {
        "engine.rpm",
        "j_max_m_s2, m/s²",
        "engine.rod_ratio = 0.25",
        "engine.rod_ratio = 0.3",
    } <= texts
    assert "DejaVuSans-" not in svg  # no glyphs drawn as outlines


def test_units_in_a_range_give_numeric_key_columns_and_a_png(tmp_path):
    request = _request(
        tmp_path, ["engine.bore=70:90:3 mm"], plot="v_mean_m_s", key=("csv",), plot_formats=("png",)
    )
    request.options.formats = []  # no per-point files: the key and the plot only
    report, _ = run_sweep(request)
    key = pd.read_csv(tmp_path / "out" / "answer_key.csv")
    assert key["engine.bore [mm]"].tolist() == [70, 80, 90]
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        ".crankdyn-manifest.json",
        "answer_key.csv",
        "sweep-v_mean_m_s.png",
    ]
    assert (tmp_path / "out" / "sweep-v_mean_m_s.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_bundled_sweep_file(tmp_path):
    sweep = read_sweep_file(SWEEP_FILE)
    assert [(a.name, a.values) for a in sweep.axes] == [
        ("engine.bore", ["76 mm", "80 mm", "84 mm", "88 mm"]),
        ("engine.rod_ratio", [0.26, 0.28, 0.30]),
    ]
    assert sweep.fixed == {"engine.rpm": 5600} and sweep.points == 12
    assert (sweep.plot_y, sweep.plot_x) == ("M_cylinder_max_Nm", "engine.bore")
    # --set replaces a field of the file and adds another
    merged = sweep_from_args(
        ["engine.rod_ratio=0.3", "engine.rpm=4000,5000"], SWEEP_FILE, None, None
    )
    assert [a.name for a in merged.axes] == ["engine.bore", "engine.rpm"]
    assert merged.fixed == {"engine.rod_ratio": 0.3} and merged.points == 8


@pytest.mark.parametrize(
    "args, field, message",
    [
        (["--set", "engine.rpm=2000:6000:1"], "engine.rpm", "whole number >= 2"),
        (["--set", "engine.bore=76 mm:0.088 m:3"], "engine.bore", "one unit"),
        (
            ["--set", "engine.bore=-10 mm:80 mm:3"],
            "engine.bore",
            ">= 0.1 mm",
        ),  # a value the scene refuses, before any run
        (["--set", "engine.boer=70 mm,80 mm"], "boer", "bore"),
        (["--set", "engine..rpm=1,2"], "engine..rpm", "dotted scene path"),
        (["--set", "engine.rpm"], "--set", "NAME=VALUES"),
        (["--set", "engine.rpm=3000"], "--set", "nothing to sweep"),
        (["--set", "engine.rpm=1000,2000", "--plot", "j_maximum"], "--plot", "j_max_m_s2"),
        (
            ["--set", "engine.rpm=1000,2000", "--plot", "j_max_m_s2", "--plot-x", "engine.bore"],
            "--plot-x",
            "engine.rpm",
        ),
        (
            [
                "--set",
                "engine.rpm=1000:2000:13",
                "--set",
                "engine.bore=70mm,80mm",
                "--plot",
                "j_max_m_s2",
                "--plot-x",
                "engine.bore",
            ],
            "--plot",
            "at most 12",
        ),
        (["--set", "engine.rpm=1000,2000", "--key", "csv,ods"], "--key", "csv,xlsx,parquet"),
    ],
)
def test_bad_sweeps_exit_2_naming_the_field_and_write_nothing(
    tmp_path, capsys, args, field, message
):
    # the command's own main in this process (the bundled sweep below runs the command itself)
    try:
        code = main(["sweep", str(KINEMATICS), "-o", str(tmp_path / "out"), *args])
    except SystemExit as exit_:  # the argument parser's refusal
        code = exit_.code
    stderr = capsys.readouterr().err
    assert code == 2, stderr
    assert field in stderr and message in stderr, stderr
    assert "Traceback" not in stderr and not (tmp_path / "out").exists()


def test_a_bad_sweep_file_is_refused(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        '[sweep]\n"engine.rpm" = { from = 1000, to = 2000 }\n[plots]\ny = "x"\n', encoding="utf-8"
    )
    with pytest.raises(SceneError) as info:
        read_sweep_file(path)
    assert "plots" in str(info.value) and "unknown table" in str(info.value)
    path.write_text('[sweep]\n"engine.rpm" = { from = 1000, to = 2000 }\n', encoding="utf-8")
    with pytest.raises(SceneError) as info:
        read_sweep_file(path)
    assert "engine.rpm" in str(info.value) and "count = N" in str(info.value)


def test_the_sweep_command_runs_the_bundled_file(tmp_path):
    done = run_cli(
        "sweep",
        str(examples_dir() / "petrol-1cyl.toml"),
        "--grid",
        str(SWEEP_FILE),
        "-o",
        str(tmp_path / "study"),
        "--set",
        "engine.bore=80 mm,84 mm",
        "--set",
        "engine.rod_ratio=0.26,0.3",
        "--stages",
        "kinematics,indicator,forces",
        "-q",
    )
    assert done.returncode == 0, done.stderr
    assert "4 of 4 points computed" in done.stdout
    key = pd.read_csv(tmp_path / "study" / "answer_key.csv")
    assert key["engine.bore [mm]"].tolist() == [80, 80, 84, 84]
    # p_j at TDC per piston area: m_j*R*omega^2*(1+lambda)/F_p, m_j = piston group + 0.275 of the rod
    omega = math.pi * 5600 / 30
    for _, row in key.iterrows():
        area = math.pi * (row["engine.bore [mm]"] / 1000) ** 2 / 4
        mass = 0.45 + 0.275 * 0.60
        expected = -mass * 0.039 * omega**2 * (1 + row["engine.rod_ratio"]) / area / 1e6
        assert row["p_j_tdc_MPa"] == pytest.approx(expected, rel=1e-4)
    assert (tmp_path / "study" / "sweep-M_cylinder_max_Nm.svg").is_file()
    assert not [
        p for p in (tmp_path / "study").iterdir() if p.is_dir()
    ]  # no per-point files by default


def test_a_combination_bad_only_together_is_a_failure_row_not_a_refusal(tmp_path):
    request = _request(
        tmp_path,
        ["engine.stroke=100mm,300mm", "engine.rod_length=120mm,400mm"],
        plot="v_max_m_s",
        key=("csv",),
    )
    report, _ = run_sweep(
        request
    )  # 120 mm suits the 100 mm stroke, not the 300 mm one (R = 150 mm)
    assert [(o.name, o.ok) for o in report.outcomes] == [
        ("p01", True),
        ("p02", True),
        ("p03", False),
        ("p04", True),
    ]
    assert (
        "engine.rod_length" in report.failures[0].error
        and "crank radius" in report.failures[0].error
    )
    failures = pd.read_csv(tmp_path / "out" / "failures.csv")
    assert failures["row"].tolist() == [3]
    key = pd.read_csv(tmp_path / "out" / "answer_key.csv")
    assert list(zip(key["engine.stroke [mm]"], key["engine.rod_length [mm]"], strict=True)) == [
        (100, 120),
        (100, 400),
        (300, 400),
    ]
    assert (tmp_path / "out" / "sweep-v_max_m_s.svg").is_file()  # drawn with a gap where p03 failed
