"""The live preview's study worker (crankdyn.background.StudyWorker): forked before the server's
threads, it computes the study of each save while the page is rendered; the study it sends is the
one the server would compute, a scene changed meanwhile is computed in place, a dead worker leaves
the study to the server, and stopping the preview leaves no process behind.

Each case runs in a fresh interpreter: the worker is forked only by a process with no other
thread (a pytest-xdist worker has some)."""

import textwrap
from pathlib import Path

import pytest
from child_processes import run_fresh

pytestmark = pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="the study worker is forked")

SETUP = f"TESTS = {str(Path(__file__).resolve().parent)!r}\n" + """
import os, re, shutil, signal, sys, tempfile, threading
from pathlib import Path
sys.path.insert(0, TESTS)
from child_processes import children
from crankdyn import background
from crankdyn.background import StudyWorker
from crankdyn.cli import examples_dir
from crankdyn.serve import Preview

folder = Path(tempfile.mkdtemp())
scene = folder / "scene.toml"
shutil.copy(examples_dir() / "kinematics-only.toml", scene)
STUDY = "numerics_kinematics"

taken = []
take = background.WorkerJob.take
def counting_take(self, name):
    got = take(self, name)
    taken.append((name, got is not None))
    return got
background.WorkerJob.take = counting_take

def values(output):
    # the study's numbers but its measured times (which differ from run to run)
    def plain(x):
        if isinstance(x, dict):
            return {k: plain(v) for k, v in x.items() if "time" not in k and "timing" not in k and "loops" not in k}
        if isinstance(x, list):
            return [plain(v) for v in x]
        return x
    return plain(output.results)

def with_worker():
    preview = Preview(scene)
    preview._worker = StudyWorker.start()  # as Preview.start() does, without its threads
    return preview

def finish(preview):
    preview.stop()
    assert preview._worker is None and not children(), children()
    print("ok")

def edit(rod_mm):
    text = scene.read_text(encoding="utf-8")
    scene.write_text(re.sub(r'rod_length = "[0-9.]+ mm"', f'rod_length = "{rod_mm} mm"', text), encoding="utf-8")
"""


def run(code: str):
    return run_fresh(SETUP, code, timeout=180)


def test_the_worker_computes_each_saves_study_as_the_server_would():
    run("""
    preview = with_worker()
    assert preview._worker is not None
    preview._study_s = preview._stages_s = 0.0  # a quick study: the worker's, waited for
    for rod in (200, 210):
        edit(rod)
        snapshot = preview.build()
        assert snapshot.state == "report" and not snapshot.pending
        assert taken[-1] == (STUDY, True), taken  # the worker's output
        by_worker = preview.stage_cache._entries[STUDY].output
        in_place = Preview(scene)  # no worker: computed in this process
        in_place.build()
        assert values(in_place.stage_cache._entries[STUDY].output) == values(by_worker)
    worker = preview._worker.pid
    preview.stop()
    assert preview._worker is None and not children(), children()
    print("ok")
    """)


def test_a_scene_changed_between_the_page_and_its_study_is_computed_here():
    run("""
    from crankdyn.cache import StageCache
    from crankdyn.pipeline import run_for_preview
    from crankdyn.plugins import default_registry
    from crankdyn.report.i18n import available_languages
    from crankdyn.report.section_cache import SectionCache
    from crankdyn.scene import load_scene
    registry, cache, sections, worker = default_registry(), StageCache(), SectionCache(), StudyWorker.start()

    def render(defer, studies=None):
        return run_for_preview(load_scene(scene), registry, None, available_languages(), cache, sections,
                               defer, studies, worker)
    result, rendered, deferred = render(True)  # the page: the worker starts on the study of 200 mm
    assert result.pending == [STUDY] and deferred is not None and deferred.background is not None
    edit(230)  # saved again before the study was taken
    result, rendered, rest = render(False, deferred)
    deferred.close_background()
    assert not result.pending and rest is None and (STUDY, True) not in taken, taken
    fresh = Preview(scene)
    fresh.build()
    assert values(result.outputs[STUDY]) == values(fresh.stage_cache._entries[STUDY].output)
    edit(240)  # and the worker serves the next save (the unwanted answer read first)
    result, rendered, deferred = render(True)
    while deferred.background is None:  # still busy with the unwanted study: computed here
        result, rendered, deferred = render(True)
    result, rendered, rest = render(False, deferred)
    assert taken[-1] == (STUDY, True), taken
    worker.stop()
    assert not children()
    print("ok")
    """)


def test_a_dead_worker_leaves_the_study_to_the_server():
    run("""
    preview = with_worker()
    os.kill(preview._worker.pid, signal.SIGKILL)
    os.waitpid(preview._worker.pid, 0)
    preview._study_s = preview._stages_s = 0.0  # a quick study: the worker's, if it could
    snapshot = preview.build()
    assert snapshot.state == "report" and not snapshot.pending and STUDY in preview.stage_cache._entries
    assert (STUDY, True) not in taken and not preview._worker.alive
    finish(preview)
    """)


