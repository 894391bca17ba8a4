"""Batched linear Kalman filter banks — eqs (45)–(52) of the mode-signature paper (LMP mode detection with
Gold-code signatures, IEEE CDC 2008): the prediction-error decomposition.

A *bank* is C filters that share the measurement record but have their own time-varying
transition matrices F_k^c (C, n, n). Their Riccati recursions do not depend on the measurements,
so :func:`riccati` runs once per bank and :func:`innovation_costs` reuses the gains for any number
of measurement records (trials). Nothing loops over filters or trials; the only loop is over time.

Conventions: the filter starts from the predicted prior (x0, P0) at k = 0 and processes y_0 first;
after the update at k it predicts with F_k to k + 1. Updates use the Joseph form and the
covariance is re-symmetrised after each prediction, so P stays symmetric positive definite.

Missing samples: a step whose measurement is missing (NaN) is *predict-only* — no update, no term in
J, the covariance propagated (P ← F P Fᵀ + Q). The missing steps are part of the bank's
measurement-independent recursion (``riccati(..., skip=...)``): one recursion serves every record with
the same missing pattern. This is the exact likelihood of the samples that are present: the prediction
error decomposition of eqs (48)–(49) over the observed samples, the transition over a gap being the
product of the F_k it spans.

The loops over time take an optional ``progress`` callback, called with the number of time steps done
once per block of :data:`PROGRESS_BLOCK` steps (and at the end): a long single record shows a bar.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

TransitionFn = Callable[[int], np.ndarray]
Progress = Callable[[int], None] | None
PROGRESS_BLOCK = 64  # time steps between two progress reports


class MissingSamples(ValueError):
    """A missing measurement (NaN) where the computation cannot skip it.

    Attributes:
        index: 0-based sample (time step) of the first offending measurement.
        trial: 0-based record of the batch that holds it.
        column: Its measurement component (for example 1 = bearing of [range, bearing]), or None for the
            whole sample.
        reason: What cannot be done, without the position.
    """

    def __init__(self, reason: str, index: int, trial: int = 0, column: int | None = None) -> None:
        self.reason = reason
        self.index = int(index)
        self.trial = int(trial)
        self.column = column
        where = f"sample {self.index}" + (f" of record {self.trial}" if self.trial else "")
        where += "" if column is None else f", component {column}"
        super().__init__(f"{where}: {reason}")


def missing_steps(y: np.ndarray, what: str = "the filter") -> np.ndarray:
    """The missing samples of records y (B, N) or (B, N, m): a (B, N) mask, True where the sample is NaN
    (every component). ±inf is refused (ValueError); so is a sample with some components NaN and some not
    (:class:`MissingSamples` naming the first present one): ``what`` updates with all or none."""
    y = np.asarray(y, dtype=float)
    if np.isinf(y).any():
        raise ValueError("measurements contain inf")
    nan = np.isnan(y)
    if nan.ndim == 2:
        return nan
    every = nan.all(axis=-1)
    partial = nan.any(axis=-1) & ~every
    if partial.any():
        b, k = np.argwhere(partial)[0]
        col = int(np.flatnonzero(~nan[b, k])[0])
        raise MissingSamples(
            f"is present while another component of the sample is missing (NaN): {what} updates with all "
            "of a sample's components or none (leave them all empty to skip the sample)", int(k), int(b), col,
        )  # fmt: skip
    return every


def missing_patterns(missing: np.ndarray) -> list[tuple[np.ndarray | None, np.ndarray]]:
    """The records grouped by missing pattern: [(pattern (N,) bool or None for "none missing", the records
    (indices) with it)], in order of first appearance. One group when no sample is missing."""
    missing = np.asarray(missing, bool)
    B = missing.shape[0]
    if not missing.any():
        return [(None, np.arange(B))]
    patterns, first, inverse = np.unique(missing, axis=0, return_index=True, return_inverse=True)
    inverse = np.asarray(inverse).reshape(-1)
    order = np.argsort(first)
    return [(patterns[g] if patterns[g].any() else None, np.flatnonzero(inverse == g)) for g in order]


def shared_progress(progress: Progress, parts: int) -> Progress:
    """A ``progress`` callback for ``parts`` passes that each report the whole work: it reports 1/parts of
    what they report, so the steps still add up to the whole."""
    if progress is None or parts == 1:
        return progress
    state = [0, 0]  # steps reported by the passes, steps passed on

    def report(n: int) -> None:
        state[0] += n
        done = state[0] // parts
        if done > state[1]:
            progress(done - state[1])
            state[1] = done

    return report


def step_reporter(progress: Progress, n_steps: int, block: int = PROGRESS_BLOCK) -> Callable[[int], None]:
    """A hook to call after time step k (0-based) of ``n_steps``: it calls ``progress`` with the steps done
    since its last call, once per ``block`` steps and after the last step (nothing without ``progress``)."""
    if progress is None:
        return lambda k: None

    def done(k: int) -> None:
        if (k + 1) % block == 0 or k + 1 == n_steps:
            progress(k + 1 - (k // block) * block)

    return done


@dataclass(frozen=True)
class BankGains:
    """Measurement-independent part of a bank's recursion.

    Attributes:
        K: Kalman gains, (C, N, n, m) (zero at a skipped step).
        S_inv: Inverse innovation covariances, (C, N, m, m) (zero at a skipped step).
        logdet_2pi_S: log det(2π S_k), (C, N) (zero at a skipped step).
        skip: The predict-only steps (N,) bool, or None (every step updates).
    """

    K: np.ndarray
    S_inv: np.ndarray
    logdet_2pi_S: np.ndarray
    skip: np.ndarray | None = None


def _check_psd(name: str, M: np.ndarray) -> None:
    if not np.all(np.isfinite(M)):
        raise ValueError(f"{name} has non-finite entries")
    if not np.allclose(M, np.swapaxes(M, -1, -2), atol=1e-12 * max(1.0, float(np.abs(M).max()))):
        raise ValueError(f"{name} is not symmetric")
    if np.min(np.linalg.eigvalsh(M)) < -1e-12 * max(1.0, float(np.abs(M).max())):
        raise ValueError(f"{name} is not positive semi-definite")


def riccati(
    F_at: TransitionFn,
    H: np.ndarray,
    Q: np.ndarray,
    R: np.ndarray,
    P0: np.ndarray,
    n_steps: int,
    n_filters: int,
    *,
    progress: Progress = None,
    skip: np.ndarray | None = None,
) -> BankGains:
    """Run the covariance recursion of C filters for N steps.

    Args:
        F_at: k ↦ transition F_k of every filter, shape (C, n, n) (or (n, n), broadcast).
        H: Measurement matrix (m, n), shared.
        Q: Process-noise covariance, (n, n) or (C, n, n).
        R: Measurement-noise covariance (m, m).
        P0: Prior covariance (n, n) or (C, n, n).
        n_steps: N, the number of measurements.
        n_filters: C.
        progress: Called with the number of steps done, per block of steps (see the module docstring).
        skip: (N,) bool: the steps whose measurement is missing (predict-only: no update; their gain,
            S⁻¹ and log det are stored as zero). None: every step updates.

    Returns:
        Gains, inverse innovation covariances and log det(2πS) for every filter and step.
    """
    H = np.atleast_2d(np.asarray(H, dtype=float))
    R = np.atleast_2d(np.asarray(R, dtype=float))
    Q = np.asarray(Q, dtype=float)
    P0 = np.asarray(P0, dtype=float)
    m, n = H.shape
    for name, M in (("Q", Q), ("R", R), ("P0", P0)):
        _check_psd(name, M)
    if np.min(np.linalg.eigvalsh(R)) <= 0:
        raise ValueError("R must be positive definite")
    eye = np.eye(n)
    P = np.broadcast_to(P0, (n_filters, n, n)).copy()
    K_all = np.empty((n_filters, n_steps, n, m))
    S_inv_all = np.empty((n_filters, n_steps, m, m))
    logdet_all = np.empty((n_filters, n_steps))
    scalar = m == 1
    tick = step_reporter(progress, n_steps)
    if skip is not None:
        skip = np.asarray(skip, bool)
        if skip.shape != (n_steps,):
            raise ValueError(f"skip must be ({n_steps},) bool, got shape {skip.shape}")
        if not skip.any():
            skip = None
    for k in range(n_steps):
        if skip is not None and skip[k]:  # predict-only: P carries over to the prediction
            K_all[:, k], S_inv_all[:, k], logdet_all[:, k] = 0.0, 0.0, 0.0
            if k + 1 < n_steps:
                F = F_at(k)
                P = F @ P @ np.swapaxes(F, -1, -2) + Q
                P = 0.5 * (P + np.swapaxes(P, -1, -2))
            tick(k)
            continue
        PHt = P @ H.T  # (C, n, m)
        S = H @ PHt + R  # innovation covariance, eq (47)
        if scalar:  # 1×1: no LAPACK calls
            S_inv = 1.0 / S
            logdet_all[:, k] = np.log(2 * np.pi * S[:, 0, 0])
        else:
            S_inv = np.linalg.inv(S)
            logdet_all[:, k] = np.linalg.slogdet(2 * np.pi * S)[1]
        K = PHt @ S_inv  # Kalman gain
        IKH = eye - K @ H
        P = IKH @ P @ np.swapaxes(IKH, -1, -2) + K @ R @ np.swapaxes(K, -1, -2)  # Joseph form
        K_all[:, k], S_inv_all[:, k] = K, S_inv
        if k + 1 < n_steps:
            F = F_at(k)
            P = F @ P @ np.swapaxes(F, -1, -2) + Q
            P = 0.5 * (P + np.swapaxes(P, -1, -2))
        tick(k)
    return BankGains(K_all, S_inv_all, logdet_all, skip)


def innovation_costs(
    F_at: TransitionFn,
    H: np.ndarray,
    gains: BankGains,
    x0: np.ndarray,
    y: np.ndarray,
    horizons: Sequence[int],
    *,
    include_logdet: bool = False,
    progress: Progress = None,
    block: int | None = None,
) -> np.ndarray:
    """Cumulative innovation costs J(n) of every filter on every record, read at the horizons.

    J(n) = ½ Σ_{j<n} ν_jᵀ S_j⁻¹ ν_j (eq 52), plus ½ Σ log det(2π S_j) when ``include_logdet``
    (the full negative log-likelihood of eqs 48–49); the sums run over the samples that are present
    (``gains.skip`` marks the missing ones, which must be NaN in every record, and only they).

    Args:
        F_at: As for :func:`riccati` (must be the same bank).
        H: (m, n).
        gains: From :func:`riccati`.
        x0: Prior mean (n,) or (C, n).
        y: Measurement records, (B, N) for m = 1 or (B, N, m).
        horizons: Sample counts n at which to read J (1 ≤ n ≤ N), any order.
        progress: Called with the number of steps done, per block of steps.
        block: Evaluate the records in consecutive blocks of this many (None: all at once). A record's
            J then depends on its block only, not on the other records of the call, to the last bit.

    Returns:
        J of shape (C, B, len(horizons)).
    """
    H = np.atleast_2d(np.asarray(H, dtype=float))
    m, n = H.shape
    y = np.asarray(y, dtype=float)
    if y.ndim == 2:
        y = y[..., None]
    B, N, my = y.shape
    if my != m:
        raise ValueError(f"measurements have dimension {my}, H has {m} rows")
    C = gains.K.shape[0]
    hz = np.asarray(horizons, dtype=int)
    if hz.size == 0 or hz.min() < 1 or hz.max() > N:
        raise ValueError(f"horizons must lie in 1..{N} samples")
    skip = gains.skip
    nan = np.isnan(y)
    if skip is None and nan.any():
        b, k, _ = np.argwhere(nan)[0]
        raise MissingSamples("is missing (NaN) but the gains update there (give riccati the skip mask)", k, b)
    if skip is not None and not (np.all(nan[:, skip]) and not np.any(nan[:, ~skip])):
        raise ValueError("the records' missing samples (NaN) are not the steps the gains skip")
    if block is not None and B > block:
        starts = range(0, B, block)
        tell = shared_progress(progress, len(starts))
        parts = [
            innovation_costs(
                F_at, H, gains, x0, y[s : s + block], hz, include_logdet=include_logdet, progress=tell
            )
            for s in starts
        ]
        return np.concatenate(parts, axis=1)
    # state means with the trials last, (C, n, B): the per-step products are (n×n)·(n×B) per filter
    x = np.repeat(np.broadcast_to(np.asarray(x0, dtype=float), (C, n))[:, :, None], B, axis=2)
    yT = np.ascontiguousarray(np.moveaxis(y, 0, -1))  # (N, m, B)
    J = np.zeros((C, B))
    out = np.empty((C, B, hz.size))
    read_at = {int(h): np.flatnonzero(hz == h) for h in np.unique(hz)}
    scalar = m == 1
    tick = step_reporter(progress, N)
    for k in range(N):
        if skip is not None and skip[k]:  # predict-only
            if k + 1 in read_at:
                out[:, :, read_at[k + 1]] = J[:, :, None]
            if k + 1 < N:
                x = np.broadcast_to(F_at(k), (C, n, n)) @ x
            tick(k)
            continue
        nu = yT[k][None] - H @ x  # innovation ν_k, (C, m, B)
        if scalar:  # m = 1: S⁻¹ is a number per filter
            J += 0.5 * gains.S_inv[:, k, 0, :] * nu[:, 0, :] ** 2  # ½ ν² / S, eq (49)
        else:
            J += 0.5 * np.einsum("cib,cij,cjb->cb", nu, gains.S_inv[:, k], nu)
        if include_logdet:
            J += 0.5 * gains.logdet_2pi_S[:, k][:, None]
        x += gains.K[:, k] @ nu  # measurement update
        if k + 1 in read_at:
            out[:, :, read_at[k + 1]] = J[:, :, None]
        if k + 1 < N:
            x = np.broadcast_to(F_at(k), (C, n, n)) @ x  # prediction x_{k+1} = F_k x_k
        tick(k)
    return out


def expected_costs_white_noise(
    F_at: TransitionFn,
    H: np.ndarray,
    gains: BankGains,
    R_true: np.ndarray,
    n_steps: int,
    horizons: Sequence[int],
    *,
    progress: Progress = None,
) -> np.ndarray:
    """E[J(n)] of every filter when the measurements are zero-mean white noise of covariance R_true.

    The estimate is a linear function of the data, x̂⁺ = (I − K H) x̂ + K y, x̂_{k+1} = F_k x̂⁺, so
    Σ_k = Cov(x̂_k) follows the Lyapunov recursion Σ⁺ = (I−KH) Σ (I−KH)ᵀ + K R_true Kᵀ, Σ ← F Σ⁺ Fᵀ,
    and E[ν_k ν_kᵀ] = H Σ_k Hᵀ + R_true, E[½ νᵀS⁻¹ν] = ½ tr(S⁻¹ E[ννᵀ]). Exact, no sampling. A step the
    gains skip (a missing sample) adds nothing and only predicts, Σ ← F Σ Fᵀ.

    Returns:
        (C, len(horizons)).
    """
    H = np.atleast_2d(np.asarray(H, dtype=float))
    R_true = np.atleast_2d(np.asarray(R_true, dtype=float))
    n = H.shape[1]
    C = gains.K.shape[0]
    hz = np.asarray(horizons, dtype=int)
    Sig = np.zeros((C, n, n))
    EJ = np.zeros(C)
    out = np.empty((C, hz.size))
    read_at = {int(h): np.flatnonzero(hz == h) for h in np.unique(hz)}
    eye = np.eye(n)
    tick = step_reporter(progress, n_steps)
    skip = gains.skip
    for k in range(n_steps):
        if skip is not None and skip[k]:  # predict-only
            if k + 1 in read_at:
                out[:, read_at[k + 1]] = EJ[:, None]
            if k + 1 < n_steps:
                F = np.broadcast_to(F_at(k), (C, n, n))
                Sig = F @ Sig @ np.swapaxes(F, -1, -2)
            tick(k)
            continue
        Enu = H @ Sig @ H.T + R_true  # E[ν νᵀ], (C, m, m)
        EJ += 0.5 * np.einsum("cij,cji->c", gains.S_inv[:, k], Enu)
        if k + 1 in read_at:
            out[:, read_at[k + 1]] = EJ[:, None]
        K = gains.K[:, k]
        IKH = eye - K @ H
        Sig = IKH @ Sig @ np.swapaxes(IKH, -1, -2) + K @ R_true @ np.swapaxes(K, -1, -2)
        if k + 1 < n_steps:
            F = np.broadcast_to(F_at(k), (C, n, n))
            Sig = F @ Sig @ np.swapaxes(F, -1, -2)
        tick(k)
    return out


@dataclass(frozen=True)
class Update:
    """One batched Kalman measurement update (leading axes are any batch of runs × models).

    Attributes:
        x, P: updated mean (..., n) and covariance (..., n, n) (Joseph form).
        nu: innovation (..., m); S_inv: its inverse covariance (..., m, m); K: gain (..., n, m).
        loglik: log N(ν; 0, S) (..., ), computed from log det S, never from a density value.
    """

    x: np.ndarray
    P: np.ndarray
    nu: np.ndarray
    S_inv: np.ndarray
    K: np.ndarray
    loglik: np.ndarray


def spd_inv_logdet(A: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Inverse and log-determinant of a batch of symmetric matrices that should be positive definite
    (closed form for 2×2, LAPACK otherwise).

    Returns:
        inv (..., p, p), log det (...) and a mask of the matrices that are positive definite; where it is
        False the inverse is NaN and the log-determinant −inf (no exception: callers decide).
    """
    if A.shape[-1] == 2:
        a, b, d = A[..., 0, 0], 0.5 * (A[..., 0, 1] + A[..., 1, 0]), A[..., 1, 1]
        det = a * d - b * b
        ok = (a > 0) & (det > 0)
        safe = np.where(ok, det, 1.0)
        inv = np.empty_like(A)
        inv[..., 0, 0], inv[..., 1, 1] = d / safe, a / safe
        inv[..., 0, 1] = inv[..., 1, 0] = -b / safe
        inv[~ok] = np.nan
        return inv, np.where(ok, np.log(safe), -np.inf), ok
    sign, logdet = np.linalg.slogdet(A)
    ok = sign > 0
    inv = np.linalg.inv(np.where(ok[..., None, None], A, np.eye(A.shape[-1])))
    inv[~ok] = np.nan
    return inv, np.where(ok, logdet, -np.inf), ok


