"""The kinematic scheme's texts (Fig. 3.1) cross no line of the drawing: the bank labels of a V
engine, R among the rods of a V, radial or in-line six, and the crank star's labels, where
cranks in one direction (1 and 4 of an in-line four) share one label instead of overprinting."""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
from conftest import drawing_positions

from crankdyn.cli import examples_dir
from crankdyn.report import mechanism_drawing as md
from crankdyn.scene.model import load_scene


@cache
def _positions(example: str):
    return drawing_positions(load_scene(examples_dir() / f"{example}.toml"))


@cache  # read only: each example's scheme drawn once per test process
def _scheme(example: str):
    positions = _positions(example)
    labels = {k: f"{k} = {value * 1e3:g} mm" for k, value in positions.dimensions.items()}
    fig, _ = md.scheme_figure(positions, 0, labels, "Crank star", "Firing order: 1")
    fig.canvas.draw()
    return fig


def _segments(ax):
    """(line, display-coordinate polyline) of every member drawn: liners and their hatching
    (lines of 1 pt and more) and the links (a LineCollection); not the thin or dash-dotted lines
    of the axes and the dimensions, which a text may meet at its end."""
    from matplotlib.collections import LineCollection

    for line in ax.lines:
        if line.get_linestyle() not in ("-.", "None") and line.get_linewidth() >= 0.8:
            yield line, line.get_transform().transform(np.column_stack(line.get_data()))
    for collection in ax.collections:
        if isinstance(collection, LineCollection):
            widths = np.broadcast_to(collection.get_linewidths(), (len(collection.get_segments()),))
            for segment, width in zip(collection.get_segments(), widths, strict=True):
                if width >= 0.8:
                    yield collection, collection.get_transform().transform(segment)


def _crossed_lines(ax, text, renderer) -> list:
    """The members of the drawing that pass through the box of ``text`` (display coordinates)."""
    box = text.get_window_extent(renderer).padded(-1.0)
    crossed = []
    for member, xy in _segments(ax):
        for a, b in zip(xy[:-1], xy[1:], strict=True):
            points = a + (b - a) * np.linspace(0.0, 1.0, 50)[:, None]
            if any(box.contains(*p) for p in points):
                crossed.append(member)
                break
    return crossed


@pytest.mark.parametrize(
    "example",
    ["v8-petrol", "radial9-aircraft", "inline6-diesel-trace", "inline4-petrol", "petrol-1cyl"],
)
def test_the_scheme_texts_cross_no_member_of_the_mechanism(example):
    fig = _scheme(example)
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    cylinders = {g.label for g in _positions(example).guides if g.label}
    wanted = [t for t in ax.texts if t.get_text().startswith("R =") or t.get_text() in cylinders]
    assert any(t.get_text().startswith("R =") for t in wanted)
    for text in wanted:
        assert not _crossed_lines(ax, text, renderer), (
            f"{example}: {text.get_text()!r} crosses the drawing"
        )


def test_a_v_engines_bank_labels_grow_away_from_their_liners():
    fig = _scheme("v8-petrol")
    banks = {t.get_text(): t for t in fig.axes[0].texts if t.get_text() in ("1L", "1R")}
    assert set(banks) == {"1L", "1R"}  # the front view: each bank's first cylinder
    assert banks["1L"].get_ha() == "right" and banks["1R"].get_ha() == "left"


def test_cranks_in_one_direction_share_one_label_in_the_star():
    star = _scheme("inline4-petrol").axes[1]
    labels = sorted(t.get_text() for t in star.texts if "," in t.get_text())
    assert labels == [
        "1, 4",
        "2, 3",
    ]  # an in-line engine's cylinders are its cranks' numbers: no brackets
    star8 = _scheme("v8-petrol").axes[1]
    assert sorted(t.get_text() for t in star8.texts if "(" in t.get_text()) == [
        "1\n(1L, 1R)",
        "2\n(2L, 2R)",
        "3\n(3L, 3R)",
        "4\n(4L, 4R)",
    ]


def test_outward_alignment_follows_the_direction():
    assert md.outward_alignment((0.0, 1.0)) == {"ha": "center", "va": "bottom"}
    assert md.outward_alignment((-0.7, 0.7)) == {"ha": "right", "va": "bottom"}
    assert md.outward_alignment((0.7, -0.7)) == {"ha": "left", "va": "top"}


@pytest.mark.parametrize(
    "label, lines",
    [
        ("Порядок роботи: 1 – 3 – 4 – 2", ["Порядок роботи: 1 – 3 – 4 – 2"]),
        # an in-line five's order would leave its last cylinder alone on a second line
        ("Порядок роботи: 1 – 2 – 4 – 5 – 3", ["Порядок роботи:", "1 – 2 – 4 – 5 – 3"]),
        (
            "Порядок роботи: 1Л – 1П – 4Л – 2Л – 2П – 3Л – 3П – 4П",
            ["Порядок роботи:", "1Л – 1П – 4Л – 2Л –", "2П – 3Л – 3П – 4П"],
        ),
        (
            "Firing order: 1 – 3 – 5 – 7 – 9 – 2 – 4 – 6 – 8",
            ["Firing order:", "1 – 3 – 5 – 7 – 9 –", "2 – 4 – 6 – 8"],
        ),
    ],
)
def test_a_firing_order_breaks_after_its_title_and_into_even_lines(label, lines):
    """The crank star's firing order: on one line where it fits the star's width; else the title
    on its own line and the order in as few lines as it needs, of even length, each broken after
    a dash."""
    assert md._wrapped_order(label).split("\n") == lines
    assert all(len(line) <= 30 for line in lines[1:])
