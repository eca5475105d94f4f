"""The ``[torsion]`` table's options model: the shaft's stiffnesses and the torsional model's choices."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, model_validator

from crankdyn.scene import number as _number
from crankdyn.scene import quantity as _quantity
from crankdyn.scene.units import parse_quantity


def _stiffness(kind_max: float = 1e12):
    return _quantity("torsional_stiffness", gt=0, le=kind_max, unit="N*m/rad")


def _stiffness_list(value):
    """One stiffness for every span, or a list with one per span."""
    items = value if isinstance(value, list) else [value]
    if not items:
        raise ValueError("give a stiffness such as '3e5 N*m/rad', or a list with one per span")
    out = []
    for item in items:
        stiffness = parse_quantity(item, "torsional_stiffness")
        if not 0 < stiffness <= 1e12:
            raise ValueError(f"{item!r}: must be > 0 and <= 1e12 N*m/rad")
        out.append(stiffness)
    return out if isinstance(value, list) else out[0]


class TorsionOptions(BaseModel):
    """The [torsion] table: the torsional multi-mass model of the crankshaft."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    span_stiffness: Annotated[float | list[float], BeforeValidator(_stiffness_list)]
    flywheel_stiffness: _stiffness() | None = None
    free_end_inertia: _quantity("moment_of_inertia", gt=0, le=1e6, unit="kg*m^2") | None = None
    free_end_stiffness: _stiffness() | None = None
    load_inertia: _quantity("moment_of_inertia", gt=0, le=1e6, unit="kg*m^2") | None = None
    coupling_stiffness: _stiffness() | None = None
    damping_ratio: _number(ge=0, lt=1) = 0.02
    solver: Literal["auto", "RK45", "Radau", "BDF", "LSODA"] = "auto"
    rtol: _number(ge=1e-10, le=1e-2) = 1e-4
    steady_tolerance: _number(gt=0, le=0.1) = 1e-3
    max_cycles: _number(ge=1, le=200) = 30
    compare_solvers: bool = True
    compare_rtols: list[_number(ge=1e-10, le=1e-2)] = [1e-3, 1e-4]
    reference_rtol: _number(ge=1e-12, le=1e-4) = 1e-6
    compare_fraction: _number(gt=0, le=1) = 0.25
    explicit_budget: _number(ge=100, le=1e7) = 20000

    @model_validator(mode="after")
    def _consistent(self) -> TorsionOptions:
        if (self.free_end_inertia is None) != (self.free_end_stiffness is None):
            raise ValueError(
                "give free_end_inertia and free_end_stiffness together (a disc ahead of crank 1: "
                "timing gear, pulley or damper, and the stiffness of the crank nose), or neither"
            )
        if (self.load_inertia is None) != (self.coupling_stiffness is None):
            raise ValueError(
                "give load_inertia and coupling_stiffness together (the load disc and the coupling "
                "between the flywheel and it), or neither (the load torque then acts on the flywheel)"
            )
        if self.reference_rtol >= min(self.compare_rtols, default=1.0):
            raise ValueError("reference_rtol must be smaller than every compare_rtols value")
        return self
