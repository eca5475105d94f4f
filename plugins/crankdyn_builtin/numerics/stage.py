"""Error against run time, measured on the scene itself.

Three studies, all measured when the report is made:

* **angle step** — the scene's own pipeline (the stages that provide the forces and the engine
  torque) is re-run at angle steps from 30° to 0.1°; at each step the run time (best of a few
  repeats, ``time.perf_counter``) and the errors of the mean torque, the indicated work, the
  extremes of the tangential force t and the largest resultant crank-pin force q are recorded.
  The reference does not use the method under test (sampling on a uniform grid, the periodic
  trapezoidal rule, the largest grid value): the cycle integrals are Gauss–Legendre quadratures
  of the pointwise model on 0.25° panels (checked against 0.5° panels), the extremes a dense
  0.01° search refined twice by a factor of 100 around the best point. The mean torque comes
  from the torque integral directly (single-cylinder and central/fork rods: cylinders × ∮M dα/Θ),
  for articulated rods from virtual work (Σ ∮p dV over master and slave cylinders / Θ).
  A theoretical diagram's work is also checked against its closed form.
* **piston kinematics** — the textbook two-term form, the Maclaurin series in λ with 3, 4 and 5
  terms (power and harmonic forms, :mod:`crankdyn.physics.series`) and the exact form: largest
  error of s and j against an extended-precision evaluation of the exact form, and time per
  evaluation.
* **solvers** — other plugins add error-against-time rows with the ``crankdyn_error_probes`` hook
  (e.g. a flywheel speed solver at a range of tolerances).

The pipeline is re-run through the orchestrator's runner (``SERVICE_RUNNER`` in ``inputs``), over
the registry the scene itself runs with; this stage never builds a registry of its own.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from html import escape
from pathlib import Path
from typing import Annotated, Any

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from crankdyn.contracts import ENGINE_TORQUE, FORCES, GAS_PRESSURE, KINEMATICS
from crankdyn.errors import CrankdynError, PluginError, Problem, SceneError
from crankdyn.physics import articulated as art
from crankdyn.physics import forces as phys
from crankdyn.physics import indicator as ind
from crankdyn.physics import kinematics as kin
from crankdyn.physics import pressure_trace as trace
from crankdyn.physics import series
from crankdyn.physics.extrema import first_argmax
from crankdyn.physics.layout import step_on_grid_deg
from crankdyn.plugin_types import (  # noqa: F401
    SERVICE_ASIDE,
    SERVICE_ERROR_PROBES,
    SERVICE_RUNNER,
    ErrorProbe,
    ProbePoint,
    Stage,
    StageOutput,
)
from crankdyn.report.figures import new_figure
from crankdyn.scene import (
    Analysis,
    Scene,
    _problems,  # one error format for every refusal
    number,
    options,
)
from crankdyn.scene_inputs import cycle_parameters, engine_layout, rounding_parameters

#: This plugin's own section templates (``templates/sections/<stage>.html.j2``).
TEMPLATES = Path(__file__).resolve().parent / "templates"

DEFAULT_STEPS_DEG = (30.0, 15.0, 10.0, 5.0, 2.0, 1.0, 0.5, 0.25, 0.1)
# timeit-style timing of a step's compute: calls per timed repeat grow (1, 2, 5, 10, 20, ...)
# until one repeat takes at least this long, then the best of ``repeats`` such repeats is kept.
# Short repeats, many of them, taken in turns over the steps: the minimum of many short windows
# is what an unloaded machine gives, even when other jobs share the cores.
_MIN_REPEAT_S = 2.5e-4
# A whole re-run through the stages (a mechanism without a pointwise model) costs the study itself
# once per repeat: best of a few is enough there, since its fixed overhead is part of what it times.
_RERUN_REPEATS = 3
# The steps' timing stops before ``repeats`` once this many rounds in a row lowered no step's best
# time by more than this fraction (the minima have settled; a loaded machine gets more rounds).
_SETTLED_ROUNDS = 3
_SETTLED_RELATIVE = 0.01
_FALLBACK_REFERENCE_STEP_DEG = 0.05
# Pointwise reference: Gauss-Legendre panels and the dense extremum search.
_PANEL_DEG = 0.25
_GAUSS_ORDER = 8
_SEARCH_STEP_DEG = 0.01
_SEARCH_REFINEMENTS = 2  # each refines the step 100-fold around the best point
# Piston-kinematics study grid (one revolution).
_KINEMATICS_POINTS = 3600
# Errors below this (relative) are shown as this on log axes.
_LOG_FLOOR = 1e-16

QUANTITIES = ("mean_torque", "indicated_work", "tangential_max", "tangential_min", "resultant_max")
QUANTITY_UNITS = {"mean_torque": "Nm", "indicated_work": "J", "tangential_max": "Pa", "tangential_min": "Pa",
                  "resultant_max": "Pa"}


class NumericsOptions(BaseModel):
    """The optional [numerics] table."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    steps_deg: list[number(ge=0.01, le=30)] = list(DEFAULT_STEPS_DEG)
    repeats: Annotated[int, Field(ge=1, le=100)] = 15
    time_budget_s: Annotated[float, Field(gt=0, le=3600)] = 10.0
    max_error_percent: Annotated[float, Field(gt=0)] = 1.0
    tolerance: Annotated[float, Field(gt=0, lt=0.1)] = 1e-3  # relative error allowed in the reported peaks
    kinematics_forms: bool = True


# ------------------------------------------------------------------ solver studies
# Other plugins add error-against-time rows through the ``crankdyn_error_probes`` hook
# (crankdyn.hookspecs); ProbePoint and ErrorProbe live in crankdyn.plugin_types and are
# re-exported here for existing imports.


# ------------------------------------------------------------------ scene copies and re-runs
def scene_with_step(scene: Scene, step_deg: float) -> Scene:
    """A validated copy of ``scene`` at another angle step (tables at every point, all stages).

    The copy keeps every table, the plugin tables and ``base_dir``; the scene-level checks
    (the step divides the cycle) run again and raise SceneError when they fail.
    """
    analysis = Analysis.model_validate({"angle_step_deg": step_deg, "table_step_deg": step_deg,
                                        "kinematics": scene.analysis.kinematics, "stages": None})
    try:
        return Scene.model_validate({**dict(scene), "analysis": analysis})
    except ValidationError as exc:
        raise SceneError(_problems(exc, {})) from None


def _needed_stages(scene, runner) -> list[str]:
    return [s.name for s in runner.stages.values()
            if (FORCES in s.provides or ENGINE_TORQUE in s.provides) and runner.applies(s, scene) is None]


@dataclass
class StepRun:
    step_deg: float
    points: int
    time_s: float  # wall time of the one re-run that gave ``values`` (overhead included)
    values: dict[str, float]
    outputs: dict[str, Any] = field(default_factory=dict)
    theoretical_work_J: float | None = None


