"""The mechanism drawn: its kinematic scheme, its characteristic positions and (HTML) its motion.

Any mechanism whose plugin gives ``Mechanism.geometry`` is drawn (see
:class:`crankdyn.plugin_types.MechanismGeometry`). The characteristic positions (TDC, BDC, the
extremes of the piston velocity and acceleration) are taken from the kinematics the
``kinematics`` data key carries (``drawing``); a mechanism without a piston motion (the vane
engine) is drawn from its geometry's output travel (``drawing_linkage``).
"""

from __future__ import annotations

from functools import partial
from pathlib import Path

import numpy as np
from markupsafe import Markup

from crankdyn.contracts import KINEMATICS
from crankdyn.physics.extrema import first_argmax, first_argmin
from crankdyn.physics.scalar_search import minimize_bounded
from crankdyn.plugin_types import SERVICE_RUNNER, Stage, StageOutput
from crankdyn.report import mechanism_drawing as md

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

#: The characteristic positions, in the order they are drawn.
POSITIONS = ("tdc", "bdc", "v_max", "v_min", "j_max", "j_min")
#: The crank angle the scheme is drawn at (deg from cylinder 1's TDC): the crank, the rod and
#: their angles α and β apart and visible, as a textbook draws the mechanism (at TDC the rod
#: covers the crank).
SCHEME_ANGLE_DEG = 45.0
#: The crank angle of the scheme of an engine with articulated rods: cylinder 1's TDC, where the
#: master rod's knuckle pins stand clear of the shaft's axis (at 45 deg one of them covers it).
ARTICULATED_SCHEME_ANGLE_DEG = 0.0
#: Frames of the animation per revolution (at most; never finer than the scene's grid).
FRAMES_PER_REVOLUTION = 180


def mechanism_geometry(scene, services):
    """The ``geometry`` callable of the scene's mechanism in the run's registry, or None."""
    mechanism = services[SERVICE_RUNNER].registry.mechanisms.get(scene.engine.mechanism)
    return None if mechanism is None else mechanism.geometry


def _has_piston_motion(scene, services) -> bool:
    runner = services[SERVICE_RUNNER]
    return any(KINEMATICS in s.provides and runner.applies(s, scene) is None for s in runner.stages.values())


def applies(scene, services) -> str | None:
    if mechanism_geometry(scene, services) is None:
        return f"the mechanism {scene.engine.mechanism!r} gives no geometry to draw"
    if not _has_piston_motion(scene, services):
        return "no stage provides the piston motion for this mechanism (drawn by drawing_linkage)"
    return None


def applies_linkage(scene, services) -> str | None:
    if mechanism_geometry(scene, services) is None:
        return f"the mechanism {scene.engine.mechanism!r} gives no geometry to draw"
    if _has_piston_motion(scene, services):
        return "the mechanism has a piston motion (drawn by the drawing stage)"
    return None


def _refined(travel_at, angle_deg, values, order: int, kind: str) -> float:
    """The crank angle (deg) of the first extreme of d^order s/d alpha^order, refined off the grid.

    ``travel_at(alpha_deg)`` is the travel at any angle; the derivatives are central differences.
    """
    i = first_argmax(values) if kind == "max" else first_argmin(values)
    if travel_at is None or len(angle_deg) < 2:
        return float(angle_deg[i])
    sign = 1.0 if kind == "max" else -1.0
    h = 2.0  # deg: with Richardson the truncation error is O(h^4); round-off grows as h shrinks

    def derivative(a, h):
        s = np.asarray(travel_at(np.array([a - h, a, a + h])), dtype=float)
        return (s[2] - s[0]) / (2 * h) if order == 1 else (s[2] - 2 * s[1] + s[0]) / h**2

    def f(a):
        if order == 0:
            return float(np.asarray(travel_at(np.array([a])), dtype=float)[0])
        # Richardson extrapolation of the central difference: error O(h^4), far below 1e-6 deg.
        return float((4 * derivative(a, h) - derivative(a, 2 * h)) / 3)

    step = angle_deg[1] - angle_deg[0]
    res = minimize_bounded(lambda a: -sign * f(a), angle_deg[i] - step, angle_deg[i] + step, xatol=1e-9)
    return float(res.x) if -res.fun >= sign * f(angle_deg[i]) else float(angle_deg[i])


def characteristic_angles(angle_deg, s, v, j, travel_at=None) -> dict[str, float]:
    """Crank angles (deg, in [0, 360)) of TDC, BDC and the velocity and acceleration extremes."""
    found = {"tdc": _refined(travel_at, angle_deg, s, 0, "min"), "bdc": _refined(travel_at, angle_deg, s, 0, "max"),
             "v_max": _refined(travel_at, angle_deg, v, 1, "max"), "v_min": _refined(travel_at, angle_deg, v, 1, "min"),
             "j_max": _refined(travel_at, angle_deg, j, 2, "max"), "j_min": _refined(travel_at, angle_deg, j, 2, "min")}
    wrapped = {k: float(a % 360.0) for k, a in found.items()}
    return {k: 0.0 if min(a, 360.0 - a) < 1e-6 else a for k, a in wrapped.items()}


