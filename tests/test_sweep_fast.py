"""A sweep's answer key computed in chunks (crankdyn.batch.grid_run) equals the key of each point run
through the whole pipeline on its own, column by column; the studies run once."""

from __future__ import annotations

import dataclasses
import math
import os
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from crankdyn.batch.grid_run import KeyRun, chunks, evaluate, execute_key, key_plan, run_chunk
from crankdyn.batch.sweep import SweepRequest, base_for, run_sweep, sweep_from_args, variants
from crankdyn.batch.variants import (
    RunOptions,
    Variant,
    _variant_scene,
    answer_key,
    load_base,
    run_variant,
)
from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import is_study, plan, run_stage, stage_inputs
from crankdyn.parallel.pool import OutOfTime
from crankdyn.plugin.registry import Registry, default_registry
from crankdyn.plugin.types import AnswerColumn, Stage, StageOutput, StagePresentation

PETROL = examples_dir() / "petrol-1cyl.toml"
RELATIVE = 1e-9


def _grid(sets: list[str], scene: Path = PETROL):
    sweep = sweep_from_args(sets, None, None, None)
    base, base_dir = load_base(scene)
    base, _ = base_for(base, sweep)
    return base, base_dir, variants(sweep)[1]


def _per_point(base, base_dir, points, stages=None):
    """Each point through the whole pipeline on its own (the path of a sweep with files)."""
    return [run_variant(base, base_dir, v, "", [], None, stages) for v in points]


def _assert_same_keys(fast, slow):
    assert [o.row for o in fast] == [o.row for o in slow]
    for a, b in zip(fast, slow, strict=True):
        assert a.ok == b.ok, (a.error, b.error)
        assert set(a.answers) == set(b.answers)
        for column, expected in b.answers.items():
            got = a.answers[column]
            if expected is None:
                assert got is None, column
            else:
                assert got == pytest.approx(expected, rel=RELATIVE, abs=1e-300), (a.name, column)


# Three fields each stage of the key reads: the speed (kinematics, forces, torque), the rod ratio
# (the extremes' root searches) and the peak pressure (the indicator's rounding).
TWELVE = [
    "engine.rpm=3000:6000:3",
    "engine.rod_ratio=0.25,0.3",
    "cycle.max_pressure=5.5 MPa,6.5 MPa",
]


def test_twelve_points_in_chunks_equal_the_points_run_alone():
    base, base_dir, points = _grid(TWELVE)
    assert len(points) == 12
    fast = run_chunk(base, base_dir, points, None, None)
    slow = _per_point(base, base_dir, points)
    _assert_same_keys(fast, slow)
    assert all(o.ok for o in fast)
    # the answers vary over the grid: the key is not one point's answers repeated
    assert len({o.answers["j_max_m_s2"] for o in fast}) == 6
    assert len({o.answers["p_max_MPa"] for o in fast}) == 2


def test_the_chunked_sweep_on_worker_processes_equals_the_points_run_alone():
    base, base_dir, points = _grid(TWELVE)
    options = RunOptions([], jobs=2, progress=False)
    outcomes, stop = execute_key(points, base, base_dir, options)
    assert stop == 0
    _assert_same_keys(outcomes, _per_point(base, base_dir, points))


def test_a_failing_point_fails_alone_and_the_others_of_its_chunk_keep_their_answers():
    # a peak 170° after TDC is past the exhaust opening: the indicator refuses those points
    base, base_dir, points = _grid(
        ["engine.rod_ratio=0.28,0.3", "cycle.rounding.peak_angle_after_tdc_deg=12,170"]
    )
    fast = run_chunk(base, base_dir, points, None, None)
    slow = _per_point(base, base_dir, points)
    assert [o.ok for o in fast] == [o.ok for o in slow] == [True, False, True, False]
    for a, b in zip(fast, slow, strict=True):
        assert a.error == b.error
    _assert_same_keys(fast, slow)


