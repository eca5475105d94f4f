"""Articulated (master and slave) connecting rods: exact slave kinematics and bay statics.

Geometry (Poda 2007 §1.1 fig. 2, §3.3 fig. 11): the master rod runs from the crank pin B
to the master piston pin A on the master cylinder axis; the slave rod is hinged on the
master rod at the pin C, at distance ``pin_radius`` r from B and at angle ``pin_angle``
gamma_1 from the master rod axis, towards the slave cylinder, whose axis lies at the bank
angle gamma from the master axis (in the direction of rotation).

Vectors are written in the master cylinder frame: unit ``a`` along the master axis
(away from the shaft), unit ``n`` perpendicular to it, towards the slave bank. The
master crank angle alpha is measured from the master TDC in the direction of rotation,
so the crank pin is B = R (cos alpha, sin alpha).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from .extrema import first_argmin
from .scalar_search import brentq, minimize_bounded


@dataclass(frozen=True)
class SlaveGeometry:
    crank_radius_m: float
    rod_length_m: float  # master rod L
    pin_radius_m: float  # r
    pin_angle_rad: float  # gamma_1
    bank_angle_rad: float  # gamma, slave axis from the master axis
    slave_rod_length_m: float  # l


@dataclass(frozen=True)
class SlaveMotion:
    """Slave piston and pin motion over the given master crank angles (SI)."""

    pin_a_m: np.ndarray  # C in the master frame
    pin_n_m: np.ndarray
    pin_velocity_a_m_s: np.ndarray
    pin_velocity_n_m_s: np.ndarray
    piston_position_m: (
        np.ndarray
    )  # slave piston pin distance from the shaft axis along the slave axis
    piston_velocity_m_s: np.ndarray  # d(position)/dt
    piston_acceleration_m_s2: np.ndarray
    slave_rod_angle_rad: np.ndarray  # beta_l, textbook eq. (33)


def _master(alpha, R, L, w):
    lam = R / L
    sin_b = lam * np.sin(alpha)
    beta = np.arcsin(sin_b)
    cos_b = np.cos(beta)
    beta_dot = w * lam * np.cos(alpha) / cos_b
    beta_ddot = -(w**2) * lam * (1 - lam**2) * np.sin(alpha) / cos_b**3
    return beta, beta_dot, beta_ddot


def slave_motion(
    master_crank_angle_rad, geometry: SlaveGeometry, angular_velocity_rad_s: float = 1.0
) -> SlaveMotion:
    """Exact slave-piston kinematics from the linkage geometry (derived; eq. (33) for the rod angle).

    The pin is C = B + r (cos(gamma_1 - beta), sin(gamma_1 - beta)); the slave piston pin lies
    on the slave axis at x = C.a_s + sqrt(l^2 - (C.n_s)^2). Velocities and accelerations are the
    analytic time derivatives at constant crank speed.
    """
    g = geometry
    alpha = np.asarray(master_crank_angle_rad, dtype=float)
    R, L, r, w = g.crank_radius_m, g.rod_length_m, g.pin_radius_m, angular_velocity_rad_s
    beta, bd, bdd = _master(alpha, R, L, w)
    phi = g.pin_angle_rad - beta
    # Crank pin B and its derivatives.
    Ba, Bn = R * np.cos(alpha), R * np.sin(alpha)
    Ba_d, Bn_d = -R * w * np.sin(alpha), R * w * np.cos(alpha)
    Ba_dd, Bn_dd = -R * w**2 * np.cos(alpha), -R * w**2 * np.sin(alpha)
    # Pin C = B + r e(phi), phi' = -beta'.
    Ca, Cn = Ba + r * np.cos(phi), Bn + r * np.sin(phi)
    Ca_d = Ba_d + r * np.sin(phi) * bd
    Cn_d = Bn_d - r * np.cos(phi) * bd
    Ca_dd = Ba_dd + r * (np.sin(phi) * bdd - np.cos(phi) * bd**2)
    Cn_dd = Bn_dd - r * (np.cos(phi) * bdd + np.sin(phi) * bd**2)
    # Slave axis frame.
    cg, sg = np.cos(g.bank_angle_rad), np.sin(g.bank_angle_rad)
    ca, cn = Ca * cg + Cn * sg, -Ca * sg + Cn * cg
    ca_d, cn_d = Ca_d * cg + Cn_d * sg, -Ca_d * sg + Cn_d * cg
    ca_dd, cn_dd = Ca_dd * cg + Cn_dd * sg, -Ca_dd * sg + Cn_dd * cg
    l = g.slave_rod_length_m
    if np.any(np.abs(cn) >= l):
        raise ValueError(
            "the slave rod cannot reach its cylinder axis: slave_rod_length is too short for this pin"
        )
    root = np.sqrt(l**2 - cn**2)
    x = ca + root
    x_d = ca_d - cn * cn_d / root
    x_dd = ca_dd - (cn_d**2 + cn * cn_dd) / root - (cn * cn_d) ** 2 / root**3
    return SlaveMotion(
        pin_a_m=Ca,
        pin_n_m=Cn,
        pin_velocity_a_m_s=Ca_d,
        pin_velocity_n_m_s=Cn_d,
        piston_position_m=x,
        piston_velocity_m_s=x_d,
        piston_acceleration_m_s2=x_dd,
        slave_rod_angle_rad=np.arcsin(cn / l),
    )


@functools.lru_cache(maxsize=4096)
def slave_dead_centres(geometry: SlaveGeometry) -> tuple[float, float, float, float]:
    """(x_tdc_m, master angle at slave TDC rad, x_bdc_m, master angle at slave BDC rad).

    Located on a dense grid and refined by Brent's root search on the analytic piston velocity
    (zero at a dead centre), so the angles are exact to round-off (a search on the flat position
    itself finds them only to ~1e-8 rad).

    Remembered per geometry (a frozen, hashable value; the answer is a tuple of floats): an
    articulated engine's run asks for the same slaves' dead centres again and again (the slave rod
    length of equal compression is solved for in every run of the bays stage, and the numerics study
    runs that stage once per angle step, the drawing's geometry once more).
    """
    grid = np.linspace(0.0, 2 * np.pi, 3601)[:-1]
    x = slave_motion(grid, geometry).piston_position_m
    out = []

    def velocity(a):
        return float(slave_motion(np.array([a]), geometry).piston_velocity_m_s[0])

    for sign in (-1.0, 1.0):  # maximum of x (TDC), then minimum (BDC)
        i = first_argmin(sign * x)
        lo, hi = grid[i] - 2 * np.pi / 3600, grid[i] + 2 * np.pi / 3600
        if velocity(lo) * velocity(hi) < 0:
            a = brentq(velocity, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
        else:  # no sign change across the bracket (not expected): the bounded search on the position
            a = minimize_bounded(
                lambda t: sign * float(slave_motion(np.array([t]), geometry).piston_position_m[0]),  # noqa: B023 - called within this iteration
                lo,
                hi,
                xatol=1e-12,
            ).x
        out += [
            float(slave_motion(np.array([a]), geometry).piston_position_m[0]),
            float(a) % (2 * np.pi),
        ]
    return out[0], out[1], out[2], out[3]


def slave_acceleration_harmonics(
    geometry: SlaveGeometry, max_order: int, samples: int = 1024
) -> np.ndarray:
    """Fourier coefficients A_n, n = 0 .. max_order, of a slave piston's acceleration over R w^2.

    ``j(alpha) = R w^2 Re(sum_n A_n exp(i n alpha))`` with ``j`` positive towards the shaft at the
    cylinder's nominal TDC and ``alpha`` the crank angle from the slave axis (the master's angle
    minus the bank angle gamma), the convention of
    :func:`crankdyn.physics.balancing.acceleration_harmonics`. By the FFT of the exact
    acceleration (:func:`slave_motion`): it is analytic and periodic, so the coefficients are exact
    to round-off once ``samples`` exceeds twice the highest order that matters. A slave's first
    harmonic is the master's; its second is larger and out of phase with it.
    """
    if samples <= 2 * max_order:
        raise ValueError("samples must exceed twice max_order")
    alpha = 2 * np.pi * np.arange(samples) / samples
    motion = slave_motion(alpha + geometry.bank_angle_rad, geometry, 1.0)
    j = -motion.piston_acceleration_m_s2 / geometry.crank_radius_m
    spectrum = np.fft.rfft(j) / samples
    coefficients = 2.0 * spectrum[: max_order + 1]
    coefficients[0] = spectrum[0]
    return coefficients


def slave_rod_length_textbook_m(
    rod_length_m: float, pin_radius_m: float, rod_ratio: float, bank_angle_rad: float
) -> float:
    """Poda (2007) eq. (3), with gamma_1 = gamma: l = (L - r)/cos(phi),
    phi = arctan(2 sqrt(L r) sin(beta_1/2)/(L - r)), beta_1 = arcsin(lambda sin gamma)."""
    beta1 = np.arcsin(rod_ratio * np.sin(bank_angle_rad))
    phi = np.arctan(
        2 * np.sqrt(rod_length_m * pin_radius_m) * np.sin(beta1 / 2) / (rod_length_m - pin_radius_m)
    )
    return float((rod_length_m - pin_radius_m) / np.cos(phi))


def pin_angle_textbook_rad(
    compression_ratio: float, rod_ratio: float, bank_angle_rad: float
) -> float:
    """Poda (2007) eq. (5): gamma_1 = gamma + arcsin((eps-1) lambda sin gamma / ((eps+1) + 2 sqrt(eps (1 - lambda^2 sin^2 gamma))))."""
    s = rod_ratio * np.sin(bank_angle_rad)
    eps = compression_ratio
    return float(
        bank_angle_rad + np.arcsin((eps - 1) * s / ((eps + 1) + 2 * np.sqrt(eps * (1 - s**2))))
    )


def deck_height_m(crank_radius_m: float, rod_length_m: float, compression_ratio: float) -> float:
    """Distance of every cylinder's head from the shaft axis along its own axis, m.

    H = R + L + S/(eps - 1), S = 2R: the master piston pin at TDC is R + L from the axis and the
    clearance S/(eps - 1) above it gives the master cylinder its compression ratio eps (derived from
    V_c = F S/(eps - 1), Poda 2007 eq. (11)).
    """
    return crank_radius_m + rod_length_m + 2 * crank_radius_m / (compression_ratio - 1)


def slave_cylinder_volume_m3(
    master_crank_angle_rad, geometry: SlaveGeometry, deck_height: float, piston_area_m2: float
):
    """Volume of a slave cylinder at the master crank angles, m^3: V = F (H - x).

    ``x`` is the slave piston pin's distance from the shaft axis along the slave axis
    (:func:`slave_motion`) and ``H`` the head's (:func:`deck_height_m`); the piston pin stands for
    the crown, which is a constant distance above it in every cylinder alike.
    """
    x = slave_motion(master_crank_angle_rad, geometry).piston_position_m
    return piston_area_m2 * (deck_height - x)


def slave_rod_length_equal_compression_m(
    geometry: SlaveGeometry, compression_ratio: float
) -> float:
    """Slave rod length giving the slave cylinder the master's compression ratio exactly.

    All cylinders share the deck height H = R + L + S/(eps - 1) above the shaft axis (S = 2R);
    the slave's ratio is (H - x_bdc)/(H - x_tdc). Solved for l by Brent's method.
    """
    R, L = geometry.crank_radius_m, geometry.rod_length_m
    deck = deck_height_m(R, L, compression_ratio)

    def mismatch(length):
        # ratio of the slave cylinder minus the target
        g = SlaveGeometry(
            R, L, geometry.pin_radius_m, geometry.pin_angle_rad, geometry.bank_angle_rad, length
        )
        x_tdc, _, x_bdc, _ = slave_dead_centres(g)
        return (deck - x_bdc) / (deck - x_tdc) - compression_ratio

    # The slave TDC rises almost one-for-one with l: the ratio grows from small values
    # (long clearance) to infinity as the clearance closes. Bracket that branch.
    start = L - geometry.pin_radius_m
    g0 = SlaveGeometry(
        R, L, geometry.pin_radius_m, geometry.pin_angle_rad, geometry.bank_angle_rad, start
    )
    gap = deck - slave_dead_centres(g0)[0]
    hi = start + 0.9 * gap
    lo = start + 0.9 * gap - 2 * R
    for _ in range(60):
        if mismatch(hi) > 0:
            break
        hi = hi + 0.5 * (start + gap - hi)
    else:
        raise ValueError("no slave rod length gives the master's compression ratio")
    # The rod must reach the slave axis at every crank angle: l > max |C . n_s| (independent of l).
    probe = SlaveGeometry(
        R, L, geometry.pin_radius_m, geometry.pin_angle_rad, geometry.bank_angle_rad, 10 * (L + R)
    )
    motion = slave_motion(np.linspace(0, 2 * np.pi, 7201), probe)
    cg, sg = np.cos(geometry.bank_angle_rad), np.sin(geometry.bank_angle_rad)
    shortest = float(np.max(np.abs(-motion.pin_a_m * sg + motion.pin_n_m * cg))) * (1 + 1e-6)
    lo = max(lo, shortest)
    while mismatch(lo) > 0:
        if lo <= shortest:
            raise ValueError(
                "no slave rod length gives the master's compression ratio with this pin "
                "(the rod would have to be shorter than its reach to the slave axis)"
            )
        lo = max(lo - 2 * R, shortest)
    return float(brentq(mismatch, lo, hi, xtol=1e-13))


def reduced_master_rod_masses(
    master_rod_kg: float,
    master_cm_from_big_end_m: float,
    rod_length_m: float,
    slave_rotating_kg: float,
    slave_pin_kg: float,
    pin_radius_m: float,
    pin_angle_rad: float,
) -> tuple[float, float]:
    """(reciprocating, rotating) masses of the reduced master rod, Poda (2007) §3.2 (fig. 9).

    The slave rod's rotating part and its pin sit at C; b_2 = r cos gamma_1 is their distance
    from the big end along the master rod, b_1 = L - b_2 (statically equivalent split).
    """
    b2 = pin_radius_m * np.cos(pin_angle_rad)
    b1 = rod_length_m - b2
    lumped = slave_rotating_kg + slave_pin_kg
    l_r = master_cm_from_big_end_m
    reciprocating = (master_rod_kg * l_r + lumped * b2) / rod_length_m
    rotating = (master_rod_kg * (rod_length_m - l_r) + lumped * b1) / rod_length_m
    return float(reciprocating), float(rotating)


def bay_crank_pin_forces(
    master_crank_angle_rad,
    master_rod_angle_rad,
    master_total_Pa,
    crank_radius_m,
    rod_length_m,
    slaves: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]],
):
    """Forces of a whole bay on the crank pin by statics of the master rod (specific, Pa).

    ``slaves``: for every slave cylinder (pin_a_m, pin_n_m, slave_rod_angle_rad, total_Pa,
    bank_angle_rad) on the master angle grid. The master rod carries the master piston
    force p1 along the master axis and the wall reaction N at A, each slave rod's force
    K_l = p1_l / cos(beta_l) at C, and the crank-pin reaction at B; moments about B fix N.
    Returns (tangential_Pa, radial_Pa, master_side_Pa) with the textbook signs: t in the
    direction of rotation, z towards the shaft axis, n as in eq. (22)/(28).

    For one cylinder it reduces to eq. (22)-(25); with slaves it reproduces eq. (27)-(30).
    """
    alpha = np.asarray(master_crank_angle_rad, dtype=float)
    beta = np.asarray(master_rod_angle_rad, dtype=float)
    p1 = np.asarray(master_total_Pa, dtype=float)
    L = rod_length_m
    Ba, Bn = crank_radius_m * np.cos(alpha), crank_radius_m * np.sin(alpha)
    # Moment of the slave forces about B, and their sum.
    moment = np.zeros_like(alpha)
    Fa = -p1.copy()
    Fn = np.zeros_like(alpha)
    for pin_a, pin_n, slave_beta, slave_p1, gamma in slaves:
        k = slave_p1 / np.cos(slave_beta)
        direction = gamma - slave_beta  # of the slave rod from C towards the slave piston, from a
        fa, fn = -k * np.cos(direction), -k * np.sin(direction)
        moment += (pin_a - Ba) * fn - (pin_n - Bn) * fa
        Fa += fa
        Fn += fn
    # (A-B) x F_A with A-B = L (cos b, -sin b), F_A = (-p1, N):  L cos b N - L sin b p1.
    side = (L * np.sin(beta) * p1 - moment) / (L * np.cos(beta))
    Fn += side
    tangential = -Fa * np.sin(alpha) + Fn * np.cos(alpha)
    radial = -(Fa * np.cos(alpha) + Fn * np.sin(alpha))
    return tangential, radial, side


def bay_tangential_contributions(
    master_crank_angle_rad,
    master_rod_angle_rad,
    master_total_Pa,
    crank_radius_m,
    rod_length_m,
    slaves: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]],
) -> list[np.ndarray]:
    """Each cylinder's part of the bay's tangential force on the crank pin (specific, Pa): the
    master cylinder's first, then every slave's in the order of ``slaves``.

    The master rod's statics (:func:`bay_crank_pin_forces`, same arguments) is linear in the
    piston forces, so a cylinder's part is the bay's force with that cylinder's force alone; the
    parts sum to the bay's t. By virtual work each part is that piston's force times its
    piston's displacement per radian of the crank, divided by R (the rods massless)."""
    alpha = np.asarray(master_crank_angle_rad, dtype=float)
    zero = np.zeros_like(alpha)
    master, _, _ = bay_crank_pin_forces(
        alpha,
        master_rod_angle_rad,
        master_total_Pa,
        crank_radius_m,
        rod_length_m,
        [(a, n, b, zero, g) for a, n, b, _, g in slaves],
    )
    parts = [master]
    for pin_a, pin_n, slave_beta, slave_p1, gamma in slaves:
        alone, _, _ = bay_crank_pin_forces(
            alpha,
            master_rod_angle_rad,
            zero,
            crank_radius_m,
            rod_length_m,
            [(pin_a, pin_n, slave_beta, slave_p1, gamma)],
        )
        parts.append(alone)
    return parts
