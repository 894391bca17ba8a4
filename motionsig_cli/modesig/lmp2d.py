"""The 2-D radar experiment of the mode-signature paper (47th IEEE CDC, Cancún, 2008, §IV.B, Fig 7): one radar record through the sigma-point bank, and the Fig 7 Monte Carlo (one
trial = draw (i, τ, θ), simulate, detect) as the job :class:`RadarLmpJob`.

The random streams are those of :mod:`motionsig_cli.modesig.lmp1d` with two-column noise:
``trial_rng(seed, t, 0)`` draws i, τ, θ (the same values as the 1-D trial t), ``(seed, t, 1)`` the
(x, y) process noise and ``(seed, t, 2)`` the (range, bearing) measurement noise. ``motionsig
simulate --example 2d --seed s`` is trial 0 of ``motionsig detect --montecarlo --example 2d --seed s``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from motionsig_cli.config import ConfigError, integer, one_of
from motionsig_cli.detection.lmp import LMPResult, RadarLMPConfig, candidate_grid, lmp_detect_radar
from motionsig_cli.detection.lmp_linearised import CENTERS, lmp_detect_radar_linearised
from motionsig_cli.engine import check_run_time, tasks_of, trials_per_task
from motionsig_cli.filters.kalman import Progress
from motionsig_cli.models.vehicle2d import SEED_ANR_PAIRS, Vehicle2D, anr_pair_variances, simulate_2d
from motionsig_cli.modesig.lmp1d import (
    CORRECT,
    FIG_HORIZONS,
    MAX_NULL_TRIALS,
    NULL_OFFSET,
    CalibrationCell,
    Codes,
    CorrectCurves,
    CorrectRates,
    JobHorizons,
    RecordHorizons,
    Threshold,
    TrialDraw,
    _tuple,
    calibration_null_trials,
    check_horizons,
    check_threshold,
    check_values,
    n_grid_candidates,
    null_trials_warning,
    record_notes,
    roc_curve,
    table1_chips,
    threshold_for,
    trial_signatures,
)
from motionsig_cli.modesig.lmp_record import RecordResult, record_result, sigma_meta
from motionsig_cli.modesig.record_reading import VehicleRecord, record_horizons
from motionsig_cli.rng import DEFAULT_SEED
from motionsig_cli.tables import Table, make_meta

MAX_SECONDS = 3600.0  # estimated run time limit of one run
MAX_GB = 4.0  # estimated memory limit of one bank
MAX_HORIZON_S = 1e6  # the Monte Carlo's longest horizon [s]
MAX_FR = 1e6  # the Monte Carlo's highest reference frequency [Hz]
RADAR_METHODS = ("bank", "linearised")
LINEARISED_S = (
    1.5e-5  # the linearised path: s per record and time step, records of several pairs at once (measured)
)
# trials per task of the linearised path (every ANR pair of them in one call): its per-step cost is mostly
# per call, so few large tasks (two for Fig 7's 50 trials: one per worker of a 2-core machine)
LINEARISED_BLOCK = 25


def check_radar_method(method: str, center: str) -> None:
    """``method`` bank or linearised; centring (``center`` other than none) needs the linearised path."""
    one_of("method", method, RADAR_METHODS)
    one_of("center", center, CENTERS)
    if center != "none" and method != "linearised":
        raise ConfigError("center", center, "needs the linearised path (method linearised)")


def detect_radar_records(
    method: str, y: np.ndarray, chips: np.ndarray, vehicle: Vehicle2D, m_rho: int, cfg: RadarLMPConfig,
    horizons: Sequence[int], *, center: str = "none", noise: np.ndarray | None = None, progress: Progress = None,
) -> LMPResult:  # fmt: skip
    """Eq (52) on radar records by the bank or the linearised path (``noise``: true (R_κ, R_χ) per record,
    the linearised path only; the bank takes the vehicle's)."""
    if method == "bank":
        return lmp_detect_radar(y, chips, vehicle, m_rho, cfg, horizons, progress=progress)
    return lmp_detect_radar_linearised(
        y,
        chips,
        vehicle,
        m_rho,
        cfg,
        horizons,
        noise=noise,
        center=center,
        progress=progress,  # type: ignore[arg-type]
    )


def simulate_trials_2d(
    vehicle: Vehicle2D,
    chips: np.ndarray,
    m_rho: int,
    f_c: float,
    n_samples: int,
    seed: int,
    trials: Sequence[int],
    *,
    signature: bool = True,
) -> tuple[dict[str, np.ndarray], list[TrialDraw]]:
    """Simulated records of the given trials (``simulate_2d`` output, B = len(trials)) and their draws."""
    draws, z, zd = trial_signatures(
        chips, m_rho, f_c, vehicle.T, n_samples, seed, trials, signature=signature, dims=2
    )
    sim = simulate_2d(vehicle, z, zd, np.stack([d.w for d in draws]), np.stack([d.v for d in draws]))
    return sim, draws


def check_size(
    field_name: str,
    value: Any,
    n_filters: int,
    trials: int,
    n_samples: int,
    batch: int,
    *,
    parallel: bool = True,
) -> None:
    """Refuse, before any work, a run over ~4 GB per worker (each worker holds one bank) or over the time
    limit (:func:`~motionsig_cli.engine.check_run_time`: ~1 h on the workers the run has; ``parallel=False``:
    one record in this process): ~(2 + 10/B) µs per filter-step for B records at once (measured), and the
    candidate replicas and transitions, ~6 arrays of (filters × samples) doubles. The :class:`ConfigError`
    names ``field_name`` (the field to change) with its ``value``."""
    seconds = float(n_filters) * trials * n_samples * (2 + 10 / batch) * 1e-6
    gb = 6.0 * n_filters * n_samples * 8 / 1e9
    if gb > MAX_GB:
        raise ConfigError(
            field_name, value, f"would need an estimated {gb:.2g} GB{' per worker' if parallel else ''} for the "
            f"bank of {n_filters} filters; the limit is {MAX_GB:g} GB: shorter horizons or a coarser grid",
        )  # fmt: skip
    check_run_time(
        field_name, value, seconds, MAX_SECONDS, parallel=parallel,
        also="fewer trials, shorter horizons or a coarser grid; or " if parallel else "shorter horizons or a "
        "coarser grid; or ",
    )  # fmt: skip


def n_candidates(chips: np.ndarray, m_rho: int, cfg: RadarLMPConfig) -> int:
    """Candidates (i, τ, f_c) of the grid."""
    return len(candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg.as_grid))


