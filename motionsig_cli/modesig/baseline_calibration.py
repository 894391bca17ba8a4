"""``detect --calibrate --detector estimate-correlate``: the estimate-then-correlate baseline's threshold
calibration on the records of ``detect --calibrate`` (the mode-signature paper, 47th IEEE CDC, Cancún,
2008, §I: the detector the LMP test replaces).

The job is a thin layer over :class:`~motionsig_cli.modesig.baseline_roc.BaselineRocJob`: one such job
per (f_r, R) cell supplies the records (its :meth:`~BaselineRocJob.records`: signature trial t from
``trial_rng(seed, t, 0|1|2)``, null trial t from ``trial_rng(seed, 2^40 + t, …)``, the streams of the
LMP's ``detect --calibrate``, so both detectors are calibrated on the same records) and the checks of the
shared fields; only the baseline runs on them (:func:`estimate_correlate_detect`). The threshold rule, the
cells and the table's columns are those of the LMP's calibration
(:class:`~motionsig_cli.modesig.lmp1d.CalibrationJob`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from motionsig_cli.config import ConfigError, integer, positive
from motionsig_cli.detection.estimate_correlate import ECConfig, estimate_correlate_detect
from motionsig_cli.engine import tasks_of
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.modesig.baseline_roc import BaselineRocJob
from motionsig_cli.modesig.lmp1d import (
    FIG_HORIZONS,
    SEED_ANR_LABELS,
    CalibrationCell,
    Codes,
    anr_db,
    null_trials_warning,
    roc_curve,
    threshold_for,
)
from motionsig_cli.rng import DEFAULT_SEED
from motionsig_cli.tables import Table, make_meta

TRIALS_PER_TASK = 100  # records per task (fixed by the parameters, never the machine)


@dataclass(frozen=True)
class _Outcomes:
    lam: np.ndarray  # (B, H) max over candidates of the baseline's statistic
    ok: np.ndarray  # (B, H) (i, τ) right


@dataclass(frozen=True, eq=False)
class BaselineCalibrationJob:
    """The baseline's null distribution of max_c ρ(c), its threshold for ``pfa`` and P_D at it, per
    (f_r, R, horizon).

    Attributes:
        ec: The baseline's settings.
        fr_list, R_list: Reference frequencies [Hz] and measurement variances of the cells.
        horizons_s: Horizons [s]; None: every 10 s to 80 s.
        trials, null_trials, pfa, seed: As in :class:`~motionsig_cli.modesig.lmp1d.CalibrationJob`
            (null_trials None: ⌈20 / pfa⌉).
        vehicle: The simulated truth and the model the baseline's filter assumes (its R and f_r are each
            cell's); its a_sig must be > 0.
        codes, m_rho, f_c: The codes, samples per chip and carrier of the records.
    """

    name: ClassVar[str] = "detect --calibrate --detector estimate-correlate"

    ec: ECConfig = field(default_factory=ECConfig)
    fr_list: tuple[float, ...] = (0.01,)
    R_list: tuple[float, ...] = (1e-1, 1e-2, 1e-3, 1e-5)
    horizons_s: tuple[float, ...] | None = None
    trials: int = 50
    null_trials: int | None = None
    pfa: float = 0.01
    seed: int = DEFAULT_SEED
    vehicle: Vehicle1D = field(default_factory=Vehicle1D)
    codes: Codes = "corrected"
    m_rho: int = 20
    f_c: float = 1.0

    def __post_init__(self) -> None:
        if not isinstance(self.ec, ECConfig):
            raise ConfigError("ec", self.ec, "is not an ECConfig")
        for name in ("fr_list", "R_list"):
            value = tuple(getattr(self, name) or ())
            if not value:
                raise ConfigError(name, value, "holds no value")
            object.__setattr__(self, name, value)
        object.__setattr__(self, "horizons_s", tuple(self.horizons_s or FIG_HORIZONS))
        positive("a_sig", self.vehicle.a_sig)  # a signature to detect (the a_sig of the signature records)
        integer("trials", self.trials, 1)
        cell = self.cell(0)  # BaselineRocJob checks the rest (pfa, null_trials, horizons, codes, m_rho, f_c)
        object.__setattr__(self, "null_trials", cell.null_trials)
        for k in range(len(self.keys)):
            self.cell(k)

    @property
    def keys(self) -> list[tuple[float, float]]:
        """The cells' (R, f_r), R-major (the order of the LMP's calibration table)."""
        return [(float(R), float(fr)) for R in self.R_list for fr in self.fr_list]

    def cell(self, k: int) -> BaselineRocJob:
        """The :class:`BaselineRocJob` of cell k (one amplitude: the vehicle's a_sig)."""
        R, fr = self.keys[k]
        return BaselineRocJob(
            "1d", (self.vehicle.a_sig,), self.horizons_s, self.trials, self.null_trials, self.pfa, self.seed,
            replace(self.vehicle, R=R, f_r=fr), ec=self.ec, codes=self.codes, m_rho=self.m_rho, f_c=self.f_c,
        )  # fmt: skip

    @property
    def warning(self) -> str | None:
        """A note when the null trials are too few for the target P_FA."""
        return null_trials_warning(self.null_trials, self.pfa)

    def tasks(self) -> list[tuple[int, int, range]]:
        """``(cell, 0 | 1, trials)``: 0 = null records, 1 = signature records; the null tasks first."""
        out = [(k, 0, r) for k in range(len(self.keys)) for r in tasks_of(self.null_trials, TRIALS_PER_TASK)]
        return out + [
            (k, 1, r) for k in range(len(self.keys)) for r in tasks_of(self.trials, TRIALS_PER_TASK)
        ]

    def task_size(self, task: tuple[int, int, range]) -> int:
        return len(task[2])

    def run_task(self, task: tuple[int, int, range]) -> _Outcomes:
        k, which, ids = task
        job = self.cell(k)
        y, modes, taus = job.records((which, 0, ids))
        res = estimate_correlate_detect(y, job.chips, job.vehicle, self.m_rho, self.ec, job.horizon_samples)  # type: ignore[arg-type]
        best, mx = res.best()
        c = res.candidates
        return _Outcomes(mx, (c.mode[best] == modes[:, None]) & (c.tau[best] == taus[:, None]))

    def reduce(
        self, tasks: Sequence[tuple[int, int, range]], results: Sequence[_Outcomes]
    ) -> BaselineCalibration:
        def joined(k: int, which: int, attr: str) -> np.ndarray:
            mine = [getattr(o, attr) for t, o in zip(tasks, results, strict=True) if t[:2] == (k, which)]
            return np.concatenate(mine, axis=0)  # (trials, H)

        cells, null, signal = [], {}, {}
        for k, (R, fr) in enumerate(self.keys):
            null[R, fr], signal[R, fr], ok = joined(k, 0, "lam"), joined(k, 1, "lam"), joined(k, 1, "ok")
            for j, h in enumerate(self.horizons_s):
                thr = threshold_for(null[R, fr][:, j], self.pfa)
                det = signal[R, fr][:, j] > thr
                cells.append(
                    CalibrationCell(
                        fr, R, float(h), self.pfa, thr, self.null_trials, int(np.sum(null[R, fr][:, j] > thr)),
                        self.trials, int(det.sum()), int(np.sum(det & ok[:, j])),
                    )
                )  # fmt: skip
        return BaselineCalibration(self, cells, null, signal)

    def identity(self) -> dict[str, Any]:
        return dict(
            detector="estimate-correlate", ec=repr(self.ec), fr_list=list(self.fr_list), R_list=list(self.R_list),
            horizons_s=list(self.horizons_s), trials=self.trials, null_trials=self.null_trials, pfa=self.pfa,
            seed=self.seed, vehicle=repr(self.vehicle), codes=self.codes, m_rho=self.m_rho, f_c=self.f_c,
        )  # fmt: skip


@dataclass(frozen=True, eq=False)
class BaselineCalibration:
    """The cells and the raw maxima ``null[(R, f_r)]``, ``signal[(R, f_r)]`` (trials, H), for ROC curves."""

    job: BaselineCalibrationJob
    cells: list[CalibrationCell]
    null: dict[tuple[float, float], np.ndarray]
    signal: dict[tuple[float, float], np.ndarray]

    def table(self) -> Table:
        """The columns of the LMP's ``detect --calibrate`` table; the metadata names the detector."""
        job, veh = self.job, self.job.vehicle
        rows = []
        for c in self.cells:
            lin, l10, lnl = anr_db(c.R, veh.a_sig)
            rows.append(
                (c.f_r, c.R, lin, l10, lnl, SEED_ANR_LABELS.get(c.R, ""), c.horizon_s, c.pfa, c.threshold,
                 c.false_alarms / c.null_trials, c.null_trials, c.pd, c.pd_se, c.detections_correct / c.trials,
                 c.trials)
            )  # fmt: skip
        ec = job.ec
        meta = make_meta(
            "detect --calibrate", detector="estimate-correlate", pfa=job.pfa, trials=job.trials,
            null_trials=job.null_trials, fr_list=list(job.fr_list), R_list=list(job.R_list),
            horizons_s=list(job.horizons_s), seed=job.seed, c_r=ec.c_r, Q0=list(ec.Q0), q_e=ec.q_e,
            a_nom=ec.a_nom, P0=ec.P0, A_r=ec.A_r, lag=ec.lag, estimate=ec.estimate, detrend=ec.detrend,
            tau_grid=ec.tau_grid, fc_grid=list(ec.fc_grid), zdot=ec.zdot, T=veh.T, m_rho=job.m_rho, f_c=job.f_c,
            K=list(veh.K), a_sig=veh.a_sig, a_r=veh.a_r, sigma_a=veh.sigma_a, codes=job.codes,
            statistic="max over candidates of the estimate-then-correlate statistic; declare present when it "
            "exceeds the threshold",
            threshold_rule="order statistic of the null maxima leaving at most floor(pfa * null_trials) above it",
            trial_streams="signature trial t: SeedSequence(seed, spawn_key=(t, 0|1|2)); "
            "null trial t: spawn_key=(2^40 + t, 0|1|2), drawn with no signature (the LMP's --calibrate records)",
        )  # fmt: skip
        columns = ("f_r", "R", "anr_linear", "anr_db_log10", "anr_db_paper_ln", "seed_anr_label", "horizon_s",
                   "pfa_target", "threshold", "pfa_in_sample", "null_trials", "pd", "pd_se", "pd_and_correct",
                   "trials")  # fmt: skip
        return Table(columns, rows, meta)

    def figure_data(self) -> tuple[dict[str, dict[str, tuple[np.ndarray, np.ndarray]]], float, str]:
        """The arguments of :func:`motionsig_cli.plotting.calibration_roc_figure`."""
        job = self.job
        panels = {}
        for R, fr in job.keys:
            name = f"ANR {anr_db(R, job.vehicle.a_sig)[2]:.1f} paper dB (R={R:g})" + (
                f", f_r={fr:g}" if len(job.fr_list) > 1 else ""
            )
            panels[name] = {
                f"{h:g} s": roc_curve(self.null[R, fr][:, j], self.signal[R, fr][:, j])
                for j, h in enumerate(job.horizons_s)
            }
        return panels, job.pfa, f"estimate-correlate: {job.trials} + {job.null_trials} null trials"

    def summary(self) -> str:
        job = self.job
        return (
            f"{len(self.cells)} cells (estimate-then-correlate); threshold for P_FA = {job.pfa:g} from "
            f"{job.null_trials} null trials each"
        )


EC_FIELDS = ("c_r", "Q0", "P0", "A_r", "tau_grid", "fc_grid", "zdot")  # the LMP settings the baseline shares


def baseline_calibration_job(
    lmp: dict[str, Any], fr_list: Sequence[float] | None, R_list: Sequence[float] | None,
    horizons_s: Sequence[float] | None, trials: int, null_trials: int | None, pfa: float, seed: int,
    model: dict[str, Any],
) -> BaselineCalibrationJob:  # fmt: skip
    """The job of ``detect --calibrate --detector estimate-correlate`` from the LMP's settings (``lmp``: the
    :class:`~motionsig_cli.detection.lmp.LMPConfig` fields; those of :data:`EC_FIELDS` carry over, the rest
    have no counterpart in the baseline) and the Monte Carlo's model (vehicle, m_rho, f_c)."""
    ec = ECConfig(**{k: v for k, v in lmp.items() if k in EC_FIELDS})
    return BaselineCalibrationJob(
        ec, tuple(fr_list or (0.01,)), tuple(R_list or (1e-1, 1e-2, 1e-3, 1e-5)),
        None if horizons_s is None else tuple(horizons_s), trials, null_trials, pfa, seed, **model,
    )  # fmt: skip
