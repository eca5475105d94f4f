"""crankdyn.engine.frozen_heap: the collector skips what is alive at the start of a report, and gets it all
back at the end (a batch worker or the preview server must not keep a report's objects); it is
off while the report command imports its modules."""

from __future__ import annotations

import gc
import subprocess
import sys

from child_processes import in_fresh_process

from crankdyn.engine.frozen_heap import collector_paused, freeze_more, frozen_heap


def test_the_heap_is_frozen_inside_and_given_back_after():
    assert gc.get_freeze_count() == 0
    with frozen_heap():
        frozen = gc.get_freeze_count()
        assert frozen > 0
        kept = [object() for _ in range(10)]  # noqa: F841 - alive across freeze_more
        later = [[] for _ in range(1000)]  # noqa: F841 - tracked containers allocated after the start
        freeze_more()
        assert gc.get_freeze_count() >= frozen + 1000
    assert gc.get_freeze_count() == 0


def test_nested_scopes_give_back_only_at_the_outermost_end():
    with frozen_heap():
        with frozen_heap():
            pass
        assert gc.get_freeze_count() > 0  # still inside the outer report
    assert gc.get_freeze_count() == 0


def test_freeze_more_outside_a_report_does_nothing():
    freeze_more()
    assert gc.get_freeze_count() == 0


def test_a_cycle_made_inside_is_collected_after():
    # in a fresh interpreter: two full collections of a test worker's heap take seconds
    code = """
import gc, weakref
from crankdyn.engine.frozen_heap import freeze_more, frozen_heap

class Node:
    pass

with frozen_heap():
    a, b = Node(), Node()
    a.other, b.other = b, a
    alive = weakref.ref(a)
    freeze_more()  # the cycle is now in the permanent generation
    del a, b
    gc.collect()
    assert alive() is not None  # frozen: not collected while the report is built
gc.collect()
assert alive() is None  # given back: collected once the report is done
print("ok")
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr


def test_the_collector_is_paused_within_and_as_it_was_after():
    assert gc.isenabled()
    with collector_paused():
        assert not gc.isenabled()
    assert gc.isenabled()
    gc.disable()  # a program that turned it off keeps it off
    try:
        with collector_paused():
            assert not gc.isenabled()
        assert not gc.isenabled()
    finally:
        gc.enable()


def test_what_a_paused_block_made_inside_a_report_is_frozen_as_it_ends():
    """An import makes objects that live as long as the report: frozen as the block ends, the
    first pass after it does not walk them; outside a report nothing is frozen."""
    with collector_paused():
        outside = [[] for _ in range(1000)]  # noqa: F841 - alive after the block
    assert gc.get_freeze_count() == 0
    with frozen_heap():
        before = gc.get_freeze_count()
        with collector_paused():
            made = [[] for _ in range(1000)]  # noqa: F841 - alive after the block
        assert gc.get_freeze_count() >= before + 1000
        assert gc.isenabled()
    assert gc.get_freeze_count() == 0


def _recorded(seen, name, function):
    def wrapper(*args, **kwargs):
        seen[name] = gc.isenabled()
        return function(*args, **kwargs)

    return wrapper


def test_the_report_command_loads_its_plugins_with_the_collector_off(monkeypatch, tmp_path):
    """Its imports and the scene's reading run without the collector, the rendering with it."""
    from crankdyn import cli
    from crankdyn.output import pipeline
    from crankdyn.plugin import registry as registries

    seen: dict[str, bool] = {}
    loaded = registries.default_registry
    monkeypatch.setattr(registries, "default_registry", _recorded(seen, "plugins", loaded))
    monkeypatch.setattr(pipeline, "render_files", _recorded(seen, "render", pipeline.render_files))
    scene = cli.examples_dir() / "kinematics-only.toml"
    assert cli.main(["report", str(scene), "-o", str(tmp_path), "--format", "html", "-q"]) == 0
    assert seen == {"plugins": False, "render": True} and gc.isenabled()


@in_fresh_process
def test_matplotlib_is_imported_with_the_collector_off_while_the_stages_run_aside(monkeypatch):
    from conftest import example_data

    from crankdyn.output import pipeline
    from crankdyn.plugin.registry import default_registry
    from crankdyn.report import figures
    from crankdyn.scene.model import scene_from_dict

    seen: dict[str, bool] = {}
    monkeypatch.setattr(figures, "prepare", _recorded(seen, "matplotlib", figures.prepare))
    scene = scene_from_dict(example_data("kinematics-only"))
    result = pipeline._run_aside(scene, default_registry(), None, ())
    assert result is not None and "kinematics" in result.outputs  # computed by the child
    assert seen == {"matplotlib": False} and gc.isenabled()
    result.close_background()
