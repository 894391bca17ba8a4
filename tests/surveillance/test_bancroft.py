"""The closed-form start (Bancroft 1985, and the planar variant) on random geometries with known answers,
and the ground network of the multilateration use case: every epoch converges to the weighted least-squares
minimum that a plain Gauss-Newton started at the truth finds."""

from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares

from motionsig_cli.geodesy import enu_to_ecef, geodetic_to_ecef
from motionsig_cli.surveillance.bancroft import bancroft, planar_start
from motionsig_cli.surveillance.toa_fix import C_M_PER_S, receiver_plane, solve_snapshot

GPS_RADIUS_M = 26_560e3


def _satellites(rng, p, E, K):
    """(E, K, 3) satellites at the GPS orbit radius above 10° elevation from p (E, 3)."""
    out = np.empty((E, K, 3))
    for e in range(E):
        up = p[e] / np.linalg.norm(p[e])
        k = 0
        while k < K:
            d = rng.normal(size=3)
            d /= np.linalg.norm(d)
            if d @ up < np.sin(np.radians(10)):
                continue
            # the point at the orbit radius along d from p
            b = p[e] @ d
            t = -b + np.sqrt(b * b - p[e] @ p[e] + GPS_RADIUS_M**2)
            out[e, k] = p[e] + t * d
            k += 1
    return out


def test_bancroft_recovers_the_answer_on_random_gnss_geometries():
    rng = np.random.default_rng(11)
    E = 200
    lat, lon = rng.uniform(-80, 80, E), rng.uniform(-180, 180, E)
    p = geodetic_to_ecef(lat, lon, rng.uniform(-100, 10_000, E))
    b = rng.uniform(-3e5, 3e5, E)  # receiver clock offsets up to 1 ms
    for K in (4, 6, 10):
        S = _satellites(rng, p, E, K)
        rho = np.linalg.norm(p[:, None] - S, axis=-1) + b[:, None]
        P, B = bancroft(S, rho, np.ones((E, K)))
        err = np.linalg.norm(P - p[:, None], axis=-1)
        j = np.nanargmin(err, axis=1)
        assert np.max(err[np.arange(E), j]) < 1e-3, K  # one root is the answer (to float64 rounding)
        assert np.max(np.abs(B[np.arange(E), j] - b)) < 1e-3
        # the refined fix from the closed form is the answer too, with no starting point given
        fix = solve_snapshot(rho, S, sigma=1.0)
        assert fix.converged.all() and np.max(np.linalg.norm(fix.position - p, axis=1)) < 1e-4


def _ground(rng, E, K=6, radius=25e3, lat0=47.45, lon0=8.56):
    """Stations within ``radius`` of a point (a 50 km network), heights 0-300 m: nearly planar."""
    r = radius * np.sqrt(rng.uniform(0.05, 1.0, (E, K)))
    a = rng.uniform(0, 2 * np.pi, (E, K))
    enu = np.stack([r * np.cos(a), r * np.sin(a), rng.uniform(0, 300, (E, K))], axis=-1)
    return np.stack([enu_to_ecef(enu[e], lat0, lon0, 400.0) for e in range(E)]), lat0, lon0


def test_the_planar_closed_form_recovers_the_answer_on_random_ground_networks():
    rng = np.random.default_rng(12)
    E, K = 200, 6
    S, lat0, lon0 = _ground(rng, E, K)
    enu = np.c_[rng.uniform(-40e3, 40e3, (E, 2)), rng.uniform(500, 12e3, E)]
    p = np.stack([enu_to_ecef(enu[e], lat0, lon0, 0.0) for e in range(E)])
    b = rng.uniform(-3e5, 3e5, E)
    rho = np.linalg.norm(p[:, None] - S, axis=-1) + b[:, None]
    used = np.ones((E, K), bool)
    centre, normal, flat = receiver_plane(S, used)
    assert np.all(flat < 0.1)  # nearly planar: the planar closed form applies
    normal *= np.sign(np.einsum("ei,ei->e", normal, centre))[:, None]
    P, _ = planar_start(S, rho, np.ones((E, K)), centre, normal)
    # an approximation (the stations are not exactly in one plane): the start is near the answer ...
    near = np.linalg.norm(P[:, 0] - p, axis=1)
    assert np.median(near) < 2e3
    # ... and the refinement from it reaches the answer on every epoch
    fix = solve_snapshot(rho, S, sigma=1.0)
    assert fix.converged.all() and np.max(np.linalg.norm(fix.position - p, axis=1)) < 1e-4
    assert np.max(np.abs(fix.bias - b)) < 1e-4


def _minimum(S, rho, sig, x0):
    """The independent minimiser: scipy's Levenberg-Marquardt (MINPACK) started at the truth, tight
    tolerances, about the stations' centroid."""
    o = S.mean(axis=0)
    fit = least_squares(lambda x: (rho - np.linalg.norm(x[:3] - (S - o), axis=1) - x[3]) / sig,
                        np.r_[x0[:3] - o, x0[3]], method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15,
                        max_nfev=10_000)  # fmt: skip
    return np.r_[fit.x[:3] + o, fit.x[3]]


def test_a_ground_network_converges_on_every_epoch_to_the_wls_minimum():
    """6 stations within 50 km, the transmitter 3 km up, a 1 ms clock offset, 10 ns timing noise, 20 epochs:
    every epoch converges, to within 0.5 m of scipy's Levenberg-Marquardt started at the truth."""
    rng = np.random.default_rng(36)
    E, K, sig = 20, 6, C_M_PER_S * 10e-9
    S1, lat0, lon0 = _ground(rng, 1, K)
    S = S1[0]
    enu = np.c_[rng.uniform(-30e3, 30e3, (E, 2)), np.full(E, 3000.0)]
    p = np.stack([enu_to_ecef(enu[e], lat0, lon0, 0.0) for e in range(E)])
    b = C_M_PER_S * 1e-3
    rho = np.linalg.norm(p[:, None] - S, axis=-1) + b + sig * rng.standard_normal((E, K))
    fix = solve_snapshot(rho, S, sigma=sig)
    assert fix.converged.all() and fix.iterations.max() <= 20 and (fix.status == "").all()
    for e in range(E):
        ref = _minimum(S, rho[e], sig, np.r_[p[e], b])
        assert np.linalg.norm(fix.position[e] - ref[:3]) < 0.5, e
        assert abs(fix.bias[e] - ref[3]) < 0.5
