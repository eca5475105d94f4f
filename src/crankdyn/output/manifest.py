"""The output folder's manifest: what crankdyn wrote there, byte for byte, so a rerun may tidy up.

Each run writes ``.crankdyn-manifest.json`` listing every file it wrote with its size and SHA-256.
The manifest carries a format marker and the folder it was written for; one without the marker, or
written for another folder (a folder copied or moved together with its manifest), is ignored.

A later run into the same folder

* replaces a file only when the file is byte-for-byte what crankdyn wrote there (or identical to
  what it writes now); a file the user edited, or a file of the user's that has the name of an
  output, is kept and the run is refused, unless ``force`` is given;
* removes the files of the previous run that it does not write again only when they are
  byte-for-byte what crankdyn wrote; an edited one is kept and named in a warning;
* never writes through a symbolic link or outside the folder: every folder below the output folder
  is opened without following links, and every file is created there without following them.

The output folder itself may be a link (the user named it); nothing below it may be one.
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import secrets
import stat
import warnings
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from ..errors import OutputError
from ..version import __version__

MANIFEST = ".crankdyn-manifest.json"
FORMAT_MARKER = "crankdyn output manifest"
FORMAT_VERSION = 2

_DIR_FLAGS = os.O_RDONLY | getattr(os, "O_DIRECTORY", 0) | getattr(os, "O_NOFOLLOW", 0)
_FILE_FLAGS = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0)
_SHOWN_CONFLICTS = 5


class KeptFileWarning(UserWarning):
    """A file crankdyn wrote earlier was changed since, so a rerun kept it instead of removing it."""


@dataclass(frozen=True)
class Version:
    """One state of a file: its size in bytes and its SHA-256 in hex."""

    size: int
    sha256: str

    @classmethod
    def of(cls, payload: bytes) -> Version:
        return cls(len(payload), hashlib.sha256(payload).hexdigest())

    def as_json(self) -> dict[str, object]:
        return {"size": self.size, "sha256": self.sha256}


@dataclass
class _Plan:
    """What a run does to the folder, decided before anything is written."""

    to_write: dict[str, bytes] = field(default_factory=dict)
    unchanged: set[str] = field(default_factory=set)
    conflicts: list[str] = field(default_factory=list)


def write_outputs(out_dir: Path, files: dict[str, bytes], *, force: bool = False) -> list[Path]:
    """Write ``files`` (relative name -> bytes) below ``out_dir``, tidy the previous run's files and
    record the new manifest; return the paths of ``files``.

    Each file appears whole or not at all (a temporary file renamed into place). Raises
    :class:`crankdyn.errors.OutputError`, with nothing written, when the folder cannot be made or
    written, when a name is taken by a link or a folder, or when a file there is not what crankdyn
    wrote (an edited output, a user's own file) and ``force`` is not given. A previous output that
    was edited since is kept and named in a :class:`KeptFileWarning`.
    """
    out_dir = Path(out_dir)
    for name in files:
        _check_name(name)
    with _Folder.open(out_dir) as folder:
        previous = read_manifest(folder, out_dir)
        plan = _plan(folder, files, previous, force)
        if plan.conflicts:
            raise OutputError(_conflict_message(out_dir, plan.conflicts))
        new_versions = {name: Version.of(payload) for name, payload in files.items()}
        # First a manifest of every state the folder may be in while writing, so a run stopped
        # half-way (a time limit, Ctrl-C) leaves each file recognisable as crankdyn's to the next.
        interim = {name: list(versions) for name, versions in previous.items()}
        for name, version in new_versions.items():
            interim.setdefault(name, [])
            if version not in interim[name]:
                interim[name].append(version)
        folder.write(MANIFEST, _manifest_bytes(out_dir, interim))
        for name, payload in plan.to_write.items():
            folder.write(name, payload)
        for name in sorted(set(previous) - set(files)):
            _remove_if_unchanged(folder, out_dir, name, previous[name])
        folder.write(MANIFEST, _manifest_bytes(out_dir, {n: [v] for n, v in new_versions.items()}))
    return [out_dir / name for name in files]


def check_outputs(
    out_dir: Path, names: list[str] | tuple[str, ...], *, force: bool = False
) -> None:
    """Raise :class:`crankdyn.errors.OutputError` when :func:`write_outputs` would refuse to write
    ``names`` into ``out_dir`` whatever their content (a user's file, an edited output, a link):
    a batch checks its answer key's place before it computes its variants. Writes nothing."""
    out_dir = Path(out_dir)
    if not out_dir.exists() and not out_dir.is_symlink():
        return
    with _Folder.open(out_dir) as folder:
        previous = read_manifest(folder, out_dir)
        payloads = {name: None for name in names}
        plan = _plan(folder, payloads, previous, force)  # type: ignore[arg-type]
        if plan.conflicts:
            raise OutputError(_conflict_message(out_dir, plan.conflicts))


def _plan(
    folder: _Folder, files: dict[str, bytes], previous: dict[str, list[Version]], force: bool
) -> _Plan:
    plan = _Plan()
    for name, payload in {MANIFEST: b"", **files}.items():
        state = folder.inspect(name)
        if state.kind == "missing":
            plan.to_write[name] = payload
        elif state.kind == "blocked":
            plan.conflicts.append(f"{name}: {state.detail}")
        elif state.kind == "link":
            if force:
                plan.to_write[name] = (
                    payload  # the link itself is replaced; its target is untouched
                )
            else:
                plan.conflicts.append(
                    f"{name}: a symbolic link (crankdyn writes nothing through links)"
                )
        elif name == MANIFEST:
            if not (force or _is_a_manifest(state.content)):
                plan.conflicts.append(f"{name}: not a crankdyn manifest")
        elif state.content == payload:
            plan.unchanged.add(name)
        elif force or Version.of(state.content) in previous.get(name, ()):
            plan.to_write[name] = payload
        else:
            plan.conflicts.append(
                f"{name}: "
                + (
                    "changed since crankdyn wrote it"
                    if name in previous
                    else "not written by crankdyn"
                )
            )
    plan.to_write.pop(MANIFEST, None)  # written twice by write_outputs itself
    return plan


def _conflict_message(out_dir: Path, conflicts: list[str]) -> str:
    shown = conflicts[:_SHOWN_CONFLICTS]
    more = len(conflicts) - len(shown)
    lines = [f"output folder {out_dir}: {len(conflicts)} file(s) in the way, nothing written:"]
    lines += [f"  - {line}" for line in shown]
    if more:
        lines.append(f"  - and {more} more")
    lines.append(
        "move them away, choose another folder with -o, or give --force to replace "
        "files that are in the way (links are replaced, never followed)"
    )
    return "\n".join(lines)


def _remove_if_unchanged(
    folder: _Folder, out_dir: Path, name: str, versions: list[Version]
) -> None:
    state = folder.inspect(name)
    if state.kind == "missing":
        return
    if state.kind == "file" and Version.of(state.content) in versions:
        folder.remove(name)
        return
    what = "changed since crankdyn wrote it" if state.kind == "file" else "no longer a plain file"
    warnings.warn(
        KeptFileWarning(f"kept {out_dir / name}: {what}; this run no longer writes it"),
        stacklevel=3,
    )


def _manifest_bytes(out_dir: Path, entries: dict[str, list[Version]]) -> bytes:
    document = {
        "format": FORMAT_MARKER,
        "format_version": FORMAT_VERSION,
        "folder": _folder_key(out_dir),
        "crankdyn_version": __version__,
        "files": {
            name: [v.as_json() for v in versions] for name, versions in sorted(entries.items())
        },
    }
    return (json.dumps(document, indent=2, ensure_ascii=False) + "\n").encode("utf-8")


def _folder_key(out_dir: Path) -> str:
    return str(Path(out_dir).resolve())


def read_manifest(folder: _Folder, out_dir: Path) -> dict[str, list[Version]]:
    """The files (name -> the states crankdyn left them in) of the manifest in ``folder``; empty when
    there is none, or it is not crankdyn's, or it was written for another folder."""
    state = folder.inspect(MANIFEST)
    if state.kind != "file":
        return {}
    try:
        document = json.loads(state.content.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError):
        return {}
    if not (
        isinstance(document, dict)
        and document.get("format") == FORMAT_MARKER
        and document.get("format_version") == FORMAT_VERSION
        and document.get("folder") == _folder_key(out_dir)
        and isinstance(document.get("files"), dict)
    ):
        return {}
    entries: dict[str, list[Version]] = {}
    for name, versions in document["files"].items():
        parsed = [_version(v) for v in versions] if isinstance(versions, list) else []
        valid = [v for v in parsed if v is not None]
        if valid and _valid_name(name) and name != MANIFEST:
            entries[name] = valid
    return entries


def _version(entry: object) -> Version | None:
    if not isinstance(entry, dict):
        return None
    size, digest = entry.get("size"), entry.get("sha256")
    if (
        isinstance(size, int)
        and not isinstance(size, bool)
        and size >= 0
        and isinstance(digest, str)
        and len(digest) == 64
        and all(c in "0123456789abcdef" for c in digest)
    ):
        return Version(size, digest)
    return None


def _is_a_manifest(content: bytes) -> bool:
    """Whether a file named like the manifest is one crankdyn wrote (this format or an older one)."""
    try:
        document = json.loads(content.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError):
        return False
    return isinstance(document, dict) and (
        "crankdyn_version" in document or document.get("format") == FORMAT_MARKER
    )


def _valid_name(name: object) -> bool:
    if not isinstance(name, str) or not name or "\\" in name or "\x00" in name:
        return False
    path = PurePosixPath(name)
    return (
        not path.is_absolute()
        and all(part not in ("", ".", "..") for part in path.parts)
        and str(path) == name
    )


def _check_name(name: str) -> None:
    if not _valid_name(name):
        raise ValueError(f"output name {name!r} is not a relative path inside the output folder")


@dataclass(frozen=True)
class _State:
    kind: str  # "missing", "file", "link" or "blocked" (a folder, a device, a link above it ...)
    content: bytes = b""
    detail: str = ""


class _Folder:
    """The output folder, opened once; every path below it is reached without following links."""

    def __init__(self, out_dir: Path, fd: int):
        self.out_dir = out_dir
        self.fd = fd

    @classmethod
    def open(cls, out_dir: Path) -> _Folder:
        try:
            if out_dir.exists() and not out_dir.is_dir():
                raise OutputError(
                    f"output folder {out_dir}: exists and is not a folder; give -o a folder"
                )
            out_dir.mkdir(parents=True, exist_ok=True)
            fd = os.open(out_dir, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
        except OutputError:
            raise
        except OSError as exc:
            raise OutputError(
                f"output folder {out_dir}: cannot be made or opened ({exc.strerror}); "
                "give -o a folder you may write to"
            ) from None
        folder = cls(out_dir, fd)
        if not os.access(out_dir, os.W_OK):
            folder.close()
            raise OutputError(
                f"output folder {out_dir}: not writable; give -o a folder you may write to"
            )
        return folder

    def __enter__(self) -> _Folder:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def close(self) -> None:
        if self.fd >= 0:
            os.close(self.fd)
            self.fd = -1

    def _parent(self, name: str, create: bool) -> int | None:
        """A descriptor of the folder holding ``name`` (the caller closes it); None when a folder
        on the way is missing and ``create`` is false. Raises _Blocked when one is not a folder."""
        fd = os.dup(self.fd)
        parts = PurePosixPath(name).parts[:-1]
        for index, part in enumerate(parts):
            try:
                next_fd = os.open(part, _DIR_FLAGS, dir_fd=fd)
            except FileNotFoundError:
                if not create:
                    os.close(fd)
                    return None
                try:
                    os.mkdir(part, 0o777, dir_fd=fd)
                    next_fd = os.open(part, _DIR_FLAGS, dir_fd=fd)
                except OSError as exc:
                    os.close(fd)
                    raise OutputError(
                        f"output folder {self.out_dir}: cannot make "
                        f"{'/'.join(parts[: index + 1])} ({exc.strerror})"
                    ) from None
            except OSError as exc:
                os.close(fd)
                where = "/".join(parts[: index + 1])
                if exc.errno in (errno.ELOOP, errno.ENOTDIR, errno.EMLINK):
                    raise _Blocked(
                        f"{where} is a link or not a folder (crankdyn writes nothing through links)"
                    ) from None
                raise OutputError(
                    f"output folder {self.out_dir}: cannot open {where} ({exc.strerror})"
                ) from None
            os.close(fd)
            fd = next_fd
        return fd

    def inspect(self, name: str) -> _State:
        """What is at ``name`` now, read without following links."""
        try:
            parent = self._parent(name, create=False)
        except _Blocked as blocked:
            return _State("blocked", detail=str(blocked))
        if parent is None:
            return _State("missing")
        leaf = PurePosixPath(name).name
        try:
            info = os.stat(leaf, dir_fd=parent, follow_symlinks=False)
            if stat.S_ISLNK(info.st_mode):
                return _State("link")
            if not stat.S_ISREG(info.st_mode):
                return _State(
                    "blocked", detail="a folder or special file where crankdyn writes a file"
                )
            fd = os.open(leaf, _FILE_FLAGS, dir_fd=parent)
            with os.fdopen(fd, "rb") as handle:
                return _State("file", content=handle.read())
        except FileNotFoundError:
            return _State("missing")
        except OSError as exc:
            return _State("blocked", detail=f"cannot be read ({exc.strerror})")
        finally:
            os.close(parent)

    def write(self, name: str, payload: bytes) -> None:
        """Write ``name`` whole, through a temporary file renamed into place, with the mode the
        user's umask gives new files."""
        try:
            parent = self._parent(name, create=True)
        except _Blocked as blocked:
            raise OutputError(f"output folder {self.out_dir}: {blocked}") from None
        assert parent is not None
        leaf = PurePosixPath(name).name
        temporary = f".{leaf}.{secrets.token_hex(6)}.tmp"
        try:
            fd = os.open(
                temporary,
                os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0),
                0o666,
                dir_fd=parent,
            )
            try:
                with os.fdopen(fd, "wb") as handle:
                    handle.write(payload)
                os.replace(temporary, leaf, src_dir_fd=parent, dst_dir_fd=parent)
            except BaseException:
                try:
                    os.unlink(temporary, dir_fd=parent)
                except OSError:
                    pass
                raise
        except OSError as exc:
            raise OutputError(
                f"output folder {self.out_dir}: cannot write {name} ({exc.strerror})"
            ) from None
        finally:
            os.close(parent)

    def remove(self, name: str) -> None:
        """Remove the file ``name``, then the folders it leaves empty (never the output folder)."""
        parts = PurePosixPath(name).parts
        for depth in range(len(parts), 0, -1):
            try:
                parent = self._parent("/".join(parts[:depth]), create=False)
            except (_Blocked, OutputError):
                return
            if parent is None:
                return
            try:
                if depth == len(parts):
                    os.unlink(parts[-1], dir_fd=parent)
                else:
                    os.rmdir(parts[depth - 1], dir_fd=parent)  # only succeeds when empty
            except OSError:
                return
            finally:
                os.close(parent)


class _Blocked(Exception):
    """A folder on the way to a name is a link or not a folder."""


def file_mode() -> int:
    """The mode a new file gets under the user's umask (0644 with the usual 022)."""
    return 0o666 & ~_umask()


def _umask() -> int:
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)  # no way to read it without setting it elsewhere
    os.umask(mask)
    return mask
