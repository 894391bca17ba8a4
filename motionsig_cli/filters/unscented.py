"""Unscented (sigma-point) Kalman filters, batched — the radar example of the mode-signature paper (LMP mode
detection with Gold-code signatures, IEEE CDC 2008, §IV.B, eqs 59–62).

The scaled unscented transform (Julier 2002; Van der Merwe's parametrisation, the one FilterPy's
``MerweScaledSigmaPoints`` uses) with n states, λ = α²(n + κ) − n and c = √(n + λ)::

    χ_0 = x,  χ_j = x + c L_j,  χ_{n+j} = x − c L_j        L = lower Cholesky factor of P, L_j its columns
    W^m_0 = λ/(n+λ),  W^c_0 = W^m_0 + 1 − α² + β,  W_j = 1/(2(n+λ))  (j ≥ 1)
    ŷ = Σ W^m_i h(χ_i),  S = Σ W^c_i e_i e_iᵀ + R,  P_xy = Σ W^c_i (χ_i − x) e_iᵀ,  e_i = h(χ_i) − ŷ

Angular measurement components are averaged about the central point, ŷ = h(χ_0) + Σ W^m_i
wrap(h(χ_i) − h(χ_0)), and every residual is wrapped to (−π, π].

**The reduction that makes the bank fast (exact, not an approximation).** If h reads only the leading
p state components, the sigma points χ_{±j} with j > p move no component h reads (columns j > p of
a *lower* Cholesky factor are zero in rows < j), so h(χ_{±j}) = h(χ_0), their residuals cancel in
P_xy and add 2(n − p) copies of e_0e_0ᵀ to S. Only the first p columns of L are needed; they are
the first p steps of a left-looking Cholesky factorisation. For the radar (h reads x and y, state
[x, ẋ, y, …]) p = 3: three of ten columns, 7 of 21 evaluations of h, the same numbers.

The prediction is linear and exact (x ← F x, P ← F P Fᵀ + Q: the models are linear in the state); it uses the
structure of the LMP banks, F_k^c = F_0 + Σ_r g_r[c, k] e_{row_r} e_{col_r}ᵀ, so the shared F_0 is
one matrix product over every filter and trial and the time-varying entries are rank-one terms.

Missing samples: a record whose sample k is NaN (every component) skips the update at k — no term in J
or in the log-determinants, x and P carried to the prediction unchanged; the mask is per (record,
step), so records with different gaps share one bank. A step no record measures runs the prediction
only; at a step some records miss, their innovations and gains are zeroed (and their covariances kept
out of the factorisations, so they are neither repaired nor counted). A sample with some components
present and some missing is refused (:class:`~motionsig_cli.filters.kalman.MissingSamples`).

Covariance safety: the update P ← P − W Wᵀ (W = P_xy L_S⁻ᵀ) is symmetric to the last bit; a
Cholesky pivot of P or S at or below zero (a valid input can do this: a singular prior, rounding, or a
negative W^c_0 from β < 0) is repaired by projecting onto the positive semi-definite matrices (S onto
R + PSD) and is *counted*; a non-finite number stops the run with an error instead of returning NaN.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError
from motionsig_cli.filters.kalman import Progress, missing_steps, step_reporter
from motionsig_cli.models.radar import wrap_angle

JITTER_START = 1e-12  # first relative jitter tried by a repair (× the mean diagonal), then ×100 per retry


@dataclass(frozen=True, slots=True)
class SigmaPointParams:
    """Scaled unscented-transform parameters (assumed: α = 1, β = 2, κ = 0; the paper does not state them).

    Attributes:
        alpha: Spread of the sigma points, finite and > 0 (and not so small that the centre weight
            cancels the others: see :meth:`weights`).
        beta: Prior-knowledge term in W^c_0, finite (2 is optimal for Gaussians).
        kappa: Secondary scaling, finite; n + λ = α²(n + κ) must be > 0 for the filter's n states
            (checked by :meth:`weights`, which knows n).
    """

    alpha: float = 1.0
    beta: float = 2.0
    kappa: float = 0.0

    def __post_init__(self) -> None:
        if not (_finite(self.alpha) and self.alpha > 0):
            raise ConfigError("alpha", self.alpha, "is not a finite number > 0")
        for name in ("beta", "kappa"):
            if not _finite(getattr(self, name)):
                raise ConfigError(name, getattr(self, name), "is not a finite number")

    def weights(self, n: int) -> tuple[float, float, float, float]:
        """(W^m_0, W^c_0, W_j, c) for n states (a :class:`ConfigError` names the parameter that does not
        suit n)."""
        try:
            n_lam = self.alpha**2 * (n + self.kappa)  # n + λ, formed without the cancellation of λ + n
        except OverflowError:
            n_lam = math.inf
        if not math.isfinite(n_lam):
            raise ConfigError("alpha", self.alpha, f"makes alpha^2 (n + kappa) overflow (n = {n} states)")
        if not n_lam > 0:
            raise ConfigError(
                "kappa", self.kappa, f"makes alpha^2 (n + kappa) <= 0 for the filter of n = {n} states"
            )
        wm0 = 1.0 - n / n_lam  # λ / (n + λ)
        if abs(wm0) > 1e8:
            raise ConfigError(
                "alpha",
                self.alpha,
                f"gives a centre weight of {wm0:.3g} (n = {n} states): the weighted sums would cancel to "
                "fewer than 8 significant digits; use alpha >= 1e-4",
            )
        return wm0, wm0 + 1 - self.alpha**2 + self.beta, 0.5 / n_lam, math.sqrt(n_lam)


def _finite(value: float) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and math.isfinite(value)


def _wrap_where(d: np.ndarray, angular: np.ndarray) -> np.ndarray:
    """Wrap the angular components (last axis) of d to (−π, π]."""
    if angular.any():
        d = d.copy()
        d[..., angular] = wrap_angle(d[..., angular])
    return d


# ---------------------------------------------------------------------------------------------------
# Reference path: the full 2n + 1 points, any h (tests, notebook)
# ---------------------------------------------------------------------------------------------------


def sigma_points(x: np.ndarray, P: np.ndarray, params: SigmaPointParams) -> np.ndarray:
    """The 2n + 1 sigma points, (..., 2n + 1, n), ordered χ_0, χ_{1..n}, χ_{n+1..2n} (FilterPy's order)."""
    x = np.asarray(x, dtype=float)
    n = x.shape[-1]
    *_, c = params.weights(n)
    L = np.linalg.cholesky(np.asarray(P, dtype=float))
    cols = c * np.swapaxes(L, -1, -2)  # row j = c L_j
    return np.concatenate([x[..., None, :], x[..., None, :] + cols, x[..., None, :] - cols], axis=-2)


def unscented_transform(
    x: np.ndarray,
    P: np.ndarray,
    h: Callable[[np.ndarray], np.ndarray],
    params: SigmaPointParams,
    angular: Sequence[bool] = (),
    R: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ŷ, S, P_xy) of y = h(x) + v for x ~ N(x, P) by the scaled UT over all 2n + 1 points.

    Args:
        x: Mean (..., n).  P: Covariance (..., n, n).
        h: Maps states (..., n) to measurements (..., m).
        angular: m flags; flagged components are averaged about χ_0 and their residuals wrapped.
        R: Additive measurement-noise covariance (m, m); zero if None.
    """
    X = sigma_points(x, P, params)
    n = X.shape[-1]
    wm0, wc0, wj, _ = params.weights(n)
    Y = np.asarray(h(X), dtype=float)
    m = Y.shape[-1]
    ang = np.zeros(m, bool) if len(angular) == 0 else np.asarray(angular, bool)
    wm = np.full(2 * n + 1, wj)
    wm[0] = wm0
    wc = wm.copy()
    wc[0] = wc0
    d = _wrap_where(Y - Y[..., :1, :], ang)
    y_hat = Y[..., 0, :] + np.einsum("i,...im->...m", wm, d)
    y_hat = _wrap_where(y_hat, ang)
    e = _wrap_where(Y - y_hat[..., None, :], ang)
    S = np.einsum("i,...ia,...ib->...ab", wc, e, e)
    if R is not None:
        S = S + np.asarray(R, dtype=float)
    Pxy = np.einsum("i,...ia,...ib->...ab", wc, X - np.asarray(x)[..., None, :], e)
    return y_hat, S, Pxy


# ---------------------------------------------------------------------------------------------------
# Batched bank. Layout: matrix indices first, filters and trials last — x (n, C, B), P (n, n, C, B) —
# so every per-filter operation is an elementwise operation on contiguous (C, B) blocks and the
# shared F_0 is one BLAS matrix product over the whole bank.
# ---------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class StructuredTransition:
    """F_k^c = F_0 + Σ_r g[c, k, r] e_{row_r} e_{col_r}ᵀ for C filters (the LMP banks' structure, eq 44).

    Attributes:
        F0: Shared part (n, n).
        entries: (row, column) of each time-varying entry, r of them (may be empty).
        g: Values added at those entries, (C, N, r) (C = 1 and r = 0 for a constant model).
    """

    F0: np.ndarray
    entries: tuple[tuple[int, int], ...]
    g: np.ndarray

    def __post_init__(self) -> None:
        n = self.F0.shape[0]
        if self.F0.shape != (n, n) or self.g.ndim != 3 or self.g.shape[2] != len(self.entries):
            raise ValueError("F0 must be (n, n) and g (C, N, len(entries))")
        if any(not (0 <= i < n and 0 <= j < n) for i, j in self.entries):
            raise ValueError("transition entries must index the state")

    @classmethod
    def constant(cls, F: np.ndarray, n_steps: int) -> StructuredTransition:
        """One constant model."""
        return cls(np.asarray(F, float), (), np.zeros((1, n_steps, 0)))

    @property
    def n_filters(self) -> int:
        return int(self.g.shape[0])

    def dense(self, k: int) -> np.ndarray:
        """F_k of every filter, (C, n, n) (reference; the bank never forms it)."""
        F = np.repeat(self.F0[None], self.n_filters, axis=0)
        for r, (i, j) in enumerate(self.entries):
            F[:, i, j] += self.g[:, k, r]
        return F

    def predict(self, x: np.ndarray, P: np.ndarray, k: int, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """x ← F_k x, P ← F_k P F_kᵀ + Q for x (n, C, B) and symmetric P (n, n, C, B), **in place**.

        F_k = I + E_k with E_k sparse (F_0 − I has 12 non-zeros in the 2-D radar bank, plus the two
        amplitude entries), so F P = P + Σ E_ij e_i P_j· (row updates) and (F P) Fᵀ = F P + Σ E_ij
        (F P)_·j e_iᵀ (column updates): a few elementwise passes over contiguous (C, B) blocks instead
        of two dense products. Rows (columns) that are both read and written are read from a copy taken
        first. The result's upper triangle is then copied from its lower one: symmetric to the last bit.
        """
        n = x.shape[0]
        gk = self.g[:, k, :, None]  # (C, r, 1): broadcasts over the trials
        E0 = self.F0 - np.eye(n)
        terms: list[tuple[int, int, Any]] = [
            (int(i), int(j), float(E0[i, j])) for i, j in zip(*np.nonzero(E0), strict=True)
        ]
        terms += [(i, j, gk[:, r]) for r, (i, j) in enumerate(self.entries)]
        both = {j for _, j, _ in terms} & {i for i, _, _ in terms}
        old_x = {j: x[j].copy() for j in both}
        old_rows = {j: P[j].copy() for j in both}
        for i, j, e in terms:
            x[i] += e * old_x.get(j, x[j])  # x ← F x
            P[i] += e * old_rows.get(j, P[j])  # P ← F P (rows)
        old_cols = {j: P[:, j].copy() for j in both}
        for i, j, e in terms:
            P[:, i] += e * old_cols.get(j, P[:, j])  # P ← (F P) Fᵀ (columns)
        for i in range(n - 1):
            P[i, i + 1 :] = P[i + 1 :, i]  # mirror the lower triangle
        if np.count_nonzero(Q - np.diag(np.diag(Q))):
            P += Q[:, :, None, None]
        else:
            for i in range(n):
                P[i, i] += Q[i, i]
        return x, P


@dataclass(frozen=True)
class SigmaMeasurement:
    """A measurement model for the bank.

    Attributes:
        h: Maps the leading ``lead`` state components, stacked on the FIRST axis (lead, ...), to
            measurements (m, ...).
        lead: h reads state components 0 … lead − 1 only (the reduction of the module docstring).
        R: Measurement-noise covariance (m, m), positive definite.
        angular: m flags for angle components (wrapped).
    """

    h: Callable[[np.ndarray], np.ndarray]
    lead: int
    R: np.ndarray
    angular: tuple[bool, ...]

    def __post_init__(self) -> None:
        m = len(self.angular)
        if self.R.shape != (m, m) or self.lead < 1:
            raise ValueError("R must be (m, m) with one angular flag per component, and lead >= 1")
        if not (np.all(np.isfinite(self.R)) and np.min(np.linalg.eigvalsh(self.R)) > 0):
            raise ValueError("measurement-noise covariance R must be positive definite")


def _wrap_rows(d: np.ndarray, angular: np.ndarray) -> np.ndarray:
    """Wrap the angular components (first axis) of d to (−π, π], in place."""
    for a in np.flatnonzero(angular):
        if np.any(np.abs(d[a]) > np.pi):  # rare: the modulo costs more than the test
            d[a] = wrap_angle(d[a])
    return d


def _left_cholesky(A: np.ndarray, p: int) -> tuple[np.ndarray, np.ndarray]:
    """First p columns of the lower Cholesky factor of A (n, n, ...) by left-looking elimination.

    Returns:
        L (n, p, ...) and the smallest pivot of each matrix (...) (≤ 0 marks a failed factorisation;
        the affected entries of L are then meaningless).
    """
    n = A.shape[0]
    L = np.zeros((n, p, *A.shape[2:]))
    min_piv = np.full(A.shape[2:], np.inf)
    for j in range(p):
        v = A[:, j].copy()
        for q in range(j):
            v[j:] -= L[j:, q] * L[j, q]
        d = v[j]
        min_piv = np.minimum(min_piv, d)
        L[j:, j] = v[j:] * (1.0 / np.sqrt(np.where(d > 0, d, np.inf)))  # a failed pivot gives a zero column
    return L, min_piv


def _repaired_cholesky(
    A: np.ndarray, p: int, floor: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, int]:
    """:func:`_left_cholesky` that repairs the matrices it cannot factor, and counts them.

    A failed matrix is symmetrised and projected onto the positive semi-definite cone by clipping its
    eigenvalues (Higham's nearest PSD matrix): at 0 above ``floor`` when one is given (an innovation
    covariance is the PSD spread of h(χ) plus R, so S is repaired to R + (S − R)₊), else at 1e-12 × its
    largest |eigenvalue|. Should that still not factor, a diagonal jitter grows ×100 from 1e-12 × the mean
    diagonal. Returns (L, the possibly repaired A, number of repaired matrices).
    """
    L, piv = _left_cholesky(A, p)
    bad = ~(piv > 0)
    if not bad.any():
        return L, A, 0
    Ab = np.moveaxis(A[..., bad], -1, 0)  # (k, n, n)
    if not np.all(np.isfinite(Ab)):
        raise FloatingPointError("a covariance became non-finite in the sigma-point bank")
    n = A.shape[0]
    base = np.zeros((n, n)) if floor is None else np.asarray(floor, float)
    lam, V = np.linalg.eigh(0.5 * (Ab + np.swapaxes(Ab, 1, 2)) - base)
    if floor is None:
        lam = np.maximum(lam, 1e-12 * np.max(np.abs(lam), axis=1, keepdims=True))
    else:
        lam = np.maximum(lam, 0.0)
    fixed = (V * lam[:, None, :]) @ np.swapaxes(V, 1, 2) + base
    Lb, pb = _left_cholesky(np.moveaxis(fixed, 0, -1), p)
    scale = np.maximum(np.abs(np.trace(fixed, axis1=1, axis2=2)) / n, np.finfo(float).tiny)
    rel = JITTER_START
    while not np.all(pb > 0):
        fixed = fixed + (rel * scale)[:, None, None] * np.eye(n)
        Lb, pb = _left_cholesky(np.moveaxis(fixed, 0, -1), p)
        rel *= 100.0
        if rel > 1.0:
            raise FloatingPointError("a covariance could not be repaired (jitter above its own scale)")
    A = A.copy()
    A[..., bad] = np.moveaxis(fixed, 0, -1)
    L[..., bad] = Lb
    return L, A, int(bad.sum())


def _forward(L: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Solve L u = b for lower-triangular L (m, m, ...) and b (m, ...) (b may carry extra leading
    axes after the first: (m, k, ...) with L broadcast) by forward substitution."""
    m = L.shape[0]
    u = np.empty_like(b)
    for i in range(m):
        acc = b[i].copy()
        for q in range(i):
            acc -= L[i, q] * u[q]
        u[i] = acc / L[i, i]
    return u


@dataclass(frozen=True)
class BankCosts:
    """Innovation costs of a sigma-point bank.

    Attributes:
        J: ½ Σ_{j<n} ν_jᵀ S_j⁻¹ ν_j at each horizon, (C, B, H) (eq 52's J).
        half_logdet: ½ Σ_{j<n} log det(2π S_j), (C, B, H); J + half_logdet = −log-likelihood (eqs 48–49).
        repairs_P: (filter, trial, step) triples whose state covariance needed a jitter repair.
        repairs_S: Likewise for the innovation covariance.
        x: The state estimate after the last sample (its update, or none where it is missing), (C, B, n).
        P: Its covariance, (C, B, n, n).
    """

    J: np.ndarray
    half_logdet: np.ndarray
    repairs_P: int
    repairs_S: int
    x: np.ndarray | None = None
    P: np.ndarray | None = None


def ukf_bank_costs(
    trans: StructuredTransition,
    Q: np.ndarray,
    meas: SigmaMeasurement,
    x0: np.ndarray,
    P0: np.ndarray,
    y: np.ndarray,
    horizons: Sequence[int],
    params: SigmaPointParams,
    *,
    progress: Progress = None,
) -> BankCosts:
    """Run C unscented filters on B records at once and read their innovation costs at the horizons.

    Every filter starts from the predicted prior (x0, P0) at k = 0, updates with y_0, then predicts
    with F_0 to k = 1, and so on (the convention of :mod:`motionsig_cli.filters.kalman`).

    Args:
        trans: The bank's transitions (C filters, N ≥ number of samples).
        Q: Process noise (n, n).
        meas: Measurement model (m components).
        x0: Prior mean (n,).  P0: Prior covariance (n, n).
        y: Records (B, N) for m = 1 or (B, N, m); a NaN sample (every component) is missing: predict-only.
        horizons: Sample counts at which to read the costs (1 ≤ n ≤ N).
        params: Sigma-point parameters.
        progress: Called with the number of time steps done, once per block of steps (see
            :func:`motionsig_cli.filters.kalman.step_reporter`).
    """
    y = np.asarray(y, dtype=float)
    if y.ndim == 2:
        y = y[..., None]
    B, N, m = y.shape
    n = trans.F0.shape[0]
    C = trans.n_filters
    p = meas.lead
    if m != len(meas.angular) or p > n or trans.g.shape[1] < N - 1:
        raise ValueError("record, measurement model and transitions do not fit together")
    missing = missing_steps(y, "the sigma-point filter")  # (B, N)
    present = ~missing
    hz = np.asarray(horizons, dtype=int)
    if hz.size == 0 or hz.min() < 1 or hz.max() > N:
        raise ValueError(f"horizons must lie in 1..{N} samples")
    _, wc0, wj, c = params.weights(n)  # W^m_0 drops out: ŷ is taken about χ_0
    ang = np.asarray(meas.angular, bool)
    Rm = np.asarray(meas.R, float)[:, :, None, None]
    Q = np.asarray(Q, float)
    yk_all = np.ascontiguousarray(np.moveaxis(y, 0, -1))[:, :, None, :]  # (N, m, 1, B)
    x = np.broadcast_to(np.asarray(x0, float)[:, None, None], (n, C, B)).copy()
    P = np.broadcast_to(np.asarray(P0, float)[:, :, None, None], (n, n, C, B)).copy()
    J = np.zeros((C, B))
    LD = np.zeros((C, B))
    J_out = np.empty((C, B, hz.size))
    LD_out = np.empty((C, B, hz.size))
    read_at = {int(h): np.flatnonzero(hz == h) for h in np.unique(hz)}
    rep_P = rep_S = 0
    half_log2pi = 0.5 * m * math.log(2 * math.pi)
    w_e0 = wc0 + 2 * (n - p) * wj  # χ_0 and the 2(n − p) points that move nothing h reads
    tick = step_reporter(progress, N)
    some_missing = missing.any(axis=0)  # (N,)
    none_present = ~present.any(axis=0)
    eye_n = np.eye(n)[:, :, None, None]
    for k in range(N):
        pk: np.ndarray | None = None  # the records measured at k, where some are not
        if none_present[k]:  # predict-only for every record
            if k + 1 in read_at:
                J_out[:, :, read_at[k + 1]] = J[..., None]
                LD_out[:, :, read_at[k + 1]] = LD[..., None]
            if k + 1 < N:
                x, P = trans.predict(x, P, k, Q)
            tick(k)
            continue
        if some_missing[k]:
            pk = present[:, k]
        # --- sigma points along the first p columns of chol(P) ------------------------------------
        if pk is None:
            L, P, nb = _repaired_cholesky(P, p)  # (n, p, C, B)
        else:  # the missing records' P stays out of the factorisation (and the repair count)
            L, P_fact, nb = _repaired_cholesky(np.where(pk, P, eye_n), p)
            P = np.where(pk, P_fact, P)
        rep_P += nb
        xl = x[:p, None]  # (p, 1, C, B)
        step = c * L[:p]  # step[:, j] = c L_j on the lead components, (p, p, C, B)
        Y0 = meas.h(x[:p])  # (m, C, B)
        Yp = meas.h(xl + step)  # (m, p, C, B)
        Ym = meas.h(xl - step)
        d = _wrap_rows(Yp - Y0[:, None], ang) + _wrap_rows(Ym - Y0[:, None], ang)
        y_hat = _wrap_rows(Y0 + wj * d.sum(1), ang)  # Σ W^m_i h(χ_i), angles about χ_0
        e0 = _wrap_rows(Y0 - y_hat, ang)
        ep = _wrap_rows(Yp - y_hat[:, None], ang)
        em = _wrap_rows(Ym - y_hat[:, None], ang)
        S = np.empty((m, m, C, B))
        for a in range(m):
            for b in range(a + 1):
                S[a, b] = w_e0 * e0[a] * e0[b] + wj * ((ep[a] * ep[b]).sum(0) + (em[a] * em[b]).sum(0))
                S[b, a] = S[a, b]
        S += Rm  # S = Σ W^c_i e_i e_iᵀ + R
        if pk is not None:
            S = np.where(pk, S, Rm)  # a missing record's S is never used: keep it out of the repairs
        de = (wj * c) * (ep - em)  # (m, p, C, B)
        Pxy = L[:, None, 0] * de[None, :, 0]  # Σ W^c_i (χ_i − x) e_iᵀ = W c Σ_j L_j (e_{+j} − e_{−j})ᵀ
        for j in range(1, p):
            Pxy += L[:, None, j] * de[None, :, j]  # (n, m, C, B)
        # --- innovation, likelihood and update ----------------------------------------------------
        Ls, S, nbs = _repaired_cholesky(S, m, floor=Rm[:, :, 0, 0])  # S = L_S L_Sᵀ, (m, m, C, B)
        rep_S += nbs
        nu = _wrap_rows(yk_all[k] - y_hat, ang)  # ν_k, eq (47), bearing wrapped
        if pk is not None:
            nu = np.where(pk, nu, 0.0)  # no innovation where the sample is missing
        u = _forward(Ls, nu)  # L_S⁻¹ ν
        J += 0.5 * (u * u).sum(0)  # ½ νᵀ S⁻¹ ν, eq (52)
        ld = np.log(np.diagonal(Ls, axis1=0, axis2=1)).sum(-1) + half_log2pi  # ½ log det 2πS
        LD += ld if pk is None else np.where(pk, ld, 0.0)
        W = _forward(Ls[:, :, None], np.swapaxes(Pxy, 0, 1))  # rows of P_xy L_S⁻ᵀ, (m, n, C, B)
        if pk is not None:
            W = np.where(pk, W, 0.0)  # no gain: x and P carry over
        for a in range(m):
            Wa = W[a]
            x += Wa * u[a]  # x + K ν with K = P_xy S⁻¹ = W L_S⁻¹
            for i in range(n):
                P[i] -= Wa[i] * Wa  # P − K S Kᵀ = P − W Wᵀ, row by row (symmetric to the last bit)
        if k + 1 in read_at:
            J_out[:, :, read_at[k + 1]] = J[..., None]
            LD_out[:, :, read_at[k + 1]] = LD[..., None]
        if k + 1 < N:
            x, P = trans.predict(x, P, k, Q)
        tick(k)
    if not (np.all(np.isfinite(J_out)) and np.all(np.isfinite(LD_out))):
        raise FloatingPointError("the sigma-point bank produced a non-finite cost")
    return BankCosts(J_out, LD_out, rep_P, rep_S, np.moveaxis(x, 0, -1), np.moveaxis(P, (0, 1), (-2, -1)))


def linear_measurement(H: np.ndarray, R: np.ndarray) -> SigmaMeasurement:
    """A linear measurement y = H x + v as a :class:`SigmaMeasurement` (the UT is then exact: the bank
    equals a Kalman filter, the cross-check of the two banks)."""
    H = np.atleast_2d(np.asarray(H, float))
    nz = np.flatnonzero(np.any(H != 0, axis=0))
    lead = int(nz.max()) + 1 if nz.size else 1
    Hl = H[:, :lead]
    return SigmaMeasurement(
        lambda s: np.tensordot(Hl, s, axes=(1, 0)),
        lead,
        np.atleast_2d(np.asarray(R, float)),
        (False,) * H.shape[0],
    )
