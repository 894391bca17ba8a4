"""Sequential likelihood ratio for track existence from several sensors, after Govaers, *Evaluation of
Distributed Detection Methods for Agile Targets* (Fraunhofer FKIE, slides): three ways of fusing the
sensors' data into one score, kept in the registry :data:`FUSION_METHODS`.

All scores are log likelihood ratios, accumulated scan by scan: log LR(k) = log LR(k−1) + log Λ(k).

- **CKF** (centralised Kalman filter): one filter with all data; per scan predict with (F, Q), then the
  local update (:func:`motionsig_cli.filters.pda.local_update`) of each sensor in turn;
  log Λ(k) = Σ_s log p̄ˢ.
- **LKF** (local Kalman filters): one filter per sensor with (F, Q); fused LR = (1/S) Σ_s LRˢ, i.e.
  logsumexp − log S (``lkf_mean="log"``: the mean of the log LRs).
- **DKF** (distributed Kalman filter, here the federated relaxed-evolution approximation): local filters
  with the relaxed evolution model Pˢ ← FPˢFᵀ + S·Q, initialised at (m₀, S·P₀), so that the product of
  the S local Gaussians is the centralised one. The fusion centre receives (xˢ, Pˢ, p̄ˢ) and computes
  log Λ(k) = log c_{k|k} − log c_{k|k−1} + Σ_s log p̄ˢ, with c = ∫ ∏_s N(x; xˢ, Pˢ) dx evaluated by the
  sequential product c = ∏_{s=1}^{S−1} N(x^{s+1}; x^{(1:s)}, P^{(1:s)} + P^{s+1}) (the slides' P^{s}
  corrected to P^{s+1}).

Sensors may differ (noise, field of view, p_D, clutter): :class:`SensorModel` per sensor in
``TrackExistenceModel.sensor_models``; without them every sensor shares the model's values.

A new fusion rule is one scoring function and one entry of :data:`FUSION_METHODS`; the command's
``--methods`` choices and help, and the experiment, are read from there.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from motionsig_cli.config import ConfigError, in_range, one_of
from motionsig_cli.filters.pda import local_update
from motionsig_cli.models.radar import MeasurementModel

__all__ = [
    "FUSION_METHODS",
    "LKF_MEANS",
    "METHODS",
    "FusionMethod",
    "FusionOptions",
    "ScanData",
    "SensorModel",
    "TrackExistenceModel",
    "check_methods",
    "log_gauss",
    "log_product_constant",
    "run_methods",
    "score_ckf",
    "score_dkf",
    "score_lkf",
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


def log_product_constant(means: Sequence[np.ndarray], covs: Sequence[np.ndarray]) -> np.ndarray:
    """log ∫ ∏_s N(x; x_s, P_s) dx by the sequential product of Gaussians (the slides' form, corrected).

    N(x; a, A)·N(x; b, B) = N(a; b, A + B)·N(x; c, C) with C = A − A(A+B)⁻¹A and
    c = a + A(A+B)⁻¹(b − a) (the Kalman form: no inverse of a single covariance). Batched over runs;
    0 for a single Gaussian.
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
    return out


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


@dataclass(frozen=True)
class FusionOptions:
    """Options of the fusion rules (one field per rule that has one).

    Attributes:
        lkf_mean: LKF's mean of the local scores, one of :data:`LKF_MEANS`.
    """

    lkf_mean: str = "lr"

    def __post_init__(self) -> None:
        one_of("lkf_mean", self.lkf_mean, LKF_MEANS)


def _update(
    model: TrackExistenceModel,
    m: np.ndarray,
    P: np.ndarray,
    Z: np.ndarray,
    V: np.ndarray,
    sensor: np.ndarray,
    s: int | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sensor ``s``'s update of its filters, or (``s`` None) of a sensor-major stack of every sensor's
    filters (S·R rows), each row with its own sensor's values."""
    if not model.sensor_models:
        return local_update(m, P, Z, V, sensor, model.meas, model.pd, model.log_rho)
    if s is not None:
        meas, pd, log_rho = model.sensor(s)
        return local_update(m, P, Z, V, sensor, meas, pd, log_rho)
    noise, pd_s, log_rho_s = model._per_sensor
    rows = np.repeat(np.arange(model.n_sensors), m.shape[0] // model.n_sensors)
    return local_update(m, P, Z, V, sensor, model.meas, pd_s[rows], log_rho_s[rows], noise[rows])


def _stacked(scan: ScanData, S: int, R: int) -> tuple[np.ndarray, np.ndarray]:
    """All sensors' measurements as one (S·R, M, 2) batch, padded to a common M (sensor-major)."""
    M = max(z.shape[1] for z in scan.Z)
    Z = np.zeros((S, R, M, 2))
    V = np.zeros((S, R, M), dtype=bool)
    for s, (z, v) in enumerate(zip(scan.Z, scan.valid, strict=True)):
        Z[s, :, : z.shape[1]] = z
        V[s, :, : z.shape[1]] = v
    return Z.reshape(S * R, M, 2), V.reshape(S * R, M)


def score_ckf(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """CKF: one filter updated by every sensor in turn; log LR (R, K)."""
    R, S = m0.shape[0], model.n_sensors
    F, Q = model.F, model.Q
    out = np.zeros((R, len(scans)))
    m, P = m0.copy(), np.broadcast_to(model.m0_cov, (R, 4, 4)).copy()
    total = np.zeros(R)
    for k, scan in enumerate(scans):
        m, P = m @ F.T, F @ P @ F.T + Q
        lam = np.zeros(R)
        for s in range(S):  # sequential by construction: each sensor updates the running estimate
            m, P, lp = _update(model, m, P, scan.Z[s], scan.valid[s], model.sensors[s], s)
            lam += lp
        total = total + lam
        out[:, k] = total
    return out


def score_lkf(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """LKF: S independent local filters (one batch of S·R, sensor-major), their LRs (or log LRs, with
    ``options.lkf_mean = "log"``) averaged; log LR (R, K)."""
    R, S = m0.shape[0], model.n_sensors
    F, Q = model.F, model.Q
    out = np.zeros((R, len(scans)))
    P0b = np.broadcast_to(model.m0_cov, (R, 4, 4))
    m, P = np.tile(m0, (S, 1)), np.tile(P0b, (S, 1, 1))
    sensor_rows = np.repeat(model.sensors, R, axis=0)  # (S·R, 2)
    score = np.zeros((S, R))
    for k, scan in enumerate(scans):
        Zs, Vs = _stacked(scan, S, R)
        m, P, lp = _update(model, m @ F.T, F @ P @ F.T + Q, Zs, Vs, sensor_rows)
        score += lp.reshape(S, R)
        if options.lkf_mean == "lr":
            top = score.max(axis=0)
            safe = np.where(np.isneginf(top), 0.0, top)
            with np.errstate(divide="ignore"):
                fused = safe + np.log(np.mean(np.exp(score - safe), axis=0))  # log of the mean LR
        else:
            fused = score.mean(axis=0)
        out[:, k] = fused
    return out


def score_dkf(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """DKF: local filters on the relaxed evolution model (S·Q, initialised at S·P₀, no feedback), fused
    through the product constants c_{k|k−1} and c_{k|k}; log LR (R, K)."""
    R, S = m0.shape[0], model.n_sensors
    F, Q = model.F, model.Q
    out = np.zeros((R, len(scans)))
    P0b = np.broadcast_to(model.m0_cov, (R, 4, 4))
    m, P = np.tile(m0, (S, 1)), S * np.tile(P0b, (S, 1, 1))  # relaxed: ∏ N(·; m0, S·P0) ∝ N(·; m0, P0)
    sensor_rows = np.repeat(model.sensors, R, axis=0)  # (S·R, 2)
    total = np.zeros(R)
    for k, scan in enumerate(scans):
        Zs, Vs = _stacked(scan, S, R)
        m, P = m @ F.T, F @ P @ F.T + S * Q  # relaxed evolution model
        log_c_prior = log_product_constant(list(m.reshape(S, R, 4)), list(P.reshape(S, R, 4, 4)))
        m, P, lp = _update(model, m, P, Zs, Vs, sensor_rows)
        log_c_post = log_product_constant(list(m.reshape(S, R, 4)), list(P.reshape(S, R, 4, 4)))
        total = total + lp.reshape(S, R).sum(axis=0) + log_c_post - log_c_prior
        out[:, k] = total
    return out


ScoreFn = Callable[[TrackExistenceModel, np.ndarray, Sequence[ScanData], FusionOptions], np.ndarray]
"""``score(model, m0 (R, 4), scans, options)`` → log LR(k), k = 1..K, per run: (R, K)."""


@dataclass(frozen=True)
class FusionMethod:
    """One way of fusing the sensors' data into a track-existence score.

    Attributes:
        abbreviation: The short name used in the slides (``CKF``).
        title: What the abbreviation stands for (``centralised Kalman filter``).
        description: How the sensors' data reach the score, in a few words.
        score: The scoring function (:data:`ScoreFn`).
    """

    abbreviation: str
    title: str
    description: str
    score: ScoreFn

    @property
    def help(self) -> str:
        """``CKF = centralised Kalman filter: …``, for help texts."""
        return f"{self.abbreviation} = {self.title}: {self.description}"


FUSION_METHODS: dict[str, FusionMethod] = {
    "ckf": FusionMethod("CKF", "centralised Kalman filter", "all measurements at one filter", score_ckf),
    "dkf": FusionMethod(
        "DKF",
        "distributed Kalman filter",
        "here the federated relaxed-evolution approximation (local filters on S·Q, fused at a centre)",
        score_dkf,
    ),
    "lkf": FusionMethod(
        "LKF", "local Kalman filters", "one per sensor, their likelihood ratios averaged", score_lkf
    ),
}
"""The fusion rules by name (the command's ``--methods`` values), in output order."""

METHODS = tuple(FUSION_METHODS)


def check_methods(methods: Sequence[str], field: str = "methods") -> tuple[str, ...]:
    """``methods`` as a tuple if it is a non-empty selection of :data:`FUSION_METHODS`, else
    :class:`~motionsig_cli.config.ConfigError` naming ``field``."""
    names = tuple(methods)
    if not names:
        raise ConfigError(field, names, f"is empty: choose from {', '.join(METHODS)}")
    for name in names:
        one_of(field, name, METHODS)
    return names


def run_methods(
    model: TrackExistenceModel,
    m0: np.ndarray,
    scans: Sequence[ScanData],
    methods: Sequence[str] = METHODS,
    *,
    lkf_mean: str = "lr",
) -> dict[str, np.ndarray]:
    """log LR(k) for k = 1..K of each method, (R, K) per method, from initial track means m0 (R, 4)."""
    options = FusionOptions(lkf_mean)
    return {name: FUSION_METHODS[name].score(model, m0, scans, options) for name in check_methods(methods)}
