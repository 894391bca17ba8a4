"""Missed scans in the GLR/MLR input tracker (detection/glr.py): a NaN measurement is a predict-only step;
the onset statistics get no innovation from it while the signature matrices still propagate
(M_{k+1}(n) = F_ξ M_k(n)); the onset window counts scans, missed ones included; no declaration at a missed scan.

The references are written here from the hypotheses themselves, with nothing of motionsig_cli but the model
matrices: a plain Kalman filter that skips the update at a NaN, re-run with a hypothesised input u from onset
n; the log-likelihood ratio ℓ(u) is an exact quadratic gᵀu − ½uᵀAu (gains do not depend on u), read off by
central differences, so ΔJ(n) = 2 max ℓ = gᵀA⁻¹g and J_MLR(n) = log ∫ exp ℓ(u) N(u; 0, σ_u² I) du =
½ gᵀ(A + σ_u⁻² I)⁻¹g − ½ log det(I + σ_u² A)."""

import math

import numpy as np
import pytest

from motionsig_cli.detection.glr import GLRConfig, InputModel, input_tracker
from motionsig_cli.models.motion import H_POS4, cv_input_model, two_point_init

T, SIGMA, Q0 = 1.0, 50.0, 1.0


def _model(sigma: float = SIGMA) -> InputModel:
    F, G, Q = cv_input_model(T, Q0)
    return InputModel(F, G, Q, H_POS4, sigma * sigma * np.eye(2))


def _truth(N: int, u, onset: int) -> np.ndarray:
    """Noise-free CV positions (N, 2), the input u from index ``onset`` on (it first moves onset + 1)."""
    x = np.array([0.0, 0.0, 0.0, 450.0])
    F, G, _ = cv_input_model(T, 0.0)
    out = np.empty((N, 2))
    for k in range(N):
        out[k] = x[[0, 2]]
        x = F @ x + (G @ np.asarray(u, float) if k >= onset else 0.0)
    return out


def _loglik(z, model, xp, Pp, u=None, onset=0, upto=None):
    """Σ log N(ν_j; 0, S_j) of a Kalman filter from the predicted prior (xp, Pp) at z[0], the update skipped
    at a NaN row, the known input u added in every prediction from scan j ≥ onset."""
    F, G, Q, H, R = model.F, model.G, model.Q, model.H, model.R
    x, P, total = xp.copy(), Pp.copy(), 0.0
    last = len(z) - 1 if upto is None else upto
    for j in range(last + 1):
        if np.all(np.isfinite(z[j])):
            S = H @ P @ H.T + R
            nu = z[j] - H @ x
            total += -0.5 * (nu @ np.linalg.solve(S, nu) + math.log(np.linalg.det(2 * np.pi * S)))
            K = P @ H.T @ np.linalg.inv(S)
            x = x + K @ nu
            A = np.eye(4) - K @ H
            P = A @ P @ A.T + K @ R @ K.T
        x = F @ x + (G @ u if (u is not None and j >= onset) else 0.0)
        P = F @ P @ F.T + Q
    return total


def _quadratic(z, model, xp, Pp, onset, upto, h=10.0):
    """g, A of ℓ(u) = gᵀu − ½uᵀAu by central differences (exact for a quadratic up to rounding)."""
    base = _loglik(z, model, xp, Pp, upto=upto)

    def ell(u):
        return _loglik(z, model, xp, Pp, np.asarray(u, float), onset, upto) - base

    e = np.eye(2) * h
    g = np.array([(ell(e[i]) - ell(-e[i])) / (2 * h) for i in range(2)])
    A = np.empty((2, 2))
    for i in range(2):
        A[i, i] = -(ell(e[i]) - 2 * ell(np.zeros(2)) + ell(-e[i])) / h**2
    A[0, 1] = A[1, 0] = -(ell(e[0] + e[1]) - ell(e[0] - e[1]) - ell(e[1] - e[0]) + ell(-e[0] - e[1])) / (
        4 * h * h
    )
    return g, A


def _noisy(N: int, seed: int, gone: list[int]) -> np.ndarray:
    rng = np.random.default_rng(seed)
    z = _truth(N, (12.0, -8.0), 22)[None] + SIGMA * rng.standard_normal((1, N, 2))
    z[0, gone] = np.nan
    return z


MISSED = [9, 20, 21, 24, 25, 28, 33]  # record indices (the tracker sees z[:, 2:]: local index − 2)


def test_cv_filter_with_missed_scans_is_a_kalman_filter_that_skips_the_updates():
    z = _noisy(60, 1, MISSED)
    model = _model()
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    out = input_tracker(z[:, 2:], model, x0, P0, GLRConfig(method="none"), keep_P=True)
    x, P = x0[0].copy(), P0.copy()
    for j, zk in enumerate(z[0, 2:]):
        x, P = model.F @ x, model.F @ P @ model.F.T + model.Q
        if np.all(np.isfinite(zk)):
            S = model.H @ P @ model.H.T + model.R
            K = P @ model.H.T @ np.linalg.inv(S)
            x = x + K @ (zk - model.H @ x)
            A = np.eye(4) - K @ model.H
            P = A @ P @ A.T + K @ model.R @ K.T
        np.testing.assert_allclose(out.x[0, j], x, rtol=1e-11, atol=1e-8)
        np.testing.assert_allclose(out.P[0, j], P, rtol=1e-10, atol=1e-10 * np.abs(P).max())
    assert not out.detected.any()