def test_the_key_plan_keeps_the_key_stages_their_prerequisites_and_no_study():
    registry = default_registry()
    base, base_dir, points = _grid(TWELVE)
    scene = _variant_scene(base, base_dir, points[0], None, ())
    full = plan(scene, registry)
    kept = key_plan(full, registry)
    names = [s.name for s in kept.order]
    assert names == [s.name for s in full.order if s.name in names]  # the plan's order
    assert not any(is_study(s) for s in kept.order)
    assert any(is_study(s) for s in full.order)  # the example has a study, left out
    provided = {key for s in kept.order for key in s.provides}
    for stage in kept.order:  # every stage kept fills the key or feeds one kept
        assert stage.answer_columns or any(
            key in (*other.requires, *other.uses) for other in kept.order for key in stage.provides
        )
        assert set(stage.requires) <= provided
    left_out = [s for s in full.order if s.name not in names and not is_study(s)]
    assert left_out and not any(s.answer_columns for s in left_out)
    key_stages = {c.stage for c in answer_key.answer_columns(registry)}
    assert key_stages & {s.name for s in full.order} <= set(names)


def _same(got, expected, what):
    if isinstance(expected, np.ndarray):
        scale = float(np.max(np.abs(expected))) if expected.size else 1.0
        np.testing.assert_allclose(
            got, expected, rtol=RELATIVE, atol=1e-12 * (scale or 1.0), err_msg=what
        )
    elif isinstance(expected, (float, int, np.floating)) and not isinstance(expected, bool):
        assert got == pytest.approx(expected, rel=RELATIVE, abs=1e-300), what
    elif isinstance(expected, dict):
        assert set(got) == set(expected), what
        for key, value in expected.items():
            _same(got[key], value, f"{what}.{key}")
    elif dataclasses.is_dataclass(expected):
        for name, value in vars(expected).items():
            if not callable(value):
                _same(getattr(got, name), value, f"{what}.{name}")
    else:
        assert got == expected, what


# Other cycles and engines: a diesel's rounding, a two-stroke diagram, four cylinders (the torque
# repeats every 180°), a measured pressure trace (the indicator runs point by point).
OTHER_SCENES = [
    ("diesel-1cyl.toml", ["engine.rpm=1800,2600", "engine.rod_ratio=0.26,0.3"]),
    ("two-stroke-1cyl.toml", ["engine.rpm=3000,5000"]),
    ("inline4-petrol.toml", ["engine.rpm=3000,5500"]),
    ("inline6-diesel-trace.toml", ["engine.rpm=1500,1700"]),
]


def test_run_many_gives_the_data_and_results_of_run_point_by_point():
    checked = _check_run_many(TWELVE, PETROL)
    # the stages that dominate a point of the single-cylinder key compute their chunk as arrays
    assert {"kinematics", "indicator", "forces", "torque"} <= checked


@pytest.mark.parametrize("name, sets", OTHER_SCENES, ids=[n for n, _ in OTHER_SCENES])
def test_run_many_gives_what_run_gives_for_other_engines(name, sets):
    assert _check_run_many(sets, examples_dir() / name)


def _check_run_many(sets, scene_path) -> set[str]:
    """Each key stage's run_many against its run, point by point, over the grid ``sets`` of
    ``scene_path``; the names of the stages checked."""
    registry = default_registry()
    base, base_dir, points = _grid(sets, scene_path)
    scenes = [_variant_scene(base, base_dir, v, None, ()) for v in points]
    the_plan = key_plan(plan(scenes[0], registry), registry)
    data = [{} for _ in scenes]
    checked = set()
    for stage in the_plan.order:
        inputs = [stage_inputs(stage, d, registry) for d in data]
        singles = [
            run_stage(stage, scene, given)[0] for scene, given in zip(scenes, inputs, strict=True)
        ]
        if stage.run_many is not None:
            checked.add(stage.name)
            for output, single in zip(stage.run_many(scenes, inputs), singles, strict=False):
                _same(output.results, single.results, f"{stage.name} results")
                _same(output.data, single.data, f"{stage.name} data")
                # the curves a later stage reads off the grid: the same function of the angle
                for key, value in single.data.items():
                    if getattr(value, "displacement_at", None) is not None:
                        angles = np.array([0.0, 33.3, 181.0])
                        _same(
                            output.data[key].displacement_at(angles),
                            value.displacement_at(angles),
                            key,
                        )
        for d, single in zip(data, singles, strict=True):
            d.update(single.data)
    return checked


def _registry_with(run_many) -> Registry:
    """The installed registry with every stage's ``run_many`` replaced by ``run_many``."""
    registry = default_registry()
    stages = {n: dataclasses.replace(s, run_many=run_many) for n, s in registry.stages.items()}
    return dataclasses.replace(registry, stages=stages)


