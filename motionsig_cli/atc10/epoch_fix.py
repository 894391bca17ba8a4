"""One multilateration epoch from Python: a transmitter's position and emission time from the times of
arrival of its pulse at several receivers — the snapshot fix of ``motionsig track-sat solve``
(:mod:`motionsig_cli.atc10.toa_solve`), ATC-10 §4.2 (eqs 4.2.1–4.2.3, 4.5.1–4.5.4).

The times of arrival T_i become pseudoranges ρ_i = c (T_i − t_ref) (eq 4.2.1 with the epoch's nominal time
t_ref) and :func:`~motionsig_cli.surveillance.toa_fix.solve_snapshot` solves ρ_i = ‖p − S_i‖ + b by weighted
least squares (from the closed-form solution, Gauss–Newton on a thin QR, with the mirror-image start for a
ground network): the same
solver, the same numbers as the command.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motionsig_cli.config import ConfigError, positive
from motionsig_cli.geodesy import ecef_to_geodetic, geodetic_to_ecef
from motionsig_cli.surveillance.toa_fix import C_M_PER_S, SingularGeometry, solve_snapshot

__all__ = ["EpochFix", "solve_epoch"]


@dataclass(frozen=True)
class EpochFix:
    """The fix of one epoch.

    Attributes:
        position: (3,) ECEF position of the transmitter [m].
        lat_deg, lon_deg, alt_m: the same as WGS-84 latitude, longitude [deg] and height [m].
        emission_time: the estimated emission time τ [s] (on the receivers' time scale).
        covariance: (4, 4) covariance of (x, y, z, c τ) [m²] (eq 4.5.3 with the weights 1/σ_i²).
        sd_enu: (3,) standard deviations east, north, up [m].
        gdop, pdop, hdop, vdop, tdop: dilutions of precision (unweighted geometry).
        residuals: (K,) ρ_i − ‖p̂ − S_i‖ − b̂ [m] (NaN for a receiver without a time).
        chi2: Σ (residual_i / σ_i)².
        n_used: receivers used.
        converged: the Gauss–Newton iteration converged.

    Examples:
        Four receivers about 20 km apart (east, north, up [m] about 45° N, 0° E), the transmitter 5 km up:

        >>> import numpy as np
        >>> from motionsig_cli import solve_epoch
        >>> from motionsig_cli.geodesy import enu_to_ecef
        >>> enu = [[-1e4, -8e3, 0], [1.2e4, -1e4, 50], [9e3, 1.1e4, -30], [-7e3, 9e3, 100]]
        >>> S = enu_to_ecef(np.array(enu, float), 45.0, 0.0, 0.0)
        >>> p = enu_to_ecef(np.array([1000.0, 2000.0, 5000.0]), 45.0, 0.0, 0.0)
        >>> fix = solve_epoch(S, np.linalg.norm(S - p, axis=1) / 299_792_458.0)
        >>> fix.n_used, fix.sd_enu.shape, bool(np.linalg.norm(fix.position - p) < 1e-3)
        (4, (3,), True)
    """

    position: np.ndarray
    lat_deg: float
    lon_deg: float
    alt_m: float
    emission_time: float
    covariance: np.ndarray
    sd_enu: np.ndarray
    gdop: float
    pdop: float
    hdop: float
    vdop: float
    tdop: float
    residuals: np.ndarray
    chi2: float
    n_used: int
    converged: bool


def solve_epoch(
    receivers: np.ndarray,
    toa: np.ndarray,
    *,
    sigma: float | np.ndarray = 1e-8,
    start: tuple[float, float, float] | None = None,
    max_iter: int = 20,
) -> EpochFix:
    """The transmitter's position and emission time from times of arrival at K ≥ 4 receivers.

    Args:
        receivers: (K, 3) ECEF receiver positions [m] (:func:`motionsig_cli.geodesy.geodetic_to_ecef`
            converts latitude, longitude, height).
        toa: (K,) times of arrival [s] (NaN: no time at that receiver).
        sigma: the times' standard deviation [s]: one number, or (K,) one per receiver (default 10 ns).
        start: (latitude [deg], longitude [deg], height [m]) to start from; None: the closed-form solution
            (Bancroft's; for a ground network the planar one above the receivers).
        max_iter: most Gauss–Newton steps.

    Raises:
        ConfigError: a bad argument, naming it (``receivers``, ``toa``, ``sigma``, …; a geometry that
            cannot fix position and clock, such as fewer than 4 receivers, on ``receivers``).

    Examples:
        Five receivers around Boston and a transmitter 3 km up, exact times of arrival:

        >>> import numpy as np
        >>> from motionsig_cli import solve_epoch
        >>> from motionsig_cli.geodesy import geodetic_to_ecef
        >>> S = geodetic_to_ecef([42.0, 42.2, 42.1, 41.9, 42.3], [-71.0, -71.1, -70.8, -71.2, -70.9], 0.0)
        >>> p = geodetic_to_ecef(42.1, -71.0, 3000.0)
        >>> toa = 1.0 + np.linalg.norm(S - p, axis=1) / 299_792_458.0  # emitted at t = 1 s
        >>> fix = solve_epoch(S, toa)
        >>> round(fix.alt_m, 3), round(fix.emission_time, 12), fix.converged
        (3000.0, 1.0, True)
    """
    S = np.asarray(receivers, float)
    T = np.asarray(toa, float)
    if S.ndim != 2 or S.shape[1] != 3:
        raise ConfigError("receivers", f"shape {S.shape}", "is not (K, 3) ECEF positions [m]")
    if T.shape != (S.shape[0],):
        raise ConfigError("toa", f"shape {T.shape}", f"is not ({S.shape[0]},): one time per receiver [s]")
    if np.any(np.isinf(T)):
        raise ConfigError("toa", "inf", "must be finite [s] (NaN: no time at that receiver)")
    sig = np.asarray(sigma, float)
    if sig.shape not in ((), T.shape):
        raise ConfigError("sigma", f"shape {sig.shape}", f"is not a number or ({T.size},) [s]")
    for v in np.atleast_1d(sig):
        positive("sigma", float(v), unit="s")
    if not np.isfinite(T).any():
        raise ConfigError("toa", "all NaN", "has no time of arrival")
    t_ref = float(np.nanmin(T))  # the epoch's nominal time: ρ stays small, b = c (τ − t_ref)
    rho = C_M_PER_S * (T - t_ref)
    p0 = None if start is None else geodetic_to_ecef(*start)
    try:
        fix = solve_snapshot(rho[None], S, sigma=(C_M_PER_S * np.broadcast_to(sig, T.shape))[None], p0=p0,
                             max_iter=max_iter)  # fmt: skip
    except SingularGeometry as exc:
        raise ConfigError(
            "receivers", f"{S.shape[0]} receivers", f"cannot fix position and clock: {exc.reason}"
        ) from None
    lat, lon, alt = ecef_to_geodetic(fix.position, strict=False)
    return EpochFix(
        position=fix.position[0], lat_deg=float(lat[0]), lon_deg=float(lon[0]), alt_m=float(alt[0]),
        emission_time=t_ref + float(fix.clock_offset_s[0]), covariance=fix.covariance[0],
        sd_enu=fix.sd_enu()[0], gdop=float(fix.gdop[0]), pdop=float(fix.pdop[0]), hdop=float(fix.hdop[0]),
        vdop=float(fix.vdop[0]), tdop=float(fix.tdop[0]), residuals=fix.residuals[0], chi2=float(fix.chi2[0]),
        n_used=int(fix.n_used[0]), converged=bool(fix.converged[0]),
    )  # fmt: skip
