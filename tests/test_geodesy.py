"""WGS-84 conversions against pymap3d (an independent implementation) and their own inverses.

Tolerances: 1e-6 m and 1e-9 deg against pymap3d, as double precision allows with room (positions of
6.4e6 to 1e8 m carry about 1e-9 to 1.5e-8 m of rounding). pymap3d's inverse (You, 2000, no iteration) is
itself accurate to 1e-9 deg only up to about 100 km above the ellipsoid (measured: 1.2e-11 deg at 100 km,
7e-8 deg at 1000 km, 1.6e-4 deg at 9e4 km), so above that the oracle is pymap3d's forward transformation
(a closed form, exact to rounding): our inverse of its ECEF must give back the grid.
"""

import numpy as np
import pymap3d
import pytest

from motionsig_cli import geodesy as g

LAT = np.array([-90.0, -89.9999999, -89.5, -60.0, -1e-9, 0.0, 1e-9, 30.0, 45.0, 89.5, 89.9999999, 90.0])
LON = np.array([-180.0, -179.99, -90.0, 0.0, 1e-9, 45.0, 120.0, 179.99, 180.0])
ALT_LOW = np.array([-11_000.0, -430.0, 0.0, 1.0, 1_000.0, 12_000.0, 100_000.0])
ALT_HIGH = np.array([1e6, 2.02e7, 3.5786e7, 9.3e7])


def _grid(alt):
    la, lo, h = np.meshgrid(LAT, LON, alt, indexing="ij")
    return la.ravel(), lo.ravel(), h.ravel()


def _dlon(a, b):
    return np.abs((a - b + 180.0) % 360.0 - 180.0)


@pytest.mark.parametrize("alt", [ALT_LOW, ALT_HIGH], ids=["low", "high"])
def test_geodetic_to_ecef_equals_pymap3d(alt):
    lat, lon, h = _grid(alt)
    ours = g.geodetic_to_ecef(lat, lon, h)
    ref = np.stack(pymap3d.geodetic2ecef(lat, lon, h), axis=-1)
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-6)


def test_ecef_to_geodetic_equals_pymap3d_up_to_100_km():
    lat, lon, h = _grid(ALT_LOW)
    x, y, z = pymap3d.geodetic2ecef(lat, lon, h)
    la, lo, hh = g.ecef_to_geodetic(np.stack([x, y, z], axis=-1))
    rla, rlo, rh = pymap3d.ecef2geodetic(x, y, z)
    assert np.max(np.abs(la - rla)) < 1e-9
    pole = np.abs(rla) > 89.99999  # longitude is undefined at the poles (both give some value)
    assert np.max(_dlon(lo, rlo)[~pole]) < 1e-9
    assert np.max(np.abs(hh - rh)) < 1e-6


@pytest.mark.parametrize("alt", [ALT_LOW, ALT_HIGH], ids=["low", "high"])
def test_ecef_to_geodetic_inverts_pymap3d_forward(alt):
    """The inverse of pymap3d's ECEF gives back the grid (all altitudes, poles included)."""
    lat, lon, h = _grid(alt)
    xyz = np.stack(pymap3d.geodetic2ecef(lat, lon, h), axis=-1)
    la, lo, hh = g.ecef_to_geodetic(xyz)
    assert np.max(np.abs(la - lat)) < 1e-9
    pole = np.abs(lat) == 90.0
    assert np.max(_dlon(lo, lon)[~pole]) < 1e-9
    assert np.max(np.abs(hh - h)) < 1e-6