def _values(data, cylinders: int) -> dict[str, float]:
    """The judged numbers: the engine's mean torque (the cylinder's times ``cylinders`` when no
    stage gives the engine torque), the cylinder's indicated work, t_max, t_min and q_max."""
    forces, gas = data[FORCES], data[GAS_PRESSURE]
    torque = data[ENGINE_TORQUE].torque_Nm if ENGINE_TORQUE in data else cylinders * forces.torque_Nm
    q = phys.resultant_crank_pin_pressure_Pa(forces.tangential_Pa, forces.radial_Pa, forces.centrifugal_Pa)
    return {"mean_torque": float(np.mean(torque)), "indicated_work": float(gas.indicated_work_J),
            "tangential_max": float(np.max(forces.tangential_Pa)),
            "tangential_min": float(np.min(forces.tangential_Pa)), "resultant_max": float(np.max(q))}


def run_at_step(scene: Scene, step_deg: float, repeats: int = 1, *, runner) -> StepRun:
    """Re-run the stages that give forces and engine torque at ``step_deg`` once.

    ``runner``: the orchestrator's :class:`crankdyn.orchestrator.Runner` (``SERVICE_RUNNER``).
    ``repeats`` is kept for callers of earlier versions: the run time of the study is measured
    separately (:func:`time_steps`), with repeats, so one run gives the values.
    """
    copy = scene_with_step(scene, step_deg)
    the_plan = runner.plan(copy, _needed_stages(copy, runner))
    start = time.perf_counter()
    result = runner.run(copy, the_plan)
    elapsed = time.perf_counter() - start
    data = {}
    for output in result.outputs.values():
        data.update(output.data)
    if not {FORCES, GAS_PRESSURE} <= set(data):
        raise PluginError("the re-run pipeline gives no forces")
    indicator = result.outputs.get("indicator")
    theoretical = None
    if indicator is not None and "theoretical_diagram_mean_pressure_Pa" in indicator.results:
        theoretical = indicator.results["theoretical_diagram_mean_pressure_Pa"] * indicator.results["swept_volume_m3"]
    return StepRun(step_deg=step_deg, points=len(copy.crank_angles_deg), time_s=elapsed,
                   values=_values(data, scene.engine.cylinders),
                   outputs=result.outputs, theoretical_work_J=theoretical)


# ------------------------------------------------------------------ timing (timeit-style)
@dataclass(frozen=True)
class Timing:
    """Best time per call of a function: ``loops`` calls per timed repeat, best of ``repeats``."""

    best_s: float
    loops: int
    repeats: int


def _autorange(fn: Callable[[], Any], min_time_s: float, clock: Callable[[], float]) -> tuple[int, float]:
    """(loops, seconds per call): loops 1, 2, 5, 10, 20, 50, ... until one repeat takes ``min_time_s``
    (as :meth:`timeit.Timer.autorange`)."""
    base = 1
    while True:
        for loops in (base, 2 * base, 5 * base):
            start = clock()
            for _ in range(loops):
                fn()
            elapsed = clock() - start
            if elapsed >= min_time_s or loops >= 1 << 20:
                return loops, elapsed / loops
        base *= 10


def best_times(functions: list[Callable[[], Any]], repeats: int, *, min_time_s: float = _MIN_REPEAT_S,
               clock: Callable[[], float] = time.perf_counter, settled_rounds: int = 0) -> list[Timing]:
    """timeit-style best time per call of each function, the repeats taken in turns.

    Each function's loop count is found as :meth:`timeit.Timer.autorange` does (that first
    measurement counts as its first repeat); then up to ``repeats - 1`` further repeats go round
    all the functions in turn (backwards and forwards), so a burst of load on the machine slows
    every function alike rather than one step of the study, each repeat after one untimed call
    (warm caches). The minimum is kept: load only ever adds time.

    With ``settled_rounds`` > 0 the repeats stop early, once that many rounds in a row have
    lowered no function's best time by more than ``_SETTLED_RELATIVE``: the minima have settled,
    and further rounds cost time without changing them. A loaded machine keeps lowering some
    minimum, so it gets more rounds, up to ``repeats``.
    """
    ranged = [_autorange(fn, min_time_s, clock) for fn in functions]
    best = [per_call for _, per_call in ranged]
    taken, quiet = 1, 0
    for round_ in range(max(1, repeats) - 1):
        if settled_rounds and quiet >= settled_rounds:
            break
        # every other round backwards: no function always follows the same one (cache state)
        order = range(len(functions)) if round_ % 2 else range(len(functions) - 1, -1, -1)
        lowered = False
        for k in order:
            fn, loops = functions[k], ranged[k][0]
            fn()  # untimed: the previous function left other data in the caches
            start = clock()
            for _ in range(loops):
                fn()
            per_call = (clock() - start) / loops
            lowered |= per_call < best[k] * (1 - _SETTLED_RELATIVE)
            best[k] = min(best[k], per_call)
        taken += 1
        quiet = 0 if lowered else quiet + 1
    return [Timing(b, loops, taken) for b, (loops, _) in zip(best, ranged, strict=True)]


def _step_formulas(model: PointwiseModel, run: StepRun) -> Callable[[], tuple]:
    """The formulas of a step on its N angles: piston acceleration, rod angle, forces, torque, and the
    judged values (mean torque, t_max, t_min, q_max), from the step's pressure curve."""
    gas = next(o.data[GAS_PRESSURE] for o in run.outputs.values() if GAS_PRESSURE in o.data)
    angles, pressure = np.asarray(gas.crank_angle_deg, dtype=float), np.asarray(gas.pressure_Pa, dtype=float)

    def formulas():
        tangential, resultant, torque = model.forces(angles, pressure)
        return (np.mean(torque), np.max(tangential), np.min(tangential),
                None if resultant is None else np.max(resultant))
    return formulas


def time_steps(scene: Scene, runs: list[StepRun], repeats: int, runner, *,
               clock: Callable[[], float] = time.perf_counter) -> tuple[str, list[Timing], float | None]:
    """(what was timed, a :class:`Timing` per run, the fixed per-call overhead in s or None).

    ``formulas``: each step's formulas (:func:`_step_formulas`) on its own angles; the re-run
    through the stages costs a fixed amount more per call (argument checks, the rounding's junction
    points, results and tables) — the overhead, the smallest difference over the steps between the
    whole re-run and its formulas. ``rerun``: without a pointwise model of the mechanism the whole
    re-run is timed, overhead included (None).
    """
    motion = _motion(runs[0])
    try:
        model = PointwiseModel(scene, motion)
    except ValueError:
        model = None
    if model is None:
        plans = []
        for r in runs:
            copy = scene_with_step(scene, r.step_deg)
            plans.append(functools.partial(runner.run, copy, runner.plan(copy, _needed_stages(copy, runner))))
        return "rerun", best_times(plans, min(repeats, _RERUN_REPEATS), min_time_s=_MIN_REPEAT_S, clock=clock), None
    timings = best_times([_step_formulas(model, r) for r in runs], repeats, min_time_s=_MIN_REPEAT_S, clock=clock,
                         settled_rounds=_SETTLED_ROUNDS)
    overhead = max(0.0, min(r.time_s - t.best_s for r, t in zip(runs, timings, strict=True)))
    return "formulas", timings, overhead


# ------------------------------------------------------------------ the pointwise reference
def _gauss_nodes(edges_rad: np.ndarray, order: int = _GAUSS_ORDER):
    """Nodes and weights of composite Gauss-Legendre quadrature on the panels ``edges``."""
    x, w = np.polynomial.legendre.leggauss(order)
    a, b = edges_rad[:-1, None], edges_rad[1:, None]
    half = 0.5 * (b - a)
    return ((a + b) * 0.5 + half * x).ravel(), (half * w).ravel()


