"""Positions as users have them into a local east/north plane: round trips, pymap3d (test-only), radar plots
against a direct geometric construction, the covariance against Monte Carlo of the nonlinear conversion, the
bearing conventions, ADS-B NACp, and refusals that name the argument."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from motionsig_cli import geodesy as g
from motionsig_cli.config import ConfigError
from motionsig_cli.surveillance import local_positions as lp
from motionsig_cli.surveillance.local_positions import (
    LocalFrame,
    cartesian_covariance,
    default_origin,
    nacp_to_sigma,
    polar_to_local,
)

pm = pytest.importorskip("pymap3d")

SENSOR = LocalFrame(48.35, 11.78, 450.0)
"""A radar near Munich airport."""
FRAME = LocalFrame(48.0, 11.0, 0.0)
"""The tracking frame's origin, about 70 km from the radar (not at the sensor)."""


def _targets(rng, n, centre=SENSOR, spread=2.5, alt=(300.0, 12500.0)):
    lat = centre.lat_deg + rng.uniform(-spread, spread, n)
    lon = centre.lon_deg + rng.uniform(-spread, spread, n) / math.cos(math.radians(centre.lat_deg))
    return lat, lon, rng.uniform(*alt, n)


def _ecef(lat, lon, alt):
    return g.geodetic_to_ecef(lat, lon, alt)


def test_round_trips_to_a_micrometre():
    rng = np.random.default_rng(1)
    lat, lon, alt = _targets(rng, 400, FRAME, spread=2.7, alt=(-100.0, 12500.0))  # up to ≈ 300 km
    enu = FRAME.to_local(lat, lon, alt)
    assert enu.shape == (400, 3) and np.max(np.hypot(enu[:, 0], enu[:, 1])) > 250e3
    la, lo, h = FRAME.to_geodetic(enu[:, 0], enu[:, 1], enu[:, 2])  # 3-D, exact
    assert np.max(np.linalg.norm(_ecef(la, lo, h) - _ecef(lat, lon, alt), axis=-1)) < 1e-6
    la, lo, h = FRAME.to_geodetic(enu[:, 0], enu[:, 1], alt_m=alt)  # up dropped, the altitude kept
    assert np.max(np.linalg.norm(_ecef(la, lo, h) - _ecef(lat, lon, alt), axis=-1)) < 1e-6
    again = FRAME.to_local(la, lo, h)
    assert np.max(np.abs(again[:, :2] - enu[:, :2])) < 1e-6


def test_against_pymap3d():
    rng = np.random.default_rng(2)
    lat, lon, alt = _targets(rng, 200, FRAME)
    o = (FRAME.lat_deg, FRAME.lon_deg, FRAME.alt_m)
    e, n, u = pm.geodetic2enu(lat, lon, alt, *o)
    np.testing.assert_allclose(FRAME.to_local(lat, lon, alt), np.column_stack([e, n, u]), rtol=0, atol=1e-6)
    la, lo, h = pm.enu2geodetic(e, n, u, *o)
    la2, lo2, h2 = FRAME.to_geodetic(e, n, u)
    assert np.max(np.linalg.norm(_ecef(la, lo, h) - _ecef(la2, lo2, h2), axis=-1)) < 1e-6


def test_the_planes_curvature_numbers_of_the_docstring():
    """Eq 3–4: a point on the ellipsoid 100 km due north (meridian arc) is 785 m below the plane (±1 %) and
    drawn about d³/(6R²) = 4.1 m short (the meridian radius here is 6.37e6 m)."""
    a, e2 = g.WGS84_A, g.WGS84_E2
    origin = LocalFrame(48.0, 11.0, 0.0)

    def arc(lat2):
        f = lambda p: a * (1 - e2) / (1 - e2 * math.sin(p) ** 2) ** 1.5  # noqa: E731 - meridian radius M
        return quad(f, math.radians(48.0), math.radians(lat2), epsabs=1e-9)[0]

    lat2 = 48.0 + 100e3 / 111.2e3
    for _ in range(5):  # the latitude 100 km of meridian arc north
        lat2 += math.degrees((100e3 - arc(lat2)) / 6.37e6)
    assert arc(lat2) == pytest.approx(100e3, abs=1e-6)
    enu = origin.to_local(lat2, 11.0, 0.0)[0]
    assert enu[2] == pytest.approx(-(100e3**2) / (2 * 6.37e6), rel=0.01)
    assert 100e3 - enu[1] == pytest.approx(100e3**3 / (6 * 6.37e6**2), rel=0.02)  # 4.1 m


