"""Sequential likelihood ratio for track existence from several sensors: centralised (CKF), mean of local
scores (LKF) and distributed (DKF) — seed 001; spec §2.4.

All scores are log likelihood ratios, accumulated scan by scan: log LR(k) = log LR(k−1) + log Λ(k).

- **CKF**: one filter with all data; per scan predict with (F, Q), then the local update (§2.3) of each
  sensor in turn; log Λ(k) = Σ_s log p̄ˢ.
- **LKF**: one filter per sensor with (F, Q); fused LR = (1/S) Σ_s LRˢ, i.e. logsumexp − log S
  (``lkf_mean="log"``: the mean of the log LRs).
- **DKF**: local filters with the relaxed evolution model Pˢ ← FPˢFᵀ + S·Q, initialised at (m₀, S·P₀),
  so that the product of the S local Gaussians is the centralised one. The fusion centre receives
  (xˢ, Pˢ, p̄ˢ) and computes log Λ(k) = log c_{k|k} − log c_{k|k−1} + Σ_s log p̄ˢ, with
  c = ∫ ∏_s N(x; xˢ, Pˢ) dx evaluated by the sequential product
  c = ∏_{s=1}^{S−1} N(x^{s+1}; x^{(1:s)}, P^{(1:s)} + P^{s+1}) (the slides' P^{s} corrected to P^{s+1}).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from motionsig_cli.filters.pda import local_update
from motionsig_cli.models.radar import MeasurementModel

__all__ = ["METHODS", "ScanData", "TrackExistenceModel", "log_gauss", "log_product_constant", "run_methods"]

METHODS = ("ckf", "dkf", "lkf")


def log_gauss(x: np.ndarray, m: np.ndarray, C: np.ndarray) -> np.ndarray:
    """log N(x; m, C) for batches (..., n), (..., n, n), by Cholesky."""
    L = np.linalg.cholesky(C)
    d = np.linalg.solve(L, (x - m)[..., None])[..., 0]
    n = x.shape[-1]
    return (
        -0.5 * np.sum(d**2, axis=-1)
        - 0.5 * n * math.log(2 * math.pi)
        - np.sum(np.log(np.diagonal(L, axis1=-2, axis2=-1)), axis=-1)
    )


def log_product_constant(means: Sequence[np.ndarray], covs: Sequence[np.ndarray]) -> np.ndarray:
    """log ∫ ∏_s N(x; x_s, P_s) dx by the sequential product of Gaussians (spec §2.4, corrected).

    N(x; a, A)·N(x; b, B) = N(a; b, A + B)·N(x; c, C) with C = A − A(A+B)⁻¹A and
    c = a + A(A+B)⁻¹(b − a) (the Kalman form: no inverse of a single covariance). Batched over runs;
    0 for a single Gaussian.
    """
    a, A = means[0], covs[0]
    out = np.zeros(a.shape[:-1])
    for b, B in zip(means[1:], covs[1:], strict=True):
        AB = A + B
        out = out + log_gauss(b, a, AB)
        G = np.swapaxes(np.linalg.solve(AB, A), -1, -2)  # A(A+B)⁻¹ (symmetric A, AB)
        a = a + np.einsum("...ij,...j->...i", G, b - a)
        A = A - G @ A
        A = 0.5 * (A + np.swapaxes(A, -1, -2))
    return out


@dataclass(frozen=True)
class TrackExistenceModel:
    """What every method knows: motion model, sensors, measurement model, clutter density, p_D and the
    track prior."""

    F: np.ndarray
    Q: np.ndarray
    sensors: np.ndarray
    meas: MeasurementModel
    pd: float
    clutter_rate: float
    m0_cov: np.ndarray

    def __post_init__(self) -> None:
        if not 0.0 < self.pd <= 1.0:
            raise ValueError(f"p_D = {self.pd:g} is outside (0, 1]")
        if not (math.isfinite(self.clutter_rate) and self.clutter_rate >= 0):
            raise ValueError("the clutter rate must be >= 0")
        if len(self.sensors) < 1:
            raise ValueError("at least one sensor is needed")
        if np.any(np.linalg.eigvalsh(self.Q) < -1e-12) or np.any(np.linalg.eigvalsh(self.m0_cov) <= 0):
            raise ValueError("Q must be positive semi-definite and P0 positive definite")

    @property
    def n_sensors(self) -> int:
        return len(self.sensors)

    @property
    def log_rho(self) -> float:
        """log ρ_F, the clutter density in measurement space (−inf-safe: a tiny floor when λ_F = 0)."""
        return math.log(max(self.clutter_rate, 1e-300) / self.meas.fov_volume)


@dataclass(frozen=True)
class ScanData:
    """Measurements of one scan: per sensor an (R, M_s, 2) array and its (R, M_s) validity mask."""

    Z: tuple[np.ndarray, ...]
    valid: tuple[np.ndarray, ...]


def run_methods(
    model: TrackExistenceModel,
    m0: np.ndarray,
    scans: Sequence[ScanData],
    methods: Sequence[str] = METHODS,
    *,
    lkf_mean: str = "lr",
) -> dict[str, np.ndarray]:
    """log LR(k) for k = 1..K of each method, (R, K) per method, from initial track means m0 (R, 4)."""
    R = m0.shape[0]
    S = model.n_sensors
    F, Q, P0 = model.F, model.Q, model.m0_cov
    out = {name: np.zeros((R, len(scans))) for name in methods}
    P0b = np.broadcast_to(P0, (R, 4, 4))
    ckf = (m0.copy(), P0b.copy())
    # the S local filters of LKF and DKF are independent: one batch of S·R filters, sensor-major
    lkf = (np.tile(m0, (S, 1)), np.tile(P0b, (S, 1, 1)))
    lkf_score = np.zeros((S, R))
    dkf = (np.tile(m0, (S, 1)), S * np.tile(P0b, (S, 1, 1)))  # relaxed: ∏ N(·; m0, S·P0) ∝ N(·; m0, P0)
    sensor_rows = np.repeat(model.sensors, R, axis=0)  # (S·R, 2)
    total = {name: np.zeros(R) for name in methods}

    def upd(
        m: np.ndarray, P: np.ndarray, Z: np.ndarray, V: np.ndarray, sensor: np.ndarray
    ) -> tuple[np.ndarray, ...]:
        return local_update(m, P, Z, V, sensor, model.meas, model.pd, model.log_rho)

    def stacked(scan: ScanData) -> tuple[np.ndarray, np.ndarray]:
        """All sensors' measurements as one (S·R, M, 2) batch, padded to a common M."""
        M = max(z.shape[1] for z in scan.Z)
        Z = np.zeros((S, R, M, 2))
        V = np.zeros((S, R, M), dtype=bool)
        for s, (z, v) in enumerate(zip(scan.Z, scan.valid, strict=True)):
            Z[s, :, : z.shape[1]] = z
            V[s, :, : z.shape[1]] = v
        return Z.reshape(S * R, M, 2), V.reshape(S * R, M)

    for k, scan in enumerate(scans):
        if "ckf" in methods:
            m, P = ckf
            m, P = m @ F.T, F @ P @ F.T + Q
            lam = np.zeros(R)
            for s in range(S):  # sequential by construction: each sensor updates the running estimate
                m, P, lp = upd(m, P, scan.Z[s], scan.valid[s], model.sensors[s])
                lam += lp
            ckf = (m, P)
            total["ckf"] = total["ckf"] + lam
            out["ckf"][:, k] = total["ckf"]
        if "lkf" in methods or "dkf" in methods:
            Zs, Vs = stacked(scan)
        if "lkf" in methods:
            m, P = lkf
            m, P, lp = upd(m @ F.T, F @ P @ F.T + Q, Zs, Vs, sensor_rows)
            lkf = (m, P)
            lkf_score += lp.reshape(S, R)
            if lkf_mean == "lr":
                top = lkf_score.max(axis=0)
                safe = np.where(np.isneginf(top), 0.0, top)
                with np.errstate(divide="ignore"):
                    fused = safe + np.log(np.mean(np.exp(lkf_score - safe), axis=0))  # log of the mean LR
            else:
                fused = lkf_score.mean(axis=0)
            out["lkf"][:, k] = fused
        if "dkf" in methods:
            m, P = dkf
            m, P = m @ F.T, F @ P @ F.T + S * Q  # relaxed evolution model
            log_c_prior = log_product_constant(list(m.reshape(S, R, 4)), list(P.reshape(S, R, 4, 4)))
            m, P, lp = upd(m, P, Zs, Vs, sensor_rows)
            dkf = (m, P)
            log_c_post = log_product_constant(list(m.reshape(S, R, 4)), list(P.reshape(S, R, 4, 4)))
            total["dkf"] = total["dkf"] + lp.reshape(S, R).sum(axis=0) + log_c_post - log_c_prior
            out["dkf"][:, k] = total["dkf"]
    return out