class PointwiseModel:
    """The single-cylinder model of the stages, evaluated at any crank angle.

    For the central crank-slider it calls the same physics functions as the kinematics,
    indicator and forces stages, but at arbitrary angles, so integrals and extremes can be taken
    without the angle grid. For another mechanism it takes the displacement from the mechanism's
    ``PistonMotion.displacement_at``, differentiates it numerically (fourth-order central
    differences) and gets the tangential force by virtual work, t R = p1 ds/dalpha; the radial
    force needs the mechanism's own geometry, so ``forces`` gives no q then (None).
    """

    # central-difference steps for a mechanism known only by displacement_at, deg: the
    # truncation and round-off errors of ds/dalpha and d2s/dalpha2 are then ~1e-12 and ~1e-10 of R
    _FD_STEP_ARM_DEG = 0.01
    _FD_STEP_ACCEL_DEG = 0.05

    def __init__(self, scene: Scene, motion=None):
        e, m, c = scene.engine, scene.masses, scene.cycle
        self.scene = scene
        self.analytic = e.mechanism == "crank_slider"
        if not self.analytic and (motion is None or motion.displacement_at is None):
            raise ValueError(f"the {e.mechanism!r} kinematics give no displacement at any angle")
        self._displacement_at = None if self.analytic else motion.displacement_at
        self.radius, self.ratio, self.omega = e.crank_radius_m, e.rod_ratio_value, e.angular_velocity_rad_s
        self.cycle_deg = e.cycle_deg
        self.exact = scene.analysis.kinematics == "exact"
        self.area = float(phys.piston_area_m2(e.bore))
        self.swept = self.area * e.stroke
        self.p0 = e.crankcase_pressure
        rod_rec, rod_rot = phys.rod_mass_split_kg(m.rod, e.rod_length_m, scene.rod_cm_from_big_end_m)
        self.reciprocating = float(m.piston_group + rod_rec)
        self.centrifugal = float(phys.centrifugal_pressure_Pa(rod_rot + m.crank_pin + 2.0 * m.crank_web,
                                                              self.radius, self.omega, self.area))
        self.clearance = float(ind.clearance_volume_m3(self.swept, c.compression_ratio))
        if c.source == "trace":
            path = scene.resolve(c.trace_file)
            fmt = c.trace_format or ("diesel-rk" if path.suffix.lower() == ".ind" else "csv")
            reader = trace.read_diesel_rk_ind if fmt == "diesel-rk" else trace.read_pressure_csv
            self._trace = reader(path)
            self._target_tdc = 360.0 if e.strokes == 4 else 0.0
            shifted = np.mod(self._trace[0] + self._target_tdc - c.trace_firing_tdc_deg, self.cycle_deg)
            self.knots_deg = np.unique(shifted)
        else:
            self._trace = None
            self._params = cycle_parameters(scene)
            self._rounding = rounding_parameters(scene)
            self.knots_deg = np.array([])

    # kinematics of the chosen method
    def displacement(self, a_deg):
        if not self.analytic:
            return np.asarray(self._displacement_at(np.asarray(a_deg, dtype=float)), dtype=float)
        a = np.radians(a_deg)
        f = kin.piston_displacement_exact_m if self.exact else kin.piston_displacement_approx_m
        return f(a, self.radius, self.ratio)

    def arm(self, a_deg):
        """ds/dalpha, m/rad."""
        if not self.analytic:
            a, h = np.asarray(a_deg, dtype=float), self._FD_STEP_ARM_DEG
            s = self.displacement
            return (-s(a + 2 * h) + 8 * s(a + h) - 8 * s(a - h) + s(a - 2 * h)) / (12 * math.radians(h))
        a = np.radians(a_deg)
        f = kin.piston_velocity_exact_m_s if self.exact else kin.piston_velocity_approx_m_s
        return f(a, self.radius, self.ratio, 1.0)

    def acceleration(self, a_deg):
        """d2s/dt2 at constant omega, m/s^2."""
        if not self.analytic:
            a, h = np.asarray(a_deg, dtype=float), self._FD_STEP_ACCEL_DEG
            s = self.displacement
            d2 = ((-s(a + 2 * h) + 16 * s(a + h) - 30 * s(a) + 16 * s(a - h) - s(a - 2 * h))
                  / (12 * math.radians(h) ** 2))
            return self.omega**2 * d2
        f = kin.piston_acceleration_exact_m_s2 if self.exact else kin.piston_acceleration_approx_m_s2
        return f(np.radians(a_deg), self.radius, self.ratio, self.omega)

    def volume(self, a_deg):
        return self.clearance + self.area * self.displacement(a_deg)

    def pressure(self, a_deg):
        a_deg = np.asarray(a_deg, dtype=float)
        if self._trace is not None:
            c = self.scene.cycle
            return trace.to_cycle_grid(self._trace[0], self._trace[1], self.cycle_deg, a_deg,
                                       c.trace_firing_tdc_deg, self._target_tdc)
        return ind.rounded_pressure_Pa(a_deg, self.volume(a_deg), self.clearance, self._params, self._rounding,
                                       volume_function=self.volume)

    def forces(self, a_deg, pressure=None):
        """(tangential_Pa, resultant_Pa or None, torque_Nm) at the angles ``a_deg``."""
        a = np.radians(a_deg)
        p = self.pressure(a_deg) if pressure is None else pressure
        total = p - self.p0 + phys.inertia_pressure_Pa(self.reciprocating, self.acceleration(a_deg), self.area)
        if not self.analytic:  # virtual work: t R F = p1 F ds/dalpha
            tangential = total * self.arm(a_deg) / self.radius
            return tangential, None, phys.crank_torque_Nm(tangential, self.radius, self.area)
        rod = phys.rod_force_components(total, a, kin.rod_angle_rad(a, self.ratio))
        q = phys.resultant_crank_pin_pressure_Pa(rod.tangential_Pa, rod.radial_Pa, self.centrifugal)
        return rod.tangential_Pa, q, phys.crank_torque_Nm(rod.tangential_Pa, self.radius, self.area)

    # integrals
    def panel_edges_deg(self, panel_deg: float) -> np.ndarray:
        uniform = np.arange(0.0, self.cycle_deg + 0.5 * panel_deg, panel_deg)
        return np.unique(np.concatenate([uniform, self.knots_deg, [self.cycle_deg]]))

    def integrals(self, panel_deg: float = _PANEL_DEG) -> tuple[float, float]:
        """(indicated work J, mean crank torque N m) of one cylinder by Gauss-Legendre panels."""
        nodes, weights = _gauss_nodes(np.radians(self.panel_edges_deg(panel_deg)))
        a_deg = np.degrees(nodes)
        p = self.pressure(a_deg)
        work = float(np.sum(weights * p * self.area * self.arm(a_deg)))
        _, _, torque = self.forces(a_deg, p)
        return work, float(np.sum(weights * torque) / math.radians(self.cycle_deg))

    def extremes(self) -> dict[str, float]:
        """Largest and smallest t and largest q: dense search refined around the best points."""
        n = int(round(self.cycle_deg / _SEARCH_STEP_DEG))
        a = np.arange(n) * _SEARCH_STEP_DEG
        t, q, _ = self.forces(a)
        kinds = (("tangential_max", 0, 1.0), ("tangential_min", 0, -1.0), ("resultant_max", 1, 1.0))
        if q is None:
            kinds = kinds[:2]
        centres = [float(a[first_argmax(sign * (t, q)[which])]) for _, which, sign in kinds]
        best = [float(np.max(sign * (t, q)[which])) for _, which, sign in kinds]
        step = _SEARCH_STEP_DEG
        offsets = np.linspace(-1.0, 1.0, 201)
        for _ in range(_SEARCH_REFINEMENTS):
            # one evaluation for the three local grids
            local = np.concatenate([c + step * offsets for c in centres])
            lt, lq, _ = self.forces(np.mod(local, self.cycle_deg))
            for k, (_, which, sign) in enumerate(kinds):
                part = sign * (lt, lq)[which][k * offsets.size:(k + 1) * offsets.size]
                i = first_argmax(part)
                centres[k] = float(local[k * offsets.size + i])
                best[k] = max(best[k], float(part[i]))
            step /= 100.0
        return {name: sign * value for (name, _, sign), value in zip(kinds, best, strict=True)}


