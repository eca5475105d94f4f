"""Vector (polar) load diagrams of crank pins, main journals and their bearings (Poda 2007 §5)."""

from __future__ import annotations

import math
import re
from functools import partial
from pathlib import Path

import numpy as np
from markupsafe import Markup
from pydantic import BaseModel, ConfigDict

from crankdyn.contracts import BAY_LOADS, COUNTERWEIGHTS, CRANK_LOADS, KINEMATICS
from crankdyn.errors import Problem, SceneError
from crankdyn.physics import bearings as brg
from crankdyn.physics import layout as lay
from crankdyn.physics.extrema import first_argmax
from crankdyn.plugin_types import PlausibilityRule, Stage, StageOutput, Symbol
from crankdyn.report.figures import crank_angle_axis, new_figure
from crankdyn.scene import number, options, quantity
from crankdyn_builtin.bearings.worked import (
    journal_name,
    loads_equal,
    most_loaded,
    pin_rows,
    worked_bearing,
)

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

# Typical proportions (fractions of the bore / of the journal diameter) for car and tractor
# engines, used when the scene gives no journal dimensions.
DEFAULT_PIN_DIAMETER_PER_BORE = 0.63
DEFAULT_PIN_WIDTH_PER_DIAMETER = 0.60
DEFAULT_MAIN_DIAMETER_PER_BORE = 0.70
DEFAULT_MAIN_WIDTH_PER_DIAMETER = 0.45


