"""The radar LMP statistic of eq (52) without a filter bank: one sigma-point filter per record and a
projection of every candidate's filtered replica through that filter's linearisation (the radar analogue
of :mod:`motionsig_cli.detection.lmp_fft`, for §IV.B of the mode-signature paper, eqs 59–62).

Derivation (notebook "LMP with a sigma-point filter on radar measurements", section "A fast path"). A
sigma-point filter is, step by step, the Kalman filter of its *statistically linearised* model: with
P_k the predicted covariance, P_xy,k and S_k the unscented cross-covariance and innovation covariance,

    H_k = P_xy,kᵀ P_k⁻¹,   K_k = P_xy,k S_k⁻¹ = P_k H_kᵀ S_k⁻¹,   R̃_k = S_k − H_k P_k H_kᵀ,

(its gain is the Kalman gain of (H_k, R̃_k)). Only x and y enter eq (60), so with the lower Cholesky
factor L_k of P_k and D_k (3×2) the scaled sigma-point differences of the bank's reduction
(P_xy = L_k[:, :3] D_k), H_k = [D_kᵀ L_k[:3, :3]⁻¹, 0]. Under H1 (eq 62) the amplitudes a = (a_x, a_y)
enter the ẋ and ẏ rows with g_k = T(k1 z_k + k2 ż_k). For a *linear* measurement and a constant amplitude
(Q_a = 0) with prior a ~ N(0, P0 I) independent of the other states, the H1 model is the base model plus
the regressor a: y_k = (base part) + Φ_k a, where the 8×2 response δ of the base filter to a unit
amplitude column follows

    δ_0 = 0,   δ_{k+1} = F0 (I − K_k H_k) δ_k + [e_ẋ, e_ẏ] g_k,   ψ_k = L_S,k⁻¹ H_k δ_k   (2×2)

and the Gaussian integral over a gives, exactly (★ of the 1-D FFT path, now with two regressors),

    J_{H1} = J_base − ½ bᵀ (I/P0 + A)⁻¹ b,   b = Σ_k ψ_kᵀ e_k (2×1),   A = Σ_k ψ_kᵀ ψ_k (2×2),

e_k = L_S,k⁻¹ ν_k the base filter's whitened innovations. So Λ(c) = 2(J_H0 − J_base) + G_cos(c) +
G_sin(c), G = ½ bᵀ(I/P0 + A)⁻¹ b: one base filter per record, and per candidate a linear recursion
(run on a basis of the replicas, see Implementation below) and two inner products. The base filter is the H1 model's first eight states: eq (62)'s Q differs there from eq (61)'s,
so the H0 filter (for J_H0) and the base filter (Q^{H1}[:8]) both run, two filters instead of 2C + 1;
the term 2(J_H0 − J_base) is the same for every candidate.

Approximations on the radar (the bank is the reference): (i) each H1 filter of the bank linearises h
about its *own* estimate and covariance, the projection about the base filter's (the amplitude prior
P0 = 1 widens the bank's H1 sigma points; the error is second order in the signature's position
response over the curvature of h at 70 m); (ii) eq (62) gives the amplitudes random walks
(Q^{H1}[8:] = 10⁻¹, 10⁰ per step), which (★) ignores: the bank's amplitudes wander, the projection's
are constant; (iii) nothing else: the prior and the gains are the bank's. With a linear measurement
and Q^{H1}[8:] = 0 the projection equals the bank to rounding (the oracle test).

H0 centring (ours, as the 1-D ``center="h0-noise"``): with white measurement noise of the true
covariance R (R_filter / c_r) and no process noise, the base filter's error ε_k and the running b are
jointly Gaussian and zero-mean under the linearisation, with

    P^ε_{k+1} = A_k P^ε_k A_kᵀ + F0 K_k R Kₖᵀ F0ᵀ,   X_{k+1} = A_k X_k + Γ_k ψ_k      (X = E[ε bᵀ])
    Γ_k = (A_k P^ε_k H_kᵀ − F0 K_k R) L_S,k⁻ᵀ,   Σe_k = L_S,k⁻¹ (H_k P^ε_k H_kᵀ + R) L_S,k⁻ᵀ
    Σb_{k+1} = Σb_k + ψ_kᵀ H̄_k X_k + (ψ_kᵀ H̄_k X_k)ᵀ + ψ_kᵀ Σe_k ψ_k          (H̄ = L_S⁻¹ H)

(A_k = F0(I − K_k H_k)), so E[G] = ½ tr(M Σb) and, with the cos–sin cross term,
Var[G_cos + G_sin] = ½ tr((M_c Σ_cc)²) + ½ tr((M_s Σ_ss)²) + tr(M_c Σ_cs M_s Σ_sc), M = (I/P0 + A)⁻¹.
``center="h0-noise"`` subtracts E[G_cos + G_sin] (the candidate-dependent part of E[Λ(c) | H0]: the
rest, 2 E[J_H0 − J_base], is the same for every candidate); ``center="standardised"`` returns the z-score
(G − E G) / sd G, without the candidate-independent term.

Missing samples (a NaN row) are predict-only steps: no update and no term in any J (K_k = 0, the
response only propagates), as in the bank.

Implementation (exact rearrangements, no further approximation). (a) The replicas are linear in the chip
values: with p_k = Σ_q s_q 1[j(k) = q] (s_q = ±1, eq 1) every replica is g(c) = Σ_q S_cq β_q over a basis
β of unit-chip replicas (one per chip slot q and code-phase class τ mod m_ρ and f_c: n_ρ = 31 per carrier
and cos/sin on the chip grid instead of 93 candidates), so the recursion runs on the basis (a third of the
columns) and b(c) = S_c b_β, A(c) = S_c G_β S_cᵀ with the Gram G_β = Σ_k ψ_β,kᵀ ψ_β,k (one matrix product
per horizon segment). (b) The sigma-point filters run on every record at once with the records on the last
axis: closed-form Cholesky factors of the 3×3 lead block and of the 2×2 S, the predict F0 P F0ᵀ + Q as two
matrix products; the response recursion δ' = F0 δ − (F0 W_k) ψ_k (K_k H_k = W_k H̄_k, rank m) and ψ_k come
from one batched (n + m) × n product per record and step, fused with the filter pass (nothing per step is
kept but the current horizon segment of ψ).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from motionsig_cli.config import ConfigError, one_of
from motionsig_cli.detection.lmp import (
    Candidates,
    LMPResult,
    RadarLMPConfig,
    candidate_grid,
    checked_horizons,
    radar_measurement,
    radar_records,
)
from motionsig_cli.filters.kalman import Progress, missing_steps, step_reporter
from motionsig_cli.filters.unscented import SigmaMeasurement, linear_measurement
from motionsig_cli.models.radar import wrap_angle
from motionsig_cli.models.vehicle2d import IXD, IYD, Vehicle2D, prior_mean_2d, transition_h0_2d
from motionsig_cli.signals.signature import chip_index, replica_bank

__all__ = [
    "CENTERS",
    "H_POSITION",
    "MEASUREMENTS",
    "ReplicaBasis",
    "lmp_detect_radar_linearised",
    "replica_basis",
]

CENTERS = ("none", "h0-noise", "standardised")
MEASUREMENTS = ("radar", "position")
Center = Literal["none", "h0-noise", "standardised"]
H_POSITION = np.array([[1.0, 0, 0, 0, 0, 0, 0, 0], [0, 0, 1.0, 0, 0, 0, 0, 0]])  # y = (x, y) + v
SEGMENT = 256  # most time steps of ψ kept between two Gram updates
# the Gram updates are kept below the size above which OpenBLAS threads a matrix product (m·n·k ≈ 2.6e5): on
# these small products a thread pool costs more than it gains (measured 2-3x slower on a shared 2-core machine)
BLAS_SINGLE = 262144


# ------------------------------------------------------------------------------------------ replica basis
@dataclass(frozen=True)
class ReplicaBasis:
    """The candidates' a-columns g = T(k1 z + k2 ż) (eq 62) on a basis of unit-chip replicas:
    ``g_cos = S @ cos``, ``g_sin = S @ sin`` (to rounding; exactly for the analytic ż).

    Attributes:
        S: Chip values of each candidate on the basis, (C, r) (entries ±1 or 0).
        cos, sin: Basis a-columns, (r, N).
    """

    S: np.ndarray
    cos: np.ndarray
    sin: np.ndarray


def replica_basis(
    chips: np.ndarray, cands: Candidates, T: float, K: tuple[float, float], m_rho: int, n: int, zdot: str
) -> ReplicaBasis:
    """The basis of (a) in the module docstring: code phases whose chip-index sequences j(k) (eq 1, from
    k = −1 for the finite-difference ż) differ by a constant are one class; a basis replica is a unit
    chip in one slot of a class's representative phase, one per carrier; slots never reached are left out."""
    chips = np.asarray(chips, float)
    n_rho = chips.shape[1]
    k = np.arange(-1, n)
    k1, k2 = K
    index: dict[tuple[float, bytes, int], int] = {}  # (f_c, class key, relative slot) -> basis row
    rows: list[tuple[int, int, float]] = []  # (slot of the representative phase, its phase, f_c)
    S_cols = np.empty((len(cands.tau), n_rho), dtype=int)
    for c, (tau, fc) in enumerate(zip(cands.tau, cands.f_c, strict=True)):
        j = chip_index(k, int(tau), m_rho, n_rho)
        key = ((j - j[0]) % n_rho).tobytes()
        for q in range(n_rho):
            lab = (float(fc), key, (q - int(j[0])) % n_rho)
            if lab not in index:
                index[lab] = len(rows)
                rows.append((q, int(tau), float(fc)))
            S_cols[c, q] = index[lab]
    q_r, tau_r, fc_r = (np.array(a) for a in zip(*rows, strict=True))
    z_c, z_s, zd_c, zd_s = replica_bank(np.eye(n_rho), q_r, tau_r, fc_r, T, m_rho, n, zdot)  # type: ignore[arg-type]
    cos, sin = T * (k1 * z_c + k2 * zd_c), T * (k1 * z_s + k2 * zd_s)
    used = np.flatnonzero(np.any(cos != 0, axis=1) | np.any(sin != 0, axis=1))
    new = np.full(len(rows), -1)
    new[used] = np.arange(used.size)
    S = np.zeros((len(cands.tau), used.size))
    cand_rows = np.repeat(np.arange(len(cands.tau)), n_rho)
    cols = new[S_cols.ravel()]
    vals = chips[np.repeat(cands.mode, n_rho), np.tile(np.arange(n_rho), len(cands.tau))]
    keep = cols >= 0
    np.add.at(S, (cand_rows[keep], cols[keep]), vals[keep])
    return ReplicaBasis(S, np.ascontiguousarray(cos[used]), np.ascontiguousarray(sin[used]))