def _slave_work_J(model: PointwiseModel, scene, bays_results, panel_deg: float) -> float:
    """Indicated work per cycle of the slave cylinders of one bay, from their exact kinematics."""
    layout = engine_layout(scene)
    e = scene.engine
    by_label = {c.label: c for c in layout.cylinders}
    master = layout.bay(0)[0]
    edges = model.panel_edges_deg(panel_deg)
    nodes, weights = _gauss_nodes(np.radians(edges))
    a_deg = np.degrees(nodes)
    total = 0.0
    for slave in bays_results["slaves"]:
        g = art.SlaveGeometry(e.crank_radius_m, e.rod_length_m, bays_results["pin_radius_m"],
                              math.radians(slave["pin_angle_deg"]), math.radians(slave["bank_angle_deg"]),
                              slave["slave_rod_length_m"])
        motion = art.slave_motion(nodes, g, 1.0)  # velocity = dx/dalpha, m/rad
        delta = (by_label[slave["cylinder"]].firing_delay_deg - master.firing_delay_deg) % layout.cycle_deg
        delta += slave["tdc_master_angle_deg"] - slave["bank_angle_deg"]
        p = model.pressure(np.mod(a_deg - delta, layout.cycle_deg))
        total += float(np.sum(weights * p * model.area * (-motion.piston_velocity_m_s)))
    return total


@dataclass
class Reference:
    method: str  # "quadrature", "mixed" or "fine_step"
    values: dict[str, float]
    uncertainty: dict[str, float]  # relative
    time_s: float
    theoretical_work_J: float | None = None
    note: str = ""


def _motion(run: StepRun):
    return next((o.data[KINEMATICS] for o in run.outputs.values() if KINEMATICS in o.data), None)


def reference_values(scene: Scene, sample: StepRun, runner) -> Reference:
    """The reference of the step study (see the module docstring).

    ``quadrature``: everything from the pointwise model; ``mixed``: a mechanism known only by its
    displacement — integrals and t by the pointwise model, q from the fine step; ``fine_step``:
    the same calculation at 0.05 deg (articulated rods with two-term kinematics).
    """
    start = time.perf_counter()
    e = scene.engine
    articulated = e.rod_type == "articulated"
    analytic = e.mechanism == "crank_slider"
    motion = _motion(sample)
    if articulated and scene.analysis.kinematics != "exact" or (
            not analytic and (articulated or motion is None or motion.displacement_at is None)):
        run = run_at_step(scene, _FALLBACK_REFERENCE_STEP_DEG, repeats=1, runner=runner)
        return Reference("fine_step", run.values, {}, time.perf_counter() - start,
                         note=f"{_FALLBACK_REFERENCE_STEP_DEG:g}")
    model = PointwiseModel(scene, motion)
    work, mean = model.integrals(_PANEL_DEG)
    work_coarse, mean_coarse = model.integrals(2 * _PANEL_DEG)
    cycle_rad = math.radians(e.cycle_deg)
    if articulated:
        bays_results = sample.outputs["bays"].results
        slaves = _slave_work_J(model, scene, bays_results, _PANEL_DEG)
        slaves_coarse = _slave_work_J(model, scene, bays_results, 2 * _PANEL_DEG)
        cranks = len(bays_results["crank_angles_deg"])
        engine_mean = cranks * (work + slaves) / cycle_rad
        engine_mean_coarse = cranks * (work_coarse + slaves_coarse) / cycle_rad
    else:
        engine_mean, engine_mean_coarse = e.cylinders * mean, e.cylinders * mean_coarse
    values = {"mean_torque": engine_mean, "indicated_work": work, **model.extremes()}
    method = "quadrature"
    if "resultant_max" not in values:
        values["resultant_max"] = run_at_step(scene, _FALLBACK_REFERENCE_STEP_DEG, repeats=1, runner=runner).values["resultant_max"]
        method = "mixed"

    def rel(a, b):
        return abs(a - b) / abs(b) if b else abs(a - b)

    uncertainty = {"mean_torque": rel(engine_mean_coarse, engine_mean), "indicated_work": rel(work_coarse, work)}
    theoretical = None
    # The closed form assumes dead centres at 0/180 deg and a swept volume F*S: true of the central
    # crank-slider, not of an offset or planetary linkage (their strokes and phases differ).
    if scene.cycle.source == "theoretical" and analytic:
        params = model._params
        pumping = (params.intake_pressure_Pa - params.exhaust_pressure_Pa) if e.strokes == 4 else 0.0
        theoretical = (ind.theoretical_mean_indicated_pressure_Pa(params) + pumping) * model.swept
    return Reference(method, values, uncertainty, time.perf_counter() - start, theoretical)


# ------------------------------------------------------------------ piston-kinematics forms
def _exact_extended(alpha_deg: np.ndarray, radius: float, ratio: float):
    """Exact s and j/omega^2 in extended precision (np.longdouble), returned as float64."""
    a = np.radians(np.asarray(alpha_deg, dtype=np.longdouble))
    lam = np.longdouble(ratio)
    R = np.longdouble(radius)
    sin_a, cos_a = np.sin(a), np.cos(a)
    half = np.sin(a / 2)
    cos_b = np.sqrt(1 - (lam * sin_a) ** 2)
    s = R * (2 * half * half + lam * sin_a * sin_a / (1 + cos_b))
    j = R * (cos_a - sin_a * lam * sin_a / cos_b + lam * cos_a**2 / cos_b**3)
    return s, j


