"""Kinematic schemes of any mechanism from its :class:`~crankdyn.plugin.types.MechanismGeometry`.

One module for every mechanism: ground pivots with hatching, revolute joints as small
circles, bars for links, pistons in their liners (or sliders in their slots), gear pitch
circles, traced curves, dimension lines (R, L, e, D) and a multi-cylinder engine's crank
star. Drawing only: every position comes from the geometry; nothing is computed here but
the placement of symbols. Lengths are drawn in millimetres.
"""

from __future__ import annotations

import base64
import hashlib
import io
import json
from contextlib import contextmanager
from dataclasses import replace
from types import MappingProxyType
from typing import Any

import numpy as np
from markupsafe import escape

from . import figure_memo
from .figures import STYLE, hide_axes

MM = 1e3
JOINT_R = 0.012  # joint circle radius, fraction of the drawing's extent
INK = "0.1"
LABEL_GAP = 0.2  # room for the cylinder label beyond the liner, fraction of the extent
LABEL_OFFSET = 0.05  # where the cylinder label starts beyond the liner, fraction of the extent
LABEL_BOX = {
    "facecolor": "white",
    "edgecolor": "none",
    "pad": 0.5,
}  # a dimension's text over the lines it crosses
#: A dimension's or a parameter's text on a drawing: small, dark grey, on a white box that keeps
#: the lines under it from crossing its letters.
DIMENSION_TEXT = MappingProxyType({"fontsize": 8, "color": "0.15", "bbox": LABEL_BOX})


def view_rotation_rad(geometry) -> float:
    """Clockwise turn of the view that sets a V (W, X ...) symmetric about the vertical: minus the
    mean of the cylinder axes' angles, when they lie within a half turn (never for a radial); two
    opposed axes (a boxer's) are laid horizontal with the first bank on the left."""
    axes = sorted(
        {round(float(np.arctan2(*g.direction)), 9) for g in geometry.guides if g.moving is None}
    )
    if len(axes) == 2 and abs(axes[1] - axes[0] - np.pi) < 1e-9:
        # two opposed banks (a boxer's) lie horizontal, the first bank on the left
        first = float(np.arctan2(*geometry.guides[0].direction))
        return -0.5 * np.pi - first
    if len(axes) < 2 or axes[-1] - axes[0] >= np.pi - 1e-9:
        return 0.0
    return -0.5 * (axes[0] + axes[-1])


def upright(geometry):
    """A copy of ``geometry`` turned by :func:`view_rotation_rad` (display only; lengths unchanged)."""

    turn = view_rotation_rad(geometry)
    if turn == 0.0:
        return geometry
    c, s_ = np.cos(turn), np.sin(turn)
    rot = np.array([[c, s_], [-s_, c]])  # clockwise by ``turn`` in the y-up frame

    def r(points):
        return np.asarray(points, dtype=float) @ rot.T

    guides = [
        replace(g, origin_m=tuple(r(g.origin_m)), direction=tuple(r(g.direction)))
        for g in geometry.guides
    ]
    return replace(
        geometry,
        joints={k: r(v) for k, v in geometry.joints.items()},
        traces={k: r(v) for k, v in geometry.traces.items()},
        guides=guides,
        cranks=[(label, lag - np.degrees(turn), cyl) for label, lag, cyl in geometry.cranks],
    )


def _axis_key(g):
    return (
        round(g.origin_m[0], 9),
        round(g.origin_m[1], 9),
        round(g.direction[0], 6),
        round(g.direction[1], 6),
        g.moving,
    )


def front_view(geometry):
    """What a front view shows: on each cylinder axis only its first cylinder (the nearest to the
    viewer), with its rod and crank; the cylinders behind it (an in-line engine's row, a V's
    banks) are left out, as the cranks they hang on are on the crank star beside the drawing.

    Drawn in one plane, an in-line four's pistons 1 and 2 shared one liner and its crank pin at
    0° and 180° one piston pin, which no reader takes for the scheme of a mechanism."""
    first: dict = {}
    for g in geometry.guides:
        first.setdefault(_axis_key(g), g)
    if len(first) == len(geometry.guides):
        return geometry
    kept = list(first.values())
    wrists = {g.joint for g in kept}
    labels = {g.label for g in kept}
    # a cylinder's own links: its rod (the slave's master link and web too, found by the slave
    # rod's big-end pin: the labels may be the report's, "1П" for the links' "1R"), then its crank
    big_ends = {l[1] for l in geometry.links if l[0].startswith("rod_") and l[2] in wrists}
    own = [
        l
        for l in geometry.links
        if (l[0].startswith("rod_") and l[2] in wrists)
        or (l[0].startswith("master_web_") and l[1] in big_ends)
        or (
            l[0].startswith("master_")
            and not l[0].startswith("master_web_")
            and (l[2] in big_ends or l[0].split("_")[-1] in labels)
        )
    ]
    pins = {l[1] for l in own}
    cranks = [l for l in geometry.links if l[0].startswith("crank") and l[2] in pins]
    links = cranks + own
    used = {j for _, a, b in links for j in (a, b)} | set(geometry.fixed)
    return replace(
        geometry,
        links=links,
        guides=kept,
        joints={k: v for k, v in geometry.joints.items() if k in used},
    )


def _extent_mm(geometry) -> float:
    points = np.concatenate([p.reshape(-1, 2) for p in geometry.joints.values()]) * MM
    span = np.ptp(points, axis=0).max()
    return float(max(span, geometry.dimensions.get("D", 0.0) * MM * 2, 1e-3))


def _guide_frame(geometry, guide, i):
    """Origin (mm), unit direction and unit normal of a guide at frame i."""
    if guide.moving is not None:
        a, b = (geometry.joints[j][i] * MM for j in guide.moving)
        d = (b - a) / np.linalg.norm(b - a)
        return a, d, np.array([d[1], -d[0]])
    d = np.asarray(guide.direction, dtype=float)
    return np.asarray(guide.origin_m, dtype=float) * MM, d, np.array([d[1], -d[0]])


SKIRT = 0.35  # the piston below its pin, fraction of the bore
PISTON_FILL = "0.85"  # a piston's shade: a solid body, lighter than a shaded counterweight
CROWN = 0.45  # the piston above its pin, fraction of the bore
SHORT_SKIRT = 0.12  # the least skirt drawn, where the neighbouring cylinders leave no room
HATCH = 0.02  # the spacing of a wall's hatching strokes, fraction of the extent
HATCH_SLANT = 0.7  # a stroke's reach out of the wall and back along it, fraction of the spacing


def liner_ends_mm(guide, geometry=None) -> tuple[float, float]:
    """(skirt end, crown end) of a cylinder liner along its axis from ``origin_m`` (mm): the piston
    pin's travel with the piston's skirt (:func:`piston_skirt_mm`) and a crown of 0.45 bore beyond
    it; with ``geometry``, a liner starts no nearer the shaft than its neighbours' walls allow
    (:func:`liner_floor_mm`), so that the cylinders of a radial or a V do not cross."""
    bottom = guide.travel_m[0] * MM - piston_skirt_mm(guide, geometry)
    if geometry is not None:
        bottom = max(bottom, liner_floor_mm(geometry, guide))
    return bottom, (guide.travel_m[1] + CROWN * guide.bore_m) * MM


def liner_floor_mm(geometry, guide) -> float:
    """The distance from the guide's origin (mm) beyond which its liner's walls and hatching clear
    those of every cylinder whose axis leaves the same origin at another angle: two liners of
    half-width h at an angle θ meet at h / tan(θ/2) from the shaft. -inf when nothing is near, or
    when the angle is too narrow for the liners to part within the piston's travel."""
    if guide.moving is not None or guide.bore_m <= 0:
        return -np.inf
    gap = _extent_mm(geometry) * 0.02 * 0.4  # part of the hatching's depth between the liners
    floor = -np.inf
    for theta, half in _neighbour_angles(geometry, guide):
        floor = max(floor, (half + gap) / np.tan(theta / 2))
    travel = [v * MM for v in guide.travel_m]
    return floor if floor <= travel[0] + 0.5 * (travel[1] - travel[0]) else -np.inf


def hatch_start_mm(geometry, guide) -> float:
    """The distance from the guide's origin (mm) where its walls' hatching may start: the strokes,
    reaching ``HATCH_SLANT`` of their spacing out of the wall and back towards the shaft, clear
    those of every cylinder whose axis leaves the same origin at another angle (two walls at an
    angle θ, meeting at h / tan(θ/2), part by 2 sin(θ/2) per unit of length). -inf when nothing
    is near."""
    if guide.moving is not None or guide.bore_m <= 0:
        return -np.inf
    depth = HATCH * HATCH_SLANT * _extent_mm(geometry)
    start = -np.inf
    for theta, half in _neighbour_angles(geometry, guide):
        start = max(start, half / np.tan(theta / 2) + depth + depth / np.sin(theta / 2))
    return start


def _neighbour_angles(geometry, guide):
    """(angle between the axes, rad; the wider half-bore, mm) of every other cylinder whose axis
    leaves the guide's origin."""
    d = np.asarray(guide.direction, dtype=float)
    for other in geometry.guides:
        if (
            other.moving is not None
            or other.bore_m <= 0
            or not np.allclose(other.origin_m, guide.origin_m)
        ):
            continue
        cos_theta = float(np.clip(np.dot(d, np.asarray(other.direction, dtype=float)), -1.0, 1.0))
        theta = float(np.arccos(cos_theta))
        if 1e-6 <= theta <= np.pi - 1e-6:
            yield theta, max(guide.bore_m, other.bore_m) * MM / 2


def piston_skirt_mm(guide, geometry=None) -> float:
    """The piston's length below its pin (mm): 0.35 bore, shortened (to 0.12 bore at least) where
    the liner is cut short by its neighbours (:func:`liner_floor_mm`), as a radial engine's
    pistons are, so that at its dead centre the piston stays in its cylinder and clear of the
    pistons beside it."""
    full = SKIRT * guide.bore_m * MM
    if geometry is None:
        return full
    room = guide.travel_m[0] * MM - liner_floor_mm(geometry, guide)
    return float(np.clip(room, SHORT_SKIRT * guide.bore_m * MM, full))


def _hatch(ax, start, end, normal, size, color, alpha, skip: float = 0.0, zorder=None):
    """Ground hatching: short strokes at 45 degrees on the ``normal`` side of start-end (one artist);
    the strokes begin ``skip`` (mm) along the wall from ``start``; ``zorder``: over what."""
    from matplotlib.collections import (
        LineCollection,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
    )

    layer = {} if zorder is None else {"zorder": zorder}
    ax.plot(
        *np.c_[start, end], color=color, lw=1.0, ls="-", alpha=alpha, solid_capstyle="butt", **layer
    )
    length = float(np.linalg.norm(end - start))
    d = (end - start) / length
    skip = float(min(max(skip, 0.0), 0.5 * length))
    count = max(int((length - skip) / size), 2)
    p = start + np.outer(np.linspace(skip, length, count + 1), d)
    q = p + (normal - d) * size * HATCH_SLANT
    ax.add_collection(
        LineCollection(
            list(np.stack([p, q], axis=1)), colors=[color], linewidths=0.6, alpha=alpha, **layer
        )
    )


def _hatch_fixed_gear(ax, geometry, i: int, centre, radius_mm: float, extent, color, alpha):
    """A fixed gear (a planetary mechanism's ring or sun) hatched as ground (ГОСТ 2.770): short
    strokes on the side away from the planet that rolls on it, outside a ring, inside a sun."""
    from matplotlib.collections import (
        LineCollection,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
    )

    planets = [geometry.joints[c][i] * MM for c, _, kind in geometry.circles if kind != "fixed"]
    inside = bool(planets) and float(np.linalg.norm(planets[0] - centre)) < radius_mm
    side = 1.0 if inside else -1.0
    size = extent * HATCH
    angles = np.radians(np.arange(0.0, 360.0, 360.0 / max(int(2 * np.pi * radius_mm / size), 12)))
    radial = np.stack([np.sin(angles), np.cos(angles)], axis=1)
    tangent = np.stack([np.cos(angles), -np.sin(angles)], axis=1)
    start = np.asarray(centre) + radius_mm * radial
    end = start + (side * radial - tangent) * size * HATCH_SLANT
    ax.add_collection(
        LineCollection(
            list(np.stack([start, end], axis=1)), colors=[color], linewidths=0.5, alpha=alpha
        )
    )


def draw_planetary_marks(ax, geometry, i: int, marks: dict[str, str]) -> None:
    """A planetary mechanism's letters at frame ``i``: O (shaft axis), C (planet centre), B (the
    planet's pin, the rod's big end), A (piston pin), K (pitch point on the fixed gear), the
    carrier angle α from the cylinder axis and the sense of rotation ω; nothing for another
    mechanism (its marks are :func:`draw_angle_marks`')."""
    j = geometry.joints
    names = ("crank_centre", "planet_centre", "crank_pin", "wrist_pin")
    if not all(name in j for name in names) or not geometry.guides:
        return
    extent = _extent_mm(geometry)
    o, c, b, a = (j[name][i] * MM for name in names)
    letter = {"fontsize": 9, "color": "0.1", "zorder": 7, "fontstyle": "italic"}
    carrier = float(np.linalg.norm(c - o))
    u = (c - o) / max(carrier, 1e-12)
    normal = np.array([u[1], -u[0]])
    ax.text(*(o + np.array([1.0, -0.15]) * extent * 0.035), "O", ha="left", va="center", **letter)
    ax.text(*(c + normal * extent * 0.03), "C", ha="left", va="center", **letter)
    pin = b - c
    away = pin / max(float(np.linalg.norm(pin)), 1e-12)
    ax.text(*(b + away * extent * 0.035), "B", ha="center", va="center", **letter)
    _, d, n = _guide_frame(geometry, geometry.guides[0], i)
    ax.text(*(a - n * extent * 0.03), "A", ha="right", va="center", **letter)
    fixed = next((r for name, r, kind in geometry.circles if kind == "fixed"), None)
    if fixed is not None:
        k = o + u * fixed * MM
        ax.plot(*k, "o", color="0.1", ms=2.5, zorder=7)
        ax.text(*(k + u * extent * 0.035), "K", ha="center", va="center", **letter)
    if marks and carrier > 0:
        ax.plot(*np.c_[o, o + d * carrier * 1.35], color="0.45", lw=0.5, ls="-.", zorder=1)
        _angle_arc(ax, o, d, u, carrier * 0.3, marks["alpha"], extent)
        _rotation_arrow(ax, o, carrier * 0.45, marks["omega"], extent)


def draw_ground(ax, centre, size, color=INK, alpha=1.0):
    """A fixed revolute joint: a small triangle on a hatched base below ``centre``."""
    c = np.asarray(centre)
    tri = np.array([c, c + [-size, -1.6 * size], c + [size, -1.6 * size], c])
    # the support stands in front of a counterweight turned towards it: white behind its
    # triangle and hatching, which stay whole (ГОСТ 2.770)
    below = c + np.array([[-1.9, -1.6], [1.9, -1.6], [1.9, -2.4], [-1.9, -2.4]]) * size
    ax.fill(*np.vstack([tri[:3], below[[1, 2, 3, 0]]]).T, color="white", lw=0, zorder=3.55)
    ax.plot(tri[:, 0], tri[:, 1], color=color, lw=1.0, ls="-", alpha=alpha, zorder=3.6)
    _hatch(
        ax,
        c + [-1.6 * size, -1.6 * size],
        c + [1.6 * size, -1.6 * size],
        np.array([0.0, -1.0]),
        size * 0.8,
        color,
        alpha,
        zorder=3.6,
    )


def draw_guide(ax, geometry, guide, i, extent, color=INK, alpha=1.0):
    """A cylinder liner with the piston in it, or a slot with the slider block."""
    o, d, n = _guide_frame(geometry, guide, i)
    low, high = (v * MM for v in guide.travel_m)
    pin = geometry.joints[guide.joint][i] * MM
    if guide.bore_m > 0:
        half = guide.bore_m * MM / 2
        skirt = piston_skirt_mm(guide, geometry)
        crown = CROWN * guide.bore_m * MM
        bottom, top = liner_ends_mm(guide, geometry)
        skip = hatch_start_mm(geometry, guide) - bottom  # clear of the neighbours' hatching
        for side in (-1, 1):
            a, b = o + d * bottom + n * side * half, o + d * top + n * side * half
            _hatch(ax, a, b, n * side, extent * HATCH, color, alpha, skip)
        axis = np.array([o + d * (bottom - 0.04 * extent), o + d * (top + 0.04 * extent)])
        ax.plot(axis[:, 0], axis[:, 1], color="0.45", lw=0.5, ls="-.", alpha=alpha, zorder=1)
        pos = float(np.dot(pin - o, d))
        corners = [pos - skirt, pos + crown]
        rect = np.array(
            [
                o + d * corners[0] - n * half * 0.97,
                o + d * corners[1] - n * half * 0.97,
                o + d * corners[1] + n * half * 0.97,
                o + d * corners[0] + n * half * 0.97,
            ]
        )
        ax.fill(  # a link: the thick solid line of ГОСТ 2.770, the walls being thin; shaded
            rect[:, 0],  # as a solid body moving in its liner
            rect[:, 1],
            facecolor=PISTON_FILL,
            gid="piston",
            edgecolor=color,
            lw=2.0,
            ls="-",
            alpha=alpha,
            zorder=3,
        )
        if guide.label:
            _guide_label(ax, o, d, n, top, half, guide.label, extent, color=color, alpha=alpha)
    else:
        width = extent * 0.035
        for side in (-1, 1):
            a, b = (
                o + d * (low - width) + n * side * width,
                o + d * (high + width) + n * side * width,
            )
            ax.plot(*np.c_[a, b], color=color, lw=1.0, ls="-", alpha=alpha)
        block = np.array(
            [
                pin - d * width * 1.2 - n * width,
                pin + d * width * 1.2 - n * width,
                pin + d * width * 1.2 + n * width,
                pin - d * width * 1.2 + n * width,
            ]
        )
        ax.fill(
            block[:, 0],
            block[:, 1],
            facecolor="white",
            edgecolor=color,
            lw=1.2,
            ls="-",
            alpha=alpha,
            zorder=3,
        )