def test_default_origin_is_the_bounding_box_midpoint():
    lat = np.array([48.0, np.nan, 49.0, 48.2])
    lon = np.array([11.0, 5.0, 12.0, 11.9])
    f = default_origin(lat, lon)
    assert (f.lat_deg, f.lon_deg, f.alt_m) == (48.5, 11.5, 0.0)
    assert default_origin(lat[::-1], lon[::-1]) == f  # the rows' order does not matter
    f = default_origin([10.0, 12.0], [179.0, -177.0])  # across the antimeridian: the short box
    assert f.lat_deg == 11.0 and f.lon_deg == pytest.approx(-179.0)
    with pytest.raises(ConfigError) as exc:
        default_origin([np.nan], [1.0])
    assert exc.value.field == "lat"


def test_radar_plots_against_a_geometric_construction():
    """Targets at known lat/lon/alt; their slant range, azimuth and elevation from the sensor by pymap3d; back
    into the frame by elevation or by the target's altitude: within 1 mm of pymap3d's ENU of the target."""
    rng = np.random.default_rng(3)
    lat, lon, alt = _targets(rng, 300, SENSOR, spread=2.0)
    az, el, srange = pm.geodetic2aer(lat, lon, alt, SENSOR.lat_deg, SENSOR.lon_deg, SENSOR.alt_m)
    e, n, u = pm.geodetic2enu(lat, lon, alt, FRAME.lat_deg, FRAME.lon_deg, FRAME.alt_m)
    want = np.column_stack([e, n])
    assert srange.max() > 200e3
    kw = dict(sigma_range_m=50.0, sigma_bearing_rad=1e-3)
    by_el = polar_to_local(srange, np.radians(az), SENSOR, FRAME, elevation_rad=np.radians(el), **kw)
    by_alt = polar_to_local(srange, np.radians(az), SENSOR, FRAME, altitude_m=alt, **kw)
    for out, kind in ((by_el, "slant-elevation"), (by_alt, "slant-altitude")):
        assert out.range_kind == kind and out.notes == ()
        assert np.max(np.abs(out.position - want)) < 1e-3
        assert np.max(np.abs(out.up - u)) < 1e-3
    np.testing.assert_allclose(by_alt.elevation_rad, np.radians(el), rtol=0, atol=1e-9)
    # the sensor as the frame: pymap3d's aer2enu
    ae, an, au = pm.aer2enu(az, el, srange)
    same = polar_to_local(srange, np.radians(az), SENSOR, SENSOR, elevation_rad=np.radians(el), **kw)
    np.testing.assert_allclose(same.position, np.column_stack([ae, an]), rtol=0, atol=1e-6)
    np.testing.assert_allclose(same.up, au, rtol=0, atol=1e-6)
    # the sensor given as (lat, lon, alt)
    tup = polar_to_local(srange, np.radians(az), (48.35, 11.78, 450.0), FRAME, altitude_m=alt, **kw)
    np.testing.assert_array_equal(tup.position, by_alt.position)


def test_ground_range_is_an_assumption_the_result_states():
    out = polar_to_local(
        [10e3, 20e3], [0.0, 0.5 * math.pi], SENSOR, SENSOR, sigma_range_m=1, sigma_bearing_rad=1e-3
    )
    np.testing.assert_allclose(out.position, [[0.0, 10e3], [20e3, 0.0]], atol=1e-6)
    assert out.range_kind == "ground" and "assumed" in out.notes[0]
    assert out.meta()["range_kind"] == "ground" and out.meta()["notes"] == list(out.notes)