# ---------------------------------------------------------------------------------------------- helpers
def _wrap(d: np.ndarray, angular: np.ndarray) -> np.ndarray:
    """Wrap the angular components (first axis) of d to (−π, π], in place."""
    for a in angular:
        if np.any(np.abs(d[a]) > np.pi):
            d[a] = wrap_angle(d[a])
    return d


def _noise(vehicle: Vehicle2D, noise: np.ndarray | None, B: int) -> np.ndarray:
    """True (R_κ, R_χ) per record, (B, 2): ``noise`` or the vehicle's."""
    if noise is None:
        return np.broadcast_to([vehicle.R_range, vehicle.R_bearing], (B, 2)).astype(float)
    noise = np.asarray(noise, float)
    if noise.shape != (B, 2) or not np.all(np.isfinite(noise)) or not np.all(noise > 0):
        raise ValueError("noise must hold a finite (R_range, R_bearing) > 0 per record, (B, 2)")
    return noise


# ------------------------------------------------------------------------------------------- the detector
def lmp_detect_radar_linearised(
    y: np.ndarray,
    chips: np.ndarray,
    vehicle: Vehicle2D,
    m_rho: int,
    cfg: RadarLMPConfig,
    horizons: Sequence[int],
    *,
    noise: np.ndarray | None = None,
    measurement: Literal["radar", "position"] = "radar",
    center: Center = "none",
    progress: Progress = None,
) -> LMPResult:
    """Eq (52) for every candidate from one H0 and one base sigma-point filter per record and the projection
    of the candidates' filtered replicas (module docstring). Same inputs and result layout as
    :func:`~motionsig_cli.detection.lmp.lmp_detect_radar`; J_cos and J_sin are J_base − G (+ the log-det
    term with ``cfg.include_logdet``).

    Args:
        y: Records [range, bearing] (B, N, 2) (or (N, 2)); a NaN row is a missing sample (predict-only).
        noise: True (R_κ, R_χ) per record, (B, 2) (records of several noise levels in one call); None: the
            vehicle's. The filters assume c_r times them.
        measurement: ``"radar"`` (eq 60) or ``"position"`` (y = (x, y) + v: the linear case, where the
            projection is exact for Q^{H1}[8:] = 0; for tests and the notebook).
        center: ``"none"`` (eq 52), ``"h0-noise"`` (E[G | H0] subtracted) or ``"standardised"`` (z-score of G).
        progress: Called with the time steps done (one pass over the records), per block of steps.

    Raises:
        FloatingPointError: a covariance that does not factor (the bank would repair it; this path stops).
    """
    one_of("center", center, CENTERS)
    one_of("measurement", measurement, MEASUREMENTS)
    y = radar_records(y)
    hz = checked_horizons(y, horizons)
    B, N, _ = y.shape
    R_true = _noise(vehicle, noise, B)
    meas = (
        radar_measurement(vehicle, cfg.c_r)
        if measurement == "radar"
        else linear_measurement(H_POSITION, cfg.c_r * np.diag([vehicle.R_range, vehicle.R_bearing]))
    )
    F0 = transition_h0_2d(vehicle.T, vehicle.K)
    cands = candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg.as_grid)
    C = len(cands)
    basis = replica_basis(chips, cands, vehicle.T, vehicle.K, m_rho, N, cfg.zdot)
    shared = tuple(cfg.Q1[:8]) == tuple(cfg.Q0)  # the base filter is the H0 filter
    Qs = [np.diag(cfg.Q0)] if shared else [np.diag(cfg.Q0), np.diag(np.asarray(cfg.Q1[:8], float))]
    run = _Pass(
        F0, Qs, meas, R_true, cfg, y, hz, basis, center != "none", prior_mean_2d(vehicle.start, False)
    )
    run.go(progress)
    J0 = run.J[0] + (run.LD[0] if cfg.include_logdet else 0.0)
    Jb = run.J[-1] + (run.LD[-1] if cfg.include_logdet else 0.0)
    proj = run.projection(C)
    G = proj.gain  # (2C, B, H)
    J1 = Jb[None] - G
    if cfg.include_logdet:
        J1 = J1 + proj.half_logdet_ratio
    J_cos, J_sin = J1[:C], J1[C:]
    Lam = 2 * J0[None] - J_cos - J_sin
    if center == "h0-noise":
        assert proj.mean is not None
        Lam = Lam - proj.mean[:C] - proj.mean[C:]
    elif center == "standardised":
        assert proj.mean is not None and proj.var_pair is not None
        Lam = (G[:C] + G[C:] - proj.mean[:C] - proj.mean[C:]) / np.sqrt(proj.var_pair)
    return LMPResult(cands, hz, J0, J_cos, J_sin, Lam)