def test_a_failing_run_many_falls_back_to_run_point_by_point():
    calls = []

    def refuses(scenes, inputs):
        calls.append(len(scenes))
        raise RuntimeError("cannot")

    base, base_dir, points = _grid(TWELVE[:2])
    scenes = [_variant_scene(base, base_dir, v, None, ()) for v in points]
    fallen = evaluate(scenes, _registry_with(refuses))
    plain = evaluate(scenes, _registry_with(None))
    assert calls and all(n == len(scenes) for n in calls)
    for (run_a, results_a, error_a), (run_b, results_b, error_b) in zip(fallen, plain, strict=True):
        assert run_a == run_b and not error_a and not error_b
        for stage, results in results_b.items():
            assert results_a[stage].keys() == results.keys()


def test_chunks_cover_every_point_once_in_order():
    base, base_dir, points = _grid(["engine.rpm=2000:6000:101"])
    for workers in (1, 2, 8):
        parts = chunks(points, workers, size=30)
        assert [v.row for part in parts for v in part] == [v.row for v in points]
        assert max(map(len, parts)) <= 30
        assert len(parts) >= min(2 * workers, len(points))
    assert chunks([], 2) == []


def test_the_sweep_runs_the_study_once_and_says_so(tmp_path):
    sweep = sweep_from_args(["engine.rpm=3000:5000:3"], None, None, None)
    options = RunOptions([], jobs=1, progress=False)
    request = SweepRequest(PETROL, sweep, tmp_path / "out", options, ["csv", "xlsx"])
    report, notes = run_sweep(request)
    assert not report.failures and len(report.outcomes) == 3
    studies = [s.name for s in default_registry().stages.values() if is_study(s)]
    said = [n for n in notes if "ran once, for the base scene" in n]
    assert said and all(any(f"'{name}'" in n for name in studies) for n in said)
    sheet = pd.read_excel(tmp_path / "out" / "answer_key.xlsx", sheet_name="notes")
    assert sheet["note"].tolist() == notes  # the key's own notes say how it was computed
    assert not any("numerics" in o.stages_run for o in report.outcomes)
    assert math.isfinite(report.outcomes[0].answers["p_max_MPa"])


@pytest.mark.slow
def test_a_larger_grid_in_chunks_equals_the_points_run_alone():
    base, base_dir, points = _grid(
        [
            "engine.rpm=2000:7000:6",
            "engine.rod_ratio=0.24:0.32:5",
            "cycle.max_pressure=4.5 MPa,6 MPa,7.5 MPa",
            "engine.bore=76 mm,88 mm",
        ]
    )
    assert len(points) == 180
    outcomes, _ = execute_key(points, base, base_dir, RunOptions([], jobs=2, progress=False))
    _assert_same_keys(outcomes, _per_point(base, base_dir, points))


def test_on_dask_the_points_go_in_chunks_and_give_the_local_key(monkeypatch):
    distributed = pytest.importorskip("distributed")
    import crankdyn.batch.grid_run as grid_run

    submitted = []
    real = grid_run.run_all_dask

    def counting(items, *args, **kwargs):
        submitted.append([len(item) for item in items])
        return real(items, *args, **kwargs)

    monkeypatch.setattr(grid_run, "run_all_dask", counting)
    base, base_dir, points = _grid(TWELVE)
    local, _ = execute_key(points, base, base_dir, RunOptions([], jobs=1, progress=False))
    with distributed.LocalCluster(
        processes=False, n_workers=1, threads_per_worker=2, dashboard_address=None
    ) as cluster:
        options = RunOptions([], progress=False, scheduler=cluster.scheduler_address)
        remote, stop = execute_key(points, base, base_dir, options)
    assert stop == 0
    # one task per chunk (two per worker thread here), every point in one of them
    assert submitted == [[3, 3, 3, 3]]
    _assert_same_keys(remote, local)


HANG_RPM = 4444


def _hang_at(scene, inputs):
    if scene.engine.rpm == HANG_RPM:
        time.sleep(60.0)  # far beyond the time limit: finishing at all proves the point was stopped
    return StageOutput(results={"x": 1.0})


