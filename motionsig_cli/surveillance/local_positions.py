"""Measured positions as users have them — ADS-B latitude, longitude and altitude, radar plots in range and
bearing — in one local east/north plane, each with its measurement covariance, for the trackers.

**The plane** (:class:`LocalFrame`). The tangent plane of the WGS-84 ellipsoid at a geodetic origin
(φ₀, λ₀, h₀), with east, north and up along the ellipsoid's normal (:mod:`motionsig_cli.geodesy`). A point
(φ, λ, h) has the ECEF position

    (1)  X = (N + h) cos φ cos λ,  Y = (N + h) cos φ sin λ,  Z = (N(1 − e²) + h) sin φ,
         N = a / √(1 − e² sin² φ),

and the local coordinates

    (2)  (e, n, u)ᵀ = C(φ₀, λ₀) (X − X₀),

where the rows of C are the east, north and up unit vectors at the origin. The inverse is
X = X₀ + Cᵀ (e, n, u)ᵀ followed by Vermeille's closed form for (φ, λ, h); both are exact (the round trip
holds to ≈ 10⁻⁹ m). For horizontal tracking only (e, n) is kept and **up is dropped**. That is not an
approximation of the conversion — (e, n) are the exact coordinates of the point's projection onto the
plane — but the plane is flat and the Earth is not. On a sphere of radius R ≈ 6371 km, a point at
distance d from the origin along the surface

    (3)  lies u ≈ −d²/(2R) below the plane (785 m at 100 km, 7.06 km at 300 km), and
    (4)  is drawn at the plane distance R sin(d/R) ≈ d − d³/(6R²): shortened by 0.51 m at 50 km, 4.1 m at
         100 km, 111 m at 300 km (4 × 10⁻⁵ of the distance at 100 km).

A target moving uniformly along a great circle at speed v therefore shows in the plane an apparent
acceleration, the horizontal part of its centripetal v²/R about the Earth's centre seen from a normal
tilted by d/R:

    (5)  |a| ≈ (v²/R) sin(d/R):  1.5 × 10⁻⁴ m/s² at 100 km, 4.6 × 10⁻⁴ m/s² at 300 km for v = 250 m/s,

0.8 m over 100 s at 100 km: far below any tracker's process noise. Within a few hundred kilometres of the
origin the plane is as good as the data (radar bearing errors of 0.1° are 175 m at 100 km). The plane's
(e, n) of a point depend on its height, though: along the normal at distance d the horizontal position
moves by h sin(d/R) (157 m for h = 10 km at 100 km, eq 5's tilt), so a position converted to the plane
with its altitude must be converted back with the same altitude (:meth:`LocalFrame.to_geodetic` with
``alt_m``), never with up = 0.

**The origin** a command uses when the user names none (:func:`default_origin`): the midpoint of the
latitude/longitude bounding box of the valid reports, at height 0. It does not depend on the order of the
rows (the first report could be at an edge, doubling the largest distance and multiplying the distortion of
eq 4 by eight), and it bounds the largest distance by half the box's diagonal.

**Radar plots** (:func:`polar_to_local`). A sensor at (φ_s, λ_s, h_s) measures the slant range r and the
bearing θ, clockwise from north by default (the surveillance convention; ``convention="math"``: counter-
clockwise from east). With ground range ρ and elevation ε, in the sensor's own east-north-up frame,

    (6)  north-clockwise:  e_s = ρ sin θ,  n_s = ρ cos θ;    math:  e_s = ρ cos θ,  n_s = ρ sin θ;
    (7)  ρ = r cos ε,  u_s = r sin ε.

The elevation comes from one of three sources:

- given (``elevation_rad``, a 3-D radar): eq 7 directly;
- from the target's height h_t (``altitude_m``, e.g. Mode C), on a sphere of the radius of curvature R_α
  of the ellipsoid in the bearing's direction (Euler: 1/R_α = cos²α/M + sin²α/N, α the azimuth from
  north, M and N the meridian and prime-vertical radii at φ_s). The Earth's centre, the sensor at
  B = R_α + h_s from it and the target at R_α + h_t form a triangle with sides B, r and R_α + h_t, and
  the angle between the line of sight and the sensor's horizon is ε, so by the law of cosines

      (8)  (R_α + h_t)² = B² + r² + 2 r B sin ε,   sin ε = ((R_α + h_t)² − B² − r²) / (2 r B),

  which needs |sin ε| ≤ 1 (a range shorter than the height difference is refused). That ε is then
  refined on the ellipsoid itself by Newton steps on f(ε) = h(ε) − h_t, with h(ε) the WGS-84 height of
  the point of eq 6–7 and f'(ε) ≈ r B cos ε / (R_α + h_t) (eq 8 differentiated), until |f| < 0.1 µm;
- neither: the range is taken as the ground range (ρ = r, u_s = 0: a point in the sensor's tangent
  plane). That is an assumption, and the result says so (:attr:`PolarPositions.notes`): for a target
  at height Δh above the sensor the ground range is r cos ε ≈ r − Δh²/(2r), so a range taken as
  ground range is 0.5 km too long at 10 km height and 100 km range, 2.7 km at 20 km.

The point is then taken from the sensor's frame to ECEF and into the frame's (eq 2): the sensor need not
be at the frame's origin. The altitude is the height above the WGS-84 ellipsoid; a barometric (Mode C)
altitude differs from it by the geoid (±100 m) and the atmosphere's departure from the standard one (a
few hundred m), which moves ρ by −tan ε · δh (eq 10): give ``sigma_altitude_m`` to carry it.

**Covariance** (first order, the standard converted-measurement approximation). With the measurement
noise (σ_r, σ_θ and σ_ε or σ_h), the sensor-frame Jacobian of (e_s, n_s, u_s) is, north-clockwise (the
math convention swaps sin and cos and the sign of the bearing column),

    (9)  ∂(e_s, n_s)/∂θ = ρ (cos θ, −sin θ),   ∂(e_s, n_s)/∂ρ = (sin θ, cos θ),
    (10) ∂ρ/∂r = cos ε, ∂u_s/∂r = sin ε, ∂ρ/∂ε = −r sin ε, ∂u_s/∂ε = r cos ε     (elevation given),
         ∂ρ/∂r = sec ε + r tan ε / B, ∂u_s/∂r = −r/B,
         ∂ρ/∂h_t = −tan ε (R_α + h_t)/B, ∂u_s/∂h_t = (R_α + h_t)/B                 (from the altitude:
         eq 8 differentiated, ρ = r cos ε; flat-Earth limit ρ = √(r² − Δh²), ∂ρ/∂r = r/ρ = sec ε),
         ∂ρ/∂r = 1, u_s = 0                                                        (ground range);

and in the frame P = J Σ Jᵀ with J = T[:2, :] J_s, T = C_f C_sᵀ the rotation from the sensor's ENU to the
frame's (its horizontal block is a rotation by the meridian convergence, its up column tilts by d/R), and
Σ = diag(σ_r², σ_θ², σ_ε² or σ_h²). The linearisation is the standard converted-measurement approximation;
it is consistent while the bearing error's curvature is small against the range error:

    (11) ρ σ_θ² / σ_ρ < 0.4     (Lerro & Bar-Shalom, *Tracking with debiased consistent converted
         measurements versus EKF*, IEEE Trans. AES 29(3), 1993),

e.g. 100 km, σ_θ = 0.2° (3.5 mrad), σ_r = 50 m: 0.024; the ratio is returned per row
(:attr:`PolarPositions.linearity`). Beyond it (long ranges, coarse bearings) ``debias=True`` gives Lerro &
Bar-Shalom's additive debiased converted measurement in the sensor's plane, with μ = ρ_m (cos, sin)(θ_m)
(e^{−σ_θ²} − e^{−σ_θ²/2}) subtracted and their covariance (eq 12, :func:`debiased_polar`), then rotated
as above.

**ADS-B accuracy** (:func:`nacp_to_sigma`). A position report's NACp bounds its *estimated position
uncertainty* (EPU), a 95 % horizontal radius (RTCA DO-260B). For a circular bivariate normal with σ per
axis, the horizontal error's radius R is Rayleigh distributed:

    (13) P(R ≤ ρ) = 1 − exp(−ρ² / (2σ²)) = 0.95  ⇔  ρ = σ √(−2 ln 0.05) = 2.4477 σ,

so σ = EPU / 2.4477 per axis (an upper bound, since the EPU is one). A horizontal covariance σ² I in the
report's own ENU is σ² I in the frame's to within (d/R)²/2 (10⁻⁴ at 100 km): :func:`cartesian_covariance`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError, in_range, one_of
from motionsig_cli.geodesy import (
    WGS84_A,
    WGS84_E2,
    ecef_to_enu,
    ecef_to_geodetic,
    enu_rotation,
    enu_to_ecef,
    geodetic_to_ecef,
)

__all__ = [
    "CONVENTIONS",
    "EPU_95_FACTOR",
    "LINEARITY_LIMIT",
    "NACP_EPU_M",
    "RANGE_KINDS",
    "LocalFrame",
    "PolarPositions",
    "cartesian_covariance",
    "debiased_polar",
    "default_origin",
    "nacp_to_sigma",
    "polar_to_local",
    "wrap_angle",
]

CONVENTIONS = ("north-clockwise", "math")
"""Bearing conventions: clockwise from north (surveillance), or counter-clockwise from east (math)."""
RANGE_KINDS = ("slant-elevation", "slant-altitude", "ground")
"""How a range was read: slant with a measured elevation, slant with the elevation from the target's
altitude, or taken as the ground range (assumed)."""
LINEARITY_LIMIT = 0.4
"""Lerro & Bar-Shalom's bound on ρ σ_θ² / σ_ρ under which the linearised covariance is consistent."""
EPU_95_FACTOR = math.sqrt(-2.0 * math.log(0.05))
"""√(−2 ln 0.05) ≈ 2.4477: the 95 % radius of a circular bivariate normal in units of σ per axis (eq 13)."""
_NMI = 1852.0
NACP_EPU_M: dict[int, float] = {
    11: 3.0,
    10: 10.0,
    9: 30.0,
    8: 0.05 * _NMI,
    7: 0.1 * _NMI,
    6: 0.3 * _NMI,
    5: 0.5 * _NMI,
    4: 1.0 * _NMI,
    3: 2.0 * _NMI,
    2: 4.0 * _NMI,
    1: 10.0 * _NMI,
    0: math.nan,
}
"""NACp → the bound on the 95 % horizontal EPU [m] (RTCA DO-260B; NACp 0: unknown, ≥ 10 NM: NaN)."""
_NEWTON_TOL_M = 1e-7
_NEWTON_MAX = 20