def test_no_worker_is_forked_beside_other_threads():
    run("""
    gate = threading.Event()
    thread = threading.Thread(target=gate.wait)
    thread.start()
    try:
        assert StudyWorker.start() is None
    finally:
        gate.set()
        thread.join()
    assert not children()
    print("ok")
    """)


@pytest.mark.long
def test_a_quick_study_is_waited_for_and_the_page_is_shown_once_whole():
    run("""
    from crankdyn import serve
    preview = with_worker()
    published = []
    publish = preview._publish
    preview._publish = lambda *args: published.append(publish(*args)) or published[-1]
    preview.build()  # the first save: no study time known yet, the page first, then the whole
    assert [bool(s.pending) for s in published] == [True, False]
    assert preview._study_s is not None and preview._study_s < serve.STUDY_INLINE_S
    stages_first = preview._stages_s  # every stage ran (first pass), then the study (second)
    edit(215)  # a save that runs few stages again
    preview.build()
    assert stages_first > 0  # the first pass's stages, not the second pass's none
    assert preview._stages_s < serve.WORKER_STAGES_S
    edit(220)
    del published[:]
    snapshot = preview.build()  # the study took less than STUDY_INLINE_S: waited for, one page
    assert len(published) == 1 and not snapshot.pending and b'class="pending"' not in snapshot.page
    assert taken[-1] == (STUDY, True), taken
    kept = preview.stage_cache._entries[STUDY].output  # kept as if run in the server
    runs = dict(preview.stage_cache.runs)
    preview.build()  # nothing changed: nothing computed again, in the server or the worker
    assert preview.stage_cache._entries[STUDY].output is kept and dict(preview.stage_cache.runs) == runs
    serve.STUDY_INLINE_S = 0.0  # a slow study: the page first again, the study computed here
    edit(230)
    del published[:]
    asked = len(taken)
    preview.build()
    assert [bool(s.pending) for s in published] == [True, False] and len(taken) == asked
    finish(preview)
    """)


# A registry of two stages, as in test_background: a base and a study of it, slow when asked to be.
REGISTRY = """
import time
from crankdyn.plugin_types import Stage, StageOutput
from crankdyn.plugins import Registry
from crankdyn.scene import scene_from_dict
from conftest import example_data

def stage(name, run, provides=(), requires=(), last=False):
    return Stage(name=name, title_key=name, requires=tuple(requires), provides=tuple(provides),
                 applies=lambda scene: None, run=run, render=lambda output, ctx: "", last=last)

def base(scene, inputs):
    return StageOutput(data={"x": float(scene.masses.piston_group)})

def study(scene, inputs):
    if inputs["x"] > 10:  # a scene that makes the study slow
        time.sleep(60)
    return StageOutput(results={"twice_x": 2 * inputs["x"], "pid": os.getpid(), "marker": "custom"})

registry = Registry()
for s in (stage("base", base, provides=["x"]), stage("study", study, requires=["x"], last=True)):
    registry.stages[s.name] = s

def with_mass(kg):
    data = example_data("petrol-1cyl")
    data["masses"]["piston_group"] = f"{kg} kg"
    return scene_from_dict(data)
"""


def test_the_worker_computes_with_the_registry_it_was_given():
    run(REGISTRY + textwrap.dedent("""
    worker = StudyWorker.start(registry)
    job = worker.submit(with_mass(0.5), None, ["study"])
    output, elapsed = job.take("study")
    assert output.results["marker"] == "custom" and output.results["twice_x"] == 1.0
    assert output.results["pid"] == worker.pid and elapsed > 0
    worker.stop()
    assert not children()
    print("ok")
    """))


def test_a_busy_worker_leaves_the_next_study_to_the_server_and_stops_at_once():
    run(REGISTRY + textwrap.dedent("""
    worker = StudyWorker.start(registry)
    slow = worker.submit(with_mass(20), None, ["study"])  # sleeps a minute in the worker
    assert slow is not None
    assert worker.submit(with_mass(0.5), None, ["study"]) is None  # not queued behind it: computed here
    got = []
    waiting = threading.Thread(target=lambda: got.append(slow.take("study")))
    waiting.start()  # a builder waiting for the slow study ...
    time.sleep(0.5)
    worker.stop()  # ... does not keep the preview from stopping
    waiting.join(10)
    assert not waiting.is_alive() and got == [None] and not worker.alive
    assert not children()
    print("ok")
    """))


def test_a_save_that_computes_nothing_keeps_the_last_study_time():
    run("""
    preview = with_worker()
    preview.build()
    first = preview._study_s
    assert first is not None and first > 0
    preview._study_s = 123.0
    preview.build()  # nothing changed: the study is a cache hit, its time says nothing
    assert preview._study_s == 123.0
    edit(250)
    preview.build()
    assert preview._study_s != 123.0 and preview._study_s > 0
    entry_time = preview._study_s
    preview.stop()
    print("ok")
    """)
