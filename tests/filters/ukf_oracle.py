"""Independent test oracle: scaled unscented Kalman filter and the 2-D radar vehicle (spec §1.6–§1.7).

Everything here is written from the formulas in the spec, deliberately slowly and explicitly (plain
Python loops over sigma points and time steps), so that it can serve as a reference for the fast
implementation in ``motionsig_cli``. It must not import anything from ``motionsig_cli``.

Conventions
-----------
* Angles are wrapped to the half-open interval (-pi, pi]: ``wrap(pi) == pi`` and ``wrap(-pi) == pi``.
* Scaled unscented transform (Van der Merwe): ``lam = alpha**2 (n + kappa) - n``; sigma points use the
  *upper* Cholesky factor ``U`` of ``(n + lam) P`` (``U.T @ U == (n + lam) P``) and take its rows, in
  FilterPy's ``MerweScaledSigmaPoints`` order: ``x, x + U[0], ..., x + U[n-1], x - U[0], ..., x - U[n-1]``.
* The UKF has additive process and measurement noise; the prediction step is the exact linear KF
  prediction ``x <- F x``, ``P <- F P F^T + Q``. The filter starts from a *predicted* prior and updates
  with the first measurement before the first prediction.
* 2-D closed-loop vehicle state order: ``[x, xdot, y, ydot, r_x, rdot_x, r_y, rdot_y]`` (+ ``[a_x, a_y]``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
import scipy.linalg

__all__ = [
    "merwe_weights",
    "range_bearing",
    "sigma_points",
    "simulate_2d",
    "transition_2d",
    "ukf_run",
    "ut_moments",
    "wrap",
]

TWO_PI = 2.0 * np.pi


# ----------------------------------------------------------------------------------------------------
# Angles
# ----------------------------------------------------------------------------------------------------
def wrap(a: float | np.ndarray) -> float | np.ndarray:
    """Wrap angle(s) to (-pi, pi].

    ``np.mod(a + pi, 2 pi) - pi`` lies in [-pi, pi); the single value -pi is then mapped to +pi, so that
    an input of exactly pi (or -pi, or 3 pi, ...) returns pi.

    Args:
        a: scalar or array of angles in radians.

    Returns:
        The wrapped angle(s): a Python float for scalar input, otherwise an ndarray of the same shape.
    """
    arr = np.asarray(a, dtype=float)
    out = np.mod(arr + np.pi, TWO_PI) - np.pi
    out = np.where(out <= -np.pi, np.pi, out)
    if out.ndim == 0:
        return float(out)
    return out


# ----------------------------------------------------------------------------------------------------
# Scaled unscented transform
# ----------------------------------------------------------------------------------------------------
def merwe_weights(n: int, alpha: float, beta: float, kappa: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Weights of the scaled unscented transform (Van der Merwe), 2n + 1 points.

    Args:
        n: state dimension.
        alpha, beta, kappa: the usual scaling parameters.

    Returns:
        ``(Wm, Wc, c)``: mean weights (2n+1,), covariance weights (2n+1,) and the spread ``c = sqrt(n + lam)``
        with ``lam = alpha**2 (n + kappa) - n``.
    """
    lam = alpha**2 * (n + kappa) - n
    Wm = np.empty(2 * n + 1)
    Wc = np.empty(2 * n + 1)
    Wm[0] = lam / (n + lam)
    Wc[0] = Wm[0] + (1.0 - alpha**2 + beta)
    for i in range(1, 2 * n + 1):
        Wm[i] = 1.0 / (2.0 * (n + lam))
        Wc[i] = 1.0 / (2.0 * (n + lam))
    c = float(np.sqrt(n + lam))
    return Wm, Wc, c


def sigma_points(x: np.ndarray, P: np.ndarray, alpha: float, beta: float, kappa: float) -> np.ndarray:
    """Scaled sigma points in FilterPy ``MerweScaledSigmaPoints`` order.

    ``U = cholesky((n + lam) P, lower=False)`` (upper factor); ``chi_0 = x``, ``chi_i = x + U[i-1]`` and
    ``chi_{n+i} = x - U[i-1]`` for ``i = 1..n`` (rows of ``U``).

    Args:
        x: mean (n,).
        P: covariance (n, n), symmetric positive definite.
        alpha, beta, kappa: scaling parameters (``beta`` does not affect the points).

    Returns:
        Sigma points, shape (2n + 1, n).
    """
    x = np.asarray(x, dtype=float).reshape(-1)
    P = np.asarray(P, dtype=float)
    n = x.shape[0]
    lam = alpha**2 * (n + kappa) - n
    U = scipy.linalg.cholesky((n + lam) * P, lower=False)
    chi = np.empty((2 * n + 1, n))
    chi[0] = x
    for i in range(1, n + 1):
        chi[i] = x + U[i - 1]
        chi[n + i] = x - U[i - 1]
    return chi


