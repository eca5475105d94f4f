"""A generated table of bad and hostile scenes (well over 200): each is refused by ``report`` with exit 2,
a message naming the field, no traceback and nothing written, and ``check`` says exactly the same.

They run in-process through the command line's ``main()`` (a handful also as real processes), so the
whole table takes a few seconds; a scene that made the parser hang (``"9**9**9 mm"``) would hang here.
"""

from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest
from conftest import example_data, run_cli

from crankdyn.cli import main

# Quantity texts no field may accept: arithmetic, no number, no unit, two numbers, NaN/inf, huge
# exponents, unknown units, unit powers beyond 4, operators left dangling, control characters.
BAD_QUANTITIES = [
    "9**9**9 mm",
    "82 parsec**9**9",
    "1/0 mm",
    "82 mm / 0",
    "10**400 mm",
    "1e400 mm",
    "mm",
    "8 10 mm",
    "2*41 mm",
    "(82) mm",
    "82",
    "",
    "   ",
    "nan mm",
    "inf mm",
    "-inf mm",
    "82 parsecz",
    "82 mm^5",
    "82 mm**-9",
    "82 mm/",
    "82 mm*",
    "82 / mm",
    "0x52 mm",
    "82 mm; rm -rf /",
    "82 mm\u0000",
    "82 mm\n",
    "82,5,5 mm",
    "82 mm^0",
    "1" * 70 + " mm",
    "82 kg m^2 s^-2 A^3 K mol cd sr",
]
QUANTITY_FIELDS = [
    "engine.bore",
    "engine.crankcase_pressure",
    "masses.piston_group",
    "cycle.max_pressure",
    "cycle.rounding.combustion_delay_time",
]


def _set(data: dict, dotted: str, value) -> dict:
    data = copy.deepcopy(data)
    *parents, last = dotted.split(".")
    target = data
    for key in parents:
        target = target.setdefault(key, {})
    if value is None:
        target.pop(last, None)
    else:
        target[last] = value
    return data


def _trace(name: str) -> dict:
    return {"source": "trace", "trace_file": name, "compression_ratio": 9.5}


def _petrol(**tables) -> dict:
    data = copy.deepcopy(example_data("petrol-1cyl"))
    for table, body in tables.items():
        data[table] = body
    return data


# (case id, scene data or raw TOML text, extra files {name: text}, text the message must contain)
CASES: list[tuple[str, object, dict, str]] = []
for field in QUANTITY_FIELDS:
    for k, text in enumerate(BAD_QUANTITIES):
        CASES.append((f"{field}-q{k}", _set(example_data("petrol-1cyl"), field, text), {}, field))

_GOOD = example_data("petrol-1cyl")
for field, value in [
    ("engine.bore", [82, "mm"]),
    ("engine.bore", {"value": 82}),
    ("engine.bore", True),
    ("engine.bore", 82),
    ("engine.rpm", "fast"),
    ("engine.rpm", "5600 rpm"),
    ("engine.rpm", -1),
    ("engine.rpm", float("nan")),
    ("engine.rpm", float("inf")),
    ("engine.strokes", "4"),
    ("engine.strokes", 3),
    ("engine.cylinders", 0),
    ("engine.cylinders", 25),
    ("engine.rod_ratio", 1.5),
    ("engine.mechanism", "perpetuum"),
    ("engine.layout", "star"),
    ("report.year", 1),
    ("report.language", "tlh"),
    ("cycle.compression_index", 9),
    ("analysis.angle_step_deg", 7),
    ("analysis.stages", ["kinematics", "telepathy"]),
    ("analysis.stages", "kinematics"),
    ("masses.rod_cm_fraction", 2),
    ("engine.boer", "82 mm"),
    ("masses.pistn_group", "0.4 kg"),
    ("cycle.rounding.ignition_advance_deg", 90),
]:
    CASES.append(
        (
            f"type-{field}-{value!r}"[:60],
            _set(_GOOD, field, value),
            {},
            field.rsplit(".", 1)[0] if field.endswith(("boer", "pistn_group")) else field,
        )
    )

for field, text in [
    ("report.title", "Report\u0007"),
    ("report.student", "Bob\u001b[31m"),
    ("report.city", "a\tb"),
    ("report.group", "ME\r41"),
    ("engine.name", "line 1\nline 2"),
    ("report.supervisor", "\u009b1m"),
    ("report.university", "x\u007f"),
]:
    CASES.append((f"control-{field}", _set(_GOOD, field, text), {}, field))

for wrong, right in [
    ("engin", "engine"),
    ("egnine", "engine"),
    ("masess", "masses"),
    ("cycel", "cycle"),
    ("reprot", "report"),
    ("analisys", "analysis"),
]:
    data = copy.deepcopy(_GOOD)
    data[wrong] = data.pop(right, {"angle_step_deg": 1})
    CASES.append((f"table-{wrong}", data, {}, f"did you mean [{right}]"))