class BearingOptions(BaseModel):
    """The [bearings] table."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    crank_pin_diameter: quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    crank_pin_width: quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    main_journal_diameter: quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    main_journal_width: quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    span_ratio: number(gt=0, lt=1) = 0.5
    pins: list[int] | None = None
    journals: list[int] | None = None
    wear_spread_deg: number(gt=0, le=90) = 60.0


#: Allowable specific loads of crank-pin bearings, MPa: (mean, largest) for petrol engines and
#: for diesels (Kolchin and Demidov, the wear diagram of the crank pin: mean 4-12 MPa and largest
#: 7-20 MPa in petrol engines, mean 6-16 MPa and largest 20-42 MPa in diesels; the upper ends
#: are the limits). An engine of unknown ignition (a measured trace) is judged as a diesel.
ALLOWABLE_PIN_PRESSURE_MPA = {"spark": (12.0, 20.0), "diesel": (16.0, 42.0)}
ALLOWABLE_PRESSURE_SOURCE = "kolchin2002"


def _pin_pressure(scene, results=None) -> list[tuple[str, dict]]:
    """The most loaded crank pin's mean and largest bearing pressure against the allowable ones
    of its kind of engine (:data:`ALLOWABLE_PIN_PRESSURE_MPA`)."""
    pins = (results or {}).get("crank_pins")
    if not pins:
        return []
    ignition = getattr(scene.cycle, "ignition", None) if scene.cycle is not None else None
    kind = "spark" if ignition == "spark" else "diesel"
    mean_limit, max_limit = ALLOWABLE_PIN_PRESSURE_MPA[kind]
    p_mean = max(pin["mean_MPa"] for pin in pins)
    p_max = max(pin["max_MPa"] for pin in pins)
    if p_mean <= mean_limit and p_max <= max_limit:
        return []
    return [(f"bearings.plausibility_pin_pressure_{kind}", {
        "p_mean": float(p_mean), "p_max": float(p_max), "mean_limit": mean_limit,
        "max_limit": max_limit, "source": ALLOWABLE_PRESSURE_SOURCE})]


def applies(scene) -> str | None:
    if scene.masses is None:
        return "the scene has no [masses]"
    return None


def _dimensions(scene, opts):
    bore = scene.engine.bore
    d_pin = opts.crank_pin_diameter or DEFAULT_PIN_DIAMETER_PER_BORE * bore
    w_pin = opts.crank_pin_width or DEFAULT_PIN_WIDTH_PER_DIAMETER * d_pin
    d_main = opts.main_journal_diameter or DEFAULT_MAIN_DIAMETER_PER_BORE * bore
    w_main = opts.main_journal_width or DEFAULT_MAIN_WIDTH_PER_DIAMETER * d_main
    defaulted = [name for name in ("crank_pin_diameter", "crank_pin_width", "main_journal_diameter",
                                   "main_journal_width") if getattr(opts, name) is None]
    return d_pin, w_pin, d_main, w_main, defaulted


def _tables(angle, pin, rod, journal, bearing, wear_pins, wear_journals) -> dict:
    """The stage's tables: every pin, rod bearing, journal and main bearing load (t, z components
    in Pa, per crank angle), and the wear diagrams (N per surface angle)."""
    cranks = len(pin[0])
    table = {"crank_angle_deg": angle}
    for k in range(cranks):
        table.update({f"pin{k + 1}_t_Pa": pin[0][k], f"pin{k + 1}_z_Pa": pin[1][k],
                      f"rod_bearing{k + 1}_t_Pa": rod[0][k], f"rod_bearing{k + 1}_z_Pa": rod[1][k]})
    for j in range(cranks + 1):
        table.update({f"journal{j}_t_Pa": journal[0][j], f"journal{j}_z_Pa": journal[1][j],
                      f"main_bearing{j}_t_Pa": bearing[0][j], f"main_bearing{j}_z_Pa": bearing[1][j]})
    wear = {"surface_angle_deg": wear_pins[0][0]}
    for k in range(cranks):
        wear[f"pin{k + 1}_wear_N"] = wear_pins[k][1]
    for j in range(cranks + 1):
        wear[f"journal{j}_wear_N"] = wear_journals[j][1]
    return {"bearings": table, "wear": wear}


def _counterweight_loads_Pa(fitted, cranks: int, area_m2: float) -> tuple[np.ndarray, np.ndarray]:
    """Per-crank (t, z) of the fitted counterweights (:class:`crankdyn.contracts.Counterweights`)
    per piston area [Pa]; zeros without counterweights (none fitted, or no balancing in the plan)."""
    if fitted is None:
        return np.zeros(cranks), np.zeros(cranks)
    return brg.counterweight_crank_load_Pa(fitted.crank, np.asarray(fitted.centrifugal_N) / area_m2,
                                           fitted.angle_from_crank_rad, cranks)


def _pin_and_rod_loads(loads, bays, motion, layout):
    """(pin t, pin z, rod-bearing t, rod-bearing z), each (cranks, N): the rods' load on each crank
    pin in crank axes, and the rod bearing of each bay's master rod in rod axes."""
    angle = loads.crank_angle_deg
    pin_t, pin_z = brg.crank_pin_load(loads.tangential_Pa, loads.radial_Pa, bays.centrifugal_rod_Pa)
    master = layout.bay(0)[0]
    rod_t, rod_z = np.zeros_like(pin_t), np.zeros_like(pin_z)
    revolution = int(round(360 / (angle[1] - angle[0])))
    # the crank's angle from the cylinder axis is alpha + this (an offset crank-slider's phi_TDC)
    tdc = motion.extra.get("crank_angle_at_tdc_rad", 0.0)
    for k in range(layout.cranks):
        # Each bay's master rod sees its crank at its own cycle angle.
        delay = layout.bay(k)[0].firing_delay_deg - master.firing_delay_deg
        local = np.radians((angle - delay) % 360.0)
        # without a rod (a Scotch yoke) the pin's bearing is the slider's, along the cylinder axis
        beta = (0.0 if motion.rod_angle_rad is None else
                np.interp(np.degrees(local), motion.crank_angle_deg[:revolution],
                          motion.rod_angle_rad[:revolution], period=360.0))
        rod_t[k], rod_z[k] = brg.rod_bearing_load(pin_t[k], pin_z[k], local + tdc, beta)
    return pin_t, pin_z, rod_t, rod_z


