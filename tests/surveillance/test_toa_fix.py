"""The snapshot TOA fix against gnss_lib_py's weighted least squares, its covariance against Monte Carlo, its
DOPs against the report's constellation constants, and its refusals."""

import math
import warnings

import numpy as np
import pytest

from motionsig_cli import geodesy as g
from motionsig_cli.surveillance import toa_fix as tf
from motionsig_cli.surveillance.clock_tracking import pseudo_measurement
from motionsig_cli.surveillance.multilateration import metrics

gnss_snapshot = pytest.importorskip("gnss_lib_py.algorithms.snapshot")
NavData = pytest.importorskip("gnss_lib_py.navdata.navdata").NavData

C = tf.C_M_PER_S
WAM = np.array(
    [[0, 0, 0], [15e3, 2e3, 30], [-12e3, 8e3, -20], [3e3, -14e3, 60], [-6e3, -9e3, 10], [9e3, 12e3, -5]]
)
"""Six ground receivers around an airport (east, north, up [m] about 48.35 N, 11.79 E, 453 m)."""
ORIGIN = (48.3538, 11.7861, 453.0)


def _wam(E, rng, sigma=3.0, alt=(2000.0, 4000.0)):
    S = g.enu_to_ecef(WAM.astype(float), *ORIGIN)
    enu = np.column_stack([np.linspace(-20e3, 20e3, E), np.linspace(5e3, -5e3, E), np.linspace(*alt, E)])
    truth = g.enu_to_ecef(enu, *ORIGIN)
    b = rng.uniform(-3e4, 3e4, E)
    sig = np.broadcast_to(np.asarray(sigma, float), (E, len(S)))
    rho = np.linalg.norm(truth[:, None] - S, axis=-1) + b[:, None] + rng.standard_normal((E, len(S))) * sig
    return S, truth, b, sig, rho


def _gnss(E, K, rng):
    """K satellites 20 200 km up, a user moving from the ground to 9 km, clock offsets of ±100 µs."""
    S = g.geodetic_to_ecef(rng.uniform(-10, 70, K), rng.uniform(-40, 60, K), 2.02e7)
    user = g.geodetic_to_ecef(np.linspace(40, 41, E), np.linspace(10, 11, E), np.linspace(0, 9000, E))
    b = rng.uniform(-3e4, 3e4, E)
    sig = rng.uniform(2.0, 10.0, (E, K))
    rho = np.linalg.norm(user[:, None] - S, axis=-1) + b[:, None] + rng.standard_normal((E, K)) * sig
    return S, user, b, sig, rho


def test_fix_equals_gnss_lib_py_weighted_least_squares():
    """solve_wls on a NavData with the same pseudoranges, satellite positions and weights 1/σ² (satellite
    positions taken as given at reception: sv_rx_time=True; two measurements dropped). Both converge to
    the same least-squares minimum; their stopping rules differ (theirs: step norm < 1e-7, ours < 1e-6 m),
    so the fixes agree to far better than the 1e-3 m asked (measured: 2e-8 m)."""
    rng = np.random.default_rng(2)
    E, K = 20, 8
    S, _, _, sig, rho = _gnss(E, K, rng)
    rho[3, 1] = rho[11, 6] = np.nan
    fix = tf.solve_snapshot(rho, S, sigma=sig)
    e, k = np.nonzero(np.isfinite(rho))
    nd = NavData()
    nd["gps_millis"] = e * 1000.0
    nd["x_sv_m"], nd["y_sv_m"], nd["z_sv_m"] = S[k, 0], S[k, 1], S[k, 2]
    nd["corr_pr_m"] = rho[e, k]
    nd["weight"] = 1.0 / sig[e, k] ** 2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = gnss_snapshot.solve_wls(nd, weight_type="weight", sv_rx_time=True, tol=1e-7, max_count=50)
    xyz = np.stack([ref["x_rx_wls_m"], ref["y_rx_wls_m"], ref["z_rx_wls_m"]], axis=-1)
    np.testing.assert_allclose(fix.position, xyz, rtol=0, atol=1e-3)
    np.testing.assert_allclose(fix.bias, ref["b_rx_wls_m"], rtol=0, atol=1e-3)
    lat, lon, _ = g.ecef_to_geodetic(fix.position)
    np.testing.assert_allclose(lat, ref["lat_rx_wls_deg"], atol=1e-9)
    np.testing.assert_allclose(lon, ref["lon_rx_wls_deg"], atol=1e-9)
    assert fix.converged.all() and fix.n_used.tolist() == [8] * 3 + [7] + [8] * 7 + [7] + [8] * 8


