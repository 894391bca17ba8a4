"""Missed scans in the IMM (filters/imm.py): a NaN measurement is a predict-only step — mixing and the
model-matched predictions run, the update is skipped, every model's likelihood is 1, so the model
probabilities follow the Markov chain alone.

The references here are independent plain-numpy loops written in this file (a Kalman filter, a textbook IMM
with its update skipped at the missed scans); they use nothing from motionsig_cli but the model matrices they
are handed."""

import numpy as np
import pytest

from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.models.motion import H_POS6, ModelSet, imm_models, two_point_init

T, SIGMA = 1.0, 50.0
R = SIGMA**2 * np.eye(2)
H = np.array([[1.0, 0, 0, 0, 0, 0], [0, 0, 1.0, 0, 0, 0]])


def _ca_model(T: float, q: float) -> tuple[np.ndarray, np.ndarray]:
    """A constant-acceleration model written out here: Φ and the white-noise-jerk Q = q G Gᵀ,
    G = (T²/2, T, 1) per axis, state [x, ẋ, y, ẏ, ẍ, ÿ]."""
    Phi = np.eye(6)
    Phi[0, 1] = Phi[2, 3] = Phi[1, 4] = Phi[3, 5] = T
    Phi[0, 4] = Phi[2, 5] = T * T / 2
    G = np.zeros((6, 2))
    G[0, 0] = G[2, 1] = T * T / 2
    G[1, 0] = G[3, 1] = T
    G[4, 0] = G[5, 1] = 1.0
    return Phi, q * G @ G.T


def _record(N: int, seed: int, missed: float = 0.15) -> tuple[np.ndarray, np.ndarray]:
    """Measurements (N, 2) of a target that accelerates from scan 40 on, with a fraction of the scans after
    the first two set to NaN; and the mask of missed scans."""
    rng = np.random.default_rng(seed)
    t = np.arange(N) * T
    acc = np.where(t >= 40, 0.5 * 15.0 * (t - 40) ** 2, 0.0)
    pos = np.stack([300.0 * t + acc, 2000.0 - 200.0 * t], axis=1)
    z = pos + SIGMA * rng.standard_normal((N, 2))
    gone = np.zeros(N, dtype=bool)
    gone[2:] = rng.random(N - 2) < missed
    gone[[10, 11, 12]] = True  # a run of three missed scans
    z[gone] = np.nan
    return z, gone


def _kf_step(x, P, zk, Phi, Q):
    """One Kalman step: the prediction x ← Φx, P ← ΦPΦᵀ + Q, then (zk measured) the Joseph update
    P ← (I − KH) P (I − KH)ᵀ + KRKᵀ. Returns x, P and the innovation ν and its covariance S (None, None
    where zk is a NaN row: a prediction only)."""
    x = Phi @ x
    P = Phi @ P @ Phi.T + Q
    if not np.all(np.isfinite(zk)):
        return x, P, None, None
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    nu = zk - H @ x
    x = x + K @ nu
    A = np.eye(6) - K @ H
    P = A @ P @ A.T + K @ R @ K.T
    return x, P, nu, S


def _kf_skip(z, Phi, Q, x0, P0):
    """Plain Kalman filter (Joseph update); a NaN row is a prediction only. Returns x, P, log-likelihoods."""
    x, P = x0.copy(), P0.copy()
    xs, Ps, ll = [], [], []
    for zk in z:
        x, P, nu, S = _kf_step(x, P, zk, Phi, Q)
        if S is not None:
            ll.append(-0.5 * (nu @ np.linalg.solve(S, nu) + np.log(np.linalg.det(2 * np.pi * S))))
        else:
            ll.append(0.0)
        xs.append(x)
        Ps.append(P)
    return np.array(xs), np.array(Ps), np.array(ll)


def test_one_model_imm_with_missed_scans_is_a_kalman_filter_that_skips_the_updates():
    z, gone = _record(120, 1)
    Phi, Q = _ca_model(T, 0.5)
    ms = ModelSet(Phi[None], Q[None], np.array([[1.0]]), np.array([1.0]))
    x0, P0 = two_point_init(z[0], z[1], T, SIGMA)
    tr = imm_filter(z[None, 2:], H_POS6, R, ms, x0, P0, keep_P=True)
    ref_x, ref_P, ref_ll = _kf_skip(z[2:], Phi, Q, x0, P0)
    scale = np.maximum(np.abs(ref_x).max(axis=0), 1.0)
    assert np.max(np.abs(tr.x[0] - ref_x) / scale) < 1e-10  # measured 4e-14
    np.testing.assert_allclose(tr.P[0], ref_P, rtol=1e-9, atol=1e-9 * np.abs(ref_P).max())
    np.testing.assert_allclose(tr.loglik[0, :, 0], ref_ll, rtol=1e-10, atol=1e-10)
    miss = gone[2:]
    assert miss.sum() >= 10 and np.all(tr.loglik[0, miss] == 0.0)
    # a missed scan grows the position variance; the next measured one shrinks it again
    k = int(np.flatnonzero(miss)[0])
    assert tr.P[0, k, 0, 0] > tr.P[0, k - 1, 0, 0] and tr.P[0, k + 3, 0, 0] < tr.P[0, k + 2, 0, 0]


