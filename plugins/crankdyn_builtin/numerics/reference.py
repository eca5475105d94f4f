"""The references the studies are measured against, none of which uses the method under test.

The cycle integrals are Gauss–Legendre quadratures of the pointwise model on 0.25° panels
(checked against 0.5° panels), the extremes a dense 0.01° search refined twice by a factor of 100
around the best point. The mean torque comes from the torque integral directly (single-cylinder
and central/fork rods: cylinders × ∮M dα/Θ), for articulated rods from virtual work (Σ ∮p dV
over master and slave cylinders / Θ). The piston kinematics' forms (the textbook two-term form,
the Maclaurin series in λ, :mod:`crankdyn.physics.series`) are measured against an
extended-precision evaluation of the exact form."""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from crankdyn.physics import articulated as art
from crankdyn.physics import forces as phys
from crankdyn.physics import indicator as ind
from crankdyn.physics import kinematics as kin
from crankdyn.physics import pressure_trace as trace
from crankdyn.physics import series
from crankdyn.physics.extrema import first_argmax
from crankdyn.plugin.contracts import RodDynamicsOptions
from crankdyn.plugin.scene_inputs import (
    cycle_parameters,
    engine_layout,
    rounding_parameters,
    slave_cylinder_pressure,
)
from crankdyn.scene import (
    Scene,
    options,
)

from .steps import StepRun, _motion, best_times, drawn_rounding, run_at_step

FALLBACK_REFERENCE_STEP_DEG = 0.05


# Pointwise reference: Gauss-Legendre panels and the dense extremum search.
PANEL_DEG = 0.25


GAUSS_ORDER = 8


SEARCH_STEP_DEG = 0.01


_SEARCH_REFINEMENTS = 2  # each refines the step 100-fold around the best point


# Piston-kinematics study grid (one revolution).
_KINEMATICS_POINTS = 3600


