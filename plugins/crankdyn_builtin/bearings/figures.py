"""The ``bearings`` stage's figures, drawn with matplotlib."""

from __future__ import annotations

import math
import re
from functools import partial

import numpy as np
from markupsafe import Markup

from crankdyn.report.figures import crank_angle_axis, new_figure
from crankdyn_builtin.bearings.compute import rod_bearing_name
from crankdyn_builtin.bearings.worked import (
    journal_name,
)

from .labels import LABEL_PT, _coinciding, _curve_samples, _label_places, _pole_and_oil_hole


def _polar(
    ctx,
    t_Pa,
    z_Pa,
    angle,
    pole_z,
    title,
    oil_deg,
    diameter_scale,
    labels_every,
    name,
    caption,
    axes=("t", "z"),
    see=("bearings.see_polar", {}),
):
    """A polar load diagram's markup, and whether it is narrow enough to stand beside another;
    ``axes``: the names of its horizontal and vertical components (crank axes t, z unless the
    diagram is drawn in the rod's or the engine's axes); ``see``: the key and placeholders of
    the sentence announcing it, which names the journal or bearing (two diagrams side by side
    are not each announced as just "the vector diagram")."""
    width_cm = _polar_size(t_Pa / 1e6, z_Pa / 1e6, pole_z, diameter_scale)[0]
    return ctx.figure(
        partial(
            _polar_drawing,
            ctx.t,
            t_Pa,
            z_Pa,
            angle,
            pole_z,
            title,
            oil_deg,
            diameter_scale,
            labels_every,
            axes,
        ),
        caption,
        name,
        see=see[0],
        see_params=see[1],
    ), width_cm <= HALF_WIDTH_CM


#: A diagram at most this wide (cm) stands beside the next one: two tall, narrow diagrams on a
#: page instead of one on each, with half of it empty.
HALF_WIDTH_CM = 8.0

#: A polar diagram's height, cm, and a tall one's at most (with its caption and the sentence
#: above a pair it still shares a page with text; the Word file's pages keep each figure with its
#: caption at these sizes).
POLAR_HEIGHT_CM = 12.0
POLAR_HEIGHT_MAX_CM = 13.0
#: The least height of a flat polar diagram's figure, cm (its title, axis and tick labels).
POLAR_HEIGHT_MIN_CM = 5.0


def _polar_extent(t, z, pole_z, diameter_scale) -> tuple[float, float, float, float]:
    """(span, the journal circle's radius, the t and z ranges shown) of a polar diagram (MPa)."""
    span = max(np.max(np.abs(t)), np.max(np.abs(z)), abs(pole_z), 1e-9)
    radius = diameter_scale * span
    shown_t = max(np.max(t), radius) - min(np.min(t), -radius)
    shown_z = max(np.max(z), pole_z + radius) - min(np.min(z), pole_z - radius)
    return span, radius, shown_t, shown_z


def _polar_size(t, z, pole_z, diameter_scale) -> tuple[float, float]:
    """(width, height) in cm of a polar diagram of ``t``, ``z`` (MPa) around the pole: equal scales
    on both axes; a tall diagram (a crank pin's or a main journal's, far from its pole) gets a
    taller figure (at most :data:`POLAR_HEIGHT_MAX_CM`) only as wide as its plot needs (with the
    ticks and labels ≈ 2.4 cm), a wide one a wider figure only as tall as its plot needs."""
    return _size_for(*_polar_extent(t, z, pole_z, diameter_scale)[2:])