def _guide_label(ax, o, d, n, top, half, label: str, extent: float, **style) -> None:
    """A cylinder's label beyond the liner's end, growing away from it (:func:`outward_alignment`).
    A tilted bank's label ("1L, 2L, 3L, 4L") goes beside the liner's end, on its outer side, so
    that it leaves the room beyond the end to the bore's dimension line."""
    if "," in label and abs(float(d[0])) > 0.3:
        outer = n if float(n[0]) * float(d[0]) > 0 else -n
        at = o + d * top + outer * (half + LABEL_OFFSET * extent)
        ax.text(*at, label, fontsize=8, **style, **outward_alignment(outer))
    else:
        ax.text(
            *(o + d * (top + LABEL_OFFSET * extent)),
            label,
            fontsize=8,
            **style,
            **outward_alignment(d),
        )


def outward_alignment(direction) -> dict[str, str]:
    """Text alignment that makes a label grow along ``direction`` from its anchor: the label of a
    tilted cylinder (a V or radial bank) then starts beyond the liner's end instead of being
    centred on it, where a long label ("1L, 2L, 3L, 4L") would cross the liner."""
    dx, dy = float(direction[0]), float(direction[1])
    return {
        "ha": "left" if dx > 0.3 else "right" if dx < -0.3 else "center",
        "va": "bottom" if dy > 0.3 else "top" if dy < -0.3 else "center",
    }


def draw_mechanism(
    ax, geometry, i: int, color=INK, alpha: float = 1.0, static: bool = True
) -> None:
    """The mechanism at frame ``i``; ``static=False`` leaves out ground, guides and traces."""
    with _autoscaled_once(ax):
        _draw_mechanism(ax, geometry, i, color, alpha, static)
    ax.autoscale_view()
    ax.set_aspect("equal")
    hide_axes(ax)


@contextmanager
def _autoscaled_once(ax):
    """Inside, the axes' limits are not autoscaled: matplotlib otherwise autoscales them anew,
    over every artist added so far, each time a collection is added (a drawing adds dozens).
    The data limits still grow with each artist, so the autoscale after it (as it was) sees them
    all."""
    on = ax.get_autoscalex_on(), ax.get_autoscaley_on()
    ax.set_autoscale_on(False)
    try:
        yield
    finally:
        ax.set_autoscalex_on(on[0])
        ax.set_autoscaley_on(on[1])


def _draw_mechanism(ax, geometry, i: int, color, alpha: float, static: bool) -> None:
    extent = _extent_mm(geometry)
    r_joint = extent * JOINT_R
    if static:
        for path in geometry.traces.values():
            ax.plot(path[:, 0] * MM, path[:, 1] * MM, color="0.55", lw=0.7, ls=(0, (4, 2)))
        for centre, radius, kind in geometry.circles:
            if kind == "fixed":
                c = geometry.joints[centre][i] * MM
                ax.add_patch(_circle(c, radius * MM, color, alpha, ls="-."))
                _hatch_fixed_gear(ax, geometry, i, c, radius * MM, extent, color, alpha)
    for centre, radius, kind in geometry.circles:
        if kind != "fixed":
            ax.add_patch(
                _circle(geometry.joints[centre][i] * MM, radius * MM, color, alpha, ls="-.")
            )
    for guide in _one_per_axis(geometry.guides):
        draw_guide(ax, geometry, guide, i, extent, color, alpha)
    from matplotlib.collections import (  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
        LineCollection,
        PatchCollection,
    )
    from matplotlib.patches import (
        Circle,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
    )

    bodies = master_rod_bodies(geometry, i)
    for outline in bodies:
        ax.fill(
            outline[:, 0],
            outline[:, 1],
            facecolor="0.86",
            edgecolor=color,
            lw=1.6,
            ls="-",
            alpha=alpha,
            zorder=3.5,
            joinstyle="round",
        )
    for outline in counterweights(geometry, i):
        ax.fill(
            outline[:, 0],
            outline[:, 1],
            facecolor="0.93",
            edgecolor=color,
            lw=1.0,
            ls="-",
            alpha=alpha,
            zorder=1.5,
        )
    bars = [
        [geometry.joints[a][i] * MM, geometry.joints[b][i] * MM]
        for _, a, b in drawn_links(geometry)
    ]
    ax.add_collection(
        LineCollection(
            bars, colors=[color], linewidths=2.0, alpha=alpha, capstyle="round", zorder=4
        )
    )
    if static:
        for name in geometry.fixed:
            draw_ground(ax, geometry.joints[name][i] * MM, r_joint * 1.6, color, alpha)
    circles = [
        Circle(p[i] * MM, r_joint) for name, p in geometry.joints.items() if name != "vane_tip"
    ]
    ax.add_collection(
        PatchCollection(
            circles, facecolor="white", edgecolor=color, linewidths=1.1, alpha=alpha, zorder=5
        )
    )


def drawn_links(geometry):
    """The links drawn as bars: all but a master rod's members from its big end to its knuckle
    pins (``master_*``), which :func:`master_rod_bodies` draws as one rigid body."""
    return [link for link in geometry.links if not link[0].startswith("master_")]


def master_rod_joints(geometry) -> list[list[str]]:
    """The knuckle pins of each master rod in order round its crank pin (at the first frame: the
    body is rigid, so the order holds at every frame): the animation's bodies."""
    pins: dict[str, list[str]] = {}
    for name, a, b in geometry.links:
        if name.startswith("master_") and not name.startswith("master_web_"):
            pins.setdefault(a, []).append(b)
    webs = {a: b for name, a, b in geometry.links if name.startswith("master_web_")}
    bodies = []
    for centre, knuckles in pins.items():
        c = geometry.joints[centre][0]
        angles = [np.arctan2(*(geometry.joints[k][0] - c)[::-1]) for k in knuckles]
        names = [k for _, k in sorted(zip(angles, knuckles, strict=False))]
        if len(names) == 1 and names[0] in webs:
            # a V's master rod with one slave: the plate through its big end, the slave's pin on
            # its lug and its own piston pin, so the slave rod hangs on the master, not in the air
            names = [centre, names[0], webs[names[0]]]
        bodies.append(names + [centre] if len(names) == 2 else names)
    return [b for b in bodies if len(b) >= 3]


def master_rod_bodies(geometry, i: int) -> list:
    """The big end of each master rod at frame ``i`` (mm): the polygon through its knuckle pins
    (:func:`master_rod_joints`), drawn filled as one rigid member (ГОСТ 2.770: a link with more
    than two joints), the master's shank leaving it as a bar."""
    return [
        np.array([geometry.joints[k][i] * MM for k in names])
        for names in master_rod_joints(geometry)
    ]


#: A crank's counterweight as drawn: a segment of a disc opposite the crank pin (radius and
#: half-angle), a symbol of the crank's balance mass, not its size.
COUNTERWEIGHT_RADIUS = 0.6
COUNTERWEIGHT_HALF_ANGLE_DEG = 55.0


def counterweights(geometry, i: int) -> list:
    """Outlines (mm) of the counterweights of a piston engine's cranks at frame ``i``: on every
    link ``crank`` or ``crank_<k>`` from the shaft's axis, when the mechanism has a cylinder;
    only on the cranks ``geometry.counterweight_cranks`` names, when it names them."""
    if not any(g.bore_m > 0 and g.moving is None for g in geometry.guides):
        return []
    chosen = getattr(geometry, "counterweight_cranks", None)
    turned = dict(getattr(geometry, "counterweight_angles", ()))
    outlines = []
    for name, a, b in geometry.links:
        if a != "crank_centre" or not (name == "crank" or name.removeprefix("crank_").isdigit()):
            continue
        number = 1 if name == "crank" else int(name.removeprefix("crank_"))
        if chosen is not None and number not in chosen:
            continue
        c, pin = geometry.joints[a][i] * MM, geometry.joints[b][i] * MM
        radius = float(np.linalg.norm(pin - c))
        if radius <= 0:
            continue
        # the crank turns clockwise on the drawing: an angle in the direction of rotation from
        # the pin's direction is subtracted; opposite the pin (pi) unless the balancing says
        towards = np.arctan2(pin[1] - c[1], pin[0] - c[0])
        away = towards - turned.get(number, np.pi)
        half = np.radians(COUNTERWEIGHT_HALF_ANGLE_DEG)
        arc = np.linspace(away - half, away + half, 24)
        rim = c + COUNTERWEIGHT_RADIUS * radius * np.c_[np.cos(arc), np.sin(arc)]
        outlines.append(np.vstack([c, rim, c]))
    return outlines


def _one_per_axis(guides):
    """Guides on one axis (a bank's cylinders in front view) drawn once, labelled together."""

    merged: dict = {}
    for g in guides:
        key = _axis_key(g)
        if key in merged:
            first = merged[key]
            merged[key] = replace(
                first, label=f"{first.label}, {g.label}" if g.label else first.label
            )
        else:
            merged[key] = g
    return list(merged.values())


def _circle(centre, radius, color, alpha, ls="-", fill=False):
    from matplotlib.patches import (
        Circle,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
    )

    return Circle(
        centre,
        radius,
        facecolor="white" if fill else "none",
        edgecolor=color,
        lw=1.0 if not fill else 1.1,
        ls=ls,
        alpha=alpha,
        zorder=5 if fill else 2,
    )


def _dimension_arrow(ax, a, b, gid: str = "") -> None:
    """A dimension line's arrow from ``a`` to ``b`` (mm), heads at both ends."""
    arrow = ax.annotate(
        "",
        xy=b,
        xytext=a,
        arrowprops={
            "arrowstyle": "<|-|>",
            "color": "0.35",
            "lw": 0.6,
            "shrinkA": 0,
            "shrinkB": 0,
            "mutation_scale": 7,
        },
    )
    if gid:
        arrow.set_gid(gid)


def _dimension(ax, p, q, text, offset, extent, key: str = "", from_feature: bool = False):
    """A dimension (ГОСТ 2.307) of the feature p-q (mm): two extension lines from the feature's
    points along the normal, the dimension line with its arrows between them shifted by
    ``offset``, the extension lines running past it, and the text parallel to the dimension line,
    above it (on the side its letters stand up to), near its middle. ``from_feature``: the
    extension lines start at the feature's points (a liner's wall ends), else just clear of them
    (a joint's circle). ``key`` names the artists (``gid``: ``dimension-<key>-...``)."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    d = (q - p) / max(np.linalg.norm(q - p), 1e-12)
    n = np.array([-d[1], d[0]])
    a, b = p + n * offset, q + n * offset
    out = n * np.sign(offset)
    for k, (end, base) in enumerate(((a, p), (b, q)), start=1):
        (line,) = ax.plot(
            *np.c_[
                base + (0.0 if from_feature else 0.01 * extent) * out,
                end + out * extent * 0.02,
            ],
            color="0.35",
            lw=0.5,
            ls="-",
        )
        line.set_gid(f"dimension-{key}-extension-{k}")
        if key == "r":  # from the crank pin's axis U, under the master rod's shaded body
            line.set_zorder(3.6)
    _dimension_arrow(ax, a, b, f"dimension-{key}-line")
    if text:
        _dimension_text(ax, a, b, text, extent, f"dimension-{key}-text")


def _readable_rotation_deg(d) -> float:
    """The text angle (deg) along the direction ``d``, read from the bottom or from the right of
    the sheet (ГОСТ 2.307, ISO 129-1): in (-60, 120], a line steeper than 60 deg read upwards."""
    rotation = float(np.degrees(np.arctan2(d[1], d[0])))
    if rotation > 120.0 + 1e-9:
        return rotation - 180.0
    if rotation <= -60.0 + 1e-9:
        return rotation + 180.0
    return rotation


def _dimension_text(ax, a, b, text: str, extent: float, gid: str):
    """A dimension's text over the middle of the dimension line a-b (mm), parallel to it, on the
    side its letters stand up to (ГОСТ 2.307: above a horizontal line, left of a vertical one)."""
    rotation = _readable_rotation_deg(np.asarray(b, float) - np.asarray(a, float))
    up = np.array([-np.sin(np.radians(rotation)), np.cos(np.radians(rotation))])
    label = ax.text(
        *((np.asarray(a) + np.asarray(b)) / 2 + up * extent * 0.006),
        text,
        rotation=rotation,
        rotation_mode="anchor",
        ha="center",
        va="bottom",
        **DIMENSION_TEXT,
        zorder=7,
    )
    label.set_gid(gid)
    return label


def draw_dimensions(ax, geometry, i: int, labels: dict[str, str]) -> None:
    """Dimension lines for R (crank), L (rod), e (offset) and D (bore) at frame ``i``."""
    extent = _extent_mm(geometry)
    labels = {k: v for k, v in labels.items() if k in geometry.dimensions}
    j = geometry.joints
    crank = next((l for l in geometry.links if l[0] in ("crank", "crank_1", "carrier")), None)
    rod = next(
        (l for l in geometry.links if l[0] in ("rod", "core") or l[0].startswith("rod_")), None
    )
    if "a" in labels and "R" not in labels:  # a planetary carrier's radius a, drawn as a crank's
        labels = {**labels, "R": labels["a"]}
    if is_radial(geometry) and crank and rod:
        _radial_dimensions(ax, geometry, i, labels, crank, rod, extent)
        return
    if crank and "R" in labels:
        _crank_radius(ax, geometry, i, crank, labels["R"], extent)
    if crank and master_rod_joints(geometry):
        _slave_dimensions(ax, geometry, i, labels, extent)
    liners = any(g.bore_m > 0 and g.moving is None for g in geometry.guides)
    if rod and "L" in labels and liners:
        # its text over the dimension line, where that crosses no liner, piston or other bank
        _rod_length_clear(ax, geometry, i, rod, labels["L"], extent)
    elif rod and "L" in labels:
        # Outside the slot, so the text stays clear of it.
        clear = geometry.dimensions.get("D", 0.0) * MM / 2 + extent * 0.06
        _dimension(
            ax,
            j[rod[1]][i] * MM,
            j[rod[2]][i] * MM,
            labels["L"],
            max(extent * 0.09, clear),
            extent,
            "L",
        )
    guide = geometry.guides[0] if geometry.guides else None
    if "e" in labels and guide is not None:
        _offset_dimension(ax, geometry, i, guide, rod, labels["e"], extent)
    if "D" in labels:
        _bore_dimension(ax, geometry, i, labels["D"], extent)


def _bore_dimension(ax, geometry, i: int, text: str, extent: float) -> None:
    """D: across the first cylinder's liner end, above its label."""
    guide = geometry.guides[0] if geometry.guides else None
    if guide is None or guide.bore_m <= 0:
        return
    o, d, n = _guide_frame(geometry, guide, i)
    # above the cylinder's label (its number), which would otherwise sit in the text
    clear = extent * (0.05 + (LABEL_GAP * 0.6 + 0.04 if guide.label else 0.0))
    top = o + d * liner_ends_mm(guide, geometry)[1]
    half = guide.bore_m * MM / 2
    # the extension lines from the liner's wall ends, past the label, to the dimension line
    _dimension(ax, top - n * half, top + n * half, text, clear, extent, "D", from_feature=True)


def _radial_dimensions(ax, geometry, i: int, labels: dict[str, str], crank, rod, extent: float):
    """A radial's D, R, r and L (:func:`_radial_dimension`), each kept off the links and the
    ones before it: D first, over the first cylinder, then the crank's R under the master rod's
    body, the knuckle pins' r and the master rod's L. No slave rod length: the slave rods differ
    slightly in length, and among the other rods no dimension line stands near one of them."""
    j = geometry.joints
    if "D" in labels:
        _bore_dimension(ax, geometry, i, labels["D"], extent)
    if "R" in labels:
        ends = [(j[crank[1]][i] * MM, j[crank[2]][i] * MM)]
        _radial_dimension(ax, geometry, i, ends, labels["R"], extent, "R")
    # r before L: r's extension lines start under the master rod's body and may reach far, and
    # L's text, placed after them, keeps off them
    _slave_dimensions(ax, geometry, i, {k: v for k, v in labels.items() if k == "r"}, extent)
    if "L" in labels:
        ends = [(j[rod[1]][i] * MM, j[rod[2]][i] * MM)]
        _radial_dimension(ax, geometry, i, ends, labels["L"], extent, "L")
    # the slave rods' lengths differ slightly and no full-length dimension line stands near a
    # slave rod among the others: the note gives them in its table of the slave rods instead


def _crank_radius(ax, geometry, i: int, crank, text: str, extent: float) -> None:
    """R: below the whole mechanism when several cylinder axes meet at the crank pin, beside it
    when an in-line engine's rods fan out, else beside the crank itself."""
    if len(_one_per_axis(geometry.guides)) > 1:
        _crank_radius_below(ax, geometry, i, crank, text, extent)
        return
    if len({round(float(lag) % 360.0, 6) for _, lag, _ in geometry.cranks}) > 2:
        _crank_radius_aside(ax, geometry, i, crank, text, extent)
        return
    p, q = (geometry.joints[name][i] * MM for name in crank[1:])
    _dimension(ax, p, q, "", -extent * 0.06, extent, "R")
    # a crank at an angle: its text level, just beyond the middle of the dimension line, away
    # from the crank, which a text along the line would reach with its corners
    d = (q - p) / max(float(np.linalg.norm(q - p)), 1e-12)
    side = -np.array([-d[1], d[0]])
    ax.text(
        *((p + q) / 2 + side * extent * 0.075),
        text,
        **DIMENSION_TEXT,
        gid="dimension-R-text",
        ha="left" if side[0] > 0.5 else "right" if side[0] < -0.5 else "center",
        va="bottom" if side[1] > 0.5 else "top" if side[1] < -0.5 else "center",
    )


def _offset_dimension(ax, geometry, i: int, guide, rod, text: str, extent: float) -> None:
    """e: between the vertical through the crank axis and the cylinder axis, below the liner."""
    j = geometry.joints
    feature = liner_ends_mm(guide, geometry)[0]
    y = feature - extent * 0.03
    ax.plot([0.0, 0.0], [0.0, y + extent * 0.04], color="0.45", lw=0.5, ls="-.")
    # the extension lines from the two axes down past the dimension line
    x_e = guide.origin_m[0] * MM
    _dimension(ax, (0.0, feature), (x_e, feature), "", (y - feature) * np.sign(x_e), extent, "e")
    # on the side the rod does not cross at that height
    ends = sorted([0.0, x_e])
    rod_x = _x_at(j[rod[1]][i] * MM, j[rod[2]][i] * MM, y) if rod else None
    left = rod_x is not None and rod_x > ends[1]
    # too short for its text between the arrows: the text on the dimension line's extension
    ax.text(
        ends[0] - extent * 0.03 if left else ends[1] + extent * 0.03,
        y,
        text,
        gid="dimension-e-text",
        ha="right" if left else "left",
        va="center",
        **DIMENSION_TEXT,
    )


