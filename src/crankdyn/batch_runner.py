"""Running a batch's variants in worker processes, each with a time limit.

Every variant runs in a process of its own (forked where the platform allows, so the
plugins and libraries loaded once by the parent are shared), at most ``jobs`` at a
time. A variant that exceeds ``timeout`` seconds is killed and becomes a failure row;
a worker that dies without an answer is one too. Ctrl-C stops the workers and ends the
loop cleanly: the caller still writes the answer key and the failure list of what
finished.
"""

from __future__ import annotations

import multiprocessing
import signal
import time
from collections import deque
from collections.abc import Callable, Sequence
from multiprocessing.connection import wait

DEFAULT_TIMEOUT_S = 120.0


def _context():
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("fork" if "fork" in methods else None)


def _child(connection, function: Callable, args: tuple) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    try:
        connection.send(function(*args))
    finally:
        connection.close()


def run_all(items: Sequence, function: Callable, args_of: Callable, jobs: int, timeout_s: float,
            finished: Callable, failed: Callable[[object, str, float], object]) -> list:
    """Run ``function(*args_of(item))`` for every item in worker processes, ``jobs`` at a time.

    ``finished(outcome)`` is called with each result as it arrives; ``failed(item, reason,
    seconds)`` makes the outcome of an item that timed out or whose worker died. Returns
    the items not finished when Ctrl-C stopped the run (empty when everything ran).
    """
    context = _context()
    queue = deque(items)
    running: dict = {}  # connection -> (process, item, start time)
    try:
        while queue or running:
            while queue and len(running) < jobs:
                item = queue.popleft()
                receive, send = context.Pipe(duplex=False)
                process = context.Process(target=_child, args=(send, function, args_of(item)), daemon=True)
                process.start()
                send.close()
                running[receive] = (process, item, time.monotonic())
            now = time.monotonic()
            left = min(start + timeout_s - now for _, _, start in running.values())
            for connection in wait(list(running), timeout=max(0.0, left)):
                process, item, start = running.pop(connection)
                try:
                    outcome = connection.recv()
                except (EOFError, OSError):
                    process.join(5)
                    outcome = failed(item, f"the worker ended without a result (exit code {process.exitcode})",
                                     time.monotonic() - start)
                connection.close()
                process.join(5)
                finished(outcome)
            now = time.monotonic()
            for connection, (process, item, start) in list(running.items()):
                if now - start >= timeout_s:
                    _stop(process)
                    connection.close()
                    del running[connection]
                    finished(failed(item, f"stopped after {timeout_s:g} s (the time limit, --timeout)", now - start))
    except KeyboardInterrupt:
        unfinished = [item for _, item, _ in running.values()] + list(queue)
        for connection, (process, _, _) in running.items():
            _stop(process)
            connection.close()
        return unfinished
    return []


def _stop(process) -> None:
    process.kill()
    process.join(5)
