"""Batched Kalman bank against two oracles: a dense Gaussian log-density and a per-filter loop."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import multivariate_normal

from motionsig_cli.filters.kalman import innovation_costs, riccati


def _random_system(rng, C, n, m, N):
    # stable time-varying dynamics (spectral radius < 1), so covariances stay bounded
    F = rng.normal(scale=0.3 / np.sqrt(n), size=(C, N, n, n)) + 0.7 * np.eye(n)
    H = rng.normal(size=(m, n))
    A = rng.normal(size=(n, n))
    Q = A @ A.T * 0.1 + 0.01 * np.eye(n)
    Rm = rng.normal(size=(m, m))
    R = Rm @ Rm.T + 0.5 * np.eye(m)
    P0 = np.eye(n) * 2.0
    x0 = rng.normal(size=n)
    return F, H, Q, R, P0, x0


def _dense_negloglik(F, H, Q, R, P0, x0, y):
    """−log p(y_0..y_{N−1}) from the joint Gaussian of the stacked measurements (no filtering)."""
    N, n = F.shape[0], F.shape[1]
    # x_k = A_k x_0 + sum_j B_kj w_j with x_0 ~ N(x0, P0): build the linear map from (x_0, w_0..w_{N-2})
    dim = n + n * (N - 1)
    maps = []
    M = np.zeros((n, dim))
    M[:, :n] = np.eye(n)
    for k in range(N):
        maps.append(M.copy())
        if k + 1 < N:
            M = F[k] @ M
            M[:, n + n * k : n + n * (k + 1)] += np.eye(n)
    cov_src = np.zeros((dim, dim))
    cov_src[:n, :n] = P0
    for k in range(N - 1):
        cov_src[n + n * k : n + n * (k + 1), n + n * k : n + n * (k + 1)] = Q
    mean_src = np.zeros(dim)
    mean_src[:n] = x0
    G = np.vstack([H @ Mk for Mk in maps])  # (N m, dim)
    mu = G @ mean_src
    Sigma = G @ cov_src @ G.T + np.kron(np.eye(N), R)
    return -multivariate_normal(mean=mu, cov=Sigma).logpdf(y.reshape(-1))


@settings(max_examples=15, deadline=None)
@given(st.integers(1, 3), st.integers(1, 2), st.integers(2, 12), st.integers(0, 10_000))
def test_bank_equals_dense_gaussian(n, m, N, seed):
    """With the log-det term, the prediction-error decomposition (eqs 45–49) gives exactly the
    joint Gaussian negative log-density of the stacked measurements."""
    rng = np.random.default_rng(seed)
    C, B = 3, 2
    F, H, Q, R, P0, x0 = _random_system(rng, C, n, m, N)
    y = rng.normal(size=(B, N, m))
    gains = riccati(lambda k: F[:, k], H, Q, R, P0, N, C)
    J = innovation_costs(lambda k: F[:, k], H, gains, x0, y, [N], include_logdet=True)
    for c in range(C):
        for b in range(B):
            np.testing.assert_allclose(J[c, b, 0], _dense_negloglik(F[c], H, Q, R, P0, x0, y[b]), rtol=1e-9)


def _reference_filter(F, H, Q, R, P0, x0, y):
    """Textbook single-filter loop (standard-form update), returns cumulative ½ Σ νᵀS⁻¹ν per step."""
    x, P, J, out = x0.copy(), P0.copy(), 0.0, []
    for k in range(len(y)):
        S = H @ P @ H.T + R
        K = P @ H.T @ np.linalg.inv(S)
        nu = y[k] - H @ x
        J += 0.5 * nu @ np.linalg.solve(S, nu)
        out.append(J)
        x = x + K @ nu
        P = P - K @ S @ K.T
        x = F[k] @ x
        P = F[k] @ P @ F[k].T + Q
    return np.array(out)


def test_bank_equals_per_filter_loop():
    rng = np.random.default_rng(1)
    C, n, m, N, B = 7, 4, 1, 60, 3
    F, H, Q, R, P0, x0 = _random_system(rng, C, n, m, N)
    y = rng.normal(size=(B, N, m))
    horizons = [1, 10, 33, 60]
    gains = riccati(lambda k: F[:, k], H, Q, R, P0, N, C)
    J = innovation_costs(lambda k: F[:, k], H, gains, x0, y, horizons)
    for c in range(C):
        for b in range(B):
            ref = _reference_filter(F[c], H, Q, R, P0, x0, y[b])
            np.testing.assert_allclose(J[c, b], ref[np.array(horizons) - 1], rtol=1e-10)


def test_covariance_input_validation():
    F = np.eye(2)
    with pytest.raises(ValueError, match="R must be positive definite"):
        riccati(lambda k: F, np.array([[1.0, 0.0]]), np.eye(2), np.zeros((1, 1)), np.eye(2), 5, 1)
    with pytest.raises(ValueError, match="Q is not positive semi-definite"):
        riccati(lambda k: F, np.array([[1.0, 0.0]]), -np.eye(2), np.eye(1), np.eye(2), 5, 1)
    with pytest.raises(ValueError, match="Q is not symmetric"):
        riccati(
            lambda k: F,
            np.array([[1.0, 0.0]]),
            np.array([[1.0, 0.5], [0.0, 1.0]]),
            np.eye(1),
            np.eye(2),
            5,
            1,
        )