def _x_at(a, b, y: float) -> float | None:
    """The abscissa at which the segment a-b (mm) crosses the height ``y``; None if it does not."""
    if (a[1] - y) * (b[1] - y) > 0 or a[1] == b[1]:
        return None
    return float(a[0] + (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]))


def piston_outline_mm(geometry, guide, i: int) -> np.ndarray:
    """A piston's four corners (mm) at frame ``i``: from its skirt's end (:func:`piston_skirt_mm`
    below its pin) to its crown, the bore wide, as the scheme draws it."""
    o, d, n = _guide_frame(geometry, guide, i)
    half = guide.bore_m * MM / 2
    pos = float(np.dot(geometry.joints[guide.joint][i] * MM - o, d))
    low, high = pos - piston_skirt_mm(guide, geometry), pos + CROWN * guide.bore_m * MM
    return np.array(
        [
            o + d * low - n * half,
            o + d * high - n * half,
            o + d * high + n * half,
            o + d * low + n * half,
        ]
    )


def member_segments_mm(geometry, i: int) -> np.ndarray:
    """(n, 2, 2) segments (mm) of what the scheme draws at frame ``i`` with a thick line: the
    bars, the master rods' outlines, the liners' walls and the pistons; what a text must not cross."""
    j = geometry.joints
    segments = [(j[a][i] * MM, j[b][i] * MM) for _, a, b in drawn_links(geometry)]
    for outline in master_rod_bodies(geometry, i):
        segments += list(zip(outline, np.roll(outline, -1, axis=0), strict=False))
    for guide in _one_per_axis(geometry.guides):
        if guide.bore_m <= 0 or guide.moving is not None:
            continue
        o, d, n = _guide_frame(geometry, guide, i)
        half = guide.bore_m * MM / 2
        bottom, top = liner_ends_mm(guide, geometry)
        segments += [
            (o + d * bottom + n * side * half, o + d * top + n * side * half) for side in (-1, 1)
        ]
        corners = list(piston_outline_mm(geometry, guide, i))
        segments += list(zip(corners, corners[1:] + corners[:1], strict=False))
    return np.array(segments, dtype=float).reshape(-1, 2, 2)


def text_crosses(box, segments_display) -> bool:
    """Whether any segment (display coordinates, (n, 2, 2)) passes through ``box`` (a Bbox)."""
    if len(segments_display) == 0:
        return False
    t = np.linspace(0.0, 1.0, 60)[None, :, None]
    points = (
        segments_display[:, :1, :] + (segments_display[:, 1:, :] - segments_display[:, :1, :]) * t
    )
    inside = (
        (points[..., 0] > box.x0)
        & (points[..., 0] < box.x1)
        & (points[..., 1] > box.y0)
        & (points[..., 1] < box.y1)
    )
    return bool(inside.any())


def _rod_length_clear(ax, geometry, i: int, rod, text: str, extent: float) -> None:
    """L of a mechanism with cylinders (a radial, a V, one whose scheme has no marks): the dimension
    line beside the rod, clear of its liner, with the text along it and above it (ГОСТ 2.307) at
    the first offset and place whose box, with the depth of a wall's hatching round it, crosses no
    bar, body, liner or piston (the nearest when none is)."""
    j = geometry.joints
    p, q = j[rod[1]][i] * MM, j[rod[2]][i] * MM
    d = (q - p) / max(np.linalg.norm(q - p), 1e-12)
    n = np.array([-d[1], d[0]])
    rotation = _readable_rotation_deg(d)
    up = np.array([-np.sin(np.radians(rotation)), np.cos(np.radians(rotation))])
    segments = ax.transData.transform(member_segments_mm(geometry, i).reshape(-1, 2)).reshape(
        -1, 2, 2
    )
    renderer = ax.figure.canvas.get_renderer()
    # and the texts written before it (R below a W's or a radial's crank)
    for written in [t for t in ax.texts if t.get_text()]:
        box = written.get_window_extent(renderer)
        corners = np.array([[box.x0, box.y0], [box.x1, box.y0], [box.x1, box.y1], [box.x0, box.y1]])
        edges = np.stack([corners, np.roll(corners, -1, axis=0)], axis=1)
        segments = np.concatenate([segments, edges])
    label = ax.text(
        0.0,
        0.0,
        text,
        rotation_mode="anchor",
        ha="center",
        va="bottom",
        **DIMENSION_TEXT,
        zorder=7,
    )
    # the text's own box, level (display units): a slanted text's upright box would take in
    # the walls beside it
    size = label.get_window_extent(renderer)
    label.set_rotation(rotation)
    # of two banks, on the outer side of the rod, where no other bank's liner is
    axes = _one_per_axis(geometry.guides)
    signs: tuple[float, ...] = (-1.0, 1.0)
    if len(axes) == 2:
        others = sum(np.asarray(g.direction, float) for g in axes if g.joint != rod[2])
        signs = (-1.0,) if float(np.dot(n, others)) > 0 else (1.0,)
    clear = {sign: _rod_dimension_clearance(geometry, i, rod, sign, extent) for sign in signs}
    candidates = [
        (sign * (clear[sign] + k * extent * 0.04), share)
        for k in range(4)
        for sign in signs
        for share in (0.5, 0.6, 0.4, 0.7, 0.3, 0.8, 0.9, 0.2)
    ]
    hatching = float(
        np.ptp(ax.transData.transform([[0.0, 0.0], [HATCH * HATCH_SLANT * extent, 0.0]])[:, 0])
    )
    # clear of the hatching's strokes, with a gap, where there is room, else of the walls only,
    # else the first place
    tries = [(c, 1.6 * hatching) for c in candidates] + [(c, 0.0) for c in candidates]
    for (offset, share), pad in tries + [(candidates[0], 0.0)]:
        anchor = p + (q - p) * share + n * offset + up * extent * 0.006
        label.set_position(anchor)
        at = ax.transData.transform(anchor)
        if not _slanted_text_crosses(at, rotation, size.width, size.height, pad, segments):
            break
    label.set_gid("dimension-L-text")
    _dimension(ax, p, q, "", offset, extent, "L")


def _rod_dimension_clearance(geometry, i: int, rod, side: float, extent: float) -> float:
    """How far from the rod, on its ``side`` (+1: along the rod's left normal), its L's dimension
    line runs (mm): past the walls of its cylinder and their hatching wherever they lie beside
    the rod, which leans off the cylinder's axis, so a line close to the wall at the piston pin
    would cross it near the crank pin."""
    j = geometry.joints
    p, q = j[rod[1]][i] * MM, j[rod[2]][i] * MM
    length = max(float(np.linalg.norm(q - p)), 1e-12)
    d = (q - p) / length
    n = np.array([-d[1], d[0]]) * side
    gap = HATCH * HATCH_SLANT * extent + extent * 0.03
    least = geometry.dimensions.get("D", 0.0) * MM / 2 + gap
    guide = next((g for g in geometry.guides if g.joint == rod[2] and g.bore_m > 0), None)
    if guide is None:
        return least
    o, gd, gn = _guide_frame(geometry, guide, i)
    bottom, top = liner_ends_mm(guide, geometry)
    half = guide.bore_m * MM / 2
    reach = []
    for wall_side in (-1.0, 1.0):
        wall = o + np.outer(np.linspace(bottom, top, 80), gd) + gn * wall_side * half
        along = (wall - p) @ d
        beside = (along > -gap) & (along < length + gap)
        if beside.any():
            reach.append(float(((wall[beside] - p) @ n).max()) + gap)
    return max([least] + reach)


def _slanted_text_crosses(anchor, rotation_deg, width, height, pad, segments) -> bool:
    """Whether any segment (display coordinates, (n, 2, 2)) passes through the box of a text
    ``width`` x ``height`` turned by ``rotation_deg`` about the middle of its foot ``anchor``
    (ha center, va bottom), widened by ``pad`` on every side."""
    if len(segments) == 0:
        return False
    t = np.linspace(0.0, 1.0, 60)[None, :, None]
    points = (segments[:, :1, :] + (segments[:, 1:, :] - segments[:, :1, :]) * t).reshape(-1, 2)
    c, s_ = np.cos(np.radians(rotation_deg)), np.sin(np.radians(rotation_deg))
    local = (points - np.asarray(anchor, float)) @ np.array([[c, -s_], [s_, c]])
    inside = (
        (np.abs(local[:, 0]) < width / 2 + pad)
        & (local[:, 1] > -pad)
        & (local[:, 1] < height + pad)
    )
    return bool(inside.any())


def _direction_deg(v) -> float:
    """The angle of the vector ``v`` in degrees, counter-clockwise from +x (matplotlib's arcs)."""
    return float(np.degrees(np.arctan2(v[1], v[0])))


def _angle_arc(ax, centre, start, end, radius, text: str, extent: float, sub: str = "") -> None:
    """An arc from direction ``start`` to ``end`` (unit vectors) around ``centre`` (mm), the
    shorter way, with its symbol (and its subscript ``sub``) just outside the middle of the arc."""
    from matplotlib.patches import (
        Arc,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
    )

    a, b = _direction_deg(start), _direction_deg(end)
    # no angle (β at a dead centre): no arc, which would be drawn as a whole circle
    flat = abs((b - a + 180.0) % 360.0 - 180.0) < 0.05
    if (b - a) % 360.0 > 180.0:  # the shorter way round: from end to start counter-clockwise
        a, b = b, a
    if not flat:
        ax.add_patch(
            Arc(
                centre,
                2 * radius,
                2 * radius,
                theta1=a,
                theta2=b if b > a else b + 360.0,
                color="0.2",
                lw=0.6,
                zorder=6,
            )
        )
    middle = np.radians(a + ((b - a) % 360.0) / 2)
    at = np.asarray(centre) + (radius + extent * 0.025) * np.array([np.cos(middle), np.sin(middle)])
    if text:
        _lettered(ax, at, text, sub, ha="center", va="center", fontstyle="italic")


#: The crank pin's axis on an engine's scheme: not B, the bearing width of the bearings section
#: (nor K, the second-order vector of a bay, nor C, the centrifugal force).
PIN_MARK = "U"


def _lettered(ax, at, letter: str, sub: str = "", **style):
    """A letter of the scheme (O, A, B, α, β) at ``at`` (mm) with its subscript (a bank's letter:
    A with L for the left bank's piston pin) set smaller at the letter's lower right; the
    artists drawn."""
    text = ax.text(*at, letter, fontsize=9, color="0.1", zorder=7, **style)
    name = f"mark-{letter}_{sub}" if sub else f"mark-{letter}"  # an SVG id: one per mark
    text.set_gid(name)
    if not sub:
        return [text]
    return [
        text,
        ax.annotate(
            sub,
            xy=(1.0, 0.1),
            xycoords=text,
            xytext=(0.4, 0.0),
            textcoords="offset points",
            ha="left",
            va="center",
            fontsize=6.5,
            color="0.1",
            zorder=7,
            fontstyle=style.get("fontstyle", "normal"),
            gid=f"{name}-index",
        ),
    ]


def _rotation_arrow(ax, centre, radius, text: str, extent: float, middle_deg: float | None = None):
    """A curved arrow clockwise (the crank's sense of rotation) around ``centre``, named ``text``
    (ω): by default on the upper left, clear of the counterweight below the shaft of a crank at
    45 deg; else spanning 60 deg about the direction ``middle_deg`` (deg from +x). Returns the
    arrow and its text."""
    from matplotlib.patches import (
        FancyArrowPatch,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
    )

    c = np.asarray(centre, dtype=float)
    middle_deg = 135.0 if middle_deg is None else middle_deg
    start, end = (
        c + radius * np.array([np.cos(np.radians(t)), np.sin(np.radians(t))])
        for t in (middle_deg + 30.0, middle_deg - 30.0)
    )
    at, alignment = _rotation_label_place(c, radius, extent, middle_deg)
    arrow = ax.add_patch(
        FancyArrowPatch(
            start,
            end,
            connectionstyle="arc3,rad=-0.35",
            arrowstyle="-|>",
            mutation_scale=7,
            color="0.2",
            lw=0.6,
            zorder=6,
        )
    )
    (label,) = _lettered(ax, at, text, fontstyle="italic", **alignment)
    return arrow, label


def _rotation_label_place(centre, radius: float, extent: float, middle_deg: float):
    """(place in mm, alignment) of the letter ω of :func:`_rotation_arrow`: just outside the
    arrow's middle, growing away from the shaft."""
    middle = np.array([np.cos(np.radians(middle_deg + 5.0)), np.sin(np.radians(middle_deg + 5.0))])
    return np.asarray(centre, float) + (radius + extent * 0.03) * middle, outward_alignment(middle)


def angle_mark_parts(geometry):
    """(liner, crank, rod) that :func:`draw_angle_marks` marks: the first cylinder's liner, the
    crank (a link named ``crank`` or ``crank_1`` from ``crank_centre``) and the rod from its pin to
    that liner's piston pin; None when the mechanism has no such crank and rod, when the first
    guide is no cylinder liner, or when the
    drawing shows more than one cylinder axis (a V's or a radial's marks would cross the other
    banks' liners and rods)."""
    if (
        len(geometry.guides) != 1
        or geometry.guides[0].moving is not None
        or geometry.guides[0].bore_m <= 0
    ):
        return None
    guide = geometry.guides[0]
    crank = next(
        (l for l in geometry.links if l[0] in ("crank", "crank_1") and l[1] == "crank_centre"), None
    )
    rod = (
        None
        if crank is None
        else next((l for l in geometry.links if l[1] == crank[2] and l[2] == guide.joint), None)
    )
    # all or nothing: the section's text names every mark (a planetary gear's carrier is no crank)
    return None if crank is None or rod is None else (guide, crank, rod)


def bank_mark_parts(geometry):
    """(crank, [(liner, rod), ...]) of an engine whose front view shows two or more cylinder axes
    (a V, a boxer, a W, an X: each bank's first cylinder), the rods of all of them on the one
    crank pin of a crank ``crank`` or ``crank_1`` from ``crank_centre``, in the order of the
    guides (cylinder 1's bank first); None otherwise (one axis: :func:`angle_mark_parts`; a master
    rod's slaves, which have no rod on the crank pin: :func:`radial_mark_parts`)."""
    crank = _marked_crank(geometry, 2)
    if crank is None:
        return None
    # each bank's rod: on the one crank pin, or (a boxer's) on its cylinder's own crank pin
    pins = {l[2] for l in geometry.links if l[0].startswith("crank") and l[1] == "crank_centre"}
    rods = [
        next((l for l in geometry.links if l[1] in pins and l[2] == g.joint), None)
        for g in geometry.guides
    ]
    if any(rod is None for rod in rods) or rods[0][1] != crank[2]:
        return None
    return crank, list(zip(geometry.guides, rods, strict=True))


def radial_mark_parts(geometry):
    """(crank, [(liner, rod), ...]) of an engine of three or more cylinder axes round one crank
    pin with a master rod (a radial): the master rod on the crank pin, each slave rod (``rod_*``)
    on its knuckle pin; None otherwise (:func:`bank_mark_parts`)."""
    crank = _marked_crank(geometry, 3)
    if crank is None or not master_rod_joints(geometry) or bank_mark_parts(geometry) is not None:
        return None
    rods = [
        next((l for l in geometry.links if l[0].startswith("rod") and l[2] == g.joint), None)
        for g in geometry.guides
    ]
    if any(rod is None for rod in rods):
        return None
    return crank, list(zip(geometry.guides, rods, strict=True))


def _marked_crank(geometry, least_axes: int):
    """The crank (``crank`` or ``crank_1`` from ``crank_centre``) of an engine whose front view
    shows at least ``least_axes`` cylinder liners; None otherwise."""
    guides = geometry.guides
    if len(guides) < least_axes or any(g.moving is not None or g.bore_m <= 0 for g in guides):
        return None
    return next(
        (l for l in geometry.links if l[0] in ("crank", "crank_1") and l[1] == "crank_centre"), None
    )


def own_crank_pins(pairs) -> bool:
    """Whether the banks' rods of :func:`bank_mark_parts` sit on crank pins of their own (a
    boxer's), not on one pin shared by all."""
    return len({rod[1] for _, rod in pairs}) > 1


def bank_letter(label: str) -> str:
    """The index a bank's marks carry: a cylinder label's bank letter ("1L" → "L", "1Л" → "Л"),
    the label itself when it has none."""
    letter = str(label).lstrip("0123456789")
    return letter or str(label)


def _zero_line(ax, geometry, guide, i, centre, zero, radius, extent) -> None:
    """The line the crank angle is measured from: the crank at TDC, through the crank centre; up
    to the liner's own axis when it is that axis (a central cylinder), so that it runs unbroken."""
    o, d, n = _guide_frame(geometry, guide, i)
    bottom = float(np.dot(o - centre, d)) + liner_ends_mm(guide)[0] - 0.04 * extent
    collinear = (
        abs(float(np.dot(o - centre, n))) < 1e-9 * extent and float(np.dot(zero, d)) > 1 - 1e-12
    )
    top = max(radius * 1.35, bottom) if collinear else radius * 1.35
    ax.plot(
        *np.c_[centre - zero * radius * 0.5, centre + zero * top],
        color="0.45",
        lw=0.5,
        ls="-.",
        zorder=1,
    )


def _arc_radius_clear_of_dimensions(ax, centre, start, end, radius: float, extent: float):
    """An angle arc's radius (mm) about ``centre`` from direction ``start`` to ``end``: ``radius``,
    or less (down to 0.6 of it) where a dimension's extension or dimension line drawn before
    passes through the arc's sector (a V's L, from the crank pin out past the first bank's
    axis): the arc then stays inside that line, clear of it by 1.2 % of the extent."""
    a, b = _direction_deg(start), _direction_deg(end)
    if (b - a) % 360.0 > 180.0:
        a, b = b, a
    span = (b - a) % 360.0
    nearest = np.inf
    for line in ax.lines:
        if not str(line.get_gid() or "").startswith("dimension-"):
            continue
        points = np.asarray(line.get_xydata(), float)
        for p, q in zip(points[:-1], points[1:], strict=True):
            samples = p + np.outer(np.linspace(0.0, 1.0, 60), q - p) - np.asarray(centre, float)
            angles = (np.degrees(np.arctan2(samples[:, 1], samples[:, 0])) - a) % 360.0
            inside = angles <= span
            if inside.any():
                nearest = min(nearest, float(np.hypot(*samples[inside].T).min()))
    margin = extent * 0.012
    if nearest - margin >= radius or nearest < radius * 0.6 + margin:
        return radius
    return nearest - margin


