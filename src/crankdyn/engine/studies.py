"""The studies of a report computed in a forked child while the report is rendered.

The error against run time (the ``numerics`` stage) re-runs the pipeline at nine steps and times
them: about half a second in which ``crankdyn report`` would otherwise only wait, with the second
core idle, before it imports matplotlib and Jinja and renders the sections. No stage waits for a
study (:func:`crankdyn.engine.orchestrator.is_study`), so a child forked after the other stages
computes
the studies meanwhile, and the report takes each study's output when its section comes.

The child inherits everything (nothing is pickled on the way in) and sends back, for each study
in plan order, the pickled ``(name, StageOutput, seconds)``. A study that raises in the child, an
output that cannot be pickled, or a child that dies is computed again in the report's process
(:meth:`crankdyn.engine.orchestrator.RunResult.study_output`), so the result, and any error, is the
one
the serial run gives.
"""

from __future__ import annotations

import os
import pickle
import tempfile

from ..errors import StageTimeLimit
from ..parallel.fork import can_fork, fork_with_pipe, stop_child
from ..parallel.messages import receive_message, send_message
from ..plugin.types import StageOutput
from .orchestrator import Plan, RunResult, resume_plan, run_plan, run_stage


class ForkedStudies:
    """A child computing a result's deferred studies; see the module docstring."""

    def __init__(self, pid: int, reader) -> None:
        self.pid = pid
        self._reader = reader
        self._received: dict[str, tuple | None] = {}
        self._ended = False

    @classmethod
    def start(cls, result: RunResult) -> ForkedStudies | None:
        """Fork the child for ``result.deferred`` (None: nothing deferred, or no safe fork)."""
        jobs = [
            (s, result.deferred[s.name]) for s in result.plan.order if s.name in result.deferred
        ]
        if not jobs:
            return None
        child = _fork_sending(lambda out: _compute(result.scene, jobs, out))
        return None if child is None else cls(*child)

    def take(self, name: str) -> tuple | None:
        """(output, seconds) of study ``name`` from the child; None if the child could not give it."""
        while name not in self._received and not self._ended:
            try:
                got, output, elapsed = pickle.load(self._reader)
            except Exception:  # EOF (the child died or is done), a broken message
                self._ended = True
                break
            self._received[got] = None if output is None else (output, elapsed)
        taken = self._received.pop(name, None)
        if taken is not None and isinstance(taken[0], StageTimeLimit):
            raise taken[0]  # computed again here, it would only take as long again
        return taken

    def close(self) -> None:
        """Stop the child if it is still computing, and reap it."""
        self._reader.close()
        stop_child(self.pid)


def _fork_sending(send) -> tuple[int, object] | None:
    """(pid, the file its messages are read from) of a child forked to run ``send(out)`` and
    leave; None where no child may or can be forked (another thread; EAGAIN, ENOMEM): the caller
    then computes in its own process."""
    forked = fork_with_pipe() if can_fork() else None
    if forked is None:
        return None
    pid, read_fd, write_fd = forked
    if pid == 0:  # the child: compute, send, and leave without running the parent's exit code
        status = 0
        try:
            os.close(read_fd)
            with os.fdopen(write_fd, "wb") as out:
                send(out)
        except BaseException:
            status = 1
        finally:
            os._exit(status)
    # closed here at once, so that children forked later (the figures') do not hold it open
    os.close(write_fd)
    return pid, os.fdopen(read_fd, "rb")


def _compute(scene, jobs, out) -> None:
    for stage, inputs in jobs:
        try:
            output, elapsed = run_stage(stage, scene, inputs)
            message = pickle.dumps((stage.name, output, elapsed), protocol=pickle.HIGHEST_PROTOCOL)
        except StageTimeLimit as exc:  # raised by the report's process as it is
            message = pickle.dumps((stage.name, exc, 0.0), protocol=pickle.HIGHEST_PROTOCOL)
        except Exception:  # computed again in the report's process, which then raises it
            message = pickle.dumps((stage.name, None, 0.0), protocol=pickle.HIGHEST_PROTOCOL)
        out.write(message)
        out.flush()


