"""Offset (desaxial) crank-slider: mechanism and kinematics stage.

The kinematics are exact for any pin offset e; the force, torque and indicator stages
take them through ``PistonMotion`` unchanged (the force stage resolves the rod force at
the crank's angle from the cylinder axis, ``extra["crank_angle_at_tdc_rad"]``).

The computation: ``applies``, ``run`` and their pure helpers.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from crankdyn.errors import Problem
from crankdyn.physics import kinematics as central
from crankdyn.physics import offset_crank as oc
from crankdyn.physics.extrema import first_argmax
from crankdyn.physics.scalar_search import minimize_bounded
from crankdyn.plugin.contracts import KINEMATICS, PistonMotion
from crankdyn.plugin.types import Digits, StageOutput
from crankdyn.scene import options

from .options import OffsetParams
from .precision import STROKE_DIGITS

MECHANISM = "offset_crank_slider"

#: Plugin tables that only a multi-cylinder engine reads (the articulated rods).
MULTI_CYLINDER_TABLES = ("articulated",)


def _layout_problems(scene) -> list[Problem]:
    """An offset crank-slider engine has one or more cylinders, each with its own central-type rod
    on its crank pin (in line, V, boxer); articulated rods are built on a central master rod."""
    problems = []
    if scene.engine.rod_type == "articulated":
        problems.append(
            Problem(
                "engine.rod_type",
                "articulated",
                "the offset crank-slider's rods are its own: "
                "central or fork_and_blade (articulated rods need the central crank-slider)",
            )
        )
    for table in MULTI_CYLINDER_TABLES:
        if table in scene.plugin_tables():
            problems.append(
                Problem(
                    table,
                    f"[{table}]",
                    "applies to articulated rods, which the offset crank-slider does not have",
                )
            )
    return problems


def check(scene) -> list[Problem]:
    problems = _layout_problems(scene)
    params = options(scene, "mechanism", OffsetParams)
    R, L = scene.engine.crank_radius_m, scene.engine.rod_length_m
    try:
        oc.check_offset(R, L, params.offset)
    except ValueError:
        problems.append(
            Problem(
                "mechanism.offset",
                scene.mechanism.get("offset"),
                f"|e| must be < L - R = {(L - R) * 1e3:g} mm: with a larger offset the rod cannot "
                "reach the crank pin at every angle (the crank cannot turn a full revolution), "
                "and at |e| = L - R the linkage locks at BDC",
            )
        )
    return problems


def applies(scene) -> str | None:
    if scene.engine.mechanism != MECHANISM:
        return f"the scene's mechanism is {scene.engine.mechanism!r}, not the offset crank-slider"
    return None


def _extreme(fn, angle_deg, values, sign):
    """Refine a grid extreme of ``fn`` (a function of alpha in rad): (value, angle in deg)."""
    i = first_argmax(sign * values)
    step = np.radians(angle_deg[1] - angle_deg[0]) if len(angle_deg) > 1 else 0.1
    centre = np.radians(angle_deg[i])
    res = minimize_bounded(
        lambda a: -sign * float(fn(a)), centre - step, centre + step, xatol=1e-12
    )
    best = float(res.x) if -res.fun >= sign * values[i] else centre
    return float(fn(best)), float(np.degrees(best) % 360.0)


def _velocity_and_acceleration_extremes(v_of, j_of, angle_deg, v, j) -> dict:
    """The piston's largest and smallest velocity (m/s) and acceleration (m/s²) with their crank
    angles (°), each refined from the grid sample by :func:`_extreme`."""
    out = {}
    for name, of, values in (("v", v_of, v), ("j", j_of, j)):
        unit = "m_s" if name == "v" else "m_s2"
        for which, sign in (("max", +1.0), ("min", -1.0)):
            value, angle = _extreme(of, angle_deg, values, sign)
            out[f"{name}_{which}_{unit}"], out[f"{name}_{which}_crank_angle_deg"] = value, angle
    return out


def _notes(scene, results: dict, stroke_m: float, crank_radius_m: float) -> list:
    """What the section says about the offset mechanism replacing the central one."""
    notes = [("offset_crank.note_replaced", {"tdc": results["tdc_crank_angle_from_axis_deg"]})]
    if scene.analysis.kinematics == "approximate":
        notes.append(("offset_crank.note_exact_only", {}))
    if scene.cycle is not None:
        four = scene.engine.strokes == 4
        notes.append(
            (
                "offset_crank.note_indicator" if four else "offset_crank.note_indicator_two",
                {
                    "stroke_mm": Digits(stroke_m * 1e3, STROKE_DIGITS),
                    "throw_mm": 2e3 * crank_radius_m,
                    "bdc": results["bdc_crank_angle_deg"],
                    "bdc_expansion": 360.0 + results["bdc_crank_angle_deg"],
                },
            )
        )
    return notes


def _displacement_at_deg(radius_m: float, ratio: float, offset_ratio: float, crank_angle_deg):
    """Piston displacement (m) at any crank angle (deg); module level, so the output pickles."""
    return oc.piston_displacement_m(np.radians(crank_angle_deg), radius_m, ratio, offset_ratio)


@dataclass(frozen=True)
class _Offset:
    """The offset crank-slider's crank radius R, lambda = R/L, k = e/L and angular velocity, with
    its piston's motion at any crank angle (rad from TDC)."""

    R: float
    lam: float
    k: float
    omega: float

    def s_of(self, a):
        """Piston displacement, m."""
        return oc.piston_displacement_m(a, self.R, self.lam, self.k)

    def v_of(self, a):
        """Piston velocity, m/s."""
        return oc.piston_velocity_m_s(a, self.R, self.lam, self.k, self.omega)

    def j_of(self, a):
        """Piston acceleration, m/s²."""
        return oc.piston_acceleration_m_s2(a, self.R, self.lam, self.k, self.omega)


