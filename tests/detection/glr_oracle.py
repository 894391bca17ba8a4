"""Independent brute-force oracle for the GLR and MLR maneuver tests (known-input Kalman filter re-runs).

Nothing here uses a bias-propagation recursion or a closed-form least-squares formula for the test
statistics: every likelihood ratio is obtained by *re-running* a Kalman filter with a hypothesised
constant input ``u`` and differencing Gaussian innovation log-likelihoods. It must not import anything
from ``motionsig_cli``.

Model (state ``[x, xdot, y, ydot]``)
------------------------------------
``F = blockdiag([[1, T], [0, 1]], [[1, T], [0, 1]])``,
``Gu = [[T^2/2, 0], [T, 0], [0, T^2/2], [0, T]]``,
``Q = q0 blockdiag(C, C)`` with ``C = [[T^3/3, T^2/2], [T^2/2, T]]`` (continuous white-noise acceleration),
``H`` picks ``x`` and ``y``, ``R = sigma^2 I_2``.

Scan indexing
-------------
Measurements ``z[j]``, ``j = 0..N-1``. ``(x0, P0)`` is the *predicted* prior at scan 0, so ``z[0]`` is
processed first by an update. After the update at scan ``j`` the filter predicts to ``j + 1`` with
``x <- F x (+ Gu u if j >= onset)``, ``P <- F P F^T + Q``. An input "from onset n" therefore first
affects the prediction of scan ``n + 1``.

Log-likelihood ratio ``l(u) = kf_loglik(u, onset=n, upto=k) - kf_loglik(None, upto=k)``;
``Delta J(n) = 2 max_u l(u)``; ``J_MLR(n) = log int exp(l(u)) N(u; 0, sigma_u^2 I_2) du``.

Why ``l`` is an exact concave quadratic in ``u``: the gain and ``S_j`` do not depend on ``u`` and the
innovations are affine in ``u``, so ``l(u) = l(0) + g^T u - u^T A u / 2`` with ``A >= 0``. Central finite
differences (step ``h``) reproduce the gradient and Hessian of a quadratic *exactly* for any ``h`` (only
rounding remains), which is how the maximiser / mode is located below. The statistic values themselves
are always evaluated through the filters.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy import integrate
from scipy.stats import multivariate_normal

__all__ = ["glr_brute", "kf_loglik", "mlr_brute", "model_matrices"]


def model_matrices(T: float, sigma: float, q0: float) -> dict[str, np.ndarray]:
    """Return ``F``, ``Gu``, ``Q``, ``H``, ``R`` of the CV model with a 2-D acceleration input."""
    F1 = np.array([[1.0, T], [0.0, 1.0]])
    F = np.zeros((4, 4))
    F[0:2, 0:2] = F1
    F[2:4, 2:4] = F1
    Gu = np.array([[0.5 * T * T, 0.0], [T, 0.0], [0.0, 0.5 * T * T], [0.0, T]])
    C = np.array([[T**3 / 3.0, T**2 / 2.0], [T**2 / 2.0, T]])
    Q = np.zeros((4, 4))
    Q[0:2, 0:2] = q0 * C
    Q[2:4, 2:4] = q0 * C
    H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
    R = sigma * sigma * np.eye(2)
    return {"F": F, "Gu": Gu, "Q": Q, "H": H, "R": R}


def kf_loglik(
    z: np.ndarray,
    T: float,
    sigma: float,
    q0: float,
    x0: np.ndarray,
    P0: np.ndarray,
    u: np.ndarray | None = None,
    onset: int | None = None,
    upto: int | None = None,
) -> float:
    """Gaussian innovation log-likelihood of a Kalman filter, optionally driven by a known input.

    Args:
        z: (N, 2) position measurements at scans 0..N-1.
        T: scan period.
        sigma: measurement noise standard deviation.
        q0: process-noise power spectral density.
        x0: (4,) predicted prior mean at scan 0.
        P0: (4, 4) predicted prior covariance at scan 0.
        u: (2,) known constant input, or None for no input.
        onset: input onset ``n``: ``Gu u`` is added in every prediction from scan ``j >= n`` to ``j + 1``.
            Ignored when ``u`` is None; ``None`` means 0.
        upto: last scan (inclusive) whose innovation enters the sum; default ``N - 1``.

    Returns:
        ``sum_{j=0}^{upto} log N(nu_j; 0, S_j)`` (via ``scipy.stats.multivariate_normal.logpdf``).
    """
    z = np.asarray(z, dtype=float)
    N = z.shape[0]
    last = N - 1 if upto is None else int(upto)
    start = 0 if onset is None else int(onset)
    m = model_matrices(T, sigma, q0)
    F, Gu, Q, H, R = m["F"], m["Gu"], m["Q"], m["H"], m["R"]
    x = np.asarray(x0, dtype=float).copy()
    P = np.asarray(P0, dtype=float).copy()
    total = 0.0
    for j in range(last + 1):
        # update with z[j]
        nu = z[j] - H @ x
        S = H @ P @ H.T + R
        S = 0.5 * (S + S.T)
        total += float(multivariate_normal.logpdf(nu, mean=np.zeros(2), cov=S))
        K = P @ H.T @ np.linalg.inv(S)
        x = x + K @ nu
        P = (np.eye(4) - K @ H) @ P
        P = 0.5 * (P + P.T)
        if j == last:
            break
        # predict to j + 1
        x = F @ x
        if u is not None and j >= start:
            x = x + Gu @ np.asarray(u, dtype=float)
        P = F @ P @ F.T + Q
    return total


def _llr_function(
    z: np.ndarray, T: float, sigma: float, q0: float, x0: np.ndarray, P0: np.ndarray, k: int, n: int
) -> Callable[[np.ndarray], float]:
    """Return ``l(u) = kf_loglik(u, onset=n, upto=k) - kf_loglik(None, upto=k)`` (baseline cached)."""
    base = kf_loglik(z, T, sigma, q0, x0, P0, None, None, k)

    def llr(u: np.ndarray) -> float:
        return kf_loglik(z, T, sigma, q0, x0, P0, np.asarray(u, dtype=float), n, k) - base

    return llr


def _fd_grad_hess(f: Callable[[np.ndarray], float], c: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Central finite-difference gradient and Hessian of ``f`` at ``c`` (exact for quadratics)."""
    g = np.zeros(2)
    Hs = np.zeros((2, 2))
    f0 = f(c)
    e = np.eye(2)
    for i in range(2):
        fp = f(c + h * e[i])
        fm = f(c - h * e[i])
        g[i] = (fp - fm) / (2.0 * h)
        Hs[i, i] = (fp - 2.0 * f0 + fm) / (h * h)
    fpp = f(c + h * e[0] + h * e[1])
    fpm = f(c + h * e[0] - h * e[1])
    fmp = f(c - h * e[0] + h * e[1])
    fmm = f(c - h * e[0] - h * e[1])
    Hs[0, 1] = Hs[1, 0] = (fpp - fpm - fmp + fmm) / (4.0 * h * h)
    return g, Hs


