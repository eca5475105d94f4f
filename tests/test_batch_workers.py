"""The batch's worker processes (crankdyn.parallel.pool.run_all): each runs several items in turn
(keeping what it loaded), is replaced after VARIANTS_PER_WORKER items, and one that hangs or dies
fails only its own item; nothing is left running, even when the batch's process dies."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time

import pytest

from crankdyn.parallel import pool as batch_runner
from crankdyn.parallel.pool import VARIANTS_PER_WORKER, run_all

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="workers are forked")


def _pid_and_value(value):
    if value == "die":
        os._exit(3)
    if value == "hang":
        time.sleep(60)
    return os.getpid(), value


def _run(items, jobs=1, timeout_s=30.0):
    outcomes = []
    unfinished = run_all(
        items,
        _pid_and_value,
        lambda item: (item,),
        jobs,
        timeout_s,
        outcomes.append,
        lambda item, reason, seconds: ("failed", item, reason),
    )
    assert unfinished == []
    return outcomes


def _children() -> list[int]:
    mine = str(os.getpid())
    pids = []
    for stat in os.listdir("/proc"):
        if stat.isdigit():
            try:
                with open(f"/proc/{stat}/stat") as f:
                    fields = f.read().rsplit(") ", 1)[1].split()
            except OSError:
                continue
            if fields[1] == mine and fields[0] != "Z":
                pids.append(int(stat))
    return pids


def test_a_worker_runs_items_in_turn_and_is_replaced_after_its_share():
    outcomes = _run(list(range(VARIANTS_PER_WORKER + 2)))
    assert [value for _, value in outcomes] == list(range(VARIANTS_PER_WORKER + 2))
    pids = [pid for pid, _ in outcomes]
    assert len(set(pids[:VARIANTS_PER_WORKER])) == 1  # one worker for its whole share
    assert pids[VARIANTS_PER_WORKER] != pids[0]  # then a fresh one
    assert not _children()


@pytest.mark.slow  # waits out a time limit: in the slow tier, which CI runs
def test_a_dead_or_hung_worker_fails_its_item_only():
    outcomes = _run(["a", "die", "b", "hang", "c"], jobs=1, timeout_s=2.0)
    assert [o[1] for o in outcomes] == ["a", "die", "b", "hang", "c"]
    assert outcomes[1][0] == "failed" and "exit code 3" in outcomes[1][2]
    assert outcomes[3][0] == "failed" and "stopped after 2 s" in outcomes[3][2]
    assert (
        len({outcomes[0][0], outcomes[2][0], outcomes[4][0]}) == 3
    )  # a new worker after each lost one
    assert not _children()


def test_an_idle_worker_that_died_is_replaced():
    outcomes = []
    workers = []
    start = batch_runner._start

    def start_and_kill_the_idle(function, idle, args):
        for worker in idle:  # the idle worker dies before it is given the next item
            os.kill(worker.pid, 9)
            os.waitpid(worker.pid, 0)
        worker = start(function, idle, args)
        workers.append(worker.pid)
        return worker

    batch_runner._start = start_and_kill_the_idle
    try:
        run_all(
            ["a", "b"],
            _pid_and_value,
            lambda item: (item,),
            1,
            30.0,
            outcomes.append,
            lambda item, reason, seconds: ("failed", item, reason),
        )
    finally:
        batch_runner._start = start
    assert [value for _, value in outcomes] == ["a", "b"]
    assert outcomes[0][0] != outcomes[1][0]
    assert not _children()


def test_workers_leave_when_the_batch_process_dies():
    # the batch's process ends without stopping its worker (killed, out of memory, ...)
    code = """
    import os, sys
    from crankdyn.parallel.pool import _Worker
    worker = _Worker(print)
    print(worker.pid, flush=True)
    os._exit(0)
    """
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=60
    )
    pid = int(done.stdout.split()[0])
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and os.path.exists(f"/proc/{pid}"):
        try:
            with open(f"/proc/{pid}/stat") as f:
                if f.read().rsplit(") ", 1)[1].split()[0] == "Z":
                    break
        except OSError:
            break
        time.sleep(0.1)
    else:
        assert not os.path.exists(f"/proc/{pid}"), "the orphaned worker is still running"


def _slow_value(value):
    time.sleep(0.2)
    return os.getpid(), value


def test_meanwhile_runs_once_while_the_first_items_are_computed():
    events = []
    outcomes = []
    run_all(
        [1, 2, 3, 4],
        _slow_value,
        lambda item: (item,),
        2,
        30.0,
        lambda outcome: (outcomes.append(outcome), events.append("finished")),
        lambda item, reason, seconds: ("failed", item, reason),
        meanwhile=lambda: events.append("meanwhile"),
    )
    # called once, before any item came back (both workers were busy with the first two)
    assert events[0] == "meanwhile" and events.count("meanwhile") == 1
    assert sorted(value for _, value in outcomes) == [1, 2, 3, 4]


def test_the_answer_keys_workbook_writer_can_be_loaded_ahead():
    code = (
        "import sys\n"
        "from crankdyn.batch import variants\n"
        "assert 'openpyxl' not in sys.modules\n"
        "variants.load_key_writers()\n"
        "assert 'openpyxl.workbook' in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
