"""Resource limits and meaningless values: every case exits 2 naming the field, the value and
the limit, with no traceback and nothing written; the Python API raises SceneError or TypeError
with the command line's messages."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import example_data, modified, write_scene

import crankdyn
from crankdyn.cli import main
from crankdyn.physics import firing_explorer
from crankdyn.physics import pressure_trace as trace
from crankdyn.scene.model import MAX_SCENE_BYTES

ROOT = Path(__file__).resolve().parent.parent
KINEMATICS_ONLY = ROOT / "examples" / "kinematics-only.toml"
INT64_MAX = 9223372036854775807  # TOML's largest integer, 2^63 - 1


def _refused(capsys, argv: list[str], *expected: str) -> str:
    code = main(argv)
    captured = capsys.readouterr()
    assert code == 2, captured
    for text in expected:
        assert text in captured.err, captured.err
    assert "Traceback" not in captured.err and 'File "' not in captured.err
    assert "internal error" not in captured.err
    return captured.err


def _check_refused(tmp_path: Path, capsys, changes: dict, *expected: str) -> str:
    scene = write_scene(tmp_path / "scene.toml", modified("kinematics-only", changes))
    return _refused(capsys, ["check", str(scene)], *expected)


# --------------------------------------------------------------------------- scene values


def test_title_longer_than_the_limit_is_refused(tmp_path, capsys):
    title = "T" * 1001
    err = _check_refused(
        tmp_path,
        capsys,
        {"report": {"title": title}},
        "report.title = 'TTTT",
        "at most 1000 characters",
        "(it has 1001)",
    )
    assert title not in err  # the value is shortened in the message


def test_bytes_title_longer_than_the_limit_is_refused():
    with pytest.raises(crankdyn.SceneError, match=r"report.title = b'TTT.*at most 1000 characters"):
        crankdyn.load(KINEMATICS_ONLY, {"report.title": b"T" * 1001})


def test_title_at_the_limit_is_accepted():
    scene = crankdyn.load(KINEMATICS_ONLY, {"report.title": "T" * 1000})
    assert scene.report.title == "T" * 1000


def test_scene_file_larger_than_the_limit_is_refused(tmp_path, capsys):
    scene = tmp_path / "big.toml"
    text = KINEMATICS_ONLY.read_text(encoding="utf-8")
    padding = "x" * (1_000_001 - len(text.encode()) - 3)
    scene.write_text(text + "# " + padding + "\n", encoding="utf-8")
    assert scene.stat().st_size == 1_000_001 == MAX_SCENE_BYTES + 1
    _refused(capsys, ["check", str(scene)], "scene = ", "at most 1000000 bytes", "(it has 1000001)")


def test_integer_of_400_digits_is_refused_naming_the_field(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    text = KINEMATICS_ONLY.read_text(encoding="utf-8")
    assert "\nrpm = " in text
    head, tail = text.split("\nrpm = ", 1)
    rest = tail.split("\n", 1)[1]
    scene.write_text(head + "\nrpm = " + "9" * 400 + "\n" + rest, encoding="utf-8")
    _refused(
        capsys,
        ["check", str(scene)],
        "engine.rpm = 99999999999999999999... (400 digits)",
        str(INT64_MAX),
    )


def test_integer_beyond_pythons_text_conversion_is_refused(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(
        "x = " + "7" * 5000 + "\n" + KINEMATICS_ONLY.read_text(encoding="utf-8"), encoding="utf-8"
    )
    _refused(capsys, ["check", str(scene)], "scene = ", "2^63 - 1")


@pytest.mark.parametrize(
    "value, shown", [(2**63, "9223372036854775808"), (-(2**63) - 1, "-9223372036854775809")]
)
def test_integers_just_outside_64_bits_are_refused(value, shown):
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(KINEMATICS_ONLY, {"engine.cylinders": value})
    assert f"engine.cylinders = {shown}: an integer must lie between" in str(caught.value)


@pytest.mark.parametrize("kind", [list, tuple])
def test_array_longer_than_the_limit_is_refused(kind):
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(KINEMATICS_ONLY, {"engine.crank_angles_deg": kind([0] * 10_001)})
    expected = (
        "engine.crank_angles_deg = '(an array of 10001 items)': an array may hold at most 10000"
    )
    assert expected in str(caught.value)


def test_table_with_more_keys_than_the_limit_is_refused():
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(KINEMATICS_ONLY, {"engine": {f"k{n}": n for n in range(10_001)}})
    expected = "engine = '(a table of 10001 keys)': a table may hold at most 10000 keys"
    assert expected in str(caught.value)


def test_key_longer_than_the_limit_is_refused():
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(KINEMATICS_ONLY, {"engine": {"k" * 101: 1}})
    message = str(caught.value)
    assert "a key may be at most 100 characters long" in message and "k" * 101 not in message


# --------------------------------------------------------------------------- meaningless values


def test_subnormal_rpm_is_refused(tmp_path, capsys):
    _check_refused(
        tmp_path,
        capsys,
        {"engine": {"rpm": 5e-324}},
        "engine.rpm = 5e-324",
        "too close to zero to compute with (below 2.23e-308)",
    )


def test_rpm_below_one_is_refused(tmp_path, capsys):
    _check_refused(
        tmp_path, capsys, {"engine": {"rpm": 0.5}}, "engine.rpm = 0.5: must be >= 1 and <= 30000"
    )


def test_float_literal_that_underflows_to_zero_is_refused(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    text = KINEMATICS_ONLY.read_text(encoding="utf-8")
    head, tail = text.split("\nrpm = ", 1)
    scene.write_text(head + "\nrpm = 1e-400\n" + tail.split("\n", 1)[1], encoding="utf-8")
    _refused(capsys, ["check", str(scene)], "engine.rpm = '1e-400'", "too close to zero")


@pytest.mark.parametrize("bore", ["1e-320 mm", "1e-310 um", "1e-400 mm"])
def test_quantity_that_underflows_in_si_is_refused(tmp_path, capsys, bore):
    _check_refused(
        tmp_path, capsys, {"engine": {"bore": bore}}, f"engine.bore = '{bore}'", "too close to zero"
    )


def test_bore_below_a_tenth_of_a_millimetre_is_refused(tmp_path, capsys):
    _check_refused(
        tmp_path,
        capsys,
        {"engine": {"bore": "0.09 mm"}},
        "engine.bore = '0.09 mm': must be >= 0.1 mm",
    )


def test_tiny_rod_ratio_is_refused(tmp_path, capsys):
    _check_refused(
        tmp_path,
        capsys,
        {"engine": {"rod_ratio": 1e-300, "rod_length": None}},
        "engine.rod_ratio = 1e-300: must be >= 1e-06",
    )


def test_subnormal_in_a_plugin_table_is_refused():
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(KINEMATICS_ONLY, {"numerics.tolerance": 5e-324})
    assert "numerics.tolerance = 5e-324: is too close to zero" in str(caught.value)


@pytest.mark.long
def test_smallest_engine_accepted_computes_without_numeric_warnings(tmp_path):
    """The lower limits together (0.1 mm, 1 rpm, lambda 1e-6, 1 mg): every stage runs and numpy
    warns of nothing (a RuntimeWarning is turned into an error here)."""
    scene = write_scene(
        tmp_path / "tiny.toml",
        modified(
            "petrol-1cyl",
            {
                "engine": {"bore": "0.1 mm", "stroke": "0.1 mm", "rpm": 1, "rod_ratio": 1e-6},
                "masses": {
                    "piston_group": "1e-6 kg",
                    "rod": "1e-6 kg",
                    "crank_pin": "0 kg",
                    "crank_web": "0 kg",
                },
            },
        ),
    )
    env = {**os.environ, "PYTHONWARNINGS": "error::RuntimeWarning"}
    done = subprocess.run(
        [sys.executable, "-m", "crankdyn", "check", str(scene)],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert "Warning" not in done.stderr and 'File "' not in done.stderr


def test_refusal_in_a_separate_process_shows_no_warning_or_path(tmp_path):
    scene = write_scene(
        tmp_path / "scene.toml", modified("petrol-1cyl", {"engine": {"rpm": 5e-324}})
    )
    argv = [sys.executable, "-m", "crankdyn", "report", str(scene), "-o", str(tmp_path / "out")]
    done = subprocess.run(argv, capture_output=True, text=True, timeout=300)
    assert done.returncode == 2
    assert done.stderr.startswith("crankdyn: invalid scene")
    assert "engine.rpm = 5e-324" in done.stderr
    assert "Warning" not in done.stderr and ".py" not in done.stderr
    assert not (tmp_path / "out").exists()


# --------------------------------------------------------------------------- pressure traces


def _trace_scene(tmp_path: Path, name: str = "trace.csv") -> Path:
    changes = {
        "cycle": {
            "source": "trace",
            "trace_file": name,
            "ignition": None,
            "rounding": None,
            "mean_indicated_pressure": None,
        }
    }
    return write_scene(tmp_path / "scene.toml", modified("petrol-1cyl", changes))


def _write_trace(path: Path, rows: int) -> None:
    step = 720.0 / rows
    with path.open("w", encoding="utf-8") as handle:
        handle.write("crank_angle_deg,pressure_bar\n")
        for k in range(rows):
            angle = k * step
            handle.write(f"{angle!r},{1.0 + 40.0 * math.exp(-(((angle - 370.0) / 20.0) ** 2))!r}\n")


def test_trace_with_more_rows_than_the_limit_is_refused(tmp_path, capsys):
    _write_trace(tmp_path / "trace.csv", 100_001)
    _refused(
        capsys,
        ["check", str(_trace_scene(tmp_path))],
        "cycle.trace_file = 'trace.csv'",
        "more than 100000 data rows",
    )


def test_trace_larger_than_the_byte_limit_is_refused_before_reading(tmp_path, capsys):
    path = tmp_path / "trace.csv"
    with path.open("wb") as handle:  # sparse: no disk is used for the hole
        handle.truncate(32 * 1024 * 1024 + 1)
    _refused(
        capsys,
        ["check", str(_trace_scene(tmp_path))],
        "cycle.trace_file = 'trace.csv'",
        "the file has 33554433 bytes",
        "at most 33554432 bytes",
    )


@pytest.mark.parametrize("cell", ["1" * 200_000, '"' + "1" * 200_000 + '"'])
def test_trace_cell_over_128_kb_is_refused_naming_the_line(tmp_path, capsys, cell):
    text = f"crank_angle_deg,pressure_bar\n0,{cell}\n1,2\n"
    (tmp_path / "trace.csv").write_text(text, encoding="utf-8")
    _refused(
        capsys,
        ["check", str(_trace_scene(tmp_path))],
        "trace.csv, line 2: longer than 10000 characters",
    )


def test_diesel_rk_file_with_too_many_columns_is_refused(tmp_path):
    path = tmp_path / "wide.ind"
    names = [f"c{k}" for k in range(65)]
    path.write_text(" ".join(names) + "\nArrays\n" + " ".join(["1"] * 65) + "\n", encoding="utf-8")
    with pytest.raises(trace.PressureTraceError, match="65 column names; at most 64"):
        trace.read_diesel_rk_ind_table(path)


def test_trace_is_parsed_once_per_run_and_again_after_an_edit(tmp_path, monkeypatch):
    _write_trace(tmp_path / "trace.csv", 1440)
    calls = []
    parse = trace._parse_csv

    def counting(name, lines):
        calls.append(name)
        return parse(name, lines)

    monkeypatch.setattr(trace, "_parse_csv", counting)
    result = crankdyn.run(_trace_scene(tmp_path))
    assert "numerics" in result.stages_run and "indicator" in result.stages_run
    assert len(calls) == 1  # the indicator and numerics stages (several steps) share one reading
    _write_trace(tmp_path / "trace.csv", 2880)  # another size: read again
    angle, _ = trace.read_pressure_csv(tmp_path / "trace.csv")
    assert len(calls) == 2 and len(angle) == 2880


def test_trace_values_read_through_the_stream(tmp_path):
    path = tmp_path / "trace.csv"
    path.write_text('angle [deg], p [MPa]\n\n0,0.1\n"90","2.5"\n180,0.2\n', encoding="utf-8")
    angle, pressure = trace.read_pressure_csv(path)
    assert angle.tolist() == [0.0, 90.0, 180.0]
    assert pressure.tolist() == [0.1e6, 2.5e6, 0.2e6]
    angle[0] = 5.0  # the caller's copy: the next reading is unchanged
    assert trace.read_pressure_csv(path)[0].tolist() == [0.0, 90.0, 180.0]


def test_trace_errors_keep_their_line_numbers(tmp_path):
    path = tmp_path / "trace.csv"
    path.write_text("angle,p_bar\n0,1\n\n10,1\n10,2\n", encoding="utf-8")
    with pytest.raises(
        trace.PressureTraceError, match=r"line 5: crank angle 10 deg does not exceed"
    ):
        trace.read_pressure_csv(path)
    path.write_text("angle,p_bar\n0,1\n10,-1\n", encoding="utf-8")
    with pytest.raises(trace.PressureTraceError, match=r"line 3: pressure \[bar\] -1 is negative"):
        trace.read_pressure_csv(path)


# --------------------------------------------------------------------------- explore


def test_explore_all_above_the_limit_is_refused(capsys):
    orders = math.factorial(10 - 1)  # an in-line 10, four-stroke: (i - 1)! even-firing orders
    assert orders > firing_explorer.MAX_RANKED_ORDERS == 50_000
    _refused(
        capsys,
        ["explore", "--cylinders", "10", "--all"],
        "--all = ",
        f"{orders:,} even-firing orders",
        "at most 50,000",
        "--top N",
    )


def test_explore_top_above_the_limit_is_refused_for_a_w24(capsys):
    _refused(
        capsys,
        ["explore", "--cylinders", "24", "--layout", "W", "--bank-angle", "30", "--top", "50001"],
        "--top = 50001",
        "at most 50,000",
    )


def test_explore_all_within_the_limit_lists_every_order(capsys):
    assert main(["explore", "--cylinders", "8", "--all"]) == 0
    lines = capsys.readouterr().out.splitlines()
    ranks = [line.split()[0] for line in lines[3:]]
    assert ranks == [str(k) for k in range(1, math.factorial(8 - 1) + 1)]


@pytest.mark.parametrize("angle", ["nan", "inf", "5e-324", "360", "-5"])
def test_explore_bank_angle_out_of_range_is_refused(capsys, angle):
    _refused(
        capsys,
        ["explore", "--cylinders", "8", "--layout", "V", "--bank-angle", angle],
        "--bank-angle = ",
        "> 0 and < 360",
    )


# --------------------------------------------------------------------------- the Python API


def test_api_reads_a_bom_as_the_command_line_does(tmp_path, capsys):
    scene = tmp_path / "bom.toml"
    scene.write_text("\ufeff" + KINEMATICS_ONLY.read_text(encoding="utf-8"), encoding="utf-8")
    assert crankdyn.load(scene).engine == crankdyn.load(KINEMATICS_ONLY).engine
    assert main(["check", str(scene)]) == 0
    capsys.readouterr()


def test_api_refuses_deeply_nested_toml_with_a_scene_error(tmp_path):
    scene = tmp_path / "deep.toml"
    scene.write_text("x = " + "[" * 100_000 + "]" * 100_000 + "\n", encoding="utf-8")
    with pytest.raises(crankdyn.SceneError, match="nested too deeply"):
        crankdyn.load(scene)


def _nested(depth: int) -> dict:
    data: dict = {"end": 1}
    for _ in range(depth):
        data = {"a": data}
    return data


def test_api_refuses_deep_and_cyclic_dicts_with_a_scene_error():
    with pytest.raises(crankdyn.SceneError, match="nested at most 16 levels deep"):
        crankdyn.load(_nested(100_000))
    with pytest.raises(crankdyn.SceneError, match="nested at most 16 levels deep"):
        crankdyn.load(KINEMATICS_ONLY, {"engine.name": _nested(100_000)})
    cyclic: dict = {}
    cyclic["self"] = cyclic
    with pytest.raises(crankdyn.SceneError, match="nested at most 16 levels deep"):
        crankdyn.load({**example_data("kinematics-only"), "engine": cyclic})


def test_api_refuses_a_huge_integer_with_a_scene_error():
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(KINEMATICS_ONLY, {"engine.rpm": 10**400})
    assert "engine.rpm = 10000000000000000000... (401 digits)" in str(caught.value)


def test_api_and_command_line_give_the_same_problems(tmp_path, capsys):
    changes = {"engine": {"rpm": 5e-324}, "report": {"title": "T" * 2000}}
    scene = write_scene(tmp_path / "scene.toml", modified("kinematics-only", changes))
    err = _refused(capsys, ["check", str(scene)])
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(scene)
    assert [str(p) for p in caught.value.problems] == [line[4:] for line in err.splitlines()[1:]]
    assert len(caught.value.problems) == 2


def test_api_takes_a_string_of_stages_as_one_name():
    by_name = crankdyn.run(KINEMATICS_ONLY, stages="kinematics")
    assert by_name.stages_run == crankdyn.run(KINEMATICS_ONLY, stages=["kinematics"]).stages_run
    assert "kinematics" in by_name.stages_run and "k" not in by_name.stages_run


def test_api_write_takes_a_string_as_one_format(tmp_path):
    result = crankdyn.run(KINEMATICS_ONLY, stages="kinematics")
    written = result.write(tmp_path / "out", formats="json")
    names = {p.name for p in written}
    assert "results.json" in names and not any(n.endswith((".html", ".pdf", ".csv")) for n in names)


@pytest.mark.parametrize("stages", [5, [5], {"kinematics": 1}, [b"kinematics"]])
def test_api_refuses_stages_of_a_wrong_type(stages):
    with pytest.raises(TypeError, match="stages must be"):
        crankdyn.run(KINEMATICS_ONLY, stages=stages)


def test_api_refuses_an_endless_stage_list():
    import itertools

    with pytest.raises(crankdyn.SceneError, match="at most 1000 stage names"):
        crankdyn.run(KINEMATICS_ONLY, stages=itertools.repeat("kinematics"))


@pytest.mark.parametrize("overrides", [5, [("engine.rpm", 3000)], "engine.rpm=3000"])
def test_api_refuses_overrides_that_are_not_a_mapping(overrides):
    with pytest.raises(TypeError, match="overrides must be a mapping"):
        crankdyn.load(KINEMATICS_ONLY, overrides)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
def test_a_pipe_as_scene_is_refused_without_waiting(tmp_path, capsys):
    pipe = tmp_path / "scene.toml"
    os.mkfifo(pipe)
    _refused(capsys, ["check", str(pipe)], "scene = ", "not a regular file")
    with pytest.raises(crankdyn.SceneError, match="not a regular file"):
        crankdyn.load(pipe)


def test_api_refuses_a_file_name_with_a_nul_character():
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load("scene\x00.toml")
    assert str(caught.value).startswith("invalid scene scene\\x00.toml: 1 problem(s)")
    assert "not a file name" in str(caught.value)


def test_a_message_lists_at_most_50_problems_each_cut_to_1000_characters():
    unknown = {f"key{k}": 1 for k in range(60)}
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(KINEMATICS_ONLY, {"engine": unknown})
    lines = str(caught.value).splitlines()
    assert len(caught.value.problems) == 60
    assert len(lines) == 1 + 50 + 1 and lines[-1] == "  ... and 10 more"
    labels = list(range(1, 5001))  # four cylinders: labels 5 to 5000 do not exist
    with pytest.raises(crankdyn.SceneError) as caught:
        crankdyn.load(KINEMATICS_ONLY, {"engine.cylinders": 4, "engine.firing_order": labels})
    line = next(x for x in str(caught.value).splitlines() if "engine.firing_order" in x)
    assert line.endswith("...") and len(line) < 1200


def test_trace_file_name_too_long_for_the_file_system_is_refused(tmp_path, capsys):
    name = "t" * 300 + ".csv"  # longer than a file name may be (255 bytes on common file systems)
    _refused(
        capsys,
        ["check", str(_trace_scene(tmp_path, name))],
        "cycle.trace_file = 'tttt",
        "cannot be looked up",
    )


@pytest.mark.skipif(not hasattr(os, "symlink"), reason="symbolic links")
def test_trace_file_in_a_loop_of_links_is_refused(tmp_path, capsys):
    os.symlink(tmp_path / "b.csv", tmp_path / "a.csv")
    os.symlink(tmp_path / "a.csv", tmp_path / "b.csv")
    _refused(
        capsys,
        ["check", str(_trace_scene(tmp_path, "a.csv"))],
        "cycle.trace_file = 'a.csv'",
        "cannot be looked up",
    )


def test_trace_of_blank_lines_is_refused_by_its_line_count(tmp_path, capsys):
    text = "angle,p_bar\n" + "\n" * 200_000 + "0,1\n"
    (tmp_path / "trace.csv").write_text(text, encoding="utf-8")
    _refused(capsys, ["check", str(_trace_scene(tmp_path))], "more than 200000 lines")


def test_preview_watch_list_survives_hostile_scenes(tmp_path):
    from crankdyn.preview.server import referenced_files

    dotted = tmp_path / "dotted.toml"
    dotted.write_text("x." * 5000 + "y = 1\n", encoding="utf-8")
    huge = tmp_path / "huge.toml"
    huge.write_text("x = " + "7" * 5000 + "\n", encoding="utf-8")
    assert referenced_files(dotted) == set() and referenced_files(huge) == set()
    with_bom = tmp_path / "bom.toml"
    with_bom.write_text('\ufeff[cycle]\ntrace_file = "p.csv"\n', encoding="utf-8")
    assert referenced_files(with_bom) == {tmp_path / "p.csv"}
