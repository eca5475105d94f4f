"""The live preview's study worker (crankdyn.engine.studies.StudyWorker): forked before the server's
threads, it computes the study of each save while the page is rendered; the study it sends is the
one the server would compute, a scene changed meanwhile is computed in place, a dead worker leaves
the study to the server, and stopping the preview leaves no process behind.

Each case runs in a pytest process of its own (``in_fresh_process``): the worker is forked only by
a process with no other thread (a pytest-xdist worker has some)."""

import os
import re
import shutil
import signal
import threading

import pytest
from child_processes import children, in_fresh_process
from conftest import example_data

from crankdyn.cli import examples_dir
from crankdyn.engine import studies as background
from crankdyn.engine.studies import StudyWorker
from crankdyn.plugin.registry import Registry
from crankdyn.plugin.types import Stage, StageOutput, StagePresentation
from crankdyn.preview import server as serve
from crankdyn.preview.server import Preview
from crankdyn.scene.model import scene_from_dict

pytestmark = [
    pytest.mark.skipif(not hasattr(os, "fork"), reason="the study worker is forked"),
    # each case a pytest process of its own: in the slow tier, which CI runs
    pytest.mark.slow,
]

STUDY = "numerics_kinematics"


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "scene.toml"
    shutil.copy(examples_dir() / "kinematics-only.toml", path)
    return path


@pytest.fixture
def taken(monkeypatch):
    """(study name, whether the worker's output was taken) of every WorkerJob.take."""
    record = []
    take = background.WorkerJob.take

    def counting_take(self, name):
        got = take(self, name)
        record.append((name, got is not None))
        return got

    monkeypatch.setattr(background.WorkerJob, "take", counting_take)
    return record


def values(output):
    """The study's numbers but its measured times (which differ from run to run)."""

    def plain(x):
        if isinstance(x, dict):
            return {
                k: plain(v)
                for k, v in x.items()
                if "time" not in k and "timing" not in k and "loops" not in k
            }
        if isinstance(x, list):
            return [plain(v) for v in x]
        return x

    return plain(output.results)


def with_worker(scene):
    preview = Preview(scene)
    preview._worker = StudyWorker.start()  # as Preview.start() does, without its threads
    return preview


def finish(preview):
    preview.stop()
    assert preview._worker is None and not children()


def edit(scene, rod_mm):
    text = scene.read_text(encoding="utf-8")
    scene.write_text(
        re.sub(r'rod_length = "[0-9.]+ mm"', f'rod_length = "{rod_mm} mm"', text), encoding="utf-8"
    )


@in_fresh_process
def test_the_worker_computes_each_saves_study_as_the_server_would(scene, taken):
    preview = with_worker(scene)
    assert preview._worker is not None
    preview._study_s = preview._stages_s = 0.0  # a quick study: the worker's
    for rod in (200, 210):
        edit(scene, rod)
        snapshot = preview.build()
        assert snapshot.state == "report" and not snapshot.pending
        assert taken[-1] == (STUDY, True)  # the worker's output
        by_worker = preview.stage_cache._entries[STUDY].output
        in_place = Preview(scene)  # no worker: computed in this process
        in_place.build()
        assert values(in_place.stage_cache._entries[STUDY].output) == values(by_worker)
    finish(preview)


@in_fresh_process
def test_a_scene_changed_between_the_page_and_its_study_is_computed_here(scene, taken):
    from crankdyn.engine.stage_cache import StageCache
    from crankdyn.output.pipeline import run_for_preview
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report.i18n import available_languages
    from crankdyn.report.section_cache import SectionCache
    from crankdyn.scene.model import load_scene

    registry, cache, sections, worker = (
        default_registry(),
        StageCache(),
        SectionCache(),
        StudyWorker.start(),
    )

    def render(defer, studies=None):
        return run_for_preview(
            load_scene(scene),
            registry,
            None,
            available_languages(),
            cache,
            sections,
            defer,
            studies,
            worker,
        )

    result, rendered, deferred = render(True)  # the page: the worker starts on the study of 200 mm
    assert result.pending == [STUDY] and deferred is not None and deferred.background is not None
    edit(scene, 230)  # saved again before the study was taken
    result, rendered, rest = render(False, deferred)
    deferred.close_background()
    assert not result.pending and rest is None and (STUDY, True) not in taken
    fresh = Preview(scene)
    fresh.build()
    assert values(result.outputs[STUDY]) == values(fresh.stage_cache._entries[STUDY].output)
    edit(scene, 240)  # and the worker serves the next save (the unwanted answer read first)
    result, rendered, deferred = render(True)
    while deferred.background is None:  # still busy with the unwanted study: computed here
        result, rendered, deferred = render(True)
    result, rendered, rest = render(False, deferred)
    assert taken[-1] == (STUDY, True)
    worker.stop()
    assert not children()


@in_fresh_process
def test_a_dead_worker_leaves_the_study_to_the_server(scene, taken):
    preview = with_worker(scene)
    os.kill(preview._worker.pid, signal.SIGKILL)
    os.waitpid(preview._worker.pid, 0)
    preview._study_s = preview._stages_s = 0.0  # a quick study: the worker's, if it could
    snapshot = preview.build()
    assert (
        snapshot.state == "report"
        and not snapshot.pending
        and STUDY in preview.stage_cache._entries
    )
    assert (STUDY, True) not in taken and not preview._worker.alive
    finish(preview)


