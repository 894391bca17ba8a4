"""The LMP statistic of eq (52) without a filter bank: one H0 filter and FFT cross-correlations.

Derivation (notebook "LMP detector", section "The FFT fast path"). With a constant amplitude
(Q_a = 0) and the prior a ~ N(0, P0) independent of the other states, the H1 model of eq (44) is the
H0 model plus a known regressor: y_k = (H0 part) + a·u_k, where u_k is the position response of the
closed loop to the a-column g_k = T(k1 z_k + k2 ż_k) (eq 44, row ẋ). Run the H0 Kalman filter on u
alone: its innovations φ_k are a linear filtering of g (δ_{k+1} = F0(I − K_k H) δ_k + e₂ g_k,
φ_k = H δ_k). With whitened innovations e_k = ν_k/√S_k and ψ_k = φ_k/√S_k, the Gaussian integral over a
gives, exactly,

    J_{H1} = J_{H0} − ½ b² / (1/P0 + A),    b = Σ_k ψ_k e_k,   A = Σ_k ψ_k²         (★)

so eq (52) is Λ = ½ b_cos²/(1/P0 + A_cos) + ½ b_sin²/(1/P0 + A_sin): every candidate needs only an
inner product of the *one* H0 innovation sequence with its filtered replica.

In steady state (K_k = K̄, S_k = S̄) the regressor filter is time-invariant, with impulse response
h[m] = H Āᵐ⁻¹ e₂/√S̄ (Ā = F0(I − K̄H)). Writing the replicas as g_cos = Re(γ p_{k−τ} e^{iωk}),
g_sin = Re(−iγ p_{k−τ} e^{iωk}) (γ = T(k1 + i k2 ω_c), analytic ż, ω = 2π f_c T, p the ±1 chip
sequence of period P = n_ρ m_ρ samples), the filtered replica of code phase τ is
ψ_k = Re(e^{iωk} d_{k−τ}) with the P-periodic d = (h e^{−iωm}) ⊛ (γ p). Then

    b_cos(τ) + i b_sin(τ) = Σ_{k<n} e_k e^{iωk} d_{k−τ} = Σ_j Ē_n[j] d[(j − τ) mod P],

Ē_n the demodulated innovations folded modulo P: one length-P circular cross-correlation (FFT)
gives all code phases at once; A_cos, A_sin follow the same way from |d|² and d².

Exact vs approximate: (★) is exact for Q_a = 0. The FFT form adds two approximations that decay
with the filter's memory: the steady-state gain (the bank's gains start from P0) and the infinite
past of the periodic convolution (the bank's filtered replica starts from rest at k = 0). With
Q_a > 0 the amplitude wanders and (★) no longer holds: the bank is then the reference.
``lmp_detect_projection`` evaluates (★) exactly with the time-varying filters (no FFT), the oracle
that isolates the steady-state approximation.

The filters' model is :func:`~motionsig_cli.detection.lmp.filter_model`'s: the reference as a random-walk
state (A_r cv or identity, 4 H0 states) or as a known input (A_r known, 2 H0 states [x, ẋ]: the known
reference's response is subtracted from y first, exactly as the bank does), Q per step or a continuous
density (q_model). Both need Q_a = 0; the FFT path does not apply to a wandering amplitude (Q_a > 0), to
the sigma-point bank, to weights "exact" or to the centring.

Missing samples: the FFT form needs every sample (the steady-state filter and the periodic convolution
assume an unbroken record), so both paths here refuse a NaN measurement with
:class:`~motionsig_cli.filters.kalman.MissingSamples` (its ``index`` names the first one); the filter bank
(:func:`~motionsig_cli.detection.lmp.lmp_detect`) skips missing samples.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np
import scipy.linalg

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.lmp import (
    Candidates,
    LMPConfig,
    LMPResult,
    candidate_grid,
    checked_horizons,
    filter_model,
    known_input_removed,
)
from motionsig_cli.filters.kalman import MissingSamples, riccati
from motionsig_cli.models.vehicle import Vehicle1D, amplitude_column
from motionsig_cli.signals.signature import replica_bank

__all__ = [
    "FFT_CANNOT_SKIP",
    "MissingSamples",
    "check_fft_config",
    "lmp_detect_fft",
    "lmp_detect_projection",
    "periodic_replicas",
    "regressor_impulse",
    "steady_state",
    "whitened_innovations",
]

FFT_CANNOT_SKIP = "the FFT path cannot skip a missing sample: use the filter bank (method bank)"
H_POS = np.array([[1.0, 0.0, 0.0, 0.0]])  # the 4-state model's position row (2 states: its first two)
E_VEL = np.array([0.0, 1.0, 0.0, 0.0])  # the a-column enters the ẋ row (eq 44)
MAX_TAIL = 1_000_000  # impulse-response samples kept at most


def check_fft_config(cfg: LMPConfig) -> None:
    """The settings the FFT path implements: a :class:`ConfigError` of the field ``method`` (the choice of
    this path) says which setting it does not."""
    if cfg.Q_a != 0:
        raise ConfigError("method", "fft", f"needs a constant amplitude, Q_a = 0 (got {cfg.Q_a:g})")
    if cfg.weights != "paper":
        raise ConfigError("method", "fft", "implements weights='paper' (eq 52) only")
    if cfg.center != "none":
        raise ConfigError("method", "fft", "implements center='none' only")
    if cfg.zdot != "analytic":
        raise ConfigError("method", "fft", "implements the analytic replica derivative only")


def steady_state(vehicle: Vehicle1D, cfg: LMPConfig) -> tuple[np.ndarray, float, np.ndarray]:
    """(K̄, S̄, Ā): steady-state update gain (n,), innovation variance and Ā = F0(I − K̄H) of the H0 filter
    (n = 4 states, or 2 with a known reference).

    The predicted covariance solves the discrete algebraic Riccati equation of eqs (45)–(47)."""
    model = filter_model(vehicle, cfg)
    F0, H, n = model.F0, model.H(), model.n
    R = cfg.c_r * vehicle.R
    P = scipy.linalg.solve_discrete_are(F0.T, H.T, model.Q0, np.array([[R]]))  # P = F P Fᵀ − … + Q
    P = 0.5 * (P + P.T)
    S = float(P[0, 0] + R)  # S̄ = H P̄ Hᵀ + R, eq (47)
    K = P[:, 0] / S  # K̄ = P̄ Hᵀ S̄⁻¹
    A = F0 @ (np.eye(n) - np.outer(K, H[0]))
    return K, S, A


def whitened_innovations(y: np.ndarray, vehicle: Vehicle1D, cfg: LMPConfig) -> tuple[np.ndarray, float]:
    """e_k = ν_k/√S̄ of the steady-state H0 filter on records y (B, N), and S̄ (with ``A_r="known"``, y is
    the record less the known reference's response: :func:`lmp_detect_fft` subtracts it)."""
    K, S, _ = steady_state(vehicle, cfg)
    model = filter_model(vehicle, cfg)
    F0, n = model.F0, model.n
    y = np.atleast_2d(np.asarray(y, dtype=float))
    B, N = y.shape
    x = np.zeros((n, B))
    e = np.empty((B, N))
    FK = F0 @ K
    A = F0 - np.outer(FK, H_POS[0, :n])  # x_{k+1|k} = Ā x_{k|k−1} + F0 K̄ y_k
    for k in range(N):
        nu = y[:, k] - x[0]  # ν_k = y_k − H x_{k|k−1}
        e[:, k] = nu
        x = A @ x + FK[:, None] * y[:, k][None, :]
    return e / np.sqrt(S), S


def regressor_impulse(vehicle: Vehicle1D, cfg: LMPConfig, tol: float = 1e-13) -> np.ndarray:
    """h[m] = H Āᵐ⁻¹ e₂ / √S̄ (h[0] = 0), until it is below ``tol`` of its peak for good."""
    _, S, A = steady_state(vehicle, cfg)
    rho = float(np.max(np.abs(np.linalg.eigvals(A))))
    if not rho < 1:
        raise ValueError("the steady-state H0 filter is not stable; the FFT path does not apply")
    n = int(min(MAX_TAIL, max(64, np.ceil(np.log(tol) / np.log(rho)) + 64)))
    h = np.zeros(n)
    d = E_VEL[: A.shape[0]].copy()
    for m in range(1, n):
        h[m] = d[0]
        d = A @ d
    return h / np.sqrt(S)


def _fold(x: np.ndarray, P: int) -> np.ndarray:
    """Σ over k ≡ j (mod P) along the last axis → (..., P)."""
    n = x.shape[-1]
    pad = (-n) % P
    if pad:
        x = np.concatenate([x, np.zeros((*x.shape[:-1], pad), dtype=x.dtype)], axis=-1)
    return x.reshape(*x.shape[:-1], -1, P).sum(axis=-2)


def _xcorr(a_hat: np.ndarray, d: np.ndarray) -> np.ndarray:
    """X[τ] = Σ_j a[j] d[(j − τ) mod P] from fft(a) (…, P) and d (P,)."""
    return np.fft.ifft(a_hat * np.conj(np.fft.fft(np.conj(d))), axis=-1)


def periodic_replicas(
    chips: np.ndarray, vehicle: Vehicle1D, m_rho: int, f_c: float, h: np.ndarray
) -> np.ndarray:
    """d (M, P): the filtered, demodulated replica of code phase 0 of every mode (one code period)."""
    chips = np.asarray(chips, dtype=float)
    P = chips.shape[1] * m_rho
    k1, k2 = vehicle.K
    w = 2 * np.pi * f_c * vehicle.T  # carrier advance per sample
    gamma = vehicle.T * (k1 + 1j * k2 * 2 * np.pi * f_c)  # g = Re(γ p e^{iωk}), eq (44) a-column
    p = np.repeat(chips, m_rho, axis=1)  # (M, P), chip j held for m_ρ samples (eq 1, τ = 0)
    h_w = _fold(h * np.exp(-1j * w * np.arange(h.size)), P)  # h_ω folded modulo P
    return np.fft.ifft(np.fft.fft(h_w)[None, :] * np.fft.fft(gamma * p, axis=1), axis=1)


def _checked_inputs(
    y: np.ndarray, horizons: Sequence[int], cfg: LMPConfig, vehicle: Vehicle1D, reference: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """Records (B, N) and horizons of the FFT and projection paths, checked as :func:`lmp_detect` does, and
    no missing sample (:class:`MissingSamples` names the first); with ``A_r="known"`` the known reference's
    response subtracted (:func:`~motionsig_cli.detection.lmp.known_input_removed`)."""
    check_fft_config(cfg)
    y = np.atleast_2d(np.asarray(y, dtype=float))
    nan = np.isnan(y)
    if nan.any():
        b, k = np.argwhere(nan)[0]
        raise MissingSamples(FFT_CANNOT_SKIP, int(k), int(b))
    hz = checked_horizons(y, horizons)
    return known_input_removed(y, vehicle, cfg, reference), hz


def lmp_detect_fft(
    y: np.ndarray, chips: np.ndarray, vehicle: Vehicle1D, m_rho: int, cfg: LMPConfig, horizons: Sequence[int],
    reference: np.ndarray | None = None,
) -> LMPResult:  # fmt: skip
    """Eq (52) for every candidate from one steady-state H0 filter and FFT cross-correlations.

    Same inputs (``reference``: the known reference of ``A_r="known"``, as for
    :func:`motionsig_cli.detection.lmp.lmp_detect`) and result layout as
    :func:`~motionsig_cli.detection.lmp.lmp_detect`; J_cos and J_sin are J_{H0} − ½ b²/(1/P0 + A) of (★).

    Examples:
        The FFT path gives the filter bank's result layout (its steady-state filter makes the values close to
        the bank's, not equal; constant amplitude, Q_a = 0):

        >>> import numpy as np
        >>> from motionsig_cli import LMPConfig, Vehicle1D, lmp_detect, lmp_detect_fft, parse_codes
        >>> chips = parse_codes("corrected").chips
        >>> y = 1e-3 * np.random.default_rng(0).standard_normal(310)
        >>> cfg = LMPConfig(Q_a=0.0)
        >>> bank = lmp_detect(y, chips, Vehicle1D(), 2, cfg, [310])
        >>> fft = lmp_detect_fft(y, chips, Vehicle1D(), 2, cfg, [310])
        >>> fft.Lambda.shape == bank.Lambda.shape == (93, 1, 1)
        True
    """
    y, hz = _checked_inputs(y, horizons, cfg, vehicle, reference)
    B, N = y.shape
    chips = np.asarray(chips, dtype=float)
    M, n_rho = chips.shape
    P = n_rho * m_rho
    cands = candidate_grid(M, n_rho, m_rho, cfg)
    e, S = whitened_innovations(y, vehicle, cfg)
    J0 = 0.5 * np.cumsum(e**2, axis=1)[:, hz - 1]  # (B, H)
    if cfg.include_logdet:
        J0 = J0 + 0.5 * hz[None, :] * np.log(2 * np.pi * S)
    h = regressor_impulse(vehicle, cfg)
    k = np.arange(N)
    mask = k[None, :] < hz[:, None]  # (H, N): sample k lies within horizon n
    step = m_rho if cfg.tau_grid == "chips" else 1
    taus = np.arange(0, P, step)
    nF = len(cfg.fc_grid)
    Lam = np.empty((M, taus.size, nF, B, hz.size))
    bc = np.empty_like(Lam)
    bs = np.empty_like(Lam)
    Ac = np.empty((M, taus.size, nF, hz.size))
    As = np.empty_like(Ac)
    for f, f_c in enumerate(cfg.fc_grid):
        w = 2 * np.pi * f_c * vehicle.T
        d = periodic_replicas(chips, vehicle, m_rho, f_c, h)  # (M, P)
        rot = np.exp(1j * w * k)
        Ebar = np.fft.fft(_fold((e * rot)[:, None, :] * mask[None], P), axis=-1)  # (B, H, P)
        ones = np.fft.fft(_fold(mask.astype(float), P), axis=-1)  # (H, P)
        rot2 = np.fft.fft(_fold(rot[None, :] ** 2 * mask, P), axis=-1)
        for m in range(M):
            X = _xcorr(Ebar, d[m])[..., taus]  # (B, H, τ): b_cos + i b_sin
            half = 0.5 * _xcorr(ones, np.abs(d[m]) ** 2)[..., taus].real  # ½ Σ|d|²
            cross = 0.5 * _xcorr(rot2, d[m] ** 2)[..., taus].real  # ½ Re Σ e^{2iωk} d²
            A_cos, A_sin = (half + cross).T, (half - cross).T  # (τ, H)
            if w == 0:  # f_c = 0: the sin replica is identically zero
                A_sin = np.zeros_like(A_sin)
            Ac[m, :, f], As[m, :, f] = A_cos, A_sin
            bc[m, :, f] = np.moveaxis(X.real, -1, 0)
            bs[m, :, f] = np.moveaxis(X.imag, -1, 0) if w != 0 else 0.0
    gain_c = 0.5 * bc**2 / (1 / cfg.P0 + Ac[:, :, :, None, :])  # ½ b²/(1/P0 + A), (★)
    gain_s = 0.5 * bs**2 / (1 / cfg.P0 + As[:, :, :, None, :])
    J_cos = (J0[None, None, None] - gain_c).reshape(len(cands), B, hz.size)
    J_sin = (J0[None, None, None] - gain_s).reshape(len(cands), B, hz.size)
    Lam = (gain_c + gain_s).reshape(len(cands), B, hz.size)  # eq (52) via (★)
    if cfg.include_logdet:  # ½ Σ log det 2πS of H1 = H0's + ½ log(1 + P0 A)
        ld = 0.5 * (np.log1p(cfg.P0 * Ac) + np.log1p(cfg.P0 * As)).reshape(len(cands), 1, hz.size)
        Lam = Lam - ld
        J_cos = J_cos + 0.5 * np.log1p(cfg.P0 * Ac).reshape(len(cands), 1, hz.size)
        J_sin = J_sin + 0.5 * np.log1p(cfg.P0 * As).reshape(len(cands), 1, hz.size)
    return LMPResult(cands, hz, J0, J_cos, J_sin, Lam)


def lmp_detect_projection(
    y: np.ndarray, chips: np.ndarray, vehicle: Vehicle1D, m_rho: int, cfg: LMPConfig, horizons: Sequence[int],
    reference: np.ndarray | None = None,
) -> LMPResult:  # fmt: skip
    """Eq (52) through (★) with the exact time-varying H0 filter (the bank's gains, no steady state).

    Equal to the filter bank with Q_a = 0 up to rounding: the check of (★) and the oracle that
    separates the FFT path's steady-state approximation from the identity itself.
    """
    y, hz = _checked_inputs(y, horizons, cfg, vehicle, reference)
    B, N = y.shape
    chips = np.asarray(chips, dtype=float)
    cands: Candidates = candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg)
    C = len(cands)
    model = filter_model(vehicle, cfg)
    F0, n = model.F0, model.n
    g0 = riccati(
        lambda k: F0, model.H(), model.Q0, np.array([[cfg.c_r * vehicle.R]]), cfg.P0 * np.eye(n), N, 1
    )
    K = g0.K[0, :, :, 0]  # (N, n)
    s = np.sqrt(g0.S_inv[0, :, 0, 0])  # 1/√S_k
    # whitened H0 innovations (time-varying filter), (B, N)
    x = np.zeros((n, B))
    e = np.empty((B, N))
    for k in range(N):
        nu = y[:, k] - x[0]
        e[:, k] = nu * s[k]
        x = F0 @ (x + K[k][:, None] * nu[None, :])
    # regressors ψ of all 2C replicas: δ_{k+1} = F0 (I − K_k H) δ_k + e₂ g_k, ψ_k = H δ_k / √S_k
    z_cos, z_sin, zd_cos, zd_sin = replica_bank(chips, cands.mode, cands.tau, cands.f_c, vehicle.T, m_rho, N)
    g = np.concatenate([amplitude_column(vehicle, z_cos, zd_cos), amplitude_column(vehicle, z_sin, zd_sin)])
    psi = np.empty((2 * C, N))
    dlt = np.zeros((n, 2 * C))
    for k in range(N):
        phi = dlt[0].copy()
        psi[:, k] = phi * s[k]
        dlt = F0 @ (dlt - K[k][:, None] * phi[None, :])
        dlt[1] += g[:, k]
    bounds = np.concatenate([[0], np.sort(np.unique(hz))])
    b = np.zeros((2 * C, B))
    A = np.zeros(2 * C)
    bh: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    for lo, hi in itertools.pairwise(bounds):
        b = b + psi[:, lo:hi] @ e[:, lo:hi].T
        A = A + np.sum(psi[:, lo:hi] ** 2, axis=1)
        bh[int(hi)] = (b.copy(), A.copy())
    J0 = 0.5 * np.cumsum(e**2, axis=1)[:, hz - 1]
    if cfg.include_logdet:
        J0 = J0 + 0.5 * np.cumsum(g0.logdet_2pi_S[0])[hz - 1][None, :]
    gain = np.stack([0.5 * bh[int(n)][0] ** 2 / (1 / cfg.P0 + bh[int(n)][1][:, None]) for n in hz], axis=-1)
    J1 = J0[None] - gain
    Lam = gain[:C] + gain[C:]
    if cfg.include_logdet:
        ld = np.stack([0.5 * np.log1p(cfg.P0 * bh[int(n)][1]) for n in hz], axis=-1)[:, None, :]
        J1 = J1 + ld
        Lam = Lam - ld[:C] - ld[C:]
    return LMPResult(cands, hz, J0, J1[:C], J1[C:], Lam)
