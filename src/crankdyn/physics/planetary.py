"""Planetary crank mechanisms: the rod's big end on an epicycloid or a hypocycloid.

The carrier (planet carrier, "водило") is the crank and turns with the shaft. A planet gear
on the carrier rolls on a fixed gear: outside a fixed sun gear (``gear = "external"``) or
inside a fixed ring gear (``gear = "internal"``). The rod's big end is hinged on the planet
at the pin radius ``e`` from the planet centre, so it runs on an epicycloid or a
hypocycloid (a curtate or prolate one unless the pin lies on the pitch circle); the small
end slides on the cylinder axis through the shaft axis. The gear ratio of the fixed gear to
the planet (tooth counts or pitch diameters) and the pin radius are the design parameters
(Ismailov, figs. 1-3).

Frame and conventions: those of :mod:`crankdyn.physics.rod_dynamics` (origin on the shaft
axis, ``z`` towards the cylinder head, ``x`` in the direction the carrier tip moves at the
top). ``phi`` is the carrier angle from the cylinder axis in the direction of rotation; the
planet centre is C = a (sin phi, cos phi). The pin's angle in the fixed frame is
``theta = psi0 + k phi``, where ``psi0`` (the pin phase) is its angle from the carrier line
at phi = 0 and ``k = omega_planet / omega`` the planet's speed ratio.

References
----------
Ismailov, O. R. Determination and evaluation of the kinematics of crank mechanisms of
different schemes (in Uzbek, abstracts in Russian and English). The source gives the
schemes and trajectories (figs. 1-3) but no formulas for the planetary mechanism; every
relation here was derived for crankdyn (rolling without slip, loop closure, statics of the
planet) and is checked in the tests (straight-line hypocycloid, finite differences,
virtual work).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import NamedTuple

import numpy as np

from .extrema import first_argmax
from .rod_dynamics import SliderMotion, slider_from_big_end
from .scalar_search import brentq, minimize_bounded

__all__ = [
    "PlanetaryGeometry",
    "carrier_radius_m",
    "planet_speed_ratio",
    "motion_period_revolutions",
    "big_end_path",
    "slider_motion",
    "DeadCentres",
    "dead_centres",
    "Reversal",
    "piston_reversals",
    "sign_changes",
    "lateral_reach_m",
    "ForceTransmission",
    "force_transmission",
    "rod_line_distance_m",
]

GEARS = ("external", "internal")


def _as_float_array(value):
    return np.asarray(value, dtype=float)


def _sign(gear: str) -> float:
    if gear not in GEARS:
        raise ValueError(f"gear must be one of {GEARS}")
    return 1.0 if gear == "external" else -1.0


def carrier_radius_m(gear, fixed_pitch_radius_m, planet_pitch_radius_m):
    r"""Distance a from the shaft axis to the planet centre.

    Returns
    -------
    float
        :math:`a = r_f + r_p` (external mesh) or :math:`a = r_f - r_p` (internal mesh) [m].

    Notes
    -----
    The pitch circles touch: outside each other for a sun gear, the planet inside the
    ring for a ring gear (which needs r_p < r_f).
    """
    s = _sign(gear)
    r_f, r_p = float(fixed_pitch_radius_m), float(planet_pitch_radius_m)
    if r_f <= 0 or r_p <= 0:
        raise ValueError("pitch radii must be positive")
    if s < 0 and r_p >= r_f:
        raise ValueError("a planet inside a ring gear must be smaller than the ring")
    return r_f + s * r_p


def planet_speed_ratio(gear, fixed_pitch_radius_m, planet_pitch_radius_m):
    r"""Absolute angular velocity of the planet over that of the carrier.

    Returns
    -------
    float
        :math:`k = 1 + r_f/r_p` (external) or :math:`k = 1 - r_f/r_p` (internal).

    Notes
    -----
    Derived from rolling without slip: the planet's point on the pitch point K is at
    rest, v_C + omega_p x (K - C) = 0 with |v_C| = omega a. For the ring gear k < 0:
    the planet turns against the carrier (k = -1 for the ratio 2:1).
    """
    s = _sign(gear)
    carrier_radius_m(gear, fixed_pitch_radius_m, planet_pitch_radius_m)  # validates
    return 1.0 + s * float(fixed_pitch_radius_m) / float(planet_pitch_radius_m)


def motion_period_revolutions(gear_ratio, tolerance=1e-9, max_denominator=1000):
    r"""Number of carrier revolutions after which the mechanism repeats its motion.

    Parameters
    ----------
    gear_ratio : float or fractions.Fraction
        r_f / r_p = z_f / z_p.

    Returns
    -------
    int or None
        The denominator q of the ratio in lowest terms (the pin returns to the same place
        relative to the carrier after q revolutions, when the planet has turned q r_f/r_p
        times relative to the carrier); None if the ratio is not a fraction with a
        denominator up to ``max_denominator`` within ``tolerance`` (relative).
    """
    if isinstance(gear_ratio, Fraction):
        return gear_ratio.denominator
    ratio = float(gear_ratio)
    fraction = Fraction(ratio).limit_denominator(max_denominator)
    if abs(float(fraction) - ratio) > tolerance * abs(ratio):
        return None
    return fraction.denominator


@dataclass(frozen=True)
class PlanetaryGeometry:
    """A planetary crank mechanism (SI; angles in rad)."""

    gear: str  # "external" (fixed sun: epicycloid) or "internal" (fixed ring: hypocycloid)
    fixed_pitch_radius_m: float
    planet_pitch_radius_m: float
    pin_radius_m: float
    pin_phase_rad: float
    rod_length_m: float

    @property
    def carrier_radius_m(self) -> float:
        return carrier_radius_m(self.gear, self.fixed_pitch_radius_m, self.planet_pitch_radius_m)

    @property
    def planet_speed_ratio(self) -> float:
        return planet_speed_ratio(self.gear, self.fixed_pitch_radius_m, self.planet_pitch_radius_m)

    @property
    def gear_ratio(self) -> float:
        return self.fixed_pitch_radius_m / self.planet_pitch_radius_m

    @property
    def mesh_sign(self) -> float:
        return _sign(self.gear)


def big_end_path(carrier_angle_rad, geometry: PlanetaryGeometry):
    r"""Position of the rod's big end (the pin on the planet) and its carrier-angle derivatives.

    Parameters
    ----------
    carrier_angle_rad : array_like
        phi [rad].
    geometry : PlanetaryGeometry

    Returns
    -------
    x, z, x_d1, z_d1, x_d2, z_d2 : numpy.ndarray
        B [m], dB/d(phi) [m/rad], d^2B/d(phi)^2 [m/rad^2].

    Notes
    -----
    Derived:

    .. math::
        B = a(\sin\varphi, \cos\varphi) + e(\sin\theta, \cos\theta),\quad
        \theta = \psi_0 + k\varphi,

    an epicycloid (k > 1) or hypocycloid (k < 0), traced with the pin on the pitch
    circle (e = r_p) and curtate or prolate otherwise. For the ring gear with
    r_f = 2 r_p (k = -1, a = r_p) and e = r_p,
    :math:`B = 2r_p\cos(\varphi - \psi_0/2)(\sin\tfrac{\psi_0}{2}, \cos\tfrac{\psi_0}{2})`:
    a straight line through the shaft axis (Cardan's circles), along the cylinder axis for
    psi0 = 0, where the piston moves harmonically.
    """
    phi = _as_float_array(carrier_angle_rad)
    a, e, k = geometry.carrier_radius_m, geometry.pin_radius_m, geometry.planet_speed_ratio
    theta = geometry.pin_phase_rad + k * phi
    sp, cp, st, ct = np.sin(phi), np.cos(phi), np.sin(theta), np.cos(theta)
    return (
        a * sp + e * st,
        a * cp + e * ct,
        a * cp + e * k * ct,
        -a * sp - e * k * st,
        -a * sp - e * k * k * st,
        -a * cp - e * k * k * ct,
    )


def slider_motion(carrier_angle_rad, geometry: PlanetaryGeometry) -> SliderMotion:
    """Piston pin and rod angle (see :func:`crankdyn.physics.rod_dynamics.slider_from_big_end`)."""
    x, z, x_d1, z_d1, x_d2, z_d2 = big_end_path(carrier_angle_rad, geometry)
    return slider_from_big_end(x, z, x_d1, z_d1, x_d2, z_d2, geometry.rod_length_m)


def lateral_reach_m(geometry: PlanetaryGeometry, revolutions: int = 1) -> float:
    r"""Largest distance of the big end from the cylinder axis, max |x_B|, over the motion.

    Notes
    -----
    A dense sample refined with a bounded scalar search; it never exceeds a + e.
    """
    n = 4096 * max(int(revolutions), 1)
    phi = np.linspace(0.0, 2.0 * np.pi * max(int(revolutions), 1), n, endpoint=False)
    x = np.abs(big_end_path(phi, geometry)[0])
    i = first_argmax(x)
    step = phi[1] - phi[0]
    best = minimize_bounded(
        lambda p: -abs(float(big_end_path(p, geometry)[0])),
        phi[i] - step,
        phi[i] + step,
        xatol=1e-13,
    )
    return float(max(x[i], -best.fun))


class DeadCentres(NamedTuple):
    """Extremes of the piston-pin height over one period of the motion."""

    tdc_carrier_angle_rad: float
    bdc_carrier_angle_rad: float
    tdc_height_m: float
    bdc_height_m: float
    stroke_m: float


def _refine_extreme(phi_i, step, geometry, sign):
    def slope(p):
        return float(slider_motion(p, geometry).pin_z_d1_m)

    lo, hi = phi_i - step, phi_i + step
    f_lo, f_hi = slope(lo), slope(hi)
    if f_lo == 0.0:
        return lo
    if f_hi == 0.0:
        return hi
    if np.sign(f_lo) != np.sign(f_hi):
        return brentq(slope, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
    result = minimize_bounded(
        lambda p: -sign * float(slider_motion(p, geometry).pin_z_m), lo, hi, xatol=1e-13
    )
    return float(result.x)


def dead_centres(geometry: PlanetaryGeometry, revolutions: int = 1) -> DeadCentres:
    r"""TDC and BDC (global extremes of the piston-pin height) and the stroke.

    Parameters
    ----------
    geometry : PlanetaryGeometry
    revolutions : int
        Period of the motion in carrier revolutions (:func:`motion_period_revolutions`).

    Returns
    -------
    DeadCentres
        Carrier angles in [0, 2 pi revolutions) of the first global maximum and minimum.

    Notes
    -----
    Derived: for psi0 = 0 the carrier angle 0 is TDC exactly, because
    z_A = z_B + sqrt(L^2 - x_B^2) <= |B| + L <= a + e + L with equality only when the
    pin is on the cylinder axis at its outermost point (phi = 0). Otherwise the extremes
    are found on a dense sample and refined with Brent's method on dz_A/d(phi).
    """
    turns = max(int(revolutions), 1)
    n = 4096 * turns
    phi = np.linspace(0.0, 2.0 * np.pi * turns, n, endpoint=False)
    z = slider_motion(phi, geometry).pin_z_m
    step = phi[1] - phi[0]
    # Symmetric mechanisms reach the same extreme more than once; take the first one.
    tie = 1e-9 * float(np.max(z) - np.min(z))
    first_max = int(np.flatnonzero(z >= np.max(z) - tie)[0])
    first_min = int(np.flatnonzero(z <= np.min(z) + tie)[0])
    if geometry.pin_phase_rad == 0.0:
        tdc = 0.0
    else:
        tdc = _refine_extreme(phi[first_max], step, geometry, +1.0) % (2.0 * np.pi * turns)
    bdc = _refine_extreme(phi[first_min], step, geometry, -1.0) % (2.0 * np.pi * turns)
    z_tdc = float(slider_motion(tdc, geometry).pin_z_m)
    z_bdc = float(slider_motion(bdc, geometry).pin_z_m)
    return DeadCentres(float(tdc), float(bdc), z_tdc, z_bdc, z_tdc - z_bdc)


def sign_changes(function, period_rad: float, samples: int = 4096) -> list[float]:
    r"""Angles in [0, period) where a smooth periodic function of the carrier angle changes sign.

    Parameters
    ----------
    function : callable
        f(phi) for an array or a float phi [rad].
    period_rad : float
    samples : int
        Points of the scan; a pair of roots closer than the step may be missed.

    Returns
    -------
    list of float
        The roots, ascending, each refined with Brent's method. A root where the function only
        touches zero (an even-order root) is not a sign change and is not returned.

    Notes
    -----
    The scan is offset by half a step, so that a root on a round angle (0, pi) falls between two
    samples rather than on one, where its sign would be ambiguous.
    """
    step = period_rad / samples
    phi = (np.arange(samples) + 0.5) * step
    values = _as_float_array(function(phi))
    following = np.roll(values, -1)
    found = []
    for i in np.flatnonzero(np.sign(values) * np.sign(following) < 0):
        lo = phi[i]
        hi = lo + step

        def scalar(p):
            return float(function(p))

        root = brentq(scalar, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
        found.append(float(root % period_rad))
    return sorted(found)


class Reversal(NamedTuple):
    """A local extreme of the piston-pin height: the piston stops and reverses there."""

    carrier_angle_rad: float
    height_m: float
    kind: str  # "tdc" (a local maximum of the height) or "bdc" (a local minimum)


def piston_reversals(geometry: PlanetaryGeometry, revolutions: int = 1) -> list[Reversal]:
    r"""Every local extreme of the piston-pin height over one period, ascending in carrier angle.

    Returns
    -------
    list of Reversal
        The roots of dz_A/d(phi) where it changes sign: a maximum (+ to −) is a top dead
        centre, a minimum a bottom one. A conventional crank-slider has two per revolution; a
        planetary mechanism may have more (a secondary stroke between two bottom dead centres,
        e.g. z_B = a cos phi + e cos 2phi for a ring gear of ratio 3 with psi0 = 0).
    """
    period = 2.0 * np.pi * max(int(revolutions), 1)

    def slope(p):
        return slider_motion(p, geometry).pin_z_d1_m

    found = []
    for root in sign_changes(slope, period, 4096 * max(int(revolutions), 1)):
        root = 0.0 if min(root, period - root) < 1e-9 else root
        before, after = float(slope(root - 1e-4)), float(slope(root + 1e-4))
        kind = "tdc" if before > 0 > after else "bdc"
        found.append(Reversal(root, float(slider_motion(root, geometry).pin_z_m), kind))
    return sorted(found)


class ForceTransmission(NamedTuple):
    """Loads per unit axial piston force (positive towards the shaft), all dimensionless or in m.

    Attributes
    ----------
    carrier_torque_arm_m : torque on the carrier per unit piston force [m] (N m per N).
    rod_force : rod force per unit piston force, 1/cos(beta) (compression positive).
    rod_line_arm_m : signed distance from the shaft axis to the rod's line of action [m]
        (the source's arm MN; positive when the rod force alone would drive the carrier).
    tooth_tangential : tangential tooth force of the fixed gear on the planet, along the
        direction of rotation at the pitch point.
    tooth_radial : its separating component along the carrier line (outwards positive).
    carrier_tangential, carrier_radial : load of the planet on the carrier pin, in the
        direction of rotation and towards the shaft axis.
    """

    carrier_torque_arm_m: np.ndarray
    rod_force: np.ndarray
    rod_line_arm_m: np.ndarray
    tooth_tangential: np.ndarray
    tooth_radial: np.ndarray
    carrier_tangential: np.ndarray
    carrier_radial: np.ndarray


def rod_line_distance_m(point_x_m, point_z_m, big_end_x_m, big_end_z_m, rod_angle_rad):
    r"""Signed distance of a point from the rod's line, measured like a moment arm.

    Returns
    -------
    numpy.ndarray
        :math:`(z_B - z_P)\sin\beta + (x_B - x_P)\cos\beta` [m]: the moment about P, in the
        direction of rotation, of a unit force along the rod pushing the big end away from
        the piston, (sin beta, -cos beta).
    """
    beta = _as_float_array(rod_angle_rad)
    dx = _as_float_array(big_end_x_m) - _as_float_array(point_x_m)
    dz = _as_float_array(big_end_z_m) - _as_float_array(point_z_m)
    return dz * np.sin(beta) + dx * np.cos(beta)


def force_transmission(
    carrier_angle_rad, geometry: PlanetaryGeometry, pressure_angle_rad=0.3490658503988659
):
    r"""How a unit axial piston force reaches the carrier.

    Parameters
    ----------
    carrier_angle_rad : array_like
        phi [rad].
    geometry : PlanetaryGeometry
    pressure_angle_rad : float
        Pressure angle of the gear mesh (sets the separating tooth force only); default 20 deg.

    Returns
    -------
    ForceTransmission

    Notes
    -----
    Derived from the statics of the (massless) rod and planet. The rod pushes the pin
    with :math:`F_P = (\tan\beta, -1)` per unit axial force. The planet is held by F_P at
    the pin P, the tooth force of the fixed gear at the pitch point K and the carrier's
    bearing force at its centre C; moments about C give the tangential tooth force
    :math:`f_t = -[(P - C)\times F_P]/(s\,r_p)` (s = +1 for the sun gear, -1 for the
    ring gear, K - C = -s r_p u), the pressure angle its separating part
    :math:`f_r = s|f_t|\tan\alpha_w`. The carrier pin carries F_P + F_K, so the carrier
    torque is :math:`M = a\,(F_P + F_K)\cdot t`, t = (cos phi, -sin phi). By virtual work
    M = ds/d(alpha) for a unit force — the tests check this identity. The rod's moment
    about the shaft axis alone, F_P's arm (the source's MN, fig. 3), is not the carrier
    torque: the fixed gear's tooth force at K = r_f u adds :math:`r_f f_t`.
    """
    phi = _as_float_array(carrier_angle_rad)
    x, z, *_ = big_end_path(phi, geometry)
    slider = slider_motion(phi, geometry)
    beta = slider.rod_angle_rad
    tan_b = np.tan(beta)
    s = geometry.mesh_sign
    a, r_p, e = geometry.carrier_radius_m, geometry.planet_pitch_radius_m, geometry.pin_radius_m
    theta = geometry.pin_phase_rad + geometry.planet_speed_ratio * phi
    u = (np.sin(phi), np.cos(phi))
    t = (np.cos(phi), -np.sin(phi))
    fp = (tan_b, -np.ones_like(tan_b))
    # (P - C) x F_P, counter-clockwise positive: x F_z - z F_x
    moment_c = e * np.sin(theta) * fp[1] - e * np.cos(theta) * fp[0]
    f_t = -moment_c / (s * r_p)
    f_r = s * np.abs(f_t) * np.tan(float(pressure_angle_rad))
    load = (fp[0] + f_t * t[0] + f_r * u[0], fp[1] + f_t * t[1] + f_r * u[1])
    tangential = load[0] * t[0] + load[1] * t[1]
    radial = -(load[0] * u[0] + load[1] * u[1])
    return ForceTransmission(
        carrier_torque_arm_m=a * tangential,
        rod_force=1.0 / np.cos(beta),
        rod_line_arm_m=rod_line_distance_m(0.0, 0.0, x, z, beta),
        tooth_tangential=f_t,
        tooth_radial=f_r,
        carrier_tangential=tangential,
        carrier_radial=radial,
    )
