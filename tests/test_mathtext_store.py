"""Typeset mathtext labels kept between runs (crankdyn.report.mathtext_store): a label read back
draws exactly the SVG a freshly typeset one draws, and a damaged, foreign or switched-off store
only costs the typesetting again."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from crankdyn.report import mathtext_store

LABELS = [r"$p_{\rm g}$, MPa", r"$\alpha$, °", r"$M_{\rm к}$, Н·м", r"$\frac{1}{2}\sqrt{x^2}$"]


def _typeset(label: str, size: float = 9.0):
    """matplotlib's own typesetting of ``label`` (no cache of any kind)."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.mathtext import MathTextParser

    parser = MathTextParser("path")
    typeset = getattr(MathTextParser._parse_cached, "__wrapped__", None)
    if typeset is None:  # crankdyn replaced matplotlib's cache: its own function keeps the original
        return parser.parse(label, 72, FontProperties(size=size))
    return typeset(parser, label, 72, FontProperties(size=size), True, _flags())


def _flags():
    from matplotlib.ft2font import LoadFlags

    return LoadFlags.NO_HINTING


def _key(store, label: str, size: float = 9.0):
    from matplotlib.font_manager import FontProperties

    return store.key(label, 72, FontProperties(size=size), _flags())


def _saved(path, labels):
    """A store at ``path`` that typeset ``labels`` and saved them."""
    store = mathtext_store.MathtextStore(path)
    for label in labels:
        store.put(_key(store, label), _typeset(label))
    store.save()
    return store


def _stored(tmp_path, label: str):
    """(path, key, the file's data) after one store typeset and saved ``label``."""
    path = tmp_path / "store.json"
    store = mathtext_store.MathtextStore(path)
    key = _key(store, label)
    store.put(key, _typeset(label))
    store.save()
    return path, key, {"records": _records(path)}


def _records(path) -> dict:
    """The records of the store's file, as the store reads them (key -> the record's JSON text)."""
    return mathtext_store._load(path)


def _write(path, records: dict) -> None:
    """A store's file holding ``records`` (JSON texts, as text or UTF-8), as the store writes them."""
    encoded = {k: v if isinstance(v, bytes) else v.encode() for k, v in records.items()}
    with open(path, "wb") as out:
        mathtext_store._write(out, encoded)


def test_a_label_read_back_is_the_label_typeset(tmp_path):
    path = tmp_path / "store.json"
    writer = mathtext_store.MathtextStore(path)
    for label in LABELS:
        writer.put(_key(writer, label), _typeset(label))
    writer.save()
    reader = mathtext_store.MathtextStore(path)
    for label in LABELS:
        fresh, stored = _typeset(label), reader.get(_key(reader, label))
        assert stored is not None, label
        assert (stored.width, stored.height, stored.depth, stored.rects) == (
            fresh.width,
            fresh.height,
            fresh.depth,
            fresh.rects,
        )
        assert [(g[0].fname, *g[1:]) for g in stored.glyphs] == [
            (g[0].fname, *g[1:]) for g in fresh.glyphs
        ]
        assert [type(v) for v in stored[:3]] == [type(v) for v in fresh[:3]]
    # another size, another string: not in the store
    assert reader.get(_key(reader, LABELS[0], size=10.0)) is None
    assert reader.get(_key(reader, r"$\beta$")) is None


def test_a_damaged_store_is_ignored_and_replaced(tmp_path):
    path = tmp_path / "store.json"
    path.write_text('{"format": 1, "records": {"broken', encoding="utf-8")
    store = mathtext_store.MathtextStore(path)
    assert store.get(_key(store, LABELS[0])) is None
    store.put(_key(store, LABELS[0]), _typeset(LABELS[0]))
    store.save()
    assert len(_records(path)) == 1


def test_a_record_naming_a_file_that_is_not_a_known_font_is_not_used(tmp_path):
    path, key, data = _stored(tmp_path, LABELS[0])
    record = json.loads(data["records"][key])
    record[3][0][0] = str(path)  # any file that is not one of matplotlib's fonts, stamped as it is
    record[5][str(path)] = mathtext_store._stamp(str(path))
    data["records"][key] = json.dumps(record)
    _write(path, data["records"])
    assert mathtext_store._valid(record)  # well formed: refused for its font only
    reader = mathtext_store.MathtextStore(path)
    assert reader.get(key) is None


