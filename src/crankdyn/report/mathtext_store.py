"""Typeset mathtext labels kept on disk between runs, so that a report does not typeset again
the labels every report has (``$\\alpha$, °``, ``$p_{\\rm g}$, MPa`` ...).

matplotlib typesets a label with pyparsing, about 5 ms each; a report's figures have about 70
distinct labels, and each figure-drawing process typesets its own: a third of the figures'
drawing time. A typeset label (matplotlib's ``VectorParse``: its box and each glyph's font file,
size, code and position) is a small record; this module keeps those records in one JSON file
in matplotlib's cache folder (``matplotlib.get_cachedir()``, where it keeps its font list).

Safe to share and to lose:
- JSON, never pickle: a record names a font only by a path, and a path that is not one of
  matplotlib's known fonts discards the record;
- every record is keyed by what matplotlib's own result depends on: the string, dpi, font
  properties, glyph loading flags, matplotlib's version, every ``mathtext.*`` and ``font.*``
  setting and the list of fonts matplotlib knows, so a changed setting or font is a miss;
- a damaged or foreign file is ignored (and later replaced); written atomically, so a reader
  never sees half a file; two writers at once lose at most each other's new records;
- each record is kept in the file as a JSON text of its own, on a line of its own after its key
  and a tab, and parsed (and checked) only when a label asks for it: a full store (4096 records,
  10 MB: reports in three languages, a teacher's variants) is read in 10 ms, where parsing it as
  one JSON document took 40 ms of every report's start.

``CRANKDYN_MATHTEXT_CACHE`` names another file, or ``off`` for none (the cold benchmark).
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import os
import tempfile
from pathlib import Path

#: Environment variable: the store's file, or "off" for no store.
STORE_ENV = "CRANKDYN_MATHTEXT_CACHE"
#: Records kept in the file (the newest); a report has ~70, a variant's labels are the same.
MAX_RECORDS = 4096
_FORMAT = 4  # 4: a line per record, "key<TAB>record" (3: one JSON document; 2: nested lists)
#: The file's first line; a file that does not start with it is not read.
_HEADER = json.dumps({"format": _FORMAT})


class MathtextStore:
    """Records read from the file once, and those typeset since, written back by :meth:`save`."""

    def __init__(self, path: Path | None):
        self.path = path
        # key: the record's JSON text (UTF-8), parsed by get()
        self._records: dict[str, bytes] | None = None
        self._new: dict[str, bytes] = {}
        self._used: set[str] = set()  # keys read back in this process: kept as the newest by save()
        self._context: tuple | None = None  # (rc and fonts state, its digest)
        self._rc_keys: tuple[str, ...] | None = None  # the rc settings typesetting depends on
        self._known_fonts: frozenset[str] | None = None

    # -------------------------------------------------------------- lookup
    def key(self, s: str, dpi: float, prop, load_glyph_flags) -> str:
        return json.dumps(
            [self._context_digest(), s, float(dpi), _font_key(prop), str(load_glyph_flags)],
            ensure_ascii=False,
        )

    def get(self, key: str):
        """The stored ``VectorParse`` for ``key``, or None."""
        text = self._read().get(key)
        if text is None:
            return None
        try:
            record = json.loads(text)
            if not _valid(record):  # a damaged or foreign record is dropped, never drawn
                return None
            parse = _parse_from_record(record, self._fonts())
        except Exception:  # noqa: BLE001 - a record that cannot be used is typeset afresh
            return None
        self._used.add(key)
        return parse

    def put(self, key: str, parse) -> None:
        record = _record_of(parse)
        if record is not None:
            text = json.dumps(record, separators=(",", ":")).encode("utf-8")
            self._read()[key] = text
            self._new[key] = text

    # -------------------------------------------------------------- the file
    def preload(self) -> None:
        """Read the file and list matplotlib's fonts now (before forking drawers, which inherit both)."""
        self._read()
        if self._records:
            self._fonts()
            self._context_digest()

    def _read(self) -> dict:
        if self._records is None:
            self._records = _load(self.path) if self.path is not None else {}
        return self._records

    def save(self) -> None:
        """Merge this process's new records into the file (newest kept), atomically."""
        if not self._new or self.path is None:
            return
        new, self._new = self._new, {}
        records = _load(self.path)
        # this run's labels, new or read back, move to the end: the cap drops the least recently used
        recent = {key: records[key] for key in self._used if key in records}
        recent.update(new)
        for key in recent:
            records.pop(key, None)
        records.update(recent)
        kept = dict(list(records.items())[-MAX_RECORDS:])
        temporary = None
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            handle, temporary = tempfile.mkstemp(
                dir=self.path.parent, prefix=self.path.name, suffix=".tmp"
            )
            with os.fdopen(handle, "wb") as out:
                _write(out, kept)
            os.replace(temporary, self.path)
        except OSError:  # a read-only or full cache folder: the next run typesets again
            if temporary is not None and os.path.exists(temporary):
                os.unlink(temporary)

    # -------------------------------------------------------------- context
    def _context_digest(self) -> str:
        import matplotlib  # lazy: heavy optional import

        rc = matplotlib.rcParams
        if self._rc_keys is None:
            self._rc_keys = tuple(
                k for k in rc if k.startswith(("mathtext.", "font.", "text.kerning_factor"))
            )
        # read as stored: RcParams.items() checks every one of its ~320 keys for deprecation, 1.7 ms
        # a label
        state = (
            matplotlib.__version__,
            tuple((k, repr(dict.__getitem__(rc, k))) for k in self._rc_keys),
        )
        if self._context is None or self._context[0] != state:
            fonts = sorted(self._fonts())
            digest = hashlib.sha256(repr((state, fonts)).encode("utf-8")).hexdigest()[:16]
            self._context = (state, digest)
        return self._context[1]

    def _fonts(self) -> frozenset[str]:
        """The font files matplotlib knows: the only paths a record may name."""
        if self._known_fonts is None:
            from matplotlib.font_manager import fontManager  # lazy: heavy optional import

            self._known_fonts = frozenset(str(f.fname) for f in fontManager.ttflist)
        return self._known_fonts