def run(scene, inputs) -> StageOutput:
    engine = scene.engine
    params = options(scene, "mechanism", OffsetParams)
    R, L, e = engine.crank_radius_m, engine.rod_length_m, params.offset
    mechanism = _Offset(R, R / L, params.offset / L, engine.angular_velocity_rad_s)
    geometry = oc.dead_centres(R, L, e)
    angle_deg = scene.crank_angles_deg
    alpha = np.radians(angle_deg)
    phi = alpha + geometry.tdc_angle_rad
    curves = _offset_curves(mechanism, alpha, phi)
    results = _offset_results(mechanism, L, e, geometry, angle_deg, curves)
    table = _offset_table(angle_deg, phi, curves, mechanism.omega)
    return StageOutput(
        data={KINEMATICS: _offset_motion(mechanism, L, e, geometry, angle_deg, curves)},
        results=results,
        tables={"offset_crank": table},
        notes=_notes(scene, results, geometry.stroke_m, R),
    )


def _offset_table(angle_deg, phi, curves: dict, omega: float) -> dict:
    """The table: the piston's and the rod's motion, the torque arm v/omega and the central
    crank-slider's piston motion."""
    return {
        "crank_angle_deg": angle_deg,
        "crank_angle_from_axis_deg": np.degrees(phi),
        "piston_displacement_m": curves["piston_displacement_m"],
        "piston_velocity_m_s": curves["piston_velocity_m_s"],
        "piston_acceleration_m_s2": curves["piston_acceleration_m_s2"],
        "rod_angle_deg": curves["rod_angle_deg"],
        "rod_angular_velocity_rad_s": curves["rod_angular_velocity_rad_s"],
        "rod_angular_acceleration_rad_s2": curves["rod_angular_acceleration_rad_s2"],
        "torque_arm_m": curves["piston_velocity_m_s"] / omega,
        "central_piston_displacement_m": curves["central_piston_displacement_m"],
        "central_piston_velocity_m_s": curves["central_piston_velocity_m_s"],
        "central_piston_acceleration_m_s2": curves["central_piston_acceleration_m_s2"],
    }