# ---------------------------------------------------------------------------------------- one record
@dataclass(frozen=True, eq=False)
class RadarRecordDetection(RecordHorizons):
    """Eq (52) with the sigma-point bank on one radar record: the argmax per horizon, or every candidate.

    Attributes:
        record: The record (:func:`motionsig_cli.modesig.record_reading.read_vehicle_record`); a
            missing sample (a NaN row) is a predict-only step of the bank.
        cfg: Detector settings.
        horizons: Horizons [s] (see :func:`~motionsig_cli.modesig.record_reading.record_horizons`);
            None: every 10 s. The run is refused above ~1 h or ~4 GB (:func:`check_size`).
        threshold: Declare "signature present" when max Λ >= threshold: one number, or one per horizon
            (a threshold calibrated for the record); None: no decision.
        candidates: Every candidate's statistic instead of the argmax.
        threshold_meta: How a calibrated threshold was found (metadata), or None.
        method: ``"bank"`` (2C + 1 sigma-point filters) or ``"linearised"`` (one H0 and one base filter and
            the projection of :mod:`motionsig_cli.detection.lmp_linearised`; missing samples are predict-only
            steps on both).
        center: ``"none"``, ``"h0-noise"`` or ``"standardised"`` (the linearised path only).
    """

    record: VehicleRecord
    cfg: RadarLMPConfig
    horizons: tuple[float, ...] | None = None
    threshold: Threshold = None
    candidates: bool = False
    threshold_meta: dict[str, Any] | None = None
    method: str = "bank"
    center: str = "none"

    def __post_init__(self) -> None:
        check_radar_method(self.method, self.center)
        rec, T = self.record, self.record.vehicle.T
        hs = record_horizons(self.horizons, rec.y.shape[0] * T, T)
        object.__setattr__(self, "horizons", tuple(hs))
        n_modes, n_rho = rec.chips.shape
        C = n_grid_candidates(n_modes, n_rho, rec.m_rho, self.cfg.tau_grid, len(self.cfg.fc_grid))
        check_size("horizons", max(hs), 2 * C + 1, 1, self.n_used, 1, parallel=False)
        check_threshold(self.threshold, len(hs))

    @property
    def steps(self) -> int:
        """The time steps :meth:`detect` reports to its ``progress`` callback."""
        return self.n_used

    @property
    def title(self) -> str:
        """The Fig 3-style panel's title."""
        v = self.record.vehicle
        return (
            f"horizon {self.horizons[-1]:g} s, R_range = {v.R_range:.3g}, R_bearing = {v.R_bearing:.3g}, "
            f"c_r = {self.cfg.c_r:g}"
        )

    def detect(self, progress: Progress = None) -> RecordResult:
        """Run the bank; ``progress`` is called with the time steps done, per block of steps.

        Raises:
            InputError: a missing sample within the horizons where the bank cannot skip one, naming its line.
        """
        rec, cfg, hz = self.record, self.cfg, self.horizon_samples
        y = rec.y[: self.n_used]
        try:
            res = detect_radar_records(
                self.method,
                y,
                rec.chips,
                rec.vehicle,
                rec.m_rho,
                cfg,
                hz,
                center=self.center,
                progress=progress,
            )
        except ValueError as exc:
            if np.isnan(y).any():  # a bank without predict-only steps
                self.missing_checked(f"the filter bank cannot skip a missing sample ({exc})")
            raise
        params = dict(
            source=rec.source, example="2d", filter="ukf",
            **({"method": self.method, "center": self.center} if self.method != "bank" else {}), c_r=cfg.c_r, Q0=list(cfg.Q0), Q1=list(cfg.Q1),
            P0=cfg.P0, tau_grid=cfg.tau_grid, fc_grid=list(cfg.fc_grid), include_logdet=cfg.include_logdet,
            zdot=cfg.zdot, horizons_s=list(self.horizons),
            threshold=list(self.threshold) if isinstance(self.threshold, tuple) else self.threshold,
            **sigma_meta(cfg.sigma, res.repairs),
            **({"threshold_calibration": self.threshold_meta} if self.threshold_meta else {}),
            **rec.provenance, input_meta=rec.meta,
        )  # fmt: skip
        return record_result(
            res, list(self.horizons), hz, rec.truth, params, rec.chips.shape, rec.m_rho,
            candidates=self.candidates, threshold=self.threshold, notes=record_notes(rec, self.n_used),
        )  # fmt: skip


