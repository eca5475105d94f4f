"""A sweep's chunk in a process told to give freed memory back at once (a Dask worker's
``MALLOC_TRIM_THRESHOLD_``): its arrays' memory is reused while the chunk computes
(crankdyn.parallel.allocator), and the process is left as it was configured."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

from crankdyn.parallel.allocator import chunk_arrays_reused

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="glibc's mallopt and page-fault counts"
)

#: Page faults of making and freeing a megabyte array 200 times, outside, inside and after
#: chunk_arrays_reused, printed by a fresh process.
_FAULTS = textwrap.dedent(
    """
    import resource
    import numpy as np
    from crankdyn.parallel.allocator import chunk_arrays_reused

    def faults():
        before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        for _ in range(200):
            np.ones(131072).sum()  # 1 MiB, made, touched and freed
        return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before

    outside = faults()
    with chunk_arrays_reused() as changed:
        faults()  # the heap grows to the array's size once
        inside = faults()
    print(changed, outside, inside, faults())
    """
)


def _faults(environment: dict) -> tuple[str, int, int, int]:
    done = subprocess.run(
        [sys.executable, "-c", _FAULTS], env=environment, capture_output=True, text=True, check=True
    )
    changed, outside, inside, after = done.stdout.split()
    return changed, int(outside), int(inside), int(after)


def test_a_chunks_arrays_reuse_freed_memory_in_a_worker_that_trims_at_once():
    environment = {**os.environ, "MALLOC_TRIM_THRESHOLD_": "65536"}
    changed, outside, inside, after = _faults(environment)
    assert changed == "True"
    assert outside > 200 * 100  # each array's 256 pages faulted in afresh
    assert inside < outside / 20  # reused
    assert after > outside / 2  # and as the environment configured it afterwards


def test_nothing_changes_where_the_environment_sets_no_trim_threshold(monkeypatch):
    environment = {k: v for k, v in os.environ.items() if k != "MALLOC_TRIM_THRESHOLD_"}
    changed, *_ = _faults(environment)
    assert changed == "False"
    monkeypatch.delenv("MALLOC_TRIM_THRESHOLD_", raising=False)
    with chunk_arrays_reused() as here:
        assert here is False