def _maximise_quadratic(
    f: Callable[[np.ndarray], float], h: float, iters: int = 3
) -> tuple[np.ndarray, np.ndarray]:
    """Newton iterations with finite-difference derivatives for a concave quadratic ``f`` on R^2.

    One iteration is exact for a quadratic; the extra iterations only polish rounding.

    Returns:
        ``(u_hat, A)`` with ``A = -Hessian`` (positive definite for a strictly concave ``f``).
    """
    c = np.zeros(2)
    A = np.eye(2)
    for _ in range(iters):
        g, Hs = _fd_grad_hess(f, c, h)
        A = -Hs
        if np.any(np.linalg.eigvalsh(0.5 * (A + A.T)) <= 0.0):
            raise ValueError("log-likelihood ratio is not strictly concave in u (input not observable)")
        c = c + np.linalg.solve(A, g)
    return c, A


def glr_brute(
    z: np.ndarray, T: float, sigma: float, q0: float, x0: np.ndarray, P0: np.ndarray, k: int, n: int
) -> tuple[float, np.ndarray]:
    """Brute-force GLR statistic for onset ``n`` at the current scan ``k`` (``n < k``).

    ``l(u)`` is evaluated only through Kalman filters re-run with the input; its maximiser is found by
    Newton steps with exact (for a quadratic) central finite differences, step 10 in input units.

    Returns:
        ``(Delta J, u_hat)`` with ``Delta J = 2 max_u l(u)`` (evaluated as ``2 l(u_hat)`` by a filter run).
    """
    if not 0 <= n < k:
        raise ValueError("need 0 <= n < k")
    llr = _llr_function(z, T, sigma, q0, x0, P0, k, n)
    u_hat, _A = _maximise_quadratic(llr, h=10.0)
    return 2.0 * llr(u_hat), u_hat


