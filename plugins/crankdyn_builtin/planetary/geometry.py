"""Geometry of the planetary crank mechanism, from :mod:`crankdyn.physics.planetary`.

Frame: see :class:`crankdyn.plugin.types.MechanismGeometry` (the physics module's frame:
``x`` lateral, ``y`` = its ``z``). The crank angle is measured from TDC, the carrier angle
from the cylinder axis: phi = alpha + phi_TDC.
"""

from __future__ import annotations

import numpy as np

from crankdyn.physics import planetary as pl
from crankdyn.physics.plane import polar
from crankdyn.plugin.types import Guide, MechanismGeometry

from .compute import geometry_of


def planetary_geometry(scene, crank_angle_rad) -> MechanismGeometry:
    """Carrier O-C, the planet's pin arm C-B (B on the epi-/hypocycloid), rod B-A, piston pin A."""
    params, geometry = geometry_of(scene)
    revolutions = pl.motion_period_revolutions(params.ratio())
    dc = pl.dead_centres(geometry, revolutions)
    alpha = np.asarray(crank_angle_rad, dtype=float)
    phi = alpha + dc.tdc_carrier_angle_rad
    x, z, *_ = pl.big_end_path(phi, geometry)
    slider = pl.slider_motion(phi, geometry)
    joints = {
        "crank_centre": np.zeros((len(alpha), 2)),
        "planet_centre": polar(geometry.carrier_radius_m, phi),
        "crank_pin": np.stack([x, z], axis=-1),
        "wrist_pin": np.stack([np.zeros_like(z), slider.pin_z_m], axis=-1),
    }
    path = np.linspace(0.0, 2 * np.pi * revolutions, 721 * revolutions)
    px, pz, *_ = pl.big_end_path(path, geometry)
    return MechanismGeometry(
        joints=joints,
        links=[
            ("carrier", "crank_centre", "planet_centre"),
            ("planet", "planet_centre", "crank_pin"),
            ("rod", "crank_pin", "wrist_pin"),
        ],
        guides=[
            Guide(
                "wrist_pin",
                travel_m=(dc.bdc_height_m, dc.tdc_height_m),
                bore_m=scene.engine.bore,
                label="1",
            )
        ],
        circles=[
            ("crank_centre", geometry.fixed_pitch_radius_m, "fixed"),
            ("planet_centre", geometry.planet_pitch_radius_m, "moving"),
        ],
        traces={"big_end_path": np.stack([px, pz], axis=-1)},
        dimensions={
            "a": geometry.carrier_radius_m,  # the carrier's radius, not a crank's R
            "L": geometry.rod_length_m,
            "D": scene.engine.bore,
        },
        travel_m=dc.tdc_height_m - slider.pin_z_m,
    )