def run(scene, inputs) -> StageOutput:
    loads, bays, motion = inputs[CRANK_LOADS], inputs[BAY_LOADS], inputs[KINEMATICS]
    opts = options(scene, "bearings", BearingOptions)
    layout = bays.layout
    cranks = layout.cranks
    angle = loads.crank_angle_deg
    theta = np.radians(angle)
    area = loads.piston_area_m2
    d_pin, w_pin, d_main, w_main, defaulted = _dimensions(scene, opts)
    for key, values, limit in (("bearings.pins", opts.pins, cranks), ("bearings.journals", opts.journals, cranks + 1)):
        if values is not None and any(not 1 <= v <= limit for v in values):
            raise SceneError(Problem(key, values, f"numbers from 1 to {limit}"))

    pin_t, pin_z, rod_t, rod_z = _pin_and_rod_loads(loads, bays, motion, layout)

    # Main journals: each crank a beam on two supports; forces in the engine frame.
    # each crank's angle from the engine's vertical (the cylinder axis of a one-cylinder engine)
    tdc = motion.extra.get("crank_angle_at_tdc_rad", 0.0)
    positions = np.array([theta + tdc - np.radians(lag) for lag in layout.crank_lag_deg])
    # with the counterweights the balancing section fits (their centrifugal force on the webs)
    cw_t, cw_z = _counterweight_loads_Pa(inputs.get(COUNTERWEIGHTS), cranks, area)
    fa, fn = brg.crank_force_engine_frame(loads.tangential_Pa + cw_t[:, None], loads.radial_Pa + cw_z[:, None],
                                          loads.centrifugal_Pa, positions)
    share_after = np.full(cranks, opts.span_ratio)
    ja, jn = brg.journal_loads(fa, fn, 1.0 - share_after, share_after)
    # Journal diagram: force of the bearing on the journal (the reaction, -J) in the axes of the
    # preceding crank (crank 1 for the free-end journal); bearing diagram: J in engine axes.
    journal_t, journal_z = np.zeros_like(ja), np.zeros_like(ja)
    for j in range(cranks + 1):
        e_t, e_z = brg.crank_axes(positions[max(j - 1, 0)])
        journal_t[j], journal_z[j] = brg.to_frame(-ja[j], -jn[j], e_t, e_z)
    engine_t, engine_z = brg.crank_axes(np.zeros(1))
    bearing_t, bearing_z = brg.to_frame(ja, jn, engine_t, engine_z)

    def summary(t, z, d, w):
        s = brg.polar_summary(t, z, area, d, w, angle)
        # Contact point on the rotating part: opposite to the force applied to it.
        psi, wear = brg.wear_diagram(-t, -z, np.hypot(t, z) * area, opts.wear_spread_deg)
        start, end, centre = brg.least_loaded_arc(psi, wear)
        s.update({"oil_hole_deg": centre, "least_loaded_arc_deg": [start, end]})
        return s, (psi, wear)

    pins, wear_pins = zip(*[summary(pin_t[k], pin_z[k], d_pin, w_pin) for k in range(cranks)], strict=True)
    journals, wear_journals = zip(*[summary(journal_t[j], journal_z[j], d_main, w_main) for j in range(cranks + 1)], strict=True)
    most_loaded_pin = first_argmax([p["max_N"] for p in pins]) + 1
    most_loaded_journal = first_argmax([j["max_N"] for j in journals]) + 1
    drawn_pins = opts.pins or [most_loaded_pin]
    drawn_journals = opts.journals or [most_loaded_journal]

    results = {
        # an offset crank-slider's crank is this far past the cylinder axis at TDC (0: central)
        "crank_angle_at_tdc_deg": math.degrees(motion.extra.get("crank_angle_at_tdc_rad", 0.0)),
        "dimensions": {"crank_pin_diameter_m": d_pin, "crank_pin_width_m": w_pin, "main_journal_diameter_m": d_main,
                       "main_journal_width_m": w_main, "defaulted": defaulted},
        "crank_pins": [{"crank": k + 1, **pins[k]} for k in range(cranks)],
        "with_counterweights": bool(np.any(cw_t) or np.any(cw_z)),
        "main_journals": [{"journal": lay.journal_label(j), **journals[j]} for j in range(cranks + 1)],
        "rod_bearings": [{"crank": k + 1, **brg.polar_summary(rod_t[k], rod_z[k], area, d_pin, w_pin)}
                         for k in range(cranks)],
        "main_bearings": [{"journal": lay.journal_label(j), **brg.polar_summary(bearing_t[j], bearing_z[j], area, d_main, w_main)}
                          for j in range(cranks + 1)],
        "drawn_pins": drawn_pins,
        "drawn_journals": drawn_journals,
        "span_ratio": opts.span_ratio,  # l'/l of every crank
        "chosen_by_default": opts.pins is None and opts.journals is None,
        "centrifugal_rod_Pa": bays.centrifugal_rod_Pa,
    }
    tables = _tables(angle, (pin_t, pin_z), (rod_t, rod_z), (journal_t, journal_z), (bearing_t, bearing_z),
                     wear_pins, wear_journals)
    return StageOutput(data={}, results=results, tables=tables,
                       notes=[("bearings.note_dimensions", {"names": ", ".join(defaulted)})] if defaulted else [])


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


_PLACES = ((2, 2, "left", "bottom"), (-2, 2, "right", "bottom"), (2, -2, "left", "top"), (-2, -2, "right", "top"),
           (7, 7, "left", "bottom"), (-7, 7, "right", "bottom"), (7, -7, "left", "top"), (-7, -7, "right", "top"))
#: Further out, tried only where a label nearer would sit on the curve.
_FAR_PLACES = ((12, 12, "left", "bottom"), (-12, 12, "right", "bottom"), (12, -12, "left", "top"),
               (-12, -12, "right", "top"))