def _font_key(prop) -> list:
    return [
        list(prop.get_family()),
        prop.get_style(),
        prop.get_variant(),
        str(prop.get_weight()),
        str(prop.get_stretch()),
        float(prop.get_size_in_points()),
        str(prop.get_file()),
        prop.get_math_fontfamily(),
    ]


def _record_of(parse) -> list | None:
    """A ``VectorParse`` as JSON values, with the size and time of each font file it names; None
    where it is not one this module can give back the same: a glyph not as matplotlib 3.11 gives
    it (font, size, code, glyph index, x, y), a font without a single file or not its first face."""
    glyphs, stamps = [], {}
    for glyph in parse.glyphs:
        if len(glyph) != 6:  # matplotlib before 3.11 had no glyph index: not stored
            return None
        font, size, code, index, x, y = glyph
        path = getattr(font, "fname", None)
        if not isinstance(path, str) or getattr(font, "face_index", 0) != 0:
            return None
        if path not in stamps:
            stamps[path] = _stamp(path)
            if stamps[path] is None:
                return None
        glyphs.append([path, float(size), int(code), int(index), float(x), float(y)])
    return [
        float(parse.width),
        float(parse.height),
        float(parse.depth),
        glyphs,
        [[float(v) for v in rect] for rect in parse.rects],
        stamps,
    ]


@functools.cache
def _stamp(path: str) -> list | None:
    """A font file's size and modification time (ns): a font replaced in place is a miss (read
    once per process and font: every label read back checks the fonts it names)."""
    try:
        info = os.stat(path)
    except OSError:
        return None
    return [info.st_size, info.st_mtime_ns]


def _finite(*values) -> bool:
    return all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in values
    )


def _valid(record) -> bool:
    """Whether ``record`` has exactly the shape :func:`_record_of` writes (a damaged or foreign
    file's record is dropped, never drawn)."""
    if not (isinstance(record, list) and len(record) == 6 and _finite(*record[:3])):
        return False
    glyphs, rects, stamps = record[3], record[4], record[5]
    if not (isinstance(glyphs, list) and isinstance(rects, list) and isinstance(stamps, dict)):
        return False
    for glyph in glyphs:
        if not (
            isinstance(glyph, list)
            and len(glyph) == 6
            and isinstance(glyph[0], str)
            and glyph[0] in stamps
            and _finite(*glyph[1:])
            and isinstance(glyph[2], int)
            and isinstance(glyph[3], int)
            and 0 <= glyph[2] <= 0x10FFFF
            and 0 <= glyph[3] < 1 << 32
        ):
            return False
    return all(isinstance(r, list) and len(r) == 4 and _finite(*r) for r in rects) and all(
        isinstance(v, list) and len(v) == 2 and all(isinstance(n, int) for n in v)
        for v in stamps.values()
    )