def test_conventions_math_and_north_clockwise():
    """θ clockwise from north (east = ρ sin θ) and φ = π/2 − θ counter-clockwise from east (x = ρ cos φ) are
    one point with one covariance."""
    theta = np.radians([0.0, 30.0, 135.0, -100.0])
    kw = dict(sigma_range_m=30.0, sigma_bearing_rad=2e-3, altitude_m=9000.0)
    nc = polar_to_local(50e3, theta, SENSOR, FRAME, **kw)
    ma = polar_to_local(50e3, lp.wrap_angle(np.pi / 2 - theta), SENSOR, FRAME, convention="math", **kw)
    np.testing.assert_allclose(ma.position, nc.position, rtol=0, atol=1e-6)
    np.testing.assert_allclose(ma.covariance, nc.covariance, rtol=1e-9, atol=1e-9)
    e = polar_to_local(1e3, 0.0, SENSOR, SENSOR, sigma_range_m=1, sigma_bearing_rad=0, convention="math")
    n = polar_to_local(1e3, 0.0, SENSOR, SENSOR, sigma_range_m=1, sigma_bearing_rad=0)
    np.testing.assert_allclose(e.position, [[1e3, 0.0]], atol=1e-9)
    np.testing.assert_allclose(n.position, [[0.0, 1e3]], atol=1e-9)
    assert nc.meta()["bearing_convention"] == "north-clockwise"


def test_wrap_angle():
    np.testing.assert_allclose(
        lp.wrap_angle([math.pi, -math.pi, 3 * math.pi, 0.1]), [math.pi, math.pi, math.pi, 0.1]
    )


def _whitened(S, P):
    L = np.linalg.cholesky(P)
    Li = np.linalg.inv(L)
    return Li @ S @ Li.T


@pytest.mark.parametrize(
    ("mode", "kw", "noise"),
    [
        ("elevation", {"elevation_rad": 0.15}, {"sigma_elevation_rad": 4e-3}),
        ("altitude", {"altitude_m": 9000.0}, {"sigma_altitude_m": 150.0}),
        ("ground", {}, {}),
    ],
)
def test_covariance_against_monte_carlo(mode, kw, noise):
    """20 000 draws of (r, θ, ε or h) through the nonlinear conversion, sensor ≠ frame: the sample covariance
    whitened by the linearised one is I within 5 standard errors (diagonal 5√(2/n) = 0.05, off-diagonal
    5√(1/n) = 0.035); the sample mean is the truth's conversion within 5 standard errors."""
    rng = np.random.default_rng(7)
    n = 20_000
    r0, th0, sr, sth = 80e3, math.radians(40.0), 50.0, 1.5e-3
    truth = polar_to_local(r0, th0, SENSOR, FRAME, sigma_range_m=sr, sigma_bearing_rad=sth, **kw, **noise)
    assert truth.linearity[0] < lp.LINEARITY_LIMIT
    draws = {k: v + rng.standard_normal(n) * next(iter(noise.values())) for k, v in kw.items()}
    r = r0 + sr * rng.standard_normal(n)
    th = th0 + sth * rng.standard_normal(n)
    mc = polar_to_local(r, th, SENSOR, FRAME, sigma_range_m=0.0, sigma_bearing_rad=0.0, **draws)
    S = np.cov(mc.position.T)
    W = _whitened(S, truth.covariance[0])
    assert np.all(np.abs(np.diag(W) - 1) < 5 * math.sqrt(2 / n)), (mode, W)
    assert abs(W[0, 1]) < 5 * math.sqrt(1 / n), (mode, W)
    m = np.linalg.solve(np.linalg.cholesky(truth.covariance[0]), mc.position.mean(axis=0) - truth.position[0])
    assert np.all(np.abs(m) * math.sqrt(n) < 5), (mode, m)
    if mode != "ground":  # the extra noise matters: without it the covariance is smaller
        bare = polar_to_local(r0, th0, SENSOR, FRAME, sigma_range_m=sr, sigma_bearing_rad=sth, **kw)
        assert np.trace(bare.covariance[0]) < 0.99 * np.trace(truth.covariance[0])


