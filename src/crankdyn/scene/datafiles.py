"""Where a scene's data files (``cycle.trace_file`` ...) may come from.

Only from the scene's own folder and below, or from a folder the user named with
``--data-dir`` on the command line; never from a path the scene alone chooses
(``/etc/passwd``, ``../../secret.csv``). Links are resolved before the check.
"""

from __future__ import annotations

from pathlib import Path


def data_file_problem(
    name: str, base_dir: str, data_dirs: tuple[str, ...] = (), must_exist: bool = True
) -> str | None:
    """Why the data file ``name`` of a scene in ``base_dir`` may not be read, or None if it may."""
    if not isinstance(name, str) or not name.strip() or "\x00" in name:
        return "must be a file name relative to the scene's folder"
    try:
        path = (Path(base_dir) / name).resolve()
        roots = [Path(base_dir).resolve(), *(Path(d).resolve() for d in data_dirs)]
    except (OSError, RuntimeError) as exc:  # a loop of links
        return f"cannot be looked up ({getattr(exc, 'strerror', None) or exc})"
    if not any(path == root or root in path.parents for root in roots):
        return (
            "data files are read only from the scene's folder and below; for a file elsewhere "
            "give its folder with --data-dir DIR on the command line"
        )
    try:
        found = path.is_file()
    except OSError as exc:  # a name too long for the file system, a folder that may not be read
        return f"cannot be looked up ({exc.strerror or exc.__class__.__name__})"
    if must_exist and not found:
        return "file not found (a data file is looked for relative to the scene's folder)"
    return None
