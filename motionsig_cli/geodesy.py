"""WGS-84 coordinates: geodetic (latitude, longitude, ellipsoidal height) ↔ Earth-centred Earth-fixed (ECEF)
↔ local east-north-up (ENU). Vectorised over any leading shape; angles in degrees, lengths in metres.

- :func:`geodetic_to_ecef`: the closed form X = (N + h) cos φ cos λ, Y = (N + h) cos φ sin λ,
  Z = (N(1 − e²) + h) sin φ with the prime-vertical radius N = a/√(1 − e² sin² φ).
- :func:`ecef_to_geodetic`: the exact closed form of Vermeille (*Direct transformation from geocentric
  coordinates to geodetic coordinates*, Journal of Geodesy 76, 2002, 451–454), no iteration. It holds
  outside the evolute of the ellipsoid's meridian, i.e. everywhere but within about a·e² ≈ 43 km of the
  Earth's centre, where the geodetic latitude is not unique; such points are refused. Its error is a few
  units of the last place (≈ 10⁻⁹ m at the Earth's surface, measured in the tests by the round trip and
  against pymap3d).
- :func:`enu_rotation`, :func:`ecef_to_enu`, :func:`enu_to_ecef`: the local frame of a geodetic origin
  (east, north, and up along the ellipsoid's normal), and :func:`covariance_to_enu` for a 3×3 ECEF
  covariance.

The ellipsoid is WGS-84 (NIMA TR8350.2: a = 6 378 137 m, 1/f = 298.257 223 563). The spherical-Earth
helpers of :mod:`motionsig_cli.surveillance.multilateration` (the report's analyses) are left as they are.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "WGS84_A",
    "WGS84_B",
    "WGS84_E2",
    "WGS84_F",
    "covariance_to_enu",
    "ecef_to_enu",
    "ecef_to_geodetic",
    "enu_rotation",
    "enu_to_ecef",
    "geodetic_to_ecef",
    "surface_point",
]

WGS84_A = 6378137.0
"""Semi-major axis a [m] (WGS-84)."""
WGS84_F = 1.0 / 298.257223563
"""Flattening f (WGS-84)."""
WGS84_B = WGS84_A * (1.0 - WGS84_F)
"""Semi-minor axis b = a(1 − f) [m]."""
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)
"""First eccentricity squared e² = f(2 − f)."""
_E4 = WGS84_E2**2
EVOLUTE_M = WGS84_A * WGS84_E2
"""Points closer than about this to the Earth's centre (a·e² ≈ 42.7 km) lie inside the evolute of the
meridian ellipse: their geodetic latitude is not unique and :func:`ecef_to_geodetic` refuses them."""


def geodetic_to_ecef(
    lat_deg: np.ndarray | float, lon_deg: np.ndarray | float, alt_m: np.ndarray | float
) -> np.ndarray:
    """ECEF position [m], shape (..., 3), of geodetic latitude, longitude [deg] and height above the
    WGS-84 ellipsoid [m] (broadcast against each other)."""
    lat = np.radians(np.asarray(lat_deg, dtype=float))
    lon = np.radians(np.asarray(lon_deg, dtype=float))
    h = np.asarray(alt_m, dtype=float)
    s, c = np.sin(lat), np.cos(lat)
    n = WGS84_A / np.sqrt(1.0 - WGS84_E2 * s * s)  # prime-vertical radius of curvature
    return np.stack(
        np.broadcast_arrays(
            (n + h) * c * np.cos(lon), (n + h) * c * np.sin(lon), (n * (1.0 - WGS84_E2) + h) * s
        ),
        axis=-1,
    )


def ecef_to_geodetic(xyz: np.ndarray, *, strict: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Geodetic latitude, longitude [deg] (in (−180, 180]) and height above the WGS-84 ellipsoid [m] of
    ECEF positions ``xyz`` (..., 3) [m], by Vermeille's closed form (module docstring).

    Args:
        xyz: ECEF positions [m].
        strict: raise for a position that is not finite or lies within the evolute; False: NaN there.

    Raises:
        ValueError: (``strict``) a position that is not finite, or lies within the evolute (≈ 43 km of the
            centre).
    """
    xyz = np.asarray(xyz, dtype=float)
    if xyz.shape[-1:] != (3,):
        raise ValueError(f"ECEF positions need 3 components in the last axis, got shape {xyz.shape}")
    finite = np.all(np.isfinite(xyz), axis=-1)
    if strict and not np.all(finite):
        raise ValueError("ECEF positions must be finite")
    xyz = np.where(finite[..., None], xyz, WGS84_A)
    X, Y, Z = xyz[..., 0], xyz[..., 1], xyz[..., 2]
    rho2 = X * X + Y * Y
    p = rho2 / WGS84_A**2
    q = (1.0 - WGS84_E2) * Z * Z / WGS84_A**2
    r = (p + q - _E4) / 6.0
    inside = ~(r > 0.0)
    if strict and np.any(inside):
        raise ValueError(
            f"a position within {EVOLUTE_M / 1e3:.1f} km of the Earth's centre has no unique geodetic latitude"
        )
    valid = finite & ~inside
    r = np.where(inside, 1.0, r)
    s = _E4 * p * q / (4.0 * r**3)
    t = np.cbrt(1.0 + s + np.sqrt(s * (2.0 + s)))
    u = r * (1.0 + t + 1.0 / t)
    v = np.sqrt(u * u + _E4 * q)
    w = WGS84_E2 * (u + v - q) / (2.0 * v)
    k = np.sqrt(u + v + w * w) - w
    rho = np.sqrt(rho2)
    D = k * rho / (k + WGS84_E2)
    dz = np.sqrt(D * D + Z * Z)
    lat = 2.0 * np.arctan2(Z, D + dz)
    lon = np.arctan2(Y, X)
    h = (k + WGS84_E2 - 1.0) / k * dz
    lat, lon = np.degrees(lat), np.degrees(lon)
    if not np.all(valid):
        lat, lon, h = (np.where(valid, v, np.nan) for v in (lat, lon, h))
    return lat, lon, h


