"""Batched linear Kalman filter banks — eqs (45)–(52) of the mode-signature paper (47th IEEE CDC, Cancún, 2008): the prediction-error decomposition.

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

The structured path: where one state is measured (H = e_sᵀ, so S is a number and the gain a column)
and the transitions of every filter and step differ from one shared matrix A only in the entries of one
column (F_k^c = A + v_k^c e_jᵀ: the LMP banks of eq 44, whose H1 filters add the amplitude column to the
ẋ row), the recursions run on that structure (:func:`column_structure` finds it by comparing the
transitions exactly; other banks take the general stacked-matrix recursion): covariances stored as
their distinct entries with the filters last (:class:`_Packed`), so that A P Aᵀ of every filter is one
BLAS product per step and the v terms a few elementwise passes; the Joseph update in closed form; the
means of every filter and trial as one array, A x one BLAS product per step. A bank whose transition is
constant stops its Riccati recursion where the predicted covariance repeats to the last bit (its fixed
point: the remaining steps would compute the same numbers) and, with constant gains, computes its
innovations block by block in time (:func:`_steady_tail`). The two paths agree to rounding (tests).

The loops over time take an optional ``progress`` callback, called with the number of time steps done
once per block of :data:`PROGRESS_BLOCK` steps (and at the end): a long single record shows a bar.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

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
        transition: The structure of the bank's F_k found by :func:`riccati` (:class:`ColumnStructure`),
            reused by :func:`innovation_costs` and :func:`expected_costs_white_noise` when they are given
            the same ``F_at`` callable; None where the bank ran the dense recursion.
    """

    K: np.ndarray
    S_inv: np.ndarray
    logdet_2pi_S: np.ndarray
    skip: np.ndarray | None = None
    transition: ColumnStructure | None = field(default=None, repr=False, compare=False)


def _check_psd(name: str, M: np.ndarray) -> None:
    if not np.all(np.isfinite(M)):
        raise ValueError(f"{name} has non-finite entries")
    if not np.allclose(M, np.swapaxes(M, -1, -2), atol=1e-12 * max(1.0, float(np.abs(M).max()))):
        raise ValueError(f"{name} is not symmetric")
    if np.min(np.linalg.eigvalsh(M)) < -1e-12 * max(1.0, float(np.abs(M).max())):
        raise ValueError(f"{name} is not positive semi-definite")


# ---------------------------------------------------------------------------------------------------
# The structured path: H = e_sᵀ (one state measured), F_k^c = A + v_k^c e_jᵀ (the LMP banks, eq 44)
# ---------------------------------------------------------------------------------------------------

STRUCTURE_BLOCK = 64  # time steps of F_k held at once while :func:`column_structure` reads a bank


@dataclass(frozen=True)
class ColumnStructure:
    """A bank whose transitions differ from one shared matrix in a single column:
    F_k^c = A + Σ_{r ∈ rows} v[k, r, c] e_r e_colᵀ (eq 44: the H1 filters' a-column in the ẋ row).

    Attributes:
        A: The shared part (n, n), zero at the varying entries (rows, col).
        col: The column j of the varying entries (meaningless when ``rows`` is empty).
        rows: Their rows (may be empty: every filter has the transition A at every step).
        values: F_k^c at (rows, col), (N − 1, len(rows), C) (C = 1: the same for every filter).
        source: The ``F_at`` callable read (None: built directly).
    """

    A: np.ndarray
    col: int
    rows: tuple[int, ...]
    values: np.ndarray
    source: TransitionFn | None = None

    def __getstate__(self) -> dict[str, object]:
        """Pickled without ``source`` (a closure may not pickle; a copy is matched to no callable)."""
        return {**self.__dict__, "source": None}


