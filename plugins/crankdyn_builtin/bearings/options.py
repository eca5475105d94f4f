"""The options model of the ``bearings`` plugin's scene table and its helpers."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from crankdyn.scene import number, quantity


class BearingOptions(BaseModel):
    """The [bearings] table."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    crank_pin_diameter: quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    crank_pin_width: quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    main_journal_diameter: quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    main_journal_width: quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    span_ratio: number(gt=0, lt=1) = 0.5
    pins: list[int] | None = None
    journals: list[int] | None = None
    wear_spread_deg: number(gt=0, le=90) = 60.0