def test_debiased_conversion_where_the_linearisation_fails():
    """σ_θ = 0.1 rad at 100 km, σ_r = 10 m (ρσ_θ²/σ_r = 100 ≫ 0.4): the linearised conversion is ≈ ρσ_θ²/2 =
    500 m short along the bearing (> 5 SE of the Monte Carlo) and its covariance far too small; Lerro &
    Bar-Shalom's debiased one is unbiased within 5 SE and consistent: its mean NEES is 2 within 5 SE, where
    the linearised one's is over 1000 (7400 measured)."""
    rng = np.random.default_rng(11)
    n = 20_000
    rho, th, sr, sth = 100e3, math.radians(60.0), 10.0, 0.1
    r = rho + sr * rng.standard_normal(n)
    t = th + sth * rng.standard_normal(n)
    want = np.array([rho * math.sin(th), rho * math.cos(th)])
    kw = dict(sigma_range_m=sr, sigma_bearing_rad=sth)
    lin = polar_to_local(r, t, SENSOR, SENSOR, **kw)
    deb = polar_to_local(r, t, SENSOR, SENSOR, debias=True, **kw)
    assert deb.debiased and deb.meta()["covariance"].startswith("debiased")
    assert np.all(lin.linearity > 50)
    err = deb.position - want
    se = err.std(axis=0) / math.sqrt(n)
    assert np.all(np.abs(err.mean(axis=0)) < 5 * se)
    bias_lin = (lin.position - want).mean(axis=0) @ np.array([math.sin(th), math.cos(th)])
    assert bias_lin == pytest.approx(-rho * (1 - math.exp(-(sth**2) / 2)), rel=0.2)
    assert abs(bias_lin) > 5 * np.max(se)

    def nees(out):
        e = out.position - want
        return np.einsum("ni,nij,nj->n", e, np.linalg.inv(out.covariance), e)

    q = nees(deb)  # consistent: mean 2 (two dimensions)
    assert abs(q.mean() - 2.0) < 5 * q.std() / math.sqrt(n)
    assert nees(lin).mean() > 1000  # the linearised covariance is far too small along the bearing


def test_nacp_to_sigma_is_the_95_percent_radius():
    epu = {11: 3.0, 10: 10.0, 9: 30.0, 8: 92.6, 7: 185.2, 6: 555.6, 5: 926.0, 4: 1852.0}
    s = nacp_to_sigma(list(epu))
    np.testing.assert_allclose(s * 2.4477468306808166, list(epu.values()), rtol=1e-12)
    assert lp.EPU_95_FACTOR == pytest.approx(2.4477, abs=1e-4)
    # the 95 % radius of a circular normal with that σ: Rayleigh, and Monte Carlo
    assert 1 - math.exp(-(3.0**2) / (2 * s[0] ** 2)) == pytest.approx(0.95, abs=1e-12)
    rng = np.random.default_rng(5)
    xy = rng.standard_normal((200_000, 2)) * s[0]
    assert np.mean(np.hypot(*xy.T) <= 3.0) == pytest.approx(0.95, abs=0.002)
    assert math.isnan(nacp_to_sigma(0)[0])
    for bad in (12, -1, 3.5, "x", True):
        with pytest.raises(ConfigError) as exc:
            nacp_to_sigma(bad)
        assert exc.value.field == "nacp"


