"""The exact ROC under multiple-access noise (beyond the report).

Condition on the number K ~ Binomial(M, q) of overlapping interferers; given K = k the noise is the sum
S_k of k iid amplitudes from the common density C, so

    p_f = Σ_k Bin(k; M, q) P(S_k ≥ θ),        p_m = Σ_k Bin(k; M, q) P(S_k < θ − 1) = Σ_k … P(S_k > 1 − θ)

(K = 0 never contributes for θ ∈ (0, 1); the last form uses the symmetry of C). The sum runs from the
first k whose support reaches the level until the binomial terms fall 40 decades below the running sum.

The tails of S_k are the densities' own ``log_tail`` (the registry member says whether a density has
one: :attr:`~motionsig_cli.surveillance.densities.DensityKind.exact_roc`), all sums of positive terms
(no cancellation, relative accuracy ~k²ε down to 10⁻³⁰⁰):

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
from scipy.stats import binom

from motionsig_cli.config import ConfigError
from motionsig_cli.surveillance.amplitude import irwin_hall_tail as irwin_hall_tail  # re-exported
from motionsig_cli.surveillance.densities import DENSITIES, kind_of
from motionsig_cli.surveillance.multiple_access import MANModel

TAIL_DECADES = 40.0  # stop when the binomial weight is this many decades below the running sum
MAX_TERMS = 20_000
MAX_MEAN_ACTIVE = 2000.0  # Mq above which the exact sum is refused (too long; the MAN is near Gaussian)


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
        with np.errstate(divide="ignore"):
            acc = np.logaddexp(acc, lw + dens.log_tail(k, x, strict))  # ln P(S_k ≥ x), or > x when strict
        if k > mean and lw < np.min(acc) - TAIL_DECADES * math.log(10.0) and np.all(np.isfinite(acc)):
            break
        if k > mean and lw < -800.0:
            break
        k += 1
        if k - k_lo > MAX_TERMS:
            raise ConfigError(
                "N",
                model.N,
                "needs more than 20000 binomial terms in the exact ROC; use the bounds or Monte Carlo",
            )
    return acc, k


def exact_roc(model: MANModel, theta: np.ndarray) -> ExactRoc:
    """The exact (p_f, p_m) at thresholds θ ∈ (0, 1) for a common density whose registry member has an
    exact ROC (a :class:`ConfigError` naming ``density`` otherwise, or ``N`` when Mq is too large)."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    if np.any(~((theta > 0.0) & (theta < 1.0))):
        raise ConfigError("theta", theta.tolist(), "must lie in the open interval (0, 1)")
    if model.trivial:
        return ExactRoc(theta, np.full_like(theta, -np.inf), np.full_like(theta, -np.inf), 0)
    dens = model.common_density
    kind = None if dens is None else kind_of(dens)
    if kind is None or not kind.exact_roc:
        exact = ", ".join(k.name for k in DENSITIES.values() if k.exact_roc)
        raise ConfigError(
            "density",
            "mixed" if dens is None else dens.name,
            f"has no exact ROC (it exists for a common {exact} density); use Monte Carlo",
        )
    if model.mean_active > MAX_MEAN_ACTIVE:
        raise ConfigError(
            "N",
            model.N,
            f"gives Mq = {model.mean_active:.4g} overlapping interferers on average: the exact sum is too "
            "long; the MAN is then close to Gaussian (Theorem 3.1)",
        )
    log_pf, k1 = _log_sum_over_k(model, theta, strict=False)  # P(n ≥ θ)
    log_pm, k2 = _log_sum_over_k(model, 1.0 - theta, strict=True)  # P(n < θ − 1) = P(−n > 1 − θ)
    return ExactRoc(theta, log_pf, log_pm, max(k1, k2))
