"""The studies computed in a forked child while the report is rendered (crankdyn.background):
the same outputs as the serial run, and every way the child can fail ends with the study
computed in the report's process (its own error raised there), no process left behind.

Each case runs in a fresh interpreter: the child is forked only by a process with no other
thread (a pytest-xdist worker has some)."""

from pathlib import Path

import pytest
from child_processes import run_fresh

pytestmark = pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="the studies' child is forked")

# the fresh interpreter imports the tests folder's helpers from here
SETUP = f"TESTS = {str(Path(__file__).resolve().parent)!r}\n" + """
import os, sys
from crankdyn.background import ForkedStudies, start_studies
from crankdyn.errors import Problem, SceneError
from crankdyn.orchestrator import plan, run_plan
from crankdyn.plugin_types import Stage, StageOutput
from crankdyn.plugins import Registry
from crankdyn.scene import scene_from_dict
sys.path.insert(0, TESTS)
from conftest import example_data
from child_processes import children

PARENT = os.getpid()
scene = scene_from_dict(example_data("petrol-1cyl"))

def stage(name, run, provides=(), requires=(), last=False):
    return Stage(name=name, title_key=name, requires=tuple(requires), provides=tuple(provides),
                 applies=lambda scene: None, run=run, render=lambda output, ctx: "", last=last)

def base(scene, inputs):
    return StageOutput(data={"x": 21.0})

def study(scene, inputs):
    return StageOutput(results={"twice_x": 2 * inputs["x"], "pid": os.getpid()})

def registry(*studies):
    reg = Registry()
    for s in (stage("base", base, provides=["x"]), *studies):
        reg.stages[s.name] = s
    return reg

def deferred(reg):
    result = run_plan(scene, plan(scene, reg), defer_studies=True)
    assert list(result.deferred) == [s.name for s in reg.stages.values() if s.last], result.deferred
    return start_studies(result)
"""


def run(code: str):
    return run_fresh(SETUP, code, timeout=120)


def test_a_study_is_computed_in_the_child_with_the_serial_result():
    run("""
    reg = registry(stage("study", study, requires=["x"], last=True))
    result = deferred(reg)
    assert result.background is not None and "study" not in result.outputs
    output = result.study_output("study")
    assert output.results["twice_x"] == 42.0
    assert output.results["pid"] != PARENT  # computed aside
    assert result.timing_s["study"] > 0 and result.pending == []
    result.complete()
    assert result.background is None and not children()
    serial = run_plan(scene, plan(scene, reg))
    assert serial.outputs["study"].results["twice_x"] == 42.0 and serial.deferred == {}
    print("ok")
    """)


def test_studies_come_back_in_plan_order_and_complete_takes_the_rest():
    run("""
    def other(scene, inputs):
        return StageOutput(results={"pid": os.getpid()})
    reg = registry(stage("a_study", study, requires=["x"], last=True), stage("b_study", other, last=True))
    result = deferred(reg)
    result.complete()
    assert [n for n in result.outputs] == ["base", "a_study", "b_study"]
    assert all(result.outputs[n].results["pid"] != PARENT for n in ("a_study", "b_study"))
    assert not children()
    print("ok")
    """)


def test_a_study_failing_in_the_child_raises_its_own_error_here():
    run("""
    def refused(scene, inputs):
        raise SceneError(Problem("numerics.tolerance", 1e-9, "a step the study can reach"))
    result = deferred(registry(stage("study", refused, last=True)))
    try:
        result.study_output("study")
    except SceneError as exc:
        assert exc.problems[0].field == "numerics.tolerance"
    else:
        raise AssertionError("no error")
    result.close_background()
    assert not children()
    print("ok")
    """)


def test_an_output_that_cannot_be_pickled_is_computed_here():
    run("""
    def closure(scene, inputs):
        return StageOutput(results={"pid": os.getpid(), "f": lambda: 1})
    result = deferred(registry(stage("study", closure, last=True)))
    assert result.study_output("study").results["pid"] == PARENT
    result.complete()
    assert not children()
    print("ok")
    """)


def test_a_child_that_dies_leaves_the_study_to_this_process():
    run("""
    def dies(scene, inputs):
        if os.getpid() != PARENT:
            os._exit(3)
        return StageOutput(results={"pid": os.getpid()})
    result = deferred(registry(stage("study", dies, last=True)))
    assert result.study_output("study").results["pid"] == PARENT
    result.complete()
    assert not children()
    print("ok")
    """)


def test_a_report_that_fails_meanwhile_leaves_no_child():
    run("""
    import time
    def slow(scene, inputs):
        time.sleep(60)
        return StageOutput()
    result = deferred(registry(stage("study", slow, last=True)))
    start = time.perf_counter()
    result.close_background()  # as run_and_render does when rendering raised
    assert time.perf_counter() - start < 10 and not children()
    print("ok")
    """)


