"""Fault detection and exclusion (FDE) for snapshot fixes, RAIM-style: a χ² test of each epoch's weighted
residuals, and the most likely faulty receiver excluded and the epoch solved again while the redundancy
allows (Parkinson & Axelrad, "Autonomous GPS Integrity Monitoring Using the Pseudorange Residual",
Navigation 35(2), 1988; Brown, "A Baseline GPS RAIM Scheme and a Note on the Equivalence of Three RAIM
Methods", Navigation 39(3), 1992).

**Test.** With K receivers and known σ_i, the weighted sum of squared residuals of the least-squares fix,
T = Σ (r_i/σ_i)² = rᵀWr, is χ²-distributed with K − 4 degrees of freedom when the errors are Gaussian
and there is no fault (Parkinson & Axelrad's test statistic, Brown's "SSE" form). An alarm is raised when
T > T_α = F⁻¹_{χ²(K−4)}(1 − α) for the false-alarm probability α per epoch. With a bias f on receiver i, T is
non-central χ² with non-centrality λ = (f/σ_i)² (1 − h_ii), h_ii the leverage of the receiver (the diagonal of
the whitened hat matrix W^½H(HᵀWH)⁻¹HᵀW^½): the detection probability is P(χ²(K−4, λ) > T_α).

**Exclusion.** The receiver with the largest standardised residual |r_i|/(σ_i √(1 − h_ii)) is excluded
(for a single bias in a linear model with the others unbiased, the largest standardised residual is
the maximum-likelihood identification; Brown 1992 compares it with the parity-space methods)
and the epoch solved again without it; the test is repeated while the remaining receivers can still be
tested (K − 1 ≥ 5: a set of four fits exactly and cannot confirm an exclusion). An epoch whose test still
fails when no more receivers can be excluded keeps its fix, flagged as failing the test.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields

import numpy as np
from scipy import stats

from motionsig_cli.config import in_range
from motionsig_cli.surveillance.multilateration import thin_qr
from motionsig_cli.surveillance.toa_fix import MIN_RECEIVERS, SnapshotFix

__all__ = ["FaultExclusion", "FdeResult", "chi2_threshold", "exclude_faults", "standardised_residuals"]

P_FA = 1e-3
"""Default false-alarm probability of the test per epoch (assumed: one false exclusion in a thousand epochs
of fault-free data)."""


@dataclass(frozen=True)
class FaultExclusion:
    """The FDE's parameters (checked here, once).

    Attributes:
        p_fa: false-alarm probability of the χ² test per epoch, in (0, 0.5].
        enabled: test and exclude (False: the fixes as solved, the statistic still reported).
    """

    p_fa: float = P_FA
    enabled: bool = True

    def __post_init__(self) -> None:
        in_range("p_fa", self.p_fa, 0.0, 0.5, lo_open=True)


@dataclass(frozen=True)
class FdeResult:
    """The fixes after fault detection and exclusion.

    Attributes:
        fix: the final fixes (the receivers excluded left out).
        excluded: (E, K) the receivers excluded at each epoch.
        statistic: (E,) T = rᵀWr of the final fix (NaN without a fix).
        threshold: (E,) T_α for its degrees of freedom (NaN without redundancy: K = 4, no test).
        first_statistic, first_threshold: (E,) the same before any exclusion.
        alarm: (E,) the final fix still fails the test (no receiver left to exclude, or exclusion off).
        p_fa: the false-alarm probability used.
    """

    fix: SnapshotFix
    excluded: np.ndarray
    statistic: np.ndarray
    threshold: np.ndarray
    first_statistic: np.ndarray
    first_threshold: np.ndarray
    alarm: np.ndarray
    p_fa: float


def chi2_threshold(dof: np.ndarray, p_fa: float) -> np.ndarray:
    """T_α = F⁻¹_{χ²(dof)}(1 − p_fa) per epoch (NaN where dof < 1)."""
    d = np.asarray(dof, float)
    with np.errstate(invalid="ignore"):
        return np.where(d >= 1, stats.chi2.isf(p_fa, np.maximum(d, 1)), np.nan)


def standardised_residuals(fix: SnapshotFix, receivers: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """(E, K) |r_i|/(σ_i √(1 − h_ii)) at the fixes (NaN where a receiver is absent or the epoch has no fix).

    Args:
        fix: the fixes (``normalised`` = r_i/σ_i, NaN where absent).
        receivers: (E, K, 3) ECEF positions [m].
        sigma: (E, K) σ_i [m].
    """
    z = fix.normalised
    used = np.isfinite(z)
    S = np.where(used[..., None], receivers, 0.0)
    p = np.where(np.isfinite(fix.position), fix.position, 0.0)
    d = p[:, None, :] - S
    rng = np.linalg.norm(d, axis=-1)
    U = d / np.where(rng > 0, rng, 1.0)[..., None]
    w = np.where(used, 1.0 / np.where(used, sigma, 1.0), 0.0)
    Q, _ = thin_qr(np.concatenate([U, np.ones((*U.shape[:-1], 1))], axis=-1) * w[..., None])
    h = np.sum(Q * Q, axis=-1)  # the leverages: the whitened hat matrix's diagonal
    with np.errstate(invalid="ignore"):
        out = np.abs(z) / np.sqrt(np.maximum(1.0 - h, 1e-12))
    return np.where(used & fix.ok[:, None], out, np.nan)


def _merge(a: SnapshotFix, b: SnapshotFix, idx: np.ndarray) -> SnapshotFix:
    """``a`` with the epochs ``idx`` replaced by ``b``'s (of len(idx) epochs)."""
    out: dict[str, object] = {}
    for f in fields(SnapshotFix):
        va, vb = getattr(a, f.name), getattr(b, f.name)
        if isinstance(va, np.ndarray):
            va = va.copy()
            va[idx] = vb
        out[f.name] = va
    return SnapshotFix(**out)  # type: ignore[arg-type]