@pytest.mark.parametrize(
    "damage",
    [
        "[1, 2",
        "[1.0, 2.0, 3.0, [], [], {}, 7]",
        '{"a": 1}',
        '[1.0, 1.0, 1.0, [["/no/font", 9.0, 65, 1, 0.0, 0.0]], [], {}]',
    ],
)
def test_a_damaged_record_is_dropped_and_the_others_read(tmp_path, damage):
    """Records are checked when a label asks for one, not when the file is read: a damaged
    record costs its own label's typesetting, the rest of the store still serves."""
    path = tmp_path / "store.json"
    store = _saved(path, LABELS[:2])
    data = {"records": _records(path)}
    data["records"][_key(store, LABELS[0])] = damage
    _write(path, data["records"])
    reader = mathtext_store.MathtextStore(path)
    assert reader.get(_key(reader, LABELS[0])) is None
    assert reader.get(_key(reader, LABELS[1])) is not None


def test_a_label_typeset_under_other_font_or_mathtext_settings_has_another_key(tmp_path):
    """The key holds the settings typesetting reads (mathtext.*, font.*), read as they stand when
    the label is asked for (inside a figure's rc_context), and no others."""
    import matplotlib

    store = mathtext_store.MathtextStore(tmp_path / "store.json")
    plain = _key(store, LABELS[0])
    with matplotlib.rc_context({"mathtext.fontset": "stix"}):
        assert _key(store, LABELS[0]) != plain
    with matplotlib.rc_context({"font.family": ["serif"]}):
        assert _key(store, LABELS[0]) != plain
    with matplotlib.rc_context({"lines.linewidth": 7.0}):
        assert _key(store, LABELS[0]) == plain
    assert _key(store, LABELS[0]) == plain


def test_the_store_keeps_the_newest_records_only(tmp_path, monkeypatch):
    monkeypatch.setattr(mathtext_store, "MAX_RECORDS", 2)
    path = tmp_path / "store.json"
    store = _saved(path, LABELS[:3])
    kept = _records(path)
    assert list(kept) == [_key(store, label) for label in LABELS[1:3]]


def test_the_store_can_be_switched_off_or_moved(monkeypatch, tmp_path):
    monkeypatch.setenv(mathtext_store.STORE_ENV, "off")
    assert mathtext_store.store_path() is None
    store = mathtext_store.MathtextStore(None)
    store.put(_key(store, LABELS[0]), _typeset(LABELS[0]))
    store.save()  # nowhere to write: nothing happens
    monkeypatch.setenv(mathtext_store.STORE_ENV, str(tmp_path / "elsewhere.json"))
    assert mathtext_store.store_path() == tmp_path / "elsewhere.json"


FIGURE = r"""
import hashlib, sys
import matplotlib._mathtext as M
typeset = []
parse = M.Parser.parse
M.Parser.parse = lambda self, s, *a, **k: typeset.append(s) or parse(self, s, *a, **k)
from crankdyn.report import figures, mathtext_store
fig, ax = figures.new_figure(8, 5)
ax.plot([0, 1], [0, 2])
ax.set_xlabel(r"$\alpha$, °")
ax.set_ylabel(r"$p_{\rm g}$, MPa")
ax.set_title(r"$\frac{\pi D^2}{4}$")
svg = figures.to_svg(fig)
mathtext_store.save()
print(hashlib.sha256(svg).hexdigest(), len(typeset))
"""


def test_a_figure_drawn_from_the_store_is_byte_for_byte_the_typeset_one(tmp_path):
    """Two processes: the first typesets and stores the labels, the second reads them back."""
    env = {**__import__("os").environ, mathtext_store.STORE_ENV: str(tmp_path / "store.json")}

    def draw():
        done = subprocess.run(
            [sys.executable, "-c", FIGURE], env=env, capture_output=True, text=True, timeout=120
        )
        assert done.returncode == 0, done.stderr
        digest, typeset = done.stdout.split()
        return digest, int(typeset)

    cold, warm = draw(), draw()
    assert cold[1] > 0 and warm[1] == 0  # the second process typeset nothing
    assert cold[0] == warm[0]


@pytest.mark.parametrize("label", LABELS)
def test_the_store_keys_on_the_matplotlib_settings(tmp_path, label):
    import matplotlib

    store = mathtext_store.MathtextStore(tmp_path / "store.json")
    key = _key(store, label)
    with matplotlib.rc_context({"mathtext.fontset": "stix"}):
        assert _key(store, label) != key
    assert _key(store, label) == key


