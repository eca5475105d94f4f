"""Balancing of piston engines by dynamically equivalent vector models (Poda 2007 §6.1-6.2).

Frame and conventions
---------------------
* Forces act in the plane perpendicular to the crankshaft, seen from the free end. A vector
  in that plane is a complex number ``w = y + i x``: ``y`` is the engine's vertical (the
  axis of symmetry of a bay: the cylinder axis of an in-line engine, the bisector of the
  banks of a V, the middle bank of a W or Y, cylinder 1 of a radial), ``x`` is horizontal,
  positive in the direction in which a crank pin at the top moves. A vector at angle ``phi``
  from the vertical, measured in the direction of rotation, is ``exp(i phi)``, so turning
  with the shaft multiplies by ``exp(i theta)``.
* ``theta`` is the shaft angle: at ``theta = 0`` crank 1 points along the axis of cylinder 1
  (its TDC). Crank k trails crank 1 by ``crank_lag_deg[k]`` (see :mod:`crankdyn.physics.layout`),
  so cylinder i is at its own crank angle ``alpha_i = theta - delta_i`` with
  ``delta_i = lag_k(i) + psi_i`` (``psi_i`` its bank axis angle from bank 0).
* Reciprocating inertia forces are positive from the shaft towards the cylinder head
  (textbook §6); the force of cylinder i is ``m_s j(alpha_i)`` along its axis, where ``j`` is
  the piston acceleration (positive at TDC, towards the shaft).
* Positions along the shaft are measured from the middle of the crank row (the textbook's
  reference, the crankshaft's centre of mass), bay k at ``(k - (cranks - 1)/2) a``. A
  longitudinal moment is described by the planar vector ``m = sum z_i F_i`` (N*m): the couple
  acts in the plane through the shaft axis along ``m``, and its forces on the power-take-off
  side point along ``+m``. Its magnitude is the moment.

Harmonic (vector) model
-----------------------
The exact piston acceleration of a central crank-slider is the even Fourier series
``j = R w^2 (A1 cos a + A2 cos 2a + A4 cos 4a + A6 cos 6a + ...)`` with ``A1 = 1`` exactly
and (series in lambda, derived here)::

    A2 =  lambda + lambda^3/4 + 15 lambda^5/128 + 35 lambda^7/512 + ...
    A4 = -(lambda^3/4 + 3 lambda^5/16 + 35 lambda^7/256 + ...)
    A6 =  9 lambda^5/128 + 45 lambda^7/512 + ...
    A8 = -5 lambda^7/256 + ...

(the textbook keeps ``A1`` and ``A2 ~ lambda``, eq. 55-56). The force of order n of one
cylinder, ``C_n cos(n alpha_i) e_i`` with ``C_n = A_n m_s R w^2``, is the sum of two vectors of
constant length ``C_n/2`` turning at ``+n w`` and ``-n w``. Summed over the cylinders, the
resultant of order n is ``f exp(i n theta) + b exp(-i n theta)`` with the co-rotating
amplitude ``f = C_n/2 sum exp(i(phi_i - n delta_i))`` and the counter-rotating amplitude
``b = C_n/2 sum exp(i(phi_i + n delta_i))`` (``phi_i`` the cylinder axis angle from the
vertical). For a V bay these are the textbook's F and P (first order, eq. 64-66) and K and Z
(second order, eq. 74-76); for an in-line engine ``|f| = |b|`` and ``2f`` is the textbook's
fictitious resultant of the C_I (C_II) vectors. The hodograph is an ellipse with semi-axes
``|f| + |b|`` and ``||f| - |b||``; its x and y semi-axes (textbook A, B) are
``|f - conj(b)|`` and ``|f + conj(b)|``.

References
----------
Poda, V. B. (2007). Dynamic calculation and balancing of piston internal combustion
engines (in Ukrainian). Kharkiv: KhAI. §6, eqs. (54)-(82), figs. 26-33.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import kinematics as kin
from . import offset_crank as oc
from .layout import EngineLayout

ROMAN = {
    1: "I",
    2: "II",
    3: "III",
    4: "IV",
    5: "V",
    6: "VI",
    8: "VIII",
    10: "X",
    12: "XII",
    14: "XIV",
    16: "XVI",
}


def roman(order: int) -> str:
    """Roman numeral of a harmonic order (as the textbook names P_I, P_II)."""
    return ROMAN.get(order, str(order))


# --------------------------------------------------------------------------- piston acceleration series


def acceleration_harmonics(
    rod_ratio: float, max_order: int = 64, samples: int = 1024, offset_ratio: float = 0.0
) -> np.ndarray:
    """Fourier coefficients A_n of the exact piston acceleration, n = 0 .. max_order.

    ``j(alpha) = R w^2 sum_n A_n cos(n alpha)`` for the central crank-slider (derived here;
    the textbook's two-term form keeps A_1 = 1 and A_2 = lambda). Computed by the FFT of the
    exact closed form sampled at ``samples`` points: the function is analytic and periodic,
    so the coefficients are exact to machine precision once ``samples`` exceeds twice the
    highest order that matters (aliasing falls off like the coefficients themselves).

    Parameters
    ----------
    rod_ratio : float
        lambda = R/L, 0 < lambda < 1.
    max_order : int
        Highest order returned.
    samples : int
        FFT length (a power of two, > 2*max_order).
    offset_ratio : float
        k = e/L of an offset crank-slider (alpha then counts from its TDC). With k != 0 the
        acceleration is not even in alpha and the coefficients are complex,
        ``j = R w^2 Re(sum_n A_n exp(i n alpha))``, ``A_n = a_n - i b_n`` of
        ``a_n cos(n alpha) + b_n sin(n alpha)``; every order appears, odd ones too.

    Returns
    -------
    numpy.ndarray
        A_n for n = 0..max_order (dimensionless); real for k = 0, where odd n > 1 are zero to
        round-off.
    """
    if samples <= 2 * max_order:
        raise ValueError("samples must exceed twice max_order")
    alpha = 2 * np.pi * np.arange(samples) / samples
    if offset_ratio:
        j = oc.piston_acceleration_m_s2(alpha, 1.0, rod_ratio, offset_ratio, 1.0)
        spectrum = np.fft.rfft(j) / samples
        coefficients = 2.0 * spectrum[: max_order + 1]
        coefficients[0] = spectrum[0]
        return coefficients
    j = kin.piston_acceleration_exact_m_s2(alpha, 1.0, rod_ratio, 1.0)
    spectrum = np.fft.rfft(j) / samples
    real_coefficients = 2.0 * spectrum.real[: max_order + 1]
    real_coefficients[0] = spectrum.real[0]
    return real_coefficients


def acceleration_series(rod_ratio: float) -> dict[int, float]:
    """The power series of A_2, A_4, A_6, A_8 to O(lambda^7) (derived; see the module docstring)."""
    lam = rod_ratio
    return {
        1: 1.0,
        2: lam + lam**3 / 4 + 15 * lam**5 / 128 + 35 * lam**7 / 512,
        4: -(lam**3 / 4 + 3 * lam**5 / 16 + 35 * lam**7 / 256),
        6: 9 * lam**5 / 128 + 45 * lam**7 / 512,
        8: -5 * lam**7 / 256,
    }


def orders_needed(
    rod_ratio: float, tolerance: float = 1e-15, max_order: int = 512, offset_ratio: float = 0.0
) -> int:
    """Highest order whose A_n still exceeds ``tolerance`` (the series is truncated after it): an
    even order for the central crank-slider, any order with an offset (``offset_ratio`` k = e/L).

    The coefficients fall roughly like (lambda / (1 + sqrt(1 - lambda^2)))^n: order 18 for
    lambda = 0.28, about 250 for lambda = 0.99.
    """
    a = acceleration_harmonics(
        rod_ratio, max_order, samples=4 * max_order, offset_ratio=offset_ratio
    )
    orders = range(2, max_order + 1, 1 if offset_ratio else 2)
    significant = [n for n in orders if abs(a[n]) > tolerance]
    return max(significant) if significant else 2


def inertia_orders(highest_order: int, offset_ratio: float = 0.0) -> list[int]:
    """The orders of the reciprocating inertia force up to ``highest_order``: 1 and the even ones
    of the central crank-slider, every order of an offset one."""
    if offset_ratio:
        return list(range(1, highest_order + 1))
    return [1] + list(range(2, highest_order + 1, 2))


def harmonics_for(rod_ratio: float, highest_order: int, offset_ratio: float = 0.0) -> np.ndarray:
    """:func:`acceleration_harmonics` up to at least ``highest_order`` (and 12), exact to round-off."""
    top = max(int(highest_order), 12)
    samples = 1024
    while samples <= 4 * top:
        samples *= 2
    return acceleration_harmonics(rod_ratio, top, samples, offset_ratio)


# --------------------------------------------------------------------------- geometry


@dataclass(frozen=True)
class BalanceGeometry:
    """Where every cylinder and crank is, for the vector models (angles in rad, positions in units of a).

    ``cylinder_axis_rad`` phi_i: cylinder axis from the vertical; ``cylinder_phase_rad`` delta_i:
    shaft angle at which cylinder i is at its TDC (mod 2 pi); ``cylinder_position`` and
    ``crank_position``: along the shaft from the middle of the row, in units of the cylinder
    spacing a; ``crank_direction_rad`` kappa_k: direction of crank k at theta = 0.

    An engine with articulated rods has cylinders unlike the master: ``cylinder_weight`` is each
    cylinder's reciprocating mass over the reference m_s of :class:`Masses` and
    ``cylinder_harmonic_ratio[n, i]`` its acceleration's harmonic of order n over the reference
    (master) one, ``A_ni / A_n``, complex (a slave piston's second harmonic is larger and out of
    phase); None: like the reference in every cylinder.
    """

    cylinder_axis_rad: np.ndarray
    cylinder_phase_rad: np.ndarray
    cylinder_position: np.ndarray
    cylinder_bay: np.ndarray
    crank_direction_rad: np.ndarray
    crank_position: np.ndarray
    vertical_deg: float
    labels: tuple[str, ...] = ()
    cylinder_weight: np.ndarray | None = None
    cylinder_harmonic_ratio: np.ndarray | None = None

    @property
    def cylinders(self) -> int:
        return int(self.cylinder_axis_rad.shape[-1])

    @property
    def weights(self) -> np.ndarray:
        """Each cylinder's reciprocating mass over m_s (ones unless ``cylinder_weight`` is given)."""
        if self.cylinder_weight is None:
            return np.ones(self.cylinders)
        return np.asarray(self.cylinder_weight, dtype=float)

    def weights_for(self, order: int) -> np.ndarray:
        """Each cylinder's order-``order`` force over the reference cylinder's C_n: its mass ratio
        times its harmonic ratio (complex where a cylinder's harmonic is out of phase)."""
        if self.cylinder_harmonic_ratio is None or order >= len(self.cylinder_harmonic_ratio):
            return self.weights
        return self.weights * self.cylinder_harmonic_ratio[order]

    @property
    def cranks(self) -> int:
        return int(self.crank_direction_rad.shape[-1])


def vertical_axis_deg(layout: str, bank_angle_deg: float | None) -> float:
    """Bank-axis angle (from bank 0) of the engine's vertical: the symmetry axis of a bay."""
    if layout in ("inline", "radial"):
        return 0.0
    if layout == "boxer":
        return 90.0
    if bank_angle_deg is None:
        raise ValueError(f"the {layout} layout needs a bank angle")
    if layout in ("V", "X"):
        return 0.5 * float(bank_angle_deg)
    if layout in ("W", "Y"):
        return float(bank_angle_deg)
    raise ValueError(f"unknown layout {layout!r}")


def geometry(banks_deg, bays, crank_lags_deg, vertical_deg: float, labels=()) -> BalanceGeometry:
    """Geometry from each cylinder's bank-axis angle psi and bay, and each crank's lag (deg).

    ``crank_lags_deg`` may have leading dimensions (many crank arrangements at once, as the
    firing-order explorer uses); cylinder data are shared.
    """
    psi = np.radians(np.asarray(banks_deg, dtype=float))
    bays = np.asarray(bays, dtype=int)
    lags = np.radians(np.asarray(crank_lags_deg, dtype=float))
    cranks = lags.shape[-1]
    centre = 0.5 * (cranks - 1)
    vertical = math.radians(vertical_deg)
    return BalanceGeometry(
        cylinder_axis_rad=psi - vertical,
        cylinder_phase_rad=lags[..., bays] + psi,
        cylinder_position=bays - centre,
        cylinder_bay=bays,
        crank_direction_rad=-lags - vertical,
        crank_position=np.arange(cranks) - centre,
        vertical_deg=vertical_deg,
        labels=tuple(labels),
    )


def geometry_from_layout(layout: EngineLayout) -> BalanceGeometry:
    """The balancing geometry of an engine layout (textbook §6 assumptions 2-3: the banks of a
    bay lie in one plane, adjacent bays are one cylinder spacing apart)."""
    cylinders = layout.cylinders
    return geometry(
        [c.axis_deg for c in cylinders],
        [c.bay for c in cylinders],
        list(layout.crank_lag_deg),
        vertical_axis_deg(layout.layout, layout.bank_angle_deg),
        [c.label for c in cylinders],
    )


# --------------------------------------------------------------------------- vector models


@dataclass(frozen=True)
class OrderModel:
    """Resultant of one order: ``force(theta) = f e^{i n theta} + b e^{-i n theta}``, same for the moment.

    Amplitudes are complex in the frame of the module docstring, in units of the order's own
    amplitude (C for order 0 = rotating masses, C_n = A_n C_I otherwise) and, for moments,
    of the cylinder spacing a. ``order`` 0 denotes the rotating masses (they turn at +w).
    """

    order: int
    force_forward: complex | np.ndarray
    force_backward: complex | np.ndarray
    moment_forward: complex | np.ndarray
    moment_backward: complex | np.ndarray

    @property
    def speed(self) -> int:
        """Angular speed of the co-rotating vector, in multiples of w."""
        return 1 if self.order == 0 else self.order

    @property
    def force_max(self):
        return np.abs(self.force_forward) + np.abs(self.force_backward)

    @property
    def moment_max(self):
        return np.abs(self.moment_forward) + np.abs(self.moment_backward)

    def force(self, theta_rad):
        return _value(self.force_forward, self.force_backward, self.speed, theta_rad)

    def moment(self, theta_rad):
        return _value(self.moment_forward, self.moment_backward, self.speed, theta_rad)


def _value(forward, backward, speed, theta_rad):
    phase = np.exp(1j * speed * np.asarray(theta_rad, dtype=float))
    return forward * phase + backward * np.conj(phase)


def rotating_model(g: BalanceGeometry) -> OrderModel:
    """Centrifugal forces of the unbalanced rotating masses, one unit vector per crank (textbook §6.1, first stage).

    ``sum C_k = C sum exp(i kappa_k)`` turns with the shaft; so does its moment.
    """
    unit = np.exp(1j * g.crank_direction_rad)
    force = unit.sum(axis=-1)
    moment = (unit * g.crank_position).sum(axis=-1)
    zero = np.zeros_like(force)
    return OrderModel(0, force, zero, moment, zero)


def scaled(model: OrderModel, amplitude) -> OrderModel:
    """``model`` times a harmonic's amplitude ``A_n C_I``: the co-rotating parts times it, the
    counter-rotating ones times its conjugate (``Re(A e^{i n alpha}) = (A e^{i n alpha} +
    conj(A) e^{-i n alpha}) / 2``); a real amplitude scales both alike."""
    back = np.conj(amplitude)
    return OrderModel(
        model.order,
        model.force_forward * amplitude,
        model.force_backward * back,
        model.moment_forward * amplitude,
        model.moment_backward * back,
    )


def internal_moment_max(g: BalanceGeometry) -> float:
    r"""The largest internal moment of the cranks' centrifugal forces along the shaft, in units
    of C a (one crank's centrifugal force times the cylinder spacing).

    Where the centrifugal forces and their moment are free of resultant (balanced by the crank
    arrangement), the cranks on either side of a cross-section of the shaft still bend it and
    the crankcase with the moment

    .. math:: M(x) = C\,a \sum_{x_k < x} e^{i\kappa_k}\,(x - x_k),

    the same from either side. :math:`|M(x)|` is convex between two cranks (a vector linear in
    x), so its largest value is at a crank's plane; e.g. 1 for an in-line four (cranks 0, 180,
    180, 0°), :math:`\sqrt{3}` for an in-line six. Poda (2007) section 6: counterweights on
    the webs relieve the main bearings and the crankcase of these internal moments.
    """
    unit = np.exp(1j * np.asarray(g.crank_direction_rad, dtype=float))
    x = np.asarray(g.crank_position, dtype=float)
    return max(
        (float(abs(np.sum(unit[:j] * (x[j] - x[:j])))) for j in range(1, len(x))), default=0.0
    )


def reciprocating_model(g: BalanceGeometry, order: int) -> OrderModel:
    """Order-n reciprocating forces as co- and counter-rotating vectors (textbook §6.1-6.2, extended to any n).

    Per unit amplitude C_n of one cylinder: ``f = 1/2 sum w_i exp(i(phi_i - n delta_i))``,
    ``b = 1/2 sum conj(w_i) exp(i(phi_i + n delta_i))`` (``w_i`` the cylinder's order-n force over
    the reference's, :meth:`BalanceGeometry.weights_for`: its force ``Re(w_i A_n e^{i n alpha})``
    splits into ``w_i A_n/2`` turning forward and its conjugate turning back); moments weight each
    term with the cylinder's position (units of a).
    """
    w = g.weights_for(order)
    forward = 0.5 * w * np.exp(1j * (g.cylinder_axis_rad - order * g.cylinder_phase_rad))
    backward = 0.5 * np.conj(w) * np.exp(1j * (g.cylinder_axis_rad + order * g.cylinder_phase_rad))
    z = g.cylinder_position
    return OrderModel(
        order,
        forward.sum(axis=-1),
        backward.sum(axis=-1),
        (forward * z).sum(axis=-1),
        (backward * z).sum(axis=-1),
    )


@dataclass(frozen=True)
class Hodograph:
    """The ellipse traced by a resultant ``f e^{i n theta} + b e^{-i n theta}`` (any consistent unit)."""

    semi_major: float
    semi_minor: float
    major_axis_deg: float  # direction of the major axis from the vertical, in [0, 180)
    x_amplitude: float  # textbook A (horizontal semi-axis of the projection)
    y_amplitude: float  # textbook B
    sense: str  # "forward" (turns with the shaft), "backward", "line" (|f| = |b|) or "none"
    theta_at_max_deg: float  # first shaft angle in [0, 180/n) at which the length is largest (it repeats every 180/n)


def hodograph(
    forward: complex, backward: complex, speed: int, tolerance: float = 1e-12
) -> Hodograph:
    """Semi-axes, orientation and sense of the elliptic hodograph (textbook eq. 60-63, 70-73)."""
    f, b = abs(forward), abs(backward)
    scale = max(f + b, 1e-300)
    if f + b <= tolerance:
        return Hodograph(0.0, 0.0, 0.0, 0.0, 0.0, "none", 0.0)
    # The length is largest when the two vectors line up: n theta = (arg b - arg f)/2.
    arg_f = math.atan2(forward.imag, forward.real) if f > tolerance * scale else None
    arg_b = math.atan2(backward.imag, backward.real) if b > tolerance * scale else None
    if arg_f is None:
        direction, theta = arg_b, 0.0
    elif arg_b is None:
        direction, theta = arg_f, 0.0
    else:
        theta = ((arg_b - arg_f) / 2.0) / speed
        direction = arg_f + speed * theta
    assert direction is not None  # f + b > tolerance: f or b is above tolerance * scale
    period = 2 * math.pi / speed
    theta = theta % (period / 2.0) if arg_f is not None and arg_b is not None else 0.0
    if abs(f - b) <= tolerance * scale:
        sense = "line"
    else:
        sense = "forward" if f > b else "backward"
    return Hodograph(
        semi_major=f + b,
        semi_minor=abs(f - b),
        major_axis_deg=math.degrees(direction) % 180.0,
        x_amplitude=float(abs(forward - np.conj(backward))),
        y_amplitude=float(abs(forward + np.conj(backward))),
        sense=sense,
        theta_at_max_deg=math.degrees(theta) % (360.0 / speed),
    )


def bay_vectors(axes_rad, order: int, weights=None) -> tuple[complex, complex]:
    """The textbook's F, P (order 1) or K, Z (order 2) of one bay, per unit C_n, signed.

    Taken when the bay's crank points along the vertical (the textbook's alpha = 0 on the
    bay's axis of symmetry): ``F_n = 1/2 sum exp(i(1 - n) phi_b)``, ``P_n = 1/2 sum exp(i(1 + n) phi_b)``
    over the bank axes phi_b of the bay. For a bay symmetric about the vertical both are real
    and equal the textbook's values, e.g. V: F = 1, P = cos(gamma), K = cos(gamma/2),
    Z = cos(3 gamma/2); W: F = 1.5, P = 0.5 + cos(2 gamma), K = 0.5 + cos(gamma), Z = 0.5 + cos(3 gamma).
    ``weights``: each cylinder's order-n force over the reference's (complex; a slave cylinder's,
    :meth:`BalanceGeometry.weights_for`), multiplying its term forward and its conjugate back.
    """
    phi = np.asarray(axes_rad, dtype=float)
    w = np.ones(phi.shape) if weights is None else np.asarray(weights)
    forward = 0.5 * (w * np.exp(1j * (1 - order) * phi)).sum()
    backward = 0.5 * (np.conj(w) * np.exp(1j * (1 + order) * phi)).sum()
    return complex(forward), complex(backward)


# --------------------------------------------------------------------------- the real forces, cylinder by cylinder


@dataclass(frozen=True)
class Masses:
    """Masses and speed for the absolute values (SI)."""

    reciprocating_kg: float  # m_s per cylinder
    rotating_kg: float  # m_R per crank (pin, webs at R, rotating parts of all rods on the pin)
    crank_radius_m: float
    rod_ratio: float
    angular_velocity_rad_s: float
    offset_ratio: float = 0.0  # k = e/L of an offset crank-slider
    #: per cylinder, its own piston acceleration (m/s^2, positive towards the shaft at TDC) at its
    #: crank angle alpha_i in rad, where it is not the reference's (a slave piston); None: all alike
    cylinder_accelerations: tuple | None = None

    def cylinder_acceleration_m_s2(self, alpha_rad) -> np.ndarray:
        """Every cylinder's exact piston acceleration, m/s^2, at its own crank angles
        ``alpha_rad[..., i]``: its own function where it has one, else the closed form."""
        alpha = np.asarray(alpha_rad, dtype=float)
        j = self.piston_acceleration_m_s2(alpha)
        for i, own in enumerate(self.cylinder_accelerations or ()):
            if own is not None:
                j[..., i] = own(alpha[..., i])
        return j

    def piston_acceleration_m_s2(self, alpha_rad):
        """The exact piston acceleration at the crank angle ``alpha_rad`` from TDC (closed form)."""
        R, lam, w = self.crank_radius_m, self.rod_ratio, self.angular_velocity_rad_s
        if self.offset_ratio:
            return oc.piston_acceleration_m_s2(alpha_rad, R, lam, self.offset_ratio, w)
        return kin.piston_acceleration_exact_m_s2(alpha_rad, R, lam, w)

    @property
    def centrifugal_N(self) -> float:
        """C = m_R R w^2 (textbook eq. 35)."""
        return self.rotating_kg * self.crank_radius_m * self.angular_velocity_rad_s**2

    @property
    def first_order_N(self) -> float:
        """C_I = m_s R w^2 (textbook eq. 55)."""
        return self.reciprocating_kg * self.crank_radius_m * self.angular_velocity_rad_s**2

    @property
    def second_order_textbook_N(self) -> float:
        """C_II = lambda C_I (textbook eq. 56)."""
        return self.rod_ratio * self.first_order_N


def time_domain_sum(g: BalanceGeometry, masses: Masses, theta_rad, spacing_m: float = 1.0):
    """Resultant force (N) and moment vector (N*m) of the real forces, summed cylinder by cylinder.

    Each cylinder contributes its exact reciprocating inertia force ``w_i m_s j_i(alpha_i)`` along
    its own axis (``j_i`` its own piston's acceleration, :meth:`Masses.cylinder_acceleration_m_s2`,
    no series) and each crank its centrifugal force
    ``m_R R w^2`` along the crank; the moment sums position times force.

    Returns
    -------
    force, moment : complex numpy arrays over ``theta_rad`` (frame of the module docstring).
    """
    theta = np.asarray(theta_rad, dtype=float)[:, None]
    alpha = theta - g.cylinder_phase_rad[None, :]
    j = masses.cylinder_acceleration_m_s2(alpha)
    recip = masses.reciprocating_kg * g.weights * j * np.exp(1j * g.cylinder_axis_rad)[None, :]
    crank = masses.centrifugal_N * np.exp(1j * (theta + g.crank_direction_rad[None, :]))
    force = recip.sum(axis=1) + crank.sum(axis=1)
    moment = (recip * g.cylinder_position).sum(axis=1) + (crank * g.crank_position).sum(axis=1)
    return force, moment * spacing_m


def vector_method_sum(
    g: BalanceGeometry,
    masses: Masses,
    theta_rad,
    orders,
    spacing_m: float = 1.0,
    harmonics: np.ndarray | None = None,
    rotating: bool = True,
):
    """The same resultants from the vector models: rotating masses plus the given orders (N, N*m)."""
    if harmonics is None:
        harmonics = harmonics_for(masses.rod_ratio, max(orders, default=2), masses.offset_ratio)
    theta = np.asarray(theta_rad, dtype=float)
    force = np.zeros(theta.shape, dtype=complex)
    moment = np.zeros(theta.shape, dtype=complex)
    if rotating:
        model = rotating_model(g)
        force += masses.centrifugal_N * model.force(theta)
        moment += masses.centrifugal_N * model.moment(theta)
    for n in orders:
        model = scaled(reciprocating_model(g, n), harmonics[n] * masses.first_order_N)
        force += model.force(theta)
        moment += model.moment(theta)
    return force, moment * spacing_m


# --------------------------------------------------------------------------- balancing means


@dataclass(frozen=True)
class RotatingMass:
    """A balancing mass: ``mass_radius_kg_m`` (m*r) at ``position`` along the shaft (units of a,
    from the middle of the row) turning at ``speed`` times the crankshaft speed (negative:
    the opposite way), at angle ``phase_deg`` from the vertical when theta = 0."""

    mass_radius_kg_m: float
    position: float
    speed: int
    phase_deg: float

    def force_N(self, theta_rad, angular_velocity_rad_s: float):
        w = self.speed * angular_velocity_rad_s
        return (
            self.mass_radius_kg_m
            * w**2
            * np.exp(
                1j
                * (math.radians(self.phase_deg) + self.speed * np.asarray(theta_rad, dtype=float))
            )
        )


def _turn_deg(angle_deg: float) -> float:
    """An angle in [0, 360) deg: a round-off below 0 (-1e-14) is 0, not 360."""
    turned = angle_deg % 360.0
    return 0.0 if turned > 360.0 - 1e-9 else turned


def masses_for(
    force_N: complex,
    moment_N_units: complex,
    speed: int,
    angular_velocity_rad_s: float,
    positions: tuple[float, float],
    tolerance: float,
) -> list[RotatingMass]:
    """Two masses at ``positions`` (units of a) turning at ``speed`` w whose forces cancel a
    rotating force amplitude ``force_N`` and moment amplitude ``moment_N_units`` (N * a).

    With ``F_1 + F_2 = -force`` and ``z_1 F_1 + z_2 F_2 = -moment``. If both positions coincide
    (one crank), a single mass cancels the force (the moment must then be zero).
    """
    z1, z2 = positions
    w2 = (speed * angular_velocity_rad_s) ** 2
    if abs(z2 - z1) < 1e-12:
        if abs(moment_N_units) > tolerance:
            raise ValueError("a moment cannot be balanced by masses in one plane")
        targets = [(-force_N, z1)]
    else:
        f2 = (-moment_N_units + z1 * force_N) / (z2 - z1)
        f1 = -force_N - f2
        targets = [(f1, z1), (f2, z2)]
    out = []
    for target, z in targets:
        if abs(target) <= tolerance:
            continue
        out.append(
            RotatingMass(
                mass_radius_kg_m=float(abs(target)) / w2,
                position=float(z),
                speed=speed,
                phase_deg=_turn_deg(math.degrees(math.atan2(target.imag, target.real))),
            )
        )
    return out


@dataclass
class BalancingMeans:
    """Counterweights (on the crankshaft, speed +1) and balance shafts (any speed)."""

    counterweights: list[RotatingMass] = field(default_factory=list)
    shafts: dict[int, list[RotatingMass]] = field(default_factory=dict)  # speed ratio -> masses
    balanced_orders: tuple[int, ...] = ()

    def all_masses(self) -> list[RotatingMass]:
        return list(self.counterweights) + [m for masses in self.shafts.values() for m in masses]

    def forces(self, theta_rad, angular_velocity_rad_s: float, spacing_m: float = 1.0):
        theta = np.asarray(theta_rad, dtype=float)
        force = np.zeros(theta.shape, dtype=complex)
        moment = np.zeros(theta.shape, dtype=complex)
        for m in self.all_masses():
            f = m.force_N(theta, angular_velocity_rad_s)
            force += f
            moment += m.position * f
        return force, moment * spacing_m


def design_means(
    g: BalanceGeometry,
    masses: Masses,
    harmonics: np.ndarray,
    balance_orders,
    counterweights: str = "ends",
    first_order_forward: str = "crankshaft",
    shaft_positions: tuple[float, float] | None = None,
    relative_tolerance: float = 1e-9,
    leave: tuple[int, ...] = (),
) -> BalancingMeans:
    """Counterweights and balance shafts that cancel the rotating forces and the given orders.

    * Crankshaft counterweights take the centrifugal resultant and its moment and, with
      ``first_order_forward = "crankshaft"``, the co-rotating half of the first-order forces
      and moments (textbook §6.2: Q = F + C). ``counterweights = "ends"`` puts them on the
      webs of the first and last cranks (textbook fig. 28); ``"every_crank"`` gives every crank
      its own counterweight opposite its crank (each crank balanced by itself).
    * Every other unbalanced rotating component of order n gets a balance shaft turning at
      ``+n w`` (co-rotating part) or ``-n w`` (counter-rotating part) with two masses at
      ``shaft_positions`` (default: the planes of the first and last cranks); a +n/-n pair of
      equal shafts is Lanchester's balancer (textbook figs. 27-28).

    The rotating parts in ``leave`` get no means: they are left (signed speeds, +n the co-rotating
    part of order n, -n its counter-rotating part).

    Returns masses in kg*m (mass times radius); the caller divides by the chosen radii.
    """
    w = masses.angular_velocity_rad_s
    scale = masses.centrifugal_N * g.cranks + masses.first_order_N * g.cylinders
    tol = relative_tolerance * max(scale, 1e-300)
    ends = (float(g.crank_position[0]), float(g.crank_position[-1]))
    shaft_positions = ends if shaft_positions is None else shaft_positions
    means = BalancingMeans(balanced_orders=tuple(sorted(set(balance_orders))))
    rot = rotating_model(g)
    first = reciprocating_model(g, 1)
    c1 = harmonics[1] * masses.first_order_N
    forward_on_crank = 1 in balance_orders and first_order_forward == "crankshaft"
    if counterweights == "every_crank":
        for k in range(g.cranks):
            target = masses.centrifugal_N * np.exp(1j * g.crank_direction_rad[k])
            if forward_on_crank:
                members = g.cylinder_bay == k
                target = (
                    target
                    + c1
                    * 0.5
                    * (
                        g.weights_for(1)[members]
                        * np.exp(
                            1j * (g.cylinder_axis_rad[members] - g.cylinder_phase_rad[members])
                        )
                    ).sum()
                )
            means.counterweights += masses_for(
                complex(target), 0.0, 1, w, (float(g.crank_position[k]),) * 2, tol
            )
    else:
        force = masses.centrifugal_N * complex(rot.force_forward)
        moment = masses.centrifugal_N * complex(rot.moment_forward)
        if forward_on_crank:
            force += c1 * complex(first.force_forward)
            moment += c1 * complex(first.moment_forward)
        means.counterweights = masses_for(force, moment, 1, w, ends, tol)
    for n in sorted(set(balance_orders)):
        model = scaled(reciprocating_model(g, n), harmonics[n] * masses.first_order_N)
        parts = [(-n, complex(model.force_backward), complex(model.moment_backward))]
        if not (n == 1 and first_order_forward == "crankshaft"):
            parts.insert(0, (n, complex(model.force_forward), complex(model.moment_forward)))
        for speed, f, m in parts:
            if speed in leave or abs(f) <= tol and abs(m) <= tol:
                continue
            means.shafts[speed] = masses_for(f, m, speed, w, shaft_positions, tol)
    return means
