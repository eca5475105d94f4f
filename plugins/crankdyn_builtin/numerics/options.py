"""The optional ``[numerics]`` scene table: the angle steps studied, the repeats and the time
budget, the error allowed."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field

from crankdyn.scene import (
    number,
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
