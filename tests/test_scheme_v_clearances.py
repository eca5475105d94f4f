"""A V engine's kinematic scheme keeps its dimensions clear of what they measure (ГОСТ 2.307,
2.770): the crank radius R's dimension line stands off the crank by more than an arrowhead's
length on the sheet, with its text by a leader; the rod length L's dimension line runs outside
its cylinder's walls and their hatching; the α arc stays clear of L's extension line; the
shaft's support is drawn over the counterweight.

Independent values: an arrowhead of 2.5 mm on the sheet (ГОСТ 2.307 gives 2.5-5 mm); lines
less than 0.5 mm apart on the sheet, about their own width (ГОСТ 2.303), print as touching; the
hatching's depth is the scheme's own stroke length."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import shared_run
from test_scheme_dimensions import MARKS

from crankdyn.report import mechanism_drawing as md

ARROWHEAD_MM = 2.5
APART_MM = 0.5


#: a V6 of 90° whose L's extension line from the crank pin passes close by the α arc
V6 = {
    "engine": {
        "cylinders": 6,
        "firing_order": ["1L", "1R", "3L", "3R", "2L", "2R"],
        "uneven_firing": True,
        "crank_angles_deg": [0, 120, 240],
        "bore": "92 mm",
        "stroke": "80 mm",
        "rod_length": "145 mm",
        "cylinder_spacing": "106 mm",
    }
}


@pytest.fixture(scope="module", params=[{}, V6], ids=["v8", "v6"])
def scheme(request):
    output = shared_run("v8-petrol", request.param, stages=("drawing",)).outputs["drawing"]
    positions = output.artifacts["positions"]
    labels = {k: f"{k} = {value * 1e3:g} mm" for k, value in positions.dimensions.items()}
    frame = len(output.results["crank_angles_deg"])
    fig, scale = md.scheme_figure(positions, frame, labels, "Crank star", "Firing order: 1", MARKS)
    fig.canvas.draw()
    geometry = md.upright(md.front_view(positions))
    return fig.axes[0], geometry, frame, scale


def _annotation(ax, gid):
    (found,) = [t for t in ax.texts if t.get_gid() == gid]
    return np.asarray(found.xyann, float), np.asarray(found.xy, float)


def _distance_to_line(points, a, b):
    d = (b - a) / np.linalg.norm(b - a)
    rel = np.asarray(points, float) - a
    return np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0])


def _crosses(p, q, r, s) -> bool:
    """Whether the segments p-q and r-s cross."""

    def side(a, b, c):
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    return side(p, q, r) != side(p, q, s) and side(r, s, p) != side(r, s, q)


def test_the_crank_radius_stands_off_the_crank_by_more_than_an_arrowhead(scheme):
    ax, geometry, frame, scale = scheme
    j = geometry.joints
    crank = next(link for link in geometry.links if link[0] in ("crank", "crank_1"))
    o, b = j[crank[1]][frame] * md.MM, j[crank[2]][frame] * md.MM
    start, end = _annotation(ax, "dimension-R-line")
    gap_mm = _distance_to_line([start, end], o, b).min() * scale
    assert gap_mm > ARROWHEAD_MM
    assert any(line.get_gid() == "dimension-R-text-leader" for line in ax.lines)


def test_the_rod_length_runs_outside_its_cylinders_walls_and_hatching(scheme):
    ax, geometry, frame, _ = scheme
    start, end = _annotation(ax, "dimension-L-line")
    extent = md._extent_mm(geometry)
    depth = md.HATCH * md.HATCH_SLANT * extent
    for guide in md._one_per_axis(geometry.guides):
        o, d, n = md._guide_frame(geometry, guide, frame)
        bottom, top = md.liner_ends_mm(guide, geometry)
        half = guide.bore_m * md.MM / 2
        for side in (-1, 1):  # the wall, and the line of its hatching's strokes' tips
            for reach in (half, half + depth):
                wall = (o + d * bottom + n * side * reach, o + d * top + n * side * reach)
                assert not _crosses(start, end, *wall), (guide.label, side, reach)


def _to_segment(points, a, b):
    """Each point's distance to the segment a-b."""
    d = b - a
    t = np.clip(((points - a) @ d) / float(d @ d), 0.0, 1.0)
    return np.hypot(*(points - (a + np.outer(t, d))).T)


def test_the_alpha_arc_stays_clear_of_the_rod_lengths_extension_line(scheme):
    ax, _, _, scale = scheme
    from matplotlib.patches import Arc

    arcs = [p for p in ax.patches if isinstance(p, Arc)]
    assert arcs
    (extension,) = [line for line in ax.lines if line.get_gid() == "dimension-L-extension-1"]
    a, b = np.asarray(extension.get_xydata(), float)  # from the crank pin
    for arc in arcs:
        angles = np.radians(np.linspace(arc.theta1, arc.theta2, 180))
        points = np.asarray(arc.center) + arc.width / 2 * np.c_[np.cos(angles), np.sin(angles)]
        assert _to_segment(points, a, b).min() * scale > APART_MM


def test_the_support_is_drawn_over_the_counterweight(scheme):
    ax, *_ = scheme
    from matplotlib.collections import LineCollection

    counterweight = [p for p in ax.patches if np.allclose(p.get_facecolor()[:3], 0.93)]
    assert counterweight
    hatching = [  # the support's, of thin strokes, over the shaded parts
        c
        for c in ax.collections
        if isinstance(c, LineCollection) and c.get_zorder() > 3 and c.get_linewidths()[0] < 1
    ]
    assert hatching
    assert min(c.get_zorder() for c in hatching) > max(p.get_zorder() for p in counterweight)


def test_the_pistons_are_drawn_thicker_than_the_walls_and_shaded(scheme):
    ax, geometry, *_ = scheme
    from matplotlib.colors import to_rgba
    from matplotlib.patches import Polygon

    pistons = [p for p in ax.patches if isinstance(p, Polygon) and p.get_gid() == "piston"]
    assert len(pistons) == len(md._one_per_axis(geometry.guides))
    # solid bodies: shaded, not white like the paper
    assert all(to_rgba(p.get_facecolor())[:3] != (1.0, 1.0, 1.0) for p in pistons)
    walls = [line.get_linewidth() for line in ax.lines if line.get_solid_capstyle() == "butt"]
    assert walls
    assert min(p.get_linewidth() for p in pistons) > 1.5 * max(walls)
