"""Independent test oracle: textbook interacting-multiple-model (IMM) filter and a plain Kalman filter.

Everything here is written directly from the textbook IMM recursion, deliberately slowly and explicitly
(plain Python loops over models and scans), so that it can serve as a reference for the fast
implementation in ``motionsig_cli``. It must not import anything from ``motionsig_cli``.

Conventions
-----------
* Measurements ``z`` have shape (N, 2): Cartesian positions at scans 0..N-1 (0-based), noise
  ``R = sigma**2 I_2``.
* State order ``X = [x, xdot, y, ydot, xddot, yddot]`` (6-D); ``H`` picks ``x`` and ``y``.
* Initialisation at scan 1 by two-point differencing of ``z[0]`` and ``z[1]``; the per-axis position /
  velocity covariance is ``[[s2, s2/T], [s2/T, 2 s2/T**2]]`` (``s2 = sigma**2``), the acceleration block
  is zero.
* The recursion runs for scans 2..N-1; all returned arrays have N-2 rows, row ``i`` <-> scan ``i + 2``.
* ``Pi[i, j] = P(model j at k | model i at k-1)``; model ``j`` has process noise ``G_j Q_j G_j^T``.
* Model likelihoods use ``scipy.stats.multivariate_normal.pdf`` in the linear domain (textbook form).
"""

from __future__ import annotations

import numpy as np
from scipy.stats import multivariate_normal

__all__ = ["H_MEAS", "imm_oracle", "init_two_point", "kf_oracle"]