def _bank_marks(
    ax, geometry, i: int, marks: dict[str, str], banks, tdc_frame: int, rod_angles: bool = True
) -> None:
    """The marks of :func:`draw_angle_marks` on an engine of two or more banks: O, B, each bank's
    piston pin A and (``rod_angles``) rod angle β with the bank's letter as index, the crank angle
    α from cylinder 1's TDC (its axis; no arc where the crank stands on that axis), ω; each
    letter, and the arrow ω, where it stands clearest of everything drawn before it
    (:class:`_Clearance`): round a V's shaft the crank, the rods, the dimensions R and L and the
    counterweight leave little room."""
    crank, pairs = banks
    extent = _extent_mm(geometry)
    j = geometry.joints
    centre, pin = j[crank[1]][i] * MM, j[crank[2]][i] * MM
    radius = float(np.linalg.norm(pin - centre))
    if radius <= 0:
        return
    at_tdc = j[crank[2]][tdc_frame] * MM - j[crank[1]][tdc_frame] * MM
    zero = at_tdc / max(float(np.linalg.norm(at_tdc)), 1e-12)
    along = (pin - centre) / radius
    _zero_line(ax, geometry, pairs[0][0], i, centre, zero, radius, extent)
    for guide, rod in pairs if rod_angles else []:  # the arcs β first: the letters keep clear
        wrist, big_end = j[guide.joint][i] * MM, j[rod[1]][i] * MM
        length = float(np.linalg.norm(big_end - wrist))
        _, d, _ = _guide_frame(geometry, guide, i)
        rod_direction = (big_end - wrist) / length
        sin_beta = _sine_between(-d, rod_direction)
        radius = _rod_angle_radius(geometry, guide, length, extent, sin_beta)
        _angle_arc(ax, wrist, -d, rod_direction, radius, "", extent)
    alpha_arc = float(np.dot(zero, along)) < np.cos(np.radians(1.0))  # none on the zero line
    # among three or more rods round the crank pin α's letter goes where it is clearest (below);
    # two banks' (a V's, a boxer's) stands outside the arc's middle
    placed_alpha = alpha_arc and len(pairs) > 2
    alpha_radius = _arc_radius_clear_of_dimensions(ax, centre, zero, along, radius * 0.55, extent)
    if alpha_arc:
        _angle_arc(
            ax, centre, zero, along, alpha_radius, "" if placed_alpha else marks["alpha"], extent
        )
    clearance = _Clearance(ax, geometry, i, extent)
    _clearest_rotation_arrow(ax, clearance, centre, radius, marks["omega"], extent)
    if placed_alpha:
        clearance.place(
            _beside_arc(centre, zero, along, alpha_radius, extent),
            marks["alpha"],
            fontstyle="italic",
        )
    # round a radial's hub, where nine rods leave the master rod, O may stand a little farther
    reach = extent * np.array([0.035, 0.05] if rod_angles else [0.035, 0.05, 0.065, 0.08])
    clearance.place(_ring(centre, reach), "O", off_bodies=True)
    # a boxer's banks: a crank pin per cylinder, each B with its cylinder's index
    own_pins = rod_angles and own_crank_pins(pairs)
    if not own_pins:
        clearance.place(_ring(pin, extent * np.array([0.035, 0.05])), PIN_MARK)
    for guide, rod in pairs:
        _, d, n = _guide_frame(geometry, guide, i)
        wrist, big_end = j[guide.joint][i] * MM, j[rod[1]][i] * MM
        sub = bank_letter(guide.label)
        if own_pins:  # two letters with indices beside the shaft's O: room a little farther out
            clearance.place(_ring(big_end, extent * np.array([0.035, 0.05, 0.065])), PIN_MARK, sub)
        clearance.place(_ring(wrist, extent * np.array([0.035, 0.05])), "A", sub)
        if rod_angles:
            places = _rod_angle_places(geometry, guide, wrist, big_end, d, n, extent)
            clearance.place(
                places, marks["beta"], sub, off_bodies=True, enough=0.0, fontstyle="italic"
            )


def _clearest_rotation_arrow(ax, clearance, centre, radius: float, text: str, extent: float):
    """The arrow ω round the shaft where it and its letter stand clearest of what is drawn, as
    large as a single cylinder's on its page (a V's crank is short beside its banks); then
    itself an obstacle to the letters placed after it."""
    candidates = [
        (float(middle), max(radius * 0.4, extent * share))
        for share in (0.09, 0.07, 0.11)
        for middle in np.arange(0.0, 360.0, 15.0)
    ]
    best, best_clear = candidates[0], -np.inf
    # the letter's box measured once for each alignment it takes, at its first place: at every
    # other place it is the same box moved; the arrow itself is judged by its arc's points
    outlines: dict[tuple[str, str], np.ndarray] = {}
    for middle, arrow_radius in candidates:
        at, alignment = _rotation_label_place(centre, arrow_radius, extent, middle)
        key = (alignment["ha"], alignment["va"])
        if key not in outlines:
            (label,) = _lettered(ax, at, text, fontstyle="italic", **alignment)
            outlines[key] = clearance.text_outline(label) - at
            label.remove()
        arc = _arc_points(centre, arrow_radius, middle - 30.0, middle + 30.0)
        clear = min(clearance.of_points(arc), clearance.of_outline(outlines[key] + at))
        if clear > best_clear + 1e-9:
            best, best_clear = (middle, arrow_radius), clear
    _rotation_arrow(ax, centre, best[1], text, extent, best[0])
    clearance.add_points(_arc_points(centre, best[1], best[0] - 30.0, best[0] + 30.0))
    clearance.add_last_text()


def _sine_between(a, b) -> float:
    """|sin| of the angle between two unit vectors of the sheet."""
    return abs(float(a[0] * b[1] - a[1] * b[0]))


def _rod_angle_radius(geometry, guide, length: float, extent: float, sin_beta: float) -> float:
    """The radius (mm) of a rod's angle β arc round its piston pin: 0.3 of the rod, beyond the
    piston's skirt where a short rod's arc would lie under the piston (a shaded body), and far
    enough out that β's letter fits between the rod and the axis (a letter is about 0.035 of the
    drawing's extent high); at most 0.7 of the rod."""
    clear = piston_skirt_mm(guide, geometry) + extent * 0.02
    fits = extent * 0.035 / max(sin_beta, 1e-3)
    return float(min(max(0.3 * length, clear, fits), 0.7 * length))


def _rod_angle_places(geometry, guide, wrist, big_end, d, n, extent: float) -> list:
    """Places for β's letter (mm): inside the angle, on its bisector just beyond the arc, then
    beside the arc's end on the cylinder's axis on either side (never on the piston)."""
    length = float(np.linalg.norm(big_end - wrist))
    sin_beta = _sine_between(-d, (big_end - wrist) / length)
    radius = _rod_angle_radius(geometry, guide, length, extent, sin_beta)
    bisector = (big_end - wrist) / length - d
    bisector /= max(float(np.linalg.norm(bisector)), 1e-12)
    inside = [wrist + bisector * (radius + extent * k) for k in (0.02, 0.035, 0.05)]
    end = wrist - d * radius
    return inside + [end + n * side * extent * k for side in (-1, 1) for k in (0.025, 0.04)]


def _beside_arc(centre, start, end, radius: float, extent: float) -> list:
    """Places for an arc's letter (mm): outside its middle as :func:`_angle_arc` sets it first,
    then outside and inside it at a quarter and three quarters of the way."""
    a = _direction_deg(start)
    span = (_direction_deg(end) - a) % 360.0
    if span > 180.0:  # the shorter way round, as the arc is drawn
        a, span = a + span, 360.0 - span
    places = []
    for share in (0.5, 0.25, 0.75):
        t = np.radians(a + span * share)
        ray = np.array([np.cos(t), np.sin(t)])
        for reach in (radius + extent * 0.025, radius + extent * 0.04, radius - extent * 0.025):
            if reach > 0:
                places.append(np.asarray(centre, float) + reach * ray)
    return places


def _arc_points(centre, radius: float, start_deg: float, end_deg: float) -> np.ndarray:
    t = np.radians(np.linspace(start_deg, end_deg, 24))
    return np.asarray(centre, float) + radius * np.c_[np.cos(t), np.sin(t)]


def _ring(centre, distances) -> list:
    """Places round ``centre`` (mm) at each of ``distances``, every 30 deg."""
    t = np.radians(np.arange(0.0, 360.0, 30.0))
    return [
        np.asarray(centre, float) + r * np.array([np.cos(a), np.sin(a)])
        for r in distances
        for a in t
    ]


def _text_corners_mm(ax, text, renderer) -> np.ndarray:
    """The corners of a text's box (mm, closed), measured again only when the text, its place,
    its font or the axes' scale change: the placement search asks for every text's box at every
    dimension it tries."""
    key = (
        text,
        text.get_text(),
        tuple(text.get_position()),
        text.get_rotation(),
        text.get_rotation_mode(),
        text.get_ha(),
        text.get_va(),
        text.get_fontsize(),
        ax.figure.dpi,
        tuple(ax.transData.get_affine().get_matrix().ravel()),
    )
    boxes = ax.__dict__.setdefault("_crankdyn_text_boxes", {})
    corners = boxes.get(id(text))
    if corners is not None and corners[0] == key:
        return corners[1]
    box = text.get_window_extent(renderer)
    outline = ax.transData.inverted().transform(
        [[box.x0, box.y0], [box.x1, box.y0], [box.x1, box.y1], [box.x0, box.y1], [box.x0, box.y0]]
    )
    boxes[id(text)] = (key, outline)
    return outline


class _Clearance:
    """How far a new mark would stand from everything drawn on the scheme's axes (mm): points
    along its lines, bars, hatching, outlines, arcs, dimension arrows and texts' boxes."""

    def __init__(self, ax, geometry, i: int, extent: float):
        self.ax, self.extent = ax, extent
        self.renderer = ax.figure.canvas.get_renderer()
        self.step = extent * 0.004
        polylines = [np.column_stack(line.get_data()).astype(float) for line in ax.lines]
        # a collection's segments (the walls' hatching) once: they stay as drawn
        known = ax.__dict__.setdefault("_crankdyn_segments", {})
        for collection in ax.collections:
            segments = known.get(id(collection))
            if segments is None or segments[0] is not collection:
                segments = known[id(collection)] = (
                    collection,
                    [
                        np.asarray(segment, float)
                        for segment in getattr(collection, "get_segments", lambda: [])()
                    ],
                )
            polylines += segments[1]
        from matplotlib.patches import Arc  # lazy: heavy optional import

        to_data = ax.transData.inverted()
        for patch in ax.patches:
            if isinstance(patch, Arc):  # the arc drawn, not its whole ellipse
                polylines.append(
                    _arc_points(patch.center, patch.width / 2, patch.theta1, patch.theta2)
                )
            else:
                polylines.append(to_data.transform(patch.get_verts()))
        points = [self._along_all(polylines)]
        for text in ax.texts:
            points.append(self._text_points(text))
        points += [np.array([p[i] * MM]) for p in geometry.joints.values()]
        self.points = np.concatenate([p.reshape(-1, 2) for p in points if len(p)])
        # shaded links (a master rod's body, a counterweight): a letter inside one stands clear
        # of its outline but reads as that link's; the shaft's axis O is no point of theirs
        from matplotlib.colors import to_rgba  # lazy: heavy optional import
        from matplotlib.patches import Polygon  # lazy: heavy optional import
        from matplotlib.path import Path  # lazy: heavy optional import

        self.bodies = [
            Path(to_data.transform(patch.get_verts()))
            for patch in ax.patches
            if isinstance(patch, Polygon)
            and patch.get_fill()
            and to_rgba(patch.get_facecolor())[:3] != (1.0, 1.0, 1.0)
            and patch.get_gid() != "piston"  # its pin's letter A belongs to it
        ]
        self._tree: Any = (
            None  # the points' k-d tree, built once for all queries until points change
        )

    def _along(self, polyline) -> np.ndarray:
        """Points every ``step`` along a polyline (mm)."""
        if len(polyline) < 2:
            return polyline.reshape(-1, 2)
        return _sampled_many(polyline[:-1], polyline[1:], self.step)[0]

    def _along_all(self, polylines) -> np.ndarray:
        """:meth:`_along` of every polyline, at once."""
        polylines = [p.reshape(-1, 2) for p in polylines]
        single = [p for p in polylines if len(p) == 1]
        starts = [p[:-1] for p in polylines if len(p) >= 2]
        ends = [p[1:] for p in polylines if len(p) >= 2]
        if starts:
            single.append(_sampled_many(np.concatenate(starts), np.concatenate(ends), self.step)[0])
        return np.concatenate(single) if single else np.empty((0, 2))

    def text_outline(self, text) -> np.ndarray:
        """Points along the outline of a text's box (mm), as the clearances measure it."""
        return self._text_points(text)

    def _text_points(self, text) -> np.ndarray:
        """The outline of a text's box (a dimension's arrow: its line), mm."""
        if not text.get_text():
            if hasattr(text, "xyann"):
                return self._along(np.array([text.xyann, text.xy], dtype=float))
            return np.empty((0, 2))
        return self._along(_text_corners_mm(self.ax, text, self.renderer))

    def _tree_built(self) -> None:
        """The drawn points' k-d tree, built once until points are added."""
        if self._tree is None:
            from scipy.spatial import cKDTree  # lazy: heavy optional import

            self._tree = cKDTree(self.points)

    def of_points(self, points) -> float:
        """The least distance (mm) from ``points`` to anything drawn."""
        self._tree_built()
        distances, _ = self._tree.query(np.asarray(points, float))
        return float(np.min(distances))

    def add_points(self, points) -> None:
        self.points = np.concatenate([self.points, np.asarray(points, float).reshape(-1, 2)])
        self._tree = None

    def add_last_text(self) -> None:
        self.add_points(self._text_points(self.ax.texts[-1]))

    def of_box(self, artist, off_bodies: bool = False) -> float:
        """The distance (mm) from a text's box to the nearest thing drawn; minus the number of
        points of it inside the box when something crosses it (``off_bodies``: or when the box
        lies on a shaded link, counted worse than any crossing)."""
        return self.of_outline(self._text_points(artist), off_bodies)

    def of_outline(self, outline, off_bodies: bool = False) -> float:
        """:meth:`of_box` of a box given by its outline's points (mm)."""
        low, high = outline.min(axis=0), outline.max(axis=0)
        bodies = self.bodies if off_bodies else []
        covered = sum(int(body.contains_points(outline).sum()) for body in bodies)
        if covered:
            return -float(len(self.points) + covered)
        # the points inside the box, among those within its half-diagonal of its centre
        self._tree_built()
        near = self._tree.query_ball_point((low + high) / 2, float(np.linalg.norm(high - low)) / 2)
        points = self.points[near]
        inside = np.count_nonzero(np.all((points > low) & (points < high), axis=1))
        return -float(inside) if inside else self.of_points(outline)

    def place(
        self,
        candidates,
        letter: str,
        sub: str = "",
        off_bodies: bool = False,
        enough: float | None = None,
        **style,
    ) -> None:
        """The letter (with its subscript) centred at the candidate place whose box stands
        clearest of everything drawn (``off_bodies``: and off the shaded links; ``enough``: at
        the first place whose box stands that clear, mm, the candidates being in the order of
        preference); then itself an obstacle to the next."""
        best, best_clear = candidates[0], -np.inf
        # the letter's boxes once, at the first place: at every other they are the same moved
        first = np.asarray(candidates[0], float)
        artists = _lettered(self.ax, first, letter, sub, ha="center", va="center", **style)
        outlines = [self._text_points(a) - first for a in artists]
        for artist in artists:
            artist.remove()
        for at in candidates:
            at_mm = np.asarray(at, float)
            clear = min(self.of_outline(outline + at_mm, off_bodies) for outline in outlines)
            if clear > best_clear + 1e-9:
                best, best_clear = at, clear
            if enough is not None and clear >= enough:
                break
        for artist in _lettered(self.ax, best, letter, sub, ha="center", va="center", **style):
            self.add_points(self._text_points(artist))


def draw_angle_marks(
    ax,
    geometry,
    i: int,
    marks: dict[str, str],
    labels: dict[str, str] | None = None,
    tdc_frame: int = 0,
) -> None:
    """What a textbook's kinematic scheme marks, at frame ``i``, where the geometry has what it
    names (:func:`angle_mark_parts`): the joints O (shaft axis), B (crank pin), A (piston pin); the
    crank angle α from the crank's direction at TDC (frame ``tdc_frame``: the cylinder's axis, or
    beside it for an offset cylinder, whose angles count from TDC too); the rod's angle β from the
    axis; the sense of rotation ω; the piston pin's dead centres (ВМТ, НМТ) with the stroke
    between them (``labels["S"]``); the rod's length (``labels["L"]``) by a leader, not by a
    dimension line, which would cross the liner and the piston of a rod at an angle."""
    parts = angle_mark_parts(geometry) if marks else None
    if parts is None:
        banks = bank_mark_parts(geometry) if marks else None
        if banks is not None:
            _bank_marks(ax, geometry, i, marks, banks, tdc_frame)
        radial = radial_mark_parts(geometry) if marks and banks is None else None
        if radial is not None:  # a slave rod's angle is not the β of the crank-slider
            _bank_marks(ax, geometry, i, marks, radial, tdc_frame, rod_angles=False)
        return
    labels = labels or {}
    guide, crank, _ = parts
    extent = _extent_mm(geometry)
    j = geometry.joints
    o, d, n = _guide_frame(geometry, guide, i)
    wrist = j[guide.joint][i] * MM
    _lettered(ax, wrist - n * extent * 0.03, "A", ha="right", va="center")
    centre, pin = j[crank[1]][i] * MM, j[crank[2]][i] * MM
    radius = float(np.linalg.norm(pin - centre))
    at_tdc = j[crank[2]][tdc_frame] * MM - j[crank[1]][tdc_frame] * MM
    zero = at_tdc / max(float(np.linalg.norm(at_tdc)), 1e-12)
    _zero_line(ax, geometry, guide, i, centre, zero, radius, extent)
    # right of the shaft's axis: the counterweight lies opposite the crank, below on the left
    _lettered(ax, centre + np.array([1.0, -0.15]) * extent * 0.035, "O", ha="left", va="center")
    if radius > 0:
        at = pin + (pin - centre) / radius * extent * 0.03
        _lettered(ax, at, PIN_MARK, ha="left", va="center")
        _angle_arc(ax, centre, zero, (pin - centre) / radius, radius * 0.55, marks["alpha"], extent)
        _rotation_arrow(ax, centre, radius * 0.4, marks["omega"], extent)
    length = float(np.linalg.norm(pin - wrist))
    _angle_arc(ax, wrist, -d, (pin - wrist) / length, length * 0.3, marks["beta"], extent)
    if "L" in labels:
        _rod_length_aside(ax, pin, wrist, o, d, n, guide, labels["L"], extent)
    _stroke(ax, o, d, n, guide, marks, labels.get("S", ""), extent)


