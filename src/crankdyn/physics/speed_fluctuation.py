r"""Crankshaft speed fluctuation with the variable reduced inertia of the crank mechanisms.

The equation of motion
----------------------
Everything that turns with the crankshaft, reduced to it, has the kinetic energy
:math:`T=\tfrac12 J(\alpha)\dot\alpha^2` with the reduced moment of inertia

.. math:: J(\alpha) = J_0 + \sum_i m_{s,i}\,s_i'(\alpha)^2,
          \qquad s_i'(\alpha) = \frac{ds_i}{d\alpha},

where :math:`J_0` holds the constant parts (flywheel, the crankshaft itself, the rotating
masses :math:`m_R R^2` of every crank) and the sum runs over the reciprocating masses
:math:`m_s` of the cylinders, each with its own phase. Lagrange's equation with the
generalised force :math:`M_g(\alpha)-M_{load}` (gas torque minus the load) gives

.. math:: J(\alpha)\,\dot\omega + \tfrac12 J'(\alpha)\,\omega^2 = M_g(\alpha) - M_{load}.
   :label: motion

Two facts make this module exact rather than approximate:

* **The inertia torque of the textbook is the** :math:`\tfrac12 J'\omega^2` **term.** At a
  constant speed :math:`\omega_n` the inertia force :math:`-m_s j` with
  :math:`j=\omega_n^2 s''` gives the torque :math:`-m_s\omega_n^2 s''s' =
  -\tfrac12 J'(\alpha)\,\omega_n^2`. So the gas torque follows from the output torque of
  the torque stage (gas + inertia at the nominal speed) as
  :math:`M_g = M + \tfrac12 J'\omega_n^2` (:func:`gas_torque_Nm`), with no second
  force calculation.
* **The equation is linear in the kinetic energy.** Since
  :math:`\frac{d}{d\alpha}\big(\tfrac12 J\omega^2\big) = J\omega\frac{d\omega}{d\alpha}
  + \tfrac12 J'\omega^2` and :math:`\dot\omega=\omega\,d\omega/d\alpha`, eq. (motion) is
  :math:`dE/d\alpha = M_g - M_{load}` for :math:`E=\tfrac12 J\omega^2`, so

  .. math:: \omega(\alpha) = \sqrt{\frac{2\,(E_0 + W(\alpha))}{J(\alpha)}},\qquad
            W(\alpha)=\int_0^\alpha (M_g - M_{load})\,d\alpha .

  With :math:`M_{load}` equal to the cycle mean of :math:`M_g` (the steady state) every
  such solution is periodic; :math:`E_0` is fixed by the mean speed, here the time mean
  :math:`\Phi/T` over a cycle of angle :math:`\Phi`. This quadrature solution
  (:func:`periodic_speed`) is the exact reference against which the time-stepping ODE
  solvers are measured (:func:`phase_error`). It is exact for the trigonometric
  interpolant of the grid torques (:class:`PeriodicSeries`), whose integral is closed-form.

With a constant load the mean speed is neutrally stable (every :math:`E_0` gives a periodic
solution), so the steady state is selected by the nominal mean speed; a load that grows with
the speed would select it by itself, and is not modelled here.

References
----------
Den Hartog, J. P. (1956). *Mechanical Vibrations*, 4th ed. (reduced inertia of the
crank mechanism, variable with the crank angle).
Hairer, E., & Wanner, G. (1996). *Solving Ordinary Differential Equations II: Stiff and
Differential-Algebraic Problems*, 2nd ed. (stability regions; Radau IIA; BDF).
"""

from __future__ import annotations

import cmath
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from . import kinematics as kin
from .extrema import first_argmax, first_argmin
from .lazy import integrate
from .scalar_search import brentq, minimize_bounded

__all__ = [
    "arm_derivatives",
    "reciprocating_inertia_kg_m2",
    "mean_arm_squared_m2",
    "gas_torque_Nm",
    "PeriodicSeries",
    "InertiaSeries",
    "DiscSeries",
    "inertia_series",
    "PeriodicSpeed",
    "periodic_speed",
    "flywheel_for_irregularity",
    "single_mass_rhs",
    "SolverRun",
    "run_solver",
    "phase_error",
    "stable_step_s",
    "SolverChoice",
    "choose_solver",
    "significant_order",
    "harmonic_amplitudes",
]


# --------------------------------------------------------------------------- reduced inertia


def arm_derivatives(crank_angle_rad, crank_radius_m, rod_ratio):
    r"""First and second derivatives of the exact piston displacement w.r.t. the crank angle.

    Parameters
    ----------
    crank_angle_rad : float or array_like
        Crank angle from the cylinder's TDC [rad].
    crank_radius_m, rod_ratio : float
        R [m] and :math:`\lambda = R/L` [-].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        :math:`s'=ds/d\alpha` [m/rad] and :math:`s''=d^2s/d\alpha^2` [m/rad^2]: the exact
        velocity and acceleration of :mod:`crankdyn.physics.kinematics` at unit angular
        velocity (at constant :math:`\omega`, :math:`v=\omega s'` and :math:`j=\omega^2 s''`).
    """
    first = kin.piston_velocity_exact_m_s(crank_angle_rad, crank_radius_m, rod_ratio, 1.0)
    second = kin.piston_acceleration_exact_m_s2(crank_angle_rad, crank_radius_m, rod_ratio, 1.0)
    return first, second


def reciprocating_inertia_kg_m2(
    crank_angle_rad, phase_rad, reciprocating_kg, crank_radius_m, rod_ratio
):
    r"""Reduced inertia of reciprocating masses and its derivative, per cylinder.

    Parameters
    ----------
    crank_angle_rad : array_like
        Shaft angle :math:`\alpha` [rad].
    phase_rad : float or array_like
        Shaft angle at which each cylinder's piston is at its TDC (firing delay) [rad];
        broadcast against ``crank_angle_rad``.
    reciprocating_kg : float or array_like
        :math:`m_s` of each cylinder [kg].
    crank_radius_m, rod_ratio : float
        R [m], :math:`\lambda` [-].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        :math:`m_s s'(\alpha-\varphi)^2` [kg m^2] and its derivative
        :math:`2 m_s s' s''` [kg m^2/rad].

    Notes
    -----
    Derived: kinetic energy :math:`\tfrac12 m_s v^2 = \tfrac12 m_s s'^2\omega^2` of a mass
    moving with the piston (Den Hartog 1956).
    """
    first, second = arm_derivatives(
        np.asarray(crank_angle_rad) - np.asarray(phase_rad), crank_radius_m, rod_ratio
    )
    mass = np.asarray(reciprocating_kg, dtype=float)
    return mass * first * first, 2.0 * mass * first * second


