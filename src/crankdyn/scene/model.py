"""The scene: one TOML file describing a mechanism, its engine cycle and the report.

Loading is the only place where units are parsed; everything after it is SI.
pydantic does the structural validation (unknown keys, missing values, types)
because its error locations name the exact field; the range and consistency
checks are ours so that every message states the allowed range in the user's units.
"""

from __future__ import annotations

import datetime
import difflib
import math
import stat
import sys
import tomllib
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    PrivateAttr,
    ValidationError,
    model_validator,
)

from ..errors import MISSING, Problem, SceneError
from ..physics import firing_explorer as fe
from ..physics import layout as lay
from ..physics.indicator import lost_stroke_fraction
from ..physics.layout import nearest_steps_deg, step_on_grid_deg
from .datafiles import data_file_problem
from .inputcheck import TOO_CLOSE_TO_ZERO, structure_problems, table_problems, toml_float
from .units import parse_quantity


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)


def _quantity(
    kind: str,
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
    unit: str = "",
    scale: float = 1.0,
):
    """An SI float read from a unit string, with a range stated in ``unit`` (SI value = shown * scale)."""

    def check(value: float) -> float:
        def shown(x: float) -> str:
            return f"{x / scale:g} {unit}".strip()

        parts = []
        ok = True
        if gt is not None:
            parts.append(f"> {shown(gt)}")
            ok &= value > gt
        if ge is not None:
            parts.append(f">= {shown(ge)}")
            ok &= value >= ge
        if lt is not None:
            parts.append(f"< {shown(lt)}")
            ok &= value < lt
        if le is not None:
            parts.append(f"<= {shown(le)}")
            ok &= value <= le
        if not ok:
            raise ValueError("must be " + " and ".join(parts))
        return value

    return Annotated[
        float, BeforeValidator(lambda v: parse_quantity(v, kind)), AfterValidator(check)
    ]