# ------------------------------------------------------------------ the pointwise reference
def _gauss_nodes(edges_rad: np.ndarray, order: int = GAUSS_ORDER):
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

    def __init__(self, scene: Scene, motion=None, rounding=None):
        e, m, c = scene.engine, scene.masses, scene.cycle
        self.scene = scene
        self.analytic = e.mechanism == "crank_slider"
        if not self.analytic and (motion is None or motion.displacement_at is None):
            raise ValueError(f"the {e.mechanism!r} kinematics give no displacement at any angle")
        self._displacement_at = None if self.analytic else motion.displacement_at
        self.radius, self.ratio, self.omega = (
            e.crank_radius_m,
            e.rod_ratio_value,
            e.angular_velocity_rad_s,
        )
        self.cycle_deg = e.cycle_deg
        self.exact = scene.analysis.kinematics == "exact"
        self.area = float(phys.piston_area_m2(e.bore))
        # the piston's own stroke and BDC, as the indicator diagram takes them: an offset
        # crank-slider's stroke exceeds 2R and its BDC is not at 180 deg
        extra = {} if motion is None else motion.extra
        self.swept = self.area * float(extra.get("stroke_m", e.stroke))
        self._bdc_deg = float(extra.get("bdc_crank_angle_deg", 180.0))
        self.p0 = e.crankcase_pressure
        rod_rec, rod_rot = phys.rod_mass_split_kg(
            m.rod, e.rod_length_m, scene.rod_cm_from_big_end_m
        )
        self.reciprocating = float(m.piston_group + rod_rec)
        self.centrifugal = float(
            phys.centrifugal_pressure_Pa(
                rod_rot + m.crank_pin + 2.0 * m.crank_web, self.radius, self.omega, self.area
            )
        )
        self.clearance = float(ind.clearance_volume_m3(self.swept, c.compression_ratio))
        if c.source == "trace":
            path = scene.resolve(c.trace_file)
            fmt = c.trace_format or ("diesel-rk" if path.suffix.lower() == ".ind" else "csv")
            reader = trace.read_diesel_rk_ind if fmt == "diesel-rk" else trace.read_pressure_csv
            self._trace = reader(path)
            self._target_tdc = 360.0 if e.strokes == 4 else 0.0
            shifted = np.mod(
                self._trace[0] + self._target_tdc - c.trace_firing_tdc_deg, self.cycle_deg
            )
            self.knots_deg = _sorted_distinct(shifted)
        else:
            self._trace = None
            self._params = dataclasses.replace(cycle_parameters(scene), bdc_deg=self._bdc_deg)
            # the rounding's parameters as the indicator drew them (given: the run's), else the
            # scene's
            self._rounding = rounding if rounding is not None else rounding_parameters(scene)
            opening = self._rounding.exhaust_opens_before_bdc_deg
            if e.strokes == 2 and opening > 0 and not self.analytic:
                # the exhaust ports' lost stroke fraction, as the indicator diagram takes it: by
                # the mechanism's own displacement (the central crank-slider's exact one is the
                # scene's cycle parameters')
                travel = float(
                    np.ravel(self._displacement_at(np.asarray([self._bdc_deg - opening])))[0]
                )
                psi = min(max(1.0 - travel * self.area / self.swept, 0.0), 1.0 - 1e-12)
                self._params = dataclasses.replace(self._params, lost_stroke_fraction=psi)
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
            return (-s(a + 2 * h) + 8 * s(a + h) - 8 * s(a - h) + s(a - 2 * h)) / (
                12 * math.radians(h)
            )
        a = np.radians(a_deg)
        f = kin.piston_velocity_exact_m_s if self.exact else kin.piston_velocity_approx_m_s
        return f(a, self.radius, self.ratio, 1.0)

    def acceleration(self, a_deg):
        """d2s/dt2 at constant omega, m/s^2."""
        if not self.analytic:
            a, h = np.asarray(a_deg, dtype=float), self._FD_STEP_ACCEL_DEG
            s = self.displacement
            d2 = (-s(a + 2 * h) + 16 * s(a + h) - 30 * s(a) + 16 * s(a - h) - s(a - 2 * h)) / (
                12 * math.radians(h) ** 2
            )
            return self.omega**2 * d2
        f = (
            kin.piston_acceleration_exact_m_s2
            if self.exact
            else kin.piston_acceleration_approx_m_s2
        )
        return f(np.radians(a_deg), self.radius, self.ratio, self.omega)

    def volume(self, a_deg):
        return self.clearance + self.area * self.displacement(a_deg)

    def pressure(self, a_deg):
        a_deg = np.asarray(a_deg, dtype=float)
        if self._trace is not None:
            c = self.scene.cycle
            return trace.to_cycle_grid(
                self._trace[0],
                self._trace[1],
                self.cycle_deg,
                a_deg,
                c.trace_firing_tdc_deg,
                self._target_tdc,
            )
        return ind.rounded_pressure_Pa(
            a_deg,
            self.volume(a_deg),
            self.clearance,
            self._params,
            self._rounding,
            volume_function=self.volume,
        )

    def forces(self, a_deg, pressure=None):
        """(tangential_Pa, resultant_Pa or None, torque_Nm) at the angles ``a_deg``."""
        a = np.radians(a_deg)
        p = self.pressure(a_deg) if pressure is None else pressure
        total = (
            p
            - self.p0
            + phys.inertia_pressure_Pa(self.reciprocating, self.acceleration(a_deg), self.area)
        )
        if not self.analytic:  # virtual work: t R F = p1 F ds/dalpha
            tangential = total * self.arm(a_deg) / self.radius
            return tangential, None, phys.crank_torque_Nm(tangential, self.radius, self.area)
        rod = phys.rod_force_components(total, a, kin.rod_angle_rad(a, self.ratio))
        q = phys.resultant_crank_pin_pressure_Pa(rod.tangential_Pa, rod.radial_Pa, self.centrifugal)
        return rod.tangential_Pa, q, phys.crank_torque_Nm(rod.tangential_Pa, self.radius, self.area)

    # integrals
    def panel_edges_deg(self, panel_deg: float) -> np.ndarray:
        uniform = np.arange(0.0, self.cycle_deg + 0.5 * panel_deg, panel_deg)
        return _sorted_distinct(np.concatenate([uniform, self.knots_deg, [self.cycle_deg]]))

    def integrals(self, panel_deg: float = PANEL_DEG) -> tuple[float, float]:
        """(indicated work J, mean crank torque N m) of one cylinder by Gauss-Legendre panels."""
        nodes, weights = _gauss_nodes(np.radians(self.panel_edges_deg(panel_deg)))
        a_deg = np.degrees(nodes)
        p = self.pressure(a_deg)
        work = float(np.sum(weights * p * self.area * self.arm(a_deg)))
        _, _, torque = self.forces(a_deg, p)
        return work, float(np.sum(weights * torque) / math.radians(self.cycle_deg))

    def extremes(self) -> dict[str, float]:
        """Largest and smallest t and largest q: dense search refined around the best points."""
        n = int(round(self.cycle_deg / SEARCH_STEP_DEG))
        a = np.arange(n) * SEARCH_STEP_DEG
        t, q, _ = self.forces(a)
        kinds = (("tangential_max", 0, 1.0), ("tangential_min", 0, -1.0), ("resultant_max", 1, 1.0))
        if q is None:
            kinds = kinds[:2]
        centres = [float(a[first_argmax(sign * (t, q)[which])]) for _, which, sign in kinds]
        best = [float(np.max(sign * (t, q)[which])) for _, which, sign in kinds]
        step = SEARCH_STEP_DEG
        offsets = np.linspace(-1.0, 1.0, 201)
        for _ in range(_SEARCH_REFINEMENTS):
            # one evaluation for the three local grids
            local = np.concatenate([c + step * offsets for c in centres])
            lt, lq, _ = self.forces(np.mod(local, self.cycle_deg))
            for k, (_, which, sign) in enumerate(kinds):
                part = sign * (lt, lq)[which][k * offsets.size : (k + 1) * offsets.size]
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
        g = art.SlaveGeometry(
            e.crank_radius_m,
            e.rod_length_m,
            bays_results["pin_radius_m"],
            math.radians(slave["pin_angle_deg"]),
            math.radians(slave["bank_angle_deg"]),
            slave["slave_rod_length_m"],
        )
        motion = art.slave_motion(nodes, g, 1.0)  # velocity = dx/dalpha, m/rad
        delta = (
            by_label[slave["cylinder"]].firing_delay_deg - master.firing_delay_deg
        ) % layout.cycle_deg
        delta += slave["tdc_master_angle_deg"] - slave["bank_angle_deg"]
        own_angle = np.mod(a_deg - delta, layout.cycle_deg)
        if scene.cycle.source == "theoretical":
            p, _ = slave_cylinder_pressure(scene, g, model.area, own_angle)
        else:
            p = model.pressure(own_angle)
        total += float(np.sum(weights * p * model.area * (-motion.piston_velocity_m_s)))
    return total