@pytest.mark.parametrize("k", [28, 23, 31])  # a measured scan; missed scans (record 25, 33: local 23, 31)
def test_glr_and_mlr_statistics_with_missed_scans_equal_kalman_reruns(k):
    """ΔJ(n) and J_MLR(n) of every onset of the window at scan k (local index) equal the values from filters
    re-run with the input, the updates skipped at the missed scans. An onset with no measured scan after it
    (n = k − 1 at a missed scan k) is not testable (NaN)."""
    z = _noisy(45, 2, MISSED)
    model = _model()
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    glr = input_tracker(z[:, 2:], model, x0, P0, GLRConfig(threshold=math.inf))
    mlr = input_tracker(z[:, 2:], model, x0, P0, GLRConfig(method="mlr", threshold=math.inf, sigma_u=8.0))
    zz = z[0, 2:]
    xp, Pp = model.F @ x0[0], model.F @ P0 @ model.F.T + model.Q
    seen = np.all(np.isfinite(zz), axis=1)
    checked = 0
    for d in range(10):
        n = k - 1 - d
        if not seen[n + 1 : k + 1].any():
            assert np.isnan(glr.dJ[0, k, d]) and np.isnan(mlr.score[0, k, d])
            continue
        g, A = _quadratic(zz, model, xp, Pp, n, k)
        dJ = g @ np.linalg.solve(A, g)
        J = (
            0.5 * g @ np.linalg.solve(A + np.eye(2) / 8.0**2, g)
            - 0.5 * np.linalg.slogdet(np.eye(2) + 8.0**2 * A)[1]
        )
        assert glr.dJ[0, k, d] == pytest.approx(dJ, rel=1e-8, abs=1e-8)  # measured ≤ 6e-12 (differences)
        assert mlr.score[0, k, d] == pytest.approx(J, rel=1e-8, abs=1e-8)  # measured ≤ 4e-14
        checked += 1
    assert checked >= 8
    if not seen[k]:  # a missed scan adds nothing: the statistics of the scan before, shifted by one onset
        np.testing.assert_array_equal(glr.dJ[0, k, 1:], glr.dJ[0, k - 1, :-1])


def test_noise_free_step_across_missed_scans_is_recovered_exactly():
    """A noise-free step u from onset n with missed scans at the onset and after it: the first declaration
    has n̂ = n and û = u exactly, and the corrected state is the truth — the signature matrices propagated
    over the missed scans are right. No declaration at a missed scan, not even with a threshold of 0."""
    u, onset, N = np.array([20.0, -10.0]), 30, 70
    z = _truth(N, u, onset)[None].copy()
    gone = [onset, onset + 2, onset + 3, onset + 5]
    z[0, gone] = np.nan
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    out = input_tracker(z[:, 2:], _model(), x0, P0, GLRConfig(window=20), keep_P=True)
    k = np.flatnonzero(out.detected[0])
    assert k.size == 1
    assert out.onset[0, k[0]] + 2 == onset  # local index 0 is record index 2
    assert k[0] + 2 > onset + 5  # declared after the missed scans
    np.testing.assert_allclose(out.u_jump[0, k[0]], u, rtol=1e-9, atol=1e-9)
    F, G, _ = cv_input_model(T, 0.0)
    x = np.array([0.0, 0.0, 0.0, 450.0])
    for j in range(k[0] + 2):
        x = F @ x + (G @ u if j >= onset else 0.0)
    np.testing.assert_allclose(out.x[0, k[0]], x, rtol=1e-9, atol=1e-6)
    # threshold 0: a declaration at every measured scan with a testable onset, never at a missed one
    zn = _noisy(45, 3, MISSED)
    x0, P0 = two_point_init(zn[:, 0], zn[:, 1], T, SIGMA, n=4)
    every = input_tracker(zn[:, 2:], _model(), x0, P0, GLRConfig(threshold=0.0))
    seen = np.all(np.isfinite(zn[0, 2:]), axis=1)
    assert not every.detected[0, ~seen].any()
    assert every.detected[0, 1:][seen[1:]].all()


@pytest.mark.parametrize("method", ["glr", "mlr"])
def test_runs_are_independent_and_unaffected_runs_are_bit_identical(method):
    rng = np.random.default_rng(4)
    z = _truth(80, (15.0, 5.0), 40)[None] + SIGMA * rng.standard_normal((3, 80, 2))
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    cfg = GLRConfig(method=method)
    full = input_tracker(z[:, 2:], _model(), x0, P0, cfg, keep_P=True)
    holes = z.copy()
    holes[1, [41, 42, 60]] = np.nan
    some = input_tracker(holes[:, 2:], _model(), x0, P0, cfg, keep_P=True)
    for name in ("x", "P", "stat", "dJ", "score", "detected", "onset", "u_jump", "u_cur"):
        for b in (0, 2):
            np.testing.assert_array_equal(getattr(some, name)[b], getattr(full, name)[b])
    assert not np.array_equal(some.x[1], full.x[1])
    alone = input_tracker(holes[1:2, 2:], _model(), x0[1:2], P0, cfg)
    np.testing.assert_allclose(some.x[1], alone.x[0], rtol=1e-12, atol=1e-8)
    np.testing.assert_array_equal(some.detected[1], alone.detected[0])


def test_infinite_measurements_are_refused():
    z = _truth(10, (0.0, 0.0), 0)[None].copy()
    z[0, 4, 0] = -np.inf
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    with pytest.raises(ValueError, match="finite"):
        input_tracker(z[:, 2:], _model(), x0, P0, GLRConfig())
