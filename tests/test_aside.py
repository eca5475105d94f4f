"""Work a stage hands aside (crankdyn.parallel.fork): computed in a forked child only when the report's
process has a spare core, the same value as computed in place, and every way the child can fail
ends with the value computed in the stage's process (its own error raised there), no process
left behind.

Each forking case runs in a pytest process of its own (``in_fresh_process``): a child is forked
only by a process with no other thread (a pytest-xdist worker has some)."""

import os

import pytest
from child_processes import children, in_fresh_process

from crankdyn.parallel.fork import aside, spare_core

forking = pytest.mark.skipif(
    not hasattr(os, "fork") or len(os.sched_getaffinity(0)) < 2,
    reason="a child is forked only on a machine with a spare core",
)


def where(x):
    return (os.getpid(), 2 * x)


def test_without_a_spare_core_the_value_is_computed_in_place_when_asked():
    calls = []

    def fn(x):
        calls.append(x)
        return (os.getpid(), 2 * x)

    with aside(fn, 21) as handle:
        assert calls == []  # nothing yet: computed when asked
        assert handle.result() == (os.getpid(), 42)
    with spare_core(False):
        assert aside(fn, 1).result() == (os.getpid(), 2)


@forking
@in_fresh_process
def test_with_a_spare_core_a_child_computes_it():
    parent = os.getpid()
    with spare_core():
        with aside(where, 21) as handle:
            pid, value = handle.result()
    assert value == 42 and pid != parent
    assert children() == []
    # outside the block nothing forks
    assert aside(where, 1).result() == (parent, 2)


@forking
@in_fresh_process
def test_the_child_does_not_fork_again():
    parent = os.getpid()

    def nested(x):
        return aside(where, x).result()

    with spare_core():
        pid, value = aside(nested, 5).result()
    assert value == 10 and pid != parent  # the child computed the inner call itself


@forking
@in_fresh_process
def test_an_error_in_the_child_is_raised_by_the_stage_process():
    parent = os.getpid()

    def fails(x):
        raise ValueError(f"no {x} here (pid {os.getpid()})")

    with spare_core():
        handle = aside(fails, 3)
        with pytest.raises(ValueError) as info:
            handle.result()
    assert str(info.value) == f"no 3 here (pid {parent})"  # raised again in this process
    assert children() == []


@forking
@in_fresh_process
def test_a_child_that_dies_or_sends_what_cannot_be_pickled_is_replaced():
    parent = os.getpid()

    def dies(x):
        if os.getpid() != parent:
            os._exit(3)
        return ("here", x)

    def unpicklable(x):
        return (lambda: x) if os.getpid() != parent else ("here", x)

    with spare_core():
        assert aside(dies, 1).result() == ("here", 1)
        assert aside(unpicklable, 2).result() == ("here", 2)
    assert children() == []


@forking
@in_fresh_process
def test_leaving_early_stops_the_child():
    never, kept_open = os.pipe()  # nothing is ever written: the child could only be stopped

    def blocked(x):
        os.read(never, 1)
        return x

    with spare_core():
        with pytest.raises(KeyError):
            with aside(blocked, 1):
                assert len(children()) == 1
                raise KeyError("the stage failed meanwhile")
    assert children() == []
    os.close(never)
    os.close(kept_open)


def _untimed(value):
    if isinstance(value, dict):
        return {
            k: _untimed(v)
            for k, v in value.items()
            if not (k.endswith("_s") or "time" in k or "loops" in k or "overhead" in k)
        }
    if isinstance(value, list):
        return [_untimed(v) for v in value]
    return value


@forking
@in_fresh_process
def test_the_error_study_is_the_same_with_and_without_the_spare_core(monkeypatch):
    # the numerics stage computes its reference, kinematics forms and solver studies aside:
    # every value but the measured times is the one the serial run gives
    from conftest import example_data

    from crankdyn.engine.orchestrator import run_scene
    from crankdyn.plugin.registry import default_registry
    from crankdyn.scene.model import scene_from_dict

    data = example_data("petrol-1cyl")
    data["numerics"] = {"steps_deg": [30, 10, 2], "repeats": 2}
    scene, registry = scene_from_dict(data), default_registry()
    forks = []
    real_fork = os.fork

    def counted_fork():
        forks.append(1)
        return real_fork()

    monkeypatch.setattr(os, "fork", counted_fork)
    serial = run_scene(scene, registry).outputs["numerics"].results
    assert forks == []
    with spare_core():
        beside = run_scene(scene, registry).outputs["numerics"].results
    assert len(forks) == 1  # the study's side part was computed in a child
    assert _untimed(beside) == _untimed(serial)
    assert beside["kinematics_forms"] and beside["reference"] and len(beside["steps"]) == 4
    assert children() == []