#: The polar diagrams' angle labels, pt (6 pt is too small to read in print).
LABEL_PT = 7.0


def _label_places(points, texts, per_pt, bounds=None, order=None, obstacles=(), curve=None) -> list[tuple | None]:
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
        if bounds is not None and (box[0] < bounds[0] or box[1] < bounds[1] or box[2] > bounds[2] or box[3] > bounds[3]):
            return False
        return all(min(box[2], c[2]) <= max(box[0], c[0]) or min(box[3], c[3]) <= max(box[1], c[1]) for c in placed)

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
        return 0 if curve is None else int(np.count_nonzero((curve[0] > inner[0]) & (curve[0] < inner[2]) &
                                                             (curve[1] > inner[1]) & (curve[1] < inner[3])))

    for i in (range(len(points)) if order is None else order):
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

    return sorted(_PLACES[:4], key=facing) + sorted(_PLACES[4:], key=facing) + sorted(_FAR_PLACES, key=facing)


def _curve_samples(x, y, spacing: float, most: int = 1500) -> tuple[np.ndarray, np.ndarray]:
    """Points along the closed curve (x, y) no more than about ``spacing`` apart (a label box a
    segment crosses between two samples still holds one), from at most ``most`` of its points."""
    keep = max(1, int(math.ceil(len(x) / most)))
    xs, ys = np.append(x[::keep], x[0]), np.append(y[::keep], y[0])
    pieces = np.maximum(1, np.ceil(np.hypot(np.diff(xs), np.diff(ys)) / max(spacing, 1e-12)).astype(int))
    pieces = np.minimum(pieces, 50)
    share = np.concatenate([np.arange(n) / n for n in pieces])
    start = np.repeat(np.arange(len(pieces)), pieces)
    return xs[start] + share * (xs[start + 1] - xs[start]), ys[start] + share * (ys[start + 1] - ys[start])


def _pole_and_oil_hole(pole_z: float, radius: float, oil_deg: float | None, per_pt: float) -> list[tuple]:
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


def _polar(ctx, t_Pa, z_Pa, angle, pole_z, title, oil_deg, diameter_scale, labels_every, name, caption,
           axes=("t", "z"), see=("bearings.see_polar", {})):
    """A polar load diagram's markup, and whether it is narrow enough to stand beside another;
    ``axes``: the names of its horizontal and vertical components (crank axes t, z unless the
    diagram is drawn in the rod's or the engine's axes); ``see``: the key and placeholders of
    the sentence announcing it, which names the journal or bearing (two diagrams side by side
    are not each announced as just "the vector diagram")."""
    width_cm = _polar_size(t_Pa / 1e6, z_Pa / 1e6, pole_z, diameter_scale)[0]
    return ctx.figure(partial(_polar_drawing, ctx.t, t_Pa, z_Pa, angle, pole_z, title, oil_deg, diameter_scale,
                              labels_every, axes), caption, name, see=see[0], see_params=see[1]), \
        width_cm <= HALF_WIDTH_CM


