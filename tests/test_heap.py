"""crankdyn.engine.frozen_heap: the collector skips what is alive at the start of a report, and gets it all
back at the end (a batch worker or the preview server must not keep a report's objects)."""

from __future__ import annotations

import gc
import subprocess
import sys

from crankdyn.engine.frozen_heap import freeze_more, frozen_heap


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
