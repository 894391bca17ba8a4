"""Independent oracle for ``track-sat`` (ATC-10, Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory,
1972, §4: satellite multilateration with clock tracking).

Written from the report's equations and the project's written reference values only, without reference
to ``motionsig_cli``. It deliberately uses *different* methods from those of the production code, so that
agreement is meaningful:

* geometry: mpmath at 50 digits with explicit normal-equation inverses (no QR);
* ψ(α): polynomial root of ψ³ + (27α/4)(ψ − 1) = 0 (no closed-form cube roots);
* clock-error variance: brute-force covariance of explicit coefficient vectors over the
  independent primitives {a_0, w_1..w_n, v_0..v_n} (no χ recursion);
* snapshot LS covariance (eq. 4.1.1): via a random differencing matrix H (no projection identity).

Units: c = 1 (light-ns) for geometry; times in ns; RMS converted with a caller-given c in ft/ns.
"""

from __future__ import annotations

from collections.abc import Sequence

import mpmath as mp
import numpy as np

_DPS = 50

EX_I: list[tuple[float, float]] = [
    (14.9, 152.7), (63.4, 115.0), (36.6, 101.8), (51.0, 123.2), (51.0, 106.8), (60.1, 80.5), (60.1, 79.5),
]  # fmt: skip
EX_II: list[tuple[float, float]] = [
    (27.0, 109.8), (44.5, 129.5), (62.6, 80.4), (62.6, 114.6),
    (56.2, 111.6), (27.0, 85.3), (44.5, 65.5), (56.2, 83.4),
]  # fmt: skip


def _ecef(lat_deg: float, lon_deg: float, r: mp.mpf) -> mp.matrix:
    """Spherical-Earth ECEF point; longitudes used exactly as given."""
    phi, lam = mp.radians(mp.mpf(str(lat_deg))), mp.radians(mp.mpf(str(lon_deg)))
    return mp.matrix([r * mp.cos(phi) * mp.cos(lam), r * mp.cos(phi) * mp.sin(lam), r * mp.sin(phi)])


def geometry_oracle(
    sats_latlon_deg: Sequence[tuple[float, float]],
    aircraft_latlon_deg: tuple[float, float] = (45.0, 120.0),
    r_sat_over_re: float = 9.235,
    r_earth_km: float = 6378.137,
    subset: Sequence[int] | None = None,
) -> dict[str, float | None]:
    """β, tr, b, b_literal and GDOP of one constellation (the report's notation).

    ``subset`` holds **1-based** satellite numbers (e.g. ``(1, 2, 3)``, as in Table 4.1); None = all.
    U has rows u_i = unit vector from satellite i to the aircraft (altitude 0).  With c = 1:
    beta = K − 1'U(U'U)⁻¹U'1, tr = tr (U'U)⁻¹, b = 1'U(U'U)⁻²U'1 (= 1'(UU')⁻¹1 for K = 3, the correct
    b3), b_literal = 1'(U'U)⁻¹1 (frame-dependent, what the report apparently used for K = 3),
    gdop = sqrt(tr + b/beta) for K ≥ 4, else None.
    """
    with mp.workdps(_DPS):
        idx = range(1, len(sats_latlon_deg) + 1) if subset is None else subset
        re = mp.mpf(str(r_earth_km))
        rs = re * mp.mpf(str(r_sat_over_re))
        p = _ecef(aircraft_latlon_deg[0], aircraft_latlon_deg[1], re)
        rows = []
        for i in idx:
            d = p - _ecef(*sats_latlon_deg[i - 1], rs)
            rows.append([x / mp.norm(d) for x in d])
        k = len(rows)
        u = mp.matrix(rows)
        one = mp.ones(k, 1)
        ninv = mp.inverse(u.T * u)
        ut1 = u.T * one
        beta = k - (ut1.T * ninv * ut1)[0]
        tr = sum(ninv[j, j] for j in range(3))
        b = (ut1.T * ninv * ninv * ut1)[0]
        b_lit = (mp.ones(1, 3) * ninv * mp.ones(3, 1))[0]
        gdop = mp.sqrt(tr + b / beta) if k >= 4 else None
        return {
            "beta": float(beta),
            "tr": float(tr),
            "b": float(b),
            "b_literal": float(b_lit),
            "gdop": None if gdop is None else float(gdop),
        }


def psi_oracle(alpha: float) -> float:
    """ψ(α): the unique real root in (0, 1) of ψ³ + (27α/4)(ψ − 1) = 0 (eq. 4.5.34)."""
    if alpha < 0:
        raise ValueError("alpha must be >= 0")
    if alpha == 0:
        return 0.0
    with mp.workdps(_DPS):
        c = mp.mpf(27) * mp.mpf(alpha) / 4
        roots = mp.polyroots([-c, c, 0, 1], maxsteps=500, extraprec=200, asc=True)
        real = [mp.re(r) for r in roots if abs(mp.im(r)) < mp.mpf(10) ** (-30) and 0 < mp.re(r) < 1]
        if len(real) != 1:  # fall back to bisection on the monotone cubic
            real = [mp.findroot(lambda x: x**3 + c * (x - 1), (mp.mpf(0), mp.mpf(1)), solver="bisect")]
        return float(real[0])


