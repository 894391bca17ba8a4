"""The local node update of the track-existence test: an EKF step over all hypotheses "measurement j is
the target" (j = 1..m) and "no target detection" (j = 0), with the likelihood-ratio increment and a
moment-matched (PDA-style) posterior (Govaers, *Evaluation of Distributed Detection Methods for Agile
Targets*: the local likelihood-ratio update).

For a prior N(x; m, P), linearised measurement ẑ = h(m), H = ∂h/∂x, S = HPHᵀ + R, K = PHᵀS⁻¹:

    log p*⁰ = log(1 − p_D),   log p*ʲ = log(p_D/ρ_F) + log N(νⱼ; 0, S),  νⱼ = zⱼ − ẑ (bearing wrapped)
    log p̄  = logsumexp_{j=0..m} log p*ʲ                          (j = 0, the missed detection, included: the slides sum j = 1..m here but j = 0..m in the normalisation)
    m⁺ = m + K ν̄,   ν̄ = Σ pⱼνⱼ  (pⱼ = p*ʲ/p̄, ν₀ = 0)
    P⁺ = p₀P + (1 − p₀)P₁ + K(Σ pⱼνⱼνⱼᵀ − ν̄ν̄ᵀ)Kᵀ,   P₁ = (I − KH)P(I − KH)ᵀ + KRKᵀ (Joseph)

which is exactly the moment match of the components (m + Kνⱼ, P₁) and (m, P). Batched over runs; a
run's measurement list is padded to a common length with a validity mask.

**Validation gate** (optional, gate probability P_G; the PDAF's gate, Bar-Shalom & Tse, *Tracking in a
cluttered environment with probabilistic data association*, Automatica 1975). The gate is the ellipse
G = {z : (z − ẑ)ᵀS⁻¹(z − ẑ) ≤ γ}; for a 2-vector the squared Mahalanobis distance of the target's
measurement is χ²₂, P(d² ≤ γ) = 1 − e^{−γ/2}, so γ = −2 ln(1 − P_G) (exact, no table). Measurements
outside G are ignored: the data of the scan are the m_G measurements inside it. With Poisson clutter of
density ρ_F (unchanged by the gate) and the target detected with p_D,

    p(Z_G | h0) = e^{−ρ_F|G|} ∏ⱼ ρ_F
    p(Z_G | x, h1) = e^{−ρ_F|G|} [ (1 − p_D P_G) ∏ⱼ ρ_F + p_D P_G Σⱼ (N(zⱼ; ẑ, S)/P_G) ∏_{i≠j} ρ_F ]

(the target is detected *and* falls in the gate with probability p_D·P_G; given that, its measurement
has the density N(z; ẑ, S)/P_G on G, the Gaussian renormalised by the gate). Their ratio is

    Λ = (1 − p_D P_G) + (p_D P_G/ρ_F) Σ_{j ∈ G} N(zⱼ; ẑ, S)/P_G
      = (1 − p_D P_G) + (p_D/ρ_F) Σ_{j ∈ G} N(zⱼ; ẑ, S),

so log p*⁰ = log(1 − p_D P_G), log p*ʲ is unchanged for j ∈ G and −∞ outside it. Under h0 its mean is
E[Λ] = 1 − p_D P_G + (p_D/ρ_F)·ρ_F·∫_G N dz = 1 (when G lies in the field of view): the gated ratio is
still a likelihood ratio. As in the PDAF, the "no target measurement in G" hypothesis keeps the prior
(m, P) (the truncation of the prior to the measurements outside G is neglected). With P_G = 1 the gate
is the whole space and the update is the ungated one to the last bit.
"""

from __future__ import annotations

import math

import numpy as np

from motionsig_cli.models.radar import MeasurementModel, wrap_angle

__all__ = ["gate_threshold", "local_update", "log_gauss_2"]

LOG_2PI = math.log(2.0 * math.pi)