def test_the_real_error_study_comes_from_the_child_in_a_report():
    run("""
    from crankdyn import pipeline
    from crankdyn.plugins import default_registry
    taken = []
    take = ForkedStudies.take
    ForkedStudies.take = lambda self, name: taken.append((name, take(self, name))) or taken[-1][1]
    result, files = pipeline.run_and_render(scene, default_registry(), ["html", "json"])
    assert [name for name, got in taken if got is not None] == ["numerics"], taken
    assert "numerics" in result.outputs and result.background is None and not children()
    assert b'"numerics"' in files["results.json"] and "report.html" in files
    print("ok")
    """)


# ----------------------------------------------------------------- the whole run in a child (ForkedRun)
RUN_SETUP = """
from crankdyn.background import ForkedRun

def located(scene, inputs):
    return StageOutput(data={"x": 21.0}, results={"pid": os.getpid()})

def located_registry(*studies, base_run=located):
    reg = Registry()
    for s in (stage("base", base_run, provides=["x"]), *studies):
        reg.stages[s.name] = s
    return reg
"""


def run_whole(code: str):
    return run_fresh(SETUP + RUN_SETUP, code, timeout=120)


def test_the_stages_computed_in_a_child_give_the_serial_result_and_the_studies_follow():
    run_whole("""
    reg = located_registry(stage("study", study, requires=["x"], last=True))
    the_plan = plan(scene, reg)
    result = ForkedRun.start(scene, the_plan).result()
    assert result.outputs["base"].results["pid"] != PARENT  # computed aside
    assert result.outputs["base"].data == {"x": 21.0} and result.timing_s["base"] > 0
    assert list(result.deferred) == ["study"] and result.deferred["study"] == {"x": 21.0}
    assert result.study_output("study").results == {"twice_x": 42.0, "pid": result.outputs["base"].results["pid"]}
    result.complete()
    assert result.background is None and not children()
    print("ok")
    """)


def test_a_stage_failing_in_the_child_or_outputs_that_cannot_be_pickled_leave_the_run_to_this_process():
    """One fresh interpreter for both (each costs a second and a half of the suite)."""
    run_whole("""
    def refused(scene, inputs):
        if os.getpid() != PARENT:
            raise SceneError(Problem("engine.bore", 0.0, "a bore above zero"))
        raise RuntimeError("only the child should have run this")
    reg = located_registry(base_run=refused)
    assert ForkedRun.start(scene, plan(scene, reg)).result() is None and not children()
    def closure(scene, inputs):
        return StageOutput(data={"x": lambda: 21.0})
    assert ForkedRun.start(scene, plan(scene, located_registry(base_run=closure))).result() is None
    assert not children()
    print("ok")
    """)


def test_a_report_computes_its_stages_in_a_child_while_it_prepares_the_figures():
    run("""
    import sys
    from crankdyn import background, pipeline
    from crankdyn.plugins import default_registry
    got = []
    result_of = background.ForkedRun.result
    def recorded(self):
        got.append(("scipy" in sys.modules, "matplotlib.figure" in sys.modules))
        return result_of(self)
    background.ForkedRun.result = recorded
    result, files = pipeline.run_and_render(scene, default_registry(), ["html", "json"])
    # this process imported matplotlib, not scipy, while the child computed
    assert got == [(False, True)], got
    assert result.background is None and not children() and "report.html" in files
    print("ok")
    """)


def test_no_process_to_be_had_leaves_the_run_and_the_studies_to_this_process():
    """A review: os.fork raising EAGAIN made the report fail (exit 1) and leaked the pipe."""
    run_whole("""
    import errno
    real_fork = os.fork
    def refused():
        raise OSError(errno.EAGAIN, "Resource temporarily unavailable")
    before = len(os.listdir("/proc/self/fd"))
    os.fork = refused
    reg = located_registry(stage("study", study, requires=["x"], last=True))
    assert ForkedRun.start(scene, plan(scene, reg)) is None
    result = deferred(reg)  # run_plan here, the studies' child refused too
    assert result.background is None and result.study_output("study").results["pid"] == PARENT
    from crankdyn.report.figures import draw_jobs
    assert draw_jobs([lambda i=i: str(i).encode() for i in range(6)], workers=2) == [str(i).encode() for i in range(6)]
    os.fork = real_fork
    assert len(os.listdir("/proc/self/fd")) == before, "a pipe left open"
    print("ok")
    """)


def test_an_interrupt_while_waiting_for_the_run_stops_the_child():
    """A review: KeyboardInterrupt in ForkedRun.result left the child computing."""
    run_whole("""
    import signal, time
    def slow(scene, inputs):
        time.sleep(60)
        return StageOutput(data={"x": 1.0})
    forked = ForkedRun.start(scene, plan(scene, located_registry(base_run=slow)))
    signal.signal(signal.SIGALRM, lambda *a: (_ for _ in ()).throw(KeyboardInterrupt()))
    signal.setitimer(signal.ITIMER_REAL, 0.3)
    try:
        forked.result()
    except KeyboardInterrupt:
        pass
    else:
        raise AssertionError("no interrupt")
    assert not children()
    print("ok")
    """)
