"""Tracking the transmit time: the report's estimator, its exact error recursion, the steady state and
the three-satellite outage (ATC-10, Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972: §4.5, App. H).

**Scalar reduction (exact).** At an epoch with K ≥ 4 satellites the clock pseudo-measurement

    y_n = 1'(I − P_n)(T̂_n − k_n)/β_n = τ_n + v_n,   Var v_n = R_n = σ²/β_n,

is uncorrelated with the position part F'ε. Then (4.5.3) is τ̂_0 = y_0, and (4.5.16) is
τ̂_n = τ̂⁻ + g_n(y_n − τ̂⁻) with τ̂⁻ = τ̂_{n−1} + τ̄ and g_n = γ_nβ_n = σ²_τn/(σ²_τn + R_n) (eq 4.5.20),
a level-only Kalman-type filter whose prior variance accounts for the correlation of the previous
error with the new increment (eqs 4.5.21–4.5.24, corrected). The position follows by (4.5.17):
p̂_n = p* + (U'U)⁻¹U'(T̂_n − k_n − τ̂_n 1); with three satellites (4.5.28), p̂_n = p* + U⁻¹(…).

**Error recursion.** With V_n = Var ξ_τn and χ_n = −E[Δ_j ξ_τn] (j > n; the same for all
such j under ρ = 1):

    V⁻ = V_{n−1} + 2σ0² + 2χ_{n−1}                   (4.5.21/4.5.24: σ²_τn)
    χ⁻ = χ_{n−1} + σ0²
    V_n = (1 − g)²V⁻ + g²R_n,  χ_n = (1 − g)χ⁻      (4.5.18, 4.5.22; g = 0 in an outage, 4.5.27)

which for the optimal g is V_n = (1 − g)V⁻ = σ²γ_n. The mean-square position error is
E‖ξ_pn‖² = σ²·tr_n + V_n·b_n (eq 4.5.35, corrected), in c = 1 units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from motionsig_cli.surveillance.clock import alpha_of, psi
from motionsig_cli.surveillance.multilateration import directions, qr_parts, solve_upper

__all__ = [
    "ClockRecursion",
    "RateKalmanClock",
    "ReportClock",
    "SteadyState",
    "clock_error_recursion",
    "outage_gamma_tilde",
    "position_update",
    "pseudo_measurement",
    "steady_state",
    "table_4_3_values",
]


@dataclass(frozen=True)
class ClockRecursion:
    """Result of :func:`clock_error_recursion` (arrays (..., E) over epochs n = 0..E−1).

    Attributes:
        V: Var ξ_τn, the clock-error variance after epoch n [ns²].
        chi: χ_n = −E[Δ_j ξ_τn], j > n [ns²].
        prior: σ²_τn = V⁻, the prediction variance (NaN at LS epochs) [ns²].
        gain: g_n = γ_nβ_n (1 at LS epochs, 0 without a clock measurement).
    """

    V: np.ndarray
    chi: np.ndarray
    prior: np.ndarray
    gain: np.ndarray


def clock_error_recursion(
    sigma: float,
    sigma0: np.ndarray | float,
    beta: np.ndarray,
    update: np.ndarray,
    *,
    reinit: np.ndarray | None = None,
    gain: np.ndarray | float | None = None,
) -> ClockRecursion:
    """The exact error recursion of the report's clock tracker (eqs 4.5.5, 4.5.18–4.5.27).

    Args:
        sigma: TOA error σ [ns].
        sigma0: clock scale σ0 [ns]; any shape broadcasting against ``beta[..., 0]`` (cases).
        beta: (..., E) β_n of the satellites in use at each epoch (ignored where ``update`` is False).
        update: (E,) True where the epoch carries clock information (K ≥ 4); False in an outage.
        reinit: (E,) True where the estimator restarts by least squares (epoch 0 always does; the
            report's choice after an outage). Requires ``update`` there.
        gain: None for the optimal recursive gain; a constant g (broadcast over cases) for the
            report's steady-state shortcut, applied from n = 1 (V = (1−g)²V⁻ + g²R).

    Returns:
        :class:`ClockRecursion`.
    """
    beta = np.asarray(beta, dtype=float)
    update = np.asarray(update, dtype=bool)
    E = update.shape[-1]
    reinit = np.zeros(E, dtype=bool) if reinit is None else np.asarray(reinit, dtype=bool).copy()
    reinit[0] = True
    if not update[0] or np.any(reinit & ~update):
        raise ValueError("a least-squares (re)initialisation needs K >= 4 satellites at that epoch")
    s02 = np.asarray(sigma0, dtype=float) ** 2
    shape = np.broadcast_shapes(beta.shape[:-1], s02.shape)
    beta = np.broadcast_to(beta, (*shape, E))
    s02 = np.broadcast_to(s02, shape)
    g_fixed = None if gain is None else np.broadcast_to(np.asarray(gain, dtype=float), shape)
    V = np.empty((*shape, E))
    chi = np.empty_like(V)
    prior = np.full_like(V, np.nan)
    g_out = np.empty_like(V)
    sigma2 = float(sigma) ** 2
    v = np.zeros(shape)
    c = np.zeros(shape)
    for n in range(E):
        if reinit[n]:
            v = sigma2 / beta[..., n]  # (4.5.5): σ²_ξτ0 = σ²/β_0
            c = np.zeros(shape)  # ξ_τ depends on ε only
            g = np.ones(shape)
        else:
            vm = v + 2.0 * s02 + 2.0 * c  # (4.5.21)/(4.5.24): σ²_τn
            cm = c + s02
            prior[..., n] = vm
            if update[n]:
                R = sigma2 / beta[..., n]
                if g_fixed is None:
                    g = vm / (vm + R)  # (4.5.20): g = γ_n β_n
                    a = R / (vm + R)  # a_n = 1 − g without cancellation when σ0 ≫ σ
                    v = a * vm  # (4.5.18): σ²γ_n
                else:
                    g = g_fixed
                    a = 1.0 - g
                    v = a**2 * vm + g**2 * R
                c = a * cm  # (4.5.22): a_n(χ + σ0²)
            else:
                g = np.zeros(shape)
                v, c = vm, cm  # (4.5.27) in recursive form
        V[..., n], chi[..., n], g_out[..., n] = v, c, g
    return ClockRecursion(V=V, chi=chi, prior=prior, gain=g_out)


@dataclass(frozen=True)
class SteadyState:
    """Steady state of the tracker with constant β (eqs 4.5.26, 4.5.32–4.5.34)."""

    alpha: np.ndarray
    psi: np.ndarray
    gamma: np.ndarray
    V: np.ndarray
    chi: np.ndarray


def steady_state(sigma: float, sigma0: np.ndarray | float, beta: np.ndarray | float) -> SteadyState:
    """α = (8/27)σ0²β/σ² (4.5.32), ψ(α) (4.5.34), γ = ψ/β (4.5.33), V = σ²ψ/β and χ = σ0²(1 − ψ)/ψ."""
    a = alpha_of(sigma0, sigma, beta)
    p = psi(a)
    s02 = np.asarray(sigma0, dtype=float) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        chi = np.where(p > 0, s02 * (1.0 - p) / np.where(p > 0, p, 1.0), 0.0)
    return SteadyState(alpha=a, psi=p, gamma=p / beta, V=float(sigma) ** 2 * p / beta, chi=chi)


def outage_gamma_tilde(
    sigma: float, sigma0: np.ndarray | float, beta: np.ndarray | float, m: np.ndarray | int
) -> np.ndarray:
    """γ̃_{N+m} = σ²_ξτ/σ² after m outage epochs from steady state (eq 4.5.37′ = 4.5.27/σ²):
    (1/β)[ψ + (27/8)α{((2 − ψ)/ψ)m + m²}], written as ψ/β + (σ0/σ)²{((2 − ψ)/ψ)m + m²}."""
    ss = steady_state(sigma, sigma0, beta)
    m = np.asarray(m, dtype=float)
    r2 = (np.asarray(sigma0, dtype=float) / sigma) ** 2
    return ss.psi / beta + r2 * ((2.0 - ss.psi) / ss.psi * m + m**2)


def table_4_3_values(
    sigma: float,
    sigma0: np.ndarray | float,
    beta: float,
    tr: float,
    b: float,
    tr3: float,
    b3: float,
    c_ft_per_ns: float,
) -> dict[str, np.ndarray]:
    """Table 4.3's columns from the constellation constants:
    e0 = cσ√(tr + b/β), eN = cσ√(tr + (ψ/β)b), e_{N+1} = cσ√(tr3 + γ̃_{N+1}·b3) [ft]."""
    ss = steady_state(sigma, sigma0, beta)
    cs = c_ft_per_ns * sigma
    e0 = cs * math.sqrt(tr + b / beta)  # (4.5.7) = (4.1.2)
    eN = cs * np.sqrt(tr + ss.psi / beta * b)  # (4.5.35) with (4.5.37)
    eN1 = cs * np.sqrt(tr3 + outage_gamma_tilde(sigma, sigma0, beta, 1) * b3)  # (4.5.30) with (4.5.37′)
    return {"alpha": ss.alpha, "psi": ss.psi, "e0": np.broadcast_to(e0, ss.psi.shape), "eN": eN, "eN1": eN1}


# --- the data path ----------------------------------------------------------------------------------


def pseudo_measurement(T: np.ndarray, sats: np.ndarray, p_star: np.ndarray) -> dict[str, np.ndarray]:
    """Linearise at p* and reduce an epoch to its clock pseudo-measurement.

    Args:
        T: (..., K) arrival times [ns], nominal epoch removed.
        sats: (K, 3) satellite positions [light-ns].
        p_star: (..., 3) linearisation point [light-ns].

    Returns:
        dict with ``z`` = T − k (..., K), Q, R of U, ``beta`` (...,) and ``y`` = w·z/β (NaN for K = 3).
    """
    U, k = directions(sats, p_star)
    Q, R, w = qr_parts(U)
    z = T - k  # T̂_n − k_n (4.2.3), η_d = 0
    K = U.shape[-2]
    if K > 3:
        beta = np.einsum("...k,...k->...", w, w)
        y = np.einsum("...k,...k->...", w, z) / beta  # 1'(I − P)(T̂ − k)/β
    else:
        beta = np.zeros(U.shape[:-2])
        y = np.full(U.shape[:-2], np.nan)
    return {"z": z, "Q": Q, "R": R, "beta": beta, "y": y}


def position_update(pm: dict[str, np.ndarray], p_star: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """p̂ = p* + (U'U)⁻¹U'(T̂ − k − τ̂1) = p* + R⁻¹Q'(z − τ̂1) (eqs 4.5.4, 4.5.17, 4.5.28)."""
    r = pm["z"] - tau[..., None]
    qtr = np.einsum("...kj,...k->...j", pm["Q"], r)
    return p_star + solve_upper(pm["R"], qtr)


class ReportClock:
    """The report's constrained clock estimator (4.5.16, 4.5.20–4.5.25), batched over runs.

    State per run: τ̂ (deviation from the nominal epoch), V and χ of :func:`clock_error_recursion`.
    The gain uses each run's own β_n at its linearisation point.
    """

    def __init__(self, sigma: float, sigma0: float, *, steady_gain: np.ndarray | None = None) -> None:
        self.sigma2 = float(sigma) ** 2
        self.s02 = float(sigma0) ** 2
        self.steady_gain = steady_gain
        self.tau = np.empty(0)
        self.V = np.empty(0)
        self.chi = np.empty(0)

    def reinit(self, tau: np.ndarray, beta: np.ndarray) -> None:
        """Least-squares (re)start: τ̂ = y, V = σ²/β, χ = 0 (4.5.3, 4.5.5)."""
        self.tau, self.V, self.chi = tau.copy(), self.sigma2 / beta, np.zeros_like(tau)

    def prior(self) -> tuple[np.ndarray, np.ndarray]:
        """τ̂⁻ = τ̂_{n−1} (+ τ̄, removed with the nominal epoch) and its variance σ²_τn (4.5.21/4.5.24)."""
        return self.tau, self.V + 2.0 * self.s02 + 2.0 * self.chi

    def gain(self, vm: np.ndarray, beta: np.ndarray) -> np.ndarray:
        """g_n = γ_nβ_n = σ²_τn/(σ²_τn + σ²/β_n) (4.5.20), or the constant steady-state gain."""
        if self.steady_gain is not None:
            return np.broadcast_to(self.steady_gain, vm.shape)
        return vm * beta / (vm * beta + self.sigma2)

    def estimate(self, y: np.ndarray, beta: np.ndarray | None) -> np.ndarray:
        """τ̂_n for this epoch's pseudo-measurement (None: no clock information, K = 3)."""
        tm, vm = self.prior()
        if beta is None:
            return tm
        return tm + self.gain(vm, beta) * (y - tm)  # (4.5.16)

    def commit(self, y: np.ndarray, beta: np.ndarray | None) -> None:
        """Advance the state with the epoch's final pseudo-measurement."""
        tm, vm = self.prior()
        cm = self.chi + self.s02
        if beta is None:  # (4.5.27): prediction only
            self.V, self.chi = vm, cm
            return
        g = self.gain(vm, beta)
        R = self.sigma2 / beta
        a = 1.0 - g if self.steady_gain is not None else R / (vm + R)  # a = 1 − g, no cancellation
        self.tau = tm + g * (y - tm)
        self.V = a**2 * vm + g**2 * R
        self.chi = a * cm


class RateKalmanClock:
    """Comparator ``kf2`` (our addition; the report has no such filter): a Kalman filter on [phase, rate] driven by y_n, built for the
    ρ = 1 model: Φ = [[1, 1], [0, 1]], Q = diag(σ0², q_r), H = [1 0], R_n = σ²/β_n; initial
    x̂ = [y_0, 0], P = diag(σ²/β_0, σ0²). Joseph-form update keeps P symmetric positive definite."""

    PHI = np.array([[1.0, 1.0], [0.0, 1.0]])

    def __init__(self, sigma: float, sigma0: float, q_rate: float = 0.0) -> None:
        self.sigma2 = float(sigma) ** 2
        self.s02 = float(sigma0) ** 2
        self.Q = np.diag([self.s02, float(q_rate)])
        self.x = np.empty((0, 2))
        self.P = np.empty((0, 2, 2))

    def reinit(self, tau: np.ndarray, beta: np.ndarray) -> None:
        """x̂ = [y_0, 0], P = diag(σ²/β_0, σ0²)."""
        n = tau.shape[0]
        self.x = np.stack([tau, np.zeros(n)], axis=-1)
        self.P = np.zeros((n, 2, 2))
        self.P[:, 0, 0] = self.sigma2 / beta
        self.P[:, 1, 1] = self.s02

    def _predict(self) -> tuple[np.ndarray, np.ndarray]:
        xm = self.x @ self.PHI.T
        Pm = self.PHI @ self.P @ self.PHI.T + self.Q
        return xm, Pm

    def _update(self, y: np.ndarray, beta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        xm, Pm = self._predict()
        R = self.sigma2 / beta
        S = Pm[:, 0, 0] + R
        Kg = Pm[:, :, 0] / S[:, None]
        x = xm + Kg * (y - xm[:, 0])[:, None]
        IKH = np.eye(2) - Kg[:, :, None] * np.array([1.0, 0.0])[None, None, :]
        P = IKH @ Pm @ np.swapaxes(IKH, -1, -2) + R[:, None, None] * Kg[:, :, None] * Kg[:, None, :]  # Joseph
        return x, 0.5 * (P + np.swapaxes(P, -1, -2))

    def estimate(self, y: np.ndarray, beta: np.ndarray | None) -> np.ndarray:
        """Phase estimate for this epoch (prediction only when ``beta`` is None)."""
        if beta is None:
            return self._predict()[0][:, 0]
        return self._update(y, beta)[0][:, 0]

    def commit(self, y: np.ndarray, beta: np.ndarray | None) -> None:
        """Advance the filter with the epoch's final pseudo-measurement."""
        self.x, self.P = self._predict() if beta is None else self._update(y, beta)
