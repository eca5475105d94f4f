"""Where the labels of the bearings' polar load diagrams go: candidate places around each point,
clear of the drawn curve, the pole, the oil hole and each other."""

from __future__ import annotations

import math

import numpy as np


def _coinciding(x, y, tolerance) -> list[tuple[int, list[int]]]:
    """The points (x, y) in groups of those within ``tolerance`` of a group's first point, in
    order: (index of the first, indices of the group)."""
    groups: list[tuple[int, list[int]]] = []
    for k in range(len(x)):
        for first, members in groups:
            if math.hypot(x[k] - x[first], y[k] - y[first]) <= tolerance:
                members.append(k)
                break
        else:
            groups.append((k, [k]))
    return groups


_PLACES = (
    (2, 2, "left", "bottom"),
    (-2, 2, "right", "bottom"),
    (2, -2, "left", "top"),
    (-2, -2, "right", "top"),
    (7, 7, "left", "bottom"),
    (-7, 7, "right", "bottom"),
    (7, -7, "left", "top"),
    (-7, -7, "right", "top"),
)

#: Further out, tried only where a label nearer would sit on the curve.
_FAR_PLACES = (
    (12, 12, "left", "bottom"),
    (-12, 12, "right", "bottom"),
    (12, -12, "left", "top"),
    (-12, -12, "right", "top"),
)

#: The polar diagrams' angle labels, pt (6 pt is too small to read in print).
LABEL_PT = 7.0


def _label_places(
    points, texts, per_pt, bounds=None, order=None, obstacles=(), curve=None
) -> list[tuple | None]:
    """(dx, dy in points, ha, va) for a :data:`LABEL_PT` label at each point (x right, y up, data units;
    ``per_pt`` data units per point), or None where no label fits: up and right of the point, or
    the first other corner, near or a little further out, whose box meets no label placed
    before it and stays inside ``bounds`` (x0, y0, x1, y1: the plotting area, so that no label
    covers a tick label). Labels are placed in ``order`` (indices; default: as given), the
    most important first; a point whose label has no room keeps its mark only, as the table
    gives its numbers (crowded labels printed over each other are unreadable: "300, 660" on
    the tick label "4"). Boxes are kept 2 pt apart: two labels side by side without a gap read
    as one number ("210, 570" beside "30": "210, 57030"). ``obstacles``: boxes (x0, y0, x1, y1)
    no label may cover (the pole's mark and letter, the oil hole's line).

    A label goes only where it is nearer its own point than any other point (placed far out, it
    was read as the next mark's).

    ``curve``: (x, y) arrays of points along the drawn curve (:func:`_curve_samples`): a label
    then goes to the first free corner, facing away from the curve's centre, whose box the curve
    does not cross ("90, 450" sat on the loop it labels), or where every free corner is crossed,
    to the one the curve crosses least."""
    placed: list[tuple[float, float, float, float]] = list(obstacles)
    out: list[tuple | None] = [None] * len(points)
    gap = 1.0 * per_pt  # each box grows by half the gap on every side
    centre = None if curve is None else (float(np.mean(curve[0])), float(np.mean(curve[1])))

    def free(box) -> bool:
        if bounds is not None and (
            box[0] < bounds[0] or box[1] < bounds[1] or box[2] > bounds[2] or box[3] > bounds[3]
        ):
            return False
        return all(
            min(box[2], c[2]) <= max(box[0], c[0]) or min(box[3], c[3]) <= max(box[1], c[1])
            for c in placed
        )

    xy = np.asarray(points, dtype=float).reshape(-1, 2)

    def own_nearest(i, inner) -> bool:
        # a label read as another mark's ("330" beside the 480° mark, 1.5 pt nearer it): the box
        # must be nearer its own mark than any other, by half a point at least
        dx = np.maximum.reduce([inner[0] - xy[:, 0], np.zeros(len(xy)), xy[:, 0] - inner[2]])
        dy = np.maximum.reduce([inner[1] - xy[:, 1], np.zeros(len(xy)), xy[:, 1] - inner[3]])
        distance = np.hypot(dx, dy)
        others = np.delete(distance, i)
        return not len(others) or bool(np.min(others) > distance[i] + 0.5 * per_pt)

    def crossings(inner) -> int:
        return (
            0
            if curve is None
            else int(
                np.count_nonzero(
                    (curve[0] > inner[0])
                    & (curve[0] < inner[2])
                    & (curve[1] > inner[1])
                    & (curve[1] < inner[3])
                )
            )
        )

    for i in range(len(points)) if order is None else order:
        (x, y), text = points[i], texts[i]
        # DejaVu Sans digits: 0.64 em wide; a line 1.17 em high
        width, height = len(text) * 0.64 * LABEL_PT * per_pt, 1.17 * LABEL_PT * per_pt
        best = None  # (points of the curve under the label, place, box)
        for place in _candidates(x, y, centre, width, height, per_pt):
            x0 = x + place[0] * per_pt - (width if place[2] == "right" else 0.0)
            y0 = y + place[1] * per_pt - (height if place[3] == "top" else 0.0)
            box = (x0 - gap, y0 - gap, x0 + width + gap, y0 + height + gap)
            if free(box) and own_nearest(i, (x0, y0, x0 + width, y0 + height)):
                under = crossings((x0, y0, x0 + width, y0 + height))
                if best is None or under < best[0]:
                    best = (under, place, box)
                if under == 0:
                    break
        if best is not None:
            placed.append(best[2])
            out[i] = best[1]
    return out