def column_structure(F_at: TransitionFn, n_steps: int, n_filters: int, n: int) -> ColumnStructure | None:
    """The :class:`ColumnStructure` of the transitions F_at(k), k < n_steps − 1 (the ones a recursion of
    n_steps applies), found by comparing every entry of every F_k^c with filter 0's F_0, exactly; None
    where the entries that differ span more than one column, or F_at's shapes are not (n, n) or
    (n_filters, n, n) throughout.

    Each F_k is compared as it comes and the entries known to vary are copied out (F_at may return one
    array that it changes in place); every :data:`STRUCTURE_BLOCK` steps the entries that differed so far
    are collected, and a block that reveals a new varying entry is read again (the earlier blocks held
    F_0's value there)."""
    n_pred = max(n_steps - 1, 0)
    if n_pred == 0:
        return ColumnStructure(np.zeros((n, n)), 0, (), np.zeros((0, 0, 1)), F_at)
    F_first = np.asarray(F_at(0), dtype=float)
    F_first = F_first[None] if F_first.ndim == 2 else F_first
    if F_first.ndim != 3 or F_first.shape[1:] != (n, n) or F_first.shape[0] not in (1, n_filters):
        return None
    shape = F_first.shape
    ref = F_first[0].copy()
    if shape[0] == 1:  # one F for every filter: hold them all, compare once
        every = np.empty((n_pred, n, n))
        for k in range(n_pred):
            Fk = np.asarray(F_at(k), dtype=float)
            if Fk.shape != (n, n) and Fk.shape != shape:
                return None
            every[k] = Fk.reshape(n, n)
        varying = np.not_equal(every, ref).any(axis=0)
        cols = np.flatnonzero(varying.any(axis=0))
        if cols.size > 1:
            return None
        col = int(cols[0]) if cols.size else 0
        rows = tuple(int(r) for r in np.flatnonzero(varying[:, col])) if cols.size else ()
        A = ref.copy()
        A[list(rows), col] = 0.0
        return ColumnStructure(A, col, rows, every[:, list(rows), col][:, :, None], F_at)
    ref_all = np.ascontiguousarray(np.broadcast_to(ref, shape))
    differs, step_differs = np.zeros(shape, bool), np.empty(shape, bool)
    col, rows = 0, ()  # the varying entries found so far
    values: dict[int, np.ndarray] = {}  # row r ↦ F_k^c at (r, col), (N − 1, C)

    def read(start: int, stop: int, check: bool) -> bool:
        for k in range(start, stop):
            Fk = np.asarray(F_at(k), dtype=float)
            if Fk.shape != shape and Fk.shape != (n, n):
                return False
            if check:
                np.not_equal(Fk, ref_all, out=step_differs)  # NaN differs from everything
                np.logical_or(differs, step_differs, out=differs)
            for r in rows:
                values[r][k] = Fk[..., r, col]
        return True

    for start in range(0, n_pred, STRUCTURE_BLOCK):
        stop = min(start + STRUCTURE_BLOCK, n_pred)
        if not read(start, stop, True):
            return None
        varying = differs.any(axis=0)
        cols = np.flatnonzero(varying.any(axis=0))
        if cols.size > 1:
            return None
        new_rows = tuple(int(r) for r in np.flatnonzero(varying[:, cols[0]])) if cols.size else ()
        if new_rows != rows:  # entries that vary first in this block: F_0's value before it
            col = int(cols[0])
            for r in set(new_rows) - set(rows):
                values[r] = np.empty((n_pred, shape[0]))
                values[r][:start] = ref[r, col]
            rows = new_rows
            read(start, stop, False)
    A = ref.copy()
    A[list(rows), col] = 0.0
    v = np.stack([values[r] for r in rows], axis=1) if rows else np.zeros((n_pred, 0, 1))
    return ColumnStructure(A, col, rows, v, F_at)


def measured_state(H: np.ndarray) -> int | None:
    """s where H = e_sᵀ (one row, a single 1, zeros elsewhere), else None."""
    if H.shape[0] != 1:
        return None
    nz = np.flatnonzero(H[0])
    return int(nz[0]) if nz.size == 1 and H[0, nz[0]] == 1.0 else None


