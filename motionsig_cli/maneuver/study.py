"""The maneuvering-target scenario of Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated
JRC System* ("the paper"), and its Monte Carlo: a target that turns twice, position measurements, and four
trackers on the same runs — the IMM of three Kalman filters, the GLR and MLR input-estimation trackers, and
the constant-velocity Kalman filter they start from.

Scans are numbered k = 1..N as in the paper. Interval k covers (t_k, t_{k+1}]; the input u(k) is held over
it: p(k+1) = p(k) + v(k)T + ½u(k)T², v(k+1) = v(k) + u(k)T (exact constant-acceleration kinematics). Every
tracker initialises by two-point differencing at scan 2, so estimates start at scan 3.

**Measurements.** A :class:`MeasurementSource` turns the truth into the records the trackers see; the
sources are registered in :data:`SOURCES`: ``gaussian`` (true position + N(0, σ²) Cartesian noise per
axis, :class:`GaussianPositions`) and ``ebpsk`` (positions located by the EBPSK radar front end, with a
covariance R(k) per run and scan and missed detections:
:class:`~motionsig_cli.maneuver.ebpsk_tracking.EbpskPositions`; every tracker then runs with the time-varying
R(k)). Run r draws only from ``trial_rng(seed, r)``, its seed child: every σ and
every method therefore sees the same draws (common random numbers), and a result does not depend on the
number of runs, their order or how they are chunked.

**Monte Carlo.** :class:`ManeuverJob` implements :class:`motionsig_cli.engine.MonteCarloJob`: a task is a
chunk of consecutive runs at one σ (:meth:`ManeuverJob.run_task` returns the chunk's error sums and
declarations), chunks are sized from :func:`cost` only, and :meth:`ManeuverJob.reduce` adds the partial sums
in task order — so a result is byte-identical on 1 worker, N workers or a Dask cluster.

**Reports.** :class:`ManeuverStudy` is what the command asks for (a job and a view of its results);
:func:`report` turns the job's result into the table (per scan, per input change or one summary row per σ and
method), the one-line summary and the figures' data. :func:`measurement_table` writes the simulated records;
one record read from a file is tracked by :mod:`motionsig_cli.maneuver.record`.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import asdict, dataclass
from typing import Any, ClassVar, Protocol

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of
from motionsig_cli.detection.glr import (
    CHI2_2_999,
    CONTINUATIONS,
    CORRECTIONS,
    SIGMA_U_RANGE,
    WINDOW_RANGE,
    GLRConfig,
    InputModel,
    input_tracker,
)
from motionsig_cli.engine import Engine, check_run_time, run_job, tasks_of, trials_per_task
from motionsig_cli.filters.consistency import Consistency
from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.maneuver.ebpsk_tracking import EbpskPositions
from motionsig_cli.maneuver.scenario import FIRST_SCAN, PRESETS, ManeuverScenario
from motionsig_cli.models.motion import (
    AIRCRAFT_SOJOURN,
    G2_FORMS,
    H_POS4,
    H_POS6,
    MU0_PAPER,
    PI_PAPER,
    Q0_RANGE,
    Q_PAPER,
    ModelSet,
    aircraft_models,
    check_distribution,
    check_transition,
    coordinated_turn_models,
    cv_input_model,
    imm_models,
    two_point_init,
)
from motionsig_cli.rng import trial_rng
from motionsig_cli.tables import Table, make_meta

__all__ = [
    "METHODS",
    "PRESETS",
    "SOURCES",
    "VIEWS",
    "DetectionSummary",
    "ErrorStats",
    "GaussianPositions",
    "MCPartial",
    "MCResult",
    "ManeuverJob",
    "ManeuverReport",
    "ManeuverScenario",
    "ManeuverStudy",
    "MeasurementSource",
    "SingularCovariance",
    "TrackerConfig",
    "Tracks",
    "detection_summary",
    "error_stats",
    "measurement_source",
    "measurement_table",
    "measurements",
    "measurements_cov",
    "monte_carlo",
    "report",
    "run_trackers",
    "track",
    "track_from",
    "two_point_init_cov",
]

METHODS = ("imm", "glr", "mlr", "cv")
"""Trackers: IMM (§IV), GLR and MLR input estimation (§II–III), and the constant-velocity KF (no detection)."""
VIEWS = ("scans", "events", "summary")
"""Tables of a Monte Carlo: per scan, per true input change, one summary row per σ and method."""
SIGMA_RANGE = (1e-3, 1e7)
"""Measurement noise σ per axis [m]: 1 mm to 10 000 km covers every sensor (σ² stays a normal double)."""
MAX_SIGMAS = 10
"""Most σ values in one Monte Carlo."""
RUNS_RANGE = (1, 1_000_000)
"""Monte Carlo runs (every run's declarations are kept for the detection statistics)."""
RESPONSE_RANGE = (1, 10_000)
"""Response window W [scans]: a declaration needs at least the scan after the change; 10 000 scans is far longer
than any maneuver's transient (declarations are then told apart by their estimated onsets alone)."""
MAX_SECONDS = 600.0
"""Largest estimated run time of a :class:`ManeuverStudy`."""
MAX_MEASUREMENT_ROWS = 1_000_000
"""Largest table of simulated records (:func:`measurement_table`)."""
IMM_Q_RANGE = (0.0, 1e6)
"""IMM acceleration-increment variances accepted [(m/s²)²]: 0 is a noise-free model; 1e6, a random acceleration
of 1 km/s² per scan, is far beyond any vehicle (and keeps q G Gᵀ far from overflow)."""


@dataclass(frozen=True)
class TrackerConfig:
    """Tracker settings (the paper's values where it gives them; the assumptions are options).

    Attributes:
        g2: form of G₂ = G₃, one of :data:`~motionsig_cli.models.motion.G2_FORMS`.
        Pi, mu0: IMM transition matrix (3 × 3, rows non-negative summing to 1) and initial model
            probabilities (3, non-negative, summing to 1).
        q0: acceleration psd q̃₀ of the GLR/MLR/CV filter [m²/s³], in
            :data:`~motionsig_cli.models.motion.Q0_RANGE` ([0, 1e6]: 0 is the exact CV model; 1e6 m²/s³, a
            velocity random walk of 1 km/s in one second, is far beyond any vehicle).
        window: GLR/MLR onset window s [scans], in :data:`~motionsig_cli.detection.glr.WINDOW_RANGE`.
        glr_threshold: GLR threshold λ on ΔJ, a finite number ≥ 0 (ΔJ is never negative; the ``cv`` method
            is the tracker that never declares).
        mlr_threshold: MLR threshold h on max_n J(n), any finite number (J is a log-likelihood ratio and
            may be negative; the paper's h is 0).
        sigma_u: MLR prior standard deviation σ_u of each input [m/s²], in
            :data:`~motionsig_cli.detection.glr.SIGMA_U_RANGE`.
        correction, continuation: see :class:`~motionsig_cli.detection.glr.GLRConfig`.
        imm_q: the IMM models' acceleration-increment variances (q₁, q₂, q₃) [(m/s²)²]: model j's process
            noise is q_j G_j G_jᵀ (:func:`~motionsig_cli.models.motion.imm_models`); default the paper's
            Q₁ = 0, Q₂ = 0.001 I, Q₃ = 0.0144 I (§IV), each in :data:`IMM_Q_RANGE`. With ``imm_model =
            "aircraft"``, the models' psds (q̃₁ [m²/s³], q̃₂, q̃₃ [m²/s⁵], each > 0:
            :func:`~motionsig_cli.models.motion.aircraft_models`).
        imm_model: ``paper`` (the paper's three models, one discrete noise per step), ``aircraft``
            (continuous-time CV and two Wiener-acceleration models for real aircraft on irregular times) or
            ``turns`` (CV and coordinated turns at ±3°/s: :func:`~motionsig_cli.models.motion.coordinated_turn_models`).
        sojourn: mean sojourn τ_i in each model [s] (``aircraft`` only; ``Pi`` is then built from it).
        sigma_floor: the smallest σ [m] an estimate from a record may give (0: none); a smaller estimate is
            raised to it (:func:`~motionsig_cli.maneuver.record.choose_sigma`).
        max_speed, max_accel: the plausibility limits of the consistency checks [m/s, m/s²]
            (:class:`~motionsig_cli.filters.consistency.Consistency`): ``paper`` 5000 m/s (its trajectory as
            printed reaches 3268 m/s) and 100 m/s²; ``aircraft`` 600 m/s (Mach 1.8 at altitude) and 100 m/s².
        declare: the IMM's declaration thresholds (on, off) on the manoeuvre probability 1 − μ_CV: a
            manoeuvre is declared when it rises above ``on`` and may be declared again once it has fallen
            below ``off`` (hysteresis), 0 < off < on < 1.

    :data:`TUNINGS` holds the two sets of defaults: ``paper`` (the class defaults) and ``aircraft`` (for
    real records; :meth:`tuned`).

    Examples:
        >>> from motionsig_cli import ConfigError, TrackerConfig
        >>> TrackerConfig(window=5, glr_threshold=20.0).glr("glr").threshold
        20.0
        >>> try:
        ...     TrackerConfig(window=0)
        ... except ConfigError as exc:
        ...     print(exc.field, exc.value)
        window 0
    """

    g2: str = "paper-fixed"
    Pi: tuple[tuple[float, ...], ...] = PI_PAPER
    mu0: tuple[float, ...] = MU0_PAPER
    q0: float = 1.0
    window: int = 10
    glr_threshold: float = CHI2_2_999
    mlr_threshold: float = 0.0
    sigma_u: float = 20.0
    correction: str = "exact"
    continuation: str = "estimate"
    imm_q: tuple[float, ...] = Q_PAPER
    imm_model: str = "paper"
    sojourn: tuple[float, ...] = AIRCRAFT_SOJOURN
    declare: tuple[float, float] = (0.9, 0.5)
    sigma_floor: float = 0.0
    max_speed: float = 5000.0
    max_accel: float = 100.0

    def __post_init__(self) -> None:
        one_of("g2", self.g2, G2_FORMS)
        one_of("imm_model", self.imm_model, ("paper", "aircraft", "turns"))
        object.__setattr__(self, "imm_q", _check_imm_q(self.imm_q))
        if self.imm_model != "paper" and min(self.imm_q) <= 0:
            raise ConfigError("imm_q", self.imm_q, "must be > 0 for every aircraft model (psds)")
        try:
            soj = tuple(float(v) for v in self.sojourn)
        except (TypeError, ValueError):
            raise ConfigError("sojourn", self.sojourn, "is not three times [s]") from None
        if len(soj) != 3 or not all(math.isfinite(v) and v > 0 for v in soj):
            raise ConfigError("sojourn", self.sojourn, "is not three mean sojourn times > 0 [s]")
        object.__setattr__(self, "sojourn", soj)
        try:
            on, off = (float(v) for v in self.declare)
        except (TypeError, ValueError):
            raise ConfigError("declare", self.declare, "is not two probabilities (on, off)") from None
        if not (0 < off < on < 1):
            raise ConfigError("declare", self.declare, "is not 0 < off < on < 1")
        object.__setattr__(self, "declare", (on, off))
        in_range("sigma_floor", self.sigma_floor, 0.0, SIGMA_RANGE[1], unit="m")
        in_range("max_speed", self.max_speed, 1e-3, 3e8, unit="m/s")
        in_range("max_accel", self.max_accel, 1e-3, 1e6, unit="m/s²")
        Pi = check_transition("Pi", self.Pi, r=3)
        mu0 = check_distribution("mu0", self.mu0, r=3)
        object.__setattr__(self, "Pi", tuple(tuple(row) for row in Pi.tolist()))
        object.__setattr__(self, "mu0", tuple(mu0.tolist()))
        in_range("q0", self.q0, *Q0_RANGE, unit="m²/s³")
        integer("window", self.window, *WINDOW_RANGE)
        if not (isinstance(self.glr_threshold, int | float) and math.isfinite(self.glr_threshold)
                and self.glr_threshold >= 0):  # fmt: skip
            raise ConfigError(
                "glr_threshold", self.glr_threshold, "is not a finite number >= 0 (ΔJ is never negative)"
            )
        in_range("mlr_threshold", self.mlr_threshold)
        in_range("sigma_u", self.sigma_u, *SIGMA_U_RANGE, unit="m/s²")
        one_of("correction", self.correction, CORRECTIONS)
        one_of("continuation", self.continuation, CONTINUATIONS)

    @classmethod
    def tuned(cls, tuning: str, **given: Any) -> TrackerConfig:
        """The defaults of ``tuning`` (a key of :data:`TUNINGS`) with the ``given`` fields over them."""
        one_of("tuning", tuning, tuple(TUNINGS))
        return cls(**{**TUNINGS[tuning], **given})

    def models(self, T: float) -> ModelSet:
        """The IMM's model set (``imm_model``) at the period T [s] (its ``steps`` give any Δt)."""
        if self.imm_model == "turns":
            return coordinated_turn_models(q=self.imm_q, sojourn=self.sojourn, mu0=self.mu0, T=T)  # type: ignore[arg-type]
        if self.imm_model == "aircraft":
            return aircraft_models(q=self.imm_q, sojourn=self.sojourn, mu0=self.mu0, T=T)  # type: ignore[arg-type]
        return imm_models(T, g2=self.g2, q=self.imm_q, Pi=np.asarray(self.Pi), mu0=np.asarray(self.mu0))  # type: ignore[arg-type]

    def consistency(self) -> Consistency:
        """The consistency checks with this configuration's plausibility limits."""
        return Consistency(max_speed=self.max_speed, max_accel=self.max_accel)

    def glr(self, method: str) -> GLRConfig:
        """The detector of ``method`` (``glr``, ``mlr`` or ``none``: the CV filter)."""
        thr = {"glr": self.glr_threshold, "mlr": self.mlr_threshold, "none": math.inf}[method]
        return GLRConfig(method=method, window=self.window, threshold=thr, sigma_u=self.sigma_u,
                         correction=self.correction, continuation=self.continuation)  # fmt: skip

    def meta(self) -> dict[str, Any]:
        """The detector settings as a record's provenance names them."""
        return {"q0": self.q0, "window": self.window, "glr_threshold": self.glr_threshold,
                "mlr_threshold": self.mlr_threshold, "sigma_u": self.sigma_u, "correction": self.correction,
                "continuation": self.continuation, "g2": self.g2, "imm_q": list(self.imm_q),
                "imm_model": self.imm_model, "sojourn": list(self.sojourn),
                "declare": list(self.declare), "sigma_floor": self.sigma_floor,
                "max_speed": self.max_speed, "max_accel": self.max_accel}  # fmt: skip


AIRCRAFT_SIGMA_FLOOR = 92.6 / 2.4477
"""The ``aircraft`` tuning's σ floor [m per axis], 37.8 m: the bound of NACp 8 (EPU < 92.6 m, the accuracy the
ADS-B mandates require), as a 95 % horizontal radius of a circular normal (÷ √(−2 ln 0.05) = 2.4477;
:func:`~motionsig_cli.surveillance.local_positions.nacp_to_sigma`). Feeds deliver smoothed or interpolated
positions whose scatter estimates σ at 0.001–14 m on the test data's five flights, below what the
position's own accuracy category guarantees."""

TUNINGS: dict[str, dict[str, Any]] = {
    "paper": {},
    "aircraft": {
        "imm_model": "turns",
        "imm_q": (1.0, 5.0, 5.0),
        "declare": (0.8, 0.5),
        "q0": 0.5,
        "window": 20,
        "glr_threshold": 40.0,
        "mlr_threshold": 15.0,
        "sigma_u": 10.0,
        "sigma_floor": AIRCRAFT_SIGMA_FLOOR,
        "max_speed": 600.0,
    },
}
"""Tracker defaults: ``paper`` (the paper's values and this project's reading of the unstated ones: the
class defaults, used for the paper's scenario) and ``aircraft`` (for real records: every model with process
noise, the thresholds set for a false-alarm rate on real straight flight — measured in the notebook
*Tracking a real flight*). The aircraft IMM is CV and coordinated turns at ±3°/s (psds 1, 5, 5 m²/s³,
declaring at 1 − μ_CV > 0.8): on the five real flights of the test data it finds 87 of 113 turns (77 %) at
5.7 false alarms per hour, against 81 (72 %) at 14.4/h for CV with two Wiener-acceleration models
(:func:`~motionsig_cli.models.motion.aircraft_models`, ``imm_model="aircraft"``) — chosen on these flights."""


def _check_imm_q(q: Any) -> tuple[float, ...]:
    """Three acceleration-increment variances, one per IMM model, each in :data:`IMM_Q_RANGE`."""
    try:
        vals = tuple(float(v) for v in q)
    except (TypeError, ValueError):
        raise ConfigError("imm_q", q, "is not three variances (one per IMM model: CV, CA, CA)") from None
    if len(vals) != 3:
        raise ConfigError("imm_q", vals, "is not three variances (one per IMM model: CV, CA, CA)")
    for v in vals:
        in_range("imm_q", v, *IMM_Q_RANGE, unit="(m/s²)²")
    return vals


def _check_sigma(field_name: str, sigma: float) -> float:
    return in_range(field_name, sigma, *SIGMA_RANGE, unit="m")


def _check_methods(methods: Sequence[str]) -> None:
    if not methods:
        raise ConfigError("methods", tuple(methods), f"is empty; choose from {', '.join(METHODS)}")
    for m in methods:
        one_of("methods", m, METHODS)


# ------------------------------------------------------------------------------- measurement sources
class MeasurementSource(Protocol):
    """What feeds the trackers: the measurement records of a batch of runs, made from the truth.

    A source draws run r's randomness only from the generator it gets for that run (``trial_rng(seed, r)``,
    the run's seed child), so run r's record does not depend on the other runs. Register a new source in
    :data:`SOURCES`.
    """

    name: ClassVar[str]
    seeding: ClassVar[str]
    """How run r's draws are made (the tables' provenance)."""

    def measure(self, truth: np.ndarray, sigma: float, rngs: Sequence[np.random.Generator]) -> np.ndarray:
        """Position measurements z (B, N, 2) of B runs at scans 1..N.

        Args:
            truth: (N, 4) true states [x, ẋ, y, ẏ] at scans 1..N.
            sigma: measurement noise σ per axis [m] (the trackers assume R = σ² I).
            rngs: one generator per run, the run's seed child.
        """
        ...

    def measure_cov(
        self, truth: np.ndarray, sigma: float, rngs: Sequence[np.random.Generator]
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """The measurements z (B, N, 2) and their covariances R (B, N, 2, 2), or None when the trackers are to
        assume R = σ² I (NaN rows of z: missed scans)."""
        ...


@dataclass(frozen=True)
class GaussianPositions:
    """Cartesian position measurements: z = true position + σ w, w ~ N(0, I) (N, 2) per run (§V)."""

    name: ClassVar[str] = "gaussian"
    seeding: ClassVar[str] = (
        "run r draws w_r ~ N(0, I) (scans x 2) from SeedSequence(seed).spawn(...)[r]; z = truth + σ w_r "
        "(the same w_r for every σ and method)"
    )

    def measure(self, truth: np.ndarray, sigma: float, rngs: Sequence[np.random.Generator]) -> np.ndarray:
        """z (B, N, 2) = truth position + σ w_r, w_r = ``rngs[r].standard_normal((N, 2))``."""
        n = truth.shape[0]
        pos = truth[:, [0, 2]]
        w = np.stack([g.standard_normal((n, 2)) for g in rngs]) if len(rngs) else np.zeros((0, n, 2))
        return pos[None] + sigma * w

    def measure_cov(
        self, truth: np.ndarray, sigma: float, rngs: Sequence[np.random.Generator]
    ) -> tuple[np.ndarray, None]:
        """(:meth:`measure`, None): the trackers assume R = σ² I."""
        return self.measure(truth, sigma, rngs), None


SOURCES: dict[str, MeasurementSource] = {s.name: s for s in (GaussianPositions(), EbpskPositions())}
"""The measurement sources by name (``ebpsk``: the front end with its defaults, calibrated to σ): add a
member here. A job may also carry a configured source instance (:attr:`ManeuverJob.source`)."""

Source = str | MeasurementSource
"""A registered source's name or a configured source."""


def measurement_source(name: Source) -> MeasurementSource:
    """The registered source ``name`` (:class:`ConfigError` on ``source`` if there is none), or ``name`` itself
    when it is a source."""
    if not isinstance(name, str):
        return name
    return SOURCES[one_of("source", name, tuple(SOURCES))]


def measurements(
    sc: ManeuverScenario, sigma: float, runs: Sequence[int], seed: int, source: Source = "gaussian"
) -> np.ndarray:
    """z (B, N, 2) of runs ``runs`` from ``source`` (default: truth position + σ w_r, w_r from
    ``trial_rng(seed, r)``)."""
    return measurements_cov(sc, sigma, runs, seed, source)[0]


def measurements_cov(
    sc: ManeuverScenario, sigma: float, runs: Sequence[int], seed: int, source: Source = "gaussian"
) -> tuple[np.ndarray, np.ndarray | None]:
    """z (B, N, 2) and R (B, N, 2, 2) or None (R = σ² I) of runs ``runs`` from ``source``."""
    _check_sigma("sigma", sigma)
    src = measurement_source(source)
    return src.measure_cov(sc.truth(), sigma, [trial_rng(seed, int(r)) for r in runs])


def two_point_init_cov(
    z_a: np.ndarray, z_b: np.ndarray, R_a: np.ndarray, R_b: np.ndarray, T: float, n: int = 6
) -> tuple[np.ndarray, np.ndarray]:
    """Two-point differencing with measurement covariances R_a, R_b (B, 2, 2) of z_a, z_b (B, 2), T apart:
    the state of :func:`~motionsig_cli.models.motion.two_point_init` and its exact covariance, position R_b,
    position–velocity R_b/T, velocity (R_a + R_b)/T² (the paper's P(2/2), §IV, with R(1), R(2) for δ² I)."""
    x, _ = two_point_init(z_a, z_b, T, 1.0, n=n)
    B = x.shape[0]
    pos, vel = [0, 2], [1, 3]
    P = np.zeros((B, n, n))
    P[:, np.ix_(pos, pos)[0], np.ix_(pos, pos)[1]] = R_b
    P[:, np.ix_(pos, vel)[0], np.ix_(pos, vel)[1]] = R_b / T
    P[:, np.ix_(vel, pos)[0], np.ix_(vel, pos)[1]] = R_b / T
    P[:, np.ix_(vel, vel)[0], np.ix_(vel, vel)[1]] = (R_a + R_b) / (T * T)
    return x, P


@dataclass(frozen=True)
class Tracks:
    """One tracker's output on B runs for scans 3..N.

    Attributes:
        state: (B, N−2, 6) estimates [x, ẋ, y, ẏ, a_x, a_y] (the acceleration is the IMM's combined estimate
            or the GLR/MLR tracker's current input estimate; 0 for the CV filter).
        mu: (B, N−2, r) IMM model probabilities (None for the other trackers).
        detected, onset, u_jump: GLR/MLR declarations (onset as an absolute scan number, −1 if none).
        stat: (B, N−2) the maximum detection statistic of each scan (GLR/MLR).
    """

    state: np.ndarray
    mu: np.ndarray | None = None
    detected: np.ndarray | None = None
    onset: np.ndarray | None = None
    u_jump: np.ndarray | None = None
    stat: np.ndarray | None = None

    @property
    def pos(self) -> np.ndarray:
        """(B, N−2, 2) estimated positions."""
        return self.state[..., [0, 2]]


def track(
    method: str, z: np.ndarray, T: float, sigma: float, cfg: TrackerConfig, *, R: np.ndarray | None = None
) -> Tracks:
    """Run one tracker on measurement records z (B, N, 2) of scans 1..N (two-point initialisation on scans
    1 and 2, which must be measured; a NaN later is a missed scan, a predict-only step). ``R`` (B, N, 2, 2):
    the measurements' covariance per run and scan (None: σ² I)."""
    z = np.asarray(z, float)
    if z.ndim != 3 or z.shape[1] < 3 or z.shape[2] != 2:
        raise ValueError(f"z must be (runs, scans >= 3, 2); got shape {z.shape}")
    if R is None:
        return track_from(method, z[:, 0], z[:, 1], z[:, 2:], T, sigma, cfg)
    R = np.asarray(R, float)
    if R.shape != (*z.shape, 2):
        raise ValueError(f"R must be {(*z.shape, 2)}; got shape {R.shape}")
    return track_from(
        method, z[:, 0], z[:, 1], z[:, 2:], T, sigma, cfg, R=R[:, 2:], init_R=(R[:, 0], R[:, 1])
    )


def track_from(
    method: str,
    z_a: np.ndarray,
    z_b: np.ndarray,
    z: np.ndarray,
    T: float,
    sigma: float,
    cfg: TrackerConfig,
    *,
    init_gap: int = 1,
    first_scan: int = FIRST_SCAN,
    R: np.ndarray | None = None,
    init_R: tuple[np.ndarray, np.ndarray] | None = None,
) -> Tracks:
    """Run one tracker from a two-point initialisation on ``z_a``, ``z_b`` (B, 2), ``init_gap`` scans apart,
    over the following scans z (B, N, 2) (NaN rows: missed scans, predict-only).

    The velocity of the initialisation is (z_b − z_a)/(init_gap T) and its covariance that of
    :func:`~motionsig_cli.models.motion.two_point_init` with the period init_gap·T (the two measured scans
    nearest the start need not be adjacent). ``first_scan`` is the scan number of z[:, 0]: the declared
    onsets are returned in that numbering.

    ``R`` (B, N, 2, 2) gives the covariance of every measurement of z (time-varying R: the trackers use it
    in place of σ² I) and ``init_R`` the covariances of z_a and z_b (the initial covariance of
    :func:`two_point_init_cov`); both or neither.
    """
    one_of("method", method, METHODS)
    integer("init_gap", init_gap, 1)
    z = np.asarray(z, float)
    if z.ndim != 3 or z.shape[2] != 2 or z.shape[1] < 1:
        raise ValueError(f"z must be (runs, scans >= 1, 2); got shape {z.shape}")
    if (R is None) != (init_R is None):
        raise ValueError("give R and init_R together")
    R_scan = R
    R = sigma * sigma * np.eye(2)
    T_init = T if init_gap == 1 else init_gap * T
    if method == "imm":
        ms = imm_models(T, g2=cfg.g2, q=cfg.imm_q, Pi=np.asarray(cfg.Pi), mu0=np.asarray(cfg.mu0))
        if init_R is None:
            x0, P0 = two_point_init(z_a, z_b, T_init, sigma, n=6)
        else:
            x0, P0 = two_point_init_cov(z_a, z_b, *init_R, T_init, n=6)
        tr = imm_filter(z, H_POS6, R if R_scan is None else R_scan, ms, x0, P0)
        return Tracks(tr.x, mu=tr.mu)
    F, G, Q = cv_input_model(T, cfg.q0)
    if init_R is None:
        x0, P0 = two_point_init(z_a, z_b, T_init, sigma, n=4)
    else:
        x0, P0 = two_point_init_cov(z_a, z_b, *init_R, T_init, n=4)
    it = input_tracker(
        z, InputModel(F, G, Q, H_POS4, R), x0, P0, cfg.glr("none" if method == "cv" else method), R=R_scan
    )
    state = np.concatenate([it.x, it.u_cur], axis=-1)
    if method == "cv":
        return Tracks(state)
    onset = np.where(it.onset >= 0, it.onset + first_scan, -1)  # local index 0 is scan first_scan
    return Tracks(state, detected=it.detected, onset=onset, u_jump=it.u_jump, stat=it.stat)


def run_trackers(
    sc: ManeuverScenario,
    sigma: float,
    runs: Sequence[int],
    seed: int,
    methods: Sequence[str],
    cfg: TrackerConfig,
    source: Source = "gaussian",
) -> dict[str, Tracks]:
    """All requested trackers on the same runs (measurements from ``source``, with their covariances R(k)
    when the source gives them)."""
    z, R = measurements_cov(sc, sigma, runs, seed, source)
    return {m: track(m, z, sc.T, sigma, cfg, R=R) for m in methods}


@dataclass(frozen=True)
class MCResult:
    """One tracker's Monte Carlo result at one σ.

    Attributes:
        stats: eqs (14)–(15) and the RMS error per scan.
        track0: (N−2, 2) the estimated track of run 0 (Fig 2).
        mu: (N−2, r) mean IMM model probabilities, or None.
        detected, onset: (M, N−2) GLR/MLR declarations and onset estimates, or None.
    """

    stats: ErrorStats
    track0: np.ndarray
    mu: np.ndarray | None
    detected: np.ndarray | None
    onset: np.ndarray | None


class SingularCovariance(ConfigError, np.linalg.LinAlgError):
    """A covariance stopped being positive definite in floating point at this σ: a bad σ/T combination,
    reported as a bad ``sigma``. Picklable, so it crosses process boundaries intact."""

    def __init__(self, sigma: float, T: float) -> None:
        super().__init__(
            "sigma",
            sigma,
            f"m is too small for the motion over T = {T:g} s: the innovation covariance is numerically "
            "singular (increase σ or decrease T)",
        )
        self.sigma, self.T = sigma, T

    def __reduce__(self) -> tuple[type[SingularCovariance], tuple[float, float]]:
        return SingularCovariance, (self.sigma, self.T)


@contextlib.contextmanager
def _numerics(sigma: float, T: float) -> Iterator[None]:
    """A covariance that stops being positive definite in floating point is a bad σ/T combination, not a bug."""
    try:
        yield
    except np.linalg.LinAlgError as exc:
        if isinstance(exc, SingularCovariance):
            raise
        raise SingularCovariance(sigma, T) from None


@dataclass(frozen=True)
class ManeuverJob:
    """A Monte Carlo (a :class:`~motionsig_cli.engine.MonteCarloJob`): runs 0..runs−1 of every σ, measured
    by ``source`` and tracked by ``methods``.

    A task is ``(σ index, range of runs)``; :meth:`tasks` chunks the runs into tasks of :meth:`runs_per_task`
    runs (``chunk``, or from the cost model), never from the number of workers, so the floating-point sums —
    added in task order by :meth:`reduce` — are the same however the tasks are spread.

    Attributes:
        sigmas: measurement noise σ per axis [m], each in :data:`SIGMA_RANGE`, at most :data:`MAX_SIGMAS`.
        runs: Monte Carlo runs, in :data:`RUNS_RANGE`.
        seed: root seed (≥ 0); run r draws from ``trial_rng(seed, r)``.
        methods: trackers, among :data:`METHODS`.
        source: the measurement source, a key of :data:`SOURCES` or a configured source (e.g.
            :class:`~motionsig_cli.maneuver.ebpsk_tracking.EbpskPositions` with its radar).
        chunk: runs per task (None: from :func:`cost`).
        quiet_fp: run the trackers and the reduction under ``np.errstate(all="ignore")``.
    """

    name: ClassVar[str] = "maneuver"

    sc: ManeuverScenario
    sigmas: tuple[float, ...]
    runs: int
    seed: int
    methods: tuple[str, ...]
    cfg: TrackerConfig
    source: Source = "gaussian"
    chunk: int | None = None
    quiet_fp: bool = False

    def __post_init__(self) -> None:
        if not self.sigmas:
            raise ConfigError("sigmas", tuple(self.sigmas), "is empty; give at least one σ")
        if len(self.sigmas) > MAX_SIGMAS:
            raise ConfigError("sigmas", tuple(self.sigmas), f"has more than {MAX_SIGMAS} values")
        for s in self.sigmas:
            _check_sigma("sigmas", s)
        integer("runs", self.runs, *RUNS_RANGE)
        integer("seed", self.seed, 0)
        _check_methods(self.methods)
        measurement_source(self.source)
        if self.chunk is not None:
            integer("chunk", self.chunk, 1)

    def runs_per_task(self) -> int:
        """``chunk``, or runs per task worth at least the engine's minimum task time *and* 4× the per-batch
        overhead of :func:`cost` (the trackers' Python loop over scans), so that chunking costs ≤ 25 % extra;
        at most 250 runs (bounded memory). Scales with ``$MOTIONSIG_MIN_TASK_SECONDS`` (tests: 1 run)."""
        if self.chunk is not None:
            return self.chunk
        fixed = cost(self.sc.scans, 0, self.methods, 1)
        per_run = cost(self.sc.scans, 1, self.methods, 1) - fixed + self._source_seconds(1)
        return trials_per_task(per_run, fixed_seconds=fixed, at_most=250)

    def _source_seconds(self, runs: int) -> float:
        """The source's own cost for ``runs`` runs at one σ (0 for the Gaussian source)."""
        per = getattr(measurement_source(self.source), "seconds_per_run", None)
        return 0.0 if per is None else runs * per(self.sc.scans)

    def seconds(self) -> float:
        """Estimated run time [s]: :func:`cost` plus the source's measurements."""
        return cost(self.sc.scans, self.runs, self.methods, len(self.sigmas)) + len(self.sigmas) * (
            self._source_seconds(self.runs)
        )

    def tasks(self) -> list[tuple[int, range]]:
        """(σ index, runs) in σ order, runs in increasing order within a σ."""
        per_task = self.runs_per_task()
        return [(i, r) for i in range(len(self.sigmas)) for r in tasks_of(self.runs, per_task)]

    def task_size(self, task: tuple[int, range]) -> int:
        """Runs in ``task``."""
        return len(task[1])

    def identity(self) -> dict[str, Any]:
        """Everything the task results depend on (JSON values), for a checkpoint's manifest."""
        return {
            "scenario": {
                "preset": self.sc.preset,
                "T": self.sc.T,
                "scans": self.sc.scans,
                "p0": list(self.sc.p0),
            },
            "sigmas": list(self.sigmas),
            "runs": self.runs,
            "seed": self.seed,
            "methods": list(self.methods),
            "tracker": asdict(self.cfg),
            "source": self.source if isinstance(self.source, str) else self.source.identity(),
            "runs_per_task": self.runs_per_task(),
        }

    def _fp(self) -> contextlib.AbstractContextManager[Any]:
        return np.errstate(all="ignore") if self.quiet_fp else contextlib.nullcontext()

    def run_task(self, task: tuple[int, range]) -> dict[str, MCPartial]:
        """Every tracker on the task's runs at σ = ``sigmas[i]``: per tracker, the sums of the errors."""
        i, runs = task
        sigma = self.sigmas[i]
        truth = self.sc.truth()[FIRST_SCAN - 1 :, [0, 2]]
        with _numerics(sigma, self.sc.T), self._fp():
            tracks = run_trackers(self.sc, sigma, runs, self.seed, self.methods, self.cfg, self.source)
            out = {}
            for m, tr in tracks.items():
                err = truth[None] - tr.pos
                out[m] = MCPartial(
                    err.sum(axis=0),
                    (err * err).sum(axis=0),
                    None if tr.mu is None else tr.mu.sum(axis=0),
                    tr.pos[0] if runs.start == 0 and len(runs) else None,
                    tr.detected,
                    tr.onset,
                )
        return out

    def reduce(
        self, tasks: Sequence[tuple[int, range]], results: Sequence[dict[str, MCPartial]]
    ) -> dict[float, dict[str, MCResult]]:
        """Per σ and tracker, the Monte Carlo result: the tasks' sums added in task order (eqs 14–15)."""
        per_sigma: list[list[dict[str, MCPartial]]] = [[] for _ in self.sigmas]
        for (i, _), part in zip(tasks, results, strict=True):
            per_sigma[i].append(part)
        with self._fp():
            return {
                sigma: {m: self._result([part[m] for part in parts]) for m in self.methods}
                for sigma, parts in zip(self.sigmas, per_sigma, strict=True)
            }

    def _result(self, parts: Sequence[MCPartial]) -> MCResult:
        """One tracker's result at one σ from its tasks' sums, in task order."""
        n = self.runs
        n_scan = self.sc.scans - FIRST_SCAN + 1
        s1, s2 = np.zeros((n_scan, 2)), np.zeros((n_scan, 2))
        mu = track0 = None
        det, on = [], []
        for p in parts:
            s1 += p.s1
            s2 += p.s2
            if p.mu is not None:
                mu = p.mu if mu is None else mu + p.mu
            if track0 is None:
                track0 = p.track0
            if p.detected is not None:
                det.append(p.detected)
                on.append(p.onset)
        mean = s1 / n  # eq (14)
        msq = s2 / n
        sd = np.sqrt(np.maximum(msq - mean * mean, 0.0))  # eq (15)
        stats = ErrorStats(np.arange(FIRST_SCAN, self.sc.scans + 1), mean, sd, np.sqrt(msq.sum(axis=1)))
        return MCResult(stats, track0, None if mu is None else mu / n,
                        np.concatenate(det) if det else None, np.concatenate(on) if on else None)  # fmt: skip


@dataclass(frozen=True)
class MCPartial:
    """One tracker's sums over the runs of one task (error = truth − estimate, scans 3..N).

    Attributes:
        s1, s2: (N−2, 2) Σ e and Σ e² over the task's runs.
        mu: (N−2, r) Σ IMM model probabilities, or None.
        track0: (N−2, 2) run 0's estimated track if the task holds run 0, else None.
        detected, onset: (runs, N−2) GLR/MLR declarations, or None.
    """

    s1: np.ndarray
    s2: np.ndarray
    mu: np.ndarray | None
    track0: np.ndarray | None
    detected: np.ndarray | None
    onset: np.ndarray | None


def monte_carlo(
    sc: ManeuverScenario,
    sigma: float,
    n_runs: int,
    seed: int,
    methods: Sequence[str],
    cfg: TrackerConfig,
    *,
    chunk: int = 250,
    on_chunk: Callable[[int], None] | None = None,
    engine: Engine | None = None,
    source: Source = "gaussian",
) -> dict[str, MCResult]:
    """Runs 0..n_runs−1 at one σ in chunks of ``chunk`` runs (memory stays bounded) on ``engine`` (default:
    in this process); sums of errors are accumulated in chunk order, so the result does not depend on the
    engine, and on the chunk size only through floating-point summation order. ``on_chunk`` gets each
    finished chunk's number of runs."""
    job = ManeuverJob(sc, (sigma,), n_runs, seed, tuple(methods), cfg, source=source, chunk=chunk)
    return run_job(job, engine, progress=on_chunk)[sigma]


def cost(scans: int, runs: int, methods: Sequence[str], n_sigma: int) -> float:
    """Rough run time [s] on a 2-core machine: a per-scan loop overhead of ~0.25 ms per method plus ~15 µs per
    run-scan for the IMM, GLR and MLR and ~6 µs for the CV filter (measured: ``make bench``)."""
    per_run = sum(6e-6 if m == "cv" else 15e-6 for m in methods)
    return n_sigma * scans * (0.25e-3 * len(methods) + per_run * runs)


@dataclass(frozen=True)
class ErrorStats:
    """Per-scan error statistics over M runs (truth − estimate), scans 3..N.

    Attributes:
        scan: (N−2,) scan numbers.
        mean: (N−2, 2) ē_x, ē_y, eq (14).
        sd: (N−2, 2) σ_x̂, σ_ŷ, eq (15) (1/M normalisation as printed).
        rms: (N−2,) RMS position error √(mean over runs of e_x² + e_y²).
    """

    scan: np.ndarray
    mean: np.ndarray
    sd: np.ndarray
    rms: np.ndarray


def error_stats(sc: ManeuverScenario, pos: np.ndarray) -> ErrorStats:
    """Eqs (14)–(15) and the RMS position error of estimates pos (M, N−2, 2)."""
    truth = sc.truth()[FIRST_SCAN - 1 :, [0, 2]]
    err = truth[None] - pos  # truth − estimate (eq 14 sign)
    mean = err.mean(axis=0)  # ē(k), eq (14)
    msq = (err * err).mean(axis=0)
    sd = np.sqrt(np.maximum(msq - mean * mean, 0.0))  # σ(k), eq (15)
    rms = np.sqrt(msq.sum(axis=1))
    return ErrorStats(np.arange(FIRST_SCAN, sc.scans + 1), mean, sd, rms)


@dataclass(frozen=True)
class DetectionSummary:
    """Detection performance of a GLR/MLR tracker over M runs.

    Attributes:
        events: one row per true input change: (onset scan, jump (u_x, u_y), fraction of runs detected,
            mean and median delay [scans after the onset], mean and RMS onset-estimate error [scans]).
        false_alarms_per_1000: declarations per 1000 non-maneuvering scans (scans whose last ``response``
            intervals had zero input), with its binomial-style standard error.
        quiet_scans: number of such scans per run.
        other: declarations neither attributed to a change nor in a non-maneuvering scan, per run.
        response: W, a declaration at scan k can be attributed to a change n with n < k ≤ n + W.
    """

    events: list[tuple[int, tuple[float, float], float, float, float, float, float]]
    false_alarms_per_1000: float
    false_alarms_se: float
    quiet_scans: int
    other: float
    response: int


def detection_summary(
    sc: ManeuverScenario, detected: np.ndarray, onset: np.ndarray, response: int
) -> DetectionSummary:
    """Attribute each declaration (``detected``, ``onset``: (M, N−2) for scans 3..N) to a true input change
    or count it as a false alarm.

    A declaration at scan k with onset estimate n̂ is attributed, among the changes n with n < k ≤ n + W, to the
    one nearest to n̂ (ties to the later change): two changes a few scans apart (the end of turn 1 at 300 and
    the start of turn 2 at 305) are then told apart by the estimated onset, not by the declaration scan.
    """
    integer("response", response, *RESPONSE_RANGE)
    M = detected.shape[0]
    scans = np.arange(FIRST_SCAN, sc.scans + 1)
    ev = sc.events()
    owner = np.full(detected.shape, -1)  # change attributed to each declaration (−1: none)
    best = np.full(detected.shape, np.inf)
    near_event = np.zeros(scans.size, dtype=bool)
    for i, (n, _) in enumerate(ev):
        eligible = (scans > n) & (scans <= n + response)
        near_event |= eligible
        dist = np.where(detected & eligible[None], np.abs(onset - n), np.inf)
        take = np.isfinite(dist) & (dist <= best)
        owner[take], best[take] = i, dist[take]
    u = sc.inputs()
    moving = np.array([np.any(u[max(k - 1 - response, 0) : k - 1] != 0) for k in scans])
    quiet = ~near_event & ~moving
    rows = []
    for i, (n, du) in enumerate(ev):
        mine = owner == i
        hit = mine.any(axis=1)
        first = np.argmax(mine, axis=1)
        delay = scans[first[hit]] - n
        onset_err = onset[np.flatnonzero(hit), first[hit]] - n
        rows.append((n, du, float(hit.mean()),
                     float(delay.mean()) if hit.any() else math.nan,
                     float(np.median(delay)) if hit.any() else math.nan,
                     float(onset_err.mean()) if hit.any() else math.nan,
                     float(np.sqrt(np.mean(onset_err**2.0))) if hit.any() else math.nan))  # fmt: skip
    n_quiet = int(quiet.sum())
    fa = detected[:, quiet]
    rate = float(fa.mean()) if n_quiet else math.nan
    per_run = fa.sum(axis=1) if n_quiet else np.zeros(M)
    se = float(per_run.std(ddof=1) / math.sqrt(M) / n_quiet) if (n_quiet and M > 1) else math.nan
    other = float((detected & (owner < 0) & ~quiet[None]).sum() / M)
    return DetectionSummary(rows, 1000 * rate, 1000 * se, n_quiet, other, response)


# ------------------------------------------------------------------------------------------ reports
@dataclass(frozen=True)
class ManeuverStudy:
    """What the command asks for: the Monte Carlo ``job`` and the view of its results.

    Attributes:
        view: one of :data:`VIEWS`; ``events`` needs ``glr`` or ``mlr`` among the job's methods.
        response: W [scans], in :data:`RESPONSE_RANGE`: a declaration at scan k can be attributed to a
            change n with n < k ≤ n + W (:func:`detection_summary`).
        max_seconds: the largest estimated run time (:func:`cost`) accepted.
    """

    job: ManeuverJob
    view: str = "scans"
    response: int = 30
    max_seconds: float = MAX_SECONDS

    def __post_init__(self) -> None:
        one_of("view", self.view, VIEWS)
        integer("response", self.response, *RESPONSE_RANGE)
        job = self.job
        if self.view == "events" and not {"glr", "mlr"} & set(job.methods):
            raise ConfigError("view", self.view, "needs glr or mlr among the methods")
        what = f"runs ({job.sc.scans} scans x {len(job.sigmas)} σ x {len(job.methods)} methods) "
        check_run_time("runs", job.runs, job.seconds(), self.max_seconds, what=what)


@dataclass(frozen=True)
class ManeuverReport:
    """A study's results for people: the table, a one-line summary and the figures' data.

    Attributes:
        table: the view's table with its provenance.
        note: the RMS position error of every σ and method, one line.
        track_figure: keyword arguments of :func:`motionsig_cli.plotting.maneuver_figure` (the first
            method: Figs 2–4 of the paper and the IMM model probabilities).
        compare_figure: keyword arguments of :func:`motionsig_cli.plotting.maneuver_comparison_figure`.
    """

    table: Table
    note: str
    track_figure: dict[str, Any]
    compare_figure: dict[str, Any]


def _cell(v: float | None) -> float | None:
    """An undefined statistic (no detection, one run) is an empty cell, not 'nan'."""
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else v


def _phase_rms(sc: ManeuverScenario, st: ErrorStats) -> list[float]:
    """RMS position error over each phase of :meth:`ManeuverScenario.phases`."""
    out = []
    for _, a, b in sc.phases():
        sel = (st.scan >= a) & (st.scan < b)
        out.append(float(np.sqrt(np.mean(st.rms[sel] ** 2))) if sel.any() else math.nan)
    return out


Results = dict[float, dict[str, MCResult]]
Rows = tuple[tuple[str, ...], list[tuple[Any, ...]]]


def _scan_rows(sc: ManeuverScenario, results: Results, methods: Sequence[str], response: int) -> Rows:
    """Per σ, method and scan: eqs (14)–(15), the RMS error, mean model probabilities, declaration rate."""
    cols = ("sigma", "method", "scan", "ebar_x", "ebar_y", "sd_x", "sd_y", "rms_pos", "mu_1", "mu_2", "mu_3",
            "declared")  # fmt: skip
    rows: list[tuple[Any, ...]] = []
    for s, r in results.items():
        for m in methods:
            st, mu, det = r[m].stats, r[m].mu, r[m].detected
            rate = det.mean(axis=0) if det is not None else None
            for i, k in enumerate(st.scan):
                rows.append((s, m, int(k), float(st.mean[i, 0]), float(st.mean[i, 1]), float(st.sd[i, 0]),
                             float(st.sd[i, 1]), float(st.rms[i]),
                             *((float(v) for v in mu[i]) if mu is not None else (None, None, None)),
                             float(rate[i]) if rate is not None else None))  # fmt: skip
    return cols, rows


def _event_rows(sc: ManeuverScenario, results: Results, methods: Sequence[str], response: int) -> Rows:
    """Per σ, detecting method and true input change: detection fraction, delay and onset error."""
    cols = ("sigma", "method", "onset_scan", "du_x", "du_y", "runs", "detected", "mean_delay", "median_delay",
            "mean_onset_error", "rms_onset_error")  # fmt: skip
    rows: list[tuple[Any, ...]] = []
    for s, r in results.items():
        for m in methods:
            if r[m].detected is None:
                continue
            d = detection_summary(sc, r[m].detected, r[m].onset, response)
            n_runs = r[m].detected.shape[0]
            for n, du, frac, md, med, oe, roe in d.events:
                rows.append((s, m, n, du[0], du[1], n_runs, frac, *map(_cell, (md, med, oe, roe))))
    return cols, rows


def _summary_rows(sc: ManeuverScenario, results: Results, methods: Sequence[str], response: int) -> Rows:
    """One row per σ and method: RMS error per phase, false alarms, detection and delay of each change."""
    names = [p for p, _, _ in sc.phases()]
    ev = sc.events()
    cols = ("sigma", "method", *(f"rms_{p.replace(' ', '')}" for p in names), "false_alarms_per_1000",
            "false_alarms_se", "quiet_scans", "other_per_run",
            *(f"detected_{n}" for n, _ in ev), *(f"delay_{n}" for n, _ in ev))  # fmt: skip
    rows: list[tuple[Any, ...]] = []
    for s, r in results.items():
        for m in methods:
            ph = _phase_rms(sc, r[m].stats)
            if r[m].detected is None:
                rows.append((s, m, *ph, None, None, None, None, *(None for _ in ev), *(None for _ in ev)))
                continue
            d = detection_summary(sc, r[m].detected, r[m].onset, response)
            rows.append((s, m, *map(_cell, ph), _cell(d.false_alarms_per_1000), _cell(d.false_alarms_se),
                         d.quiet_scans, d.other, *(e[2] for e in d.events), *(_cell(e[3]) for e in d.events)))  # fmt: skip
    return cols, rows


_VIEW_ROWS: dict[str, Callable[[ManeuverScenario, Results, Sequence[str], int], Rows]] = {
    "scans": _scan_rows,
    "events": _event_rows,
    "summary": _summary_rows,
}


def _source_meta(job: ManeuverJob) -> dict[str, Any]:
    """The measurements' provenance: for the Gaussian source the line it always had; for a front end its
    parameters."""
    src = measurement_source(job.source)
    if src.name == "gaussian":
        return {"radar": "the EBPSK parameters of Table I of Yao, Teng & Wu, Maneuvering Target Tracking Based on "
                "EBPSK Modulated JRC System (f_c 10 GHz, 100 MHz IF, f_s 1 GHz, K = 2, N = 7) do not enter the "
                "trackers"}  # fmt: skip
    meta = getattr(src, "meta", None)
    return {
        "radar": f"measurements from the '{src.name}' front end; the trackers use its covariance R(k) per scan",
        "front_end": meta(job.sc.truth(), job.sigmas) if meta is not None else src.name,
    }


def report(study: ManeuverStudy, results: Results) -> ManeuverReport:
    """The table of ``study.view``, its provenance, the summary line and the figures' data, from the job's
    result (:meth:`ManeuverJob.reduce`)."""
    job = study.job
    sc, cfg, methods = job.sc, job.cfg, job.methods
    ms = imm_models(sc.T, g2=cfg.g2, q=cfg.imm_q, Pi=np.asarray(cfg.Pi), mu0=np.asarray(cfg.mu0))
    cols, rows = _VIEW_ROWS[study.view](sc, results, methods, study.response)
    meta = make_meta(
        "maneuver",
        view=study.view,
        methods=list(methods),
        sigma=list(job.sigmas),
        runs=job.runs,
        seed=job.seed,
        seeding=measurement_source(job.source).seeding,
        scenario={
            "preset": sc.preset,
            "T": sc.T,
            "scans": sc.scans,
            "p0": list(sc.p0),
            "v0": list(sc.v0),
            "segments [from, to) scans, u_x, u_y": [list(x) for x in sc.segments],
            "kinematics": "exact constant acceleration over each interval; noise-free truth",
        },
        imm={
            "G2": cfg.g2,
            "transition": ms.Pi.tolist(),
            "mu0": ms.mu0.tolist(),
            "Q": list(cfg.imm_q),
            "models": list(ms.names),
            "init": "two-point differencing at scan 2",
        },
        glr={
            "q0": cfg.q0,
            "window": cfg.window,
            "threshold": cfg.glr_threshold,
            "correction": cfg.correction,
            "continuation": cfg.continuation,
        },
        mlr={"sigma_u": cfg.sigma_u, "threshold": cfg.mlr_threshold},
        response_window=study.response,
        first_scan=FIRST_SCAN,
        error_sign="truth - estimate (eq 14); sd with 1/M (eq 15)",
        **_source_meta(job),
    )
    scan = np.arange(FIRST_SCAN, sc.scans + 1)
    events = tuple(n for n, _ in sc.events())
    first = methods[0]
    per = [
        (s, r[first].track0, r[first].stats.mean, r[first].stats.sd, r[first].mu) for s, r in results.items()
    ]
    track_figure = {"truth": sc.truth(), "scan": scan, "per_sigma": per, "method": first.upper(),
                    "model_names": ms.names if first == "imm" else (), "events": events}  # fmt: skip
    rms = {(s, m): r[m].stats.rms for s, r in results.items() for m in methods}
    rate = {(s, m): r[m].detected.mean(axis=0) for s, r in results.items() for m in methods
            if r[m].detected is not None}  # fmt: skip
    note = "; ".join(
        f"σ={s:g} {m} RMS {np.sqrt(np.mean(r[m].stats.rms ** 2)):.0f} m"
        for s, r in results.items()
        for m in methods
    )
    return ManeuverReport(
        Table(columns=cols, rows=rows, meta=meta),
        note,
        track_figure,
        {"scan": scan, "rms": rms, "rate": rate, "events": events},
    )


def measurement_table(job: ManeuverJob) -> Table:
    """The simulated records of the job's runs (every σ), one row per run and scan, with the truth: the input
    of :func:`motionsig_cli.maneuver.record.track_record`. At most :data:`MAX_MEASUREMENT_ROWS`
    rows."""
    sc = job.sc
    if job.runs * sc.scans * len(job.sigmas) > MAX_MEASUREMENT_ROWS:
        raise ConfigError(
            "runs",
            job.runs,
            f"runs x {sc.scans} scans x {len(job.sigmas)} σ are more than {MAX_MEASUREMENT_ROWS:.0e} "
            "measurement rows",
        )
    truth = sc.truth()
    rows = []
    for s in job.sigmas:
        z = measurements(sc, s, range(job.runs), job.seed, job.source)
        for r in range(job.runs):
            for i in range(sc.scans):
                rows.append((s, r, i + 1, i * sc.T, _cell(float(z[r, i, 0])), _cell(float(z[r, i, 1])),
                             float(truth[i, 0]), float(truth[i, 2])))  # fmt: skip
    sigma = job.sigmas[0] if len(job.sigmas) == 1 else list(job.sigmas)
    meta = make_meta("maneuver", view="measurements", sigma=sigma, T=sc.T, preset=sc.preset, runs=job.runs,
                     seed=job.seed, scans=sc.scans)  # fmt: skip
    cols = ("sigma", "run", "scan", "t", "z_x", "z_y", "x_true", "y_true")
    return Table(columns=cols, rows=rows, meta=meta)