def mlr_brute(
    z: np.ndarray,
    T: float,
    sigma: float,
    q0: float,
    x0: np.ndarray,
    P0: np.ndarray,
    k: int,
    n: int,
    sigma_u: float,
    method: str = "gauss-hermite",
    order: int = 20,
) -> float:
    """Brute-force MLR statistic ``log int exp(l(u)) N(u; 0, sigma_u^2 I_2) du`` by 2-D numerical quadrature.

    Let ``g(u) = l(u) + log N(u; 0, sigma_u^2 I)``, always evaluated through Kalman filters re-run with the
    input. Its mode ``u*`` and ``A = -Hess g`` are located by finite-difference Newton steps; with
    ``A = L L^T`` we substitute ``u = u* + L^{-T} w`` (Jacobian ``1/det L``), so the integral becomes
    ``exp(g(u*)) / det L * int exp(g(u(w)) - g(u*)) dw`` and the result is returned in the log domain
    (subtracting ``g(u*)`` keeps the integrand in [0, 1], no overflow for large likelihood ratios).

    Methods:
        ``"gauss-hermite"`` (default): tensor Gauss–Hermite rule of ``order`` points per axis in ``w``,
        ``int f(w) dw = sum_ab W_a W_b f(w_ab) exp(|w_ab|^2 / 2)`` with ``w = sqrt(2) t`` (physicists'
        nodes ``t``, weights ``W = sqrt(2) w_GH``). Accuracy: the rule is exact for ``exp(-|w|^2/2)``
        times any polynomial of degree <= ``2 order - 1`` per axis. Since ``g`` is a quadratic in ``u``,
        ``f(w) exp(|w|^2/2) = exp(r(w))`` where ``r`` is a quadratic whose coefficients are only the
        rounding-level errors (~1e-9) of the finite-difference ``u*``, ``A``; the rule then errs by
        O(|r|^2) ~ 1e-18, far below 1e-8 (the value itself still comes from the filters, so a
        non-quadratic ``l`` would show up as an order-dependence, checked in the self-test).
        ``"dblquad"``: ``scipy.integrate.dblquad`` over the box ``w in [-10, 10]^2`` (truncated mass below
        ``2 erfc(10/sqrt 2) ~ 3e-23``), epsrel 1e-10. Assumption-free but slow (~10^4-10^5 filter runs).
    """
    if not 0 <= n < k:
        raise ValueError("need 0 <= n < k")
    llr = _llr_function(z, T, sigma, q0, x0, P0, k, n)
    prior_cov = sigma_u * sigma_u * np.eye(2)

    def g(u: np.ndarray) -> float:
        return llr(u) + float(multivariate_normal.logpdf(u, mean=np.zeros(2), cov=prior_cov))

    u_star, A = _maximise_quadratic(g, h=max(sigma_u, 1.0))
    g_star = g(u_star)
    L = np.linalg.cholesky(0.5 * (A + A.T))  # A = L L^T
    M = np.linalg.inv(L.T)  # u = u* + M w  =>  (u - u*)^T A (u - u*) = |w|^2
    log_jac = float(np.log(abs(np.linalg.det(M))))

    if method == "dblquad":

        def integrand(w2: float, w1: float) -> float:
            u = u_star + M @ np.array([w1, w2])
            return float(np.exp(g(u) - g_star))

        val, _err = integrate.dblquad(integrand, -10.0, 10.0, -10.0, 10.0, epsabs=0.0, epsrel=1e-10)
        return g_star + log_jac + float(np.log(val))

    if method != "gauss-hermite":
        raise ValueError(f"unknown method {method!r}")
    t, wts = np.polynomial.hermite.hermgauss(order)
    total = 0.0
    for a in range(order):
        for b in range(order):
            w = np.sqrt(2.0) * np.array([t[a], t[b]])
            u = u_star + M @ w
            # weight of the physicists' rule in w = sqrt(2) t: 2 * wts_a * wts_b, times exp(|w|^2 / 2)
            total += 2.0 * wts[a] * wts[b] * float(np.exp(g(u) - g_star + 0.5 * (w @ w)))
    return g_star + log_jac + float(np.log(total))


