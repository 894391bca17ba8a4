"""The structured Kalman bank (H = e_sᵀ, F_k^c = A + v_k^c e_jᵀ, the LMP banks of eq 44) against two
independent implementations: the dense stacked-matrix recursion of the same module (forced by making
the structure search fail) and a textbook single-filter loop."""

import numpy as np
import pytest

import motionsig_cli.filters.kalman as kal
from motionsig_cli.filters.kalman import (
    column_structure,
    expected_costs_white_noise,
    innovation_costs,
    measured_state,
    riccati,
)


def _structured_bank(rng, C, n, N, rows, col, shared_Q=True):
    """A stable bank: A = 0.8 I + small coupling, entries (rows, col) varying per filter and step."""
    A = 0.8 * np.eye(n) + rng.normal(scale=0.1, size=(n, n))
    F = np.repeat(np.repeat(A[None, None], C, axis=0), N, axis=1)  # (C, N, n, n)
    for r in rows:
        F[:, :, r, col] = rng.normal(scale=0.3, size=(C, N))
    G = rng.normal(size=(n, n))
    Q = 0.1 * G @ G.T + 0.01 * np.eye(n)
    if not shared_Q:
        Q = Q[None] * rng.uniform(0.5, 2.0, size=(C, 1, 1))
    P0 = np.eye(n) * 2.0
    return F, Q, P0


def _lmp_bank(seed, C, N, B, r):
    """The LMP-shaped bank (5 states, the a-column in row 1, the first state measured with variance r), B
    records of white noise and the bank's gains: F, Q, P0, H, y, gains."""
    rng = np.random.default_rng(seed)
    F, Q, P0 = _structured_bank(rng, C, 5, N, (1,), 4)
    H = np.array([[1.0, 0, 0, 0, 0]])
    y = rng.normal(size=(B, N))
    gains = riccati(lambda k: F[:, k], H, Q, np.array([[r]]), P0, N, C)
    return F, Q, P0, H, y, gains


def _dense(monkeypatch):
    monkeypatch.setattr(kal, "column_structure", lambda *a, **k: None)


CASES = [  # (n, s, rows, col, skip, shared_Q, include_logdet, B)
    (5, 0, (1,), 4, False, True, False, 3),
    (5, 0, (1,), 4, True, True, True, 20),  # B ≥ 16: the J buffer of 8 steps, several flushes
    (4, 2, (0, 3), 1, False, False, True, 2),  # H in the middle, two varying rows, Q per filter
    (3, 2, (2,), 2, True, True, False, 17),  # the varying entry is on the measured row and column
    (4, 1, (), 0, False, True, True, 2),  # constant F: no varying entry
]


@pytest.mark.parametrize(("n", "s", "rows", "col", "with_skip", "shared_Q", "logdet", "B"), CASES)
def test_structured_equals_dense(monkeypatch, n, s, rows, col, with_skip, shared_Q, logdet, B):
    """Gains, costs and white-noise expectations agree with the dense recursion to rounding (1e-12)."""
    rng = np.random.default_rng(n * 100 + s * 10 + len(rows))
    C, N = 4, 90
    F, Q, P0 = _structured_bank(rng, C, n, N, rows, col, shared_Q)
    H = np.zeros((1, n))
    H[0, s] = 1.0
    R = np.array([[0.3]])
    skip = np.zeros(N, bool)
    if with_skip:
        skip[[5, 6, 40]] = True
    y = rng.normal(size=(B, N))
    y[:, skip] = np.nan
    x0 = rng.normal(size=n)
    hz = [1, 7, 40, 63, 90]

    def F_at(k):
        return F[:, k]

    def run():
        g = riccati(F_at, H, Q, R, P0, N, C, skip=skip if with_skip else None)
        J = innovation_costs(F_at, H, g, x0, y, hz, include_logdet=logdet)
        EJ = expected_costs_white_noise(F_at, H, g, np.array([[0.5]]), N, hz)
        return g, J, EJ

    g_fast, J_fast, E_fast = run()
    assert g_fast.transition is not None and g_fast.transition.rows == tuple(sorted(rows))
    with monkeypatch.context() as mp:
        _dense(mp)
        g_ref, J_ref, E_ref = run()
    assert g_ref.transition is None
    for a, b in ((g_fast.K, g_ref.K), (g_fast.S_inv, g_ref.S_inv), (g_fast.logdet_2pi_S, g_ref.logdet_2pi_S)):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(J_fast, J_ref, rtol=1e-12)
    np.testing.assert_allclose(E_fast, E_ref, rtol=1e-12)


