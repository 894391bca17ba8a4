"""The seed-001 scenario and its Monte Carlo: S radars on a circle, a nearly-constant-velocity target (or
none), Poisson clutter uniform in each field of view, and the three track-existence scores (spec §2.5).

Run r draws only from ``trial_rng(seed, r)`` (truth, detections, clutter, the initial track draw), so a
result does not depend on the number of runs or on their order.

The command's Monte Carlo (:class:`SlrtJob`) runs on the engine (:mod:`motionsig_cli.engine`): tasks are
chunks of consecutive runs of one case, sized from :func:`cost` only (never from the worker count), and
:func:`collect` joins the chunks in task order, so the scores are the same on 1 worker, N workers or Dask.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from functools import partial
from typing import Any

import numpy as np

from motionsig_cli.detection.sprt import Decisions, first_crossing, wald_thresholds
from motionsig_cli.detection.track_existence import METHODS, ScanData, TrackExistenceModel, run_methods
from motionsig_cli.engine import Engine, run_tasks, tasks_of, trials_per_task
from motionsig_cli.models.radar import MeasurementModel, cv_model, wrap_angle
from motionsig_cli.rng import trial_rng

__all__ = [
    "SlrtJob",
    "SlrtScenario",
    "collect",
    "decisions",
    "generate",
    "monte_carlo",
    "run",
    "score_task",
    "summarise",
]

MAX_SECONDS = 240.0
"""Largest estimated run time accepted (:func:`cost`)."""
MAX_BYTES = 2 * 1024**3
"""Largest estimated memory for the generated measurements."""


@dataclass(frozen=True)
class SlrtScenario:
    """Spec §2.5 defaults; every value the slides leave open is an option (marked [A] in the spec).

    Attributes:
        n_sensors: radars on a circle of radius ``radius`` m at equally spaced azimuths from 0°.
        target: a target is present (h1) or only clutter (h0).
        pd_true: detection probability of the data; ``pd_filter``: the one the filters assume.
        clutter_rate: mean false alarms per sensor per scan (λ_F).
        sigma_r, sigma_phi_deg: range–bearing noise (m, degrees); Cartesian sensors use σ_r on both axes.
        meas_model: ``range_bearing`` or ``cartesian``.
        q: acceleration psd q̃ [m²/s³]; T: scan period [s]; scans: number of scans.
        x0: truth initial state [x, ẋ, y, ẏ]; p0_sd: track prior standard deviations (position, velocity).
        fov_range: field-of-view radius [m].
    """

    n_sensors: int = 4
    radius: float = 13_000.0
    target: bool = True
    pd_true: float = 0.9
    pd_filter: float = 0.9
    clutter_rate: float = 5.0
    sigma_r: float = 50.0
    sigma_phi_deg: float = 0.2
    meas_model: str = "range_bearing"
    q: float = 10.0
    T: float = 1.0
    scans: int = 30
    x0: tuple[float, float, float, float] = (0.0, 150.0, 0.0, 50.0)
    p0_sd: tuple[float, float] = (200.0, 50.0)
    fov_range: float = 26_000.0

    def __post_init__(self) -> None:
        if self.n_sensors < 1:
            raise ValueError("at least one sensor is needed")
        if not (math.isfinite(self.radius) and 0 <= self.radius < self.fov_range):
            raise ValueError(
                f"sensor circle radius must be in [0, {self.fov_range:g}) m (beyond it the target starts "
                "outside every field of view)"
            )
        if self.n_sensors > 1 and self.radius < 1.0:
            raise ValueError("all sensors at one point: give a circle radius of at least 1 m")
        if not (math.isfinite(self.q) and 0 <= self.q <= 1e6) or not (
            math.isfinite(self.T) and 0 < self.T <= 3600
        ):
            raise ValueError("acceleration psd must be in [0, 1e6] and the scan period in (0, 3600] s")
        for name, v in (("p_D (data)", self.pd_true), ("p_D (filters)", self.pd_filter)):
            if not 0.0 < v <= 1.0:
                raise ValueError(f"{name} = {v:g} is outside (0, 1]")
        if not (math.isfinite(self.clutter_rate) and self.clutter_rate >= 0):
            raise ValueError("the clutter rate must be a finite number >= 0")
        if self.pd_filter == 1.0 and self.clutter_rate > 0:
            raise ValueError("p_D = 1 for the filters is only meaningful without clutter")
        if not (1e-3 <= self.sigma_r <= 1e5 and 1e-6 <= self.sigma_phi_deg <= 90.0):
            raise ValueError(
                "measurement noise must satisfy 1e-3 <= sigma_r <= 1e5 m and 1e-6 <= sigma_phi <= 90 deg "
                "(R positive definite and well conditioned)"
            )
        if self.scans < 1:
            raise ValueError("at least one scan")
        if not all(v > 0 and math.isfinite(v) for v in self.p0_sd):
            raise ValueError("track prior standard deviations must be > 0")

    @property
    def sensors(self) -> np.ndarray:
        """(S, 2) sensor positions."""
        az = 2.0 * math.pi * np.arange(self.n_sensors) / self.n_sensors
        return self.radius * np.stack([np.cos(az), np.sin(az)], axis=-1)

    def measurement(self) -> MeasurementModel:
        if self.meas_model == "range_bearing":
            R = np.diag([self.sigma_r**2, math.radians(self.sigma_phi_deg) ** 2])
        else:
            R = np.diag([self.sigma_r**2, self.sigma_r**2])
        return MeasurementModel(self.meas_model, R, self.fov_range)

    def model(self) -> TrackExistenceModel:
        F, Q = cv_model(self.T, self.q)
        p, v = self.p0_sd
        return TrackExistenceModel(
            F,
            Q,
            self.sensors,
            self.measurement(),
            self.pd_filter,
            self.clutter_rate,
            np.diag([p * p, v * v, p * p, v * v]),
        )


@dataclass(frozen=True)
class Generated:
    """Truth, initial track means and the measurements of every scan for a batch of runs."""

    truth: np.ndarray  # (R, K, 4)
    m0: np.ndarray  # (R, 4)
    scans: list[ScanData]
    clutter_counts: np.ndarray  # (R, K, S)


def generate(sc: SlrtScenario, runs: Sequence[int], seed: int) -> Generated:
    """Draw the scenario for the given run indices (spec §2.5)."""
    F, Q = cv_model(sc.T, sc.q)
    meas = sc.measurement()
    sensors = sc.sensors
    LQ = np.linalg.cholesky(Q + 1e-12 * np.eye(4))
    LR = np.linalg.cholesky(meas.R)
    p, v = sc.p0_sd
    L0 = np.diag([p, v, p, v])
    S, K = sc.n_sensors, sc.scans
    truth = np.empty((len(runs), K, 4))
    m0 = np.empty((len(runs), 4))
    per_run: list[list[list[np.ndarray]]] = []
    counts = np.zeros((len(runs), K, S), dtype=int)
    for i, r in enumerate(runs):
        g = trial_rng(seed, r)
        x = np.asarray(sc.x0, dtype=float)
        m0[i] = x + L0 @ g.standard_normal(4)  # the same draw around x0 with or without a target
        zs: list[list[np.ndarray]] = []
        for k in range(K):
            x = F @ x + LQ @ g.standard_normal(4)  # first scan at t = T
            truth[i, k] = x
            row = []
            for s in range(S):
                n_fa = g.poisson(sc.clutter_rate)
                counts[i, k, s] = n_fa
                z = meas.clutter(g, n_fa, sensors[s])
                detect = g.random() < sc.pd_true
                noise = LR @ g.standard_normal(2)
                if sc.target and detect:
                    zt = meas.h(x, sensors[s]) + noise
                    if meas.angular is not None:
                        zt[1] = wrap_angle(zt[1])
                    if meas.in_fov(zt, sensors[s]):
                        z = np.vstack([zt[None, :], z])
                row.append(z)
            zs.append(row)
        per_run.append(zs)
    scans = []
    for k in range(K):
        Zs, Vs = [], []
        for s in range(S):
            M = max(len(per_run[i][k][s]) for i in range(len(runs)))
            Z = np.zeros((len(runs), M, 2))
            V = np.zeros((len(runs), M), dtype=bool)
            for i in range(len(runs)):
                z = per_run[i][k][s]
                Z[i, : len(z)] = z
                V[i, : len(z)] = True
            Zs.append(Z)
            Vs.append(V)
        scans.append(ScanData(tuple(Zs), tuple(Vs)))
    return Generated(truth, m0, scans, counts)


def run(
    sc: SlrtScenario, runs: int, seed: int, methods: Sequence[str] = METHODS, *, lkf_mean: str = "lr"
) -> tuple[dict[str, np.ndarray], Generated]:
    """log LR (runs × scans) per method, and the generated data."""
    if runs < 1:
        raise ValueError("the number of Monte Carlo runs must be >= 1")
    nbytes = cost(sc, runs)[1]
    if nbytes > MAX_BYTES:  # the time budget is the command layer's call (scripts may run longer)
        raise ValueError(f"the measurements would need about {nbytes / 1e9:.1f} GB; the limit is 2 GB")
    gen = generate(sc, range(runs), seed)
    return run_methods(sc.model(), gen.m0, gen.scans, methods, lkf_mean=lkf_mean), gen


@dataclass(frozen=True)
class SlrtJob:
    """The command's Monte Carlo: runs 0..runs−1 of every case, scored by ``methods``.

    A task is ``(case index, range of runs)``; :meth:`tasks` chunks each case's runs into tasks of
    :meth:`runs_per_task` runs (from the cost model, so the chunking — and with it every floating-point
    result — depends on the parameters only, never on the number of workers).
    """

    cases: tuple[SlrtScenario, ...]
    runs: int
    seed: int
    methods: tuple[str, ...] = METHODS
    lkf_mean: str = "lr"

    def __post_init__(self) -> None:
        if not self.cases:
            raise ValueError("at least one case")
        if self.runs < 1:
            raise ValueError("the number of Monte Carlo runs must be >= 1")
        if not self.methods or any(m not in METHODS for m in self.methods):
            raise ValueError(f"methods must be among {', '.join(METHODS)}; got {self.methods!r}")

    def runs_per_task(self) -> int:
        """Runs per task: worth at least the engine's minimum task time *and* 4× the per-batch overhead of
        the cost model (the filters' Python loop over scans and sensors), so that chunking costs ≤ 25 %
        extra. Both scale with ``$MOTIONSIG_MIN_TASK_SECONDS`` (tests set it tiny: one run per task)."""
        fixed = max(cost(sc, 0)[0] for sc in self.cases)
        per_run = max(cost(sc, 1)[0] - cost(sc, 0)[0] for sc in self.cases)
        return trials_per_task(per_run, fixed_seconds=fixed)

    def tasks(self) -> list[tuple[int, range]]:
        """(case, runs) in case order, runs in increasing order within a case."""
        per_task = self.runs_per_task()
        return [(c, r) for c in range(len(self.cases)) for r in tasks_of(self.runs, per_task)]

    def identity(self) -> dict[str, Any]:
        """Everything the task results depend on (JSON values), for a checkpoint's manifest."""
        return {
            "cases": [asdict(sc) for sc in self.cases],
            "runs": self.runs,
            "seed": self.seed,
            "methods": list(self.methods),
            "lkf_mean": self.lkf_mean,
            "runs_per_task": self.runs_per_task(),
        }


def score_task(job: SlrtJob, task: tuple[int, range]) -> dict[str, np.ndarray]:
    """One task: log LR (runs in the task × scans) per method of one case (module level: picklable)."""
    case, runs = task
    sc = job.cases[case]
    gen = generate(sc, runs, job.seed)
    return run_methods(sc.model(), gen.m0, gen.scans, job.methods, lkf_mean=job.lkf_mean)


def collect(
    job: SlrtJob, tasks: Sequence[tuple[int, range]], results: Sequence[dict[str, np.ndarray]]
) -> list[dict[str, np.ndarray]]:
    """Per case, the log LR (runs × scans) per method: the tasks' results joined in task order."""
    parts: list[list[dict[str, np.ndarray]]] = [[] for _ in job.cases]
    for (case, _), res in zip(tasks, results, strict=True):
        parts[case].append(res)
    return [{m: np.concatenate([p[m] for p in ps]) for m in job.methods} for ps in parts]


def monte_carlo(
    job: SlrtJob, engine: Engine | None = None, *, progress: Callable[[int], None] | None = None
) -> list[dict[str, np.ndarray]]:
    """:func:`score_task` over :meth:`SlrtJob.tasks` on ``engine`` (default: in this process), then
    :func:`collect`. ``progress`` is called with the number of runs of each finished task."""
    tasks = job.tasks()
    results = run_tasks(
        partial(score_task, job),
        tasks,
        Engine() if engine is None else engine,
        sizes=[len(r) for _, r in tasks],
        progress=progress,
        identity={"command": "slrt", **job.identity()},
    )
    return collect(job, tasks, results)


def scan_xy(
    sc: SlrtScenario, gen: Generated, run: int, scan: int
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """One scan of one run in Cartesian x–y, per sensor: (false alarms, target detections). The generator puts
    the target detection (if any) first in each sensor's list."""
    clutter_xy, target_xy = [], []
    for s in range(sc.n_sensors):
        Z = gen.scans[scan].Z[s][run][gen.scans[scan].valid[s][run]]
        if sc.meas_model == "cartesian":
            xy = Z
        else:
            xy = sc.sensors[s] + Z[:, :1] * np.stack([np.cos(Z[:, 1]), np.sin(Z[:, 1])], axis=-1)
        n_t = len(xy) - int(gen.clutter_counts[run, scan, s])
        target_xy.append(xy[:n_t])
        clutter_xy.append(xy[n_t:])
    return clutter_xy, target_xy


def cost(sc: SlrtScenario, runs: int, cases: int = 1) -> tuple[float, float]:
    """Rough (seconds, bytes) of ``cases`` Monte Carlo cases: a fixed cost per sensor-scan (≈ 0.9 ms of
    Python) plus a per-run cost that grows with the clutter."""
    per_sensor_scan = (
        0.9e-3 + 3e-5 * runs * (1.0 + sc.clutter_rate / 5.0) + 2e-5 * runs
    )  # filters + generation
    seconds = cases * sc.scans * sc.n_sensors * per_sensor_scan
    nbytes = (
        sc.scans
        * sc.n_sensors
        * runs
        * (sc.clutter_rate + 4.0 * math.sqrt(sc.clutter_rate + 1.0) + 2.0)
        * 17.0
    )
    return seconds, nbytes


def summarise(loglr: np.ndarray) -> dict[str, np.ndarray]:
    """Mean, median and the 5 / 95 % quantiles over runs, per scan (quantiles without interpolation, so a
    score of −inf — p_D = 1 and a missed target — stays −inf instead of becoming NaN)."""
    return {
        "mean": loglr.mean(axis=0),
        "median": np.quantile(loglr, 0.5, axis=0, method="inverted_cdf"),
        "q05": np.quantile(loglr, 0.05, axis=0, method="inverted_cdf"),
        "q95": np.quantile(loglr, 0.95, axis=0, method="inverted_cdf"),
    }


def decisions(loglr: np.ndarray, alpha: float, beta: float) -> Decisions:
    """Wald's first-crossing decisions on each run."""
    log_a, log_b = wald_thresholds(alpha, beta)
    return first_crossing(loglr, log_a, log_b)
