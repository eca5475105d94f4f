"""Running a batch's variants in worker processes, each with a time limit.

The variants run in worker processes (forked where the platform allows, so the plugins
and libraries loaded once by the parent are shared), at most ``jobs`` at a time, each
worker running several variants in turn. A variant that exceeds ``timeout`` seconds is
killed with its worker and becomes a failure row; a worker that dies without an answer
is one too. Ctrl-C, and SIGTERM (what ``kill``, ``timeout`` and job schedulers send) alike,
stops the workers and ends the loop cleanly: the caller still writes the answer key and the
failure list of what finished.
"""

from __future__ import annotations

import gc
import os
import pickle
import select
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from multiprocessing.connection import Pipe, wait

from .fork import stop_child

DEFAULT_TIMEOUT_S = 120.0

#: The longest time limit a variant may be given (``--timeout``), and the longest wait for a Dask
#: scheduler (``--connect-timeout``): one day, in seconds.
MAX_TIMEOUT_S = 86_400.0


def check_seconds(option: str, value: object) -> float:
    """``value`` as a number of seconds above 0 and at most :data:`MAX_TIMEOUT_S`; anything else
    (infinity, NaN, a negative number, a string) raises UsageError naming ``option``."""
    from ..errors import (
        UsageError,  # lazy: heavy optional import (the runner itself needs no errors)
    )

    number = value if isinstance(value, (int, float)) and not isinstance(value, bool) else None
    if number is None or not 0 < number <= MAX_TIMEOUT_S:  # False for NaN too
        shown = (
            repr(value)
            if number is None
            else f"{number:g}"
            if isinstance(number, float)
            else str(number)
        )
        raise UsageError(
            f"{option} {shown}: give a number of seconds above 0 and at most "
            f"{MAX_TIMEOUT_S:g} (one day)"
        )
    return float(number)


class StopSignal(KeyboardInterrupt):
    """The KeyboardInterrupt a signal handled as Ctrl-C raises; ``number`` is the signal's."""

    def __init__(self, number: int):
        super().__init__(f"signal {number}")
        self.number = number


@contextmanager
def stop_signals() -> Iterator[list[int]]:
    """While the block runs, SIGTERM is handled as Ctrl-C is: it raises :class:`StopSignal` (once;
    a further signal while the run stops is let pass). Yields the list the received signal's
    number is put in. Only the main thread can handle signals: elsewhere nothing changes, and a
    signal the process ignores stays ignored."""
    received: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield received
        return

    def stop(number, frame):
        if not received:
            received.append(number)
            raise StopSignal(number)

    wanted = {signal.SIGTERM: signal.SIG_DFL, signal.SIGINT: signal.default_int_handler}
    previous = {number: signal.getsignal(number) for number in wanted}
    mine = [number for number, default in wanted.items() if previous[number] is default]
    for number in mine:
        signal.signal(number, stop)
    try:
        yield received
    finally:
        for number in mine:
            signal.signal(number, previous[number])


#: Variants one worker process runs before a fresh fork of the batch's process replaces it. A
#: worker keeps what its first variant loaded and typeset (mathtext, text metrics, compiled
#: templates, locale data) for the next ones: a fork per variant lost it every time, about a third
#: more CPU per variant. The bound keeps a long batch's workers from growing.
VARIANTS_PER_WORKER = 16