def enu_rotation(lat_deg: np.ndarray | float, lon_deg: np.ndarray | float) -> np.ndarray:
    """Rotation (..., 3, 3) from ECEF to the local frame at geodetic (lat, lon): its rows are the east,
    north and up unit vectors (up along the ellipsoid's normal) in ECEF components."""
    lat = np.radians(np.asarray(lat_deg, dtype=float))
    lon = np.radians(np.asarray(lon_deg, dtype=float))
    lat, lon = np.broadcast_arrays(lat, lon)
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    zero = np.zeros_like(lat)
    east = np.stack([-so, co, zero], axis=-1)
    north = np.stack([-sl * co, -sl * so, cl], axis=-1)
    up = np.stack([cl * co, cl * so, sl], axis=-1)
    return np.stack([east, north, up], axis=-2)


def ecef_to_enu(
    xyz: np.ndarray, lat0_deg: np.ndarray | float, lon0_deg: np.ndarray | float, alt0_m: np.ndarray | float
) -> np.ndarray:
    """East, north, up [m] (..., 3) of ECEF positions ``xyz`` relative to the geodetic origin."""
    origin = geodetic_to_ecef(lat0_deg, lon0_deg, alt0_m)
    d = np.asarray(xyz, dtype=float) - origin
    return np.einsum("...ij,...j->...i", enu_rotation(lat0_deg, lon0_deg), d)


def enu_to_ecef(
    enu: np.ndarray, lat0_deg: np.ndarray | float, lon0_deg: np.ndarray | float, alt0_m: np.ndarray | float
) -> np.ndarray:
    """ECEF positions [m] (..., 3) of local east, north, up offsets ``enu`` [m] from the geodetic origin."""
    origin = geodetic_to_ecef(lat0_deg, lon0_deg, alt0_m)
    return origin + np.einsum("...ji,...j->...i", enu_rotation(lat0_deg, lon0_deg), np.asarray(enu, float))


def covariance_to_enu(P: np.ndarray, lat_deg: np.ndarray | float, lon_deg: np.ndarray | float) -> np.ndarray:
    """A 3×3 ECEF position covariance (..., 3, 3) in the local east-north-up frame: C P Cᵀ (symmetrised)."""
    C = enu_rotation(lat_deg, lon_deg)
    out = C @ np.asarray(P, dtype=float) @ np.swapaxes(C, -1, -2)
    return 0.5 * (out + np.swapaxes(out, -1, -2))


def surface_point(xyz: np.ndarray, alt_m: float = 0.0) -> np.ndarray:
    """The point at height ``alt_m`` above the WGS-84 ellipsoid along the geodetic normal through the
    ellipsoid point nearest ``xyz`` (..., 3) — e.g. the receivers' centroid "pushed to the surface".
    A point within the evolute (near the centre) is pushed along its geocentric direction instead."""
    xyz = np.asarray(xyz, dtype=float)
    r = np.linalg.norm(xyz, axis=-1, keepdims=True)
    inside = r[..., 0] < 2.0 * EVOLUTE_M
    direction = np.where(r > 0, xyz / np.where(r > 0, r, 1.0), np.array([1.0, 0.0, 0.0]))
    safe = np.where(inside[..., None], direction * WGS84_A, xyz)
    lat, lon, _ = ecef_to_geodetic(safe)
    return geodetic_to_ecef(lat, lon, alt_m)
