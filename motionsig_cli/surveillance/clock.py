"""The aircraft clock model (ATC-10 App. G, §4.3) and the steady-state tracking gain ψ(α) (eqs 4.5.26–4.5.34).

The transmitter sends pulse n at τ_n = τ_0 + nτ̄ + x_n, where the deviation x_n of its cheap
oscillator has second-order statistics (App. G)

    E[x_m x_n] = σ1² min(m, n) + ½σ2²(m^{2ρ} + n^{2ρ} − |m − n|^{2ρ}),   x_0 = 0,

a random walk in phase (white frequency noise, σ1) plus Mandelbrot–Van Ness fractional Brownian
motion (flicker frequency noise, σ2, ½ < ρ < 1). Section 4 uses σ1 = σ2 = σ0 and ρ = 1 (eq 4.3.1),
where x_n = Σ_{i≤n} w_i + n·a_0 with w_i, a_0 iid (0, σ0²) — the OCR's "Σw_i + α_0" lacks the n.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import integrate, special

from motionsig_cli.config import in_range

__all__ = [
    "ClockModel",
    "alpha_of",
    "convergence_rule",
    "mvn_constant",
    "mvn_constant_quad",
    "psi",
    "psi_large",
    "psi_small",
]


def alpha_of(sigma0: np.ndarray | float, sigma: np.ndarray | float, beta: np.ndarray | float) -> np.ndarray:
    """α = (8/27)·σ0²β/σ² (eq 4.5.32)."""
    return (8.0 / 27.0) * np.asarray(sigma0, dtype=float) ** 2 * np.asarray(beta) / np.asarray(sigma) ** 2


def psi(alpha: np.ndarray | float) -> np.ndarray:
    """ψ(α), the steady-state clock gain γβ: the real root in [0, 1) of ψ³ + (27α/4)(ψ − 1) = 0 (eq 4.5.34).

    For α ≤ 1 the closed form (3/2)α^{1/3}{[1 + √(1+α)]^{1/3} + [1 − √(1+α)]^{1/3}} with real cube roots
    and 1 − √(1+α) rewritten as −α/(1 + √(1+α)) starts Newton's method on the cubic; for α > 1, where
    the two cube roots cancel, Newton starts at ψ = 1. Six steps reach working precision over the whole
    range (the raw closed form errs by 2·10⁻⁷ at α = 10⁻¹⁵ and exceeds 1 at α = 10¹²).
    ψ(0) = 0; ψ → 1 as α → ∞.
    """
    a = np.asarray(alpha, dtype=float)
    if np.any(~(a >= 0)):
        raise ValueError("alpha must be >= 0 (alpha = (8/27) sigma0^2 beta / sigma^2)")
    with np.errstate(all="ignore"):
        c = 6.75 * a  # 27α/4
        s = np.sqrt(1.0 + a)
        closed = 1.5 * np.cbrt(a) * (np.cbrt(1.0 + s) + np.cbrt(-a / (1.0 + s)))  # (4.5.34)
        # For α > 1 the two cube roots cancel (catastrophically for α ≳ 1e15): start Newton at ψ = 1
        # instead, where f(ψ) = ψ³ + c(ψ − 1) is convex and increasing, so Newton descends monotonically.
        x = np.where(a > 1.0, 1.0, closed)
        for _ in range(6):  # f' = 3ψ² + c > 0; quadratic convergence from either start
            f = x**3 + c * (x - 1.0)
            fp = 3.0 * x**2 + c
            x = np.where(fp > 0, x - f / np.where(fp > 0, fp, 1.0), x)
    x = np.clip(np.where(np.isinf(c), 1.0, x), 0.0, 1.0) + 0.0  # + 0.0: no −0.0 at α = −0.0
    return x if x.ndim else x[()]


def psi_large(alpha: np.ndarray | float) -> np.ndarray:
    """Fig 4.1's large-α approximation ψ ≈ 1 − (4/27)/α (the report labels it α ≥ 1)."""
    return 1.0 - (4.0 / 27.0) / np.asarray(alpha, dtype=float)


def psi_small(alpha: np.ndarray | float) -> np.ndarray:
    """Fig 4.1's small-α approximation ψ ≈ (3/2)·2^{1/3}[α^{1/3} − (α/2)^{2/3}] (the report labels it α ≤ 0.3)."""
    a = np.asarray(alpha, dtype=float)
    return 1.5 * 2.0 ** (1.0 / 3.0) * (np.cbrt(a) - np.cbrt(a / 2.0) ** 2)


def convergence_rule(psi_value: float) -> float:
    """Steps for s_n = Σ(1 − ψ)^i to come within 10 % of its limit: ln 0.1 / ln(1 − ψ) − 1 (text after 4.5.37;
    the OCR dropped the ln 0.1)."""
    return math.log(0.1) / math.log1p(-psi_value) - 1.0