def test_ground_network_fix_equals_gnss_lib_py_from_the_same_start():
    """A wide-area multilateration geometry (receivers on the ground, transmitter above): gnss_lib_py's
    wls() from our starting point (from the Earth's centre, its default, it diverges on such a geometry)."""
    rng = np.random.default_rng(1)
    S, truth, _, sig, rho = _wam(12, rng)
    fix = tf.solve_snapshot(rho, S, sigma=sig)
    p0 = tf.default_start(np.broadcast_to(S, (12, *S.shape)), np.ones(rho.shape, bool))
    for e in range(12):
        x0 = np.concatenate([p0[e], [0.0]])[:, None]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ref = gnss_snapshot.wls(
                x0, S.copy(), rho[e][:, None], 1.0 / sig[e] ** 2, False, 1e-7, 50, sv_rx_time=True
            )
        np.testing.assert_allclose(fix.position[e], ref[:3, 0], rtol=0, atol=1e-3)
        np.testing.assert_allclose(fix.bias[e], ref[3, 0], rtol=0, atol=1e-3)
    assert np.all(np.linalg.norm(fix.position - truth, axis=1) < 200.0)  # the right (upper) solution


def test_the_starting_point_chooses_the_side_of_a_ground_network():
    """Receivers nearly in one plane: the fix and its mirror image below the plane fit about equally well
    (measured per-epoch χ² differences up to ~16 for 3 m noise). From any start above the receivers
    (the default 10 km above their centroid; 5 km up and 6 km off; 20 m above the plane) every fix is the
    upper one; from below, the lower one. Summed over epochs, χ² prefers the true side by far."""
    rng = np.random.default_rng(21)
    S, truth, _, sig, rho = _wam(120, rng)
    starts = [None, g.geodetic_to_ecef(48.3, 11.8, 5000.0), g.geodetic_to_ecef(48.36, 11.8, 520.0)]
    fixes = [tf.solve_snapshot(rho, S, sigma=sig, p0=p0) for p0 in starts]
    for f in fixes:
        assert f.converged.all() and np.max(np.linalg.norm(f.position - truth, axis=1)) < 300.0
        np.testing.assert_allclose(f.position, fixes[0].position, rtol=0, atol=1e-5)
    assert fixes[1].mirrored.sum() > 0  # Gauss–Newton alone reached the mirror image from that start
    below = tf.solve_snapshot(rho, S, sigma=sig, p0=g.geodetic_to_ecef(48.3, 11.8, -5000.0))
    alt = g.ecef_to_geodetic(below.position)[2]
    assert below.converged.all() and np.all(alt < 0.0)
    assert np.sum(below.chi2 - below.other_chi2) > 100.0  # the upper fixes fit better in total
    np.testing.assert_allclose(below.other_chi2, fixes[0].chi2, rtol=1e-6)
    # without the mirror check the result depends on the start
    plain = tf.solve_snapshot(rho, S, sigma=sig, p0=starts[1], mirror=False)
    assert np.max(np.linalg.norm(plain.position - truth, axis=1)) > 1000.0
    # a satellite geometry is not planar: no mirror search
    Sg, _, _, sg, rg = _gnss(5, 8, rng)
    assert np.isnan(tf.solve_snapshot(rg, Sg, sigma=sg).other_chi2).all()


def test_noise_free_measurements_are_recovered_exactly():
    rng = np.random.default_rng(7)
    S, truth, b, _, _ = _wam(30, rng)
    rho = np.linalg.norm(truth[:, None] - S, axis=-1) + b[:, None]
    fix = tf.solve_snapshot(rho, S, sigma=3.0)
    np.testing.assert_allclose(fix.position, truth, rtol=0, atol=1e-6)
    np.testing.assert_allclose(fix.bias, b, rtol=0, atol=1e-6)
    assert np.nanmax(np.abs(fix.residuals)) < 1e-6 and fix.converged.all()
    np.testing.assert_allclose(fix.clock_offset_s, b / C, rtol=1e-12)