# ------------------------------------------------------------------------------ the Fig 7 Monte Carlo
@dataclass(frozen=True)
class RadarMCCell(CorrectRates):
    """Monte Carlo result of one (ANR pair, horizon) cell of Fig 7."""

    f_r: float
    pair: int  # 1-based index in the run's list of (R_κ, R_χ)
    R_range: float
    R_bearing: float
    horizon_s: float
    trials: int
    correct: int
    mode_correct: int
    repairs: int  # covariance repairs (state + innovation) in this pair's banks, over all horizons


@dataclass(frozen=True, eq=False)
class RadarLmpJob(JobHorizons):
    """The Fig 7 Monte Carlo: % correct (i, τ) vs horizon for every reference frequency and (R_κ, R_χ) pair.

    One record per trial (the longest horizon) serves every horizon; trial t uses the same draws in
    every pair (common random numbers), so pairs differ only by the noise level. Tasks of ≥ 0.1 s
    (a sigma-point trial costs ≈ 1.6 µs per filter-step, 2C + 1 filters), at most 50 trials, of one
    (f_r, pair) each; the counts do not depend on the engine or on ``chunk``.

    Attributes:
        cfg: Detector settings.
        fr_list: Reference frequencies [Hz], each in [0, 1e6] (the paper: 0.01).
        anr_pairs: Fig 7's (angle, range) ANR pairs, each 1–4 (their variances: ``anr_pair_variances``).
        pairs: (R_κ, R_χ) per pair; None: those of ``anr_pairs``. Given, they replace them (and the job has
            no table: its rows are labelled by the Fig 7 pairs).
        horizons_s: Horizons [s], each in [T, 1e6]; None: every 10 s to 80 s.
        trials: Trials per (f_r, pair) cell, >= 1; the run is refused above ~1 h or ~4 GB.
        seed, signature, vehicle, codes, chips, m_rho, f_c, chunk: As in
            :class:`~motionsig_cli.modesig.lmp1d.LmpJob`.
        method: ``"bank"`` (the sigma-point bank) or ``"linearised"`` (the projection of
            :mod:`motionsig_cli.detection.lmp_linearised`: a task is a block of trials at every pair at once).
        center: ``"none"``, ``"h0-noise"`` or ``"standardised"`` (the linearised path only).
        trial_offset: Trial t draws as trial ``trial_offset + t`` (the null records of a calibration).
    """

    name: ClassVar[str] = "detect --montecarlo --example 2d"

    cfg: RadarLMPConfig = field(default_factory=RadarLMPConfig)
    fr_list: tuple[float, ...] = (0.01,)
    anr_pairs: tuple[int, ...] = (1, 2, 3, 4)
    pairs: tuple[tuple[float, float], ...] | None = None
    horizons_s: tuple[float, ...] | None = None
    trials: int = 50
    seed: int = DEFAULT_SEED
    signature: bool = True
    vehicle: Vehicle2D = field(default_factory=Vehicle2D)
    codes: Codes = "corrected"
    chips: np.ndarray | None = None
    m_rho: int = 20
    f_c: float = 1.0
    chunk: int | None = None
    method: str = "bank"
    center: str = "none"
    trial_offset: int = 0

    def __post_init__(self) -> None:
        check_radar_method(self.method, self.center)
        for name in ("fr_list", "anr_pairs", "pairs", "horizons_s"):
            object.__setattr__(self, name, _tuple(getattr(self, name)))
        check_values("fr_list", self.fr_list, 0.0, unit="Hz")
        if self.pairs is None:
            if not self.anr_pairs:
                raise ConfigError("anr_pairs", self.anr_pairs, "holds no pair")
            for p in self.anr_pairs:
                one_of("anr_pairs", p, (1, 2, 3, 4))
            pairs = tuple(anr_pair_variances(p, self.vehicle.a_sig) for p in self.anr_pairs)
            object.__setattr__(self, "pairs", pairs)
        else:
            object.__setattr__(self, "pairs", tuple((float(a), float(b)) for a, b in self.pairs))
            object.__setattr__(self, "anr_pairs", ())
        if self.horizons_s is None:
            object.__setattr__(self, "horizons_s", FIG_HORIZONS)
        check_horizons(self.horizons_s, self.vehicle.T, MAX_HORIZON_S)
        check_values("fr_list", self.fr_list, 0.0, MAX_FR, unit="Hz")
        integer("trials", self.trials, 1)
        integer("seed", self.seed, 0)
        one_of("signature", self.signature, (False, True))
        one_of("codes", self.codes, ("corrected", "printed"))
        object.__setattr__(
            self, "chips", np.asarray(table1_chips(self.codes) if self.chips is None else self.chips, float)
        )
        integer("m_rho", self.m_rho, 1)
        if self.chunk is not None:
            integer("chunk", self.chunk, 1)
        n_runs = self.trials * len(self.fr_list) * len(self.pairs)
        if self.method == "bank":
            check_size(
                "trials", self.trials, 2 * self.n_candidates + 1, n_runs, self.n_samples, min(self.trials, 25)
            )
        elif n_runs * self.n_samples * LINEARISED_S > MAX_SECONDS:
            raise ConfigError(
                "trials", self.trials, f"would take ~{n_runs * self.n_samples * LINEARISED_S / 3600:.2g} h "
                f"(limit {MAX_SECONDS / 3600:g} h): fewer trials or shorter horizons",
            )  # fmt: skip

    @property
    def n_candidates(self) -> int:
        return n_candidates(self.chips, self.m_rho, self.cfg)

    def tasks(self) -> list[tuple[float, int, float, float, range]]:
        """(f_r, pair index, R_κ, R_χ, trials), f_r-major then pair."""
        C = self.n_candidates
        if self.method == "linearised":  # every pair in one task: (f_r, 0, nan, nan, trials)
            per = self.chunk or LINEARISED_BLOCK
            return [
                (float(fr), 0, math.nan, math.nan, r)
                for fr in self.fr_list
                for r in tasks_of(self.trials, per)
            ]
        per = self.chunk or min(50, trials_per_task(self.n_samples * (2 * C + 1) * 1.6e-6))
        keys = [(fr, p, pr) for fr in self.fr_list for p, pr in enumerate(self.pairs, start=1)]
        return [
            (float(fr), p, float(pr[0]), float(pr[1]), r)
            for fr, p, pr in keys
            for r in tasks_of(self.trials, per)
        ]

    def task_size(self, task: tuple[float, int, float, float, range]) -> int:
        return len(task[4])

    def run_task(self, task: tuple[float, int, float, float, range]) -> tuple[np.ndarray, np.ndarray, int]:
        """Trials ``task[4]`` of one (f_r, pair) → (% correct counts (H,), mode counts (H,), repairs); of the
        linearised path, every pair → counts (P, H)."""
        out = self.outcomes(task)
        ok, ok_mode = out["ok"], out["ok_mode"]
        if task[1] == 0:
            return ok.sum(1), ok_mode.sum(1), 0
        return ok[0].sum(0), ok_mode[0].sum(0), out["repairs"]

    def outcomes(self, task: tuple[float, int, float, float, range]) -> dict[str, Any]:
        """Per trial of a task: ``ok``, ``ok_mode``, ``lam_max``, ``best`` (P, B, H) (P = 1 pair, or every pair
        for the linearised path's tasks) and ``repairs``."""
        fr, pair, R_range, R_bearing, ids = task
        n = round(max(self.horizons_s) / self.vehicle.T)
        hz = [round(h / self.vehicle.T) for h in self.horizons_s]
        trials = [self.trial_offset + t for t in ids]
        pairs = self.pairs if pair == 0 else ((R_range, R_bearing),)
        ys, draws = [], []
        for Rk, Rc in pairs:
            veh = replace(self.vehicle, f_r=fr, R_range=Rk, R_bearing=Rc)
            sim, d = simulate_trials_2d(veh, self.chips, self.m_rho, self.f_c, n, self.seed, trials,
                                        signature=self.signature)  # fmt: skip
            ys.append(sim["y"])
            draws = d
        if self.method == "bank":
            res = lmp_detect_radar(ys[0], self.chips, veh, self.m_rho, self.cfg, hz)
        else:
            noise = np.repeat(np.asarray(pairs, float), len(ids), axis=0)
            res = lmp_detect_radar_linearised(np.concatenate(ys), self.chips, veh, self.m_rho, self.cfg, hz,
                                              noise=noise, center=self.center)  # type: ignore[arg-type]  # fmt: skip
        best, lam = res.best()  # (P·B, H)
        c = res.candidates
        shape = (len(pairs), len(ids), len(hz))
        ok_mode = (c.mode[best] == np.tile([d.mode for d in draws], len(pairs))[:, None]).reshape(shape)
        ok = ok_mode & (c.tau[best] == np.tile([d.tau for d in draws], len(pairs))[:, None]).reshape(shape)
        return dict(ok=ok, ok_mode=ok_mode, lam_max=lam.reshape(shape), best=best.reshape(shape),
                    repairs=int(sum(res.repairs)))  # fmt: skip

    def reduce(self, tasks: Sequence[tuple[float, int, float, float, range]],
               results: Sequence[tuple[np.ndarray, np.ndarray, int]]) -> RadarMonteCarlo:  # fmt: skip
        """Sum the tasks' counts (in task order) into the (f_r, pair, horizon) cells."""
        cells: list[RadarMCCell] = []
        for fr in self.fr_list:
            for p, (R_range, R_bearing) in enumerate(self.pairs, start=1):
                if self.method == "linearised":  # every pair in each task: row p − 1
                    mine = [
                        (r[0][p - 1], r[1][p - 1], 0)
                        for t, r in zip(tasks, results, strict=True)
                        if t[0] == fr
                    ]
                else:
                    mine = [res for t, res in zip(tasks, results, strict=True) if t[0] == fr and t[1] == p]
                ok_n = np.sum([m[0] for m in mine], axis=0)
                okm_n = np.sum([m[1] for m in mine], axis=0)
                repairs = sum(m[2] for m in mine)
                for j, hs in enumerate(self.horizons_s):
                    cells.append(
                        RadarMCCell(fr, p, R_range, R_bearing, float(hs), self.trials, int(ok_n[j]), int(okm_n[j]),
                                    repairs)
                    )  # fmt: skip
        return RadarMonteCarlo(self, cells)

    def identity(self) -> dict[str, Any]:
        extra = {} if self.method == "bank" else dict(method=self.method, center=self.center)
        if self.trial_offset:
            extra["trial_offset"] = self.trial_offset
        return dict(
            cfg=repr(self.cfg), fr_list=list(self.fr_list), pairs=[list(p) for p in self.pairs],
            horizons_s=list(self.horizons_s), trials=self.trials, seed=self.seed, signature=self.signature, **extra,
        )  # fmt: skip