def _period_deg(angle_deg, s) -> float:
    """360 when the travel repeats every revolution on the grid, else the whole grid's span."""
    step = angle_deg[1] - angle_deg[0]
    span = step * len(angle_deg)
    shift = int(round(360.0 / step))
    if span > 360.0 + 1e-9 and np.allclose(s[:len(s) - shift], s[shift:], rtol=0, atol=1e-9 * np.ptp(s)):
        return 360.0
    return float(min(span, 360.0)) if span <= 360.0 + 1e-9 else float(span)


def _motion(scene, inputs):
    """(angle deg, s, v, j, travel_at) from the kinematics, or from the geometry's travel."""
    motion = inputs.get(KINEMATICS)
    if motion is not None:
        return (motion.crank_angle_deg, motion.piston_displacement_m, motion.piston_velocity_m_s,
                motion.piston_acceleration_m_s2, motion.displacement_at)
    geometry = mechanism_geometry(scene, inputs)
    angle = scene.crank_angles_deg
    angle = angle[angle < 360.0]

    def travel_at(a_deg):
        return geometry(scene, np.radians(np.atleast_1d(a_deg))).travel_m

    s = travel_at(angle)
    step = np.radians(angle[1] - angle[0])
    v = (np.roll(s, -1) - np.roll(s, 1)) / (2 * step)
    j = (np.roll(s, -1) - 2 * s + np.roll(s, 1)) / step**2
    return angle, s, v, j, travel_at


def scheme_angle_deg(geometry) -> float:
    """The crank angle the scheme is drawn at: :data:`ARTICULATED_SCHEME_ANGLE_DEG` for a
    mechanism with a master rod, :data:`SCHEME_ANGLE_DEG` otherwise."""
    if md.master_rod_bodies(geometry, 0):
        return ARTICULATED_SCHEME_ANGLE_DEG
    return SCHEME_ANGLE_DEG


def run(scene, inputs) -> StageOutput:
    """Geometry at the characteristic angles and at the animation's frames (physics only)."""
    geometry_of = mechanism_geometry(scene, inputs)
    angle, s, v, j, travel_at = _motion(scene, inputs)
    angles = characteristic_angles(angle, s, v, j, travel_at)
    period = _period_deg(angle, s)
    step = angle[1] - angle[0]
    every = max(1, int(round(period / FRAMES_PER_REVOLUTION / step))) if period <= 360.0 else \
        max(1, int(round(period / (2 * FRAMES_PER_REVOLUTION) / step)))
    frames_deg = np.arange(0.0, period - 1e-9, step * every)
    # the characteristic positions, then the scheme's
    scheme_angle = scheme_angle_deg(geometry_of(scene, np.zeros(1)))
    at = np.radians([angles[k] for k in POSITIONS] + [scheme_angle])
    positions = geometry_of(scene, at)
    animation = geometry_of(scene, np.radians(frames_deg))
    grid = np.rint(np.interp(frames_deg, angle, np.arange(len(angle)))).astype(int)
    curves = {"v": np.asarray(v)[grid], "j": np.asarray(j)[grid]}
    results = {"crank_angles_deg": {k: angles[k] for k in POSITIONS}, "animation_frames": int(len(frames_deg)),
               "animation_step_deg": float(step * every), "motion_period_deg": period,
               "scheme_angle_deg": scheme_angle}
    # No tables: the joint positions are drawing data (kept for render only), the angles are in results.
    return StageOutput(results=results,
                       artifacts={"positions": positions, "animation": animation, "curves": curves})


def _labels(geometry, ctx) -> dict[str, str]:
    mm = ctx.t("unit.mm")
    return {k: f"{k} = {ctx.t.number_g(value * 1e3, 4)} {mm}" for k, value in geometry.dimensions.items()}


def position_frames(angles: dict[str, float], caption) -> list[tuple[int, str]]:
    """The positions figure's panels (index into :data:`POSITIONS`, caption) in the order the crank
    reaches them (a supervisor: j_min at 158,2° came after v_min at 284,6°), those at one angle
    merged (:func:`_merged_frames`); ``caption(key)`` writes a panel's caption."""
    order = sorted(range(len(POSITIONS)), key=lambda i: angles[POSITIONS[i]] % 360.0)
    return _merged_frames([(i, caption(POSITIONS[i]), angles[POSITIONS[i]]) for i in order])