def test_covariance_equals_the_monte_carlo_spread_of_the_fixes():
    """N = 4000 noise draws of one geometry (solved as 4000 epochs at once): the sample covariance of the
    errors equals (HᵀWH)⁻¹ within Monte Carlo error. The sample variance of N Gaussian errors has relative
    standard error √(2/N) = 2.2 %; the test allows 4 of them on each of the four variances."""
    rng = np.random.default_rng(11)
    N = 4000
    S = g.enu_to_ecef(WAM.astype(float), *ORIGIN)
    p = g.enu_to_ecef(np.array([4e3, -3e3, 3000.0]), *ORIGIN)
    sig = np.array([2.0, 3.0, 5.0, 3.0, 4.0, 6.0])
    rho = np.linalg.norm(p - S, axis=-1) + 1e4 + rng.standard_normal((N, 6)) * sig
    fix = tf.solve_snapshot(rho, S, sigma=sig)
    err = np.column_stack([fix.position - p, fix.bias - 1e4])
    sample = np.cov(err.T)
    P = fix.covariance.mean(axis=0)  # evaluated at each fix: it varies by < 1 % over the draws
    rel = np.diag(sample) / np.diag(P) - 1.0
    assert np.all(np.abs(rel) < 4 * math.sqrt(2 / N)), rel
    # the normalised residuals have K − 4 = 2 degrees of freedom: mean χ² = 2 (sd of the mean 2/√N)
    assert abs(fix.chi2.mean() - 2.0) < 4 * 2.0 / math.sqrt(N)
    # negative control: twice the noise is detected
    rho2 = np.linalg.norm(p - S, axis=-1) + 1e4 + rng.standard_normal((N, 6)) * sig * 2.0
    fix2 = tf.solve_snapshot(rho2, S, sigma=sig)
    err2 = np.column_stack([fix2.position - p, fix2.bias - 1e4])
    assert np.all(np.diag(np.cov(err2.T)) / np.diag(P) - 1.0 > 4 * math.sqrt(2 / N))


def test_variance_factor_scales_the_covariance():
    rng = np.random.default_rng(12)
    S, _, _, sig, rho = _wam(2000, rng, sigma=3.0)
    known = tf.solve_snapshot(rho, S, sigma=sig)
    half = tf.solve_snapshot(rho, S, sigma=1.5, scale="pooled")  # σ given at half its value
    unit = tf.solve_snapshot(rho, S, scale="pooled")  # unit weights
    dof = 2 * 2000  # K − 4 = 2 per epoch
    se = math.sqrt(2.0 / dof)
    assert abs(known.chi2.sum() / dof - 1.0) < 4 * se
    assert abs(half.variance_factor[0] / 4.0 - 1.0) < 4 * se
    assert abs(unit.variance_factor[0] / 9.0 - 1.0) < 4 * se
    # (1e-8: an epoch whose χ² is flat along one direction stops where its step is below its own rounding)
    np.testing.assert_allclose(half.covariance, known.covariance * half.variance_factor[0] / 4.0, rtol=1e-8)
    per = tf.solve_snapshot(rho, S, sigma=sig, scale="epoch")
    np.testing.assert_allclose(per.variance_factor, known.chi2 / 2.0, rtol=1e-12)


def test_dops_and_the_reports_constellation_constants():
    """PDOP² = tr + b/β (the report's GDOP k, eq 4.1.2), TDOP² = 1/β (eq 4.5.5), GDOP² = PDOP² + TDOP²,
    HDOP² + VDOP² = PDOP², from :func:`multilateration.metrics` of the directions at the fix."""
    rng = np.random.default_rng(5)
    S, _, _, sig, rho = _wam(10, rng)
    fix = tf.solve_snapshot(rho, S, sigma=sig)
    U = fix.position[:, None, :] - S
    U /= np.linalg.norm(U, axis=-1, keepdims=True)
    m = metrics(U)
    np.testing.assert_allclose(fix.pdop**2, m.tr + m.b / m.beta, rtol=1e-9)
    np.testing.assert_allclose(fix.tdop**2, 1.0 / m.beta, rtol=1e-9)
    np.testing.assert_allclose(fix.gdop**2, fix.pdop**2 + fix.tdop**2, rtol=1e-12)
    np.testing.assert_allclose(fix.hdop**2 + fix.vdop**2, fix.pdop**2, rtol=1e-12)
    # with equal σ the covariance is σ² G
    np.testing.assert_allclose(np.sqrt(np.trace(fix.covariance, axis1=1, axis2=2)) / 3.0, fix.gdop, rtol=1e-9)
    sd_enu = fix.sd_enu()
    np.testing.assert_allclose(np.hypot(sd_enu[:, 0], sd_enu[:, 1]) / 3.0, fix.hdop, rtol=1e-9)


