"""Indicator diagram of a piston engine: theoretical cycle, rounding, work.

Pure numerical functions over numpy arrays.  Units are SI (Pa, m^3, J);
crank angles are in degrees where the name says ``_deg``, measured from TDC
in the direction of rotation.

Angle conventions
-----------------
Four-stroke cycle, ``crank_angle_deg`` in [0, 720):
0 = TDC at the start of intake, 180 = BDC (end of intake, start of
compression), 360 = firing TDC, 540 = BDC (end of expansion), 720 = TDC at
the end of exhaust.

Two-stroke cycle, ``crank_angle_deg`` in [0, 360):
0 = firing TDC, 180 = BDC, 360 = TDC.  The textbook starts the two-stroke
table at BDC; here zero is TDC for both cycles.  A port-scavenged two-stroke
opens its exhaust ports phi_b before BDC (point b) and closes them as
far after it (point a'): the lost stroke fraction psi of the stroke is spent
on gas exchange, compression starts at a' and expansion ends at b
(Kolchin and Demidov; Blair 1996, ch. 1).

Method source: V.B. Poda, *Dynamic calculation and balancing of piston
ICEs*, KhAI 2007, section 3.1 (equations 12-16) and Appendix V (valve
timing).  Equations marked "derived" were derived for this module.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .hermite import hermite_cubic

__all__ = [
    "clearance_volume_m3",
    "cylinder_volume_m3",
    "isobar_peak_angle_deg",
    "lost_stroke_fraction",
    "CycleParameters",
    "actual_compression_ratio",
    "port_closing_volume_m3",
    "port_closing_deg",
    "BLOWDOWN_FRACTION",
    "PORT_CLOSING_ROUNDING_FRACTION",
    "compression_end_pressure_Pa",
    "expansion_end_pressure_Pa",
    "pressure_ratio",
    "theoretical_pressure_Pa",
    "theoretical_mean_indicated_pressure_Pa",
    "RoundingParameters",
    "default_combustion_delay_deg",
    "rounded_pressure_Pa",
    "combustion_junctions_deg",
    "indicated_work_J",
    "pumping_work_J",
    "mean_indicated_pressure_Pa",
    "crank_angle_from_volume_approx_deg",
    "crank_angle_from_volume_exact_deg",
]

# Step of the internal (caller-independent) angle grid used to locate the
# junction J between the combustion rounding and the expansion line, deg.
_JUNCTION_SEARCH_STEP_DEG = 0.01
# Tolerance of the junction angle, deg.
_JUNCTION_TOLERANCE_DEG = 1e-10
_JUNCTION_REFINE_POINTS = 64  # points per refinement of the junction's bracket
_JUNCTION_SCAN_CHUNK = 1000  # grid points tested at a time when looking for the junction (10 deg)
_JUNCTION_MANY_FIRST_CHUNK = 200  # the first part of the grid tested for many diagrams at once
# Largest cyclic gap of the caller's grid from which the cylinder volume may
# be reconstructed by a periodic spline (the textbook table step is 10-15 deg).
_MAX_VOLUME_GRID_STEP_DEG = 15.0
# Relative tolerance for volumes at the ends of their physical range.
_VOLUME_RTOL = 1e-9


# ---------------------------------------------------------------------------
# Volumes
# ---------------------------------------------------------------------------
def clearance_volume_m3(swept_volume_m3, compression_ratio):
    """Clearance (combustion-chamber) volume from swept volume and compression ratio.

    Parameters
    ----------
    swept_volume_m3 : float or array_like
        Swept (displacement) volume of one cylinder V_h, m^3, > 0: the full
        stroke's, also for a port-scavenged two-stroke.
    compression_ratio : float or array_like
        Geometric compression ratio epsilon = (V_c + V_h)/V_c, > 1 (for a
        two-stroke the actual ratio from the port closing is
        :func:`actual_compression_ratio`).

    Returns
    -------
    numpy.ndarray or float
        Clearance volume V_c = V_h / (epsilon - 1), m^3.

    Raises
    ------
    ValueError
        If ``swept_volume_m3`` <= 0 or ``compression_ratio`` <= 1.

    Notes
    -----
    Poda (2007), eq. (14).
    """
    swept = np.asarray(swept_volume_m3, dtype=float)
    ratio = np.asarray(compression_ratio, dtype=float)
    _require(np.all(swept > 0), "swept_volume_m3", swept_volume_m3, "> 0")
    _require(np.all(ratio > 1), "compression_ratio", compression_ratio, "> 1")
    return swept / (ratio - 1.0)


def cylinder_volume_m3(piston_displacement_m, piston_area_m2, clearance_volume_m3):
    """Instantaneous cylinder volume from the piston displacement.

    Parameters
    ----------
    piston_displacement_m : float or array_like
        Piston displacement from TDC s, m, >= 0.
    piston_area_m2 : float
        Piston crown area F = pi D^2 / 4, m^2, > 0.
    clearance_volume_m3 : float
        Clearance volume V_c, m^3, > 0.

    Returns
    -------
    numpy.ndarray or float
        Cylinder volume V = V_c + F s, m^3.

    Raises
    ------
    ValueError
        If the area or the clearance volume is not positive, or a
        displacement is negative.

    Notes
    -----
    Geometry of the cylinder (V_a = V_c + V_h, Poda 2007 eq. (15), is the
    special case s = S).
    """
    displacement = np.asarray(piston_displacement_m, dtype=float)
    _require(piston_area_m2 > 0, "piston_area_m2", piston_area_m2, "> 0")
    _require(clearance_volume_m3 > 0, "clearance_volume_m3", clearance_volume_m3, "> 0")
    _require(
        np.all(displacement >= 0),
        "piston_displacement_m",
        _worst(displacement, displacement < 0),
        ">= 0",
    )
    return clearance_volume_m3 + piston_area_m2 * displacement


def lost_stroke_fraction(exhaust_opens_before_bdc_deg, rod_ratio):
    """Lost stroke fraction psi of a port-scavenged two-stroke engine.

    Parameters
    ----------
    exhaust_opens_before_bdc_deg : float or array_like
        Exhaust port opening phi_b before BDC, deg, in [0, 180).
    rod_ratio : float
        lambda = R / L of the central crank-slider, in (0, 1).

    Returns
    -------
    numpy.ndarray or float
        psi = 1 - s_b / S, dimensionless, in [0, 1): the part of the stroke
        during which the exhaust ports are open.  s_b is the piston travel
        from TDC to the port edge, at alpha_b = 180 - phi_b, S = 2R.

    Raises
    ------
    ValueError
        If the angle is outside [0, 180) or the rod ratio outside (0, 1).

    Notes
    -----
    Kolchin and Demidov (two-stroke thermal calculation: psi is the stroke
    lost to the exhaust ports); Blair (1996), ch. 1 (port timing).  The
    displacement is the exact crank-slider one,
    s = R[(1 - cos alpha) + (1 - cos beta)/lambda], sin beta = lambda sin alpha,
    evaluated as R[2 sin^2(alpha/2) + lambda sin^2 alpha / (1 + cos beta)].
    The ports close where the piston covers them again, symmetrically at
    180 + phi_b.
    """
    phi = np.asarray(exhaust_opens_before_bdc_deg, dtype=float)
    _require(
        np.all(np.isfinite(phi) & (phi >= 0) & (phi < 180)),
        "exhaust_opens_before_bdc_deg",
        exhaust_opens_before_bdc_deg,
        "[0, 180) deg",
    )
    _require(np.isfinite(rod_ratio) and 0 < rod_ratio < 1, "rod_ratio", rod_ratio, "(0, 1)")
    alpha = np.radians(180.0 - phi)
    sin_a = np.sin(alpha)
    cos_b = np.sqrt(1.0 - (rod_ratio * sin_a) ** 2)
    s_over_r = 2.0 * np.sin(0.5 * alpha) ** 2 + rod_ratio * sin_a**2 / (1.0 + cos_b)
    psi = 1.0 - 0.5 * s_over_r
    return psi if np.ndim(psi) else float(psi)


# ---------------------------------------------------------------------------
# Cycle parameters
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class CycleParameters:
    """Parameters of the theoretical cycle from the thermal calculation (SI).

    Attributes
    ----------
    strokes : int
        2 or 4.
    ignition : str
        ``"spark"`` (constant-volume heat addition) or ``"diesel"`` (mixed
        cycle: constant volume, then constant pressure).
    compression_ratio : float
        Geometric compression ratio epsilon = V_a / V_c = (V_c + V_h)/V_c, > 1.
    intake_pressure_Pa : float
        p_a, absolute pressure at the start of compression, Pa, > 0.  Also
        the intake-line pressure of a four-stroke diagram and the scavenging
        pressure of a two-stroke one while its ports are open.
    compression_index : float
        Polytropic index of compression n1, > 1.
    max_pressure_Pa : float
        Theoretical maximum cycle pressure p_z, Pa; must exceed the
        compression-end pressure p_c = p_a epsilon^n1.
    pre_expansion_ratio : float
        rho = V_z / V_c.  Exactly 1.0 for spark ignition; 1 <= rho < epsilon
        for a diesel.
    expansion_index : float
        Polytropic index of expansion n2, > 1.
    exhaust_pressure_Pa : float or None
        p_r, absolute pressure of the exhaust stroke, Pa, > 0.  Required for
        a four-stroke cycle, ignored (may be None) for a two-stroke cycle.
    bdc_deg : float, default 180
        Crank angle of BDC after each TDC, deg, in (0, 360): the points a and
        b of the diagram and the exhaust drop lie there.  180 for the central
        crank-slider; an offset crank-slider reaches BDC later (its stroke
        from TDC to BDC takes more than half a turn).
    lost_stroke_fraction : float, default 0
        Two-stroke only: psi, the part of the stroke during which the
        exhaust ports are open (:func:`lost_stroke_fraction`), in [0, 1).
        Compression starts at the port closing a' and expansion ends at the
        port opening b, both at V_a' = V_c + (1 - psi) V_h; 0 keeps the
        whole stroke (gas exchange at BDC).
    """

    strokes: int
    ignition: str
    compression_ratio: float
    intake_pressure_Pa: float
    compression_index: float
    max_pressure_Pa: float
    pre_expansion_ratio: float
    expansion_index: float
    exhaust_pressure_Pa: float | None = None
    bdc_deg: float = 180.0
    lost_stroke_fraction: float = 0.0

    def __post_init__(self):
        _require(self.strokes in (2, 4), "strokes", self.strokes, "2 or 4")
        psi = self.lost_stroke_fraction
        _require(
            np.isfinite(psi) and 0.0 <= psi < 1.0 and (psi == 0.0 or self.strokes == 2),
            "lost_stroke_fraction",
            psi,
            "[0, 1) for a two-stroke cycle, 0 for a four-stroke one",
        )
        _require(
            np.isfinite(self.bdc_deg) and 0.0 < self.bdc_deg < 360.0,
            "bdc_deg",
            self.bdc_deg,
            "(0, 360) deg after TDC",
        )
        _require(
            self.ignition in ("spark", "diesel"), "ignition", self.ignition, "'spark' or 'diesel'"
        )
        _require(
            np.isfinite(self.compression_ratio) and self.compression_ratio > 1,
            "compression_ratio",
            self.compression_ratio,
            "> 1",
        )
        _require(
            np.isfinite(self.intake_pressure_Pa) and self.intake_pressure_Pa > 0,
            "intake_pressure_Pa",
            self.intake_pressure_Pa,
            "> 0 (absolute)",
        )
        _require(
            np.isfinite(self.compression_index) and self.compression_index > 1,
            "compression_index",
            self.compression_index,
            "> 1",
        )
        _require(
            np.isfinite(self.expansion_index) and self.expansion_index > 1,
            "expansion_index",
            self.expansion_index,
            "> 1",
        )
        if self.ignition == "spark":
            _require(
                self.pre_expansion_ratio == 1.0,
                "pre_expansion_ratio",
                self.pre_expansion_ratio,
                "exactly 1.0 for spark ignition",
            )
        else:
            eps = actual_compression_ratio(self)
            _require(
                1.0 <= self.pre_expansion_ratio < eps,
                "pre_expansion_ratio",
                self.pre_expansion_ratio,
                f"[1, compression_ratio={eps:.6g}) for a diesel"
                if eps == self.compression_ratio
                else f"[1, {eps:.6g}) for a diesel: the actual compression ratio from the "
                "exhaust ports' closing (lost_stroke_fraction = "
                f"{self.lost_stroke_fraction:.4g})",
            )
        p_c = compression_end_pressure_Pa(self)
        _require(
            np.isfinite(self.max_pressure_Pa) and self.max_pressure_Pa > p_c,
            "max_pressure_Pa",
            self.max_pressure_Pa,
            f"> compression-end pressure p_a*eps^n1 = {p_c:.6g} Pa",
        )
        if self.strokes == 4:
            _require(
                self.exhaust_pressure_Pa is not None
                and np.isfinite(self.exhaust_pressure_Pa)
                and self.exhaust_pressure_Pa > 0,
                "exhaust_pressure_Pa",
                self.exhaust_pressure_Pa,
                "> 0 (absolute) for a four-stroke cycle",
            )


def actual_compression_ratio(params):
    """Compression ratio from the start of compression.

    Parameters
    ----------
    params : CycleParameters

    Returns
    -------
    float
        epsilon_d = V_a' / V_c = 1 + (1 - psi)(epsilon - 1), dimensionless:
        the geometric epsilon itself when psi = 0 (a four-stroke cycle, or a
        two-stroke one without ports).

    Notes
    -----
    Kolchin and Demidov (two-stroke engines: the actual compression ratio
    from the closing of the exhaust ports); V_a' = V_c + (1 - psi) V_h with
    V_h = (epsilon - 1) V_c.
    """
    psi = params.lost_stroke_fraction
    return _actual_ratio(params.compression_ratio, psi)


def _actual_ratio(eps, psi):
    """1 + (1 - psi)(eps - 1), exactly eps where psi = 0 (scalars or columns)."""
    if np.ndim(psi) == 0 and psi == 0.0:
        return eps
    return np.where(psi == 0.0, eps, 1.0 + (1.0 - psi) * (eps - 1.0))


def port_closing_volume_m3(clearance_volume_m3, params):
    """Cylinder volume at the start of compression and the end of expansion.

    Parameters
    ----------
    clearance_volume_m3 : float
        V_c, m^3, > 0.
    params : CycleParameters

    Returns
    -------
    float
        V_a' = epsilon_d V_c = V_c + (1 - psi) V_h, m^3: the port closing a'
        and opening b of a two-stroke, V_a = V_c + V_h otherwise.

    Notes
    -----
    Kolchin and Demidov; :func:`actual_compression_ratio`.
    """
    return actual_compression_ratio(params) * clearance_volume_m3


def compression_end_pressure_Pa(params):
    """Pressure at the end of polytropic compression.

    Parameters
    ----------
    params : CycleParameters

    Returns
    -------
    float
        p_c = p_a epsilon_d^n1, Pa; epsilon_d = epsilon unless a two-stroke's
        ports take the lost stroke fraction psi
        (:func:`actual_compression_ratio`).

    Notes
    -----
    Poda (2007) eq. (12) evaluated at V = V_c; Kolchin and Demidov for the
    compression from the port closing a'.
    """
    return params.intake_pressure_Pa * actual_compression_ratio(params) ** params.compression_index


def expansion_end_pressure_Pa(params):
    """Pressure at the end of polytropic expansion (at V_a).

    Parameters
    ----------
    params : CycleParameters

    Returns
    -------
    float
        p_b = p_z (rho / epsilon_d)^n2, Pa (rho = 1 for spark ignition;
        epsilon_d = epsilon unless a two-stroke's ports open at V_a').

    Notes
    -----
    Derived from the expansion polytrope p V^n2 = const started at
    V_z = rho V_c with p_z and ended at V_a = epsilon V_c (a two-stroke's at
    the exhaust port opening b, V_b = V_a' for symmetric ports); consistent
    with Poda (2007) eq. (13) and Kolchin and Demidov.
    """
    return (
        params.max_pressure_Pa
        * (params.pre_expansion_ratio / actual_compression_ratio(params)) ** params.expansion_index
    )


def pressure_ratio(params):
    """Pressure-rise ratio of the heat addition at constant volume.

    Parameters
    ----------
    params : CycleParameters

    Returns
    -------
    float
        lambda_p = p_z / p_c, dimensionless (> 1).

    Notes
    -----
    Definition from the thermal calculation.
    """
    return params.max_pressure_Pa / compression_end_pressure_Pa(params)


# ---------------------------------------------------------------------------
# Theoretical diagram
# ---------------------------------------------------------------------------
def _start_volume_m3(clearance_m3, params):
    """V_a' = epsilon_d V_c (V_a where psi = 0); params may hold columns."""
    psi = getattr(params, "lost_stroke_fraction", 0.0)
    return _actual_ratio(params.compression_ratio, psi) * clearance_m3


def _compression_line_Pa(volume_m3, clearance_m3, params):
    """p_a (V_a' / V)^n1 with V capped at V_a' (eq. 12)."""
    v_a = _start_volume_m3(clearance_m3, params)
    v = np.minimum(volume_m3, v_a)
    return params.intake_pressure_Pa * (v_a / v) ** params.compression_index


def _compression_slope_Pa_per_deg(volume_m3, dvolume_m3_per_deg, clearance_m3, params):
    """d/dalpha of the compression line, Pa/deg."""
    v_a = _start_volume_m3(clearance_m3, params)
    p = _compression_line_Pa(volume_m3, clearance_m3, params)
    dp_dv = np.where(volume_m3 < v_a, -params.compression_index * p / volume_m3, 0.0)
    return dp_dv * dvolume_m3_per_deg


def _expansion_line_Pa(volume_m3, clearance_m3, params):
    """min(p_z, p_z (rho V_c / V)^n2) with V capped at V_a' (eq. 13)."""
    v_a = _start_volume_m3(clearance_m3, params)
    v = np.minimum(volume_m3, v_a)
    ratio = params.pre_expansion_ratio * clearance_m3 / v
    return params.max_pressure_Pa * np.minimum(1.0, ratio) ** params.expansion_index


def _expansion_slope_Pa_per_deg(volume_m3, dvolume_m3_per_deg, clearance_m3, params):
    """d/dalpha of the expansion line (zero on the isobar), Pa/deg."""
    v_a = _start_volume_m3(clearance_m3, params)
    v_z = params.pre_expansion_ratio * clearance_m3
    p = _expansion_line_Pa(volume_m3, clearance_m3, params)
    on_polytrope = (volume_m3 > v_z) & (volume_m3 < v_a)
    dp_dv = np.where(on_polytrope, -params.expansion_index * p / volume_m3, 0.0)
    return dp_dv * dvolume_m3_per_deg


def _cycle_deg(params):
    return 720.0 if params.strokes == 4 else 360.0


def _firing_tdc_deg(params):
    return 360.0 if params.strokes == 4 else 0.0


def _check_volumes(volume, clearance_volume_m3, params):
    _require(
        np.isfinite(clearance_volume_m3) and clearance_volume_m3 > 0,
        "clearance_volume_m3",
        clearance_volume_m3,
        "> 0",
    )
    _require(np.all(np.isfinite(volume)), "volume_m3", "non-finite values", "finite values")
    low = clearance_volume_m3 * (1.0 - _VOLUME_RTOL)
    _require(
        np.all(volume >= low),
        "volume_m3",
        _worst(volume, volume < low),
        f">= clearance_volume_m3 = {clearance_volume_m3:.6g} m^3",
    )


def theoretical_pressure_Pa(crank_angle_deg, volume_m3, clearance_volume_m3, params):
    """Theoretical (sharp-cornered) indicator diagram on a crank-angle grid.

    Parameters
    ----------
    crank_angle_deg : array_like
        Crank angle alpha, deg, from TDC at the start of intake (four-stroke)
        or from firing TDC (two-stroke).  Reduced modulo the cycle length
        (720 or 360 deg).
    volume_m3 : array_like
        Cylinder volume at the same angles, m^3, same shape, >= V_c.
    clearance_volume_m3 : float
        Clearance volume V_c, m^3, > 0.  The full volume used by the
        polytropes is V_a = epsilon V_c.
    params : CycleParameters

    Returns
    -------
    numpy.ndarray
        Absolute cylinder pressure, Pa, same shape as ``crank_angle_deg``.

    Notes
    -----
    Four-stroke:

    * intake, alpha in [0, 180]: p_a;
    * compression, (180, 360): p = p_a (V_a/V)^n1 (eq. 12);
    * firing TDC, alpha = 360: isochoric jump to p_z;
    * expansion, [360, 540]: p = min(p_z, p_z (rho V_c / V)^n2), i.e. the
      diesel isobar p_z up to V = rho V_c followed by the polytrope
      p_b (V_a/V)^n2 (eq. 13); for spark ignition rho = 1;
    * exhaust, (540, 720): p_r (isochoric drop at BDC).

    Two-stroke: expansion on [0, 180] (p_z at 0, with the diesel isobar),
    compression on (180, 360) from p_a; the isochoric jump back to p_z
    happens at 360 = 0.  With ports (psi > 0) expansion ends at the exhaust
    port opening b, V = V_a' = V_c + (1 - psi) V_h, at p_b = p_z (rho V_c /
    V_a')^n2; there the pressure drops at constant volume to the scavenging
    pressure p_a and stays at p_a while V > V_a' (ports open, b -> BDC ->
    a'); compression p_a (V_a'/V)^n1 starts at the port closing a'
    (Kolchin and Demidov; Blair 1996, ch. 1).

    Volumes above V_a' (V_a without ports; otherwise possible only with
    inconsistent geometry) hold the polytropes at p_a / p_b.  With
    consistent geometry the pressure at BDC equals p_a (after intake or with
    ports open) and p_b (after a four-stroke's expansion).
    Poda (2007) eqs. (12)-(15).
    """
    alpha = np.asarray(crank_angle_deg, dtype=float)
    volume = np.asarray(volume_m3, dtype=float)
    _require(
        alpha.shape == volume.shape,
        "volume_m3",
        f"shape {volume.shape}",
        f"the shape of crank_angle_deg {alpha.shape}",
    )
    _require(np.all(np.isfinite(alpha)), "crank_angle_deg", "non-finite values", "finite values")
    _check_volumes(volume, clearance_volume_m3, params)

    cycle = _cycle_deg(params)
    a = np.mod(alpha, cycle)
    p_comp = _compression_line_Pa(volume, clearance_volume_m3, params)
    p_exp = _expansion_line_Pa(volume, clearance_volume_m3, params)
    bdc = params.bdc_deg
    if params.strokes == 4:
        conditions = [a <= bdc, a < 360.0, a <= 360.0 + bdc]
        choices = [np.full_like(a, params.intake_pressure_Pa), p_comp, p_exp]
        return np.select(conditions, choices, default=params.exhaust_pressure_Pa)
    if params.lost_stroke_fraction > 0.0:
        # ports open from b to a' (the volume above V_a'): the scavenging pressure p_a
        v_port = port_closing_volume_m3(clearance_volume_m3, params) * (1.0 + _VOLUME_RTOL)
        p_exp = np.where(volume > v_port, params.intake_pressure_Pa, p_exp)
    return np.where(a <= bdc, p_exp, p_comp)


def theoretical_mean_indicated_pressure_Pa(params):
    """Closed-form mean indicated pressure of the theoretical cycle (unrounded).

    Parameters
    ----------
    params : CycleParameters

    Returns
    -------
    float
        p_i' = (1 - psi) p_c/(eps_d-1) [lambda_p (rho-1) + lambda_p rho/(n2-1)
        (1 - 1/delta^(n2-1)) - 1/(n1-1) (1 - 1/eps_d^(n1-1))], Pa,
        with delta = eps_d/rho; eps_d = eps and psi = 0 unless a two-stroke's
        ports take the lost stroke fraction psi (:func:`actual_compression_ratio`).

    Notes
    -----
    Derived: the work of the closed part of the cycle per unit swept volume,

    * isobar V_c -> rho V_c: p_z (rho - 1) V_c,
    * expansion polytrope rho V_c -> V_a':
      p_z rho V_c / (n2 - 1) [1 - delta^(1-n2)],
    * compression polytrope V_a' -> V_c (negative work):
      p_c V_c / (n1 - 1) [1 - eps_d^(1-n1)],

    divided by the useful stroke's volume V_a' - V_c = (eps_d - 1) V_c gives
    the bracket; Kolchin and Demidov refer the two-stroke's p_i' computed over
    the useful stroke to the whole stroke by the factor (1 - psi), so that
    p_i' = (work of the polytropes) / V_h (V_a' = V_a, psi = 0, in a
    four-stroke cycle).  For spark ignition rho = 1 and the first
    term vanishes.  The gas-exchange (pumping) loop is excluded: the
    four-stroke diagram of :func:`theoretical_pressure_Pa` has, in addition,
    the work (p_a - p_r) V_h of its intake and exhaust lines; the two-stroke's
    scavenging at p_a between b and a' does no net work.
    """
    eps = actual_compression_ratio(params)
    rho = params.pre_expansion_ratio
    n1 = params.compression_index
    n2 = params.expansion_index
    lam = pressure_ratio(params)
    delta = eps / rho
    p_c = compression_end_pressure_Pa(params)
    bracket = (
        lam * (rho - 1.0)
        + lam * rho / (n2 - 1.0) * (1.0 - delta ** (1.0 - n2))
        - 1.0 / (n1 - 1.0) * (1.0 - eps ** (1.0 - n1))
    )
    mean = p_c / (eps - 1.0) * bracket
    if params.lost_stroke_fraction > 0.0:
        mean *= 1.0 - params.lost_stroke_fraction
    return mean


def theoretical_diagram_mean_pressure_Pa(params):
    """Mean pressure of the whole sharp-cornered theoretical diagram, Pa: the closed form
    :func:`theoretical_mean_indicated_pressure_Pa` plus a four-stroke's pumping strokes, the
    intake at p_a and the exhaust at p_r (their loop's mean pressure p_a − p_r; none in a
    two-stroke cycle). The grid integral of :func:`theoretical_pressure_Pa` over the cycle tends
    to it as the step shrinks (a central crank-slider, no exhaust ports)."""
    pumping = params.intake_pressure_Pa - params.exhaust_pressure_Pa if params.strokes == 4 else 0.0
    return theoretical_mean_indicated_pressure_Pa(params) + pumping


# ---------------------------------------------------------------------------
# Rounding
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class RoundingParameters:
    """Angles and pressures that turn the theoretical diagram into an actual one.

    Attributes
    ----------
    ignition_advance_deg : float
        Spark advance (textbook 20-25 deg) or injection advance (10-40 deg)
        before firing TDC (point 3), deg, in (0, 90).
    combustion_delay_deg : float
        Ignition delay 3 -> C' in crank degrees, in [0, ignition_advance_deg);
        see :func:`default_combustion_delay_deg`.
    pressure_rise_to_tdc_Pa : float
        Pressure rise C' -> C'' above the compression-end pressure: the
        actual pressure at firing TDC is p_c + this, Pa, >= 0 (textbook
        0.4-0.6 MPa).
    peak_pressure_fraction : float
        p_z' / p_z, in (0, 1] (textbook 0.8-0.9); where it would put Z' above
        the theoretical diagram, p_z' is lowered (:func:`peak_pressure_Pa`).
    peak_angle_after_tdc_deg : float
        Angle of the actual maximum Z' after firing TDC, deg, in (0, 90)
        (textbook 10-15).
    exhaust_opens_before_bdc_deg : float, default 0
        Exhaust valve / port opening before BDC (b'), deg, in [0, 180);
        0 keeps the sharp drop at BDC.  Typical four-stroke 40-70.
    exhaust_closes_after_tdc_deg : float, default 0
        Four-stroke only: exhaust valve closing after the exhaust TDC, deg,
        in [0, 180).  Typical 10-30.
    intake_opens_before_tdc_deg : float, default 0
        Four-stroke only: intake valve opening before the exhaust TDC, deg,
        in [0, 180).  Typical 10-30.
    intake_closes_after_bdc_deg : float, default 0
        Four-stroke only: intake valve closing after BDC, deg, in [0, 180).
        Typical 40-80.  Validated and kept for valve-timing output; it does
        not change the diagram because the compression line already leaves
        the intake line with zero slope at BDC.

    Notes
    -----
    Poda (2007) section 3.1 and Appendix V (valve timing alpha_1...alpha_4).
    """

    ignition_advance_deg: float
    combustion_delay_deg: float
    pressure_rise_to_tdc_Pa: float
    peak_pressure_fraction: float
    peak_angle_after_tdc_deg: float
    exhaust_opens_before_bdc_deg: float = 0.0
    exhaust_closes_after_tdc_deg: float = 0.0
    intake_opens_before_tdc_deg: float = 0.0
    intake_closes_after_bdc_deg: float = 0.0

    def __post_init__(self):
        adv = self.ignition_advance_deg
        _require(np.isfinite(adv) and 0 < adv < 90, "ignition_advance_deg", adv, "(0, 90) deg")
        delay = self.combustion_delay_deg
        _require(
            np.isfinite(delay) and 0 <= delay < adv,
            "combustion_delay_deg",
            delay,
            f"[0, ignition_advance_deg={adv}) deg so that C' lies before firing TDC",
        )
        _require(
            np.isfinite(self.pressure_rise_to_tdc_Pa) and self.pressure_rise_to_tdc_Pa >= 0,
            "pressure_rise_to_tdc_Pa",
            self.pressure_rise_to_tdc_Pa,
            ">= 0 Pa",
        )
        _require(
            0 < self.peak_pressure_fraction <= 1,
            "peak_pressure_fraction",
            self.peak_pressure_fraction,
            "(0, 1]",
        )
        _require(
            0 < self.peak_angle_after_tdc_deg < 90,
            "peak_angle_after_tdc_deg",
            self.peak_angle_after_tdc_deg,
            "(0, 90) deg",
        )
        for name in (
            "exhaust_opens_before_bdc_deg",
            "exhaust_closes_after_tdc_deg",
            "intake_opens_before_tdc_deg",
            "intake_closes_after_bdc_deg",
        ):
            value = getattr(self, name)
            _require(np.isfinite(value) and 0 <= value < 180, name, value, "[0, 180) deg")


def default_combustion_delay_deg(ignition, advance_deg, rpm, delay_time_s=1.5e-3):
    """Textbook estimate of the ignition delay 3 -> C' in crank degrees.

    Parameters
    ----------
    ignition : str
        ``"spark"`` or ``"diesel"``.
    advance_deg : float
        Spark or injection advance, deg, > 0.
    rpm : float
        Crankshaft speed n, rev/min, > 0 (used for diesels only).
    delay_time_s : float, default 1.5e-3
        Diesel ignition delay time tau, s, > 0 (textbook 1.2e-3...2.0e-3).

    Returns
    -------
    float
        Delay, deg: 0.11 * advance_deg for spark ignition (textbook
        0.10...0.12), 6 n tau for a diesel.

    Notes
    -----
    Poda (2007) section 3.1; 6 n tau converts a time to crank degrees
    (360 deg/rev * n/60 rev/s).
    """
    _require(ignition in ("spark", "diesel"), "ignition", ignition, "'spark' or 'diesel'")
    _require(np.isfinite(advance_deg) and advance_deg > 0, "advance_deg", advance_deg, "> 0 deg")
    _require(np.isfinite(rpm) and rpm > 0, "rpm", rpm, "> 0 rev/min")
    _require(np.isfinite(delay_time_s) and delay_time_s > 0, "delay_time_s", delay_time_s, "> 0 s")
    if ignition == "spark":
        return 0.11 * advance_deg
    return 6.0 * rpm * delay_time_s


def _hermite_is_monotone(slope_start, slope_end, secant):
    """Fritsch-Carlson (1980) necessary and sufficient monotonicity test.

    For the cubic Hermite segment with end derivatives ``slope_start``,
    ``slope_end`` and secant slope ``secant`` (non-zero).
    """
    if secant == 0:
        return slope_start == 0 and slope_end == 0
    a = slope_start / secant
    b = slope_end / secant
    tol = 1e-12
    if a < -tol or b < -tol:
        return False
    if a + b - 2.0 <= tol or 2.0 * a + b - 3.0 <= tol or a + 2.0 * b - 3.0 <= tol:
        return True
    phi = a - (2.0 * a + b - 3.0) ** 2 / (3.0 * (a + b - 2.0))
    return phi >= -tol


def _pchip_interior_slope(h1, m1, h2, m2):
    """Weighted harmonic mean of two secants (Fritsch-Butland / PCHIP)."""
    if m1 * m2 <= 0:
        return 0.0
    w1 = 2.0 * h2 + h1
    w2 = h2 + 2.0 * h1
    return (w1 + w2) / (w1 / m1 + w2 / m2)


def _volume_interpolant(alpha, volume, cycle):
    """Periodic cubic spline V(alpha) and dV/dalpha from the caller's samples."""
    _require(
        alpha.ndim == 1 and alpha.size >= 4,
        "crank_angle_deg",
        f"array of shape {alpha.shape}",
        "a 1-D grid of >= 4 points when volume_function is not given",
    )
    _require(
        np.all(np.diff(alpha) > 0) and alpha[0] >= 0 and alpha[-1] < cycle,
        "crank_angle_deg",
        f"[{alpha[0]}, ..., {alpha[-1]}]",
        f"strictly increasing values in [0, {cycle:g}) when volume_function is not given",
    )
    gaps = np.diff(np.append(alpha, alpha[0] + cycle))
    _require(
        gaps.max() <= _MAX_VOLUME_GRID_STEP_DEG,
        "crank_angle_deg",
        f"largest step {gaps.max():g} deg",
        f"steps <= {_MAX_VOLUME_GRID_STEP_DEG:g} deg (or pass volume_function)",
    )
    from scipy.interpolate import (
        CubicSpline,  # lazy: heavy optional import (~25 ms; sampled volumes only)
    )

    spline = CubicSpline(
        np.append(alpha, alpha[0] + cycle), np.append(volume, volume[0]), bc_type="periodic"
    )
    derivative = spline.derivative()
    start = alpha[0]

    def volume_and_slope(angle_deg):
        x = start + np.mod(np.asarray(angle_deg, dtype=float) - start, cycle)
        return spline(x), derivative(x)

    return volume_and_slope


def _function_volume(volume_function, cycle):
    """V(alpha) and a central-difference dV/dalpha from a user function."""
    step = 1e-4  # deg; truncation error ~1e-9 relative for engine kinematics

    def volume_and_slope(angle_deg):
        a = np.mod(np.asarray(angle_deg, dtype=float), cycle)
        v = np.asarray(volume_function(a), dtype=float)
        dv = (
            np.asarray(volume_function(a + step), dtype=float)
            - np.asarray(volume_function(a - step), dtype=float)
        ) / (2.0 * step)
        return v, dv

    return volume_and_slope


def _find_junction_deg(psi_peak, psi_limit, peak_Pa, expansion_at):
    """First angle after Z' joining the expansion line monotonically (see docstring)."""

    def passing(psi):
        # Vectorised form of the Fritsch-Carlson test for a zero start slope:
        # 0 <= beta = slope / secant <= 3 (same tolerance as _hermite_is_monotone).
        p, slope = expansion_at(psi)
        secant = (p - peak_Pa) / (psi - psi_peak)
        with np.errstate(divide="ignore", invalid="ignore"):
            beta = slope / secant
        return (p < peak_Pa) & (beta >= -1e-12) & (beta <= 3.0 + 1e-12)

    def passes(psi):
        p, slope = expansion_at(np.asarray([psi]))
        p, slope = float(p[0]), float(slope[0])
        if not p < peak_Pa:
            return False
        secant = (p - peak_Pa) / (psi - psi_peak)
        return _hermite_is_monotone(0.0, slope, secant)

    n = int(np.floor((psi_limit - psi_peak) / _JUNCTION_SEARCH_STEP_DEG))
    # The grid psi_peak + k * step, k = 1..n, is tested a chunk at a time from Z' on: J lies a few
    # tens of degrees after Z', so the rest of the grid up to the limit need not be evaluated (the
    # points are the same numbers as on the whole grid, and so is the first that passes).
    first = None
    for begin in range(1, n + 1, _JUNCTION_SCAN_CHUNK):
        k = np.arange(begin, min(begin + _JUNCTION_SCAN_CHUNK, n + 1))
        hits = np.nonzero(passing(psi_peak + _JUNCTION_SEARCH_STEP_DEG * k))[0]
        if hits.size:
            first = int(k[hits[0]])
            break
    if first is None:
        return None
    hi = float(psi_peak + _JUNCTION_SEARCH_STEP_DEG * first)
    lo = psi_peak if first == 1 else float(psi_peak + _JUNCTION_SEARCH_STEP_DEG * (first - 1))
    if not passes(hi):
        return None
    # Refined on ever finer grids (each 1/64 of the bracket), not by scalar bisection: five
    # vectorised evaluations instead of some thirty scalar ones reach the same 1e-10 deg.
    while hi - lo > _JUNCTION_TOLERANCE_DEG:
        inner = lo + (hi - lo) * np.arange(1, _JUNCTION_REFINE_POINTS) / _JUNCTION_REFINE_POINTS
        inner = inner[(inner > lo) & (inner < hi)]
        if inner.size == 0:  # the bracket is down to adjacent floats
            break
        ok = np.nonzero(passing(inner))[0]
        if ok.size:
            hi, lo = float(inner[ok[0]]), (lo if ok[0] == 0 else float(inner[ok[0] - 1]))
        else:
            lo = float(inner[-1])
    return hi


def combustion_junctions_deg(params, rounding, clearance_volume_m3, volume_function):
    """The junction J of the combustion rounding of many diagrams at once.

    Parameters
    ----------
    params : sequence of CycleParameters
        One per diagram, all of one number of strokes.
    rounding : sequence of RoundingParameters
        One per diagram.
    clearance_volume_m3 : array_like, shape (P,)
        Clearance volume V_c of each diagram, m^3, > 0.
    volume_function : callable
        ``volume_function(angle_deg, rows) -> volume_m3``: the cylinder volume,
        m^3, of the diagrams ``rows`` (an index array) at crank angles
        ``angle_deg`` of shape (len(rows), M), deg, row by row; as the
        ``volume_function`` of :func:`rounded_pressure_Pa`, it must accept
        angles 1e-4 deg outside the cycle.

    Returns
    -------
    numpy.ndarray, shape (P,)
        psi_J, deg after firing TDC; NaN for a diagram whose rounding from Z'
        joins the expansion line nowhere before b'.

    Notes
    -----
    Row by row the same search as :func:`rounded_pressure_Pa` makes for one
    diagram (:func:`_combustion_rounding`): the first angle of the 0.01-deg
    grid after Z' where a monotone Hermite segment from Z' (zero slope) meets
    the expansion line (eq. 13, derived construction), refined on grids of
    1/64 of the bracket to 1e-10 deg.  The grids hold the same numbers, so each
    row's J equals the one-diagram search's; pass it to
    :func:`rounded_pressure_Pa` as ``junction_deg``.
    """
    count = len(params)
    lines = _many_diagram_lines(params, rounding, clearance_volume_m3, volume_function)
    psi_peak = np.array([r.peak_angle_after_tdc_deg for r in rounding], dtype=float)
    psi_limit = np.array(
        [
            p.bdc_deg - r.exhaust_opens_before_bdc_deg
            for r, p in zip(rounding, params, strict=False)
        ],
        dtype=float,
    )
    at_peak = lines.expansion_at(psi_peak[:, None], np.arange(count))[0][:, 0]
    peak = np.array(
        [
            _peak_Pa(r, p, float(theoretical))
            for r, p, theoretical in zip(rounding, params, at_peak, strict=False)
        ],
        dtype=float,
    )
    first = _first_passing_steps(psi_peak, psi_limit, peak, lines)
    found = np.flatnonzero(first > 0)
    junction = np.full(count, np.nan)
    if found.size == 0:
        return junction
    found, lo, hi = _junction_brackets(found, first, psi_peak, peak, lines)
    junction[found] = _refined_junctions(found, lo, hi, psi_peak, peak, lines)
    return junction


def _many_diagram_lines(params, rounding, clearance_volume_m3, volume_function) -> _ColumnLines:
    """The compression and expansion lines of many diagrams, one per row; diagrams of mixed
    strokes or a rounding count that does not match raise ValueError."""
    count = len(params)
    _require(
        count == len(rounding) and count > 0,
        "rounding",
        f"{len(rounding)} entries",
        f"one per diagram ({count}), at least one",
    )
    cycle = _cycle_deg(params[0])
    _require(
        all(_cycle_deg(p) == cycle for p in params),
        "params",
        "mixed strokes",
        "diagrams of one number of strokes",
    )
    tdc = _firing_tdc_deg(params[0])
    return _ColumnLines(
        np.asarray(clearance_volume_m3, dtype=float).reshape(count, 1),
        params,
        volume_function,
        tdc,
        cycle,
    )


def _junction_brackets(found, first, psi_peak, peak, lines):
    """(rows, lo, hi): the rows ``found`` whose first passing grid step ``first`` surely holds
    the junction (below the peak, a monotone segment at its end), with that step's bracket."""
    step = _JUNCTION_SEARCH_STEP_DEG
    hi = psi_peak[found] + step * first[found]
    lo = np.where(first[found] == 1, psi_peak[found], psi_peak[found] + step * (first[found] - 1))
    p, slope = lines.expansion_at(hi[:, None], found)
    sure = np.array(
        [
            bool(p[k, 0] < peak[row])
            and _hermite_is_monotone(
                0.0, float(slope[k, 0]), float((p[k, 0] - peak[row]) / (hi[k] - psi_peak[row]))
            )
            for k, row in enumerate(found)
        ],
        dtype=bool,
    )
    return found[sure], lo[sure], hi[sure]


def _passing_many(psi, psi_peak, peak_Pa, lines, rows):
    """The Fritsch-Carlson test of :func:`_find_junction_deg` row by row, psi of shape (rows, M)."""
    p, slope = lines.expansion_at(psi, rows)
    secant = (p - peak_Pa) / (psi - psi_peak)
    with np.errstate(divide="ignore", invalid="ignore"):
        beta = slope / secant
    return (p < peak_Pa) & (beta >= -1e-12) & (beta <= 3.0 + 1e-12)


def _first_passing_steps(psi_peak, psi_limit, peak, lines):
    """Per row, the first k >= 1 of the 0.01-deg grid psi_peak + k * step (up to psi_limit)
    that passes the test, 0 where none does; scanned a part of the grid at a time, the first
    2 deg (J lies 1-2 deg after Z' in a typical diagram), then parts twice as long each time."""
    step = _JUNCTION_SEARCH_STEP_DEG
    last = np.floor((psi_limit - psi_peak) / step).astype(int)
    first = np.zeros(len(psi_peak), dtype=int)
    pending = last >= 1
    begin, size = 1, _JUNCTION_MANY_FIRST_CHUNK
    while pending.any():
        rows = np.flatnonzero(pending)
        k = np.arange(begin, begin + size)
        psi = psi_peak[rows, None] + step * k[None, :]
        hits = _passing_many(psi, psi_peak[rows, None], peak[rows, None], lines, rows)
        hits &= k[None, :] <= last[rows, None]
        hit = hits.any(axis=1)
        first[rows[hit]] = k[np.argmax(hits[hit], axis=1)]
        pending[rows[hit]] = False
        begin += size
        size = min(2 * size, _JUNCTION_SCAN_CHUNK)
        pending &= last >= begin
    return first


def _refined_junctions(rows, lo, hi, psi_peak, peak, lines):
    """Each bracket (lo, hi] of the junction narrowed to 1e-10 deg on grids of 1/64 of it, row by
    row as :func:`_find_junction_deg` narrows one; returns hi."""
    lo, hi = lo.copy(), hi.copy()
    active = np.flatnonzero(hi - lo > _JUNCTION_TOLERANCE_DEG)
    while active.size:
        a_lo, a_hi = lo[active, None], hi[active, None]
        # as _find_junction_deg writes it, operation for operation: the same numbers
        inner = (
            a_lo + (a_hi - a_lo) * np.arange(1, _JUNCTION_REFINE_POINTS) / _JUNCTION_REFINE_POINTS
        )
        valid = (inner > a_lo) & (inner < a_hi)
        ok = (
            _passing_many(
                inner, psi_peak[rows[active], None], peak[rows[active], None], lines, rows[active]
            )
            & valid
        )
        any_ok = ok.any(axis=1)
        first_ok = np.argmax(ok, axis=1)
        columns = np.arange(inner.shape[1])
        last_valid = np.where(valid, columns, -1).max(axis=1)
        for k, row in enumerate(active):
            if last_valid[k] < 0:  # the bracket is down to adjacent floats
                lo[row] = hi[row]
                continue
            if any_ok[k]:
                j = first_ok[k]
                before = lo[row] if j == 0 or not valid[k, j - 1] else inner[k, j - 1]
                hi[row], lo[row] = inner[k, j], before
            else:
                lo[row] = inner[k, last_valid[k]]
        active = active[hi[active] - lo[active] > _JUNCTION_TOLERANCE_DEG]
    return hi


class _ColumnLines:
    """The expansion line and its slope of many diagrams, their numbers as columns (P, 1)."""

    def __init__(self, clearance_m3, params, volume_function, tdc_deg, cycle_deg):
        def column(name):
            return np.array([getattr(p, name) for p in params], dtype=float)[:, None]

        self.clearance_m3 = clearance_m3
        self.columns = {
            name: column(name)
            for name in (
                "compression_ratio",
                "lost_stroke_fraction",
                "pre_expansion_ratio",
                "max_pressure_Pa",
                "expansion_index",
            )
        }
        self.volume_function = volume_function
        self.tdc_deg = tdc_deg
        self.cycle_deg = cycle_deg

    def expansion_at(self, psi, rows):
        """(p, dp/dpsi) of the expansion line of diagrams ``rows`` at psi (rows, M), Pa, Pa/deg;
        dV/dalpha by the central difference of :func:`_function_volume`."""
        step = 1e-4
        a = np.mod(np.asarray(self.tdc_deg + psi, dtype=float), self.cycle_deg)
        v = np.asarray(self.volume_function(a, rows), dtype=float)
        dv = (
            np.asarray(self.volume_function(a + step, rows), dtype=float)
            - np.asarray(self.volume_function(a - step, rows), dtype=float)
        ) / (2.0 * step)
        params = _Columns({name: c[rows] for name, c in self.columns.items()})
        clearance = self.clearance_m3[rows]
        return (
            _expansion_line_Pa(v, clearance, params),
            _expansion_slope_Pa_per_deg(v, dv, clearance, params),
        )


class _Columns:
    """Cycle parameters as attributes holding columns (P, 1), for the lines' formulas."""

    def __init__(self, values: dict):
        self.__dict__.update(values)


def _local_offset_deg(alpha, start_deg, cycle):
    """Angle travelled from ``start_deg`` to ``alpha`` in the direction of rotation."""
    return np.mod(alpha - start_deg, cycle)


def rounded_pressure_Pa(
    crank_angle_deg,
    volume_m3,
    clearance_volume_m3,
    params,
    rounding,
    *,
    volume_function: Callable | None = None,
    junction_deg: float | None = None,
    theoretical_Pa=None,
):
    """Actual-cycle indicator diagram: the theoretical diagram with rounded corners.

    Parameters
    ----------
    crank_angle_deg : array_like
        Crank angles alpha, deg (conventions as in
        :func:`theoretical_pressure_Pa`).  Without ``volume_function`` this
        must be a strictly increasing 1-D grid covering the cycle, in
        [0, 720) or [0, 360), with steps <= 15 deg.
    volume_m3 : array_like
        Cylinder volume at those angles, m^3, same shape.
    clearance_volume_m3 : float
        Clearance volume V_c, m^3, > 0.
    params : CycleParameters
    rounding : RoundingParameters
    volume_function : callable, optional
        ``volume_function(angle_deg_array) -> volume_m3_array`` on the same
        cycle; it is called with angles reduced modulo the cycle and
        +-1e-4 deg around them (central difference for dV/dalpha), so it
        must accept angles slightly outside [0, cycle).  The rounding needs V
        and dV/dalpha where the caller's grid may miss (C', b', J).  If given, these are
        taken from it and the result is exactly independent of the caller's
        grid; otherwise they come from a periodic cubic spline through
        (crank_angle_deg, volume_m3), which reproduces engine kinematics to
        ~1e-9 relative on a 1-deg grid.
    junction_deg : float, optional
        The junction J, deg after firing TDC, found by the caller
        (:func:`combustion_junctions_deg`); NaN: none fits (ValueError).
    theoretical_Pa : array_like, optional
        :func:`theoretical_pressure_Pa` at these angles, if already computed.

    Returns
    -------
    numpy.ndarray
        Absolute cylinder pressure, Pa, same shape as ``crank_angle_deg``.

    Raises
    ------
    ValueError
        If the rounding points do not fit on the diagram (the message names
        the offending parameter), or the inputs are invalid.

    Notes
    -----
    Angles psi are relative to firing TDC; every rounding segment is a cubic
    Hermite curve, evaluated analytically at the caller's angles, that matches
    the theoretical line in value and slope at both of its ends, so the
    diagram is C1 wherever rounding acts.  The steps, each its own function:
    combustion C' -> C'' -> Z' -> J (:func:`_combustion_rounding`), the
    exhaust drop at BDC (:func:`_exhaust_drop`) and the gas exchange at the
    exhaust TDC (:func:`_gas_exchange_step`).  Elsewhere the theoretical
    diagram is kept.  The rounding windows must not overlap (C' after the
    previous window, J before b', the exhaust rounding end before the intake
    opening), else ValueError.

    Poda (2007) section 3.1 gives the points 3, C', C'', Z', b' and typical values; the joining curves are derived.
    """
    alpha = np.asarray(crank_angle_deg, dtype=float)
    volume = np.asarray(volume_m3, dtype=float)
    _check_rounding_inputs(params, rounding)
    pressure = _theoretical_or_given(alpha, volume, clearance_volume_m3, params, theoretical_Pa)
    cycle = _cycle_deg(params)
    lines = _one_diagram_lines(alpha, volume, clearance_volume_m3, params, volume_function)
    pressure, psi_j = _combustion_rounding(alpha, pressure, lines, rounding, cycle, junction_deg)
    pressure = _exhaust_drop(alpha, pressure, lines, rounding, cycle, psi_j)
    if params.strokes == 4:
        pressure = _gas_exchange_step(alpha, pressure, params, rounding, lines.tdc_deg, cycle)
    return pressure


def _theoretical_or_given(alpha, volume, clearance_volume_m3, params, theoretical_Pa):
    """The theoretical pressure at the angles ``alpha``, Pa: the caller's, or computed."""
    if theoretical_Pa is None:
        return theoretical_pressure_Pa(alpha, volume, clearance_volume_m3, params)
    return np.asarray(theoretical_Pa, dtype=float)


def _one_diagram_lines(alpha, volume, clearance_volume_m3, params, volume_function) -> _Lines:
    """The compression and expansion lines of one diagram, its volume from ``volume_function``
    or, without one, from a periodic spline through the caller's (angle, volume) points."""
    cycle = _cycle_deg(params)
    tdc = _firing_tdc_deg(params)
    if volume_function is None:
        volume_at = _volume_interpolant(alpha, volume, cycle)
    else:
        volume_at = _function_volume(volume_function, cycle)
    return _Lines(volume_at, tdc, clearance_volume_m3, params)


def _check_rounding_inputs(params, rounding) -> None:
    """The types of ``params`` and ``rounding``; a two-stroke cycle has no valve timing near TDC."""
    _require(
        isinstance(params, CycleParameters),
        "params",
        type(params).__name__,
        "a CycleParameters instance",
    )
    _require(
        isinstance(rounding, RoundingParameters),
        "rounding",
        type(rounding).__name__,
        "a RoundingParameters instance",
    )
    if params.strokes != 4:
        for name in (
            "exhaust_closes_after_tdc_deg",
            "intake_opens_before_tdc_deg",
            "intake_closes_after_bdc_deg",
        ):
            _require(
                getattr(rounding, name) == 0,
                name,
                getattr(rounding, name),
                "0 for a two-stroke cycle (only exhaust_opens_before_bdc_deg applies)",
            )


@dataclass(frozen=True)
class _Lines:
    """The compression and expansion lines and their slopes at angles psi after firing TDC."""

    volume_at: Callable
    tdc_deg: float
    clearance_volume_m3: float
    params: CycleParameters

    def compression_at(self, psi):
        """(p, dp/dpsi) of the compression line, Pa and Pa/deg."""
        v, dv = self.volume_at(self.tdc_deg + psi)
        return (
            _compression_line_Pa(v, self.clearance_volume_m3, self.params),
            _compression_slope_Pa_per_deg(v, dv, self.clearance_volume_m3, self.params),
        )

    def expansion_at(self, psi):
        """(p, dp/dpsi) of the expansion line, Pa and Pa/deg."""
        v, dv = self.volume_at(self.tdc_deg + psi)
        return (
            _expansion_line_Pa(v, self.clearance_volume_m3, self.params),
            _expansion_slope_Pa_per_deg(v, dv, self.clearance_volume_m3, self.params),
        )


def _drop_end_psi_deg(rounding, bdc_deg: float = 180.0) -> float:
    """End of the exhaust drop, deg after firing TDC: BDC + exhaust_opens_before_bdc / 2."""
    return bdc_deg + 0.5 * rounding.exhaust_opens_before_bdc_deg


#: A peak p_z' that would lie above the theoretical diagram at Z' is taken at this fraction of
#: the theoretical pressure there: the rounded diagram stays inside the theoretical one, and the
#: rounding from Z' still meets the expansion line smoothly further on.
PEAK_BELOW_EXPANSION = 0.97


def _peak_Pa(rounding, params, theoretical_at_peak_Pa: float) -> float:
    """p_z', Pa: fraction * p_z, or :data:`PEAK_BELOW_EXPANSION` of the theoretical diagram's
    pressure at Z' (its expansion line, or p_z on a diesel's isobar) where fraction * p_z would
    exceed it."""
    wanted = rounding.peak_pressure_fraction * params.max_pressure_Pa
    if wanted <= theoretical_at_peak_Pa:
        return wanted
    return PEAK_BELOW_EXPANSION * theoretical_at_peak_Pa


def peak_pressure_Pa(
    crank_angle_deg, volume_m3, clearance_volume_m3, params, rounding, *, volume_function=None
) -> float:
    """The rounded diagram's peak pressure p_z' at Z', Pa, as :func:`rounded_pressure_Pa` takes
    it: ``peak_pressure_fraction`` * p_z, or lower (:data:`PEAK_BELOW_EXPANSION` of the
    theoretical pressure there) where that would lie above the theoretical diagram at Z'; the
    arguments as :func:`rounded_pressure_Pa`'s.

    Poda (2007) section 3.1: Z' lies 10-15 deg after TDC at p_z' = (0.8-0.9) p_z; the actual
    diagram lies inside the theoretical one.
    """
    alpha = np.asarray(crank_angle_deg, dtype=float)
    lines = _one_diagram_lines(
        alpha, np.asarray(volume_m3, dtype=float), clearance_volume_m3, params, volume_function
    )
    return _peak_at(lines, rounding)


#: The pressure rise from the end of compression c to TDC c″ the rounding takes by default, Pa
#: (Poda 2007 section 3.1: 0.4-0.6 MPa for most engines), and its largest share of p_c
#: (Kolchin and Demidov: p_c″ = (1.15-1.25) p_c), which an engine of a low compression end
#: pressure (a low compression ratio, a two-stroke's lost stroke) keeps to.
USUAL_PRESSURE_RISE_PA = 0.5e6
LARGEST_PRESSURE_RISE_SHARE = 0.25


def usual_pressure_rise_Pa(params) -> float:
    """The rise p_c″ − p_c the rounding takes where the scene gives none, Pa:
    :data:`USUAL_PRESSURE_RISE_PA`, at most :data:`LARGEST_PRESSURE_RISE_SHARE` of the
    compression end pressure p_c (:func:`compression_end_pressure_Pa`)."""
    return min(
        USUAL_PRESSURE_RISE_PA, LARGEST_PRESSURE_RISE_SHARE * compression_end_pressure_Pa(params)
    )


#: Where a diesel's rounded diagram peaks when its scene gives no angle: Z' on the isobar z'z of
#: heat added at constant pressure, this share of its length from TDC (Poda 2007 section 3.1:
#: "approximately 2/3 of the segment's length"), where the theoretical pressure is p_z itself.
DIESEL_PEAK_ISOBAR_SHARE = 2.0 / 3.0


def isobar_point_volume_m3(
    clearance_volume_m3: float, params, share: float = DIESEL_PEAK_ISOBAR_SHARE
) -> float:
    """The cylinder volume ``share`` along the isobar z'z, m^3: V_c (1 + share (rho - 1)) (the
    isobar runs from V_c at TDC to rho V_c at z)."""
    return clearance_volume_m3 * (1.0 + share * (params.pre_expansion_ratio - 1.0))


def isobar_peak_angle_deg(
    crank_angle_deg,
    volume_m3,
    clearance_volume_m3,
    params,
    *,
    share: float = DIESEL_PEAK_ISOBAR_SHARE,
    volume_function=None,
) -> float | None:
    """Crank angle after firing TDC, deg, at which the cylinder volume reaches
    V_c (1 + share (rho - 1)): the point ``share`` along the isobar z'z of a cycle with heat
    added at constant pressure (Poda 2007 section 3.1 puts a diesel's actual peak Z' at about
    2/3 of it); None without an isobar (rho = 1).

    The arguments as :func:`rounded_pressure_Pa`'s; the volume rises monotonically from TDC to
    the isobar's end, so the angle is found by bisection (to 1e-10 deg) between TDC and 90 deg.
    """
    if params.pre_expansion_ratio <= 1.0:
        return None
    lines = _one_diagram_lines(
        np.asarray(crank_angle_deg, dtype=float),
        np.asarray(volume_m3, dtype=float),
        clearance_volume_m3,
        params,
        volume_function,
    )
    target = isobar_point_volume_m3(clearance_volume_m3, params, share)
    low, high = 0.0, 90.0
    while high - low > 1e-10:
        middle = 0.5 * (low + high)
        volume = float(np.ravel(lines.volume_at(np.asarray([lines.tdc_deg + middle]))[0])[0])
        low, high = (middle, high) if volume < target else (low, middle)
    return 0.5 * (low + high)


def _peak_at(lines: _Lines, rounding) -> float:
    """p_z' of one diagram's lines (:func:`_peak_Pa` at Z')."""
    at_peak = float(lines.expansion_at(np.asarray([rounding.peak_angle_after_tdc_deg]))[0][0])
    return _peak_Pa(rounding, lines.params, at_peak)


def _combustion_rounding(alpha, pressure, lines: _Lines, rounding, cycle, junction_deg=None):
    """Combustion rounding C' -> C'' -> Z' -> J laid over ``pressure`` (Pa); returns (pressure, psi_J).

    C' at psi = -(advance - delay) lies on the compression line (its value and
    slope), C'' at psi = 0 has p_c + rise, Z' at psi = peak_angle has
    p_z' = fraction * p_z and zero slope.  From C' to C'' the pressure is the
    compression line plus a monotone cubic excess from zero (value and slope)
    at C' to the rise at TDC: once burning has begun the pressure lies above
    the compression line.  The slope at C'' is the weighted harmonic mean of
    the neighbouring secants (PCHIP), at most what keeps that excess monotone;
    the segment C''-Z' must pass the Fritsch-Carlson monotonicity test, so the
    curve rises monotonically and its maximum is exactly p_z' at Z'.  The junction J is
    the first angle after Z' at which the expansion line lies below p_z' and
    a monotone Hermite segment from Z' (zero slope) to J (expansion line's
    value and slope) exists; for a zero start slope the Fritsch-Carlson test
    reduces to slope_J <= 3 * secant.  It is found on an internal 0.01-deg
    grid, refined on finer grids to 1e-10 deg (unless ``junction_deg`` gives
    it: NaN for none).
    """
    params = lines.params
    peak = _peak_at(lines, rounding)
    psi_c1 = -(rounding.ignition_advance_deg - rounding.combustion_delay_deg)
    psi_peak = rounding.peak_angle_after_tdc_deg
    psi_b1 = params.bdc_deg - rounding.exhaust_opens_before_bdc_deg
    _check_combustion_window(rounding, params, psi_c1)
    p_c, p_c2, d_c2 = _combustion_rise(lines, rounding, psi_c1, peak)
    psi_j = _combustion_junction(lines, rounding, peak, psi_b1, junction_deg)
    p_j, s_j = (float(x[0]) for x in lines.expansion_at(np.asarray([psi_j])))
    # burning from C': the compression line plus a monotone excess rising from zero (value and
    # slope) at C' to p_C'' - p_c at TDC, so the pressure never falls below the compression
    excess = hermite_cubic([psi_c1, 0.0], [0.0, p_c2 - p_c], [0.0, d_c2])
    after = hermite_cubic([0.0, psi_peak, psi_j], [p_c2, peak, p_j], [d_c2, 0.0, s_j])

    def combustion(psi):
        psi = np.asarray(psi, dtype=float)
        before = psi < 0.0
        return np.where(
            before,
            lines.compression_at(np.where(before, psi, psi_c1))[0] + excess(psi),
            after(psi),
        )

    offset = _local_offset_deg(alpha, lines.tdc_deg + psi_c1, cycle)
    in_window = offset <= psi_j - psi_c1
    return _laid_over(pressure, in_window, combustion, psi_c1 + offset), psi_j


def _check_combustion_window(rounding, params, psi_c1: float) -> None:
    """The combustion window fits the cycle: a two-stroke's drop at BDC ends before C', and the
    exhaust opening point b' follows the peak Z'."""
    eo = rounding.exhaust_opens_before_bdc_deg
    psi_peak = rounding.peak_angle_after_tdc_deg
    bdc = params.bdc_deg
    if params.strokes != 4 and params.lost_stroke_fraction == 0.0:
        # the drop end (after BDC) must precede C' (before the next firing TDC); with ports,
        # the rounding after their closing is checked where it is built (_port_rounding)
        _require(
            _drop_end_psi_deg(rounding, bdc) - 360.0 < psi_c1,
            "exhaust_opens_before_bdc_deg",
            eo,
            f"< {2.0 * (psi_c1 + 360.0 - bdc):.6g} deg so that the drop at BDC ends "
            "before the combustion point C'",
        )
    _require(
        psi_peak < bdc - eo,
        "exhaust_opens_before_bdc_deg",
        eo,
        f"< {bdc - psi_peak:g} deg so that b' follows the peak Z' "
        f"(peak_angle_after_tdc_deg = {psi_peak:g})",
    )


def _combustion_rise(lines: _Lines, rounding, psi_c1: float, peak: float):
    """(p at TDC on the compression line p_c, p_C'', slope at C''), Pa and Pa/deg, of a monotone
    rise from C' on the compression line through C'' to the peak Z'.

    The slope at C'' is the PCHIP one of the secants C'-C'' and C''-Z', at most three times the
    secant of the excess p_C'' - p_c over C'-C'': the excess over the compression line that
    :func:`_combustion_rounding` lays on from C' then rises monotonically (Fritsch-Carlson)."""
    p_c = float(lines.compression_at(np.asarray([0.0]))[0][0])
    psi_peak = rounding.peak_angle_after_tdc_deg
    p_c1 = float(lines.compression_at(np.asarray([psi_c1]))[0][0])
    p_c2 = compression_end_pressure_Pa(lines.params) + rounding.pressure_rise_to_tdc_Pa
    _require(
        p_c2 < peak,
        "pressure_rise_to_tdc_Pa",
        rounding.pressure_rise_to_tdc_Pa,
        f"< p_z' - p_c = {peak - p_c:.6g} Pa (peak_pressure_fraction * p_z "
        "must exceed the pressure at TDC)",
    )
    h1, h2 = -psi_c1, psi_peak
    m1 = (p_c2 - p_c1) / h1
    m2 = (peak - p_c2) / h2
    d_c2 = min(_pchip_interior_slope(h1, m1, h2, m2), 3.0 * (p_c2 - p_c) / h1)
    _require(
        _hermite_is_monotone(d_c2, 0.0, m2),
        "peak_angle_after_tdc_deg",
        psi_peak,
        "a value for which the C''-Z' rounding is monotone",
    )
    return p_c, p_c2, d_c2


def _combustion_junction(lines: _Lines, rounding, peak: float, psi_b1: float, junction_deg):
    """psi_J, deg after firing TDC: the caller's ``junction_deg`` or searched; none before b'
    raises ValueError."""
    psi_peak = rounding.peak_angle_after_tdc_deg
    if junction_deg is None:
        psi_j = _find_junction_deg(psi_peak, psi_b1, peak, lines.expansion_at)
    else:
        psi_j = None if np.isnan(junction_deg) else float(junction_deg)
    _require(
        psi_j is not None,
        "peak_angle_after_tdc_deg / peak_pressure_fraction / exhaust_opens_before_bdc_deg",
        f"{psi_peak} deg / {rounding.peak_pressure_fraction} / "
        f"{rounding.exhaust_opens_before_bdc_deg} deg",
        "values for which the rounding from Z' joins the expansion line "
        f"monotonically before the exhaust opening point b' ({psi_b1:g} deg after "
        "firing TDC)",
    )
    return psi_j


def _exhaust_drop(alpha, pressure, lines: _Lines, rounding, cycle, psi_j):
    """Exhaust rounding at BDC laid over ``pressure`` (Pa); nothing when the exhaust opens at BDC.

    Four-stroke: b' = 540 - exhaust_opens_before_bdc on the expansion line
    (value, slope) -> BDC at (p_b + p_r)/2 (PCHIP slope) -> p_r with zero
    slope at 540 + exhaust_opens_before_bdc/2; both segments must be
    monotone.  Two-stroke with a positive opening angle: the same three points
    with p_a in place of p_r, the last one on the compression line (value and
    slope), so the curve may dip slightly below that rising line just before
    joining it.
    """
    params = lines.params
    four = params.strokes == 4
    eo = rounding.exhaust_opens_before_bdc_deg
    if not eo > 0:
        return pressure
    if params.lost_stroke_fraction > 0.0:
        return _port_rounding(alpha, pressure, lines, rounding, cycle, psi_j)
    p_b = expansion_end_pressure_Pa(params)
    p_low = params.exhaust_pressure_Pa if four else params.intake_pressure_Pa
    bdc = params.bdc_deg
    psi_b1 = bdc - eo
    drop_end_psi = _drop_end_psi_deg(rounding, bdc)
    _require(
        p_b > p_low,
        "exhaust_pressure_Pa" if four else "intake_pressure_Pa",
        p_low,
        f"< expansion-end pressure p_b = {p_b:.6g} Pa for the exhaust rounding",
    )
    _require(
        psi_j < psi_b1,
        "exhaust_opens_before_bdc_deg",
        eo,
        f"< {bdc - psi_j:.6g} deg so that b' follows the combustion rounding junction J",
    )
    p_b1, s_b1 = (float(x[0]) for x in lines.expansion_at(np.asarray([psi_b1])))
    p_mid = 0.5 * (p_b + p_low)
    if four:
        p_end, s_end = p_low, 0.0
    else:
        p_end, s_end = (float(x[0]) for x in lines.compression_at(np.asarray([drop_end_psi])))
    h1, h2 = eo, 0.5 * eo
    m1 = (p_mid - p_b1) / h1
    m2 = (p_end - p_mid) / h2
    d_mid = _pchip_interior_slope(h1, m1, h2, m2)
    _require(
        _hermite_is_monotone(s_b1, d_mid, m1),
        "exhaust_opens_before_bdc_deg",
        eo,
        "a value for which the b'-BDC rounding is monotone",
    )
    if four:
        _require(
            _hermite_is_monotone(d_mid, s_end, m2),
            "exhaust_opens_before_bdc_deg",
            eo,
            "a value for which the BDC-exhaust rounding is monotone",
        )
    drop = hermite_cubic([psi_b1, bdc, drop_end_psi], [p_b1, p_mid, p_end], [s_b1, d_mid, s_end])
    offset = _local_offset_deg(alpha, lines.tdc_deg + psi_b1, cycle)
    in_window = offset <= 1.5 * eo
    return _laid_over(pressure, in_window, drop, psi_b1 + offset)


#: Length of the blowdown after the exhaust port opening b, as a fraction of the port opening
#: angle before BDC: the cylinder is down at the scavenging pressure about when the transfer ports
#: open, some 15-25 deg after the exhaust ports (Blair 1996, ch. 1).
BLOWDOWN_FRACTION = 0.25
#: Length of the compression rounding after the port closing a', the same fraction: the ports
#: are covered gradually, and the charge is trapped a little after the geometric closing.
PORT_CLOSING_ROUNDING_FRACTION = 0.25


def port_closing_deg(lines_or_volume_at, clearance_volume_m3, params):
    """The port closing a', deg after firing TDC: where the volume falls back to V_a' after BDC.

    ``lines_or_volume_at`` is ``volume_at(angle_deg) -> (V, dV/dalpha)`` over the cycle's
    angles.  Bisection on [BDC, BDC + 180): the volume decreases monotonically there.
    """
    volume_at = getattr(lines_or_volume_at, "volume_at", lines_or_volume_at)
    tdc = _firing_tdc_deg(params)
    target = port_closing_volume_m3(clearance_volume_m3, params)
    lo, hi = params.bdc_deg, params.bdc_deg + 180.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        v = float(np.ravel(volume_at(np.asarray([tdc + mid]))[0])[0])
        if v > target:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-12:
            break
    return 0.5 * (lo + hi)


def _port_rounding(alpha, pressure, lines: _Lines, rounding, cycle, psi_j):
    """A port-scavenged two-stroke's gas exchange laid over ``pressure`` (Pa).

    Blowdown: from the exhaust port opening b (bdc - phi_b, the expansion
    line's value p_b and slope) down to the scavenging pressure p_a with zero
    slope BLOWDOWN_FRACTION * phi_b later, well before BDC; the cylinder then stays at p_a
    (the theoretical diagram) until the port closing a'; compression rounding:
    from a' (p_a, zero slope) onto the compression line (its value and slope)
    PORT_CLOSING_ROUNDING_FRACTION * phi_b later.  Both cubic Hermite segments
    must pass the Fritsch-Carlson test, so the pressure between b and a' never
    falls below p_a.  Derived construction; the phases after Blair (1996), ch. 1.
    """
    params = lines.params
    eo = rounding.exhaust_opens_before_bdc_deg
    p_low = params.intake_pressure_Pa
    psi_b = params.bdc_deg - eo
    _require(
        psi_j < psi_b,
        "exhaust_opens_before_bdc_deg",
        eo,
        f"< {params.bdc_deg - psi_j:.6g} deg so that b follows the combustion rounding junction J",
    )
    p_b, s_b = (float(x[0]) for x in lines.expansion_at(np.asarray([psi_b])))
    _require(
        p_b > p_low,
        "intake_pressure_Pa",
        p_low,
        f"< expansion-end pressure p_b = {p_b:.6g} Pa for the exhaust blowdown",
    )
    blowdown = BLOWDOWN_FRACTION * eo
    _require(
        _hermite_is_monotone(s_b, 0.0, (p_low - p_b) / blowdown),
        "exhaust_opens_before_bdc_deg",
        eo,
        "a value for which the blowdown from the port opening b is monotone",
    )
    drop = hermite_cubic([psi_b, psi_b + blowdown], [p_b, p_low], [s_b, 0.0])
    psi_a = port_closing_deg(lines, lines.clearance_volume_m3, params)
    psi_end = psi_a + PORT_CLOSING_ROUNDING_FRACTION * eo
    psi_c1 = -(rounding.ignition_advance_deg - rounding.combustion_delay_deg)
    _require(
        psi_end - 360.0 < psi_c1,
        "exhaust_opens_before_bdc_deg",
        eo,
        "a smaller value, so that the compression rounding after the port closing a' "
        f"({psi_a:.6g} deg) ends before the combustion point C' ({psi_c1 + 360.0:.6g} deg)",
    )
    p_end, s_end = (float(x[0]) for x in lines.compression_at(np.asarray([psi_end])))
    _require(
        _hermite_is_monotone(0.0, s_end, (p_end - p_low) / (psi_end - psi_a)),
        "exhaust_opens_before_bdc_deg",
        eo,
        "a value for which the compression rounding after the port closing a' is monotone",
    )
    closing = hermite_cubic([psi_a, psi_end], [p_low, p_end], [0.0, s_end])
    offset = _local_offset_deg(alpha, lines.tdc_deg + psi_b, cycle)
    pressure = _laid_over(pressure, offset <= blowdown, drop, psi_b + offset)
    offset = _local_offset_deg(alpha, lines.tdc_deg + psi_a, cycle)
    return _laid_over(pressure, offset <= psi_end - psi_a, closing, psi_a + offset)


def _laid_over(pressure, in_window, curve, at):
    """``pressure`` with ``curve(at)`` where ``in_window``: the curve evaluated in its window only
    (the same numbers as everywhere, a few of them)."""
    if np.ndim(pressure) == 0 or np.shape(in_window) != np.shape(pressure):
        return np.where(in_window, curve(at), pressure)
    out = np.array(pressure, dtype=float)
    out[in_window] = curve(np.broadcast_to(at, np.shape(pressure))[in_window])
    return out


def _gas_exchange_step(alpha, pressure, params, rounding, tdc, cycle):
    """Four-stroke gas exchange at the exhaust TDC laid over ``pressure`` (Pa).

    p_r -> p_a with zero end slopes (smoothstep 3t^2 - 2t^3, monotone) between
    720 - intake_opens_before_tdc and 0 + exhaust_closes_after_tdc, wrapping
    through 720/0; halfway it is (p_r + p_a)/2.  If both angles are 0 the
    step stays sharp.
    """
    io = rounding.intake_opens_before_tdc_deg
    ec = rounding.exhaust_closes_after_tdc_deg
    drop_end_psi = _drop_end_psi_deg(rounding, params.bdc_deg)
    _require(
        720.0 - io > tdc + drop_end_psi,
        "intake_opens_before_tdc_deg",
        io,
        f"< {720.0 - (tdc + drop_end_psi):.6g} deg so that the intake "
        "opening follows the end of the exhaust rounding "
        "(540 + exhaust_opens_before_bdc_deg/2)",
    )
    width = io + ec
    if width > 0:
        offset = _local_offset_deg(alpha, 720.0 - io, cycle)
        in_window = offset <= width
        t = np.clip(offset / width, 0.0, 1.0)
        smooth = params.exhaust_pressure_Pa + (
            params.intake_pressure_Pa - params.exhaust_pressure_Pa
        ) * t * t * (3.0 - 2.0 * t)
        pressure = np.where(in_window, smooth, pressure)
    return pressure


# ---------------------------------------------------------------------------
# Work and mean pressure
# ---------------------------------------------------------------------------
def indicated_work_J(pressure_Pa, volume_m3):
    """Indicated work of one cycle, the closed-loop integral of p dV.

    Parameters
    ----------
    pressure_Pa : array_like
        Cylinder pressure over one cycle, Pa, 1-D, on a periodic grid with the
        end point excluded (e.g. 0, 1, ..., 719 deg).
    volume_m3 : array_like
        Cylinder volume at the same samples, m^3, same shape.

    Returns
    -------
    float
        W_i = closed integral of p dV, J.  Positive for an engine cycle
        traversed in the direction of rotation; pumping loops count with
        their sign.

    Notes
    -----
    The first sample is appended to close the loop and the integral is taken
    with the trapezoid rule in V: sum of (p_k + p_{k+1})/2 (V_{k+1} - V_k).
    Derived (planimetering of the diagram in Poda 2007, section 3.1).
    """
    p = np.asarray(pressure_Pa, dtype=float)
    v = np.asarray(volume_m3, dtype=float)
    _require(
        p.ndim == 1 and p.size >= 3,
        "pressure_Pa",
        f"array of shape {p.shape}",
        "a 1-D array of >= 3 samples",
    )
    _require(
        v.shape == p.shape, "volume_m3", f"shape {v.shape}", f"the shape of pressure_Pa {p.shape}"
    )
    _require(
        np.all(np.isfinite(p)) and np.all(np.isfinite(v)),
        "pressure_Pa/volume_m3",
        "non-finite values",
        "finite values",
    )
    p_closed = np.append(p, p[0])
    v_closed = np.append(v, v[0])
    return float(np.sum(0.5 * (p_closed[1:] + p_closed[:-1]) * np.diff(v_closed)))


#: The four-stroke cycle's gas-exchange strokes, deg: exhaust from BDC (540°) to TDC (720°), then
#: intake from TDC (0°) to BDC (180°), with α = 0 at the TDC that starts the intake (Poda 2007, §3.1).
PUMPING_STROKES_DEG = ((540.0, 720.0), (0.0, 180.0))


def pumping_work_J(pressure_Pa, volume_m3, crank_angle_deg, strokes: int, bdc_deg=180.0):
    """Work of the gas-exchange (pumping) strokes of one cycle, J: the part of the indicated work
    done during exhaust and intake; zero for a two-stroke cycle, which has no such strokes.

    Parameters
    ----------
    pressure_Pa, volume_m3 : array_like
        Cylinder pressure (Pa) and volume (m^3) over one cycle, as for :func:`indicated_work_J`.
    crank_angle_deg : array_like
        Their crank angles, deg: a uniform grid 0, h, ..., 720 − h (α = 0 at the TDC before intake).
    strokes : int
        2 or 4.
    bdc_deg : float, default 180
        BDC after each TDC, deg (:class:`CycleParameters`): the strokes run
        360° + BDC…720° and 0°…BDC.

    Returns
    -------
    float
        W_pump = integral of p dV over 540°…720° and 0°…180°, J (central crank-slider); negative when the cylinder exhausts
        at a higher pressure than it takes in (p_r > p_a).

    Notes
    -----
    The thermal calculation's mean indicated pressure covers the compression and expansion
    strokes only (its p_i′ is the closed form of those strokes, :func:`theoretical_mean_indicated_pressure_Pa`),
    the pumping losses being counted with the mechanical ones; the diagram's p_i to compare with
    it is therefore (W_i − W_pump) / V_h, the "gross" indicated work of Heywood (1988), §2.4.
    Same trapezoid rule as :func:`indicated_work_J`, with the ends of each stroke interpolated
    linearly where they fall between samples. For the theoretical diagram it equals
    (p_a − p_r) V_h, the pumping loop of :func:`theoretical_pressure_Pa`.
    """
    if strokes == 2:
        return 0.0
    _require(strokes == 4, "strokes", strokes, "2 or 4")
    p = np.asarray(pressure_Pa, dtype=float)
    v = np.asarray(volume_m3, dtype=float)
    a = np.asarray(crank_angle_deg, dtype=float)
    _require(
        a.shape == p.shape == v.shape and a.size >= 3,
        "crank_angle_deg",
        f"shape {a.shape}",
        f"the shape of pressure_Pa {p.shape}",
    )
    step = a[1] - a[0]
    _require(
        abs(a[0]) < 1e-9 * step and abs(a[-1] + step - 720.0) < 1e-6 * step,
        "crank_angle_deg",
        f"{a[0]:g} .. {a[-1]:g}",
        "a uniform grid from 0 to 720 deg less one step",
    )
    # the closed cycle: the first sample again at 720°
    a, p, v = np.append(a, 720.0), np.append(p, p[0]), np.append(v, v[0])
    work = 0.0
    exhaust, intake = PUMPING_STROKES_DEG
    strokes_deg = ((exhaust[0] + bdc_deg - 180.0, exhaust[1]), (intake[0], bdc_deg))
    for start, end in strokes_deg:
        inside = (a > start) & (a < end)
        ap = np.concatenate(([start], a[inside], [end]))
        pp, vp = np.interp(ap, a, p), np.interp(ap, a, v)
        work += float(np.sum(0.5 * (pp[1:] + pp[:-1]) * np.diff(vp)))
    return work


def mean_indicated_pressure_Pa(work_J, swept_volume_m3):
    """Mean indicated pressure from the indicated work.

    Parameters
    ----------
    work_J : float or array_like
        Indicated work per cycle, J.
    swept_volume_m3 : float
        Swept volume V_h, m^3, > 0.

    Returns
    -------
    float or numpy.ndarray
        p_i = W_i / V_h, Pa.

    Notes
    -----
    Poda (2007) section 3.1 (p_i' = L_i / V_h).
    """
    _require(
        np.isfinite(swept_volume_m3) and swept_volume_m3 > 0,
        "swept_volume_m3",
        swept_volume_m3,
        "> 0",
    )
    if np.ndim(work_J):
        return np.asarray(work_J, dtype=float) / swept_volume_m3
    return float(work_J) / swept_volume_m3


# ---------------------------------------------------------------------------
# Crank angle from volume
# ---------------------------------------------------------------------------
def _displacement_ratio(volume_m3, clearance_volume_m3, bore_m, crank_radius_m, rod_ratio):
    """Validated s/R and (2R - s)/R from the cylinder volume."""
    volume = np.asarray(volume_m3, dtype=float)
    _require(
        np.isfinite(clearance_volume_m3) and clearance_volume_m3 > 0,
        "clearance_volume_m3",
        clearance_volume_m3,
        "> 0",
    )
    _require(np.isfinite(bore_m) and bore_m > 0, "bore_m", bore_m, "> 0")
    _require(
        np.isfinite(crank_radius_m) and crank_radius_m > 0, "crank_radius_m", crank_radius_m, "> 0"
    )
    _require(
        np.isfinite(rod_ratio) and 0 < rod_ratio < 1,
        "rod_ratio",
        rod_ratio,
        "(0, 1) (lambda = R/L)",
    )
    area = 0.25 * np.pi * bore_m**2
    s_over_r = (volume - clearance_volume_m3) / (area * crank_radius_m)
    tol = 1e-9
    bad = ~np.isfinite(s_over_r) | (s_over_r < -tol) | (s_over_r > 2.0 + tol)
    v_max = clearance_volume_m3 + 2.0 * area * crank_radius_m
    _require(
        not np.any(bad),
        "volume_m3",
        _worst(volume, bad),
        f"[{clearance_volume_m3:.6g}, {v_max:.6g}] m^3 (V_c ... V_c + pi D^2/4 * 2R)",
    )
    s_over_r = np.clip(s_over_r, 0.0, 2.0)
    # distance from BDC computed from the volume directly (no cancellation)
    w_over_r = np.clip((v_max - volume) / (area * crank_radius_m), 0.0, 2.0)
    return s_over_r, w_over_r


def crank_angle_from_volume_approx_deg(
    volume_m3, clearance_volume_m3, bore_m, crank_radius_m, rod_ratio
):
    """Crank angle from cylinder volume, inverting the two-term displacement.

    Parameters
    ----------
    volume_m3 : float or array_like
        Cylinder volume, m^3, in [V_c, V_c + pi D^2/4 * 2R].
    clearance_volume_m3 : float
        Clearance volume V_c, m^3, > 0.
    bore_m : float
        Cylinder bore D, m, > 0.
    crank_radius_m : float
        Crank radius R, m, > 0.
    rod_ratio : float
        lambda = R / L, in (0, 1).

    Returns
    -------
    numpy.ndarray or float
        Crank angle alpha in [0, 180] deg.

    Notes
    -----
    Poda (2007) eq. (16) inverts eq. (9),
    s = R[(1 + lambda/4) - (cos a + lambda/4 cos 2a)],
    i.e. (lambda/2) c^2 + c - (1 + lambda/2 - s/R) = 0 with c = cos a:
    c = [sqrt(1 - 2 lambda (s/R - 1 - lambda/2)) - 1] / lambda.
    Evaluated here in the equivalent, well-conditioned form (derived)
    1 - c = 2 sigma / [(1+lambda) + sqrt((1+lambda)^2 - 2 lambda sigma)],
    1 + c = 2 omega / [(1-lambda) + sqrt((1-lambda)^2 + 2 lambda omega)],
    sigma = s/R, omega = 2 - sigma, a = 2 atan2(sqrt(1-c), sqrt(1+c)).
    """
    sigma, omega = _displacement_ratio(
        volume_m3, clearance_volume_m3, bore_m, crank_radius_m, rod_ratio
    )
    lam = rod_ratio
    one_minus_c = 2.0 * sigma / ((1.0 + lam) + np.sqrt((1.0 + lam) ** 2 - 2.0 * lam * sigma))
    one_plus_c = 2.0 * omega / ((1.0 - lam) + np.sqrt((1.0 - lam) ** 2 + 2.0 * lam * omega))
    angle = np.degrees(2.0 * np.arctan2(np.sqrt(one_minus_c), np.sqrt(one_plus_c)))
    return angle if np.ndim(volume_m3) else float(angle)


def crank_angle_from_volume_exact_deg(
    volume_m3, clearance_volume_m3, bore_m, crank_radius_m, rod_ratio
):
    """Crank angle from cylinder volume for the exact crank-slider kinematics.

    Parameters
    ----------
    volume_m3 : float or array_like
        Cylinder volume, m^3, in [V_c, V_c + pi D^2/4 * 2R].
    clearance_volume_m3 : float
        Clearance volume V_c, m^3, > 0.
    bore_m : float
        Cylinder bore D, m, > 0.
    crank_radius_m : float
        Crank radius R, m, > 0.
    rod_ratio : float
        lambda = R / L, in (0, 1).

    Returns
    -------
    numpy.ndarray or float
        Crank angle alpha in [0, 180] deg.

    Notes
    -----
    Derived.  Exact displacement s = R[(1 - cos a) + (1/lambda)(1 - cos b)],
    sin b = lambda sin a.  With x = 1 + 1/lambda - s/R = cos a + (1/lambda) cos b
    (the crank-centre to piston-pin distance over R), squaring
    (1/lambda) cos b = x - cos a cancels the cos^2 a terms, so the
    "quadratic" is linear: cos a = (x^2 + 1 - 1/lambda^2) / (2 x)
    (the law of cosines in the crank triangle).  The root satisfies
    x - cos a >= 0, i.e. it is the physical branch (cos b > 0).
    For conditioning near the dead centres it is evaluated as
    1 - cos a = sigma (2/lambda - sigma) / (2x), 1 + cos a = omega (2/lambda + omega) / (2x),
    a = 2 atan2(sqrt(1 - cos a), sqrt(1 + cos a)), with sigma = s/R, omega = 2 - sigma.
    """
    sigma, omega = _displacement_ratio(
        volume_m3, clearance_volume_m3, bore_m, crank_radius_m, rod_ratio
    )
    inv = 1.0 / rod_ratio
    one_minus_c = sigma * (2.0 * inv - sigma)
    one_plus_c = omega * (2.0 * inv + omega)
    # the common factor 1/(2x) cancels in atan2
    angle = np.degrees(2.0 * np.arctan2(np.sqrt(one_minus_c), np.sqrt(one_plus_c)))
    return angle if np.ndim(volume_m3) else float(angle)


# ---------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------
def _require(condition, name, value, allowed):
    """Raise ValueError naming the parameter, its value and the allowed range."""
    if not condition:
        raise ValueError(f"{name} = {value!r} is invalid; allowed: {allowed}")


def _worst(values, mask):
    """A short description of offending array entries for error messages."""
    values = np.asarray(values)
    mask = np.asarray(mask)
    if values.ndim == 0:
        return float(values)
    bad = values[mask] if mask.shape == values.shape else values
    if bad.size == 0:
        return "array"
    return f"{bad.size} offending value(s), e.g. {float(bad.flat[0]):.6g}"