def _rod_length_aside(ax, pin, wrist, o, d, n, guide, text: str, extent: float) -> None:
    """The rod's length written beside the liner, on the side the rod leans away from, joined by
    a leader to the rod below the liner (at most a third of the way up from the crank pin), so
    that the leader crosses neither the liner's wall nor the piston."""
    below = liner_ends_mm(guide)[0] - 0.09 * extent  # under the liner and the offset e
    rise = float(np.dot(wrist - pin, d))
    share = (
        1.0 / 3.0
        if rise <= 0
        else min(1.0 / 3.0, max(0.0, (below - float(np.dot(pin - o, d))) / rise))
    )
    anchor = pin + (wrist - pin) * share
    side = -1.0 if float(np.dot(pin - wrist, n)) > 0 else 1.0  # away from the crank pin
    half = guide.bore_m * MM / 2
    along = float(np.dot(anchor - o, d))
    at = o + d * along + n * side * (half + extent * 0.06)
    ax.plot(*np.c_[anchor, at], color="0.35", lw=0.5, ls="-")
    ax.text(
        *(at + n * side * extent * 0.01),
        text,
        va="center",
        ha="left" if float((n * side)[0]) > 0 else "right",
        **DIMENSION_TEXT,
    )


def _stroke(ax, o, d, n, guide, marks, text: str, extent: float) -> None:
    """The piston pin's dead centres beside the liner (a short line at each, named ВМТ and НМТ),
    and the stroke S between them as a dimension line with its text."""
    half = guide.bore_m * MM / 2
    ends = []
    dead_centres = ((guide.travel_m[1], marks["tdc"]), (guide.travel_m[0], marks["bdc"]))
    for k, (distance, name) in enumerate(dead_centres, start=1):
        at = o + d * distance * MM
        start, end = at + n * (half + extent * 0.035), at + n * (half + extent * 0.11)
        # the dead centre's line is the stroke's extension line: past the dimension line
        ax.plot(*np.c_[start, end], color="0.2", lw=0.6, ls="-", gid=f"dimension-S-extension-{k}")
        ax.text(*(end + n * extent * 0.01), name, fontsize=8, color="0.15", **outward_alignment(n))
        ends.append(at + n * (half + extent * 0.09))
    if text:
        _dimension_arrow(ax, ends[0], ends[1], "dimension-S-line")
        _dimension_text(ax, ends[1], ends[0], text, extent, "dimension-S-text")


def _crank_radius_below(ax, geometry, i: int, crank, text: str, extent: float) -> None:
    """R of an engine with several cylinders: the rods of every bank meet at the crank pin, so the
    text goes where nothing drawn is, joined to the crank's dimension line by a leader."""
    j = geometry.joints
    p, q = j[crank[1]][i] * MM, j[crank[2]][i] * MM
    bodies = master_rod_joints(geometry)
    if bodies:  # the line beside the master rod's body, the text by a short leader
        # the body reaches its knuckle pins round the crank pin: the line clear of it
        hub = max(float(np.linalg.norm(j[k][i] * MM - q)) for body in bodies for k in body)
        offset = hub + extent * 0.03
        _dimension(ax, p, q, "", -offset, extent, "R")
        d = (q - p) / max(np.linalg.norm(q - p), 1e-12)
        mid = (p + q) / 2 + np.array([d[1], -d[0]]) * offset
        _leader_text(ax, geometry, i, mid, text, extent, "dimension-R-text")
        return
    # a bank's rods meet at the pin: the line clear of the crank by the room of its arrows, the
    # text where nothing drawn is, by a leader to the line's middle (ГОСТ 2.307)
    offset = -extent * 0.065
    _dimension(ax, p, q, "", offset, extent, "R")
    d = (q - p) / max(np.linalg.norm(q - p), 1e-12)
    mid = (p + q) / 2 + np.array([d[1], -d[0]]) * -offset
    _leader_text(ax, geometry, i, mid, text, extent, "dimension-R-text")


def _leader_text(
    ax,
    geometry,
    i: int,
    at,
    text: str,
    extent: float,
    gid: str,
    shapes=None,
    strict=False,
    clearance=None,
) -> bool:
    """A dimension's ``text`` clear of everything drawn and off the shaded links, near ``at`` (mm,
    the middle of its dimension line), joined to it by a leader to the nearest middle of the
    box's sides (ГОСТ 2.307): of the places clear enough, the one whose leader is the shortest
    and crosses the fewest lines; given the links' ``shapes`` (:func:`link_shapes_mm`), only
    where neither the box nor the leader reaches a link, if there is such a place
    (``clearance``: a :class:`_Clearance` of what is drawn now, if already built)."""
    clearance = clearance or _Clearance(ax, geometry, i, extent)
    at = np.asarray(at, float)
    # the box's outline about its centre: the same text at every place tried
    label = ax.text(*at, text, ha="center", va="center", fontsize=8, bbox=LABEL_BOX)
    box = clearance._text_points(label) - at
    label.remove()
    best = _leader_place(clearance, at, box, extent, shapes) if shapes is not None else None
    if best is None and strict:
        return False
    if best is None:
        best = _leader_place(clearance, at, box, extent, None)
    label = ax.text(*best, text, ha="center", va="center", gid=gid, **DIMENSION_TEXT)
    end = _leader_end(clearance._text_points(label), at)
    ax.plot(*np.c_[at, end], color="0.35", lw=0.5, ls="-", gid=gid + "-leader")
    return True


def _leader_place(clearance, at, box, extent: float, shapes):
    """:func:`_leader_text`'s place of a text's box (its outline about its centre, mm); None
    where ``shapes`` are given and no place keeps the box and the leader off them. Found once
    for the same drawing (:meth:`_Links.remembered`): its dimensions are placed on the same
    lines and texts both times a scheme is drawn at a scale."""
    if shapes is None:
        return _leader_place_searched(clearance, at, box, extent, shapes)
    digest = hashlib.blake2b(digest_size=16)
    for part in (np.asarray(at, float), box, clearance.points):
        digest.update(np.ascontiguousarray(part).tobytes())
    for body in clearance.bodies:
        digest.update(np.ascontiguousarray(body.vertices).tobytes())
    marks = _marks_tree(clearance.ax, extent * 0.003)
    if marks is not None:
        digest.update(np.ascontiguousarray(marks.data).tobytes())
    place = shapes.remembered(
        ("leader", digest.digest(), extent),
        lambda: _leader_place_searched(clearance, at, box, extent, shapes),
    )
    return None if place is None else place.copy()


def _leader_place_searched(clearance, at, box, extent: float, shapes):
    """:func:`_leader_place`, searched."""
    best, best_score, enough = None, None, extent * 0.012
    # off the links: a finer search, the room between them being narrow
    reaches = (0.04, 0.02, 7.5) if shapes is not None else (0.07, 0.03, 15.0)
    angles = np.radians(np.arange(0.0, 360.0, reaches[2]))
    rays = np.column_stack([np.cos(angles), np.sin(angles)])
    rings = np.arange(reaches[0], 0.62, reaches[1])
    # every place tried, ring by ring, with its leader's end, tested against the links a few
    # rings at once: the search mostly ends near the dimension line
    places = at + extent * rings[:, None, None] * rays[None, :, :]
    ends = _leader_ends(box, places.reshape(-1, 2), at).reshape(places.shape)
    usable = np.ones(places.shape[:2], bool)
    tested = 0 if shapes is not None else len(rings)
    for k, reach in enumerate(rings):
        if k >= tested:
            tested = len(rings) if tested else min(4, len(rings))
            usable[k:tested] = _leader_places_off_links(
                clearance.ax,
                at,
                box,
                places[k:tested].reshape(-1, 2),
                ends[k:tested].reshape(-1, 2),
                shapes,
                extent,
            ).reshape(tested - k, -1)
        for m in np.flatnonzero(usable[k]):
            place, end = places[k, m], ends[k, m]
            clear = min(clearance.of_outline(box + place, off_bodies=True), enough)
            if best_score is not None and clear < best_score[0]:
                continue  # less clear than the best: its leader cannot make up for it
            # a step farther weighs as much as a step of the leader on a line
            crossings = _leader_crossings(clearance, at, end)
            score = (clear, -(crossings + reach / 0.03))
            if best_score is None or score > best_score:
                best, best_score, best_crossings = place, score, crossings
        # clear enough with a leader crossing nothing: no place farther out scores higher
        if best_score is not None and best_score[0] >= enough and best_crossings == 0:
            break
    return best


def _leader_places_off_links(ax, at, box, places, ends, shapes, extent: float) -> np.ndarray:
    """Which ``places`` (mm) of a text's box (its closed outline about its centre, mm) keep the
    box, its outline and the leader from ``at`` to its ``ends`` off the links and the box off
    the marks drawn (:func:`_off_marks`): the cheap tests first, each on all the places left."""
    margin, step = extent * 0.005, extent * 0.003
    ring = _ring_outline(np.vstack([box, box[:1]]), step)
    usable = np.ones(len(places), bool)

    def keep(test) -> None:
        kept = np.flatnonzero(usable)
        if len(kept):
            usable[kept] = test(kept)

    def outline_off_links(every: int):
        def test(kept):
            outlines = (ring[None, ::every, :] + places[kept][:, None, :]).reshape(-1, 2)
            owner = np.repeat(np.arange(len(kept)), len(ring[::every]))
            return ~shapes.touched(outlines, owner, len(kept), margin, 1)

        return test

    def leader_off_links(every: int):
        def test(kept):
            leaders, owner = _sampled_many(np.broadcast_to(at, (len(kept), 2)), ends[kept], step)
            few = _every(owner, every)
            return ~shapes.touched(leaders[few], owner[few], len(kept), margin, 1)

        return test

    marks = _marks_tree(ax, step)

    def outline_off_marks(every: int):
        def test(kept):
            outlines = (ring[None, ::every, :] + places[kept][:, None, :]).reshape(-1, 2)
            distances, _ = marks.query(outlines, distance_upper_bound=margin)
            return distances.reshape(len(kept), -1).min(axis=1) >= margin

        return test

    # a link through the circle inside the box (about its centre) passes through the box
    inner = min(float(-box.min(axis=0).max()), float(box.max(axis=0).min()))
    if inner > 0:
        keep(lambda kept: shapes.tree.query(places[kept], distance_upper_bound=inner)[0] >= inner)
    # a few points of each outline and leader first: most places are known by them
    keep(outline_off_links(32))
    keep(outline_off_links(8))
    keep(leader_off_links(8))
    keep(lambda kept: ~shapes.through_many(np.vstack([box, box[:1]]), places[kept]))
    if marks is not None:
        keep(lambda kept: ~_marks_inside(marks, box, places[kept]))
        keep(outline_off_marks(8))
        keep(outline_off_marks(1))
    keep(outline_off_links(1))
    keep(leader_off_links(1))
    return usable


def _near_pairs(tree, centres, radius: float):
    """(place, point) index pairs of the k-d tree's points within ``radius`` (mm) of each of
    ``centres``."""
    near = tree.query_ball_point(centres, radius)
    counts = np.array([len(n) for n in near], int)
    if not counts.sum():
        return np.zeros(0, int), np.zeros(0, int)
    owner = np.repeat(np.arange(len(centres)), counts)
    return owner, np.concatenate([np.asarray(n, int) for n in near if len(n)])


def _marks_inside(tree, box, places) -> np.ndarray:
    """Which ``places`` (mm) of a text's box (its outline about its centre, mm) hold a point of
    the marks drawn (:func:`_marks_tree`): :func:`_off_marks`'s second test at many places."""
    low, high = box.min(axis=0), box.max(axis=0)
    owner, index = _near_pairs(tree, (low + high) / 2 + places, float(np.linalg.norm(high - low)))
    points = tree.data[index]
    inside = np.all((points > low + places[owner]) & (points < high + places[owner]), axis=1)
    return np.bincount(owner[inside], minlength=len(places)) > 0


def _leader_ends(box, places, at) -> np.ndarray:
    """:func:`_leader_end` of a text's box (its outline about its centre, mm) at each of
    ``places``."""
    low, high = box.min(axis=0) + places, box.max(axis=0) + places
    middle = (low + high) / 2
    sides = np.stack(
        [
            np.column_stack([low[:, 0], middle[:, 1]]),
            np.column_stack([high[:, 0], middle[:, 1]]),
            np.column_stack([middle[:, 0], low[:, 1]]),
            np.column_stack([middle[:, 0], high[:, 1]]),
        ],
        axis=1,
    )
    nearest = np.argmin(np.linalg.norm(sides - at, axis=2), axis=1)
    return sides[np.arange(len(places)), nearest]


def _leader_end(box, at):
    """The middle of the side of a text's box (its outline, mm) nearest ``at``."""
    return _leader_ends(box, np.zeros((1, 2)), np.asarray(at, float))[0]


def _leader_crossings(clearance, start, end) -> int:
    """How many steps of a leader from ``start`` to ``end`` (mm) run on something drawn (past
    its first steps, on the dimension line it starts from)."""
    length = float(np.linalg.norm(end - start))
    count = max(int(length / clearance.step), 1)
    points = start + (end - start) * np.linspace(0.0, 1.0, count + 1)[:, None]
    points = points[np.linalg.norm(points - start, axis=1) > clearance.extent * 0.02]
    if not len(points):
        return 0
    clearance.of_points(points[:1])  # builds the tree
    distances, _ = clearance._tree.query(points)
    return int(np.count_nonzero(distances < clearance.extent * 0.004))


def _slave_dimensions(ax, geometry, i: int, labels: dict[str, str], extent: float) -> None:
    """The knuckle-pin radius r (crank pin to a slave's pin) and the slave rod's length (its pin
    to its piston pin), those of ``labels``: a radial's r by :func:`_radial_dimension` on any of
    its slave pins (a radial's scheme gives no slave rod length, :func:`_radial_dimensions`);
    another engine's on the first slave, each a dimension line beside the link with its text by
    a short leader (:func:`_leader_text`)."""
    j = geometry.joints
    bodies = master_rod_joints(geometry)
    slave = next(
        (l for l in geometry.links if l[0].startswith("rod_") and l[1].startswith("slave_pin")),
        None,
    )
    if not bodies or slave is None:
        return
    centre = next(a for name, a, _ in geometry.links if name.startswith("master_"))
    pin = slave[1]
    for key, (a, b) in (("r", (centre, pin)), ("l_s", (pin, slave[2]))):
        if key not in labels:
            continue
        if is_radial(geometry) and key == "r":  # any knuckle pin: all stand r from U
            pins = [l[1] for l in geometry.links if l[0].startswith("rod_") and "slave" in l[1]]
            links = [(j[centre][i] * MM, j[pin][i] * MM) for pin in pins]
            _radial_dimension(ax, geometry, i, links, labels[key], extent, key)
            continue
        p, q = j[a][i] * MM, j[b][i] * MM
        offset = extent * 0.03
        if key == "r":  # the knuckle pins lie on the master rod's body: the line beside it
            c = j[centre][i] * MM
            offset += max(float(np.linalg.norm(j[k][i] * MM - c)) for body in bodies for k in body)
        _dimension(ax, p, q, "", offset, extent, key)
        d = (q - p) / max(np.linalg.norm(q - p), 1e-12)
        mid = (p + q) / 2 + np.array([-d[1], d[0]]) * offset
        _leader_text(ax, geometry, i, mid, labels[key], extent, f"dimension-{key}-text")


def cylinder_axes(geometry) -> int:
    """How many cylinder axes the scheme draws (a V engine's two, a radial's one per cylinder)."""
    return len(_one_per_axis(geometry.guides))


def is_radial(geometry) -> bool:
    """A radial engine: master rods with slave rods round one crank pin, cylinders on more than
    two axes."""
    return bool(master_rod_joints(geometry)) and len(_one_per_axis(geometry.guides)) > 2


_LINK_SHAPES: dict = {}


def link_shapes_mm(geometry, i: int) -> _Links:
    """:func:`_link_shapes_built`, built once for a geometry's frame: a scheme's placement
    search asks for them at every dimension and place it tries."""
    key = (id(geometry), i)
    cached = _LINK_SHAPES.get(key)
    if cached is None or cached[0] is not geometry:
        if len(_LINK_SHAPES) >= 8:  # a few geometries at a time: the memory stays bounded
            _LINK_SHAPES.clear()
        cached = _LINK_SHAPES[key] = (geometry, _link_shapes_built(geometry, i))
    return cached[1]


def _link_shapes_built(geometry, i: int) -> _Links:
    """What a dimension line, its arrows, a leader and a dimension's text keep off at frame ``i``
    (mm): the segments of the links (:func:`member_segments_mm`) with the outer edge of each
    wall's hatching, and the areas they enclose (a master rod's body, a piston, a wall's band of
    hatching), on which a line lies without crossing an outline."""
    extent = _extent_mm(geometry)
    segments = list(member_segments_mm(geometry, i))
    areas = list(master_rod_bodies(geometry, i))
    depth = HATCH * HATCH_SLANT * extent
    j = geometry.joints
    for guide in _one_per_axis(geometry.guides):
        if guide.bore_m <= 0 or guide.moving is not None:
            continue
        o, d, n = _guide_frame(geometry, guide, i)
        half = guide.bore_m * MM / 2
        bottom, top = liner_ends_mm(guide, geometry)
        for side in (-1.0, 1.0):
            a, b = o + d * bottom + n * side * half, o + d * top + n * side * half
            out = n * side * depth
            segments.append((a + out, b + out))
            areas.append(np.array([a, b, b + out, a + out]))
        areas.append(piston_outline_mm(geometry, guide, i))
    # the joints' circles and the supports under the fixed ones
    r_joint = extent * JOINT_R
    ring = np.column_stack(
        [np.cos(np.linspace(0, 2 * np.pi, 25)), np.sin(np.linspace(0, 2 * np.pi, 25))]
    )
    for name, points in j.items():
        if name == "vane_tip":
            continue
        outline = points[i] * MM + ring * r_joint
        if name in geometry.fixed:
            size = r_joint * 1.6
            outline = (
                points[i] * MM
                + np.array(
                    [[0.0, 0.0], [-1.9, -1.6], [-1.9, -2.4], [1.9, -2.4], [1.9, -1.6], [0.0, 0.0]]
                )
                * size
            )
        segments += list(zip(outline[:-1], outline[1:], strict=True))
        areas.append(outline)
    return _Links(np.array(segments, dtype=float).reshape(-1, 2, 2), areas, extent * 0.003)