def test_round_trip_of_random_ecef_points_is_exact_to_rounding():
    rng = np.random.default_rng(3)
    d = rng.standard_normal((20_000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    r = np.exp(rng.uniform(np.log(6.3e6), np.log(1e8), (20_000, 1)))
    xyz = d * r
    back = g.geodetic_to_ecef(*g.ecef_to_geodetic(xyz))
    err = np.linalg.norm(back - xyz, axis=1)
    assert np.max(err / r[:, 0]) < 1e-15  # a few units of the last place: 1e-8 m at 1e8 m
    near = r[:, 0] < 6.4e6
    assert np.max(err[near]) < 1e-8


def test_latitude_at_the_poles_and_the_equator_is_exact():
    la, _, h = g.ecef_to_geodetic(
        np.array([[0.0, 0.0, g.WGS84_B], [0.0, 0.0, -g.WGS84_B - 5.0], [g.WGS84_A, 0, 0]])
    )
    np.testing.assert_array_equal(la, [90.0, -90.0, 0.0])
    np.testing.assert_allclose(h, [0.0, 5.0, 0.0], atol=1e-8)


def test_enu_equals_pymap3d():
    rng = np.random.default_rng(4)
    lat0, lon0, h0 = 48.3538, 11.7861, 453.0
    enu = rng.uniform(-50e3, 50e3, (500, 3))
    ours = g.enu_to_ecef(enu, lat0, lon0, h0)
    ref = np.stack(pymap3d.enu2ecef(enu[:, 0], enu[:, 1], enu[:, 2], lat0, lon0, h0), axis=-1)
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-6)
    back = g.ecef_to_enu(ref, lat0, lon0, h0)
    ref_back = np.stack(pymap3d.ecef2enu(ref[:, 0], ref[:, 1], ref[:, 2], lat0, lon0, h0), axis=-1)
    np.testing.assert_allclose(back, ref_back, rtol=0, atol=1e-6)
    np.testing.assert_allclose(back, enu, rtol=0, atol=1e-6)


def test_enu_rotation_is_orthonormal_and_up_is_the_ellipsoid_normal():
    lat = np.array([-90.0, -45.0, 0.0, 30.0, 90.0])
    lon = np.array([0.0, 200.0, -180.0, 10.0, 33.0])
    C = g.enu_rotation(lat, lon)
    np.testing.assert_allclose(C @ np.swapaxes(C, -1, -2), np.broadcast_to(np.eye(3), C.shape), atol=1e-15)
    np.testing.assert_allclose(np.linalg.det(C), 1.0, atol=1e-15)  # east × north = up
    # up is the normal: moving up by 1 m changes the ellipsoidal height by 1 m and nothing else
    p = g.geodetic_to_ecef(lat, lon, 100.0) + C[:, 2]
    la, _, h = g.ecef_to_geodetic(p)
    np.testing.assert_allclose(h, 101.0, atol=1e-8)
    np.testing.assert_allclose(la, lat, atol=1e-12)


def test_covariance_rotation():
    rng = np.random.default_rng(5)
    A = rng.standard_normal((7, 3, 3))
    P = A @ np.swapaxes(A, -1, -2)
    lat, lon = rng.uniform(-90, 90, 7), rng.uniform(-180, 180, 7)
    Q = g.covariance_to_enu(P, lat, lon)
    C = g.enu_rotation(lat, lon)
    np.testing.assert_allclose(Q, C @ P @ np.swapaxes(C, -1, -2), atol=1e-12)
    np.testing.assert_allclose(np.trace(Q, axis1=1, axis2=2), np.trace(P, axis1=1, axis2=2), rtol=1e-12)


def test_the_centre_of_the_earth_is_refused_or_nan():
    with pytest.raises(ValueError, match="no unique geodetic latitude"):
        g.ecef_to_geodetic(np.array([1e3, 0.0, 0.0]))
    with pytest.raises(ValueError, match="finite"):
        g.ecef_to_geodetic(np.array([np.nan, 0.0, 7e6]))
    la, _, h = g.ecef_to_geodetic(np.array([[1e3, 0.0, 0.0], [np.inf, 0, 0], [7e6, 0, 0]]), strict=False)
    assert np.isnan(la[:2]).all() and np.isnan(h[:2]).all() and h[2] == pytest.approx(7e6 - g.WGS84_A)


def test_surface_point_keeps_latitude_and_longitude():
    xyz = g.geodetic_to_ecef(np.array([48.0, -33.0]), np.array([11.0, 151.0]), np.array([2.0e7, -500.0]))
    s = g.surface_point(xyz, 10_000.0)
    la, lo, h = g.ecef_to_geodetic(s)
    np.testing.assert_allclose(la, [48.0, -33.0], atol=1e-12)
    np.testing.assert_allclose(lo, [11.0, 151.0], atol=1e-12)
    np.testing.assert_allclose(h, 10_000.0, atol=1e-8)
