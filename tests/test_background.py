"""The studies computed in a forked child while the report is rendered (crankdyn.engine.studies):
the same outputs as the serial run, and every way the child can fail ends with the study
computed in the report's process (its own error raised there), no process left behind.

Each case runs in a pytest process of its own (``in_fresh_process``): the child is forked only by
a process with no other thread (a pytest-xdist worker has some)."""

import errno
import os
import select
import signal
import sys

import pytest
from child_processes import children, in_fresh_process
from conftest import example_data

from crankdyn.engine.orchestrator import plan, run_plan
from crankdyn.engine.studies import ForkedRun, ForkedStudies, start_studies
from crankdyn.errors import Problem, SceneError
from crankdyn.plugin.registry import Registry
from crankdyn.plugin.types import Stage, StageOutput, StagePresentation
from crankdyn.scene.model import scene_from_dict

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="the studies' child is forked")


def _scene():
    return scene_from_dict(example_data("petrol-1cyl"))


def stage(name, run, provides=(), requires=(), last=False):
    return Stage(
        name=name,
        requires=tuple(requires),
        provides=tuple(provides),
        applies=lambda scene: None,
        run=run,
        last=last,
        presentation=StagePresentation(title_key=name, render=lambda output, ctx: ""),
    )


def base(scene, inputs):
    return StageOutput(data={"x": 21.0})


def study(scene, inputs):
    return StageOutput(results={"twice_x": 2 * inputs["x"], "pid": os.getpid()})


def registry(*studies, base_run=base):
    reg = Registry()
    for s in (stage("base", base_run, provides=["x"]), *studies):
        reg.stages[s.name] = s
    return reg


def deferred(scene, reg):
    result = run_plan(scene, plan(scene, reg), defer_studies=True)
    assert list(result.deferred) == [s.name for s in reg.stages.values() if s.last]
    return start_studies(result)


def located(scene, inputs):
    return StageOutput(data={"x": 21.0}, results={"pid": os.getpid()})


def blocked_forever():
    """A stage body that only a stop can end: it reads a pipe nobody writes."""
    never, _kept_open = os.pipe()
    os.read(never, 1)


@in_fresh_process
def test_a_study_is_computed_in_the_child_with_the_serial_result():
    scene, parent = _scene(), os.getpid()
    reg = registry(stage("study", study, requires=["x"], last=True))
    result = deferred(scene, reg)
    assert result.background is not None and "study" not in result.outputs
    output = result.study_output("study")
    assert output.results["twice_x"] == 42.0
    assert output.results["pid"] != parent  # computed aside
    assert result.timing_s["study"] > 0 and result.pending == []
    result.complete()
    assert result.background is None and not children()
    serial = run_plan(scene, plan(scene, reg))
    assert serial.outputs["study"].results["twice_x"] == 42.0 and serial.deferred == {}


@in_fresh_process
def test_studies_come_back_in_plan_order_and_complete_takes_the_rest():
    scene, parent = _scene(), os.getpid()

    def other(scene, inputs):
        return StageOutput(results={"pid": os.getpid()})

    reg = registry(
        stage("a_study", study, requires=["x"], last=True), stage("b_study", other, last=True)
    )
    result = deferred(scene, reg)
    result.complete()
    assert list(result.outputs) == ["base", "a_study", "b_study"]
    assert all(result.outputs[n].results["pid"] != parent for n in ("a_study", "b_study"))
    assert not children()


@in_fresh_process
def test_a_study_failing_in_the_child_raises_its_own_error_here():
    def refused(scene, inputs):
        raise SceneError(Problem("numerics.tolerance", 1e-9, "a step the study can reach"))

    result = deferred(_scene(), registry(stage("study", refused, last=True)))
    with pytest.raises(SceneError) as info:
        result.study_output("study")
    assert info.value.problems[0].field == "numerics.tolerance"
    result.close_background()
    assert not children()


@in_fresh_process
def test_an_output_that_cannot_be_pickled_is_computed_here():
    parent = os.getpid()

    def closure(scene, inputs):
        return StageOutput(results={"pid": os.getpid(), "f": lambda: 1})

    result = deferred(_scene(), registry(stage("study", closure, last=True)))
    assert result.study_output("study").results["pid"] == parent
    result.complete()
    assert not children()


@in_fresh_process
def test_a_child_that_dies_leaves_the_study_to_this_process():
    parent = os.getpid()

    def dies(scene, inputs):
        if os.getpid() != parent:
            os._exit(3)
        return StageOutput(results={"pid": os.getpid()})

    result = deferred(_scene(), registry(stage("study", dies, last=True)))
    assert result.study_output("study").results["pid"] == parent
    result.complete()
    assert not children()


@in_fresh_process
def test_a_report_that_fails_meanwhile_leaves_no_child():
    def never_ends(scene, inputs):
        blocked_forever()
        return StageOutput()

    result = deferred(_scene(), registry(stage("study", never_ends, last=True)))
    assert len(children()) == 1
    result.close_background()  # as run_and_render does when rendering raised: the child is stopped
    assert not children()


# a whole report with its forked study child: in the slow tier, which CI runs
@pytest.mark.slow
@in_fresh_process
def test_the_real_error_study_comes_from_the_child_in_a_report(monkeypatch):
    from crankdyn.output import pipeline
    from crankdyn.plugin.registry import default_registry

    taken = []
    take = ForkedStudies.take

    def recorded(self, name):
        got = take(self, name)
        taken.append((name, got))
        return got

    monkeypatch.setattr(ForkedStudies, "take", recorded)
    result, files = pipeline.run_and_render(_scene(), default_registry(), ["html", "json"])
    assert [name for name, got in taken if got is not None] == ["numerics"]
    assert "numerics" in result.outputs and result.background is None and not children()
    assert b'"numerics"' in files["results.json"] and "report.html" in files