#: A diagram at most this wide (cm) stands beside the next one: two tall, narrow diagrams on a
#: page instead of one on each, with half of it empty.
HALF_WIDTH_CM = 8.0


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
    taller figure (at most 13 cm: with its caption and the sentence above a pair it still shares a
    page with text) only as wide as its plot needs (with the ticks and labels ≈ 2.4 cm), a wide one
    a wider figure."""
    return _size_for(*_polar_extent(t, z, pole_z, diameter_scale)[2:])


def _size_for(shown_t: float, shown_z: float) -> tuple[float, float]:
    """(width, height) in cm of a polar diagram showing these t and z ranges (:func:`_polar_size`)."""
    aspect = max(shown_z, 1e-9) / max(shown_t, 1e-9)
    if aspect < 1:
        return min(16.0, 12.0 / math.sqrt(aspect)), 12.0
    height = min(13.0, 12.0 * math.sqrt(aspect))
    return min(12.0, max(7.0, 1.1 * (height - 2.2) / aspect + 2.4)), height


def _polar_drawing(translator, t_Pa, z_Pa, angle, pole_z, title, oil_deg, diameter_scale, labels_every, axes):
    """The polar load diagram's figure (:func:`_polar`)."""
    t, z = t_Pa / 1e6, z_Pa / 1e6
    span, radius, shown_t, shown_z = _polar_extent(t, z, pole_z, diameter_scale)
    width_cm, height_cm = _size_for(shown_t, shown_z)
    fig, ax = new_figure(width_cm, height_cm)
    ax.plot(np.append(t, t[0]), np.append(z, z[0]), color="C0", lw=1.2)  # the closed curve
    step = angle[1] - angle[0]
    every = max(int(round(labels_every / step)), 1)
    ax.plot(t[::every], z[::every], "o", ms=2.5, color="C3", linestyle="none")  # one artist for all marks
    ax.axhline(0, color="0.3", lw=0.6)
    ax.axvline(0, color="0.3", lw=0.6)
    # Points that (nearly) coincide, as alpha and alpha + 360 deg do where inertia dominates, get
    # one label "210, 570" instead of two printed over each other.
    groups = _coinciding(t[::every], z[::every], 0.03 * span)
    texts = [", ".join(translator.angle(angle[k * every], step) for k in same)
             for _, same in groups]
    anchors = [(t[i * every], z[i * every]) for i, _ in groups]
    # the axes take the figure less about 2 cm for the tick labels, axis labels and title; with
    # equal aspect the range that fills its box sets the scale (matplotlib's 5 % margins added);
    # z grows downwards on the page
    box_pt = ((width_cm - 2.0) * 72 / 2.54, (height_cm - 2.2) * 72 / 2.54)
    per_pt = 1.1 * max(shown_t / box_pt[0], shown_z / box_pt[1], 1e-12)
    screen = [(x, -y) for x, y in anchors]
    low_t, high_t = min(np.min(t), -radius), max(np.max(t), radius)
    low_z, high_z = min(np.min(z), pole_z - radius), max(np.max(z), pole_z + radius)
    margin_t, margin_z = 0.05 * (high_t - low_t), 0.05 * (high_z - low_z)  # matplotlib's own margins
    bounds = (low_t - margin_t, -(high_z + margin_z), high_t + margin_t, -(low_z - margin_z))
    # the largest load's label first, then the dead centres' (multiples of 90 deg), then the rest
    q = np.hypot([a[0] for a in anchors], [a[1] - pole_z for a in anchors])
    peak = int(np.argmax(q)) if len(q) else 0
    def rank(g: int):
        angles = [angle[k * every] for k in groups[g][1]]
        return (g != peak, not any(abs(a % 90.0) < 1e-9 for a in angles), g)
    order = sorted(range(len(groups)), key=rank)
    obstacles = _pole_and_oil_hole(pole_z, radius, oil_deg, per_pt)
    curve = _curve_samples(t, -z, 2.0 * per_pt)  # screen coordinates, as the labels'
    for (x, y), text, place in zip(anchors, texts, _label_places(screen, texts, per_pt, bounds, order, obstacles,
                                                                 curve), strict=True):
        if place is not None:
            dx, dy, ha, va = place
            ax.annotate(text, (x, y), fontsize=LABEL_PT, xytext=(dx, dy), textcoords="offset points", ha=ha, va=va)
    circle = np.linspace(0, 2 * np.pi, 200)
    # The pole O, where the journal sits (shifted from O1 by the constant centrifugal load).
    ax.plot(radius * np.sin(circle), pole_z + radius * np.cos(circle), color="0.2", lw=0.8)
    ax.plot([0], [pole_z], "k+", ms=8)
    ax.annotate("O", (0, pole_z), xytext=(-9, -9), textcoords="offset points", fontsize=8, style="italic")
    if oil_deg is not None:
        psi = np.radians(oil_deg)
        ax.plot([0, radius * np.sin(psi)], [pole_z, pole_z + radius * np.cos(psi)], color="C2", lw=2)
        ax.plot(radius * np.sin(psi), pole_z + radius * np.cos(psi), "o", color="C2", ms=5)
    ax.set_aspect("equal")
    ax.invert_yaxis()  # +z points from the pin towards the shaft axis: drawn downwards as in fig. 17
    ax.set_xlabel(f"{axes[0]}, " + translator("unit.MPa"))
    ax.set_ylabel(f"{axes[1]}, " + translator("unit.MPa"))
    ax.set_title(title, fontsize=9)
    return fig


def _side_by_side(pairs: list) -> list:
    """The diagrams' markup, each two narrow ones (a crank pin and its rod bearing, a main journal
    and its bearing) in one row."""
    out = []
    for k in range(0, len(pairs) - 1, 2):
        (first, narrow_first), (second, narrow_second) = pairs[k], pairs[k + 1]
        out += [_figure_row(first, second)] if narrow_first and narrow_second else [first, second]
    return out + [markup for markup, _ in pairs[len(pairs) - len(pairs) % 2:]]