def _radial_dimension(ax, geometry, i: int, links, text: str, extent: float, key: str) -> None:
    """A radial's R, L, r or slave rod's length, of one of the equal ``links`` (p, q pairs, mm),
    its links radiating round the crank pin, the nearest that stands off every link: a dimension
    line near its link (within a fifth of the drawing), else the value written along the link,
    else a dimension line farther out, its extension lines crossing the links, else the value on
    a leader's shelf pointing at the link (ГОСТ 2.703). The knuckle pins' radius r stays by the
    master rod's body: where nothing there is clear, its line beside the body, its text by the
    leader crossing the fewest lines."""

    def placed(least: float, most: float, strict: bool) -> bool:
        # the nearest on either side of each link: the text may have room on one side only
        drawn = _marks_tree(ax, extent * 0.003)
        found = sorted(
            (abs(offset), k, offset)
            for k, (p, q) in enumerate(links)
            for offset in _nearest_each_side(
                _clear_offsets(ax, geometry, i, p, q, extent, least, most, drawn)
            )
        )
        return any(
            _dimension_off_links(
                ax, geometry, i, links[k][0], links[k][1], text, extent, key, offset, strict
            )
            for _, k, offset in found
        )

    if placed(extent * 0.03, extent * 0.2, True):
        return
    shapes = link_shapes_mm(geometry, i)
    clearance = _Clearance(ax, geometry, i, extent)
    if _note_along(ax, geometry, i, links, text, extent, key, shapes, clearance, False):
        return
    if key == "r":  # the knuckle pins' radius, by the master rod's body: never far from it
        if not placed(extent * 0.2, extent * 0.35, True):
            # no room off the links: beside the body, the text by the leader crossing fewest
            p, q = (np.asarray(v, float) for v in links[0])
            offset = float(np.linalg.norm(q - p)) + extent * 0.03
            _dimension_off_links(ax, geometry, i, p, q, text, extent, key, offset, False)
        return
    if placed(extent * 0.2, extent * 0.6, True) or placed(extent * 0.03, extent * 0.6, False):
        return
    _shelf_note(ax, geometry, i, links, text, extent, key)


def _nearest_each_side(offsets) -> list:
    """The first offset of each sign from ``offsets`` (nearest first)."""
    chosen: dict[bool, float] = {}
    for offset in offsets:
        chosen.setdefault(offset > 0.0, offset)
        if len(chosen) == 2:
            break
    return list(chosen.values())


def _sampled(a, b, step: float) -> np.ndarray:
    """Points every ``step`` (mm) from ``a`` to ``b``, both ends included."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    count = max(int(np.linalg.norm(b - a) / step), 1)
    return a + (b - a) * np.linspace(0.0, 1.0, count + 1)[:, None]


def _sampled_many(starts, ends, step: float):
    """:func:`_sampled` of every segment ``starts[k]``-``ends[k]`` (mm) at once: the points and,
    for each, the index of its segment."""
    starts = np.asarray(starts, float).reshape(-1, 2)
    spans = np.asarray(ends, float).reshape(-1, 2) - starts
    counts = np.maximum((np.linalg.norm(spans, axis=1) / step).astype(int), 1)
    owner = np.repeat(np.arange(len(starts)), counts + 1)
    first = np.repeat(np.cumsum(counts + 1) - (counts + 1), counts + 1)
    share = (np.arange(len(owner)) - first) / np.repeat(counts, counts + 1)
    return starts[owner] + spans[owner] * share[:, None], owner


def _every(owner, every: int) -> np.ndarray:
    """Which points are each group's first and every ``every``-th after (``owner``: each
    point's group, the groups in order)."""
    if every <= 1:
        return np.ones(len(owner), bool)
    starts = np.flatnonzero(np.r_[True, owner[1:] != owner[:-1]])
    rank = np.arange(len(owner)) - np.repeat(starts, np.diff(np.r_[starts, len(owner)]))
    return rank % every == 0


def off_links(points, shapes, margin: float) -> bool:
    """Whether every point (mm) stands at least ``margin`` off the links' segments and outside
    the areas they enclose (:func:`link_shapes_mm`)."""
    points = np.asarray(points, float).reshape(-1, 2)
    if len(points) == 0:
        return True
    return shapes.off(points, margin)


class _Links:
    """The links' segments and areas (mm) with a k-d tree of points along the segments, dense
    enough (``step``) that a point's distance to them is known within a quarter step."""

    def __init__(self, segments, areas, step: float):
        from matplotlib.path import Path  # lazy: heavy optional import
        from scipy.spatial import cKDTree  # lazy: heavy optional import

        self.segments = segments
        self.areas = [Path(area) for area in areas]
        self.bounds = [(area.min(axis=0), area.max(axis=0)) for area in areas]
        self.lows = np.array([low for low, _ in self.bounds]).reshape(-1, 2)
        self.highs = np.array([high for _, high in self.bounds]).reshape(-1, 2)
        self.step = step
        self.memo: dict = {}
        segments = np.asarray(segments, float).reshape(-1, 2, 2)
        self.tree = cKDTree(_sampled_many(segments[:, 0], segments[:, 1], step / 2)[0])

    def remembered(self, key, found):
        """``found()``, once for each ``key``: a search off these links, asked again for the
        same drawing (a scheme is drawn twice at a scale, to fit it and then with its marks)."""
        if key not in self.memo:
            if len(self.memo) >= 256:  # a few schemes' searches: the memory stays bounded
                self.memo.clear()
            self.memo[key] = found()
        return self.memo[key]

    def touched(self, points, owner, count: int, margin: float, first: int = 8) -> np.ndarray:
        """Which of ``count`` groups of ``points`` (mm; ``owner``: each point's group, the
        groups in order) has a point within ``margin`` of a link's segment or inside an area:
        :meth:`off` of many places tried at once. Every ``first`` point of a group first: most
        places tried touch a link, and so are known at a fraction of the cost."""
        points = np.asarray(points, float).reshape(-1, 2)
        if first <= 1:
            return self._touched(points, owner, count, margin)
        few = _every(owner, first)
        hit = self._touched(points[few], owner[few], count, margin)
        rest = ~hit[owner] & ~few
        hit |= self._touched(points[rest], owner[rest], count, margin)
        return hit

    def _near_points(self, points, owner, margin: float, run: int = 8) -> np.ndarray:
        """Which ``points`` may stand within ``margin`` of a link's segment: those of each run
        of ``run`` points of a group whose bounding circle comes within ``margin`` of one (a
        point no farther than r from a centre at a distance d stands at least d - r off)."""
        first = _every(owner, run) | np.r_[True, owner[1:] != owner[:-1]]
        starts = np.flatnonzero(first)
        low = np.minimum.reduceat(points, starts, axis=0)
        high = np.maximum.reduceat(points, starts, axis=0)
        radius = np.linalg.norm(high - low, axis=1) / 2
        bound = float(radius.max()) + margin + self.step if len(radius) else 0.0
        distances, _ = self.tree.query((low + high) / 2, distance_upper_bound=bound)
        close = distances < radius + margin
        return close[np.cumsum(first) - 1]

    def _touched(self, points, owner, count: int, margin: float) -> np.ndarray:
        hit = np.zeros(count, bool)
        if not len(points):
            return hit
        # runs of points only where the groups are long (a short one is its own run): long
        # runs first, the points of those near a link in short runs
        near = np.ones(len(points), bool)
        for run in (32, 8) if len(points) > 16 * count else ():
            kept = np.flatnonzero(near)
            near[kept] = self._near_points(points[kept], owner[kept], margin, run)
        distances, _ = self.tree.query(points[near], distance_upper_bound=margin + self.step)
        hit[owner[near][distances < margin]] = True
        # the areas only for the groups still clear of the segments
        live = ~hit[owner]
        points, owner = points[live], owner[live]
        if not len(owner):
            return hit
        changes = np.asarray(owner[1:] != owner[:-1], bool)
        starts = np.flatnonzero(np.concatenate([[True], changes]))
        groups = owner[starts]
        lows = np.minimum.reduceat(points, starts, axis=0)
        highs = np.maximum.reduceat(points, starts, axis=0)
        # each group against each area's bounds at once; an area's outline only where they meet
        meets: np.ndarray = np.all(
            (highs[:, None, :] >= self.lows[None, :, :])
            & (lows[:, None, :] <= self.highs[None, :, :]),
            axis=2,
        )
        for k in np.flatnonzero(meets.any(axis=0)):
            near = np.zeros(count, bool)
            near[groups[meets[:, k]]] = True
            near &= ~hit
            if not near.any():
                continue
            tried = np.flatnonzero(near[owner])
            inside = self.areas[k].contains_points(points[tried])
            hit[owner[tried[inside]]] = True
        return hit

    def off(self, points, margin: float) -> bool:
        distances, _ = self.tree.query(points, distance_upper_bound=margin + self.step)
        if float(distances.min()) < margin:
            return False
        low, high = points.min(axis=0), points.max(axis=0)
        near = np.flatnonzero(((high >= self.lows) & (low <= self.highs)).all(axis=1))
        return not any(self.areas[k].contains_points(points).any() for k in near)

    def through_many(self, outline, places) -> np.ndarray:
        """:meth:`through` of the closed ``outline`` (mm) moved to each of ``places``."""
        from matplotlib.path import Path  # lazy: heavy optional import

        places = np.asarray(places, float).reshape(-1, 2)
        low, high = outline.min(axis=0), outline.max(axis=0)
        owner, index = _near_pairs(
            self.tree, (low + high) / 2 + places, float(np.linalg.norm(high - low)) / 2
        )
        if not len(owner):
            return np.zeros(len(places), bool)
        inside = Path(outline).contains_points(self.tree.data[index] - places[owner])
        return np.bincount(owner[inside], minlength=len(places)) > 0

    def through(self, outline) -> bool:
        """Whether a link's segment passes inside the closed ``outline`` (mm)."""
        from matplotlib.path import Path  # lazy: heavy optional import

        low, high = outline.min(axis=0), outline.max(axis=0)
        near = self.tree.query_ball_point((low + high) / 2, float(np.linalg.norm(high - low)) / 2)
        return bool(len(near)) and bool(Path(outline).contains_points(self.tree.data[near]).any())


def _box_off_links(outline, shapes, margin: float, step: float) -> bool:
    """Whether a text's box (its closed outline, mm) stands ``margin`` off the links and no
    link passes through it."""
    return off_links(_ring_outline(outline, step), shapes, margin) and not shapes.through(outline)


def _text_outline_mm(ax, label) -> np.ndarray:
    """The closed outline (mm) of a text's box with its padding, turned as the text is."""
    renderer = ax.figure.canvas.get_renderer()
    rotation = label.get_rotation()
    label.set_rotation(0.0)
    box = label.get_window_extent(renderer)
    label.set_rotation(rotation)
    patch = label.get_bbox_patch()
    pad = (patch.get_boxstyle().pad if patch else 0.0) * label.get_fontsize() * ax.figure.dpi / 72
    anchor = ax.transData.transform(label.get_position())
    corners = np.array(
        [[box.x0, box.y0], [box.x1, box.y0], [box.x1, box.y1], [box.x0, box.y1], [box.x0, box.y0]]
    ) + np.array([[-pad, -pad], [pad, -pad], [pad, pad], [-pad, pad], [-pad, -pad]])
    c, s = np.cos(np.radians(rotation)), np.sin(np.radians(rotation))
    turned = (corners - anchor) @ np.array([[c, s], [-s, c]]) + anchor
    return ax.transData.inverted().transform(turned)


def _clear_offsets(
    ax, geometry, i: int, p, q, extent: float, least: float, most: float, drawn=False
) -> list:
    """The offsets (mm, signed along p-q's left normal) from ``least`` to ``most``, nearest
    first, at which a dimension line of p-q (mm) and its arrows stand off every link and
    everything drawn (``drawn``: :func:`_marks_tree`, if already built; the extension lines may
    cross links: ГОСТ 2.307)."""
    shapes = link_shapes_mm(geometry, i)
    p, q = np.asarray(p, float), np.asarray(q, float)
    d = (q - p) / max(float(np.linalg.norm(q - p)), 1e-12)
    n = np.array([-d[1], d[0]])
    margin, step = extent * 0.005, extent * 0.003
    if drawn is False:
        drawn = _marks_tree(ax, step)
    # each offset on the left, then on the right, all the lines tested at once
    offsets = np.ravel(
        np.arange(least, most, extent * 0.01)[:, None] * np.array([1.0, -1.0])[None, :]
    )
    if not len(offsets):
        return []
    lines, owner = _sampled_many(p + np.outer(offsets, n), q + np.outer(offsets, n), step)
    # off the links: the same for the same link and shapes, whatever else is drawn
    clear = shapes.remembered(
        ("offsets", p.tobytes(), q.tobytes(), extent, least, most),
        lambda: ~shapes.touched(lines, owner, len(offsets), margin),
    ).copy()
    if drawn is not None:
        distances, _ = drawn.query(lines, distance_upper_bound=margin)
        clear &= np.bincount(owner[distances < margin], minlength=len(offsets)) == 0
    return [float(offset) for offset in offsets[clear]]


def _text_beyond(ax, a, b, text: str, extent: float, gid: str, shapes) -> bool:
    """A short dimension's text on its dimension line a-b (mm) continued past one arrow
    (ГОСТ 2.307: no room between the arrows), where the text and the continued line stand off
    the links and the marks drawn; whether it is drawn."""
    margin, step = extent * 0.005, extent * 0.003
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = (b - a) / max(float(np.linalg.norm(b - a)), 1e-12)
    marks = _marks_tree(ax, step)
    label = _dimension_text(ax, a, b, text, extent, gid)
    corners = _text_outline_mm(ax, label)
    width = float(np.linalg.norm(corners[1] - corners[0]))
    lifted = label.get_position()
    for start, direction in ((b, d), (a, -d)):
        end = start + direction * (width + extent * 0.02)
        middle = (start + end) / 2 + direction * extent * 0.005
        label.set_position(middle + (np.asarray(lifted, float) - (a + b) / 2))
        outline = _text_outline_mm(ax, label)
        line = _sampled(start + direction * extent * 0.01, end, step)
        if (
            off_links(line, shapes, margin)
            and _box_off_links(outline, shapes, margin, step)
            and _off_marks(marks, outline[:-1], margin, step)
        ):
            ax.plot(*np.c_[start, end], color="0.35", lw=0.5, ls="-", gid=gid + "-shelf")
            return True
    label.remove()
    return False


def _off_marks(tree, outline, margin: float, step: float) -> bool:
    """Whether a text's box (its outline, mm) stands ``margin`` off the dimensions and texts
    drawn (:func:`_marks_tree`) with none of them inside it."""
    if tree is None:
        return True
    if float(tree.query(_ring_outline(np.vstack([outline, outline[:1]]), step))[0].min()) < margin:
        return False
    low, high = outline.min(axis=0), outline.max(axis=0)
    near = tree.data[tree.query_ball_point((low + high) / 2, float(np.linalg.norm(high - low)))]
    return not np.any(np.all((near > low) & (near < high), axis=1))


def _marks_state(ax, step: float) -> list:
    """What :func:`_marks_tree` depends on: the dimensions' lines, every text with its place,
    the axes' scale."""
    state: list = [step, tuple(ax.transData.get_affine().get_matrix().ravel())]
    state += [line for line in ax.lines if (line.get_gid() or "").startswith("dimension-")]
    for text in ax.texts:
        xyann = tuple(np.ravel(text.xyann)) if hasattr(text, "xyann") else None
        state.append(
            (text, text.get_text(), tuple(text.get_position()), text.get_rotation(), xyann)
        )
    return state


def _marks_tree(ax, step: float):
    """A k-d tree of points (mm) along the dimensions drawn so far and round every text's box,
    which a new dimension line keeps off (the axes' centre lines it may cross); None if none.
    Built again only when they change: the placement search asks for it at every place."""
    state = _marks_state(ax, step)
    cached = getattr(ax, "_crankdyn_marks", None)
    # artists compare as themselves: the same state is the same artists with the same places
    if cached is not None and cached[0] == state:
        return cached[1]
    tree = _marks_tree_built(ax, step)
    ax._crankdyn_marks = (state, tree)
    return tree


def _marks_tree_built(ax, step: float):
    """:func:`_marks_tree`, built."""
    from scipy.spatial import cKDTree  # lazy: heavy optional import

    renderer = ax.figure.canvas.get_renderer()
    points, starts, ends = [], [], []
    for line in ax.lines:
        if (line.get_gid() or "").startswith("dimension-"):
            xy = np.column_stack(line.get_data()).astype(float)
            starts.append(xy[:-1])
            ends.append(xy[1:])
    for text in ax.texts:
        if not text.get_text() and hasattr(text, "xyann"):
            starts.append(np.asarray(text.xyann, float).reshape(1, 2))
            ends.append(np.asarray(text.xy, float).reshape(1, 2))
        elif text.get_text():
            points.append(_ring_outline(_text_corners_mm(ax, text, renderer), step))
    if starts:
        points.append(_sampled_many(np.concatenate(starts), np.concatenate(ends), step)[0])
    return cKDTree(np.concatenate(points)) if points else None


