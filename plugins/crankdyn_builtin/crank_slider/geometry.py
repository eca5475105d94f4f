"""Geometry of the central crank-slider, alone or as the banks of a multi-cylinder engine.

Joint positions come from the kinematics' own functions (:mod:`crankdyn.physics.kinematics`
for a central or fork rod, :mod:`crankdyn.physics.articulated` for slave rods), so the drawing
and the tables share one geometry. Frame: see :class:`crankdyn.plugin.types.MechanismGeometry`.
"""

from __future__ import annotations

import math

import numpy as np

from crankdyn.physics import articulated as art
from crankdyn.physics import kinematics as kin
from crankdyn.physics.plane import along, polar, unit
from crankdyn.plugin.contracts import ArticulatedOptions
from crankdyn.plugin.scene_inputs import engine_layout, slave_geometries
from crankdyn.plugin.types import Guide, MechanismGeometry
from crankdyn.scene import options

#: The scene table of the articulated rods (the bay stage's), read for the slave rods' drawing.
ARTICULATED = "articulated"


def single_geometry(scene, crank_angle_rad) -> MechanismGeometry:
    """One central crank-slider: crank O-B, rod B-A, piston pin A on the cylinder axis (its one
    cylinder is not numbered in the drawing)."""
    e = scene.engine
    R, L = e.crank_radius_m, e.rod_length_m
    alpha = np.asarray(crank_angle_rad, dtype=float)
    s = kin.piston_displacement_exact_m(alpha, R, R / L)
    joints = {
        "crank_centre": np.zeros((len(alpha), 2)),
        "crank_pin": polar(R, alpha),
        "wrist_pin": along(0.0, R + L - s),
    }
    return MechanismGeometry(
        joints=joints,
        links=[("crank", "crank_centre", "crank_pin"), ("rod", "crank_pin", "wrist_pin")],
        guides=[Guide("wrist_pin", travel_m=(L - R, L + R), bore_m=e.bore)],
        dimensions={"R": R, "L": L, "D": e.bore, "S": 2 * R},  # a central crank-slider's stroke
        travel_m=s,
    )


def engine_geometry(scene, crank_angle_rad) -> MechanismGeometry:
    """A multi-cylinder engine in front view: every crank, rod and piston in one plane.

    ``crank_angle_rad`` is the crank angle of cylinder 1 (the shaft angle). Crank k trails
    crank 1 by its lag; a cylinder whose axis lies at psi (clockwise from cylinder 1) is at
    its own crank angle ``alpha - lag - psi``. Articulated slave rods hang on the master rod
    of their crank at the pin C of :func:`crankdyn.physics.articulated.slave_motion`.
    """
    e = scene.engine
    if e.cylinders == 1:
        return single_geometry(scene, crank_angle_rad)
    layout = engine_layout(scene)
    R, L = e.crank_radius_m, e.rod_length_m
    alpha = np.asarray(crank_angle_rad, dtype=float)
    n = len(alpha)
    joints = {"crank_centre": np.zeros((n, 2))}
    links, guides, cranks = [], [], []
    slaves = _slaves(scene, layout) if e.rod_type == "articulated" else {}
    travel = None
    for k, lag in enumerate(layout.crank_lag_deg):
        pin = f"crank_pin_{k + 1}"
        shaft = alpha - math.radians(lag)
        joints[pin] = polar(R, shaft)
        links.append((f"crank_{k + 1}", "crank_centre", pin))
        bay = layout.bay(k)
        cranks.append((str(k + 1), float(lag), tuple(c.label for c in bay)))
        master = next(c for c in bay if c.master)
        for c in bay:
            psi = math.radians(c.axis_deg)
            wrist = f"wrist_pin_{c.label}"
            if c.master or not slaves:
                s = kin.piston_displacement_exact_m(shaft - psi, R, R / L)
                joints[wrist] = along(psi, R + L - s)
                links.append((f"rod_{c.label}", pin, wrist))
                low, high = L - R, L + R
                if travel is None:
                    travel = s
            else:
                g = slaves[round(c.axis_deg - master.axis_deg, 9)]
                psi_m = math.radians(master.axis_deg)
                motion = art.slave_motion(shaft - psi_m, g)
                slave_pin = f"slave_pin_{c.label}"
                # Master frame (a along the master axis, n clockwise from it) to the drawing frame.
                joints[slave_pin] = (
                    motion.pin_a_m[:, None] * unit(psi_m)[None, :]
                    + motion.pin_n_m[:, None] * unit(psi_m + math.pi / 2)[None, :]
                )
                joints[wrist] = along(psi, motion.piston_position_m)
                master_wrist = f"wrist_pin_{master.label}"
                links += [
                    (f"master_{c.label}", pin, slave_pin),
                    (f"master_web_{c.label}", slave_pin, master_wrist),
                    (f"rod_{c.label}", slave_pin, wrist),
                ]
                x_tdc, _, x_bdc, _ = art.slave_dead_centres(g)
                low, high = x_bdc, x_tdc
            guides.append(
                Guide(
                    wrist,
                    direction=tuple(unit(psi)),
                    travel_m=(low, high),
                    bore_m=e.bore,
                    label=c.label,
                )
            )
    dimensions = {"R": R, "L": L, "D": e.bore, "S": 2 * R}
    if slaves:  # a radial's knuckle-pin radius r and its first slave rod's length
        first = next(iter(slaves.values()))
        dimensions |= {"r": first.pin_radius_m, "l_s": first.slave_rod_length_m}
    return MechanismGeometry(
        joints=joints,
        links=links,
        guides=guides,
        dimensions=dimensions,
        travel_m=travel,
        cranks=cranks,
        firing_order=tuple(layout.firing_order),
    )


def _slaves(scene, layout) -> dict[float, art.SlaveGeometry]:
    """Slave-rod geometry by the slave's bank angle from its master (deg)."""
    opts = options(scene, ARTICULATED, ArticulatedOptions)
    return {
        round(math.degrees(g.bank_angle_rad), 9): g
        for _, g in slave_geometries(scene, layout, opts, ARTICULATED)
    }
