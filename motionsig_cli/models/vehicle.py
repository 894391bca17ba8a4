"""The 1-D closed-loop vehicle of seed 000 §IV.A (eqs 53–55) and its augmented filter models (eq 44).

Truth (spec §1.6)::

    x_{k+1} = [[1, T], [0, 1]] x_k + [0, T]ᵀ u_k + [T²/2, T]ᵀ w_k          eq (53), w ~ N(0, σ_a²)
    u_k     = K (−x_k + r_k + a_sig [z_k, ż_k]ᵀ)                              controller, eq (54)
    y_k     = [1, 0] x_k + v_k,   v ~ N(0, R)                               eq (55)
    r_k     = [a_r sin(2π f_r t_k), 2π f_r a_r cos(2π f_r t_k)]ᵀ            nominal reference

Filter models (eq 44 with true-state feedback, A_r a constant-velocity random walk)::

    state H0: [x, ẋ, r, ṙ];  H1: [x, ẋ, r, ṙ, a]
    F^{H1}_k = [[1, T, 0, 0, 0],
                [−T k1, 1 − T k2, T k1, T k2, T (k1 z_k + k2 ż_k)],
                [0, 0, 1, T, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1]]
    F^{H0} = upper-left 4×4 block;  H = [1, 0, 0, 0(, 0)]
    Q^{H0} = diag(1e-3, 1e2, 1e-1, 1e1) (eq 56);  Q^{H1} = diag(…, Q_a = 1) (eq 57, "10⁰")
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

Q0_DIAG = (1e-3, 1e2, 1e-1, 1e1)  # eq (56), per step
QA_DEFAULT = 1.0  # eq (57) last entry, read as 10^0


def pole_placement_gain(T: float, wn: float = 4 * math.pi, zeta: float = 0.7) -> tuple[float, float]:
    """K = [k1, k2] placing the poles of A − BK at e^{sT}, s = −ζω_n ± jω_n√(1−ζ²) (spec §1.8).

    det(zI − (A − BK)) = z² + (T k2 − 2) z + (1 − T k2 + T² k1) = z² + α1 z + α0 with
    α1 = −2 e^{−ζω_nT} cos(ω_d T), α0 = e^{−2ζω_nT}  ⇒  k2 = (2 + α1)/T, k1 = (1 + α1 + α0)/T².
    """
    if not (T > 0 and wn > 0 and 0 < zeta < 1):
        raise ValueError("pole placement needs T > 0, wn > 0 and 0 < zeta < 1")
    wd = wn * math.sqrt(1 - zeta**2)
    a1 = -2 * math.exp(-zeta * wn * T) * math.cos(wd * T)
    a0 = math.exp(-2 * zeta * wn * T)
    return (1 + a1 + a0) / T**2, (2 + a1) / T


@dataclass(frozen=True, slots=True)
class Vehicle1D:
    """Parameters of the 1-D example (defaults: spec §1.8; [A] = assumption, seed silent).

    Attributes:
        T: Sample interval [s] [A].
        K: Feedback gain (k1, k2); default pole placement ω_n = 4π, ζ = 0.7 [A].
        a_sig: Signature amplitude (0.5, seed).
        a_r: Nominal reference amplitude (10, seed).
        f_r: Nominal reference frequency [Hz] (0.01, 0.1 or 1, seed).
        sigma_a: True white-acceleration noise [m/s²] [A].
        R: Measurement-noise variance (1e-1 … 1e-5, derived from the seed's ANR labels).
    """

    T: float = 0.05
    K: tuple[float, float] = field(default_factory=lambda: pole_placement_gain(0.05))
    a_sig: float = 0.5
    a_r: float = 10.0
    f_r: float = 0.01
    sigma_a: float = 0.01
    R: float = 1e-5

    def __post_init__(self) -> None:
        for name in ("T", "R"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be positive and finite, got {v}")
        for name in ("a_sig", "a_r", "f_r", "sigma_a"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"{name} must be finite and >= 0, got {v}")
        if len(self.K) != 2 or not all(math.isfinite(k) for k in self.K):
            raise ValueError(f"K must be two finite gains, got {self.K}")

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