def mvn_constant_quad(rho: float) -> float:
    """Mandelbrot–Van Ness constant V0(ρ) by quadrature of its App. G definition:
    Γ(ρ + ½)⁻² [1/(2ρ) + ∫₀^∞ ((1 + s)^{ρ−½} − s^{ρ−½})² ds], ½ < ρ < 1."""
    if not 0.5 < rho < 1.0:
        raise ValueError("rho must lie in (1/2, 1)")
    h = rho - 0.5

    def f(s: float) -> float:
        return ((1.0 + s) ** h - s**h) ** 2

    inner = integrate.quad(f, 0.0, 1.0, limit=200)[0] + integrate.quad(f, 1.0, np.inf, limit=200)[0]
    return (1.0 / (2.0 * rho) + inner) / special.gamma(rho + 0.5) ** 2


def mvn_constant(rho: float) -> float:
    """V0(ρ) in closed form, Γ(2 − 2ρ)·cos(πρ) / (πρ(1 − 2ρ)) (Mandelbrot & Van Ness 1968; equals
    :func:`mvn_constant_quad`, and 1 at ρ = ½). It diverges as ρ → 1, which is why App. G absorbs it into σ2."""
    if not 0.5 < rho < 1.0:
        raise ValueError("rho must lie in (1/2, 1)")
    return special.gamma(2.0 - 2.0 * rho) * math.cos(math.pi * rho) / (math.pi * rho * (1.0 - 2.0 * rho))


@dataclass(frozen=True)
class ClockModel:
    """Second-order model of the transmit-time deviation x_n = τ_n − τ_0 − nτ̄ (App. G; eq 4.3.1 when
    σ1 = σ2 = σ0 and ρ = 1).

    Attributes:
        sigma1: random-walk phase scale σ1 [ns per √update].
        sigma2: flicker scale σ2 [ns].
        rho: flicker exponent, ½ < ρ ≤ 1 (ρ = 1: a random constant rate).
    """

    sigma1: float
    sigma2: float
    rho: float = 1.0

    def __post_init__(self) -> None:
        in_range("sigma1", self.sigma1, 0.0, unit="ns")
        in_range("sigma2", self.sigma2, 0.0, unit="ns")
        in_range("rho", self.rho, 0.5, 1.0, lo_open=True)

    @classmethod
    def simplified(cls, sigma0: float) -> ClockModel:
        """The §4.3 model: σ1 = σ2 = σ0, ρ = 1 (eq 4.3.1)."""
        return cls(sigma0, sigma0, 1.0)

    def covariance(self, n: int) -> np.ndarray:
        """E[x_i x_j] for i, j = 1..n (x_0 = 0 exactly), App. G / eq 4.3.1b without the mean term."""
        k = np.arange(1, n + 1, dtype=float)
        m, nn = np.meshgrid(k, k, indexing="ij")
        two_rho = 2.0 * self.rho
        return self.sigma1**2 * np.minimum(m, nn) + 0.5 * self.sigma2**2 * (
            m**two_rho + nn**two_rho - np.abs(m - nn) ** two_rho
        )

    def increment_autocov(self, lag: np.ndarray | int) -> np.ndarray:
        """E[Δ_n Δ_{n−i}] of the increments Δ_n = x_n − x_{n−1} (eq 4.5.23 and its App. G form):
        σ1²δ_{i0} + ½σ2²(|i+1|^{2ρ} − 2|i|^{2ρ} + |i−1|^{2ρ}). With ρ = 1: 2σ0² at lag 0, σ0² otherwise."""
        i = np.abs(np.asarray(lag, dtype=float))
        r2 = 2.0 * self.rho
        return self.sigma1**2 * (i == 0) + 0.5 * self.sigma2**2 * (
            (i + 1) ** r2 - 2 * i**r2 + np.abs(i - 1) ** r2
        )

    def sample(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """One path x_0..x_n (x_0 = 0). ρ = 1: Σw_i(σ1) + n·a_0(σ2) directly; ρ < 1: Cholesky of
        :meth:`covariance` (the σ1 term keeps it positive definite; n ≤ 5000)."""
        if self.rho == 1.0 or self.sigma1 == self.sigma2 == 0.0:
            w = rng.standard_normal(n) * self.sigma1
            a0 = rng.standard_normal() * self.sigma2 * (self.rho == 1.0)  # a perfect clock (σ = 0) stays 0
            return np.concatenate([[0.0], np.cumsum(w) + a0 * np.arange(1, n + 1)])
        return np.concatenate([[0.0], self.cholesky(n) @ rng.standard_normal(n)])

    def cholesky(self, n: int) -> np.ndarray:
        """Lower Cholesky factor of :meth:`covariance` (n ≤ 5000)."""
        if n > 5000:
            raise ValueError(f"{n} epochs with rho < 1: the Cholesky path generator is limited to 5000")
        return np.linalg.cholesky(self.covariance(n))
