"""The ``[flywheel]`` scene table: a chosen flywheel or the irregularity to design one for."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, model_validator

from crankdyn.scene import number as _number
from crankdyn.scene import quantity as _quantity


class FlywheelOptions(BaseModel):
    """The [flywheel] table."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    required_irregularity: _number(gt=0, le=0.2) | None = None
    inertia: _quantity("moment_of_inertia", gt=0, le=1e5, unit="kg*m^2") | None = None
    engine_inertia: _quantity("moment_of_inertia", ge=0, le=1e5, unit="kg*m^2") = "0 kg*m^2"
    rim_mean_diameter: _quantity("length", gt=0, le=10.0, unit="mm", scale=1e-3) | None = None
    rim_width: _quantity("length", gt=0, le=5.0, unit="mm", scale=1e-3) | None = None
    rim_density: _quantity("density", gt=0, le=25000, unit="kg/m^3") = "7200 kg/m^3"
    rim_fraction: _number(gt=0, le=1) = 1.0
    max_rim_speed: _quantity("velocity", gt=0, le=1000, unit="m/s") | None = None

    @model_validator(mode="after")
    def _something_to_do(self) -> FlywheelOptions:
        if self.required_irregularity is None and self.inertia is None:
            raise ValueError(
                "give required_irregularity (delta, e.g. 0.01, to design the flywheel) "
                "and/or inertia (a chosen flywheel, e.g. '0.12 kg*m^2')"
            )
        if self.rim_width is not None and self.rim_mean_diameter is None:
            raise ValueError("rim_width needs rim_mean_diameter")
        return self
