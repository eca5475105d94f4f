"""The optional ``[numerics]`` scene table: the angle steps studied, the repeats and the time
budget, the error allowed."""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field

from crankdyn.scene import (
    number,
    options,
)

DEFAULT_STEPS_DEG = (30.0, 15.0, 10.0, 5.0, 2.0, 1.0, 0.5, 0.25, 0.1)


class NumericsOptions(BaseModel):
    """The optional [numerics] table."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    steps_deg: list[number(ge=0.01, le=30)] = list(DEFAULT_STEPS_DEG)
    repeats: Annotated[int, Field(ge=1, le=100)] = 15
    time_budget_s: Annotated[float, Field(gt=0, le=3600)] = 10.0
    max_error_percent: Annotated[float, Field(gt=0)] = 1.0
    tolerance: Annotated[float, Field(gt=0, lt=0.1)] = (
        1e-3  # relative error allowed in the reported peaks
    )
    kinematics_forms: bool = True


#: The relative error of the peaks that a 1 deg step keeps for the bundled engines.
ONE_DEGREE_TOLERANCE = 1e-3


#: The steps a firing interval takes at least: the excess work ΔL is read off the torque's
#: cumulative integral over one interval, and a V16 two-stroke's 22.5° interval loses 1.1 % of
#: ΔL at 0.94° (24 steps), 0.13 % at 72 steps; a V8's 90° interval takes 90 steps at 1°.
STEPS_PER_FIRING_INTERVAL = 72


def default_angle_step_deg(scene) -> float:
    """The step [deg] a scene without ``analysis.angle_step_deg`` is computed at: 1 deg x
    sqrt(tolerance / 0.1 %), and no more than the mean firing interval (the cycle over the
    cylinders) over :data:`STEPS_PER_FIRING_INTERVAL` times the same factor. The error of a peak
    read off a grid grows as the step squared (f(x0 + h/2) = f_max - f''(x0) h^2/8), and 1 deg
    keeps the peaks of the bundled engines within 0.1 % (the study measures it for every scene
    and reports it)."""
    tolerance = options(scene, "numerics", NumericsOptions).tolerance
    factor = math.sqrt(tolerance / ONE_DEGREE_TOLERANCE)
    interval = scene.engine.cycle_deg / max(scene.engine.cylinders, 1)
    return factor * min(1.0, interval / STEPS_PER_FIRING_INTERVAL)