def mean_arm_squared_m2(crank_radius_m, rod_ratio, points: int = 720) -> float:
    r"""Cycle mean of :math:`s'(\alpha)^2` [m^2/rad^2] (exact kinematics).

    Notes
    -----
    Periodic trapezoid rule (spectrally accurate for this smooth periodic integrand). For
    the two-term kinematics the mean is :math:`R^2(\tfrac12+\tfrac{\lambda^2}{8})`, which
    the exact value approaches to :math:`O(\lambda^4)`; the mean reduced inertia of one
    cylinder is :math:`m_s` times this value (the cycle mean of :math:`J(\alpha)` used as
    the engine's own inertia by the energy method).
    """
    alpha = np.arange(points) * (2 * np.pi / points)
    first, _ = arm_derivatives(alpha, crank_radius_m, rod_ratio)
    return float(np.mean(first * first))


def gas_torque_Nm(total_torque_Nm, reciprocating_inertia_derivative_kg_m2, angular_velocity_rad_s):
    r"""Gas torque from the output torque at constant speed: :math:`M_g = M + \tfrac12 J'\omega_n^2`.

    Parameters
    ----------
    total_torque_Nm : array_like
        Torque of gas and inertia forces computed at the constant speed :math:`\omega_n` [N m].
    reciprocating_inertia_derivative_kg_m2 : array_like
        :math:`J'(\alpha)` of the same reciprocating masses [kg m^2/rad].
    angular_velocity_rad_s : float
        :math:`\omega_n` [rad/s].

    Returns
    -------
    numpy.ndarray
        :math:`M_g` [N m] (module docstring: the inertia torque is :math:`-\tfrac12 J'\omega_n^2`).
    """
    return (
        np.asarray(total_torque_Nm)
        + 0.5 * np.asarray(reciprocating_inertia_derivative_kg_m2) * angular_velocity_rad_s**2
    )


#: Complex elements of one block of powers (16 MiB): bounds the memory of evaluating a series
#: with many harmonics at many angles (angles x harmonics would grow with the square of the step count).
_BLOCK_ELEMENTS = 1 << 20
#: A set of angles is taken as the uniform grid when every angle is within this fraction of
#: the period of ``k * period / M`` (rounding of degrees to radians is ~1e-16 of it).
_GRID_TOLERANCE = 1e-13
#: Below this many (angle, harmonic) products a grid is summed directly (the FFT agrees to
#: rounding, which an adaptive ODE solver started from it would amplify
#: into a different step sequence); above it the direct sum would grow with the square of the
#: number of angles.
_GRID_MIN_WORK = 1 << 23
#: From this many harmonics on, the single-disc right-hand side (and a series at one angle) sums elementwise
#: instead of by a BLAS product: OpenBLAS splits a product this long over threads, which on a
#: machine busy with other processes costs milliseconds per call (thousands of calls per solve).
#: Shorter series (every bundled example at its own step) keep the BLAS product, single-threaded there.
_BLAS_MAX_WIDTH = 2048