def _mahalanobis_2(nu: np.ndarray, S: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(νᵀS⁻¹ν (..., M), log √det S (...)) for 2-vectors ν (..., M, 2) and covariances S (..., 2, 2), by the
    2×2 Cholesky factor."""
    l11 = np.sqrt(S[..., 0, 0])
    l21 = S[..., 1, 0] / l11
    l22 = np.sqrt(S[..., 1, 1] - l21**2)
    a = nu[..., 0] / l11[..., None]
    b = (nu[..., 1] - l21[..., None] * a) / l22[..., None]
    return a**2 + b**2, np.log(l11 * l22)


def log_gauss_2(nu: np.ndarray, S: np.ndarray) -> np.ndarray:
    """log N(ν; 0, S) for 2-vectors ν (..., M, 2) and covariances S (..., 2, 2), by the 2×2 Cholesky factor."""
    d2, log_det_half = _mahalanobis_2(nu, S)
    return -0.5 * d2 - LOG_2PI - log_det_half[..., None]


def gate_threshold(gate_pg: float) -> float:
    """γ with P(χ²₂ ≤ γ) = P_G: γ = −2 ln(1 − P_G) (the χ² law with 2 degrees of freedom is exponential);
    ∞ for P_G = 1."""
    return -2.0 * math.log1p(-gate_pg) if gate_pg < 1.0 else math.inf


def local_update(
    m: np.ndarray,
    P: np.ndarray,
    Z: np.ndarray,
    valid: np.ndarray,
    sensor: np.ndarray,
    model: MeasurementModel,
    pd: float | np.ndarray,
    log_rho: float | np.ndarray,
    noise: np.ndarray | None = None,
    gate_pg: float | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One sensor's update of a batch of filters (the local update of the module docstring).

    Args:
        m, P: priors (R, 4), (R, 4, 4).
        Z: (R, M, 2) measurements (padded); valid: (R, M) mask.
        sensor: (2,) sensor position, or (R, 2): one per filter (a batch of several sensors' filters).
        model: measurement model.
        pd: detection probability in (0, 1]; with pd = 1 the j = 0 term is omitted. Or (R,): one per
            filter (filters of sensors with different p_D in one batch).
        log_rho: log of the clutter density ρ_F in measurement space, or (R,): one per filter.
        noise: (R, 2, 2): one measurement noise covariance per filter (default: ``model.R`` for all).
        gate_pg: the validation gate's probability P_G in (0, 1] (module docstring), or None: no gate.
            Measurements outside the gate are ignored and the missed-detection term is 1 − p_D·P_G.

    Per-filter values give, filter by filter, the same numbers as a call with that filter's scalars:
    log p_D and log(1 − p_D) are taken with :mod:`math` for each distinct value.

    Returns:
        (m⁺, P⁺, log p̄) with shapes (R, 4), (R, 4, 4), (R,).
    """
    zhat = model.h(m, sensor)
    H = model.jacobian(m, sensor)
    HP = H @ P
    Rn = model.R if noise is None else noise
    S = HP @ np.swapaxes(H, -1, -2) + Rn
    S = 0.5 * (S + np.swapaxes(S, -1, -2))
    nu = Z - zhat[:, None, :]
    if model.angular is not None:
        nu[..., model.angular] = wrap_angle(nu[..., model.angular])
    d2, log_det_half = _mahalanobis_2(nu, S)
    log_n = -0.5 * d2 - LOG_2PI - log_det_half[..., None]  # log N(νⱼ; 0, S), as log_gauss_2
    if gate_pg is not None:  # the validation gate: measurements with d² > γ are ignored
        valid = valid & (d2 <= gate_threshold(gate_pg))
    if np.ndim(pd) == 0 and np.ndim(log_rho) == 0:
        logw = math.log(pd) - log_rho + log_n  # log p*ʲ
        miss = pd if gate_pg is None else pd * gate_pg  # p_D·P_G with a gate
        logw0 = math.log1p(-miss) if miss < 1.0 else -np.inf  # log p*⁰
    else:  # one p_D and ρ_F per filter
        log_pd, logw0 = _log_pd(np.broadcast_to(np.asarray(pd, dtype=float), m.shape[:1]), gate_pg)
        logw = (log_pd - np.broadcast_to(log_rho, m.shape[:1]))[:, None] + log_n
    logw = np.where(valid, logw, -np.inf)
    top = np.maximum(np.max(logw, axis=-1, initial=-np.inf), logw0)
    impossible = np.isneginf(top)  # p_D = 1 and no measurement: Λ = 0, log p̄ = −inf (certain deletion)
    top = np.where(impossible, 0.0, top)
    with np.errstate(divide="ignore"):
        log_pbar = top + np.log(
            np.exp(logw0 - top) + np.sum(np.exp(logw - top[:, None]), axis=-1)
        )  # logsumexp
    ref = np.where(impossible, 0.0, log_pbar)
    p = np.exp(logw - ref[:, None])  # (R, M), zero where invalid
    p0 = np.where(impossible, 1.0, np.exp(logw0 - ref))  # an impossible update leaves the prior unchanged
    nu = np.where(valid[..., None], nu, 0.0)
    K = np.swapaxes(np.linalg.solve(S, HP), -1, -2)  # PHᵀS⁻¹ (S symmetric)
    nubar = np.einsum("rm,rmi->ri", p, nu)
    m_plus = m + np.einsum("rij,rj->ri", K, nubar)
    IKH = np.eye(4) - K @ H
    P1 = IKH @ P @ np.swapaxes(IKH, -1, -2) + K @ Rn @ np.swapaxes(K, -1, -2)  # Joseph
    spread = np.einsum("rm,rmi,rmj->rij", p, nu, nu) - np.einsum("ri,rj->rij", nubar, nubar)
    P_plus = p0[:, None, None] * P + (1.0 - p0)[:, None, None] * P1 + K @ spread @ np.swapaxes(K, -1, -2)
    return m_plus, 0.5 * (P_plus + np.swapaxes(P_plus, -1, -2)), log_pbar


def _log_pd(pd: np.ndarray, gate_pg: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(log p_D, log(1 − p_D·P_G)) per filter (P_G = 1 without a gate), −inf for the second where
    p_D·P_G = 1: each distinct value by :mod:`math`, as the scalar path computes it."""
    values, index = np.unique(pd, return_inverse=True)
    log_pd = np.array([math.log(v) for v in values])
    miss = [v if gate_pg is None else v * gate_pg for v in values]
    log_miss = np.array([math.log1p(-v) if v < 1.0 else -math.inf for v in miss])
    return log_pd[index], log_miss[index]