class RadarMonteCarlo(CorrectCurves["RadarLmpJob", "RadarMCCell"]):
    """The cells of a :class:`RadarLmpJob`, and the command's table, figure data and summary."""

    def table(self) -> Table:
        """One row per (f_r, pair, horizon); the ANRs in the paper's 10·ln "dB", a_sig²/(2R) per channel."""
        job, veh = self.job, self.job.vehicle
        if len(job.anr_pairs) != len(job.pairs):
            raise ValueError("a table needs the Fig 7 pairs (anr_pairs), not explicit variances")
        rows = []
        for c in self.cells:
            pid = job.anr_pairs[c.pair - 1]
            a_ang, a_rng = veh.a_sig**2 / (2 * c.R_bearing), veh.a_sig**2 / (2 * c.R_range)
            rows.append(
                (c.f_r, pid, c.R_range, c.R_bearing, 10 * math.log(a_ang), 10 * math.log(a_rng),
                 SEED_ANR_PAIRS[pid - 1][0], SEED_ANR_PAIRS[pid - 1][1], c.horizon_s, c.pct, c.se_pct, c.pct_mode,
                 c.correct, c.trials, c.repairs)
            )  # fmt: skip
        cfg, n_cand = job.cfg, job.n_candidates
        meta = make_meta(
            "detect --montecarlo --example 2d", trials=job.trials, fr_list=list(job.fr_list),
            anr_pairs=list(job.anr_pairs), horizons_s=list(job.horizons_s), seed=job.seed, signature=job.signature,
            filter="ukf", **({"method": job.method, "center": job.center} if job.method != "bank" else {}), c_r=cfg.c_r, Q0=list(cfg.Q0), Q1=list(cfg.Q1), P0=cfg.P0, tau_grid=cfg.tau_grid,
            fc_grid=list(cfg.fc_grid), include_logdet=cfg.include_logdet, zdot=cfg.zdot, ut_alpha=cfg.sigma.alpha,
            ut_beta=cfg.sigma.beta, ut_kappa=cfg.sigma.kappa, T=veh.T, m_rho=job.m_rho, f_c=job.f_c, K=list(veh.K),
            a_sig=veh.a_sig, a_r=veh.a_r, sigma_a=veh.sigma_a, start=list(veh.start), sig_axes=veh.sig_axes,
            codes=job.codes, n_candidates=n_cand, chance_pct=100.0 / n_cand,
            correct=CORRECT,
            anr="the paper's 10*ln dB, a_sig^2 / (2 R) per channel; R_range inverted from the printed range label",
            trial_streams="trial t: SeedSequence(seed, spawn_key=(t, 0|1|2)) for (i,tau,theta) | (x,y) process | "
            "(range,bearing) noise",
        )  # fmt: skip
        columns = ("f_r", "anr_pair", "R_range", "R_bearing", "anr_angle_db_paper_ln", "anr_range_db_paper_ln",
                   "seed_angle_label", "seed_range_label", "horizon_s", "pct_correct", "se_pct", "pct_mode_correct",
                   "correct", "trials", "covariance_repairs")  # fmt: skip
        return Table(columns, rows, meta)

    def series(self) -> list[tuple[str, Callable[[Any], bool]]]:
        """One curve per ANR pair, labelled (angle, range)."""
        labels = [SEED_ANR_PAIRS[pid - 1] for pid in self.job.anr_pairs]
        return [
            (f"({ang:g}, {rg:g})", lambda c, k=k: c.pair == k) for k, (ang, rg) in enumerate(labels, start=1)
        ]

    def title(self) -> str:
        what = "UKF bank" if self.job.method == "bank" else "linearised projection"
        return f"2-D radar, {what}: {self.job.trials} trials per cell, c_r = {self.job.cfg.c_r:g}"

    def summary(self) -> str:
        reps = sum(c.repairs for c in self.cells) // max(1, len(self.job.horizons_s))
        return f"{super().summary()}; {reps} covariance repairs"