def _textbook(F, H, Q, R, P0, x0, y):
    """One filter, standard-form update: cumulative ½ Σ ν²/S after each step."""
    x, P, J, out = x0.copy(), P0.copy(), 0.0, []
    for k in range(len(y)):
        S = (H @ P @ H.T)[0, 0] + R
        K = (P @ H.T)[:, 0] / S
        nu = y[k] - (H @ x)[0]
        J += 0.5 * nu * nu / S
        out.append(J)
        x = F[k] @ (x + K * nu)
        P = F[k] @ (P - np.outer(K, K) * S) @ F[k].T + Q
    return np.array(out)


def test_structured_equals_textbook_loop():
    """The LMP-shaped bank (5 states, the a-column in row 1) on 20 records against a per-filter loop."""
    C, n, N, B = 6, 5, 120, 20
    F, Q, P0, H, y, gains = _lmp_bank(7, C, N, B, 0.4)
    J = innovation_costs(lambda k: F[:, k], H, gains, np.zeros(n), y, [30, N])
    for c in range(C):
        for b in (0, 7, B - 1):
            ref = _textbook(F[c], H, Q, 0.4, P0, np.zeros(n), y[b])
            np.testing.assert_allclose(J[c, b], ref[[29, N - 1]], rtol=1e-10)


