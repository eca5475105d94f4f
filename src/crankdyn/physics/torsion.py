r"""Torsional multi-mass model of the crankshaft: natural modes, harmonic excitation, time response.

The model
---------
A chain of discs on massless shaft spans, numbered from the free end: one disc per crank
(the reduced inertia of its crank mechanisms, variable with the angle), the flywheel and,
optionally, the driven load behind a coupling. Span j between discs j and j+1 has the
torsional stiffness :math:`k_j`. With the twist-dependent restoring torques
:math:`K\theta` and a damping torque :math:`C\dot\theta`, Lagrange's equations give for
every disc

.. math:: J_i(\theta_i)\,\ddot\theta_i + \tfrac12 J_i'(\theta_i)\,\dot\theta_i^2
          = M_{g,i}(\theta_i) - (K\theta)_i - (C\dot\theta)_i - \delta_{i,\mathrm{last}} M_{load},

the multi-mass form of the single-mass equation of :mod:`crankdyn.physics.speed_fluctuation`
(summing the rows with all :math:`\theta_i` equal gives it back: the rigid-shaft limit).

Natural modes are those of the linearised chain with the mean inertias:
:math:`K v = \omega^2 \mathrm{diag}(J) v` (a symmetric-definite generalised eigenproblem; the
first mode is the rigid rotation, :math:`\omega_0 = 0`). For two discs this gives the closed
form :math:`\omega = \sqrt{k (J_1 + J_2)/(J_1 J_2)}`.

Damping is modal: every elastic mode gets the same damping ratio :math:`\zeta`, i.e.
:math:`C = M\Phi\,\mathrm{diag}(2\zeta\omega_s)\,\Phi^T M` with mass-normalised modes
:math:`\Phi^T M \Phi = I` (the rigid mode is undamped, so the mean speed is set by the
torques alone).

Why the problem becomes stiff: the eigenvalues of the linearised system are
:math:`-\zeta\omega_s \pm i\omega_s\sqrt{1-\zeta^2}`. A stiff, light shaft has a large
:math:`\omega_{max}` while the response that matters varies only with the torque harmonics
of the firing frequency. An explicit method must keep :math:`h\lambda` inside its small
stability region for the fastest mode (:func:`crankdyn.physics.speed_fluctuation.stable_step_s`),
an A-stable implicit one only has to follow the solution.

References
----------
Den Hartog, J. P. (1956). *Mechanical Vibrations*, 4th ed. (multi-cylinder engines:
natural frequencies of a shaft with several discs, harmonic orders and the relative
vector sum of each order).
Hairer, E., & Wanner, G. (1996). *Solving Ordinary Differential Equations II*, 2nd ed.
(stiffness; A- and L-stability of Radau IIA; BDF of order >= 3 is not A-stable).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .extrema import first_argmax
from .lazy import linalg
from .speed_fluctuation import DiscSeries, InertiaSeries, PeriodicSeries, SolverRun, run_solver

__all__ = [
    "stiffness_matrix",
    "Modes",
    "natural_modes",
    "modal_damping_matrix",
    "modal_eigenvalues",
    "linear_eigenvalues",
    "forced_response",
    "relative_vector_sum",
    "critical_speed_rpm",
    "ShaftModel",
    "SteadyState",
    "periodic_steady_state",
]


def stiffness_matrix(span_stiffness_N_m_rad) -> np.ndarray:
    r"""Stiffness matrix K of a chain of discs (n = spans + 1) [N m/rad].

    Notes
    -----
    Span j (stiffness :math:`k_j`) adds :math:`k_j` to :math:`K_{jj}` and :math:`K_{j+1,j+1}`
    and :math:`-k_j` to the two off-diagonal places (Den Hartog 1956).
    """
    k = np.asarray(span_stiffness_N_m_rad, dtype=float)
    n = k.size + 1
    K = np.zeros((n, n))
    for j, kj in enumerate(k):
        K[j, j] += kj
        K[j + 1, j + 1] += kj
        K[j, j + 1] -= kj
        K[j + 1, j] -= kj
    return K


class Modes(NamedTuple):
    """Natural modes of a disc chain (ascending; mode 0 is the rigid rotation)."""

    omega_rad_s: np.ndarray  # (n,)
    shapes: (
        np.ndarray
    )  # (n, n), column s: mode s scaled to max |amplitude| = 1, largest entry positive
    mass_normalised: np.ndarray  # (n, n), Phi^T M Phi = I


def natural_modes(inertias_kg_m2, span_stiffness_N_m_rad) -> Modes:
    r"""Natural frequencies and mode shapes from :math:`K v = \omega^2 M v`, M = diag(J).

    Parameters
    ----------
    inertias_kg_m2 : array_like, shape (n,)
        Disc inertias (mean values for the crank discs) [kg m^2], all > 0.
    span_stiffness_N_m_rad : array_like, shape (n - 1,)
        Span stiffnesses [N m/rad], all > 0.

    Returns
    -------
    Modes
    """
    J = np.asarray(inertias_kg_m2, dtype=float)
    if np.any(J <= 0):
        raise ValueError("all inertias must be positive")
    K = stiffness_matrix(span_stiffness_N_m_rad)
    values, vectors = linalg.eigh(K, np.diag(J))
    omega = np.sqrt(np.clip(values, 0.0, None))
    omega[0] = 0.0  # the rigid mode (round-off gives +-1e-8)
    shapes = vectors / np.max(np.abs(vectors), axis=0)
    # Sign convention: the largest entry of each mode is +1.
    signs = np.sign([shapes[first_argmax(np.abs(shapes[:, k])), k] for k in range(J.size)])
    return Modes(omega, shapes * signs, vectors * signs)


def modal_damping_matrix(
    inertias_kg_m2, span_stiffness_N_m_rad, damping_ratio: float
) -> np.ndarray:
    r"""Damping matrix with the ratio :math:`\zeta` in every elastic mode [N m s/rad].

    Notes
    -----
    With mass-normalised modes :math:`\Phi` (:math:`\Phi^TM\Phi=I`), :math:`\Phi^TC\Phi =
    \mathrm{diag}(2\zeta\omega_s)` requires :math:`C = M\Phi\,\mathrm{diag}(2\zeta\omega_s)\,\Phi^TM`.
    """
    J = np.asarray(inertias_kg_m2, dtype=float)
    modes = natural_modes(J, span_stiffness_N_m_rad)
    M = np.diag(J)
    return (
        M
        @ modes.mass_normalised
        @ np.diag(2.0 * damping_ratio * modes.omega_rad_s)
        @ modes.mass_normalised.T
        @ M
    )


def modal_eigenvalues(natural_frequencies_rad_s, damping_ratio: float) -> np.ndarray:
    r"""Eigenvalues :math:`-\zeta\omega_s \pm i\omega_s\sqrt{1-\zeta^2}` of the elastic modes [1/s].

    Exact for the linearised chain with modal damping (each mode is an independent damped
    oscillator); the rigid mode's double zero is left out.
    """
    omega = np.asarray(natural_frequencies_rad_s, dtype=float)
    omega = omega[omega > 0]
    damped = omega * np.sqrt(max(1.0 - damping_ratio**2, 0.0))
    real = -damping_ratio * omega
    return np.concatenate([real + 1j * damped, real - 1j * damped])


def linear_eigenvalues(inertias_kg_m2, stiffness: np.ndarray, damping: np.ndarray) -> np.ndarray:
    r"""Eigenvalues of :math:`\dot x = A x`, :math:`A=\begin{pmatrix}0&I\\-M^{-1}K&-M^{-1}C\end{pmatrix}` [1/s]."""
    J = np.asarray(inertias_kg_m2, dtype=float)
    n = J.size
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -stiffness / J[:, None]
    A[n:, n:] = -damping / J[:, None]
    return np.linalg.eigvals(A)


def forced_response(
    inertias_kg_m2,
    stiffness: np.ndarray,
    damping: np.ndarray,
    node_torque: PeriodicSeries,
    angular_velocity_rad_s: float,
    reference_node: int,
) -> PeriodicSeries:
    r"""Periodic steady response of the linear chain to periodic torques (frequency domain).

    Parameters
    ----------
    inertias_kg_m2 : array_like, shape (n,)
        Constant (mean) disc inertias [kg m^2].
    stiffness, damping : ndarray (n, n)
        K [N m/rad] and C [N m s/rad].
    node_torque : PeriodicSeries
        Torque on every disc (n columns) as a function of the mean shaft angle
        :math:`\alpha=\omega_n t` over one cycle [N m]; its column means must sum to zero
        (the load balances the engine).
    angular_velocity_rad_s : float
        Mean speed :math:`\omega_n` [rad/s].
    reference_node : int
        Disc whose mean twist is zero.

    Returns
    -------
    PeriodicSeries
        Disc angles relative to the rigid rotation, :math:`x_i(\alpha)` [rad], with
        :math:`\theta_i = \alpha + x_i`. Harmonic k of the cycle (frequency
        :math:`\Omega_k = k\,\omega_n\,2\pi/\Phi`) solves
        :math:`(K-\Omega_k^2M+i\Omega_k C)X_k=T_k`; the mean twist solves :math:`K x_0 = T_0`
        with the reference disc fixed.

    Notes
    -----
    The classical forced-vibration solution of a disc chain (Den Hartog 1956) with
    constant inertias and the torques of gas and inertia forces at constant speed; used to
    start the time integration of the nonlinear model close to its periodic state, and as a
    check of it.
    """
    J = np.asarray(inertias_kg_m2, dtype=float)
    n = J.size
    M = np.diag(J)
    coefficients = np.empty_like(node_torque.coefficients)
    for k, (omega_k, torque_k) in enumerate(
        zip(node_torque.wavenumbers * angular_velocity_rad_s, node_torque.coefficients, strict=True)
    ):
        coefficients[k] = np.linalg.solve(
            stiffness - omega_k**2 * M + 1j * omega_k * damping, torque_k
        )
    keep = np.array([i for i in range(n) if i != reference_node])
    mean = np.zeros(n)
    mean[keep] = np.linalg.solve(stiffness[np.ix_(keep, keep)], node_torque.mean[keep])
    return PeriodicSeries(mean, coefficients, node_torque.period_rad)


def relative_vector_sum(mode_amplitude_per_cylinder, phase_rad, order: float) -> float:
    r"""Relative vector sum :math:`|\sum_i a_i e^{i\nu\varphi_i}|` of one harmonic order.

    Parameters
    ----------
    mode_amplitude_per_cylinder : array_like
        Mode-shape amplitude at the crank of each cylinder (max 1 over the chain).
    phase_rad : array_like
        Firing delay of each cylinder in shaft angle [rad].
    order : float
        Harmonic order :math:`\nu` per crankshaft revolution.

    Returns
    -------
    float
        The work the order-:math:`\nu` torque of every cylinder does on the mode is
        proportional to this sum (Den Hartog 1956): "major orders" (multiples of
        cylinders/2 for an even-firing four-stroke in-line engine) have all vectors in phase.
    """
    a = np.asarray(mode_amplitude_per_cylinder, dtype=float)
    phi = np.asarray(phase_rad, dtype=float)
    return float(abs(np.sum(a * np.exp(1j * order * phi))))


def crank_vector_sum(mode_amplitude_per_crank, crank_coefficients) -> float:
    r"""Relative vector sum of one order over the cranks, from each crank's own harmonic:
    :math:`|\sum_k a_k c_{\nu,k}| / |c_{\nu,1}|`.

    Parameters
    ----------
    mode_amplitude_per_crank : array_like, shape (m,)
        Mode-shape amplitude at each crank's disc.
    crank_coefficients : array_like of complex, shape (m,)
        The order's complex harmonic coefficient of each crank's torque (all its cylinders).

    Returns
    -------
    float
        :func:`relative_vector_sum` where each crank's torque is the first one's shifted by its
        firing delay, :math:`c_{\nu,k} = c_{\nu,1} e^{-i\nu\varphi_k}`; it stays right where
        a crank carries several cylinders (a V engine's pin), whose order-:math:`\nu`
        harmonics the crank's coefficient already sums (a sum over the cylinders with the
        crank's harmonic would count them twice). 0 where the first crank's harmonic is nil.
    """
    a = np.asarray(mode_amplitude_per_crank, dtype=float)
    c = np.asarray(crank_coefficients, dtype=complex)
    first = abs(c[0])
    return float(abs(np.sum(a * c)) / first) if first > 0 else 0.0


def critical_speed_rpm(natural_frequency_rad_s, order):
    r"""Crankshaft speed at which order :math:`\nu` resonates with a mode: :math:`n = 30\omega_s/(\pi\nu)` [rpm]."""
    return 30.0 * np.asarray(natural_frequency_rad_s) / (np.pi * np.asarray(order))


class ShaftModel:
    r"""Right-hand side and Jacobian of the disc chain in twist coordinates.

    The discs are numbered along the shaft (free end first); the crank discs have the
    variable reduced inertia of their crank mechanisms, the others (a pulley or timing gear
    at the free end, the flywheel, the load) constant inertias. The state is
    ``z = (theta_ref, phi_i for every disc but the reference disc, omega_1..omega_n)``: the
    reference disc (the flywheel) carries the absolute angle and the others their twist
    :math:`\varphi_i=\theta_i-\theta_{ref}` relative to it, so the error control of the
    solvers sees the small twists directly rather than as tiny differences of large angles.

    Parameters
    ----------
    crank_gas_torque : PeriodicSeries
        Gas torque of every crank (one column per crank, in shaft order) over the cycle [N m].
    crank_inertia : list of InertiaSeries
        Reduced inertia of every crank disc.
    crank_nodes : sequence of int
        Disc index of every crank.
    inertias_kg_m2 : array_like, shape (n,)
        Inertia of every disc; the values at the crank discs are ignored (taken from
        ``crank_inertia``).
    stiffness, damping : ndarray (n, n)
        K and C.
    load_torque_Nm : float
        Constant load torque on the last disc (:func:`periodic_steady_state` adjusts it so that
        the load absorbs what the engine delivers less what the shaft damping dissipates).
    reference_node : int
        Index of the disc whose absolute angle is kept (the flywheel).
    """

    def __init__(
        self,
        crank_gas_torque: PeriodicSeries,
        crank_inertia: list[InertiaSeries],
        crank_nodes,
        inertias_kg_m2,
        stiffness,
        damping,
        load_torque_Nm: float,
        reference_node: int,
    ):
        self.torque = crank_gas_torque
        self.crank_nodes = np.asarray(crank_nodes, dtype=int)
        self.cranks = self.crank_nodes.size
        self.base_inertia = np.asarray(inertias_kg_m2, dtype=float).copy()
        self.n = self.base_inertia.size
        self.K = np.asarray(stiffness, dtype=float)
        self.C = np.asarray(damping, dtype=float)
        self.load = float(load_torque_Nm)
        self.ref = int(reference_node)
        self.others_idx = np.array([i for i in range(self.n) if i != self.ref])
        # Crank inertia series stacked: J_k(theta) = c0_k + Re sum_q C_kq e^{i q theta}.
        width = max(s.coefficients.size for s in crank_inertia)
        self.c0 = np.array([s.constant_kg_m2 for s in crank_inertia])
        coeffs = np.zeros((self.cranks, max(width, 1)), dtype=complex)
        for k, s in enumerate(crank_inertia):
            coeffs[k, : s.coefficients.size] = s.coefficients
        self.coeffs = coeffs
        self.q = np.arange(1, coeffs.shape[1] + 1)
        self.dcoeffs = 1j * self.q * coeffs
        self.base_inertia[self.crank_nodes] = self.c0
        self.mean_inertias = self.base_inertia.copy()
        self.discs = DiscSeries(crank_gas_torque, list(crank_inertia))
        # theta = P @ z_theta; d z_theta / dt = Q @ omega
        P = np.zeros((self.n, self.n))
        Q = np.zeros((self.n, self.n))
        P[:, 0] = 1.0
        Q[0, self.ref] = 1.0
        for row, node in enumerate(self.others_idx, start=1):
            P[node, row] = 1.0
            Q[row, node] = 1.0
            Q[row, self.ref] = -1.0
        self.P, self.Q = P, Q
        self.KP = self.K @ P

    def angles(self, z) -> np.ndarray:
        return self.P @ z[: self.n]

    def state(self, theta, omega) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        z_theta = np.concatenate([[theta[self.ref]], theta[self.others_idx] - theta[self.ref]])
        return np.concatenate([z_theta, np.asarray(omega, dtype=float)])

    def inertia(self, theta_cranks):
        base = np.exp(1j * theta_cranks)[:, None]
        phase = np.cumprod(np.broadcast_to(base, (self.cranks, self.q.size)), axis=1)
        j = self.c0 + (phase * self.coeffs).sum(axis=1).real
        dj = (phase * self.dcoeffs).sum(axis=1).real
        return j, dj

    def forces(self, theta, omega):
        """Generalised forces without the shaft (gas torque, the 1/2 J' omega^2 term, the load),
        the disc inertias and J' of the cranks."""
        f = np.zeros(self.n)
        values = self.discs(theta[self.crank_nodes])
        j, dj = values[:, 1], values[:, 2]
        f[self.crank_nodes] = values[:, 0] - 0.5 * dj * omega[self.crank_nodes] ** 2
        f[-1] -= self.load
        inertia = self.base_inertia.copy()
        inertia[self.crank_nodes] = j
        return f, inertia, dj

    def __call__(self, t, z):
        n = self.n
        theta = self.P @ z[:n]
        omega = z[n:]
        f, inertia, _ = self.forces(theta, omega)
        accel = (f - self.K @ theta - self.C @ omega) / inertia
        return np.concatenate([self.Q @ omega, accel])

    def jacobian(self, t, z):
        """Jacobian of the shaft terms and of the 1/2 J' omega^2 term; the slow variation of
        the gas torque and the inertia with the angle is left out (the implicit solvers need
        only an approximation)."""
        n = self.n
        theta = self.P @ z[:n]
        omega = z[n:]
        _, inertia, dj = self.forces(theta, omega)
        j = inertia[self.crank_nodes]
        jac = np.zeros((2 * n, 2 * n))
        jac[:n, n:] = self.Q
        jac[n:, :n] = -self.KP / inertia[:, None]
        dd = -self.C / inertia[:, None]
        dd[self.crank_nodes, self.crank_nodes] -= dj * omega[self.crank_nodes] / j
        jac[n:, n:] = dd
        return jac

    def quasi_static_state(self, theta_ref: float, omega) -> np.ndarray:
        r"""Twists that balance the torques at ``theta_ref`` with a common angular acceleration.

        Solves :math:`K\theta = f - J a_0` with :math:`a_0=\sum f/\sum J` (the rigid
        acceleration), fixing the reference disc: a start without the transient that an
        untwisted shaft would ring with.
        """
        omega = np.broadcast_to(np.asarray(omega, dtype=float), (self.n,)).copy()
        theta = np.full(self.n, float(theta_ref))
        keep = self.others_idx
        for _ in range(3):  # the twists move the crank angles a little: iterate
            f, inertia, _ = self.forces(theta, omega)
            rhs = f - inertia * (f.sum() / inertia.sum())
            theta = np.full(self.n, float(theta_ref))
            theta[keep] += np.linalg.solve(self.K[np.ix_(keep, keep)], rhs[keep])
        return self.state(theta, omega)

    def energy(self, z) -> float:
        """Kinetic energy of the discs plus the strain energy of the spans [J]."""
        theta = self.P @ z[: self.n]
        omega = z[self.n :]
        _, inertia, _ = self.forces(theta, omega)
        return float(0.5 * np.sum(inertia * omega**2) + 0.5 * theta @ self.K @ theta)


class SteadyState(NamedTuple):
    """Result of :func:`periodic_steady_state`."""

    state: np.ndarray  # z at the start of the periodic cycle (reference angle = start angle)
    cycle_time_s: float
    cycles: int
    converged: bool
    change: float  # last change per cycle (scaled, see periodic_steady_state)
    history: list  # change per cycle
    runs: list  # SolverRun of each cycle (with dense output; the last one is the periodic cycle)
    load_torque_Nm: float  # the load torque of the steady state


def periodic_steady_state(
    model: ShaftModel,
    z0,
    period_rad: float,
    cycle_time_guess_s: float,
    method: str,
    rtol: float,
    atol,
    twist_scale_rad: float,
    speed_scale_rad_s: float,
    tolerance: float = 1e-6,
    max_cycles: int = 30,
) -> SteadyState:
    r"""Integrate cycle after cycle until the state returns to itself (a periodic steady state).

    Each cycle ends when the reference (flywheel) angle has advanced by the cycle angle
    :math:`\Phi` (a terminal event), and the next starts from that state shifted back by
    :math:`\Phi` (the equations are :math:`\Phi`-periodic in the angles). The change per cycle is
    :math:`\max(\max|\Delta\varphi|/\varphi_s, \max|\Delta\omega|/\omega_s)` with the given
    scales (the twist and the speed swing); the iteration stops when it falls below
    ``tolerance``, which must stay above the solver's own error at ``rtol``. Transients decay like
    :math:`e^{-\zeta\omega_1 t}`, so the number of cycles grows with light damping.

    The load torque is corrected after every cycle by the change of the total energy
    divided by the cycle angle: the shaft damping dissipates a little of the engine's work,
    and a load equal to the mean gas torque would slow the (undamped) rigid rotation a
    little every cycle. At the steady state the energy returns to itself exactly, the mean
    speed is the starting one and the load torque is the mean gas torque less the damping loss.
    The model's ``load`` is left at that value.
    """
    z = np.asarray(z0, dtype=float).copy()
    start_angle = float(z[0])
    n = model.n
    history: list[float] = []
    runs: list[SolverRun] = []
    cycle_time = cycle_time_guess_s

    def one_cycle(t, y):
        return y[0] - (start_angle + period_rad)

    one_cycle.terminal = True  # type: ignore[attr-defined]  # scipy reads an event's attributes
    one_cycle.direction = 1  # type: ignore[attr-defined]
    change = np.inf
    for cycle in range(1, max_cycles + 1):
        run = run_solver(
            model,
            (0.0, 2.0 * cycle_time),
            z,
            method,
            rtol,
            atol,
            jac=model.jacobian,
            events=one_cycle,
            dense_output=True,
        )
        runs.append(run)
        if not run.success or not run.t_events or run.t_events[0].size == 0 or run.y_events is None:
            return SteadyState(z, cycle_time, cycle, False, float("nan"), history, runs, model.load)
        cycle_time = float(run.t_events[0][0])
        z_end = np.array(run.y_events[0][0], dtype=np.float64)
        z_end[0] -= period_rad
        gained = model.energy(z_end) - model.energy(z)
        model.load += gained / period_rad
        change = max(
            float(np.max(np.abs(z_end[1:n] - z[1:n]))) / twist_scale_rad,
            float(np.max(np.abs(z_end[n:] - z[n:]))) / speed_scale_rad_s,
        )
        history.append(change)
        # Keep the starting speed level: the speed the rigid rotation gained or lost in this
        # cycle (inertia-weighted mean) is given back before the next one; with the corrected
        # load this vanishes at convergence, so the converged state is a true periodic orbit.
        weights = model.mean_inertias / model.mean_inertias.sum()
        z_end[n:] += float(weights @ (z[n:] - z_end[n:]))
        z = z_end
        z[0] = start_angle
        if change < tolerance:
            return SteadyState(z, cycle_time, cycle, True, change, history, runs, model.load)
    return SteadyState(z, cycle_time, max_cycles, False, change, history, runs, model.load)
