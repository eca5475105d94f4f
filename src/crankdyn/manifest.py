"""The output folder's manifest: what crankdyn wrote there, so the next run can tidy up.

Each run writes ``.crankdyn-manifest.json`` listing the files it wrote. A later run
into the same folder removes the files of the previous manifest that it does not
write again (old figures, tables of stages no longer run) and nothing else: a file
put there by hand, or by another program, is never touched. A manifest entry that is
absolute, climbs out of the folder, or is not a regular file is ignored.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from . import outputs
from .version import __version__

MANIFEST = ".crankdyn-manifest.json"


def write_outputs(out_dir: Path, files: dict[str, bytes]) -> list[Path]:
    """Write ``files`` (relative name -> bytes) below ``out_dir`` atomically, remove the stale files
    of the previous run's manifest and record the new manifest; return the paths written."""
    out_dir = Path(out_dir)
    previous = previous_files(out_dir)
    # First a manifest of everything that may be there once writing starts, so a run killed
    # half-way (a batch time limit, Ctrl-C) still leaves every file it wrote listed for the next.
    outputs.write_atomically(out_dir, {MANIFEST: _manifest(previous | set(files), __version__)})
    written = outputs.write_atomically(out_dir, files)
    remove_stale(out_dir, previous - set(files))
    outputs.write_atomically(out_dir, {MANIFEST: _manifest(set(files), __version__)})
    return written


def _manifest(names: set[str], version: str) -> bytes:
    return outputs.json_bytes({"crankdyn_version": version, "files": sorted(names)})


def previous_files(out_dir: Path) -> set[str]:
    """The relative names the previous run's manifest lists (empty if there is none or it is unreadable)."""
    try:
        document = json.loads((out_dir / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return set()
    names = document.get("files") if isinstance(document, dict) else None
    if not isinstance(names, list):
        return set()
    return {n for n in names if isinstance(n, str)}


def remove_stale(out_dir: Path, names: set[str]) -> list[Path]:
    """Remove the regular files ``names`` below ``out_dir`` (links and anything outside are left alone),
    then the folders they leave empty; return the files removed."""
    root = out_dir.resolve()
    removed = []
    for name in sorted(names):
        if not name or name == MANIFEST or Path(name).is_absolute() or ".." in Path(name).parts:
            continue
        path = out_dir / name
        try:
            if path.is_symlink() or not path.is_file() or root not in path.resolve().parents:
                continue
            path.unlink()
        except OSError:
            continue
        removed.append(path)
        parent = path.parent
        while parent.resolve() != root and root in parent.resolve().parents:
            try:
                parent.rmdir()  # only succeeds when empty
            except OSError:
                break
            parent = parent.parent
    return removed


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