def test_steady_gains_and_time_invariant_tail(monkeypatch):
    """A constant bank reaches the fixed point of its Riccati recursion (the gains are then copied) and
    its innovations run block by block in time; both agree with the dense step-by-step recursion."""
    rng = np.random.default_rng(3)
    n, N, B = 4, 400, 30
    A = 0.9 * np.eye(n) + rng.normal(scale=0.05, size=(n, n))
    H = np.array([[1.0, 0, 0, 0]])
    Q, P0, R = 0.05 * np.eye(n), np.eye(n), np.array([[0.2]])
    y = rng.normal(size=(B, N))
    hz = [3, 100, 257, N]
    g = riccati(lambda k: A, H, Q, R, P0, N, 1)
    assert kal._steady_from(g.K[0][..., 0][:, :, None], g.S_inv[0, :, 0, 0][:, None], None, N) < N - 64
    J = innovation_costs(lambda k: A, H, g, np.zeros(n), y, hz, include_logdet=True)
    with monkeypatch.context() as mp:
        _dense(mp)
        g_ref = riccati(lambda k: A, H, Q, R, P0, N, 1)
        J_ref = innovation_costs(lambda k: A, H, g_ref, np.zeros(n), y, hz, include_logdet=True)
    np.testing.assert_allclose(g.K, g_ref.K, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(J, J_ref, rtol=1e-12)


def test_record_blocks_do_not_change_costs():
    C, n, N, B = 3, 5, 50, 21
    F, _, _, H, y, g = _lmp_bank(11, C, N, B, 0.3)
    whole = innovation_costs(lambda k: F[:, k], H, g, np.zeros(n), y, [N])
    parts = innovation_costs(lambda k: F[:, k], H, g, np.zeros(n), y, [N], block=4)
    np.testing.assert_allclose(parts, whole, rtol=1e-13)


def test_column_structure_found_exactly():
    """One array changed in place by F_at (as lmp_detect's), an entry that starts to vary only after the
    first block, a shared (n, n) F, and two varying columns (no structure)."""
    rng = np.random.default_rng(0)
    C, n, N = 3, 4, 200
    base = rng.normal(size=(n, n))
    g = rng.normal(size=(C, N))
    g[:, :150] = base[2, 3]  # constant (= F_0's entry) for the first two blocks of 64 steps
    F = np.repeat(base[None], C, axis=0)

    def F_at(k):
        F[:, 2, 3] = g[:, k]
        return F

    st = column_structure(F_at, N, C, n)
    assert st is not None and st.col == 3 and st.rows == (2,)
    np.testing.assert_array_equal(st.values[:, 0], g[:, : N - 1].T)
    expected_A = base.copy()
    expected_A[2, 3] = 0.0
    np.testing.assert_array_equal(st.A, expected_A)
    shared = column_structure(lambda k: base, N, C, n)
    assert shared is not None and shared.rows == () and shared.values.shape == (N - 1, 0, 1)
    two = np.repeat(base[None], N, axis=0)
    two[:, 0, 0] += np.arange(N)
    two[:, 1, 2] += np.arange(N)
    assert column_structure(lambda k: two[k], N, 1, n) is None
    assert column_structure(lambda k: np.eye(n + 1), N, 1, n) is None  # wrong shape


def test_measured_state():
    assert measured_state(np.array([[0.0, 1.0, 0.0]])) == 1
    assert measured_state(np.array([[1.0, 0.0]])) == 0
    assert measured_state(np.array([[2.0, 0.0]])) is None
    assert measured_state(np.array([[1.0, 1.0]])) is None
    assert measured_state(np.eye(2)) is None


def test_gains_pickle_without_the_callable():
    """Gains travel between processes: the structure pickles, without the (unpicklable) closure."""
    import pickle

    F = np.array([[1.0, 0.1], [0.0, 1.0]])
    g = riccati(lambda k: F, np.array([[1.0, 0.0]]), 0.01 * np.eye(2), np.array([[0.1]]), np.eye(2), 50, 1)
    back = pickle.loads(pickle.dumps(g))
    assert back.transition is not None and back.transition.source is None
    np.testing.assert_array_equal(back.K, g.K)


def test_sparse_transition_rows(monkeypatch):
    """The 1-D LMP model's F (eq 44: rows of one or two entries next to the closed-loop row and the
    identity rows) and a sparse one with an empty row, against the dense recursion."""
    from motionsig_cli.models.vehicle import Vehicle1D, transition_h0

    rng = np.random.default_rng(5)
    C, N, B = 5, 80, 4
    lmp = np.zeros((5, 5))
    lmp[:4, :4] = transition_h0(Vehicle1D())
    lmp[4, 4] = 1.0
    odd = np.array([[0.0, 0.0, 0.0, 0.0], [0.3, 1.0, 0.0, 0.0], [0.0, 0.0, 0.7, 0.2], [0.1, 0.0, 0.0, 1.0]])
    for base, (r, c) in ((lmp, (1, 4)), (odd, (2, 0))):
        n = base.shape[0]
        F = np.repeat(np.repeat(base[None, None], C, axis=0), N, axis=1)
        F[:, :, r, c] = rng.normal(scale=0.2, size=(C, N))
        H = np.zeros((1, n))
        H[0, 0] = 1.0
        Q, R, P0 = np.diag(rng.uniform(0.01, 0.5, n)), np.array([[0.2]]), np.eye(n)
        y = rng.normal(size=(B, N))

        def run(F=F, H=H, Q=Q, n=n, R=R, P0=P0, y=y):
            g = riccati(lambda k: F[:, k], H, Q, R, P0, N, C)
            return innovation_costs(lambda k: F[:, k], H, g, np.zeros(n), y, [N // 2, N])

        fast = run()
        with monkeypatch.context() as mp:
            _dense(mp)
            ref = run()
        np.testing.assert_allclose(fast, ref, rtol=1e-12)
