"""The estimate-then-correlate mode detector: the suboptimal baseline that the mode-signature paper (47th IEEE CDC, Cancún, 2008, §I) replaces by its LMP test.

The paper describes its predecessor (Otanez and Campbell, *Mode estimation switching using perturbation
signatures for hybrid multi-vehicle systems*, AIAA GNC 2005) in one sentence: a Kalman filter estimates the
motion of the vehicle *and* the mode perturbation signature, and the estimate is then correlated with a
set of signature replicas. That paper's filter model and statistic are not available to us; the details
below are **assumed** from that sentence and the vehicle model the LMP detector uses.

The signature acts on the vehicle through the controller, u = K(−x + r + a [z, ż]ᵀ) (eq 54): it adds
the command perturbation e_k = a (k1 z_k + k2 ż_k) to the velocity row. The baseline filter estimates it as
one more state, with no knowledge of the code, phase or carrier::

    state [x, ẋ, r, ṙ, e]  (1-D)            [x, ẋ, y, ẏ, r_x, ṙ_x, r_y, ṙ_y, e_x, e_y]  (radar)
    ẋ_{k+1} = ẋ_k + T(−k1 x_k − k2 ẋ_k + k1 r_k + k2 ṙ_k) + T e_k      (eq 44 with a T e_k column)
    e_{k+1} = e_k + w^e_k,   w^e ~ N(0, q_e)                           (random walk) [A]

(the reference model and its Q are the LMP filters' own, eqs 56 and 61, so both detectors know the same).
The estimate to correlate is either ``"perturbation"`` (ê) or ``"command"`` (the whole estimated command
on top of the state feedback, k1 r̂ + k2 ṙ̂ + ê) [A: command]. The perturbation and the reference enter the
same row, so only their sum is observable: ê alone wanders between them and identifies no candidate
(measured: at most 1 % correct at every a_sig), and ``"perturbation"`` is kept only to show it. Write ĉ for
the estimate correlated. For every candidate c = (i, τ, f_c), with the candidate's command replicas
g_cos = k1 z_cos + k2 ż_cos and g_sin likewise (the replicas of eqs 2–3), and the estimate read ``lag``
samples later (e_k first reaches a position measurement at k + 2 [A]; a scan of lag 0–4 without the
detrending below, at a_sig = 0.05, R = 1e-3, 20 s, P_FA = 0.05, gave P_D 0.78, 0.89, 0.86, 0.80, 0.73 on 200
records, lags 1 and 2 equal within their SE of ≈ 0.025, and q_e × 0.1 or × 10 moved none of them by more)::

    ρ_cos(c, n) = Σ_{k < n−lag} ĉ_{k+lag} g_cos,k,   ρ_sin likewise
    Λ_b(c, n)   = (ρ_cos² + ρ_sin²) / E_c(n),   E_c(n) = ½ Σ_{k < n−lag} (g_cos,k² + g_sin,k²)
    (î, τ̂, f̂_c) = argmax_c Λ_b(c),  λ_b* = max_c Λ_b(c)         (the detection statistic, thresholded)

with ĉ first *detrended*: its moving average over ``detrend`` samples subtracted (default one carrier period,
1/(f_c T) samples, of the lowest carrier in the grid) [A]. The estimated command carries the nominal
reference's own command k1 r + k2 ṙ (amplitude k1 a_r ≈ 1600 at the defaults, against k1 a_sig ≈ 80), and its
slow variation leaks into every correlation. A command replica has zero mean over each chip (one
carrier cycle per chip at the defaults), so the moving average removes the slow part and leaves the
signature except next to chip flips. Measured (a_sig = 0.02, R = 1e-3, P_FA = 0.05, 200 + 400 records):
P_D 0.18 and 0.70 at 10 and 40 s without it, 0.995 and 1.0 with it (windows of 10 and 40 samples: 0.96–1.0).
This is the non-coherent (cos/sin quadrature) correlation, the unknown carrier phase θ removed as in the LMP's
pair of filters; on the radar the two axes' energies add. Under z = cos θ z_cos − sin θ z_sin (eqs 2–3)
a perfect estimate ĉ = e gives Λ_b ≈ a² E_c at the true candidate.

One filter serves every candidate (the LMP runs 2C + 1), so the baseline is cheap: the 1-D filter is linear
(one Riccati recursion, :func:`~motionsig_cli.filters.kalman.riccati`, shared by all records), the radar
filter a sigma-point filter (:func:`~motionsig_cli.filters.unscented.unscented_transform`) vectorised over
records. ``q_e`` None tunes the filter to the paper's amplitude ``a_nom`` = 0.5: q_e = a_nom² · mean (g_{k+1}
− g_k)² over the candidates' replicas, the mean-square step of the true perturbation [A]. Records with
missing samples are refused.

[A] = our assumption (the source of the baseline is not available; see above).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from scipy.ndimage import uniform_filter1d

from motionsig_cli.config import ConfigError, integer, one_of, positive
from motionsig_cli.detection.lmp import (
    Candidates,
    LMPConfig,
    candidate_grid,
    check_grid,
    check_variance,
    check_variances,
    checked_horizons,
    radar_records,
)
from motionsig_cli.filters.kalman import riccati, spd_inv_logdet
from motionsig_cli.filters.unscented import SigmaPointParams, unscented_transform
from motionsig_cli.models.radar import wrap_angle
from motionsig_cli.models.vehicle import Q0_DIAG, Vehicle1D, transition_h0
from motionsig_cli.models.vehicle2d import (
    IAX,
    IAY,
    IRX,
    IRXD,
    IRY,
    IRYD,
    IXD,
    IYD,
    Q0_2D,
    Vehicle2D,
    prior_mean_2d,
    range_bearing,
    transition_h1_2d_base,
)
from motionsig_cli.signals.signature import replica_bank

ESTIMATES = ("command", "perturbation")
A_NOM = 0.5  # the paper's signature amplitude: the default tuning of q_e


def _check_common(cfg: ECConfig | RadarECConfig) -> None:
    positive("c_r", cfg.c_r)
    if cfg.q_e is not None:
        check_variance("q_e", cfg.q_e)
    positive("a_nom", cfg.a_nom)
    positive("P0", cfg.P0)
    integer("lag", cfg.lag, 0)
    one_of("estimate", cfg.estimate, ESTIMATES)
    if cfg.detrend is not None:
        integer("detrend", cfg.detrend, 0)
    check_grid(cfg.tau_grid, cfg.fc_grid, False, cfg.zdot)


@dataclass(frozen=True, slots=True)
class ECConfig:
    """Settings of the 1-D estimate-then-correlate detector ([A] = assumed, see the module docstring).

    Attributes:
        c_r: Filter measurement covariance c_r · R (the LMP's default, 100).
        Q0: Per-step process noise of [x, ẋ, r, ṙ] (the LMP's eq 56).
        q_e: Per-step variance of the perturbation's random walk, finite and >= 0; None: matched to
            ``a_nom`` (module docstring) [A].
        a_nom: The amplitude the matched q_e assumes (> 0) [A: the paper's 0.5].
        P0: Prior covariance scale of [x, ẋ, r, ṙ] (the perturbation's prior variance is its matched
            variance a_nom² · mean g²) [A: 1].
        A_r: Reference random walk, ``"cv"`` or ``"identity"`` (as the LMP's).
        lag: Samples between a perturbation and the estimate it is read from (>= 0) [A: 2].
        estimate: ``"command"`` (k1 r̂ + k2 ṙ̂ + ê) or ``"perturbation"`` (ê) [A: command].
        detrend: Samples of the moving average subtracted from the estimate before the correlation (>= 1;
            1 subtracts the estimate itself: use 0 for none); None: one carrier period of the lowest
            positive carrier in ``fc_grid`` (none if every carrier is 0) [A].
        tau_grid, fc_grid, zdot: The candidates, as the LMP's (:class:`~motionsig_cli.detection.lmp.LMPConfig`).
    """

    c_r: float = 100.0
    Q0: tuple[float, float, float, float] = Q0_DIAG
    q_e: float | None = None
    a_nom: float = A_NOM
    P0: float = 1.0
    A_r: Literal["cv", "identity"] = "cv"
    lag: int = 2
    estimate: Literal["command", "perturbation"] = "command"
    detrend: int | None = None
    tau_grid: Literal["chips", "samples"] = "chips"
    fc_grid: tuple[float, ...] = (1.0,)
    zdot: Literal["analytic", "finite-difference"] = "analytic"

    def __post_init__(self) -> None:
        _check_common(self)
        check_variances("Q0", self.Q0, 4, "[x, xdot, r, rdot] (eq 56)")
        one_of("A_r", self.A_r, ("cv", "identity"))

    @property
    def as_grid(self) -> LMPConfig:
        return LMPConfig(tau_grid=self.tau_grid, fc_grid=self.fc_grid)


@dataclass(frozen=True, slots=True)
class RadarECConfig:
    """Settings of the radar estimate-then-correlate detector: as :class:`ECConfig`, with the LMP radar
    filter's H0 process noise (eq 61) for the 8 motion and reference states, and the sigma-point
    parameters of the LMP radar bank."""

    c_r: float = 100.0
    Q0: tuple[float, ...] = Q0_2D
    q_e: float | None = None
    a_nom: float = A_NOM
    P0: float = 1.0
    lag: int = 2
    estimate: Literal["command", "perturbation"] = "command"
    detrend: int | None = None
    tau_grid: Literal["chips", "samples"] = "chips"
    fc_grid: tuple[float, ...] = (1.0,)
    zdot: Literal["analytic", "finite-difference"] = "analytic"
    sigma: SigmaPointParams = field(default_factory=SigmaPointParams)

    def __post_init__(self) -> None:
        _check_common(self)
        check_variances("Q0", self.Q0, 8, "the states [x, xdot, y, ydot, r_x, rdot_x, r_y, rdot_y] (eq 61)")
        if not isinstance(self.sigma, SigmaPointParams):
            raise ConfigError("sigma", self.sigma, "is not a SigmaPointParams")
        self.sigma.weights(10)

    @property
    def as_grid(self) -> LMPConfig:
        return LMPConfig(tau_grid=self.tau_grid, fc_grid=self.fc_grid)


@dataclass(frozen=True)
class ECResult:
    """The correlation statistic per candidate, record and horizon.

    Attributes:
        candidates: The grid (as the LMP's).  horizons: Horizons in samples (H,).
        Lambda: Λ_b, (C, B, H).
        estimate: The estimate ĉ before detrending (B, N) (radar: (B, N, 2), x and y axes).
        q_e: The random-walk variance the filter used.
    """

    candidates: Candidates
    horizons: np.ndarray
    Lambda: np.ndarray
    estimate: np.ndarray
    q_e: float

    def best(self) -> tuple[np.ndarray, np.ndarray]:
        """argmax index and max value over candidates, each (B, H)."""
        return np.argmax(self.Lambda, axis=0), np.max(self.Lambda, axis=0)


def command_replicas(
    chips: np.ndarray, cands: Candidates, K: tuple[float, float], T: float, m_rho: int, n: int, zdot: str
) -> tuple[np.ndarray, np.ndarray]:
    """g_cos = k1 z_cos + k2 ż_cos and g_sin likewise (C, n): the command perturbation of a unit-amplitude
    signature of each candidate (eq 54)."""
    z_cos, z_sin, zd_cos, zd_sin = replica_bank(chips, cands.mode, cands.tau, cands.f_c, T, m_rho, n, zdot)  # type: ignore[arg-type]
    k1, k2 = K
    return k1 * z_cos + k2 * zd_cos, k1 * z_sin + k2 * zd_sin


def matched_q_e(g_cos: np.ndarray, g_sin: np.ndarray, a_nom: float) -> tuple[float, float]:
    """(q_e, σ_e²): the mean-square step and the mean square of a_nom · g over the replicas (both
    quadratures, so over the carrier phase)."""
    step = 0.5 * (np.mean(np.diff(g_cos, axis=1) ** 2) + np.mean(np.diff(g_sin, axis=1) ** 2))
    power = 0.5 * (np.mean(g_cos**2) + np.mean(g_sin**2))
    return float(a_nom**2 * step), float(a_nom**2 * power)


def correlate(est: np.ndarray, g_cos: np.ndarray, g_sin: np.ndarray, hz: np.ndarray, lag: int) -> np.ndarray:
    """Λ_b (C, B, H) of estimates ``est`` (B, N) or (B, N, A) (A axes, energies added) against the
    replicas (C, N), read at the horizons ``hz`` (samples; ρ sums k < n − lag)."""
    if est.ndim == 2:
        est = est[..., None]
    B, _, A = est.shape
    C = g_cos.shape[0]
    out = np.zeros((C, B, hz.size))
    gc2 = np.cumsum(0.5 * (g_cos**2 + g_sin**2), axis=1)  # (C, N)
    for j, n in enumerate(hz):
        m = int(n) - lag  # products ê_{k+lag} g_k, k < m
        if m < 1:
            continue
        for a in range(A):
            e = est[:, lag : lag + m, a]  # (B, m)
            rc = g_cos[:, :m] @ e.T  # (C, B)
            rs = g_sin[:, :m] @ e.T
            out[:, :, j] += rc**2 + rs**2
        out[:, :, j] /= gc2[:, m - 1][:, None]
    return out


def detrend_window(cfg: ECConfig | RadarECConfig, T: float) -> int:
    """The moving-average length of ``cfg.detrend`` (0: none)."""
    if cfg.detrend is not None:
        return cfg.detrend
    fcs = [f for f in cfg.fc_grid if f > 0]
    return max(1, round(1.0 / (min(fcs) * T))) if fcs else 0


def detrended(est: np.ndarray, window: int) -> np.ndarray:
    """``est`` (B, N, ...) minus its centred moving average over ``window`` samples (edges: the nearest
    sample repeated); ``window`` 0: unchanged."""
    if window == 0:
        return est
    return est - uniform_filter1d(est, window, axis=1, mode="nearest")


def _refuse_missing(y: np.ndarray) -> None:
    if np.isnan(y).any():
        raise ValueError("the estimate-then-correlate detector does not skip missing samples (NaN)")


def estimate_correlate_detect(
    y: np.ndarray,
    chips: np.ndarray,
    vehicle: Vehicle1D,
    m_rho: int,
    cfg: ECConfig,
    horizons: Sequence[int],
) -> ECResult:
    """The 1-D baseline on B position records at once (module docstring).

    Args:
        y: Position measurements (B, N) (or (N,)), no missing sample.
        chips: Bipolar codes (M, n_ρ).  vehicle: T, K, R the filter assumes (R_KF = c_r R).
        m_rho: Samples per chip.  cfg: Settings.  horizons: Horizons in samples.
    """
    y = np.atleast_2d(np.asarray(y, dtype=float))
    hz = checked_horizons(y, horizons)
    _refuse_missing(y)
    B, N = y.shape
    T, (k1, k2) = vehicle.T, vehicle.K
    cands = candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg.as_grid)
    g_cos, g_sin = command_replicas(chips, cands, vehicle.K, T, m_rho, N, cfg.zdot)
    q_match, var_e = matched_q_e(g_cos, g_sin, cfg.a_nom)
    q_e = q_match if cfg.q_e is None else cfg.q_e
    F = np.zeros((5, 5))
    F[:4, :4] = transition_h0(vehicle, cfg.A_r)
    F[1, 4] = T  # ẋ_{k+1} += T e_k (eq 44 with the perturbation as a state)
    F[4, 4] = 1.0  # random walk
    H = np.array([[1.0, 0.0, 0.0, 0.0, 0.0]])
    Q = np.diag([*cfg.Q0, q_e])
    P0 = np.diag([cfg.P0] * 4 + [var_e])
    gains = riccati(lambda k: F, H, Q, np.array([[cfg.c_r * vehicle.R]]), P0, N, 1)
    Kg = gains.K[0, :, :, 0]  # (N, 5)
    read = np.array([k1, k2, 1.0]) if cfg.estimate == "command" else np.array([0.0, 0.0, 1.0])
    x = np.zeros((5, B))
    est = np.empty((B, N))
    for k in range(N):
        x += Kg[k][:, None] * (y[:, k] - x[0])[None]  # update with ν_k = y_k − x̂_0
        est[:, k] = read @ x[2:]  # k1 r̂ + k2 ṙ̂ + ê, or ê
        x = F @ x  # predict
    lam = correlate(detrended(est, detrend_window(cfg, T)), g_cos, g_sin, hz, cfg.lag)
    return ECResult(cands, hz, lam, est, q_e)


def _rb(s: np.ndarray) -> np.ndarray:
    """Range and bearing (eq 60) of states (..., 10)."""
    return range_bearing(s, axis=-1)


def estimate_correlate_detect_radar(
    y: np.ndarray,
    chips: np.ndarray,
    vehicle: Vehicle2D,
    m_rho: int,
    cfg: RadarECConfig,
    horizons: Sequence[int],
) -> ECResult:
    """The radar baseline: one sigma-point filter per record (vectorised over records) on the 10-state
    model of the module docstring, range/bearing measurements (eq 60), the two axes' estimates
    correlated with the same replicas and their energies added.

    Args:
        y: Records [range, bearing] (B, N, 2) (or (N, 2)), no missing sample.
        chips, m_rho, horizons: As for :func:`estimate_correlate_detect`.
        vehicle: T, K, start, R_κ, R_χ the filter assumes.  cfg: Settings.
    """
    y = radar_records(y)
    hz = checked_horizons(y, horizons)
    _refuse_missing(y)
    B, N, _ = y.shape
    T, (k1, k2) = vehicle.T, vehicle.K
    cands = candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg.as_grid)
    g_cos, g_sin = command_replicas(chips, cands, vehicle.K, T, m_rho, N, cfg.zdot)
    q_match, var_e = matched_q_e(g_cos, g_sin, cfg.a_nom)
    q_e = q_match if cfg.q_e is None else cfg.q_e
    F = transition_h1_2d_base(T, vehicle.K)
    F[IXD, IAX] = F[IYD, IAY] = T  # ẋ, ẏ rows += T e (the perturbation as a state per axis)
    Q = np.diag([*cfg.Q0, q_e, q_e])
    R = cfg.c_r * np.diag([vehicle.R_range, vehicle.R_bearing])
    x = np.broadcast_to(prior_mean_2d(vehicle.start, True), (B, 10)).copy()
    P = np.broadcast_to(np.diag([cfg.P0] * 8 + [var_e, var_e]), (B, 10, 10)).copy()
    read = np.zeros((2, 10))  # rows: the x-axis and y-axis estimate
    if cfg.estimate == "command":
        read[0, [IRX, IRXD]] = read[1, [IRY, IRYD]] = (k1, k2)
    read[0, IAX] = read[1, IAY] = 1.0
    ang = (False, True)
    est = np.empty((B, N, 2))
    for k in range(N):
        y_hat, S, Pxy = unscented_transform(x, P, _rb, cfg.sigma, ang, R)
        S_inv, _, ok = spd_inv_logdet(S)
        if not ok.all():
            raise FloatingPointError(
                "the innovation covariance of the baseline filter is not positive definite"
            )
        nu = y[:, k] - y_hat
        nu[:, 1] = wrap_angle(nu[:, 1])  # bearing residual wrapped
        Kg = Pxy @ S_inv  # (B, 10, 2)
        x = x + (Kg @ nu[:, :, None])[..., 0]
        P = P - Kg @ S @ np.swapaxes(Kg, 1, 2)
        est[:, k] = x @ read.T
        x = x @ F.T
        P = F @ P @ F.T + Q
        P = 0.5 * (P + np.swapaxes(P, 1, 2))
    lam = correlate(detrended(est, detrend_window(cfg, T)), g_cos, g_sin, hz, cfg.lag)
    return ECResult(cands, hz, lam, est, q_e)