def _sorted_distinct(values: np.ndarray) -> np.ndarray:
    """``values`` sorted, each distinct value once: ``np.unique`` of a float array, without
    the masked-array module numpy imports on that function's first call (25 ms of a report's
    compute)."""
    ordered = np.sort(np.asarray(values, dtype=float).ravel())
    if ordered.size == 0:
        return ordered
    return ordered[np.concatenate(([True], ordered[1:] != ordered[:-1]))]


@dataclass
class Reference:
    method: str  # "quadrature", "mixed" or "fine_step"
    values: dict[str, float]
    uncertainty: dict[str, float]  # relative
    time_s: float
    theoretical_work_J: float | None = None
    note: str = ""


def reference_values(scene: Scene, sample: StepRun, runner) -> Reference:
    """The reference of the step study (see the module docstring).

    ``quadrature``: everything from the pointwise model; ``mixed``: a mechanism known only by its
    displacement — integrals and t by the pointwise model, q from the fine step; ``fine_step``:
    the same calculation at 0.05 deg (articulated rods with two-term kinematics; loads of the
    rigid rod, ``[rod_dynamics] apply_to_loads``, which the two-mass pointwise model does not
    give).
    """
    start = time.perf_counter()
    e = scene.engine
    articulated = e.rod_type == "articulated"
    analytic = e.mechanism == "crank_slider"
    motion = _motion(sample)
    rigid_rod = options(scene, "rod_dynamics", RodDynamicsOptions).apply_to_loads
    if (
        rigid_rod
        or articulated
        and scene.analysis.kinematics != "exact"
        or (not analytic and (articulated or motion is None or motion.displacement_at is None))
    ):
        run = run_at_step(scene, FALLBACK_REFERENCE_STEP_DEG, repeats=1, runner=runner)
        return Reference(
            "fine_step",
            run.values,
            {},
            time.perf_counter() - start,
            note=f"{FALLBACK_REFERENCE_STEP_DEG:g}",
        )
    model = PointwiseModel(scene, motion, drawn_rounding(sample))
    work, mean = model.integrals(PANEL_DEG)
    work_coarse, mean_coarse = model.integrals(2 * PANEL_DEG)
    cycle_rad = math.radians(e.cycle_deg)
    if articulated:
        bays_results = sample.outputs["bays"].results
        slaves = _slave_work_J(model, scene, bays_results, PANEL_DEG)
        slaves_coarse = _slave_work_J(model, scene, bays_results, 2 * PANEL_DEG)
        cranks = len(bays_results["crank_angles_deg"])
        engine_mean = cranks * (work + slaves) / cycle_rad
        engine_mean_coarse = cranks * (work_coarse + slaves_coarse) / cycle_rad
    else:
        engine_mean, engine_mean_coarse = e.cylinders * mean, e.cylinders * mean_coarse
    values = {"mean_torque": engine_mean, "indicated_work": work, **model.extremes()}
    method = "quadrature"
    if "resultant_max" not in values:
        values["resultant_max"] = run_at_step(
            scene, FALLBACK_REFERENCE_STEP_DEG, repeats=1, runner=runner
        ).values["resultant_max"]
        method = "mixed"

    def rel(a, b):
        return abs(a - b) / abs(b) if b else abs(a - b)

    uncertainty = {
        "mean_torque": rel(engine_mean_coarse, engine_mean),
        "indicated_work": rel(work_coarse, work),
    }
    theoretical = None
    # The closed form assumes dead centres at 0/180 deg and a swept volume F*S: true of the central
    # crank-slider, not of an offset or planetary linkage (their strokes and phases differ).
    if scene.cycle.source == "theoretical" and analytic:
        theoretical = ind.theoretical_diagram_mean_pressure_Pa(model._params) * model.swept
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


