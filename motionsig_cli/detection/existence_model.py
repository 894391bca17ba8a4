"""What every track-existence fusion rule shares (Govaers, *Evaluation of Distributed Detection Methods for
Agile Targets*, Fraunhofer FKIE, slides): the model the filters know (:class:`TrackExistenceModel`, with
optional per-sensor :class:`SensorModel`), one scan's measurements (:class:`ScanData`), the rules'
options (:class:`FusionOptions`), the constant of a product of Gaussians (:func:`log_product_constant`,
:func:`fuse_gaussians`), one sensor's update of a batch of filters (:func:`sensor_update`) and the local
filters' own scores (:func:`local_scores`).

The rules themselves, and their registry, are in :mod:`motionsig_cli.detection.track_existence`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of
from motionsig_cli.detection.sprt import wald_thresholds
from motionsig_cli.filters.pda import local_update
from motionsig_cli.models.radar import MeasurementModel

__all__ = [
    "LKF_MEANS",
    "FusionOptions",
    "FusionSettings",
    "ScanData",
    "SensorModel",
    "TrackExistenceModel",
    "fuse_gaussians",
    "local_scores",
    "log_gauss",
    "log_product_constant",
    "sensor_update",
    "stack_scan",
]

LKF_MEANS = ("lr", "log")
"""LKF's fusion of the local scores: the mean of the likelihood ratios (the slides) or of their logs."""


def log_gauss(x: np.ndarray, m: np.ndarray, C: np.ndarray) -> np.ndarray:
    """log N(x; m, C) for batches (..., n), (..., n, n), by Cholesky."""
    L = np.linalg.cholesky(C)
    d = np.linalg.solve(L, (x - m)[..., None])[..., 0]
    n = x.shape[-1]
    return (
        -0.5 * np.sum(d**2, axis=-1)
        - 0.5 * n * math.log(2 * math.pi)
        - np.sum(np.log(np.diagonal(L, axis1=-2, axis2=-1)), axis=-1)
    )


