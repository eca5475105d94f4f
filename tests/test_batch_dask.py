"""``crankdyn batch --scheduler ADDRESS``: the same batch on a Dask cluster gives the same answer key,
failures and files as the local worker processes; the time limit holds there too; an unreachable
scheduler is a clear error."""

from __future__ import annotations

import csv
import gc
import io
import json
import subprocess
import sys
from dataclasses import replace

import pytest
from conftest import run_cli
from test_batch_limits import MARKER_PREFIX, SLOW_RPM, SLOW_STAGE

import crankdyn.batch.variants as batch
from crankdyn.batch.variants import run_batch
from crankdyn.cli import examples_dir
from crankdyn.plugin.registry import default_registry

distributed = pytest.importorskip("distributed")

BASE = examples_dir() / "kinematics-only.toml"


@pytest.fixture(scope="module")
def cluster():
    """One in-process Dask cluster (threads, no worker processes to start) for the module."""
    with distributed.LocalCluster(
        processes=False, n_workers=1, threads_per_worker=2, dashboard_address=None
    ) as local:
        yield local


def _variants(path):
    path.write_text(
        "variant,engine.rpm,engine.bore,report.student\n"
        "a,3000,,Ann\nb,3600,84 mm,Bob\nbad,4200,-84 mm,Cy\nd,4800,76 mm,Dee\n",
        encoding="utf-8",
    )
    return path


def _rows(path):
    return list(csv.DictReader(io.StringIO(path.read_text(encoding="utf-8"))))


def test_a_dask_cluster_gives_the_same_answer_key_failures_and_files(tmp_path, cluster):
    variants = _variants(tmp_path / "v.csv")
    local = run_batch(variants, BASE, tmp_path / "local", ["json"], jobs=2, progress=False)
    remote = run_batch(
        variants,
        BASE,
        tmp_path / "dask",
        ["json"],
        progress=False,
        scheduler=cluster.scheduler_address,
    )
    assert [(o.row, o.name, o.ok, o.error) for o in remote.outcomes] == [
        (o.row, o.name, o.ok, o.error) for o in local.outcomes
    ]
    assert [o.name for o in remote.failures] == ["bad"] and "engine.bore" in remote.failures[
        0
    ].error
    for name in ("answer_key.csv", "failures.csv"):
        assert (tmp_path / "dask" / name).read_bytes() == (
            tmp_path / "local" / name
        ).read_bytes(), name
    key = _rows(tmp_path / "dask" / "answer_key.csv")
    assert [r["variant"] for r in key] == ["a", "b", "d"] and [r["row"] for r in key] == [
        "1",
        "2",
        "4",
    ]
    for name in (
        "a",
        "b",
        "d",
    ):  # the files rendered on the worker were written here, as the pool writes them
        written = sorted(
            p.relative_to(tmp_path / "dask" / name) for p in (tmp_path / "dask" / name).rglob("*")
        )
        assert written == sorted(
            p.relative_to(tmp_path / "local" / name) for p in (tmp_path / "local" / name).rglob("*")
        )
        results = json.loads(
            (tmp_path / "dask" / name / "results.json").read_text(encoding="utf-8")
        )
        assert results["kinematics"]["v_max_m_s"] == pytest.approx(
            float(next(r for r in key if r["variant"] == name)["v_max_m_s"]), rel=1e-5
        )
    assert not (tmp_path / "dask" / "bad").exists()
    # Each variant got its own speed: v_mean = S*n/30 with S = 100 mm.
    assert [float(r["v_mean_m_s"]) for r in key] == pytest.approx(
        [0.1 * rpm / 30 for rpm in (3000, 3600, 4800)]
    )