_SEE = re.compile(r'<p class="see">(.*?)</p>', flags=re.S)


def _figure_row(first, second) -> Markup:
    """Two figures side by side, announced together in one paragraph above the row (each one's
    sentence in its own half-width column takes two lines, and the row then does not fit under
    a chapter's text: a 27 %-full page, and the captions at different heights)."""
    sentences = " ".join(m.group(1) for block in (first, second) for m in [_SEE.search(str(block))] if m)
    blocks = "".join(_SEE.sub("", str(block), count=1) for block in (first, second))
    return Markup(f'<div class="figure-row-block"><p class="see">{sentences}</p>'
                  f'<div class="figure-row">{blocks}</div></div>')


def _wear_figure(ctx, wear, r):
    """Wear diagram of the drawn crank pin (load spread over +-60 deg around each contact point)."""
    k = r["drawn_pins"][0]
    single = len(r["crank_pins"]) == 1
    caption = _one_of(ctx.t, "bearings.wear_caption", k, single)
    return ctx.figure(partial(_wear_drawing, wear, r, k), caption, f"wear_pin{k}", see="bearings.see_wear_pin",
                      see_params=_crank_number(k, single))


def _wear_drawing(wear, r, k):
    """The wear diagram's figure (:func:`_wear_figure`)."""
    fig, ax = new_figure(10, 10, subplot_kw={"projection": "polar"})
    ax.set_theta_zero_location("S")  # +z (towards the shaft axis) drawn downwards, as the polar diagrams
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
        ax.annotate("", xy=(angle, 0.25), xytext=(0.0, 0.0),
                    arrowprops={"arrowstyle": "-|>", "color": "0.25", "lw": 1.0})
        ax.text(angle, 0.33, name, ha="center", va="center", fontsize=10)  # inside the wear (from 0.4 in)
    ax.set_ylim(0, 1.15)
    ax.set_yticks([])
    ax.grid(False, axis="y")
    ax.spines["polar"].set_visible(False)  # the journal's circle is the only circle
    return fig


def _crank_number(k, single: bool) -> dict:
    """``{k}`` of a sentence naming crank (pin) ``k`` ("на шатунну шийку{k}"): " 1", or nothing
    when there is one crank."""
    return {"k": "" if single else f" {k}"}


def _one_of(t, key: str, k, single: bool) -> str:
    """The catalog text ``key`` for crank (pin) ``k``, without the number when there is one crank."""
    return re.sub(r"\s+([:;,.)])", r"\1", re.sub(r"\s+", " ", t(key, k="" if single else k))).strip()


def _load_range(ctx, kind: str, load: dict, name) -> str:
    """What a load diagram shows, in a sentence: the load's range over the cycle and its mean."""
    if "min_crank_angle_deg" not in load:
        return ""
    t = ctx.t
    return t(f"bearings.range_{kind}", name=name, min=t.fixed(load["min_N"] / 1e3, 2),
             max=t.fixed(load["max_N"] / 1e3, 2), mean=t.fixed(load["mean_N"] / 1e3, 2),
             min_angle=ctx.angle_text(load["min_crank_angle_deg"]),
             max_angle=ctx.angle_text(load["max_crank_angle_deg"]))


def _unrolled_figure(ctx, f, r, angle, single: bool):
    """The unrolled diagrams: the load's magnitude on the drawn crank pins and main journals."""
    return ctx.figure(partial(_unrolled_drawing, ctx.t, ctx.cycle_deg, f, r, angle, single),
                      ctx.t("bearings.unrolled_caption"), "unrolled", see="bearings.see_unrolled")


def _unrolled_drawing(t, cycle_deg, f, r, angle, single: bool):
    """The unrolled diagrams' figure (:func:`_unrolled_figure`)."""
    fig, ax = new_figure(16, 8)
    for k in r["drawn_pins"]:
        ax.plot(angle, np.hypot(f[f"pin{k}_t_Pa"], f[f"pin{k}_z_Pa"]) / 1e6,
                label=_one_of(t, "bearings.pin_label", k, single))
    for j in r["drawn_journals"]:
        label = journal_name(r["main_journals"][j - 1])
        ax.plot(angle, np.hypot(f[f"journal{j - 1}_t_Pa"], f[f"journal{j - 1}_z_Pa"]) / 1e6,
                label=t("bearings.journal_label", label=label))
    crank_angle_axis(ax, cycle_deg, t("axis.crank_angle"))
    ax.set_ylabel("|q_pin|, |R_j|, " + t("unit.MPa"))  # the symbols of equations (7.1) and (7.3)
    ax.legend(loc="upper right", fontsize=8)
    return fig