def _size_for(shown_t: float, shown_z: float) -> tuple[float, float]:
    """(width, height) in cm of a polar diagram showing these t and z ranges (:func:`_polar_size`)."""
    aspect = max(shown_z, 1e-9) / max(shown_t, 1e-9)
    if aspect < 1:
        width = min(16.0, POLAR_HEIGHT_CM / math.sqrt(aspect))
        # only as tall as the plot at that width needs (a flat one at the full width is a strip:
        # a figure of the usual height would leave most of the page around it empty)
        plot = 1.1 * (width - 2.0) * aspect + 2.2
        return width, min(POLAR_HEIGHT_CM, max(POLAR_HEIGHT_MIN_CM, plot))
    height = min(POLAR_HEIGHT_MAX_CM, POLAR_HEIGHT_CM * math.sqrt(aspect))
    return min(12.0, max(7.0, 1.1 * (height - 2.2) / aspect + 2.4)), height


def _polar_drawing(
    translator, t_Pa, z_Pa, angle, pole_z, title, oil_deg, diameter_scale, labels_every, axes
):
    """The polar load diagram's figure (:func:`_polar`)."""
    t, z = t_Pa / 1e6, z_Pa / 1e6
    span, radius, shown_t, shown_z = _polar_extent(t, z, pole_z, diameter_scale)
    width_cm, height_cm = _size_for(shown_t, shown_z)
    fig, ax = new_figure(width_cm, height_cm)
    ax.plot(np.append(t, t[0]), np.append(z, z[0]), color="C0", lw=1.2)  # the closed curve
    step = angle[1] - angle[0]
    every = max(int(round(labels_every / step)), 1)
    ax.plot(
        t[::every], z[::every], "o", ms=2.5, color="C3", linestyle="none"
    )  # one artist for all marks
    ax.axhline(0, color="0.3", lw=0.6)
    ax.axvline(0, color="0.3", lw=0.6)
    # the axes take the figure less about 2 cm for the tick labels, axis labels and title; with
    # equal aspect the range that fills its box sets the scale (matplotlib's 5 % margins added);
    # z grows downwards on the page
    box_pt = ((width_cm - 2.0) * 72 / 2.54, (height_cm - 2.2) * 72 / 2.54)
    per_pt = 1.1 * max(shown_t / box_pt[0], shown_z / box_pt[1], 1e-12)
    _angle_labels(ax, translator, (t, z), angle, every, span, per_pt, (pole_z, radius, oil_deg))
    _pole_and_journal(ax, pole_z, radius, oil_deg)
    margin = 0.05 * shown_t  # matplotlib's autoscale margins
    left, right = min(np.min(t), -radius) - margin, max(np.max(t), radius) + margin
    _fitting_ticks(ax.xaxis, (left, right), per_pt)
    ax.set_aspect("equal")
    ax.invert_yaxis()  # +z points from the pin towards the shaft axis: drawn downwards as in fig. 17
    ax.set_xlabel(f"{axes[0]}, " + translator("unit.MPa"))
    ax.set_ylabel(f"{axes[1]}, " + translator("unit.MPa"))
    ax.set_title(title, fontsize=9)
    return fig


#: The room a tick label of a polar diagram takes along the horizontal axis, gap included (pt):
#: "−0,25" at 9 pt is about 27 pt wide.
TICK_ROOM_PT = 34.0