def ut_moments(
    x: np.ndarray,
    P: np.ndarray,
    h: Callable[[np.ndarray], np.ndarray],
    alpha: float,
    beta: float,
    kappa: float,
    angular: Sequence[bool],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unscented-transform moments of ``y = h(x)`` for ``x ~ N(x, P)`` (no measurement noise).

    Angular components of ``y`` are averaged around the centre point: ``Y_0 + sum_i Wm_i wrap(Y_i - Y_0)``
    (then wrapped); their residuals are wrapped too.

    Args:
        x: mean (n,).
        P: covariance (n, n).
        h: measurement function, state (n,) -> measurement (m,).
        alpha, beta, kappa: scaling parameters.
        angular: m booleans, True for angle-valued measurement components.

    Returns:
        ``(y_mean, S_noiseless, Pxy)`` with shapes (m,), (m, m), (n, m).
    """
    x = np.asarray(x, dtype=float).reshape(-1)
    n = x.shape[0]
    Wm, Wc, _ = merwe_weights(n, alpha, beta, kappa)
    chi = sigma_points(x, P, alpha, beta, kappa)
    Y = np.array([np.asarray(h(chi[i]), dtype=float).reshape(-1) for i in range(2 * n + 1)])
    m = Y.shape[1]
    ang = [bool(b) for b in angular]
    if len(ang) != m:
        raise ValueError(f"angular has {len(ang)} entries, measurement has {m}")

    y_mean = np.zeros(m)
    for j in range(m):
        if ang[j]:
            acc = 0.0
            for i in range(2 * n + 1):
                acc += Wm[i] * wrap(Y[i, j] - Y[0, j])
            y_mean[j] = wrap(Y[0, j] + acc)
        else:
            acc = 0.0
            for i in range(2 * n + 1):
                acc += Wm[i] * Y[i, j]
            y_mean[j] = acc

    S = np.zeros((m, m))
    Pxy = np.zeros((n, m))
    for i in range(2 * n + 1):
        e = Y[i] - y_mean
        for j in range(m):
            if ang[j]:
                e[j] = wrap(e[j])
        dx = chi[i] - x
        S += Wc[i] * np.outer(e, e)
        Pxy += Wc[i] * np.outer(dx, e)
    return y_mean, S, Pxy


# ----------------------------------------------------------------------------------------------------
# UKF run
# ----------------------------------------------------------------------------------------------------
def ukf_run(
    F_seq: Sequence[np.ndarray] | np.ndarray,
    Q: np.ndarray,
    h: Callable[[np.ndarray], np.ndarray],
    R: np.ndarray,
    x0: np.ndarray,
    P0: np.ndarray,
    ys: np.ndarray,
    alpha: float = 1.0,
    beta: float = 2.0,
    kappa: float = 0.0,
    angular: Sequence[bool] | None = None,
) -> dict[str, np.ndarray]:
    """Additive-noise UKF with UT update and exact linear prediction.

    Starts from the *predicted* prior ``(x0, P0)`` at k = 0. For k = 0..N-1: update with ``ys[k]``
    (``S = S0 + R``, ``nu = ys[k] - y_mean`` with angular components wrapped, ``K = Pxy S^-1``,
    ``x += K nu``, ``P -= K S K^T``), record ``nu, S, q = nu^T S^-1 nu, log det(2 pi S)``; then, if
    k < N-1, predict ``x = F_k x``, ``P = F_k P F_k^T + Q``.

    Args:
        F_seq: transition matrices; ``F_seq[k]`` is used for the prediction k -> k+1 (at least N-1 of
            them). A single 2-D (n, n) array is accepted as a constant transition.
        Q: process noise covariance (n, n), per step.
        h: measurement function, state (n,) -> measurement (m,).
        R: measurement noise covariance (m, m) (a scalar or (m,) diagonal is also accepted).
        x0, P0: predicted prior mean (n,) and covariance (n, n) at k = 0.
        ys: measurements (N, m).
        alpha, beta, kappa: UT scaling parameters.
        angular: m booleans for angle-valued measurement components (default: none).

    Returns:
        dict with ``'nu'`` (N, m), ``'S'`` (N, m, m), ``'q'`` (N,), ``'logdet'`` (N,) (= log det 2 pi S),
        ``'x'`` (n,) and ``'P'`` (n, n) final posterior, ``'J'`` = 0.5 cumsum(q) (N,) and
        ``'loglik'`` = -0.5 cumsum(q + logdet) (N,).
    """
    ys = np.asarray(ys, dtype=float)
    if ys.ndim == 1:
        ys = ys[:, None]
    N, m = ys.shape
    x = np.asarray(x0, dtype=float).reshape(-1).copy()
    P = np.asarray(P0, dtype=float).copy()
    Q = np.asarray(Q, dtype=float)
    R = np.asarray(R, dtype=float)
    if R.ndim == 0:
        R = R * np.eye(m)
    elif R.ndim == 1:
        R = np.diag(R)
    if angular is None:
        angular = (False,) * m
    ang = [bool(b) for b in angular]
    F_arr = np.asarray(F_seq, dtype=float)
    constant_F = F_arr.ndim == 2

    nus = np.zeros((N, m))
    Ss = np.zeros((N, m, m))
    qs = np.zeros(N)
    logdets = np.zeros(N)

    for k in range(N):
        # --- update with ys[k] ---
        y_mean, S0, Pxy = ut_moments(x, P, h, alpha, beta, kappa, ang)
        S = S0 + R
        nu = ys[k] - y_mean
        for j in range(m):
            if ang[j]:
                nu[j] = wrap(nu[j])
        S_inv = np.linalg.inv(S)
        K = Pxy @ S_inv
        x = x + K @ nu
        P = P - K @ S @ K.T
        sign, ld = np.linalg.slogdet(TWO_PI * S)
        if sign <= 0:
            raise np.linalg.LinAlgError("innovation covariance is not positive definite")
        nus[k] = nu
        Ss[k] = S
        qs[k] = float(nu @ S_inv @ nu)
        logdets[k] = ld

        # --- exact linear prediction ---
        if k < N - 1:
            F = F_arr if constant_F else F_arr[k]
            x = F @ x
            P = F @ P @ F.T + Q

    return {
        "nu": nus,
        "S": Ss,
        "q": qs,
        "logdet": logdets,
        "x": x,
        "P": P,
        "J": 0.5 * np.cumsum(qs),
        "loglik": -0.5 * np.cumsum(qs + logdets),
    }


# ----------------------------------------------------------------------------------------------------
# Radar measurement and 2-D closed-loop vehicle (spec §1.7, eqs 59-62)
# ----------------------------------------------------------------------------------------------------
def range_bearing(x: np.ndarray) -> np.ndarray:
    """Radar at the origin: ``[sqrt(px^2 + py^2), atan2(py, px)]`` with ``px = x[0]``, ``py = x[2]``.

    Args:
        x: state vector (any length >= 3) with positions at indices 0 (x) and 2 (y).

    Returns:
        ``[range, bearing]`` (2,).
    """
    px = float(x[0])
    py = float(x[2])
    return np.array([np.sqrt(px * px + py * py), np.arctan2(py, px)])


def transition_2d(T: float, k1: float, k2: float, g: tuple[float, float] | None = None) -> np.ndarray:
    """Closed-loop transition of the 2-D vehicle with reference states (and optional amplitudes).

    State order ``[x, xdot, y, ydot, r_x, rdot_x, r_y, rdot_y]`` (8x8) or, when ``g = (g_x, g_y)`` is
    given, ``[..., a_x, a_y]`` (10x10). Per axis (p, v, r, rd):

    * ``p'  = p + T v``
    * ``v'  = -T k1 p + (1 - T k2) v + T k1 r + T k2 rd  (+ g_axis a_axis)``
    * ``r'  = r + T rd``
    * ``rd' = rd``
    * ``a'  = a``

    Args:
        T: sample period.
        k1, k2: controller gains.
        g: ``(g_x, g_y)`` with ``g_axis = T (k1 z_k + k2 zdot_k)``, or None for the 8-state model.

    Returns:
        F, (8, 8) or (10, 10).
    """
    n = 8 if g is None else 10
    F = np.zeros((n, n))
    # (position index, velocity index, reference index, reference-rate index, amplitude index)
    axes = [(0, 1, 4, 5, 8), (2, 3, 6, 7, 9)]
    for axis, (ip, iv, ir, ird, ia) in enumerate(axes):
        F[ip, ip] = 1.0
        F[ip, iv] = T
        F[iv, ip] = -T * k1
        F[iv, iv] = 1.0 - T * k2
        F[iv, ir] = T * k1
        F[iv, ird] = T * k2
        F[ir, ir] = 1.0
        F[ir, ird] = T
        F[ird, ird] = 1.0
        if g is not None:
            F[iv, ia] = float(g[axis])
            F[ia, ia] = 1.0
    return F


def simulate_2d(
    T: float,
    k1: float,
    k2: float,
    a_x: float,
    a_y: float,
    a_r: float,
    f_r: float,
    sigma_a: float,
    R_range: float,
    R_bearing: float,
    start: tuple[float, float],
    z: np.ndarray,
    zdot: np.ndarray,
    w: np.ndarray,
    v: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Truth simulation of the 2-D closed-loop vehicle with a radar at the origin.

    Per axis the truth is ``[pos, vel]``, starting at ``start`` with zero velocity. References
    ``r_axis(t) = start_axis + a_r sin(2 pi f_r t)``, ``rdot(t) = 2 pi f_r a_r cos(2 pi f_r t)``, t_k = k T.
    For k = 0..N-1: record the state, measure (range/bearing of the true position plus noise, bearing
    wrapped), then apply ``u = k1 (-pos + r + a_axis z_k) + k2 (-vel + rdot + a_axis zdot_k)`` and
    ``acc = sigma_a w[k, axis]``: ``pos' = pos + T vel + T^2/2 acc``, ``vel' = vel + T u + T acc``.

    Args:
        T: sample period.
        k1, k2: controller gains.
        a_x, a_y: signature amplitude per axis.
        a_r, f_r: reference amplitude and frequency.
        sigma_a: acceleration noise standard deviation.
        R_range, R_bearing: measurement noise variances (m^2, rad^2).
        start: ``(x0, y0)`` start position (also the reference centre).
        z, zdot: signature and its derivative, shape (N,).
        w: standard-normal process draws (N, 2) (column 0 = x axis, 1 = y axis).
        v: standard-normal measurement draws (N, 2) (column 0 = range, 1 = bearing).

    Returns:
        ``(X, Y)``: truth ``[x, xdot, y, ydot]`` per step (N, 4) and measurements ``[range, bearing]`` (N, 2).
    """
    z = np.asarray(z, dtype=float).reshape(-1)
    zdot = np.asarray(zdot, dtype=float).reshape(-1)
    w = np.asarray(w, dtype=float)
    v = np.asarray(v, dtype=float)
    N = z.shape[0]
    amp = [float(a_x), float(a_y)]
    centre = [float(start[0]), float(start[1])]
    pos = [centre[0], centre[1]]
    vel = [0.0, 0.0]

    X = np.zeros((N, 4))
    Y = np.zeros((N, 2))
    for k in range(N):
        t = k * T
        X[k] = [pos[0], vel[0], pos[1], vel[1]]
        rng = np.sqrt(pos[0] ** 2 + pos[1] ** 2)
        brg = np.arctan2(pos[1], pos[0])
        Y[k, 0] = rng + np.sqrt(R_range) * v[k, 0]
        Y[k, 1] = wrap(brg + np.sqrt(R_bearing) * v[k, 1])

        ref_rate = TWO_PI * f_r * a_r * np.cos(TWO_PI * f_r * t)
        for axis in range(2):
            ref = centre[axis] + a_r * np.sin(TWO_PI * f_r * t)
            u = k1 * (-pos[axis] + ref + amp[axis] * z[k]) + k2 * (
                -vel[axis] + ref_rate + amp[axis] * zdot[k]
            )
            acc = sigma_a * w[k, axis]
            new_pos = pos[axis] + T * vel[axis] + 0.5 * T**2 * acc
            new_vel = vel[axis] + T * u + T * acc
            pos[axis] = new_pos
            vel[axis] = new_vel
    return X, Y
