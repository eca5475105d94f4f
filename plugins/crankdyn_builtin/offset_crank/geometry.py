"""Geometry of the offset (desaxial) crank-slider, from :mod:`crankdyn.physics.offset_crank`.

Frame: see :class:`crankdyn.plugin.types.MechanismGeometry` (it is the physics module's frame:
``x`` lateral, ``y`` = its ``z``). The cylinder axis is the line x = e.
"""

from __future__ import annotations

import numpy as np

from crankdyn.physics import offset_crank as oc
from crankdyn.physics.plane import polar
from crankdyn.plugin.scene_inputs import engine_layout
from crankdyn.plugin.types import Guide, MechanismGeometry
from crankdyn.scene import options

from .options import OffsetParams


def offset_geometry(scene, crank_angle_rad) -> MechanismGeometry:
    """Crank O-B at phi = alpha + phi_TDC, rod B-A, piston pin A = (e, z_A) on the offset axis."""
    e = scene.engine
    R, L, offset = (
        e.crank_radius_m,
        e.rod_length_m,
        options(scene, "mechanism", OffsetParams).offset,
    )
    dc = oc.dead_centres(R, L, offset)
    alpha = np.asarray(crank_angle_rad, dtype=float)
    phi = alpha + dc.tdc_angle_rad
    z = oc.piston_pin_height_m(phi, R, R / L, offset / L)
    joints = {
        "crank_centre": np.zeros((len(alpha), 2)),
        "crank_pin": polar(R, phi),
        "wrist_pin": np.stack([np.full_like(z, offset), z], axis=-1),
    }
    return MechanismGeometry(
        joints=joints,
        links=[("crank", "crank_centre", "crank_pin"), ("rod", "crank_pin", "wrist_pin")],
        guides=[
            Guide(
                "wrist_pin",
                origin_m=(offset, 0.0),
                travel_m=(dc.bdc_height_m, dc.tdc_height_m),
                bore_m=e.bore,
                label="1",
            )
        ],
        dimensions={
            "R": R,
            "L": L,
            "e": offset,
            "D": e.bore,
            "S": dc.tdc_height_m - dc.bdc_height_m,
        },
        travel_m=oc.piston_displacement_m(alpha, R, R / L, offset / L),
        **_crank_star(scene),
    )


def _crank_star(scene) -> dict:
    """A multi-cylinder engine's cranks (the scheme's crank star) and firing order: the scheme
    draws the first cylinder's mechanism, the star the directions of all the cranks."""
    if scene.engine.cylinders < 2:
        return {}
    layout = engine_layout(scene)
    cranks = [
        (str(k + 1), float(lag), tuple(c.label for c in layout.bay(k)))
        for k, lag in enumerate(layout.crank_lag_deg)
    ]
    return {"cranks": cranks, "firing_order": tuple(layout.firing_order)}
