"""Errors that reach the user as one clear message, never as a traceback."""

from __future__ import annotations

from dataclasses import dataclass

#: Characters of what one problem says is allowed (a message listing ten thousand bad items
#: would bury the others).
MAX_MESSAGE = 1000
#: Problems a message lists (all of them stay in ``SceneError.problems``).
MAX_LISTED = 50


@dataclass(frozen=True)
class Problem:
    """One thing wrong with the input: where, what was given, what is allowed."""

    field: str
    value: object
    allowed: str

    def __str__(self) -> str:
        shown = "(missing)" if self.value is _MISSING else shorten(self.value)
        allowed = self.allowed
        if len(allowed) > MAX_MESSAGE:
            allowed = allowed[: MAX_MESSAGE - 3] + "..."
        return f"{self.field} = {shown}: {allowed}"


def shorten(value: object, limit: int = 100) -> str:
    """``repr(value)`` (so control characters are escaped) cut to about ``limit`` characters."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


class _Missing:
    def __repr__(self) -> str:
        return "(missing)"


_MISSING = _Missing()
MISSING = _MISSING


class CrankdynError(Exception):
    """Base class of the errors the command line turns into a message and exit code 2."""


class SceneError(CrankdynError):
    """The scene (or a file it refers to) is invalid; carries every problem found."""

    def __init__(self, problems: list[Problem] | Problem, source: str | None = None):
        self.problems = [problems] if isinstance(problems, Problem) else list(problems)
        self.source = source
        super().__init__(self._message())

    def _message(self) -> str:
        source = self.source
        if source is not None and not source.isprintable():  # control characters escaped
            source = repr(source)[1:-1]
        if source is not None and len(source) > 200:
            source = source[:197] + "..."
        head = f"invalid scene {source}" if source else "invalid scene"
        lines = [f"{head}: {len(self.problems)} problem(s)"]
        lines += [f"  - {p}" for p in self.problems[:MAX_LISTED]]
        if len(self.problems) > MAX_LISTED:
            lines.append(f"  ... and {len(self.problems) - MAX_LISTED} more")
        return "\n".join(lines)


class UsageError(CrankdynError):
    """A wrong command-line request (unknown example, format, existing file): its message as it is."""


class PluginError(CrankdynError):
    """A plugin is inconsistent: duplicate names, unmet requirements, cycles."""


class OutputError(CrankdynError):
    """The output folder cannot take the run's files: not a folder, not writable, or a file in the
    way that crankdyn did not write (kept unless the run is forced)."""


class PluginFailure(PluginError):
    """A plugin failed: its import or a hook raised, a stage's ``applies``, ``run`` or ``render``
    (a mechanism's ``check``, ``geometry``) raised or returned what :mod:`crankdyn.plugin.types`
    does not allow, or a stage ran past the time limit. The message is
    ``plugin '<plugin>' (<where>): <what>``; ``where`` is ``import``, ``hook <name>``,
    ``stage '<name>'``, ``mechanism '<name>'`` or ``error probe '<name>'``."""

    def __init__(self, plugin: str, where: str, what: str):
        self.plugin, self.where, self.what = plugin, where, what
        super().__init__(f"plugin {plugin!r} ({where}): {what}")

    def __reduce__(self):  # sent back from a forked child as it is
        return (type(self), (self.plugin, self.where, self.what))


class StageTimeLimit(PluginFailure):
    """A plugin's stage (or hook) ran past the time limit one stage may take
    (``crankdyn report --timeout``, :func:`crankdyn.plugin.guard.stage_time_limit`)."""