# ------------------------------------------------------------------------------ threshold calibration
@dataclass(frozen=True)
class RadarCalibrationCell(CalibrationCell):
    """:class:`~motionsig_cli.modesig.lmp1d.CalibrationCell` of one (f_r, ANR pair, horizon) of Fig 7
    (its ``R`` is the range variance R_κ), with the null argmax's spread over the candidates.

    Attributes:
        pair: 1-based index in the job's pairs.  R_bearing: R_χ [rad²].
        h0_top_mode_pct: % of the null records whose argmax lies in the most frequent mode (33.3 % uniform).
        h0_chi2_p: p-value of the chi-square test of a uniform null argmax over the candidates.
    """

    pair: int = 0
    R_bearing: float = math.nan
    h0_top_mode_pct: float = math.nan
    h0_chi2_p: float = math.nan


@dataclass(frozen=True, eq=False)
class RadarCalibrationJob:
    """``detect --calibrate --example 2d``: the null distribution of λ* = max_c Λ(c) (records without a
    signature), the threshold for ``pfa`` and P_D at it, per (f_r, ANR pair, horizon), and the ROC curves.

    Its tasks are those of two :class:`RadarLmpJob` arms: the null arm (``null_trials``, no signature, trial
    t drawn as trial 2^40 + t, the streams of the 1-D calibration) and the signature arm (``trials``).

    Attributes:
        method: ``"linearised"`` (default: the bank costs ~30 s per 50 trials and pair, and 20/P_FA null
            trials per pair add up) or ``"bank"``.
        center: ``"none"``, ``"h0-noise"`` or ``"standardised"`` (:mod:`motionsig_cli.detection.lmp_linearised`).
        pfa: Target false-alarm probability in (0, 1).  null_trials: per pair, 1 … MAX_NULL_TRIALS; None:
            ⌈20 / pfa⌉.  trials: signature trials per pair.
        Others: as in :class:`RadarLmpJob`.
    """

    name: ClassVar[str] = "detect --calibrate --example 2d"

    cfg: RadarLMPConfig = field(default_factory=RadarLMPConfig)
    fr_list: tuple[float, ...] = (0.01,)
    anr_pairs: tuple[int, ...] = (1, 2, 3, 4)
    horizons_s: tuple[float, ...] | None = None
    trials: int = 50
    null_trials: int | None = None
    pfa: float = 0.01
    seed: int = DEFAULT_SEED
    method: str = "linearised"
    center: str = "none"
    vehicle: Vehicle2D = field(default_factory=Vehicle2D)
    codes: Codes = "corrected"
    chips: np.ndarray | None = None
    m_rho: int = 20
    f_c: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "null_trials", calibration_null_trials(self.pfa, self.null_trials))
        for name in ("null_trials", "trials"):
            integer(name, getattr(self, name), 1, MAX_NULL_TRIALS)
        arm = self.arm(False)  # checks the shared fields (and the run time of the larger arm)
        self.arm(True)
        for name in ("fr_list", "anr_pairs", "horizons_s", "chips"):
            object.__setattr__(self, name, getattr(arm, name))

    def arm(self, signature: bool) -> RadarLmpJob:
        """The signature arm (``trials``) or the null arm (``null_trials``, no signature)."""
        return RadarLmpJob(
            self.cfg, self.fr_list, self.anr_pairs, None, self.horizons_s,
            self.trials if signature else self.null_trials, self.seed, signature, self.vehicle, self.codes,
            self.chips, self.m_rho, self.f_c, None, self.method, self.center, 0 if signature else NULL_OFFSET,
        )  # fmt: skip

    @property
    def warning(self) -> str | None:
        """A note when the null trials are too few for the target P_FA."""
        assert self.null_trials is not None
        return null_trials_warning(self.null_trials, self.pfa)

    def tasks(self) -> list[tuple[int, tuple[float, int, float, float, range]]]:
        """``(0 | 1, task of that arm)``: 0 = null records, 1 = with a signature; the null tasks first."""
        return [(0, t) for t in self.arm(False).tasks()] + [(1, t) for t in self.arm(True).tasks()]

    def task_size(self, task: tuple[int, tuple[float, int, float, float, range]]) -> int:
        return len(task[1][4])

    def run_task(self, task: tuple[int, tuple[float, int, float, float, range]]) -> dict[str, Any]:
        return self.arm(task[0] == 1).outcomes(task[1])

    def reduce(self, tasks: Sequence[tuple[int, Any]], results: Sequence[dict[str, Any]]) -> RadarCalibration:
        arm = self.arm(True)
        n_pairs = len(arm.pairs)

        def joined(which: int, fr: float, key: str) -> np.ndarray:
            """(P, trials, H) of one arm and f_r: the linearised tasks hold every pair, the bank's one each."""
            mine = [
                (t[1], res[key])
                for (w, t), res in zip(tasks, results, strict=True)
                if w == which and t[0] == fr
            ]
            if self.method == "linearised":
                return np.concatenate([a for _, a in mine], axis=1)
            return np.stack(
                [np.concatenate([a[0] for p, a in mine if p == q]) for q in range(1, n_pairs + 1)]
            )

        cands = candidate_grid(arm.chips.shape[0], arm.chips.shape[1], self.m_rho, self.cfg.as_grid)
        C = len(cands)
        null, sig, corr, h0_best = {}, {}, {}, {}
        cells: list[RadarCalibrationCell] = []
        from scipy.stats import chi2

        for fr in arm.fr_list:
            null[fr], sig[fr] = joined(0, fr, "lam_max"), joined(1, fr, "lam_max")
            corr[fr], h0_best[fr] = joined(1, fr, "ok"), joined(0, fr, "best")
            for p, (Rk, Rc) in enumerate(arm.pairs, start=1):
                for j, hs in enumerate(arm.horizons_s):
                    n0 = null[fr][p - 1, :, j]
                    thr = threshold_for(n0, self.pfa)
                    det = sig[fr][p - 1, :, j] > thr
                    best = h0_best[fr][p - 1, :, j]
                    counts = np.bincount(best, minlength=C)
                    expect = best.size / C
                    chi = float(np.sum((counts - expect) ** 2) / expect)
                    top = (
                        100.0
                        * np.max(np.bincount(cands.mode[best], minlength=arm.chips.shape[0]))
                        / best.size
                    )
                    cells.append(
                        RadarCalibrationCell(
                            fr, Rk, float(hs), self.pfa, thr, int(self.null_trials or 0), int(np.sum(n0 > thr)),
                            self.trials, int(det.sum()), int(np.sum(det & corr[fr][p - 1, :, j])), p, Rc, top,
                            float(chi2.sf(chi, C - 1)),
                        )
                    )  # fmt: skip
        return RadarCalibration(cells, null, sig, self)

    def identity(self) -> dict[str, Any]:
        return dict(
            method=self.method, center=self.center, cfg=repr(self.cfg), fr_list=list(self.fr_list),
            anr_pairs=list(self.anr_pairs), horizons_s=list(self.horizons_s or ()), trials=self.trials,
            null_trials=self.null_trials, pfa=self.pfa, seed=self.seed,
        )  # fmt: skip


