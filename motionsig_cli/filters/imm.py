"""Interacting multiple model (IMM) filter, batched over Monte Carlo runs — eqs (7)–(13) of Yao, Teng & Wu,
*Maneuvering Target Tracking Based on EBPSK Modulated JRC System* ("the paper"), corrected.

One cycle (§IV), for every run b and model j at once (the only loop is over scans):

1. predicted model probabilities  c̄_j = Σ_i p_ij μ_i(k−1);
2. mixing probabilities           μ_{i|j} = p_ij μ_i(k−1) / c̄_j   (the paper prints a spurious Σ_i);
3. mixing, eqs (9)–(10)           X̂_0j = Σ_i μ_{i|j} X̂_i,  P_0j = Σ_i μ_{i|j} [P_i + (X̂_i − X̂_0j)(·)ᵀ];
4. model-matched Kalman filters   X̂_j(k|k−1) = Φ_j X̂_0j,  P_j(k|k−1) = Φ_j P_0j Φ_jᵀ + G_j Q_j G_jᵀ,
                                  Joseph-form update with Z(k);
5. likelihoods, eq (11)           log Λ_j = log N(v_j; 0, S_j);
6. model probabilities            μ_j(k) = Λ_j c̄_j / Σ_l Λ_l c̄_l;
7. output, eqs (12)–(13)          X̂ = Σ_j μ_j X̂_j,  P = Σ_j μ_j [P_j + (X̂_j − X̂)(·)ᵀ]  (eq 13 as printed
                                  reuses the mixing weights μ_ij and P_0j; it is the combined covariance).

**Missed scans** (a NaN measurement) are predict-only: steps 1–4 run (mixing and model-matched
prediction), the update is skipped (X̂_j(k|k) = X̂_j(k|k−1), P_j(k|k) = P_j(k|k−1)), and every model gets the
likelihood Λ_j = 1 (log Λ_j = 0), so step 6 gives μ_j(k) = c̄_j: the model probabilities are propagated by
the Markov chain alone. Runs are independent: each run's missed scans are its own (vectorised with a mask),
and with every scan measured the recursion is the one above, bit for bit.

**Time-varying measurement covariance.** R may be one (m, m) matrix shared by every run and scan, or one per run
and scan, (B, N, m, m) — e.g. the covariance of a location step whose accuracy changes along the track (eq (8)
with R(k), eq (11) with S_j(k) = H P_j(k|k−1) Hᵀ + R(k)). Entries of R at a missed scan are ignored (they may be
NaN). With a single (m, m) R the recursion is the one above, bit for bit.

**Irregular time.** With ``dt`` (the time of each step since the one before, per run), every step uses
the model set at its own Δt (:attr:`~motionsig_cli.models.motion.ModelSet.steps`): Φ_j(Δt_k), the process
noise of Δt_k and Π(Δt_k) in steps 1–4. With Δt_k = T at every step the recursion is the one above, bit for
bit.

**Consistency** (``consistency``: :mod:`motionsig_cli.filters.consistency`). The IMM's innovation is that of
the combined prediction, ν = z − H x̄, S = H P̄ Hᵀ + R with x̄ = Σ_j c̄_j X̂_j(k|k−1) and P̄ = Σ_j c̄_j [P_j(k|k−1)
+ (X̂_j − x̄)(·)ᵀ]; a gated measurement makes the step predict-only (as a missed scan), and a track that
fails a check restarts from two points with μ = μ₀.

Steps 1, 2 and 6 run in the log domain (log-sum-exp), so a model whose likelihood underflows a double
keeps a finite log-probability and the probabilities never become 0/0. A model with c̄_j = 0 (unreachable,
e.g. switched off with p_ij = 0 and μ_j = 0) gets the mixing weights μ_{i|j} = μ_i: its estimate stays
finite and enters the output with weight exactly 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motionsig_cli.filters.consistency import Consistency, Monitor
from motionsig_cli.filters.kalman import joseph_update, spd_inv_logdet
from motionsig_cli.models.motion import ModelSet, two_point_restart

__all__ = ["IMMTrack", "imm_filter", "logsumexp", "scan_covariances"]


def logsumexp(a: np.ndarray, axis: int) -> np.ndarray:
    """log Σ exp(a) along ``axis``; −inf when every term is −inf (never NaN)."""
    m = np.max(a, axis=axis, keepdims=True)
    m_safe = np.where(np.isfinite(m), m, 0.0)
    with np.errstate(divide="ignore"):
        out = np.log(np.sum(np.exp(a - m_safe), axis=axis, keepdims=True)) + m_safe
    return np.squeeze(out, axis=axis)


def scan_covariances(R: np.ndarray, measured: np.ndarray) -> np.ndarray:
    """Per-scan measurement covariances (B, N, m, m) checked where measured (finite, symmetric, positive
    definite; ValueError otherwise) and replaced by I at the missed scans (their update is discarded)."""
    R = np.asarray(R, float)
    mask = np.asarray(measured, bool)
    if R.ndim != 4 or R.shape[:2] != mask.shape or R.shape[2] != R.shape[3]:
        raise ValueError(f"R must be (runs, scans, m, m) matching the measurements; got {R.shape}")
    Rm = R[mask]
    if Rm.size:
        if not np.all(np.isfinite(Rm)):
            raise ValueError("R must be finite at every measured scan")
        if np.any(
            np.abs(Rm - np.swapaxes(Rm, -1, -2)) > 1e-9 * (np.abs(Rm).max(axis=(-1, -2))[:, None, None])
        ):
            raise ValueError("R must be symmetric at every measured scan")
        if np.any(np.linalg.eigvalsh(Rm)[:, 0] <= 0):
            raise ValueError("R must be positive definite at every measured scan")
    if mask.all():
        return R
    return np.where(mask[..., None, None], R, np.eye(R.shape[-1]))


@dataclass(frozen=True)
class IMMTrack:
    """IMM output for B runs over N scans.

    Attributes:
        x: (B, N, n) combined estimates X̂(k|k), eq (12).
        P: (B, N, n, n) combined covariances (eq 13 corrected), or None when not kept.
        log_mu: (B, N, r) log model probabilities log μ_j(k).
        loglik: (B, N, r) model-conditioned innovation log-likelihoods log Λ_j(k), eq (11); 0 at a missed
            scan (likelihood 1 for every model).
        nis, gated, reinit: (B, N) with ``consistency``: the combined prediction's normalised innovation
            squared (NaN where not measured), the validation gate's rejections, and the re-initialisations'
            reason codes (:data:`~motionsig_cli.filters.consistency.REASONS`); None without.
    """

    x: np.ndarray
    P: np.ndarray | None
    log_mu: np.ndarray
    loglik: np.ndarray
    nis: np.ndarray | None = None
    gated: np.ndarray | None = None
    reinit: np.ndarray | None = None

    @property
    def mu(self) -> np.ndarray:
        """Model probabilities μ_j(k), (B, N, r)."""
        return np.exp(self.log_mu)


def _weighted(c: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Σ_j c_j X_j: (B, r) weights of (B, r, n) vectors, (B, n)."""
    return (c[:, None, :] @ X)[:, 0]