def _offset_curves(mechanism: _Offset, alpha, phi) -> dict:
    """The piston's and the rod's motion over the cycle (``phi``: crank angle from the cylinder
    axis), and the central crank-slider's piston motion of the same R and lambda."""
    R, lam, k, omega = mechanism.R, mechanism.lam, mechanism.k, mechanism.omega
    beta = oc.rod_angle_rad(phi, lam, k)
    return {
        "piston_displacement_m": mechanism.s_of(alpha),
        "piston_velocity_m_s": mechanism.v_of(alpha),
        "piston_acceleration_m_s2": mechanism.j_of(alpha),
        "rod_angle_rad": beta,
        "rod_angle_deg": np.degrees(beta),
        "rod_angular_velocity_rad_s": oc.rod_angular_velocity_rad_s(alpha, R, lam, k, omega),
        "rod_angular_acceleration_rad_s2": oc.rod_angular_acceleration_rad_s2(
            alpha, R, lam, k, omega
        ),
        "central_piston_displacement_m": central.piston_displacement_exact_m(alpha, R, lam),
        "central_piston_velocity_m_s": central.piston_velocity_exact_m_s(alpha, R, lam, omega),
        "central_piston_acceleration_m_s2": central.piston_acceleration_exact_m_s2(
            alpha, R, lam, omega
        ),
    }


def _offset_results(mechanism: _Offset, L: float, e: float, geometry, angle_deg, curves) -> dict:
    """The results: sizes, dead centres and stroke, the piston's and the rod's extremes, and the
    central crank-slider's largest velocity and acceleration for comparison."""
    R, lam, k, omega = mechanism.R, mechanism.lam, mechanism.k, mechanism.omega
    v, j = curves["piston_velocity_m_s"], curves["piston_acceleration_m_s2"]
    return {
        "crank_radius_m": R,
        "rod_length_m": L,
        "rod_ratio": lam,
        "offset_m": e,
        "offset_ratio": k,
        "angular_velocity_rad_s": omega,
        "method": "exact",
        "tdc_crank_angle_from_axis_deg": float(np.degrees(geometry.tdc_angle_rad)),
        "bdc_crank_angle_from_axis_deg": float(np.degrees(geometry.bdc_angle_rad)),
        "bdc_crank_angle_deg": float(np.degrees(geometry.bdc_after_tdc_rad)),
        "stroke_m": geometry.stroke_m,
        "stroke_excess_m": geometry.stroke_m - 2.0 * R,
        "stroke_time_ratio": geometry.stroke_time_ratio,
        "mean_piston_speed_m_s": geometry.stroke_m * omega / np.pi,
        **_velocity_and_acceleration_extremes(mechanism.v_of, mechanism.j_of, angle_deg, v, j),
        "rod_angle_max_deg": float(np.degrees(np.arcsin(lam - k))),
        "rod_angle_min_deg": float(np.degrees(-np.arcsin(lam + k))),
        "rod_angular_velocity_max_rad_s": float(
            np.max(np.abs(curves["rod_angular_velocity_rad_s"]))
        ),
        "rod_angular_acceleration_max_rad_s2": float(
            np.max(np.abs(curves["rod_angular_acceleration_rad_s2"]))
        ),
        "central_v_max_m_s": float(np.max(curves["central_piston_velocity_m_s"])),
        "central_j_max_m_s2": float(central.max_piston_acceleration_m_s2(R, lam, omega)),
    }


def _offset_motion(mechanism: _Offset, L: float, e: float, geometry, angle_deg, curves):
    """The motion handed on to the later stages."""
    return PistonMotion(
        crank_angle_deg=angle_deg,
        piston_displacement_m=curves["piston_displacement_m"],
        piston_velocity_m_s=curves["piston_velocity_m_s"],
        piston_acceleration_m_s2=curves["piston_acceleration_m_s2"],
        rod_angle_rad=curves["rod_angle_rad"],
        crank_radius_m=mechanism.R,
        angular_velocity_rad_s=mechanism.omega,
        method="exact",
        extra={
            "rod_ratio": mechanism.lam,
            "rod_length_m": L,
            "offset_m": e,
            "crank_angle_at_tdc_rad": geometry.tdc_angle_rad,
            # the piston's stroke and BDC: the indicator diagram's V_h and its points a, b
            "stroke_m": geometry.stroke_m,
            "bdc_crank_angle_deg": float(np.degrees(geometry.bdc_after_tdc_rad)),
            "rod_angular_velocity_rad_s": curves["rod_angular_velocity_rad_s"],
            "rod_angular_acceleration_rad_s2": curves["rod_angular_acceleration_rad_s2"],
        },
        displacement_at=functools.partial(
            _displacement_at_deg, mechanism.R, mechanism.lam, mechanism.k
        ),
    )
