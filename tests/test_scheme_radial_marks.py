"""A radial's kinematic scheme (ГОСТ 2.770, 2.307): the shaft's axis O stands off the shaded
master rod and counterweight; the knuckle-pin radius r and the slave rod's length are dimensioned
beside their links, with the crank radius R, each text crossing no member and standing off the
shaded links, over its dimension line, past an arrow or joined to the line by a leader shorter
than the mechanism's half width;
the characteristic positions are drawn at a standard scale, the panel's width over its limits.

Independent values: r and the slave rod's length from the example's [articulated] pin_radius and
the joints' distance on the drawing; the standard scales of ГОСТ 2.302."""

from __future__ import annotations

import tomllib

import numpy as np
from matplotlib.path import Path
from test_scheme_labels import _crossed_lines, _positions

from crankdyn.cli import examples_dir
from crankdyn.report import mechanism_drawing as md

EXAMPLE = "radial9-aircraft"
STANDARD = {1.0, 1 / 2, 1 / 2.5, 1 / 4, 1 / 5, 1 / 10, 1 / 15, 1 / 20, 1 / 25, 1 / 40, 1 / 50}


MARKS = {"alpha": "α", "beta": "β", "omega": "ω", "tdc": "TDC", "bdc": "BDC"}


def _scheme():
    """The scheme as the report draws it: with its marks (O, A, B, ω)."""
    positions = _positions(EXAMPLE)
    labels = {k: f"{k} = {value * 1e3:g} mm" for k, value in positions.dimensions.items()}
    fig, _ = md.scheme_figure(positions, 0, labels, "Crank star", "Firing order: 1", MARKS)
    fig.canvas.draw()
    return fig


def _shaded(ax):
    from matplotlib.colors import to_rgba
    from matplotlib.patches import Polygon

    return [
        Path(p.get_verts())
        for p in ax.patches
        if isinstance(p, Polygon) and p.get_fill() and to_rgba(p.get_facecolor())[:3] != (1, 1, 1)
    ]


def _on_shaded(ax, text, renderer) -> bool:
    box = text.get_window_extent(renderer)
    corners = [(box.x0, box.y0), (box.x1, box.y0), (box.x1, box.y1), (box.x0, box.y1)]
    centre = [((box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2)]
    return any(body.contains_points(corners + centre).any() for body in _shaded(ax))


def test_o_and_the_dimension_texts_stand_off_the_links():
    fig = _scheme()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    assert _shaded(ax), "the master rod's body is drawn shaded"
    o = next(t for t in ax.texts if t.get_gid() == "mark-O")
    assert not _on_shaded(ax, o, renderer)
    for key in ("R", "r"):  # no slave rod length on a radial: its table gives them
        text = next(t for t in ax.texts if t.get_gid() == f"dimension-{key}-text")
        assert not _on_shaded(ax, text, renderer), key
        assert not _crossed_lines(ax, text, renderer), key
        # over its dimension line, past its arrow or by a leader shorter than half the width
        for leader in (
            line for line in ax.lines if line.get_gid() == f"dimension-{key}-text-leader"
        ):
            xy = np.column_stack(leader.get_data())
            x0, x1 = ax.get_xlim()
            assert np.linalg.norm(xy[1] - xy[0]) < (x1 - x0) / 2, key
        assert any(line.get_gid() == f"dimension-{key}-line" for line in ax.texts), key


def test_r_and_the_slave_rod_are_dimensioned_with_their_values():
    positions = _positions(EXAMPLE)
    with open(examples_dir() / f"{EXAMPLE}.toml", "rb") as fh:
        given = tomllib.load(fh)["articulated"]["pin_radius"]
    r = positions.dimensions["r"]
    assert abs(r - float(given.split()[0]) / 1e3) < 1e-12
    slave = next(l for l in positions.links if l[0].startswith("rod_") and "slave" in l[1])
    length = np.linalg.norm(positions.joints[slave[2]][0] - positions.joints[slave[1]][0])
    assert abs(positions.dimensions["l_s"] - length) < 1e-9
    centre = positions.joints[next(l[1] for l in positions.links if l[0].startswith("master_"))]
    assert abs(np.linalg.norm(positions.joints[slave[1]][0] - centre[0]) - r) < 1e-9


def test_the_positions_are_drawn_at_a_standard_scale():
    positions = _positions(EXAMPLE)
    scale = md.positions_scale(positions)
    assert min(abs(scale - s) for s in STANDARD) < 1e-12
    fig = md.positions_figure(positions, [(0, "TDC\nα = 0°")])
    ax = fig.axes[0]
    width_mm = ax.get_position().width * fig.get_figwidth() * 25.4
    (x0, x1) = ax.get_xlim()
    assert abs(width_mm / (x1 - x0) - scale) < 1e-6  # the limits in mm


def test_a_letter_kept_off_the_shaded_links_goes_outside_one_it_would_stand_clear_in():
    """Inside a large shaded body a letter stands farthest from every outline; kept off the
    shaded links, it takes the place outside, though nearer the outline."""
    from types import SimpleNamespace

    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.set_xlim(-100, 100)
    ax.set_ylim(-100, 100)
    ax.fill([-50, 50, 50, -50], [-50, -50, 50, 50], facecolor="0.86", edgecolor="k")
    fig.canvas.draw()
    geometry = SimpleNamespace(joints={})
    places = [np.array([0.0, 0.0]), np.array([70.0, 0.0])]
    for off_bodies, expected in ((False, places[0]), (True, places[1])):
        clearance = md._Clearance(ax, geometry, 0, 200.0)
        clearance.place(places, "O", off_bodies=off_bodies)
        letter = ax.texts[-1]
        assert np.allclose(letter.get_position(), expected), off_bodies
        letter.remove()
    plt.close(fig)