def test_singular_geometries_are_refused_naming_the_epoch():
    rng = np.random.default_rng(3)
    S, _, _, sig, rho = _wam(5, rng)
    line = np.array([S[0] + t * (S[1] - S[0]) for t in (0.0, 0.3, 0.7, 1.0, 1.4)])  # five on a straight line
    rho_line = np.linalg.norm(g.enu_to_ecef(np.array([1e3, 2e3, 3e3]), *ORIGIN) - line, axis=-1) + 5.0
    rs = np.vstack([rho[:2, :5], rho_line[None], rho[2:, :5]])
    Ss = np.stack([S[:5], S[:5], line, S[:5], S[:5], S[:5]])
    with pytest.raises(tf.SingularGeometry, match="singular") as exc:
        tf.solve_snapshot(rs, Ss, sigma=3.0)
    assert exc.value.epoch == 2
    few = rho.copy()
    few[3, 2:] = np.nan
    with pytest.raises(tf.SingularGeometry, match="2 receiver") as exc:
        tf.solve_snapshot(few, S, sigma=sig)
    assert exc.value.epoch == 3


def test_non_convergence_is_flagged_and_retried_from_a_neighbour():
    rng = np.random.default_rng(9)
    S, truth, _, sig, rho = _wam(20, rng)  # 2 km between epochs
    short = tf.solve_snapshot(rho, S, sigma=sig, max_iter=2, retry=False)
    assert not short.converged.any() and (short.iterations == 2).all()
    # epoch 3 starts 640 000 km out: restarted from epoch 2's fix, it converges
    p0 = tf.default_start(np.broadcast_to(S, (20, *S.shape)), np.ones(rho.shape, bool))
    p0[3] = 100.0 * p0[3]
    fix = tf.solve_snapshot(rho, S, sigma=sig, p0=p0, max_iter=12)
    assert np.flatnonzero(fix.retried).tolist() == [3]
    assert fix.converged.all() and np.all(np.linalg.norm(fix.position - truth, axis=1) < 200)
    plain = tf.solve_snapshot(rho, S, sigma=sig, p0=p0, max_iter=12, retry=False)
    assert np.flatnonzero(~plain.converged).tolist() == [3]  # flagged, not refused as a singular geometry


def test_weighted_pseudo_measurement_with_equal_sigma_is_the_reports():
    """With equal σ the whitened reduction is the report's 1'(I − P)(T − k)/β (clock_tracking), β̃ = β/σ²."""
    rng = np.random.default_rng(2)
    S, truth, b, _, _ = _wam(1, rng)
    p_star = truth[0] + np.array([30.0, -20.0, 50.0])
    rho = np.linalg.norm(truth[0] - S, axis=-1) + b[0] + rng.standard_normal(6) * 3.0
    sigma = 3.0
    pm = tf.weighted_pseudo_measurement(rho, S, np.full(6, 1 / sigma), p_star)
    ref = pseudo_measurement(rho, S, p_star)  # units: metres throughout (c = 1 in any unit)
    assert pm.y == pytest.approx(float(ref["y"]), rel=1e-12)
    assert pm.beta == pytest.approx(float(ref["beta"]) / sigma**2, rel=1e-12)
    p = tf.weighted_position_update(pm, p_star, pm.y)
    from motionsig_cli.surveillance.clock_tracking import position_update

    np.testing.assert_allclose(p, position_update(ref, p_star, np.asarray(ref["y"])), rtol=0, atol=1e-6)
    # three receivers: no clock information
    pm3 = tf.weighted_pseudo_measurement(rho, S, np.array([1, 1, 1, 0, 0, 0]) / sigma, p_star)
    assert pm3.beta == 0.0 and np.isnan(pm3.y)


def test_bad_arguments_name_the_field():
    rng = np.random.default_rng(2)
    S, _, _, _, rho = _wam(2, rng)
    from motionsig_cli.config import ConfigError

    for kw, field in (({"scale": "x"}, "scale"), ({"tol": 0.0}, "tol"), ({"max_iter": 0}, "max_iter"),
                      ({"sigma": -1.0}, "sigma")):  # fmt: skip
        with pytest.raises(ConfigError) as exc:
            tf.solve_snapshot(rho, S, **kw)
        assert exc.value.field == field
