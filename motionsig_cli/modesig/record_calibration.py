"""Is there a signature in ONE user record at all? A threshold on max Λ calibrated for that record.

The detector of eq (52) always names a best candidate, λ* = max_c Λ(c) (eq 29), signature or not.
To test for a signature at a false-alarm probability P_FA, the threshold must be the (1 − P_FA)
quantile of λ* on records *without* a signature that are otherwise like the user's: the same model
(the vehicle, measurement variance and codes the filters assume), the same length and the same
missing samples (a missing sample is a predict-only step of every filter, which changes the null
distribution). :class:`RecordNullJob` simulates such null records, runs the same detector on each and
keeps λ* per horizon; :class:`RecordThreshold` holds the thresholds (the order-statistic rule of
:func:`~motionsig_cli.modesig.lmp1d.threshold_for`, shared with ``detect --calibrate``).

Random streams: null trial t draws from ``SeedSequence(seed, spawn_key=(2^40 + t, 0|1|2))`` (the null
trials of :class:`~motionsig_cli.modesig.lmp1d.CalibrationJob`), so it never reuses the streams of
``motionsig simulate --seed s`` (trial 0). The trials are evaluated in fixed blocks of
:attr:`RecordNullJob.block` trials (a block's floating-point work does not depend on which other trials
share its task), so the thresholds are identical for any chunking, worker count or scheduler.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of
from motionsig_cli.detection.lmp import (
    LMPConfig,
    LMPResult,
    RadarLMPConfig,
    candidate_grid,
    lmp_detect,
    lmp_detect_radar,
)
from motionsig_cli.detection.lmp_fft import lmp_detect_fft
from motionsig_cli.detection.lmp_linearised import lmp_detect_radar_linearised
from motionsig_cli.engine import check_run_time, trials_per_task
from motionsig_cli.filters.unscented import SigmaPointParams
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.models.vehicle2d import Vehicle2D
from motionsig_cli.modesig.lmp1d import (
    MAX_BANK_GB,
    MAX_NULL_TRIALS,
    NULL_OFFSET,
    Method,
    check_record_detector,
    simulate_trials,
    threshold_for,
)
from motionsig_cli.modesig.lmp2d import check_radar_method, simulate_trials_2d
from motionsig_cli.modesig.record_reading import VehicleRecord, record_horizons
from motionsig_cli.rng import DEFAULT_SEED

MAX_SECONDS = 600.0  # the interactive limit of the estimated run time on the run's workers (check_run_time)
HOW = "null records simulated from the record's model, same length and missing samples"
# trials evaluated together (see the module docstring), at most: many for the Kalman bank and the FFT path
# (their per-trial work is a few elementwise passes), few for the sigma-point banks (their covariances are
# kept per trial); fewer where a block's arrays would exceed BLOCK_BYTES (assumed: 50 MB for the banks, a
# working set that stays near the caches: the innovations of a 6000-filter bank ran ~1.5x slower per trial
# in blocks of 170; 250 MB for the FFT path, whose fixed cost per call is worth sharing over more trials)
BLOCK = {"kf": 256, "fft": 256, "ukf": 16, "linearised": 64}
BLOCK_BYTES = {"kf": 5e7, "fft": 2.5e8, "ukf": 5e7, "linearised": 2.5e8}
# cost model [s], measured on a 2-core machine (see RecordNullJob.cost)
KF_RICCATI = 1.6e-6  # per filter-step of the Riccati recursion (once per task)
KF_TRIAL = 3e-8  # per filter-step and trial of the innovations (2e-8 … 5e-8 measured, by bank and block)
SIM_STEP = 1e-5  # per time step and block of the simulation's loop
# the FFT path: per call (steady state, impulse response) and per code-period sample, mode, horizon and
# carrier (the replicas' FFTs); per trial and carrier: per sample (whitening), per sample and horizon (the
# folded innovations), per code-period sample, mode and horizon (the cross-correlations)
FFT_CALL, FFT_CALL_XCORR = 0.05, 1.5e-7
FFT_SAMPLE, FFT_FOLD, FFT_XCORR = 1e-7, 2e-8, 5e-8
UKF_TRIAL_1D = 4e-7  # per filter-step and trial of the 1-D sigma-point bank (4 and 5 states), blocks of 16
UKF_TRIAL_2D = 1.3e-6  # per filter-step and trial of the radar bank (8 and 10 states), blocks of 16
# the radar's linearised path: per time step and call (its per-step fixed cost), per time step and trial
LIN_CALL, LIN_TRIAL = 3e-4, 1.5e-5


@dataclass(frozen=True)
class RecordThreshold:
    """The null distribution of λ* for one record and the thresholds it gives.

    Attributes:
        thresholds: The threshold per horizon (H,): declare "signature present" when λ* > threshold.
        pfa: The target false-alarm probability.
        null_trials: Null records simulated.
        horizons: The horizons [s].
        null_max: λ* of every null record, (null_trials, H).
        method, filter: The detector that ran (``filter`` is ``"ukf"`` for a radar record).
        seed: Root seed of the null trials.
    """

    thresholds: np.ndarray
    pfa: float
    null_trials: int
    horizons: tuple[float, ...]
    null_max: np.ndarray
    method: str
    filter: str
    seed: int

    @property
    def false_alarms(self) -> np.ndarray:
        """Null maxima above each threshold (H,): at most ⌊pfa · null_trials⌋."""
        return np.sum(self.null_max > self.thresholds[None, :], axis=0)

    @property
    def warning(self) -> str | None:
        """A note when the null trials are too few for the target P_FA."""
        if self.null_trials * self.pfa >= 1:
            return None
        return (
            f"warning: {self.null_trials} null records < 1/P_FA: the threshold is the largest null maximum, "
            f"its false-alarm rate is not {self.pfa:g}"
        )

    def decide(self, lam_max: np.ndarray) -> np.ndarray:
        """The decision per horizon for the record's λ* (H,): True = "signature present"."""
        return np.asarray(lam_max, float) > self.thresholds

    def meta(self) -> dict[str, Any]:
        """The calibration as metadata (JSON values)."""
        return dict(
            pfa=self.pfa,
            null_trials=self.null_trials,
            thresholds=[float(t) for t in self.thresholds],
            horizons_s=list(self.horizons),
            method=self.method,
            filter=self.filter,
            how=HOW,
            threshold_rule="order statistic of the null maxima leaving at most floor(pfa * null_trials) above it",
            decision="signature present when max over candidates of Lambda (eq 29) > threshold",
            null_seed=self.seed,
            null_streams="null record t: SeedSequence(seed, spawn_key=(2^40 + t, 0|1|2)), no signature",
        )