@in_fresh_process
def test_no_worker_is_forked_beside_other_threads():
    gate = threading.Event()
    thread = threading.Thread(target=gate.wait)
    thread.start()
    try:
        assert StudyWorker.start() is None
    finally:
        gate.set()
        thread.join()
    assert not children()


@pytest.mark.long
@in_fresh_process
def test_a_quick_study_is_the_workers_and_follows_the_page(scene, taken, monkeypatch):
    # Whether a study counts as quick is decided from its measured time (serve.STUDY_INLINE_S,
    # serve.WORKER_STAGES_S); the limits are set here so that the decision does not depend on
    # how fast this machine is at the moment.
    monkeypatch.setattr(serve, "STUDY_INLINE_S", float("inf"))
    monkeypatch.setattr(serve, "WORKER_STAGES_S", float("inf"))
    preview = with_worker(scene)
    published = []
    publish = preview._publish

    def recorded(*args):
        published.append(publish(*args))
        return published[-1]

    preview._publish = recorded
    preview.build()  # the first save: no study time known yet, the page first, then the whole
    assert [bool(s.pending) for s in published] == [True, False]
    assert preview._study_s is not None and preview._study_s > 0
    stages_first = preview._stages_s  # every stage ran (first pass), then the study (second)
    assert stages_first > 0
    edit(scene, 215)  # a save that runs the stages again
    preview.build()
    assert preview._stages_s is not None and preview._stages_s > 0  # this save's stages, measured
    edit(scene, 220)
    del published[:]
    snapshot = preview.build()  # a quick study: the page without it, then the worker's study
    assert [bool(s.pending) for s in published] == [True, False]
    assert b'class="pending"' in published[0].page and b'class="pending"' not in snapshot.page
    assert taken[-1] == (STUDY, True)
    kept = preview.stage_cache._entries[STUDY].output  # kept as if run in the server
    runs = dict(preview.stage_cache.runs)
    preview.build()  # nothing changed: nothing computed again, in the server or the worker
    assert (
        preview.stage_cache._entries[STUDY].output is kept
        and dict(preview.stage_cache.runs) == runs
    )
    monkeypatch.setattr(
        serve, "STUDY_INLINE_S", 0.0
    )  # a slow study: the page first again, computed here
    edit(scene, 230)
    del published[:]
    asked = len(taken)
    preview.build()
    assert [bool(s.pending) for s in published] == [True, False] and len(taken) == asked
    finish(preview)


# A registry of two stages, as in test_background: a base and a study of it, slow when asked to be.
def _stage(name, run, provides=(), requires=(), last=False):
    return Stage(
        name=name,
        requires=tuple(requires),
        provides=tuple(provides),
        applies=lambda scene: None,
        run=run,
        last=last,
        presentation=StagePresentation(title_key=name, render=lambda output, ctx: ""),
    )


def _base(scene, inputs):
    return StageOutput(data={"x": float(scene.masses.piston_group)})


def _study(scene, inputs):
    if (
        inputs["x"] > 10
    ):  # a scene whose study never ends by itself: it waits on a pipe nobody writes
        never, _kept_open = os.pipe()
        os.read(never, 1)
    return StageOutput(results={"twice_x": 2 * inputs["x"], "pid": os.getpid(), "marker": "custom"})


def _registry():
    registry = Registry()
    for s in (
        _stage("base", _base, provides=["x"]),
        _stage("study", _study, requires=["x"], last=True),
    ):
        registry.stages[s.name] = s
    return registry


def _with_mass(kg):
    data = example_data("petrol-1cyl")
    data["masses"]["piston_group"] = f"{kg} kg"
    return scene_from_dict(data)


@in_fresh_process
def test_the_worker_computes_with_the_registry_it_was_given():
    worker = StudyWorker.start(_registry())
    job = worker.submit(_with_mass(0.5), None, ["study"])
    output, elapsed = job.take("study")
    assert output.results["marker"] == "custom" and output.results["twice_x"] == 1.0
    assert output.results["pid"] == worker.pid and elapsed > 0
    worker.stop()
    assert not children()


@in_fresh_process
def test_a_busy_worker_leaves_the_next_study_to_the_server_and_stops_at_once():
    worker = StudyWorker.start(_registry())
    endless = worker.submit(_with_mass(20), None, ["study"])  # never ends in the worker
    assert endless is not None
    assert (
        worker.submit(_with_mass(0.5), None, ["study"]) is None
    )  # not queued behind it: computed here
    got = []
    waiting_started = threading.Event()

    def wait_for_the_study():
        waiting_started.set()
        got.append(endless.take("study"))

    waiting = threading.Thread(target=wait_for_the_study)
    waiting.start()  # a builder waiting for the endless study ...
    assert waiting_started.wait(60)
    worker.stop()  # ... does not keep the preview from stopping
    waiting.join(60)
    assert not waiting.is_alive() and got == [None] and not worker.alive
    assert not children()


@in_fresh_process
def test_a_save_that_computes_nothing_keeps_the_last_study_time(scene):
    preview = with_worker(scene)
    preview.build()
    first = preview._study_s
    assert first is not None and first > 0
    preview._study_s = 123.0
    preview.build()  # nothing changed: the study is a cache hit, its time says nothing
    assert preview._study_s == 123.0
    edit(scene, 250)
    preview.build()
    assert preview._study_s != 123.0 and preview._study_s > 0
    finish(preview)