def _parse_from_record(record: list, known_fonts: frozenset[str]):
    import numpy as np  # lazy: heavy optional import (with matplotlib)
    from matplotlib.font_manager import get_font  # lazy: heavy optional import
    from matplotlib.mathtext import VectorParse  # lazy: heavy optional import

    # the record has the shape _record_of writes: made by it, or read back by MathtextStore.get, which checks that
    width, height, depth, glyphs, rects, stamps = record
    for path, stamp in stamps.items():
        if path not in known_fonts or _stamp(path) != stamp:
            raise ValueError("a font matplotlib does not know, or one changed since")
    # matplotlib gives the box and each glyph's height as numpy floats: the same values back
    return VectorParse(
        np.float64(width),
        np.float64(height),
        np.float64(depth),
        [
            (get_font(path), float(size), int(code), int(index), float(x), np.float64(y))
            for path, size, code, index, x, y in glyphs
        ],
        [tuple(float(v) for v in rect) for rect in rects],
    )


def _load(path: Path | None) -> dict[str, bytes]:
    """The records of the store's file (key -> the record's JSON text, UTF-8); {} for none, or a
    file that is damaged, foreign or of another format."""
    if path is None:
        return {}
    try:
        with open(path, "rb") as handle:
            start = handle.readline(len(_HEADER) + 2)
            data = handle.read()
    except OSError:
        return {}
    if start.rstrip(b"\n") != _HEADER.encode("ascii"):
        return _earlier(start + data) if start.startswith(b"{") else {}
    records = {}
    # each record is checked when it is read back (get): most of a large store is never asked for
    for line in data.split(b"\n"):
        key, tab, record = line.partition(b"\t")
        if tab:
            try:
                records[key.decode("utf-8")] = record
            except UnicodeDecodeError:  # a damaged line: its label is typeset again
                continue
    return records


def _earlier(data: bytes) -> dict[str, bytes]:
    """The records of a store in the earlier layout, one JSON document (format 3): read once, then
    written anew in this one; {} for anything else."""
    try:
        document = json.loads(data)
    except ValueError:
        return {}
    if not isinstance(document, dict) or document.get("format") != 3:
        return {}
    records = document.get("records")
    if not isinstance(records, dict):
        return {}
    return {
        k: v.encode("utf-8")
        for k, v in records.items()
        if isinstance(k, str) and isinstance(v, str) and not {"\t", "\n"} & set(k + v)
    }


def _write(out, records: dict[str, bytes]) -> None:
    """``records`` as the store's file, to binary ``out``: the header, then a line per record. A
    key and a record are JSON texts, which hold no tab and no line break of their own."""
    out.write(_HEADER.encode("ascii") + b"\n")
    out.writelines(b"%s\t%s\n" % (key.encode("utf-8"), record) for key, record in records.items())


def store_path() -> Path | None:
    """The store's file: ``CRANKDYN_MATHTEXT_CACHE``, or crankdyn-mathtext.json in matplotlib's
    cache folder; None when switched off."""
    value = os.environ.get(STORE_ENV, "").strip()
    if value.lower() in {"off", "0", "no", "none"}:
        return None
    if value:
        return Path(value)
    import matplotlib  # lazy: heavy optional import

    return Path(matplotlib.get_cachedir()) / "crankdyn-mathtext.json"


_store: MathtextStore | None = None


def store() -> MathtextStore:
    """This process's store (made on first use; a forked child shares what was read before)."""
    global _store
    if _store is None:
        _store = MathtextStore(store_path())
    return _store


def save() -> None:
    """Write this process's new records, if any (after drawing; a forked drawer before it exits)."""
    if _store is not None:
        _store.save()
