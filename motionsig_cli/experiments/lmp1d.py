"""The 1-D LMP experiment of seed 000 §IV.A: one trial = draw (i, τ, θ), simulate, detect.

Random streams (so a trial's numbers depend on (seed, trial) only, never on batching):
``trial_rng(seed, t, 0)`` draws i, τ, θ; ``(seed, t, 1)`` the process noise; ``(seed, t, 2)`` the
measurement noise. ``motionsig simulate --seed s`` with the defaults is trial 0 of
``motionsig detect --montecarlo --seed s`` at the same settings.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import partial
from typing import Any, Literal

import numpy as np

from motionsig_cli.detection.lmp import LMPConfig, LMPResult, candidate_grid, lmp_detect
from motionsig_cli.detection.lmp_fft import lmp_detect_fft
from motionsig_cli.engine import Engine, run_tasks, tasks_of, trials_per_task
from motionsig_cli.models.vehicle import Vehicle1D, simulate_1d
from motionsig_cli.rng import trial_rng
from motionsig_cli.signals.signature import ZdotMethod, replica_bank

SEED_ANR_LABELS = {1e-1: 2.2, 1e-2: 25.3, 1e-3: 48.3, 1e-5: 94.3}  # seed 000 Figs 4–6 axis labels ("dB")


def anr_db(R: float, a_sig: float = 0.5) -> tuple[float, float, float]:
    """ANR = a²/(2R) (eq 58) as (linear, 10·log10 dB, the seed's 10·ln "dB")."""
    anr = a_sig**2 / (2 * R)
    return anr, 10 * math.log10(anr), 10 * math.log(anr)


@dataclass(frozen=True)
class TrialDraw:
    """The random inputs of one trial."""

    mode: int  # 0-based
    tau: int  # samples (on the chip grid)
    theta: float
    w: np.ndarray  # standard-normal process noise, (N,) or (N, 2)
    v: np.ndarray  # standard-normal measurement noise, (N,) or (N, 2)


def draw_trial(
    seed: int, trial: int, n_samples: int, n_modes: int, n_rho: int, m_rho: int, dims: int = 1
) -> TrialDraw:
    """Draw i ~ U{modes}, τ ~ U{chip grid}, θ ~ U[0, 2π) and the two noise sequences of one trial.

    ``dims = 2`` (the radar example) draws (N, 2) noise: (x, y) process noise, (range, bearing)
    measurement noise; i, τ and θ are the same as for ``dims = 1``.
    """
    g = trial_rng(seed, trial, 0)
    mode = int(g.integers(n_modes))
    tau = int(g.integers(n_rho)) * m_rho
    theta = float(g.uniform(0.0, 2 * math.pi))
    shape = n_samples if dims == 1 else (n_samples, dims)
    w = trial_rng(seed, trial, 1).standard_normal(shape)
    v = trial_rng(seed, trial, 2).standard_normal(shape)
    return TrialDraw(mode, tau, theta, w, v)


def signature_batch(
    chips: np.ndarray,
    modes: np.ndarray,
    taus: np.ndarray,
    thetas: np.ndarray,
    f_c: float,
    T: float,
    m_rho: int,
    n: int,
    zdot: ZdotMethod = "analytic",
) -> tuple[np.ndarray, np.ndarray]:
    """z = cos θ z_cos − sin θ z_sin and ż for a batch of (i, τ, θ) (eqs 2–3, f_d = 0)."""
    fcs = np.full(len(modes), f_c)
    zc, zs, dc, ds = replica_bank(chips, np.asarray(modes), np.asarray(taus), fcs, T, m_rho, n, zdot)
    c, s = np.cos(thetas)[:, None], np.sin(thetas)[:, None]
    return c * zc - s * zs, c * dc - s * ds


def simulate_trials(
    vehicle: Vehicle1D,
    chips: np.ndarray,
    m_rho: int,
    f_c: float,
    n_samples: int,
    seed: int,
    trials: Sequence[int],
    *,
    signature: bool = True,
) -> tuple[np.ndarray, list[TrialDraw]]:
    """Measurements (B, N) of the given trials and their draws."""
    draws = [draw_trial(seed, t, n_samples, chips.shape[0], chips.shape[1], m_rho) for t in trials]
    modes = np.array([d.mode for d in draws])
    taus = np.array([d.tau for d in draws])
    thetas = np.array([d.theta for d in draws])
    z, zd = signature_batch(chips, modes, taus, thetas, f_c, vehicle.T, m_rho, n_samples)
    if not signature:
        z, zd = np.zeros_like(z), np.zeros_like(zd)
    sim = simulate_1d(vehicle, z, zd, np.stack([d.w for d in draws]), np.stack([d.v for d in draws]))
    return sim["y"], draws


class CorrectRates:
    """% correct, % mode correct and the binomial standard error of a cell with ``trials``, ``correct`` and
    ``mode_correct`` (shared by the 1-D and the 2-D radar Monte Carlo cells)."""

    trials: int
    correct: int
    mode_correct: int

    @property
    def pct(self) -> float:
        return 100.0 * self.correct / self.trials

    @property
    def pct_mode(self) -> float:
        return 100.0 * self.mode_correct / self.trials

    @property
    def se_pct(self) -> float:
        """Binomial standard error of the percentage, √(p(1−p)/n)."""
        p = self.correct / self.trials
        return 100.0 * math.sqrt(p * (1 - p) / self.trials)


@dataclass(frozen=True)
class MCCell(CorrectRates):
    """Monte Carlo result of one (f_r, R, horizon) cell."""

    f_r: float
    R: float
    horizon_s: float
    trials: int
    correct: int
    mode_correct: int


Method = Literal["bank", "fft"]


@dataclass(frozen=True)
class MCSpec:
    """Everything a Monte Carlo task of Figs 4–6 needs (picklable: it travels to the workers)."""

    vehicle: Vehicle1D
    chips: np.ndarray
    m_rho: int
    f_c: float
    cfg: LMPConfig
    fr_list: tuple[float, ...]
    horizons_s: tuple[float, ...]
    seed: int
    signature: bool = True
    method: Method = "bank"

    @property
    def n_samples(self) -> int:
        return round(max(self.horizons_s) / self.vehicle.T)

    @property
    def horizon_samples(self) -> list[int]:
        return [round(h / self.vehicle.T) for h in self.horizons_s]


@dataclass(frozen=True)
class TrialOutcomes:
    """Per-trial results of one task: (f_r, trial, horizon) arrays."""

    ok: np.ndarray  # (i, τ) both right
    ok_mode: np.ndarray  # mode right
    lam_max: np.ndarray  # λ* = max_c Λ(c), eq (29)


def detect_batch(y: np.ndarray, spec: MCSpec, R: float) -> LMPResult:
    """The configured detector (bank or FFT path) on records y (B, N) at measurement variance R."""
    veh = replace(spec.vehicle, R=R)
    if spec.method == "fft":
        return lmp_detect_fft(y, spec.chips, veh, spec.m_rho, spec.cfg, spec.horizon_samples)
    return lmp_detect(y, spec.chips, veh, spec.m_rho, spec.cfg, spec.horizon_samples)


def mc_task(spec: MCSpec, task: tuple[float, range]) -> TrialOutcomes:
    """One task: the trials ``task[1]`` at measurement variance ``task[0]``, every f_r."""
    R, ids = task
    ys, truths = [], []
    for fr in spec.fr_list:
        veh = replace(spec.vehicle, R=R, f_r=fr)
        y, draws = simulate_trials(
            veh,
            spec.chips,
            spec.m_rho,
            spec.f_c,
            spec.n_samples,
            spec.seed,
            list(ids),
            signature=spec.signature,
        )
        ys.append(y)
        truths.extend(draws)
    res = detect_batch(np.concatenate(ys), spec, R)
    best, lam = res.best()  # (F·B, H), records ordered f_r-major
    c = res.candidates
    ok_mode = c.mode[best] == np.array([d.mode for d in truths])[:, None]
    ok = ok_mode & (c.tau[best] == np.array([d.tau for d in truths])[:, None])
    shape = (len(spec.fr_list), len(ids), len(spec.horizons_s))
    return TrialOutcomes(ok.reshape(shape), ok_mode.reshape(shape), lam.reshape(shape))


def task_cost(spec: MCSpec) -> tuple[float, float]:
    """Cost model [s] of a task at one R: (fixed, per trial over all f_r), measured on a 2-core machine.

    The bank's fixed part is its Riccati recursion (2C + 1 filters, ≈ 0.37 s at N = 1600), the per-trial
    part the innovations (≈ 1.2e-8 s per filter-step); the FFT path's fixed part is the simulation and
    whitening loops over N (≈ 2e-5 s per sample), its per-trial part ≈ 8e-7 s per sample and f_r.
    """
    n, F = spec.n_samples, len(spec.fr_list)
    if spec.method == "fft":
        return n * 2e-5, F * n * 8e-7
    C = len(candidate_grid(spec.chips.shape[0], spec.chips.shape[1], spec.m_rho, spec.cfg))
    return n * 2.3e-4, F * n * (2 * C + 1) * 1.2e-8


def mc_tasks(
    spec: MCSpec, R_list: Sequence[float], trials: int, *, chunk: int | None = None
) -> list[tuple[float, range]]:
    """The tasks of a run: for every R, the trials in chunks worth ≥ 0.1 s and ≥ 4× the task's fixed cost
    (so chunking adds at most 25 %), with at most 200 records in memory."""
    if trials < 1:
        raise ValueError("the number of trials must be >= 1")
    fixed, per_trial = task_cost(spec)
    per = chunk or min(max(1, 200 // len(spec.fr_list)), trials_per_task(per_trial, fixed_seconds=fixed))
    return [(float(R), r) for R in R_list for r in tasks_of(trials, per)]


def cells_of(spec: MCSpec, R_list: Sequence[float], trials: int, tasks: Sequence[tuple[float, range]],
             results: Sequence[TrialOutcomes]) -> list[MCCell]:  # fmt: skip
    """Sum the tasks' outcomes (in task order) into the (f_r, R, horizon) cells."""
    cells: list[MCCell] = []
    for R in R_list:
        mine = [res for (r, _), res in zip(tasks, results, strict=True) if r == R]
        ok = np.concatenate([m.ok for m in mine], axis=1).sum(axis=1)  # (F, H)
        okm = np.concatenate([m.ok_mode for m in mine], axis=1).sum(axis=1)
        for f, fr in enumerate(spec.fr_list):
            for j, hs in enumerate(spec.horizons_s):
                cells.append(MCCell(fr, R, float(hs), trials, int(ok[f, j]), int(okm[f, j])))
    return cells


def monte_carlo(
    vehicle: Vehicle1D,
    chips: np.ndarray,
    m_rho: int,
    f_c: float,
    cfg: LMPConfig,
    fr_list: Sequence[float],
    R_list: Sequence[float],
    horizons_s: Sequence[float],
    trials: int,
    seed: int,
    *,
    chunk: int | None = None,
    on_chunk: Callable[[int], None] | None = None,
    signature: bool = True,
    method: Method = "bank",
    engine: Engine | None = None,
    identity: dict[str, Any] | None = None,
) -> list[MCCell]:
    """% correct (i, τ) vs horizon for every (f_r, R) — Figs 4–6.

    One record per trial (the longest horizon) serves every horizon. Trial t of every cell uses the
    same draws (common random numbers across f_r and R), so cells differ only by f_r and R. One
    Riccati recursion per task serves all f_r and trials (the filters do not know f_r). The tasks run
    on ``engine`` (default: this process); the counts do not depend on it or on ``chunk``.
    """
    spec = MCSpec(vehicle, np.asarray(chips, float), m_rho, f_c, cfg, tuple(fr_list), tuple(horizons_s), seed,
                  signature, method)  # fmt: skip
    tasks = mc_tasks(spec, R_list, trials, chunk=chunk)
    results = run_tasks(
        partial(mc_task, spec),
        tasks,
        engine or Engine(),
        sizes=[len(t[1]) for t in tasks],
        progress=on_chunk,
        identity=identity,
    )
    return cells_of(spec, R_list, trials, tasks, results)


# ------------------------------------------------------------------------------ threshold calibration
NULL_OFFSET = (
    1 << 40
)  # null trial t draws from trial_rng(seed, NULL_OFFSET + t, …): independent of the H1 trials


@dataclass(frozen=True)
class CalibrationCell:
    """Threshold for a false-alarm probability and the detection probability at it, one (f_r, R, horizon).

    ``threshold`` is the order statistic of the null maxima λ* = max_c Λ(c) (no signature) that leaves
    at most ``pfa`` of them above it; "present" is declared when λ* > threshold.
    """

    f_r: float
    R: float
    horizon_s: float
    pfa: float
    threshold: float
    null_trials: int
    false_alarms: int  # null maxima above the threshold (the in-sample P_FA ≤ pfa)
    trials: int
    detections: int  # signature trials with λ* > threshold
    detections_correct: int  # … and (i, τ) right

    @property
    def pd(self) -> float:
        return self.detections / self.trials

    @property
    def pd_se(self) -> float:
        return math.sqrt(self.pd * (1 - self.pd) / self.trials)


def threshold_for(null_max: np.ndarray, pfa: float) -> float:
    """The smallest order statistic t of ``null_max`` with #{λ* > t} ≤ ⌊pfa n⌋."""
    s = np.sort(np.asarray(null_max, dtype=float))
    n = s.size
    k = math.floor(pfa * n)  # maxima allowed above the threshold
    if k >= n:
        return -math.inf
    return float(s[n - k - 1])


def calib_task(specs: tuple[MCSpec, MCSpec], task: tuple[int, float, range]) -> TrialOutcomes:
    """A calibration task: ``task = (0 | 1, R, trials)``, 0 = null records (no signature), 1 = with it."""
    which, R, ids = task
    if which == 0:
        ids = range(NULL_OFFSET + ids.start, NULL_OFFSET + ids.stop)
    return mc_task(specs[which], (R, ids))


@dataclass(frozen=True)
class Calibration:
    """Cells plus the raw maxima (for ROC curves): ``null[R]``, ``signal[R]`` are (F, trials, H)."""

    cells: list[CalibrationCell]
    null: dict[float, np.ndarray]
    signal: dict[float, np.ndarray]
    correct: dict[float, np.ndarray]


def calibrate(
    spec: MCSpec,
    R_list: Sequence[float],
    trials: int,
    null_trials: int,
    pfa: float,
    *,
    engine: Engine | None = None,
    identity: dict[str, Any] | None = None,
    on_chunk: Callable[[int], None] | None = None,
) -> Calibration:
    """Null distribution of λ*, the threshold for ``pfa`` and P_D at it, per (f_r, R, horizon).

    The result does not depend on the engine. The chunking (fixed by the parameters) batches the
    filters' floating-point work, so another chunk size may move the thresholds' last bits; the
    counts are exact integers either way.
    """
    if not 0 < pfa < 1:
        raise ValueError(f"the false-alarm probability must lie in (0, 1), got {pfa:g}")
    if null_trials < 1 or trials < 1:
        raise ValueError("trials and null trials must be >= 1")
    specs = (replace(spec, signature=False), replace(spec, signature=True))
    tasks = [(0, R, r) for R, r in mc_tasks(specs[0], R_list, null_trials)]
    tasks += [(1, R, r) for R, r in mc_tasks(specs[1], R_list, trials)]
    results = run_tasks(
        partial(calib_task, specs),
        tasks,
        engine or Engine(),
        sizes=[len(t[2]) for t in tasks],
        progress=on_chunk,
        identity=identity,
    )
    null, sig, corr = {}, {}, {}
    for R in R_list:
        null[R] = np.concatenate(
            [o.lam_max for t, o in zip(tasks, results, strict=True) if t[:2] == (0, R)], axis=1
        )
        sig[R] = np.concatenate(
            [o.lam_max for t, o in zip(tasks, results, strict=True) if t[:2] == (1, R)], axis=1
        )
        corr[R] = np.concatenate(
            [o.ok for t, o in zip(tasks, results, strict=True) if t[:2] == (1, R)], axis=1
        )
    cells = []
    for R in R_list:
        for f, fr in enumerate(spec.fr_list):
            for j, hs in enumerate(spec.horizons_s):
                thr = threshold_for(null[R][f, :, j], pfa)
                det = sig[R][f, :, j] > thr
                cells.append(
                    CalibrationCell(
                        fr, float(R), float(hs), pfa, thr, null_trials, int(np.sum(null[R][f, :, j] > thr)),
                        trials, int(det.sum()), int(np.sum(det & corr[R][f, :, j])),
                    )
                )  # fmt: skip
    return Calibration(cells, null, sig, corr)


def roc_curve(null_max: np.ndarray, signal_max: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Empirical (P_FA, P_D) of the test λ* > t for every t among the pooled maxima."""
    t = np.unique(np.concatenate([null_max, signal_max]))
    n0, n1 = np.sort(null_max), np.sort(signal_max)
    pfa = 1.0 - np.searchsorted(n0, t, side="right") / n0.size
    pd = 1.0 - np.searchsorted(n1, t, side="right") / n1.size
    return np.concatenate([[1.0], pfa]), np.concatenate([[1.0], pd])