@pytest.mark.slow  # waits out a time limit: in the slow tier, which CI runs
def test_a_chunk_out_of_time_runs_again_point_by_point_and_only_the_hung_point_fails(monkeypatch):
    hanging = Stage(
        name="hang_for_test",
        requires=(),
        provides=(),
        applies=lambda scene: None,
        run=_hang_at,
        answer_columns=(AnswerColumn("hang_x", "x"),),
        presentation=StagePresentation(
            title_key="kinematics.title", render=lambda output, ctx: None
        ),
    )
    registry = default_registry()
    stages = {**registry.stages, hanging.name: hanging}
    base, base_dir = load_base(examples_dir() / "kinematics-only.toml")
    points = [
        Variant(k, f"p{k}", {"engine": {"rpm": rpm}}, {"variant": f"p{k}"})
        for k, rpm in enumerate([3000, HANG_RPM, 3500, 4000], start=1)
    ]
    options = RunOptions([], jobs=1, progress=False, timeout=1.0)
    run = KeyRun(dataclasses.replace(registry, stages=stages))  # forked workers inherit it
    outcomes, stop = execute_key(points, base, base_dir, options, run)
    assert stop == 0
    assert [o.ok for o in outcomes] == [True, False, True, True]
    assert "time limit" in outcomes[1].error
    assert [o.answers["hang_x"] for o in outcomes if o.ok] == [1.0, 1.0, 1.0]


def test_a_chunk_given_no_time_stops_before_its_first_stage():
    ran = []

    def counting(scene, inputs):
        ran.append(scene.engine.rpm)
        return StageOutput(results={"x": 1.0})

    counted = Stage(
        name="count_for_test",
        requires=(),
        provides=(),
        applies=lambda scene: None,
        run=counting,
        answer_columns=(AnswerColumn("count_x", "x"),),
        presentation=StagePresentation(
            title_key="kinematics.title", render=lambda output, ctx: None
        ),
    )
    registry = default_registry()
    registry = dataclasses.replace(registry, stages={**registry.stages, counted.name: counted})
    base, base_dir, points = _grid(TWELVE[:1])
    scenes = [_variant_scene(base, base_dir, v, None, ()) for v in points]
    with pytest.raises(OutOfTime):
        evaluate(scenes, registry, deadline=time.monotonic())
    assert ran == []
    evaluate(scenes, registry, deadline=time.monotonic() + 3600.0)
    assert ran == [3000.0, 4500.0, 6000.0]


def test_on_dask_a_chunk_runs_in_the_worker_and_one_out_of_time_runs_again_point_by_point(
    monkeypatch,
):
    distributed = pytest.importorskip("distributed")
    import crankdyn.batch.grid_run as grid_run

    in_worker = []

    def out_of_time(deadline):  # every chunk with a limit stops at once; the points alone run
        if deadline is not None:
            in_worker.append(os.getpid())
            raise OutOfTime

    monkeypatch.setattr(grid_run, "_check_time", out_of_time)
    base, base_dir, points = _grid(TWELVE[:2])
    local, _ = execute_key(points, base, base_dir, RunOptions([], jobs=1, progress=False))
    with distributed.LocalCluster(
        processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None
    ) as cluster:
        options = RunOptions([], progress=False, scheduler=cluster.scheduler_address)
        remote, stop = execute_key(points, base, base_dir, options)
    assert stop == 0
    # the chunks ran in the worker's process (this one: the cluster's worker is a thread here)
    assert in_worker and set(in_worker) == {os.getpid()}
    _assert_same_keys(remote, local)


