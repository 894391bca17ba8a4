"""The LMP detector against the estimate-then-correlate baseline at equal false-alarm rate: P_D versus the
signature amplitude a_sig and the horizon, 1-D and radar (the mode-signature paper, 47th IEEE CDC, Cancún, 2008, §I: the LMP test replaces an estimate-then-correlate detector and is
locally most powerful as a_sig → 0).

Both detectors see the same records. Null records (no signature) set each detector's threshold for the
target P_FA per horizon (:func:`~motionsig_cli.modesig.lmp1d.threshold_for`); the signature records,
one set per a_sig, give P_D at it. The streams are those of ``detect --calibrate``: signature trial t draws
from ``trial_rng(seed, t, 0|1|2)`` (i, τ, θ | process | measurement noise) for *every* a_sig (common random
numbers: the cells differ only by the amplitude), null trial t from ``trial_rng(seed, 2^40 + t, …)``.
Because both detectors see the same records, the difference of their P_D has a paired standard error
(``se_diff``), smaller than either binomial SE when the detections are correlated.

The job is a :class:`~motionsig_cli.engine.MonteCarloJob`: its counts do not depend on the engine.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, ClassVar, Literal

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of
from motionsig_cli.detection.estimate_correlate import (
    ECConfig,
    RadarECConfig,
    estimate_correlate_detect,
    estimate_correlate_detect_radar,
)
from motionsig_cli.detection.lmp import LMPConfig, RadarLMPConfig, lmp_detect, lmp_detect_radar
from motionsig_cli.engine import tasks_of, trials_per_task
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.models.vehicle2d import Vehicle2D
from motionsig_cli.modesig.lmp1d import (
    MAX_NULL_TRIALS,
    NULL_OFFSET,
    Codes,
    DetectionRate,
    JobHorizons,
    check_horizons,
    check_values,
    roc_curve,
    simulate_trials,
    table1_chips,
    threshold_for,
)
from motionsig_cli.modesig.lmp2d import simulate_trials_2d
from motionsig_cli.rng import DEFAULT_SEED
from motionsig_cli.tables import Table, make_meta

DETECTORS = ("lmp", "estimate-correlate")
A_LIST = (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0)
HORIZONS = (10.0, 20.0, 40.0, 80.0)
R_1D = 1e-3  # the 1-D default measurement variance (the paper's ANR label 48.3 at a_sig = 0.5)
Example = Literal["1d", "radar"]


@dataclass(frozen=True)
class Outcomes:
    """One task's per-trial results, detectors first: ``lam`` the statistic's maximum and ``ok`` (i, τ)
    right, each (2, B, H)."""

    lam: np.ndarray
    ok: np.ndarray


@dataclass(frozen=True)
class RocCell(DetectionRate):
    """P_D at the threshold for ``pfa`` of one detector, amplitude and horizon."""

    detector: str
    a_sig: float
    horizon_s: float
    threshold: float
    false_alarms: int
    null_trials: int
    detections: int
    detections_correct: int
    correct: int
    trials: int
    diff: float  # P_D(this) − P_D(other detector), same records
    se_diff: float  # its paired standard error


@dataclass(frozen=True, eq=False)
class BaselineRocJob(JobHorizons):
    """P_D at equal P_FA of the LMP detector and the estimate-then-correlate baseline, per (a_sig, horizon).

    Attributes:
        example: ``"1d"`` (position records, the LMP's Kalman bank) or ``"radar"`` (range/bearing records, the
            LMP's sigma-point bank).
        a_list: Signature amplitudes of the signature records, each finite and > 0.
        horizons_s: Horizons [s], each at least one sample.
        trials: Signature trials per amplitude, 1 … :data:`MAX_NULL_TRIALS`.
        null_trials: Null trials (shared by every amplitude), 1 … :data:`MAX_NULL_TRIALS`; None: ⌈20/pfa⌉.
        pfa: Target false-alarm probability, in (0, 1).
        seed: Root seed (>= 0).
        vehicle: The truth and the filters' model (its a_sig is replaced by each of ``a_list``); None: the
            1-D vehicle at R = :data:`R_1D`, or the radar vehicle at Fig 7's best ANR pair.
        lmp: The LMP settings (:class:`LMPConfig` or :class:`RadarLMPConfig`); None: the defaults.
        ec: The baseline's settings (:class:`ECConfig` or :class:`RadarECConfig`); None: the defaults.
        codes, m_rho, f_c: The codes, samples per chip and carrier of the records.
        chunk: Trials per task (None: from the cost model).
        label: A name for the run (the table's first column; metadata only).
    """

    name: ClassVar[str] = "baseline-roc"

    example: Example = "1d"
    a_list: tuple[float, ...] = A_LIST
    horizons_s: tuple[float, ...] = HORIZONS
    trials: int = 200
    null_trials: int | None = None
    pfa: float = 0.01
    seed: int = DEFAULT_SEED
    vehicle: Vehicle1D | Vehicle2D | None = None
    lmp: LMPConfig | RadarLMPConfig | None = None
    ec: ECConfig | RadarECConfig | None = None
    codes: Codes = "corrected"
    m_rho: int = 20
    f_c: float = 1.0
    chunk: int | None = None
    label: str = ""

    def __post_init__(self) -> None:
        one_of("example", self.example, ("1d", "radar"))
        radar = self.example == "radar"
        for name in ("a_list", "horizons_s"):
            value = getattr(self, name)
            object.__setattr__(self, name, tuple(value) if isinstance(value, list) else value)
        defaults = {
            "vehicle": Vehicle2D() if radar else Vehicle1D(R=R_1D),
            "lmp": RadarLMPConfig() if radar else LMPConfig(),
            "ec": RadarECConfig() if radar else ECConfig(),
        }
        kinds = {
            "vehicle": Vehicle2D if radar else Vehicle1D,
            "lmp": RadarLMPConfig if radar else LMPConfig,
            "ec": RadarECConfig if radar else ECConfig,
        }
        for name, default in defaults.items():
            if getattr(self, name) is None:
                object.__setattr__(self, name, default)
            if not isinstance(getattr(self, name), kinds[name]):
                raise ConfigError(
                    name, getattr(self, name), f"is not a {kinds[name].__name__} ({self.example})"
                )
        check_values("a_list", self.a_list, 0.0, lo_open=True)
        check_horizons(self.horizons_s, self.vehicle.T)
        in_range("pfa", self.pfa, 0.0, 1.0, lo_open=True, hi_open=True)
        if self.null_trials is None:
            object.__setattr__(self, "null_trials", math.ceil(20 / self.pfa))
        for name in ("trials", "null_trials"):
            integer(name, getattr(self, name), 1)
            if getattr(self, name) > MAX_NULL_TRIALS:
                raise ConfigError(name, getattr(self, name), f"is too many: at most {MAX_NULL_TRIALS:.0e}")
        integer("seed", self.seed, 0)
        one_of("codes", self.codes, ("corrected", "printed"))
        integer("m_rho", self.m_rho, 1)
        in_range("f_c", self.f_c, 0.0, unit="Hz")
        if self.chunk is not None:
            integer("chunk", self.chunk, 1)

    @property
    def chips(self) -> np.ndarray:
        return table1_chips(self.codes)

    def cost(self) -> tuple[float, float]:
        """(fixed, per trial) seconds of a task (2 cores, measured): the 1-D LMP bank's Riccati recursion and
        innovations (187 filters); the radar's sigma-point bank (~3 µs per filter-step per record) and
        baseline filter (~0.3 ms per step for a batch)."""
        n = self.n_samples
        if self.example == "radar":
            return n * 3e-4, n * 187 * 3e-6
        return n * 2.3e-4, n * 187 * 1.2e-8

    def tasks(self) -> list[tuple[int, int, range]]:
        """``(0, -1, trials)`` null records, then ``(1, a index, trials)`` per amplitude."""
        fixed, per_trial = self.cost()
        per = self.chunk or min(200, trials_per_task(per_trial, fixed_seconds=fixed))
        null = [(0, -1, r) for r in tasks_of(self.null_trials, per)]
        return null + [(1, a, r) for a in range(len(self.a_list)) for r in tasks_of(self.trials, per)]

    def task_size(self, task: tuple[int, int, range]) -> int:
        return len(task[2])

    def records(self, task: tuple[int, int, range]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The task's records and their true (mode, τ) (B,) each."""
        which, a, ids = task
        signature = which == 1
        trials = list(ids) if signature else [NULL_OFFSET + t for t in ids]
        veh = replace(self.vehicle, a_sig=self.a_list[a]) if signature else self.vehicle
        args = (veh, self.chips, self.m_rho, self.f_c, self.n_samples, self.seed, trials)
        if self.example == "radar":
            sim, draws = simulate_trials_2d(*args, signature=signature)  # type: ignore[arg-type]
            y = sim["y"]
        else:
            y, draws = simulate_trials(*args, signature=signature)  # type: ignore[arg-type]
        return y, np.array([d.mode for d in draws]), np.array([d.tau for d in draws])

    def run_task(self, task: tuple[int, int, range]) -> Outcomes:
        y, modes, taus = self.records(task)
        hz, chips, veh = self.horizon_samples, self.chips, self.vehicle
        if self.example == "radar":
            results = (
                lmp_detect_radar(y, chips, veh, self.m_rho, self.lmp, hz),  # type: ignore[arg-type]
                estimate_correlate_detect_radar(y, chips, veh, self.m_rho, self.ec, hz),  # type: ignore[arg-type]
            )
        else:
            results = (
                lmp_detect(y, chips, veh, self.m_rho, self.lmp, hz),  # type: ignore[arg-type]
                estimate_correlate_detect(y, chips, veh, self.m_rho, self.ec, hz),  # type: ignore[arg-type]
            )
        lam, ok = [], []
        for res in results:
            best, mx = res.best()
            c = res.candidates
            lam.append(mx)
            ok.append((c.mode[best] == modes[:, None]) & (c.tau[best] == taus[:, None]))
        return Outcomes(np.stack(lam), np.stack(ok))

    def reduce(self, tasks: Sequence[tuple[int, int, range]], results: Sequence[Outcomes]) -> BaselineRoc:
        def joined(which: int, a: int, attr: str) -> np.ndarray:
            mine = [getattr(o, attr) for t, o in zip(tasks, results, strict=True) if t[:2] == (which, a)]
            return np.concatenate(mine, axis=1)  # (2, trials, H)

        null = joined(0, -1, "lam")
        thr = np.array([[threshold_for(null[d, :, j], self.pfa) for j in range(len(self.horizons_s))]
                        for d in range(2)])  # fmt: skip
        signal = {a: joined(1, i, "lam") for i, a in enumerate(self.a_list)}
        correct = {a: joined(1, i, "ok") for i, a in enumerate(self.a_list)}
        cells = []
        for a in self.a_list:
            det = signal[a] > thr[:, None, :]  # (2, trials, H)
            for d, name in enumerate(DETECTORS):
                for j, h in enumerate(self.horizons_s):
                    paired = det[d, :, j].astype(float) - det[1 - d, :, j]
                    se = (
                        float(np.std(paired, ddof=1) / math.sqrt(paired.size))
                        if paired.size > 1
                        else math.nan
                    )
                    cells.append(
                        RocCell(
                            name, float(a), float(h), float(thr[d, j]), int(np.sum(null[d, :, j] > thr[d, j])),
                            self.null_trials, int(det[d, :, j].sum()), int(np.sum(det[d, :, j] & correct[a][d, :, j])),
                            int(correct[a][d, :, j].sum()), self.trials, float(paired.mean()), se,
                        )
                    )  # fmt: skip
        return BaselineRoc(self, cells, null, signal)

    def identity(self) -> dict[str, Any]:
        return dict(
            example=self.example, a_list=list(self.a_list), horizons_s=list(self.horizons_s), trials=self.trials,
            null_trials=self.null_trials, pfa=self.pfa, seed=self.seed, vehicle=repr(self.vehicle),
            lmp=repr(self.lmp), ec=repr(self.ec), codes=self.codes, m_rho=self.m_rho, f_c=self.f_c,
        )  # fmt: skip


def anr_db(vehicle: Vehicle1D | Vehicle2D, a_sig: float) -> float:
    """10·log10 ANR = a²/(2R) (eq 58) of the position measurement (1-D) or the range (radar)."""
    R = vehicle.R if isinstance(vehicle, Vehicle1D) else vehicle.R_range
    return 10 * math.log10(a_sig**2 / (2 * R))


@dataclass(frozen=True, eq=False)
class BaselineRoc:
    """The cells, and the raw maxima for ROC curves: ``null`` (2, null_trials, H), ``signal[a]`` (2, trials,
    H), detectors in the order of :data:`DETECTORS`."""

    job: BaselineRocJob
    cells: list[RocCell]
    null: np.ndarray
    signal: dict[float, np.ndarray]

    def cell(self, detector: str, a_sig: float, horizon_s: float) -> RocCell:
        return next(
            c for c in self.cells if (c.detector, c.a_sig, c.horizon_s) == (detector, a_sig, horizon_s)
        )

    def roc(self, detector: str, a_sig: float, horizon_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Empirical (P_FA, P_D) curve of one detector, amplitude and horizon."""
        d, j = DETECTORS.index(detector), self.job.horizons_s.index(horizon_s)
        return roc_curve(self.null[d, :, j], self.signal[a_sig][d, :, j])

    def table(self) -> Table:
        job = self.job
        rows = [
            (job.label, job.example, job.vehicle.f_r, c.detector, c.a_sig, anr_db(job.vehicle, c.a_sig), c.horizon_s, job.pfa, c.threshold,
             c.false_alarms / c.null_trials, c.null_trials, c.pd, c.pd_se, c.diff, c.se_diff,
             c.detections_correct / c.trials, c.correct / c.trials, c.trials)
            for c in self.cells
        ]  # fmt: skip
        meta = make_meta(
            "baseline-roc", example=job.example, a_list=list(job.a_list), horizons_s=list(job.horizons_s),
            trials=job.trials, null_trials=job.null_trials, pfa=job.pfa, seed=job.seed, vehicle=repr(job.vehicle),
            lmp=repr(job.lmp), estimate_correlate=repr(job.ec), codes=job.codes, m_rho=job.m_rho, f_c=job.f_c,
            anr="10 log10(a_sig^2 / (2 R)) of the position measurement (1d) or the range (radar)",
            threshold_rule="per detector and horizon: order statistic of the null maxima leaving at most "
            "floor(pfa * null_trials) above it",
            pd_minus_other="P_D(this detector) - P_D(the other), same records; se_diff its paired standard error",
            trial_streams="signature trial t (every a_sig): SeedSequence(seed, spawn_key=(t, 0|1|2)); "
            "null trial t: spawn_key=(2^40 + t, 0|1|2), no signature",
        )  # fmt: skip
        columns = ("run", "example", "f_r", "detector", "a_sig", "anr_db_log10", "horizon_s", "pfa_target", "threshold",
                   "pfa_in_sample", "null_trials", "pd", "pd_se", "pd_minus_other", "se_diff", "pd_and_correct",
                   "frac_correct_argmax", "trials")  # fmt: skip
        return Table(columns, rows, meta)