def _merged_frames(frames: list[tuple[int, str, float]]) -> list[tuple[int, str]]:
    """One panel per distinct position: of a central crank-slider, TDC is also where the piston's
    acceleration is largest, and two identical panels ("ВМТ" and "j_max", both at 0°) would be
    drawn. Captions are "what\nα = …"; positions within 0.05° share a panel, their names joined."""
    merged: list[tuple[int, list[str], str, float]] = []
    for i, caption, angle in frames:
        name, _, at = caption.partition("\n")
        same = next((m for m in merged if abs((m[3] - angle + 180.0) % 360.0 - 180.0) < 0.05), None)
        if same is None:
            merged.append((i, [name], at, angle))
        else:
            same[1].append(name)
    return [(i, ", ".join(names) + "\n" + at) for i, names, at, _ in merged]


def _front_view_kind(positions) -> str:
    """"row": the scheme shows one cylinder of an in-line row; "rows": one of each bank; "": all."""
    shown = md.front_view(positions).guides
    if len(shown) == len(positions.guides):
        return ""
    return "row" if len(shown) == 1 else "rows"


def scale_text(scale: float, t) -> str:
    """A drawing's scale as written on it: "1:2,5" (a reduction), "1:1", "2:1" (an enlargement)."""
    return f"{t.number_g(scale, 4)}:1" if scale >= 1 else f"1:{t.number_g(1 / scale, 4)}"


def render(output: StageOutput, ctx) -> str:
    """The scheme (at :data:`SCHEME_ANGLE_DEG`), the positions figure and the animated block (drawing only)."""
    t = ctx.t
    positions, animation = output.artifacts["positions"], output.artifacts["animation"]
    angles = output.results["crank_angles_deg"]
    order = " – ".join(positions.firing_order)
    marks = {"alpha": "α", "beta": "β", "omega": "ω", "tdc": t("drawing.mark_tdc"), "bdc": t("drawing.mark_bdc")}
    fig, scale = md.scheme_figure(positions, len(POSITIONS), _labels(positions, ctx), t("drawing.crank_star"),
                                 t("drawing.firing_order", order=order) if order else "", marks)
    scale = scale_text(scale, t)
    scheme_angle = ctx.angle_text(output.results["scheme_angle_deg"])
    figure_scheme = ctx.figure(fig, t("drawing.scheme_caption", scale=scale, angle=scheme_angle), "scheme",
                               see="drawing.see_scheme")
    # none for a whole degree, the step's resolution otherwise: "0°", "75,4°", "180°", "284,6°"
    frames = position_frames(angles, lambda k: t("drawing.position_" + k, angle=ctx.angle_text(angles[k])))
    figure_positions = _positions_figures(ctx, positions, frames)
    svg, payload = md.animation_svg(animation)
    curves = output.artifacts["curves"]
    plot = md.cursor_plot_svg(curves["v"], curves["j"], t("drawing.curve_v"), t("drawing.curve_j"))
    # no conclusion of its own: the kinematics section's states the same angles, computed
    marked = md.angle_mark_parts(md.front_view(positions)) is not None  # the text names each mark
    return ctx.render_template("sections/drawing.html.j2", figure_scheme=figure_scheme, scale=scale,
                               scheme_angle=scheme_angle, marks=marked, stroke="S" in positions.dimensions,
                               front_view=_front_view_kind(positions),
                               master_rod=bool(md.master_rod_bodies(positions, 0)),
                               counterweight=bool(md.counterweights(positions, 0)),
                               figure_positions=figure_positions, svg=Markup(svg), plot=Markup(plot),
                               payload=Markup(payload.replace("</", "<\\/")),
                               step=output.results["animation_step_deg"], angles=angles, positions=POSITIONS)


def _positions_figures(ctx, positions, frames) -> Markup:
    """The positions figure, on as many figures as the page needs (:func:`md.positions_sheets`):
    the second and later ones captioned as the continuation."""
    t = ctx.t
    sheets = md.positions_sheets(positions, frames)
    parts = [ctx.figure(partial(md.positions_figure, positions, sheets[0]), t("drawing.positions_caption"),
                        "positions", see="drawing.see_positions")]
    for k, sheet in enumerate(sheets[1:], start=2):
        parts.append(ctx.figure(partial(md.positions_figure, positions, sheet),
                                t("drawing.positions_caption_continued"), f"positions_{k}",
                                see="drawing.see_positions_continued"))
    return Markup("\n").join(parts)


_COMMON = dict(template_dir=TEMPLATES, title_key="drawing.title", provides=(), run=run, render=render,
               references=("poda2007",), figures=("scheme", "positions", "positions_*"), tables=(),
               services=(SERVICE_RUNNER,))

DRAWING_STAGE = Stage(name="drawing", requires=(KINEMATICS,), applies=applies, **_COMMON)
# After the mechanism's own section (nothing orders it: it requires no data).
LINKAGE_DRAWING_STAGE = Stage(name="drawing_linkage", requires=(), applies=applies_linkage, last=True, **_COMMON)