def _fitting_ticks(axis, limits: tuple[float, float], per_pt: float) -> None:
    """Ticks on a narrow horizontal ``axis`` spanning ``limits`` (MPa, drawn at ``per_pt`` MPa a
    point): as many as their labels fit side by side, at least two; where even two do not fit
    upright (a tall, narrow diagram: a main bearing loaded mostly along one axis) the labels
    are turned a quarter, instead of being printed over one another or left with one."""
    from matplotlib.ticker import MaxNLocator  # lazy: heavy optional import (matplotlib)

    low, high = limits
    length_pt = (high - low) / per_pt
    if length_pt >= 4 * TICK_ROOM_PT:  # room for matplotlib's own choice
        return
    locator = MaxNLocator(
        nbins=max(2, int(length_pt // TICK_ROOM_PT)), steps=[1, 2, 2.5, 5, 10], min_n_ticks=2
    )
    axis.set_major_locator(locator)
    ticks = [v for v in locator.tick_values(low, high) if low <= v <= high]
    if len(ticks) >= 2 and (ticks[1] - ticks[0]) / per_pt < _label_room_pt(ticks):
        axis.set_tick_params(labelrotation=90)


#: The width of a digit (or a sign) of a 9 pt tick label and the least gap between two labels, pt.
DIGIT_PT, LABEL_GAP_PT = 5.0, 7.0


def _label_room_pt(ticks) -> float:
    """The room the widest of these ticks' labels takes along the axis, gap included (pt):
    "−1" needs far less than :data:`TICK_ROOM_PT`, which is sized for "−0,25"."""
    return max(len(f"{round(v, 6):g}") for v in ticks) * DIGIT_PT + LABEL_GAP_PT


def _angle_labels(ax, translator, curve_tz, angle, every, span, per_pt, journal) -> None:
    """Label every marked point of the diagram with its crank angle where a label fits
    (``journal``: the pole's z, the journal's drawn radius and the oil hole's angle)."""
    t, z = curve_tz
    pole_z, radius, oil_deg = journal
    step = angle[1] - angle[0]
    # Points that (nearly) coincide, as alpha and alpha + 360 deg do where inertia dominates, get
    # one label "210, 570" instead of two printed over each other.
    groups = _coinciding(t[::every], z[::every], 0.03 * span)
    texts = [
        ", ".join(translator.angle(angle[k * every], step) for k in same) for _, same in groups
    ]
    anchors = [(t[i * every], z[i * every]) for i, _ in groups]
    screen = [(x, -y) for x, y in anchors]
    bounds = _screen_bounds(t, z, pole_z, radius)
    order = _label_order(anchors, groups, angle, every, pole_z)
    obstacles = _pole_and_oil_hole(pole_z, radius, oil_deg, per_pt)
    curve = _curve_samples(t, -z, 2.0 * per_pt)  # screen coordinates, as the labels'
    for (x, y), text, place in zip(
        anchors,
        texts,
        _label_places(screen, texts, per_pt, bounds, order, obstacles, curve),
        strict=True,
    ):
        if place is not None:
            dx, dy, ha, va = place
            ax.annotate(
                text,
                (x, y),
                fontsize=LABEL_PT,
                xytext=(dx, dy),
                textcoords="offset points",
                ha=ha,
                va=va,
                # a point of the curve, inside the axes' limits (autoscaled to the curve): not
                # asked whether it is inside each time the label is measured or drawn
                annotation_clip=False,
            )


def _screen_bounds(t, z, pole_z: float, radius: float) -> tuple[float, float, float, float]:
    """The drawn area (t low, -z high, t high, -z low) in screen coordinates, with matplotlib's
    own 5 % margins around the curve and the journal's circle."""
    low_t, high_t = min(np.min(t), -radius), max(np.max(t), radius)
    low_z, high_z = min(np.min(z), pole_z - radius), max(np.max(z), pole_z + radius)
    margin_t, margin_z = (
        0.05 * (high_t - low_t),
        0.05 * (high_z - low_z),
    )  # matplotlib's own margins
    return (low_t - margin_t, -(high_z + margin_z), high_t + margin_t, -(low_z - margin_z))


def _label_order(anchors, groups, angle, every, pole_z: float) -> list[int]:
    """The order labels are placed in: the largest load's first, then the dead centres'
    (multiples of 90 deg), then the rest."""
    q = np.hypot([a[0] for a in anchors], [a[1] - pole_z for a in anchors])
    peak = int(np.argmax(q)) if len(q) else 0

    def rank(g: int):
        angles = [angle[k * every] for k in groups[g][1]]
        return (g != peak, not any(abs(a % 90.0) < 1e-9 for a in angles), g)

    return sorted(range(len(groups)), key=rank)


def _pole_and_journal(ax, pole_z: float, radius: float, oil_deg) -> None:
    """Draw the journal's circle about the pole O and the oil hole's direction."""
    circle = np.linspace(0, 2 * np.pi, 200)
    # The pole O, where the journal sits (shifted from O1 by the constant centrifugal load).
    ax.plot(radius * np.sin(circle), pole_z + radius * np.cos(circle), color="0.2", lw=0.8)
    ax.plot([0], [pole_z], "k+", ms=8)
    ax.annotate(
        "O", (0, pole_z), xytext=(-9, -9), textcoords="offset points", fontsize=8, style="italic"
    )
    if oil_deg is not None:
        psi = np.radians(oil_deg)
        ax.plot(
            [0, radius * np.sin(psi)], [pole_z, pole_z + radius * np.cos(psi)], color="C2", lw=2
        )
        ax.plot(radius * np.sin(psi), pole_z + radius * np.cos(psi), "o", color="C2", ms=5)


def _side_by_side(groups: list) -> list:
    """The diagrams' markup, each two narrow ones of a group (a crank pin and its rod bearing, the
    rod bearings side by side on one pin, a main journal and its bearing) in one row."""
    out = []
    for pairs in groups:
        for k in range(0, len(pairs) - 1, 2):
            (first, narrow_first), (second, narrow_second) = pairs[k], pairs[k + 1]
            together = narrow_first and narrow_second
            out += [_figure_row(first, second)] if together else [first, second]
        out += [markup for markup, _ in pairs[len(pairs) - len(pairs) % 2 :]]
    return out


_SEE = re.compile(r'<p class="see">(.*?)</p>', flags=re.S)


def _figure_row(first, second) -> Markup:
    """Two figures side by side, announced together in one paragraph above the row (each one's
    sentence in its own half-width column takes two lines, and the row then does not fit under
    a chapter's text: a 27 %-full page, and the captions at different heights)."""
    sentences = " ".join(
        m.group(1) for block in (first, second) for m in [_SEE.search(str(block))] if m
    )
    blocks = "".join(_SEE.sub("", str(block), count=1) for block in (first, second))
    return Markup(
        f'<div class="figure-row-block"><p class="see">{sentences}</p>'
        f'<div class="figure-row">{blocks}</div></div>'
    )


def _wear_figure(ctx, wear, r):
    """Wear diagram of the drawn crank pin (load spread over +-60 deg around each contact point)."""
    k = r["drawn_pins"][0]
    single = len(r["crank_pins"]) == 1
    caption = _one_of(ctx.t, "bearings.wear_caption", k, single)
    return ctx.figure(
        partial(_wear_drawing, wear, r, k),
        caption,
        f"wear_pin{k}",
        see="bearings.see_wear_pin",
        see_params=_crank_number(k, single),
    )


def _wear_drawing(wear, r, k):
    """The wear diagram's figure (:func:`_wear_figure`)."""
    fig, ax = new_figure(10, 10, subplot_kw={"projection": "polar"})
    ax.set_theta_zero_location(
        "S"
    )  # +z (towards the shaft axis) drawn downwards, as the polar diagrams
    ax.set_theta_direction(1)
    psi = np.radians(wear["surface_angle_deg"])
    load = wear[f"pin{k}_wear_N"]
    # as the textbook draws it: the journal's circle, the wear laid inwards from it (the largest
    # to 0.6 of the radius), the oil hole where the circle is least worn
    depth = 0.6 * load / max(float(load.max()), 1e-300)
    closed = np.append(psi, psi[0])
    ax.fill_between(closed, 1.0 - np.append(depth, depth[0]), 1.0, color="C1", alpha=0.5, lw=0)
    ax.plot(np.linspace(0, 2 * np.pi, 361), np.ones(361), color="0.2", lw=1.0)
    oil = np.radians(r["crank_pins"][k - 1]["oil_hole_deg"])
    ax.plot([oil, oil], [0.85, 1.12], color="C2", lw=2)
    # the crank's axes the angles are counted in, as the polar diagrams draw them (without them
    # 0° and +z are nowhere): z towards the shaft axis, t in the direction of rotation
    for angle, name in ((0.0, "$z$"), (np.pi / 2, "$t$")):
        ax.annotate(
            "",
            xy=(angle, 0.25),
            xytext=(0.0, 0.0),
            arrowprops={"arrowstyle": "-|>", "color": "0.25", "lw": 1.0},
        )
        ax.text(
            angle, 0.33, name, ha="center", va="center", fontsize=10
        )  # inside the wear (from 0.4 in)
    ax.set_ylim(0, 1.15)
    ax.set_yticks([])
    ax.grid(False, axis="y")
    ax.spines["polar"].set_visible(False)  # the journal's circle is the only circle
    return fig


def _crank_number(k, single: bool) -> dict:
    """``{k}`` of a sentence naming crank (pin) ``k`` ("на шатунну шийку{k}"): " 1", or nothing
    when there is one crank."""
    return {"k": "" if single else f" {k}", "the": "the " if single else ""}


def _one_of(t, key: str, k, single: bool, **values) -> str:
    """The catalog text ``key`` for crank (pin) ``k``, without the number when there is one crank."""
    return re.sub(
        r"\s+([:;,.)])",
        r"\1",
        # "the crank pin" of one crank, "crank pin 2" of several (an English article)
        re.sub(r"\s+", " ", t(key, k="" if single else k, the="the " if single else "", **values)),
    ).strip()


def _unrolled_figure(ctx, f, r, angle, single: bool):
    """The unrolled diagrams: the load's magnitude on the drawn crank pins and main journals."""
    return ctx.figure(
        partial(_unrolled_drawing, ctx.t, ctx.cycle_deg, f, r, angle, single),
        ctx.t("bearings.unrolled_caption"),
        "unrolled",
        see="bearings.see_unrolled",
    )


def _unrolled_drawing(t, cycle_deg, f, r, angle, single: bool):
    """The unrolled diagrams' figure (:func:`_unrolled_figure`)."""
    fig, ax = new_figure(16, 8)
    for k in r["drawn_pins"]:
        ax.plot(
            angle,
            np.hypot(f[f"pin{k}_t_Pa"], f[f"pin{k}_z_Pa"]) / 1e6,
            label=_one_of(t, "bearings.pin_label", k, single),
        )
    for j in r["drawn_journals"]:
        label = journal_name(r["main_journals"][j - 1])
        ax.plot(
            angle,
            np.hypot(f[f"journal{j - 1}_t_Pa"], f[f"journal{j - 1}_z_Pa"]) / 1e6,
            label=t("bearings.journal_label", label=label),
        )
    crank_angle_axis(ax, cycle_deg, t("axis.crank_angle"))
    # the equations' symbols of the journals drawn, by name (0–1, 1–2), not the general R_{i,i+1}
    names = [journal_name(r["main_journals"][j - 1]) for j in r["drawn_journals"]]
    journal = ", ".join(f"|R_{{{name}}}|" for name in names) if names else "|R_{i,i+1}|"
    ax.set_ylabel(f"|q_pin|, {journal}, " + t("unit.MPa"))
    ax.legend(loc="upper right", fontsize=8)
    return fig


def _shared_pins(ctx, r) -> bool:
    """One rod on each crank pin (in-line engines: False) or several sharing one (V, W, radial)."""
    return ctx.scene is not None and ctx.scene.engine.cylinders > len(r["crank_pins"])


def _polar_diagrams(ctx, r, f, angle, single: bool) -> list:
    """(markup, narrow) of each polar diagram, in groups that may share rows: a crank pin and its
    rod bearing (the pin alone and its rod bearings side by side together when several share it),
    a main journal and its bearing."""
    t = ctx.t
    labels_every = 30.0 if ctx.cycle_deg > 360 else 15.0
    c_rod = r["centrifugal_rod_Pa"] / 1e6
    pin_caption = "bearings.pin_caption_shared" if _shared_pins(ctx, r) else "bearings.pin_caption"
    groups = []
    for k in r["drawn_pins"]:
        pin = r["crank_pins"][k - 1]
        pin_diagram = _polar(
            ctx,
            f[f"pin{k}_t_Pa"],
            f[f"pin{k}_z_Pa"] - r["centrifugal_rod_Pa"],
            angle,
            -c_rod,
            _one_of(t, "bearings.pin_title", k, single),
            pin["oil_hole_deg"],
            0.12,
            labels_every,
            f"pin{k}",
            _one_of(t, pin_caption, k, single),
            see=("bearings.see_polar_pin", _crank_number(k, single)),
        )
        rods = _rod_diagrams(ctx, r, f, angle, k, single, labels_every)
        groups += [[pin_diagram, *rods]] if len(rods) == 1 else [[pin_diagram], rods]
    for j in r["drawn_journals"]:
        journal = r["main_journals"][j - 1]
        groups.append(
            [
                _polar(
                    ctx,
                    f[f"journal{j - 1}_t_Pa"],
                    f[f"journal{j - 1}_z_Pa"],
                    angle,
                    0.0,
                    t("bearings.journal_title", label=journal_name(journal)),
                    journal["oil_hole_deg"],
                    0.12,
                    labels_every,
                    f"journal{j - 1}",
                    # one crank: "the crank's axes", without its number
                    t(
                        "bearings.journal_caption_single" if single else "bearings.journal_caption",
                        label=journal_name(journal),
                        crank=max(j - 1, 1),
                    ),
                    see=("bearings.see_polar_journal", {"label": journal_name(journal)}),
                ),
                _polar(
                    ctx,
                    f[f"main_bearing{j - 1}_t_Pa"],
                    f[f"main_bearing{j - 1}_z_Pa"],
                    angle,
                    0.0,
                    t("bearings.main_bearing_title", label=journal_name(journal)),
                    None,
                    0.12,
                    labels_every,
                    f"main_bearing{j - 1}",
                    t("bearings.main_bearing_caption", label=journal_name(journal)),
                    axes=(t("bearings.axis_engine_x"), t("bearings.axis_engine_y")),
                    see=("bearings.see_polar_main_bearing", {"label": journal_name(journal)}),
                ),
            ]
        )
    return groups


def _rod_diagrams(ctx, r, f, angle, k: int, single: bool, labels_every: float) -> list:
    """(markup, narrow) of the big-end bearing diagrams of crank pin ``k``: its one bearing, or
    each of the bearings side by side on it, each in its own rod's axes."""
    t = ctx.t
    axes = (t("bearings.axis_rod_t"), t("bearings.axis_rod_z"))
    if not r.get("rod_bearings_per_pin"):
        return [
            _polar(
                ctx,
                f[f"rod_bearing{k}_t_Pa"],
                f[f"rod_bearing{k}_z_Pa"],
                angle,
                0.0,
                _one_of(t, "bearings.rod_title", k, single),
                None,
                0.12,
                labels_every,
                f"rod_bearing{k}",
                _one_of(t, "bearings.rod_caption", k, single),
                axes=axes,
                see=("bearings.see_polar_rod", _crank_number(k, single)),
            )
        ]
    rods = [rod for rod in r["rod_bearings"] if rod["crank"] == k]
    out = []
    for place, rod in enumerate(rods, start=1):
        name = rod_bearing_name(k, place)
        out.append(
            _polar(
                ctx,
                f[f"{name}_t_Pa"],
                f[f"{name}_z_Pa"],
                angle,
                0.0,
                t("bearings.rod_title_cylinder", cylinder=t.cylinder(rod["cylinder"])),
                None,
                0.12,
                labels_every,
                name,
                _one_of(
                    t,
                    "bearings.rod_caption_cylinder",
                    k,
                    single,
                    cylinder=t.cylinder(rod["cylinder"]),
                ),
                axes=axes,
                see=("bearings.see_polar_rod_cylinder", {"cylinder": t.cylinder(rod["cylinder"])}),
            )
        )
    return out