def _imm_textbook(z, models, Pi, mu0, x0, P0):
    """Textbook IMM (loops over models), the update and the likelihood skipped at a NaN row."""
    r = len(models)
    mu = np.array(mu0, float)
    X = [x0.copy() for _ in range(r)]
    P = [P0.copy() for _ in range(r)]
    xs, mus = [], []
    for zk in z:
        cbar = Pi.T @ mu
        w = Pi * mu[:, None] / cbar[None, :]  # μ_{i|j}
        X0 = [sum(w[i, j] * X[i] for i in range(r)) for j in range(r)]
        P0j = [
            sum(w[i, j] * (P[i] + np.outer(X[i] - X0[j], X[i] - X0[j])) for i in range(r)) for j in range(r)
        ]
        lik = np.ones(r)
        for j, (Phi, Q) in enumerate(models):
            x, Pj, nu, S = _kf_step(X0[j], P0j[j], zk, Phi, Q)
            if S is not None:
                lik[j] = np.exp(-0.5 * nu @ np.linalg.solve(S, nu)) / np.sqrt(np.linalg.det(2 * np.pi * S))
            X[j], P[j] = x, Pj
        mu = lik * cbar / np.sum(lik * cbar)
        xs.append(sum(mu[j] * X[j] for j in range(r)))
        mus.append(mu)
    return np.array(xs), np.array(mus)


def test_three_model_imm_with_missed_scans_equals_a_textbook_imm_and_mu_follows_the_chain():
    z, gone = _record(150, 2)
    ms = imm_models(T)  # the paper's three models; the reference gets their matrices
    x0, P0 = two_point_init(z[0], z[1], T, SIGMA)
    tr = imm_filter(z[None, 2:], H_POS6, R, ms, x0, P0)
    models = [(ms.Phi[j], ms.Qd[j]) for j in range(3)]
    ref_x, ref_mu = _imm_textbook(z[2:], models, ms.Pi, ms.mu0, x0, P0)
    scale = np.maximum(np.abs(ref_x).max(axis=0), 1.0)
    assert np.max(np.abs(tr.x[0] - ref_x) / scale) < 1e-9  # measured 4e-13
    np.testing.assert_allclose(tr.mu[0], ref_mu, atol=1e-9)  # measured 3e-12
    # at a missed scan μ(k) = Πᵀ μ(k−1): the Markov chain alone
    miss = np.flatnonzero(gone[2:])
    miss = miss[miss > 0]
    np.testing.assert_allclose(tr.mu[0, miss], tr.mu[0, miss - 1] @ ms.Pi, rtol=1e-12)


def test_runs_are_independent_and_unaffected_runs_are_bit_identical():
    """Vectorised over runs: each run's missed scans are its own. A NaN in run 1 leaves runs 0 and 2 bit for
    bit as they are without it; each run of the batch equals that run alone."""
    zs = np.stack([_record(90, s, missed=0.0)[0] for s in (3, 4, 5)])
    ms = imm_models(T)
    x0, P0 = two_point_init(zs[:, 0], zs[:, 1], T, SIGMA)
    full = imm_filter(zs[:, 2:], H_POS6, R, ms, x0, P0, keep_P=True)
    holes = zs.copy()
    holes[1, [20, 21, 50]] = np.nan
    holes[1, 30, 0] = np.nan  # one coordinate missing: the scan is missed
    some = imm_filter(holes[:, 2:], H_POS6, R, ms, x0, P0, keep_P=True)
    for b in (0, 2):
        np.testing.assert_array_equal(some.x[b], full.x[b])
        np.testing.assert_array_equal(some.P[b], full.P[b])
        np.testing.assert_array_equal(some.log_mu[b], full.log_mu[b])
    assert not np.array_equal(some.x[1], full.x[1])
    alone = imm_filter(holes[1:2, 2:], H_POS6, R, ms, x0[1:2], P0, keep_P=True)
    np.testing.assert_allclose(some.x[1], alone.x[0], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(some.mu[1], alone.mu[0], rtol=1e-12, atol=1e-15)
    assert np.all(some.loglik[1, [18, 19, 28, 48]] == 0.0)  # z[:, 2:] shifts the scan index by 2


def test_infinite_measurements_are_refused():
    z, _ = _record(20, 6, missed=0.0)
    z[5, 1] = np.inf
    ms = imm_models(T)
    x0, P0 = two_point_init(z[0], z[1], T, SIGMA)
    with pytest.raises(ValueError, match="finite"):
        imm_filter(z[None, 2:], H_POS6, R, ms, x0, P0)