if __name__ == "__main__":
    import sys

    from scipy.optimize import minimize

    rng = np.random.default_rng(12345)
    T_, sigma_, q0_, N_ = 1.0, 50.0, 1.0, 25
    mats = model_matrices(T_, sigma_, q0_)
    u_true = np.array([20.0, -10.0])
    onset_true = 12
    x = np.array([0.0, 200.0, 0.0, -100.0])
    z_ = np.zeros((N_, 2))
    chol_Q = np.linalg.cholesky(mats["Q"])
    for j_ in range(N_):
        z_[j_] = mats["H"] @ x + sigma_ * rng.standard_normal(2)
        x = mats["F"] @ x + chol_Q @ rng.standard_normal(4)
        if j_ >= onset_true:
            x = x + mats["Gu"] @ u_true
    x0_ = np.array([z_[0, 0], (z_[1, 0] - z_[0, 0]) / T_, z_[0, 1], (z_[1, 1] - z_[0, 1]) / T_])
    P0_ = np.diag([sigma_**2, 2 * sigma_**2 / T_**2, sigma_**2, 2 * sigma_**2 / T_**2])

    k_ = 20
    for n_ in range(10, 15):
        dJ, uh = glr_brute(z_, T_, sigma_, q0_, x0_, P0_, k_, n_)
        print(f"k={k_} n={n_}: Delta J = {dJ:12.6f}   u_hat = ({uh[0]:9.4f}, {uh[1]:9.4f})")

    # Cross-check the GLR maximiser against a generic numerical optimiser at the true onset.
    llr_ = _llr_function(z_, T_, sigma_, q0_, x0_, P0_, k_, onset_true)
    res = minimize(
        lambda u: -llr_(u), np.zeros(2), method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-12}
    )
    dJ_nm = 2.0 * -res.fun
    dJ_fd, uh_fd = glr_brute(z_, T_, sigma_, q0_, x0_, P0_, k_, onset_true)
    print(f"Nelder-Mead check n={onset_true}: Delta J = {dJ_nm:.9f} (diff {dJ_nm - dJ_fd:.2e}), u = {res.x}")

    # MLR: Gauss-Hermite at two orders, and (slow, optional) adaptive dblquad.
    for su in (30.0, 5.0):
        j20 = mlr_brute(z_, T_, sigma_, q0_, x0_, P0_, k_, onset_true, su)
        j30 = mlr_brute(z_, T_, sigma_, q0_, x0_, P0_, k_, onset_true, su, order=30)
        msg = f"MLR n={onset_true} sigma_u={su}: GH(20) = {j20:.10f}  GH(30) = {j30:.10f}"
        if "--dblquad" in sys.argv:
            jdq = mlr_brute(z_, T_, sigma_, q0_, x0_, P0_, k_, onset_true, su, method="dblquad")
            msg += f"  dblquad = {jdq:.10f}"
        print(msg)