def tracker_mse_oracle(
    sigma: float,
    sigma0: float,
    beta: float,
    n_epochs: int,
    outage_start: int | None = None,
    gains: float | Sequence[float] | None = None,
    return_gains: bool = False,
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Clock-error variance V_n = Var(τ̂_n − τ_n), n = 0..n_epochs, by brute-force covariance (App. G, §4.5).

    Primitives (independent, zero mean): a_0 (var σ0²), w_1..w_N (var σ0²), v_0..v_N (var R = σ²/β).
    Clock deviation d_n = Σ_{i≤n} w_i + n·a_0 (ρ = 1, τ_0 cancels); pseudo-measurement y_n = d_n + v_n.
    Estimator: d̂_0 = y_0; for n ≥ 1, d̂⁻ = d̂_{n−1}; d̂_n = d̂⁻ + g_n (y_n − d̂⁻) unless
    n > outage_start (then d̂_n = d̂⁻, g_n = 0).  ``gains``: None → optimal causal gain
    g_n = Var(d̂⁻ − d_n)/(Var(d̂⁻ − d_n) + R) from the explicit covariance; scalar → constant gain;
    sequence → gains[n] used at epoch n (gains[0] ignored).  Returns V (and the gains, g_0 = 1).
    """
    nn = int(n_epochs)
    var_r = sigma**2 / beta
    # coefficient layout: [a_0 | w_1..w_N | v_0..v_N]
    wts = np.concatenate([[sigma0**2], np.full(nn, sigma0**2), np.full(nn + 1, var_r)])

    def d_coef(n: int) -> np.ndarray:
        c = np.zeros(2 * nn + 2)
        c[0] = n
        c[1 : n + 1] = 1.0
        return c

    def var(c: np.ndarray) -> float:
        return float(np.sum(wts * c * c))

    est = np.zeros(2 * nn + 2)
    est[nn + 1] = 1.0  # d̂_0 = y_0 = d_0 + v_0 with d_0 = 0
    v_out = np.empty(nn + 1)
    g_out = np.empty(nn + 1)
    v_out[0], g_out[0] = var(est - d_coef(0)), 1.0
    for n in range(1, nn + 1):
        dn = d_coef(n)
        if outage_start is not None and n > outage_start:
            g = 0.0
        elif gains is None:
            vm = var(est - dn)
            g = vm / (vm + var_r)
        elif np.ndim(gains) == 0:
            g = float(gains)  # type: ignore[arg-type]
        else:
            g = float(gains[n])  # type: ignore[index]
        if g != 0.0:
            yn = dn.copy()
            yn[nn + 1 + n] = 1.0
            est = est + g * (yn - est)
        v_out[n], g_out[n] = var(est - dn), g
    return (v_out, g_out) if return_gains else v_out


def mse_ft_oracle(
    v_n: np.ndarray | float,
    sigma: float,
    tr_n: np.ndarray | float,
    b_n: np.ndarray | float,
    c_ft_per_ns: float,
) -> np.ndarray:
    """RMS position error c·sqrt(σ²·tr_n + V_n·b_n) in ft (eq. 4.5.35, corrected)."""
    return c_ft_per_ns * np.sqrt(sigma**2 * np.asarray(tr_n) + np.asarray(v_n) * np.asarray(b_n))


def ls_covariance_oracle(u: np.ndarray, sigma: float, seed: int = 12345) -> np.ndarray:
    """Snapshot LS position covariance σ²[F'H'(HH')⁻¹HF]⁻¹ (eq. 4.1.1), F = U (c = 1).

    H = G·D with D the (K−1)×K differences e_i − e_K and G a seeded random (K−1)×(K−1) matrix, so every
    row of H sums to zero and H has full row rank.  Compare with (4.5.6).
    """
    f = np.asarray(u, dtype=float)
    k = f.shape[0]
    d = np.hstack([np.eye(k - 1), -np.ones((k - 1, 1))])
    h = np.random.default_rng(seed).standard_normal((k - 1, k - 1)) @ d
    m = f.T @ h.T @ np.linalg.inv(h @ h.T) @ h @ f
    return sigma**2 * np.linalg.inv(m)


def table_4_3_oracle(
    beta: float, tr: float, b: float, tr3: float, b3: float, sigma: float, sigma0: float, c_ft_per_ns: float
) -> tuple[float, float, float, float, float]:
    """(α, ψ, e0, eN, eN+1) by the closed forms behind Table 4.3 (m = 1)."""
    alpha = 8.0 / 27.0 * sigma0**2 * beta / sigma**2
    psi = psi_oracle(alpha)
    cs = c_ft_per_ns * sigma
    e0 = cs * np.sqrt(tr + b / beta)
    en = cs * np.sqrt(tr + psi / beta * b)
    en1 = cs * np.sqrt(tr3 + (psi / beta + (sigma0 / sigma) ** 2 * ((2.0 - psi) / psi + 1.0)) * b3)
    return alpha, psi, float(e0), float(en), float(en1)


def _unit_rows(sats: Sequence[tuple[float, float]]) -> np.ndarray:
    """Float64 U (rows sat → aircraft) at 9.235 R_E, aircraft (45°, 120°), for the (4.1.1) self-check."""
    with mp.workdps(_DPS):
        re = mp.mpf("6378.137")
        p = _ecef(45.0, 120.0, re)
        out = []
        for la, lo in sats:
            d = p - _ecef(la, lo, re * mp.mpf("9.235"))
            out.append([float(x / mp.norm(d)) for x in d])
    return np.array(out)


if __name__ == "__main__":
    print("Geometry at 9.235 R_E vs the reference table")
    ref = {
        "I": (0.05437, 7.836, 9.385, 1.297, 5.755, 1.356),
        "II": (0.003540, 3.989, 14.887, 1.165, 14.288, 1.173),
    }
    for name, sats in (("I", EX_I), ("II", EX_II)):
        g_all = geometry_oracle(sats)
        g3 = geometry_oracle(sats, subset=(1, 2, 3))
        got = (g_all["beta"], g_all["tr"], g3["tr"], g_all["b"], g3["b_literal"], g3["b"])
        labels = ("beta", "tr", "tr(1,2,3)", "b", "b_lit(1,2,3)", "b(1,2,3)")
        for lab, x, r in zip(labels, got, ref[name], strict=True):
            print(f"  Ex {name:2s} {lab:13s} oracle {x:10.5g}  ref {r:8.5g}  rel {x / r - 1:+.1e}")
        print(f"  Ex {name:2s} gdop          oracle {g_all['gdop']:10.5g}")
    print("psi(alpha) vs the reference values")
    grid = [1e-5, 1e-4, 1e-3, 1e-2, 0.1, 0.3, 1, 3, 10]
    psi_ref = [0.04016, 0.08516, 0.17710, 0.35229, 0.62984, 0.77242, 0.89411, 0.95675, 0.98581]
    for a, r in zip(grid, psi_ref, strict=True):
        print(f"  alpha {a:7.0e}  psi {psi_oracle(a):.7f}  ref {r:.5f}  diff {psi_oracle(a) - r:+.1e}")
    print("Table 4.3 closed forms (Table 4.2 inputs, c = 1 ft/ns, report b3)")
    t42 = {"I": (0.0543, 7.84, 1.30, 9.39, 5.76), "II": (0.00355, 3.99, 1.16, 14.9, 14.3)}
    for name, (be, t, bb, t3, b3) in t42.items():
        for s0 in (5.0, 50.0, 500.0):
            al, ps, e0, en, en1 = table_4_3_oracle(be, t, bb, t3, b3, 50.0, s0, 1.0)
            print(
                f"  Ex {name:2s} s0 {s0:5.0f}  alpha {al:.4e} psi {ps:.4f} e0 {e0:.1f} eN {en:.1f} eN1 {en1:.1f}"
            )
    print("Tracker V_n (brute force) -> RMS ft, Ex I, sigma 50, sigma0 5, N = 100, report convention")
    v, g = tracker_mse_oracle(50.0, 5.0, 0.0543, 160, outage_start=100, return_gains=True)
    n_all = np.arange(161)
    rms = mse_ft_oracle(v, 50.0, np.where(n_all <= 100, 7.84, 9.39), np.where(n_all <= 100, 1.30, 5.76), 1.0)
    pts = [0, 1, 2, 5, 10, 20, 50, 100, 101, 105, 110, 120, 130, 145, 160]
    want = [282, 223, 199, 173, 161, 158, 160, 160, 230, 259, 303, 403, 512, 682, 857]
    for n, w in zip(pts, want, strict=True):
        print(f"  n {n:3d}  oracle {rms[n]:7.2f}  ref {w:4d}  {'ok' if round(rms[n]) == w else 'MISMATCH'}")
    print(f"  g_100 {g[100]:.6f}  psi(alpha) {psi_oracle(8 / 27 * 25 * 0.0543 / 2500):.6f}")
    print("(4.1.1) with random H vs (4.5.6), Ex I all satellites, c = 1")
    u = _unit_rows(EX_I)
    ninv = np.linalg.inv(u.T @ u)
    one = np.ones(len(u))
    be = len(u) - one @ u @ ninv @ u.T @ one
    p456 = 2500 * ninv + 2500 / be * ninv @ u.T @ np.outer(one, one) @ u @ ninv
    p411 = ls_covariance_oracle(u, 50.0)
    print(f"  max rel diff {np.max(np.abs(p411 - p456)) / np.max(np.abs(p456)):.2e}")
