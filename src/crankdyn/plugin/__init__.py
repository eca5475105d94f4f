"""The plugin-facing API: what a plugin returns from its hooks, the data stages hand each other,
what several plugins read of a scene, and the registry the hooks are collected into.

* :mod:`crankdyn.plugin.hooks` — the hook specifications and the ``hookimpl`` marker;
* :mod:`crankdyn.plugin.types` — ``Stage``, ``StagePresentation``, ``StageOutput``, ``Mechanism``, ``Catalog``, …;
* :mod:`crankdyn.plugin.contracts` — the data keys and types stages hand each other;
* :mod:`crankdyn.plugin.scene_inputs` — what several plugins pass to the shared physics;
* :mod:`crankdyn.plugin.registry` — entry points and extra plugins collected into a ``Registry``;
* :mod:`crankdyn.plugin.guard` — a plugin's failure named; the stage time limit.
"""

from __future__ import annotations

from .contracts import (
    BAY_LOADS,
    COUNTERWEIGHTS,
    CRANK_LOADS,
    ENGINE_TORQUE,
    FLYWHEEL,
    FORCES,
    GAS_PRESSURE,
    KINEMATICS,
    ArticulatedOptions,
    BayLoads,
    Counterweights,
    CrankForces,
    CrankLoads,
    EngineTorque,
    FlywheelDesign,
    GasPressure,
    PistonMotion,
    RodDynamicsOptions,
)
from .hooks import hookimpl
from .registry import Registry, collect, default_registry, plugin_manager
from .types import (
    SERVICE_ASIDE,
    SERVICE_ERROR_PROBES,
    SERVICE_RUNNER,
    AnswerColumn,
    Catalog,
    ColumnTable,
    ErrorProbe,
    Guide,
    Mechanism,
    MechanismGeometry,
    PlausibilityRule,
    ProbePoint,
    Section,
    Stage,
    StageOutput,
    StagePresentation,
    Symbol,
    Tables,
)

__all__ = [
    "BAY_LOADS",
    "COUNTERWEIGHTS",
    "CRANK_LOADS",
    "ENGINE_TORQUE",
    "FLYWHEEL",
    "FORCES",
    "GAS_PRESSURE",
    "KINEMATICS",
    "SERVICE_ASIDE",
    "SERVICE_ERROR_PROBES",
    "SERVICE_RUNNER",
    "AnswerColumn",
    "ArticulatedOptions",
    "BayLoads",
    "Catalog",
    "ColumnTable",
    "CrankForces",
    "CrankLoads",
    "Counterweights",
    "EngineTorque",
    "ErrorProbe",
    "FlywheelDesign",
    "GasPressure",
    "Guide",
    "Mechanism",
    "MechanismGeometry",
    "PistonMotion",
    "PlausibilityRule",
    "ProbePoint",
    "Registry",
    "RodDynamicsOptions",
    "Section",
    "Stage",
    "StageOutput",
    "StagePresentation",
    "Symbol",
    "Tables",
    "collect",
    "default_registry",
    "hookimpl",
    "plugin_manager",
]
