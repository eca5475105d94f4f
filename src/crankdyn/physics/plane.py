"""Points of a mechanism's plane in the drawing frame of
:class:`crankdyn.plugin.types.MechanismGeometry`: angles clockwise from +y, lengths in m."""

from __future__ import annotations

import math

import numpy as np


def unit(angle_rad: float) -> np.ndarray:
    """The unit vector at ``angle_rad`` clockwise from +y (the drawing's crank direction)."""
    return np.array([math.sin(angle_rad), math.cos(angle_rad)])


def polar(radius_m, angle_rad) -> np.ndarray:
    """Points (n, 2) at ``radius_m`` and angles ``angle_rad`` clockwise from +y."""
    angle = np.asarray(angle_rad, dtype=float)
    return np.stack([radius_m * np.sin(angle), radius_m * np.cos(angle)], axis=-1)


def along(axis_rad: float, distance_m) -> np.ndarray:
    """Points (n, 2) on the axis through the origin at ``axis_rad``, ``distance_m`` from it."""
    return np.asarray(distance_m, dtype=float)[:, None] * unit(axis_rad)[None, :]
