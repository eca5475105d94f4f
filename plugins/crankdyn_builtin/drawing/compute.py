"""The mechanism drawn: the positions of its members at the scheme's, the characteristic and the
animation's crank angles.

Any mechanism whose plugin gives ``Mechanism.geometry`` is drawn (see
:class:`crankdyn.plugin.types.MechanismGeometry`). The characteristic positions (TDC, BDC, the
extremes of the piston velocity and acceleration) are taken from the kinematics the
``kinematics`` data key carries (``drawing``); a mechanism without a piston motion (the vane
engine) is drawn from its geometry's output travel (``drawing_linkage``).
"""

from __future__ import annotations

import numpy as np

from crankdyn.physics.extrema import first_argmax, first_argmin
from crankdyn.physics.scalar_search import minimize_bounded
from crankdyn.plugin.contracts import KINEMATICS
from crankdyn.plugin.types import SERVICE_RUNNER, StageOutput
from crankdyn.report import mechanism_drawing as md

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
    return any(
        KINEMATICS in s.provides and runner.applies(s, scene) is None
        for s in runner.stages.values()
    )


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
    res = minimize_bounded(
        lambda a: -sign * f(a), angle_deg[i] - step, angle_deg[i] + step, xatol=1e-9
    )
    return float(res.x) if -res.fun >= sign * f(angle_deg[i]) else float(angle_deg[i])


def characteristic_angles(
    angle_deg, s, v, j, travel_at=None, period_deg: float = 360.0
) -> dict[str, float]:
    """Crank angles (deg, in [0, ``period_deg``): a planetary mechanism's motion repeats over
    several turns, and its fastest travel at 647,5° is not where the crank stands at 287,5°) of
    TDC, BDC and the velocity and acceleration extremes."""
    found = {
        "tdc": _refined(travel_at, angle_deg, s, 0, "min"),
        "bdc": _refined(travel_at, angle_deg, s, 0, "max"),
        "v_max": _refined(travel_at, angle_deg, v, 1, "max"),
        "v_min": _refined(travel_at, angle_deg, v, 1, "min"),
        "j_max": _refined(travel_at, angle_deg, j, 2, "max"),
        "j_min": _refined(travel_at, angle_deg, j, 2, "min"),
    }
    wrapped = {k: float(a % period_deg) for k, a in found.items()}
    return {k: 0.0 if min(a, period_deg - a) < 1e-6 else a for k, a in wrapped.items()}


def _period_deg(angle_deg, s) -> float:
    """360 when the travel repeats every revolution on the grid, else the whole grid's span."""
    step = angle_deg[1] - angle_deg[0]
    span = step * len(angle_deg)
    shift = int(round(360.0 / step))
    if span > 360.0 + 1e-9 and np.allclose(
        s[: len(s) - shift], s[shift:], rtol=0, atol=1e-9 * np.ptp(s)
    ):
        return 360.0
    return float(min(span, 360.0)) if span <= 360.0 + 1e-9 else float(span)


def _motion(scene, inputs):
    """(angle deg, s, v, j, travel_at) from the kinematics, or from the geometry's travel."""
    motion = inputs.get(KINEMATICS)
    if motion is not None:
        return (
            motion.crank_angle_deg,
            motion.piston_displacement_m,
            motion.piston_velocity_m_s,
            motion.piston_acceleration_m_s2,
            motion.displacement_at,
        )
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
    period = _period_deg(angle, s)
    angles = characteristic_angles(angle, s, v, j, travel_at, period)
    # dead centres a mechanism reaches more than twice a turn (a planetary one), after the six
    motion = inputs.get(KINEMATICS)
    extra = motion.extra.get("dead_centres_extra_deg", {}) if motion is not None else {}
    angles.update({k: float(a) for k, a in extra.items()})
    step = angle[1] - angle[0]
    every = (
        max(1, int(round(period / FRAMES_PER_REVOLUTION / step)))
        if period <= 360.0
        else max(1, int(round(period / (2 * FRAMES_PER_REVOLUTION) / step)))
    )
    frames_deg = np.arange(0.0, period - 1e-9, step * every)
    # the characteristic positions, then the scheme's
    scheme_angle = scheme_angle_deg(geometry_of(scene, np.zeros(1)))
    at = np.radians(list(angles.values()) + [scheme_angle])
    positions = geometry_of(scene, at)
    animation = geometry_of(scene, np.radians(frames_deg))
    grid = np.rint(np.interp(frames_deg, angle, np.arange(len(angle)))).astype(int)
    curves = {"v": np.asarray(v)[grid], "j": np.asarray(j)[grid]}
    results = {
        "crank_angles_deg": dict(angles),
        "animation_frames": int(len(frames_deg)),
        "animation_step_deg": float(step * every),
        "motion_period_deg": period,
        "scheme_angle_deg": scheme_angle,
    }
    # No tables: the joint positions are drawing data (kept for render only), the angles are in results.
    return StageOutput(
        results=results,
        artifacts={"positions": positions, "animation": animation, "curves": curves},
    )