def _shared_pins(ctx, r) -> bool:
    """One rod on each crank pin (in-line engines: False) or several sharing one (V, W, radial)."""
    return ctx.scene is not None and ctx.scene.engine.cylinders > len(r["crank_pins"])


def _polar_diagrams(ctx, r, f, angle, single: bool) -> list:
    """(markup, narrow) of each polar diagram, in pairs: a crank pin and its rod bearing, a main
    journal and its bearing."""
    t = ctx.t
    labels_every = 30.0 if ctx.cycle_deg > 360 else 15.0
    c_rod = r["centrifugal_rod_Pa"] / 1e6
    pin_caption = "bearings.pin_caption_shared" if _shared_pins(ctx, r) else "bearings.pin_caption"
    polar = []
    for k in r["drawn_pins"]:
        pin = r["crank_pins"][k - 1]
        polar.append(_polar(ctx, f[f"pin{k}_t_Pa"], f[f"pin{k}_z_Pa"] - r["centrifugal_rod_Pa"],
                              angle, -c_rod, _one_of(t, "bearings.pin_title", k, single), pin["oil_hole_deg"], 0.12, labels_every,
                              f"pin{k}", _one_of(t, pin_caption, k, single),
                              see=("bearings.see_polar_pin", _crank_number(k, single))))
        polar.append(_polar(ctx, f[f"rod_bearing{k}_t_Pa"], f[f"rod_bearing{k}_z_Pa"], angle,
                              0.0, _one_of(t, "bearings.rod_title", k, single), None, 0.12, labels_every, f"rod_bearing{k}",
                              _one_of(t, "bearings.rod_caption", k, single), axes=(t("bearings.axis_rod_t"), t("bearings.axis_rod_z")),
                              see=("bearings.see_polar_rod", _crank_number(k, single))))
    for j in r["drawn_journals"]:
        journal = r["main_journals"][j - 1]
        polar.append(_polar(ctx, f[f"journal{j - 1}_t_Pa"], f[f"journal{j - 1}_z_Pa"], angle,
                              0.0, t("bearings.journal_title", label=journal_name(journal)), journal["oil_hole_deg"], 0.12,
                              labels_every, f"journal{j - 1}", t("bearings.journal_caption", label=journal_name(journal),
                                                                          crank=max(j - 1, 1)),
                              see=("bearings.see_polar_journal", {"label": journal_name(journal)})))
        polar.append(_polar(ctx, f[f"main_bearing{j - 1}_t_Pa"], f[f"main_bearing{j - 1}_z_Pa"],
                              angle, 0.0, t("bearings.main_bearing_title", label=journal_name(journal)), None, 0.12,
                              labels_every, f"main_bearing{j - 1}",
                              t("bearings.main_bearing_caption", label=journal_name(journal)),
                              axes=(t("bearings.axis_engine_x"), t("bearings.axis_engine_y")),
                              see=("bearings.see_polar_main_bearing", {"label": journal_name(journal)})))
    return polar