def _serve_variants(connection, function: Callable) -> None:
    """A worker's life: ``function(*args)`` for each ``args`` received, the result sent back,
    until told to stop (None) or its batch is gone (EOF)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not the parent's handler: a worker just ends
    parent = os.getppid()
    try:
        while True:
            try:
                # a worker forked later holds a copy of this pipe's other end: no EOF comes when
                # the batch's process dies, so a worker also leaves when it has a new parent
                if not connection.poll(1.0):
                    if os.getppid() != parent:
                        return
                    continue
                args = connection.recv()
            except (EOFError, OSError):
                return
            if args is None:
                return
            connection.send(function(*args))
    finally:
        connection.close()


class _Worker:
    """A forked worker process (it inherits the function and everything the parent loaded) and
    the parent's end of its pipe."""

    def __init__(self, function: Callable):
        self.connection, theirs = Pipe(duplex=True)
        pid = os.fork()
        if pid == 0:  # the worker: serve, then leave without the parent's exit handlers
            code = 1
            try:
                self.connection.close()
                _serve_variants(theirs, function)
                code = 0
            finally:
                os._exit(code)
        theirs.close()
        self.pid = pid
        self.variants = 0

    def ended(self, timeout_s: float = 5.0) -> int | None:
        """Wait (up to ``timeout_s``) for a worker whose pipe closed to end; its exit code, or None
        if it did not (it is then killed)."""
        deadline = time.monotonic() + timeout_s
        while True:
            try:
                pid, status = os.waitpid(self.pid, os.WNOHANG)
            except ChildProcessError:
                return None
            if pid:
                self.connection.close()
                return os.waitstatus_to_exitcode(status)
            if time.monotonic() > deadline:
                self.kill()
                return None
            time.sleep(0.01)

    def retire(self) -> None:
        """Stop an idle worker (it finishes nothing: it waits for the next variant)."""
        try:
            self.connection.send(None)
        except (OSError, ValueError):
            pass
        self.ended()

    def kill(self) -> None:
        """Stop the worker now and wait for it."""
        stop_child(self.pid)
        self.connection.close()


def _start(function: Callable, idle: list, args: tuple) -> _Worker:
    """An idle worker (else a new one) given ``args``; a worker that died while idle is replaced."""
    while idle:
        worker = idle.pop()
        try:
            worker.connection.send(args)
            return worker
        except (OSError, ValueError):
            worker.kill()
    worker = _Worker(function)
    worker.connection.send(args)
    return worker


def run_all(
    items: Sequence,
    function: Callable,
    args_of: Callable,
    jobs: int,
    timeout_s: float,
    finished: Callable,
    failed: Callable[[object, str, float], object],
    meanwhile: Callable[[], object] | None = None,
) -> list:
    """Run ``function(*args_of(item))`` for every item in worker processes, ``jobs`` at a time.

    Each worker runs up to :data:`VARIANTS_PER_WORKER` items one after the other; one that
    exceeds ``timeout_s`` is killed (its item fails) and a fresh worker takes the next item.
    ``finished(outcome)`` is called with each result as it arrives; ``failed(item, reason,
    seconds)`` makes the outcome of an item that timed out or whose worker died. ``meanwhile()``
    is called once, after the first items went to the workers, while they compute them (this
    process would otherwise only wait). Returns the items not finished when Ctrl-C stopped the
    run (empty when everything ran).
    """
    if not hasattr(os, "fork"):  # Windows: one after the other in this process, without a limit
        return _run_here(items, function, args_of, finished)
    queue = deque(items)
    idle: list[_Worker] = []
    running: dict = {}  # connection -> (worker, item, start time)
    try:
        while queue or running:
            while queue and len(running) < jobs:
                item = queue.popleft()
                worker = _start(function, idle, args_of(item))
                running[worker.connection] = (worker, item, time.monotonic())
            if meanwhile is not None:
                meanwhile, later = None, meanwhile
                later()
            now = time.monotonic()
            left = min(start + timeout_s - now for _, _, start in running.values())
            for connection in wait(list(running), timeout=max(0.0, left)):
                worker, item, start = running.pop(connection)
                try:
                    outcome = connection.recv()
                except (EOFError, OSError):
                    code = worker.ended()
                    outcome = failed(
                        item,
                        f"the worker ended without a result (exit code {code})",
                        time.monotonic() - start,
                    )
                else:
                    worker.variants += 1
                    if worker.variants < VARIANTS_PER_WORKER:
                        idle.append(worker)
                    else:
                        worker.retire()
                finished(outcome)
            now = time.monotonic()
            for connection, (worker, item, start) in list(running.items()):
                if now - start >= timeout_s:
                    worker.kill()
                    del running[connection]
                    finished(
                        failed(
                            item,
                            f"stopped after {timeout_s:g} s (the time limit, --timeout)",
                            now - start,
                        )
                    )
    except KeyboardInterrupt:
        unfinished = [item for _, item, _ in running.values()] + list(queue)
        for worker, _, _ in running.values():
            worker.kill()
        running.clear()
        return unfinished
    finally:
        for worker in idle:
            worker.retire()
        for worker, _, _ in running.values():  # an error in finished(): nothing left running
            worker.kill()
    return []