@pytest.mark.parametrize(
    "damage", ["rect of three", "huge code", "float code", "no stamps", "nan width"]
)
def test_a_damaged_record_is_never_drawn_and_is_dropped_from_the_file(tmp_path, damage):
    """A record with a rect of three numbers or a glyph code of 10**12 would pass the font check
    and fail while drawing, in every later report (save() would merge it back)."""
    path, key, data = _stored(tmp_path, LABELS[3])  # a fraction and a root: it has rects
    record = json.loads(data["records"][key])
    assert record[4], "the label has rectangles (the fraction's bar)"
    if damage == "rect of three":
        record[4][0] = record[4][0][:3]
    elif damage == "huge code":
        record[3][0][2] = 10**12
    elif damage == "float code":
        record[3][0][2] = 65.5
    elif damage == "no stamps":
        record[5] = {}
    else:
        record[0] = float("nan")
    data["records"][key] = json.dumps(record)
    _write(path, data["records"])
    reader = mathtext_store.MathtextStore(path)
    assert reader.get(key) is None
    # typeset afresh, the label's good record replaces the damaged one
    reader.put(key, _typeset(LABELS[3]))
    reader.save()
    assert _records(path)[key].decode() != data["records"][key]
    assert mathtext_store.MathtextStore(path).get(key) is not None


def test_a_font_file_changed_in_place_is_a_miss(tmp_path):
    path, key, data = _stored(tmp_path, LABELS[0])
    record = json.loads(data["records"][key])
    font = next(iter(record[5]))
    record[5][font] = [record[5][font][0], 1]  # another modification time
    data["records"][key] = json.dumps(record)
    _write(path, data["records"])
    assert mathtext_store.MathtextStore(path).get(key) is None


def test_a_glyph_of_another_matplotlib_is_not_stored_and_a_failing_store_does_not_stop_a_figure(
    tmp_path, monkeypatch
):
    """matplotlib before 3.11 gives five fields a glyph (no glyph index): such a parse is not
    stored; and whatever the store raises, the label is typeset and the figure drawn."""
    from types import SimpleNamespace

    fresh = _typeset(LABELS[0])
    older = SimpleNamespace(
        width=fresh.width,
        height=fresh.height,
        depth=fresh.depth,
        rects=fresh.rects,
        glyphs=[g[:3] + g[4:] for g in fresh.glyphs],
    )
    assert mathtext_store._record_of(older) is None

    from crankdyn.report import figures

    class Broken:
        def key(self, *args):
            raise RuntimeError("a store that fails")

    monkeypatch.setattr(mathtext_store, "store", lambda: Broken())
    fig, ax = figures.new_figure(6, 4)
    ax.set_xlabel(r"$\omega_{\rm broken}$, 1/s")
    assert b"broken" in figures.to_svg(fig)


def test_labels_read_back_are_kept_as_the_newest(tmp_path, monkeypatch):
    """The cap drops the least recently used records, not the labels every report reads back."""
    monkeypatch.setattr(mathtext_store, "MAX_RECORDS", 2)
    path = tmp_path / "store.json"
    _saved(path, LABELS[:2])
    second = mathtext_store.MathtextStore(path)
    assert second.get(_key(second, LABELS[0])) is not None  # read back in this run
    second.put(_key(second, LABELS[2]), _typeset(LABELS[2]))
    second.save()
    kept = _records(path)
    assert set(kept) == {_key(second, LABELS[0]), _key(second, LABELS[2])}


def test_the_file_is_a_line_per_record_and_an_older_file_is_replaced(tmp_path):
    """A header line, then "key<TAB>record" per line; a line cut short is skipped, the others
    read; a store in the earlier layout (one JSON document) is read and written anew."""
    path = tmp_path / "store.json"
    store = _saved(path, LABELS[:2])
    lines = path.read_text(encoding="utf-8").split("\n")
    assert json.loads(lines[0]) == {"format": mathtext_store._FORMAT}
    assert len(lines) == 4 and lines[-1] == "" and all(line.count("\t") == 1 for line in lines[1:3])
    path.write_text("\n".join([lines[0], lines[1][:20], lines[2]]) + "\n", encoding="utf-8")
    reader = mathtext_store.MathtextStore(path)
    assert reader.get(_key(store, LABELS[0])) is None
    assert reader.get(_key(store, LABELS[1])) is not None
    older = {"format": 3, "records": dict(line.split("\t") for line in lines[1:3])}
    earlier = {key: record.encode() for key, record in older["records"].items()}
    path.write_text(json.dumps(older), encoding="utf-8")
    assert _records(path) == earlier
    _saved(path, LABELS[2:3])
    assert list(_records(path)) == [*older["records"], _key(store, LABELS[2])]
    assert path.read_text(encoding="utf-8").startswith(lines[0] + "\n")
    path.write_text(json.dumps({"format": 2, "records": older["records"]}), encoding="utf-8")
    assert _records(path) == {}  # older still: typeset again
