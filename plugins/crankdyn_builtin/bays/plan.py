"""The engine's scheme in plan (ГОСТ 2.770 symbols): the crankshaft along the sheet with its
cranks numbered from the free end and drawn on their sides of the axis, its main journals as
supports, the cylinders of every bank in rows beside the shaft (bores as circles; a boxer's
horizontal cylinders as their outlines), the crank spacing a dimensioned, the free end
and the power take-off end named, and the direction of rotation seen from the free end.

Everything drawn comes from the run's layout (:func:`plan_data`): the cylinders' banks and
cranks, the banks' axis angles, the crank spacing and the side-by-side rods' offset."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from crankdyn.report.figures import new_figure

INK = "0.1"
DIMENSION = "0.35"
#: a crank spacing drawn where the scene gives none, bores (a typical in-line spacing)
SPACING_PER_BORE = 1.2


@dataclass(frozen=True)
class PlanCylinder:
    label: str  # as the report prints it (1Л)
    bank: int
    crank: int  # 0-based, from the free end
    position_m: float  # along the shaft from crank 1's plane


@dataclass(frozen=True)
class PlanTexts:
    crank: str  # "колено {number}" already without the number: "колено"
    free_end: str
    take_off_end: str
    rotation: str  # "вид со свободного конца"
    banks: tuple[str, ...]  # each bank's row name, "" for none
    spacing: str  # "a = 106 мм" or "a"
    offset: str  # the rods' offset's dimension text, "" for none


def plan_data(layout, bore_m: float, spacing_m: float | None, rod_offset_m: float) -> dict:
    """What the plan draws, from the engine's layout (:class:`crankdyn.physics.layout.
    EngineLayout`): each cylinder's label, bank and crank, and its place along the shaft (bank 0
    nearest the free end where the rods lie side by side, ``rod_offset_m`` apart), the banks'
    axis angles, the crank spacing (None: not given) and the bore, m."""
    banks = sorted({c.bank for c in layout.cylinders})
    offsets = {b: (b - 0.5 * (len(banks) - 1)) * rod_offset_m for b in banks}
    pitch = spacing_m if spacing_m else SPACING_PER_BORE * bore_m
    if layout.layout == "boxer":
        offsets = dict.fromkeys(banks, 0.0)
    return {
        "layout": layout.layout,
        "cranks": layout.cranks,
        # each crank's lag behind crank 1 in the direction of rotation, deg
        "crank_lags_deg": [float(lag) for lag in layout.crank_lag_deg],
        "spacing_m": spacing_m,
        "bore_m": bore_m,
        "rod_offset_m": rod_offset_m if len(banks) > 1 and layout.layout != "boxer" else 0.0,
        "bank_axes_deg": {
            str(b): float(next(c.axis_deg for c in layout.cylinders if c.bank == b)) for b in banks
        },
        "cylinders": [
            {
                "label": c.label,
                "bank": c.bank,
                "crank": c.bay,
                "position_m": c.bay * pitch + offsets[c.bank],
            }
            for c in layout.cylinders
        ],
    }


def row_sides(bank_axes_deg: dict[str, float]) -> dict[int, float]:
    """Each bank's side of the shaft (+: above it on the sheet, -: below, 0: straight over it,
    as its axis leans), the plan seen from above with the free end on the left: a bank leaning
    left when seen from the free end lies above the shaft. A single bank is above the shaft."""
    if len(bank_axes_deg) == 1:
        return {int(b): 1.0 for b in bank_axes_deg}
    angles = {int(b): math.radians(a) for b, a in bank_axes_deg.items()}
    x = sum(math.cos(a) for a in angles.values())
    y = sum(math.sin(a) for a in angles.values())
    # "up": the banks' mean direction; of opposed banks (a boxer, an X) the first two's bisector
    middle = math.atan2(y, x) if math.hypot(x, y) > 1e-6 else (angles[0] + angles[1]) / 2
    sides = {b: -math.sin(a - middle) for b, a in angles.items()}
    largest = max(abs(s) for s in sides.values())
    return {b: 0.0 if abs(s) < 1e-6 else s / largest for b, s in sides.items()}


def row_centres(bank_axes_deg: dict[str, float], row: float, pitch: float) -> dict[int, float]:
    """Each bank's row's centre across the sheet (mm from the shaft's axis): the banks above the
    shaft (:func:`row_sides`; one straight over it with them) stacked up from ``row``, the
    nearest-to-vertical first, ``pitch`` apart; those below it stacked down alike."""
    sides = row_sides(bank_axes_deg)
    above = sorted((b for b, s in sides.items() if s >= 0), key=lambda b: (sides[b], b))
    below = sorted((b for b, s in sides.items() if s < 0), key=lambda b: (-sides[b], b))
    centres = {b: row + k * pitch for k, b in enumerate(above)}
    centres.update({b: -row - k * pitch for k, b in enumerate(below)})
    return centres


def throw_heights(lags_deg, throw: float) -> list[float]:
    """Each crank's throw as drawn across the sheet: its projection on the plane of crank 1
    (``throw`` cos lag: crank 1 up, a crank at 180° down), at least a third of ``throw`` long so
    that a crank at 90° still shows its side (the lags are printed beside the numbers)."""
    heights = []
    for lag in lags_deg:
        c, s = math.cos(math.radians(lag)), math.sin(math.radians(lag))
        side = math.copysign(1.0, c) if abs(c) > 1e-9 else math.copysign(1.0, s)
        heights.append(side * throw * max(abs(c), 1.0 / 3.0))
    return heights


#: the crank numbers' two lines (number, lag) at 8 pt, cm on the sheet
CRANK_LABEL_CM = 0.8
WIDTH_CM = 16.0
#: where the free end's name ends, in units of a from crank 1: left of the first support
FREE_END_RIGHT = -0.62
#: the width of a character of the plan's 8-pt words on the sheet, cm (DejaVu Sans, with room)
CHARACTER_CM = 0.19


def _text_cm(text: str) -> float:
    """About how wide ``text``'s longest line is at 8 pt on the sheet, cm."""
    return CHARACTER_CM * max(len(line) for line in text.split("\n"))


def plan_figure(data: dict, texts: PlanTexts):
    """The plan (ГОСТ 2.770): the shaft as a thick line with its throws (each drawn on its side
    of the axis, :func:`throw_heights`), supports hatched under its main journals, the cylinders
    (bores as circles; a boxer's horizontal cylinders as their outlines) with their labels, crank
    spacing a dimensioned between cranks 1 and 2, the crank numbers with their lags under the
    shaft, the ends named and the rotation seen from the free end."""
    bore = data["bore_m"] * 1e3
    a = (data["spacing_m"] or SPACING_PER_BORE * data["bore_m"]) * 1e3
    cranks = data["cranks"]
    throw = 0.22 * a  # the throw drawn up from the axis
    lags = data.get("crank_lags_deg") or [0.0] * cranks
    heights = throw_heights(lags, throw)
    start, end = -0.5 * a - 0.45 * a, (cranks - 0.5) * a + 0.6 * a
    # the free end's name right of the rotation's sign, left of the first support: the sign
    # moves left as far as the name needs at the sheet's scale (which depends on where it is)
    rotation_x = start - 0.75 * a
    for _ in range(3):
        xlim = (rotation_x - 0.5 * a, end + 0.35 * a)
        units_per_cm = (xlim[1] - xlim[0]) / WIDTH_CM
        name_left = FREE_END_RIGHT * a - _text_cm(texts.free_end) * units_per_cm
        rotation_x = min(start - 0.75 * a, name_left - 0.5 * a)
    xlim = (rotation_x - 0.5 * a, end + 0.35 * a)
    units_per_cm = (xlim[1] - xlim[0]) / WIDTH_CM
    # the crank numbers under the lowest throw and the supports, two lines high
    label_top = -max(0.2 * a, -min(heights) + 0.06 * a)
    label_bottom = label_top - CRANK_LABEL_CM * units_per_cm
    boxer = data.get("layout") == "boxer"
    length = 1.4 * bore if boxer else bore  # a row's depth across the sheet
    row = throw + 0.25 * a + 0.5 * length  # a row's centre from the axis
    rows = row_centres(data["bank_axes_deg"], row, length + 0.25 * a)
    below = max(0.0, 0.5 * length - row - label_bottom + 0.1 * a)  # rows under the labels
    rows = {b: y - below if y < 0 else y for b, y in rows.items()}
    bottom = min(min(rows.values()) - 0.5 * length, label_bottom - 0.05 * a)
    top = max(rows.values()) + 0.5 * length
    ylim = (bottom - 0.55 * a, top + (0.4 * a if texts.offset else 0.2 * a))
    aspect = (ylim[1] - ylim[0]) / (xlim[1] - xlim[0])
    fig, ax = new_figure(WIDTH_CM, min(WIDTH_CM * aspect + 0.6, 14.0))
    ax.set_aspect("equal")
    ax.axis("off")
    _shaft(ax, a, heights, start, end)
    _supports(ax, a, cranks)
    _cylinders(ax, data, rows, bore, length if boxer else None)
    _row_names(ax, data, texts.banks, rows, bore)
    # the word with crank 1 only where "crank k" would not fit between two supports
    spaced = _text_cm(f"{texts.crank} {cranks}") < 0.8 * a / units_per_cm
    _crank_numbers(ax, a, cranks, texts.crank, label_top, data.get("crank_lags_deg"), spaced)
    # a's text between the extension lines where it fits, else beside the second one
    inside = _text_cm(texts.spacing) < 0.85 * a / units_per_cm
    _spacing_dimension(ax, a, heights[:2], bottom - 0.25 * a, texts.spacing, inside)
    if texts.offset:
        _offset_dimension(ax, data, rows, bore, texts.offset)
    _ends(ax, start, end, a, texts)
    _rotation(ax, rotation_x, 0.0, 0.22 * a, texts.rotation)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    return fig


def _shaft(ax, a, heights, start, end) -> None:
    """The crankshaft's axis line and its throws (webs and pin, each ``heights`` across the
    sheet) as one thick polyline."""
    web = 0.18 * a  # half the throw's length along the shaft
    xs, ys = [start], [0.0]
    for k, height in enumerate(heights):
        x = k * a
        xs += [x - web, x - web, x + web, x + web]
        ys += [0.0, height, height, 0.0]
    xs.append(end)
    ys.append(0.0)
    ax.plot(xs, ys, color=INK, lw=2.2, solid_joinstyle="miter", zorder=3)
    ax.plot([start - 0.1 * a, end + 0.1 * a], [0, 0], color=INK, lw=0.5, ls=(0, (8, 2, 1, 2)))


def _supports(ax, a, cranks) -> None:
    """A main journal's support between neighbouring cranks and at both ends: a bearing block
    around the axis on a hatched base (ГОСТ 2.770)."""
    from matplotlib.collections import LineCollection  # lazy: heavy optional import
    from matplotlib.patches import Rectangle  # lazy: heavy optional import

    half, depth = 0.07 * a, 0.1 * a
    strokes = []
    for j in range(cranks + 1):
        x = (j - 0.5) * a
        ax.add_patch(
            Rectangle(
                (x - half, -0.5 * depth), 2 * half, depth, fill=False, ec=INK, lw=1.0, zorder=4
            )
        )
        base = -0.5 * depth - 0.08 * a
        ax.plot([x, x], [-0.5 * depth, base], color=INK, lw=1.0)
        ax.plot([x - 1.6 * half, x + 1.6 * half], [base, base], color=INK, lw=1.0)
        for s in np.linspace(x - 1.6 * half, x + 1.2 * half, 5):
            strokes.append([(s, base), (s + 0.4 * half, base - 0.4 * half)])
    ax.add_collection(LineCollection(strokes, colors=[INK], linewidths=0.6))


def _cylinders(ax, data, rows, bore, length=None) -> None:
    """Each cylinder in its bank's row with its label in it (gid: the label): its bore as a
    circle, or, with ``length`` (a boxer's cylinders, horizontal: seen from above from the side),
    its outline ``length`` deep across the sheet."""
    from matplotlib.patches import Circle, Rectangle  # lazy: heavy optional import

    for c in data["cylinders"]:
        x, y = c["position_m"] * 1e3, rows[c["bank"]]
        if length is None:
            ax.add_patch(
                Circle((x, y), 0.5 * bore, fill=False, ec=INK, lw=1.4, zorder=5, gid="plan-bore")
            )
            reach = 0.6 * bore
        else:
            corner = (x - 0.5 * bore, y - 0.5 * length)
            outline = Rectangle(corner, bore, length, fill=False, ec=INK, lw=1.4, zorder=5)
            outline.set_gid("plan-cylinder-outline")
            ax.add_patch(outline)
            reach = 0.5 * length + 0.1 * bore
        ax.plot([x, x], [y - reach, y + reach], color=INK, lw=0.4, ls=(0, (8, 2, 1, 2)))
        text = ax.text(
            x,
            y,
            c["label"],
            ha="center",
            va="center",
            fontsize=9,
            zorder=6,
            bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none"},
        )
        text.set_gid("plan-cylinder")


def _row_names(ax, data, names, rows, bore) -> None:
    """A bank's name ("Л – левый ряд") left of its row's first cylinder."""
    for bank, name in enumerate(names):
        if name and bank in rows:
            first = min(c["position_m"] for c in data["cylinders"] if c["bank"] == bank) * 1e3
            ax.text(
                first - 0.65 * bore,
                rows[bank],
                name,
                ha="right",
                va="center",
                fontsize=8,
                color="0.15",
                gid="plan-bank",
            )


def _crank_numbers(ax, a, cranks, word, top, lags_deg=None, spaced: bool = True) -> None:
    """The cranks' numbers from the free end, each with its lag behind crank 1 on a second line,
    under the axis (from ``top`` down) between the supports; the word ("crank") with each number,
    or, not ``spaced``, with crank 1's alone ("crank 1", "2", "3", …), which then ends at its
    crank's plane, so that the word reaches towards the free end and not under crank 2."""
    for k in range(cranks):
        lag = f"\n({lags_deg[k]:.4g}°)" if lags_deg else ""
        name = f"{word} {k + 1}" if spaced or k == 0 else str(k + 1)
        leading = not spaced and k == 0
        ax.text(
            0.08 * a if leading else k * a,  # the number "1" over the plane
            top,
            f"{name}{lag}".strip(),
            ha="right" if leading else "center",
            multialignment="right" if leading else "center",
            va="top",
            fontsize=8,
            linespacing=1.1,
            bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none"},
            zorder=6,
            gid="plan-crank",
        )


def _spacing_dimension(ax, a, heights, y, text, inside: bool = True) -> None:
    """a between the planes of cranks 1 and 2: extension lines from their pins down to the
    dimension line, its text above it, or beside the second extension line where it is wider
    than a (not ``inside``) (gid ``plan-spacing``: the arrow, whose ends are a apart)."""
    for x, height in zip((0.0, a), heights, strict=False):
        ax.plot([x, x], [height, y - 0.05 * a], color=DIMENSION, lw=0.5, ls=(0, (8, 2, 1, 2)))
    arrow = ax.annotate(
        "",
        xy=(a, y),
        xytext=(0.0, y),
        arrowprops={
            "arrowstyle": "<|-|>",
            "color": DIMENSION,
            "lw": 0.6,
            "shrinkA": 0,
            "shrinkB": 0,
            "mutation_scale": 7,
        },
    )
    arrow.set_gid("plan-spacing")
    ax.text(
        0.5 * a if inside else 1.08 * a,
        y + 0.02 * a if inside else y,
        text,
        ha="center" if inside else "left",
        va="bottom" if inside else "center",
        fontsize=8,
        color="0.15",
        gid="plan-spacing-text",
    )


def _offset_dimension(ax, data, rows, bore, text) -> None:
    """The side-by-side rods' offset: the axes of crank 1's cylinders of the first two banks
    (gid ``plan-offset``), dimensioned above the upper row."""
    first = [c for c in data["cylinders"] if c["crank"] == 0]
    if len(first) < 2:
        return
    xs = sorted(c["position_m"] * 1e3 for c in first)[:2]
    top = max(rows.values()) + 0.5 * bore + 0.12 * bore
    y = top + 0.12 * bore
    for x in xs:
        ax.plot([x, x], [top - 0.1 * bore, y + 0.05 * bore], color=DIMENSION, lw=0.5)
    gap = xs[1] - xs[0]
    reach = 0.35 * bore
    for x, sign in ((xs[0], -1), (xs[1], 1)):  # arrows outside: the offset is small
        ax.annotate(
            "",
            xy=(x, y),
            xytext=(x + sign * reach, y),
            arrowprops={
                "arrowstyle": "-|>",
                "color": DIMENSION,
                "lw": 0.6,
                "shrinkA": 0,
                "shrinkB": 0,
                "mutation_scale": 7,
            },
        )
    ax.plot([xs[0], xs[1]], [y, y], color=DIMENSION, lw=0.6, gid="plan-offset")
    ax.text(xs[1] + reach + 0.02 * gap, y, text, ha="left", va="center", fontsize=8, color="0.15")


def _ends(ax, start, end, a, texts) -> None:
    """The free end's name left of the shaft; the take-off end: a flywheel's rim and its name."""
    from matplotlib.patches import Rectangle  # lazy: heavy optional import

    ax.text(FREE_END_RIGHT * a, 0.06 * a, texts.free_end, ha="right", va="bottom", fontsize=8)
    rim = 0.55 * a
    ax.add_patch(
        Rectangle(
            (end - 0.12 * a, -rim),
            0.12 * a,
            2 * rim,
            fc="0.86",  # shaded as a moving part: hatching marks a fixed one (ГОСТ 2.770)
            ec=INK,
            lw=1.4,
            zorder=4,
        )
    )
    ax.text(end - 0.06 * a, -rim - 0.05 * a, texts.take_off_end, ha="center", va="top", fontsize=8)


def _rotation(ax, x, y, radius, text) -> None:
    """The shaft seen from the free end: a circle and a clockwise arrow around it, captioned."""
    from matplotlib.patches import Circle, FancyArrowPatch  # lazy: heavy optional import

    ax.add_patch(Circle((x, y), 0.35 * radius, fill=False, ec=INK, lw=1.0))
    ax.plot([x - 0.5 * radius, x + 0.5 * radius], [y, y], color=INK, lw=0.4)
    ax.plot([x, x], [y - 0.5 * radius, y + 0.5 * radius], color=INK, lw=0.4)
    begin = (x + radius * math.cos(math.radians(150)), y + radius * math.sin(math.radians(150)))
    finish = (x + radius * math.cos(math.radians(-30)), y + radius * math.sin(math.radians(-30)))
    ax.add_patch(
        FancyArrowPatch(
            begin,
            finish,
            connectionstyle="arc3,rad=-0.55",
            arrowstyle="-|>",
            mutation_scale=8,
            color=INK,
            lw=0.8,
            gid="plan-rotation",
        )
    )
    ax.text(x, y + 1.3 * radius, "ω", ha="center", va="bottom", fontsize=9, style="italic")
    ax.text(x, y - 1.4 * radius, text, ha="center", va="top", fontsize=7, color="0.15", wrap=True)