def fuse_gaussians(
    means: Sequence[np.ndarray], covs: Sequence[np.ndarray]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """∏_s N(x; x_s, P_s) = c·N(x; x_f, P_f): (log c, x_f, P_f), by the sequential product of Gaussians
    (the slides' form, corrected).

    N(x; a, A)·N(x; b, B) = N(a; b, A + B)·N(x; c, C) with C = A − A(A+B)⁻¹A and
    c = a + A(A+B)⁻¹(b − a) (the Kalman form: no inverse of a single covariance); so
    c = ∏_{s=1}^{S−1} N(x^{s+1}; x^{(1:s)}, P^{(1:s)} + P^{s+1}) (the slides print P^{s} for P^{s+1}) and
    (x_f, P_f) = (x^{(1:S)}, P^{(1:S)}), the fused estimate. Batched over runs; log c = 0 for a single
    Gaussian.
    """
    a, A = means[0], covs[0]
    out = np.zeros(a.shape[:-1])
    for b, B in zip(means[1:], covs[1:], strict=True):
        AB = A + B
        out = out + log_gauss(b, a, AB)
        G = np.swapaxes(np.linalg.solve(AB, A), -1, -2)  # A(A+B)⁻¹ (symmetric A, AB)
        a = a + np.einsum("...ij,...j->...i", G, b - a)
        A = A - G @ A
        A = 0.5 * (A + np.swapaxes(A, -1, -2))
    return out, a, A


def log_product_constant(means: Sequence[np.ndarray], covs: Sequence[np.ndarray]) -> np.ndarray:
    """log ∫ ∏_s N(x; x_s, P_s) dx (:func:`fuse_gaussians`'s log c)."""
    return fuse_gaussians(means, covs)[0]


def _log_rho(clutter_rate: float, meas: MeasurementModel) -> float:
    """log ρ_F = log(λ_F / |FoV|), with a tiny floor on λ_F when it is 0."""
    return math.log(max(clutter_rate, 1e-300) / meas.fov_volume)


@dataclass(frozen=True)
class SensorModel:
    """One sensor's own values where the sensors differ: its measurement model (noise R, field of view),
    the p_D its filters assume and its clutter rate λ_F (mean false alarms per scan)."""

    meas: MeasurementModel
    pd: float
    clutter_rate: float

    def __post_init__(self) -> None:
        in_range("pd", self.pd, 0.0, 1.0, lo_open=True)
        in_range("clutter_rate", self.clutter_rate, 0.0)

    @property
    def log_rho(self) -> float:
        """log ρ_F of this sensor (as :attr:`TrackExistenceModel.log_rho`)."""
        return _log_rho(self.clutter_rate, self.meas)


@dataclass(frozen=True)
class TrackExistenceModel:
    """What every method knows: motion model, sensors, measurement model, clutter density, p_D and the
    track prior.

    ``m0_cov`` is one (4, 4) prior covariance, or (R, 4, 4): one per filter batch row (tracks started
    from different detections). ``sensor_models``: empty (every sensor has ``meas``, ``pd`` and
    ``clutter_rate``), or one :class:`SensorModel` per sensor, of the kind of ``meas`` (whose noise,
    ``pd`` and ``clutter_rate`` are then unused).
    """

    F: np.ndarray
    Q: np.ndarray
    sensors: np.ndarray
    meas: MeasurementModel
    pd: float
    clutter_rate: float
    m0_cov: np.ndarray
    sensor_models: tuple[SensorModel, ...] = ()

    def __post_init__(self) -> None:
        in_range("pd", self.pd, 0.0, 1.0, lo_open=True)
        in_range("clutter_rate", self.clutter_rate, 0.0)
        if len(self.sensors) < 1:
            raise ConfigError("sensors", len(self.sensors), "rows: at least one sensor is needed")
        if self.sensor_models:
            if len(self.sensor_models) != len(self.sensors):
                raise ConfigError(
                    "sensor_models", len(self.sensor_models), f"models for {len(self.sensors)} sensors"
                )
            for sm in self.sensor_models:
                if sm.meas.kind != self.meas.kind:
                    raise ConfigError("sensor_models", sm.meas.kind, f"is not the model's {self.meas.kind}")
        low = float(np.linalg.eigvalsh(self.Q).min())
        if low < -1e-12:
            raise ConfigError("Q", low, "is its smallest eigenvalue: Q must be positive semi-definite")
        low = float(np.linalg.eigvalsh(self.m0_cov).min())
        if low <= 0:
            raise ConfigError("m0_cov", low, "is its smallest eigenvalue: P0 must be positive definite")

    @property
    def n_sensors(self) -> int:
        return len(self.sensors)

    @property
    def log_rho(self) -> float:
        """log ρ_F, the clutter density in measurement space (−inf-safe: a tiny floor when λ_F = 0)."""
        return _log_rho(self.clutter_rate, self.meas)

    def sensor(self, s: int) -> tuple[MeasurementModel, float, float]:
        """(measurement model, p_D, log ρ_F) of sensor ``s``."""
        if not self.sensor_models:
            return self.meas, self.pd, self.log_rho
        sm = self.sensor_models[s]
        return sm.meas, sm.pd, sm.log_rho

    def detection_probabilities(self) -> tuple[float, ...]:
        """The p_D each sensor's filters assume."""
        return tuple(sm.pd for sm in self.sensor_models) or (self.pd,) * self.n_sensors

    def clutter_rates(self) -> tuple[float, ...]:
        """Each sensor's clutter rate λ_F."""
        return tuple(sm.clutter_rate for sm in self.sensor_models) or (self.clutter_rate,) * self.n_sensors

    @cached_property
    def _per_sensor(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(S, 2, 2) noise, (S,) p_D, (S,) log ρ_F of the sensors."""
        return (
            np.stack([sm.meas.R for sm in self.sensor_models]),
            np.array([sm.pd for sm in self.sensor_models]),
            np.array([sm.log_rho for sm in self.sensor_models]),
        )


@dataclass(frozen=True)
class ScanData:
    """Measurements of one scan: per sensor an (R, M_s, 2) array and its (R, M_s) validity mask."""

    Z: tuple[np.ndarray, ...]
    valid: tuple[np.ndarray, ...]


MAX_FEEDBACK_EVERY = 100_000
"""Largest ``feedback_every`` (the longest run of scans)."""


@dataclass(frozen=True)
class FusionOptions:
    """Options of the fusion rules (one field per rule that has one); every field is checked
    (:class:`~motionsig_cli.config.ConfigError` naming it).

    Attributes:
        lkf_mean: LKF's mean of the local scores, one of :data:`LKF_MEANS`.
        gate_pg: the validation gate's probability P_G in (0, 1] for every local update
            (:func:`motionsig_cli.filters.pda.local_update`), or None: no gate (the default; the slides
            gate nothing).
        feedback_every: ``fkf-feedback`` resets the local filters to the fused estimate after every
            ``feedback_every``-th scan (an integer in [1, 10⁵]; default 1: after each transmission).
        ldf_prior: LDF's prior existence probability P₀ in (0, 1) (default 0.5, assumed: prior odds 1, the
            odds every score starts from).
        ldf_weights: LDF's weights of the sensors' existence probabilities, one number ≥ 0 per sensor, not
            all 0 (they are divided by their sum), or None: equal weights (the default).
        alpha, beta: Wald's error probabilities of the local tests of the rules that decide locally
            (``naive``), in (0, 0.5); a study passes its own (default 10⁻³ and 0.1, the command's).
    """

    lkf_mean: str = "lr"
    gate_pg: float | None = None
    feedback_every: int = 1
    ldf_prior: float = 0.5
    ldf_weights: tuple[float, ...] | None = None
    alpha: float = 1e-3
    beta: float = 0.1

    def __post_init__(self) -> None:
        one_of("lkf_mean", self.lkf_mean, LKF_MEANS)
        if self.gate_pg is not None:
            in_range("gate_pg", self.gate_pg, 0.0, 1.0, lo_open=True)
        integer("feedback_every", self.feedback_every, 1, MAX_FEEDBACK_EVERY)
        in_range("ldf_prior", self.ldf_prior, 0.0, 1.0, lo_open=True, hi_open=True)
        if self.ldf_weights is not None:
            if len(self.ldf_weights) == 0:
                raise ConfigError("ldf_weights", self.ldf_weights, "is empty: one weight per sensor")
            for w in self.ldf_weights:
                in_range("ldf_weights", w, 0.0)
            if not any(float(w) > 0 for w in self.ldf_weights):
                raise ConfigError("ldf_weights", self.ldf_weights, "are all 0: at least one must be > 0")
        wald_thresholds(self.alpha, self.beta)

    @property
    def thresholds(self) -> tuple[float, float]:
        """Wald's (log A, log B) of the local tests."""
        return wald_thresholds(self.alpha, self.beta)


class FusionSettings:
    """What a study or a record's settings that carry the fields of :class:`FusionOptions` (``lkf_mean``,
    ``gate_pg``, ``feedback_every``, ``ldf_prior``, ``ldf_weights``, ``alpha``, ``beta``) derive from them:
    Wald's thresholds and the fusion rules' options."""

    lkf_mean: str
    gate_pg: float | None
    feedback_every: int
    ldf_prior: float
    ldf_weights: Sequence[float] | None
    alpha: float
    beta: float

    @property
    def thresholds(self) -> tuple[float, float]:
        """Wald's (log A, log B) = (log β/(1−α), log (1−β)/α) (:func:`~motionsig_cli.detection.sprt.wald_thresholds`)."""
        return wald_thresholds(self.alpha, self.beta)

    @property
    def options(self) -> FusionOptions:
        """The fusion rules' options, with Wald's α and β for the rules that test locally."""
        return FusionOptions(
            lkf_mean=self.lkf_mean,
            gate_pg=self.gate_pg,
            feedback_every=self.feedback_every,
            ldf_prior=self.ldf_prior,
            ldf_weights=None if self.ldf_weights is None else tuple(self.ldf_weights),
            alpha=self.alpha,
            beta=self.beta,
        )


def sensor_update(
    model: TrackExistenceModel,
    m: np.ndarray,
    P: np.ndarray,
    Z: np.ndarray,
    V: np.ndarray,
    sensor: np.ndarray,
    s: int | None = None,
    gate_pg: float | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sensor ``s``'s update of its filters, or (``s`` None) of a sensor-major stack of every sensor's
    filters (S·R rows), each row with its own sensor's values; ``gate_pg`` as
    :func:`~motionsig_cli.filters.pda.local_update`'s."""
    if not model.sensor_models:
        return local_update(m, P, Z, V, sensor, model.meas, model.pd, model.log_rho, gate_pg=gate_pg)
    if s is not None:
        meas, pd, log_rho = model.sensor(s)
        return local_update(m, P, Z, V, sensor, meas, pd, log_rho, gate_pg=gate_pg)
    noise, pd_s, log_rho_s = model._per_sensor
    rows = np.repeat(np.arange(model.n_sensors), m.shape[0] // model.n_sensors)
    return local_update(
        m, P, Z, V, sensor, model.meas, pd_s[rows], log_rho_s[rows], noise[rows], gate_pg=gate_pg
    )


def stack_scan(scan: ScanData, S: int, R: int) -> tuple[np.ndarray, np.ndarray]:
    """All sensors' measurements as one (S·R, M, 2) batch, padded to a common M (sensor-major)."""
    M = max(z.shape[1] for z in scan.Z)
    Z = np.zeros((S, R, M, 2))
    V = np.zeros((S, R, M), dtype=bool)
    for s, (z, v) in enumerate(zip(scan.Z, scan.valid, strict=True)):
        Z[s, :, : z.shape[1]] = z
        V[s, :, : z.shape[1]] = v
    return Z.reshape(S * R, M, 2), V.reshape(S * R, M)


def local_scores(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """Each sensor's own single-sensor test: S independent local filters with the true model (F, Q) from
    (m₀, P₀), one batch of S·R (sensor-major), and their log LRˢ(k) = Σ_{l≤k} log p̄ˢ_l: (S, R, K)."""
    R, S = m0.shape[0], model.n_sensors
    F, Q = model.F, model.Q
    out = np.zeros((S, R, len(scans)))
    P0b = np.broadcast_to(model.m0_cov, (R, 4, 4))
    m, P = np.tile(m0, (S, 1)), np.tile(P0b, (S, 1, 1))
    sensor_rows = np.repeat(model.sensors, R, axis=0)  # (S·R, 2)
    score = np.zeros((S, R))
    for k, scan in enumerate(scans):
        Zs, Vs = stack_scan(scan, S, R)
        m, P, lp = sensor_update(
            model, m @ F.T, F @ P @ F.T + Q, Zs, Vs, sensor_rows, gate_pg=options.gate_pg
        )
        score += lp.reshape(S, R)
        out[:, :, k] = score
    return out