def _number(
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
):
    """A plain finite number with a stated range."""

    def check(value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError("must be a number")
        try:
            value = float(value)
        except OverflowError:
            raise ValueError(
                "must be a finite number (this integer is too large for a float)"
            ) from None
        if not math.isfinite(value):
            raise ValueError("must be a finite number")
        _check_representable(value)
        parts, ok = [], True
        for symbol, bound, test in (
            (">", gt, lambda a, b: a > b),
            (">=", ge, lambda a, b: a >= b),
            ("<", lt, lambda a, b: a < b),
            ("<=", le, lambda a, b: a <= b),
        ):
            if bound is not None:
                parts.append(f"{symbol} {bound:g}")
                ok &= test(value, bound)
        if not ok:
            raise ValueError("must be " + " and ".join(parts))
        return value

    return Annotated[float, BeforeValidator(check)]


def _check_representable(value: float) -> None:
    """Refuse a nonzero value too close to zero to compute with (subnormal: its square is 0)."""
    if value != 0.0 and abs(value) < sys.float_info.min:
        raise ValueError(TOO_CLOSE_TO_ZERO)


# Public names for plugins that declare their own scene tables.
quantity = _quantity
number = _number


class ReportMeta(_Strict):
    """Title-page data and the report language."""

    title: str = "Dynamic calculation of a piston engine"
    subtitle: str = ""
    student: str = ""
    #: the grammatical form of the title page's "performed by: student" ("Виконала: студентка")
    student_gender: Literal["male", "female"] = "male"
    group: str = ""
    supervisor: str = ""
    university: str = ""
    department: str = ""
    city: str = ""
    year: Annotated[int, AfterValidator(lambda y: _year(y))] = datetime.date.today().year
    language: str = "en"
    ministry: str = ""  # default: the Ukrainian ministry in a uk note, none in ru and en
    discipline: str = ""  # the course the project belongs to
    variant: str = ""  # the student's variant number (batch sets it from the variants file)
    #: ``course``: what a course brief asks, the numerics study in an appendix; ``full``: all in the body
    detail: Literal["course", "full"] = "course"
    #: crank angle of the worked substitutions (one calculation with the numbers put in)
    worked_angle_deg: Annotated[float, Field(ge=0, le=720)] = 30.0
    #: the printed sheets: ``none`` (the page number of DSTU 3008:2015) or ``eskd``, the frame and
    #: title blocks of ДСТУ ГОСТ 2.104:2006 (form 2 on the first sheet, 2а on the others; report/frame.py)
    frame: Literal["none", "eskd"] = "none"
    #: the document's designation in the title blocks (e.g. "КП.ДВЗ.041.00.000 ПЗ"; empty: the cell is left blank)
    designation: str = ""
    #: the title block's other people (surname and initials): Н. контр. and Затв. (empty: left for a signature)
    standards_controller: str = ""
    approver: str = ""
    #: the title block's Літ. cells, one character each (a department's letter for student work, e.g. "У")
    letter: Annotated[str, Field(max_length=3)] = ""


def _year(year: int) -> int:
    if not 1900 <= year <= 2200:
        raise ValueError("must be a year between 1900 and 2200")
    return year


#: The smallest bore and stroke, m (0.1 mm).
MIN_SIZE_M = 1e-4
#: What a scene of a mechanism with a connecting rod gives of it.
ROD_CHOICE = (
    "give exactly one of rod_length (e.g. '140 mm') or rod_ratio (lambda = R/L, 0 < lambda < 1)"
)
#: The smallest rod ratio lambda = R/L (the search for the piston's extremes needs lambda^2 > 0).
MIN_ROD_RATIO = 1e-6


#: The core scene values whose default the plugins declare, read from the registry when a scene
#: is read with one (:meth:`Scene.with_plugin_defaults`).
REGISTRY_DEFAULTS = frozenset({"engine.mechanism"})


class Engine(_Strict):
    """Engine and mechanism geometry (SI after loading)."""

    name: str = ""
    #: what the engine drives: it names the power take-off end (a flywheel, an aircraft's
    #: propeller) and says whether the textbook's journal proportions (those of automotive and
    #: tractor engines) are the engine's kind; None: not stated
    application: (
        Literal[
            "automotive", "tractor", "stationary", "marine", "outboard", "aircraft", "motorcycle"
        ]
        | None
    ) = None
    #: None: the registry's default mechanism (``Mechanism.default``), filled in when the scene is
    #: loaded with a registry (``scene_from_dict(..., registry=)``) or planned
    mechanism: str | None = None
    strokes: Literal[2, 4] = 4
    cylinders: Annotated[int, AfterValidator(lambda n: _cylinders(n))] = 1
    #: at least 1 rpm: the inertia forces go as the square of the speed, and far below it they
    #: (and the speed fluctuation's ratios) vanish in round-off
    rpm: _number(ge=1, le=30000)
    #: at least 0.1 mm: below it the piston area and the swept volume vanish in round-off
    bore: _quantity("length", ge=MIN_SIZE_M, le=2.0, unit="mm", scale=1e-3)
    stroke: _quantity("length", ge=MIN_SIZE_M, le=4.0, unit="mm", scale=1e-3)
    rod_length: _quantity("length", gt=0, le=20.0, unit="mm", scale=1e-3) | None = None
    rod_ratio: _number(gt=0, lt=1) | None = None
    crankcase_pressure: _quantity("pressure", ge=0, le=1e6, unit="MPa", scale=1e6) = "0.1 MPa"
    # Multi-cylinder engines (checked in detail by the layout plugin).
    layout: Literal["inline", "V", "W", "Y", "X", "boxer", "radial"] = "inline"
    bank_angle_deg: _number(gt=0, lt=360) | None = None
    rod_type: Literal["central", "fork", "articulated"] = "central"
    firing_order: list[int | str] | None = None
    crank_angles_deg: list[_number(ge=-720, le=720)] | None = None
    cylinder_spacing: _quantity("length", gt=0, le=10.0, unit="mm", scale=1e-3) | None = None
    uneven_firing: bool = False
    #: a crosshead engine (a low-speed marine diesel): the piston rod and the crosshead move with
    #: the piston (the piston group's mass counts them), and the side force presses the
    #: crosshead's slide on its guides, not the piston on the cylinder wall
    crosshead: bool = False
    #: N_e, the rated effective power from the thermal calculation (Poda §1 lists it among the
    #: inputs): the torque section then gives the mechanical efficiency N_e/N_i and the mean
    #: effective torque N_e/ω beside the indicated ones.
    effective_power: _quantity("power", gt=0, le=1e8, unit="kW", scale=1e3) | None = None

    @model_validator(mode="after")
    def _rod(self) -> Engine:
        # Neither is a scene of a mechanism without a rod; whether the mechanism has one is
        # the mechanism's declaration (``Mechanism.needs_rod``), checked with the plugins.
        if self.rod_length is not None and self.rod_ratio is not None:
            raise ValueError(ROD_CHOICE)
        if self.rod_ratio is not None and self.rod_ratio < MIN_ROD_RATIO:
            raise _FieldError(
                "rod_ratio",
                f"must be >= {MIN_ROD_RATIO:g}: a longer rod than "
                f"{1 / MIN_ROD_RATIO:g} crank radii moves the piston as a pure sine",
            )
        if self.rod_length is not None and self.rod_length <= self.stroke / 2:
            raise _FieldError(
                "rod_length",
                f"the rod must be longer than the crank radius "
                f"(stroke/2 = {self.stroke / 2 * 1e3:g} mm), i.e. lambda = R/L < 1",
            )
        return self

    @property
    def crank_radius_m(self) -> float:
        return self.stroke / 2

    @property
    def has_rod(self) -> bool:
        """Whether the scene gives a connecting rod (``rod_length`` or ``rod_ratio``)."""
        return self.rod_length is not None or self.rod_ratio is not None

    @property
    def rod_ratio_value(self) -> float:
        """λ = R/L; a SceneError naming ``engine.rod_ratio`` when the scene gives no rod."""
        if self.rod_ratio is not None:
            return self.rod_ratio
        return self.crank_radius_m / self._given_rod_length("rod_ratio")

    @property
    def rod_length_m(self) -> float:
        """L; a SceneError naming ``engine.rod_length`` when the scene gives no rod."""
        if self.rod_length is not None:
            return self.rod_length
        if self.rod_ratio is not None:
            return self.crank_radius_m / self.rod_ratio
        return self._given_rod_length("rod_length")

    def _given_rod_length(self, field: str) -> float:
        if self.rod_length is None:
            raise SceneError(
                Problem(f"engine.{field}", MISSING, ROD_CHOICE + "; a part of the report uses it")
            )
        return self.rod_length

    @property
    def angular_velocity_rad_s(self) -> float:
        return math.pi * self.rpm / 30.0

    @property
    def cycle_deg(self) -> float:
        return 180.0 * self.strokes


def _cylinders(n: int) -> int:
    if not 1 <= n <= 24:
        raise ValueError("must be a whole number from 1 to 24")
    return n


class _FieldError(ValueError):
    """A model-level check that blames one field of the model."""

    def __init__(self, field: str, message: str):
        super().__init__(message)
        self.field = field


#: The largest mass of one mechanism's part, kg: a large low-speed marine engine's piston with its
#: rod and crosshead, or its connecting rod, weighs some ten tonnes.
MAX_PART_MASS_KG = 50_000.0
#: The largest moment of inertia of a connecting rod about its centre of mass, kg m²: such an
#: engine's rod of ten tonnes and three metres has about 10⁴.
MAX_ROD_INERTIA_KG_M2 = 50_000.0


class Masses(_Strict):
    """Moving masses of one crank mechanism."""

    piston_group: _quantity("mass", gt=0, le=MAX_PART_MASS_KG, unit="kg")
    rod: _quantity("mass", gt=0, le=MAX_PART_MASS_KG, unit="kg")
    rod_cm_from_big_end: _quantity("length", gt=0, unit="mm", scale=1e-3) | None = None
    rod_cm_fraction: _number(gt=0, lt=1) | None = None
    crank_pin: _quantity("mass", ge=0, le=MAX_PART_MASS_KG, unit="kg") = "0 kg"
    crank_web: _quantity("mass", ge=0, le=MAX_PART_MASS_KG, unit="kg") = "0 kg"
    # Moment of inertia of the rod about its centre of mass (rod_dynamics stage).
    rod_moment_of_inertia: (
        _quantity("moment_of_inertia", gt=0, le=MAX_ROD_INERTIA_KG_M2, unit="kg m^2") | None
    ) = None

    @model_validator(mode="after")
    def _cm(self) -> Masses:
        if (self.rod_cm_from_big_end is None) == (self.rod_cm_fraction is None):
            raise ValueError(
                "give exactly one of rod_cm_from_big_end (e.g. '38 mm') or rod_cm_fraction "
                "(l_R/L, textbook 0.18-0.32 for car engines)"
            )
        return self


class Rounding(_Strict):
    """Rounding of the theoretical indicator diagram (textbook section 3.1, Appendix V)."""

    ignition_advance_deg: _number(gt=0, lt=60) | None = None
    combustion_delay_deg: _number(ge=0, lt=60) | None = None
    combustion_delay_time: _quantity("time", gt=0, le=0.01, unit="ms", scale=1e-3) = "1.5 ms"
    pressure_rise_to_tdc: _quantity("pressure", ge=0, le=5e6, unit="MPa", scale=1e6) = "0.5 MPa"
    # None: 0.85 for spark ignition (p_z′ = (0.8…0.9)·p_z), 1 for a diesel (p_z′ = p_z, Kolchin)
    peak_pressure_fraction: _number(gt=0.5, le=1.0) | None = None
    peak_angle_after_tdc_deg: _number(gt=0, le=40) = 12.0
    exhaust_opens_before_bdc_deg: _number(ge=0, le=90) = 50.0
    exhaust_closes_after_tdc_deg: _number(ge=0, le=60) = 20.0
    intake_opens_before_tdc_deg: _number(ge=0, le=60) = 15.0
    intake_closes_after_bdc_deg: _number(ge=0, le=90) = 50.0


#: The cycle's values of a four-stroke engine alone: the valve timing near TDC and the exhaust
#: stroke's pressure (a two-stroke's ports are given by exhaust_opens_before_bdc_deg).
FOUR_STROKE_ONLY_FIELDS = frozenset(
    {
        "cycle.rounding.exhaust_closes_after_tdc_deg",
        "cycle.rounding.intake_opens_before_tdc_deg",
        "cycle.rounding.intake_closes_after_bdc_deg",
        "cycle.exhaust_pressure",
    }
)


class Cycle(_Strict):
    """The working cycle: theoretical indicator-diagram data or a pressure trace."""

    source: Literal["theoretical", "trace"] = "theoretical"
    ignition: Literal["spark", "diesel"] | None = None
    compression_ratio: _number(gt=1, le=40) | None = None
    intake_pressure: _quantity("pressure", gt=0, le=1e7, unit="MPa", scale=1e6) | None = None
    compression_index: _number(ge=1.0, le=1.67) | None = None
    max_pressure: _quantity("pressure", gt=0, le=5e7, unit="MPa", scale=1e6) | None = None
    pre_expansion_ratio: _number(ge=1.0, le=5.0) = 1.0
    expansion_index: _number(ge=1.0, le=1.67) | None = None
    exhaust_pressure: _quantity("pressure", gt=0, le=1e7, unit="MPa", scale=1e6) | None = None
    mean_indicated_pressure: _quantity("pressure", gt=0, le=1e7, unit="MPa", scale=1e6) | None = (
        None
    )
    rounding: Rounding = Rounding()
    trace_file: str | None = None
    trace_format: Literal["csv", "diesel-rk"] | None = None
    trace_firing_tdc_deg: _number(ge=-1440, le=1440) = 360.0

    @model_validator(mode="after")
    def _complete(self) -> Cycle:
        if self.source == "trace":
            if not self.trace_file:
                raise _FieldError(
                    "trace_file", "a trace cycle needs trace_file (CSV or Diesel-RK .ind)"
                )
            if self.compression_ratio is None:
                raise _FieldError(
                    "compression_ratio",
                    "missing: with a pressure trace the cylinder volume "
                    "V = V_c + F*s needs the clearance volume V_c = V_h/(eps - 1)",
                )
            return self
        needed = [
            "ignition",
            "compression_ratio",
            "intake_pressure",
            "compression_index",
            "max_pressure",
            "expansion_index",
        ]
        for name in needed:
            if getattr(self, name) is None:
                raise _FieldError(
                    name,
                    "missing; the theoretical indicator diagram needs "
                    + ", ".join(needed)
                    + " (and exhaust_pressure for four-stroke engines)",
                )
        if self.ignition == "spark" and self.pre_expansion_ratio != 1.0:
            raise _FieldError(
                "pre_expansion_ratio",
                "must be 1 for spark ignition (combustion at constant volume)",
            )
        if self.pre_expansion_ratio >= self.compression_ratio:
            raise _FieldError(
                "pre_expansion_ratio", f"must be < compression_ratio ({self.compression_ratio:g})"
            )
        return self

    def check_compression_end(self, strokes: int, rod_ratio: float | None) -> None:
        """A field error naming ``cycle.max_pressure`` unless p_z exceeds the compression-end pressure
        p_c = p_a·ε^n1, with a ported two-stroke's actual ratio ε_д = 1 + (1 − ψ)(ε − 1) from
        its exhaust ports' closing (ψ of the central crank-slider with ``rod_ratio``; none
        given: the geometric ε, a bound on it)."""
        if self.source != "theoretical" or self.max_pressure is None:
            return
        eps, why = self.compression_ratio, "p_a*eps^n1"
        opening = self.rounding.exhaust_opens_before_bdc_deg
        if strokes == 2 and rod_ratio is not None and 0.0 < opening:
            psi = float(lost_stroke_fraction(opening, rod_ratio))
            eps = 1.0 + (1.0 - psi) * (eps - 1.0)
            why = (
                f"p_a*eps_d^n1, eps_d = 1 + (1 - psi)*(eps - 1) = {eps:.4g}, the actual "
                f"compression ratio from the exhaust ports' closing, psi = {psi:.4g}"
            )
        pc = self.intake_pressure * eps**self.compression_index
        if self.max_pressure <= pc:
            raise _FieldError(
                "cycle.max_pressure",
                f"must exceed the compression-end pressure p_c = {pc / 1e6:.3g} MPa ({why})",
            )


DEFAULT_TABLE_STEP_DEG = 10.0
"""Crank angle between the rows of the printed tables when the scene gives none [deg]."""
DEFAULT_ANGLE_STEP_TARGET_DEG = 1.0
"""The angle step [deg] the default step is chosen for (the largest step on the engine's grid not
above it) when no plugin asks for another (``Stage.default_angle_step``): the error of a peak read
off a grid grows as the step squared (f(x0 + h/2) = f_max - f''(x0) h^2/8), and 1 deg keeps the
peaks of the bundled engines within 0.1 %."""


class Analysis(_Strict):
    """Numerical options and the choice of stages."""

    # None: chosen by the scene (``Scene._default_steps``): the largest step on the engine's
    # grid not above the step the plugins ask for (1 deg if none); the table step nearest 10 deg.
    angle_step_deg: _number(ge=0.01, le=30) | None = None
    table_step_deg: _number(ge=0.01, le=90) | None = None
    kinematics: Literal["exact", "approximate"] = "exact"
    stages: list[str] | None = None


def _same_cranks(row, crank_angles_deg) -> bool:
    """Whether an explored arrangement's cranks are the given ones (to 1e-6 deg, modulo a turn)."""
    ours = [a % 360.0 for a in row.crank_angles_deg]
    theirs = [float(a) % 360.0 for a in crank_angles_deg]
    return len(ours) == len(theirs) and all(
        min(abs(a - b), 360.0 - abs(a - b)) <= 1e-6 for a, b in zip(ours, theirs, strict=True)
    )


class Scene(_Strict):
    """A whole scene. ``base_dir`` is where relative file names in it are resolved.

    Top-level tables other than the ones below belong to plugins: ``[mechanism]`` to the
    chosen mechanism, ``[<table>]`` to the stage whose ``options_table`` names it. They are
    kept as raw dicts here and validated by ``orchestrator.check_scene`` (unclaimed
    tables are errors there), and read with :func:`options`.
    """

    model_config = ConfigDict(extra="allow", frozen=True, validate_default=True)

    report: ReportMeta = ReportMeta()
    engine: Engine
    masses: Masses | None = None
    cycle: Cycle | None = None
    analysis: Analysis = Analysis()
    mechanism: dict[str, Any] = {}
    base_dir: str = "."
    # Folders besides base_dir that data files may come from (``--data-dir``; never from the scene).
    data_dirs: tuple[str, ...] = ()
    #: the step [deg] the default angle step was chosen for (:meth:`with_plugin_defaults`)
    _angle_step_target_deg: float = PrivateAttr(default=DEFAULT_ANGLE_STEP_TARGET_DEG)

    @model_validator(mode="after")
    def _consistent(self) -> Scene:
        self._default_firing_order()
        self._default_steps()
        step = self.analysis.angle_step_deg
        cycle = self.engine.cycle_deg
        n = cycle / step
        if abs(n - round(n)) > 1e-6:
            near = ", ".join(f"{x:.12g}" for x in nearest_steps_deg(self.engine_grid_deg, step))
            raise _FieldError(
                "analysis.angle_step_deg",
                f"must divide the cycle ({cycle:g} deg for a {self.engine.strokes}-stroke engine) "
                f"and the firing intervals a whole number of times; the nearest steps that work: {near} "
                f"(or leave it out: a step that works is chosen)",
            )
        ratio = self.analysis.table_step_deg / step
        if abs(ratio - round(ratio)) > 1e-9 or round(ratio) < 1:
            k = max(1, int(ratio))
            near = ", ".join(f"{x:.6g}" for x in sorted({k * step, (k + 1) * step}))
            raise _FieldError(
                "analysis.table_step_deg",
                f"must be a whole multiple of angle_step_deg "
                f"({step:.6g} deg); it is {self.analysis.table_step_deg:g} deg; the nearest that work: {near}",
            )
        if self.cycle is not None and self.engine.strokes == 2:
            given = {f"cycle.{name}" for name in self.cycle.model_fields_set} | {
                f"cycle.rounding.{name}" for name in self.cycle.rounding.model_fields_set
            }
            if given & FOUR_STROKE_ONLY_FIELDS:
                raise _FieldError(
                    sorted(given & FOUR_STROKE_ONLY_FIELDS)[0],
                    "applies to four-stroke engines only (valve timing near TDC and "
                    "the exhaust stroke); remove it for a two-stroke engine",
                )
        if self.cycle is not None:
            rod = self.engine.rod_ratio_value if self.engine.has_rod else None
            self.cycle.check_compression_end(self.engine.strokes, rod)
        if self.cycle is not None and self.masses is None:
            raise _FieldError(
                "masses",
                "missing: a scene with cycle data needs [masses] "
                "(piston_group, rod, rod_cm_from_big_end or rod_cm_fraction)",
            )
        if self.masses is not None and not self.engine.has_rod:
            raise _FieldError(
                "engine.rod_length",
                "missing: [masses] gives a connecting rod's mass and centre of mass, split by the "
                "rod's length; " + ROD_CHOICE,
            )
        if self.masses is not None and self.masses.rod_cm_from_big_end is not None:
            if self.masses.rod_cm_from_big_end >= self.engine.rod_length_m:
                raise _FieldError(
                    "masses.rod_cm_from_big_end",
                    f"must be < the rod length ({self.engine.rod_length_m * 1e3:g} mm)",
                )
        if self.cycle is not None and self.cycle.trace_file:
            reason = self.data_file_problem(self.cycle.trace_file)
            if reason:
                raise _FieldError("cycle.trace_file", reason)
        if (
            self.cycle is not None
            and self.cycle.source == "theoretical"
            and self.engine.strokes == 4
            and self.cycle.exhaust_pressure is None
        ):
            raise _FieldError(
                "cycle.exhaust_pressure",
                "missing: a four-stroke theoretical diagram needs "
                "the exhaust pressure p_r (e.g. '0.11 MPa')",
            )
        return self

    def _default_firing_order(self) -> None:
        """A multi-cylinder engine without ``firing_order`` gets the firing-order explorer's top-ranked
        order and crank arrangement (best balance, then the firing rules), when the search is small
        (at most 50 000 arrangements of the cranks); otherwise the layout check asks for one."""
        e = self.engine
        if e.firing_order is not None or e.cylinders == 1 or e.layout == "radial":
            return

        banks = lay.LAYOUT_BANKS.get(e.layout, 1)
        cranks = e.cylinders // banks if e.cylinders % banks == 0 else e.cylinders
        if not fe.small_search(cranks):
            return

        given = e.crank_angles_deg  # a given crank arrangement: the best order that fits it
        try:
            found = fe.explore(
                e.cylinders, e.layout, e.strokes, e.bank_angle_deg, top=1 if given is None else None
            )
        except (lay.LayoutError, ValueError):
            return
        fitting = [row for row in found.rows if given is None or _same_cranks(row, given)]
        if not fitting:
            return
        best = fitting[0]
        update = {"firing_order": list(best.firing_order)}
        if e.crank_angles_deg is None:
            update["crank_angles_deg"] = list(best.crank_angles_deg)
        new = e.model_copy(update=update)
        object.__setattr__(new, "__pydantic_fields_set__", set(e.model_fields_set))
        object.__setattr__(self, "engine", new)

    @property
    def firing_order_chosen(self) -> bool:
        """True when the scene named no firing order and the explorer's top-ranked one was taken."""
        return (
            self.engine.cylinders > 1
            and "firing_order" not in self.engine.model_fields_set
            and self.engine.layout != "radial"
            and self.engine.firing_order is not None
        )

    def _default_steps(self, target_deg: float = DEFAULT_ANGLE_STEP_TARGET_DEG) -> None:
        """Fill in the angle and table steps the scene leaves out (the scene stays frozen to the user).

        Angle step: the largest step grid/k on the engine's grid (:attr:`engine_grid_deg`) not above
        ``target_deg`` (kept within 0.01-30 deg): 1 deg, or what the plugins ask for
        (:meth:`with_plugin_defaults`); the grid is narrowed to also divide the table step (10 deg
        unless given), so every table row is a whole crank angle.
        Table step for a step the scene gives: 10 deg when the step divides it, else the whole
        multiple of the step nearest 10 deg.
        """
        a = self.analysis
        given = set(a.model_fields_set)
        step = a.angle_step_deg if "angle_step_deg" in given else None
        if step is not None:
            # A step printed to 12 digits (e.g. 720/714 deg, as a refusal suggests it) is snapped
            # onto the exact divisor of the cycle it stands for.
            n = self.engine.cycle_deg / step
            if abs(n - round(n)) <= 1e-6 and round(n) >= 1:
                step = self.engine.cycle_deg / round(n)
            if step == a.angle_step_deg and "table_step_deg" in given:
                return

        table = a.table_step_deg if "table_step_deg" in given else None
        if step is None:
            # Tables print whole crank angles: the step divides the table step as well as the
            # firing delays and bank angles (the gcd of the engine's grid and the table step).
            table = DEFAULT_TABLE_STEP_DEG if table is None else table
            grid = lay.grid_deg(self.engine.cycle_deg, [self.engine_grid_deg, table])
            step = step_on_grid_deg(grid, min(30.0, max(0.01, target_deg)))
        elif table is None:
            ratio = DEFAULT_TABLE_STEP_DEG / step
            if abs(ratio - round(ratio)) <= 1e-9:
                table = DEFAULT_TABLE_STEP_DEG
            else:
                table = step * max(1, round(ratio)) if step <= DEFAULT_TABLE_STEP_DEG else step
        new = a.model_copy(update={"angle_step_deg": step, "table_step_deg": table})
        object.__setattr__(new, "__pydantic_fields_set__", given)
        object.__setattr__(self, "analysis", new)

    @property
    def engine_grid_deg(self) -> float:
        """The largest angle dividing the cycle, every firing delay and bank angle (deg); the cycle
        when the layout is invalid (its check reports that)."""
        e = self.engine
        try:
            layout = lay.build_layout(
                e.layout,
                e.strokes,
                e.cylinders,
                e.bank_angle_deg,
                e.firing_order,
                e.crank_angles_deg,
                e.rod_type,
                e.uneven_firing,
            )
        except (lay.LayoutError, ValueError):
            return e.cycle_deg
        return lay.layout_grid_deg(layout)

    def fields_not_used(self) -> frozenset[str]:
        """The dotted names of the core values this scene's engine and cycle do not use, given
        or not: a two-stroke's valve timing, a measured trace's rounding and pre-expansion, a
        theoretical cycle's trace settings, a spark-ignition engine's pre-expansion (ρ = 1) and
        ignition delay in time (its delay angle is a share of the advance)."""
        c = self.cycle
        if c is None:
            return frozenset()
        unused = set(FOUR_STROKE_ONLY_FIELDS) if self.engine.strokes == 2 else set()
        if c.source == "trace":
            unused |= {"cycle.pre_expansion_ratio"}
            unused |= {f"cycle.rounding.{name}" for name in Rounding.model_fields}
        else:
            unused.add("cycle.trace_firing_tdc_deg")
            if c.ignition == "spark":
                unused.add("cycle.pre_expansion_ratio")
            # the delay in time gives a diesel's delay angle, when the angle is not given; a
            # spark's is a share of its advance
            if c.ignition == "spark" or c.rounding.combustion_delay_deg is not None:
                unused.add("cycle.rounding.combustion_delay_time")
        return frozenset(unused)

    @property
    def angle_step_defaulted(self) -> bool:
        """True when the scene left out analysis.angle_step_deg and the default was chosen."""
        return "angle_step_deg" not in self.analysis.model_fields_set

    # Derived values used by many stages.
    @property
    def crank_angles_deg(self):
        n = round(self.engine.cycle_deg / self.analysis.angle_step_deg)
        return np.arange(n) * self.analysis.angle_step_deg

    @property
    def rod_cm_from_big_end_m(self) -> float:
        m = self.masses
        if m.rod_cm_from_big_end is not None:
            return m.rod_cm_from_big_end
        return m.rod_cm_fraction * self.engine.rod_length_m

    def resolve(self, name: str) -> Path:
        """The data file ``name`` (relative to the scene's folder); SceneError if it lies outside
        the scene's folder and every ``--data-dir``."""
        reason = self.data_file_problem(name, must_exist=False)
        if reason:
            raise SceneError(Problem("file", name, reason))
        return (Path(self.base_dir) / name).resolve()

    def data_file_problem(self, name: str, must_exist: bool = True) -> str | None:
        """Why ``name`` may not be read as a data file, or None."""
        return data_file_problem(name, self.base_dir, self.data_dirs, must_exist)

    def plugin_tables(self) -> dict[str, Any]:
        """The top-level tables that belong to plugins (not part of the core model)."""
        return dict(self.model_extra or {})

    def with_plugin_defaults(self, registry: Any) -> Scene:
        """This scene with the defaults the plugins of ``registry`` declare (a
        :class:`crankdyn.plugin.registry.Registry`; None: none): ``engine.mechanism``, when the
        scene names none, is ``registry.default_mechanism``; the angle step, when the scene gives
        none, is chosen for ``registry.default_angle_step_deg(scene)`` (1 deg when no plugin asks).
        The fields filled in stay "not given" (``crankdyn check`` lists the mechanism among the
        defaults applied). The scene itself when there is nothing to fill in."""
        scene = self
        default = getattr(registry, "default_mechanism", None)
        if scene.engine.mechanism is None and default is not None:
            engine = scene.engine.model_copy(update={"mechanism": default})
            object.__setattr__(
                engine, "__pydantic_fields_set__", set(scene.engine.model_fields_set)
            )
            scene = scene.model_copy(update={"engine": engine})
        wish = getattr(registry, "default_angle_step_deg", None)
        if scene.angle_step_defaulted and wish is not None:
            asked = wish(scene)
            target = DEFAULT_ANGLE_STEP_TARGET_DEG if asked is None else asked
            if target != scene._angle_step_target_deg:
                scene = scene.model_copy()
                scene._default_steps(target)
                scene._angle_step_target_deg = target
        return scene


def options(scene: Scene, table: str, model: type[BaseModel], data: dict | None = None):
    """Validate the plugin table ``[table]`` of ``scene`` with ``model``; errors name ``table.<field>``."""
    raw = (
        data
        if data is not None
        else (scene.mechanism if table == "mechanism" else scene.plugin_tables().get(table, {}))
    )
    if not isinstance(raw, dict):
        raise SceneError(Problem(table, raw, "must be a table ([" + table + "])"))
    try:
        return model.model_validate(raw)
    except ValidationError as exc:
        problems = _problems(exc, raw, model)
        raise SceneError(
            [
                Problem(f"{table}.{p.field}" if p.field != "scene" else table, p.value, p.allowed)
                for p in problems
            ]
        ) from None


# --------------------------------------------------------------------------- loading

#: Bytes of a scene file: a scene is a page of text; a larger file is not a scene.
MAX_SCENE_BYTES = 1_000_000


def parse_scene_text(text: str, source: str) -> dict:
    """The tables of a scene's TOML ``text`` (a leading BOM is allowed); SceneError naming
    ``source``."""
    if len(text) > MAX_SCENE_BYTES:
        raise SceneError(
            Problem(
                "scene",
                source,
                f"a scene may be at most {MAX_SCENE_BYTES} characters long (it has {len(text)})",
            ),
            source,
        )
    try:
        return tomllib.loads(text.removeprefix("\ufeff"), parse_float=toml_float)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(Problem("scene", source, f"not valid TOML: {exc}"), source) from None
    except RecursionError:
        raise SceneError(
            Problem("scene", source, "tables and arrays nested too deeply"), source
        ) from None
    except ValueError:  # an integer of thousands of digits (Python refuses to convert it)
        raise SceneError(
            Problem(
                "scene",
                source,
                "an integer must lie between -2^63 and 2^63 - 1 "
                "(64 bits, as TOML defines integers)",
            ),
            source,
        ) from None


def read_scene_data(path: str | Path) -> dict:
    """The tables of the scene file at ``path`` (UTF-8, a BOM allowed); SceneError if it
    cannot be read."""
    path = Path(path)
    source = str(path)
    try:
        status = path.stat()
        if stat.S_ISDIR(status.st_mode):
            raise IsADirectoryError
        if not stat.S_ISREG(status.st_mode):  # a pipe or a device: reading it may never end
            raise SceneError(Problem("scene", source, "not a regular file"), source)
        size = status.st_size
        if size > MAX_SCENE_BYTES:
            raise SceneError(
                Problem(
                    "scene",
                    source,
                    f"a scene file may be at most {MAX_SCENE_BYTES} bytes (it has {size})",
                ),
                source,
            )
        with path.open("rb") as handle:
            raw = handle.read(MAX_SCENE_BYTES + 1)  # a file growing meanwhile is read no further
        text = raw.decode("utf-8-sig")  # Windows Notepad saves a BOM
    except FileNotFoundError:
        raise SceneError(Problem("scene", source, "file not found"), source) from None
    except (OSError, UnicodeDecodeError) as exc:
        reason = f"cannot read the file ({exc.__class__.__name__})"
        raise SceneError(Problem("scene", source, reason), source) from None
    except ValueError:  # a NUL character in the name
        raise SceneError(Problem("scene", source, "not a file name"), source) from None
    return parse_scene_text(text, source)


def load_scene(
    path: str | Path,
    overrides: dict | None = None,
    data_dirs: tuple[str, ...] = (),
    registry: Any = None,
) -> Scene:
    """Read, validate and return the scene at ``path``; raise SceneError listing every problem.

    ``registry`` (a :class:`crankdyn.plugin.registry.Registry`): the plugins the scene is read
    for; its default mechanism is the scene's when the scene names none."""
    path = Path(path)
    source = str(path)
    data = read_scene_data(path)
    if overrides:
        data = merge(data, overrides)
    return scene_from_dict(
        data,
        base_dir=path.parent.resolve(),
        source=source,
        data_dirs=data_dirs,
        registry=registry,
    )


def merge(base: dict, overrides: dict) -> dict:
    """Return ``base`` with ``overrides`` (nested dicts) laid over it."""
    out = dict(base)
    for key, value in overrides.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merge(out[key], value)
        else:
            out[key] = value
    return out


def scene_from_dict(
    data: dict,
    base_dir: Path | str = ".",
    source: str | None = None,
    data_dirs: tuple[str, ...] = (),
    registry: Any = None,
) -> Scene:
    """The scene of the tables ``data``; SceneError listing every problem. ``registry``: as for
    :func:`load_scene`."""
    for key in ("base_dir", "data_dirs"):
        if key in data:
            raise SceneError(
                Problem(key, data[key], "unknown key (set by the loader, not the scene)"), source
            )

    problems = structure_problems(data)
    if problems:
        raise SceneError(problems, source)
    hints = table_problems(data)
    try:
        scene = Scene.model_validate(
            {
                **data,
                "base_dir": str(base_dir),
                "data_dirs": tuple(str(Path(d).resolve()) for d in data_dirs),
            }
        )
    except ValidationError as exc:
        named = {h.field for h in hints}
        raise SceneError(
            hints + [p for p in _problems(exc, data) if p.field not in named], source
        ) from None
    return scene.with_plugin_defaults(registry)


def _problems(
    exc: ValidationError, data: dict, root: type[BaseModel] | None = None
) -> list[Problem]:
    problems = []
    for error in exc.errors():
        loc = [
            str(p)
            for p in error["loc"]
            if not str(p).startswith(("function-", "literal[", "nullable["))
        ]
        # pydantic puts union members in the location ("float", "none"...); they mean nothing to a user.
        loc = [p for p in loc if p not in {"float", "none", "int", "str", "constrained-float"}]
        ctx_error = (error.get("ctx") or {}).get("error")
        if isinstance(ctx_error, _FieldError):
            loc = loc + ctx_error.field.split(".")
        field = ".".join(loc) or "scene"
        value = _lookup(data, loc)
        kind = error["type"]
        if kind == "extra_forbidden":
            parent = loc[:-1]
            model = _model_at(parent, root or Scene)
            allowed = sorted(model.model_fields) if model else []
            allowed = [a for a in allowed if a not in ("base_dir", "data_dirs")]
            close = difflib.get_close_matches(loc[-1], allowed, n=1)
            hint = f"did you mean '{close[0]}'? " if close else ""
            problems.append(
                Problem(field, value, f"unknown key; {hint}allowed keys: {', '.join(allowed)}")
            )
        elif kind == "missing":
            problems.append(Problem(field, MISSING, "required value is missing"))
        elif kind == "literal_error":
            problems.append(Problem(field, value, "allowed values: " + error["ctx"]["expected"]))
        elif kind in ("value_error", "assertion_error"):
            message = str(ctx_error) if ctx_error is not None else error["msg"]
            problems.append(Problem(field, value, message))
        else:
            problems.append(Problem(field, value, error["msg"][0].lower() + error["msg"][1:]))
    # One problem per field: union members can report the same mistake twice.
    unique, seen = [], set()
    for p in problems:
        if p.field not in seen:
            unique.append(p)
            seen.add(p.field)
    return unique


def _lookup(data: Any, loc: list[str]) -> Any:
    for key in loc:
        if isinstance(data, dict) and key in data:
            data = data[key]
        elif isinstance(data, list) and key.isdigit() and int(key) < len(data):
            data = data[int(key)]
        else:
            return MISSING
    return data


def _model_at(loc: list[str], root: type[BaseModel]):
    model: Any = root
    for key in loc:
        field = model.model_fields.get(key) if model else None
        if field is None:
            return None
        annotation = field.annotation
        candidates = getattr(annotation, "__args__", (annotation,))
        model = next(
            (c for c in candidates if isinstance(c, type) and issubclass(c, BaseModel)), None
        )
    return model
