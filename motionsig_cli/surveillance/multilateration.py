"""Satellite multilateration geometry (ATC-10, Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972:
§4.1–4.2, §4.5).

An aircraft pulse sent at τ_n reaches satellite i at T_ni = τ_n + ‖p_n − S_i‖/c + ε_ni (eq 4.2.1).
Linearised about p* (eq 4.2.3), T̂_n − k_n = τ_n·1 + F_n (p_n − p*) + ε_n with F = U/c, where the rows
of U are the unit vectors u_i from satellite i to p*.

Everything here works in "c = 1" units — times in ns, distances in light-nanoseconds — so that
F = U and the clock column 1 of [1 ⋮ U] have the same scale. Feet or metres appear only when
a result is printed, through a speed of light: exact (0.299792458 m/ns = 0.98357 ft/ns) or the
report's 1 ft/ns.

The geometry numbers of Table 4.2 come from a thin QR factorisation U = QR (never from normal
equations, which lose digits when β ≈ 3.5·10⁻³):

- β = 1'(I − P)1 = ‖(I − QQ')1‖², P = U(U'U)⁻¹U' (eq 4.5.2 / 4.5.20);
- tr = tr{(U'U)⁻¹} = ‖R⁻¹‖_F² (eq 4.5.7);
- b = 1'U(U'U)⁻²U'1 = ‖R⁻¹Q'1‖² (eq 4.5.7; for K = 3 it equals the corrected 1'(UU')⁻¹1 of eq 4.5.30);
- b_literal = 1'(U'U)⁻¹1 = ‖R⁻ᵀ1‖², the frame-dependent quantity the report's Table 4.2 prints for
  the three-satellite column (see the errata page);
- GDOP k = √(tr + b/β) (eq 4.1.2).

Every function broadcasts over leading axes (Monte Carlo runs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

R_EARTH_KM = 6378.137
"""Spherical-Earth radius [km] (WGS-84 equatorial; the report states no Earth model)."""
RSAT_REPORT_RE = 9.235
"""Orbit radius in Earth radii that reproduces Table 4.2 (our fit to the printed constants; the report says
"synchronous")."""
RSAT_GEO_KM = 42164.17
"""Geosynchronous orbit radius [km]."""
C_M_PER_NS = 0.299792458
"""Speed of light [m/ns], exact."""
FOOT_M = 0.3048
C_FT_PER_NS_EXACT = C_M_PER_NS / FOOT_M
"""Speed of light [ft/ns], exact (0.983571…)."""
C_FT_PER_NS_REPORT = 1.0
"""The report's implied speed of light [ft/ns] (our finding: Tables 4.2/4.3 are reproduced only with it)."""

COND_LIMIT = 1e8
"""cond(U) above this: the directions are (numerically) coplanar and the position is not observable."""
BETA_REL_TOL = 1e-10
"""β below ``BETA_REL_TOL · K``: the ones vector lies in the span of the directions (GDOP infinite)."""


class GeometryError(ValueError):
    """A constellation that cannot fix a position (fewer than three satellites, coplanar directions,
    ones vector in the span of the directions)."""


def ecef(lat_deg: np.ndarray | float, lon_deg: np.ndarray | float, radius: np.ndarray | float) -> np.ndarray:
    """Earth-centred Cartesian position on a sphere: (r cos φ cos λ, r cos φ sin λ, r sin φ)."""
    lat = np.radians(np.asarray(lat_deg, dtype=float))
    lon = np.radians(np.asarray(lon_deg, dtype=float))
    r = np.asarray(radius, dtype=float)
    return np.stack(
        np.broadcast_arrays(r * np.cos(lat) * np.cos(lon), r * np.cos(lat) * np.sin(lon), r * np.sin(lat)),
        axis=-1,
    )


def enu_basis(lat_deg: float, lon_deg: float) -> np.ndarray:
    """Rows: local east, north and up unit vectors at (lat, lon) in the ECEF frame of :func:`ecef`."""
    lat, lon = math.radians(lat_deg), math.radians(lon_deg)
    east = [-math.sin(lon), math.cos(lon), 0.0]
    north = [-math.sin(lat) * math.cos(lon), -math.sin(lat) * math.sin(lon), math.cos(lat)]
    up = [math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat)]
    return np.array([east, north, up])


