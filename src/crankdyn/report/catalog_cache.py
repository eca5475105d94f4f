"""Parsed catalog files kept between runs.

A report reads some thirty catalog files (the core's and each plugin's, in English and in the
report's language): 0.3 to 0.7 MB of TOML, which Python's own parser, written in Python, takes
20 to 40 ms to read, on the path of every report. The same texts stored as JSON load in a tenth
of that.

One JSON file per catalog file, in crankdyn's cache folder (``$XDG_CACHE_HOME/crankdyn``, else
``~/.cache/crankdyn``; :data:`CACHE_ENV` names another folder, or ``off`` for none), named by a
digest of the catalog's path. It holds that path with the catalog's modification time and size:
a catalog changed since (a plugin upgraded, a translation edited) is parsed again and its file
replaced. A file is written whole or not at all (a temporary file renamed); one that is damaged,
foreign or unreadable is ignored, and a folder that cannot be written keeps nothing: the
catalog is then parsed each time, as without the cache.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path

#: Environment variable: crankdyn's cache folder, or "off" for none.
CACHE_ENV = "CRANKDYN_CACHE_DIR"
_FORMAT = 1


def cache_dir() -> Path | None:
    """The folder the parsed catalogs are kept in, or None (:data:`CACHE_ENV` is ``off``, or no
    absolute folder is known: a relative one would be made in the working folder)."""
    named = os.environ.get(CACHE_ENV)
    if named == "off":
        return None
    if named:
        return Path(named)
    base = os.environ.get("XDG_CACHE_HOME", "")
    if os.path.isabs(base):  # the XDG rule: a relative value is ignored
        return Path(base) / "crankdyn"
    home = Path(os.path.expanduser("~"))
    return home / ".cache" / "crankdyn" if home.is_absolute() else None


def _file(source: str) -> Path | None:
    folder = cache_dir()
    if folder is None:
        return None
    return folder / f"catalog-{hashlib.sha256(source.encode('utf-8')).hexdigest()[:24]}.json"


def load(source: str, mtime_ns: int, size: int) -> dict | None:
    """The texts kept for catalog file ``source`` as it is now (its modification time and size),
    or None."""
    file = _file(source)
    if file is None:
        return None
    try:
        with open(file, encoding="utf-8") as handle:
            kept = json.load(handle)
    except (OSError, ValueError):  # none yet, unreadable or damaged: parsed again
        return None
    if (
        not isinstance(kept, dict)
        or kept.get("format") != _FORMAT
        or kept.get("source") != [source, mtime_ns, size]
        or not isinstance(kept.get("texts"), dict)
    ):
        return None
    return kept["texts"]


def keep(source: str, mtime_ns: int, size: int, texts: dict) -> None:
    """Keep the parsed ``texts`` of catalog file ``source`` for the next run (nothing where they
    are not JSON's own values, or the folder cannot be written)."""
    file = _file(source)
    if file is None:
        return
    try:
        text = json.dumps(
            {"format": _FORMAT, "source": [source, mtime_ns, size], "texts": texts},
            ensure_ascii=False,
        )
    except (TypeError, ValueError):  # a TOML date: not a JSON value
        return
    if json.loads(text)["texts"] != texts:  # not read back the same (a tuple, a float key)
        return
    temporary = None
    try:
        file.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=file.parent, prefix=file.name, suffix=".tmp")
        with os.fdopen(handle, "w", encoding="utf-8") as out:
            out.write(text)
        os.replace(temporary, file)
    except OSError:  # a read-only or full cache folder: parsed again next time
        if temporary is not None and os.path.exists(temporary):
            os.unlink(temporary)