@pytest.mark.slow  # waits out a time limit: in the slow tier, which CI runs
def test_the_time_limit_holds_on_a_dask_worker(tmp_path, cluster, monkeypatch):
    registry = default_registry()
    slow = replace(registry, stages={**registry.stages, SLOW_STAGE.name: SLOW_STAGE})
    # a Dask worker builds the run's registry itself, once per run: the installed plugins' and this
    # stage (a worker on another machine has the plugins installed there)
    monkeypatch.setattr(batch, "default_registry", lambda: slow)
    # Two batches, so that each limit fits its purpose whatever the load of a parallel test run
    # (a quick variant once took over 6 s here): a generous limit lets the quick variant finish
    # on the worker, a short one stops the hanging variant (which sleeps 60 s) and kills it.
    quick = tmp_path / "quick.csv"
    quick.write_text("variant,engine.rpm\nquick,3000\n", encoding="utf-8")
    done = run_batch(
        quick,
        BASE,
        tmp_path / "quick",
        ["json"],
        progress=False,
        timeout=120.0,
        scheduler=cluster.scheduler_address,
    )
    assert [(o.name, o.ok) for o in done.outcomes] == [("quick", True)], done.failures
    path = tmp_path / "v.csv"
    finished = tmp_path / "hanging-variant-finished"
    path.write_text(
        f"variant,engine.rpm,report.subtitle\nhangs,{SLOW_RPM},{MARKER_PREFIX}{finished}\n",
        encoding="utf-8",
    )
    report = run_batch(
        path,
        BASE,
        tmp_path / "out",
        ["json"],
        progress=False,
        timeout=2.0,
        scheduler=cluster.scheduler_address,
    )
    assert [(o.name, o.ok) for o in report.outcomes] == [("hangs", False)]
    assert report.failures[0].error == "stopped after 2 s (the time limit, --timeout)"
    assert not finished.exists()  # the hanging child was killed, not waited for
    assert [r["variant"] for r in _rows(tmp_path / "out" / "failures.csv")] == ["hangs"]


@pytest.mark.parametrize(
    "address, message",
    [
        ("tcp://127.0.0.1:9", "cannot reach a Dask scheduler there within 1 s"),
        ("localhost", "not a scheduler address"),
    ],
)
def test_an_unreachable_scheduler_is_a_clear_error_and_nothing_is_written(
    tmp_path, address, message
):
    variants = _variants(tmp_path / "v.csv")
    done = run_cli(
        "batch",
        str(variants),
        "--base",
        str(BASE),
        "-o",
        str(tmp_path / "out"),
        "--format",
        "json",
        "--scheduler",
        address,
        "--connect-timeout",
        "1",
    )
    assert done.returncode == 2, done.stderr
    assert f"--scheduler {address}" in done.stderr and message in done.stderr
    assert "Traceback" not in done.stderr and "Exception ignored" not in done.stderr
    assert not (tmp_path / "out").exists()


def test_jobs_and_scheduler_together_are_refused(tmp_path):
    done = run_cli(
        "batch",
        str(_variants(tmp_path / "v.csv")),
        "--base",
        str(BASE),
        "-o",
        str(tmp_path / "out"),
        "--scheduler",
        "tcp://127.0.0.1:9",
        "--jobs",
        "2",
    )
    assert done.returncode == 2 and "--jobs" in done.stderr and "nthreads" in done.stderr
    assert not (tmp_path / "out").exists()


def test_dask_is_imported_only_for_a_scheduler(tmp_path):
    """The local pool never loads dask: it stays an optional extra."""
    code = (
        "import sys; from pathlib import Path; from crankdyn.batch.variants import run_batch; "
        "r = run_batch(Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3]), ['json'], jobs=1, progress=False); "
        "print(len(r.outcomes), sorted(m for m in sys.modules if m.split('.')[0] in ('dask', 'distributed')))"
    )
    done = subprocess.run(
        [
            sys.executable,
            "-c",
            code,
            str(_variants(tmp_path / "v.csv")),
            str(BASE),
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.stdout.split() == ["4", "[]"], done.stderr


def test_a_sweep_on_the_cluster_gives_the_local_answer_key(tmp_path, cluster):
    from crankdyn.batch.sweep import SweepRequest, run_sweep, sweep_from_args
    from crankdyn.batch.variants import RunOptions

    keys = []
    for name, scheduler in (("local", None), ("dask", cluster.scheduler_address)):
        sweep = sweep_from_args(
            ["engine.rpm=2000:4000:3", "engine.rod_ratio=0.25,0.3"], None, "j_max_m_s2", None
        )
        options = RunOptions(
            [],
            jobs=None if scheduler else 2,
            progress=False,
            stages=["kinematics"],
            scheduler=scheduler,
        )
        report, _ = run_sweep(SweepRequest(BASE, sweep, tmp_path / name, options, ["csv"], ["svg"]))
        assert len(report.outcomes) == 6 and not report.failures
        keys.append((tmp_path / name / "answer_key.csv").read_bytes())
    assert keys[0] == keys[1]
    # the cluster's worker is this process (threads): its collector is left as it was
    assert gc.get_freeze_count() == 0


def test_a_child_forked_for_a_limited_call_skips_the_inherited_heap_and_the_worker_not():
    from crankdyn.parallel.pool import run_limited

    assert gc.get_freeze_count() == 0
    kind, frozen_in_child, _ = run_limited(gc.get_freeze_count, (), 30.0)
    assert kind == "ok" and frozen_in_child > 0  # the child's collector skips what it inherited
    assert gc.get_freeze_count() == 0  # and this process's collector sees all of its own again