@dataclass(frozen=True, eq=False)
class RecordNullJob:
    """Null records like one user record, the same detector on each, and λ* per horizon.

    Each null trial simulates a record of the record's model (its vehicle as the truth, no signature),
    as long as the detector's longest horizon, with the record's missing samples (NaN there), and runs
    the detector the record's detection runs. :meth:`reduce` gives a :class:`RecordThreshold`.

    Attributes:
        record: The user's record (1-D or 2-D radar; NaN marks a missing sample).
        cfg: Detector settings, :class:`LMPConfig` (1-D) or :class:`RadarLMPConfig` (radar record).
        method: ``"bank"`` or ``"fft"`` (1-D only; the FFT path cannot skip a missing sample), or for a radar
            record ``"linearised"`` (:mod:`motionsig_cli.detection.lmp_linearised`; missing samples are
            predict-only steps, as in the bank).
        filter: ``"kf"`` or ``"ukf"`` (1-D); a radar record always runs the sigma-point bank.
        sigma: Unscented-transform parameters of the 1-D ``"ukf"`` bank (a radar record uses ``cfg.sigma``).
        horizons: Horizons [s]; None: every 10 s of the record
            (:func:`~motionsig_cli.modesig.record_reading.record_horizons`).
        pfa: Target false-alarm probability, in (0, 1).
        null_trials: Null records, 1 … :data:`MAX_NULL_TRIALS`; None: ⌈20 / pfa⌉. A job estimated above
            ~10 minutes on one core is refused.
        seed: Root seed (>= 0).
        chunk: Null trials per task, rounded up to whole blocks (None: from the cost model); the result does
            not depend on it.
        center: The radar linearised path's ``center`` (``"none"``, ``"h0-noise"`` or ``"standardised"``): the
            null records run the statistic the record's detection runs.
    """

    name: ClassVar[str] = "detect --pfa"

    record: VehicleRecord
    cfg: LMPConfig | RadarLMPConfig
    method: Method | Literal["linearised"] = "bank"
    filter: Literal["kf", "ukf"] = "kf"
    sigma: SigmaPointParams = field(default_factory=SigmaPointParams)
    horizons: tuple[float, ...] | None = None
    pfa: float = 0.01
    null_trials: int | None = None
    seed: int = DEFAULT_SEED
    chunk: int | None = None
    center: str = "none"

    def __post_init__(self) -> None:
        rec = self.record
        veh = getattr(rec, "vehicle", None)
        if not isinstance(veh, Vehicle1D | Vehicle2D):
            raise ConfigError("record", type(rec).__name__, "is not a record with a 1-D or 2-D vehicle")
        y = np.asarray(rec.y, float)
        if y.shape[:1] == (0,) or y.shape[1:] != ((2,) if self.two_d else ()):
            raise ConfigError("record", y.shape, "is not a (N,) or (N, 2) array of measurements")
        if self.two_d:
            if not isinstance(self.cfg, RadarLMPConfig):
                raise ConfigError("cfg", type(self.cfg).__name__, "is not a RadarLMPConfig (a radar record)")
        elif not isinstance(self.cfg, LMPConfig):
            raise ConfigError("cfg", type(self.cfg).__name__, "is not an LMPConfig (a 1-D record)")
        one_of("filter", self.filter, ("kf", "ukf"))
        if not isinstance(self.sigma, SigmaPointParams):
            raise ConfigError("sigma", self.sigma, "is not a SigmaPointParams")
        if self.two_d:
            one_of("method", self.method, ("bank", "linearised"))
            check_radar_method(self.method, self.center)
        else:
            one_of("center", self.center, ("none",))
            assert isinstance(self.cfg, LMPConfig)
            check_record_detector(self.method, self.filter, self.cfg, self.sigma)
        T = veh.T
        hs = record_horizons(self.horizons, y.shape[0] * T, T)
        object.__setattr__(self, "horizons", tuple(float(h) for h in hs))
        if self.method == "fft" and self.missing.any():
            i = int(np.flatnonzero(self.missing)[0])
            raise ConfigError(
                "method",
                "fft",
                f"cannot skip a missing sample (sample {i}, t = {i * T:g} s): use --method bank",
            )
        in_range("pfa", self.pfa, 0.0, 1.0, lo_open=True, hi_open=True)
        if self.null_trials is None:
            n = math.ceil(20 / self.pfa)
            if n > MAX_NULL_TRIALS:
                raise ConfigError(
                    "pfa", self.pfa, f"needs 20/P_FA = {20 / self.pfa:.1e} null records by default, more than "
                    f"{MAX_NULL_TRIALS:.0e}: raise it or set the number of null trials",
                )  # fmt: skip
            object.__setattr__(self, "null_trials", n)
        integer("null_trials", self.null_trials, 1, MAX_NULL_TRIALS)
        integer("seed", self.seed, 0)
        if self.chunk is not None:
            integer("chunk", self.chunk, 1)
        n_filters = 2 * self.n_candidates + 1
        need_gb = n_filters * self.n_used * 7 * 8 / 1e9  # Kalman bank: gains, S⁻¹, log det per filter-step
        if self.bank == "kf" and need_gb > MAX_BANK_GB:
            raise ConfigError(
                "horizons", max(hs), f"s is too long for the bank of {n_filters} filters: it would need an "
                f"estimated {need_gb:.1f} GB per worker; the limit is {MAX_BANK_GB:g} GB: use shorter horizons "
                "or a coarser grid",
            )  # fmt: skip
        check_run_time(  # on the workers the run has; --max-minutes raises the limit, --checkpoint lifts it
            "null_trials", self.null_trials, self.estimate_seconds(), MAX_SECONDS, what="null records ",
            also="raise P_FA, set fewer null trials, use shorter horizons"
            + (", the FFT path (--method fft)" if self.bank == "kf" else "") + " or a coarser grid; or ",
        )  # fmt: skip

    # ------------------------------------------------------------------------------------------ shape
    @property
    def two_d(self) -> bool:
        """A radar record (range, bearing)."""
        return isinstance(self.record.vehicle, Vehicle2D)

    @property
    def bank(self) -> str:
        """What runs: ``"kf"`` (Kalman bank), ``"ukf"`` (a sigma-point bank), ``"fft"`` or ``"linearised"``
        (the radar's projection)."""
        if self.two_d and self.method == "linearised":
            return "linearised"
        if self.two_d or self.filter == "ukf":
            return "ukf"
        return "fft" if self.method == "fft" else "kf"

    @property
    def horizon_samples(self) -> list[int]:
        assert self.horizons is not None
        return [round(h / self.record.vehicle.T) for h in self.horizons]

    @property
    def n_used(self) -> int:
        """Samples of every null record (the longest horizon)."""
        return max(self.horizon_samples)

    @property
    def missing(self) -> np.ndarray:
        """The record's missing samples within the longest horizon, (n_used,) bool (a radar sample is
        missing where its row holds a NaN)."""
        y = np.asarray(self.record.y, float)[: self.n_used]
        nan = np.isnan(y)
        return nan.any(axis=1) if nan.ndim == 2 else nan

    @property
    def n_candidates(self) -> int:
        rec = self.record
        grid = self.cfg.as_grid if isinstance(self.cfg, RadarLMPConfig) else self.cfg
        return len(candidate_grid(rec.chips.shape[0], rec.chips.shape[1], rec.m_rho, grid))

    @property
    def block(self) -> int:
        """Trials evaluated together: :data:`BLOCK` of the path, fewer where a block's arrays would exceed
        :data:`BLOCK_BYTES` (a function of the parameters only, like the chunking)."""
        rec, C, H = self.record, self.n_candidates, len(self.horizons or ())
        filters = 2 * C + 1
        if self.bank == "kf":  # the bank's means, innovations and their products, (filters, 5, trials)
            per_trial = filters * 5 * 8 * 6
        elif self.bank == "fft":  # folded innovations and cross-correlations (H, period) and C statistics
            period = rec.chips.shape[1] * rec.m_rho
            per_trial = H * max(self.n_used, period) * 16 * 6 + C * H * 8 * 10
        elif self.bank == "linearised":  # the basis responses and one segment of them, and C statistics
            per_trial = 8 * 8 * rec.chips.shape[1] * (10 + 2 * 256) + C * H * 8 * 12
        else:  # the sigma-point bank's covariances and factors, (n, n, filters, trials)
            n = 10 if self.two_d else 5
            per_trial = n * n * filters * 8 * 4
        return int(max(1, min(BLOCK[self.bank], BLOCK_BYTES[self.bank] // per_trial)))

    # ------------------------------------------------------------------------------------------ cost
    def cost(self) -> tuple[float, float]:
        """Cost model [s] of a task: (fixed, per trial), measured on a 2-core machine.

        Kalman bank: its Riccati recursion, once per task (~1.6 µs per filter-step), and the innovations
        (~3e-8 s per filter-step and trial); FFT path: per call (block) ~0.05 s and 0.15 µs per code-period
        sample, mode, horizon and carrier, per trial and carrier 0.1 µs per sample, 0.02 µs per sample and
        horizon and 0.05 µs per code-period sample, mode and horizon;
        sigma-point banks: ~0.4 µs (1-D) and ~1.3 µs (radar) per filter-step and trial; the radar's linearised
        path ~15 µs per time step and trial and ~0.3 ms per time step and block. Every path adds
        the simulation loop (~10 µs per time step and block). Good to a factor of ~2 (the machine's load,
        the bank's size).
        """
        n, filters = self.n_used, 2 * self.n_candidates + 1
        sim = n * SIM_STEP / self.block
        if self.bank == "linearised":
            return 0.0, n * (LIN_TRIAL + LIN_CALL / self.block) + sim
        if self.bank == "kf":
            return n * filters * KF_RICCATI, n * filters * KF_TRIAL + sim
        if self.bank == "fft":
            M, H = self.record.chips.shape[0], len(self.horizons or ())
            period = self.record.chips.shape[1] * self.record.m_rho
            nF = len(self.cfg.fc_grid)
            call = FFT_CALL + nF * M * H * period * FFT_CALL_XCORR
            per = nF * (n * FFT_SAMPLE + n * H * FFT_FOLD + M * H * period * FFT_XCORR)
            return 0.0, per + call / self.block + sim
        return 0.0, n * filters * (UKF_TRIAL_2D if self.two_d else UKF_TRIAL_1D) + sim

    def per_task(self) -> int:
        """Null trials per task: whole blocks, worth ≥ 0.1 s and ≥ 4× the task's fixed cost."""
        fixed, per_trial = self.cost()
        want = self.chunk or trials_per_task(per_trial, fixed_seconds=fixed, at_most=MAX_NULL_TRIALS)
        return math.ceil(want / self.block) * self.block

    def estimate_seconds(self) -> float:
        """The job's estimated run time on one core [s]."""
        fixed, per_trial = self.cost()
        assert self.null_trials is not None
        return len(self.tasks()) * fixed + self.null_trials * per_trial

    # ------------------------------------------------------------------------------------------ the job
    def tasks(self) -> list[range]:
        """Null trials 0 … null_trials − 1 in chunks of whole blocks (the last one shorter)."""
        assert self.null_trials is not None
        per = self.per_task()
        return [range(s, min(self.null_trials, s + per)) for s in range(0, self.null_trials, per)]

    def task_size(self, task: range) -> int:
        return len(task)

    def simulate(self, ids: Sequence[int]) -> np.ndarray:
        """Null records of the given trials, (B, n_used) or (B, n_used, 2), NaN at the missing samples."""
        rec, n = self.record, self.n_used
        trials = [NULL_OFFSET + t for t in ids]
        if self.two_d:
            assert isinstance(rec.vehicle, Vehicle2D)
            sim, _ = simulate_trials_2d(
                rec.vehicle, rec.chips, rec.m_rho, rec.f_c, n, self.seed, trials, signature=False
            )
            y = sim["y"]
        else:
            assert isinstance(rec.vehicle, Vehicle1D)
            y, _ = simulate_trials(
                rec.vehicle, rec.chips, rec.m_rho, rec.f_c, n, self.seed, trials, signature=False
            )
        y[:, self.missing] = np.nan
        return y

    def detect(self, y: np.ndarray) -> LMPResult:
        """The record's detector on records y (B, n_used[, 2])."""
        rec, hz = self.record, self.horizon_samples
        if self.two_d:
            assert isinstance(self.cfg, RadarLMPConfig) and isinstance(rec.vehicle, Vehicle2D)
            if self.method == "linearised":
                center: Any = self.center
                return lmp_detect_radar_linearised(
                    y, rec.chips, rec.vehicle, rec.m_rho, self.cfg, hz, center=center
                )
            return lmp_detect_radar(y, rec.chips, rec.vehicle, rec.m_rho, self.cfg, hz)
        assert isinstance(self.cfg, LMPConfig) and isinstance(rec.vehicle, Vehicle1D)
        if self.method == "fft":
            return lmp_detect_fft(y, rec.chips, rec.vehicle, rec.m_rho, self.cfg, hz)
        if self.filter == "ukf":
            return lmp_detect(
                y, rec.chips, rec.vehicle, rec.m_rho, self.cfg, hz, filter="ukf", sigma=self.sigma
            )
        return lmp_detect(y, rec.chips, rec.vehicle, rec.m_rho, self.cfg, hz, block=self.block)

    def run_task(self, task: range) -> np.ndarray:
        """λ* per horizon of the null trials ``task``, (len(task), H): block by block (the Kalman bank
        shares its Riccati recursion over the task's blocks)."""
        b = self.block
        starts = range(task.start, task.stop, b)
        if self.bank == "kf":
            return self.detect(self.simulate(task)).best()[1]
        return np.concatenate(
            [self.detect(self.simulate(range(s, min(task.stop, s + b)))).best()[1] for s in starts]
        )

    def reduce(self, tasks: Sequence[range], results: Sequence[np.ndarray]) -> RecordThreshold:
        """The thresholds from every null record's λ* (tasks in order)."""
        assert self.null_trials is not None and self.horizons is not None
        null_max = np.concatenate(list(results), axis=0)
        if null_max.shape[0] != self.null_trials:
            raise ValueError("the tasks do not cover the null trials")
        thr = np.array([threshold_for(null_max[:, j], self.pfa) for j in range(null_max.shape[1])])
        return RecordThreshold(
            thr, self.pfa, self.null_trials, self.horizons, null_max, self.method,
            "ukf" if self.two_d else self.filter, self.seed,
        )  # fmt: skip

    def identity(self) -> dict[str, Any]:
        """What the null records depend on: the record's model, length and missing samples (not its
        measured values)."""
        rec = self.record
        digest = hashlib.sha256(np.packbits(self.missing).tobytes() + rec.chips.tobytes()).hexdigest()
        return dict(
            vehicle=repr(rec.vehicle), m_rho=int(rec.m_rho), f_c=float(rec.f_c), n_used=self.n_used, missing_and_codes=digest,
            cfg=repr(self.cfg), method=self.method, filter=self.filter, sigma=repr(self.sigma),
            horizons=list(self.horizons or ()), pfa=self.pfa, null_trials=self.null_trials, seed=self.seed,
            **({"center": self.center} if self.method == "linearised" else {}),
        )  # fmt: skip
