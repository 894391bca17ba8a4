"""The track-existence scenario of Govaers, *Evaluation of Distributed Detection Methods for Agile Targets*
(Fraunhofer FKIE, slides), and its Monte Carlo: S radars on a circle, a nearly-constant-velocity target (or
none), Poisson clutter uniform in each field of view, and the track-existence scores of
:data:`~motionsig_cli.detection.track_existence.FUSION_METHODS` (CKF, DKF, LKF).

Run r draws only from ``trial_rng(seed, r)`` (truth, detections, clutter, the initial track draw), so a
result does not depend on the number of runs or on their order.

The command's experiment is a :class:`SlrtStudy` (target cases at several p_D and a no-target case, the
runs, Wald's test). Its Monte Carlo, :meth:`SlrtStudy.job`, is a :class:`SlrtJob` for the engine
(:class:`motionsig_cli.engine.MonteCarloJob`): tasks are chunks of consecutive runs of one case, sized from
:func:`cost` only (never from the worker count), and joined in task order, so the scores are the same on
1 worker, N workers or Dask. :meth:`SlrtStudy.result` turns the scores into the per-scan curves or Wald's
decisions (:class:`SlrtResult`: tables, figure panels, a summary line).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of, positive
from motionsig_cli.detection.sprt import (
    Decisions,
    first_crossing,
    freeze_at_decision,
    wald_thresholds,
)
from motionsig_cli.detection.track_existence import (
    METHODS,
    FusionOptions,
    ScanData,
    TrackExistenceModel,
    check_methods,
    run_methods,
)
from motionsig_cli.engine import tasks_of, trials_per_task
from motionsig_cli.models.radar import MeasurementModel, cv_model, wrap_angle
from motionsig_cli.rng import DEFAULT_SEED, trial_rng
from motionsig_cli.tables import Table, make_meta

__all__ = [
    "VIEWS",
    "SlrtJob",
    "SlrtResult",
    "SlrtScenario",
    "SlrtStudy",
    "cost",
    "decisions",
    "generate",
    "run",
    "scan_picture",
    "scan_xy",
    "summarise",
]

MAX_SECONDS = 240.0
"""Largest estimated run time :class:`SlrtStudy` accepts (:func:`cost`)."""
MAX_BYTES = 2 * 1024**3
"""Largest estimated memory for the generated measurements."""
MAX_PD_CASES = 10
"""Most target cases (distinct p_D values) of one study."""
MEAS_MODELS = ("range_bearing", "cartesian")
VIEWS = ("curves", "decisions")
"""The tables of :meth:`SlrtResult.table`: per-scan statistics of log LR, or Wald's decisions."""
ASSUMPTIONS = (
    "assumed: measurement model, noise, field of view, scan period, sensor angles, initial track and "
    "thresholds (the slides do not give them)"
)