for name in ["/etc/passwd", "../outside.csv", "sub/../../outside.csv", "nowhere.csv", "."]:
    CASES.append((f"trace-path-{name}", _petrol(cycle=_trace(name)), {}, "cycle.trace_file"))
for label, text in [
    ("empty", ""),
    ("garbled", "angle,p [MPa]\n0,1\n1,abc\n"),
    ("no unit", "angle,p\n0,1\n1,2\n"),
    ("one row", "angle,p [MPa]\n0,1\n"),
    ("decreasing", "angle,p [MPa]\n0,1\n-1,2\n"),
    ("negative", "angle,p [MPa]\n0,1\n1,-2\n"),
    ("huge cell", "angle,p [MPa]\n0,1\n1," + "9x" * 500),
    ("binary", "\u0000\u0001\u0002"),
]:
    CASES.append(
        (
            f"trace-content-{label}",
            _petrol(cycle=_trace("trace.csv")),
            {"trace.csv": text},
            "cycle.trace_file",
        )
    )

_RAW = (Path(__file__).parents[1] / "examples" / "petrol-1cyl.toml").read_text(encoding="utf-8")
for label, text, expected in [
    ("nested arrays 5000", "x = " + "[" * 5000 + "]" * 5000 + "\n" + _RAW, "scene"),
    ("nested arrays 40", "x = " + "[" * 40 + "1" + "]" * 40 + "\n" + _RAW, "x.0.0"),
    ("nested tables", "[a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p.q.r.s]\nx = 1\n" + _RAW, "a.b.c"),
    ("not toml", "engine = {", "scene"),
    ("empty file", "", "engine"),
    ("base_dir key", 'base_dir = "/"\n' + _RAW, "base_dir"),
    ("data_dirs key", 'data_dirs = ["/"]\n' + _RAW, "data_dirs"),
    ("latin-1 bytes", b"\xff\xfe[engine]", "scene"),
]:
    CASES.append((f"raw-{label}", text, {}, expected))


def _toml(data: dict) -> str:
    """TOML for ``data`` with every string escaped (JSON escapes are valid TOML basic strings)."""

    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
        if isinstance(v, float) and v != v:
            return "nan"
        if isinstance(v, float) and v in (float("inf"), float("-inf")):
            return "inf" if v > 0 else "-inf"
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{json.dumps(k)} = {value(x)}" for k, x in v.items()) + "}"
        return repr(v)

    lines = [f"{json.dumps(k)} = {value(v)}" for k, v in data.items() if not isinstance(v, dict)]

    def table(name, body):
        lines.append(f"[{name}]")
        lines.extend(
            f"{json.dumps(k)} = {value(v)}" for k, v in body.items() if not isinstance(v, dict)
        )
        for k, v in body.items():
            if isinstance(v, dict):
                table(f"{name}.{json.dumps(k)}", v)

    for k, v in data.items():
        if isinstance(v, dict):
            table(json.dumps(k), v)
    return "\n".join(lines) + "\n"


def _write(folder: Path, scene, extra: dict) -> Path:
    work = folder / "sub"
    work.mkdir()
    (folder / "outside.csv").write_text("angle,p [MPa]\n0,1\n1,2\n", encoding="utf-8")
    for name, text in extra.items():
        (work / name).write_text(text, encoding="utf-8")
    path = work / "scene.toml"
    if isinstance(scene, bytes):
        path.write_bytes(scene)
    else:
        path.write_text(scene if isinstance(scene, str) else _toml(scene), encoding="utf-8")
    return path


def test_the_table_is_large_enough():
    assert len(CASES) >= 200
    assert len({c[0] for c in CASES}) == len(CASES)


@pytest.mark.parametrize("case, scene, extra, expected", CASES, ids=[c[0] for c in CASES])
def test_bad_scene_refused_by_report_and_check_alike(
    tmp_path, capsys, case, scene, extra, expected
):
    path = _write(tmp_path, scene, extra)
    out = tmp_path / "out"
    code = main(["report", str(path), "-o", str(out), "--format", "json,csv"])
    report = capsys.readouterr()
    assert code == 2, report
    assert expected in report.err, report.err
    assert report.err.startswith("crankdyn: invalid scene")
    assert "Traceback" not in report.err + report.out and "internal error" not in report.err
    assert not out.exists(), "nothing may be written for a bad scene"
    assert main(["check", str(path)]) == 2
    check = capsys.readouterr()
    assert check.err == report.err  # the same validation, to the letter


def test_hostile_scene_as_a_real_process(tmp_path):
    path = _write(
        tmp_path, dict((c[0], c[1]) for c in CASES)["engine.bore-q0"], {}
    )  # bore = "9**9**9 mm"
    done = run_cli("report", str(path), "-o", str(tmp_path / "out"), "--format", "json")
    assert (
        done.returncode == 2
        and "Traceback" not in done.stderr
        and "crankdyn: invalid scene" in done.stderr
    )
    assert not (tmp_path / "out").exists()
