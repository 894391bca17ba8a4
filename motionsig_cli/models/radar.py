"""Planar target motion and sensor measurement models for the track-existence test of Govaers, *Evaluation
of Distributed Detection Methods for Agile Targets* (Fraunhofer FKIE, slides).

State x = [x, ẋ, y, ẏ] (m, m/s). Nearly constant velocity with continuous white-noise acceleration of
power spectral density q̃ (the scenario's default q̃ = 10 m²/s³): per axis F = [[1, T], [0, 1]],
Q = q̃ [[T³/3, T²/2], [T²/2, T]].

Measurements from a sensor at position s: range–bearing z = [‖p − s‖, atan2(dy, dx)] (the default,
"non-linear scenario" of the slides, EKF-linearised), or linear Cartesian position z = [x, y]
(``cartesian``, for the exactness check P7). All functions broadcast over leading axes (runs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from motionsig_cli.config import ConfigError, in_range, one_of, positive

__all__ = ["MEASUREMENT_KINDS", "MeasurementModel", "cv_model", "wrap_angle"]

MEASUREMENT_KINDS = ("range_bearing", "cartesian")


def wrap_angle(a: np.ndarray) -> np.ndarray:
    """Wrap angles to (−π, π]."""
    return np.pi - np.mod(np.pi - np.asarray(a), 2.0 * np.pi)


def cv_model(T: float, q: float) -> tuple[np.ndarray, np.ndarray]:
    """F and Q of the nearly-constant-velocity model, state [x, ẋ, y, ẏ].

    Raises:
        ConfigError: the scan period T not a finite number > 0, or the acceleration psd q not finite ≥ 0.
    """
    positive("T", T, unit="s")
    in_range("q", q, 0.0, unit="m²/s³")
    f = np.array([[1.0, T], [0.0, 1.0]])
    qa = q * np.array([[T**3 / 3.0, T**2 / 2.0], [T**2 / 2.0, T]])
    F = np.zeros((4, 4))
    Q = np.zeros((4, 4))
    for i in (0, 2):
        F[i : i + 2, i : i + 2] = f
        Q[i : i + 2, i : i + 2] = qa
    return F, Q


@dataclass(frozen=True)
class MeasurementModel:
    """A sensor's measurement model.

    Attributes:
        kind: ``range_bearing`` or ``cartesian``.
        R: (2, 2) measurement noise covariance (m², rad² for range–bearing), symmetric positive definite.
        fov_range: field-of-view radius [m]: a polar box r ∈ [0, fov_range], φ ∈ [−π, π) for range–bearing,
            a square of half-width fov_range about the sensor for Cartesian.
    """

    kind: str
    R: np.ndarray
    fov_range: float = 26_000.0

    def __post_init__(self) -> None:
        one_of("kind", self.kind, MEASUREMENT_KINDS)
        R = np.asarray(self.R, dtype=float)
        if (
            R.shape != (2, 2)
            or not np.all(np.isfinite(R))
            or not np.allclose(R, R.T)
            or np.any(np.linalg.eigvalsh(R) <= 0)
        ):
            raise ConfigError("R", R.tolist(), "is not a symmetric positive definite 2x2 matrix")
        positive("fov_range", self.fov_range, unit="m")
        object.__setattr__(self, "R", R)

    @property
    def angular(self) -> int | None:
        """Index of the angle component (wrapped residuals), or None."""
        return 1 if self.kind == "range_bearing" else None

    @property
    def fov_volume(self) -> float:
        """|FoV| in measurement-space units (m·rad for range–bearing, m² for Cartesian)."""
        if self.kind == "range_bearing":
            return self.fov_range * 2.0 * math.pi
        return (2.0 * self.fov_range) ** 2

    def h(self, x: np.ndarray, sensor: np.ndarray) -> np.ndarray:
        """Noise-free measurement of states x (..., 4) from a sensor at (2,)."""
        dx, dy = x[..., 0] - sensor[..., 0], x[..., 2] - sensor[..., 1]
        if self.kind == "range_bearing":
            return np.stack([np.hypot(dx, dy), np.arctan2(dy, dx)], axis=-1)
        return np.stack([x[..., 0], x[..., 2]], axis=-1)

    def jacobian(self, x: np.ndarray, sensor: np.ndarray) -> np.ndarray:
        """∂h/∂x at x (..., 4): (..., 2, 4)."""
        H = np.zeros((*x.shape[:-1], 2, 4))
        if self.kind == "range_bearing":
            dx, dy = x[..., 0] - sensor[..., 0], x[..., 2] - sensor[..., 1]
            r2 = dx**2 + dy**2
            r = np.sqrt(r2)
            H[..., 0, 0], H[..., 0, 2] = dx / r, dy / r
            H[..., 1, 0], H[..., 1, 2] = -dy / r2, dx / r2
        else:
            H[..., 0, 0] = H[..., 1, 2] = 1.0
        return H

    def in_fov(self, z: np.ndarray, sensor: np.ndarray) -> np.ndarray:
        """Whether measurements z (..., 2) lie in the sensor's field of view."""
        if self.kind == "range_bearing":
            return (z[..., 0] >= 0.0) & (z[..., 0] <= self.fov_range)
        return np.all(np.abs(z - sensor) <= self.fov_range, axis=-1)

    def clutter(self, rng: np.random.Generator, n: int, sensor: np.ndarray) -> np.ndarray:
        """n false alarms uniform over the field of view (in measurement space)."""
        return self.place_uniform(rng.random((n, 2)), sensor)

    def place_uniform(self, u: np.ndarray, sensor: np.ndarray) -> np.ndarray:
        """Points uniform over the field of view from uniforms u (..., 2) in [0, 1): range u₀·fov_range and
        bearing (2u₁ − 1)π for range–bearing, the sensor's position plus (2u − 1)·fov_range for Cartesian
        (``sensor`` (..., 2) broadcasts against u). Elementwise, so a point depends on its own u only."""
        u = np.asarray(u, dtype=float)
        if self.kind == "range_bearing":
            return np.stack([u[..., 0] * self.fov_range, (2.0 * u[..., 1] - 1.0) * math.pi], axis=-1)
        return sensor + (2.0 * u - 1.0) * self.fov_range
