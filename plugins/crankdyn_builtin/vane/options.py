"""The options model of the ``vane`` plugin's scene table and its helpers."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from crankdyn.scene import number, quantity


class VaneParams(BaseModel):
    """The [mechanism] table of the vane engine (all optional)."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    core_offset: quantity("length", ge=0, le=2.0, unit="mm", scale=1e-3) = "0 mm"
    compare_rod_ratios: list[number(gt=0, lt=1)] = []
