"""Bad scenes: one clear message naming the field, exit code 2, no traceback, nothing written."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import modified, run_cli, write_scene

from crankdyn.cli import examples_dir, main

# (case id, changes to the petrol example, text the message must contain)
CASES = [
    (
        "rod shorter than crank",
        {"engine": {"rod_ratio": None, "rod_length": "30 mm"}},
        "engine.rod_length",
    ),
    ("lambda >= 1", {"engine": {"rod_ratio": 1.0}}, "engine.rod_ratio"),
    ("lambda > 1", {"engine": {"rod_ratio": 1.7}}, "< 1"),
    ("negative bore", {"engine": {"bore": "-82 mm"}}, "engine.bore"),
    ("zero stroke", {"engine": {"stroke": "0 mm"}}, "engine.stroke"),
    ("zero rpm", {"engine": {"rpm": 0}}, "engine.rpm"),
    ("typo key", {"engine": {"bore": None, "boer": "82 mm"}}, "did you mean 'bore'"),
    ("typo table", {"analysys": {"angle_step_deg": 1}}, "analysys"),
    ("missing rpm", {"engine": {"rpm": None}}, "engine.rpm"),
    ("missing bore", {"engine": {"bore": None}}, "engine.bore"),
    ("strokes 3", {"engine": {"strokes": 3}}, "engine.strokes"),
    ("step not dividing cycle", {"analysis": {"angle_step_deg": 7}}, "analysis.angle_step_deg"),
    (
        "table step not multiple",
        {"analysis": {"angle_step_deg": 2, "table_step_deg": 5}},
        "analysis.table_step_deg",
    ),
    ("bare number bore", {"engine": {"bore": 82}}, "unit"),
    ("wrong dimension", {"engine": {"bore": "82 kg"}}, "not a length"),
    ("unparsable unit", {"engine": {"bore": "82 parsecz"}}, "engine.bore"),
    ("negative mass", {"masses": {"piston_group": "-0.4 kg"}}, "masses.piston_group"),
    ("both rod length and ratio", {"engine": {"rod_length": "140 mm"}}, "exactly one"),
    (
        "missing rod with masses",
        {"engine": {"rod_ratio": None}},
        "engine.rod_length = (missing): missing: [masses] gives a connecting rod's mass",
    ),
    ("rod cm both ways", {"masses": {"rod_cm_from_big_end": "40 mm"}}, "exactly one"),
    (
        "rod cm beyond rod",
        {"masses": {"rod_cm_fraction": None, "rod_cm_from_big_end": "400 mm"}},
        "masses.rod_cm_from_big_end",
    ),
    ("pz below compression", {"cycle": {"max_pressure": "1.0 MPa"}}, "cycle.max_pressure"),
    ("spark with rho", {"cycle": {"pre_expansion_ratio": 1.4}}, "cycle.pre_expansion_ratio"),
    ("missing exhaust pressure", {"cycle": {"exhaust_pressure": None}}, "cycle.exhaust_pressure"),
    ("cycle without masses", {"masses": None}, "masses"),
    ("unknown ignition", {"cycle": {"ignition": "hot-bulb"}}, "cycle.ignition"),
    (
        "unknown application",
        {"engine": {"application": "airplane"}},
        "engine.application = 'airplane': allowed values: 'automotive', 'tractor'",
    ),
    (
        "compression index out of range",
        {"cycle": {"compression_index": 2.5}},
        "cycle.compression_index",
    ),
    ("unknown mechanism", {"engine": {"mechanism": "steam_walking_beam"}}, "engine.mechanism"),
    ("unknown language", {"report": {"language": "tlh"}}, "report.language"),
    (
        "unknown sheet frame",
        {"report": {"frame": "gost"}},
        "report.frame = 'gost': allowed values: 'none' or 'eskd'",
    ),
    (
        "designation not text",
        {"report": {"designation": 41}},
        "report.designation = 41: input should be a valid string",
    ),
    (
        "title-block letter too long",
        {"report": {"letter": "УНКП"}},
        "report.letter = 'УНКП': string should have at most 3 characters",
    ),
    ("unknown stage", {"analysis": {"stages": ["kinematics", "telepathy"]}}, "telepathy"),
    (
        "delay after TDC",
        {"cycle": {"rounding": {"ignition_advance_deg": 10, "combustion_delay_deg": 12}}},
        "combustion_delay_deg",
    ),
    ("two-stroke with valve timing", {"engine": {"strokes": 2}}, "four-stroke engines only"),
    (
        "trace file missing",
        {"cycle": {"source": "trace", "trace_file": "nowhere.csv"}},
        "cycle.trace_file",
    ),
]


@pytest.mark.parametrize("mechanism", ["crank_slider", "offset_crank_slider", "vane_crank_rocker"])
def test_a_mechanism_with_a_rod_refuses_a_scene_without_one(tmp_path: Path, capsys, mechanism):
    """The rod is the mechanism's requirement (``Mechanism.needs_rod``), checked with the plugins."""
    changes = {"engine": {"rod_length": None, "rod_ratio": None, "mechanism": mechanism}}
    scene = write_scene(tmp_path / "scene.toml", modified("kinematics-only", changes))
    out_dir = tmp_path / "out"
    code = main(["report", str(scene), "-o", str(out_dir), "--format", "json"])
    captured = capsys.readouterr()
    assert code == 2, captured
    expected = (
        "engine.rod_length = (missing): give exactly one of rod_length (e.g. '140 mm') or "
        f"rod_ratio (lambda = R/L, 0 < lambda < 1): the '{mechanism}' mechanism has a connecting rod"
    )
    assert expected in captured.err, captured.err
    _no_traceback(captured.err + captured.out)
    assert not out_dir.exists()