def test_a_chunk_builds_each_point_scene_as_a_batch_builds_it():
    from crankdyn.batch.grid_run import _PointScenes

    base, base_dir = load_base(PETROL)
    points = [
        Variant(1, "a", {"engine": {"rpm": 4100.0}}, {"variant": "a"}),
        Variant(
            2,
            "b",
            {"report": {"variant": "own"}, "cycle": {"max_pressure": "5 MPa"}},
            {"variant": "b"},
        ),
        Variant(3, "c", {"engine": {"rpm": -5.0}}, {"variant": "c"}),  # refused by the model
        Variant(4, "d", {"engine": {"name": "x\ty"}}, {"variant": "d"}),  # a control char
        Variant(5, "e", {"engine": {"bore": "1e-400 mm"}}, {"variant": "e"}),
    ]
    registry = default_registry()
    for language in (None, "uk"):
        built = _PointScenes(base, str(base_dir), language, (), registry)
        for variant in points:
            try:
                expected = _variant_scene(base, str(base_dir), variant, language, (), registry)
            except Exception as exc:  # noqa: BLE001 - the same error is expected
                with pytest.raises(type(exc)) as caught:
                    built.scene(variant)
                assert str(caught.value) == str(exc)
                continue
            assert built.scene(variant) == expected
    # a base naming no mechanism: the point's scene has the registry's default, as a batch's
    diesel, diesel_dir = load_base(examples_dir() / "diesel-1cyl.toml")
    assert "mechanism" not in diesel["engine"]
    point = _PointScenes(diesel, str(diesel_dir), None, (), registry).scene(points[0])
    assert point == _variant_scene(diesel, str(diesel_dir), points[0], None, (), registry)
    assert point.engine.mechanism == "crank_slider"


def test_the_registry_belongs_to_the_run_and_no_batch_module_keeps_one():
    """The run's registry is the run's (``VariantRun``/``KeyRun``): its method is the worker's
    function, a forked worker inherits it, a pickled copy (a Dask task) carries none and builds
    its own; no module of the batch keeps a registry after a run."""
    import pickle

    from crankdyn.batch import grid_run, sweep, sweep_plot
    from crankdyn.batch import variants as variants_module

    installed = default_registry()
    only = Registry(  # the run's own registry: the mechanisms and the kinematics stage only
        mechanisms=installed.mechanisms,
        stages={"kinematics": installed.stages["kinematics"]},
        catalogs=installed.catalogs,
    )
    run = KeyRun(only)
    assert run.registry is only
    base, base_dir = load_base(examples_dir() / "kinematics-only.toml")
    points = [Variant(1, "p1", {"engine": {"rpm": 3000}}, {"variant": "p1"})]
    (outcome,) = run.run_chunk(base, base_dir, points, None, None)
    assert outcome.ok and outcome.stages_run == ["kinematics"]
    # v_mean = S n / 30 with the scene's stroke S = 100 mm
    assert outcome.answers["v_mean_m_s"] == pytest.approx(0.1 * 3000 / 30, rel=1e-12)
    copy = pickle.loads(pickle.dumps(run))
    assert copy.key == run.key and "registry" not in copy._state()
    assert set(copy.registry.stages) == set(default_registry().stages)  # built anew, once
    assert copy.registry is copy.registry
    for module in (variants_module, grid_run, sweep, sweep_plot):
        kept = [
            name
            for name, value in vars(module).items()
            if isinstance(value, (Registry, variants_module.VariantRun))
        ]
        assert kept == [] and not hasattr(module, "_worker_registry"), module.__name__
        assert not hasattr(module, "_registry") and not hasattr(module, "_warmed")


def test_an_item_stuck_in_a_dask_workers_own_process_is_given_up_at_its_limit():
    from crankdyn.parallel.pool import _dask_task_here

    release = threading.Event()

    def stuck():
        release.wait()  # a stage that never checks its limit
        return "late"

    try:
        status, value, _ = _dask_task_here(None, stuck, (), 0.05)
        assert (status, value) == ("timeout", None)
        assert _dask_task_here(None, lambda: "answer", (), 10.0)[:2] == ("ok", "answer")
        with pytest.raises(ZeroDivisionError):
            _dask_task_here(None, lambda: 1 / 0, (), 10.0)
    finally:
        release.set()


def test_run_many_puts_a_diesels_peak_on_its_isobar_as_run_does(tmp_path):
    """The diesel example without its peak angle (z′ then 2/3 along the isobar, found from each
    point's own kinematics): run_many's rounding and diagram equal run's point by point."""
    text = (examples_dir() / "diesel-1cyl.toml").read_text(encoding="utf-8")
    free = "\n".join(
        line for line in text.splitlines() if not line.startswith("peak_angle_after_tdc_deg")
    )
    assert free != text
    (tmp_path / "diesel.toml").write_text(free, encoding="utf-8")
    sets = ["engine.rpm=1800,2600", "cycle.pre_expansion_ratio=1.3,1.6"]
    assert "indicator" in _check_run_many(sets, tmp_path / "diesel.toml")