def wrap_angle(a: np.ndarray | float) -> np.ndarray:
    """Angles [rad] wrapped to (−π, π]."""
    a = np.asarray(a, dtype=float)
    return np.pi - np.mod(np.pi - a, 2.0 * np.pi)


def _array(field: str, value: Any) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ConfigError(field, value, "is not a number or an array of numbers") from None
    if np.any(np.isinf(arr)):
        raise ConfigError(field, _first(arr, np.isinf(arr)), "is not finite")
    return arr


def _first(arr: np.ndarray, bad: np.ndarray) -> float:
    return float(np.asarray(arr).reshape(-1)[int(np.flatnonzero(np.asarray(bad).reshape(-1))[0])])


def _check_lat_lon(lat: np.ndarray, lon: np.ndarray, lat_field: str, lon_field: str) -> None:
    with np.errstate(invalid="ignore"):
        bad_lat = np.abs(lat) > 90.0
        bad_lon = np.abs(lon) > 360.0
    if np.any(bad_lat):
        raise ConfigError(lat_field, _first(lat, bad_lat), "is not in [-90, 90] deg")
    if np.any(bad_lon):
        raise ConfigError(lon_field, _first(lon, bad_lon), "is not in [-360, 360] deg")


@dataclass(frozen=True)
class LocalFrame:
    """The local east/north/up tangent plane of the WGS-84 ellipsoid at a geodetic origin (eq 1–2).

    Attributes:
        lat_deg: Origin latitude [deg], in [−90, 90].
        lon_deg: Origin longitude [deg], in [−180, 360] (stored as given).
        alt_m: Origin height above the ellipsoid [m], in [−11 000, 100 000].

    Raises:
        ConfigError: naming the first bad field.

    Examples:
        >>> from motionsig_cli.surveillance.local_positions import LocalFrame
        >>> frame = LocalFrame(48.35, 11.78)
        >>> enu = frame.to_local(48.35, 11.78 + 1.0, 0.0)
        >>> round(float(enu[0, 0]) / 1e3, 2), round(float(enu[0, 2]))  # 1° of longitude east, below the plane
        (74.12, -430)
    """

    lat_deg: float
    lon_deg: float
    alt_m: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "lat_deg", in_range("lat_deg", self.lat_deg, -90.0, 90.0, unit="deg"))
        object.__setattr__(self, "lon_deg", in_range("lon_deg", self.lon_deg, -180.0, 360.0, unit="deg"))
        object.__setattr__(self, "alt_m", in_range("alt_m", self.alt_m, -11000.0, 100000.0, unit="m"))

    @property
    def ecef(self) -> np.ndarray:
        """The origin's ECEF position X₀ [m] (3,)."""
        return geodetic_to_ecef(self.lat_deg, self.lon_deg, self.alt_m)

    @property
    def rotation(self) -> np.ndarray:
        """C(φ₀, λ₀) (3, 3): ECEF → (east, north, up) at the origin (eq 2)."""
        return enu_rotation(self.lat_deg, self.lon_deg)

    def to_local(
        self, lat_deg: np.ndarray | float, lon_deg: np.ndarray | float, alt_m: np.ndarray | float = 0.0
    ) -> np.ndarray:
        """East, north, up [m] (N, 3) of geodetic positions (broadcast against each other; NaN rows stay
        NaN: a missing report), eq 1–2. Keep ``[:, :2]`` for horizontal tracking (up dropped).

        Raises:
            ConfigError: a latitude beyond ±90° or a longitude beyond ±360° (naming ``lat`` or ``lon``),
                or an infinite value.
        """
        lat, lon, alt = _array("lat", lat_deg), _array("lon", lon_deg), _array("alt", alt_m)
        _check_lat_lon(lat, lon, "lat", "lon")
        lat, lon, alt = np.broadcast_arrays(np.atleast_1d(lat), np.atleast_1d(lon), np.atleast_1d(alt))
        xyz = geodetic_to_ecef(lat.reshape(-1), lon.reshape(-1), alt.reshape(-1))
        return ecef_to_enu(xyz, self.lat_deg, self.lon_deg, self.alt_m)

    def to_geodetic(
        self,
        east: np.ndarray | float,
        north: np.ndarray | float,
        up: np.ndarray | float | None = None,
        *,
        alt_m: np.ndarray | float | None = None,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Latitude, longitude [deg] (in (−180, 180]) and height [m] of plane positions, each (N,).

        With ``up`` the point is (east, north, up) of the frame, exactly (eq 2 inverted). Without it the
        point is the one whose projection onto the plane is (east, north) and whose height above the
        ellipsoid is ``alt_m`` (default: the origin's): the inverse of :meth:`to_local` with up dropped,
        found by Newton steps on up, u ← u + (h_t − h(u)) (dh/du = cos of the angle between the two
        normals, 1 − 10⁻⁴ at 100 km) until |h − h_t| < 0.1 µm.

        Raises:
            ConfigError: both ``up`` and ``alt_m`` given, or an infinite value.
        """
        if up is not None and alt_m is not None:
            raise ConfigError("alt_m", alt_m, "is given with up: give one")
        e, n = _array("east", east), _array("north", north)
        if up is not None:
            u = _array("up", up)
            e, n, u = (a.reshape(-1) for a in np.broadcast_arrays(np.atleast_1d(e), np.atleast_1d(n), u))
            xyz = enu_to_ecef(np.stack([e, n, u], axis=-1), self.lat_deg, self.lon_deg, self.alt_m)
            return ecef_to_geodetic(xyz, strict=False)
        h_t = _array("alt_m", self.alt_m if alt_m is None else alt_m)
        e, n, h_t = (a.reshape(-1) for a in np.broadcast_arrays(np.atleast_1d(e), np.atleast_1d(n), h_t))
        u = (h_t - self.alt_m) - (e * e + n * n) / (2.0 * WGS84_A)  # eq 3 as the first guess
        for _ in range(_NEWTON_MAX):
            xyz = enu_to_ecef(np.stack([e, n, u], axis=-1), self.lat_deg, self.lon_deg, self.alt_m)
            lat, lon, h = ecef_to_geodetic(xyz, strict=False)
            step = h_t - h
            if not np.any(np.abs(step) > _NEWTON_TOL_M):
                break
            u = u + np.where(np.isfinite(step), step, 0.0)
        return lat, lon, h


def default_origin(
    lat_deg: np.ndarray | Sequence[float], lon_deg: np.ndarray | Sequence[float]
) -> LocalFrame:
    """The frame a command uses when the user names no origin: the midpoint of the latitude/longitude
    bounding box of the valid (finite) reports, at height 0 (module docstring). Longitudes are taken
    relative to the first valid one, wrapped to (−180, 180], so a box across the antimeridian is the
    short one; the midpoint's longitude is wrapped to (−180, 180].

    Raises:
        ConfigError: no valid report (naming ``lat``), or a coordinate out of range.

    Examples:
        >>> from motionsig_cli.surveillance.local_positions import default_origin
        >>> default_origin([48.0, 49.0, 48.5], [179.5, -179.5, 180.0])
        LocalFrame(lat_deg=48.5, lon_deg=180.0, alt_m=0.0)
    """
    lat, lon = _array("lat", lat_deg).reshape(-1), _array("lon", lon_deg).reshape(-1)
    if lat.shape != lon.shape:
        raise ConfigError("lon", lon.shape, f"does not match the latitudes' shape {lat.shape}")
    _check_lat_lon(lat, lon, "lat", "lon")
    ok = np.isfinite(lat) & np.isfinite(lon)
    if not np.any(ok):
        raise ConfigError("lat", lat.size, "reports hold no valid position")
    lat, lon = lat[ok], lon[ok]
    rel = (lon - lon[0] + 180.0) % 360.0 - 180.0
    mid_lon = float(lon[0] + 0.5 * (rel.min() + rel.max()))
    mid_lon = 180.0 - (180.0 - mid_lon) % 360.0
    return LocalFrame(float(0.5 * (lat.min() + lat.max())), mid_lon, 0.0)


def nacp_to_sigma(nacp: np.ndarray | int | Sequence[int]) -> np.ndarray:
    """σ per horizontal axis [m] of ADS-B reports' NACp: the EPU bound of :data:`NACP_EPU_M` divided by
    :data:`EPU_95_FACTOR` (eq 13). NACp 0 (unknown accuracy) gives NaN: such a report cannot be weighted.

    Raises:
        ConfigError: a NACp that is not an integer in [0, 11] (naming ``nacp``).

    Examples:
        >>> from motionsig_cli.surveillance.local_positions import nacp_to_sigma
        >>> [round(float(s), 2) for s in nacp_to_sigma([11, 10, 9, 8])]
        [1.23, 4.09, 12.26, 37.83]
    """
    arr = np.atleast_1d(np.asarray(nacp))
    try:
        x = arr.astype(float)
    except (TypeError, ValueError):
        raise ConfigError("nacp", nacp, "is not an integer in [0, 11]") from None
    bad = ~np.isfinite(x) | (x != np.round(x)) | (x < 0) | (x > 11) | (arr.dtype == bool)
    if np.any(bad):
        raise ConfigError(
            "nacp", arr.reshape(-1)[int(np.flatnonzero(bad.reshape(-1))[0])], "is not an integer in [0, 11]"
        )
    table = np.array([NACP_EPU_M[k] for k in range(12)])
    return table[x.astype(int)] / EPU_95_FACTOR


def cartesian_covariance(
    sigma_east: np.ndarray | float, sigma_north: np.ndarray | float | None = None
) -> np.ndarray:
    """Diagonal horizontal covariances (N, 2, 2) [m²] from σ per row (east, and north: default the same,
    a circular error such as an ADS-B EPU, :func:`nacp_to_sigma`). NaN σ (unknown accuracy) gives NaN.

    Raises:
        ConfigError: a σ that is negative or infinite (naming ``sigma_east`` or ``sigma_north``).
    """
    se = _array("sigma_east", sigma_east)
    sn = se if sigma_north is None else _array("sigma_north", sigma_north)
    for field, s in (("sigma_east", se), ("sigma_north", sn)):
        with np.errstate(invalid="ignore"):
            neg = s < 0
        if np.any(neg):
            raise ConfigError(field, _first(s, neg), "is not >= 0")
    se, sn = (a.reshape(-1) for a in np.broadcast_arrays(np.atleast_1d(se), np.atleast_1d(sn)))
    out = np.zeros((se.size, 2, 2))
    out[:, 0, 0] = se * se
    out[:, 1, 1] = sn * sn
    nan = ~(np.isfinite(se) & np.isfinite(sn))
    out[nan] = np.nan
    return out


def debiased_polar(
    rho: np.ndarray, phi: np.ndarray, sigma_rho: np.ndarray, sigma_phi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Lerro & Bar-Shalom's (1993) additive debiased converted measurement of a 2-D polar one, in the math
    convention (x = ρ cos φ, y = ρ sin φ), evaluated at the measured ρ_m, φ_m with s = σ_φ²:

        (12) x_u = ρ_m cos φ_m − μ_x,  μ_x = ρ_m cos φ_m (e^{−s} − e^{−s/2})   (y with sin),
             R₁₁ = ρ_m² e^{−2s} [cos²φ_m (cosh 2s − cosh s) + sin²φ_m (sinh 2s − sinh s)]
                   + σ_ρ² e^{−2s} [cos²φ_m (2 cosh 2s − cosh s) + sin²φ_m (2 sinh 2s − sinh s)],
             R₂₂ = the same with cos and sin exchanged,
             R₁₂ = sin φ_m cos φ_m e^{−4s} [σ_ρ² + (ρ_m² + σ_ρ²)(1 − e^{s})].

    The debiased mean is unbiased to O(σ_φ⁴), and R is consistent: at ρ = 100 km, σ_φ = 0.1 rad,
    σ_ρ = 10 m the Monte Carlo's mean normalised error eᵀR⁻¹e is 2.01 (2 expected), where the linearised
    conversion's is 7400 (``tests/surveillance/test_local_positions.py``).

    Returns:
        (positions (N, 2), covariances (N, 2, 2)).
    """
    s = sigma_phi**2
    c, sn = np.cos(phi), np.sin(phi)
    k = np.exp(-s) - np.exp(-s / 2.0)
    pos = np.stack([rho * c * (1.0 - k), rho * sn * (1.0 - k)], axis=-1)
    e2 = np.exp(-2.0 * s)
    ch = np.cosh(2.0 * s) - np.cosh(s)
    sh = np.sinh(2.0 * s) - np.sinh(s)
    ch2 = 2.0 * np.cosh(2.0 * s) - np.cosh(s)
    sh2 = 2.0 * np.sinh(2.0 * s) - np.sinh(s)
    r2, v = rho * rho, sigma_rho**2
    cov = np.empty((*np.shape(rho), 2, 2))
    cov[..., 0, 0] = r2 * e2 * (c * c * ch + sn * sn * sh) + v * e2 * (c * c * ch2 + sn * sn * sh2)
    cov[..., 1, 1] = r2 * e2 * (sn * sn * ch + c * c * sh) + v * e2 * (sn * sn * ch2 + c * c * sh2)
    cov[..., 0, 1] = cov[..., 1, 0] = sn * c * np.exp(-4.0 * s) * (v + (r2 + v) * (1.0 - np.exp(s)))
    return pos, cov


@dataclass(frozen=True)
class PolarPositions:
    """Radar plots converted into a local frame (:func:`polar_to_local`), arrays over N rows (NaN where a
    measurement is missing).

    Attributes:
        position: (N, 2) east, north [m] in the frame.
        covariance: (N, 2, 2) their covariance [m²] (first order, or Lerro & Bar-Shalom's with ``debias``).
        up: (N,) up [m] in the frame.
        ground_range_m: (N,) ρ in the sensor's plane [m].
        elevation_rad: (N,) ε [rad] (0 where the range was taken as the ground range).
        linearity: (N,) ρ σ_θ² / σ_ρ (eq 11: the linearised covariance is consistent below 0.4).
        range_kind: one of :data:`RANGE_KINDS`.
        convention: the bearing convention (one of :data:`CONVENTIONS`).
        debiased: whether the debiased converted measurement was used.
        notes: what was assumed, for the output metadata.
    """

    position: np.ndarray
    covariance: np.ndarray
    up: np.ndarray
    ground_range_m: np.ndarray
    elevation_rad: np.ndarray
    linearity: np.ndarray
    range_kind: str
    convention: str
    debiased: bool
    notes: tuple[str, ...]

    def meta(self) -> dict[str, Any]:
        """What the conversion assumed, for output metadata."""
        return {
            "range_kind": self.range_kind,
            "bearing_convention": self.convention,
            "covariance": "debiased (Lerro & Bar-Shalom 1993)" if self.debiased else "linearised",
            "max_linearity": float(np.nanmax(self.linearity))
            if np.any(np.isfinite(self.linearity))
            else None,
            "notes": list(self.notes),
        }


def _as_frame(field: str, value: LocalFrame | Sequence[float]) -> LocalFrame:
    if isinstance(value, LocalFrame):
        return value
    try:
        parts = [float(v) for v in value]
    except (TypeError, ValueError):
        raise ConfigError(field, value, "is not a LocalFrame or (lat_deg, lon_deg[, alt_m])") from None
    if len(parts) not in (2, 3):
        raise ConfigError(field, value, "is not a LocalFrame or (lat_deg, lon_deg[, alt_m])")
    try:
        return LocalFrame(*parts)
    except ConfigError as exc:
        raise ConfigError(f"{field}.{exc.field}", exc.value, exc.reason) from None


def _sigma(field: str, value: Any) -> np.ndarray:
    arr = _array(field, value)
    with np.errstate(invalid="ignore"):
        bad = ~(arr >= 0)
    if np.any(bad):
        raise ConfigError(field, _first(arr, bad), "is not a finite number >= 0")
    return arr


def _euler_radius(lat_deg: float, azimuth: np.ndarray) -> np.ndarray:
    """R_α: the ellipsoid's radius of curvature at latitude φ in the direction α from north (Euler)."""
    s2 = math.sin(math.radians(lat_deg)) ** 2
    w = 1.0 - WGS84_E2 * s2
    m = WGS84_A * (1.0 - WGS84_E2) / w**1.5  # meridian
    n = WGS84_A / math.sqrt(w)  # prime vertical
    return 1.0 / (np.cos(azimuth) ** 2 / m + np.sin(azimuth) ** 2 / n)


def polar_to_local(
    range_m: np.ndarray | float,
    bearing_rad: np.ndarray | float,
    sensor: LocalFrame | Sequence[float],
    frame: LocalFrame | Sequence[float],
    *,
    sigma_range_m: np.ndarray | float,
    sigma_bearing_rad: np.ndarray | float,
    elevation_rad: np.ndarray | float | None = None,
    altitude_m: np.ndarray | float | None = None,
    sigma_elevation_rad: np.ndarray | float = 0.0,
    sigma_altitude_m: np.ndarray | float = 0.0,
    convention: str = "north-clockwise",
    debias: bool = False,
) -> PolarPositions:
    """Radar plots (slant range, bearing) of a sensor into a frame's east/north, with covariances.

    Args:
        range_m: (N,) slant range r [m] (≥ 0; NaN: missing).
        bearing_rad: (N,) bearing θ [rad] in ``convention`` (|θ| ≤ 2π; larger is a unit error).
        sensor: the sensor's position: a :class:`LocalFrame` or (lat_deg, lon_deg[, alt_m]).
        frame: the frame of the output (the sensor need not be at its origin).
        sigma_range_m, sigma_bearing_rad: σ_r [m], σ_θ [rad], scalars or per row (≥ 0).
        elevation_rad: (N,) measured elevation ε [rad] in [−π/2, π/2] (eq 7).
        altitude_m: (N,) target height above the WGS-84 ellipsoid [m], for ε from the geometry (eq 8).
        sigma_elevation_rad, sigma_altitude_m: σ of those (default 0).
        convention: one of :data:`CONVENTIONS` (eq 6).
        debias: Lerro & Bar-Shalom's debiased converted measurement (eq 12) instead of eq 9–10.

    Returns:
        :class:`PolarPositions`; its ``notes`` say when the range was taken as the ground range.

    Raises:
        ConfigError: naming the argument: a negative or infinite range, a bearing beyond ±2π, an
            elevation beyond ±π/2, both elevation and altitude, a negative σ, a σ of an elevation or
            altitude not given, shapes that do not match,
            or a range too short for the height difference (no elevation solves eq 8).

    Examples:
        >>> from motionsig_cli.surveillance.local_positions import LocalFrame, polar_to_local
        >>> site = LocalFrame(48.35, 11.78, 450.0)
        >>> out = polar_to_local([10e3], [0.5 * np.pi], site, site, sigma_range_m=50.0, sigma_bearing_rad=1e-3)
        >>> [round(float(v), 3) for v in out.position[0]], out.range_kind  # due east, range as ground range
        ([10000.0, 0.0], 'ground')
    """
    one_of("convention", convention, CONVENTIONS)
    sensor_f = _as_frame("sensor", sensor)
    frame_f = _as_frame("frame", frame)
    if elevation_rad is not None and altitude_m is not None:
        raise ConfigError("altitude_m", "given", "with elevation_rad: give one")
    r = _array("range_m", range_m)
    th = _array("bearing_rad", bearing_rad)
    with np.errstate(invalid="ignore"):
        if np.any(r < 0):
            raise ConfigError("range_m", _first(r, r < 0), "is not >= 0")
        if np.any(np.abs(th) > 2.0 * np.pi):
            raise ConfigError("bearing_rad", _first(th, np.abs(th) > 2 * np.pi), "is beyond ±2π (degrees?)")
    sr, sth = _sigma("sigma_range_m", sigma_range_m), _sigma("sigma_bearing_rad", sigma_bearing_rad)
    extra = [np.zeros(())] * 2
    if elevation_rad is not None:
        eps_in = _array("elevation_rad", elevation_rad)
        with np.errstate(invalid="ignore"):
            if np.any(np.abs(eps_in) > np.pi / 2):
                raise ConfigError(
                    "elevation_rad", _first(eps_in, np.abs(eps_in) > np.pi / 2), "is beyond ±π/2"
                )
        extra = [eps_in, _sigma("sigma_elevation_rad", sigma_elevation_rad)]
    elif altitude_m is not None:
        extra = [_array("altitude_m", altitude_m), _sigma("sigma_altitude_m", sigma_altitude_m)]
    for field, value, source in (
        ("sigma_elevation_rad", sigma_elevation_rad, elevation_rad),
        ("sigma_altitude_m", sigma_altitude_m, altitude_m),
    ):
        if source is None and np.any(np.asarray(value, dtype=float) != 0):
            raise ConfigError(field, "given", f"without {field.removeprefix('sigma_')}: it would be ignored")
    named = {"range_m": np.atleast_1d(r), "bearing_rad": th, "sigma_range_m": sr, "sigma_bearing_rad": sth}
    named.update(zip(("elevation_rad", "sigma_elevation_rad") if elevation_rad is not None else
                     ("altitude_m", "sigma_altitude_m"), extra, strict=True))  # fmt: skip
    for field, value in named.items():
        try:
            np.broadcast_shapes(named["range_m"].shape, np.shape(value))
        except ValueError:
            raise ConfigError(
                field, np.shape(value), f"does not match the ranges' shape {named['range_m'].shape}"
            ) from None
    r, th, sr, sth, x_in, sx = (
        a.reshape(-1) for a in np.broadcast_arrays(np.atleast_1d(r), th, sr, sth, *extra)
    )
    north_cw = convention == "north-clockwise"
    azimuth = th if north_cw else np.pi / 2 - th  # from north, clockwise
    notes: list[str] = []
    B = _euler_radius(sensor_f.lat_deg, azimuth) + sensor_f.alt_m
    zeros = np.zeros_like(r)
    if elevation_rad is not None:
        kind = "slant-elevation"
        eps = x_in
        rho, u_s = r * np.cos(eps), r * np.sin(eps)
        d_rho = np.stack([np.cos(eps), -r * np.sin(eps)], axis=-1)  # ∂ρ/∂(r, ε), eq 10
        d_u = np.stack([np.sin(eps), r * np.cos(eps)], axis=-1)
    elif altitude_m is not None:
        kind = "slant-altitude"
        Rt = B - sensor_f.alt_m + x_in
        with np.errstate(invalid="ignore", divide="ignore"):
            sin_eps = (Rt * Rt - B * B - r * r) / (2.0 * r * B)  # eq 8
            bad = np.abs(sin_eps) > 1.0
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ConfigError(
                "altitude_m",
                float(x_in[i]),
                f"is not reachable at range {r[i]:g} m from the sensor at {sensor_f.alt_m:g} m (row {i})",
            )
        eps = np.arcsin(np.where(r > 0, sin_eps, 0.0))
        eps = _refine_elevation(eps, r, azimuth, x_in, B, Rt, sensor_f)
        rho, u_s = r * np.cos(eps), r * np.sin(eps)
        with np.errstate(invalid="ignore", divide="ignore"):
            d_rho = np.stack([1.0 / np.cos(eps) + r * np.tan(eps) / B, -np.tan(eps) * Rt / B], axis=-1)
        d_u = np.stack([-r / B, Rt / B], axis=-1)
    else:
        kind = "ground"
        eps, rho, u_s = zeros, r.copy(), zeros
        d_rho = np.stack([np.ones_like(r), zeros], axis=-1)
        d_u = np.stack([zeros, zeros], axis=-1)
        sx = zeros
        notes.append(
            "range taken as the ground range in the sensor's tangent plane (no elevation or target altitude "
            "given): assumed"
        )
    sa, ca = np.sin(azimuth), np.cos(azimuth)
    enu_s = np.stack([rho * sa, rho * ca, u_s], axis=-1)  # eq 6–7 (azimuth from north)
    xyz = enu_to_ecef(enu_s, sensor_f.lat_deg, sensor_f.lon_deg, sensor_f.alt_m)
    enu_f = ecef_to_enu(xyz, frame_f.lat_deg, frame_f.lon_deg, frame_f.alt_m)
    T = frame_f.rotation @ sensor_f.rotation.T  # sensor ENU → frame ENU
    sign = 1.0 if north_cw else -1.0  # ∂azimuth/∂θ
    with np.errstate(invalid="ignore", divide="ignore"):
        sigma_rho = np.sqrt((d_rho[:, 0] * sr) ** 2 + (d_rho[:, 1] * sx) ** 2)
        linearity = np.where(sigma_rho > 0, rho * sth**2 / sigma_rho, np.where(sth > 0, np.inf, 0.0))
    if debias:
        phi = np.pi / 2 - azimuth  # math angle in the sensor's plane
        pos_s, cov_h = debiased_polar(rho, phi, sigma_rho, sth)
        shift = np.concatenate([pos_s - enu_s[:, :2], np.zeros((r.size, 1))], axis=-1)
        enu_f = enu_f + shift @ T.T
        cov_s = np.zeros((r.size, 3, 3))
        cov_s[:, :2, :2] = cov_h
        cov_s[:, 2, 2] = (d_u[:, 0] * sr) ** 2 + (d_u[:, 1] * sx) ** 2
        cov_s[:, :2, 2] = cov_s[:, 2, :2] = (
            np.stack([sa, ca], axis=-1)
            * ((d_rho[:, 0] * d_u[:, 0] * sr**2 + d_rho[:, 1] * d_u[:, 1] * sx**2)[:, None])
        )
        Tf = T[:2, :]
        cov = Tf @ cov_s @ Tf.T
    else:
        # J_s: ∂(e_s, n_s, u_s)/∂(r, θ, ε or h_t), eq 9–10
        J = np.zeros((r.size, 3, 3))
        J[:, 0, 0], J[:, 1, 0], J[:, 2, 0] = sa * d_rho[:, 0], ca * d_rho[:, 0], d_u[:, 0]
        J[:, 0, 1], J[:, 1, 1] = sign * rho * ca, -sign * rho * sa
        J[:, 0, 2], J[:, 1, 2], J[:, 2, 2] = sa * d_rho[:, 1], ca * d_rho[:, 1], d_u[:, 1]
        Jf = T[:2, :] @ J
        S = np.stack([sr**2, sth**2, sx**2], axis=-1)
        cov = np.einsum("nij,nj,nkj->nik", Jf, S, Jf)
    cov = 0.5 * (cov + np.swapaxes(cov, -1, -2))
    return PolarPositions(
        position=enu_f[:, :2],
        covariance=cov,
        up=enu_f[:, 2],
        ground_range_m=rho,
        elevation_rad=wrap_angle(eps),
        linearity=linearity,
        range_kind=kind,
        convention=convention,
        debiased=bool(debias),
        notes=tuple(notes),
    )


def _refine_elevation(
    eps: np.ndarray,
    r: np.ndarray,
    azimuth: np.ndarray,
    h_t: np.ndarray,
    B: np.ndarray,
    Rt: np.ndarray,
    sensor: LocalFrame,
) -> np.ndarray:
    """Newton steps on f(ε) = h(ε) − h_t on the ellipsoid, from eq 8's spherical ε (module docstring)."""
    sa, ca = np.sin(azimuth), np.cos(azimuth)
    for _ in range(_NEWTON_MAX):
        rho, u = r * np.cos(eps), r * np.sin(eps)
        xyz = enu_to_ecef(
            np.stack([rho * sa, rho * ca, u], axis=-1), sensor.lat_deg, sensor.lon_deg, sensor.alt_m
        )
        _, _, h = ecef_to_geodetic(xyz, strict=False)
        f = h - h_t
        if not np.any(np.abs(f) > _NEWTON_TOL_M):
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            step = f * Rt / (r * B * np.cos(eps))
        eps = np.clip(eps - np.where(np.isfinite(step), step, 0.0), -np.pi / 2, np.pi / 2)
    return eps