@dataclass(frozen=True)
class SlrtScenario:
    """One case of the slides' scenario. The slides give the geometry (radars on a circle of about 13 km),
    the target's motion, clutter and the p_D values; every other value is our assumption, and a field.

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

    Every field is checked (:class:`~motionsig_cli.config.ConfigError` naming it):

    - ``n_sensors`` an integer in [1, 64]; ``scans`` an integer in [1, 10⁵] (the long-run check's length);
      ``clutter_rate`` in [0, 1000]. The upper bounds are the sizes the implementation is built for (the
      filters loop over sensors and scans in Python; beyond 1000 false alarms per scan a sensor's
      measurements say nothing about the target); :class:`SlrtStudy` bounds their product by its cost.
    - ``radius`` in [0, fov_range) m: sensors at or beyond the field of view never see the target (which
      starts at the origin); with two sensors or more at least 1 m, or they all stand at one point.
    - ``pd_true``, ``pd_filter`` in (0, 1]; ``pd_filter = 1`` only without clutter (``clutter_rate = 0``).
    - ``sigma_r`` in [10⁻³, 10⁵] m and ``sigma_phi_deg`` in [10⁻⁶, 90] deg: R positive definite and well
      conditioned.
    - ``q`` in [0, 10⁶] m²/s³; ``T`` in (0, 3600] s; ``x0`` four finite numbers; ``p0_sd`` two numbers
      > 0; ``fov_range`` > 0 m; ``meas_model`` one of :data:`MEAS_MODELS`.
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
        integer("n_sensors", self.n_sensors, 1, 64)
        positive("fov_range", self.fov_range, unit="m")
        in_range("radius", self.radius, 0.0, self.fov_range, hi_open=True, unit="m")
        if self.n_sensors > 1 and self.radius < 1.0:
            raise ConfigError("radius", self.radius, "m puts all sensors at one point: use at least 1 m")
        if not isinstance(self.target, bool | np.bool_):
            raise ConfigError("target", self.target, "is not true or false")
        in_range("pd_true", self.pd_true, 0.0, 1.0, lo_open=True)
        in_range("pd_filter", self.pd_filter, 0.0, 1.0, lo_open=True)
        in_range("clutter_rate", self.clutter_rate, 0.0, 1000.0)
        if self.pd_filter == 1.0 and self.clutter_rate > 0:
            raise ConfigError(
                "pd_filter", self.pd_filter, "for the filters is only meaningful without clutter"
            )
        in_range("sigma_r", self.sigma_r, 1e-3, 1e5, unit="m")
        in_range("sigma_phi_deg", self.sigma_phi_deg, 1e-6, 90.0, unit="deg")
        one_of("meas_model", self.meas_model, MEAS_MODELS)
        in_range("q", self.q, 0.0, 1e6, unit="m²/s³")
        in_range("T", self.T, 0.0, 3600.0, lo_open=True, unit="s")
        integer("scans", self.scans, 1, 100_000)
        if len(self.x0) != 4:
            raise ConfigError("x0", self.x0, "is not four numbers [x, ẋ, y, ẏ]")
        for v in self.x0:
            in_range("x0", v)
        if len(self.p0_sd) != 2:
            raise ConfigError("p0_sd", self.p0_sd, "is not two numbers (position, velocity)")
        for v in self.p0_sd:
            positive("p0_sd", v)

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
    """Draw the scenario for the given run indices."""
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
    """log LR (runs × scans) per method, and the generated data (in this process; no time limit)."""
    integer("runs", runs, 1)
    nbytes = cost(sc, runs)[1]
    if nbytes > MAX_BYTES:
        raise ConfigError(
            "runs", runs, f"would need about {nbytes / 1e9:.1f} GB of measurements; the limit is 2 GB"
        )
    gen = generate(sc, range(runs), seed)
    return run_methods(sc.model(), gen.m0, gen.scans, methods, lkf_mean=lkf_mean), gen


Task = tuple[int, range]
"""A task of :class:`SlrtJob`: (case index, runs)."""


@dataclass(frozen=True)
class SlrtJob:
    """The Monte Carlo of a study: runs 0..runs−1 of every case, scored by ``methods`` (an engine
    :class:`~motionsig_cli.engine.MonteCarloJob`; its result is, per case, log LR (runs × scans) per method).

    A task is ``(case index, range of runs)``; :meth:`tasks` chunks each case's runs into tasks of
    :meth:`runs_per_task` runs (from the cost model, so the chunking — and with it every floating-point
    result — depends on the parameters only, never on the number of workers).
    """

    name: ClassVar[str] = "slrt"

    cases: tuple[SlrtScenario, ...]
    runs: int
    seed: int
    methods: tuple[str, ...] = METHODS
    lkf_mean: str = "lr"

    def __post_init__(self) -> None:
        if not self.cases:
            raise ConfigError("cases", self.cases, "is empty: at least one case")
        integer("runs", self.runs, 1)
        integer("seed", self.seed, 0)
        check_methods(self.methods)
        FusionOptions(self.lkf_mean)

    def runs_per_task(self) -> int:
        """Runs per task: worth at least the engine's minimum task time *and* 4× the per-batch overhead of
        the cost model (the filters' Python loop over scans and sensors), so that chunking costs ≤ 25 %
        extra. Both scale with ``$MOTIONSIG_MIN_TASK_SECONDS`` (tests set it tiny: one run per task)."""
        fixed = max(cost(sc, 0)[0] for sc in self.cases)
        per_run = max(cost(sc, 1)[0] - cost(sc, 0)[0] for sc in self.cases)
        return trials_per_task(per_run, fixed_seconds=fixed)

    def tasks(self) -> list[Task]:
        """(case, runs) in case order, runs in increasing order within a case."""
        per_task = self.runs_per_task()
        return [(c, r) for c in range(len(self.cases)) for r in tasks_of(self.runs, per_task)]

    def task_size(self, task: Task) -> int:
        """Runs in the task."""
        return len(task[1])

    def run_task(self, task: Task) -> dict[str, np.ndarray]:
        """One task: log LR (runs in the task × scans) per method of one case."""
        case, runs = task
        sc = self.cases[case]
        gen = generate(sc, runs, self.seed)
        return run_methods(sc.model(), gen.m0, gen.scans, self.methods, lkf_mean=self.lkf_mean)

    def reduce(
        self, tasks: Sequence[Task], results: Sequence[dict[str, np.ndarray]]
    ) -> list[dict[str, np.ndarray]]:
        """Per case, the log LR (runs × scans) per method: the tasks' results joined in task order."""
        parts: list[list[dict[str, np.ndarray]]] = [[] for _ in self.cases]
        for (case, _), res in zip(tasks, results, strict=True):
            parts[case].append(res)
        return [{m: np.concatenate([p[m] for p in ps]) for m in self.methods} for ps in parts]

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


def _case(base: SlrtScenario, field_name: str, pd: float, *, target: bool) -> SlrtScenario:
    """``base`` with a target (or none) and p_D = ``pd`` for data and filters; a bad p_D names ``field_name``."""
    in_range(field_name, pd, 0.0, 1.0, lo_open=True)
    try:
        return replace(base, target=target, pd_true=pd, pd_filter=pd)
    except ConfigError as exc:
        if exc.field in ("pd_true", "pd_filter"):
            raise ConfigError(field_name, pd, exc.reason) from None
        raise


@dataclass(frozen=True)
class SlrtStudy:
    """The command's experiment: target cases at several p_D and a no-target case of one scenario, every
    case scored by the chosen fusion methods on runs 0..runs−1, and Wald's test on the scores.

    Attributes:
        scenario: what the cases share (its ``target``, ``pd_true`` and ``pd_filter`` are set per case).
        pd: p_D of the target cases (data and filters alike): 1 to :data:`MAX_PD_CASES` values in (0, 1];
            a repeated value gives one case.
        no_target: also run the no-target (clutter only) case, whose filters assume p_D = ``filter_pd``
            (in (0, 1]).
        runs: Monte Carlo runs per case, ≥ 1, with an estimated run time ≤ :data:`MAX_SECONDS` and memory
            ≤ :data:`MAX_BYTES` for all cases (:func:`cost`).
        seed: root seed (run r draws from ``trial_rng(seed, r)``).
        methods: names in :data:`~motionsig_cli.detection.track_existence.FUSION_METHODS`.
        lkf_mean: LKF's mean (:class:`~motionsig_cli.detection.track_existence.FusionOptions`).
        alpha, beta: Wald's error probabilities P(confirm | no target) and P(delete | target), in (0, 0.5).
        stop: freeze each run's score at its decision (default: keep accumulating).
    """

    scenario: SlrtScenario = field(default_factory=SlrtScenario)
    pd: tuple[float, ...] = (0.9, 0.5, 0.2)
    no_target: bool = True
    filter_pd: float = 0.9
    runs: int = 50
    seed: int = DEFAULT_SEED
    methods: tuple[str, ...] = METHODS
    lkf_mean: str = "lr"
    alpha: float = 1e-3
    beta: float = 0.1
    stop: bool = False

    def __post_init__(self) -> None:
        cases = self.cases
        self.job()
        wald_thresholds(self.alpha, self.beta)
        seconds, nbytes = cost(cases[0][1], self.runs, len(cases))
        if seconds > MAX_SECONDS or nbytes > MAX_BYTES:
            sc = self.scenario
            raise ConfigError(
                "runs",
                self.runs,
                f"is too many runs for {len(cases)} case(s) x {sc.scans} scans x {sc.n_sensors} sensors: an "
                f"estimated {seconds:.0f} s and {nbytes / 1e9:.2g} GB; the limits are {MAX_SECONDS:.0f} s and 2 GB",
            )

    @cached_property
    def cases(self) -> list[tuple[str, SlrtScenario]]:
        """(label, scenario) of each case: the target cases in the order of ``pd``, then the no-target one."""
        values = tuple(dict.fromkeys(self.pd))
        if not values:
            raise ConfigError("pd", self.pd, "is empty: give at least one p_D")
        if len(values) > MAX_PD_CASES:
            raise ConfigError("pd", self.pd, f"is more than {MAX_PD_CASES} values")
        out = [(f"target, p_D = {v:g}", _case(self.scenario, "pd", v, target=True)) for v in values]
        if self.no_target:
            out.append(("no target", _case(self.scenario, "filter_pd", self.filter_pd, target=False)))
        return out

    @property
    def thresholds(self) -> tuple[float, float]:
        """Wald's (log A, log B)."""
        return wald_thresholds(self.alpha, self.beta)

    def job(self) -> SlrtJob:
        """The Monte Carlo of every case (run it with :func:`motionsig_cli.engine.run_job`)."""
        return SlrtJob(
            tuple(sc for _, sc in self.cases), self.runs, self.seed, tuple(self.methods), self.lkf_mean
        )

    def result(self, scores: Sequence[dict[str, np.ndarray]]) -> SlrtResult:
        """The job's scores checked (no NaN, no +inf) and, with ``stop``, frozen at each run's decision."""
        log_a, log_b = self.thresholds
        out = []
        for (label, _), case in zip(self.cases, scores, strict=True):
            case = dict(case)
            for m, v in case.items():
                if np.any(np.isnan(v) | (v == np.inf)):
                    raise RuntimeError(f"NaN or +inf log LR in {label}, {m}")
                if self.stop:
                    case[m] = freeze_at_decision(v, log_a, log_b)
            out.append(case)
        return SlrtResult(self, out)


CURVE_COLUMNS = (
    "case",
    "target",
    "pd",
    "method",
    "scan",
    "mean_loglr",
    "median_loglr",
    "q05_loglr",
    "q95_loglr",
)
DECISION_COLUMNS = (
    "case",
    "target",
    "pd",
    "method",
    "runs",
    "confirmed",
    "deleted",
    "undecided",
    "mean_decision_scan",
    "max_decision_scan",
    "error_rate",
    "wald_bound",
    "error_rate_se",
)


@dataclass(frozen=True)
class SlrtResult:
    """A study's scores: per case, log LR (runs × scans) per method (frozen at the decision with ``stop``)."""

    study: SlrtStudy
    scores: list[dict[str, np.ndarray]]

    def table(self, view: str) -> Table:
        """The ``curves`` or ``decisions`` table (:data:`VIEWS`) with the study's provenance."""
        one_of("view", view, VIEWS)
        columns, rows = (
            (CURVE_COLUMNS, self.curves()) if view == "curves" else (DECISION_COLUMNS, self.decisions())
        )
        return Table(columns=columns, rows=rows, meta=self.meta(view))

    def _rows(self) -> list[tuple[str, SlrtScenario, str, np.ndarray]]:
        return [
            (label, sc, m, scores[m])
            for (label, sc), scores in zip(self.study.cases, self.scores, strict=True)
            for m in self.study.methods
        ]

    def curves(self) -> list[tuple[Any, ...]]:
        """Per case, method and scan: mean, median, 5 % and 95 % quantiles of log LR over the runs."""
        rows = []
        for label, sc, m, loglr in self._rows():
            st = summarise(loglr)
            for j in range(sc.scans):
                rows.append((label, sc.target, sc.pd_filter, m, j + 1, float(st["mean"][j]), float(st["median"][j]),
                             float(st["q05"][j]), float(st["q95"][j])))  # fmt: skip
        return rows

    def decisions(self) -> list[tuple[Any, ...]]:
        """Per case and method: Wald's decisions (fractions confirmed, deleted, undecided), the mean and
        latest decision scan, the error rate (deleted with a target, confirmed without), Wald's bound on it
        (β/(1−α), α/(1−β)) and its binomial standard error (at least that of one error in ``runs``)."""
        alpha, beta, runs = self.study.alpha, self.study.beta, self.study.runs
        rows = []
        for label, sc, m, loglr in self._rows():
            d = decisions(loglr, alpha, beta)
            conf, dele = d.decision == 1, d.decision == -1
            decided = d.decision != 0
            wrong = dele if sc.target else conf
            bound = beta / (1 - alpha) if sc.target else alpha / (1 - beta)
            rows.append((label, sc.target, sc.pd_filter, m, runs, float(conf.mean()), float(dele.mean()),
                         float(1 - decided.mean()), float(d.time[decided].mean()) if decided.any() else None,
                         int(d.time.max()) if decided.any() else None, float(wrong.mean()), bound,
                         float(math.sqrt(max(wrong.mean() * (1 - wrong.mean()), 1 / runs) / runs))))  # fmt: skip
        return rows

    def meta(self, view: str) -> dict[str, Any]:
        """Provenance: the view, every parameter of the study and scenario, and how to read the scores."""
        st, sc = self.study, self.study.scenario
        log_a, log_b = st.thresholds
        shared = (
            "n_sensors",
            "radius",
            "clutter_rate",
            "sigma_r",
            "sigma_phi_deg",
            "meas_model",
            "q",
            "T",
            "scans",
        )
        return make_meta(
            "slrt",
            view=view,
            methods=list(st.methods),
            lkf_mean=st.lkf_mean,
            runs=st.runs,
            seed=st.seed,
            seeding="run r draws from SeedSequence(seed).spawn(...)[r]: truth, detections, clutter, initial track",
            scenario={
                **{k: getattr(sc, k) for k in shared},
                "x0": list(sc.x0),
                "p0_sd": list(sc.p0_sd),
                "fov_range_m": sc.fov_range,
                "sensor_azimuths": "equally spaced from 0 deg",
            },
            no_target_filter_pd=st.filter_pd if st.no_target else None,
            sprt={
                "alpha": st.alpha,
                "beta": st.beta,
                "log_A": log_a,
                "log_B": log_b,
                "rule": "first crossing",
            },
            dkf="relaxed evolution model S*Q, locals initialised at S*P0, no feedback; c by the sequential product "
            "with P^(s+1) (slides' P^s corrected)"
            if "dkf" in st.methods
            else None,
            stop=st.stop,
            clutter_floor="with --clutter 0 the clutter density is floored at 1e-300 per field of view: absolute "
            "scores are arbitrary, only differences between methods mean something"
            if sc.clutter_rate == 0
            else None,
            minus_inf="a log LR of -inf means the filters' p_D = 1 and a sensor saw nothing: the target hypothesis "
            "is impossible (certain deletion)",
            assumptions=ASSUMPTIONS,
        )

    def panels(self) -> list[tuple[str, np.ndarray, dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]]]:
        """Per case (label, scans 1..K, {method: (mean, q05, q95)}) for the figure."""
        k = np.arange(1, self.study.scenario.scans + 1)
        out = []
        for (label, _), scores in zip(self.study.cases, self.scores, strict=True):
            curves = {}
            for m in self.study.methods:
                st = summarise(scores[m])
                curves[m] = (st["mean"], st["q05"], st["q95"])
            out.append((label, k, curves))
        return out

    def summary(self) -> str:
        """One line: the mean log LR at the last scan of each case and method."""
        last = "; ".join(
            f"{label}: " + ", ".join(f"{m} {scores[m][:, -1].mean():.1f}" for m in self.study.methods)
            for (label, _), scores in zip(self.study.cases, self.scores, strict=True)
        )
        return f"slrt: mean log LR at scan {self.study.scenario.scans}: {last}"


def scan_picture(
    study: SlrtStudy,
) -> tuple[np.ndarray, list[np.ndarray], list[np.ndarray], np.ndarray, str]:
    """The last scan of run 0 of the first case, for a figure: (sensors, false alarms and target detections
    per sensor in x–y, the true track up to that scan, a title). Run 0 is drawn again: it depends on
    (seed, 0) only, so it is the run 0 of the Monte Carlo."""
    label, sc = study.cases[0]
    gen = generate(sc, range(1), study.seed)
    k = sc.scans - 1
    clutter_xy, target_xy = scan_xy(sc, gen, 0, k)
    return sc.sensors, clutter_xy, target_xy, gen.truth[0, : k + 1], f"{label}: run 0, scan {k + 1}"


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
