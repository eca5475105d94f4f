"""The options model of the ``offset_crank`` plugin's scene table and its helpers."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from crankdyn.scene import quantity


class OffsetParams(BaseModel):
    """The [mechanism] table of an offset crank-slider."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    offset: quantity("length", ge=-2.0, le=2.0, unit="mm", scale=1e-3)
