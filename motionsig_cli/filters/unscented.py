"""Unscented (sigma-point) Kalman filters, batched — the radar example of the mode-signature paper (47th IEEE CDC, Cancún, 2008, §IV.B, eqs 59–62).

The scaled unscented transform (Julier 2002; Van der Merwe's parametrisation, the one FilterPy's
``MerweScaledSigmaPoints`` uses) with n states, λ = α²(n + κ) − n and c = √(n + λ)::

    χ_0 = x,  χ_j = x + c L_j,  χ_{n+j} = x − c L_j        L = lower Cholesky factor of P, L_j its columns
    W^m_0 = λ/(n+λ),  W^c_0 = W^m_0 + 1 − α² + β,  W_j = 1/(2(n+λ))  (j ≥ 1)
    ŷ = Σ W^m_i h(χ_i),  S = Σ W^c_i e_i e_iᵀ + R,  P_xy = Σ W^c_i (χ_i − x) e_iᵀ,  e_i = h(χ_i) − ŷ

Angular measurement components are averaged about the central point, ŷ = h(χ_0) + Σ W^m_i
wrap(h(χ_i) − h(χ_0)), and every residual is wrapped to (−π, π]. With d_i = wrap(h(χ_i) − h(χ_0)) and
μ = ŷ − h(χ_0) = Σ W^m_i d_i, e_i = d_i − μ needs no wrap while every angular |d_i| and |μ| is at most
π/2, and then S − R = W_j Σ_{i≥1} d_i d_iᵀ + (β − α²) μ μᵀ (e_0 = −μ; the weights give the coefficient);
the bank uses this form, and the residuals point by point otherwise.

**The reduction that makes the bank fast (exact, not an approximation).** If h reads only the leading
p state components, the sigma points χ_{±j} with j > p move no component h reads (columns j > p of
a *lower* Cholesky factor are zero in rows < j), so h(χ_{±j}) = h(χ_0), their residuals cancel in
P_xy and add 2(n − p) copies of e_0e_0ᵀ to S. Only the first p columns of L are needed; they are
the first p steps of a left-looking Cholesky factorisation. For the radar (h reads x and y, state
[x, ẋ, y, …]) p = 3: three of ten columns, 7 of 21 evaluations of h, the same numbers.

The prediction is linear and exact (x ← F x, P ← F P Fᵀ + Q: the models are linear in the state; with
linear f the UT's predicted mean and covariance are these exactly, so no sigma points are drawn for it).
It uses the structure of the LMP banks, F_k^c = F_0 + Σ_r g_r[c, k] e_{row_r} e_{col_r}ᵀ: the bank keeps
each covariance packed, its n(n+1)/2 distinct entries grouped by the blocks of F_0's coupling graph (the
radar: the x chain, the y chain, each amplitude), so F_0 P F_0ᵀ is one small BLAS product per block over
every filter and record, and the time-varying entries are rank-one row and column updates. The packed
storage keeps P exactly symmetric and halves the update P ← P − W Wᵀ.

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
from functools import cached_property
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
    """Wrap the angular components (first axis) of d to (−π, π], in place (:func:`_wrap_rows_max`)."""
    _wrap_rows_max(d, angular)
    return d


def _wrap_rows_max(d: np.ndarray, angular: np.ndarray) -> float:
    """Wrap the angular components (first axis) of d to (−π, π], in place, and return the largest
    |entry| of those rows after wrapping (0.0 without angles). Only the entries outside [−π, π] change (a
    bearing near the branch cut puts a few of them out of range at most steps; the modulo of the whole
    row cost a fifth of the radar bank's time); the others are kept exactly."""
    top = 0.0
    for a in np.flatnonzero(angular):
        row = d[a]
        big = float(np.abs(row).max())
        if big > math.pi:
            out = np.abs(row) > math.pi
            row[out] = wrap_angle(row[out])
            big = float(np.abs(row).max())
        top = max(top, big)
    return top


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
    """:func:`_left_cholesky` that repairs the matrices it cannot factor (:func:`_repair`), and counts them.

    Returns (L, the possibly repaired A, number of repaired matrices).
    """
    L, piv = _left_cholesky(A, p)
    bad = ~(piv > 0)
    if not bad.any():
        return L, A, 0
    fixed, Lb = _repair(np.moveaxis(A[..., bad], -1, 0), p, floor)
    A = A.copy()
    A[..., bad] = np.moveaxis(fixed, 0, -1)
    L[..., bad] = Lb
    return L, A, int(bad.sum())


def _repair(Ab: np.ndarray, p: int, floor: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """Repair k symmetric matrices Ab (k, n, n) that a Cholesky factorisation failed on.

    Each is symmetrised and projected onto the positive semi-definite cone by clipping its eigenvalues
    (Higham's nearest PSD matrix): at 0 above ``floor`` when one is given (an innovation covariance is the
    PSD spread of h(χ) plus R, so S is repaired to R + (S − R)₊), else at 1e-12 × its largest |eigenvalue|.
    Should that still not factor, a diagonal jitter grows ×100 from 1e-12 × the mean diagonal.

    Returns:
        The repaired matrices (k, n, n) and the first p columns of their lower Cholesky factors (n, p, k).
    """
    if not np.all(np.isfinite(Ab)):
        raise FloatingPointError("a covariance became non-finite in the sigma-point bank")
    n = Ab.shape[1]
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
    return fixed, Lb


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


# ---------------------------------------------------------------------------------------------------
# Packed covariance storage of the bank: each symmetric n × n matrix as its n(n+1)/2 distinct entries,
# grouped so that the shared prediction F_0 P F_0ᵀ is one small matrix product per group.
# ---------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Packed:
    """Layout of the bank's covariances, derived from the sparsity of F_0.

    The states fall into the components of F_0's coupling graph (states i, j coupled where F_0[i, j] ≠ 0;
    the 2-D radar: the x chain [x, ẋ, r_x, ṙ_x], the y chain and each amplitude alone). Positions order
    the states component by component; a covariance is stored as the blocks (g, h), g ≤ h, of entries
    P[a, b] with a in component g and b in component h (the lower triangle, by positions, where g = h),
    one after the other: (n(n+1)/2, ...) rows. F_0 maps each block onto itself:
    (F_0 P F_0ᵀ)[a, b] = Σ F_0[a, i] F_0[b, j] P[i, j] over i in g, j in h, a matrix ``M`` of the block's
    size (None where it is the identity), so the shared prediction is one BLAS product per block over
    every filter and record, and the exact symmetry of P is kept by construction.

    Attributes:
        perm: perm[k] = the state at position k.  pos: its inverse.
        comps: [start, stop) positions of each component, with F_0 on it (None: identity).
        blocks: (lo, hi, g, h, M): packed rows lo..hi − 1 hold block (g, h).
        index: (n, n) packed row of entry (a, b) (state indices; symmetric).
        entries: (a, b) of each packed row (state indices).
    """

    n: int
    perm: np.ndarray
    pos: np.ndarray
    comps: tuple[tuple[int, int, np.ndarray | None], ...]
    blocks: tuple[tuple[int, int, int, int, np.ndarray | None], ...]
    index: np.ndarray
    entries: np.ndarray

    @property
    def size(self) -> int:
        return self.n * (self.n + 1) // 2

    @cached_property
    def columns(self) -> np.ndarray:
        """columns[j]: the packed rows of column j (state order), rows by position, (n, n)."""
        return self.index[self.perm].T

    @cached_property
    def rows(self) -> np.ndarray:
        """rows[i]: the packed rows of row i (state order), columns by position, (n, n)."""
        return self.index[:, self.perm]

    @cached_property
    def row_runs(self) -> tuple[tuple[tuple[slice, slice], ...], ...]:
        """:attr:`rows` as runs of evenly spaced packed rows: row_runs[i] = ((dst, src), …) with
        ``Ppk[dst]`` the entries of row i at positions ``src`` (basic slices: views, no gather/scatter)."""
        return tuple(_slice_runs(r) for r in self.rows)

    @cached_property
    def unit_rows(self) -> frozenset[int]:
        """The states j whose row of F_0 is e_jᵀ (those of a component on which F_0 is the identity: the
        bank's amplitudes); for them (F_0 P F_0ᵀ)[:, j] = F_0 P[:, j]."""
        return frozenset(int(self.perm[k]) for s, e, Fg in self.comps if Fg is None for k in range(s, e))

    @cached_property
    def max_block(self) -> int:
        return max(hi - lo for lo, hi, *_ in self.blocks)

    @cached_property
    def segments(self) -> tuple[tuple[int, int, int, int, int], ...]:
        """The downdate's segments (lo, hi, i, ws, we): packed rows lo..hi − 1 are entries (i, ws..we − 1)
        (positions) of a diagonal block (i ≥ 0), or an off-diagonal block of rows ws..we − 1 and columns
        from position −i − 1 (i < 0)."""
        return tuple(s for b in self.block_segments for s in b)

    @cached_property
    def block_segments(self) -> tuple[tuple[tuple[int, int, int, int, int], ...], ...]:
        """:attr:`segments`, block by block."""
        out = []
        for lo, hi, gi, gj, _ in self.blocks:
            s1, e1, _ = self.comps[gi]
            if gi == gj:
                out.append(
                    tuple(
                        (lo + u * (u + 1) // 2, lo + u * (u + 1) // 2 + u + 1, s1 + u, s1, s1 + u + 1)
                        for u in range(e1 - s1)
                    )
                )
            else:
                out.append(((lo, hi, -self.comps[gj][0] - 1, s1, e1),))
        return tuple(out)

    def pack(self, A: np.ndarray) -> np.ndarray:
        """Symmetric A (n, n, ...) → packed (n(n+1)/2, ...) (the lower entry of each pair)."""
        a, b = self.entries.T
        return A[np.maximum(a, b), np.minimum(a, b)]

    def unpack(self, Ppk: np.ndarray) -> np.ndarray:
        """Packed (n(n+1)/2, ...) → full symmetric (n, n, ...)."""
        return Ppk[self.index]


def _slice_runs(idx: np.ndarray) -> tuple[tuple[slice, slice], ...]:
    """Split ``dst = idx[src]`` (src = 0, 1, …) into runs where both advance by a constant step."""
    runs: list[tuple[slice, slice]] = []
    a, n = 0, len(idx)
    while a < n:
        b = a + 1
        if b < n and idx[b] != idx[a]:
            step = int(idx[b] - idx[a])
            while b + 1 < n and idx[b + 1] - idx[b] == step:
                b += 1
            b += 1
            stop = int(idx[b - 1]) + (1 if step > 0 else -1)
            runs.append((slice(int(idx[a]), None if stop < 0 else stop, step), slice(a, b)))
        else:
            runs.append((slice(int(idx[a]), int(idx[a]) + 1), slice(a, a + 1)))
        a = b
    return tuple(runs)


def _packed_layout(F0: np.ndarray) -> _Packed:
    """The :class:`_Packed` layout for the shared transition F_0 (n, n)."""
    n = F0.shape[0]
    root = list(range(n))

    def find(a: int) -> int:
        while root[a] != a:
            a = root[a]
        return a

    for i, j in zip(*np.nonzero(F0), strict=True):
        ri, rj = find(int(i)), find(int(j))
        root[max(ri, rj)] = min(ri, rj)
    groups: dict[int, list[int]] = {}
    for a in range(n):
        groups.setdefault(find(a), []).append(a)
    members = sorted(groups.values())
    perm = np.array([a for g in members for a in g], dtype=np.intp)
    pos = np.argsort(perm)
    comps, start = [], 0
    for g in members:
        Fg = F0[np.ix_(g, g)]
        comps.append((start, start + len(g), None if np.array_equal(Fg, np.eye(len(g))) else Fg.copy()))
        start += len(g)
    index = np.empty((n, n), dtype=np.intp)
    entries: list[tuple[int, int]] = []
    spans = []
    for gi, (s1, e1, _) in enumerate(comps):
        for gj in range(gi, len(comps)):
            s2, e2, _ = comps[gj]
            lo = len(entries)
            for u in range(s1, e1):
                for v in range(s2, e2) if gi != gj else range(s1, u + 1):
                    index[perm[u], perm[v]] = index[perm[v], perm[u]] = len(entries)
                    entries.append((int(perm[u]), int(perm[v])))
            spans.append((lo, len(entries), gi, gj))
    blocks = []
    for lo, hi, gi, gj in spans:
        M = np.zeros((hi - lo, hi - lo))
        rows_i, rows_j = perm[comps[gi][0] : comps[gi][1]], perm[comps[gj][0] : comps[gj][1]]
        for r in range(lo, hi):
            a, b = entries[r]
            for i in rows_i:
                for j in rows_j:
                    M[r - lo, index[i, j] - lo] += F0[a, i] * F0[b, j]
        blocks.append((lo, hi, gi, gj, None if np.array_equal(M, np.eye(hi - lo)) else M))
    return _Packed(n, perm, pos, tuple(comps), tuple(blocks), index, np.array(entries, dtype=np.intp))


def _lead_cholesky(Ppk: np.ndarray, lay: _Packed, p: int, Lc: np.ndarray, tmp: np.ndarray) -> np.ndarray:
    """:func:`_left_cholesky` of packed covariances: the first p columns (in state order) of the lower
    Cholesky factor into Lc (p, n, ...) — column j, rows by position. Returns the smallest pivot of each
    matrix (...) (≤ 0 marks a failed factorisation)."""
    min_piv = np.full(Ppk.shape[1:], np.inf)
    t = tmp[: lay.n]
    for j in range(p):
        v = Lc[j]
        np.take(Ppk, lay.columns[j], axis=0, out=v, mode="clip")  # column j of P, rows by position
        pj = lay.pos[j]
        if j:  # (the rows of states above j are not needed: they are zeroed below)
            v -= np.einsum("qi...,q...->i...", Lc[:j], Lc[:j, pj], out=t)  # Σ_{q<j} L_q L_q[j]
        d = v[pj].copy()
        np.minimum(min_piv, d, out=min_piv)
        v *= 1.0 / np.sqrt(np.where(d > 0, d, np.inf))  # a failed pivot gives a zero column
        if j:
            v[lay.pos[:j]] = 0.0  # lower triangular: L[a, j] = 0 for states a < j
    return min_piv


def _repaired_lead_cholesky(
    Ppk: np.ndarray, lay: _Packed, p: int, Lc: np.ndarray, tmp: np.ndarray
) -> tuple[np.ndarray, int]:
    """:func:`_lead_cholesky` that repairs (:func:`_repair`) the covariances it cannot factor, and counts
    them. Returns (the possibly repaired packed covariances, number repaired); Lc is filled."""
    piv = _lead_cholesky(Ppk, lay, p, Lc, tmp)
    bad = ~(piv > 0)
    if not bad.any():
        return Ppk, 0
    fixed, Lb = _repair(lay.unpack(Ppk[..., bad]).transpose(2, 0, 1), p, None)  # state order
    Ppk = Ppk.copy()
    Ppk[..., bad] = lay.pack(np.moveaxis(fixed, 0, -1))
    Lc[..., bad] = np.swapaxes(Lb, 0, 1)[:, lay.perm]
    return Ppk, int(bad.sum())


def _packed_downdate(
    Ppk: np.ndarray, lay: _Packed, W: np.ndarray, tmp: np.ndarray, block: int | None = None
) -> None:
    """Ppk ← Ppk − Σ_a W_a W_aᵀ in place (W (m, n, ...) by position; tmp scratch (≥ max_block, ...)), on
    every block or on ``block`` only.

    Segment by segment (a row of a diagonal block, or a whole off-diagonal block), so each segment is read
    once while it is in cache; Σ_a W_a[i] W_a[j] as one einsum pass, then subtracted.
    """
    segments = lay.segments if block is None else lay.block_segments[block]
    for lo, hi, i, ws, we in segments:
        seg = Ppk[lo:hi]
        if i >= 0:  # row i of a diagonal block: entries (i, ws..we − 1)
            seg -= np.einsum("a...,aj...->j...", W[:, i], W[:, ws:we], out=tmp[: hi - lo])
        else:  # off-diagonal block (rows ws..we − 1) × (columns of the other component)
            s2, e2 = -i - 1, -i - 1 + (hi - lo) // (we - ws)
            blk = seg.reshape(we - ws, e2 - s2, *seg.shape[1:])
            blk -= np.einsum(
                "ar...,ac...->rc...", W[:, ws:we], W[:, s2:e2], out=tmp[: hi - lo].reshape(blk.shape)
            )


BLAS_ONE_THREAD = 1 << 18  # OpenBLAS runs a product of m·n·k ≤ 2^18 on one thread


def _thin_matmul(M: np.ndarray, X: np.ndarray, out: np.ndarray) -> None:
    """out = M @ X for a small M (r, k) and a wide X (k, N), in column chunks that BLAS runs on one thread
    each: threads cost these thin, memory-bound products far more than they bring (and on a loaded
    machine they wait for each other). out may be a view with the columns contiguous."""
    r, k = M.shape
    N = X.shape[1]
    ch = max(256, BLAS_ONE_THREAD // max(1, r * k))
    if N <= ch:
        np.matmul(M, X, out=out)
        return
    for s in range(0, N, ch):
        np.matmul(M, X[:, s : s + ch], out=out[:, s : s + ch])


def _packed_predict(
    x: np.ndarray,
    Ppk: np.ndarray,
    xn: np.ndarray,
    lay: _Packed,
    trans: StructuredTransition,
    k: int,
    q_rows: np.ndarray,
    q_vals: np.ndarray,
    tmp: np.ndarray,
    W: np.ndarray | None = None,
    Pn: np.ndarray | None = None,
) -> np.ndarray:
    """xn ← F_k x, Ppk ← F_k P F_kᵀ + Q **in place** in the packed layout (x, xn by position, (n, C, B);
    tmp scratch (≥ max(2n, max_block), C, B)). With W, P ← P − Σ_a W_a W_aᵀ first
    (:func:`_packed_downdate`), block by block, each just before its product, while it is in cache.
    With ``Pn`` (an array like Ppk) the products go straight into Pn instead (no copy back; Ppk is left
    downdated, not predicted). Returns the array that holds the prediction (Ppk or Pn).

    With F_k = F_0 + G_k, G_k = Σ_r g_r e_{i_r} e_{j_r}ᵀ (eq 44's time-varying entries)::

        F_k P F_kᵀ = F_0 P F_0ᵀ + Σ_r g_r (e_{i_r} u_rᵀ + u_r e_{i_r}ᵀ) + Σ_{r,s} g_r g_s P[j_r, j_s] e_{i_r} e_{i_s}ᵀ

    with u_r = F_0 P[:, j_r]: one matrix product per block (:class:`_Packed`) and a few row updates.
    """
    n, CB = lay.n, x[0].size
    ents = trans.entries
    m = 0 if W is None else W.shape[0]
    cols = []  # P[:, j_r] after the downdate, by position (read before the blocks are overwritten)
    if Pn is None:
        for _, j in ents:
            col = np.take(Ppk, lay.columns[j], axis=0, mode="clip")
            for a in range(m):
                col -= W[a] * W[a, lay.pos[j]]
            cols.append(col)
    for s, e, Fg in lay.comps:
        if Fg is None:
            xn[s:e] = x[s:e]
        else:
            _thin_matmul(Fg, x[s:e].reshape(e - s, CB), xn[s:e].reshape(e - s, CB))
    for bi, (lo, hi, _, _, M) in enumerate(lay.blocks):
        if W is not None:
            _packed_downdate(Ppk, lay, W, tmp, bi)
        if M is not None:
            blk = Ppk[lo:hi].reshape(hi - lo, CB)
            if Pn is not None:
                _thin_matmul(M, blk, Pn[lo:hi].reshape(hi - lo, CB))
                continue
            out = tmp[: hi - lo].reshape(hi - lo, CB)
            _thin_matmul(M, blk, out)
            blk[...] = out
        elif Pn is not None:
            Pn[lo:hi] = Ppk[lo:hi]
    # Where row j_r of F_0 is e_jᵀ for every r (the amplitudes), u_r = F_0 P[:, j_r] is column j_r of the
    # product just formed, and P[j_r, j_s] its entry j_s: no second product, no copy taken before it.
    direct = Pn is not None and all(j in lay.unit_rows for _, j in ents)
    if Pn is not None:  # Ppk now holds P − Σ W_a W_aᵀ: its columns as they are
        cols = [np.take(Pn if direct else Ppk, lay.columns[j], axis=0, mode="clip") for _, j in ents]
        Ppk = Pn
    if ents:
        u = tmp[:n]
        # g_r of every filter spread over the records, (C, B): a (C, 1) factor against (…, C, B) would
        # broadcast in inner loops of B elements only (measured: 1.5 % of the bank's time)
        gk = [np.repeat(trans.g[:, k, r, None], x.shape[-1], axis=1) for r in range(len(ents))]
        for r, (i, j) in enumerate(ents):
            xn[lay.pos[i]] += gk[r] * x[lay.pos[j]]  # G_k x
            if direct:
                np.multiply(cols[r], gk[r], out=u)
            else:
                for s, e, Fg in lay.comps:  # u_r = F_0 P[:, j]
                    if Fg is None:
                        u[s:e] = cols[r][s:e]
                    else:
                        _thin_matmul(Fg, cols[r][s:e].reshape(e - s, CB), u[s:e].reshape(e - s, CB))
                u *= gk[r]
            u[lay.pos[i]] *= 2.0  # the diagonal entry (i, i) gets both terms
            for dst, src in lay.row_runs[i]:
                Ppk[dst] += u[src]  # g_r (e_i u_rᵀ + u_r e_iᵀ)
        for r, (ir, _) in enumerate(ents):
            for s, (is_, js) in enumerate(ents):
                if ir >= is_:  # each stored entry (i_r, i_s) once
                    Ppk[lay.index[ir, is_]] += (gk[r] * gk[s]) * cols[r][lay.pos[js]]
    for row, qv in zip(q_rows, q_vals, strict=True):
        Ppk[row] += qv  # + Q
    return Ppk


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
    states: Sequence[int] | None = None,
) -> BankCosts:
    """Run C unscented filters on B records at once and read their innovation costs at the horizons.

    Every filter starts from the predicted prior (x0, P0) at k = 0, updates with y_0, then predicts
    with F_0 to k = 1, and so on (the convention of :mod:`motionsig_cli.filters.kalman`). The covariances
    are kept packed (:class:`_Packed`); the prediction is :func:`_packed_predict`.

    **Smaller filters in the same bank** (``states``): filter c may have n_c ≤ n states, the others
    padding that nothing couples to them (F_0, that filter's time-varying entries, Q and P0 zero between
    the two sets). Its lead Cholesky columns are then zero on the padding, so only its weights differ:
    the UT of an n_c-state filter (λ, c and the centre weight from n_c), computed exactly. The radar
    detector runs its 8-state H0 filter this way beside the 10-state H1 filters: one bank, not a second
    bank of one filter whose time goes to per-step overheads.

    Args:
        trans: The bank's transitions (C filters, N ≥ number of samples).
        Q: Process noise (n, n), symmetric, or one per filter (C, n, n).
        meas: Measurement model (m components).
        x0: Prior mean (n,).  P0: Prior covariance (n, n).
        y: Records (B, N) for m = 1 or (B, N, m); a NaN sample (every component) is missing: predict-only.
        horizons: Sample counts at which to read the costs (1 ≤ n ≤ N).
        params: Sigma-point parameters.
        progress: Called with the number of time steps done, once per block of steps (see
            :func:`motionsig_cli.filters.kalman.step_reporter`).
        states: The number of states of each filter, C values in lead … n (default: n for all).
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
    Q = np.asarray(Q, float)
    n_c = _checked_states(states, trans, Q, np.asarray(P0, float), p)
    wc0, wj, c = _bank_weights(params, n_c, B)  # W^m_0 drops out: ŷ is taken about χ_0
    ang = np.asarray(meas.angular, bool)
    Rm = np.asarray(meas.R, float)[:, :, None, None]
    lay = _packed_layout(np.asarray(trans.F0, float))
    if Q.ndim == 3:  # one Q per filter: its entries spread over the records, (rows, C, B)
        Qpk = lay.pack(np.moveaxis(Q, 0, -1))  # (size, C)
        q_rows = np.flatnonzero(np.any(Qpk != 0, axis=1))
        q_vals = np.repeat(Qpk[q_rows][:, :, None], B, axis=2)
    else:
        Qpk = lay.pack(Q)
        q_rows = np.flatnonzero(Qpk)
        q_vals = Qpk[q_rows]
    yk_all = np.ascontiguousarray(np.moveaxis(y, 0, -1))[:, :, None, :]  # (N, m, 1, B)
    x = np.broadcast_to(np.asarray(x0, float)[lay.perm, None, None], (n, C, B)).copy()  # by position
    Ppk = np.broadcast_to(lay.pack(np.asarray(P0, float))[:, None, None], (lay.size, C, B)).copy()
    xn = np.empty_like(x)
    P_spare = np.empty_like(Ppk)  # the prediction goes here, then the two swap
    tmp = np.empty((max(2 * n, lay.max_block), C, B))  # scratch
    Lc = np.empty((p, n, C, B))  # the first p columns of chol(P), rows by position
    W = np.empty((m, n, C, B))
    J = np.zeros((C, B))
    LD = np.zeros((C, B))
    J_out = np.empty((C, B, hz.size))
    LD_out = np.empty((C, B, hz.size))
    read_at = {int(h): np.flatnonzero(hz == h) for h in np.unique(hz)}
    rep_P = rep_S = 0
    half_log2pi = 0.5 * m * math.log(2 * math.pi)
    n_w = n_c if np.ndim(wj) else int(n_c[0, 0])  # the filters' sizes, or the one size
    w_e0 = wc0 + 2 * (n_w - p) * wj  # χ_0 and the 2(n_c − p) points that move nothing h reads
    c_mu = w_e0 + 2 * p * wj - 2.0  # = β − α²: the weight of μ μᵀ in S from the d_i
    tick = step_reporter(progress, N)
    some_missing = missing.any(axis=0)  # (N,)
    none_present = ~present.any(axis=0)
    eye_pk = lay.pack(np.eye(n))[:, None, None]
    lead = lay.pos[:p]  # positions of the states h reads
    X = np.empty((p, 2 * p + 1, C, B))  # the sigma points on the lead components
    for k in range(N):
        pk: np.ndarray | None = None  # the records measured at k, where some are not
        if some_missing[k] and not none_present[k]:
            pk = present[:, k]
        if not none_present[k]:
            # --- sigma points along the first p columns of chol(P) --------------------------------
            if pk is None:
                Ppk, nb = _repaired_lead_cholesky(Ppk, lay, p, Lc, tmp)  # Lc (p, n, C, B)
            else:  # the missing records' P stays out of the factorisation (and the repair count)
                P_fact, nb = _repaired_lead_cholesky(np.where(pk, Ppk, eye_pk), lay, p, Lc, tmp)
                Ppk = np.where(pk, P_fact, Ppk)
            rep_P += nb
            xl = x[lead][:, None]  # (p, 1, C, B)
            step = c * np.swapaxes(Lc[:, lead], 0, 1)  # step[:, j] = c L_j on the lead components
            X[:, :1] = xl
            np.add(xl, step, out=X[:, 1 : p + 1])
            np.subtract(xl, step, out=X[:, p + 1 :])
            Y = meas.h(X)  # (m, 2p + 1, C, B): h(χ_0), h(χ_{+j}), h(χ_{−j})
            D = Y[:, 1:] - Y[:, :1]  # d_i = h(χ_i) − h(χ_0), i = 1 … 2p
            turn = _wrap_rows_max(D, ang)  # angles wrapped; the largest |d_i| of an angle
            mu = wj * D.sum(1)  # μ = ŷ − h(χ_0) = Σ W^m_i d_i (angles averaged about χ_0)
            y_hat = _wrap_rows(Y[:, 0] + mu, ang)  # Σ W^m_i h(χ_i)
            S = np.empty((m, m, C, B))
            if turn <= 0.5 * math.pi and not np.any(np.abs(mu[ang]) > 0.5 * math.pi):
                # e_i = h(χ_i) − ŷ = d_i − μ needs no wrap (|d_i − μ| < π), and e_0 = −μ, so with
                # Σ_i W^m_i d_i = μ: S − R = Σ W^c_i e_i e_iᵀ = W_j Σ_{i≥1} d_i d_iᵀ + (β − α²) μ μᵀ
                for a in range(m):
                    for b in range(a + 1):
                        Sab = np.einsum("icb,icb->cb", D[a], D[b], out=S[a, b])  # one pass, measured
                        Sab *= wj
                        Sab += c_mu * mu[a] * mu[b]
                        S[b, a] = Sab
                dpm = D[:, :p] - D[:, p:]  # e_{+j} − e_{−j} = d_{+j} − d_{−j}
            else:  # a bearing spread over more than a quarter turn: e_i = wrap(h(χ_i) − ŷ), as FilterPy
                E = _wrap_rows(Y - y_hat[:, None], ang)
                for a in range(m):
                    for b in range(a + 1):
                        Sab = np.einsum("icb,icb->cb", E[a, 1:], E[b, 1:], out=S[a, b])
                        Sab *= wj
                        Sab += w_e0 * E[a, 0] * E[b, 0]
                        S[b, a] = Sab
                dpm = E[:, 1 : p + 1] - E[:, p + 1 :]
            S += Rm  # S = Σ W^c_i e_i e_iᵀ + R
            if pk is not None:
                S = np.where(pk, S, Rm)  # a missing record's S is never used: keep it out of the repairs
            # --- innovation, likelihood and update ------------------------------------------------
            Ls, S, nbs = _repaired_cholesky(S, m, floor=Rm[:, :, 0, 0])  # S = L_S L_Sᵀ, (m, m, C, B)
            rep_S += nbs
            nu = _wrap_rows(yk_all[k] - y_hat, ang)  # ν_k, eq (47), bearing wrapped
            if pk is not None:
                nu = np.where(pk, nu, 0.0)  # no innovation where the sample is missing
            u = _forward(Ls, nu)  # L_S⁻¹ ν
            J += 0.5 * (u * u).sum(0)  # ½ νᵀ S⁻¹ ν, eq (52)
            ld = np.log(np.diagonal(Ls, axis1=0, axis2=1)).sum(-1) + half_log2pi  # ½ log det 2πS
            LD += ld if pk is None else np.where(pk, ld, 0.0)
            # P_xy = Σ W^c_i (χ_i − x) e_iᵀ = W c Σ_j L_j (e_{+j} − e_{−j})ᵀ = L_{:p} Dᵀ, so the gain's
            # square root W = P_xy L_S⁻ᵀ = L_{:p} (L_S⁻¹ D)ᵀ: G = L_S⁻¹ D is m × p, W[a] = Σ_j G[a, j] L_j
            G = _forward(Ls[:, :, None], (wj * c) * dpm)  # (m, p, C, B)
            if pk is not None:
                G = np.where(pk, G, 0.0)  # no gain: x and P carry over
            # (one einsum pass for each sum of products: a third fewer passes than a multiply and an add
            # per term, measured)
            np.einsum("jicb,ajcb->aicb", Lc, G, out=W)  # W[a] = Σ_j G[a, j] L_j
            x += np.einsum("aicb,acb->icb", W, u, out=tmp[:n])  # x + K ν with K = P_xy S⁻¹ = W L_S⁻¹
            if k + 1 == N:
                _packed_downdate(Ppk, lay, W, tmp)  # P − K S Kᵀ = P − W Wᵀ
        if k + 1 in read_at:
            J_out[:, :, read_at[k + 1]] = J[..., None]
            LD_out[:, :, read_at[k + 1]] = LD[..., None]
        if k + 1 < N:  # (P − W Wᵀ first where k was measured), then the prediction
            Wk = None if none_present[k] else W
            Ppk, P_spare = _packed_predict(x, Ppk, xn, lay, trans, k, q_rows, q_vals, tmp, Wk, P_spare), Ppk
            x, xn = xn, x
        tick(k)
    if not (np.all(np.isfinite(J_out)) and np.all(np.isfinite(LD_out))):
        raise FloatingPointError("the sigma-point bank produced a non-finite cost")
    P_full = lay.unpack(Ppk)
    return BankCosts(
        J_out, LD_out, rep_P, rep_S, np.moveaxis(x[lay.pos], 0, -1), np.moveaxis(P_full, (0, 1), (-2, -1))
    )


def _checked_states(
    states: Sequence[int] | None, trans: StructuredTransition, Q: np.ndarray, P0: np.ndarray, p: int
) -> np.ndarray:
    """The filters' state counts (C,), refused (ValueError) unless each filter's padding is uncoupled."""
    n, C = trans.F0.shape[0], trans.n_filters
    if Q.shape not in ((n, n), (C, n, n)):
        raise ValueError(f"Q must be (n, n) or (C, n, n) = ({C}, {n}, {n}), not {Q.shape}")
    if states is None:
        return np.full((C, 1), n)
    n_c = np.asarray(states, dtype=int).reshape(-1)
    if n_c.shape != (C,) or n_c.min() < p or n_c.max() > n:
        raise ValueError(f"states must be {C} numbers in {p}..{n}")
    F0 = np.asarray(trans.F0, float)
    for k in np.unique(n_c[n_c < n]):
        pad = np.arange(n) >= k
        cross = np.ix_(~pad, pad)
        Qs = Q[n_c == k] if Q.ndim == 3 else Q[None]
        touched = [r for r, (i, j) in enumerate(trans.entries) if pad[i] != pad[j]]
        if (
            np.any(F0[cross]) or np.any(F0.T[cross]) or np.any(P0[cross]) or np.any(Qs[:, ~pad][:, :, pad])
            or np.any(trans.g[np.ix_(n_c == k, np.arange(trans.g.shape[1]), touched)])
        ):  # fmt: skip
            raise ValueError(f"the filters of {k} states are coupled to their padding states {k}..{n - 1}")
    return n_c[:, None]


def _bank_weights(params: SigmaPointParams, n_c: np.ndarray, B: int) -> tuple[Any, Any, Any]:
    """(W^c_0, W_j, c) for filters of n_c states (C, 1): numbers where all filters have the same size, else
    (C, B) arrays (spread over the records: a (C, 1) factor would broadcast in short inner loops)."""
    sizes = np.unique(n_c)
    if sizes.size == 1:
        _, wc0, wj, c = params.weights(int(sizes[0]))
        return wc0, wj, c
    table = {int(k): params.weights(int(k)) for k in sizes}
    out = [np.array([table[int(k)][i] for k in n_c[:, 0]]) for i in (1, 2, 3)]
    return tuple(np.repeat(w[:, None], B, axis=1) for w in out)  # type: ignore[return-value]


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