def _no_traceback(text: str) -> None:
    assert "Traceback" not in text
    assert 'File "' not in text


@pytest.mark.parametrize("case, changes, expected", CASES, ids=[c[0] for c in CASES])
def test_bad_scene_is_refused_cleanly(tmp_path: Path, capsys, case, changes, expected):
    scene = write_scene(tmp_path / "scene.toml", modified("petrol-1cyl", changes))
    out_dir = tmp_path / "out"
    code = main(["report", str(scene), "-o", str(out_dir), "--format", "html,json,csv"])
    captured = capsys.readouterr()
    assert code == 2, captured
    assert expected in captured.err, captured.err
    assert captured.err.startswith("crankdyn: invalid scene")
    _no_traceback(captured.err + captured.out)
    assert not out_dir.exists() or not any(out_dir.rglob("*")), (
        "nothing may be written for a bad scene"
    )


@pytest.mark.parametrize(
    "rounding, field, words",
    [
        # the default delay 6·n·τ = 6 · 2500 · 1.5 ms = 22.5 deg outgrows a given advance of 20 deg
        (
            {"ignition_advance_deg": 20, "combustion_delay_time": None},
            "cycle.rounding.ignition_advance_deg = 20",
            (
                "must be more than the ignition delay 6·n·τ = 22.5 deg",
                "engine.rpm = 2500",
                "1.5 ms by default",
            ),
        ),
        (
            {"combustion_delay_time": None, "combustion_delay_deg": 30},
            "cycle.rounding.combustion_delay_deg = 30",
            ("ignition_advance_deg (22 deg)",),
        ),
    ],
)
def test_a_diesel_delay_past_the_advance_names_the_fields_to_change(
    tmp_path: Path, capsys, rounding, field, words
):
    scene = write_scene(
        tmp_path / "scene.toml",
        modified("diesel-1cyl", {"engine": {"rpm": 2500}, "cycle": {"rounding": rounding}}),
    )
    code = main(["report", str(scene), "-o", str(tmp_path / "out"), "--format", "json"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert field in err and all(w in err for w in words), err
    assert "(see message)" not in err
    _no_traceback(err)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "rpm, delay_deg, advance_deg",
    # 6·n·τ with τ = 1.5 ms: 1200 rpm gives 10.8 deg, 4 deg and more under the 18 deg default;
    # from 1800 rpm on (16.2 deg) the advance becomes ⌈delay + 4⌉: 21, 27 and 37 deg.
    [(1200, 10.8, 18.0), (1800, 16.2, 21.0), (2500, 22.5, 27.0), (3600, 32.4, 37.0)],
)
def test_a_diesel_without_an_advance_gets_one_that_outruns_its_delay(rpm, delay_deg, advance_deg):
    from crankdyn import api

    data = modified(
        "diesel-1cyl",
        {
            "engine": {"rpm": rpm},
            "cycle": {"rounding": {"ignition_advance_deg": None, "combustion_delay_time": None}},
        },
    )
    rounding = api.run(data, stages=["indicator"]).run_result.outputs["indicator"].results
    assert rounding["combustion_delay_deg"] == pytest.approx(delay_deg)
    assert rounding["ignition_advance_deg"] == advance_deg


def _trace_scene(tmp_path: Path, trace_text: str | None, name: str = "trace.csv") -> Path:
    if trace_text is not None:
        (tmp_path / name).write_text(trace_text, encoding="utf-8")
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


@pytest.mark.parametrize(
    "label, text",
    [
        ("empty", ""),
        ("header only", "crank_angle_deg,pressure_bar\n"),
        ("garbled", "crank_angle_deg,pressure_bar\n0,1.0\n1,abc\n2,1.2\n"),
        ("no unit", "angle,pressure\n0,1\n360,2\n"),
        (
            "partial cycle",
            "crank_angle_deg,pressure_bar\n"
            + "".join(f"{a},{1 + a / 100}\n" for a in range(0, 300)),
        ),
    ],
)
def test_bad_pressure_trace(tmp_path: Path, capsys, label, text):
    scene = _trace_scene(tmp_path, text)
    out_dir = tmp_path / "out"
    code = main(["report", str(scene), "-o", str(out_dir)])
    captured = capsys.readouterr()
    assert code == 2, captured
    assert "cycle.trace_file" in captured.err and "trace.csv" in captured.err, captured.err
    _no_traceback(captured.err)
    assert not out_dir.exists() or not any(out_dir.rglob("*"))


def test_unreadable_scene_files(tmp_path: Path, capsys):
    assert main(["check", str(tmp_path / "absent.toml")]) == 2
    assert "file not found" in capsys.readouterr().err
    broken = tmp_path / "broken.toml"
    broken.write_text("[engine\nrpm = 5", encoding="utf-8")
    assert main(["check", str(broken)]) == 2
    assert "not valid TOML" in capsys.readouterr().err


def test_bad_format_option(tmp_path: Path, capsys, examples):
    assert (
        main(
            [
                "report",
                str(examples / "petrol-1cyl.toml"),
                "-o",
                str(tmp_path / "o"),
                "--format",
                "doc",
            ]
        )
        == 2
    )
    assert "--format" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_subprocess_shows_no_traceback(tmp_path: Path):
    scene = write_scene(
        tmp_path / "scene.toml", modified("petrol-1cyl", {"engine": {"rod_ratio": 1.2}})
    )
    done = run_cli("report", str(scene), "-o", str(tmp_path / "out"))
    assert done.returncode == 2
    assert "engine.rod_ratio = 1.2: must be > 0 and < 1" in done.stderr
    _no_traceback(done.stderr + done.stdout)
    assert not (tmp_path / "out").exists()


def test_a_two_strokes_peak_pressure_is_checked_against_its_actual_compression(
    tmp_path: Path, capsys
):
    """A ported two-stroke compresses from the exhaust ports' closing: p_z must exceed
    p_a·ε_д^n1 with ε_д = 1 + (1 − ψ)(ε − 1), not p_a·ε^n1 (a pressure between the two is a real
    engine's); a four-stroke's bound stays p_a·ε^n1."""
    from crankdyn.physics.indicator import lost_stroke_fraction
    from crankdyn.scene.model import load_scene

    scene = load_scene(examples_dir() / "two-stroke-1cyl.toml")
    c, e = scene.cycle, scene.engine
    psi = lost_stroke_fraction(c.rounding.exhaust_opens_before_bdc_deg, e.rod_ratio_value)
    eps_d = 1.0 + (1.0 - psi) * (c.compression_ratio - 1.0)
    actual = c.intake_pressure * eps_d**c.compression_index
    geometric = c.intake_pressure * c.compression_ratio**c.compression_index
    assert actual < 0.9 * geometric
    between = f"{(actual + geometric) / 2 / 1e6:.4f} MPa"
    below = f"{0.98 * actual / 1e6:.4f} MPa"
    for pressure, strokes, refused in [(between, 2, False), (below, 2, True), (between, 4, True)]:
        # the rounding's peak and its rise at TDC kept within so low a p_z
        rounding = {"peak_pressure_fraction": 1.0, "pressure_rise_to_tdc": "0.01 MPa"}
        changes = {"cycle": {"max_pressure": pressure, "rounding": rounding}}
        if strokes == 4:
            changes["engine"] = {"strokes": 4}
            changes["cycle"]["exhaust_pressure"] = "0.11 MPa"
        path = write_scene(tmp_path / "scene.toml", modified("two-stroke-1cyl", changes))
        code = main(["check", str(path)])
        err = capsys.readouterr().err
        assert (code == 2) == refused, (pressure, strokes, err)
        if refused:
            bound = actual if strokes == 2 else geometric
            assert f"cycle.max_pressure = '{pressure}': must exceed the compression-end " in err
            assert f"p_c = {bound / 1e6:.3g} MPa" in err, err
            assert ("eps_d" in err) == (strokes == 2), err
            _no_traceback(err)


def test_a_v_engines_refused_firing_order_is_told_how_its_banks_are_lettered(
    tmp_path: Path, capsys
):
    """A 90° V6 on three pins at 120° fires its pins' L cylinders first: "1R, 1L, …" does not fit,
    and the refusal says which bank a crank reaches first."""
    engine = {
        "layout": "V",
        "bank_angle_deg": 90,
        "cylinders": 6,
        "crank_angles_deg": [0, 240, 120],
        "uneven_firing": True,
        "firing_order": ["1R", "1L", "2R", "2L", "3R", "3L"],
    }
    path = write_scene(tmp_path / "v6.toml", modified("kinematics-only", {"engine": engine}))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "does not fit the crank arrangement" in err
    assert "a crank reaches bank L's axis first and bank R's the bank angle later" in err
    fixed = {**engine, "firing_order": ["1L", "1R", "2L", "2R", "3L", "3R"]}
    path = write_scene(tmp_path / "v6.toml", modified("kinematics-only", {"engine": fixed}))
    assert main(["check", str(path)]) == 0
