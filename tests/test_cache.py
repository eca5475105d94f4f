"""Incremental preview: a stage re-runs only when the scene fields it read or its upstream data
changed. Counted stage runs, not timings."""

from __future__ import annotations

import json
from pathlib import Path

from crankdyn.cli import examples_dir
from crankdyn.engine.orchestrator import plan, run_plan
from crankdyn.engine.stage_cache import StageCache
from crankdyn.output.writers import json_bytes, results_document
from crankdyn.plugin.registry import default_registry
from crankdyn.scene.model import load_scene

REGISTRY = default_registry()
STAGES = ["forces"]  # kinematics, indicator, forces: quick, and the indicator reads no masses


def _scene(**masses):
    return load_scene(examples_dir() / "petrol-1cyl.toml", {"masses": masses} if masses else None)


def test_a_rod_mass_change_does_not_recompute_the_indicator_diagram():
    cache = StageCache()
    first = _scene()
    cache.run_plan(first, plan(first, REGISTRY, STAGES))
    assert cache.runs == {"kinematics": 1, "indicator": 1, "forces": 1}
    cache.run_plan(first, plan(first, REGISTRY, STAGES))  # nothing changed: nothing runs
    assert sum(cache.runs.values()) == 3
    heavier = _scene(rod="0.4 kg")
    result = cache.run_plan(heavier, plan(heavier, REGISTRY, STAGES))
    assert cache.runs["indicator"] == 1 and cache.runs["forces"] == 2
    # The cached result equals a fresh run of the changed scene.
    fresh = run_plan(heavier, plan(heavier, REGISTRY, STAGES))
    a, b = (json.loads(json_bytes(results_document(r))) for r in (result, fresh))
    a.pop("timing_s"), b.pop("timing_s")
    assert a == b
    assert (
        result.outputs["forces"].results
        != cache.run_plan(first, plan(first, REGISTRY, STAGES)).outputs["forces"].results
    )  # and back: the forces follow the rod mass


def test_a_cycle_change_reruns_the_indicator():
    cache = StageCache()
    scene = _scene()
    cache.run_plan(scene, plan(scene, REGISTRY, STAGES))
    changed = load_scene(
        examples_dir() / "petrol-1cyl.toml", {"cycle": {"max_pressure": "5.5 MPa"}}
    )
    cache.run_plan(changed, plan(changed, REGISTRY, STAGES))
    assert cache.runs["indicator"] == 2 and cache.runs["kinematics"] == 1


def test_reads_are_recorded_per_field_of_a_table():
    # The kinematics reads masses.rod_cm_fraction (the rod's centre of mass) but not masses.rod:
    # a rod-mass change re-runs the forces, not the kinematics.
    cache = StageCache()
    scene = _scene()
    cache.run_plan(scene, plan(scene, REGISTRY, STAGES))
    reads = cache._entries["kinematics"].reads
    assert "masses.rod_cm_fraction" in reads and "masses.rod" not in reads and "masses" not in reads
    heavier = _scene(rod="0.4 kg")
    cache.run_plan(heavier, plan(heavier, REGISTRY, STAGES))
    assert cache.runs["kinematics"] == 1 and cache.runs["forces"] == 2
    moved = _scene(rod_cm_fraction=0.3)
    cache.run_plan(moved, plan(moved, REGISTRY, STAGES))
    assert cache.runs["kinematics"] == 2


def test_a_stage_with_services_runs_through_the_cache():
    # The error study re-runs the pipeline through the runner service: the cached path hands it
    # over exactly as the plain one does (the preview of a scene with that stage failed without).
    scene = load_scene(examples_dir() / "kinematics-only.toml")
    stages = ["numerics_kinematics"] if "numerics_kinematics" in REGISTRY.stages else None
    the_plan = plan(scene, REGISTRY, stages)
    assert any(stage.services for stage in the_plan.order)
    result = StageCache().run_plan(scene, the_plan)
    assert set(result.outputs) == {stage.name for stage in the_plan.order}