def directions(sats: np.ndarray, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors u_i from each satellite to ``point`` and the ranges ‖point − S_i‖ (eq 4.2.3).

    Args:
        sats: (..., K, 3) satellite positions.
        point: (..., 3) aircraft position or linearisation point p*.

    Returns:
        U (..., K, 3) and ranges (..., K), in the units of the inputs.
    """
    d = np.asarray(point)[..., None, :] - np.asarray(sats)
    rng = np.linalg.norm(d, axis=-1)
    return d / rng[..., None], rng


def zenith_deg(U: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Zenith angle of each satellite seen from the aircraft: arccos(−u_i · up) in degrees."""
    return np.degrees(np.arccos(np.clip(-(U @ up), -1.0, 1.0)))


@dataclass(frozen=True)
class GeometryMetrics:
    """Table 4.2's constellation constants in c = 1 units (broadcast over leading axes).

    Attributes:
        K: satellites in use.
        beta: 1'(I − P)1 (eq 4.5.2); zero for K = 3.
        tr: tr{(U'U)⁻¹}.
        b: 1'U(U'U)⁻²U'1 (for K = 3: the corrected 1'(UU')⁻¹1 of eq 4.5.30).
        b_literal: 1'(U'U)⁻¹1 — frame-dependent; what the report's Table 4.2 prints for three satellites.
        cond: condition number of U.
    """

    K: int
    beta: np.ndarray
    tr: np.ndarray
    b: np.ndarray
    b_literal: np.ndarray
    cond: np.ndarray

    @property
    def gdop(self) -> np.ndarray:
        """k = √(tr + b/β) (eq 4.1.2); infinite when β = 0 (K = 3)."""
        with np.errstate(divide="ignore"):
            return np.sqrt(
                self.tr + np.where(self.beta > 0, self.b / np.where(self.beta > 0, self.beta, 1.0), np.inf)
            )


def thin_qr(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Thin QR of a stack of tall matrices A (..., K, n) with few columns, by classical Gram–Schmidt with
    one re-orthogonalisation (CGS2: orthogonal to working precision for cond(A) ≪ 1/ε).

    Vectorised over the stack; for the n ≤ 4 columns used here it is an order of magnitude faster
    than LAPACK's batched ``numpy.linalg.qr``, whose per-matrix overhead dominates (measured in the
    tests against ``numpy.linalg.qr``). R has a positive diagonal.
    """
    A = np.asarray(A, dtype=float)
    n = A.shape[-1]
    Q = np.empty_like(A)
    R = np.zeros((*A.shape[:-2], n, n))
    for j in range(n):
        v = A[..., j].copy()
        for _ in range(2):  # CGS2
            if j:
                c = np.einsum("...ki,...k->...i", Q[..., :j], v)
                R[..., :j, j] += c
                v -= np.einsum("...ki,...i->...k", Q[..., :j], c)
        r = np.sqrt(np.einsum("...k,...k->...", v, v))
        R[..., j, j] = r
        Q[..., j] = v / np.where(r > 0, r, 1.0)[..., None]
    return Q, R


def solve_upper(R: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Back substitution R x = b for a stack of small upper-triangular R (..., n, n), b (..., n)."""
    n = R.shape[-1]
    x = np.empty(np.broadcast_shapes(R.shape[:-1], b.shape))
    for i in range(n - 1, -1, -1):
        s = b[..., i] - np.einsum("...j,...j->...", R[..., i, i + 1 :], x[..., i + 1 :])
        x[..., i] = s / R[..., i, i]
    return x


def qr_parts(U: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Thin QR of U (..., K, 3) and w = (I − QQ')1, the part of the ones vector outside span(U).

    β = w·w, and 1'(I − P)z = w·z for any z (the projection is symmetric and idempotent).
    """
    Q, R = thin_qr(U)
    ones = np.ones(U.shape[:-1])
    w = ones - np.einsum("...kj,...j->...k", Q, np.einsum("...kj,...k->...j", Q, ones))
    return Q, R, w


def metrics(U: np.ndarray) -> GeometryMetrics:
    """β, tr, b, b_literal and cond(U) for directions U (..., K, 3), by QR."""
    U = np.asarray(U, dtype=float)
    K = U.shape[-2]
    if K < 3:
        raise GeometryError(f"{K} satellite(s): at least three are needed to fix a position")
    Q, R, w = qr_parts(U)
    beta = np.einsum("...k,...k->...", w, w)
    if K == 3:
        beta = np.zeros_like(beta)  # exactly: U invertible ⇒ P = I (eq 4.5.2 with K = 3)
    singular = ~np.all(np.diagonal(R, axis1=-2, axis2=-1) > 0, axis=-1)  # rank(U) < 3: no position fix
    Rinv = np.linalg.inv(np.where(singular[..., None, None], np.eye(3), R))
    tr = np.where(singular, np.inf, np.einsum("...ij,...ij->...", Rinv, Rinv))
    q1 = np.einsum("...kj,...k->...j", Q, np.ones(U.shape[:-1]))
    v = np.einsum("...ij,...j->...i", Rinv, q1)  # R⁻¹Q'1 = (U'U)⁻¹U'1
    b = np.where(singular, np.inf, np.einsum("...i,...i->...", v, v))
    s = np.einsum("...ji,...j->...i", Rinv, np.ones((*U.shape[:-2], 3)))  # R⁻ᵀ1
    b_literal = np.where(singular, np.inf, np.einsum("...i,...i->...", s, s))
    sv = np.linalg.svd(U, compute_uv=False)
    cond = sv[..., 0] / np.where(sv[..., -1] > 0, sv[..., -1], np.nan)
    return GeometryMetrics(
        K=K, beta=beta, tr=tr, b=b, b_literal=b_literal, cond=np.nan_to_num(cond, nan=np.inf)
    )


def ls_position_covariance(U: np.ndarray, sigma: float) -> np.ndarray:
    """Position-error covariance of the snapshot least-squares fix (eq 4.5.6, c = 1 units):
    σ²(U'U)⁻¹ + (σ²/β)(U'U)⁻¹U'11'U(U'U)⁻¹ — the same matrix as (4.1.1). Its trace is σ²k²."""
    Q, R, w = qr_parts(np.asarray(U, dtype=float))
    beta = np.einsum("...k,...k->...", w, w)
    Rinv = np.linalg.inv(R)
    v = np.einsum("...ij,...kj,...k->...i", Rinv, Q, np.ones(w.shape))  # (U'U)⁻¹U'1
    base = np.einsum("...ij,...kj->...ik", Rinv, Rinv)  # (U'U)⁻¹ = R⁻¹R⁻ᵀ
    return sigma**2 * (base + np.einsum("...i,...j->...ij", v, v) / beta[..., None, None])


def check_geometry(U: np.ndarray, *, labels: str = "", need_clock: bool = True) -> GeometryMetrics:
    """:func:`metrics` plus the observability checks.

    Raises:
        GeometryError: fewer than three satellites; cond(U) > 10⁸ (coplanar or repeated directions:
            GDOP infinite, position not observable); with ``need_clock`` and K ≥ 4, β < 10⁻¹⁰·K (the
            ones vector lies in the span of the directions: the clock cannot be separated from the
            position, GDOP infinite); with ``need_clock`` and K = 3 (no clock information at all).
    """
    m = metrics(U)
    where = f" ({labels})" if labels else ""
    if np.any(~np.isfinite(m.cond) | (m.cond > COND_LIMIT)):
        raise GeometryError(
            f"GDOP is infinite{where}: the satellite directions are coplanar or repeated "
            f"(cond(U) = {float(np.max(m.cond)):.3g} > {COND_LIMIT:g}), so the position is not observable"
        )
    if need_clock and m.K == 3:
        raise GeometryError(
            f"GDOP is infinite{where}: with three satellites the send time cannot be estimated "
            "(β = 0, eq 4.5.2); at least four are needed without a clock prior"
        )
    if need_clock and np.any(m.beta < BETA_REL_TOL * m.K):
        raise GeometryError(
            f"GDOP is infinite{where}: the ones vector lies in the span of the satellite directions "
            f"(β = {float(np.min(m.beta)):.3g}), so clock and position cannot be separated "
            "(e.g. all satellites at the same zenith angle)"
        )
    return m


def ls_position_clock(
    T: np.ndarray,
    sats: np.ndarray,
    p0: np.ndarray,
    *,
    tol: float = 1e-3 / C_M_PER_NS,
    max_iter: int = 10,
) -> tuple[np.ndarray, np.ndarray, int]:
    """Gauss–Newton least squares for (τ, p) from one epoch's arrival times (eqs 4.5.1–4.5.4).

    Minimises ‖T − τ1 − ‖p − S_i‖‖² in c = 1 units by QR of [1 ⋮ U] at each step.

    Args:
        T: (..., K) arrival times [ns] (nominal epoch removed).
        sats: (K, 3) or (..., K, 3) satellite positions [light-ns].
        p0: (..., 3) starting point [light-ns].
        tol: stop when every run's position step is below this [light-ns] (default 1 mm).
        max_iter: at most this many steps.

    Returns:
        τ̂ (...,), p̂ (..., 3) and the number of steps taken.
    """
    p = np.array(p0, dtype=float, copy=True)
    tau = np.zeros(p.shape[:-1])
    active = np.ones(p.shape[:-1], dtype=bool)
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 — the count is returned
        U, rng = directions(sats, p)
        A = np.concatenate([np.ones((*U.shape[:-1], 1)), U], axis=-1)  # [1 ⋮ U] (4.5.1)
        r = T - rng - tau[..., None]
        Q, R = thin_qr(A)
        step = solve_upper(R, np.einsum("...kj,...k->...j", Q, r)) * active[..., None]
        tau = tau + step[..., 0]
        p = p + step[..., 1:]
        active &= np.max(np.abs(step[..., 1:]), axis=-1) >= tol  # a converged run is frozen: its result
        if not active.any():  # depends on its own data only, not on the batch it is in
            break
    return tau, p, it
