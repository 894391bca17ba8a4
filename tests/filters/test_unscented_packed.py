"""The sigma-point bank's packed covariance storage and its closed-form prediction, against dense matrices."""

import numpy as np
import pytest

from motionsig_cli.filters import unscented as U
from motionsig_cli.models.vehicle2d import AMPLITUDE_ENTRIES_2D, Q1_2D, transition_h1_2d_base


def _spd_bank(rng, n, C, B):
    A = rng.normal(size=(n, n + 2, C, B))
    return np.einsum("ikcb,jkcb->ijcb", A, A) / n + 0.1 * np.eye(n)[:, :, None, None]


def _cases():
    """The radar H1 model (x chain, y chain, two amplitudes: 4 components, two time-varying entries that
    cross them) and a random sparse model with a full Q and an entry inside a component."""
    yield transition_h1_2d_base(0.05, (100.0, 17.0)), AMPLITUDE_ENTRIES_2D, np.diag(Q1_2D)
    rng = np.random.default_rng(1)
    F0 = np.eye(7)
    F0[0, 3], F0[3, 0], F0[1, 5], F0[5, 6], F0[2, 2] = (
        0.3,
        -0.2,
        0.7,
        1.1,
        0.9,
    )  # components {0,3} {1,5,6} {2} {4}
    Qf = rng.normal(size=(7, 7))
    yield F0, ((0, 4), (6, 2), (3, 3)), Qf @ Qf.T


def test_layout_packs_every_entry_once_and_round_trips():
    F0, _, _ = next(_cases())
    lay = U._packed_layout(F0)
    n = F0.shape[0]
    assert sorted(lay.index[np.tril_indices(n)]) == list(range(n * (n + 1) // 2))
    assert np.array_equal(lay.index, lay.index.T)
    comps = [sorted(lay.perm[s:e].tolist()) for s, e, _ in lay.comps]
    assert comps == [[0, 1, 4, 5], [2, 3, 6, 7], [8], [9]]  # the x and y chains, each amplitude alone
    assert lay.unit_rows == {8, 9}  # F_0 leaves the amplitudes alone: their product columns are F_0 P[:, j]
    other = U._packed_layout(list(_cases())[1][0])
    assert other.unit_rows == {4}  # state 2 is alone too, but F_0[2, 2] = 0.9
    P = _spd_bank(np.random.default_rng(2), n, 3, 2)
    assert np.array_equal(lay.unpack(lay.pack(P)), P)


@pytest.mark.parametrize("case", list(range(2)))
@pytest.mark.parametrize("downdate", [False, True])
@pytest.mark.parametrize("into_spare", [False, True])
def test_packed_prediction_equals_dense(case, downdate, into_spare):
    """F_k (P − Σ W_a W_aᵀ) F_kᵀ + Q from the packed blocks and rank-one terms equals the dense product of
    the filters' F_k (StructuredTransition.dense), with and without the fused downdate, in place or into
    a second array (the bank's loop)."""
    F0, entries, Q = list(_cases())[case]
    rng = np.random.default_rng(3 + case)
    n, C, B, k = F0.shape[0], 4, 3, 2
    tr = U.StructuredTransition(F0, entries, rng.normal(size=(C, 5, len(entries))))
    lay = U._packed_layout(F0)
    x = rng.normal(size=(n, C, B))
    P = _spd_bank(rng, n, C, B)
    W = 0.1 * rng.normal(size=(2, n, C, B)) if downdate else None
    Ppk = np.ascontiguousarray(lay.pack(P))
    xn = np.empty_like(x)
    Qpk = lay.pack(Q)
    rows = np.flatnonzero(Qpk)
    tmp = np.empty((max(2 * n, lay.max_block), C, B))
    spare = np.full_like(Ppk, np.nan) if into_spare else None
    Ppk = U._packed_predict(
        np.ascontiguousarray(x[lay.perm]), Ppk, xn, lay, tr, k, rows, Qpk[rows], tmp,
        None if W is None else np.ascontiguousarray(W[:, lay.perm]), spare,
    )  # fmt: skip
    assert (Ppk is spare) == into_spare
    F = tr.dense(k)  # (C, n, n)
    Pd = P - (0 if W is None else np.einsum("aicb,ajcb->ijcb", W, W))
    ref = np.einsum("cik,klcb,cjl->ijcb", F, Pd, F) + Q[:, :, None, None]
    np.testing.assert_allclose(lay.unpack(Ppk), ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    np.testing.assert_allclose(xn[lay.pos], np.einsum("cij,jcb->icb", F, x), rtol=1e-12, atol=1e-12)


def test_lead_cholesky_equals_numpy():
    """The first p columns of chol(P) from the packed storage (rows by position) equal numpy's factor."""
    F0, _, _ = next(_cases())
    lay = U._packed_layout(F0)
    rng = np.random.default_rng(4)
    P = _spd_bank(rng, 10, 3, 2)
    Lc = np.empty((3, 10, 3, 2))
    piv = U._lead_cholesky(np.ascontiguousarray(lay.pack(P)), lay, 3, Lc, np.empty((10, 3, 2)))
    ref = np.linalg.cholesky(np.moveaxis(P, (0, 1), (-2, -1)))[..., :3]  # (C, B, n, p)
    np.testing.assert_allclose(np.moveaxis(Lc[:, lay.pos], (0, 1), (-1, -2)), ref, rtol=1e-12, atol=1e-14)
    assert np.all(piv > 0)


def test_slice_runs_cover_every_index_with_views():
    """The row updates' runs of slices address exactly ``dst = idx[src]``, in any order of idx (the packed
    rows of a state's row rise, fall and jump), and the layout's runs are those of its rows."""
    rng = np.random.default_rng(5)
    cases = [np.arange(7), np.arange(7)[::-1], np.array([3]), np.array([0, 2, 4, 9, 8, 7, 1])]
    cases += [rng.permutation(12) for _ in range(20)]
    for idx in cases:
        runs = U._slice_runs(idx)
        dst = np.concatenate([np.arange(60)[d] for d, _ in runs])
        src = np.concatenate([np.arange(len(idx))[s] for _, s in runs])
        assert np.array_equal(np.sort(src), np.arange(len(idx)))
        assert np.array_equal(dst, idx[src])
    F0, _, _ = next(_cases())
    lay = U._packed_layout(F0)
    for i in range(F0.shape[0]):
        A = np.arange(lay.size, dtype=float)
        got = np.concatenate([A[d] for d, _ in lay.row_runs[i]])
        want = A[lay.rows[i]][np.concatenate([np.arange(F0.shape[0])[s_] for _, s_ in lay.row_runs[i]])]
        assert np.array_equal(got, want)
