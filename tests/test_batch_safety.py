"""Batch and sweep safety: reserved and over-long variant ids, SIGTERM handled as Ctrl-C, --jobs
capped at the cores, every size limit checked from counts before anything is built, and time
limits within a sane range."""

from __future__ import annotations

import csv
import hashlib
import itertools
import os
import signal
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import pytest

import crankdyn
import crankdyn.batch.grid_run as grid_run
import crankdyn.batch.variants as batch
from crankdyn.batch.sweep import MAX_POINTS, parse_values
from crankdyn.batch.variants import (
    MAX_FIELDS,
    MAX_VARIANT_NAME_BYTES,
    MAX_VARIANT_NAME_CHARS,
    MAX_VARIANTS,
    available_cores,
    folder_name,
    read_variants,
    run_batch,
    worker_count,
)
from crankdyn.cli import examples_dir, main
from crankdyn.errors import SceneError, UsageError
from crankdyn.output.manifest import MANIFEST
from crankdyn.parallel.pool import MAX_TIMEOUT_S, check_seconds

BASE = examples_dir() / "kinematics-only.toml"
#: Allocation a refused request may make while it is checked: far below any list of the refused
#: size (MAX_POINTS + 1 floats alone take over 3 MB).
SMALL_BYTES = 1_000_000
#: How long a test waits for an event of a subprocess (a row's output) before it fails.
EVENT_WAIT_S = 120.0


def _variants_csv(path: Path, ids: list[str]) -> Path:
    with path.open("w", encoding="utf-8", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["variant", "engine.rpm"])
        writer.writerows([name, 3000 + 10 * k] for k, name in enumerate(ids))
    return path