def _candidates(x, y, centre, width, height, per_pt) -> list[tuple]:
    """The places :func:`_label_places` tries, in its order of preference: without a curve the
    corners as listed; with one, the corners facing away from the curve's centre first (near
    before far), where a label more often clears the curve."""
    if centre is None:
        return list(_PLACES)
    away = (x - centre[0], y - centre[1])

    def facing(place) -> float:  # the label box's centre seen from the point, against "away"
        cx = place[0] * per_pt + (-width / 2 if place[2] == "right" else width / 2)
        cy = place[1] * per_pt + (-height / 2 if place[3] == "top" else height / 2)
        return -(cx * away[0] + cy * away[1]) / (math.hypot(cx, cy) * max(math.hypot(*away), 1e-12))

    return (
        sorted(_PLACES[:4], key=facing)
        + sorted(_PLACES[4:], key=facing)
        + sorted(_FAR_PLACES, key=facing)
    )


def _curve_samples(x, y, spacing: float, most: int = 1500) -> tuple[np.ndarray, np.ndarray]:
    """Points along the closed curve (x, y) no more than about ``spacing`` apart (a label box a
    segment crosses between two samples still holds one), from at most ``most`` of its points."""
    keep = max(1, int(math.ceil(len(x) / most)))
    xs, ys = np.append(x[::keep], x[0]), np.append(y[::keep], y[0])
    pieces = np.maximum(
        1, np.ceil(np.hypot(np.diff(xs), np.diff(ys)) / max(spacing, 1e-12)).astype(int)
    )
    pieces = np.minimum(pieces, 50)
    share = np.concatenate([np.arange(n) / n for n in pieces])
    start = np.repeat(np.arange(len(pieces)), pieces)
    return xs[start] + share * (xs[start + 1] - xs[start]), ys[start] + share * (
        ys[start + 1] - ys[start]
    )


def _pole_and_oil_hole(
    pole_z: float, radius: float, oil_deg: float | None, per_pt: float
) -> list[tuple]:
    """Boxes (screen data units: x right, y up = −z) that a polar diagram's labels keep clear of:
    the pole's cross and its letter O (8 pt, 9 pt down and left of it), and points along the oil
    hole's line (not "90, 330, 660" printed over the line, "180" over the O)."""
    boxes = [(-12 * per_pt, -pole_z - 12 * per_pt, 5 * per_pt, -pole_z + 5 * per_pt)]
    if oil_deg is not None:
        psi = math.radians(oil_deg)
        for share in np.linspace(0.15, 1.0, 7):
            x, y = share * radius * math.sin(psi), -(pole_z + share * radius * math.cos(psi))
            boxes.append((x - 4 * per_pt, y - 4 * per_pt, x + 4 * per_pt, y + 4 * per_pt))
    return boxes