class _Packed:
    """Packed symmetric storage of n × n covariances, filters last, (n(n+1)/2, C): row s first (entries
    (s, j), j = 0…n−1, in state order), then the other pairs i ≤ j (those of the first varying row of F
    first). Prediction P ← F P Fᵀ (+ Q) for a :class:`ColumnStructure` F = A + v e_jᵀ:
    F P Fᵀ = A P Aᵀ + v uᵀ + u vᵀ with w = A P e_j and u = w + ½ P_jj v. A P Aᵀ (+ Q) and w are one
    product of a fixed (n(n+1)/2 + n) × (n(n+1)/2 + 1) matrix with [packed P; 1] (one BLAS call for every
    filter), the v terms a few elementwise passes over the rows of F that vary.
    """

    def __init__(self, n: int, s: int, st: ColumnStructure, Q: np.ndarray | None, n_filters: int) -> None:
        r0 = st.rows[0] if st.rows else None
        first = [] if r0 is None or r0 == s else [tuple(sorted((r0, b))) for b in range(n) if b != s]
        rest = first + [
            (i, j) for i in range(n) for j in range(i, n) if s not in (i, j) and (i, j) not in first
        ]
        pairs = [(s, j) for j in range(n)] + rest
        self.n, self.s, self.st, self.npk = n, s, st, len(pairs)
        self.ia = np.array([p[0] for p in pairs])
        self.ib = np.array([p[1] for p in pairs])
        at = {frozenset(p): q for q, p in enumerate(pairs)}
        self.Ir = np.array([i for i, _ in rest], dtype=int)  # the rest: P⁺_ij = P_ij − p_i K_j
        self.Jr = np.array([j for _, j in rest], dtype=int)
        A, c, npk = st.A, st.col, len(pairs)
        Qp = None if Q is None else self.pack(Q, n_filters)
        self.Q_folded = Qp is not None and Qp.shape[1] == 1  # a shared Q: a column of the product
        self.Q = None if Qp is None or self.Q_folded else Qp
        M = np.zeros((npk + (n if st.rows else 0), npk + 1))
        for qo, (a, b) in enumerate(pairs):
            for qi, (cc, d) in enumerate(pairs):
                M[qo, qi] = A[a, cc] * A[b, d] + (A[a, d] * A[b, cc] if cc != d else 0.0)  # (A P Aᵀ)_ab
            if self.Q_folded:
                M[qo, npk] = Qp[qo, 0]  # type: ignore[index]
        if st.rows:
            for a in range(n):  # w_a = (A P e_j)_a = Σ_c A_ac P_cj
                for cc in range(n):
                    M[npk + a, at[frozenset((cc, c))]] += A[a, cc]
        self.M = M
        self.jj = at[frozenset((c, c))]
        self.row_at = {r: np.array([at[frozenset((r, b))] for b in range(n)]) for r in st.rows}
        # the first varying row r0 ≠ s: its entry (s, r0) at index r0, the others at npk_s … (contiguous)
        self.fast_row = r0 is not None and r0 != s and (s == 0 or s == n - 1)
        self.others = slice(1, n) if s == 0 else slice(0, n - 1)
        self.half_v = 0.5 * st.values  # ½ v (exact)
        self.Pu = np.empty((npk + 1, n_filters))  # [packed P⁺; 1], the product's input
        self.Pu[npk] = 1.0
        self.out = np.empty((M.shape[0], n_filters))

    def pack(self, M: np.ndarray, n_filters: int) -> np.ndarray:
        """(n, n) or (C, n, n) → (n(n+1)/2, C) ((…, 1) for a shared (n, n))."""
        M = np.asarray(M, dtype=float)
        if M.ndim == 2:
            return M[self.ia, self.ib][:, None].copy()
        return np.ascontiguousarray(np.broadcast_to(M, (n_filters, self.n, self.n))[:, self.ia, self.ib].T)

    def predict(self, k: int) -> np.ndarray:
        """F_k P F_kᵀ + Q for the packed P in ``self.Pu[:-1]``: a view of ``self.out`` (overwritten by the
        next call)."""
        npk, st = self.npk, self.st
        out = np.matmul(self.M, self.Pu, out=self.out)
        Pn = out[:npk]
        if self.Q is not None:
            Pn += self.Q
        if st.rows:
            u = out[npk:]  # w = A P e_j
            P = self.Pu
            for i, r in enumerate(st.rows):
                u[r] += P[self.jj] * self.half_v[k, i]  # u = w + ½ P_jj v
            for i, r in enumerate(st.rows):
                t = st.values[k, i] * u  # v uᵀ + u vᵀ on row r of the packed P
                t[r] *= 2.0
                if i == 0 and self.fast_row:
                    Pn[r] += t[self.s]
                    Pn[self.n : 2 * self.n - 1] += t[self.others]
                else:
                    Pn[self.row_at[r]] += t
        return Pn