def _key_rows(path: Path) -> list[dict[str, str]]:
    with path.open(encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


def _peak_bytes(function, *args) -> tuple[BaseException | None, int]:
    """(the exception ``function(*args)`` raised, the peak of memory it allocated)."""
    tracemalloc.start()
    try:
        function(*args)
        raised = None
    except Exception as exc:  # noqa: BLE001 - handed back to the test
        raised = exc
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return raised, peak


# --------------------------------------------------------------------------- reserved ids


@pytest.mark.parametrize(
    "wanted",
    [
        "answer_key.csv",
        "answer_key.xlsx",
        "answer_key.parquet",
        "failures.csv",
        MANIFEST,
        "ANSWER_KEY.CSV",
        "answer_key.csv.",
    ],
)
def test_a_reserved_variant_id_is_refused_naming_it(tmp_path, wanted):
    with pytest.raises(SceneError) as info:
        read_variants(_variants_csv(tmp_path / "v.csv", ["ok1", wanted]))
    message = str(info.value)
    assert repr(wanted) in message and "row 2, column variant" in message
    assert "another id" in message


def test_the_cli_refuses_a_reserved_id_before_anything_runs(tmp_path, capsys):
    variants = _variants_csv(tmp_path / "v.csv", ["answer_key.csv", "ok1"])
    out = tmp_path / "out"
    code = main(
        ["batch", str(variants), "--base", str(BASE), "-o", str(out), "--format", "json", "-q"]
    )
    assert code == 2 and not out.exists()
    err = capsys.readouterr().err
    assert "'answer_key.csv'" in err and "Traceback" not in err and "internal error" not in err


# --------------------------------------------------------------------------- long ids


def test_a_long_id_is_cut_with_the_hash_of_the_whole_id():
    wanted = "a" * 300
    name = folder_name(wanted, "01")
    digest = hashlib.sha256(wanted.encode("utf-8")).hexdigest()[:8]
    assert len(name) <= MAX_VARIANT_NAME_CHARS and name.endswith("-" + digest)
    assert name.startswith("a" * 60)
    assert folder_name(wanted, "01") == name  # stable between runs
    assert folder_name("short_id", "01") == "short_id"  # a short id is its own folder


def test_ids_equal_after_cutting_stay_distinct():
    first, second = "x" * 299 + "1", "x" * 299 + "2"
    assert folder_name(first, "01") != folder_name(second, "01")


def test_a_long_id_of_wide_letters_fits_the_name_bytes():
    name = folder_name("Ж" * 300, "01")  # two bytes each in UTF-8
    assert len(name.encode("utf-8")) <= MAX_VARIANT_NAME_BYTES and name.startswith("Ж")


def test_a_batch_of_300_character_ids_writes_every_row(tmp_path):
    ids = ["v" * 299 + "1", "v" * 299 + "2"]
    out = tmp_path / "out"
    variants = tmp_path / "v.csv"
    # The title page's variant given short: only the folder name is under test here.
    variants.write_text(
        "variant,report.variant\n" + "".join(f"{i},V{k}\n" for k, i in enumerate(ids)),
        encoding="utf-8",
    )
    report = run_batch(variants, BASE, out, ["json"], jobs=1, progress=False)
    assert not report.failures
    names = [folder_name(i, "01") for i in ids]
    assert all((out / n / "results.json").is_file() for n in names)
    assert [row["variant"] for row in _key_rows(out / "answer_key.csv")] == names


# --------------------------------------------------------------------------- SIGTERM


def _start(args: list[str], cwd: Path) -> subprocess.Popen:
    # Started as the leader of its own process group: the signal goes to the whole group, as `timeout` and job
    # schedulers send it, the worker processes included.
    return subprocess.Popen(
        [sys.executable, "-m", "crankdyn", *args],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        env={**os.environ, "PYTHONWARNINGS": "ignore"},
    )


def _wait_for(path: Path, process: subprocess.Popen) -> None:
    deadline = time.monotonic() + EVENT_WAIT_S
    while not path.exists():
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, f"{path} did not appear"
        time.sleep(0.02)  # a poll interval for the event, not a wait for an outcome


@pytest.mark.long
@pytest.mark.parametrize("command", ["batch", "sweep"])
def test_sigterm_writes_the_answer_key_and_failures_and_exits_143(tmp_path, command):
    rows = 100
    out = tmp_path / "out"
    prefix = "v" if command == "batch" else "p"
    names = [f"{prefix}{k:03d}" for k in range(1, rows + 1)]
    if command == "batch":
        args = ["batch", str(_variants_csv(tmp_path / "v.csv", names)), "--base", str(BASE)]
    else:
        args = ["sweep", str(BASE), f"--set=engine.rpm=1000:6000:{rows}"]
    third = out / names[2] / "results.json"
    process = _start([*args, "-o", str(out), "--format", "json", "--jobs", "1", "-q"], tmp_path)
    try:
        _wait_for(third, process)
        os.killpg(process.pid, signal.SIGTERM)
        _, err = process.communicate(timeout=EVENT_WAIT_S)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    assert process.returncode == 128 + signal.SIGTERM
    assert "interrupted (SIGTERM)" in err and "Traceback" not in err
    answered = _key_rows(out / "answer_key.csv")
    failed = _key_rows(out / "failures.csv")
    # One worker runs the rows in order: the third started only after the first two were answered.
    assert len(answered) >= 2
    assert sorted(row["variant"] for row in answered + failed) == names  # each row once
    assert all("interrupted (SIGTERM)" in row["error"] for row in failed)
    assert all((out / row["variant"] / "results.json").is_file() for row in answered)


def test_an_interruption_outside_the_run_loop_still_lists_every_row(tmp_path, monkeypatch):
    def first_then_interrupted(
        items, function, args_of, jobs, timeout, finished, failed, meanwhile=None
    ):
        finished(function(*args_of(items[0])))
        raise KeyboardInterrupt  # e.g. while the loop closes its idle workers

    monkeypatch.setattr(batch, "run_all", first_then_interrupted)
    handler = signal.getsignal(signal.SIGTERM)
    out = tmp_path / "out"
    report = run_batch(
        _variants_csv(tmp_path / "v.csv", ["v1", "v2", "v3"]), BASE, out, ["json"], progress=False
    )
    assert report.interrupted and report.stop_signal == signal.SIGINT
    assert [(o.name, o.ok) for o in report.outcomes] == [("v1", True), ("v2", False), ("v3", False)]
    assert [row["variant"] for row in _key_rows(out / "failures.csv")] == ["v2", "v3"]
    assert signal.getsignal(signal.SIGTERM) == handler  # the process's own handling is back


# --------------------------------------------------------------------------- --jobs


def test_jobs_are_capped_at_the_cores():
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    assert available_cores() == cores
    assert worker_count(1000) == cores and worker_count(None) == cores and worker_count(1) == 1


def test_the_cli_says_jobs_are_capped_and_runs_no_more_workers(tmp_path, capsys, monkeypatch):
    started = []
    real = batch.run_all
    for module in (batch, grid_run):  # a batch's variants, a sweep's chunks of points
        monkeypatch.setattr(
            module,
            "run_all",
            lambda items, function, args_of, jobs, *rest: (
                started.append(jobs) or real(items, function, args_of, jobs, *rest)
            ),
        )
    rows = available_cores() + 1
    out = tmp_path / "out"
    code = main(
        [
            "sweep",
            str(BASE),
            f"--set=engine.rpm=1000:6000:{rows}",
            "--jobs",
            "1000",
            "-o",
            str(out),
            "-q",
            "--stages",
            "kinematics",
        ]
    )
    err = capsys.readouterr().err
    assert code == 0 and started == [available_cores()]
    assert f"--jobs 1000: capped at {available_cores()}" in err
    assert len(_key_rows(out / "answer_key.csv")) == rows


# --------------------------------------------------------------------------- limits before building


def test_a_range_count_beyond_the_limit_is_refused_from_the_count():
    raised, peak = _peak_bytes(parse_values, "engine.rpm", f"1000:6000:{MAX_POINTS + 1}")
    assert isinstance(raised, SceneError) and peak < SMALL_BYTES
    assert "engine.rpm" in str(raised) and str(MAX_POINTS) in str(raised)


def test_the_cli_refuses_a_billion_points_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "out"
    code = main(
        ["sweep", str(BASE), "--set", "engine.rpm=1000:6000:1000000000", "-o", str(out), "-q"]
    )
    err = capsys.readouterr().err
    assert code == 2 and not out.exists()
    assert "engine.rpm = '1000000000'" in err and f"at most {MAX_POINTS}" in err


@pytest.mark.parametrize("text", ["0:1:step=1e-320", "1:2:" + "9" * 5000, "1:2:step=1e-300"])
def test_ranges_of_countless_values_are_refused_with_the_limit(text):
    with pytest.raises(SceneError) as info:
        parse_values("engine.rpm", text)
    assert "engine.rpm" in str(info.value) and str(MAX_POINTS) in str(info.value)


def test_a_listed_axis_beyond_the_limit_is_refused():
    from crankdyn.batch.sweep import axis_from_toml

    with pytest.raises(SceneError, match=f"at most {MAX_POINTS}"):
        axis_from_toml("engine.rpm", list(range(MAX_POINTS + 1)))


def _grid_file(path: Path, fields: int) -> Path:
    lines = ["[sweep]", *(f"f{k}.x = [1, 2]" for k in range(fields))]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("fields", [MAX_FIELDS + 1, 20_000, 50_000])
def test_a_grid_of_too_many_fields_is_refused_naming_the_limit(tmp_path, capsys, fields):
    out = tmp_path / "out"
    grid = _grid_file(tmp_path / "g.toml", fields)
    code = main(["sweep", str(BASE), "--grid", str(grid), "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and not out.exists()
    assert f"{fields} fields" in err and f"at most {MAX_FIELDS}" in err
    assert "internal error" not in err


def test_too_many_set_options_are_refused_before_their_values_are_read(tmp_path, capsys):
    sets = [f"--set=f{k}.x=1,2" for k in range(MAX_FIELDS + 1)]
    code = main(["sweep", str(BASE), *sets, "-o", str(tmp_path / "out")])
    assert code == 2 and f"at most {MAX_FIELDS}" in capsys.readouterr().err


def test_a_grid_of_too_many_points_is_refused_naming_the_limit(tmp_path, capsys):
    # 17 fields of 2 values: 131 072 points, each field well within the limit.
    sets = [f"--set=f{k}.x=1,2" for k in range(17)]
    code = main(["sweep", str(BASE), *sets, "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert 2**17 > MAX_POINTS and code == 2 and f"more than {MAX_POINTS} points" in err


def test_a_batch_csv_of_too_many_columns_or_rows_is_refused(tmp_path):
    wide = tmp_path / "wide.csv"
    header = ["variant", *(f"f{k}.x" for k in range(MAX_FIELDS + 1))]
    wide.write_text(
        ",".join(header) + "\n" + ",".join(["v1"] + ["1"] * (MAX_FIELDS + 1)) + "\n",
        encoding="utf-8",
    )
    with pytest.raises(SceneError, match=f"at most {MAX_FIELDS} scene fields"):
        read_variants(wide)
    long = tmp_path / "long.csv"
    long.write_text("engine.rpm\n" + "3000\n" * (MAX_VARIANTS + 1), encoding="utf-8")
    with pytest.raises(SceneError, match=f"{MAX_VARIANTS + 1} rows.*at most {MAX_VARIANTS}"):
        read_variants(long)


def test_a_batch_csv_cell_beyond_the_csv_field_limit_is_a_clear_error(tmp_path):
    path = tmp_path / "v.csv"
    path.write_text(
        'variant,report.student\nv1,"' + "x" * (csv.field_size_limit() + 1) + '"\n',
        encoding="utf-8",
    )
    with pytest.raises(SceneError, match="not a readable CSV file"):
        read_variants(path)


# --------------------------------------------------------------------------- the Python API


@pytest.mark.parametrize("values", [range(1, 10**9), range(10**30)])
def test_the_api_refuses_a_huge_range_from_its_length(values):
    raised, peak = _peak_bytes(crankdyn.sweep, BASE, {"engine.rpm": values})
    assert isinstance(raised, SceneError) and peak < SMALL_BYTES
    assert "engine.rpm" in str(raised) and f"at most {MAX_VARIANTS}" in str(raised)


def test_the_api_refuses_an_endless_iterator_after_the_limit():
    with pytest.raises(SceneError, match=f"{MAX_VARIANTS + 1} values"):
        crankdyn.sweep(BASE, {"engine.rpm": itertools.count(1000)})


def test_the_api_has_the_cli_point_limit():
    grid = {"engine.rpm": range(1000, 1400), "engine.stroke": range(1, 300)}  # 119 600 combinations
    raised, peak = _peak_bytes(crankdyn.sweep, BASE, grid)
    assert 400 * 299 > MAX_POINTS and isinstance(raised, SceneError) and peak < SMALL_BYTES
    assert f"more than {MAX_POINTS} combinations" in str(raised)


@pytest.mark.parametrize("fields", [MAX_FIELDS + 1, 20_000, 50_000])
def test_the_api_refuses_a_grid_of_too_many_fields(fields):
    with pytest.raises(SceneError, match=f"'{fields} fields': at most {MAX_FIELDS}"):
        crankdyn.sweep(BASE, {f"f{k}.x": [1, 2] for k in range(fields)})


@pytest.mark.parametrize("values", ["3000", 3000, {"a": 1}])
def test_the_api_refuses_a_grid_value_that_is_not_a_list(values):
    with pytest.raises(TypeError, match=r"grid\['engine.rpm'\] must be a list of values"):
        crankdyn.sweep(BASE, {"engine.rpm": values})


def test_the_api_sweep_still_runs_a_small_grid_from_an_iterator():
    grid = {"engine.rpm": (rpm for rpm in (2000, 4000))}
    frame = crankdyn.sweep(BASE, grid, stages=["kinematics"])
    assert list(frame["engine.rpm"]) == [2000, 4000]


# --------------------------------------------------------------------------- time limits


@pytest.mark.parametrize("command", ["batch", "sweep"])
@pytest.mark.parametrize("option", ["--timeout", "--connect-timeout"])
@pytest.mark.parametrize("value", ["inf", "nan", "-1", "0", "1e400", str(int(MAX_TIMEOUT_S) + 1)])
def test_a_time_limit_out_of_range_is_refused_naming_the_option(
    tmp_path, capsys, command, option, value
):
    out = tmp_path / "out"
    variants = _variants_csv(tmp_path / "v.csv", ["v1"])
    head = (
        ["batch", str(variants), "--base", str(BASE)]
        if command == "batch"
        else ["sweep", str(BASE), "--set", "engine.rpm=1000:2000:2"]
    )
    code = main([*head, "-o", str(out), f"{option}={value}"])
    err = capsys.readouterr().err
    assert code == 2 and not out.exists()
    assert f"{option} " in err and f"at most {MAX_TIMEOUT_S:g}" in err
    assert "internal error" not in err


def test_the_longest_time_limit_is_accepted():
    assert check_seconds("--timeout", MAX_TIMEOUT_S) == MAX_TIMEOUT_S
    assert check_seconds("--timeout", 0.5) == 0.5


@pytest.mark.parametrize("timeout", [float("inf"), float("nan"), -1.0, "60"])
def test_the_api_refuses_a_bad_time_limit_before_anything_is_written(tmp_path, timeout):
    out = tmp_path / "out"
    with pytest.raises(UsageError, match="timeout"):
        run_batch(
            _variants_csv(tmp_path / "v.csv", ["v1"]),
            BASE,
            out,
            ["json"],
            progress=False,
            timeout=timeout,
        )
    assert not out.exists()


def test_a_variants_file_too_large_or_not_a_file_is_refused_before_reading(tmp_path, monkeypatch):
    big = tmp_path / "variants.csv"
    big.write_text("engine.rpm\n1000\n", encoding="utf-8")
    monkeypatch.setattr(batch, "MAX_VARIANTS_FILE_BYTES", 10)
    with pytest.raises(SceneError, match="at most 10 bytes"):
        batch.read_variants(big)
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    with pytest.raises(SceneError, match="not a regular file"):
        batch.read_variants(fifo)  # a pipe would wait for a writer forever