def _dimension_off_links(
    ax, geometry, i: int, p, q, text: str, extent: float, key: str, offset, strict: bool
) -> bool:
    """A dimension of p-q (mm) at ``offset`` (:func:`_clear_offset`): its text over the line
    where that box is clear of the links and of everything drawn, else by a leader
    (:func:`_leader_text`) off the links; ``strict``: nothing drawn where there is no such
    leader. Whether it is drawn."""
    shapes = link_shapes_mm(geometry, i)
    p, q = np.asarray(p, float), np.asarray(q, float)
    d = (q - p) / max(float(np.linalg.norm(q - p)), 1e-12)
    n = np.array([-d[1], d[0]])
    margin, step = extent * 0.005, extent * 0.003
    a, b = p + n * offset, q + n * offset
    before = (list(ax.lines), list(ax.texts))
    _dimension(ax, p, q, "", offset, extent, key)
    gid = f"dimension-{key}-text"
    label = _dimension_text(ax, a, b, text, extent, gid)
    outline = _text_outline_mm(ax, label)
    label.remove()
    clearance = _Clearance(ax, geometry, i, extent)
    if (
        _box_off_links(outline, shapes, margin, step)
        and clearance.of_outline(_ring_outline(outline, step)) > 0
    ):
        _dimension_text(ax, a, b, text, extent, gid)
        return True
    if _text_beyond(ax, a, b, text, extent, gid, shapes):
        return True
    # nothing drawn since the clearance was measured: the texts tried beyond are gone
    if _leader_text(ax, geometry, i, (a + b) / 2, text, extent, gid, shapes, strict, clearance):
        return True
    for artist in [a for a in ax.lines if a not in before[0]]:
        artist.remove()
    for artist in [a for a in ax.texts if a not in before[1]]:
        artist.remove()
    return False


def _ring_outline(outline, step: float) -> np.ndarray:
    """Points at most ``step`` apart along a polyline (mm), its corners included."""
    outline = np.asarray(outline, float)
    edges = np.diff(outline, axis=0)
    lengths = np.linalg.norm(edges, axis=1)
    if not len(lengths) or lengths.max() <= step:
        return outline
    counts = np.maximum(np.ceil(lengths / step).astype(int), 1)
    edge = np.repeat(np.arange(len(edges)), counts)
    first = np.repeat(np.cumsum(counts) - counts, counts)
    share = (np.arange(int(counts.sum())) - first) / np.repeat(counts, counts)
    return np.vstack([outline[edge] + edges[edge] * share[:, None], outline[-1:]])


def _shelf_note(ax, geometry, i: int, links, text: str, extent: float, key: str) -> None:
    """A link's parameter on the shelf of a leader whose arrow points at one of the equal
    ``links`` (p, q pairs, mm) (ГОСТ 2.703, 2.316): the shortest leader, leader, shelf and text
    crossing no link and clear of everything drawn; where none is, the text along the first."""
    shapes = link_shapes_mm(geometry, i)
    clearance = _Clearance(ax, geometry, i, extent)
    # on one line; where that finds no room, the value under its symbol, as narrow again
    best = None
    for lines in dict.fromkeys((text, text.replace(" = ", " =\n", 1))):
        # the text along the link, beside it, where it has room; else on a leader's shelf
        if _note_along(ax, geometry, i, links, lines, extent, key, shapes, clearance, False):
            return
        best = _shelf_best(ax, links, lines, extent, shapes, clearance)
        if best is not None:
            text = lines
            break
    if best is None:
        _note_along(ax, geometry, i, links, text, extent, key, shapes, clearance, True)
        return
    target, elbow, end, shift = best
    arrow = ax.annotate(
        "",
        xy=target,
        xytext=elbow,
        arrowprops={
            "arrowstyle": "-|>",
            "color": "0.35",
            "lw": 0.5,
            "shrinkA": 0,
            "shrinkB": 0,
            "mutation_scale": 7,
        },
    )
    arrow.set_gid(f"dimension-{key}-leader")
    ax.plot(*np.c_[elbow, end], color="0.35", lw=0.5, ls="-", gid=f"dimension-{key}-shelf")
    ax.text(
        *shift,
        text,
        ha="left",
        va="bottom",
        **DIMENSION_TEXT,
        gid=f"dimension-{key}-text",
    )


def _shelf_best(ax, links, text: str, extent: float, shapes, clearance):
    """:func:`_shelf_place` of the text over the best of the ``links``; None where none has."""
    label = ax.text(0.0, 0.0, text, ha="left", va="bottom", fontsize=8, bbox=LABEL_BOX)
    box = _text_outline_mm(ax, label)
    label.remove()
    best, best_score = None, None
    for p, q in links:
        found = _shelf_place(
            np.asarray(p, float), np.asarray(q, float), box, extent, shapes, clearance, best_score
        )
        if found is not None and (best_score is None or found[0] < best_score):
            best_score, best = found
    return best


def _shelf_place(p, q, box, extent: float, shapes, clearance, bound=None):
    """(score, (target, elbow, shelf's end, text's foot)) of the best leader to the link p-q
    (mm) for a text of ``box`` (its outline standing on the origin, mm): a straight leader from
    a point of the link, off the other links' areas, to the shelf's near end, leader, shelf and
    text off every link and clear of everything drawn; the score (lines the leader crosses, its
    length) lowest; None where none is (or none scores below ``bound``)."""
    from matplotlib.path import Path  # lazy: heavy optional import

    margin, step = extent * 0.005, extent * 0.003
    width = float(np.ptp(box[:, 0]))
    # the box's padding round the text: the text stands on the shelf, its box just over it
    pad_x, lift = -float(box[:, 0].min()), -float(box[:, 1].min()) + margin * 0.3
    length = float(np.linalg.norm(q - p))
    d = (q - p) / max(length, 1e-12)
    # the link's points off the other links' areas (a crank under a master rod's body: its end)
    targets = [
        t
        for t in _sampled(p, q, max(step * 2, length / 12))[1:-1]
        if min(np.linalg.norm(t - p), np.linalg.norm(t - q)) > extent * JOINT_R + margin
        and not any(area.contains_point(t) for area in shapes.areas)
    ]
    best, best_score = None, bound
    for target in targets:
        for angle in np.radians(np.arange(1.0, 360.0, 3.0)):
            ray = np.array([np.cos(angle), np.sin(angle)])
            if abs(float(np.dot(ray, d))) > 0.9:
                continue  # along the link: its arrow would lie on it
            free = _free_reach(target, ray, shapes, margin, step, extent * 0.8)
            for reach in np.arange(extent * 0.03, free, extent * 0.015):
                if best_score is not None and (0, reach) >= best_score:
                    break
                elbow = target + ray * reach
                # the shelf away from the leader, or back under it where the leader comes down
                # steeply enough to stay off the text
                for sign in (1.0, -1.0) if ray[0] >= 0.0 else (-1.0, 1.0):
                    end = elbow + np.array([sign * width, 0.0])
                    shift = np.array([min(elbow[0], end[0]) + pad_x, elbow[1] + lift])
                    outline = box + shift
                    if sign * ray[0] < 0.0 and (
                        ray[1] >= 0.0
                        or Path(outline).contains_points(_sampled(target, elbow, step)).any()
                    ):
                        continue
                    if not off_links(_sampled(elbow, end, step), shapes, margin):
                        continue
                    if not _box_off_links(outline, shapes, margin, step):
                        continue
                    if clearance.of_outline(_ring_outline(outline, step)) <= 0:
                        continue
                    score = (_leader_crossings(clearance, target, elbow), reach)
                    if best_score is None or score < best_score:
                        best, best_score = (target, elbow, end, shift), score
                    break
    return None if best is None else (best_score, best)


def _free_reach(start, ray, shapes, margin: float, step: float, most: float) -> float:
    """How far (mm) a leader from ``start`` on a link runs along ``ray`` before it comes within
    ``margin`` of a link or enters a link's area (its first ``1.5 margin`` left out: it starts on
    its own link)."""
    points = start + np.outer(np.arange(margin * 1.5, most, step), ray)
    if not len(points):
        return 0.0
    distances, _ = shapes.tree.query(points, distance_upper_bound=margin + shapes.step)
    bad = distances < margin
    low, high = points.min(axis=0), points.max(axis=0)
    for k in np.flatnonzero(((high >= shapes.lows) & (low <= shapes.highs)).all(axis=1)):
        bad |= shapes.areas[k].contains_points(points)
    hit = np.flatnonzero(bad)
    return float(np.linalg.norm(points[hit[0]] - start)) - step if len(hit) else most


def _note_along(
    ax, geometry, i: int, links, text, extent: float, key: str, shapes, clearance, anyway: bool
) -> bool:
    """A link's parameter written along one of the equal ``links`` (p, q pairs, mm), beside it,
    where its box is clear of every link and of everything drawn (the nearest place to a link's
    middle); where there is none, nothing (``anyway``: by the first link's middle). Whether it
    found a place."""
    margin, step = extent * 0.005, extent * 0.003
    label = ax.text(
        0.0,
        0.0,
        text,
        ha="center",
        va="center",
        rotation_mode="anchor",
        **DIMENSION_TEXT,
        zorder=7,
        gid=f"dimension-{key}-text",
    )
    p, q = (np.asarray(v, float) for v in links[0])
    chosen, rotation, best = (p + q) / 2, _readable_rotation_deg(q - p), None
    for p, q in links:
        p, q = np.asarray(p, float), np.asarray(q, float)
        d = (q - p) / max(float(np.linalg.norm(q - p)), 1e-12)
        n = np.array([-d[1], d[0]])
        label.set_rotation(_readable_rotation_deg(d))
        label.set_position((0.0, 0.0))
        outline = _text_outline_mm(ax, label)
        ring = _ring_outline(outline, step)
        shares = (0.5, 0.6, 0.4, 0.7, 0.3, 0.8, 0.2)
        offsets = np.arange(0.02, 0.08, 0.005) * extent
        # every place at once: (share, offset, side)
        along = np.asarray(shares)[:, None, None, None] * (q - p)
        aside = (offsets[:, None] * np.array([1.0, -1.0]))[None, :, :, None] * n
        places = p + along + aside
        flat = places.reshape(-1, 2)
        owner = np.repeat(np.arange(len(flat)), len(ring))
        usable = ~shapes.touched(
            (ring[None, :, :] + flat[:, None, :]).reshape(-1, 2), owner, len(flat), margin
        )
        kept = np.flatnonzero(usable)
        usable[kept] = ~shapes.through_many(outline, flat[kept])
        usable = usable.reshape(places.shape[:3])
        for s_index, share in enumerate(shares):
            for o_index, offset in enumerate(offsets):
                score = offset + abs(share - 0.5) * extent * 0.1
                if best is not None and score >= best:
                    break
                for k_side in range(2):
                    at = places[s_index, o_index, k_side]
                    if not usable[s_index, o_index, k_side]:
                        continue
                    if clearance.of_outline(ring + at) <= 0:
                        continue
                    chosen, rotation, best = at, _readable_rotation_deg(d), score
                    break
    if best is None and not anyway:
        label.remove()
        return False
    label.set_rotation(rotation)
    label.set_position(chosen)
    return best is not None


def _crank_radius_aside(ax, geometry, i: int, crank, text: str, extent: float) -> None:
    """R of an in-line engine whose rods fan out (cranks in more than two directions): the text
    goes beside the outermost joint, joined to the crank's dimension line by a leader."""
    j = geometry.joints
    p, q = j[crank[1]][i] * MM, j[crank[2]][i] * MM
    offset = -extent * 0.06
    _dimension(ax, p, q, "", offset, extent, "R")
    d = (q - p) / max(np.linalg.norm(q - p), 1e-12)
    mid = (p + q) / 2 + np.array([-d[1], d[0]]) * offset
    right = mid[0] >= float(p[0])
    edge = (max if right else min)(float(points[i][0]) * MM for points in j.values())
    at = np.array([edge + (1 if right else -1) * extent * 0.05, mid[1]])
    ax.plot([mid[0], at[0]], [mid[1], at[1]], color="0.35", lw=0.5, ls="-")
    ax.text(
        *at,
        text,
        ha="left" if right else "right",
        va="center",
        **DIMENSION_TEXT,
        gid="dimension-R-text",
    )


def draw_crank_star(ax, geometry, title: str, firing_label: str) -> None:
    """The crank star: each crank's direction at cylinder 1's TDC, its number and its cylinders."""
    # cranks in one direction (1 and 4 of an in-line four) share one line and one label
    directions: dict[float, tuple[list[str], list[str]]] = {}
    for label, lag, cylinders in geometry.cranks:
        cranks, cyls = directions.setdefault(round(float(lag) % 360.0, 6) % 360.0, ([], []))
        cranks.append(label)
        cyls.extend(cylinders)
    for lag, (cranks, cylinders) in directions.items():
        u = np.array([np.sin(np.radians(-lag)), np.cos(np.radians(-lag))])
        ax.plot([0, u[0]], [0, u[1]], color=INK, lw=2, ls="-")
        ax.add_patch(_circle(u, 0.06, INK, 1.0, fill=True))
        # the cylinders in brackets only where they are not the cranks' own numbers (a V's 1L, 1R)
        text = (
            ", ".join(cranks)
            if list(cylinders) == list(cranks)
            else f"{', '.join(cranks)}\n({', '.join(cylinders)})"
        )
        ax.text(*(u * 1.15), text, fontsize=7, **outward_alignment(u))
    ax.add_patch(_circle((0, 0), 0.07, INK, 1.0, fill=True))
    ax.set_xlim(-1.7, 1.7)
    ax.set_ylim(-1.7, 1.7)
    ax.set_aspect("equal")
    hide_axes(ax)
    # "Crank star (at the TDC of cylinder 1)" in two lines: as narrow as the star
    ax.set_title(title.replace(" (", "\n(", 1) if len(title) > 24 else title, fontsize=8)
    ax.text(0, -1.65, _wrapped_order(firing_label), ha="center", va="top", fontsize=7)