def _run_here(items: Sequence, function: Callable, args_of: Callable, finished: Callable) -> list:
    queue = deque(items)
    try:
        while queue:
            finished(function(*args_of(queue[0])))
            queue.popleft()
    except KeyboardInterrupt:
        return list(queue)
    return []


# --------------------------------------------------------------------------- one call with a time limit

# A Dask worker runs tasks in threads. A fork copies only the forking thread, so a module another
# thread is importing at that moment would reach the child half-made (or with its import lock held):
# loading the libraries and forking happen one thread at a time.
_FORK_LOCK = threading.Lock()


def run_limited(
    function: Callable, args: tuple, timeout_s: float, prepare: Callable | None = None
) -> tuple[str, object, float]:
    """``function(*args)`` in a forked child stopped after ``timeout_s``; used on Dask workers.

    Returns ``("ok", result, seconds)``, ``("timeout", None, seconds)`` or ``("died", exit code,
    seconds)``. ``os.fork`` is used directly, not ``multiprocessing``: a Dask worker is a daemonic
    process, which ``multiprocessing`` refuses children. The child starts with everything the
    worker has loaded, so only the first task on a worker pays for the imports. Where there is no
    fork (Windows) the call runs in the worker itself, without a limit. ``prepare()`` (loading the
    libraries) runs first, under the same lock as the fork.
    """
    with _FORK_LOCK:
        if prepare is not None:
            prepare()
        start = time.monotonic()  # the limit is the variant's own time, not the wait for the lock
        if not hasattr(os, "fork"):
            return "ok", function(*args), time.monotonic() - start
        read_end, write_end = os.pipe()
        pid = _fork_frozen()
    if (
        pid == 0
    ):  # the child: compute, send the pickled answer, leave without running the worker's exit hooks
        code = 0
        try:
            os.close(read_end)
            try:
                signal.signal(signal.SIGINT, signal.SIG_IGN)
            except ValueError:  # not the main thread of the interpreter: nothing to ignore then
                pass
            data = pickle.dumps(function(*args), protocol=pickle.HIGHEST_PROTOCOL)
            with os.fdopen(write_end, "wb") as pipe:
                pipe.write(data)
        except BaseException:  # noqa: BLE001 - the parent reports the exit code
            code = 70
        finally:
            os._exit(code)
    os.close(write_end)
    chunks, deadline = [], start + timeout_s
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([read_end], [], [], left)[0]:
                stop_child(pid)
                return "timeout", None, time.monotonic() - start
            chunk = os.read(read_end, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
    finally:
        os.close(read_end)
    _, status = os.waitpid(pid, 0)
    seconds = time.monotonic() - start
    if not chunks:
        return "died", os.waitstatus_to_exitcode(status), seconds
    return "ok", pickle.loads(b"".join(chunks)), seconds


def _fork_frozen() -> int:
    """``os.fork()`` with everything this process holds out of the child's collector's sight
    (``gc.freeze``): its collections would otherwise walk every inherited object, and so copy the
    worker's memory page by page. The worker's own collector is given back its objects at once
    (unless something had frozen them before)."""
    thawed = gc.get_freeze_count() == 0
    if thawed:
        gc.freeze()
    pid = os.fork()
    if pid != 0 and thawed:
        gc.unfreeze()
    return pid


def _dask_task(prepare: Callable | None, function: Callable, args: tuple, timeout_s: float):
    """What a Dask worker runs for one item: load the libraries once per worker, then the limited call."""
    return run_limited(function, args, timeout_s, prepare)


class OutOfTime(Exception):
    """Raised by a function that keeps its own time limit (:func:`run_all_dask`'s ``in_process``)
    when it stops at it."""


#: Seconds a chunk run in a Dask worker's own process gets beyond its limit before the task
#: gives it up: the chunk checks its limit only between stages and points.
DASK_GRACE_S = 1.0


def _dask_task_here(prepare: Callable | None, function: Callable, args: tuple, timeout_s: float):
    """An item run in the Dask worker's own process: no fork, so what the worker computed for one
    item (caches, typeset labels, warmed code paths) serves the next, and no memory is copied.
    ``function`` keeps its own time limit and raises :class:`OutOfTime` when it stops at it.

    A call that never returns (a plugin's stage stuck inside one point) cannot check its limit:
    the item runs in a daemon thread, and the task answers "timeout" when the thread has not
    finished ``DASK_GRACE_S`` after the limit. The stuck call is left behind (nothing can stop a
    thread), but the sweep goes on: its points run again one by one in forked children that are
    killed at the limit.
    """
    if prepare is not None:
        with _FORK_LOCK:
            prepare()
    start = time.monotonic()
    answer: dict[str, object] = {}

    def call() -> None:
        try:
            answer["value"] = function(*args)
        except OutOfTime:
            answer["timeout"] = True
        except BaseException as exc:  # noqa: BLE001 - raised again in the task's own thread
            answer["error"] = exc

    worker = threading.Thread(target=call, name="crankdyn-dask-item", daemon=True)
    worker.start()
    worker.join(timeout_s + DASK_GRACE_S)
    seconds = time.monotonic() - start
    if worker.is_alive() or "timeout" in answer:
        return "timeout", None, seconds
    if "error" in answer:
        raise answer["error"]  # type: ignore[misc]
    return "ok", answer["value"], seconds


def connect(address: str, timeout_s: float):
    """A ``dask.distributed.Client`` of the scheduler at ``address``.

    ValueError for an address that is not one (``localhost`` without a port), ConnectionError for
    a scheduler that cannot be reached within ``timeout_s`` seconds.
    """
    from distributed import Client  # lazy: heavy optional import (the dask extra)
    from distributed.comm import resolve_address  # lazy: heavy optional import (the dask extra)

    try:
        # A malformed address is refused before a Client exists: a half-made one complains at exit.
        resolve_address(address)
    except (ValueError, TypeError) as exc:
        raise ValueError(str(exc)) from None
    try:
        return Client(address, timeout=timeout_s, set_as_default=False)
    except (OSError, TimeoutError, ValueError, TypeError) as exc:
        reason = str(exc).strip().splitlines()[0] if str(exc).strip() else exc.__class__.__name__
        raise ConnectionError(reason) from None


def run_all_dask(
    items: Sequence,
    function: Callable,
    args_of: Callable,
    client,
    timeout_s: float,
    finished: Callable,
    failed: Callable[[object, str, float], object],
    prepare: Callable | None = None,
    collect: Callable | None = None,
    in_process: bool = False,
) -> list:
    """:func:`run_all` on a Dask cluster: every item a task, each limited to ``timeout_s`` on its worker.

    ``collect(outcome)`` runs on this machine as each answer arrives (it writes the files the
    worker rendered) and returns the outcome to report. Returns the items not finished when
    Ctrl-C stopped the run. With ``in_process`` the items run in the worker's own process, not
    in a forked child: ``function`` then keeps the time limit itself (:class:`OutOfTime`).
    """
    from distributed import as_completed  # lazy: heavy optional import (the dask extra)

    task = _dask_task_here if in_process else _dask_task
    futures = {}
    for number, item in enumerate(items):
        future = client.submit(
            task,
            prepare,
            function,
            args_of(item),
            timeout_s,
            pure=False,
            key=f"crankdyn-{number}-{time.time_ns()}",
        )
        futures[future] = item
    pending = set(futures)
    try:
        for future in as_completed(list(futures), loop=client.loop):
            pending.discard(future)
            item = futures[future]
            try:
                status, value, seconds = future.result()
            except Exception as exc:  # noqa: BLE001 - a lost worker or task fails its item only
                finished(
                    failed(
                        item,
                        f"the Dask cluster returned no result ({exc.__class__.__name__}: {exc})",
                        0.0,
                    )
                )
                continue
            if status == "timeout":
                outcome = failed(
                    item, f"stopped after {timeout_s:g} s (the time limit, --timeout)", seconds
                )
            elif status == "died":
                outcome = failed(
                    item, f"the worker ended without a result (exit code {value})", seconds
                )
            else:
                outcome = collect(value) if collect else value
            finished(outcome)
    except KeyboardInterrupt:
        client.cancel(list(pending))
        return [futures[f] for f in futures if f in pending]
    return []
