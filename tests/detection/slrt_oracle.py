"""Independent, loop-based oracle for Seed S1 (distributed SLRT), spec §2 and §4 (P6, P7, P9, R7–R10).

Deliberately simple, single-run code (numpy/scipy only) written without reference to the production
package. All scores are in the log domain (spec §2.1 "Numerics").
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence

import numpy as np
from scipy import integrate
from scipy.linalg import cholesky, solve_triangular
from scipy.special import logsumexp

Array = np.ndarray
Fn = Callable[[Array], Array]


def _log_gauss(x: Array, mean: Array, cov: Array) -> float:
    """log N(x; mean, cov) via Cholesky (spec §2.1)."""
    d = np.atleast_1d(np.asarray(x, float) - np.asarray(mean, float))
    chol = cholesky(np.atleast_2d(cov), lower=True)
    sol = solve_triangular(chol, d, lower=True)
    return float(-0.5 * sol @ sol - np.log(np.diag(chol)).sum() - 0.5 * d.size * np.log(2.0 * np.pi))


def _sym(P: Array) -> Array:
    return 0.5 * (P + P.T)


def _wrap(angle: float) -> float:
    """Wrap to (−π, π] (spec §2.3 step 1)."""
    return float(np.pi - np.mod(np.pi - angle, 2.0 * np.pi))


def cv_model(T: float, q: float) -> tuple[Array, Array]:
    """Nearly-constant-velocity F, Q for state [x, vx, y, vy] (spec §2.5 'target motion')."""
    F1 = np.array([[1.0, T], [0.0, 1.0]])
    Q1 = q * np.array([[T**3 / 3.0, T**2 / 2.0], [T**2 / 2.0, T]])
    F, Q = np.zeros((4, 4)), np.zeros((4, 4))
    F[:2, :2] = F[2:, 2:] = F1
    Q[:2, :2] = Q[2:, 2:] = Q1
    return F, Q


def gaussian_product_constant_quadrature(means: Sequence[Array], covs: Sequence[Array]) -> float:
    """log c, c = ∫ ∏_s N(x; m_s, P_s) dx by quad/dblquad on ±10 sd around the fused mean (spec §2.4 FC).

    The integrand is scaled by exp(−L0), L0 = Σ_s log N(x̄; m_s, P_s) at the fused mean x̄, to avoid underflow.
    """
    means = [np.atleast_1d(np.asarray(m, float)) for m in means]
    covs = [np.atleast_2d(np.asarray(P, float)) for P in covs]
    info = sum(np.linalg.inv(P) for P in covs)
    P_f = np.linalg.inv(info)
    x_f = P_f @ sum(np.linalg.inv(P) @ m for m, P in zip(means, covs, strict=True))
    L0 = sum(_log_gauss(x_f, m, P) for m, P in zip(means, covs, strict=True))
    sd = np.sqrt(np.diag(P_f))
    lo, hi = x_f - 10.0 * sd, x_f + 10.0 * sd

    def integrand(x: Array) -> float:
        return float(np.exp(sum(_log_gauss(x, m, P) for m, P in zip(means, covs, strict=True)) - L0))

    opts = {"epsabs": 1e-14, "epsrel": 1e-12}
    if x_f.size == 1:
        val, _ = integrate.quad(lambda u: integrand(np.array([u])), lo[0], hi[0], limit=200, **opts)
    elif x_f.size == 2:
        val, _ = integrate.dblquad(
            lambda y, x: integrand(np.array([x, y])), lo[0], hi[0], lo[1], hi[1], **opts
        )
    else:
        raise ValueError("quadrature oracle supports 1-D or 2-D states only")
    return float(L0 + np.log(val))


def gaussian_product_constant_closed(means: Sequence[Array], covs: Sequence[Array]) -> float:
    """log c with c = ∏_{s=1}^{S−1} N(x^{s+1}; x^{(1:s)}, P^{(1:s)} + P^{s+1}) (spec §2.4, fixed P^{s+1}).

    With S = 1 the empty product gives log c = 0.
    """
    means = [np.atleast_1d(np.asarray(m, float)) for m in means]
    covs = [np.atleast_2d(np.asarray(P, float)) for P in covs]
    x_run, P_run = means[0], covs[0]
    log_c = 0.0
    for s in range(1, len(means)):
        log_c += _log_gauss(means[s], x_run, P_run + covs[s])
        info = np.linalg.inv(P_run) + np.linalg.inv(covs[s])
        P_new = _sym(np.linalg.inv(info))
        x_run = P_new @ (np.linalg.solve(P_run, x_run) + np.linalg.solve(covs[s], means[s]))
        P_run = P_new
    return log_c


def local_update(
    m: Array,
    P: Array,
    Z: Array,
    h: Fn,
    H_jac: Fn,
    R: Array,
    pd: float,
    rho_f: float,
    wrap_index: int | None = None,
) -> tuple[Array, Array, float]:
    """Local node update, spec §2.3 steps 1–5: explicit components + explicit moment matching.

    Returns (m⁺, P⁺, log p̄). For pd == 1 the j = 0 (missed detection) term is omitted (spec P7).
    """
    z_hat, H = np.asarray(h(m), float), np.asarray(H_jac(m), float)
    S_inn = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S_inn)
    P_det = _sym((np.eye(P.shape[0]) - K @ H) @ P)
    comps: list[tuple[Array, Array]] = []
    log_w: list[float] = []
    if pd < 1.0:
        comps.append((m.copy(), P.copy()))
        log_w.append(float(np.log(1.0 - pd)))
    for z in np.asarray(Z, float).reshape(-1, R.shape[0]):
        nu = z - z_hat
        if wrap_index is not None:
            nu[wrap_index] = _wrap(nu[wrap_index])
        log_w.append(float(np.log(pd / rho_f)) + _log_gauss(nu, np.zeros_like(nu), S_inn))
        comps.append((m + K @ nu, P_det))
    if not comps:  # pd == 1 and no measurement: the hypothesis has zero likelihood
        return m.copy(), P.copy(), -np.inf
    log_pbar = float(logsumexp(log_w))
    w = [float(np.exp(lw - log_pbar)) for lw in log_w]
    m_plus = sum((wj * mj for wj, (mj, _) in zip(w, comps, strict=True)), np.zeros(m.shape))
    P_plus = np.zeros_like(P, dtype=float)
    for wj, (mj, Pj) in zip(w, comps, strict=True):
        d = mj - m_plus
        P_plus = P_plus + wj * (Pj + np.outer(d, d))
    return m_plus, _sym(P_plus), log_pbar


def _sensor_model(pos: Array, meas_model: str) -> tuple[Fn, Fn, int | None]:
    """h, Jacobian and wrap index for one sensor (spec §2.5 'measurement'; P7 'cartesian')."""
    if meas_model == "cartesian":
        H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
        return (lambda x: H @ x), (lambda x: H), None
    if meas_model != "range_bearing":
        raise ValueError(meas_model)
    sx, sy = float(pos[0]), float(pos[1])

    def h(x: Array) -> Array:
        dx, dy = x[0] - sx, x[2] - sy
        return np.array([np.hypot(dx, dy), np.arctan2(dy, dx)])

    def jac(x: Array) -> Array:
        dx, dy = x[0] - sx, x[2] - sy
        r2 = dx * dx + dy * dy
        r = np.sqrt(r2)
        return np.array([[dx / r, 0.0, dy / r, 0.0], [-dy / r2, 0.0, dx / r2, 0.0]])

    return h, jac, 1


def run_methods(
    scan_data: Sequence[Sequence[Array]],
    sensors: Sequence[Array],
    F: Array,
    Q: Array,
    m0: Array,
    P0: Array,
    pd: float,
    rho_f: float,
    R: Array | Sequence[Array],
    meas_model: str,
) -> dict[str, Array]:
    """Cumulative log LR(k), k = 1..K, for CKF, LKF and DKF on one run (spec §2.4); log LR(0) = 0.

    scan_data[k][s]: (m_s, 2) measurements; sensors: list of positions; R: one matrix or one per sensor.
    Also returns 'CKF_inc'/'DKF_inc' (log Λ(k)).
    """
    n_sensors, n_scans = len(sensors), len(scan_data)
    Rs = list(R) if isinstance(R, (list, tuple)) else [np.asarray(R, float)] * n_sensors
    models = [_sensor_model(np.asarray(p, float), meas_model) for p in sensors]
    out = {key: np.zeros(n_scans) for key in ("CKF", "LKF", "DKF", "CKF_inc", "DKF_inc")}

    def upd(m: Array, P: Array, s: int, Z: Array) -> tuple[Array, Array, float]:
        h, jac, wi = models[s]
        return local_update(m, P, Z, h, jac, Rs[s], pd, rho_f, wi)

    # CKF: one filter, true model, sequential sensor processing with MM after each sensor.
    m, P, log_lr = np.array(m0, float), np.array(P0, float), 0.0
    for k in range(n_scans):
        m, P = F @ m, _sym(F @ P @ F.T + Q)
        lam = 0.0
        for s in range(n_sensors):
            m, P, lp = upd(m, P, s, scan_data[k][s])
            lam += lp
        log_lr += lam
        out["CKF_inc"][k], out["CKF"][k] = lam, log_lr
    # LKF: independent single-sensor filters, arithmetic mean of LRs.
    loc = [(np.array(m0, float), np.array(P0, float)) for _ in range(n_sensors)]
    log_lr_s = np.zeros(n_sensors)
    for k in range(n_scans):
        for s in range(n_sensors):
            m, P = loc[s]
            m, P, lp = upd(F @ m, _sym(F @ P @ F.T + Q), s, scan_data[k][s])
            loc[s] = (m, P)
            log_lr_s[s] += lp
        out["LKF"][k] = float(logsumexp(log_lr_s)) - np.log(n_sensors)
    # DKF: relaxed model (n_sensors·Q), locals at n_sensors·P0, FC constants from the closed form.
    loc = [(np.array(m0, float), n_sensors * np.array(P0, float)) for _ in range(n_sensors)]
    log_lr = 0.0
    for k in range(n_scans):
        pred = [(F @ m, _sym(F @ P @ F.T + n_sensors * Q)) for m, P in loc]
        log_c_pred = gaussian_product_constant_closed([p[0] for p in pred], [p[1] for p in pred])
        sum_lp = 0.0
        for s in range(n_sensors):
            m, P, lp = upd(pred[s][0], pred[s][1], s, scan_data[k][s])
            loc[s] = (m, P)
            sum_lp += lp
        log_c_post = gaussian_product_constant_closed([p[0] for p in loc], [p[1] for p in loc])
        lam = log_c_post - log_c_pred + sum_lp
        log_lr += lam
        out["DKF_inc"][k], out["DKF"][k] = lam, log_lr
    return out


def _simulate(rng, sensors, F, Q, x0, n_scans, pd, lam_f, R, meas_model, r_max=26000.0) -> list:
    """One run of spec §2.5 data: target detections (prob pd) plus Poisson clutter in the polar FoV."""
    x, data = np.array(x0, float), []
    for _ in range(n_scans):
        x = F @ x + rng.multivariate_normal(np.zeros(4), Q)
        scan = []
        for s, pos in enumerate(sensors):
            h = _sensor_model(np.asarray(pos, float), meas_model)[0]
            Rs = R[s] if isinstance(R, list) else R
            zs = [h(x) + rng.multivariate_normal(np.zeros(2), Rs)] if rng.random() < pd else []
            for _ in range(rng.poisson(lam_f)):
                zs.append(np.array([rng.uniform(0.0, r_max), rng.uniform(-np.pi, np.pi)]))
            scan.append(np.array(zs).reshape(-1, 2))
        data.append(scan)
    return data


if __name__ == "__main__":
    rng = np.random.default_rng(2024)
    print("(a) Gaussian product constant: closed form vs quadrature")
    for dim in (1, 2):
        means = [rng.normal(0.0, 2.0, dim) for _ in range(3)]
        covs = [(A := rng.normal(size=(dim, dim))) @ A.T + 0.5 * np.eye(dim) for _ in range(3)]
        lq = gaussian_product_constant_quadrature(means, covs)
        lc = gaussian_product_constant_closed(means, covs)
        perms = itertools.permutations(range(3))
        dperm = max(
            abs(gaussian_product_constant_closed([means[i] for i in p], [covs[i] for i in p]) - lc)
            for p in perms
        )
        print(
            f"  dim={dim} S=3: log c closed={lc:.12f} quad={lq:.12f} |diff|={abs(lc - lq):.2e} "
            f"max|order diff|={dperm:.2e}"
        )

    F, Q = cv_model(1.0, 10.0)
    x0 = np.array([0.0, 150.0, 0.0, 50.0])
    P0 = np.diag([200.0**2, 50.0**2, 200.0**2, 50.0**2])
    R_rb = np.diag([50.0**2, np.deg2rad(0.2) ** 2])
    rho_rb = 5.0 / (26000.0 * 2.0 * np.pi)
    ang = np.deg2rad([0.0, 90.0, 180.0, 270.0])
    radars = [13000.0 * np.array([np.cos(a), np.sin(a)]) for a in ang]

    print("(b) P6: one sensor (range-bearing, pd=0.9, λ_F=5): CKF = LKF = DKF")
    m0 = x0 + cholesky(P0, lower=True) @ rng.standard_normal(4)
    data = _simulate(rng, radars[:1], F, Q, x0, 20, 0.9, 5.0, R_rb, "range_bearing")
    res = run_methods(data, radars[:1], F, Q, m0, P0, 0.9, rho_rb, R_rb, "range_bearing")
    print(
        f"  log LR(20): CKF={res['CKF'][-1]:.6f}  max|CKF−LKF|={np.max(np.abs(res['CKF'] - res['LKF'])):.2e}"
        f"  max|CKF−DKF|={np.max(np.abs(res['CKF'] - res['DKF'])):.2e}"
    )

    print("(c) P7: 4 Cartesian sensors, R=diag(50²,50²), pd=1, no clutter, 1 meas/sensor")
    cart_pos = [rng.uniform(-20000.0, 20000.0, 2) for _ in range(4)]
    R_c = np.diag([50.0**2, 50.0**2])
    R_het = [np.diag([sd**2, sd**2]) for sd in (30.0, 50.0, 80.0, 120.0)]
    for label, Rc in (("identical R", R_c), ("heterogeneous R (30/50/80/120 m)", R_het)):
        m0 = x0 + cholesky(P0, lower=True) @ rng.standard_normal(4)
        data = _simulate(rng, cart_pos, F, Q, x0, 10, 1.0, 0.0, Rc, "cartesian")
        res = run_methods(data, cart_pos, F, Q, m0, P0, 1.0, 1e-6, Rc, "cartesian")
        d = res["DKF_inc"] - res["CKF_inc"]
        print(f"  {label}: log Λ(1) CKF={res['CKF_inc'][0]:.9f} DKF={res['DKF_inc'][0]:.9f} diff={d[0]:.2e}")
        print("    later-scan log Λ diffs (k=2..10): " + " ".join(f"{v:.1e}" for v in d[1:]))

    print("(extra) default 4-radar scenario, pd=0.9, one run, 30 scans: final log LR")
    m0 = x0 + cholesky(P0, lower=True) @ rng.standard_normal(4)
    data = _simulate(rng, radars, F, Q, x0, 30, 0.9, 5.0, R_rb, "range_bearing")
    res = run_methods(data, radars, F, Q, m0, P0, 0.9, rho_rb, R_rb, "range_bearing")
    print(f"  CKF={res['CKF'][-1]:.1f}  DKF={res['DKF'][-1]:.1f}  LKF={res['LKF'][-1]:.1f}")