def _wrapped_order(label: str, width: int = 30) -> str:
    """A firing order ("Порядок роботи: 1 – 2 – 4 – 5 – 3") in lines of at most ``width``
    characters where it can be, so that a V8's order stays as narrow as the crank star above it:
    on one line if it fits; else its title on a line of its own and the order below it; an order
    longer than a line broken after a dash into as few lines as it needs, of even length (no
    cylinder left alone on the last line)."""
    if len(label) <= width:
        return label
    title, colon, order = label.rpartition(": ")
    head = [title + colon.rstrip()] if colon else []
    order = order if colon else label
    parts = order.split(" – ")
    for count in range(1, len(parts) + 1):
        size = -(-len(parts) // count)  # parts per line, the lines as even as they can be
        lines = [" – ".join(parts[k : k + size]) for k in range(0, len(parts), size)]
        if all(len(line) + 2 <= width for line in lines) or size == 1:
            return "\n".join(head + [line + " –" for line in lines[:-1]] + lines[-1:])
    return "\n".join(head + [order])  # not reached: one part a line always ends the loop


#: Scales of a drawing, paper length : real length (ДСТУ ISO 5455, ГОСТ 2.302): enlargements,
#: full size, reductions; a larger or smaller mechanism continues the 1-2-5 steps.
DRAWING_SCALES = (
    50.0,
    20.0,
    10.0,
    5.0,
    4.0,
    2.5,
    2.0,
    1.0,
    1 / 2,
    1 / 2.5,
    1 / 4,
    1 / 5,
    1 / 10,
    1 / 15,
    1 / 20,
    1 / 25,
    1 / 40,
    1 / 50,
    1 / 75,
    1 / 100,
)
#: Room for the mechanism on the page (mm, width x height), beside the crank star when there is
#: one, and the most a figure may take: the A4 text width (210 mm less margins of 30 and 15 mm),
#: so that the page shows it at its own size and so at its scale.
SCHEME_ROOM_MM = (150.0, 150.0)
SCHEME_ROOM_WITH_STAR_MM = (112.0, 150.0)
PAGE_ROOM_MM = (165.0, 200.0)
_LIMITS_SLACK = 1.6
STAR_SIZE_MM = 40.0
_STAR_GAP_MM = 8.0
_STAR_TITLE_MM = 8.0  # the star's title of two lines above it, when the star is under the drawing
_MARGIN_MM = 2.0


def drawing_scale(extent_mm: tuple[float, float], room_mm: tuple[float, float]) -> float:
    """The largest standard scale (paper : real) at which a drawing of ``extent_mm`` (width,
    height) fits into ``room_mm``: 1/2.5 for "М 1:2,5"."""
    fits = [
        s
        for s in DRAWING_SCALES
        if extent_mm[0] * s <= room_mm[0] and extent_mm[1] * s <= room_mm[1]
    ]
    if fits:
        return fits[0]
    denominator = 1 / DRAWING_SCALES[-1]
    while extent_mm[0] > room_mm[0] * denominator or extent_mm[1] > room_mm[1] * denominator:
        denominator *= 2.5 if str(int(denominator))[0] == "2" else 2.0  # 1:200, 1:500, 1:1000, ...
    return 1 / denominator


def _smaller_scale(scale: float) -> float:
    """The next standard scale below ``scale`` (1:2 -> 1:2,5; 1:100 -> 1:200)."""
    return drawing_scale((1.0, 1.0), (scale * (1 - 1e-9), scale * (1 - 1e-9)))


def scheme_figure(
    geometry,
    i: int,
    labels: dict[str, str],
    star_title: str = "",
    firing_label: str = "",
    marks: dict[str, str] | None = None,
):
    """(figure, scale): the scheme at frame ``i`` with its dimension lines, and the crank star when
    there are cranks, drawn to a standard scale (paper : real, 0.25 for "М 1:4"); ``marks``: the
    texts of :func:`draw_angle_marks` (the angles, the sense of rotation, the dead centres).

    Laid out here, not by the tight layout (which would resize the drawing), in millimetres on
    paper: the largest standard scale at which the mechanism's limits fit its room, and then
    smaller ones while the figure with its texts is wider or taller than the page allows."""
    geometry = upright(front_view(geometry))
    (x0, x1), (y0, y1) = _limits(geometry)
    with_star = len(geometry.cranks) > 1
    room = SCHEME_ROOM_WITH_STAR_MM if with_star else SCHEME_ROOM_MM
    # the limits keep room for labels the drawing may not have: start a step or two larger
    scale = drawing_scale((x1 - x0, y1 - y0), (room[0] * _LIMITS_SLACK, room[1] * _LIMITS_SLACK))

    def fitting(start: float, below: bool, least: float = 0.0):
        """(figure, scale) at the largest scale from ``start`` down that fits; None below
        ``least``. The drawing at ``start`` is made with the angle marks at once: most
        mechanisms fit there, and a drawing without them would only be made again. Below it,
        the scale is found without the marks (placing them tries many spots), and the drawing
        with them is kept where it fits too."""
        height = SCHEME_ROOM_MM[1] if below else room[1]
        scale = start
        while scale >= least:
            texts = (labels, star_title, firing_label, scale)
            if (
                not marks
                or scale == start
                or _fits(_scheme_at(geometry, i, *texts, {}, below), height, scale)
            ):
                fig = _scheme_at(geometry, i, *texts, marks or {}, below)
                if _fits(fig, height, scale):
                    return fig, scale
            scale = _smaller_scale(scale)
        return None

    beside = fitting(scale, below=False)
    assert beside is not None  # the search runs down to the least scale
    # a wide drawing (a W) that beside its crank star would be drawn at half the scale or less is
    # drawn with the star below it
    below = fitting(scale, below=True, least=2 * beside[1]) if with_star else None
    return below or beside


def _fits(fig, height_room_mm: float, scale: float) -> bool:
    """The figure is no wider than the page's text and no higher than ``height_room_mm`` (or the
    scale is past any drawing's, where the search stops)."""
    width_mm, height_mm = (size * 25.4 for size in fig.get_size_inches())
    return width_mm <= PAGE_ROOM_MM[0] and height_mm <= height_room_mm or scale < 1e-9


def _scheme_at(
    geometry,
    i: int,
    labels: dict[str, str],
    star_title: str,
    firing_label: str,
    scale: float,
    marks: dict[str, str],
    star_below: bool = False,
):
    from .figures import (  # lazy: heavy optional import (matplotlib)
        add_axes_mm,
        drawn_box,
        fit_to_content,
        new_drawing,
    )

    (x0, x1), (y0, y1) = _limits(geometry)
    with_star = len(geometry.cranks) > 1
    width_mm, height_mm = (x1 - x0) * scale, (y1 - y0) * scale
    below = with_star and star_below
    if below:  # the star's room under the drawing: the star is placed there once it is drawn
        below_mm = _STAR_GAP_MM + _STAR_TITLE_MM + STAR_SIZE_MM
        fig = new_drawing(width_mm, height_mm + below_mm)
        ax = add_axes_mm(fig, 0.0, below_mm, width_mm, height_mm)
    else:
        fig = new_drawing(
            width_mm + _STAR_GAP_MM + STAR_SIZE_MM if with_star else width_mm,
            max(height_mm, STAR_SIZE_MM),
        )
        ax = add_axes_mm(fig, 0.0, 0.0, width_mm, height_mm)
    draw_mechanism(ax, geometry, i)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    marked = bool(marks) and angle_mark_parts(geometry) is not None
    # a marked scheme of one axis writes L beside the liner (draw_angle_marks); S only there
    draw_dimensions(ax, geometry, i, {k: v for k, v in labels.items() if not (marked and k == "L")})
    draw_angle_marks(ax, geometry, i, marks, labels)
    draw_planetary_marks(ax, geometry, i, marks)
    if below:
        # under what the mechanism draws, centred on it
        box = drawn_box([ax], fig.canvas.get_renderer())
        bottom_mm, middle_mm = (
            (box.y0 / fig.dpi * 25.4, (box.x0 + box.x1) / 2 / fig.dpi * 25.4)
            if box is not None
            else (_STAR_GAP_MM + _STAR_TITLE_MM + STAR_SIZE_MM, width_mm / 2)
        )
        star = add_axes_mm(
            fig,
            middle_mm - STAR_SIZE_MM / 2,
            bottom_mm - _STAR_GAP_MM - _STAR_TITLE_MM - STAR_SIZE_MM,
            STAR_SIZE_MM,
            STAR_SIZE_MM,
        )
        draw_crank_star(star, geometry, star_title, firing_label)
    elif with_star:
        # beside what the mechanism draws, not beside its limits' unused room
        box = drawn_box([ax], fig.canvas.get_renderer())
        right_mm = box.x1 / fig.dpi * 25.4 if box is not None else width_mm
        star = add_axes_mm(
            fig,
            right_mm + _STAR_GAP_MM,
            max(height_mm - STAR_SIZE_MM, 0.0) / 2,
            STAR_SIZE_MM,
            STAR_SIZE_MM,
        )
        draw_crank_star(star, geometry, star_title, firing_label)
    fit_to_content(fig, _MARGIN_MM)
    return fig


#: The positions figure: the A4 text width and the most it is shown high, mm: the page's text
#: height (247 mm inside the frame) less the sentence of three lines before it, its caption and
#: their margins (the print style lets this figure, and no other, be that high), so that a
#: cylinder above its crank is drawn half the text width wide; each panel's title takes one line.
TEXT_WIDTH_MM = 165.0
FIGURE_HEIGHT_MM = 207.0
_PANEL_TITLE_MM = 5.0


def _title_mm(aspect: float) -> float:
    """Room above a panel for its one-line title."""
    return _PANEL_TITLE_MM


def positions_layout(geometry, count: int) -> tuple[int, int]:
    """(panels in a row, panels on one figure) of the positions figure: two in a row, each half the
    text width (less for a mechanism so tall that half the text width would make a panel higher
    than a figure may be), as high as the mechanism at its standard scale; as many rows as the
    figure's height holds."""
    width, height = _panel_size_mm(_panel_geometry(geometry))
    cols = max(min(count, 2), 1)
    rows = max(1, int(FIGURE_HEIGHT_MM // (height + _title_mm(height / width))))
    return cols, cols * rows


def _panel_width_mm(aspect: float) -> float:
    """A positions panel's width (mm): half the text width, or less for a panel so tall that
    one row of them would be higher than a figure may be."""
    return min(TEXT_WIDTH_MM / 2, (FIGURE_HEIGHT_MM - _title_mm(aspect)) / aspect)


def _panel_limits(geometry):
    """A positions panel's limits (:func:`_panel_geometry`): room for the cylinders' numbers
    only (no dimension lines), else for the cylinder's axis past its liner; a narrow margin
    above and below, where only a joint's circle reaches past the limits' points; widened about
    their middle to the panel's width at its standard scale (:func:`positions_scale`)."""
    (x0, x1), (y0, y1) = _content_limits(geometry)
    aspect = (y1 - y0) / (x1 - x0)
    scale = _panel_scale(geometry)
    width = _panel_width_mm(aspect) / scale
    # only as high as the drawing at that scale: a standard scale smaller than the one that
    # fills the panel would leave bands of paper above and below the mechanism
    height = y1 - y0
    xm, ym = (x0 + x1) / 2, (y0 + y1) / 2
    return (xm - width / 2, xm + width / 2), (ym - height / 2, ym + height / 2)


def _content_limits(geometry):
    labelled = any(g.label for g in geometry.guides)
    return _limits(
        geometry, label_gap=0.1 if labelled else 0.045, pad_share=0.04, pad_share_y=0.015
    )


def _panel_size_mm(panel_geometry) -> tuple[float, float]:
    """(width, height) of a positions panel on paper (mm): its limits (:func:`_panel_limits`)
    at its standard scale, so that a millimetre of the mechanism is drawn as the scale says."""
    (x0, x1), (y0, y1) = _panel_limits(panel_geometry)
    scale = _panel_scale(panel_geometry)
    return (x1 - x0) * scale, (y1 - y0) * scale


def positions_scale(geometry) -> float:
    """The positions panels' standard scale (paper : real, ГОСТ 2.302): the largest at which the
    mechanism (:func:`_panel_geometry` of ``geometry``) fits its panel."""
    return _panel_scale(_panel_geometry(geometry))


def _panel_scale(panel_geometry) -> float:
    (x0, x1), (y0, y1) = _content_limits(panel_geometry)
    aspect = (y1 - y0) / (x1 - x0)
    width = _panel_width_mm(aspect)
    return drawing_scale((x1 - x0, y1 - y0), (width, width * aspect))


def _panel_geometry(geometry):
    """What a positions panel draws: the front view, upright; a lone cylinder without its
    number, which tells nothing there and would take the height of a line."""
    geometry = upright(front_view(geometry))
    if len(geometry.guides) == 1:
        geometry = replace(geometry, guides=[replace(geometry.guides[0], label="")])
    return geometry


def positions_sheets(geometry, frames: list) -> list[list]:
    """The frames split into the figures that hold them (:func:`positions_layout`), each but the
    last filled with whole rows; but a last figure of one panel takes one from the figure before
    it when that keeps two or more: five panels of a radial (two rows of two a figure) as three
    and two, not four and a lone one on a page of its own. Panels half the text width wide and
    one row high a figure (a cylinder above its crank) leave an odd one alone."""
    cols, per_sheet = positions_layout(geometry, len(frames))
    sheets = -(-len(frames) // per_sheet)
    size = -(-len(frames) // sheets)
    size = -(-size // cols) * cols if size > cols else size  # whole rows first
    sizes = [min(size, len(frames) - k) for k in range(0, len(frames), size)]
    if cols > 1 and len(sizes) > 1 and sizes[-1] == 1 and sizes[-2] > 2:
        sizes[-2:] = [sizes[-2] - 1, 2]
    starts = np.cumsum([0] + sizes)
    return [frames[a:b] for a, b in zip(starts[:-1], starts[1:], strict=True)]


def positions_figure(geometry, frames: list[tuple[int, str]]):
    """Small multiples: the mechanism at each (frame, caption), on one scale, laid out in
    millimetres (:func:`positions_layout`): each panel is a fixed share of the text width."""
    from .figures import add_axes_mm, new_drawing  # lazy: heavy optional import (matplotlib)

    geometry = _panel_geometry(geometry)
    limits = _panel_limits(geometry)
    width, height = _panel_size_mm(geometry)
    cols, _ = positions_layout(geometry, len(frames))
    rows = -(-len(frames) // cols)
    row_mm = height + _title_mm(height / width)
    fig = new_drawing(width * cols, row_mm * rows)
    for k, (i, caption) in enumerate(frames):
        row, col = divmod(k, cols)
        in_row = min(cols, len(frames) - row * cols)  # a last row's fewer panels centred
        left = (col + (cols - in_row) / 2) * width
        ax = add_axes_mm(fig, left, (rows - 1 - row) * row_mm, width, height)
        draw_mechanism(ax, geometry, i)
        ax.set_xlim(*limits[0])
        ax.set_ylim(*limits[1])
        ax.set_title(caption.replace("\n", " — "), fontsize=8, pad=2)
    return fig


def _limits(
    geometry,
    label_gap: float = LABEL_GAP,
    pad_share: float = 0.06,
    pad_share_y: float | None = None,
):
    """Axis limits (mm) holding every joint over the frames, every liner with its piston and label
    (``label_gap``: room beyond a liner, share of the span), with a margin of ``pad_share``
    (``pad_share_y`` above and below, when given)."""
    parts = [p.reshape(-1, 2) for p in geometry.joints.values()]
    parts += [t.reshape(-1, 2) for t in geometry.traces.values()]
    for c, radius, _ in geometry.circles:
        parts.append(geometry.joints[c].reshape(-1, 2) + [[-radius, -radius], [radius, radius]][0])
        parts.append(geometry.joints[c].reshape(-1, 2) + [radius, radius])
    span = np.ptp(np.concatenate(parts), axis=0).max() * MM
    for g in geometry.guides:
        if g.moving is not None:
            continue
        o, d = np.asarray(g.origin_m), np.asarray(g.direction)
        n = np.array([d[1], -d[0]])
        low = g.travel_m[0] - 0.35 * g.bore_m
        high = g.travel_m[1] + CROWN * g.bore_m + label_gap * span / MM
        half = g.bore_m / 2 + 0.02 * span / MM
        parts.append(
            np.array(
                [
                    o + d * low + n * half,
                    o + d * low - n * half,
                    o + d * high + n * half,
                    o + d * high - n * half,
                ]
            )
        )
    pts = np.concatenate(parts) * MM
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = pad_share * np.ptp(pts, axis=0).max()
    pad_y = pad if pad_share_y is None else pad_share_y * np.ptp(pts, axis=0).max()
    return (lo[0] - pad, hi[0] + pad), (lo[1] - pad_y, hi[1] + pad_y)


# --------------------------------------------------------------------------- animation


def animation_svg(geometry, view_box_frame: int = 0) -> tuple[str, str]:
    """(inline SVG, JSON frames) for the HTML animation: the static part drawn by matplotlib
    once without the moving members, the links and joints as SVG elements the script moves.

    The JSON holds, per joint, the positions (mm, y up) at every frame; links by joint names;
    pistons as (joint, guide origin, direction, half bore, skirt, crown).
    """
    geometry = upright(front_view(geometry))
    (x0, x1), (y0, y1) = _limits(geometry)
    names = list(geometry.joints)
    frames = {n: np.round(geometry.joints[n] * MM, 2).tolist() for n in names}
    extent = _extent_mm(geometry)
    pistons = [
        {
            "joint": g.joint,
            "o": [v * MM for v in g.origin_m],
            "d": list(g.direction),
            "half": g.bore_m * MM / 2 * 0.97,
            "skirt": piston_skirt_mm(g, geometry),
            "crown": CROWN * g.bore_m * MM,
        }
        for g in geometry.guides
        if g.bore_m > 0 and g.moving is None
    ]
    payload = {
        "joints": frames,
        "links": [[a, b, 1.0] for _, a, b in drawn_links(geometry)],
        "bodies": master_rod_joints(geometry),
        "pistons": pistons,
        "r": extent * JOINT_R,
        "fixed": list(geometry.fixed),
    }
    static = _static_svg_once(geometry, (x0, x1), (y0, y1))
    w, h = x1 - x0, y1 - y0
    svg = (
        f'<svg class="mech-anim" viewBox="{x0:.2f} {-y1:.2f} {w:.2f} {h:.2f}" '
        f'xmlns="http://www.w3.org/2000/svg" preserveAspectRatio="xMidYMid meet">'
        f'<image href="data:image/svg+xml;base64,{static}" x="{x0:.2f}" y="{-y1:.2f}" '
        f'width="{w:.2f}" height="{h:.2f}" preserveAspectRatio="none"/>'
        f'<g class="moving" stroke="#1a1a1a" stroke-linecap="round"></g></svg>'
    )
    return svg, json.dumps(payload, separators=(",", ":"))


def _static_svg_once(geometry, xlim, ylim) -> str:
    """:func:`_static_svg`, or the one this process drew of equal inputs
    (:mod:`crankdyn.report.figure_memo`: a batch's variants of the same dimensions)."""
    digest = figure_memo.inputs_digest(_static_svg, geometry, xlim, ylim)
    kept = figure_memo.value(digest)
    if kept is None:
        kept = _static_svg(geometry, xlim, ylim)
        figure_memo.keep_value(digest, kept)
    return kept


def _static_svg(geometry, xlim, ylim) -> str:
    """The fixed parts (liners, ground, fixed gear, traces) as a base64 SVG filling the limits."""

    import matplotlib  # lazy: heavy optional import
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # lazy: heavy optional import
    from matplotlib.figure import Figure  # lazy: heavy optional import

    with matplotlib.rc_context(STYLE):
        w, h = xlim[1] - xlim[0], ylim[1] - ylim[0]
        fig = Figure(figsize=(6.0, 6.0 * h / w))  # no pyplot state, as in figures.new_figure
        FigureCanvasAgg(fig)
        ax = fig.add_axes((0, 0, 1, 1))
        extent = _extent_mm(geometry)
        for path in geometry.traces.values():
            ax.plot(path[:, 0] * MM, path[:, 1] * MM, color="0.55", lw=0.7, ls=(0, (4, 2)))
        for centre, radius, kind in geometry.circles:
            if kind == "fixed":
                ax.add_patch(
                    _circle(geometry.joints[centre][0] * MM, radius * MM, INK, 1.0, ls="-.")
                )
        for guide in _one_per_axis(geometry.guides):
            if guide.bore_m > 0 and guide.moving is None:
                o, d, n = _guide_frame(geometry, guide, 0)
                half = guide.bore_m * MM / 2
                bottom, top = liner_ends_mm(guide, geometry)
                for side in (-1, 1):
                    _hatch(
                        ax,
                        o + d * bottom + n * side * half,
                        o + d * top + n * side * half,
                        n * side,
                        extent * 0.02,
                        INK,
                        1.0,
                    )
                if guide.label:
                    _guide_label(ax, o, d, n, top, half, guide.label, extent)
        for name in geometry.fixed:
            draw_ground(ax, geometry.joints[name][0] * MM, extent * JOINT_R * 1.6)
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        hide_axes(ax)
        buffer = io.BytesIO()
        fig.savefig(buffer, format="svg", metadata={"Date": None}, transparent=True)
    return base64.b64encode(buffer.getvalue()).decode("ascii")


def cursor_plot_svg(v, j, label_v: str, label_j: str) -> str:
    """A small inline SVG of the piston velocity and acceleration over the animation's frames
    (each scaled to its own range), with a vertical cursor line the animation moves."""
    width, height, pad = 400.0, 120.0, 6.0
    n = len(v)

    def polyline(values, color, dash=""):
        y = np.asarray(values, dtype=float)
        span = np.ptp(y) or 1.0
        ys = pad + (height - 2 * pad) * (1 - (y - y.min()) / span)
        xs = np.linspace(0.0, width, n, endpoint=False)
        points = " ".join(f"{x:.1f},{yy:.1f}" for x, yy in zip(xs, ys, strict=True))
        return (
            f'<polyline points="{points}" fill="none" stroke="{color}" stroke-width="1.5"'
            f"{' stroke-dasharray=' + chr(34) + dash + chr(34) if dash else ''}/>"
        )

    return (
        f'<svg class="mech-curves" viewBox="0 0 {width:.0f} {height + 16:.0f}" xmlns="http://www.w3.org/2000/svg">'
        f'<rect x="0" y="0" width="{width:.0f}" height="{height:.0f}" fill="none" stroke="#999" stroke-width="0.5"/>'
        + polyline(v, "#ff7f0e")
        + polyline(j, "#2ca02c", "5 3")
        + f'<line class="cursor" x1="0" x2="0" y1="0" y2="{height:.0f}" stroke="#d62728" stroke-width="1.5"/>'
        f'<text x="4" y="{height + 13:.0f}" font-size="11" fill="#ff7f0e">— {escape(label_v)}</text>'
        f'<text x="{width / 2:.0f}" y="{height + 13:.0f}" font-size="11" fill="#2ca02c">- - {escape(label_j)}</text>'
        "</svg>"
    )
