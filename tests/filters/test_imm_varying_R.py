"""Time-varying measurement covariance R(k) (one per run and scan) in the IMM and in the GLR/MLR/CV input
tracker, against independent loop-based numpy filters written here (no motionsig filter code), to 1e-10.

The oracles: a Kalman filter with per-scan R (textbook covariance form, missed scans predict-only); a
textbook IMM with per-scan R (linear-domain likelihoods; the values stay far from underflow here); and the GLR
statistic ΔJ(n) = eᵀΣe built from the H0 filter's response to a unit input step (linearity: the mean of the
innovations under H1(u, n) is the innovation sequence of the filter fed the noise-free step response).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from motionsig_cli.detection.glr import GLRConfig, InputModel, input_tracker
from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.maneuver import study as ex
from motionsig_cli.models.motion import H_POS4, H_POS6, ModelSet, cv_input_model, imm_models

T = 1.0


def _random_R(rng: np.random.Generator, B: int, N: int) -> np.ndarray:
    """SPD 2×2 covariances with σ from 20 to 500 m and random orientation and correlation."""
    s = np.exp(rng.uniform(np.log(20.0), np.log(500.0), (B, N, 2)))
    th = rng.uniform(0, np.pi, (B, N))
    c, si = np.cos(th), np.sin(th)
    U = np.stack([np.stack([c, -si], -1), np.stack([si, c], -1)], -2)
    return U @ (s[..., :, None] ** 2 * np.eye(2)) @ np.swapaxes(U, -1, -2)


def _records(seed: int, B: int, N: int, missing: float) -> tuple[np.ndarray, np.ndarray]:
    """z (B, N, 2) of a CV target with correlated noise of covariance R (B, N, 2, 2); NaN at missed scans
    (never the first two)."""
    rng = np.random.default_rng(seed)
    R = _random_R(rng, B, N)
    t = np.arange(N) * T
    truth = np.stack([1000 + 300 * t, 2000 - 150 * t + 0.5 * 2.0 * t**2], -1)
    w = (np.linalg.cholesky(R) @ rng.standard_normal((B, N, 2, 1)))[..., 0]
    z = truth[None] + w
    miss = rng.random((B, N)) < missing
    miss[:, :2] = False
    z[miss] = np.nan
    R[miss] = np.nan  # a missed scan's covariance is ignored, even NaN
    return z, R


def _kf(z, R, F, Q, H, x0, P0):
    """Textbook Kalman filter, one run, per-scan R, NaN = predict-only: updated states and covariances."""
    x, P = x0.copy(), P0.copy()
    xs, Ps, nus, Ss = [], [], [], []
    for k in range(z.shape[0]):
        x = F @ x
        P = F @ P @ F.T + Q
        if np.all(np.isfinite(z[k])):
            S = H @ P @ H.T + R[k]
            K = P @ H.T @ np.linalg.inv(S)
            nu = z[k] - H @ x
            x = x + K @ nu
            A = np.eye(len(x)) - K @ H
            P = A @ P @ A.T + K @ R[k] @ K.T
            nus.append(nu)
            Ss.append(S)
        else:
            nus.append(None)
            Ss.append(None)
        xs.append(x.copy())
        Ps.append(P.copy())
    return np.array(xs), np.array(Ps), nus, Ss


def _imm_textbook(z, R, models: ModelSet, x0, P0):
    """Textbook IMM (mixing, model-matched KFs, linear-domain likelihoods), one run, per-scan R."""
    r = models.Phi.shape[0]
    Pi, mu = np.asarray(models.Pi), np.asarray(models.mu0, float).copy()
    X = [x0.copy() for _ in range(r)]
    P = [P0.copy() for _ in range(r)]
    H = H_POS6
    out_x, out_mu = [], []
    for k in range(z.shape[0]):
        cbar = Pi.T @ mu
        w = Pi * mu[:, None] / cbar[None, :]
        X0 = [sum(w[i, j] * X[i] for i in range(r)) for j in range(r)]
        P0j = [
            sum(w[i, j] * (P[i] + np.outer(X[i] - X0[j], X[i] - X0[j])) for i in range(r)) for j in range(r)
        ]
        lik = np.ones(r)
        for j in range(r):
            xp = models.Phi[j] @ X0[j]
            Pp = models.Phi[j] @ P0j[j] @ models.Phi[j].T + models.Qd[j]
            if np.all(np.isfinite(z[k])):
                S = H @ Pp @ H.T + R[k]
                K = Pp @ H.T @ np.linalg.inv(S)
                nu = z[k] - H @ xp
                X[j] = xp + K @ nu
                A = np.eye(6) - K @ H
                P[j] = A @ Pp @ A.T + K @ R[k] @ K.T
                lik[j] = math.exp(-0.5 * nu @ np.linalg.solve(S, nu)) / (
                    2 * math.pi * math.sqrt(np.linalg.det(S))
                )
            else:
                X[j], P[j] = xp, Pp
        mu = lik * cbar / np.sum(lik * cbar)
        out_x.append(sum(mu[j] * X[j] for j in range(r)))
        out_mu.append(mu.copy())
    return np.array(out_x), np.array(out_mu)


def _init(z, R, n):
    return ex.two_point_init_cov(z[:, 0], z[:, 1], R[:, 0], R[:, 1], T, n=n)


@pytest.mark.parametrize("missing", [0.0, 0.3])
def test_one_model_imm_is_the_kalman_filter_with_per_scan_R(missing):
    z, R = _records(1, 4, 60, missing)
    full = imm_models(T, q=(0.0, 0.001, 0.0144))
    ms = ModelSet(full.Phi[1:2], full.Qd[1:2], np.ones((1, 1)), np.ones(1))
    x0, P0 = _init(z, R, 6)
    tr = imm_filter(z[:, 2:], H_POS6, R[:, 2:], ms, x0, P0, keep_P=True)
    for b in range(4):
        xs, Ps, _, _ = _kf(z[b, 2:], R[b, 2:], full.Phi[1], full.Qd[1], H_POS6, x0[b], P0[b])
        np.testing.assert_allclose(tr.x[b], xs, rtol=1e-10, atol=1e-10 * np.abs(xs).max())
        np.testing.assert_allclose(tr.P[b], Ps, rtol=1e-10, atol=1e-10 * np.abs(Ps).max())


@pytest.mark.parametrize("missing", [0.0, 0.25])
def test_three_model_imm_matches_the_textbook_imm_with_per_scan_R(missing):
    z, R = _records(2, 3, 80, missing)
    ms = imm_models(T)
    x0, P0 = _init(z, R, 6)
    tr = imm_filter(z[:, 2:], H_POS6, R[:, 2:], ms, x0, P0)
    for b in range(3):
        xs, mus = _imm_textbook(z[b, 2:], R[b, 2:], ms, x0[b], P0[b])
        np.testing.assert_allclose(tr.x[b], xs, rtol=1e-10, atol=1e-10 * np.abs(xs).max())
        np.testing.assert_allclose(tr.mu[b], mus, rtol=1e-9, atol=1e-10)


def test_constant_R_given_per_scan_equals_the_shared_R():
    """σ² I for every scan through the per-scan path gives the shared-R result (same arithmetic)."""
    z, _ = _records(3, 3, 50, 0.2)
    R = np.broadcast_to(150.0**2 * np.eye(2), (*z.shape[:2], 2, 2)).copy()
    ms = imm_models(T)
    x0, P0 = _init(z, R, 6)
    a = imm_filter(z[:, 2:], H_POS6, R[0, 0], ms, x0, P0)
    b = imm_filter(z[:, 2:], H_POS6, R[:, 2:], ms, x0, P0)
    np.testing.assert_allclose(b.x, a.x, rtol=1e-13, atol=1e-9)
    F, G, Q = cv_input_model(T, 1.0)
    model = InputModel(F, G, Q, H_POS4, R[0, 0])
    x4, P4 = _init(z, R, 4)
    for method in ("glr", "mlr", "none"):
        u = input_tracker(z[:, 2:], model, x4, P4[0], GLRConfig(method=method))
        v = input_tracker(z[:, 2:], model, x4, P4[0], GLRConfig(method=method), R=R[:, 2:])
        np.testing.assert_allclose(v.x, u.x, rtol=1e-13, atol=1e-9)
        np.testing.assert_array_equal(v.detected, u.detected)


@pytest.mark.parametrize("missing", [0.0, 0.3])
def test_cv_tracker_is_the_kalman_filter_with_per_scan_R(missing):
    z, R = _records(4, 4, 70, missing)
    F, G, Q = cv_input_model(T, 1.0)
    x0, P0 = _init(z, R, 4)
    model = InputModel(F, G, Q, H_POS4, np.eye(2))  # the model's R is replaced by the per-scan R
    it = input_tracker(z[:, 2:], model, x0, P0, GLRConfig(method="none"), R=R[:, 2:], keep_P=True)
    for b in range(4):
        xs, Ps, _, _ = _kf(z[b, 2:], R[b, 2:], F, Q, H_POS4, x0[b], P0[b])
        np.testing.assert_allclose(it.x[b], xs, rtol=1e-10, atol=1e-10 * np.abs(xs).max())
        np.testing.assert_allclose(it.P[b], Ps, rtol=1e-10, atol=1e-10 * np.abs(Ps).max())


@pytest.mark.parametrize("missing", [0.0, 0.3])
def test_glr_statistic_matches_the_step_response_oracle_with_per_scan_R(missing):
    """ΔJ(n) of every onset in the window at every scan, threshold ∞ (no declarations), against Σ and e
    built from the H0 filter's innovations on the noise-free unit-step responses."""
    z, R = _records(5, 2, 40, missing)
    F, G, Q = cv_input_model(T, 1.0)
    x0, P0 = _init(z, R, 4)
    s = 6
    cfg = GLRConfig(method="glr", window=s, threshold=math.inf)
    it = input_tracker(z[:, 2:], InputModel(F, G, Q, H_POS4, np.eye(2)), x0, P0, cfg, R=R[:, 2:])
    zz, RR = z[:, 2:], R[:, 2:]
    N = zz.shape[1]
    for b in range(2):
        _, _, nus, Ss = _kf(zz[b], RR[b], F, Q, H_POS4, x0[b], P0[b])
        seen = np.all(np.isfinite(zz[b]), axis=1)
        for k in range(N):
            for d in range(s):
                n = k - 1 - d
                if n < 0:
                    continue
                # response of the H0 filter to the truth offset of a unit input jump in axis i at onset n:
                # the input enters the prediction of scan n + 1 (x_{n+1} = F x_n + G u)
                Psi = []
                for i in range(2):
                    u = np.zeros(2)
                    u[i] = 1.0
                    xt = np.zeros(4)
                    xh, Ph = np.zeros(4), P0[b].copy()
                    cols = []
                    for j in range(N):
                        xt = F @ xt + (G @ u if j >= n + 1 else 0.0)
                        xh, Ph = F @ xh, F @ Ph @ F.T + Q
                        if seen[j]:
                            S = H_POS4 @ Ph @ H_POS4.T + RR[b, j]
                            K = Ph @ H_POS4.T @ np.linalg.inv(S)
                            nu = H_POS4 @ xt - H_POS4 @ xh
                            xh = xh + K @ nu
                            A = np.eye(4) - K @ H_POS4
                            Ph = A @ Ph @ A.T + K @ RR[b, j] @ K.T
                            cols.append(nu)
                        else:
                            cols.append(None)
                    Psi.append(cols)
                info, e = np.zeros((2, 2)), np.zeros(2)
                for j in range(n + 1, k + 1):
                    if not seen[j]:
                        continue
                    Pj = np.stack([Psi[0][j], Psi[1][j]], axis=1)
                    Si = np.linalg.inv(Ss[j])
                    info += Pj.T @ Si @ Pj
                    e += Pj.T @ Si @ nus[j]
                if not np.any(seen[n + 1 : k + 1]):
                    assert np.isnan(it.dJ[b, k, d])
                    continue
                dJ = e @ np.linalg.solve(info, e)
                assert it.dJ[b, k, d] == pytest.approx(dJ, rel=1e-8, abs=1e-10)


def test_bad_per_scan_R_is_refused():
    z, R = _records(6, 2, 20, 0.0)
    ms = imm_models(T)
    x0, P0 = _init(z, R, 6)
    bad = R[:, 2:].copy()
    bad[0, 3] = np.diag([1.0, -1.0])
    with pytest.raises(ValueError, match="positive definite"):
        imm_filter(z[:, 2:], H_POS6, bad, ms, x0, P0)
    bad = R[:, 2:].copy()
    bad[1, 4, 0, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        imm_filter(z[:, 2:], H_POS6, bad, ms, x0, P0)
    with pytest.raises(ValueError, match="must be"):
        imm_filter(z[:, 2:], H_POS6, R[:, 3:], ms, x0, P0)