def exclude_faults(
    rho: np.ndarray,
    receivers: np.ndarray,
    sigma: np.ndarray,
    solve: Callable[[np.ndarray, np.ndarray], SnapshotFix],
    cfg: FaultExclusion,
) -> FdeResult:
    """Solve, test, exclude and solve again (module docstring).

    Args:
        rho: (E, K) pseudoranges [m] (NaN: absent).
        receivers: (E, K, 3) ECEF positions [m] (for the leverages).
        sigma: (E, K) σ of each pseudorange [m].
        solve: ``solve(rho_subset, epochs)`` the unscaled fixes (``scale="none"``, known σ) of the epochs
            ``epochs`` (indices into E) with the pseudoranges ``rho_subset`` (NaN: left out).
        cfg: the test's parameters.
    """
    E, K = rho.shape
    S = np.broadcast_to(receivers, (E, K, 3))
    fix = solve(rho, np.arange(E))
    excluded = np.zeros((E, K), dtype=bool)
    thr = chi2_threshold(np.where(fix.ok, fix.n_used - MIN_RECEIVERS, 0), cfg.p_fa)
    first_stat = np.where(fix.ok, fix.chi2, np.nan)
    first_thr = thr.copy()
    for _ in range(K):
        if not cfg.enabled:
            break
        stat = np.where(fix.ok, fix.chi2, np.nan)
        thr = chi2_threshold(np.where(fix.ok, fix.n_used - MIN_RECEIVERS, 0), cfg.p_fa)
        fail = stat > thr  # NaN compares False
        can = np.flatnonzero(fail & (fix.n_used - 1 >= MIN_RECEIVERS + 1))
        if not can.size:
            break
        zs = standardised_residuals(_take(fix, can), S[can], np.broadcast_to(sigma, (E, K))[can])
        worst = np.nanargmax(np.where(np.isfinite(zs), zs, -1.0), axis=1)
        trial = excluded[can].copy()
        trial[np.arange(can.size), worst] = True
        sub = solve(np.where(trial, np.nan, rho[can]), can)
        # keep an exclusion only where the re-solve has a fix (else the epoch stays as it was, alarmed)
        good = sub.ok
        if not good.any():
            break
        excluded[can[good]] = trial[good]
        keep_idx = np.flatnonzero(good)
        part = _take(sub, keep_idx)
        fix = _merge(fix, part, can[good])
    stat = np.where(fix.ok, fix.chi2, np.nan)
    thr = chi2_threshold(np.where(fix.ok, fix.n_used - MIN_RECEIVERS, 0), cfg.p_fa)
    alarm = stat > thr
    return FdeResult(fix, excluded, stat, thr, first_stat, first_thr, alarm, cfg.p_fa)


def _take(fix: SnapshotFix, idx: np.ndarray) -> SnapshotFix:
    """The epochs ``idx`` of ``fix``."""
    out: dict[str, object] = {}
    for f in fields(SnapshotFix):
        v = getattr(fix, f.name)
        out[f.name] = v[idx] if isinstance(v, np.ndarray) else v
    return SnapshotFix(**out)  # type: ignore[arg-type]