class ForkedRun:
    """A scene's stages computed in a forked child while the report's process gets its rendering
    ready (imports matplotlib, Jinja and the catalogs, which take as long as scipy's import and
    the stages together): the two halves of a report's start-up on two cores.

    The child runs the plan with the studies deferred, leaves the pickled outputs and timings in
    a file in memory (:func:`_spool`) and goes on with the studies as :class:`ForkedStudies` does
    (the same pipe, read by one). The outputs (0.1 to 1 MB) do not go through the pipe: its
    buffer holds 64 kB, so the child would wait there, idle, until the report's process is
    ready to read them, and only then start the studies. Outputs that cannot be pickled, a
    stage that raises, or a child that dies give None: the report's process then runs the plan
    itself, so the result, and any error, is the one the serial run gives.
    """

    def __init__(self, pid: int, reader, spool: int, scene, the_plan: Plan) -> None:
        self.pid, self._reader, self._spool = pid, reader, spool
        self._scene, self._plan = scene, the_plan

    @classmethod
    def start(cls, scene, the_plan: Plan) -> ForkedRun | None:
        spool = _spool()
        child = _fork_sending(lambda out: _run_and_send(scene, the_plan, out, spool))
        if child is None:
            os.close(spool)
            return None
        return cls(*child, spool, scene, the_plan)

    def result(self) -> RunResult | None:
        """The computed result, its studies still coming from the child; None if the child failed."""
        try:
            got = pickle.load(self._reader)
            if isinstance(got, StageTimeLimit):  # computed again here, it would take as long again
                raise got
            if got is None:  # the child could not compute or send the plan
                self.close()
                return None
            outputs, timing = pickle.loads(_read_spool(self._spool, got))
            self._close_spool()
            result = resume_plan(self._scene, self._plan, outputs, timing)
        except BaseException as exc:  # also an interrupt: no child is left computing
            self.close()
            if isinstance(exc, Exception) and not isinstance(exc, StageTimeLimit):
                # EOF (the child died), a broken message: run it here
                return None
            raise
        result.background = ForkedStudies(self.pid, self._reader) if result.deferred else None
        if result.background is None:
            self.close()
        return result

    def _close_spool(self) -> None:
        if self._spool >= 0:
            os.close(self._spool)
            self._spool = -1

    def close(self) -> None:
        self._reader.close()
        self._close_spool()
        stop_child(self.pid)


def _spool() -> int:
    """The descriptor of an unnamed file in memory (memfd; elsewhere an unlinked temporary file)
    that a forked child writes and its parent reads, each at its own offsets (``pwrite``,
    ``pread``)."""
    memfd = getattr(os, "memfd_create", None)
    if memfd is not None:
        try:
            return int(memfd("crankdyn-run", getattr(os, "MFD_CLOEXEC", 0)))
        except OSError:  # no memfd in this kernel or sandbox
            pass
    fd, path = tempfile.mkstemp(prefix="crankdyn-run-")
    os.unlink(path)
    return fd


def _write_spool(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.pwrite(fd, view, len(data) - len(view)) :]


def _read_spool(fd: int, size: int) -> bytes:
    """The ``size`` bytes at the start of the spool; EOFError if it holds fewer."""
    parts, offset = [], 0
    while offset < size:
        part = os.pread(fd, size - offset, offset)
        if not part:
            raise EOFError(f"the computed outputs end at {offset} of {size} bytes")
        parts.append(part)
        offset += len(part)
    return b"".join(parts)


def _run_and_send(scene, the_plan: Plan, out, spool: int) -> None:
    try:
        result = run_plan(scene, the_plan, defer_studies=True)
        message = pickle.dumps((result.outputs, result.timing_s), protocol=pickle.HIGHEST_PROTOCOL)
        _write_spool(spool, message)
    except StageTimeLimit as exc:  # raised by the report's process as it is
        out.write(pickle.dumps(exc))
        return
    except Exception:  # run again in the report's process, which then raises it
        out.write(pickle.dumps(None))
        return
    out.write(pickle.dumps(len(message)))  # the outputs' size in the spool
    out.flush()
    _compute(
        scene,
        [(s, result.deferred[s.name]) for s in the_plan.order if s.name in result.deferred],
        out,
    )


def start_studies(result: RunResult) -> RunResult:
    """``result`` with its deferred studies being computed in a forked child (if one can be)."""
    result.background = ForkedStudies.start(result)
    return result