H_MEAS = np.array(
    [
        [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
    ]
)


def init_two_point(z: np.ndarray, T: float, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """Two-point differencing initialisation at scan index 1.

    Args:
        z: (N, 2) position measurements, N >= 2.
        T: scan period.
        sigma: measurement noise standard deviation (per axis).

    Returns:
        ``(X, P)``: the 6-D state ``[z[1,0], (z[1,0]-z[0,0])/T, z[1,1], (z[1,1]-z[0,1])/T, 0, 0]`` and its
        6x6 covariance (block-diagonal over the axes, zero acceleration block).
    """
    z = np.asarray(z, dtype=float)
    s2 = sigma * sigma
    X = np.array(
        [
            z[1, 0],
            (z[1, 0] - z[0, 0]) / T,
            z[1, 1],
            (z[1, 1] - z[0, 1]) / T,
            0.0,
            0.0,
        ]
    )
    block = np.array([[s2, s2 / T], [s2 / T, 2.0 * s2 / (T * T)]])
    P = np.zeros((6, 6))
    P[0:2, 0:2] = block
    P[2:4, 2:4] = block
    return X, P


def _kf_step(
    X: np.ndarray, P: np.ndarray, zk: np.ndarray, R: np.ndarray, Phi: np.ndarray, GQG: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """One predict + update cycle of the linear Kalman filter (plain covariance update, symmetrised).

    Returns:
        ``(X_upd, P_upd, v, S)``: updated state and covariance, innovation and its covariance.
    """
    H = H_MEAS
    Xp = Phi @ X
    Pp = Phi @ P @ Phi.T + GQG
    v = zk - H @ Xp
    S = H @ Pp @ H.T + R
    K = Pp @ H.T @ np.linalg.inv(S)
    Xu = Xp + K @ v
    Pu = (np.eye(6) - K @ H) @ Pp
    Pu = 0.5 * (Pu + Pu.T)
    return Xu, Pu, v, S


def kf_oracle(
    z: np.ndarray, T: float, sigma: float, Phi: np.ndarray, G: np.ndarray, Q: np.ndarray
) -> dict[str, np.ndarray]:
    """Single Kalman filter with the two-point initialisation at scan 1.

    Args:
        z: (N, 2) position measurements at scans 0..N-1.
        T: scan period.
        sigma: measurement noise standard deviation.
        Phi: (6, 6) transition matrix.
        G: (6, 2) noise gain.
        Q: (2, 2) process noise covariance (the state noise is ``G Q G^T``).

    Returns:
        ``{"x": (N-2, 6), "P": (N-2, 6, 6)}``: updated estimates for scans 2..N-1.
    """
    z = np.asarray(z, dtype=float)
    N = z.shape[0]
    R = sigma * sigma * np.eye(2)
    GQG = G @ Q @ G.T
    X, P = init_two_point(z, T, sigma)
    xs = np.zeros((N - 2, 6))
    Ps = np.zeros((N - 2, 6, 6))
    for k in range(2, N):
        X, P, _v, _S = _kf_step(X, P, z[k], R, Phi, GQG)
        xs[k - 2] = X
        Ps[k - 2] = P
    return {"x": xs, "P": Ps}


def imm_oracle(
    z: np.ndarray,
    T: float,
    sigma: float,
    Pi: np.ndarray,
    mu0: np.ndarray,
    models: list[tuple[np.ndarray, np.ndarray, np.ndarray]],
) -> dict[str, np.ndarray]:
    """Textbook IMM filter (mixing, model-matched KFs, probability update, combination).

    Args:
        z: (N, 2) position measurements at scans 0..N-1.
        T: scan period.
        sigma: measurement noise standard deviation.
        Pi: (r, r) Markov transition matrix, ``Pi[i, j] = P(model j at k | model i at k-1)``.
        mu0: (r,) model probabilities at the initialisation scan (scan 1).
        models: r tuples ``(Phi (6,6), G (6,2), Q (2,2))``.

    Returns:
        Dict with ``"x"`` (N-2, 6) combined estimates, ``"P"`` (N-2, 6, 6) combined covariances,
        ``"mu"`` (N-2, r) model probabilities and ``"x_models"`` (N-2, r, 6) model-conditioned estimates,
        all for scans 2..N-1.
    """
    z = np.asarray(z, dtype=float)
    Pi = np.asarray(Pi, dtype=float)
    N = z.shape[0]
    r = len(models)
    R = sigma * sigma * np.eye(2)

    X_init, P_init = init_two_point(z, T, sigma)
    Xm = [X_init.copy() for _ in range(r)]
    Pm = [P_init.copy() for _ in range(r)]
    mu = [float(m) for m in np.asarray(mu0, dtype=float)]

    out_x = np.zeros((N - 2, 6))
    out_P = np.zeros((N - 2, 6, 6))
    out_mu = np.zeros((N - 2, r))
    out_xm = np.zeros((N - 2, r, 6))

    for k in range(2, N):
        # 1. predicted model probabilities c_bar_j
        cbar = [0.0] * r
        for j in range(r):
            for i in range(r):
                cbar[j] += Pi[i, j] * mu[i]
        # 2. mixing probabilities mu_{i|j}
        mix = [[0.0] * r for _ in range(r)]  # mix[i][j]
        for j in range(r):
            for i in range(r):
                mix[i][j] = Pi[i, j] * mu[i] / cbar[j]
        # 3. mixed initial conditions
        X0 = []
        P0 = []
        for j in range(r):
            xj = np.zeros(6)
            for i in range(r):
                xj = xj + mix[i][j] * Xm[i]
            pj = np.zeros((6, 6))
            for i in range(r):
                d = Xm[i] - xj
                pj = pj + mix[i][j] * (Pm[i] + np.outer(d, d))
            X0.append(xj)
            P0.append(pj)
        # 4./5. model-matched filters and likelihoods
        lik = [0.0] * r
        newX = []
        newP = []
        for j in range(r):
            Phi, G, Q = models[j]
            Xu, Pu, v, S = _kf_step(X0[j], P0[j], z[k], R, Phi, G @ Q @ G.T)
            newX.append(Xu)
            newP.append(Pu)
            lik[j] = float(multivariate_normal.pdf(v, mean=np.zeros(2), cov=S))
        # 6. model probability update
        denom = 0.0
        for j in range(r):
            denom += lik[j] * cbar[j]
        mu = [lik[j] * cbar[j] / denom for j in range(r)]
        Xm = newX
        Pm = newP
        # 7. combination
        xc = np.zeros(6)
        for j in range(r):
            xc = xc + mu[j] * Xm[j]
        pc = np.zeros((6, 6))
        for j in range(r):
            d = Xm[j] - xc
            pc = pc + mu[j] * (Pm[j] + np.outer(d, d))
        out_x[k - 2] = xc
        out_P[k - 2] = pc
        out_mu[k - 2] = mu
        for j in range(r):
            out_xm[k - 2, j] = Xm[j]

    return {"x": out_x, "P": out_P, "mu": out_mu, "x_models": out_xm}


def _ca_model(T: float, q: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Constant-acceleration model in the state order [x, xdot, y, ydot, xddot, yddot] (self-check)."""
    Phi = np.eye(6)
    Phi[0, 1] = T
    Phi[0, 4] = 0.5 * T * T
    Phi[1, 4] = T
    Phi[2, 3] = T
    Phi[2, 5] = 0.5 * T * T
    Phi[3, 5] = T
    return Phi, _noise_gain(T, accel=1.0), q * np.eye(2)


def _cv_model(T: float, q: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Constant-velocity model (acceleration components held at zero) in the 6-D state (self-check)."""
    Phi = np.zeros((6, 6))
    Phi[0, 0] = Phi[1, 1] = Phi[2, 2] = Phi[3, 3] = 1.0
    Phi[0, 1] = T
    Phi[2, 3] = T
    return Phi, _noise_gain(T, accel=0.0), q * np.eye(2)


def _noise_gain(T: float, accel: float) -> np.ndarray:
    """Process-noise gain G of the 6-D state (x, vx, y, vy, ax, ay): white acceleration on the position and
    velocity rows, ``accel`` on the acceleration rows (1 for the acceleration model, 0 for constant velocity)."""
    G = np.zeros((6, 2))
    G[0, 0] = G[2, 1] = 0.5 * T * T
    G[1, 0] = G[3, 1] = T
    G[4, 0] = G[5, 1] = accel
    return G


if __name__ == "__main__":
    rng = np.random.default_rng(7)
    T_, sigma_, N_ = 2.0, 30.0, 40
    truth = np.zeros((N_, 2))
    pos = np.array([1000.0, -500.0])
    vel = np.array([120.0, 40.0])
    for kk in range(N_):
        truth[kk] = pos
        acc = np.array([8.0, -5.0]) if 15 <= kk < 25 else np.zeros(2)
        pos = pos + vel * T_ + 0.5 * acc * T_ * T_
        vel = vel + acc * T_
    z_ = truth + sigma_ * rng.standard_normal((N_, 2))

    ca = _ca_model(T_, 4.0)
    cv = _cv_model(T_, 0.5)

    kf = kf_oracle(z_, T_, sigma_, *ca)
    imm1 = imm_oracle(z_, T_, sigma_, np.ones((1, 1)), np.ones(1), [ca])
    print("r=1 IMM vs KF: max |dx| =", np.max(np.abs(imm1["x"] - kf["x"])))
    print("r=1 IMM vs KF: max |dP| =", np.max(np.abs(imm1["P"] - kf["P"])))

    # Two identical models must also reproduce the single KF (mixing is then a no-op).
    Pi2 = np.array([[0.9, 0.1], [0.2, 0.8]])
    imm2 = imm_oracle(z_, T_, sigma_, Pi2, np.array([0.5, 0.5]), [ca, ca])
    print("r=2 identical models vs KF: max |dx| =", np.max(np.abs(imm2["x"] - kf["x"])))

    imm_cv_ca = imm_oracle(z_, T_, sigma_, Pi2, np.array([0.9, 0.1]), [cv, ca])
    print("CV/CA IMM: mu(CA) at scans 2..N-1 =", np.round(imm_cv_ca["mu"][:, 1], 3))
    print("CV/CA IMM: final combined state  =", np.round(imm_cv_ca["x"][-1], 2))