def _riccati_structured(
    st: ColumnStructure, s: int, Q: np.ndarray, r: float, P0: np.ndarray, n_steps: int, C: int,
    tick: Callable[[int], None], skip: np.ndarray | None,
) -> BankGains:  # fmt: skip
    """:func:`riccati` for H = e_sᵀ and a :class:`ColumnStructure` (the arrays are stored filters last;
    the returned fields are views in :class:`BankGains`' layout).

    A bank with a constant transition (no varying entry, no skipped step ahead) whose predicted
    covariance repeats exactly (P_{k+1} = P_k to the last bit) has reached the fixed point of its
    recursion: the remaining gains are copies, exactly what the remaining steps would compute."""
    pk = _Packed(P0.shape[-1], s, st, Q, C)
    n, npk = pk.n, pk.npk
    P = np.ascontiguousarray(np.broadcast_to(pk.pack(P0, C), (npk, C)))
    Kt = np.zeros((n_steps, n, C))
    S_all = np.ones((n_steps, C))  # S at the steps that update (1 at a skipped step)
    Ir, Jr, Pu = pk.Ir, pk.Jr, pk.Pu
    constant = not st.rows
    last_skip = -1 if skip is None else int(np.flatnonzero(skip)[-1])
    for k in range(n_steps):
        if skip is None or not skip[k]:
            p = P[:n]  # P Hᵀ = row s of P, (n, C)
            S = np.add(p[s], r, out=S_all[k])  # innovation covariance, eq (47)
            K = np.divide(p, S, out=Kt[k])  # Kalman gain P Hᵀ S⁻¹
            # Joseph form (I−KH)P(I−KH)ᵀ + K R Kᵀ, closed for H = e_sᵀ:
            np.multiply(K, r, out=Pu[:n])  # P⁺_sj = R P_sj / S
            np.subtract(P[n:], p[Ir] * K[Jr], out=Pu[n:npk])  # P⁺_ij = P_ij − P_is P_sj / S (i, j ≠ s)
        else:
            Pu[:npk] = P
        if k + 1 < n_steps:
            P_new = pk.predict(k)  # P ← F P Fᵀ + Q
            if constant and k > last_skip and np.array_equal(P_new, P):  # the fixed point: P_{k+1} = P_k
                Kt[k + 1 :] = Kt[k]
                S_all[k + 1 :] = S_all[k]
                for j in range(k, n_steps):
                    tick(j)
                break
            P = P_new.copy() if constant else P_new
        tick(k)
    S_inv = np.divide(1.0, S_all)
    logdet = np.log(2 * np.pi * S_all)
    if skip is not None:
        S_inv[skip], logdet[skip] = 0.0, 0.0
    return BankGains(Kt.transpose(2, 0, 1)[..., None], S_inv.T[:, :, None, None], logdet.T, skip, st)


def _structure_for(gains: BankGains, F_at: TransitionFn, n_steps: int, n: int) -> ColumnStructure | None:
    st = gains.transition
    if st is not None and st.source is F_at:
        return st
    return column_structure(F_at, n_steps, gains.K.shape[0], n)


