"""Tracking one track (or a batch of tracks) given as arrays with the manoeuvre trackers of Yao, Teng & Wu,
*Maneuvering Target Tracking Based on EBPSK Modulated JRC System*: the IMM of three Kalman filters (eqs
(7)–(13)), the GLR and MLR input-estimation trackers (eqs (1)–(6)) and the constant-velocity Kalman filter.

This is the Python entry point of what ``motionsig maneuver FILE`` does to a file
(:mod:`motionsig_cli.maneuver.record`): times that lie on a uniform scan grid are placed on it (a gap is a
run of missed scans, a NaN position a missed scan: predict-only steps) and tracked with the fixed-period
models of :func:`motionsig_cli.maneuver.study.track_from` — the same code, so the numbers are those of the
command; times that do not (real sensors' irregular reports) are steps at their own times, each with its
own Δt (:func:`~motionsig_cli.filters.imm.imm_filter` and :func:`~motionsig_cli.detection.glr.input_tracker`
with ``dt``). The trackers are initialised by two-point differencing on the first two measured rows and
run from the row after.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motionsig_cli.config import ConfigError, in_range, one_of
from motionsig_cli.detection.glr import InputModel, input_tracker
from motionsig_cli.errors import InputError
from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.maneuver.record import JITTER_TOL
from motionsig_cli.maneuver.scenario import T_RANGE
from motionsig_cli.maneuver.study import METHODS, SIGMA_RANGE, TrackerConfig, Tracks, _numerics, track_from
from motionsig_cli.models.motion import H_POS4, H_POS6, cv_input_model, cv_input_steps, two_point_restart
from motionsig_cli.records import grid_period

__all__ = ["TrackResult", "track_positions"]


@dataclass(frozen=True)
class TrackResult:
    """One tracker's output on a track (or a batch of B tracks), one row per grid scan from the scan after
    the initialisation on.

    Leading batch axis: absent for a single (N, 2) track, B for a (B, N, 2) batch.

    Attributes:
        method: the tracker: ``imm``, ``glr``, ``mlr`` or ``cv``.
        T: the scan period [s].
        t: (K,) the grid time of each output row [s] (the first input time plus a whole number of T).
        row: (K,) the input row of each output scan, −1 at a scan absent from the input (a gap).
        measured: ([B,] K) whether the scan had a measurement (else it was a predict-only step).
        state: ([B,] K, 6) estimates [x [m], ẋ [m/s], y [m], ẏ [m/s], a_x [m/s²], a_y [m/s²]]; the
            acceleration is the IMM's combined estimate (eq 12) or the GLR/MLR current input estimate (0 for
            ``cv``).
        mu: ([B,] K, 3) IMM model probabilities μ_j(k) (CV, CA, CA; §IV), else None.
        detected: ([B,] K) a manoeuvre declared at the scan (GLR/MLR, §III step 3), else None.
        onset: ([B,] K) the estimated onset n̂ (eq 3) of a declaration as an output row index (−1: none or
            before the first output row), else None.
        u_jump: ([B,] K, 2) the estimated input jump û at a declaration [m/s²] (0 elsewhere), else None.
        stat: ([B,] K) the detection statistic max_n ΔJ(n) (GLR, eq 5 corrected) or max_n J(n) (MLR, eq 6),
            −inf before any onset can be tested, else None.

    Examples:
        >>> import numpy as np
        >>> from motionsig_cli import track_positions
        >>> t = np.arange(10.0)
        >>> res = track_positions(t, np.stack([5.0 * t, -2.0 * t], axis=1), 1.0, method="glr")
        >>> res.method, res.state.shape, res.detected.shape, res.mu is None
        ('glr', (8, 6), (8,), True)
    """

    method: str
    T: float
    t: np.ndarray
    row: np.ndarray
    measured: np.ndarray
    state: np.ndarray
    mu: np.ndarray | None = None
    detected: np.ndarray | None = None
    onset: np.ndarray | None = None
    u_jump: np.ndarray | None = None
    stat: np.ndarray | None = None

    @property
    def position(self) -> np.ndarray:
        """([B,] K, 2) estimated positions (x, y) [m]."""
        return self.state[..., [0, 2]]

    @property
    def velocity(self) -> np.ndarray:
        """([B,] K, 2) estimated velocities (ẋ, ẏ) [m/s]."""
        return self.state[..., [1, 3]]


def _grid(times: np.ndarray, T: float | None) -> tuple[np.ndarray, float | None]:
    """Grid steps k (from 0) of increasing ``times`` and the period (given, or :func:`grid_period`); without a
    given T, times off every grid are irregular: (0..N−1, None)."""
    if times.ndim != 1 or times.size < 3:
        raise ConfigError("times", f"shape {times.shape}", "is not at least 3 times (N,) [s]")
    if not np.all(np.isfinite(times)):
        raise ConfigError("times", "non-finite", "must be finite [s]")
    d = np.diff(times)
    if np.any(d <= 0):
        i = int(np.flatnonzero(d <= 0)[0]) + 1
        raise ConfigError(
            "times", float(times[i]), f"(row {i}) is not after the row before: times must increase"
        )
    given = T is not None
    if T is None:
        try:
            T = grid_period(times, JITTER_TOL)
        except InputError:
            return np.arange(times.size, dtype=np.int64), None
    in_range("T", T, *T_RANGE, unit="s")
    dt = times - times[0]
    k = np.rint(dt / T)
    off = np.abs(dt - k * T)
    bad = np.flatnonzero(off > JITTER_TOL * T)
    if bad.size and not given:
        return np.arange(times.size, dtype=np.int64), None
    if bad.size:
        i = int(bad[0])
        raise ConfigError(
            "times", float(times[i]), f"(row {i}) is {off[i] / T:.3g} periods off the {T:.6g} s scan grid "
            f"(tolerance {JITTER_TOL:g}): the trackers need uniform scans (gaps allowed)",
        )  # fmt: skip
    same = np.flatnonzero(np.diff(k) == 0)
    if same.size and not given:
        return np.arange(times.size, dtype=np.int64), None
    if same.size:
        i = int(same[0]) + 1
        raise ConfigError(
            "times", float(times[i]), f"(row {i}) falls on the same {T:.6g} s scan as the row before"
        )
    return k.astype(np.int64), float(T)


def _covariances(
    sigma: float | np.ndarray | None, cov: np.ndarray | None, B: int, N: int
) -> tuple[float, np.ndarray | None]:
    """(σ for the initialisation and the error messages, R (B, N, 2, 2) or None for σ² I)."""
    if cov is not None:
        if sigma is not None:
            raise ConfigError("sigma", sigma, "must be None when cov is given (one noise model)")
        R = np.asarray(cov, float)
        if R.shape == (N, 2, 2):
            R = np.broadcast_to(R, (B, N, 2, 2))
        if R.shape != (B, N, 2, 2):
            raise ConfigError("cov", f"shape {np.shape(cov)}", f"is not ({N}, 2, 2) or ({B}, {N}, 2, 2)")
        ok = np.isfinite(R).all(axis=(-1, -2))
        diag = np.sqrt(np.diagonal(R, axis1=-2, axis2=-1)[ok]) if ok.any() else np.ones(1)
        return float(np.median(diag)), R
    if sigma is None:
        raise ConfigError("sigma", None, "is required: σ per axis [m] (a number or one per row), or give cov")
    s = np.asarray(sigma, float)
    if s.ndim == 0:
        return in_range("sigma", float(s), *SIGMA_RANGE, unit="m"), None
    if s.shape != (N,):
        raise ConfigError("sigma", f"shape {s.shape}", f"is not a number or one σ per row ({N},) [m]")
    for v in s[np.isfinite(s)]:
        in_range("sigma", float(v), *SIGMA_RANGE, unit="m")
    R = (s**2)[:, None, None] * np.eye(2)  # R_k = σ_k² I (NaN at a row with no σ: it must be missed)
    return float(np.nanmedian(s)), np.broadcast_to(R, (B, N, 2, 2))


def track_positions(
    times: np.ndarray,
    positions: np.ndarray,
    sigma: float | np.ndarray | None = None,
    *,
    cov: np.ndarray | None = None,
    method: str = "imm",
    config: TrackerConfig | None = None,
    T: float | None = None,
) -> TrackResult:
    """Track positions measured at ``times`` with one of the manoeuvre trackers (module docstring).

    The times are placed on a uniform scan grid (period ``T``, else estimated from the times as the
    command does; jitter up to :data:`~motionsig_cli.maneuver.record.JITTER_TOL` of T). The trackers
    start by two-point differencing (§IV) on the first two measured scans a < b (velocity
    (z_b − z_a)/((b − a) T)) and run from scan b + 1; a NaN row, or a scan absent from ``times``, is a
    missed scan (predict-only).

    Args:
        times: (N,) increasing measurement times [s].
        positions: (N, 2) measured positions (x, y) [m] of one track, or (B, N, 2) of B tracks at the same times
            (their first two measured rows must be the same rows).
        sigma: measurement noise σ per axis [m]: one number (R = σ² I, eq 8), or (N,) one per row
            (R_k = σ_k² I). Give either ``sigma`` or ``cov``.
        cov: (N, 2, 2) or (B, N, 2, 2) measurement covariances R_k [m²] per row (time-varying R in eqs (8),
            (11) and in the GLR/MLR statistics), in place of ``sigma``.
        method: ``imm``, ``glr``, ``mlr`` or ``cv``.
        config: the trackers' settings (the paper's by default).
        T: the scan period [s]; None: estimated from the times.

    Returns:
        The estimates of every scan from b + 1 on; with one (N, 2) track, arrays without the batch axis.

    Raises:
        ConfigError: a bad argument, naming it (``times``, ``positions``, ``sigma``, ``cov``, ``method``,
            ``T``).

    Examples:
        A target moving at 10 m/s east, measured every second without noise (σ = 1 m assumed):

        >>> import numpy as np
        >>> from motionsig_cli import track_positions
        >>> t = np.arange(20.0)
        >>> z = np.stack([10.0 * t, np.zeros_like(t)], axis=1)
        >>> res = track_positions(t, z, 1.0, method="cv")
        >>> res.state.shape, float(res.t[0])
        ((18, 6), 2.0)
        >>> bool(np.allclose(res.velocity, [10.0, 0.0]))
        True
    """
    one_of("method", method, METHODS)
    cfg = config if config is not None else TrackerConfig()
    if not isinstance(cfg, TrackerConfig):
        raise ConfigError("config", type(cfg).__name__, "is not a TrackerConfig")
    times = np.asarray(times, float)
    z = np.asarray(positions, float)
    single = z.ndim == 2
    if single:
        z = z[None]
    if z.ndim != 3 or z.shape[-1] != 2 or z.shape[1] != times.shape[0]:
        raise ConfigError(
            "positions",
            f"shape {np.shape(positions)}",
            f"is not (N, 2) or (B, N, 2) with N = {times.shape[0]} times",
        )
    if np.any(np.isinf(z)):
        raise ConfigError("positions", "inf", "must be finite [m] (NaN: a missed scan)")
    k, T_grid = _grid(times, T)
    irregular = T_grid is None
    T_used = float(np.median(np.diff(times))) if T_grid is None else T_grid
    B, N = z.shape[:2]
    s, R_rows = _covariances(sigma, cov, B, N)
    K = int(k[-1]) + 1
    zg = np.full((B, K, 2), np.nan)
    zg[:, k] = z
    zg[np.isnan(zg).any(axis=-1)] = np.nan  # one coordinate missing: the scan is missed
    row = np.full(K, -1, dtype=np.int64)
    row[k] = np.arange(N)
    measured = ~np.isnan(zg).any(axis=-1)
    Rg = None
    if R_rows is not None:
        Rg = np.full((B, K, 2, 2), np.nan)
        Rg[:, k] = R_rows
        bad = measured & ~np.isfinite(Rg).all(axis=(-1, -2))
        if bad.any():
            b_, i_ = (int(v[0]) for v in np.nonzero(bad))
            raise ConfigError(
                "sigma" if cov is None else "cov", "nan", f"at row {row[i_]} (track {b_}), a measured row"
            )
    first = [np.flatnonzero(m)[:2] for m in measured]
    if any(f.size < 2 for f in first):
        raise ConfigError("positions", "too few", "need at least 2 measured rows per track to initialise")
    a, b = (int(v) for v in first[0])
    if any((int(f[0]), int(f[1])) != (a, b) for f in first):
        raise ConfigError(
            "positions", "batch", "the tracks' first two measured rows differ: track them one at a time"
        )
    if b + 1 >= K:
        raise ConfigError("positions", "too few", "no scan after the two that initialise the trackers")
    extra = {} if Rg is None else {"R": Rg[:, b + 1 :], "init_R": (Rg[:, a], Rg[:, b])}
    with _numerics(s, T_used), np.errstate(all="ignore"):
        if irregular:
            tr = _irregular(method, zg, Rg, s, times, a, b, cfg)
        else:
            tr = track_from(method, zg[:, a], zg[:, b], zg[:, b + 1 :], T_used, s, cfg, init_gap=b - a,
                            first_scan=0, **extra)  # fmt: skip
    pick = (lambda a_: None if a_ is None else a_[0]) if single else (lambda a_: a_)
    grid_t = times if irregular else times[0] + np.arange(K) * T_used
    return TrackResult(
        method=method,
        T=T_used,  # the period, or the median step of irregular times
        t=grid_t[b + 1 :],
        row=row[b + 1 :],
        measured=pick(measured[:, b + 1 :]),
        state=pick(tr.state),
        mu=pick(tr.mu),
        detected=pick(tr.detected),
        onset=pick(tr.onset),  # first_scan=0: numbered from output row 0
        u_jump=pick(tr.u_jump),
        stat=pick(tr.stat),
    )


def _irregular(
    method: str, z: np.ndarray, R: np.ndarray | None, sigma: float, times: np.ndarray, a: int, b: int,
    cfg: TrackerConfig,
) -> Tracks:  # fmt: skip
    """The trackers on irregular times: two-point start on rows a < b, then every row after b with its own
    Δt (the per-step models of the IMM and input model, eqs M1–M3 of :mod:`motionsig_cli.models.motion`)."""
    B = z.shape[0]
    Rr = np.broadcast_to(sigma * sigma * np.eye(2), (B, z.shape[1], 2, 2)) if R is None else R
    dt = np.broadcast_to(np.diff(times)[b:], (B, z.shape[1] - b - 1))
    dt0 = np.full(B, times[b] - times[a])
    zs = z[:, b + 1 :]
    Rs = None if R is None else R[:, b + 1 :]
    if method == "imm":
        x0, P0 = two_point_restart(z[:, a], z[:, b], dt0, Rr[:, a], Rr[:, b], n=6)
        imm = imm_filter(zs, H_POS6, Rs if Rs is not None else sigma * sigma, cfg.models(float(np.median(dt))), x0,
                         P0, dt=dt)  # fmt: skip
        return Tracks(imm.x, mu=imm.mu)
    F, G, Q = cv_input_model(1.0, cfg.q0)
    q0 = cfg.q0
    model = InputModel(F, G, Q, H_POS4, sigma * sigma * np.eye(2), steps=lambda d: cv_input_steps(d, q0))
    x0, P0 = two_point_restart(z[:, a], z[:, b], dt0, Rr[:, a], Rr[:, b], n=4)
    it = input_tracker(zs, model, x0, P0, cfg.glr("none" if method == "cv" else method), R=Rs, dt=dt)
    state = np.concatenate([it.x, it.u_cur], axis=-1)
    if method == "cv":
        return Tracks(state)
    return Tracks(state, detected=it.detected, onset=it.onset, u_jump=it.u_jump, stat=it.stat)