def _spread(c: np.ndarray, P: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Σ_j c_j [P_j + d_j d_jᵀ]: the covariance of a mixture, from (B, r) weights, (B, r, n, n) covariances and
    (B, r, n) deviations from its mean (eq 13), (B, n, n)."""
    B, r, n = d.shape
    return (c[:, None, :] @ P.reshape(B, r, n * n)).reshape(B, n, n) + np.swapaxes(d * c[..., None], 1, 2) @ d


def imm_filter(
    z: np.ndarray,
    H: np.ndarray,
    R: np.ndarray,
    models: ModelSet,
    x0: np.ndarray,
    P0: np.ndarray,
    *,
    keep_P: bool = False,
    dt: np.ndarray | None = None,
    consistency: Consistency | None = None,
) -> IMMTrack:
    """Run the IMM over measurement records.

    Args:
        z: (B, N, m) measurements of the scans to process (the first is the scan after initialisation), or
            (N, m) one record (the outputs then have no batch axis); a NaN (in any component) makes that run's
            scan a missed scan, a predict-only step (module docstring).
        H: (m, n) measurement matrix; R: a number r (R = r I), an (m, m) measurement noise covariance, or
            (B, N, m, m) (one record: (N, m, m)): one per run and scan (symmetric positive definite where
            measured; ignored, and may be NaN, at a missed scan).
        models: the r models, transition matrix and initial probabilities (μ at the initialisation scan).
        x0: (B, n) or (n,) initial estimate, shared by every model-conditioned filter (§IV).
        P0: (n, n) or (B, n, n) initial covariance.
        keep_P: also return the combined covariance of every scan.
        dt: (B, N) or (N,) the time of each step since the step before [s] (the first: since the
            initialisation), > 0; uses ``models.steps`` (module docstring). None: the model set's one period.
        consistency: the checks of :mod:`motionsig_cli.filters.consistency` (None: unwatched).

    Returns:
        The combined estimates, model probabilities and likelihoods of every scan.

    Examples:
        The paper's three models (§IV) on a straight track, σ = 10 m, initialised on its first two scans:

        >>> import numpy as np
        >>> from motionsig_cli import imm_filter, imm_models, two_point_init
        >>> from motionsig_cli.models.motion import H_POS6
        >>> z = np.stack([100.0 * np.arange(30), np.zeros(30)], axis=1)  # 100 m/s east, T = 1 s
        >>> x0, P0 = two_point_init(z[0], z[1], T=1.0, sigma=10.0)
        >>> tr = imm_filter(z[2:], H_POS6, 10.0**2, imm_models(1.0), x0, P0)
        >>> tr.x.shape, tr.mu.shape
        ((28, 6), (28, 3))
        >>> round(float(tr.x[-1, 1]), 6)  # ẋ [m/s]
        100.0
    """
    z = np.asarray(z, dtype=float)
    if z.ndim == 2:  # one record (N, m): run it as a batch of one and drop the batch axis
        one = imm_filter(
            z[None], H, np.asarray(R)[None] if np.ndim(R) == 3 else R, models, x0, P0, keep_P=keep_P,
            dt=None if dt is None else np.asarray(dt, float)[None], consistency=consistency,
        )  # fmt: skip

        def first(a: np.ndarray | None) -> np.ndarray | None:
            return None if a is None else a[0]

        return IMMTrack(one.x[0], first(one.P), one.log_mu[0], one.loglik[0], first(one.nis),
                        first(one.gated), first(one.reinit))  # fmt: skip
    if z.ndim != 3:
        raise ValueError(f"z must be (scans, m) or (runs, scans, m); got shape {z.shape}")
    B, N, m = z.shape
    H, R = np.asarray(H, float), np.asarray(R, float)
    if R.ndim == 0:  # a variance per component: R I
        R = float(R) * np.eye(m)
    r, n = models.r, models.n
    varying = R.ndim == 4
    if H.shape != (m, n) or R.shape not in ((m, m), (B, N, m, m)):
        raise ValueError(
            f"H must be ({m}, {n}) and R ({m}, {m}) or ({B}, {N}, {m}, {m}); got {H.shape} and {R.shape}"
        )
    measured = ~np.any(np.isnan(z), axis=-1)  # (B, N)
    if np.any(np.isinf(z)):
        raise ValueError("measurements must be finite (NaN: a missed scan)")
    every = bool(measured.all())
    if not every:
        z = np.where(measured[..., None], z, 0.0)  # any finite value: the update is discarded there
    if varying:
        R = scan_covariances(R, measured)
    steps = None
    if dt is not None:
        dt = np.broadcast_to(np.asarray(dt, float), (B, N))
        if not np.all(dt > 0):
            raise ValueError("dt must be > 0 at every step [s]")
        if models.steps is None:
            raise ValueError("this model set has one period (no steps): irregular times need ModelSet.steps")
        steps = models.steps
    Phi, Qd = models.Phi, models.Qd
    PhiT = np.swapaxes(Phi, -1, -2)
    with np.errstate(divide="ignore"):
        log_Pi = np.log(models.Pi)  # (r, r); −inf where p_ij = 0
        log_mu0 = np.log(models.mu0)
        log_mu = np.broadcast_to(log_mu0, (B, r)).copy()
    X = np.broadcast_to(np.asarray(x0, float), (B, n))[:, None, :].repeat(r, axis=1)  # (B, r, n)
    P = np.broadcast_to(np.asarray(P0, float), (B, n, n))[:, None].repeat(r, axis=1)  # (B, r, n, n)
    x_out = np.empty((B, N, n))
    P_out = np.empty((B, N, n, n)) if keep_P else None
    lm_out = np.empty((B, N, r))
    ll_out = np.empty((B, N, r))
    mon = Monitor(consistency, B, N, m) if consistency is not None else None
    if mon is not None:  # the last accepted measurement, its covariance and the time since (for a restart)
        if dt is None:
            raise ValueError("consistency needs dt (a restart's velocity is a difference over time)")
        P0b = np.broadcast_to(np.asarray(P0, float), (B, n, n))
        z_last = np.broadcast_to(np.asarray(x0, float), (B, n))[:, [0, 2]].copy()
        R_last = P0b[:, [0, 2]][:, :, [0, 2]].copy()  # the initial position covariance (R of z_b)
        since = np.zeros(B)
    for k in range(N):
        if steps is not None:  # per-step models (B, r, n, n) and Π (B, r, r)
            Phi, Qd, Pi_k = steps(dt[:, k])
            PhiT = np.swapaxes(Phi, -1, -2)
            with np.errstate(divide="ignore"):
                log_Pi = np.log(Pi_k)
        # 1–2: c̄_j and μ_{i|j} in the log domain
        a = (log_Pi if log_Pi.ndim == 3 else log_Pi[None]) + log_mu[:, :, None]  # log p_ij μ_i, (B, i, j)
        log_cbar = logsumexp(a, axis=1)  # (B, j)
        reachable = np.isfinite(log_cbar)
        with np.errstate(invalid="ignore"):
            w = np.exp(a - np.where(reachable, log_cbar, 0.0)[:, None, :])
        w = np.where(reachable[:, None, :], w, np.exp(log_mu)[:, :, None])  # unreachable j: any valid weights
        # 3: mixing, eqs (9)–(10)
        # (the sums over i as batched matrix products: an einsum of these shapes is 10-20 times slower)
        wT = np.swapaxes(w, 1, 2)  # (B, j, i)
        X0 = wT @ X  # Σ_i μ_{i|j} X̂_i, (B, j, n)
        D = np.swapaxes(X[:, :, None, :] - X0[:, None, :, :], 1, 2)  # X̂_i − X̂_0j, (B, j, i, n)
        P0j = (wT @ P.reshape(B, r, n * n)).reshape(B, r, n, n) + np.swapaxes(wT[..., None] * D, -1, -2) @ D
        # 4: model-matched prediction and update
        Xp = (Phi @ X0[..., None])[..., 0]  # X̂_j(k|k−1) = Φ_j X̂_0j
        Pp = Phi @ P0j @ PhiT + Qd  # P_j(k|k−1) = Φ_j P_0j Φ_jᵀ + G_j Q_j G_jᵀ
        Rk = R[:, k, None] if varying else R
        up = joseph_update(Xp, Pp, z[:, k, None, :], H, Rk)
        seen = measured[:, k] if (mon is not None or not every) else None  # (B,) runs measured at scan k
        if mon is not None:
            cbar = np.exp(log_cbar)
            xb = _weighted(cbar, Xp)  # the combined prediction x̄, P̄
            Pb = _spread(cbar, Pp, Xp - xb[:, None, :])
            nu = z[:, k] - xb @ H.T
            Sb = H @ Pb @ H.T + (R[:, k] if varying else R)
            S_inv, _, _ = spd_inv_logdet(Sb)
            nis = (nu[:, None, :] @ S_inv @ nu[:, :, None])[:, 0, 0]
            seen = mon.screen(k, seen, nis, nu, Sb, since + dt[:, k])  # C1: a gated measurement is not used
        if seen is None or seen.all():
            X, P, loglik = up.x, up.P, up.loglik
        else:  # predict-only where missed, likelihood 1 for every model
            X = np.where(seen[:, None, None], up.x, Xp)
            P = np.where(seen[:, None, None, None], up.P, 0.5 * (Pp + np.swapaxes(Pp, -1, -2)))
            loglik = np.where(seen[:, None], up.loglik, 0.0)
        # 5–6: likelihoods (eq 11) and model probabilities, log domain
        s = loglik + log_cbar  # log Λ_j c̄_j
        log_mu = s - logsumexp(s, axis=1)[:, None]
        # 7: output, eqs (12)–(13) corrected
        mu = np.exp(log_mu)
        xc = _weighted(mu, X)
        Pc = None
        if P_out is not None or mon is not None:
            Pc = _spread(mu, P, X - xc[:, None, :])
        if mon is not None:
            assert Pc is not None
            since = since + dt[:, k]
            bad = mon.verdict(k, np.hypot(xc[:, 1], xc[:, 3]), np.hypot(xc[:, 4], xc[:, 5]),
                              np.maximum(Pc[:, 0, 0], Pc[:, 2, 2]), np.isfinite(Pc).all(axis=(1, 2)))  # fmt: skip
            # restart from the current measurement where it was accepted, or where outliers ran out (C2)
            restart = bad & (seen | (mon.reason[:, k] == 1))
            if restart.any():  # a two-point restart on the last accepted and the current measurement
                b = np.flatnonzero(restart)
                Rb = R[b, k] if varying else np.broadcast_to(R, (b.size, m, m))
                x_new, P_new = two_point_restart(z_last[b], z[b, k], since[b], R_last[b], Rb, n=n)
                x_new, P_new = mon.cfg.restart(x_new, P_new)
                X[b] = x_new[:, None, :]
                P[b] = P_new[:, None]
                log_mu[b] = log_mu0
                xc[b], Pc[b] = x_new, P_new
                mon.reset(restart)
            coast = bad & ~restart
            if coast.any():  # no measurement to restart from: keep the position, forget the motion
                b = np.flatnonzero(coast)
                x_new, P_new = mon.cfg.coast(xc[b], Pc[b])
                X[b] = x_new[:, None, :]
                P[b] = P_new[:, None]
                log_mu[b] = log_mu0
                xc[b], Pc[b] = x_new, P_new
                mon.reset(coast)
            took = seen | restart
            z_last[took] = z[took, k]
            if varying:
                R_last[took] = R[took, k]
            since[took] = 0.0
        x_out[:, k] = xc
        if P_out is not None:
            P_out[:, k] = Pc
        lm_out[:, k] = log_mu
        ll_out[:, k] = loglik
    if mon is not None:
        return IMMTrack(x_out, P_out, lm_out, ll_out, mon.nis, mon.gated, mon.reason)
    return IMMTrack(x_out, P_out, lm_out, ll_out)