def test_a_data_file_the_stage_opened_is_a_read_keyed_by_its_contents(tmp_path):
    """The trace's name stays in the scene when its data change: the stage that opened it through
    ``scene.resolve`` runs again (and only it, and what follows from it)."""
    import shutil

    from crankdyn.engine.stage_cache import FILE

    shutil.copy(examples_dir() / "diesel-rk-trace.toml", tmp_path / "trace.toml")
    shutil.copy(examples_dir() / "diesel6-1600rpm.ind", tmp_path / "diesel6-1600rpm.ind")
    scene = load_scene(tmp_path / "trace.toml")
    cache = StageCache()
    cache.run_plan(scene, plan(scene, REGISTRY, STAGES))
    trace = (tmp_path / "diesel6-1600rpm.ind").resolve()
    assert any(
        read.startswith(FILE) and read.endswith(f":{trace}")
        for read in cache._entries["indicator"].reads
    )
    assert not any(read.startswith(FILE) for read in cache._entries["kinematics"].reads)
    cache.run_plan(scene, plan(scene, REGISTRY, STAGES))
    assert cache.runs["indicator"] == 1  # the same bytes: kept
    trace.write_bytes(trace.read_bytes().replace(b"1600", b"1601", 1) + b"\n")
    cache.run_plan(scene, plan(scene, REGISTRY, STAGES))
    assert cache.runs["indicator"] == 2 and cache.runs["kinematics"] == 1


def test_a_data_file_saved_while_its_stage_runs_is_not_taken_for_what_the_stage_read(
    tmp_path, monkeypatch
):
    """The preview's user saves a new trace while the indicator is computed from the old one: the
    entry keeps the digest of the bytes the stage opened, so the next run computes the new ones
    (a digest taken after the run would miss an edit made while the stage ran)."""
    import shutil

    import crankdyn_builtin.indicator.compute as indicator_compute

    shutil.copy(examples_dir() / "diesel-rk-trace.toml", tmp_path / "trace.toml")
    shutil.copy(examples_dir() / "diesel6-1600rpm.ind", tmp_path / "diesel6-1600rpm.ind")
    scene = load_scene(tmp_path / "trace.toml")
    read = indicator_compute.trace.read_diesel_rk_ind

    def read_then_saved(path):
        out = read(path)
        monkeypatch.setattr(indicator_compute.trace, "read_diesel_rk_ind", read)
        Path(path).write_bytes(Path(path).read_bytes().replace(b"1600", b"1601", 1) + b"\n")
        return out

    monkeypatch.setattr(indicator_compute.trace, "read_diesel_rk_ind", read_then_saved)
    cache = StageCache()
    cache.run_plan(scene, plan(scene, REGISTRY, STAGES))
    cache.run_plan(scene, plan(scene, REGISTRY, STAGES))
    assert cache.runs["indicator"] == 2 and cache.runs["kinematics"] == 1


def test_a_study_computed_elsewhere_depends_on_the_data_files_too(tmp_path):
    """A study adopted from the preview's worker counts as having read every scene field and its
    data files, so a trace edited between the grid's angles (the indicator's output unchanged)
    does not leave it stale."""
    import shutil

    from crankdyn.engine.stage_cache import FILE

    shutil.copy(examples_dir() / "diesel-rk-trace.toml", tmp_path / "trace.toml")
    shutil.copy(examples_dir() / "diesel6-1600rpm.ind", tmp_path / "diesel6-1600rpm.ind")
    scene = load_scene(tmp_path / "trace.toml")
    the_plan = plan(scene, REGISTRY, ["numerics"])
    cache = StageCache()
    cache.run_plan(scene, the_plan, defer_studies=True)
    assert cache.deferred_study("numerics")
    cache.adopt("numerics", run_plan(scene, the_plan).outputs["numerics"])
    entry = cache._entries["numerics"]
    assert any(read.startswith(FILE) for read in entry.reads)
    assert cache._valid(entry, entry.stage, scene, entry.upstream)
    trace = tmp_path / "diesel6-1600rpm.ind"
    trace.write_bytes(trace.read_bytes() + b"\n")
    assert not cache._valid(entry, entry.stage, scene, entry.upstream)
