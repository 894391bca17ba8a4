"""The quasi-optimal two-point density and its exponent against the Gaussian one — ATC-10 §3.7–3.8,
eqs (3.7.1), (3.7.20)–(3.7.27), (3.8.9)–(3.8.16).

Theorem 3.2: among symmetric amplitude densities of fixed MAN power p, the common two-point density
C*(x) = ½δ(x − A) + ½δ(x + A), A = √(p/(Mq)) (3.7.1), minimises the p_f upper bound and maximises the
p_d lower bound of (3.5.13) at once (Jensen: E x^{2n} ≥ b^n gives Φ ≥ cosh(ρ√b)). Its exponent has the
closed form (3.7.23)–(3.7.24), with the printed "(1−2τ)/α" read as (1 − 2τ/α):

    u = asinh(θ(1 − q)/√(Mqp − θ²q²)) + atanh(θ√(q/(Mp))),    ρ* = u/A     (valid iff θ < M·A)
    Expf(θ) = ρ*θ − M ln[(1 − q) + q cosh u],        Expd(θ) = Expf(1 − θ)

and, for τ/α ~ 10⁻⁵ and N ~ 10⁵, the approximation (3.7.26)–(3.7.27) (atanh dropped, 1 − q → 1 and
N − 1 → N inside; the printed log argument θ/(2Nτp/α) is θ/√(2Nτp/α)):

    Expf ≈ θ√(Nq/p)·asinh(θ/√(Nqp)) − N ln[1 − q + q√(1 + θ²/(Nqp))]

Written in terms of the Gaussian exponent G = Exp_g = θ²/(2p) (3.8.8) the same function is

    Exp(G; N, τ/α) = √(4λG)·asinh(√(G/λ)) − N ln[1 − q + q√(1 + G/λ)],  λ = Nτ/α   (3.8.16)

(printed with √(Exp_g/(Nτ)): the α is missing; (3.8.11) has it), exactly
u = asinh(√(2G)(1 − q)/√(Mq − 2Gq²)) + atanh(√(2Gq/M)), Exp = u√(2GMq) − M ln(1 − q + q cosh u).
Exp < G (cosh x − 1 ≥ x²/2: the two-point log-MGF dominates the Gaussian one of equal power), Exp → G
as N → ∞, and for q ≪ 1 Exp depends on (N, τ/α) only through λ (Figs 3.9, 3.10).
"""

from __future__ import annotations

import math

import numpy as np

LOG_COSH_SWITCH = 30.0


def log_one_plus_q_cosh_minus_one(u: np.ndarray, q: float) -> np.ndarray:
    """ln(1 − q + q cosh u) without cancellation at small u nor overflow at large u."""
    u = np.abs(np.asarray(u, dtype=float))
    small = u < LOG_COSH_SWITCH
    us = np.where(small, u, 0.0)
    lo = np.log1p(2.0 * q * np.sinh(0.5 * us) ** 2)  # cosh u − 1 = 2 sinh²(u/2)
    ub = np.where(small, LOG_COSH_SWITCH, u)
    hi = np.logaddexp(math.log1p(-q), math.log(q) + ub + np.log1p(np.exp(-2.0 * ub)) - math.log(2.0))
    return np.where(small, lo, hi)


def _check(N: float | np.ndarray, tau_over_alpha: float) -> tuple[np.ndarray, float]:
    N = np.asarray(N, dtype=float)
    if not np.all(np.isfinite(N) & (N > 1)):
        raise ValueError(f"N must be > 1; got {N!r}")
    if not (math.isfinite(tau_over_alpha) and 0.0 < 2.0 * tau_over_alpha < 1.0):
        raise ValueError(f"tau/alpha must lie in (0, 0.5); got {tau_over_alpha!r}")
    return N, 2.0 * tau_over_alpha


def two_point_amplitude(p: float, N: float, tau_over_alpha: float) -> float:
    """A = √(pα/((N − 1)2τ)) = √(p/(Mq)) (3.7.1)."""
    N_, q = _check(N, tau_over_alpha)
    return math.sqrt(p / ((float(N_) - 1.0) * q))


def quasi_optimal_exponent(
    theta: np.ndarray, p: float, N: float, tau_over_alpha: float
) -> tuple[np.ndarray, np.ndarray]:
    """(ρ*, Expf(θ)) for C* at MAN power p, closed form (3.7.23)–(3.7.24); inf where θ ≥ M·A."""
    N_, q = _check(N, tau_over_alpha)
    if not (math.isfinite(p) and p > 0.0):
        raise ValueError(f"the MAN power p must be a finite number > 0; got {p!r}")
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    M = float(N_) - 1.0
    A = math.sqrt(p / (M * q))
    ok = theta < M * A
    t = np.where(ok, theta, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.arcsinh(t * (1.0 - q) / np.sqrt(M * q * p - t * t * q * q)) + np.arctanh(
            t * math.sqrt(q / (M * p))
        )  # (3.7.23)
        rho = u / A
        E = rho * t - M * log_one_plus_q_cosh_minus_one(u, q)  # (3.7.24)
    return np.where(ok, rho, np.inf), np.where(ok, E, np.inf)


def quasi_optimal_exponent_approx(theta: np.ndarray, p: float, N: float, tau_over_alpha: float) -> np.ndarray:
    """Expf ≈ θ√(Nq/p)·asinh(θ/√(Nqp)) − N ln[1 − q + q√(1 + θ²/(Nqp))] (3.7.26)–(3.7.27)."""
    N, q = _check(N, tau_over_alpha)
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    z = theta / np.sqrt(N * q * p)
    root_m1 = z * z / (np.sqrt(1.0 + z * z) + 1.0)  # √(1 + z²) − 1 without cancellation
    return theta * np.sqrt(N * q / p) * np.arcsinh(z) - N * np.log1p(q * root_m1)


def exp_of_gaussian_exponent(G: np.ndarray, N: float, tau_over_alpha: float) -> np.ndarray:
    """Exp(G; N, τ/α) of (3.8.16) (the report's approximate form)."""
    N, q = _check(N, tau_over_alpha)
    G = np.asarray(G, dtype=float)
    if np.any(~(G >= 0.0)):
        raise ValueError("Exp_g must be >= 0")
    lam = N * tau_over_alpha
    z = np.sqrt(G / lam)
    root_m1 = z * z / (np.sqrt(1.0 + z * z) + 1.0)  # √(1 + z²) − 1 without cancellation
    return np.sqrt(4.0 * lam * G) * np.arcsinh(z) - N * np.log1p(q * root_m1)


def exp_of_gaussian_exponent_exact(G: np.ndarray, N: float, tau_over_alpha: float) -> np.ndarray:
    """Exp(G) without approximation: (3.7.24) rewritten in G (inf where 2Gq ≥ M)."""
    N, q = _check(N, tau_over_alpha)
    G = np.asarray(G, dtype=float)
    if np.any(~(G >= 0.0)):
        raise ValueError("Exp_g must be >= 0")
    M = N - 1.0
    ok = 2.0 * G * q < M
    g = np.where(ok, G, 0.0)
    u = np.arcsinh(np.sqrt(2.0 * g) * (1.0 - q) / np.sqrt(M * q - 2.0 * g * q * q)) + np.arctanh(
        np.sqrt(2.0 * g * q / M)
    )
    E = u * np.sqrt(2.0 * g * M * q) - M * log_one_plus_q_cosh_minus_one(u, q)
    return np.where(ok, E, np.inf)
