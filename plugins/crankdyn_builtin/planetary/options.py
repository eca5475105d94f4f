"""The options model of the ``planetary`` plugin's scene table and its helpers."""

from __future__ import annotations

from fractions import Fraction
from typing import Annotated, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, model_validator

from crankdyn.scene import number, quantity


def _teeth(value: int) -> int:
    if value < 3:
        raise ValueError("must be a whole number of teeth, at least 3")
    return value


Teeth = Annotated[int, AfterValidator(_teeth)]


class PlanetaryParams(BaseModel):
    """The [mechanism] table of a planetary crank mechanism."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    gear: Literal["external", "internal"]
    fixed_gear_teeth: Teeth | None = None
    planet_teeth: Teeth | None = None
    module: quantity("length", gt=0, le=0.1, unit="mm", scale=1e-3) | None = None
    fixed_gear_pitch_diameter: quantity("length", gt=0, le=4.0, unit="mm", scale=1e-3) | None = None
    planet_pitch_diameter: quantity("length", gt=0, le=4.0, unit="mm", scale=1e-3) | None = None
    pin_radius: quantity("length", ge=0, le=2.0, unit="mm", scale=1e-3)
    pin_phase_deg: number(ge=-360, le=360) = 0.0
    pressure_angle_deg: number(ge=0, lt=45) = 20.0

    @model_validator(mode="after")
    def _sizes(self) -> PlanetaryParams:
        teeth = (self.fixed_gear_teeth, self.planet_teeth, self.module)
        diameters = (self.fixed_gear_pitch_diameter, self.planet_pitch_diameter)
        by_teeth = all(v is not None for v in teeth)
        by_diameters = all(v is not None for v in diameters)
        if (
            by_teeth == by_diameters
            or (by_teeth and any(v is not None for v in diameters))
            or (by_diameters and any(v is not None for v in teeth))
        ):
            raise ValueError(
                "give either fixed_gear_teeth, planet_teeth and module, or fixed_gear_pitch_diameter "
                "and planet_pitch_diameter (the fixed gear is the sun for gear = 'external', the "
                "ring for gear = 'internal')"
            )
        if self.gear == "internal":
            planet, fixed = (
                (self.planet_teeth, self.fixed_gear_teeth)
                if by_teeth
                else (self.planet_pitch_diameter, self.fixed_gear_pitch_diameter)
            )
            if planet >= fixed:
                raise ValueError(
                    "a planet inside a ring gear must be smaller than the ring "
                    f"(planet {planet:g} >= ring {fixed:g})"
                )
        return self

    def radii_m(self) -> tuple[float, float]:
        if self.module is not None:
            return 0.5 * self.module * self.fixed_gear_teeth, 0.5 * self.module * self.planet_teeth
        return 0.5 * self.fixed_gear_pitch_diameter, 0.5 * self.planet_pitch_diameter

    def ratio(self) -> Fraction | float:
        if self.module is not None:
            return Fraction(self.fixed_gear_teeth, self.planet_teeth)
        return self.fixed_gear_pitch_diameter / self.planet_pitch_diameter