@dataclass(frozen=True)
class _Projection:
    gain: np.ndarray  # G = ½ bᵀ(I/P0 + A)⁻¹ b per replica, (2C, B, H)
    half_logdet_ratio: np.ndarray  # ½ log det(I + P0 A), (2C, B, H)
    mean: np.ndarray | None  # E[G | H0 white noise], (2C, B, H)
    var_pair: np.ndarray | None  # Var[G_cos + G_sin | H0], (C, B, H)


class _Pass:
    """One pass over the records: the H0 and base sigma-point filters (records on the last axis, the base
    filter's copies last) and, fused, the projection of the basis replicas through the base filter, with
    the H0 moments when ``moments``. Outputs per horizon: J, LD (filters, (F, B, H)); on the basis, b_β
    (H, B, 4r) and the Gram blocks (H, B, 2r, 2r) of the cos and sin columns (or Σ_β (H, B, 4r, 4r)).
    Column order of the responses: [cos-x, cos-y, sin-x, sin-y], r basis replicas each."""

    def __init__(
        self,
        F0: np.ndarray,
        Qs: list[np.ndarray],
        meas: SigmaMeasurement,
        R_true: np.ndarray,
        cfg: RadarLMPConfig,
        y: np.ndarray,
        hz: np.ndarray,
        basis: ReplicaBasis,
        moments: bool,
        x0: np.ndarray,
    ) -> None:
        self.x0 = np.asarray(x0, float)
        self.F0, self.meas, self.cfg, self.y, self.hz, self.basis, self.moments = (
            F0, meas, cfg, y, hz, basis, moments,
        )  # fmt: skip
        B, N, m = y.shape
        n, p = F0.shape[0], meas.lead
        nf = len(Qs)
        self.B, self.N, self.m, self.n, self.p, self.nf = B, N, m, n, p, nf
        R = np.zeros((m, m, B))
        R[0, 0], R[1, 1] = R_true[:, 0], R_true[:, 1]
        self.R_true = R  # (m, m, B)
        self.R_f = np.tile(cfg.c_r * R, (1, 1, nf))  # the filters' R, (m, m, nf·B)
        self.Q = np.concatenate([np.broadcast_to(q[:, :, None], (n, n, B)) for q in Qs], axis=2)

    def go(self, progress: Progress) -> None:
        """The fused pass over the time steps (the outputs of the class docstring)."""
        F0, meas, cfg, y, hz, basis = self.F0, self.meas, self.cfg, self.y, self.hz, self.basis
        B, N, m, n, p, nf = self.B, self.N, self.m, self.n, self.p, self.nf
        BB = nf * B
        base = slice((nf - 1) * B, nf * B)  # the base filter's copies
        _, wc0, wj, c = cfg.sigma.weights(n)
        w_e0 = wc0 + 2 * (n - p) * wj
        ang = [int(a) for a in np.flatnonzero(np.asarray(meas.angular, bool))]
        missing = missing_steps(y, "the sigma-point filter")  # (B, N)
        any_missing = missing.any(axis=0)
        yT = np.ascontiguousarray(np.transpose(y, (1, 2, 0)))  # (N, m, B)
        ends = np.unique(hz)
        read = {int(h): np.flatnonzero(hz == h) for h in ends}
        H = hz.size
        half_log2pi = 0.5 * m * math.log(2 * math.pi)
        x = np.repeat(self.x0[:, None], BB, axis=1)  # (n, BB)
        P = np.broadcast_to(cfg.P0 * np.eye(n)[:, :, None], (n, n, BB)).copy()
        J, LD = np.zeros(BB), np.zeros(BB)
        self.J, self.LD = np.empty((nf, B, H)), np.empty((nf, B, H))
        # responses: Z (B, n, cols) [| X (B, n, cols)], the batched products O = M Z with M = [A_k; H̄_k]
        r = basis.S.shape[1]
        cols = 4 * r
        wide = 2 * cols if self.moments else cols
        gx = np.zeros((N, wide))
        gy = np.zeros((N, wide))
        gx[:, :r], gx[:, 2 * r : 3 * r] = basis.cos.T, basis.sin.T  # a_x enters ẋ (eq 62)
        gy[:, r : 2 * r], gy[:, 3 * r : 4 * r] = basis.cos.T, basis.sin.T  # a_y enters ẏ
        Mk = np.zeros((B, n + m, n))
        Mk[:, :n, p:] = F0[:, p:]  # A_k = F0 (I − K_k H_k) differs from F0 in the lead columns only
        Os = [np.zeros((B, n + m, wide)), np.zeros((B, n + m, wide))]
        Z = Os[0][:, :n]
        width = cols if self.moments else 2 * r  # the widest Gram update's columns
        seg_len = int(min(SEGMENT, N, max(8, BLAS_SINGLE // (m * width * width))))
        Psi = np.zeros((B, m * seg_len, cols))  # ψ_k of the segment, rows (step, component)
        Eseg = np.zeros((B, m * seg_len, 1))
        bb = np.zeros((B, cols, 1))
        self.b_out = np.empty((H, B, cols))
        if self.moments:
            Vseg = np.zeros((B, m * seg_len, cols))  # V_k = H̄_k X_k + ½ Σe_k ψ_k
            Sig = np.zeros((B, cols, cols))  # Σ_k ψ_kᵀ V_k: Σ_β = Sig + Sigᵀ
            self.S_out = np.empty((H, B, cols, cols))
            Pe = np.zeros((B, n, n))
            Rt = np.ascontiguousarray(np.transpose(self.R_true, (2, 0, 1)))  # (B, m, m)
        Gc = np.zeros((B, 2 * r, 2 * r))
        Gs = np.zeros((B, 2 * r, 2 * r))
        self.Gc_out, self.Gs_out = np.empty((H, B, 2 * r, 2 * r)), np.empty((H, B, 2 * r, 2 * r))
        if p != 3 or m != 2:
            raise ValueError("the linearised path reads 3 lead states and 2 measurement components")
        Lm = np.zeros((p, p, BB))
        X = np.empty((p, 2 * p + 1, BB))
        Hw = np.zeros((m, p, BB))
        u = np.zeros((m, BB))
        wv = np.array([w_e0] + [wj] * (2 * p))
        Rf0, Rf1 = self.R_f[0, 0], self.R_f[1, 1]
        if self.moments:
            Lib = np.zeros((B, m, m))
        tick = step_reporter(progress, N)
        s0 = 0  # first step of the segment
        Pshape = (n, n * BB)
        for k in range(N):
            # ---- the sigma-point update (eq 60), every filter and record at once; L = chol P[:3, :3]
            l00 = np.sqrt(P[0, 0])
            i00 = 1.0 / l00
            l10, l20 = P[1, 0] * i00, P[2, 0] * i00
            l11 = np.sqrt(P[1, 1] - l10 * l10)
            i11 = 1.0 / l11
            l21 = (P[2, 1] - l20 * l10) * i11
            l22 = np.sqrt(P[2, 2] - l20 * l20 - l21 * l21)
            if not np.all(l00 * l11 * l22 > 0):
                raise FloatingPointError("a state covariance does not factor (use --method bank)")
            i22 = 1.0 / l22
            Lm[0, 0], Lm[1, 0], Lm[2, 0], Lm[1, 1], Lm[2, 1], Lm[2, 2] = l00, l10, l20, l11, l21, l22
            cL = c * Lm
            xl = x[:p, None]
            X[:, :1] = xl
            np.add(xl, cL, out=X[:, 1 : p + 1])  # χ_±j = x ± c L[:, j] on the lead states
            np.subtract(xl, cL, out=X[:, p + 1 :])
            Y = meas.h(X)  # (m, 2p + 1, BB)
            Y0 = Y[:, :1]
            D6 = Y[:, 1:] - Y0
            wrap = False
            for a in ang:  # no wrap can act when every angle stays within (−π, π] (two tests per step)
                lo, hi = float(Y[a].min()), float(Y[a].max())  # hi − lo bounds |h(χ_i) − h(χ_0)|
                shift = 2 * p * abs(wj) * (hi - lo)  # bound on |ŷ − h(χ_0)| in the angular components
                wrap = wrap or not (hi - lo + shift < np.pi and max(hi, -lo) + shift < np.pi)
            if wrap:
                D6 = _wrap(D6, ang)
            y_hat = Y0[:, 0] + wj * D6.sum(1)  # Σ W^m_i h(χ_i), angles about χ_0
            E7 = Y - y_hat[:, None]
            if wrap:
                y_hat, E7 = _wrap(y_hat, ang), _wrap(E7, ang)
            S = np.einsum("ajb,ijb,j->aib", E7, E7, wv)  # Σ W^c_i e_i e_iᵀ
            s00, s01, s11 = S[0, 0] + Rf0, S[0, 1], S[1, 1] + Rf1  # S_k = … + R (R diagonal)
            a0 = np.sqrt(s00)
            ia = 1.0 / a0
            ls10 = s01 * ia
            a1 = np.sqrt(s11 - ls10 * ls10)
            if not np.all(a0 * a1 > 0):
                raise FloatingPointError("an innovation covariance does not factor (use --method bank)")
            ib = 1.0 / a1
            c10 = -ls10 * ia * ib  # L_S⁻¹ = [[ia, 0], [c10, ib]]
            D = (wj * c) * (E7[:, 1 : p + 1] - E7[:, p + 1 :])  # P_xy = L[:, :3] Dᵀ, (m, 3, BB)
            j10 = -l10 * i00 * i11  # L⁻¹ (lower): diagonal i00, i11, i22
            j21 = -l21 * i11 * i22
            j20 = -(l20 * i00 + l21 * j10) * i22
            H0 = D[:, 0] * i00 + D[:, 1] * j10 + D[:, 2] * j20  # H_k = D L⁻¹ (columns x, ẋ, y)
            H1 = D[:, 1] * i11 + D[:, 2] * j21
            H2 = D[:, 2] * i22
            for col, h in enumerate((H0, H1, H2)):  # H̄_k = L_S⁻¹ H_k
                Hw[0, col] = ia * h[0]
                Hw[1, col] = c10 * h[0] + ib * h[1]
            nu = (yT[k] if nf == 1 else np.tile(yT[k], nf)) - y_hat  # ν_k, (m, BB)
            for a in ang:
                if np.abs(nu[a]).max() > np.pi:
                    nu[a] = wrap_angle(nu[a])
            u[0] = ia * nu[0]  # e_k = L_S⁻¹ ν_k
            u[1] = c10 * nu[0] + ib * nu[1]
            ld = np.log(a0 * a1)
            if any_missing[k]:
                gone = np.tile(missing[:, k], nf)
                Hw[:, :, gone] = 0.0
                u[:, gone] = 0.0
                ld[gone] = -half_log2pi
            W = np.einsum("njb,ijb->nib", P[:, :p], Hw)  # W = P_xy L_S⁻ᵀ = P[:, :3] H̄ᵀ, K = W L_S⁻¹
            x += np.einsum("nib,ib->nb", W, u)
            P -= np.einsum("nib,lib->nlb", W, W)
            J += 0.5 * (u[0] * u[0] + u[1] * u[1])
            LD += ld + half_log2pi
            # ---- the projection through the base filter: O = [A_k; H̄_k] [Z | X]
            Hwb = np.transpose(Hw[:, :, base], (2, 0, 1))  # (B, m, p)
            FWs = (F0 @ W.reshape(n, m * BB)).reshape(n, m, BB)[:, :, base]  # F0 W_k = F0 K_k L_S
            FW = np.transpose(FWs, (2, 0, 1))  # (B, n, m)
            np.subtract(F0[:, :p], np.einsum("aib,ijb->baj", FWs, Hw[:, :, base]), out=Mk[:, :n, :p])
            Mk[:, n:, :p] = Hwb  # A_k = F0 (I − K_k H_k) with K_k H_k = W_k H̄_k, and H̄_k
            Ob = Os[(k + 1) % 2]
            np.matmul(Mk, Z, out=Ob)
            i = k - s0
            Psi[:, m * i : m * i + m] = Ob[:, n:, :cols]  # ψ_k = H̄_k δ_k
            Eseg[:, m * i : m * i + m, 0] = u[:, base].T
            if self.moments:
                Lib[:, 0, 0], Lib[:, 1, 0], Lib[:, 1, 1] = ia[base], c10[base], ib[base]
                Rbar = Lib @ Rt @ np.swapaxes(Lib, 1, 2)  # L_S⁻¹ R L_S⁻ᵀ (R the true covariance)
                Hwb = np.ascontiguousarray(Hwb)
                HPe = Hwb @ Pe[:, :p]  # H̄ Pe (lead rows), (B, m, n)
                Se = HPe[:, :, :p] @ np.swapaxes(Hwb, 1, 2) + Rbar  # Σe_k
                # ψᵀ H̄X + (H̄X)ᵀ ψ + ψᵀ Σe ψ = ψᵀ V + Vᵀ ψ, with H̄_k X_k = E[e_k b_kᵀ]
                Vseg[:, m * i : m * i + m] = Ob[:, n:, cols:] + 0.5 * (Se @ Ob[:, n:, :cols])
                Ak = Mk[:, :n]
                APe = Ak @ Pe
                Gam = APe[:, :, :p] @ np.swapaxes(Hwb, 1, 2) - FW @ Rbar  # Γ_k = (A Pe Hᵀ − F0 K R) L_S⁻ᵀ
                Pe = APe @ np.swapaxes(Ak, 1, 2) + FW @ Rbar @ np.swapaxes(FW, 1, 2)
                Ob[:, :n, cols:] += Gam @ Ob[:, n:, :cols]  # X_{k+1} = A_k X_k + Γ_k ψ_k
            Z = Ob[:, :n]
            Z[:, IXD] += gx[k]
            Z[:, IYD] += gy[k]
            # ---- the filters' predict: x = F0 x, P = F0 P F0ᵀ + Q
            x = F0 @ x
            T1 = (F0 @ P.reshape(Pshape)).reshape(n, n, BB)
            P = (F0 @ np.ascontiguousarray(np.transpose(T1, (1, 0, 2))).reshape(Pshape)).reshape(n, n, BB)
            P = 0.5 * (P + np.transpose(P, (1, 0, 2))) + self.Q
            # ---- horizon segments: the Gram blocks and b_β
            h = k + 1
            if h in read or i + 1 == seg_len:
                rows = slice(0, m * (i + 1))
                Pc, Ps = Psi[:, rows, : 2 * r], Psi[:, rows, 2 * r :]
                Gc += np.swapaxes(Pc, 1, 2) @ Pc
                Gs += np.swapaxes(Ps, 1, 2) @ Ps
                bb += np.swapaxes(Psi[:, rows], 1, 2) @ Eseg[:, rows]
                if self.moments:
                    Sig += np.swapaxes(Psi[:, rows], 1, 2) @ Vseg[:, rows]
                s0 = k + 1
            if h in read:
                j = read[h]
                self.J[:, :, j] = J.reshape(nf, B)[:, :, None]
                self.LD[:, :, j] = LD.reshape(nf, B)[:, :, None]
                self.b_out[j] = bb[:, :, 0]
                self.Gc_out[j], self.Gs_out[j] = Gc, Gs
                if self.moments:
                    self.S_out[j] = Sig + np.swapaxes(Sig, 1, 2)
            tick(k)
        if not (np.all(np.isfinite(self.J)) and np.all(np.isfinite(self.LD))):
            raise FloatingPointError("the sigma-point filter produced a non-finite cost")

    def projection(self, C: int) -> _Projection:
        """The candidates' b and A from the basis (b = S b_β, A = S G_β Sᵀ), then G, the log-det ratio and,
        with moments, E[G] and Var[G_cos + G_sin] under H0 (module docstring)."""
        S = self.basis.S  # (C, r)
        r = S.shape[1]
        P0 = self.cfg.P0

        def lin(v: np.ndarray, blk: int) -> np.ndarray:  # S b over column block blk of (H, B, 4r) → (C, H, B)
            return np.einsum("cq,hbq->chb", S, v[..., blk * r : (blk + 1) * r])

        def quad(
            G: np.ndarray, i: int, j: int
        ) -> np.ndarray:  # diag S G_ij Sᵀ, blocks (.., r, r) → (C, H, B)
            Gij = G[..., i * r : (i + 1) * r, j * r : (j + 1) * r]
            return np.einsum("hbcq,cq->chb", S @ Gij, S)

        b = self.b_out
        bx = np.concatenate([lin(b, 0), lin(b, 2)])  # (2C, H, B): the cos replicas, then the sin
        by = np.concatenate([lin(b, 1), lin(b, 3)])
        axx = np.concatenate([quad(self.Gc_out, 0, 0), quad(self.Gs_out, 0, 0)])
        axy = np.concatenate([quad(self.Gc_out, 0, 1), quad(self.Gs_out, 0, 1)])
        ayy = np.concatenate([quad(self.Gc_out, 1, 1), quad(self.Gs_out, 1, 1)])
        ip = 1.0 / P0
        det = (ip + axx) * (ip + ayy) - axy**2
        # M = (I/P0 + A)⁻¹ = [[ip + ayy, −axy], [−axy, ip + axx]] / det
        mxx, mxy, myy = (ip + ayy) / det, -axy / det, (ip + axx) / det
        gain = 0.5 * (mxx * bx**2 + 2 * mxy * bx * by + myy * by**2)
        hld = 0.5 * np.log(P0**2 * det)  # ½ log det(I + P0 A)
        mean = var = None
        if self.moments:
            Sg = self.S_out  # Σ_β over [cos-x, cos-y, sin-x, sin-y]

            def sym(i: int, j: int) -> np.ndarray:
                return quad(Sg, min(i, j), max(i, j)) if i != j else quad(Sg, i, i)

            def Mof(sin: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
                sl = slice(sin * C, (sin + 1) * C)
                return mxx[sl], mxy[sl], myy[sl]

            def mat_mul(a: tuple, bm: tuple) -> tuple:  # 2×2 products of (11, 12, 21, 22) tuples
                return (
                    a[0] * bm[0] + a[1] * bm[2],
                    a[0] * bm[1] + a[1] * bm[3],
                    a[2] * bm[0] + a[3] * bm[2],
                    a[2] * bm[1] + a[3] * bm[3],
                )

            Mc, Ms = ((m0, m1, m1, m2) for m0, m1, m2 in (Mof(0), Mof(1)))
            s01, s23 = sym(0, 1), sym(2, 3)
            Scc = (sym(0, 0), s01, s01, sym(1, 1))
            Sss = (sym(2, 2), s23, s23, sym(3, 3))
            Scs = (sym(0, 2), sym(0, 3), sym(1, 2), sym(1, 3))  # E[b_cos b_sinᵀ]
            Ssc = (Scs[0], Scs[2], Scs[1], Scs[3])
            MS_c, MS_s = mat_mul(Mc, Scc), mat_mul(Ms, Sss)
            mean_c = 0.5 * (MS_c[0] + MS_c[3])
            mean_s = 0.5 * (MS_s[0] + MS_s[3])
            sq = lambda X: X[0] * X[0] + X[1] * X[2] + X[2] * X[1] + X[3] * X[3]  # tr(X²)  # noqa: E731
            cross = mat_mul(mat_mul(Mc, Scs), mat_mul(Ms, Ssc))
            var = 0.5 * sq(MS_c) + 0.5 * sq(MS_s) + (cross[0] + cross[3])
            mean = np.concatenate([mean_c, mean_s])
            mean, var = np.swapaxes(mean, 1, 2), np.swapaxes(var, 1, 2)
        if not np.all(np.isfinite(gain)):
            raise FloatingPointError("the projection produced a non-finite statistic")
        return _Projection(np.swapaxes(gain, 1, 2), np.swapaxes(hld, 1, 2), mean, var)


def check_linearised(cfg: RadarLMPConfig) -> None:
    """The settings the projection implements (all of :class:`RadarLMPConfig`: the amplitudes' random walk
    of Q^{H1}[8:] is approximated by a constant amplitude, see the module docstring); a
    :class:`ConfigError` of ``method`` otherwise."""
    if not isinstance(cfg, RadarLMPConfig):
        raise ConfigError("method", "linearised", "needs a RadarLMPConfig (the radar example)")
