"""The studies of a report computed in a forked child while the report is rendered.

The error against run time (the ``numerics`` stage) re-runs the pipeline at nine steps and times
them: about half a second in which ``crankdyn report`` would otherwise only wait, with the second
core idle, before it imports matplotlib and Jinja and renders the sections. No stage waits for a
study (:func:`crankdyn.orchestrator.is_study`), so a child forked after the other stages computes
the studies meanwhile, and the report takes each study's output when its section comes.

The child inherits everything (nothing is pickled on the way in) and sends back, for each study
in plan order, the pickled ``(name, StageOutput, seconds)``. A study that raises in the child, an
output that cannot be pickled, or a child that dies is computed again in the report's process
(:meth:`crankdyn.orchestrator.RunResult.study_output`), so the result, and any error, is the one
the serial run gives.
"""

from __future__ import annotations

import os
import pickle
import signal

from .aside import can_fork
from .orchestrator import RunResult, run_stage


class ForkedStudies:
    """A child computing a result's deferred studies; see the module docstring."""

    def __init__(self, pid: int, reader) -> None:
        self.pid = pid
        self._reader = reader
        self._received: dict[str, tuple | None] = {}
        self._ended = False

    @classmethod
    def start(cls, result: RunResult) -> "ForkedStudies | None":
        """Fork the child for ``result.deferred`` (None: nothing deferred, or no safe fork)."""
        jobs = [(s, result.deferred[s.name]) for s in result.plan.order if s.name in result.deferred]
        if not jobs or not can_fork():
            return None
        read_fd, write_fd = os.pipe()
        pid = os.fork()
        if pid == 0:  # the child: compute, send, and leave without running the parent's exit code
            status = 0
            try:
                os.close(read_fd)
                with os.fdopen(write_fd, "wb") as out:
                    _compute(result.scene, jobs, out)
            except BaseException:
                status = 1
            finally:
                os._exit(status)
        # closed here at once, so that children forked later (the figures') do not hold it open
        os.close(write_fd)
        return cls(pid, os.fdopen(read_fd, "rb"))

    def take(self, name: str) -> tuple | None:
        """(output, seconds) of study ``name`` from the child; None if the child could not give it."""
        while name not in self._received and not self._ended:
            try:
                got, output, elapsed = pickle.load(self._reader)
            except Exception:  # EOF (the child died or is done), a broken message
                self._ended = True
                break
            self._received[got] = None if output is None else (output, elapsed)
        return self._received.pop(name, None)

    def close(self) -> None:
        """Stop the child if it is still computing, and reap it."""
        self._reader.close()
        try:
            os.kill(self.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        try:
            os.waitpid(self.pid, 0)
        except ChildProcessError:
            pass


def _compute(scene, jobs, out) -> None:
    for stage, inputs in jobs:
        try:
            output, elapsed = run_stage(stage, scene, inputs)
            message = pickle.dumps((stage.name, output, elapsed), protocol=pickle.HIGHEST_PROTOCOL)
        except Exception:  # computed again in the report's process, which then raises it
            message = pickle.dumps((stage.name, None, 0.0), protocol=pickle.HIGHEST_PROTOCOL)
        out.write(message)
        out.flush()


def start_studies(result: RunResult) -> RunResult:
    """``result`` with its deferred studies being computed in a forked child (if one can be)."""
    result.background = ForkedStudies.start(result)
    return result
