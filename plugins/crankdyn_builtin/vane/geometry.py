"""Geometry of the vane engine's crank-rocker parallelogram, from :mod:`crankdyn.physics.vane`.

Frame: see :class:`crankdyn.plugin.types.MechanismGeometry`, origin on the core axis O3. The
two equal cranks (centres O1 above, O2 below, on the vertical through O3) carry the rocker
A1-A2 (a T: the bar A1-A2 and the upright slot on its middle S, at x = r sin alpha) that
translates; the core's tail O3-P (length l) ends in the slider P in the slot; the vane
continues the core beyond O3. The cranks sit side by side (1.5 r either side of the
vertical through O3) below the slider's path, so the slot spans the slider's travel 0...2r
along it; where they sit does not change the kinematics.
"""

from __future__ import annotations

import numpy as np

from crankdyn.physics import vane as vn
from crankdyn.physics.plane import polar
from crankdyn.plugin.types import Guide, MechanismGeometry


def vane_geometry(scene, crank_angle_rad) -> MechanismGeometry:
    """Joints O1, O2, A1, A2, S (cranks and rocker), O3 (core axis), P (slider), V (vane tip)."""
    r, l_tail = scene.engine.crank_radius_m, scene.engine.rod_length_m
    lam = r / l_tail
    alpha = np.asarray(crank_angle_rad, dtype=float)
    n = len(alpha)
    xk, yk = vn.rocker_position_m(alpha, r)
    slider = np.stack([xk, -vn.slider_height_below_core_m(alpha, r, lam)], axis=-1)
    base = -l_tail - 1.4 * r  # height of the cranks' centres
    o1, o2 = np.array([-1.5 * r, base]), np.array([1.5 * r, base])
    slot_base = np.array([0.0, base]) + polar(r, alpha)
    joints = {
        "crank_centre": np.zeros((n, 2)) + o1,
        "pivot_crank_2": np.zeros((n, 2)) + o2,
        "crank_pin": o1 + polar(r, alpha),
        "rocker_pin_2": o2 + polar(r, alpha),
        "slot_base": slot_base,
        "slot_top": slot_base + [0.0, 2.6 * r],
        "pivot_core": np.zeros((n, 2)),
        "slider": slider,
        "vane_tip": -0.6 * slider,
    }
    return MechanismGeometry(
        joints=joints,
        links=[
            ("crank", "crank_centre", "crank_pin"),
            ("crank_2", "pivot_crank_2", "rocker_pin_2"),
            ("rocker", "crank_pin", "rocker_pin_2"),
            ("rocker_slot", "slot_base", "slot_top"),
            ("core", "pivot_core", "slider"),
            ("vane", "pivot_core", "vane_tip"),
        ],
        fixed=("crank_centre", "pivot_crank_2", "pivot_core"),
        guides=[
            Guide("slider", moving=("slot_base", "slot_top"), travel_m=(0.4 * r, 2.4 * r), label="")
        ],
        dimensions={"R": r, "L": l_tail},
        travel_m=vn.slider_relative_position_m(alpha, r, lam),
    )
