"""The 2-D closed-loop vehicle observed by a radar: the mode-signature paper (47th IEEE CDC, Cancún, 2008), §IV.B, eqs (59)–(62).

Truth (eq 59, per axis α ∈ {x, y}, the 1-D loop of eq 53 on each axis)::

    [α, α̇]_{k+1} = [[1, T], [0, 1]] [α, α̇]_k + [0, T]ᵀ u^α_k + [T²/2, T]ᵀ σ_a w^α_k
    u^α_k = K (−[α, α̇]_k + r^α_k + a_α [z_k, ż_k]ᵀ)                        same K on both axes [A]
    r^x_k = [x_0 + a_r sin(2π f_r t_k), 2π f_r a_r cos(2π f_r t_k)],  r^y likewise about y_0  [A]

Radar at the origin (eq 60, with atan2 in place of the printed tan⁻¹(y/x), which loses the quadrant)::

    y_k = [κ, χ]ᵀ + v_k,  κ = √(x² + y²),  χ = atan2(y, x) wrapped to (−π, π],  v ~ N(0, diag(R_κ, R_χ))

Filter models (eq 44 per axis; the layouts follow from the 8 and 10 entries of eqs 61/62)::

    H0 state [x, ẋ, y, ẏ, r_x, ṙ_x, r_y, ṙ_y];  H1 adds [a_x, a_y] (one amplitude per axis)
    a_x enters the ẋ row with T (k1 z_k + k2 ż_k), a_y the ẏ row likewise (the replica of the filter)
    Q^{H0} = diag(1e-1, 1e-3, 1e-1, 1e-3, 1e-1, 1e4, 1e-1, 1e4)                         eq (61)
    Q^{H1} = diag(1e-1, 1e2, 1e-1, 1e1, 1e-2, 1e2, 1e2, 1e3, 1e-1, 1e0)                 eq (62)

[A] = our assumption (the paper does not state it); the x/y asymmetry of eq (62) is as printed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from motionsig_cli.config import ConfigError, integer, one_of, positive
from motionsig_cli.models.radar import wrap_angle
from motionsig_cli.models.vehicle import ClosedLoop

Q0_2D = (1e-1, 1e-3, 1e-1, 1e-3, 1e-1, 1e4, 1e-1, 1e4)  # eq (61), per step
Q1_2D = (1e-1, 1e2, 1e-1, 1e1, 1e-2, 1e2, 1e2, 1e3, 1e-1, 1e0)  # eq (62); last entry "100" read as 10^0

# State indices (H0 layout; H1 appends a_x = 8, a_y = 9).
IX, IXD, IY, IYD, IRX, IRXD, IRY, IRYD, IAX, IAY = range(10)

# Fig 7 (angle, range) ANR pairs in the paper's 10·ln "dB" (its §IV.B text and the Fig 7 axis).
SEED_ANR_PAIRS: tuple[tuple[float, float], ...] = ((9.2, 37.1), (32.2, 60.2), (55.2, 83.2), (101.3, 129.2))
# Bearing variances behind the angle labels: round 5·10⁻ⁿ (10·ln(0.125/R_χ) = 9.16, 32.19, 55.21, 101.27).
SEED_R_BEARING: tuple[float, ...] = (5e-2, 5e-3, 5e-4, 5e-6)
SIG_AXES = ("both", "x", "y")


def anr_pair_variances(anr_pair: int, a_sig: float = 0.5) -> tuple[float, float]:
    """(R_κ, R_χ) of Fig 7's ANR pair 1–4 (derived from the printed labels).

    R_χ is the round 5·10⁻ⁿ that reproduces the angle label at the paper's a_sig = 0.5; R_κ has no
    visible rule, so it is inverted from the printed range label, R_κ = (a²/2) e^{−label/10} (±0.5 % from
    the label's rounding). Both scale with a_sig², so a pair keeps its ANRs (a²/(2R)) for any a_sig.

    Raises:
        ConfigError: anr_pair not 1–4, or a_sig not > 0 (no variance gives an ANR then).
    """
    pair = integer("anr_pair", anr_pair)
    if pair not in (1, 2, 3, 4):
        raise ConfigError("anr_pair", anr_pair, "is not one of Fig 7's ANR pairs 1-4")
    if not (math.isfinite(a_sig) and a_sig > 0):
        raise ConfigError("a_sig", a_sig, "is not > 0, so no noise variance gives an ANR pair")
    range_label = SEED_ANR_PAIRS[pair - 1][1]
    return a_sig**2 / 2 * math.exp(-range_label / 10), SEED_R_BEARING[pair - 1] * (a_sig / 0.5) ** 2


def radar_noise(
    anr_pair: int | None, R_range: float | None, R_bearing: float | None, a_sig: float = 0.5
) -> tuple[float, float, int | None]:
    """(R_κ, R_χ, the pair they came from) given a Fig 7 ANR pair or the variances themselves.

    A variance not given comes from ``anr_pair`` (default pair 4, the best); the pair is reported only
    when both variances came from it. The variances themselves are checked by :class:`Vehicle2D`.

    Raises:
        ConfigError: a pair together with a variance, or a bad pair (see :func:`anr_pair_variances`).
    """
    if anr_pair is not None and (R_range is not None or R_bearing is not None):
        raise ConfigError("anr_pair", anr_pair, "is given together with a noise variance: give one, not both")
    if R_range is not None and R_bearing is not None:
        return R_range, R_bearing, None
    pair = 4 if anr_pair is None else anr_pair
    pr, pb = anr_pair_variances(pair, a_sig)
    both = R_range is None and R_bearing is None
    return (
        (pr if R_range is None else R_range),
        (pb if R_bearing is None else R_bearing),
        (pair if both else None),
    )


@dataclass(frozen=True, slots=True)
class Vehicle2D(ClosedLoop):
    """Parameters of the 2-D radar example ([A] = our assumption: the paper does not state it).

    Checked here, once: T, R_range and R_bearing finite and > 0; a_sig, a_r, f_r and sigma_a finite and
    ≥ 0; K two finite gains; start two finite coordinates away from the radar (the origin, where the
    bearing is undefined); sig_axes one of both, x, y.

    Attributes:
        T: Sample interval [s] (assumed: 0.05 s).
        K: Feedback gain (k1, k2), the same on both axes [A].
        a_sig: Signature amplitude a_x = a_y = a_sig on the axes in ``sig_axes`` (0.5 in the paper).
        a_r: Reference amplitude (10 in the paper).
        f_r: Reference frequency [Hz] (0.01 in the paper's Fig 7).
        sigma_a: True white-acceleration noise per axis [m/s²] (assumed: 0.01).
        R_range: Range-noise variance R_κ [m²].
        R_bearing: Bearing-noise variance R_χ [rad²].
        start: Initial position (x_0, y_0) [m], zero velocity ((70, −20) in the paper).
        sig_axes: Axes carrying the signature: ``"both"`` [A], ``"x"`` or ``"y"``.

    Raises:
        ConfigError: naming the first bad field.

    Examples:
        >>> from motionsig_cli import Vehicle2D
        >>> Vehicle2D().start
        (70.0, -20.0)
    """

    R_range: float = anr_pair_variances(4)[0]
    R_bearing: float = SEED_R_BEARING[3]
    start: tuple[float, float] = (70.0, -20.0)
    sig_axes: Literal["both", "x", "y"] = "both"

    def __post_init__(self) -> None:
        ClosedLoop.__post_init__(self)
        positive("R_range", self.R_range, unit="m²")
        positive("R_bearing", self.R_bearing, unit="rad²")
        try:
            ok = len(self.start) == 2 and all(math.isfinite(float(s)) for s in self.start)
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ConfigError("start", self.start, "is not two finite coordinates x, y [m]")
        if math.hypot(*self.start) == 0:
            raise ConfigError(
                "start", self.start, "is the radar's position (the origin): the bearing is undefined"
            )
        one_of("sig_axes", self.sig_axes, SIG_AXES)

    @property
    def amplitudes(self) -> tuple[float, float]:
        """(a_x, a_y) of the truth."""
        return (
            self.a_sig if self.sig_axes in ("both", "x") else 0.0,
            self.a_sig if self.sig_axes in ("both", "y") else 0.0,
        )

    @property
    def anr(self) -> tuple[float, float]:
        """(angle, range) ANR = a_sig² / (2 R) per channel (eq 58 applied to each measurement)."""
        return self.a_sig**2 / (2 * self.R_bearing), self.a_sig**2 / (2 * self.R_range)


def range_bearing(p: np.ndarray, axis: int = -1) -> np.ndarray:
    """Eq (60) without noise: [κ, χ] of states whose components 0 and 2 (along ``axis``) are x and y.

    The components of the result lie along the same axis.
    """
    x, y = np.take(p, IX, axis=axis), np.take(p, IY, axis=axis)
    return np.stack([np.hypot(x, y), np.arctan2(y, x)], axis=axis)


def nominal_reference_2d(cfg: Vehicle2D, t: np.ndarray) -> np.ndarray:
    """[r_x, ṙ_x, r_y, ṙ_y] at times t, shape (N, 4) [A: sine about the start point on both axes]."""
    w = 2 * np.pi * cfg.f_r
    s, c = cfg.a_r * np.sin(w * t), w * cfg.a_r * np.cos(w * t)
    return np.stack([cfg.start[0] + s, c, cfg.start[1] + s, c], axis=-1)


def simulate_2d(
    cfg: Vehicle2D, z: np.ndarray, zdot: np.ndarray, w: np.ndarray, v: np.ndarray
) -> dict[str, np.ndarray]:
    """Closed-loop truth and radar measurements for a batch of records (eqs 59–60).

    Args:
        cfg: Vehicle parameters.
        z: Signature, (B, N); scaled per axis by ``cfg.amplitudes``.
        zdot: Its derivative, (B, N).
        w: Standard-normal process-noise draws (B, N, 2) (x, y), scaled by σ_a here.
        v: Standard-normal measurement-noise draws (B, N, 2) (range, bearing), scaled here.

    Returns:
        ``t`` (N,), ``x`` (B, N, 4) true [x, ẋ, y, ẏ] at each sample, ``u`` (B, N, 2),
        ``y`` (B, N, 2) [range, bearing], ``r`` (N, 4) nominal references.

    Examples:
        >>> import numpy as np
        >>> from motionsig_cli import Vehicle2D, simulate_2d
        >>> rng = np.random.default_rng(0)
        >>> B, N = 2, 50
        >>> out = simulate_2d(Vehicle2D(), np.zeros((B, N)), np.zeros((B, N)), rng.standard_normal((B, N, 2)),
        ...                   rng.standard_normal((B, N, 2)))
        >>> sorted(out)
        ['r', 't', 'u', 'x', 'y']
    """
    z, zdot = (np.atleast_2d(np.asarray(a, dtype=float)) for a in (z, zdot))
    w, v = (np.asarray(a, dtype=float).reshape((*z.shape, 2)) for a in (w, v))
    B, N = z.shape
    T = cfg.T
    k1, k2 = cfg.K
    t = np.arange(N) * T
    r = nominal_reference_2d(cfg, t)
    amp = np.asarray(cfg.amplitudes)  # (a_x, a_y)
    pos = np.broadcast_to(np.asarray(cfg.start, float), (B, 2)).copy()  # (B, axis)
    vel = np.zeros((B, 2))
    xs = np.empty((B, N, 4))
    us = np.empty((B, N, 2))
    r_pos, r_vel = r[:, [0, 2]], r[:, [1, 3]]
    for k in range(N):
        xs[:, k, 0::2], xs[:, k, 1::2] = pos, vel
        e_pos = -pos + r_pos[k] + amp * z[:, k, None]  # −α + r^α + a_α z, eq (54) per axis
        e_vel = -vel + r_vel[k] + amp * zdot[:, k, None]
        u = k1 * e_pos + k2 * e_vel
        us[:, k] = u
        acc = cfg.sigma_a * w[:, k]
        pos, vel = pos + T * vel + 0.5 * T**2 * acc, vel + T * u + T * acc  # eq (59)
    y = range_bearing(xs)
    y[..., 0] += math.sqrt(cfg.R_range) * v[..., 0]  # eq (60)
    y[..., 1] = wrap_angle(y[..., 1] + math.sqrt(cfg.R_bearing) * v[..., 1])
    return {"t": t, "x": xs, "u": us, "y": y, "r": r}


def transition_h0_2d(T: float, K: tuple[float, float]) -> np.ndarray:
    """F^{H0} (8×8, constant): the 1-D block of eq (44) on each axis, state [x, ẋ, y, ẏ, r_x, ṙ_x, r_y, ṙ_y]."""
    k1, k2 = K
    F = np.zeros((8, 8))
    for p, v, r, rd in ((IX, IXD, IRX, IRXD), (IY, IYD, IRY, IRYD)):
        F[p, p], F[p, v] = 1.0, T
        F[v, p], F[v, v], F[v, r], F[v, rd] = -T * k1, 1 - T * k2, T * k1, T * k2
        F[r, r], F[r, rd] = 1.0, T
        F[rd, rd] = 1.0
    return F


def transition_h1_2d_base(T: float, K: tuple[float, float]) -> np.ndarray:
    """F^{H1} (10×10) with zero amplitude entries; the time-varying entries are (ẋ, a_x) and (ẏ, a_y)."""
    F = np.zeros((10, 10))
    F[:8, :8] = transition_h0_2d(T, K)
    F[IAX, IAX] = F[IAY, IAY] = 1.0
    return F


AMPLITUDE_ENTRIES_2D = ((IXD, IAX), (IYD, IAY))  # (row, column) of the two time-varying entries


def prior_mean_2d(start: tuple[float, float], with_amplitudes: bool) -> np.ndarray:
    """Filter prior mean [x_0, 0, y_0, 0, x_0, 0, y_0, 0 (, 0, 0)] [A]."""
    m = [start[0], 0.0, start[1], 0.0, start[0], 0.0, start[1], 0.0]
    return np.array(m + ([0.0, 0.0] if with_amplitudes else []))