def kinematics_forms(radius: float, ratio: float, points: int = _KINEMATICS_POINTS,
                     repeats: int = 3) -> list[dict]:
    """Largest errors of s and j and time per evaluation of s, v, j for every form.

    The errors are against the exact form evaluated in extended precision; ``exact`` itself is
    listed with its round-off error. Times are per evaluation of s, v and j on ``points``
    angles over one revolution (omega = 1 rad/s; errors of j are reported per omega^2).
    """
    a_deg = np.arange(points) * (360.0 / points)
    a = np.radians(a_deg)
    s_ref, j_ref = _exact_extended(a_deg, radius, ratio)
    forms: list[tuple[str, int | None, Callable]] = [
        ("two_term", 2, lambda: (kin.piston_displacement_approx_m(a, radius, ratio),
                                 kin.piston_velocity_approx_m_s(a, radius, ratio, 1.0),
                                 kin.piston_acceleration_approx_m_s2(a, radius, ratio, 1.0)))]
    for terms in (3, 4, 5):
        forms.append(("series", terms, functools.partial(
            lambda n: (series.piston_displacement_series_m(a, radius, ratio, n),
                       series.piston_velocity_series_m_s(a, radius, ratio, 1.0, n),
                       series.piston_acceleration_series_m_s2(a, radius, ratio, 1.0, n)), terms)))
    for terms in (3, 4, 5):
        forms.append(("harmonic", terms, functools.partial(
            lambda n: (series.piston_displacement_harmonic_m(a, radius, ratio, n),
                       series.piston_velocity_harmonic_m_s(a, radius, ratio, 1.0, n),
                       series.piston_acceleration_harmonic_m_s2(a, radius, ratio, 1.0, n)), terms)))
    forms.append(("exact", None, lambda: (kin.piston_displacement_exact_m(a, radius, ratio),
                                          kin.piston_velocity_exact_m_s(a, radius, ratio, 1.0),
                                          kin.piston_acceleration_exact_m_s2(a, radius, ratio, 1.0))))
    rows = []
    timings = best_times([fn for _, _, fn in forms], repeats)
    for (name, terms, fn), timing in zip(forms, timings, strict=True):
        s, _, j = fn()
        rows.append({"form": name, "terms": terms,
                     "displacement_error_max_m": float(np.max(np.abs(s - s_ref))),
                     "acceleration_error_max_m_s2": float(np.max(np.abs(j - j_ref))),
                     "time_per_evaluation_s": timing.best_s, "points": points})
    return rows


def _labelled_points(points, width_cm: float = 13.0, height_cm: float = 7.5, gap_cm: float = 0.45) -> list[int]:
    """Indices of the (x, y) points of a log-log plot that get a label: the coarse steps cost
    about the same time (the fixed overhead), so their labels piled up at the left; a point is
    labelled when it lies at least ``gap_cm`` from every labelled one, the plot's decades
    spread over about ``width_cm`` by ``height_cm``. The first and last are always labelled."""
    logs = np.log10(np.asarray(points, dtype=float))
    span = np.ptp(logs, axis=0)
    scale = np.array([width_cm, height_cm]) / np.where(span > 0, span, 1.0)
    placed: list[int] = []
    for k in [0, len(points) - 1] + list(range(1, len(points) - 1)):
        if k in placed:
            continue
        if k in (0, len(points) - 1) or all(np.hypot(*((logs[k] - logs[j]) * scale)) >= gap_cm for j in placed):
            placed.append(k)
    return sorted(placed)


# ------------------------------------------------------------------ the stage
def applies(scene) -> str | None:
    if scene.cycle is None or scene.masses is None:
        missing = " and ".join(t for t, v in (("[cycle]", scene.cycle), ("[masses]", scene.masses)) if v is None)
        return (f"the scene has no {missing}: there is no cycle to integrate "
                "(the kinematics part is in numerics_kinematics)")
    return None


def applies_kinematics(scene) -> str | None:
    if scene.cycle is not None and scene.masses is not None:
        return "the scene has cycle data: the numerics stage covers its kinematics too"
    if scene.engine.mechanism != "crank_slider":
        return "the series forms concern the central crank-slider only"
    return None


def _relative(value, reference):
    if reference == 0:
        return abs(value - reference)
    return abs(value - reference) / abs(reference)