class PowerSum:
    r""":math:`\sum_{k=1}^{K} c_k z^k` for one complex ``z``, in O(K) work and O(sqrt K) memory.

    With :math:`k = bB + j + 1` the sum is :math:`\sum_b (z^B)^b \sum_{j<B} c_{bB+j+1} z^{j+1}`:
    two short power tables (B and K/B entries, B = sqrt K) and one matrix-vector product over
    the coefficients stored as a (K/B, B) block. Writing the K powers out (``cumprod`` over a
    length-K row) costs a sequential complex product per harmonic and a row that, at fine
    angle steps, no longer fits the CPU's cache; this reads each coefficient once. The powers
    carry ~sqrt(K) rounding steps instead of K.
    """

    def __init__(self, coefficients):
        c = np.asarray(coefficients, dtype=complex).reshape(-1)
        self.block = max(1, math.isqrt(max(c.size - 1, 0)) + 1)
        rows = -(-c.size // self.block)
        padded = np.zeros(rows * self.block, dtype=complex)
        padded[: c.size] = c
        self._table = padded.reshape(rows, self.block)
        self._small = np.empty(self.block, dtype=complex)
        self._large = np.empty(rows, dtype=complex)

    def __call__(self, z: complex) -> complex:
        small, large = self._small, self._large
        small.fill(z)
        np.cumprod(small, out=small)  # z^1 .. z^B
        # einsum's own loop: a BLAS product this long may be split over threads, which on a
        # machine busy with other processes costs milliseconds per call (see _BLAS_MAX_WIDTH)
        inner = np.einsum("bj,j->b", self._table, small)
        if inner.size == 1:
            return complex(inner[0])
        large.fill(small[-1])
        np.cumprod(large, out=large)  # (z^B)^1 .. (z^B)^(rows)
        return complex(inner[0] + np.einsum("b,b->", large[:-1], inner[1:]))


class PeriodicSeries:
    r"""Trigonometric interpolant of samples on a uniform periodic grid, one column per quantity.

    :math:`f(\alpha)=\bar f+\mathrm{Re}\sum_{k=1}^{N/2} C_k e^{ik\,2\pi\alpha/\Phi}` passes
    through every sample (the discrete Fourier transform) and is infinitely differentiable,
    so an ODE solver's error control sees the torque as smooth. A piecewise (spline)
    interpolant would not do: a cubic spline's third derivative jumps at every knot and
    forces 5th-order solvers to step knot by knot. Its cycle mean is the periodic
    trapezoid mean of the samples, and its integral is known in closed form
    (:meth:`integral`), which makes the exact solution of :func:`periodic_speed` possible.
    """

    def __init__(self, mean, coefficients, period_rad: float):
        self.mean = np.atleast_1d(np.asarray(mean, dtype=float))
        self.coefficients = np.asarray(coefficients, dtype=complex).reshape(-1, self.mean.size)
        self.period_rad = float(period_rad)
        self.wavenumbers = np.arange(1, self.coefficients.shape[0] + 1) * (
            2.0 * np.pi / self.period_rad
        )
        self.columns = self.mean.size
        self._scratch = None
        self._first_column = np.ascontiguousarray(self.coefficients[:, 0])
        self._first_sum = (
            PowerSum(self._first_column) if self._first_column.size >= _BLAS_MAX_WIDTH else None
        )

    @classmethod
    def from_samples(cls, values, period_rad: float) -> PeriodicSeries:
        """From samples at ``k * period / N`` (k = 0..N-1) along axis 0."""
        values = np.asarray(values, dtype=float)
        column = values.reshape(values.shape[0], -1)
        n = column.shape[0]
        spectrum = np.fft.rfft(column, axis=0) / n
        coefficients = 2.0 * spectrum[1:]
        if n % 2 == 0:
            coefficients[-1] = spectrum[-1].real  # the Nyquist term is a cosine of half weight
        return cls(spectrum[0].real, coefficients, period_rad)

    def _phase(self, alpha):
        # e^{i k w1 alpha} for k = 1..K as powers of e^{i w1 alpha}: one exponential per angle
        # instead of K (the products lose ~K*1e-16, far below anything that matters here).
        alpha = np.asarray(alpha, dtype=float)
        base = np.exp(1j * self.wavenumbers[0] * alpha)[..., None]
        return np.cumprod(np.broadcast_to(base, alpha.shape + (self.wavenumbers.size,)), axis=-1)

    def __call__(self, alpha):
        """Every column at ``alpha`` (shape ``alpha.shape + (columns,)``, or ``alpha.shape`` for one column)."""
        if np.ndim(alpha) == 0 and self.columns == 1:  # the single-mass ODE's hot path
            if self._first_sum is not None:
                z = cmath.exp(1j * self.wavenumbers[0] * float(alpha))
                return float(self.mean[0] + self._first_sum(z).real)
            buffer = self._buffer(1)[0]
            buffer.fill(cmath.exp(1j * self.wavenumbers[0] * float(alpha)))
            np.cumprod(buffer, out=buffer)
            return float(self.mean[0] + (buffer @ self._first_column).real)
        value = self.mean + self._sum(alpha, self.coefficients).real
        return value[..., 0] if self.columns == 1 else value

    def _grid_points(self, alpha) -> int | None:
        """M when ``alpha`` is the uniform grid ``k * period / M`` (k = 0..M-1) to rounding, else None."""
        if alpha.ndim != 1 or alpha.size * self.wavenumbers.size < _GRID_MIN_WORK:
            return None
        m = alpha.size
        if abs(alpha[0]) > _GRID_TOLERANCE * self.period_rad:
            return None
        grid = np.arange(m) * (self.period_rad / m)
        return (
            m if float(np.max(np.abs(alpha - grid))) <= _GRID_TOLERANCE * self.period_rad else None
        )

    def _on_grid(self, coefficients, m: int):
        r""":math:`\sum_k c_k e^{2\pi i k j/M}` for j = 0..M-1 by one inverse FFT (harmonics folded mod M)."""
        folded = np.zeros((m, coefficients.shape[1]), dtype=complex)
        np.add.at(folded, np.arange(1, coefficients.shape[0] + 1) % m, coefficients)
        return np.fft.ifft(folded, axis=0) * m

    def _sum(self, alpha, coefficients, shift: bool = False):
        r""":math:`\sum_k c_k (e^{i w_k \alpha} - s)` for every alpha, s = 1 if ``shift`` else 0.

        Shape ``alpha.shape + (columns,)``. Linear in memory: on the uniform grid of M points an
        inverse FFT (O(M log M)); elsewhere the powers are built a block of angles at a time,
        never as one (angles x harmonics) matrix.
        """
        alpha = np.asarray(alpha, dtype=float)
        if alpha.ndim == 0:
            phase = self._phase(alpha)
            if shift:
                phase -= 1.0
            if (
                phase.size >= _BLAS_MAX_WIDTH
            ):  # one long vector product: elementwise (see _BLAS_MAX_WIDTH)
                return (phase[:, None] * coefficients).sum(axis=0)
            return phase @ coefficients
        m = self._grid_points(alpha)
        if m is not None:
            value = self._on_grid(coefficients, m)
            return value - coefficients.sum(axis=0) if shift else value
        flat = alpha.reshape(-1)
        out = np.empty((flat.size, coefficients.shape[1]), dtype=complex)
        rows = max(1, _BLOCK_ELEMENTS // max(self.wavenumbers.size, 1))
        for start in range(0, flat.size, rows):
            phase = self._phase(flat[start : start + rows])
            out[start : start + rows] = ((phase - 1.0) if shift else phase) @ coefficients
        return out.reshape(alpha.shape + (coefficients.shape[1],))

    def diagonal(self, angles):
        """Column k at ``angles[k]`` (the torsional model's hot path)."""
        buffer = self._buffer(self.columns)
        base = np.exp(1j * self.wavenumbers[0] * np.asarray(angles, dtype=float))
        np.multiply(self._ones, base[:, None], out=buffer)
        np.cumprod(buffer, axis=1, out=buffer)
        return self.mean + np.einsum("ck,kc->c", buffer, self.coefficients).real

    def _buffer(self, rows):
        if getattr(self, "_scratch", None) is None:
            self._ones = np.ones((self.columns, self.wavenumbers.size), dtype=complex)
            self._scratch = {}
        if rows not in self._scratch:
            self._scratch[rows] = np.empty((rows, self.wavenumbers.size), dtype=complex)
        return self._scratch[rows]

    def derivative(self) -> PeriodicSeries:
        """d/dalpha of the series (zero mean)."""
        return PeriodicSeries(
            np.zeros(self.columns),
            self.coefficients * (1j * self.wavenumbers[:, None]),
            self.period_rad,
        )

    def integral(self, alpha):
        r""":math:`\int_0^\alpha (f-\bar f)\,d\alpha` (periodic, exact)."""
        scaled = self.__dict__.get("_scaled")
        if scaled is None:
            scaled = self._scaled = self.coefficients / (1j * self.wavenumbers[:, None])
        value = self._sum(alpha, scaled, shift=True).real
        return value[..., 0] if self.columns == 1 else value


class InertiaSeries:
    r"""Reduced inertia :math:`J(\alpha)=J_0+\mathrm{Re}\sum_k C_k e^{ik\alpha}` as a Fourier series.

    Built by :func:`inertia_series`; ``self(alpha)`` returns ``(J, dJ/dalpha)`` for any angle
    (scalar or array). The series is the trigonometric interpolant of the exact
    :math:`m_s s'^2` (spectral: the coefficients fall like :math:`\lambda^k`) truncated where
    they fall below 1e-15 of the mean, so it equals the exact inertia to rounding error and its
    derivative is the exact derivative of the series (spectral differentiation).
    """

    def __init__(self, constant_kg_m2: float, coefficients):
        self.constant_kg_m2 = float(constant_kg_m2)
        self.coefficients = np.asarray(coefficients, dtype=complex)
        self.orders = np.arange(1, self.coefficients.size + 1)
        self._derivative = 1j * self.orders * self.coefficients
        self._reversed = [complex(c) for c in self.coefficients[::-1]]
        self._reversed_derivative = [complex(c) for c in self._derivative[::-1]]

    @property
    def mean_kg_m2(self) -> float:
        return self.constant_kg_m2

    def __call__(self, alpha):
        if (
            np.ndim(alpha) == 0
        ):  # the single-mass ODE's hot path: Horner's scheme in plain complex arithmetic
            z = cmath.exp(1j * float(alpha))
            value = derivative = 0j
            for c, d in zip(self._reversed, self._reversed_derivative, strict=True):
                value = value * z + c
                derivative = derivative * z + d
            return self.constant_kg_m2 + (value * z).real, (derivative * z).real
        alpha = np.asarray(alpha, dtype=float)
        base = np.exp(1j * alpha)[..., None]
        phase = np.cumprod(np.broadcast_to(base, alpha.shape + (self.orders.size,)), axis=-1)
        return (
            self.constant_kg_m2 + (phase @ self.coefficients).real,
            (phase @ self._derivative).real,
        )


class DiscSeries:
    r"""Gas torque and reduced inertia of m crank discs, evaluated together.

    Both are Fourier series in the shaft angle: the torque in multiples of
    :math:`2\pi/\Phi` (half orders for a four-stroke cycle), the inertia in whole orders, so
    one set of powers :math:`z^k`, :math:`z=e^{i\,2\pi\alpha/\Phi}`, serves both; this is
    the right-hand side's hot path. ``self(angles)`` (one angle per disc) returns an (m, 3)
    array of :math:`M_g`, :math:`J`, :math:`J'`.
    """

    def __init__(self, torque: PeriodicSeries, inertia: list):
        revolutions = torque.period_rad / (2 * np.pi)
        step = int(round(revolutions))
        if abs(revolutions - step) > 1e-9 or step < 1:
            raise ValueError("the cycle must be a whole number of revolutions")
        m = torque.columns
        if len(inertia) != m:
            raise ValueError("one inertia series per torque column")
        width = max([torque.coefficients.shape[0]] + [s.coefficients.size * step for s in inertia])
        coef = np.zeros((width, m, 3), dtype=complex)
        coef[: torque.coefficients.shape[0], :, 0] = torque.coefficients
        for c, series in enumerate(inertia):
            index = np.arange(1, series.coefficients.size + 1) * step - 1
            coef[index, c, 1] = series.coefficients
            coef[index, c, 2] = 1j * series.orders * series.coefficients
        self.coef = coef
        self.single = np.ascontiguousarray(coef[:, 0, :])
        self._long = width >= _BLAS_MAX_WIDTH
        if self._long:
            # the torque's harmonics are dense, the inertia's only every ``step``-th and few: summing
            # the three columns over the whole width (a (3, K) product) spilled out of the L2 cache
            # at fine steps and made the time grow faster than the number of angles
            self._torque_sum = PowerSum(coef[:, 0, 0])
            self._inertia_index = np.flatnonzero(np.any(coef[:, 0, 1:] != 0, axis=1))
            self._inertia_rows = np.ascontiguousarray(coef[self._inertia_index, 0, 1:])
        self.by_disc = np.ascontiguousarray(coef.transpose(1, 0, 2))  # (m, K, 3)
        self.mean = np.stack(
            [torque.mean, [s.constant_kg_m2 for s in inertia], np.zeros(m)], axis=1
        )
        self.w1 = 2 * np.pi / torque.period_rad
        self.m = m
        self._ones = np.ones((m, width), dtype=complex)
        self._powers = np.empty((m, width), dtype=complex)
        self._row = np.empty(width, dtype=complex)

    def scalar(self, alpha: float):
        """(M_g, J, J') of a single disc (m = 1) at one angle."""
        z = cmath.exp(1j * self.w1 * alpha)
        if not self._long:
            row = self._row
            row.fill(z)
            np.cumprod(row, out=row)
            value = (row @ self.single).real
            return self.mean[0, 0] + value[0], self.mean[0, 1] + value[1], value[2]
        torque = self._torque_sum(z).real
        # the inertia's few harmonics: their powers directly (k + 1 is the harmonic's number)
        powers = np.exp(1j * self.w1 * alpha * (self._inertia_index + 1.0))
        inertia = (powers @ self._inertia_rows).real
        return self.mean[0, 0] + torque, self.mean[0, 1] + inertia[0], inertia[1]

    def __call__(self, angles) -> np.ndarray:
        powers = self._powers
        np.multiply(
            self._ones, np.exp(1j * self.w1 * np.asarray(angles, dtype=float))[:, None], out=powers
        )
        np.cumprod(powers, axis=1, out=powers)
        return self.mean + np.matmul(powers[:, None, :], self.by_disc)[:, 0, :].real


def inertia_series(
    phase_rad,
    reciprocating_kg,
    crank_radius_m,
    rod_ratio,
    constant_kg_m2: float = 0.0,
    points: int = 512,
) -> InertiaSeries:
    r"""Fourier series of :math:`J_0+\sum_i m_{s,i}\,s'(\alpha-\varphi_i)^2`.

    Parameters
    ----------
    phase_rad : array_like, shape (n,)
        TDC angle of each cylinder's piston (its firing delay) [rad].
    reciprocating_kg : float or array_like, shape (n,)
        :math:`m_s` of each cylinder [kg].
    crank_radius_m, rod_ratio : float
        R [m], :math:`\lambda` [-].
    constant_kg_m2 : float
        :math:`J_0`, the constant part (flywheel, rotating masses, crankshaft) [kg m^2].
    points : int
        Samples per revolution for the transform.

    Returns
    -------
    InertiaSeries
        Its ``mean_kg_m2`` is the cycle mean :math:`J_0+\sum m_s\overline{s'^2}`.

    Notes
    -----
    A phase shift multiplies coefficient k by :math:`e^{-ik\varphi}`, so the cylinders are
    summed in the coefficients; for an in-line four the odd orders cancel.
    """
    phase = np.atleast_1d(np.asarray(phase_rad, dtype=float))
    mass = np.broadcast_to(np.asarray(reciprocating_kg, dtype=float), phase.shape)
    alpha = np.arange(points) * (2 * np.pi / points)
    first, _ = arm_derivatives(alpha, crank_radius_m, rod_ratio)
    spectrum = np.fft.rfft(first * first) / points
    mean_unit = float(spectrum[0].real)
    unit = 2.0 * spectrum[1 : points // 2]  # C_k for one unit mass at phase 0
    keep = np.nonzero(np.abs(unit) > 1e-15 * mean_unit)[0]
    unit = unit[: keep[-1] + 1] if keep.size else unit[:0]
    k = np.arange(1, unit.size + 1)
    combined = (mass[:, None] * np.exp(-1j * np.outer(phase, k))).sum(axis=0) * unit
    return InertiaSeries(constant_kg_m2 + mean_unit * float(mass.sum()), combined)


# --------------------------------------------------------------------------- exact periodic solution


class PeriodicSpeed(NamedTuple):
    """The exact periodic solution of eq. (motion) (:func:`periodic_speed`)."""

    energy_constant_J: float  # E_0 = 1/2 J(0) omega(0)^2
    load_torque_Nm: float
    period_rad: float
    cycle_time_s: float
    angle_rad: np.ndarray  # fine sampling of the cycle
    omega_rad_s: np.ndarray
    inertia_kg_m2: np.ndarray
    omega_max_rad_s: float
    omega_min_rad_s: float
    omega_max_angle_rad: float
    omega_min_angle_rad: float
    omega_mean_rad_s: float  # time mean Phi / T
    irregularity: float  # (max - min) / ((max + min) / 2)
    omega_at: Callable  # omega(alpha) for any alpha (periodic)


def periodic_speed(
    gas_torque: PeriodicSeries,
    inertia: Callable,
    mean_angular_velocity_rad_s: float,
    samples: int = 8192,
) -> PeriodicSpeed:
    r"""Exact periodic solution of :math:`J\dot\omega+\tfrac12J'\omega^2=M_g-M_{load}` by quadrature.

    Parameters
    ----------
    gas_torque : PeriodicSeries
        :math:`M_g(\alpha)` over one cycle of angle :math:`\Phi` (one column) [N m].
    inertia : callable
        ``inertia(alpha) -> (J, dJ/dalpha)`` [kg m^2, kg m^2/rad], e.g. an :class:`InertiaSeries`.
    mean_angular_velocity_rad_s : float
        Required time-mean speed :math:`\Phi/T` [rad/s].
    samples : int
        Points of the fine sampling used for the mean speed and to find the extremes.

    Returns
    -------
    PeriodicSpeed

    Notes
    -----
    Derived in the module docstring. :math:`M_{load}` is the cycle mean of :math:`M_g`, so
    :math:`W(\alpha)` is the closed-form periodic integral of the series and the solution
    closes exactly after a cycle. The energy constant solves :math:`\Phi/T(E_0)=\omega_m`
    with :math:`T=\oint d\alpha/\omega` (periodic trapezoid rule, spectrally accurate for
    this smooth integrand; Brent's method). As :math:`E_0\to-\min W` the speed vanishes at
    one angle and T diverges, so the root exists and is unique (T decreases with :math:`E_0`).
    The extremes are refined from the fine sampling by a bounded scalar search.
    """
    period_rad = gas_torque.period_rad
    load = float(gas_torque.mean[0])
    angle = np.arange(samples) * (period_rad / samples)
    cache = gas_torque.__dict__.setdefault("_integral_cache", {})
    if samples not in cache:  # the flywheel search solves this problem for several inertias
        cache[samples] = gas_torque.integral(angle)
    w = cache[samples]
    j, _ = inertia(angle)
    e0 = _energy_constant(w, j, period_rad, mean_angular_velocity_rad_s)

    def omega_at(alpha):
        jj, _ = inertia(np.asarray(alpha, dtype=float))
        return np.sqrt(2.0 * (e0 + gas_torque.integral(alpha)) / jj)

    omega = np.sqrt(2.0 * (e0 + w) / j)
    cycle_time = float(np.mean(1.0 / omega)) * period_rad
    (a_max, w_max), (a_min, w_min) = _speed_extremes(angle, omega, omega_at, period_rad)
    return PeriodicSpeed(
        e0,
        load,
        period_rad,
        cycle_time,
        angle,
        omega,
        j,
        w_max,
        w_min,
        a_max,
        a_min,
        period_rad / cycle_time,
        (w_max - w_min) / (0.5 * (w_max + w_min)),
        omega_at,
    )


def _energy_constant(w, j, period_rad: float, mean_angular_velocity_rad_s: float) -> float:
    """The energy constant E0 whose periodic speed has the required mean (Brent's method); no
    periodic solution with a positive speed raises ValueError."""
    floor = -float(np.min(w))
    scale = 0.5 * float(np.mean(j)) * mean_angular_velocity_rad_s**2

    def mean_speed_error(e0):
        omega = np.sqrt(np.maximum(2.0 * (e0 + w) / j, 0.0))
        with np.errstate(divide="ignore"):
            cycle_time = float(np.mean(1.0 / omega)) * period_rad
        return period_rad / cycle_time - mean_angular_velocity_rad_s

    low = floor + 1e-12 * max(scale, abs(floor), 1e-30)
    high = max(floor, 0.0) + 4.0 * scale + 1.0
    while mean_speed_error(high) < 0:
        high *= 4.0
    if mean_speed_error(low) >= 0:
        raise ValueError("no periodic solution with a positive speed")
    return brentq(mean_speed_error, low, high, xtol=1e-14 * high, rtol=1e-15, maxiter=200)


def _speed_extremes(angle, omega, omega_at, period_rad: float):
    """((angle, speed) of the largest speed, the same of the smallest), refined from the fine
    sampling by a bounded scalar search within one sample of each."""
    h = period_rad / len(angle)

    def refine(index, sign):
        a0 = angle[index]
        res = minimize_bounded(lambda x: -sign * float(omega_at(x)), a0 - h, a0 + h, xatol=1e-12)
        return float(res.x) % period_rad, float(omega_at(res.x))

    return refine(first_argmax(omega), +1), refine(first_argmin(omega), -1)


#: Relative tolerance on the flywheel inertia of :func:`flywheel_for_irregularity`: far below
#: the four significant digits an inertia is printed with, well above the rounding of δ(J).
FLYWHEEL_RTOL = 1e-10


def flywheel_for_irregularity(
    gas_torque: PeriodicSeries,
    inertia_with: Callable,
    mean_angular_velocity_rad_s: float,
    irregularity: float,
    first_estimate_kg_m2: float,
) -> float:
    r"""The flywheel inertia :math:`J_f` whose exact periodic solution has the irregularity δ.

    Parameters
    ----------
    gas_torque : PeriodicSeries
        :math:`M_g(\alpha)` over one cycle [N m].
    inertia_with : callable
        ``inertia_with(J_f)`` -> the reduced inertia (as for :func:`periodic_speed`, with a
        ``mean_kg_m2``) with the flywheel :math:`J_f` [kg m^2] added to its constant part.
    mean_angular_velocity_rad_s : float
        Time-mean speed [rad/s].
    irregularity : float
        Required δ = (ω_max − ω_min)/((ω_max + ω_min)/2) of the exact solution, > 0.
    first_estimate_kg_m2 : float
        A first :math:`J_f`, e.g. the energy method's, >= 0.

    Returns
    -------
    float
        :math:`J_f` >= 0 [kg m^2]; 0 when the inertia without a flywheel already keeps δ at or
        below the required one.

    Notes
    -----
    δ falls monotonically as the constant inertia grows (about as 1/J), so the root is unique. It
    is bracketed starting from the estimate scaled by δ(estimate)/δ (that 1/J law applied to the
    mean total inertia) and refined by Brent's method.
    """
    if irregularity <= 0:
        raise ValueError("irregularity must be positive")

    def excess(flywheel: float) -> float:
        speed = periodic_speed(gas_torque, inertia_with(flywheel), mean_angular_velocity_rad_s)
        return speed.irregularity - irregularity

    start = max(float(first_estimate_kg_m2), 0.0)
    rest = inertia_with(0.0).mean_kg_m2
    at_start = excess(start)
    if at_start == 0:
        return start
    scaled = (start + rest) * (at_start + irregularity) / irregularity - rest
    if at_start > 0:  # too light: the root lies above
        low, high = start, max(scaled, start) * 1.01 + 1e-12 * rest
        for _ in range(200):  # δ -> 0 as J grows: a doubling passes the root
            if excess(high) <= 0:
                break
            low, high = high, 2.0 * high + rest
    else:  # heavier than needed: the root lies below, or no flywheel is needed
        if excess(0.0) <= 0:
            return 0.0
        low, high = 0.0, start
        guess = max(scaled, 0.0) * 0.99
        if 0.0 < guess < start and excess(guess) > 0:
            low = guess
    return brentq(excess, low, high, xtol=FLYWHEEL_RTOL * rest, rtol=FLYWHEEL_RTOL, maxiter=200)


# --------------------------------------------------------------------------- time stepping


def single_mass_rhs(gas_torque: PeriodicSeries, load_torque_Nm: float, inertia: Callable):
    r"""Right-hand side of eq. (motion) in time, state ``y = (alpha, omega)``.

    Returns ``f(t, y) = (omega, (M_g(alpha) - M_load - J'(alpha) omega^2 / 2) / J(alpha))``.
    """

    if isinstance(inertia, InertiaSeries) and gas_torque.columns == 1:
        discs = DiscSeries(gas_torque, [inertia])

        def scalar_rhs(t, y):
            alpha, omega = y[0], y[1]
            m, j, dj = discs.scalar(alpha)
            return np.array([omega, (m - load_torque_Nm - 0.5 * dj * omega * omega) / j])

        return scalar_rhs

    def rhs(t, y):
        alpha, omega = y[0], y[1]
        j, dj = inertia(alpha)
        return np.array(
            [omega, (gas_torque(alpha) - load_torque_Nm - 0.5 * dj * omega * omega) / j]
        )

    return rhs


class SolverRun(NamedTuple):
    """One solve_ivp run with its cost."""

    method: str
    rtol: float
    success: bool
    message: str
    nfev: int  # right-hand-side evaluations (including finite-difference Jacobians)
    njev: int
    nlu: int
    steps: int
    time_s: float
    progress: float  # fraction of the interval covered (1 when it finished)
    t: np.ndarray
    y: np.ndarray
    sol: object  # dense output or None
    t_events: list | None = None
    y_events: list | None = None

    @property
    def steps_needed(self) -> float:
        """Steps for the whole interval: the steps taken, extrapolated when the run was stopped."""
        if self.progress <= 0:
            return float("inf")
        return self.steps / min(self.progress, 1.0)


#: scipy.integrate's solver classes by name (looked up when used: scipy is imported on first use)
_METHODS = ("RK45", "Radau", "BDF", "LSODA")


def run_solver(
    fun,
    t_span,
    y0,
    method: str,
    rtol: float,
    atol,
    jac=None,
    max_nfev: int | None = None,
    dense_output: bool = False,
    events=None,
) -> SolverRun:
    """Run one of scipy's solvers once, timing it and counting its work.

    Without ``max_nfev`` this is :func:`scipy.integrate.solve_ivp`. With it the solver is
    stepped directly (solve_ivp's own loop, without events) and stopped once it has used
    ``max_nfev`` right-hand-side evaluations: an explicit solver crawling through a stiff
    problem is then reported unsuccessful, with the steps it took and the fraction of the
    interval it covered.
    """
    options = {}
    if jac is not None and method in ("Radau", "BDF", "LSODA"):
        options["jac"] = jac
    integrate.load()  # scipy imported (on first use) before the clock starts: the solver's time only
    if max_nfev is None:
        return _solve_ivp_run(fun, t_span, y0, method, rtol, atol, options, dense_output, events)
    return _limited_run(fun, t_span, y0, method, rtol, atol, options, max_nfev)


def _solve_ivp_run(
    fun, t_span, y0, method: str, rtol: float, atol, options: dict, dense_output: bool, events
) -> SolverRun:
    """One timed :func:`scipy.integrate.solve_ivp` run."""
    start = time.perf_counter()
    sol = integrate.solve_ivp(
        fun,
        t_span,
        y0,
        method=method,
        rtol=rtol,
        atol=atol,
        dense_output=dense_output,
        events=events,
        **options,
    )
    elapsed = time.perf_counter() - start
    progress = (sol.t[-1] - t_span[0]) / (t_span[1] - t_span[0]) if sol.t.size else 0.0
    return SolverRun(
        method,
        rtol,
        bool(sol.status >= 0),
        str(sol.message),
        int(sol.nfev),
        int(sol.njev),
        int(sol.nlu),
        int(sol.t.size - 1),
        elapsed,
        float(progress),
        sol.t,
        sol.y,
        sol.sol if dense_output else None,
        sol.t_events,
        sol.y_events,
    )


def _limited_run(
    fun, t_span, y0, method: str, rtol: float, atol, options: dict, max_nfev: int
) -> SolverRun:
    """One timed run of the solver stepped directly, stopped after ``max_nfev`` evaluations."""
    start = time.perf_counter()
    if method not in _METHODS:
        raise ValueError(f"unknown solver {method!r}; allowed: {', '.join(_METHODS)}")
    solver = getattr(integrate, method)(
        fun, t_span[0], np.asarray(y0, dtype=float), t_span[1], rtol=rtol, atol=atol, **options
    )
    ts, ys = [solver.t], [solver.y.copy()]
    message = "finished"
    success = True
    while solver.status == "running":
        if solver.nfev >= max_nfev:
            success, message = False, f"stopped after {solver.nfev} evaluations"
            break
        result = solver.step()
        if solver.status == "failed":
            success, message = False, str(result)
            break
        ts.append(solver.t)
        ys.append(solver.y.copy())
    elapsed = time.perf_counter() - start
    progress = (solver.t - t_span[0]) / (t_span[1] - t_span[0])
    return SolverRun(
        method,
        rtol,
        success,
        message,
        int(solver.nfev),
        int(solver.njev),
        int(solver.nlu),
        len(ts) - 1,
        elapsed,
        float(progress),
        np.array(ts),
        np.array(ys).T,
        None,
    )


def phase_error(run: SolverRun, reference: PeriodicSpeed) -> float:
    r"""Largest :math:`|\omega-\omega_{ref}(\alpha)|/\omega_m` over the solver's own steps.

    Comparing at the solver's angle, not at its time, measures the error of the
    :math:`(\alpha,\omega)` phase curve, which is exactly known; NaN for a failed run.
    """
    if not run.success or run.y.shape[1] == 0:
        return float("nan")
    alpha, omega = run.y[0], run.y[1]
    return float(np.max(np.abs(omega - reference.omega_at(alpha))) / reference.omega_mean_rad_s)


# --------------------------------------------------------------------------- stiffness


def _rk45_stability(z):
    """Stability function R(z) = 1 + z b^T (I - zA)^-1 1 of scipy's RK45 (Dormand-Prince)."""
    b = np.asarray(integrate.RK45.B, dtype=float)
    s = len(b)
    A = np.zeros((s, s))
    A[:, : integrate.RK45.A.shape[1]] = integrate.RK45.A[:s]
    # Explicit: A is strictly lower triangular, so R is the polynomial 1 + sum_k z^k b^T A^(k-1) 1.
    coefficients = [1.0]
    power = np.ones(s)
    for _ in range(s):
        coefficients.append(float(b @ power))
        power = A @ power
    z = np.asarray(z, dtype=complex)
    return np.polynomial.polynomial.polyval(z, coefficients)


def stable_step_s(eigenvalues) -> float:
    r"""Largest step h for which scipy's RK45 is stable for all given eigenvalues [s].

    Parameters
    ----------
    eigenvalues : array_like of complex
        Eigenvalues :math:`\lambda` of the linearised system [1/s]; those below 1e-9 of the
        largest in magnitude (the rigid rotation's zeros, up to round-off) are ignored.

    Returns
    -------
    float
        The smallest, over the eigenvalues, of the first h along the ray :math:`h\lambda`
        at which :math:`|R(h\lambda)|` exceeds 1 (inf if none is limiting).

    Notes
    -----
    Hairer & Wanner (1996), §IV.2: an explicit Runge-Kutta method is stable while
    :math:`h\lambda` stays in :math:`\{|R(z)|\le 1\}`. R is the stability polynomial of
    the Dormand-Prince pair, computed from scipy's own Butcher tableau: it reaches 3.31 on
    the negative real axis but only about 1.0 on the imaginary axis, so a lightly damped
    mode of angular frequency :math:`\omega_s` limits the step to roughly :math:`1/\omega_s`.
    """
    limit = math.inf
    values = np.atleast_1d(np.asarray(eigenvalues, dtype=complex))
    largest = float(np.max(np.abs(values))) if values.size else 0.0
    for lam in values:
        size = abs(lam)
        if size <= 1e-9 * largest or size == 0:
            continue
        direction = lam / size
        radii = np.linspace(1e-3, 6.0, 6000)
        growth = np.abs(_rk45_stability(radii * direction)) - 1.0
        bad = np.nonzero(growth > 1e-12)[0]
        if bad.size == 0:
            continue
        first = bad[0]
        if first == 0:
            radius = 0.0  # unstable from the start (e.g. a purely imaginary eigenvalue)
        else:
            radius = brentq(
                lambda r: abs(_rk45_stability(r * direction)) - 1.0 - 1e-12,  # noqa: B023 - called within this iteration
                radii[first - 1],
                radii[first],
            )
        limit = min(limit, radius / size)
    return limit


class SolverChoice(NamedTuple):
    """The automatic choice between an explicit and an implicit solver, with its numbers."""

    method: str
    stiff: bool
    fastest_rad_s: float  # largest |eigenvalue| of the linearisation
    stable_step_s: float  # largest stable RK45 step
    stability_steps: float  # interval / stable step: steps RK45 needs for stability alone
    resolved_frequency_rad_s: float  # fastest motion the solution must follow
    resolution_steps: float  # steps needed to follow it (STEPS_PER_PERIOD per period)
    ratio: float  # stability_steps / resolution_steps


#: Steps per period an accurate solution of a harmonic needs (5th-order methods, rtol ~1e-5).
STEPS_PER_PERIOD = 20
#: An implicit (Radau) step costs about as much as two explicit (RK45) steps here (Newton
#: iterations with an LU of a small matrix against six stages), so it pays when stability
#: forces the explicit step below half of what accuracy needs.
STIFFNESS_THRESHOLD = 2.0


def choose_solver(eigenvalues, interval_s: float, resolved_frequency_rad_s: float) -> SolverChoice:
    r"""Explicit RK45 or implicit Radau, from the eigenvalues of the linearised problem.

    Parameters
    ----------
    eigenvalues : array_like of complex
        Eigenvalues of the linearisation [1/s] (for the shaft: of its elastic modes).
    interval_s : float
        Integration interval (one cycle) [s].
    resolved_frequency_rad_s : float
        Highest angular frequency the solution must follow: the highest significant
        harmonic of the excitation [rad/s].

    Returns
    -------
    SolverChoice
        ``stiff`` when the steps RK45 needs for stability (:func:`stable_step_s`) exceed
        :data:`STIFFNESS_THRESHOLD` times the steps needed to follow the solution
        (:data:`STEPS_PER_PERIOD` per period of ``resolved_frequency_rad_s``): the classical
        definition of stiffness (Hairer & Wanner 1996, §IV.1: stability, not accuracy,
        limits the explicit step). The implicit method chosen is Radau IIA (order 5): it is
        A- and L-stable, so lightly damped fast modes near the imaginary axis are stable at
        any step; BDF of orders 3-5 (and LSODA's stiff part) is not A-stable there.
    """
    values = np.atleast_1d(np.asarray(eigenvalues, dtype=complex))
    fastest = float(np.max(np.abs(values))) if values.size else 0.0
    h = stable_step_s(values) if fastest > 0 else math.inf
    stability = interval_s / h if math.isfinite(h) else 0.0
    resolution = max(STEPS_PER_PERIOD * resolved_frequency_rad_s * interval_s / (2 * math.pi), 1.0)
    ratio = stability / resolution
    stiff = ratio > STIFFNESS_THRESHOLD
    return SolverChoice(
        "Radau" if stiff else "RK45",
        bool(stiff),
        fastest,
        h,
        stability,
        resolved_frequency_rad_s,
        resolution,
        ratio,
    )


def significant_order(orders, coefficients, fraction: float = 0.01) -> float:
    """Highest harmonic order whose amplitude is at least ``fraction`` of the largest."""
    amplitude = np.abs(np.asarray(coefficients))
    if amplitude.size == 0 or amplitude.max() == 0:
        return 0.0
    return float(np.asarray(orders)[amplitude >= fraction * amplitude.max()].max())


def harmonic_amplitudes(values, cycle_revolutions: float, max_order: float):
    r"""Harmonic orders of a periodic quantity sampled over one cycle.

    Parameters
    ----------
    values : array_like, shape (N,)
        Samples on the cycle grid (end point excluded).
    cycle_revolutions : float
        Crankshaft revolutions per cycle (2 for a four-stroke engine).
    max_order : float
        Highest order kept (orders are per crankshaft revolution).

    Returns
    -------
    (orders, coefficients)
        Orders :math:`\nu = k/\text{revolutions}` (0.5, 1, 1.5 ... for a four-stroke engine)
        and complex coefficients :math:`c_\nu` with
        :math:`f(\alpha)=\bar f+\sum_\nu |c_\nu|\cos(\nu\alpha+\arg c_\nu)`.
    """
    values = np.asarray(values, dtype=float)
    n = values.size
    spectrum = np.fft.rfft(values) / n
    k = np.arange(spectrum.size)
    orders = k / cycle_revolutions
    keep = (k > 0) & (orders <= max_order + 1e-12)
    coefficients = 2.0 * spectrum[keep]
    if n % 2 == 0:
        coefficients[k[keep] == n // 2] /= 2.0
    return orders[keep], coefficients


@dataclass(frozen=True)
class CrankTrain:
    """Masses of the crank mechanisms as the reduced-inertia model sees them."""

    phase_rad: np.ndarray  # TDC (firing-delay) angle of every cylinder
    crank_of_cylinder: np.ndarray  # crank index of every cylinder
    reciprocating_kg: np.ndarray  # m_s of every cylinder
    rotating_kg: float  # m_R of one crank (all rods on its pin + crank pin + webs)
    cranks: int
    crank_radius_m: float
    rod_ratio: float
    articulated: bool

    def series(self, constant_kg_m2: float = 0.0, crank: int | None = None) -> InertiaSeries:
        """J(alpha) of the whole engine (or of one crank) plus ``constant_kg_m2``."""
        pick = (
            np.ones(self.phase_rad.size, bool) if crank is None else self.crank_of_cylinder == crank
        )
        cranks = self.cranks if crank is None else 1
        rotating = self.rotating_kg * self.crank_radius_m**2 * cranks
        return inertia_series(
            self.phase_rad[pick],
            self.reciprocating_kg[pick],
            self.crank_radius_m,
            self.rod_ratio,
            constant_kg_m2 + rotating,
        )