# --- the whole run in a child (ForkedRun)


@in_fresh_process
def test_the_stages_computed_in_a_child_give_the_serial_result_and_the_studies_follow():
    scene, parent = _scene(), os.getpid()
    reg = registry(stage("study", study, requires=["x"], last=True), base_run=located)
    result = ForkedRun.start(scene, plan(scene, reg)).result()
    assert result.outputs["base"].results["pid"] != parent  # computed aside
    assert result.outputs["base"].data == {"x": 21.0} and result.timing_s["base"] > 0
    assert list(result.deferred) == ["study"] and result.deferred["study"] == {"x": 21.0}
    child = result.outputs["base"].results["pid"]
    assert result.study_output("study").results == {"twice_x": 42.0, "pid": child}
    result.complete()
    assert result.background is None and not children()


@in_fresh_process
def test_the_child_starts_the_studies_before_this_process_reads_the_outputs():
    """Outputs larger than any pipe's buffer (2.4 MB) do not hold the child back: it begins the
    study while this process is still busy elsewhere (here: waiting for the study's signal)."""
    import numpy as np

    started, signal_end = os.pipe()
    fds_before = len(os.listdir("/proc/self/fd"))

    def large(scene, inputs):
        return StageOutput(data={"x": 21.0}, results={"samples": np.arange(300_000.0)})

    def signalling(scene, inputs):
        os.write(signal_end, b"s")
        return study(scene, inputs)

    reg = registry(stage("study", signalling, requires=["x"], last=True), base_run=large)
    forked = ForkedRun.start(_scene(), plan(_scene(), reg))
    ready, _, _ = select.select([started], [], [], 60.0)  # a guard against a hang, not a timing
    assert ready, "the study did not start before the outputs were read"
    result = forked.result()
    assert np.array_equal(result.outputs["base"].results["samples"], np.arange(300_000.0))
    assert result.study_output("study").results["twice_x"] == 42.0
    result.complete()
    assert not children() and len(os.listdir("/proc/self/fd")) == fds_before


@in_fresh_process
def test_a_stage_failing_or_unpicklable_outputs_in_the_child_leave_the_run_to_this_process():
    scene, parent = _scene(), os.getpid()

    def refused(scene, inputs):
        if os.getpid() != parent:
            raise SceneError(Problem("engine.bore", 0.0, "a bore above zero"))
        raise RuntimeError("only the child should have run this")

    assert ForkedRun.start(scene, plan(scene, registry(base_run=refused))).result() is None
    assert not children()

    def closure(scene, inputs):
        return StageOutput(data={"x": lambda: 21.0})

    assert ForkedRun.start(scene, plan(scene, registry(base_run=closure))).result() is None
    assert not children()


# a whole report with its forked stage child: in the slow tier, which CI runs
@pytest.mark.slow
@in_fresh_process
def test_a_report_computes_its_stages_in_a_child_while_it_prepares_the_figures(monkeypatch):
    from crankdyn.engine import studies as background
    from crankdyn.output import pipeline
    from crankdyn.plugin.registry import default_registry

    got = []
    result_of = background.ForkedRun.result

    def recorded(self):
        got.append(("scipy" in sys.modules, "matplotlib.figure" in sys.modules))
        return result_of(self)

    monkeypatch.setattr(background.ForkedRun, "result", recorded)
    result, files = pipeline.run_and_render(_scene(), default_registry(), ["html", "json"])
    # this process imported matplotlib, not scipy, while the child computed
    assert got == [(False, True)]
    assert result.background is None and not children() and "report.html" in files


@in_fresh_process
def test_no_process_to_be_had_leaves_the_run_and_the_studies_to_this_process(monkeypatch):
    """os.fork refusing (EAGAIN) leaves the work to this process: the report is made, no pipe
    left open."""
    from crankdyn.report.figures import draw_jobs

    scene, parent = _scene(), os.getpid()

    def refused():
        raise OSError(errno.EAGAIN, "Resource temporarily unavailable")

    before = len(os.listdir("/proc/self/fd"))
    monkeypatch.setattr(os, "fork", refused)
    reg = registry(stage("study", study, requires=["x"], last=True), base_run=located)
    assert ForkedRun.start(scene, plan(scene, reg)) is None
    result = deferred(scene, reg)  # run_plan here, the studies' child refused too
    assert result.background is None and result.study_output("study").results["pid"] == parent
    drawn = draw_jobs([lambda i=i: str(i).encode() for i in range(6)], workers=2)
    assert drawn == [str(i).encode() for i in range(6)]
    monkeypatch.undo()
    assert len(os.listdir("/proc/self/fd")) == before, "a pipe left open"


@in_fresh_process
def test_an_interrupt_while_waiting_for_the_run_stops_the_child():
    """Ctrl-C while the report waits for the forked run stops the child."""
    scene = _scene()

    def never_ends(scene, inputs):
        blocked_forever()
        return StageOutput(data={"x": 1.0})

    forked = ForkedRun.start(scene, plan(scene, registry(base_run=never_ends)))

    def interrupt(*_):
        raise KeyboardInterrupt

    signal.signal(signal.SIGALRM, interrupt)
    signal.setitimer(signal.ITIMER_REAL, 0.3)  # the interrupt arrives while result() waits
    with pytest.raises(KeyboardInterrupt):
        forked.result()
    assert not children()
