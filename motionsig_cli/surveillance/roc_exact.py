"""The exact ROC under multiple-access noise (beyond the report; spec ``mac-roc.md`` §11.1).

Condition on the number K ~ Binomial(M, q) of overlapping interferers; given K = k the noise is the sum
S_k of k iid amplitudes from the common density C, so

    p_f = Σ_k Bin(k; M, q) P(S_k ≥ θ),        p_m = Σ_k Bin(k; M, q) P(S_k < θ − 1) = Σ_k … P(S_k > 1 − θ)

(K = 0 never contributes for θ ∈ (0, 1); the last form uses the symmetry of C). The sum runs from the
first k whose support reaches the level until the binomial terms fall 40 decades below the running sum.

Tails of S_k, all sums of positive terms (no cancellation, relative accuracy ~k²ε down to 10⁻³⁰⁰):

* gaussian   P(S_k ≥ x) = Q(x/√(kb)) (log_ndtr);
* two-point  S_k = A(2B − k), B ~ Bin(k, ½): a lattice, ≥ for p_f and > for p_m;
* uniform    S_k = a(2·IH_k − k), IH_k Irwin–Hall. Its CDF is F_k(u) = Σ_{j≥0} N_{k+1}(u − j) with N_m
             the cardinal B-spline of order m (d/du N_{k+1}(u) = N_k(u) − N_k(u − 1) telescopes), and
             N_m is evaluated by the Cox–de Boor recursion, a convex combination at every step;
             P(IH_k ≥ t) = F_k(k − t);
* triangular the same with 2k uniforms of half-width c;
* laplace    S_k = β(G₁ − G₂), G ~ Gamma(k, 1):
             P(G₁ − G₂ ≥ y) = e^{−y} Σ_{i<k} Σ_{l≤i} y^{i−l}/(i−l)! · Γ(k+l)/(Γ(k) l! 2^{k+l}).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import gammaln, log_ndtr, logsumexp
from scipy.stats import binom

from motionsig_cli.surveillance.amplitude import Gaussian, Laplace, Triangular, TwoPoint, Uniform
from motionsig_cli.surveillance.multiple_access import MANModel

EXACT_DENSITIES = ("two-point", "uniform", "triangular", "gaussian", "laplace")
TAIL_DECADES = 40.0  # stop when the binomial weight is this many decades below the running sum
MAX_TERMS = 20_000
MAX_MEAN_ACTIVE = 2000.0  # Mq above which the exact sum is refused (too long; the MAN is near Gaussian)


def irwin_hall_tail(k: int, t: np.ndarray) -> np.ndarray:
    """P(IH_k ≥ t) for an Irwin–Hall sum of k U(0, 1) (array t), as F_k(k − t) = Σ_j N_{k+1}(k − t − j)."""
    t = np.asarray(t, dtype=float)
    u = np.clip(k - t, 0.0, float(k))  # P(IH ≥ t) = P(IH ≤ k − t)
    out = np.zeros_like(u)
    live = (u > 0.0) & (u < k)
    out[u >= k] = 1.0
    if not live.any():
        return out
    uu = u[live]
    n_shift = int(np.floor(uu.max())) + k + 2
    i = np.arange(n_shift)[:, None]
    y = uu[None, :] - i  # arguments u − i
    T = ((y >= 0.0) & (y < 1.0)).astype(float)  # N₁(u − i)
    for m in range(2, k + 2):  # Cox–de Boor: N_m(y) = [y N_{m−1}(y) + (m − y) N_{m−1}(y − 1)]/(m − 1)
        shifted = np.vstack([T[1:], np.zeros((1, T.shape[1]))])  # N_{m−1}(y − 1) = row i + 1
        T = (y * T + (m - y) * shifted) / (m - 1)
    valid = y >= 0.0  # terms j = 0 … ⌊u⌋
    out[live] = np.where(valid, T, 0.0).sum(axis=0)
    return out


def _log_tail(dens: object, k: int, x: np.ndarray, strict: bool) -> np.ndarray:
    """ln P(S_k ≥ x) (or > x when ``strict``; it matters only on the two-point lattice), x > 0."""
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        if isinstance(dens, Gaussian):
            return log_ndtr(-x / math.sqrt(k * dens.var))
        if isinstance(dens, TwoPoint):
            tt = 0.5 * (k + x / dens.A)  # S_k ≥ x ⇔ B ≥ tt
            near = np.round(tt)
            on_lattice = np.abs(tt - near) <= 1e-9 * np.maximum(1.0, tt)
            j0 = np.where(on_lattice, near + (1 if strict else 0), np.ceil(tt))
            return binom.logsf(j0 - 1, k, 0.5)
        if isinstance(dens, Uniform):
            return np.log(irwin_hall_tail(k, 0.5 * (k + x / dens.a)))
        if isinstance(dens, Triangular):
            return np.log(irwin_hall_tail(2 * k, 0.5 * (2 * k + x / dens.c)))
        if isinstance(dens, Laplace):
            y = x / dens.beta
            i = np.arange(k)[:, None]
            l_ = np.arange(k)[None, :]
            ok = l_ <= i
            c = (
                gammaln(k + l_)
                - gammaln(k)
                - gammaln(l_ + 1)
                - (k + l_) * math.log(2.0)
                - gammaln(i - l_ + 1)
            )
            c = np.where(ok, c, -np.inf)
            ly = np.log(np.maximum(y, 1e-300))[:, None, None]
            pw = np.where(ok, i - l_, 0)[None]
            terms = c[None] + np.where(pw > 0, pw * ly, 0.0)
            return -y + logsumexp(terms.reshape(len(y), -1), axis=1)
    raise ValueError(f"no exact ROC for the {getattr(dens, 'name', dens)} density")


@dataclass(frozen=True)
class ExactRoc:
    """ln p_f and ln p_m at each threshold, and the number of binomial terms summed."""

    theta: np.ndarray
    log_pf: np.ndarray
    log_pm: np.ndarray
    k_max: int

    @property
    def pd(self) -> np.ndarray:
        return -np.expm1(self.log_pm)


def _log_sum_over_k(model: MANModel, x: np.ndarray, strict: bool) -> tuple[np.ndarray, int]:
    dens = model.common_density
    M, q = model.M, model.q
    k_lo = 1
    if math.isfinite(dens.max_abs):  # S_k cannot reach x below k·max|x|
        k_lo = max(1, math.floor(float(np.min(x)) / dens.max_abs))
    acc = np.full(x.shape, -np.inf)
    k = k_lo
    mean = M * q
    while k <= M:
        lw = float(binom.logpmf(k, M, q))
        acc = np.logaddexp(acc, lw + _log_tail(dens, k, x, strict))
        if k > mean and lw < np.min(acc) - TAIL_DECADES * math.log(10.0) and np.all(np.isfinite(acc)):
            break
        if k > mean and lw < -800.0:
            break
        k += 1
        if k - k_lo > MAX_TERMS:
            raise ValueError(
                "the exact ROC needs more than 20000 binomial terms; use the bounds or Monte Carlo"
            )
    return acc, k


def exact_roc(model: MANModel, theta: np.ndarray) -> ExactRoc:
    """The exact (p_f, p_m) at thresholds θ ∈ (0, 1) for a common density (spec §11.1)."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    if np.any(~((theta > 0.0) & (theta < 1.0))):
        raise ValueError("thresholds must lie in the open interval (0, 1)")
    if model.trivial:
        return ExactRoc(theta, np.full_like(theta, -np.inf), np.full_like(theta, -np.inf), 0)
    dens = model.common_density
    if dens is None or getattr(dens, "name", "") not in EXACT_DENSITIES:
        name = getattr(dens, "name", "mixed")
        raise ValueError(
            f"the exact ROC is available for a common {', '.join(EXACT_DENSITIES)} density, not {name}; "
            "use Monte Carlo"
        )
    if model.mean_active > MAX_MEAN_ACTIVE:
        raise ValueError(
            f"Mq = {model.mean_active:.4g} overlapping interferers on average: the exact sum is too long; "
            "the MAN is then close to Gaussian (Theorem 3.1)"
        )
    log_pf, k1 = _log_sum_over_k(model, theta, strict=False)  # P(n ≥ θ)
    log_pm, k2 = _log_sum_over_k(model, 1.0 - theta, strict=True)  # P(n < θ − 1) = P(−n > 1 − θ)
    return ExactRoc(theta, log_pf, log_pm, max(k1, k2))