def test_cartesian_covariance():
    P = cartesian_covariance([1.0, 2.0], [3.0, 4.0])
    np.testing.assert_array_equal(P, [[[1, 0], [0, 9]], [[4, 0], [0, 16]]])
    P = cartesian_covariance(nacp_to_sigma([9, 0]))
    assert P[0, 0, 0] == P[0, 1, 1] == pytest.approx((30 / 2.4477468306808166) ** 2)
    assert np.all(np.isnan(P[1]))
    with pytest.raises(ConfigError) as exc:
        cartesian_covariance(1.0, -2.0)
    assert exc.value.field == "sigma_north"


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: LocalFrame(91.0, 0.0), "lat_deg"),
        (lambda: LocalFrame(0.0, 400.0), "lon_deg"),
        (lambda: LocalFrame(0.0, 0.0, 2e6), "alt_m"),
        (lambda: LocalFrame(math.nan, 0.0), "lat_deg"),
        (lambda: FRAME.to_local(95.0, 0.0), "lat"),
        (lambda: FRAME.to_geodetic(1.0, 2.0, 3.0, alt_m=4.0), "alt_m"),
        (lambda: FRAME.to_geodetic(math.inf, 2.0), "east"),
        (lambda: polar_to_local(-1.0, 0.0, SENSOR, FRAME, sigma_range_m=1, sigma_bearing_rad=1), "range_m"),
        (
            lambda: polar_to_local(1.0, 90.0, SENSOR, FRAME, sigma_range_m=1, sigma_bearing_rad=1),
            "bearing_rad",
        ),
        (
            lambda: polar_to_local(1.0, 0.0, SENSOR, FRAME, sigma_range_m=-1, sigma_bearing_rad=1),
            "sigma_range_m",
        ),
        (
            lambda: polar_to_local(1.0, 0.0, SENSOR, FRAME, sigma_range_m=1, sigma_bearing_rad=math.nan),
            "sigma_bearing_rad",
        ),
        (
            lambda: polar_to_local(
                1.0, 0.0, SENSOR, FRAME, sigma_range_m=1, sigma_bearing_rad=1, elevation_rad=2.0
            ),
            "elevation_rad",
        ),
        (
            lambda: polar_to_local(
                1.0,
                0.0,
                SENSOR,
                FRAME,
                sigma_range_m=1,
                sigma_bearing_rad=1,
                elevation_rad=0.1,
                altitude_m=1e3,
            ),
            "altitude_m",
        ),
        (
            lambda: polar_to_local(
                1e3, 0.0, SENSOR, FRAME, sigma_range_m=1, sigma_bearing_rad=1, altitude_m=1e4
            ),
            "altitude_m",
        ),
        (
            lambda: polar_to_local(
                1.0, 0.0, SENSOR, FRAME, sigma_range_m=1, sigma_bearing_rad=1, convention="compass"
            ),
            "convention",
        ),
        (
            lambda: polar_to_local(1.0, 0.0, (91.0, 0.0), FRAME, sigma_range_m=1, sigma_bearing_rad=1),
            "sensor.lat_deg",
        ),
        (lambda: polar_to_local(1.0, 0.0, SENSOR, (1.0,), sigma_range_m=1, sigma_bearing_rad=1), "frame"),
        (
            lambda: polar_to_local(
                [1.0, 2.0], 0.0, SENSOR, FRAME, sigma_range_m=[1, 2, 3], sigma_bearing_rad=1
            ),
            "sigma_range_m",
        ),
        (
            lambda: polar_to_local(
                1.0, 0.0, SENSOR, FRAME, sigma_range_m=1, sigma_bearing_rad=1, sigma_altitude_m=30
            ),
            "sigma_altitude_m",
        ),
        (
            lambda: polar_to_local(
                [1.0, 2.0], [0.0, 0.1, 0.2], SENSOR, FRAME, sigma_range_m=1, sigma_bearing_rad=1
            ),
            "bearing_rad",
        ),
    ],
)
def test_bad_arguments_name_the_field(call, field):
    """Each refusal is a ConfigError naming the argument (the command layer maps it to its option)."""
    with pytest.raises(ConfigError) as exc:
        call()
    assert exc.value.field == field


def test_missing_rows_stay_missing():
    out = polar_to_local(
        [10e3, math.nan],
        [0.1, 0.2],
        SENSOR,
        FRAME,
        sigma_range_m=10,
        sigma_bearing_rad=1e-3,
        altitude_m=[3e3, 3e3],
    )
    assert np.all(np.isfinite(out.position[0])) and np.all(np.isnan(out.position[1]))
    enu = FRAME.to_local([48.1, math.nan], [11.1, 11.2], 0.0)
    assert np.all(np.isfinite(enu[0])) and np.all(np.isnan(enu[1]))
