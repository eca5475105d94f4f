"""Work a stage hands aside: computed in a forked child on a spare core while the stage goes on.

The ``SERVICE_ASIDE`` a stage names in ``Stage.services`` is :func:`aside`: ``aside(fn, *args)``
starts ``fn(*args)`` and returns a :class:`Handle`, whose ``result()`` is the value (used as a
context manager, so that a child still computing is stopped when the stage leaves early). The
error study's reference and its kinematics and solver studies need nothing from the study's
re-runs at the other steps, so on a machine with two cores ``crankdyn report --format json``
computes them beside those re-runs instead of after them.

Whether a core is spare is the report's process's decision, not the stage's (:func:`spare_core`):
only a report that renders nothing (JSON, CSV, XLSX) has one; its figures' drawers, a batch's
variants and the preview use the cores otherwise. Without a spare core, or where a fork is not
safe, ``result()`` computes ``fn(*args)`` in the stage's own process when asked: the same value.

The child inherits everything (nothing is pickled on the way in) and sends back the pickled
value. A function that raises in the child, a value that cannot be pickled, or a child that dies
is computed again in the stage's process, so the value, and any error, is the one the serial
run gives.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import signal
import threading
from collections.abc import Callable, Iterator
from typing import Any

_spare = False  # set by spare_core() in the process that owns the cores; never in a child


@contextlib.contextmanager
def spare_core(enabled: bool = True) -> Iterator[None]:
    """Within this block, :func:`aside` may fork (when ``enabled`` and the machine has two CPUs)."""
    global _spare
    before = _spare
    _spare = enabled and _cpus() > 1
    try:
        yield
    finally:
        _spare = before


def _cpus() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # no sched_getaffinity (macOS, Windows)
        return os.cpu_count() or 1


class Handle:
    """``fn(*args)``, being computed in a child (``pid``) or not yet computed at all."""

    def __init__(
        self, fn: Callable[..., Any], args: tuple, pid: int | None = None, reader=None
    ) -> None:
        self._fn, self._args = fn, args
        self._pid, self._reader = pid, reader

    def result(self) -> Any:
        """The value of ``fn(*args)``: the child's, or computed here (also when the child failed)."""
        if self._reader is not None:
            try:
                ok, value = pickle.load(self._reader)
            except Exception:  # EOF: the child died; a broken message
                ok, value = False, None
            self.close()
            if ok:
                return value
        return self._fn(*self._args)

    def close(self) -> None:
        """Stop the child if it is still computing, and reap it (nothing when there is none)."""
        if self._reader is None:
            return
        self._reader.close()
        self._reader = None
        if self._pid is not None:  # a reader comes with its child
            stop_child(self._pid)

    def __enter__(self) -> Handle:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def stop_child(pid: int) -> None:
    """Kill the forked child ``pid`` (done or not, it has nothing more to do) and reap it; one that
    ended, or was reaped, already is no error."""
    with contextlib.suppress(ProcessLookupError):
        os.kill(pid, signal.SIGKILL)
    with contextlib.suppress(ChildProcessError):
        os.waitpid(pid, 0)


def can_fork() -> bool:
    """POSIX ``fork``, and no other thread whose held lock a child's copy could stall on."""
    return hasattr(os, "fork") and threading.active_count() == 1


def fork_with_pipe() -> tuple[int, int, int] | None:
    """(pid, read end, write end): a pipe and a fork (pid 0 in the child), or None, with nothing
    left open, where no process is to be had (EAGAIN, ENOMEM): the caller computes itself."""
    read_fd, write_fd = os.pipe()
    try:
        pid = os.fork()
    except OSError:
        os.close(read_fd)
        os.close(write_fd)
        return None
    return pid, read_fd, write_fd


def aside(fn: Callable[..., Any], *args: Any) -> Handle:
    """Start ``fn(*args)`` in a forked child if a core is spare (see the module docstring)."""
    global _spare
    if not (_spare and can_fork()):
        return Handle(fn, args)
    read_fd, write_fd = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: compute, send, and leave without running the parent's exit code
        _spare = False
        status = 0
        try:
            os.close(read_fd)
            with os.fdopen(write_fd, "wb") as out:
                try:
                    message = pickle.dumps((True, fn(*args)), protocol=pickle.HIGHEST_PROTOCOL)
                except Exception:  # computed again in the stage's process, which then raises it
                    message = pickle.dumps((False, None), protocol=pickle.HIGHEST_PROTOCOL)
                out.write(message)
        except BaseException:
            status = 1
        finally:
            os._exit(status)
    os.close(write_fd)
    return Handle(fn, args, pid, os.fdopen(read_fd, "rb"))