def render(output: StageOutput, ctx) -> str | None:
    t = ctx.t
    r = output.results
    f = output.tables.arrays("bearings")
    angle = f["crank_angle_deg"]
    single = len(r["crank_pins"]) == 1  # one crank: no neighbouring cranks, no choice of crank pin
    figures = _side_by_side(_polar_diagrams(ctx, r, f, angle, single))
    figures.append(_wear_figure(ctx, output.tables.arrays("wear"), r))
    figures.append(_unrolled_figure(ctx, f, r, angle, single))

    pins, pin_labels = pin_rows(r["crank_pins"])
    table_pins = ctx.table([
        (t("bearings.crank"), pin_labels, None),
        ("<i>Q</i><sub>max</sub>, " + t("unit.kN"), [p["max_N"] / 1e3 for p in pins], 2),
        ("<i>Q</i><sub>mean</sub>, " + t("unit.kN"), [p["mean_N"] / 1e3 for p in pins], 2),
        ("<i>p</i><sub>max</sub>, " + t("unit.MPa"), [p["max_MPa"] for p in pins], 2),
        ("<i>p</i><sub>mean</sub>, " + t("unit.MPa"), [p["mean_MPa"] for p in pins], 2),
        (t("bearings.oil_hole"), [p["oil_hole_deg"] for p in pins], 0),
    ], caption=t("bearings.pins_table_caption_single" if single else "bearings.pins_table_caption"),
        see="bearings.see_pins_single" if single else "bearings.see_pins") + \
        worked_bearing(ctx, r, "pin")
    table_journals = ctx.table([
        (t("bearings.journal"), [journal_name(j) for j in r["main_journals"]], None),
        ("<i>R</i><sub>max</sub>, " + t("unit.kN"), [j["max_N"] / 1e3 for j in r["main_journals"]], 2),
        ("<i>R</i><sub>mean</sub>, " + t("unit.kN"), [j["mean_N"] / 1e3 for j in r["main_journals"]], 2),
        ("<i>p</i><sub>max</sub>, " + t("unit.MPa"), [j["max_MPa"] for j in r["main_journals"]], 2),
        ("<i>p</i><sub>mean</sub>, " + t("unit.MPa"), [j["mean_MPa"] for j in r["main_journals"]], 2),
        (t("bearings.oil_hole"), [j["oil_hole_deg"] for j in r["main_journals"]], 0),
    ], caption=t("bearings.journals_table_caption"), see="bearings.see_journals")
    journals_table_number = ctx.last_table_number
    table_journals += worked_bearing(ctx, r, "journal")
    pin = r["crank_pins"][r["drawn_pins"][0] - 1]
    ctx.find(t("bearings.finding", q_max=ctx.num(pin["max_N"] / 1e3)))
    # the digits of table 7.1, which the conclusion repeats
    # identical cylinders on cranks of their own: the same load on every pin, shifted in phase
    pins_equal = loads_equal(r["crank_pins"])
    conclusion = "bearings.conclusion_single" if single else "bearings.conclusion_equal" if pins_equal else "bearings.conclusion"
    tied = most_loaded(r["main_journals"])
    journal = tied[0]
    journal_key = ("bearings.conclusion_journal_equal" if loads_equal(r["main_journals"]) else
                   "bearings.conclusion_journal_tied" if len(tied) > 1 else "bearings.conclusion_journal")
    ctx.conclude(t(conclusion, k=pin["crank"], q_max=ctx.t.fixed(pin["max_N"] / 1e3, 2),
                   p_mean=ctx.t.fixed(pin["mean_MPa"], 2),
                   oil=ctx.t.fixed(pin["oil_hole_deg"], 0))  # as the tables print it
                 + " " + t(journal_key, label=journal_name(journal), labels=", ".join(journal_name(j) for j in tied),
                           r_max=ctx.t.fixed(journal["max_N"] / 1e3, 2), p_mean=ctx.t.fixed(journal["mean_MPa"], 2),
                           oil=ctx.t.fixed(journal["oil_hole_deg"], 0), table=journals_table_number))
    d = r["dimensions"]
    journal_names = ", ".join(journal_name(r["main_journals"][j - 1]) for j in r["drawn_journals"])
    analysis = [_load_range(ctx, "pin_single" if single else "pin", r["crank_pins"][k - 1], k) for k in r["drawn_pins"]]
    analysis += [_load_range(ctx, "journal", r["main_journals"][j - 1], journal_name(r["main_journals"][j - 1]))
                 for j in r["drawn_journals"]]
    return ctx.render_template("sections/bearings.html.j2", r=r, figures=figures, table_pins=table_pins,
                               analysis=" ".join(a for a in analysis if a),
                               table_journals=table_journals, dims=d, shared_pins=_shared_pins(ctx, r), single=single,
                               journal_names=journal_names, pins_equal=pins_equal)


#: The crank's angle from the cylinder axis of an offset crank-slider (symbol.bearings.<key>).
SYMBOLS = {"axis_crank_angle": Symbol("φ", {}, "°")}


BEARINGS_STAGE = Stage(
    template_dir=TEMPLATES,
    name="bearings",
    # the core's letters that hold with their meaning in this section only
    section_symbols=("bearing_width", "bearing_pressure", "pin_load_max", "pin_load_mean",
                     "bearing_pressure_max", "bearing_pressure_mean", "journal_load_max",
                     "journal_load_mean"),
    title_key="bearings.title",
    requires=(CRANK_LOADS, BAY_LOADS, KINEMATICS),
    uses=(COUNTERWEIGHTS,),
    provides=(),
    applies=applies,
    run=run,
    render=render,
    figures=("pin*", "rod_bearing*", "journal*", "main_bearing*", "wear_pin*", "unrolled"),
    tables=("bearings", "wear"),
    references=("poda2007", "orlin1984"),
    plausibility=(PlausibilityRule("pin_pressure", _pin_pressure),),
    options_table="bearings",
    options_model=BearingOptions,
    symbols=SYMBOLS,
)