def joseph_update(x: np.ndarray, P: np.ndarray, z: np.ndarray, H: np.ndarray, R: np.ndarray) -> Update:
    """Measurement update of a batch of filters sharing H and R.

    ν = z − H x, S = H P Hᵀ + R, K = P Hᵀ S⁻¹, x⁺ = x + K ν,
    P⁺ = (I − K H) P (I − K H)ᵀ + K R Kᵀ (Joseph form: symmetric positive semi-definite by construction),
    log N(ν; 0, S) = −½ νᵀS⁻¹ν − ½ log det(2π S).

    Args:
        x: (..., n); P: (..., n, n); z: (..., m) broadcastable against H x; H: (m, n); R: (m, m).
    """
    m, n = H.shape
    nu = z - x @ H.T
    PHt = P @ H.T
    S = H @ PHt + R
    S_inv, logdet, ok = spd_inv_logdet(S)
    if not np.all(ok):
        raise np.linalg.LinAlgError("innovation covariance is not positive definite")
    K = PHt @ S_inv
    A = np.eye(n) - K @ H
    P_new = A @ P @ np.swapaxes(A, -1, -2) + K @ R @ np.swapaxes(K, -1, -2)
    P_new = 0.5 * (P_new + np.swapaxes(P_new, -1, -2))
    x_new = x + (K @ nu[..., None])[..., 0]
    maha = (nu[..., None, :] @ S_inv @ nu[..., :, None])[..., 0, 0]
    loglik = -0.5 * (maha + logdet + m * np.log(2.0 * np.pi))
    return Update(x_new, P_new, nu, S_inv, K, loglik)
