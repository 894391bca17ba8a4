"""The 1-D closed-loop vehicle of the mode-signature paper (LMP mode detection with Gold-code signatures,
IEEE CDC 2008), §IV.A, eqs 53–55, and its augmented filter models (eq 44).

Truth::

    x_{k+1} = [[1, T], [0, 1]] x_k + [0, T]ᵀ u_k + [T²/2, T]ᵀ w_k          eq (53), w ~ N(0, σ_a²)
    u_k     = K (−x_k + r_k + a_sig [z_k, ż_k]ᵀ)                              controller, eq (54)
    y_k     = [1, 0] x_k + v_k,   v ~ N(0, R)                               eq (55)
    r_k     = [a_r sin(2π f_r t_k), 2π f_r a_r cos(2π f_r t_k)]ᵀ            nominal reference [A]

Filter models (eq 44 with true-state feedback, A_r a constant-velocity random walk)::

    state H0: [x, ẋ, r, ṙ];  H1: [x, ẋ, r, ṙ, a]
    F^{H1}_k = [[1, T, 0, 0, 0],
                [−T k1, 1 − T k2, T k1, T k2, T (k1 z_k + k2 ż_k)],
                [0, 0, 1, T, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1]]
    F^{H0} = upper-left 4×4 block;  H = [1, 0, 0, 0(, 0)]
    Q^{H0} = diag(1e-3, 1e2, 1e-1, 1e1) (eq 56);  Q^{H1} = diag(…, Q_a = 1) (eq 57, "10⁰")

[A] = our assumption: the paper does not state it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError, in_range, one_of, positive

Q0_DIAG = (1e-3, 1e2, 1e-1, 1e1)  # eq (56), per step
QA_DEFAULT = 1.0  # eq (57) last entry, read as 10^0
DEFAULT_R = 1e-5  # the best ANR of Figs 4–6 (label 94.3)
# how an ANR in dB is read: log10, true decibels 10·log10(ANR) (the default); paper-ln, the mode-signature
# paper's "dB" labels, 10·ln(ANR) (94.3 ↔ R = 1e-5, 48.3 ↔ R = 1e-3 at a_sig = 0.5)
DB_CONVENTIONS = ("log10", "paper-ln")


def pole_placement_gain(T: float, wn: float = 4 * math.pi, zeta: float = 0.7) -> tuple[float, float]:
    """K = [k1, k2] placing the poles of A − BK at e^{sT}, s = −ζω_n ± jω_n√(1−ζ²) [A: ω_n = 4π rad/s,
    ζ = 0.7 by default].

    det(zI − (A − BK)) = z² + (T k2 − 2) z + (1 − T k2 + T² k1) = z² + α1 z + α0 with
    α1 = −2 e^{−ζω_nT} cos(ω_d T), α0 = e^{−2ζω_nT}  ⇒  k2 = (2 + α1)/T, k1 = (1 + α1 + α0)/T².

    Raises:
        ConfigError: T or wn not a finite number > 0, zeta not in (0, 1) (an underdamped pole pair),
            or T so small that T² underflows.
    """
    positive("T", T, unit="s")
    positive("wn", wn, unit="rad/s")
    in_range("zeta", zeta, 0.0, 1.0, lo_open=True, hi_open=True)
    if T**2 == 0:
        raise ConfigError("T", T, "is too small for pole placement (T² underflows)")
    wd = wn * math.sqrt(1 - zeta**2)
    a1 = -2 * math.exp(-zeta * wn * T) * math.cos(wd * T)
    a0 = math.exp(-2 * zeta * wn * T)
    return (1 + a1 + a0) / T**2, (2 + a1) / T


def check_gain(name: str, K: Any) -> None:
    """A feedback gain: two finite numbers (k1, k2), else :class:`ConfigError` naming ``name``."""
    ok = isinstance(K, Sequence) and len(K) == 2
    try:
        ok = ok and all(math.isfinite(float(k)) for k in K)
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ConfigError(name, K, "is not two finite gains k1, k2")


def measurement_variance(
    R: float | None, anr_db: float | None, db_convention: str = "log10", a_sig: float = 0.5
) -> float:
    """The measurement-noise variance R given itself or an ANR in dB (ANR = a_sig²/(2R), eq 58).

    ``db_convention`` ``"log10"`` (the default) reads the dB value as true decibels, ANR = 10^(dB/10);
    ``"paper-ln"`` as the paper's labels of Figs 4–6, 10·ln(ANR), so ANR = e^(dB/10). Neither given:
    R = 1e-5. R itself is checked by :class:`Vehicle1D`.

    Raises:
        ConfigError: both given, an unknown convention, a_sig ≤ 0 with an ANR (no R gives it), or an ANR
            whose R is not a positive finite number.
    """
    one_of("db_convention", db_convention, DB_CONVENTIONS)
    if anr_db is None:
        return DEFAULT_R if R is None else R
    if R is not None:
        raise ConfigError("anr_db", anr_db, "is given together with the variance R: give one, not both")
    if not math.isfinite(anr_db):
        raise ConfigError("anr_db", anr_db, "is not a finite number")
    if not a_sig > 0:
        raise ConfigError("a_sig", a_sig, "is not > 0, so no measurement variance gives the ANR")
    try:
        anr = math.exp(anr_db / 10) if db_convention == "paper-ln" else 10 ** (anr_db / 10)
        R = a_sig**2 / (2 * anr)
    except OverflowError:
        raise ConfigError("anr_db", anr_db, "is too large: the measurement variance R underflows") from None
    except ZeroDivisionError:
        raise ConfigError("anr_db", anr_db, "is too small: the measurement variance R overflows") from None
    if not (math.isfinite(R) and R > 0):
        raise ConfigError(
            "anr_db", anr_db, f"gives a measurement variance R = {R:g}, not a finite number > 0"
        )
    return R


@dataclass(frozen=True, slots=True)
class ClosedLoop:
    """The closed-loop fields that the 1-D (:class:`Vehicle1D`) and 2-D
    (:class:`~motionsig_cli.models.vehicle2d.Vehicle2D`) examples share, first in both; each documents
    them. Checked here: T finite and > 0; a_sig, a_r, f_r and sigma_a finite and ≥ 0; K two finite gains.
    """

    T: float = 0.05
    K: tuple[float, float] = field(default_factory=lambda: pole_placement_gain(0.05))
    a_sig: float = 0.5
    a_r: float = 10.0
    f_r: float = 0.01
    sigma_a: float = 0.01

    def __post_init__(self) -> None:
        positive("T", self.T, unit="s")
        check_gain("K", self.K)
        for name in ("a_sig", "a_r", "f_r", "sigma_a"):
            in_range(name, getattr(self, name), 0.0)


@dataclass(frozen=True, slots=True)
class Vehicle1D(ClosedLoop):
    """Parameters of the 1-D example ([A] = our assumption: the paper does not state it).

    Checked here, once: T and R finite and > 0; a_sig, a_r, f_r and sigma_a finite and ≥ 0 (a zero
    amplitude, frequency or noise is a legitimate degenerate case: a_sig = 0 carries no signature);
    K two finite gains.

    Attributes:
        T: Sample interval [s] [A: 0.05 s].
        K: Feedback gain (k1, k2); default pole placement ω_n = 4π, ζ = 0.7 [A].
        a_sig: Signature amplitude (0.5 in the paper).
        a_r: Nominal reference amplitude (10 in the paper).
        f_r: Nominal reference frequency [Hz] (0.01, 0.1 or 1 in the paper).
        sigma_a: True white-acceleration noise [m/s²] [A: 0.01].
        R: Measurement-noise variance (1e-1 … 1e-5, derived from the paper's ANR labels).

    Raises:
        ConfigError: naming the first bad field.
    """

    R: float = DEFAULT_R

    def __post_init__(self) -> None:
        ClosedLoop.__post_init__(self)
        positive("R", self.R)

    @property
    def anr(self) -> float:
        """ANR = a_sig² / (2 R) (eq 58, scalar measurement)."""
        return self.a_sig**2 / (2 * self.R)


def nominal_reference(cfg: Vehicle1D, t: np.ndarray) -> np.ndarray:
    """r_k = [a_r sin(2π f_r t), 2π f_r a_r cos(2π f_r t)], shape (N, 2) [A: sine]."""
    w = 2 * np.pi * cfg.f_r
    return np.stack([cfg.a_r * np.sin(w * t), w * cfg.a_r * np.cos(w * t)], axis=-1)


def simulate_1d(
    cfg: Vehicle1D, z: np.ndarray, zdot: np.ndarray, w: np.ndarray, v: np.ndarray
) -> dict[str, np.ndarray]:
    """Closed-loop truth and measurements for a batch of records (eqs 53–55).

    Args:
        cfg: Vehicle parameters.
        z, zdot: Signature and its derivative, (B, N) (zero for "no signature").
        w: Standard-normal process-noise draws (B, N), scaled by σ_a here.
        v: Standard-normal measurement-noise draws (B, N), scaled by √R here.

    Returns:
        ``t`` (N,), ``x`` (B, N, 2) true state at each sample, ``u`` (B, N), ``y`` (B, N),
        ``r`` (N, 2) nominal reference.
    """
    z, zdot, w, v = (np.atleast_2d(np.asarray(a, dtype=float)) for a in (z, zdot, w, v))
    B, N = z.shape
    T = cfg.T
    k1, k2 = cfg.K
    t = np.arange(N) * T
    r = nominal_reference(cfg, t)
    x = np.zeros((B, 2))
    xs = np.empty((B, N, 2))
    us = np.empty((B, N))
    for k in range(N):
        xs[:, k] = x
        e_pos = -x[:, 0] + r[k, 0] + cfg.a_sig * z[:, k]  # −x + r + a_sig t_z(z), eq (54)
        e_vel = -x[:, 1] + r[k, 1] + cfg.a_sig * zdot[:, k]
        u = k1 * e_pos + k2 * e_vel
        us[:, k] = u
        acc = cfg.sigma_a * w[:, k]
        x = np.stack(
            [x[:, 0] + T * x[:, 1] + 0.5 * T**2 * acc, x[:, 1] + T * u + T * acc], axis=-1
        )  # eq (53): A x + B u + [T²/2, T] w
    y = xs[:, :, 0] + math.sqrt(cfg.R) * v  # eq (55)
    return {"t": t, "x": xs, "u": us, "y": y, "r": r}


def transition_h0(cfg: Vehicle1D, A_r: str = "cv") -> np.ndarray:
    """F^{H0}: 4×4, constant (eq 44 without the amplitude state)."""
    T = cfg.T
    k1, k2 = cfg.K
    F = np.array(
        [
            [1.0, T, 0.0, 0.0],
            [-T * k1, 1 - T * k2, T * k1, T * k2],
            [0.0, 0.0, 1.0, T if A_r == "cv" else 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )
    return F


def amplitude_column(cfg: Vehicle1D, z: np.ndarray, zdot: np.ndarray) -> np.ndarray:
    """The time-varying a-column entry T (k1 z_k + k2 ż_k) of F^{H1}_k (eq 44, row ẋ)."""
    k1, k2 = cfg.K
    return cfg.T * (k1 * np.asarray(z) + k2 * np.asarray(zdot))