def _filters_last_gains(gains: BankGains, N: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """K (N, n, C), S⁻¹ (N, C), log det(2πS) (N, C) of a bank with m = 1 (views where they are stored so)."""
    K = np.ascontiguousarray(np.moveaxis(gains.K[:, :N, :, 0], 0, -1))
    S_inv = np.ascontiguousarray(gains.S_inv[:, :N, 0, 0].T)
    return K, S_inv, np.ascontiguousarray(gains.logdet_2pi_S[:, :N].T)


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
    """Run the covariance recursion of C filters for N steps (the structured path where it applies: see the
    module docstring; the structure found is kept in the gains for :func:`innovation_costs`).

    Args:
        F_at: k ↦ transition F_k of every filter, shape (C, n, n) (or (n, n), broadcast); a function of k
            alone (it may return one array that it changes in place), called for k = 0 … N − 2.
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
    scalar = m == 1
    tick = step_reporter(progress, n_steps)
    if skip is not None:
        skip = np.asarray(skip, bool)
        if skip.shape != (n_steps,):
            raise ValueError(f"skip must be ({n_steps},) bool, got shape {skip.shape}")
        if not skip.any():
            skip = None
    s = measured_state(H)
    st = None if s is None else column_structure(F_at, n_steps, n_filters, n)
    if st is not None and s is not None:
        return _riccati_structured(st, s, Q, float(R[0, 0]), P0, n_steps, n_filters, tick, skip)
    P = np.broadcast_to(P0, (n_filters, n, n)).copy()
    K_all = np.empty((n_filters, n_steps, n, m))
    S_inv_all = np.empty((n_filters, n_steps, m, m))
    logdet_all = np.empty((n_filters, n_steps))
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
        F_at: As for :func:`riccati` (must be the same bank; the same callable reuses the structure
            :func:`riccati` found instead of reading F_at again).
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
    s = measured_state(H)
    st = None if s is None else _structure_for(gains, F_at, N, n)
    if block is not None and B > block:
        starts = range(0, B, block)
        tell = shared_progress(progress, len(starts))
        if st is not None and s is not None:
            parts = [
                _innovation_structured(st, s, gains, x0, y[b : b + block], hz, include_logdet, tell)
                for b in starts
            ]
        else:
            parts = [
                innovation_costs(
                    F_at, H, gains, x0, y[b : b + block], hz, include_logdet=include_logdet, progress=tell
                )
                for b in starts
            ]
        return np.concatenate(parts, axis=1)
    if st is not None and s is not None:
        return _innovation_structured(st, s, gains, x0, y, hz, include_logdet, progress)
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


J_BLOCK = 8  # time steps whose innovations :func:`_innovation_structured` holds before adding them to J


def _innovation_structured(
    st: ColumnStructure, s: int, gains: BankGains, x0: np.ndarray, y: np.ndarray, hz: np.ndarray,
    include_logdet: bool, progress: Progress,
) -> np.ndarray:  # fmt: skip
    """:func:`innovation_costs` for H = e_sᵀ and a :class:`ColumnStructure` (y (B, N, 1), checked).

    Means trials and filters last, x (n, B, C). A step is ν = y_k − x_s and
    x_{k+1} = A (x + K ν) + v (x + K ν)_j = A x + (A K) ν + v (x_j + K_j ν): one BLAS product A x for every
    filter and trial over the rows of A that are not rows of the identity (the others are x + (A K) ν
    as they are), (A K) for every step beforehand. The innovations of :data:`J_BLOCK` steps are held and
    added to J together, ½ Σ S⁻¹ ν² (eq 49), before every horizon."""
    B, N, _ = y.shape
    K, S_inv, logdet = _filters_last_gains(gains, N)
    C, n = K.shape[2], K.shape[1]
    A, col, rows, vals = st.A, st.col, st.rows, st.values
    AK = np.einsum("ij,kjc->kic", A, K)[:, :, None, :]  # (N, n, 1, C)
    half_s = 0.5 * S_inv  # ½ S⁻¹: (½ S⁻¹) ν² equals ½ (S⁻¹ ν²) to the last bit
    x = np.empty((n, B, C))
    x[...] = np.broadcast_to(np.asarray(x0, dtype=float), (C, n)).T[:, None, :]
    xn = np.empty_like(x)
    yT = np.ascontiguousarray(y[:, :, 0].T)[:, :, None]  # (N, B, 1)
    J = np.zeros((B, C))
    L = min(J_BLOCK, N)
    nu = np.empty((L, B, C))
    Jb, xj = np.empty((B, C)), np.empty((B, C))
    out = np.empty((C, B, hz.size))
    read_at = {int(h): np.flatnonzero(hz == h) for h in np.unique(hz)}
    skip = gains.skip
    tick = step_reporter(progress, N)
    eye = np.eye(n)
    moving = [i for i in range(n) if i in rows or not np.array_equal(A[i], eye[i])]  # rows A x changes
    lo, hi = (moving[0], moving[-1] + 1) if moving else (0, 0)
    span, kept = slice(lo, hi), [sl for sl in (slice(0, lo), slice(hi, n)) if sl.stop > sl.start]
    upd = np.empty((hi - lo, B, C))
    # (A x)_r: the rows of A with three or more entries by one product over the range they span; the
    # other rows elementwise from their one or two entries (a coefficient-1 term last)
    dense = [i for i in range(lo, hi) if np.count_nonzero(A[i]) > 2]
    d_lo, d_hi = (dense[0], dense[-1] + 1) if dense else (0, 0)
    few = {
        i: sorted(((int(j), float(A[i, j])) for j in np.flatnonzero(A[i])), key=lambda t: t[1] == 1.0)
        for i in range(lo, hi)
        if not d_lo <= i < d_hi
    }
    A_dense = np.ascontiguousarray(A[d_lo:d_hi])
    tmp_row = np.empty((B, C))
    col_kept = not lo <= col < hi  # x_{k+1, j} = x_j + K_j ν: the v term reads it from the new x
    k_end = N if rows else _steady_from(K, S_inv, skip, N)  # from k_end on: constant F and gains
    k0 = 0  # first step whose innovation is held in nu
    for k in range(k_end):
        i = k - k0
        update = skip is None or not skip[k]
        if update:
            np.subtract(yT[k], x[s], out=nu[i])  # innovation ν_k = y_k − x_s
        else:
            nu[i] = 0.0  # predict-only: no term in J
        if k + 1 < N:  # prediction x_{k+1} = F_k (x_k + K_k ν_k)
            if d_hi > d_lo:
                np.matmul(A_dense, x.reshape(n, B * C), out=xn[d_lo:d_hi].reshape(d_hi - d_lo, B * C))
            for r, terms in few.items():  # (A x)_r from its one or two entries
                if not terms:
                    xn[r] = 0.0
                    continue
                (j0, a0), rest = terms[0], terms[1:]
                if a0 == 1.0:
                    xn[r] = x[j0]
                else:
                    np.multiply(x[j0], a0, out=xn[r])
                for j, a in rest:
                    xn[r] += x[j] if a == 1.0 else np.multiply(x[j], a, out=tmp_row)
            if update:
                if hi > lo:
                    xn[span] += np.multiply(AK[k, span], nu[i], out=upd)  # + (A K) ν
                for sl in kept:
                    np.multiply(AK[k, sl], nu[i], out=xn[sl])
                    xn[sl] += x[sl]
            else:
                for sl in kept:
                    xn[sl] = x[sl]
            if rows:
                if col_kept:
                    x_j = xn[col]
                elif update:
                    x_j = np.add(x[col], np.multiply(K[k, col], nu[i], out=xj), out=xj)
                else:
                    x_j = x[col]
                for j, r in enumerate(rows):
                    xn[r] += vals[k, j] * x_j
            x, xn = xn, x
        if k + 1 in read_at or i + 1 == L or k + 1 == k_end:  # J += ½ Σ S⁻¹ ν² over the held steps
            sq = np.multiply(nu[: i + 1], nu[: i + 1], out=nu[: i + 1])  # ν² in place
            sq *= half_s[k0 : k + 1][:, None, :]
            J += np.add.reduce(sq, axis=0, out=Jb)
            if include_logdet:
                J += 0.5 * logdet[k0 : k + 1].sum(axis=0)
            k0 = k + 1
            if k + 1 in read_at:
                out[:, :, read_at[k + 1]] = J.T[:, :, None]
        tick(k)
    if k_end < N:  # the time-invariant rest, block by block
        later = sorted(h for h in read_at if h > k_end)
        ends = [h - k_end for h in later] + ([] if later and later[-1] == N else [N - k_end])
        _, sums = _steady_tail(A, s, K[k_end], half_s[k_end], x, yT[k_end:, :, 0], ends)
        for h, Jt in zip(later, sums, strict=False):
            Jh = J + Jt
            if include_logdet:
                Jh += 0.5 * logdet[k_end:h].sum(axis=0)
            out[:, :, read_at[h]] = Jh.T[:, :, None]
        for k in range(k_end, N):
            tick(k)
    return out


def _steady_from(K: np.ndarray, S_inv: np.ndarray, skip: np.ndarray | None, N: int) -> int:
    """The first step from which K and S⁻¹ stay the same and no step is skipped (N: none worth a
    :func:`_steady_tail`, under two of its blocks)."""
    same = (K == K[-1]).all(axis=(1, 2)) & (S_inv == S_inv[-1]).all(axis=1)
    if skip is not None:
        same &= ~skip
    changes = np.flatnonzero(~same)
    k = int(changes[-1]) + 1 if changes.size else 0
    return k if N - k >= 2 * TAIL_BLOCK else N


TAIL_BLOCK = 32  # time steps per block of :func:`_steady_tail`


def _steady_tail(
    A: np.ndarray, s: int, K: np.ndarray, half_s: np.ndarray, x: np.ndarray, Y: np.ndarray, ends: list[int],
) -> tuple[np.ndarray, list[np.ndarray]]:  # fmt: skip
    """The innovations' costs of a bank with constant F = A and constant gains (K (n, C), ½ S⁻¹ (C,)) from
    the means x (n, B, C) over the data Y (M, B): ½ Σ S⁻¹ ν² (eq 49) summed up to each of ``ends``
    (steps counted from the first row of Y, increasing, the last = M).

    The filter is then time-invariant and linear in the data: over m ≤ :data:`TAIL_BLOCK` steps,
    [ν_0, …, ν_{m−1}; x_m] = W_m [x_0; y_0, …, y_{m−1}], with x_i = Z_i [x_0; y] from Z_0 = [I 0],
    Z_{i+1} = A Z_i + (A K)(e_{n+i}ᵀ − e_sᵀ Z_i) (the row of ν_i: e_{n+i}ᵀ − e_sᵀ Z_i). W is built once; a
    block is one product with the block's [x_0; y] (per filter: one BLAS call when C = 1)."""
    n, B, C = x.shape
    L = TAIL_BLOCK
    AK = A @ K  # (n, C)
    Z = np.zeros((n, n + L, C))
    Z[:, :n] = np.eye(n)[:, :, None]
    rows_nu = np.empty((L, n + L, C))
    states = [Z.copy()]
    for i in range(L):
        d = np.negative(Z[s], out=rows_nu[i])
        d[n + i] += 1.0
        Z = np.einsum("ij,jqc->iqc", A, Z) + AK[:, None, :] * d[None]
        states.append(Z)
    Wc = {}  # block length m ↦ (C, m + n, n + m)
    sums: list[np.ndarray] = []
    J = np.zeros((B, C))
    xc = np.ascontiguousarray(x.transpose(2, 0, 1))  # (C, n, B)
    k0 = 0
    for k1 in ends:
        while k0 < k1:
            m = min(L, k1 - k0)
            if m not in Wc:
                W = np.concatenate([rows_nu[:m, : n + m], states[m][:, : n + m]], axis=0)  # (m + n, n + m, C)
                Wc[m] = np.ascontiguousarray(W.transpose(2, 0, 1))
            W = Wc[m]
            src = np.concatenate([xc, np.broadcast_to(Y[k0 : k0 + m][None], (C, m, B))], axis=1)
            res = np.matmul(W, src)  # (C, m + n, B)
            nu = res[:, :m]
            J += (half_s[:, None] * (nu * nu).sum(axis=1)).T
            xc = np.ascontiguousarray(res[:, m:])
            k0 += m
        sums.append(J.copy())
    return xc.transpose(1, 2, 0), sums


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
    s = measured_state(H)
    st = None if s is None else _structure_for(gains, F_at, n_steps, n)
    if st is not None and s is not None:
        return _expected_structured(st, s, gains, float(R_true[0, 0]), n_steps, hz, progress)
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


def _expected_structured(
    st: ColumnStructure, s: int, gains: BankGains, r_true: float, n_steps: int, hz: np.ndarray,
    progress: Progress,
) -> np.ndarray:  # fmt: skip
    """:func:`expected_costs_white_noise` for H = e_sᵀ and a :class:`ColumnStructure`: Σ packed, filters
    last (:class:`_Packed`). With σ = Σ e_s (row s) and c = Σ_ss + R_true, the Lyapunov update is
    Σ⁺ = Σ − K σᵀ − σ Kᵀ + c K Kᵀ = Σ − K tᵀ − t Kᵀ, t = σ − ½ c K; E[½ ν² / S] = ½ S⁻¹ c."""
    K, S_inv, _ = _filters_last_gains(gains, n_steps)
    C, n = K.shape[2], K.shape[1]
    pk = _Packed(n, s, st, None, C)
    npk, ia, ib = pk.npk, pk.ia, pk.ib
    Sig = np.zeros((npk, C))
    EJ = np.zeros(C)
    out = np.empty((C, hz.size))
    read_at = {int(h): np.flatnonzero(hz == h) for h in np.unique(hz)}
    skip = gains.skip
    tick = step_reporter(progress, n_steps)
    Pu = pk.Pu
    for k in range(n_steps):
        if skip is None or not skip[k]:
            c = Sig[s] + r_true  # E[ν²] = Σ_ss + R_true
            EJ += 0.5 * (S_inv[k] * c)  # ½ tr(S⁻¹ E[ννᵀ])
            Kk = K[k]
            t = Sig[:n] - (0.5 * c) * Kk  # σ − ½ c K
            np.subtract(Sig, Kk[ia] * t[ib], out=Pu[:npk])
            Pu[:npk] -= t[ia] * Kk[ib]  # Σ − K tᵀ − t Kᵀ
        else:
            Pu[:npk] = Sig
        if k + 1 in read_at:
            out[:, read_at[k + 1]] = EJ[:, None]
        if k + 1 < n_steps:
            Sig = pk.predict(k).copy()  # Σ ← F Σ Fᵀ
        tick(k)
    return out


@dataclass(frozen=True)
class Update:
    """One batched Kalman measurement update (leading axes are any batch of runs × models).

    Attributes:
        x, P: updated mean (..., n) and covariance (..., n, n) (Joseph form).
        nu: innovation (..., m); S_inv: its inverse covariance (..., m, m); K: gain (..., n, m).
        loglik: log N(ν; 0, S) (..., ), computed from log det S, never from a density value.
        nis: the normalised innovation squared νᵀS⁻¹ν (..., ): χ²_m for a consistent filter.
    """

    x: np.ndarray
    P: np.ndarray
    nu: np.ndarray
    S_inv: np.ndarray
    K: np.ndarray
    loglik: np.ndarray
    nis: np.ndarray


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


def _selection(H: np.ndarray) -> np.ndarray | None:
    """The components H picks, where each row of H is one 1 among 0s (H x = x[pick]); else None."""
    if H.ndim != 2 or not np.all((H == 0.0) | (H == 1.0)) or not np.all(H.sum(axis=1) == 1.0):
        return None
    return np.argmax(H, axis=1)


def joseph_update(x: np.ndarray, P: np.ndarray, z: np.ndarray, H: np.ndarray, R: np.ndarray) -> Update:
    """Measurement update of a batch of filters sharing H and R.

    ν = z − H x, S = H P Hᵀ + R, K = P Hᵀ S⁻¹, x⁺ = x + K ν,
    P⁺ = (I − K H) P (I − K H)ᵀ + K R Kᵀ (Joseph form: symmetric positive semi-definite by construction),
    log N(ν; 0, S) = −½ νᵀS⁻¹ν − ½ log det(2π S).

    Args:
        x: (..., n); P: (..., n, n); z: (..., m) broadcastable against H x; H: (m, n); R: (m, m).
    """
    m, n = H.shape
    pick = _selection(H)
    if pick is not None:  # H picks components: products with H are gathers
        nu = z - x[..., pick]
        PHt = P[..., :, pick]
        S = PHt[..., pick, :] + R
    else:
        nu = z - x @ H.T
        PHt = P @ H.T
        S = H @ PHt + R
    S_inv, logdet, ok = spd_inv_logdet(S)
    if not np.all(ok):
        raise np.linalg.LinAlgError("innovation covariance is not positive definite")
    K = PHt @ S_inv
    KT = np.swapaxes(K, -1, -2)
    if pick is not None:  # A P Aᵀ with A = I − K H applied as two rank-m corrections (no n×n products):
        AP = P - K @ P[..., pick, :]  # A P = P − K (H P)
        P_new = AP - AP[..., :, pick] @ KT + K @ R @ KT  # (A P) Aᵀ = A P − (A P) Hᵀ Kᵀ
    else:
        A = np.eye(n) - K @ H
        P_new = A @ P @ np.swapaxes(A, -1, -2) + K @ R @ KT
    P_new = 0.5 * (P_new + np.swapaxes(P_new, -1, -2))
    x_new = x + (K @ nu[..., None])[..., 0]
    maha = (nu[..., None, :] @ S_inv @ nu[..., :, None])[..., 0, 0]
    loglik = -0.5 * (maha + logdet + m * np.log(2.0 * np.pi))
    return Update(x_new, P_new, nu, S_inv, K, loglik, maha)