def kinematics_forms(
    radius: float, ratio: float, points: int = _KINEMATICS_POINTS, repeats: int = 3
) -> list[dict]:
    """Largest errors of s and j and time per evaluation of s, v, j for every form.

    The errors are against the exact form evaluated in extended precision; ``exact`` itself is
    listed with its round-off error. Times are per evaluation of s, v and j on ``points``
    angles over one revolution (omega = 1 rad/s; errors of j are reported per omega^2).
    """
    a_deg = np.arange(points) * (360.0 / points)
    a = np.radians(a_deg)
    s_ref, j_ref = _exact_extended(a_deg, radius, ratio)
    forms: list[tuple[str, int | None, Callable]] = [
        (
            "two_term",
            2,
            lambda: (
                kin.piston_displacement_approx_m(a, radius, ratio),
                kin.piston_velocity_approx_m_s(a, radius, ratio, 1.0),
                kin.piston_acceleration_approx_m_s2(a, radius, ratio, 1.0),
            ),
        )
    ]
    for terms in (3, 4, 5):
        forms.append(
            (
                "series",
                terms,
                functools.partial(
                    lambda n: (
                        series.piston_displacement_series_m(a, radius, ratio, n),
                        series.piston_velocity_series_m_s(a, radius, ratio, 1.0, n),
                        series.piston_acceleration_series_m_s2(a, radius, ratio, 1.0, n),
                    ),
                    terms,
                ),
            )
        )
    for terms in (3, 4, 5):
        forms.append(
            (
                "harmonic",
                terms,
                functools.partial(
                    lambda n: (
                        series.piston_displacement_harmonic_m(a, radius, ratio, n),
                        series.piston_velocity_harmonic_m_s(a, radius, ratio, 1.0, n),
                        series.piston_acceleration_harmonic_m_s2(a, radius, ratio, 1.0, n),
                    ),
                    terms,
                ),
            )
        )
    forms.append(
        (
            "exact",
            None,
            lambda: (
                kin.piston_displacement_exact_m(a, radius, ratio),
                kin.piston_velocity_exact_m_s(a, radius, ratio, 1.0),
                kin.piston_acceleration_exact_m_s2(a, radius, ratio, 1.0),
            ),
        )
    )
    rows = []
    timings = best_times([fn for _, _, fn in forms], repeats)
    for (name, terms, fn), timing in zip(forms, timings, strict=True):
        s, _, j = fn()
        rows.append(
            {
                "form": name,
                "terms": terms,
                "displacement_error_max_m": float(np.max(np.abs(s - s_ref))),
                "acceleration_error_max_m_s2": float(np.max(np.abs(j - j_ref))),
                "time_per_evaluation_s": timing.best_s,
                "points": points,
            }
        )
    return rows


def labelled_points(
    points, width_cm: float = 13.0, height_cm: float = 7.5, gap_cm: float = 0.45
) -> list[int]:
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
        if k in (0, len(points) - 1) or all(
            np.hypot(*((logs[k] - logs[j]) * scale)) >= gap_cm for j in placed
        ):
            placed.append(k)
    return sorted(placed)