@dataclass(frozen=True, eq=False)
class RadarCalibration:
    """Cells plus the raw maxima (for ROC curves): ``null[f_r]``, ``signal[f_r]`` are (P, trials, H)."""

    cells: list[RadarCalibrationCell]
    null: dict[float, np.ndarray]
    signal: dict[float, np.ndarray]
    job: RadarCalibrationJob

    def table(self) -> Table:
        job, veh = self.job, self.job.vehicle
        rows = []
        for c in self.cells:
            pid = job.anr_pairs[c.pair - 1]
            a_ang, a_rng = veh.a_sig**2 / (2 * c.R_bearing), veh.a_sig**2 / (2 * c.R)
            rows.append(
                (c.f_r, pid, c.R, c.R_bearing, 10 * math.log(a_ang), 10 * math.log(a_rng), SEED_ANR_PAIRS[pid - 1][0],
                 SEED_ANR_PAIRS[pid - 1][1], c.horizon_s, c.pfa, c.threshold, c.false_alarms / c.null_trials,
                 c.null_trials, c.pd, c.pd_se, c.detections_correct / c.trials, c.trials, c.h0_top_mode_pct,
                 c.h0_chi2_p)
            )  # fmt: skip
        cfg = job.cfg
        meta = make_meta(
            "detect --calibrate --example 2d", method=job.method, center=job.center, pfa=job.pfa, trials=job.trials,
            null_trials=job.null_trials, fr_list=list(job.fr_list), anr_pairs=list(job.anr_pairs),
            horizons_s=list(job.horizons_s or ()), seed=job.seed, c_r=cfg.c_r, Q0=list(cfg.Q0), Q1=list(cfg.Q1),
            P0=cfg.P0, tau_grid=cfg.tau_grid, fc_grid=list(cfg.fc_grid), include_logdet=cfg.include_logdet,
            zdot=cfg.zdot, ut_alpha=cfg.sigma.alpha, ut_beta=cfg.sigma.beta, ut_kappa=cfg.sigma.kappa, T=veh.T,
            m_rho=job.m_rho, f_c=job.f_c, codes=job.codes,
            statistic="max over candidates of Lambda (eq 29; with center h0-noise or standardised, of the "
            "centred or standardised statistic); declare present when it exceeds the threshold",
            threshold_rule="order statistic of the null maxima leaving at most floor(pfa * null_trials) above it",
            h0_uniformity="null argmax: % in the most frequent mode (33.3 uniform), chi-square p over candidates",
            trial_streams="signature trial t: SeedSequence(seed, spawn_key=(t, 0|1|2)); "
            "null trial t: spawn_key=(2^40 + t, 0|1|2), drawn with no signature",
        )  # fmt: skip
        columns = ("f_r", "anr_pair", "R_range", "R_bearing", "anr_angle_db_paper_ln", "anr_range_db_paper_ln",
                   "seed_angle_label", "seed_range_label", "horizon_s", "pfa_target", "threshold", "pfa_in_sample",
                   "null_trials", "pd", "pd_se", "pd_and_correct", "trials", "h0_top_mode_pct",
                   "h0_argmax_chi2_p")  # fmt: skip
        return Table(columns, rows, meta)

    def figure_data(self) -> tuple[dict[str, dict[str, tuple[np.ndarray, np.ndarray]]], float, str]:
        """(panel → {horizon → ROC curve}, P_FA, title) for :func:`motionsig_cli.plotting.calibration_roc_figure`."""
        job = self.job
        panels: dict[str, dict[str, tuple[np.ndarray, np.ndarray]]] = {}
        for fr in job.fr_list:
            for p, pid in enumerate(job.anr_pairs):
                name = f"pair {pid} {SEED_ANR_PAIRS[pid - 1]}" + (
                    f", f_r={fr:g}" if len(job.fr_list) > 1 else ""
                )
                panels[name] = {
                    f"{h:g} s": roc_curve(self.null[fr][p, :, j], self.signal[fr][p, :, j])
                    for j, h in enumerate(job.horizons_s or ())
                }
        return (
            panels,
            job.pfa,
            f"2-D radar, {job.method} (center {job.center}): {job.trials} + {job.null_trials} null",
        )

    def summary(self) -> str:
        job = self.job
        return (
            f"{len(self.cells)} cells; threshold for P_FA = {job.pfa:g} from {job.null_trials} null trials per pair "
            f"({job.method}, center {job.center})"
        )
