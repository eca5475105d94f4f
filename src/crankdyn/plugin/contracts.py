"""Data passed between stages under the keys named in ``Stage.requires``/``provides``.

A third-party mechanism plugin that provides ``"kinematics"`` returns a
:class:`PistonMotion`; the force and torque stages then work for it unchanged.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict

from ..scene.model import number as _number
from ..scene.model import quantity as _quantity

if TYPE_CHECKING:
    from ..physics.indicator import RoundingParameters

KINEMATICS = "kinematics"
GAS_PRESSURE = "gas_pressure"
FORCES = "forces"
ENGINE_TORQUE = "engine_torque"
BAY_LOADS = "bay_loads"
CRANK_LOADS = "crank_loads"
FLYWHEEL = "flywheel"
COUNTERWEIGHTS = "counterweights"


@dataclass(frozen=True)
class PistonMotion:
    """Piston motion over one cycle on a uniform crank-angle grid (endpoint excluded).

    The piston displacement is measured from TDC towards the shaft. ``rod_angle_rad``
    is None for mechanisms without a connecting rod (e.g. a Scotch yoke).
    """

    crank_angle_deg: np.ndarray
    piston_displacement_m: np.ndarray
    piston_velocity_m_s: np.ndarray
    piston_acceleration_m_s2: np.ndarray
    rod_angle_rad: np.ndarray | None
    crank_radius_m: float
    angular_velocity_rad_s: float
    method: str  # "exact" or "approximate"
    extra: dict = field(default_factory=dict)
    # s(alpha_deg) in m for any angle: lets later stages evaluate the motion off the grid
    # (the indicator rounding does), so their results do not depend on the angle step.
    displacement_at: Callable[[np.ndarray], np.ndarray] | None = None

    @property
    def crank_angle_rad(self) -> np.ndarray:
        return np.radians(self.crank_angle_deg)

    @property
    def torque_arm_m(self) -> np.ndarray:
        """ds/dalpha (m/rad): the arm that turns an axial piston force into crank torque
        (virtual work: M = F * ds/dalpha for a rigid, frictionless mechanism)."""
        return self.piston_velocity_m_s / self.angular_velocity_rad_s


@dataclass(frozen=True)
class GasPressure:
    """In-cylinder absolute pressure over the cycle, on the kinematics grid.

    ``rounding`` is the rounding the diagram is drawn with (its peak p_z′ may be lower than asked,
    where that would stand above the theoretical diagram; a diesel's peak angle may be put on
    its isobar): :class:`crankdyn.physics.indicator.RoundingParameters`, None for a trace."""

    crank_angle_deg: np.ndarray
    pressure_Pa: np.ndarray
    volume_m3: np.ndarray
    source: str  # "theoretical" (rounded) or "trace"
    indicated_work_J: float
    swept_volume_m3: float
    rounding: RoundingParameters | None = None
    #: the part of ``indicated_work_J`` done in the gas-exchange strokes, J (negative where they
    #: take work; zero for a two-stroke): :func:`crankdyn.physics.indicator.pumping_work_J`
    pumping_work_J: float = 0.0


@dataclass(frozen=True)
class CrankForces:
    """Specific forces (Pa, per unit piston area) in the sign convention of Poda (2007).

    ``side_Pa`` (the piston's side force on the cylinder wall, N) and ``rod_Pa`` (the force along
    the rod, K) are those the forces stage reports: the two-mass model's, or the rigid rod's with
    ``[rod_dynamics] apply_to_loads``; None from a stage that does not give them.
    """

    crank_angle_deg: np.ndarray
    gas_Pa: np.ndarray
    inertia_Pa: np.ndarray
    total_Pa: np.ndarray
    tangential_Pa: np.ndarray
    radial_Pa: np.ndarray
    centrifugal_Pa: float
    piston_area_m2: float
    torque_Nm: np.ndarray
    side_Pa: np.ndarray | None = None
    rod_Pa: np.ndarray | None = None


@dataclass(frozen=True)
class EngineTorque:
    """Output torque of the whole engine over one cycle (for one cylinder: its crank torque).

    ``torque_Nm`` is the torque delivered at the power take-off end on the scene's grid;
    ``indicated_work_J`` the indicated work per cycle of all cylinders together.
    """

    crank_angle_deg: np.ndarray
    torque_Nm: np.ndarray
    cylinders: int
    strokes: int
    indicated_work_J: float
    angular_velocity_rad_s: float

    @property
    def mean_torque_Nm(self) -> float:
        return float(np.mean(self.torque_Nm))


@dataclass(frozen=True)
class BayLoads:
    """Specific forces of every bay (all cylinders on one crank pin) on its crank pin.

    Arrays have shape (cranks, N) on the shaft-angle grid of the scene (textbook table B.2
    summed per bay, already placed at each crank's phase): ``tangential_Pa`` t_Sigma,
    ``radial_Pa`` z_Sigma (towards the shaft axis), both in the crank's own axes.
    ``centrifugal_Pa`` is the constant c of each crank (all rotating masses, eq. 35) and
    ``centrifugal_rod_Pa`` the part of the rods alone (the crank-pin load, textbook §5.1).
    """

    crank_angle_deg: np.ndarray
    tangential_Pa: np.ndarray
    radial_Pa: np.ndarray
    centrifugal_Pa: float
    centrifugal_rod_Pa: float
    piston_area_m2: float
    crank_radius_m: float
    layout: object  # crankdyn.physics.layout.EngineLayout
    indicated_work_J: float  # per cycle, all cylinders (each with its own kinematics)
    #: articulated rods: each cylinder's part of crank 1's t (label -> array, Pa), None otherwise
    cylinder_tangential_Pa: dict | None = None


@dataclass(frozen=True)
class CrankLoads:
    """Loads on the crankshaft (textbook table B.3): per crank and per main journal, shape (cranks, N).

    ``pin_torque_Pa`` t_w (running torque on crank pin i, as a specific tangential force),
    ``journal_torque_Pa`` t_k (on the main journal after crank i; the last is the output).
    """

    crank_angle_deg: np.ndarray
    tangential_Pa: np.ndarray
    radial_Pa: np.ndarray
    resultant_Pa: np.ndarray
    pin_torque_Pa: np.ndarray
    journal_torque_Pa: np.ndarray
    centrifugal_Pa: float
    piston_area_m2: float
    crank_radius_m: float


@dataclass(frozen=True)
class Counterweights:
    """The counterweights the balancing stage fits on the crankshaft (none: empty arrays).

    ``crank``: the 0-based index (from the free end) of the crank each sits on (its two halves
    on that crank's webs); ``centrifugal_N``: its centrifugal force m r omega^2 at the scene's
    speed [N]; ``angle_from_crank_rad``: its direction from its crank's, in the direction of
    rotation (pi: opposite the crank pin); ``moment_of_inertia_kg_m2``: all of them together about
    the shaft's axis, as point masses at their centres' radius [kg m^2] (a lower bound: a real
    counterweight's radius of gyration exceeds its centre's radius); ``balance_shaft_inertia_kg_m2``:
    the masses of the balance shafts fitted with them, likewise as point masses, reduced to the
    crankshaft: Σ m ρ² n², n the shaft's speed over the crankshaft's [kg m^2] (kinetic energy
    (1/2) m ρ² (n ω)² at the crankshaft's ω).
    """

    crank: np.ndarray
    centrifugal_N: np.ndarray
    angle_from_crank_rad: np.ndarray
    moment_of_inertia_kg_m2: float = 0.0
    balance_shaft_inertia_kg_m2: float = 0.0
    balance_shafts: int = 0  # how many balance shafts are fitted

    @property
    def fitted(self) -> bool:
        """Whether any counterweight is fitted (one with a centrifugal force)."""
        return bool(np.any(self.centrifugal_N))


@dataclass(frozen=True)
class FlywheelDesign:
    """The flywheel of the energy method (flywheel stage) for the speed-fluctuation stage.

    ``flywheel_inertia_kg_m2`` is the flywheel the engine gets (the scene's chosen one, else
    the one designed for ``required_irregularity``); ``engine_inertia_kg_m2`` the constant
    own inertia of the crankshaft given in the scene (beyond the crank masses);
    ``mechanism_inertia_mean_kg_m2`` the cycle mean of the reduced inertia of the crank
    mechanisms; ``excess_work_J`` Delta L of the output torque.

    A flywheel designed for ``required_irregularity`` is the energy method's
    ``required_flywheel_inertia_kg_m2`` unless the exact periodic solution with the variable
    reduced inertia gives a larger delta with it: then ``flywheel_inertia_kg_m2`` is the one for
    which that solution gives the required delta, and ``energy_flywheel_exact_irregularity`` the
    delta of that solution with the energy method's flywheel (None when the flywheel is not
    raised).
    """

    flywheel_inertia_kg_m2: float
    engine_inertia_kg_m2: float
    mechanism_inertia_mean_kg_m2: float
    excess_work_J: float
    irregularity: float  # delta of the energy method with this flywheel
    required_irregularity: float | None
    required_flywheel_inertia_kg_m2: float | None
    energy_flywheel_exact_irregularity: float | None = None
    #: the counterweights' Σ m ρ², part of ``engine_inertia_kg_m2`` (the constant the crank
    #: train's inertia gets), kg m^2
    counterweight_inertia_kg_m2: float = 0.0
    #: the balance shafts' masses reduced to the crankshaft, Σ m ρ² n², also part of
    #: ``engine_inertia_kg_m2``, kg m^2
    balance_shaft_inertia_kg_m2: float = 0.0

    @property
    def raised_by_exact_solution(self) -> bool:
        """Whether the flywheel is the exact solution's, larger than the energy method's."""
        return self.energy_flywheel_exact_irregularity is not None


# Scene tables read by more than one plugin: the table's name is the owning stage's
# ``options_table``; the model is shared so that every reader validates it alike.


class RodOffsetOptions(BaseModel):
    """The balancing table's distance along the crank pin between the planes of rods side by
    side on it (owned by the balancing stage, whose model extends this one; the bay stage reads
    it for the engine's plan, ignoring the table's other fields)."""

    model_config = ConfigDict(extra="ignore", frozen=True, validate_default=True)

    # None: one big-end bearing's width of typical proportions
    rod_offset: _quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None


class PinSizeOptions(BaseModel):
    """The bearings table's crank-pin size (owned by the bearing stage, whose model extends this
    one): the stages that place rods side by side on a pin read the pin's width from it."""

    model_config = ConfigDict(extra="ignore", frozen=True, validate_default=True)

    crank_pin_diameter: _quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    crank_pin_width: _quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None


class ArticulatedOptions(BaseModel):
    """The articulated rods' table: slave-rod geometry and masses (owned by the bay stage; the
    crank-slider's drawing and the balancing stage read it too)."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    pin_radius: _quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3)
    pin_angle_deg: _number(gt=-360, lt=360) | None = None
    pin_angles_deg: list[_number(gt=-360, lt=360)] | None = None
    slave_rod_length: _quantity("length", gt=0, le=20.0, unit="mm", scale=1e-3) | None = None
    slave_rod: _quantity("mass", gt=0, le=5000, unit="kg") | None = None
    slave_rod_cm_fraction: _number(gt=0, lt=1) = 0.475
    slave_pin: _quantity("mass", ge=0, le=5000, unit="kg") = "0 kg"


class RodDynamicsOptions(BaseModel):
    """The connecting rod's model (owned by the rod-dynamics stage; the force stage reads
    ``apply_to_loads``)."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    model: Literal["two_mass", "three_mass", "correction_couple"] = "two_mass"
    # true: the forces (and so bays, torque, bearings) use the rigid rod with I_G instead of the
    # two-mass split; the forces section gives the difference (needs masses.rod_moment_of_inertia)
    apply_to_loads: bool = False
