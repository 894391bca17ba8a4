"""GLR and MLR maneuver detection with input estimation — eqs (1)–(6) and §III of Yao, Teng & Wu,
*Maneuvering Target Tracking Based on EBPSK Modulated JRC System* ("the paper"), made concrete and batched
over Monte Carlo runs.

A reference ("H0") Kalman filter runs on the input model x_{k+1} = F x_k + G u_k + w_k with the current input
estimate û_cur as a known input. A maneuver is a jump of the input: H1(u, n): u_j = û_cur + u for j ≥ n.

**Bias propagation.** Truth minus the H0 prediction has the mean M_j(n) u, with M_j(n) = 0 for j ≤ n and

    M_{j+1}(n) = F (I − K_j H) M_j(n) + G,                                   (bias propagation, §III)

so the H0 innovations have the mean E[ν_j] = Ψ_j(n) u, Ψ_j(n) = H M_j(n), for j ≥ n + 1.

**GLR.** With the information Σ(n)⁻¹ = Σ_j Ψ_jᵀ S_j⁻¹ Ψ_j and e(n) = Σ_j Ψ_jᵀ S_j⁻¹ ν_j over j = n+1..k, the
log-likelihood of H1(u, n) against H0 is the quadratic eᵀu − ½ uᵀΣ⁻¹u; its maximiser is the least-squares
input û(n) = Σ(n) e(n) and its maximum is ½ ΔJ(n) with

    ΔJ(n) = e(n)ᵀ Σ(n) e(n) = û(n)ᵀ Σ(n)⁻¹ û(n).                                     (eqs 3–4, corrected 5)

The paper's eq (5), −½ Σ ν*ᵀS⁻¹ν* + ½ΔJ, is the H1 log-likelihood up to constants, not the ratio. Onset
n̂ = argmax_n ΔJ(n) over n = k−s..k−1 (eq 3); detection iff ΔJ(n̂) > λ (§III step 3). Under H0 at a fixed n,
ΔJ ~ χ² with dim(u) degrees of freedom (λ = 13.8 is the 0.999 quantile of χ²₂).

**MLR** (eq 6) with the prior u ~ N(0, Σ_u):

    J(n) = ½ eᵀ (Σ⁻¹ + Σ_u⁻¹)⁻¹ e − ½ log det(I + Σ_u Σ⁻¹),                  (eq 6, Gaussian prior)

detection iff max_n J(n) > h (paper: h = 0); the input estimate is the posterior mean (Σ⁻¹ + Σ_u⁻¹)⁻¹ e with
covariance (Σ⁻¹ + Σ_u⁻¹)⁻¹.

**Correction on detection** (§III step 4) with the estimate û of covariance Σ_û at onset n̂:

* ``exact`` (default): the updated H0 estimate has the bias (I − K_k H) M_k(n̂) û and an error orthogonal to
  every innovation, hence to û − u, so x̂_{k|k} += (I − K_k H) M_k û, P_{k|k} += (I − K_k H) M_k Σ_û M_kᵀ (·)ᵀ;
* ``paper``: the paper's form, x̂_{k|k−1} += M_k û, P_{k|k−1} += M_k Σ_û M_kᵀ, then the update with z_k is
  redone (z_k enters both û and the update, so the covariance is slightly optimistic).

**Missed scans** (a NaN measurement: no detection, a gap in a record) are predict-only steps: ξ_{k|k} =
ξ_{k|k−1}, P_{k|k} = P_{k|k−1}, i.e. K_k = 0. The onset statistics follow from the same bias propagation with
K_k = 0. The truth minus the *updated* estimate at a missed scan keeps the bias M_k(n) u of the prediction
(nothing corrects it), so

    M_{k+1}(n) = F_ξ (I − K_k H_ξ) M_k(n) = F_ξ M_k(n)                          (missed scan k)

— the signature matrices still propagate — while scan k contributes no innovation: Σ(n)⁻¹ and e(n) are
sums over the *measured* scans j = n+1..k only (ΔJ(n) is still e(n)ᵀΣ(n)e(n) and stays χ²_p under H0 at a
fixed n, with as many terms as measured scans). The onset window counts scans, missed ones included (the
onsets tested at scan k are n = k−s..k−1 whatever was measured, except an onset with no measured scan after it
yet, which has no statistic), and no declaration is made at a missed scan (its statistics are those of the scan
before, less the onset that left the window). With every scan measured the recursion is the one above, bit for
bit.

**Continuation.** Later onsets are restricted to n ≥ the detection scan; the end of a maneuver is detected as
a new jump. The filter carries the current input u in its state (see :func:`input_tracker`); the correction
moves its mean by ≈ û and, with ``continuation="estimate"`` (default), gives it the covariance Σ_û, so later
scans refine it like any other state. ``continuation="known"`` is the paper's continuation (Willsky–Jones): û_cur += û
is then used as an exactly known input. That variant cannot undo an error of û except by a further
declaration; a false alarm on a short window (Σ_û of hundreds of m/s² at σ = 100 m) leaves a large wrong
acceleration in the model, and declarations cascade.

**Time-varying measurement covariance.** ``R`` (B, N, m, m) replaces the model's R with one covariance per run
and scan (e.g. a location step whose accuracy changes along the track): S_j = H P_{j|j−1} Hᵀ + R_j enters the
gains, the bias propagation and the statistics above unchanged in form. Entries at a missed scan are ignored.
With the model's single R the recursion is the one above, bit for bit.

**Irregular time.** With ``dt`` (each step's time since the step before), F, G and Q are those of the step:
F_ξ(Δt_k) = [[F(Δt_k), G(Δt_k)], [0, I]] (:attr:`InputModel.steps`), and the signature matrices propagate
with the same per-step transitions,

    M_{k+1}(n) = F_ξ(Δt_{k+1}) (I − K_k H_ξ) M_k(n),                                  (bias propagation, Δt_k)

because the truth minus the prediction obeys the same recursion as on a grid, only with the transition of
each step (the derivation of §III never uses F's constancy). A jump of u at onset n still enters at the
prediction after scan n, so M_{n+1}(n) = G(Δt_{n+1}). Δt_k = T at every step gives the recursion above to
rounding.

**Consistency** (``consistency``: :mod:`motionsig_cli.filters.consistency`): the H0 innovation's NIS gates
outliers (a gated measurement is a missed scan: no evidence for the detector either), the checks restart
a track from two points (its onset buffer emptied), and a declaration whose corrected input
|û_cur + û| exceeds the plausible acceleration is rejected (``rejected``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of
from motionsig_cli.filters.consistency import Consistency, Monitor
from motionsig_cli.filters.imm import scan_covariances
from motionsig_cli.filters.kalman import joseph_update, spd_inv_logdet
from motionsig_cli.models.motion import two_point_restart

__all__ = [
    "CHI2_2_999",
    "CONTINUATIONS",
    "CORRECTIONS",
    "METHODS",
    "SIGMA_U_RANGE",
    "WINDOW_RANGE",
    "GLRConfig",
    "InputModel",
    "InputTrack",
    "input_tracker",
]

METHODS = ("glr", "mlr", "none")
CORRECTIONS = ("exact", "paper")
CONTINUATIONS = ("estimate", "known")
CHI2_2_999 = -2.0 * math.log(1e-3)
"""0.999 quantile of χ²₂ (= 13.8155…): the default GLR threshold λ."""
WINDOW_RANGE = (1, 200)
"""Onset windows s accepted [scans]."""
SIGMA_U_RANGE = (1e-3, 1e6)
"""MLR prior standard deviations σ_u accepted [m/s²]."""


@dataclass(frozen=True)
class InputModel:
    """Linear model with an additive input, x_{k+1} = F x_k + G u_k + w_k, z_k = H x_k + v_k.

    ``steps``: None (one period), or F, G, Q as functions of the step: ``steps(dt)`` for an array of Δt of
    shape S gives (F (S, n, n), G (S, n, p), Q (S, n, n)), e.g.
    :func:`~motionsig_cli.models.motion.cv_input_steps` (irregular times: module docstring).
    """

    F: np.ndarray
    G: np.ndarray
    Q: np.ndarray
    H: np.ndarray
    R: np.ndarray
    steps: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]] | None = None

    def __post_init__(self) -> None:
        F, G, Q, H, R = (np.asarray(a, float) for a in (self.F, self.G, self.Q, self.H, self.R))
        n = F.shape[0] if F.ndim == 2 else -1
        m = H.shape[0] if H.ndim == 2 else -1
        shapes = {"F": F.shape == (n, n), "G": G.ndim == 2 and G.shape[0] == n, "Q": Q.shape == (n, n),
                  "H": H.ndim == 2 and H.shape[1] == n, "R": R.shape == (m, m)}  # fmt: skip
        for name, a in (("F", F), ("G", G), ("Q", Q), ("H", H), ("R", R)):
            if not shapes[name]:
                raise ConfigError(name, a.tolist(), f"has the shape {a.shape}, inconsistent with the others")
            if not np.all(np.isfinite(a)):
                raise ConfigError(name, a.tolist(), "has non-finite entries")
        if np.min(np.linalg.eigvalsh(0.5 * (R + R.T))) <= 0:
            raise ConfigError("R", R.tolist(), "is not positive definite")
        for k, v in (("F", F), ("G", G), ("Q", Q), ("H", H), ("R", R)):
            object.__setattr__(self, k, v)


@dataclass(frozen=True)
class GLRConfig:
    """Detector settings (the paper's values where it gives them).

    Attributes:
        method: ``glr``, ``mlr`` or ``none`` (the plain reference Kalman filter, never detecting).
        window: s, onsets n = k−s..k−1 are tested at scan k; in :data:`WINDOW_RANGE` (the ring buffer holds
            s onsets per run; 200 scans is longer than any maneuver onset worth locating).
        threshold: λ for the GLR (on ΔJ: a number ≥ 0, since ΔJ is never negative) or h for the MLR (on
            J_MLR, a log-likelihood ratio: any number); ``inf`` never declares (the statistics alone).
            Ignored by ``none``.
        sigma_u: MLR prior standard deviation of each input component [m/s²], in :data:`SIGMA_U_RANGE`
            (1 mm/s² is a prior that rules maneuvers out; 1e6 m/s² is flat for any vehicle, and σ_u² stays
            a normal double).
        correction: ``exact`` or ``paper`` (see the module docstring).
        continuation: ``estimate`` (the input estimate keeps its covariance and is refined by later scans) or
            ``known`` (the paper's continuation: the accumulated estimate is used as an exactly known input).
    """

    method: str = "glr"
    window: int = 10
    threshold: float = CHI2_2_999
    sigma_u: float = 20.0
    correction: str = "exact"
    continuation: str = "estimate"

    def __post_init__(self) -> None:
        one_of("method", self.method, METHODS)
        one_of("correction", self.correction, CORRECTIONS)
        one_of("continuation", self.continuation, CONTINUATIONS)
        integer("window", self.window, *WINDOW_RANGE)
        thr = self.threshold
        if not isinstance(thr, int | float) or math.isnan(thr) or thr == -math.inf:
            raise ConfigError("threshold", thr, "is not a number (inf never declares)")
        if self.method == "glr" and thr < 0:
            raise ConfigError("threshold", thr, "is not a number >= 0 (ΔJ is never negative)")
        in_range("sigma_u", self.sigma_u, *SIGMA_U_RANGE, unit="m/s²")


@dataclass(frozen=True)
class InputTrack:
    """Tracker output for B runs over N scans (index k = 0..N−1 of the processed record).

    Attributes:
        x, P: (B, N, n), (B, N, n, n) corrected updated estimates (P only when kept).
        stat: (B, N) max_n ΔJ(n) (GLR) or max_n J_MLR(n) (MLR); −inf before any onset can be tested.
        dJ: (B, N, s) ΔJ(n) for the onset n = k − 1 − d in column d (NaN where n is not testable).
        score: (B, N, s) the detector's statistic per onset, same layout: ΔJ(n) (GLR) or J_MLR(n) (MLR).
        detected: (B, N) a maneuver was declared at scan k.
        onset: (B, N) the estimated onset n̂ of a declared maneuver (−1 elsewhere).
        u_jump: (B, N, p) the estimated input jump û at a declaration (0 elsewhere).
        u_cur: (B, N, p) the input used in the prediction from k to k+1.
        nis, gated, reinit, rejected: (B, N) with ``consistency``: the H0 innovation's NIS (NaN where not
            measured), the validation gate's rejections, the restarts' reason codes
            (:data:`~motionsig_cli.filters.consistency.REASONS`) and the declarations rejected as implausible;
            None without.
    """

    x: np.ndarray
    P: np.ndarray | None
    stat: np.ndarray
    dJ: np.ndarray
    score: np.ndarray
    detected: np.ndarray
    onset: np.ndarray
    u_jump: np.ndarray
    u_cur: np.ndarray
    nis: np.ndarray | None = None
    gated: np.ndarray | None = None
    reinit: np.ndarray | None = None
    rejected: np.ndarray | None = None


def _quad(e: np.ndarray, A: np.ndarray) -> np.ndarray:
    """eᵀ A e over leading axes."""
    return np.einsum("...i,...ij,...j->...", e, A, e)


def input_tracker(
    z: np.ndarray,
    model: InputModel,
    x0: np.ndarray,
    P0: np.ndarray,
    cfg: GLRConfig,
    *,
    keep_P: bool = False,
    R: np.ndarray | None = None,
    dt: np.ndarray | None = None,
    consistency: Consistency | None = None,
) -> InputTrack:
    """Track with GLR or MLR maneuver detection, state correction and continuation.

    The filter runs on the state augmented with the current input, ξ = [x; u] (n + p), with
    F_ξ = [[F, G], [0, I]], H_ξ = [H, 0] and no process noise on u; u starts known (= 0, zero variance), so
    until the first declaration this is exactly the H0 filter with no input. A jump of u at onset n enters the
    u block at the prediction of scan n: M_n(n) = [0; I], M_{j+1}(n) = F_ξ (I − K_j H_ξ) M_j(n) — the
    x block of which is the bias propagation of the module docstring (M_{n+1}(n) = G).

    Args:
        z: (B, N, m) measurements of the scans to process; a NaN (in any component) makes that run's scan a
            missed scan, a predict-only step (module docstring); ±inf is refused.
        model: the input model (F, G, Q, H, R).
        x0: (B, n) or (n,) updated estimate at the scan before z[:, 0]; P0: (n, n) or (B, n, n).
        cfg: method, window, threshold, MLR prior, correction, continuation.
        keep_P: also return the covariance of every scan.
        R: (B, N, m, m) measurement covariance per run and scan, in place of ``model.R`` (module docstring);
            None: ``model.R`` for every scan.
        dt: (B, N) or (N,) each step's time since the step before [s] (> 0), with ``model.steps``; None: the
            model's one period.
        consistency: the checks of :mod:`motionsig_cli.filters.consistency` (None: unwatched; needs ``dt``).
    """
    z = np.asarray(z, float)
    if z.ndim != 3:
        raise ValueError(f"z must be (runs, scans, m); got shape {z.shape}")
    measured = ~np.any(np.isnan(z), axis=-1)  # (B, N): a NaN anywhere in z_k is a missed scan
    if np.any(np.isinf(z)):
        raise ValueError("measurements must be finite (NaN: a missed scan)")
    every = bool(measured.all())
    if not every:
        z = np.where(measured[..., None], z, 0.0)  # any finite value: the update is discarded there
    B, N, m = z.shape
    n, p = model.G.shape
    if model.H.shape[0] != m:
        raise ValueError(f"measurements have dimension {m}, H has {model.H.shape[0]} rows")
    na = n + p
    F = np.block([[model.F, model.G], [np.zeros((p, n)), np.eye(p)]])  # F_ξ
    Q = np.zeros((na, na))
    Q[:n, :n] = model.Q
    H = np.hstack([model.H, np.zeros((m, p))])  # H_ξ
    varying = R is not None
    if R is None:
        R = model.R
    elif np.shape(R) != (B, N, m, m):
        raise ValueError(f"R must be ({B}, {N}, {m}, {m}); got {np.shape(R)}")
    else:
        R = scan_covariances(R, measured)
    s = cfg.window
    eye = np.eye(na)
    Su_inv = np.eye(p) / cfg.sigma_u**2
    x = np.zeros((B, na))
    x[:, :n] = np.broadcast_to(np.asarray(x0, float), (B, n))
    P = np.zeros((B, na, na))
    P[:, :n, :n] = np.broadcast_to(np.asarray(P0, float), (B, n, n))
    jump_in = np.zeros((na, p))
    jump_in[n:] = np.eye(p)  # M_n(n) = [0; I]
    # ring buffer over onsets: slot n mod s holds M_k(n), Σ(n)⁻¹ and e(n)
    M = np.zeros((B, s, na, p))
    info = np.zeros((B, s, p, p))
    e = np.zeros((B, s, p))
    onset_of = np.full((B, s), -1, dtype=np.int64)  # onset held by each slot (−1: empty)
    fed = np.zeros((B, s), dtype=bool)  # the slot's onset has a measured scan after it (testable)
    out_x = np.empty((B, N, n))
    out_P = np.empty((B, N, n, n)) if keep_P else None
    out_stat = np.full((B, N), -np.inf)
    out_dJ = np.full((B, N, s), np.nan)
    out_score = np.full((B, N, s), np.nan)
    out_det = np.zeros((B, N), dtype=bool)
    out_onset = np.full((B, N), -1, dtype=np.int64)
    out_jump = np.zeros((B, N, p))
    out_ucur = np.zeros((B, N, p))
    rows = np.arange(B)
    detecting = cfg.method != "none"
    if dt is not None:
        dt = np.broadcast_to(np.asarray(dt, float), (B, N))
        if not np.all(dt > 0):
            raise ValueError("dt must be > 0 at every step [s]")
        if model.steps is None:
            raise ValueError(
                "this input model has one period (no steps): irregular times need InputModel.steps"
            )
        Fs = np.zeros((B, na, na))
        Fs[:, n:, n:] = np.eye(p)
        Qs = np.zeros((B, na, na))
    mon = Monitor(consistency, B, N, m) if consistency is not None else None
    if mon is not None:
        if dt is None:
            raise ValueError("consistency needs dt (a restart's velocity is a difference over time)")
        pos = np.flatnonzero(np.any(model.H != 0, axis=0))  # the measured state components
        P0b = np.broadcast_to(np.asarray(P0, float), (B, n, n))
        z_last = x[:, pos].copy()
        R_last = P0b[:, pos][:, :, pos].copy()  # the initial position covariance (R of z_b)
        since = np.zeros(B)
        rejected = np.zeros((B, N), dtype=bool)

    def start(b: np.ndarray, x_new: np.ndarray, P_new: np.ndarray) -> None:
        """Tracks b start afresh from (x_new, P_new): no input, an empty onset buffer."""
        x[b] = 0.0
        x[b, :n] = x_new
        P[b] = 0.0
        P[b, :n, :n] = P_new
        if detecting:
            onset_of[b] = -1
            M[b], info[b], e[b], fed[b] = 0.0, 0.0, 0.0, False

    for k in range(N):
        if dt is not None:  # F_ξ(Δt_k), Q(Δt_k)
            assert model.steps is not None
            Fk, Gk, Qk = model.steps(dt[:, k])
            Fs[:, :n, :n], Fs[:, :n, n:], Qs[:, :n, :n] = Fk, Gk, Qk
            F, Q = Fs, Qs
            xp = np.einsum("bij,bj->bi", F, x)
            Pp = F @ P @ np.swapaxes(F, -1, -2) + Q
        else:
            xp = (
                x @ F.T
            )  # ξ_{k|k−1} = F_ξ ξ_{k−1|k−1}: x̂ = F x̂ + G û, the current input estimate as the input
            Pp = F @ P @ F.T + Q
        Pp = 0.5 * (Pp + np.swapaxes(Pp, -1, -2))
        Rk = R[:, k] if varying else R
        up = joseph_update(xp, Pp, z[:, k], H, Rk)
        seen = None if every else measured[:, k]  # (B,) runs measured at scan k (None: all of them)
        if mon is not None:
            Sk = H @ Pp @ H.T + Rk
            seen = mon.screen(k, measured[:, k], up.nis, up.nu, Sk, since + dt[:, k])  # C1: gated = missed
        if seen is not None and seen.all():
            seen = None
        if seen is None:
            x, P, K, S_inv, nu = up.x, up.P, up.K, up.S_inv, up.nu
        else:  # predict-only where missed: K_k = 0, no innovation
            x = np.where(seen[:, None], up.x, xp)
            P = np.where(seen[:, None, None], up.P, Pp)
            K = np.where(seen[:, None, None], up.K, 0.0)
            S_inv = np.where(seen[:, None, None], up.S_inv, 0.0)  # a zero weight: Ψᵀ S⁻¹ (·) adds nothing
            nu = np.where(seen[:, None], up.nu, 0.0)
        if detecting:
            fed |= True if seen is None else seen[:, None]
            valid = (onset_of >= 0) & fed  # (B, s): onsets n = k−s..k−1 with an innovation after them
            Psi = H @ M  # Ψ_k(n) = H M_k(n), (B, s, m, p)
            PsiT_Sinv = np.swapaxes(Psi, -1, -2) @ S_inv[:, None]  # Ψᵀ S⁻¹, (B, s, p, m)
            info += PsiT_Sinv @ Psi  # Σ(n)⁻¹ += Ψ_kᵀ S_k⁻¹ Ψ_k (measured scans only)
            e += (PsiT_Sinv @ nu[:, None, :, None])[..., 0]  # e(n) += Ψ_kᵀ S_k⁻¹ ν_k
            if valid.any():
                with np.errstate(divide="ignore", invalid="ignore"):
                    Sigma, _, _ = spd_inv_logdet(info)  # Σ(n) = MSE of û(n); NaN in empty slots
                    dJ = _quad(e, Sigma)  # ΔJ(n) = eᵀ Σ e, eq (5) corrected
                    if cfg.method == "glr":
                        score = dJ
                    else:  # MLR: ½ eᵀ(Σ⁻¹ + Σ_u⁻¹)⁻¹e − ½ log det(I + Σ_u Σ⁻¹)
                        post, logdet_post, _ = spd_inv_logdet(info + Su_inv)  # (Σ⁻¹ + Σ_u⁻¹)⁻¹
                        # det(I + Σ_u Σ⁻¹) = det(Σ_u) det(Σ⁻¹ + Σ_u⁻¹)
                        score = 0.5 * _quad(e, post) - 0.5 * (logdet_post + p * math.log(cfg.sigma_u**2))
                score = np.where(valid & np.isfinite(score), score, -np.inf)  # a NaN would win argmax
                best = np.argmax(score, axis=1)  # n̂ = argmax_n, eq (3)
                stat = score[rows, best]
                out_stat[:, k] = stat
                bi, si = np.nonzero(valid)
                out_dJ[bi, k, k - 1 - onset_of[bi, si]] = dJ[bi, si]  # column d: onset k − 1 − d
                out_score[bi, k, k - 1 - onset_of[bi, si]] = score[bi, si]
                hit = np.isfinite(stat) & (stat > cfg.threshold)
                if seen is not None:
                    hit &= seen  # no new evidence at a missed scan: no declaration
                if mon is not None and np.any(hit):  # C4: an implausible corrected input is rejected
                    hb = np.flatnonzero(hit)
                    cov_h = Sigma[hb, best[hb]] if cfg.method == "glr" else post[hb, best[hb]]
                    u_h = (cov_h @ e[hb, best[hb]][..., None])[..., 0]
                    wild = ~(np.linalg.norm(x[hb, n:] + u_h, axis=-1) <= mon.cfg.max_accel)
                    rejected[hb[wild], k] = True
                    hit[hb[wild]] = False
                if np.any(hit):
                    b = np.flatnonzero(hit)
                    Mb = M[b, best[b]]  # M_k(n̂), (b, n + p, p)
                    cov_u = Sigma[b, best[b]] if cfg.method == "glr" else post[b, best[b]]
                    u_hat = (cov_u @ e[b, best[b]][..., None])[..., 0]  # û = Σ e (GLR) or the posterior mean
                    if cfg.correction == "exact":
                        A = (eye - K[b] @ H) @ Mb  # bias of the updated estimate per unit input
                        xb = x[b] + (A @ u_hat[..., None])[..., 0]
                        Pb = P[b] + A @ cov_u @ np.swapaxes(A, -1, -2)
                    else:  # the paper's step 4: correct the prediction, redo the update with z_k
                        Pb = Pp[b] + Mb @ cov_u @ np.swapaxes(Mb, -1, -2)
                        redo = joseph_update(xp[b] + (Mb @ u_hat[..., None])[..., 0],
                                             0.5 * (Pb + np.swapaxes(Pb, -1, -2)), z[b, k], H,
                                             Rk[b] if varying else Rk)  # fmt: skip
                        xb, Pb = redo.x, redo.P
                    if cfg.continuation == "known":  # the paper's continuation: û_cur is then a known input
                        Pb[:, n:, :] = 0.0
                        Pb[:, :, n:] = 0.0
                    x[b] = xb
                    P[b] = 0.5 * (Pb + np.swapaxes(Pb, -1, -2))
                    out_det[b, k] = True
                    out_onset[b, k] = onset_of[b, best[b]]
                    out_jump[b, k] = u_hat
                    onset_of[b] = -1  # later onsets n ≥ k only
            # open the slot of onset n = k (M_k(k) = [0; I]: ν_k is unaffected) and propagate every slot:
            # M_{k+1}(n) = F_ξ (I − K_k H_ξ) M_k(n)
            slot = k % s
            M[:, slot] = jump_in
            info[:, slot] = 0.0
            e[:, slot] = 0.0
            onset_of[:, slot] = k
            fed[:, slot] = False
            M = (F @ (eye - K @ H))[:, None] @ M  # = F_ξ M_k(n) at a missed scan (K_k = 0)
        if mon is not None:
            since = since + dt[:, k]
            Pd = np.diagonal(P, axis1=-2, axis2=-1)[:, pos]
            bad = mon.verdict(k, np.linalg.norm(x[:, pos + 1], axis=-1), np.linalg.norm(x[:, n:], axis=-1),
                              Pd.max(axis=-1), np.isfinite(P).all(axis=(1, 2)))  # fmt: skip
            # restart from the current measurement where it was accepted, or where outliers ran out (C2)
            restart = bad & ((measured[:, k] if seen is None else seen) | (mon.reason[:, k] == 1))
            if restart.any():  # a two-point restart; the onset buffer is emptied
                b = np.flatnonzero(restart)
                Rb = R[b, k] if varying else np.broadcast_to(R, (b.size, m, m))
                start(b, *mon.cfg.restart(*two_point_restart(z_last[b], z[b, k], since[b], R_last[b], Rb, n=n)))
                mon.reset(restart)
            coast = bad & ~restart
            if coast.any():  # no measurement to restart from: keep the position, forget the motion and input
                b = np.flatnonzero(coast)
                start(b, *mon.cfg.coast(x[b, :n], P[b, :n, :n]))
                mon.reset(coast)
            took = (measured[:, k] if seen is None else seen) | restart
            z_last[took] = z[took, k]
            if varying:
                R_last[took] = R[took, k]
            since[took] = 0.0
        out_x[:, k] = x[:, :n]
        if out_P is not None:
            out_P[:, k] = P[:, :n, :n]
        out_ucur[:, k] = x[:, n:]
    if mon is not None:
        return InputTrack(out_x, out_P, out_stat, out_dJ, out_score, out_det, out_onset, out_jump, out_ucur,
                          mon.nis, mon.gated, mon.reason, rejected)  # fmt: skip
    return InputTrack(out_x, out_P, out_stat, out_dJ, out_score, out_det, out_onset, out_jump, out_ucur)
