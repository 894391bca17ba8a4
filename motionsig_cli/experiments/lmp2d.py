"""The 2-D radar experiment of the mode-signature paper (LMP mode detection with Gold-code signatures, IEEE
CDC 2008, §IV.B, Fig 7): one radar record through the sigma-point bank, and the Fig 7 Monte Carlo (one
trial = draw (i, τ, θ), simulate, detect) as the job :class:`RadarLmpJob`.

The random streams are those of :mod:`motionsig_cli.experiments.lmp1d` with two-column noise:
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
from motionsig_cli.detection.lmp import RadarLMPConfig, candidate_grid, lmp_detect_radar
from motionsig_cli.engine import tasks_of, trials_per_task
from motionsig_cli.experiments.lmp1d import (
    CORRECT,
    FIG_HORIZONS,
    Codes,
    CorrectCurves,
    CorrectRates,
    RecordHorizons,
    Threshold,
    TrialDraw,
    _tuple,
    check_horizons,
    check_threshold,
    check_values,
    n_grid_candidates,
    record_notes,
    table1_chips,
    trial_signatures,
)
from motionsig_cli.experiments.lmp_record import RecordResult, record_result, sigma_meta
from motionsig_cli.experiments.record_reading import VehicleRecord, record_horizons
from motionsig_cli.filters.kalman import Progress
from motionsig_cli.models.vehicle2d import SEED_ANR_PAIRS, Vehicle2D, anr_pair_variances, simulate_2d
from motionsig_cli.rng import DEFAULT_SEED
from motionsig_cli.tables import Table, make_meta

MAX_SECONDS = 3600.0  # estimated run time limit of one run
MAX_GB = 4.0  # estimated memory limit of one bank
MAX_HORIZON_S = 1e6  # the Monte Carlo's longest horizon [s]
MAX_FR = 1e6  # the Monte Carlo's highest reference frequency [Hz]


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


def check_size(field_name: str, value: Any, n_filters: int, trials: int, n_samples: int, batch: int) -> None:
    """Refuse runs over ~1 h or ~4 GB before any work: ~(2 + 10/B) µs per filter-step for B records at
    once (measured), and the candidate replicas and transitions, ~6 arrays of (filters × samples) doubles.
    The :class:`ConfigError` names ``field_name`` (the field to change) with its ``value``."""
    seconds = float(n_filters) * trials * n_samples * (2 + 10 / batch) * 1e-6
    gb = 6.0 * n_filters * n_samples * 8 / 1e9
    if seconds > MAX_SECONDS or gb > MAX_GB:
        raise ConfigError(
            field_name, value, f"would take ~{seconds / 3600:.2g} h and ~{gb:.2g} GB (limits "
            f"{MAX_SECONDS / 3600:g} h, {MAX_GB:g} GB): fewer trials, shorter horizons or a coarser grid",
        )  # fmt: skip


def n_candidates(chips: np.ndarray, m_rho: int, cfg: RadarLMPConfig) -> int:
    """Candidates (i, τ, f_c) of the grid."""
    return len(candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg.as_grid))


# ---------------------------------------------------------------------------------------- one record
@dataclass(frozen=True, eq=False)
class RadarRecordDetection(RecordHorizons):
    """Eq (52) with the sigma-point bank on one radar record: the argmax per horizon, or every candidate.

    Attributes:
        record: The record (:func:`motionsig_cli.experiments.record_reading.read_vehicle_record`); a
            missing sample (a NaN row) is a predict-only step of the bank.
        cfg: Detector settings.
        horizons: Horizons [s] (see :func:`~motionsig_cli.experiments.record_reading.record_horizons`);
            None: every 10 s. The run is refused above ~1 h or ~4 GB (:func:`check_size`).
        threshold: Declare "signature present" when max Λ >= threshold: one number, or one per horizon
            (a threshold calibrated for the record); None: no decision.
        candidates: Every candidate's statistic instead of the argmax.
        threshold_meta: How a calibrated threshold was found (metadata), or None.
    """

    record: VehicleRecord
    cfg: RadarLMPConfig
    horizons: tuple[float, ...] | None = None
    threshold: Threshold = None
    candidates: bool = False
    threshold_meta: dict[str, Any] | None = None

    def __post_init__(self) -> None:
        rec, T = self.record, self.record.vehicle.T
        hs = record_horizons(self.horizons, rec.y.shape[0] * T, T)
        object.__setattr__(self, "horizons", tuple(hs))
        n_modes, n_rho = rec.chips.shape
        C = n_grid_candidates(n_modes, n_rho, rec.m_rho, self.cfg.tau_grid, len(self.cfg.fc_grid))
        check_size("horizons", max(hs), 2 * C + 1, 1, self.n_used, 1)
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
            res = lmp_detect_radar(y, rec.chips, rec.vehicle, rec.m_rho, cfg, hz, progress=progress)
        except ValueError as exc:
            if np.isnan(y).any():  # a bank without predict-only steps
                self.missing_checked(f"the filter bank cannot skip a missing sample ({exc})")
            raise
        params = dict(
            source=rec.source, example="2d", filter="ukf", c_r=cfg.c_r, Q0=list(cfg.Q0), Q1=list(cfg.Q1),
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
class RadarLmpJob:
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
            :class:`~motionsig_cli.experiments.lmp1d.LmpJob`.
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

    def __post_init__(self) -> None:
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
        check_size(
            "trials", self.trials, 2 * self.n_candidates + 1, n_runs, self.n_samples, min(self.trials, 25)
        )

    @property
    def n_samples(self) -> int:
        return round(max(self.horizons_s) / self.vehicle.T)

    @property
    def n_candidates(self) -> int:
        return n_candidates(self.chips, self.m_rho, self.cfg)

    def tasks(self) -> list[tuple[float, int, float, float, range]]:
        """(f_r, pair index, R_κ, R_χ, trials), f_r-major then pair."""
        C = self.n_candidates
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
        """Trials ``task[4]`` of one (f_r, pair) → (% correct counts (H,), mode counts (H,), repairs)."""
        fr, _, R_range, R_bearing, ids = task
        veh = replace(self.vehicle, f_r=fr, R_range=R_range, R_bearing=R_bearing)
        n = round(max(self.horizons_s) / veh.T)
        hz = [round(h / veh.T) for h in self.horizons_s]
        sim, draws = simulate_trials_2d(veh, self.chips, self.m_rho, self.f_c, n, self.seed, list(ids),
                                        signature=self.signature)  # fmt: skip
        res = lmp_detect_radar(sim["y"], self.chips, veh, self.m_rho, self.cfg, hz)
        best, _ = res.best()  # (B, H)
        c = res.candidates
        ok_mode = c.mode[best] == np.array([d.mode for d in draws])[:, None]
        ok = ok_mode & (c.tau[best] == np.array([d.tau for d in draws])[:, None])
        return ok.sum(0), ok_mode.sum(0), int(sum(res.repairs))

    def reduce(self, tasks: Sequence[tuple[float, int, float, float, range]],
               results: Sequence[tuple[np.ndarray, np.ndarray, int]]) -> RadarMonteCarlo:  # fmt: skip
        """Sum the tasks' counts (in task order) into the (f_r, pair, horizon) cells."""
        cells: list[RadarMCCell] = []
        for fr in self.fr_list:
            for p, (R_range, R_bearing) in enumerate(self.pairs, start=1):
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
        return dict(
            cfg=repr(self.cfg), fr_list=list(self.fr_list), pairs=[list(p) for p in self.pairs],
            horizons_s=list(self.horizons_s), trials=self.trials, seed=self.seed, signature=self.signature,
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
            filter="ukf", c_r=cfg.c_r, Q0=list(cfg.Q0), Q1=list(cfg.Q1), P0=cfg.P0, tau_grid=cfg.tau_grid,
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
        return f"2-D radar, UKF bank: {self.job.trials} trials per cell, c_r = {self.job.cfg.c_r:g}"

    def summary(self) -> str:
        reps = sum(c.repairs for c in self.cells) // max(1, len(self.job.horizons_s))
        return f"{super().summary()}; {reps} covariance repairs"