def _kinematics_part(scene, opts, results, tables) -> None:
    if not opts.kinematics_forms or scene.engine.mechanism != "crank_slider":
        return
    e = scene.engine
    # the forms differ by factors, not by per cent as neighbouring steps do: fewer repeats suffice
    rows = kinematics_forms(e.crank_radius_m, e.rod_ratio_value, repeats=max(3, opts.repeats // 3))
    results["kinematics_forms"] = rows
    results["kinematics_method"] = scene.analysis.kinematics
    # CSV: one text column names the form ("series-3"); no empty cells for the exact form's terms
    tables["kinematics_forms"] = (
        [{"form": row["form"] + (f"-{row['terms']}" if row["terms"] else ""),
          **{k: v for k, v in row.items() if k not in ("form", "terms")}} for row in rows])


def _step_rows(runs: list[StepRun], timings: list[Timing], reference: Reference) -> list[dict]:
    """One row per step: points, the timed formulas, the re-run's wall time, values and their errors."""
    ref = reference.values
    step_rows = []
    for r, timing in zip(runs, timings, strict=True):
        row = {"angle_step_deg": r.step_deg, "points": r.points, "time_s": timing.best_s, "timing_loops": timing.loops,
               "rerun_time_s": r.time_s}
        for q in QUANTITIES:
            row[f"{q}_{QUANTITY_UNITS[q]}"] = r.values[q]
            row[f"{q}_error_relative"] = _relative(r.values[q], ref[q])
        if reference.theoretical_work_J is not None and r.theoretical_work_J is not None:
            row["theoretical_work_error_relative"] = _relative(r.theoretical_work_J, reference.theoretical_work_J)
        step_rows.append(row)
    return step_rows


def run(scene, inputs) -> StageOutput:
    runner, probes, aside = inputs[SERVICE_RUNNER], inputs[SERVICE_ERROR_PROBES], inputs[SERVICE_ASIDE]
    opts = options(scene, "numerics", NumericsOptions)
    results: dict[str, Any] = {}
    tables: dict[str, Any] = {}
    notes: list = []
    scene_step = scene.analysis.angle_step_deg

    # The scene's own step is always in the study (first): its values are the ones this report
    # prints. The other steps follow from coarse to fine while the time budget lasts.
    # Each study step is moved onto the engine's grid (the largest step grid/k not above it), so
    # that it divides the cycle and every firing interval for any number of cylinders.
    others = sorted(set(study_steps_deg(scene, opts.steps_deg)) - {scene_step}, reverse=True)
    refused: dict[str, str] = {}
    start = time.perf_counter()
    sample = _run_or_refuse(scene, scene_step, opts, runner, refused)
    if sample is None:
        # The pipeline cannot be re-run from the installed plugins (e.g. a mechanism registered
        # only in a custom registry): no step study, said so in results.json and the report.
        results["steps_unavailable"] = refused.get(f"{scene_step:g}", "the scene's pipeline cannot be re-run")
        _merge(results, tables, _side_studies(scene, opts, None, runner, probes))
        return StageOutput(data={}, results=results, tables=tables, notes=notes)
    # the reference, the kinematics forms and the solvers need none of the other steps' re-runs:
    # computed beside them when the report's process has a core to spare (crankdyn.aside)
    with aside(_side_studies, scene, opts, sample, runner, probes) as side:
        runs = [sample]
        for step in others:
            if time.perf_counter() - start > opts.time_budget_s:
                refused[f"{step:g}"] = (f"{_BUDGET_REASON} of {opts.time_budget_s:g} s was spent "
                                        "([numerics] time_budget_s)")
                continue
            run = _run_or_refuse(scene, step, opts, runner, refused)
            if run is not None:
                runs.append(run)
        runs.sort(key=lambda r: -r.step_deg)
        timed, timings, overhead = time_steps(scene, runs, opts.repeats, runner)
        studies = side.result()
    reference = studies["reference"]
    ref = reference.values
    step_rows = _step_rows(runs, timings, reference)
    printed = sample.values  # the re-run at the scene's own step: the numbers this report prints

    at_scene = {"angle_step_deg": scene_step}
    for q in QUANTITIES:
        at_scene[f"{q}_{QUANTITY_UNITS[q]}"] = printed[q]
        at_scene[f"{q}_error_{QUANTITY_UNITS[q]}"] = abs(printed[q] - ref[q])
        at_scene[f"{q}_error_relative"] = _relative(printed[q], ref[q])

    _refuse_if_too_coarse(scene, opts, at_scene, step_rows)
    notes += _peaks_against_tolerance(scene, opts, at_scene, step_rows)

    results.update({
        "reference_method": reference.method,
        "reference_step_deg": _FALLBACK_REFERENCE_STEP_DEG if reference.method != "quadrature" else None,
        "reference_time_s": reference.time_s,
        "reference": {f"{q}_{QUANTITY_UNITS[q]}": ref[q] for q in QUANTITIES},
        "reference_uncertainty_relative": reference.uncertainty,
        "theoretical_work_closed_form_J": reference.theoretical_work_J,
        "steps": step_rows,
        "steps_timed": timed,
        "steps_timing_repeats": timings[0].repeats,
        "steps_timing_min_repeat_s": _MIN_REPEAT_S,
        "per_call_overhead_s": overhead,
        "steps_refused": refused,
        "at_scene_step": at_scene,
    })
    tables["steps"] = step_rows
    _merge(results, tables, studies)
    return StageOutput(data={}, results=results, tables=tables, notes=notes)


def _run_or_refuse(scene, step: float, opts, runner, refused: dict[str, str]) -> StepRun | None:
    """The re-run at ``step``, or None with the reason in ``refused``."""
    try:
        return run_at_step(scene, step, opts.repeats, runner=runner)
    except (CrankdynError, ValueError) as exc:
        refused[f"{step:g}"] = "; ".join(p.allowed for p in getattr(exc, "problems", [])) or str(exc)
        return None


def _side_studies(scene, opts, sample: StepRun | None, runner, probes) -> dict[str, Any]:
    """What the study computes beside the re-runs at the other steps: the reference (with a
    ``sample``, the re-run at the scene's step), the kinematics forms and the solver studies."""
    out: dict[str, Any] = {"results": {}, "tables": {}}
    if sample is not None:
        try:
            out["reference"] = reference_values(scene, sample, runner)
        except ValueError as exc:  # the pointwise model refused an angle: use a fine step, say why
            run = run_at_step(scene, _FALLBACK_REFERENCE_STEP_DEG, repeats=1, runner=runner)
            out["reference"] = Reference("fine_step", run.values, {}, 0.0, note=str(exc))
    _kinematics_part(scene, opts, out["results"], out["tables"])
    _probes(scene, out["results"], probes, runner)
    return out


def _merge(results: dict, tables: dict, studies: dict[str, Any]) -> None:
    results.update(studies["results"])
    tables.update(studies["tables"])


def study_steps_deg(scene, steps_deg) -> list[float]:
    """The study's steps on the engine's grid: each the largest grid/k not above the one asked for."""
    grid = scene.engine_grid_deg
    return sorted({step_on_grid_deg(grid, float(s)) for s in steps_deg}, reverse=True)


PEAKS = ("tangential_max", "tangential_min", "resultant_max")


def _peaks_against_tolerance(scene, opts, at_scene, step_rows) -> list:
    """The largest relative error of the reported peaks at the scene's step against [numerics] tolerance.

    Records it in ``at_scene`` and returns the method notes: how a defaulted step was chosen, and,
    when the peaks are off by more than the tolerance, the coarsest measured step that keeps them.
    """
    def worst(row):
        return max(row[f"{q}_error_relative"] for q in PEAKS)

    error = worst(at_scene)
    at_scene.update({"peaks_error_relative": error, "tolerance_relative": opts.tolerance,
                     "peaks_within_tolerance": bool(error <= opts.tolerance),
                     "step_defaulted": scene.angle_step_defaulted, "grid_deg": scene.engine_grid_deg})
    notes = []
    if scene.angle_step_defaulted:
        notes.append(("numerics.note_default_step", {"step": scene.analysis.angle_step_deg, "grid": scene.engine_grid_deg,
                                                     "tolerance": 100 * opts.tolerance, "error": 100 * error}))
    if error > opts.tolerance:
        good = [row["angle_step_deg"] for row in step_rows if worst(row) <= opts.tolerance]
        notes.append(("numerics.note_peaks_beyond", {"error": 100 * error, "tolerance": 100 * opts.tolerance,
                                                     "step": f"{max(good):.6g}" if good else "—"}))
    return notes


def _refuse_if_too_coarse(scene, opts, at_scene, step_rows) -> None:
    """No silent wrong numbers: refuse a step whose measured integrals are off by more than allowed.

    A stiff scene (e.g. an offset crank close to locking, where the piston's acceleration spikes
    near BDC) can make the scene's step far too coarse; the error is measured against the
    step-independent reference, and the message names the coarsest measured step that is good enough.
    """
    limit = opts.max_error_percent / 100.0

    def worst(row):
        return max(row["mean_torque_error_relative"], row["indicated_work_error_relative"])

    if worst(at_scene) <= limit:
        return
    good = [row for row in step_rows if worst(row) <= limit]
    if good:
        row = max(good, key=lambda r: r["angle_step_deg"])
        hint = f"Δα = {row['angle_step_deg']:g}° keeps both within it ({100 * worst(row):.2g} %)"
    else:
        hint = "choose a finer step"
    raise SceneError(Problem(
        "analysis.angle_step_deg", scene.analysis.angle_step_deg,
        f"too coarse for this scene: at {scene.analysis.angle_step_deg:g}° the mean torque is "
        f"{100 * at_scene['mean_torque_error_relative']:.3g} % and the indicated work "
        f"{100 * at_scene['indicated_work_error_relative']:.3g} % off a reference that does not depend on the step "
        f"(at most {opts.max_error_percent:g} % allowed, [numerics] max_error_percent); {hint}"))


def _probes(scene, results, probes, runner) -> None:
    studies = {}
    for probe in probes:
        try:
            if not probe.applies(scene):
                continue
            points = probe.run(scene, runner)
            studies[probe.name] = {"title": probe.title,
                                   "points": [p.__dict__ for p in points]}
        except CrankdynError as exc:
            studies[probe.name] = {"title": probe.title, "refused": str(exc), "points": []}
    if studies:
        results["solvers"] = studies


def run_kinematics(scene, inputs) -> StageOutput:
    runner, probes = inputs[SERVICE_RUNNER], inputs[SERVICE_ERROR_PROBES]
    opts = options(scene, "numerics", NumericsOptions)
    results: dict[str, Any] = {}
    tables: dict[str, Any] = {}
    _kinematics_part(scene, opts, results, tables)
    _probes(scene, results, probes, runner)
    return StageOutput(data={}, results=results, tables=tables)


# ------------------------------------------------------------------ rendering
_FORM_MARKERS = {"two_term": "s", "series": "o", "harmonic": "^", "exact": "*"}


def _plain(ctx, value: float) -> str:
    """A step such as 0.25 or 30 as typed (no padding zeros), with the language's separator."""
    return f"{value:g}".replace(".", ctx.t.decimal_separator)


def _form_label(t, row) -> str:
    if row["form"] == "exact":
        return t("numerics.form_exact")
    if row["form"] == "two_term":
        return t("numerics.form_two_term")
    return t(f"numerics.form_{row['form']}", terms=row["terms"])


def _render_kinematics(r, ctx):
    t = ctx.t
    rows = r.get("kinematics_forms")
    if not rows:
        return None, None
    table = ctx.table([
        (t("numerics.form"), [_form_label(t, row) for row in rows], None),
        ("max |Δ<i>s</i>|, " + t("unit.m"), [ctx.num(row["displacement_error_max_m"], 2) for row in rows], None),
        ("max |Δ<i>j</i>|/<i>ω</i><sup>2</sup>, " + t("unit.m"),
         [ctx.num(row["acceleration_error_max_m_s2"], 2) for row in rows], None),
        (t("numerics.time_per_evaluation"), [ctx.num(row["time_per_evaluation_s"] * 1e6, 3) for row in rows], None),
    ], caption=t("numerics.forms_caption", points=rows[0]["points"]), see="numerics.see_forms_table")
    figure = ctx.figure(functools.partial(_forms_figure, rows, t), t("numerics.forms_figure_caption"),
                        "kinematics_forms", see="numerics.see_forms_figure")
    return table, figure


def _forms_figure(rows, t):
    """The largest displacement error of each form of the piston kinematics against its time per evaluation."""
    fig, ax = new_figure(16, 8.5)
    for row in rows:
        ax.loglog([row["time_per_evaluation_s"] * 1e6], [max(row["displacement_error_max_m"], _LOG_FLOOR * 1e-3)],
                  marker=_FORM_MARKERS[row["form"]], ls="none", ms=7, label=_form_label(t, row))
    ax.set_xlabel(t("numerics.axis_time_us"))
    ax.set_ylabel(t("numerics.axis_displacement_error"))
    ax.legend(loc="best", fontsize=8, ncol=2)
    return fig


def _render_probes(r, ctx):
    t = ctx.t
    out = []
    for study in (r.get("solvers") or {}).values():
        points = study["points"]
        if not points:
            out.append((study["title"], None, study.get("refused", "")))
            continue
        table = ctx.table([
            (t("numerics.method"), [p["method"] for p in points], None),
            (t("numerics.setting"), [p["setting"] for p in points], None),
            (t("numerics.error"), [ctx.num(p["error"], 2) + " " + p["error_unit"] for p in points], None),
            (t("numerics.time_ms"), [ctx.num(p["time_s"] * 1e3, 3) for p in points], None),
        ], caption=t("numerics.solver_caption", title=study["title"]), see="numerics.see_solver")
        out.append((study["title"], table, ""))
    return out


def _render_steps(r, ctx):
    """Table, figure, the printed-error statement and the reference text of the step study."""
    t = ctx.t
    steps = r["steps"]
    labels = {"mean_torque": t("numerics.q_mean_torque"), "indicated_work": t("numerics.q_indicated_work"),
              "tangential_max": t("numerics.q_tangential_max"), "tangential_min": t("numerics.q_tangential_min"),
              "resultant_max": t("numerics.q_resultant_max")}
    has_theory = any("theoretical_work_error_relative" in s for s in steps)
    columns = [("Δ<i>α</i>, °", [_plain(ctx, s["angle_step_deg"]) for s in steps], None),
               (t("numerics.angles_count"), [str(s["points"]) for s in steps], None),  # N is the series' terms
               (t("numerics.time_ms"), [ctx.num(s["time_s"] * 1e3, 3) for s in steps], None)]
    for q in QUANTITIES:
        columns.append((labels[q] + ", %", [ctx.num(100 * s[f"{q}_error_relative"], 2) for s in steps], None))
    if has_theory:
        columns.append((t("numerics.q_theoretical_work") + ", %",
                        [ctx.num(100 * s["theoretical_work_error_relative"], 2)
                         if "theoretical_work_error_relative" in s else "—" for s in steps], None))
    table = ctx.table(columns, caption=t("numerics.steps_caption"), css_class="data wide",
                      see="numerics.see_steps_table")

    figure = ctx.figure(functools.partial(_steps_figure, steps, labels, has_theory, t),
                        t("numerics.steps_figure_caption"), "error_vs_time", see="numerics.see_steps_figure")

    a = r["at_scene_step"]
    statement = t("numerics.printed_errors", step=_plain(ctx, a["angle_step_deg"]),
                  torque=ctx.num(100 * a["mean_torque_error_relative"], 2),
                  work=ctx.num(100 * a["indicated_work_error_relative"], 2),
                  t_max=ctx.num(a["tangential_max_error_Pa"] / 1e6, 2),
                  t_min=ctx.num(a["tangential_min_error_Pa"] / 1e6, 2),
                  q_max=ctx.num(a["resultant_max_error_Pa"] / 1e6, 2))
    if r["reference_method"] in ("quadrature", "mixed"):
        uncertainty = max(r["reference_uncertainty_relative"].values(), default=0.0)
        reference_text = t("numerics.reference_quadrature", panel=_plain(ctx, _PANEL_DEG), order=_GAUSS_ORDER,
                           search=_plain(ctx, _SEARCH_STEP_DEG), uncertainty=ctx.num(100 * uncertainty, 2),
                           ms=ctx.num(r["reference_time_s"] * 1e3, 3))
        if r["reference_method"] == "mixed":
            reference_text += " " + t("numerics.reference_mixed", step=_plain(ctx, _FALLBACK_REFERENCE_STEP_DEG))
    else:
        reference_text = t("numerics.reference_fine_step", step=_plain(ctx, r["reference_step_deg"]))
    return table, figure, statement, reference_text + " " + _timing_text(r, ctx)


def _steps_figure(steps, labels, has_theory, t):
    """The errors of the step study's quantities against the run time, the points marked with their step."""
    fig, ax = new_figure(16, 10)
    times = [s["time_s"] * 1e3 for s in steps]
    highest = [100 * _LOG_FLOOR] * len(steps)  # each step's highest marker: its label goes above them all
    for i, q in enumerate(QUANTITIES):
        errors = [max(100 * s[f"{q}_error_relative"], 100 * _LOG_FLOOR) for s in steps]
        ax.loglog(times, errors, marker="os^vD"[i], label=labels[q])
        highest = [max(h, e) for h, e in zip(highest, errors, strict=True)]
    if has_theory:
        errors = [max(100 * s.get("theoretical_work_error_relative", 0.0), 100 * _LOG_FLOOR) for s in steps]
        ax.loglog(times, errors, marker="x", ls="--", color="0.4", label=t("numerics.q_theoretical_work"))
        highest = [max(h, e) for h, e in zip(highest, errors, strict=True)]
    points = [(x, max(100 * s["mean_torque_error_relative"], 100 * _LOG_FLOOR)) for s, x in zip(steps, times, strict=True)]
    for k in _labelled_points(points):  # (a supervisor: the labels printed over the markers)
        ax.annotate(f"{t.number_g(steps[k]['angle_step_deg'])}°", (times[k], highest[k]),
                    textcoords="offset points", xytext=(0, 6), ha="center", va="bottom", fontsize=7)
    ax.set_xlabel(t("numerics.axis_time_ms"))
    ax.set_ylabel(t("numerics.axis_error_percent"))
    ax.legend(loc="best", fontsize=8)
    return fig


def _timing_text(r, ctx) -> str:
    """How the step times were measured and the fixed per-call overhead they leave out."""
    common = {"repeats": r["steps_timing_repeats"], "min_ms": ctx.num(r["steps_timing_min_repeat_s"] * 1e3, 2)}
    if r["steps_timed"] == "formulas":
        return ctx.t("numerics.timing_formulas", overhead=ctx.num(r["per_call_overhead_s"] * 1e3, 2), **common)
    return ctx.t("numerics.timing_rerun", **common)


def _course_note(ctx) -> bool:
    """A course note (``[report] detail = "course"``) states the error against time in a few
    sentences; the study's tables, figures and methods belong to the full report."""
    return ctx.scene is not None and ctx.scene.report.detail == "course"


def render_course(r, ctx) -> str | None:
    """The course note's statement: the step, the errors of the main results at it and the time
    of the calculation, against the coarsest step studied (what a coarser step would save)."""
    if "steps" not in r:
        return None
    t = ctx.t
    a = r["at_scene_step"]
    statement = t("numerics.printed_errors", step=_plain(ctx, a["angle_step_deg"]),
                  torque=ctx.num(100 * a["mean_torque_error_relative"], 2),
                  work=ctx.num(100 * a["indicated_work_error_relative"], 2),
                  t_max=ctx.num(a["tangential_max_error_Pa"] / 1e6, 2),
                  t_min=ctx.num(a["tangential_min_error_Pa"] / 1e6, 2),
                  q_max=ctx.num(a["resultant_max_error_Pa"] / 1e6, 2))
    ctx.conclude(statement)
    own = min(r["steps"], key=lambda s: abs(s["angle_step_deg"] - a["angle_step_deg"]))
    coarse = max(r["steps"], key=lambda s: s["angle_step_deg"])
    text = [statement]
    if coarse is not own:
        text.append(t("numerics.course_time", step=_plain(ctx, own["angle_step_deg"]),
                      time=ctx.num(own["time_s"] * 1e3, 2),
                      coarse=_plain(ctx, coarse["angle_step_deg"]),
                      coarse_time=ctx.num(coarse["time_s"] * 1e3, 2),
                      coarse_error=ctx.num(100 * max(coarse[f"{q}_error_relative"]
                                                     for q in QUANTITIES), 2)))
    return "".join(f'<p class="printed-errors">{escape(p)}</p>' for p in text)


def render(output: StageOutput, ctx) -> str:
    r = output.results
    if _course_note(ctx):
        return render_course(r, ctx)
    step_table = step_figure = statement = reference_text = None
    if "steps" in r:
        step_table, step_figure, statement, reference_text = _render_steps(r, ctx)
        ctx.conclude(statement)
    forms_table, forms_figure = _render_kinematics(r, ctx)
    return ctx.render_template("sections/numerics.html.j2", r=r, step_table=step_table, step_figure=step_figure,
                               statement=statement, reference_text=reference_text,
                               refused=refused_steps(r, ctx),
                               unavailable=ctx.t("numerics.unavailable_pipeline") if r.get("steps_unavailable") else None,
                               forms_table=forms_table, forms_figure=forms_figure,
                               kinematics_statement=_kinematics_statement(r, ctx), probes=_render_probes(r, ctx))


#: How results.json words a step left out for the study's time budget (see ``run``).
_BUDGET_REASON = "left out: the study's time budget"


def refused_steps(r, ctx) -> list[tuple[str, str]]:
    """The steps left out of the study and why, in the report's language. results.json keeps
    the reasons as the code words them (the rule a step broke, in English); the report says
    which of the two cases it is."""
    t = ctx.t
    budget = options(ctx.scene, "numerics", NumericsOptions).time_budget_s if ctx.scene is not None else None
    out = []
    for step, reason in r.get("steps_refused", {}).items():
        if reason.startswith(_BUDGET_REASON) and budget is not None:
            why = t("numerics.refused_time_budget", budget=t.number_g(budget, 3))
        else:
            why = t("numerics.refused_not_allowed")
        out.append((t.number_g(float(step), 4), why))
    return out


def _kinematics_statement(r, ctx) -> str | None:
    rows = r.get("kinematics_forms")
    if not rows:
        return None
    t = ctx.t
    chosen = next(row for row in rows if row["form"] == ("exact" if r["kinematics_method"] == "exact" else "two_term"))
    return t("numerics.kinematics_printed_" + r["kinematics_method"],
             ds=ctx.num(chosen["displacement_error_max_m"] * 1e3, 2),
             dj=ctx.num(chosen["acceleration_error_max_m_s2"], 2))


def render_kinematics(output: StageOutput, ctx) -> str | None:
    r = output.results
    if _course_note(ctx):  # the series of the kinematics are a study of the full report
        return None
    forms_table, forms_figure = _render_kinematics(r, ctx)
    if forms_table is None and not r.get("solvers"):
        return None
    return ctx.render_template("sections/numerics.html.j2", r=r, step_table=None, step_figure=None,
                               statement=None, reference_text=None, refused=[], unavailable=None,
                               forms_table=forms_table, forms_figure=forms_figure,
                               kinematics_statement=_kinematics_statement(r, ctx), probes=_render_probes(r, ctx))


NUMERICS_STAGE = Stage(
    template_dir=TEMPLATES,
    appendix=True,  # a study of the numerics, not part of a course brief
    name="numerics",
    # the core's letters that hold with their meaning in this section only
    section_symbols=("studied_value", "angle_step", "total_torque", "series_term",
                     "tangential_max", "tangential_min", "crank_load_max",
                     "displacement_difference", "acceleration_difference"),
    title_key="numerics.title",
    requires=(KINEMATICS, GAS_PRESSURE, FORCES),
    last=True,  # it judges the numbers of the sections before it
    provides=(),
    applies=applies,
    run=run,
    render=render,
    figures=("error_vs_time", "kinematics_forms"),
    tables=("steps", "kinematics_forms"),
    references_full=("ismailov",),
    references_sentence="numerics.sources",
    options_table="numerics",
    options_model=NumericsOptions,
    services=(SERVICE_RUNNER, SERVICE_ERROR_PROBES, SERVICE_ASIDE),
)

NUMERICS_KINEMATICS_STAGE = Stage(
    template_dir=TEMPLATES,
    appendix=True,
    name="numerics_kinematics",
    # the core's letters that hold with their meaning in this section only
    section_symbols=("studied_value", "angle_step", "total_torque", "series_term",
                     "tangential_max", "tangential_min", "crank_load_max",
                     "displacement_difference", "acceleration_difference"),
    title_key="numerics.title",
    requires=(KINEMATICS,),
    provides=(),
    applies=applies_kinematics,
    run=run_kinematics,
    render=render_kinematics,
    figures=("kinematics_forms",),
    tables=("kinematics_forms",),
    last=True,
    references_full=("ismailov",),
    references_sentence="numerics.sources",
    services=(SERVICE_RUNNER, SERVICE_ERROR_PROBES),
)