# ----------------------------------------------------------------- the live preview's study worker
class StudyWorker:
    """A process that computes the live preview's studies while the server renders the rest.

    The preview shows a saved scene's page first and the error study after it; the study can be
    computed meanwhile, on the core the rendering leaves idle. A child forked at each save would
    be forked beside the server's threads (the HTTP server's, the file watcher's), which is not
    safe. So one worker is forked when the preview starts, before any thread, and each save sends
    it the scene (pickled; the stages' data holds functions that cannot be): the worker runs the
    plan itself, with the preview's registry, through a stage cache of its own (the stages before
    the study are cheap next to it), and sends the studies' outputs back, as
    :class:`ForkedStudies` does. The same scene and code give the same values.

    One job at a time, as length-prefixed pickles over a socket pair: the server sends a job only
    when it has read every answer to the previous one (the two never write to each other at
    once). While the worker is still busy with a job nobody waits for any more (the scene was
    saved again), a new save's study is computed in the server instead of waiting. A worker that
    died, or an output it could not pickle, is computed again in the server's process
    (:meth:`RunResult.study_output`).
    """

    def __init__(self, pid: int, sock) -> None:
        self.pid = pid
        self._sock = sock
        self._jobs = 0
        self._unread: int | None = None  # the job whose answers are not all read yet
        self.alive = True

    @classmethod
    def start(cls, registry=None) -> StudyWorker | None:
        """Fork the worker (None where fork is not safe: no ``fork``, or other threads running);
        it computes with ``registry`` (None: the installed plugins, loaded in the worker)."""
        import socket  # lazy: heavy optional import (only the live preview has a study worker)

        if not can_fork():
            return None
        ours, theirs = socket.socketpair()
        pid = os.fork()
        if pid == 0:  # the worker: serve jobs until the server closes the socket
            ours.close()
            status = 0
            try:
                _serve_jobs(theirs, registry)
            except BaseException:
                status = 1
            finally:
                os._exit(status)
        theirs.close()
        return cls(pid, ours)

    def submit(self, scene, stages: list[str] | None, studies: list[str]) -> WorkerJob | None:
        """Have the worker run ``scene``'s plan (``stages`` as asked for, None: all) and send
        the outputs of the ``studies`` in it; None (computed in the server) when the worker is
        busy with an earlier job, is gone, or the scene cannot be pickled."""
        if not self.alive:
            return None
        self._drain(block=False)
        if self._unread is not None:  # still computing a study nobody waits for
            return None
        try:
            message = pickle.dumps(
                (self._jobs + 1, scene, stages, studies), protocol=pickle.HIGHEST_PROTOCOL
            )
        except Exception:  # noqa: BLE001 - this scene cannot be sent: computed in the server, this time
            return None
        try:
            send_message(self._sock, message)
        except OSError:  # the worker is gone
            self._fail()
            return None
        self._jobs += 1
        self._unread = self._jobs
        return WorkerJob(self, self._jobs)

    def _read(self, job: int) -> tuple | None:
        """The worker's next message for ``job`` ((None,) at its end: no stage is named None), skipping older jobs'."""
        while self.alive and self._unread is not None:
            try:
                number, message = pickle.loads(receive_message(self._sock))
            except Exception:  # noqa: BLE001 - EOF or a broken message: the worker died
                self._fail()
                return None
            if message[0] is None and number == self._unread:
                self._unread = None
            if number == job:
                return message
        return None

    def _drain(self, block: bool = True) -> None:
        """Read the answers to the unread job: all of them, or (``block`` False) those already sent."""
        import select  # lazy: heavy optional import (only the live preview has a study worker)

        while self._unread is not None and self.alive:
            if not block and not select.select([self._sock], [], [], 0)[0]:
                return
            self._read(self._unread)

    def _fail(self) -> None:
        self.alive = False
        self._unread = None

    def stop(self) -> None:
        """End the worker and reap it (first: a thread reading its answers then sees EOF at once)."""
        self.alive = False
        stop_child(self.pid)
        self._sock.close()


class WorkerJob:
    """One save's studies at the :class:`StudyWorker`: the ``background`` of a :class:`RunResult`."""

    def __init__(self, worker: StudyWorker, number: int) -> None:
        self._worker, self._number = worker, number
        self._received: dict[str, tuple | None] = {}
        self._ended = False

    def take(self, name: str) -> tuple | None:
        """(output, seconds) of study ``name``; None if the worker could not give it."""
        while name not in self._received and not self._ended:
            message = self._worker._read(self._number)
            if message is None or message[0] is None:
                self._ended = True
                break
            got, output, elapsed = message
            self._received[got] = None if output is None else (output, elapsed)
        taken = self._received.pop(name, None)
        if taken is not None and isinstance(taken[0], StageTimeLimit):
            raise taken[0]  # computed again here, it would only take as long again
        return taken

    def wait(self, timeout: float) -> None:
        """Until the worker has an answer waiting (or ``timeout`` s have passed), reading nothing:
        the caller stays idle while the worker computes."""
        import select  # lazy: heavy optional import (only the live preview has a study worker)

        if self._received or self._ended or not self._worker.alive:
            return
        try:
            select.select([self._worker._sock], [], [], timeout)
        except (OSError, ValueError):  # the worker's socket is closed: take() says so
            pass

    def close(self) -> None:
        """Nothing to stop: the worker's remaining answers are read before its next job."""
        self._ended = True


def _serve_jobs(sock, registry=None) -> None:
    from ..plugin.registry import (
        default_registry,  # lazy: heavy optional import (the plugins, in the worker)
    )
    from .orchestrator import plan  # lazy: heavy optional import (only the preview's worker plans)
    from .stage_cache import (
        StageCache,  # lazy: heavy optional import (only the preview's worker caches stages)
    )

    cache = StageCache()
    while True:
        try:
            number, scene, stages, studies = pickle.loads(receive_message(sock))
        except EOFError:
            return
        registry = registry or default_registry()
        try:
            result = cache.run_plan(scene, plan(scene, registry, stages))
            outputs: list[tuple[str, StageOutput | None, float]] = [
                (name, result.outputs[name], result.timing_s[name]) for name in studies
            ]
        except Exception:  # noqa: BLE001 - computed again in the server's process, which then raises it
            outputs = [(name, None, 0.0) for name in studies]
        for name, output, elapsed in outputs:
            try:
                message = pickle.dumps(
                    (number, (name, output, elapsed)), protocol=pickle.HIGHEST_PROTOCOL
                )
            except Exception:  # noqa: BLE001 - an output that cannot be pickled: computed in the server
                message = pickle.dumps(
                    (number, (name, None, 0.0)), protocol=pickle.HIGHEST_PROTOCOL
                )
            send_message(sock, message)
        send_message(sock, pickle.dumps((number, (None,)), protocol=pickle.HIGHEST_PROTOCOL))
