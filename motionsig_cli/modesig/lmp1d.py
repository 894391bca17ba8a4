"""The 1-D LMP experiment of the mode-signature paper (47th IEEE CDC, Cancún, 2008, §IV.A, Figs 3–6): one record through the detector, and the Monte Carlo of Figs 4–6 (one trial =
draw (i, τ, θ), simulate, detect) with its threshold calibration.

Random streams (so a trial's numbers depend on (seed, trial) only, never on batching):
``trial_rng(seed, t, 0)`` draws i, τ, θ; ``(seed, t, 1)`` the process noise; ``(seed, t, 2)`` the
measurement noise; ``(seed, t, 3)`` the vehicle's own position sensor (drawn only with
``feedback="estimate"``). ``motionsig simulate --seed s`` with the defaults is trial 0 of
``motionsig detect --montecarlo --seed s`` at the same settings.

The Monte Carlo runs are :class:`~motionsig_cli.engine.MonteCarloJob` classes (:class:`LmpJob`,
:class:`CalibrationJob`); their results build the command's table (``table()``), the figure's data and a
one-line summary. :class:`RecordDetection` runs the detector on one record
(:mod:`motionsig_cli.modesig.record_reading` reads it, :mod:`motionsig_cli.modesig.lmp_record`
tabulates the result).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar, Generic, Literal, TypeVar

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of
from motionsig_cli.detection.lmp import (
    LMPConfig,
    LMPResult,
    candidate_grid,
    filter_model,
    lmp_detect,
    progress_steps,
)
from motionsig_cli.detection.lmp_fft import check_fft_config, lmp_detect_fft
from motionsig_cli.engine import check_run_time, tasks_of, trials_per_task
from motionsig_cli.filters.kalman import Progress
from motionsig_cli.filters.unscented import SigmaPointParams
from motionsig_cli.models.vehicle import (
    DEFAULT_R,
    ONBOARD_ESTIMATOR,
    Vehicle1D,
    nominal_reference,
    simulate_1d,
)
from motionsig_cli.models.vehicle2d import Vehicle2D
from motionsig_cli.modesig.lmp_record import RecordResult, record_result, sigma_meta
from motionsig_cli.modesig.record_reading import VehicleRecord, record_horizons
from motionsig_cli.rng import DEFAULT_SEED, trial_rng
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import table1_codes
from motionsig_cli.signals.signature import ZdotMethod, replica_bank
from motionsig_cli.tables import Table, make_meta

# the paper's axis labels of Figs 4–6 ("dB", 10·ln) for the measurement variances behind them
SEED_ANR_LABELS = {1e-1: 2.2, 1e-2: 25.3, 1e-3: 48.3, 1e-5: 94.3}
MAX_MC_TRIALS = 100_000_000  # records of one Monte Carlo run (trials x R)
MAX_NULL_TRIALS = 2_000_000  # null (and signature) trials per calibration cell: 16 B each per horizon kept
MAX_BANK_GB = 4.0  # a single record's filter bank: gains, S⁻¹ and log det of every filter and step
Method = Literal["bank", "fft"]
Codes = Literal["corrected", "printed"]


def anr_db(R: float, a_sig: float = 0.5) -> tuple[float, float, float]:
    """ANR = a²/(2R) (eq 58) as (linear, 10·log10 dB, the paper's 10·ln "dB")."""
    anr = a_sig**2 / (2 * R)
    return anr, 10 * math.log10(anr), 10 * math.log(anr)


def table1_chips(codes: Codes = "corrected") -> np.ndarray:
    """The Table I codes as bipolar chips (3, 31), floats."""
    return to_bipolar(table1_codes(codes)).astype(float)


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
    """z = cos θ z_cos − sin θ z_sin and ż for a batch of (i, τ, θ) (eqs 2–3; ``f_c`` is the carrier as
    received, f_c + f_d of eq 3)."""
    fcs = np.full(len(modes), f_c)
    zc, zs, dc, ds = replica_bank(chips, np.asarray(modes), np.asarray(taus), fcs, T, m_rho, n, zdot)
    c, s = np.cos(thetas)[:, None], np.sin(thetas)[:, None]
    return c * zc - s * zs, c * dc - s * ds


def trial_signatures(
    chips: np.ndarray,
    m_rho: int,
    f_c: float,
    T: float,
    n_samples: int,
    seed: int,
    trials: Sequence[int],
    *,
    signature: bool = True,
    dims: int = 1,
) -> tuple[list[TrialDraw], np.ndarray, np.ndarray]:
    """The draws of the given trials (:func:`draw_trial`) and their signatures z, ż (B, N) (zero without
    ``signature``): the inputs of the 1-D and the 2-D simulation."""
    draws = [draw_trial(seed, t, n_samples, chips.shape[0], chips.shape[1], m_rho, dims=dims) for t in trials]
    modes = np.array([d.mode for d in draws])
    taus = np.array([d.tau for d in draws])
    thetas = np.array([d.theta for d in draws])
    z, zd = signature_batch(chips, modes, taus, thetas, f_c, T, m_rho, n_samples)
    if not signature:
        z, zd = np.zeros_like(z), np.zeros_like(zd)
    return draws, z, zd


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
    """Measurements (B, N) of the given trials and their draws.

    The signature's carrier is f_c + ``vehicle.f_d`` (eq 3); with ``vehicle.feedback == "estimate"`` the
    vehicle's own sensor draws from ``trial_rng(seed, t, 3)``.
    """
    draws, z, zd = trial_signatures(
        chips, m_rho, f_c + vehicle.f_d, vehicle.T, n_samples, seed, trials, signature=signature
    )
    v_own = own_sensor_noise(vehicle, seed, trials, n_samples)
    sim = simulate_1d(vehicle, z, zd, np.stack([d.w for d in draws]), np.stack([d.v for d in draws]), v_own)
    return sim["y"], draws


def own_sensor_noise(
    vehicle: Vehicle1D, seed: int, trials: Sequence[int], n_samples: int
) -> np.ndarray | None:
    """The standard-normal noise (B, N) of the vehicle's own position sensor (``feedback="estimate"``):
    trial t draws from ``trial_rng(seed, t, 3)``; None with true-state feedback (nothing drawn)."""
    if vehicle.feedback != "estimate":
        return None
    return np.stack([trial_rng(seed, t, 3).standard_normal(n_samples) for t in trials])


class JobHorizons:
    """The horizons of a Monte Carlo job (``horizons_s`` [s], ``vehicle.T`` the sample period) in samples."""

    horizons_s: Sequence[float]
    vehicle: Vehicle1D | Vehicle2D

    @property
    def n_samples(self) -> int:
        """Samples a trial's record holds: the longest horizon."""
        return round(max(self.horizons_s) / self.vehicle.T)

    @property
    def horizon_samples(self) -> list[int]:
        return [round(h / self.vehicle.T) for h in self.horizons_s]


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
    """Monte Carlo result of one (f_r, R, horizon) cell; with a carrier search (more than one candidate
    carrier, or f_d ≠ 0) also the trials whose estimated carrier is the grid's nearest to the true one and
    the root-mean-square error of the estimated carrier [Hz]."""

    f_r: float
    R: float
    horizon_s: float
    trials: int
    correct: int
    mode_correct: int
    fc_correct: int | None = None
    fc_rmse: float | None = None

    @property
    def pct_fc(self) -> float:
        assert self.fc_correct is not None
        return 100.0 * self.fc_correct / self.trials


# ------------------------------------------------------------------------------- checks of the jobs
# the Monte Carlo runs' default horizons: every 10 s to 80 s (Figs 4–7)
FIG_HORIZONS = tuple(float(h) for h in range(10, 81, 10))


def check_horizons(horizons_s: Sequence[float], T: float, longest: float = math.inf) -> None:
    """Horizons [s]: at least one, each a finite number at least one sample T long (rounded to samples)
    and at most ``longest``."""
    if not horizons_s:
        raise ConfigError("horizons_s", horizons_s, "holds no horizon")
    for h in horizons_s:
        in_range("horizons_s", h, 0.0, lo_open=True, unit="s")
        if round(h / T) < 1:
            raise ConfigError("horizons_s", h, f"s is shorter than one sample (T = {T:g} s)")
        if h > longest:
            raise ConfigError("horizons_s", h, f"s is not in [{T:g}, {longest:g}] s")


def check_values(name: str, values: Sequence[float], lo: float, hi: float = math.inf, **kw: Any) -> None:
    """A non-empty list of finite numbers in [lo, hi] (``kw``: :func:`~motionsig_cli.config.in_range`'s
    options)."""
    if not values:
        raise ConfigError(name, values, "is empty")
    for v in values:
        in_range(name, v, lo, hi, **kw)


def check_method(method: str, cfg: LMPConfig) -> None:
    """``bank`` or ``fft``; the FFT path only with the settings it implements."""
    one_of("method", method, ("bank", "fft"))
    if method == "fft":
        check_fft_config(cfg)


def check_model(vehicle: Vehicle1D, cfg: LMPConfig, f_c: float) -> None:
    """The vehicle and the detector fit together: the received carrier f_c + f_d >= 0, and the filters'
    model exists (a continuous-time Q needs a real generator of F)."""
    if not isinstance(vehicle, Vehicle1D):
        raise ConfigError("vehicle", type(vehicle).__name__, "is not a Vehicle1D")
    if f_c + vehicle.f_d < 0:
        raise ConfigError(
            "f_d", vehicle.f_d, f"makes the received carrier f_c + f_d = {f_c + vehicle.f_d:g} Hz negative"
        )
    filter_model(vehicle, cfg)


def _tuple(value: Any) -> Any:
    """Lists become tuples (a job is frozen and travels to the workers)."""
    return tuple(value) if isinstance(value, list) else value


# -------------------------------------------------------------------------------- the Monte Carlo
@dataclass(frozen=True)
class TrialOutcomes:
    """Per-trial results of one task: (f_r, trial, horizon) arrays."""

    ok: np.ndarray  # (i, τ) both right
    ok_mode: np.ndarray  # mode right
    lam_max: np.ndarray  # λ* = max_c Λ(c), eq (29)
    fc_hat: np.ndarray | None = None  # the argmax's carrier [Hz] (with a carrier search, else None)


@dataclass(frozen=True, eq=False)
class LmpJob(JobHorizons):
    """The Monte Carlo of Figs 4–6: % correct (i, τ) vs horizon for every (f_r, R).

    One record per trial (the longest horizon) serves every horizon. Trial t of every cell uses the
    same draws (common random numbers across f_r and R), so cells differ only by f_r and R. One
    Riccati recursion per task serves all f_r and trials (the filters do not know f_r). A task is
    the trials of one chunk at one R (:meth:`tasks`); the counts do not depend on the engine or on
    ``chunk``.

    Attributes:
        cfg: Detector settings.
        fr_list: Reference frequencies [Hz], each finite and >= 0 (the paper: 0.01, 0.1, 1).
        R_list: Measurement variances, each finite and > 0.
        horizons_s: Horizons [s], each at least one sample; None: every 10 s to 80 s.
        trials: Trials per (f_r, R) cell, >= 1; trials × len(R_list) at most :data:`MAX_MC_TRIALS`.
        seed: Root seed (>= 0).
        signature: False: records without a signature (the argmax under H0).
        method: ``"bank"`` (2C + 1 Kalman filters) or ``"fft"`` (:mod:`motionsig_cli.detection.lmp_fft`).
        vehicle: The model (its R and f_r are set per cell): the truth's T, K, a_sig, a_r, σ_a, carrier
            offset f_d and feedback, and the filters' T, K (and, with ``A_r="known"``, the reference of each
            cell: the filters know the vehicle's commanded a_r, f_r). With f_d ≠ 0 or several carriers in
            ``cfg.fc_grid`` the table adds the carrier estimate's scores.
        codes: The Table I codes the records carry (``chips`` default to them).
        chips: Bipolar chips (M, n_ρ); None: those of ``codes``.
        m_rho: Samples per chip (>= 1).  f_c: Carrier frequency [Hz] (finite, >= 0).
        chunk: Trials per task (None: from the cost model, :meth:`cost`).
    """

    name: ClassVar[str] = "detect --montecarlo"

    cfg: LMPConfig = field(default_factory=LMPConfig)
    fr_list: tuple[float, ...] = (0.01, 0.1, 1.0)
    R_list: tuple[float, ...] = (1e-1, 1e-2, 1e-3, 1e-5)
    horizons_s: tuple[float, ...] | None = None
    trials: int = 50
    seed: int = DEFAULT_SEED
    signature: bool = True
    method: Method = "bank"
    vehicle: Vehicle1D = field(default_factory=Vehicle1D)
    codes: Codes = "corrected"
    chips: np.ndarray | None = None
    m_rho: int = 20
    f_c: float = 1.0
    chunk: int | None = None

    def __post_init__(self) -> None:
        for name in ("fr_list", "R_list", "horizons_s"):
            object.__setattr__(self, name, _tuple(getattr(self, name)))
        if self.horizons_s is None:
            object.__setattr__(self, "horizons_s", FIG_HORIZONS)
        one_of("codes", self.codes, ("corrected", "printed"))
        if self.chips is None:
            object.__setattr__(self, "chips", table1_chips(self.codes))
        object.__setattr__(self, "chips", np.asarray(self.chips, float))
        check_values("fr_list", self.fr_list, 0.0, unit="Hz")
        check_values("R_list", self.R_list, 0.0, lo_open=True)
        check_horizons(self.horizons_s, self.vehicle.T)
        integer("trials", self.trials, 1)
        if self.trials * len(self.R_list) > MAX_MC_TRIALS:
            raise ConfigError(
                "trials",
                self.trials,
                f"x {len(self.R_list)} values of R: at most {MAX_MC_TRIALS:.0e} records",
            )
        integer("seed", self.seed, 0)
        one_of("signature", self.signature, (False, True))
        check_method(self.method, self.cfg)
        integer("m_rho", self.m_rho, 1)
        in_range("f_c", self.f_c, 0.0, unit="Hz")
        check_model(self.vehicle, self.cfg, self.f_c)
        if self.chunk is not None:
            integer("chunk", self.chunk, 1)

    @property
    def n_candidates(self) -> int:
        return len(candidate_grid(self.chips.shape[0], self.chips.shape[1], self.m_rho, self.cfg))

    @property
    def carrier_search(self) -> bool:
        """Whether the table scores the carrier estimate: several candidate carriers, or f_d ≠ 0."""
        return len(self.cfg.fc_grid) > 1 or self.vehicle.f_d != 0

    def detect(self, y: np.ndarray, R: float, reference: np.ndarray | None = None) -> LMPResult:
        """The configured detector (bank or FFT path) on records y (B, N) at measurement variance R
        (``reference``: the known reference per record, (B, N, 2), with ``A_r="known"``)."""
        veh = replace(self.vehicle, R=R)
        hz = self.horizon_samples
        if self.method == "fft":
            return lmp_detect_fft(y, self.chips, veh, self.m_rho, self.cfg, hz, reference=reference)
        return lmp_detect(y, self.chips, veh, self.m_rho, self.cfg, hz, reference=reference)

    def references(self, n_records: int) -> np.ndarray | None:
        """``A_r="known"``: the nominal reference of every record of a task (f_r-major, ``n_records`` per
        f_r), (F·n_records, N, 2), the vehicle's a_r at each cell's f_r; else None."""
        if self.cfg.A_r != "known":
            return None
        t = np.arange(self.n_samples) * self.vehicle.T
        refs = [nominal_reference(replace(self.vehicle, f_r=fr), t) for fr in self.fr_list]
        return np.concatenate([np.broadcast_to(r, (n_records, *r.shape)) for r in refs])

    def cost(self) -> tuple[float, float]:
        """Cost model [s] of a task at one R: (fixed, per trial over all f_r), measured on a 2-core machine.

        The bank's fixed part is the loops over N of the simulation and of the innovations (≈ 2.8e-5 s per
        sample); its Riccati recursion (2C + 1 filters, ≈ 0.05 s at N = 1600, and the replicas) is computed once per process
        and R and kept (:mod:`motionsig_cli.cache`), so tasks may be small and keep every worker busy to
        the end of a run (a task of 50 trials, ≈ 0.2 s, took as long per trial as one of 200). The
        per-trial part is the innovations (≈ 1.2e-8 s per filter-step). The FFT path's fixed part is the
        simulation and whitening loops over N (≈ 2e-5 s per sample), its per-trial part ≈ 8e-7 s per
        sample and f_r.
        """
        n, F = self.n_samples, len(self.fr_list)
        if self.method == "fft":
            return n * 2e-5, F * n * 8e-7
        return n * 2.8e-5, F * n * (2 * self.n_candidates + 1) * 1.2e-8

    def tasks(self) -> list[tuple[float, range]]:
        """For every R, the trials in chunks worth ≥ 0.1 s and ≥ 4× the task's fixed cost (so chunking adds
        at most 25 %), with at most 200 records in memory."""
        fixed, per_trial = self.cost()
        per = self.chunk or min(
            max(1, 200 // len(self.fr_list)), trials_per_task(per_trial, fixed_seconds=fixed)
        )
        return [(float(R), r) for R in self.R_list for r in tasks_of(self.trials, per)]

    def task_size(self, task: tuple[float, range]) -> int:
        return len(task[1])

    def run_task(self, task: tuple[float, range]) -> TrialOutcomes:
        """The trials ``task[1]`` at measurement variance ``task[0]``, every f_r."""
        R, ids = task
        ys, truths = [], []
        for fr in self.fr_list:
            veh = replace(self.vehicle, R=R, f_r=fr)
            y, draws = simulate_trials(
                veh, self.chips, self.m_rho, self.f_c, self.n_samples, self.seed, list(ids),
                signature=self.signature,
            )  # fmt: skip
            ys.append(y)
            truths.extend(draws)
        res = self.detect(np.concatenate(ys), R, self.references(len(ids)))
        best, lam = res.best()  # (F·B, H), records ordered f_r-major
        c = res.candidates
        ok_mode = c.mode[best] == np.array([d.mode for d in truths])[:, None]
        ok = ok_mode & (c.tau[best] == np.array([d.tau for d in truths])[:, None])
        shape = (len(self.fr_list), len(ids), len(self.horizons_s))
        fc_hat = c.f_c[best].reshape(shape) if self.carrier_search else None
        return TrialOutcomes(ok.reshape(shape), ok_mode.reshape(shape), lam.reshape(shape), fc_hat)

    def reduce(self, tasks: Sequence[tuple[float, range]], results: Sequence[TrialOutcomes]) -> LmpMonteCarlo:
        """Sum the tasks' outcomes (in task order) into the (f_r, R, horizon) cells."""
        cells: list[MCCell] = []
        f_true = self.f_c + self.vehicle.f_d
        grid = np.asarray(self.cfg.fc_grid, float)
        nearest = grid[np.argmin(np.abs(grid - f_true))]  # the grid's carrier nearest the true one
        for R in self.R_list:
            mine = [res for (r, _), res in zip(tasks, results, strict=True) if r == R]
            ok = np.concatenate([m.ok for m in mine], axis=1).sum(axis=1)  # (F, H)
            okm = np.concatenate([m.ok_mode for m in mine], axis=1).sum(axis=1)
            fc_ok = fc_rmse = None
            if self.carrier_search:
                fc = np.concatenate(
                    [m.fc_hat for m in mine if m.fc_hat is not None], axis=1
                )  # (F, trials, H)
                fc_ok = (fc == nearest).sum(axis=1)
                fc_rmse = np.sqrt(np.mean((fc - f_true) ** 2, axis=1))
            for f, fr in enumerate(self.fr_list):
                for j, hs in enumerate(self.horizons_s):
                    extra = () if fc_ok is None else (int(fc_ok[f, j]), float(fc_rmse[f, j]))  # type: ignore[index]
                    cells.append(MCCell(fr, R, float(hs), self.trials, int(ok[f, j]), int(okm[f, j]), *extra))
        return LmpMonteCarlo(self, cells)

    def identity(self) -> dict[str, Any]:
        return dict(
            method=self.method, cfg=repr(self.cfg), fr_list=list(self.fr_list), R_list=list(self.R_list),
            horizons_s=list(self.horizons_s), trials=self.trials, seed=self.seed, signature=self.signature,
            **self._model_identity(),
        )  # fmt: skip

    def _model_identity(self) -> dict[str, Any]:
        """The vehicle, codes, m_rho and f_c where they are not the defaults (a checkpoint written before
        they could be set keeps its identity)."""
        if self.vehicle == Vehicle1D() and self.m_rho == 20 and self.f_c == 1.0 and self.codes == "corrected":
            return {}
        return dict(vehicle=repr(self.vehicle), m_rho=self.m_rho, f_c=self.f_c, codes=self.codes)


QA_KNOWN_NOTE = "Q0's r, rdot entries are unused: the filters' state is [x, xdot(, a)]"


def detector_meta(cfg: LMPConfig, *, full: bool = True) -> dict[str, Any]:
    """The detector settings as metadata (``full``: with weights, centring and the replica derivative);
    ``q_model`` where it is not per-step, and a note on Q0 with a known reference."""
    meta: dict[str, Any] = dict(
        c_r=cfg.c_r, Q0=list(cfg.Q0), Q_a=cfg.Q_a, P0=cfg.P0, A_r=cfg.A_r, tau_grid=cfg.tau_grid,
        fc_grid=list(cfg.fc_grid), include_logdet=cfg.include_logdet,
    )  # fmt: skip
    if cfg.q_model != "per-step":
        meta.update(q_model=cfg.q_model, q_units="continuous-time densities per second, discretised over T "
                    "(Van Loan, the generator log(F)/T of the filters' F)")  # fmt: skip
    if cfg.A_r == "known":
        meta.update(reference_model="the vehicle's nominal reference as a known input (cooperative)",
                    Q0_note=QA_KNOWN_NOTE)  # fmt: skip
    if full:
        meta.update(weights=cfg.weights, center=cfg.center, zdot=cfg.zdot)
    return meta


def vehicle_meta(vehicle: Vehicle1D) -> dict[str, Any]:
    """The truth's carrier offset and feedback where they are not the defaults (f_d = 0, true state)."""
    meta: dict[str, Any] = {}
    if vehicle.f_d != 0:
        meta["f_d"] = vehicle.f_d
    if vehicle.feedback != "true":
        meta.update(feedback=vehicle.feedback, onboard_estimator=ONBOARD_ESTIMATOR)
    return meta


Curves = dict[float, dict[str, tuple[np.ndarray, np.ndarray]]]
CORRECT = "mode_hat == mode and tau_hat == tau on the grid"


JobT = TypeVar("JobT")
CellT = TypeVar("CellT")


@dataclass(frozen=True, eq=False)
class CorrectCurves(Generic[JobT, CellT]):
    """The cells of a Monte Carlo job over (f_r, series, horizon): the figure data and summary line shared
    by :class:`LmpMonteCarlo` and :class:`~motionsig_cli.modesig.lmp2d.RadarMonteCarlo`."""

    job: JobT
    cells: list[CellT]

    def series(self) -> list[tuple[str, Callable[[Any], bool]]]:
        """(label, which cells) of each curve of one f_r."""
        raise NotImplementedError

    def title(self) -> str:
        raise NotImplementedError

    def figure_data(self) -> tuple[np.ndarray, Curves, str]:
        """(horizons, f_r → {series label → (% correct, SE)}, title): the arguments of
        :func:`motionsig_cli.plotting.montecarlo_figure`."""
        job = self.job
        curves: Curves = {}
        for fr in job.fr_list:
            curves[fr] = {}
            for label, picks in self.series():
                sel = [c for c in self.cells if c.f_r == fr and picks(c)]
                curves[fr][label] = (np.array([c.pct for c in sel]), np.array([c.se_pct for c in sel]))
        return np.array(job.horizons_s), curves, self.title()

    def summary(self) -> str:
        return (
            f"{len(self.cells)} cells x {self.job.trials} trials; chance level "
            f"{100.0 / self.job.n_candidates:.2f} %"
        )


class LmpMonteCarlo(CorrectCurves["LmpJob", "MCCell"]):
    """The cells of an :class:`LmpJob`, and the command's table, figure data and summary."""

    def table(self) -> Table:
        job, veh = self.job, self.job.vehicle
        rows = []
        search = job.carrier_search
        for c in self.cells:
            lin, l10, lnl = anr_db(c.R, veh.a_sig)
            rows.append(
                (c.f_r, c.R, lin, l10, lnl, SEED_ANR_LABELS.get(c.R, ""), c.horizon_s, c.pct, c.se_pct,
                 c.pct_mode, c.correct, c.trials) + ((c.pct_fc, c.fc_rmse) if search else ())
            )  # fmt: skip
        n_cand = job.n_candidates
        carrier = (
            dict(f_true=job.f_c + veh.f_d, fc_correct="fc_hat is the fc_grid value nearest f_c + f_d")
            if search
            else {}
        )
        streams = "trial t: SeedSequence(seed, spawn_key=(t, 0|1|2)) for (i,tau,theta) | process | measurement noise"
        if veh.feedback == "estimate":
            streams += " | 3: the vehicle's own position sensor"
        meta = make_meta(
            "detect --montecarlo", method=job.method, trials=job.trials, fr_list=list(job.fr_list),
            R_list=list(job.R_list), horizons_s=list(job.horizons_s), seed=job.seed, signature=job.signature,
            **detector_meta(job.cfg), T=veh.T, m_rho=job.m_rho, f_c=job.f_c, K=list(veh.K), a_sig=veh.a_sig,
            a_r=veh.a_r, sigma_a=veh.sigma_a, **vehicle_meta(veh), **carrier, codes=job.codes,
            n_candidates=n_cand, chance_pct=100.0 / n_cand, correct=CORRECT, trial_streams=streams,
        )  # fmt: skip
        columns = ("f_r", "R", "anr_linear", "anr_db_log10", "anr_db_paper_ln", "seed_anr_label", "horizon_s",
                   "pct_correct", "se_pct", "pct_mode_correct", "correct", "trials")  # fmt: skip
        if search:
            columns += ("pct_fc_correct", "fc_rmse")
        return Table(columns, rows, meta)

    def series(self) -> list[tuple[str, Callable[[Any], bool]]]:
        """One curve per R, labelled with its ANR."""
        a_sig = self.job.vehicle.a_sig
        return [
            (f"{anr_db(Rv, a_sig)[2]:.1f} (R={Rv:g})", lambda c, Rv=Rv: c.R == Rv) for Rv in self.job.R_list
        ]

    def title(self) -> str:
        return f"{self.job.trials} trials per cell, c_r = {self.job.cfg.c_r:g}"


# ------------------------------------------------------------------------------ threshold calibration
# null trial t draws from trial_rng(seed, NULL_OFFSET + t, …): independent of the H1 trials
NULL_OFFSET = 1 << 40


class DetectionRate:
    """P_D = detections / trials of a cell and its binomial standard error √(P_D (1 − P_D) / trials)."""

    detections: int
    trials: int

    @property
    def pd(self) -> float:
        return self.detections / self.trials

    @property
    def pd_se(self) -> float:
        return math.sqrt(self.pd * (1 - self.pd) / self.trials)


@dataclass(frozen=True)
class CalibrationCell(DetectionRate):
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


def calibration_null_trials(pfa: float, null_trials: int | None) -> int | None:
    """The null trials of a threshold calibration: ``null_trials`` as given, else ⌈20 / pfa⌉ (assumed: about
    20 null maxima above the threshold), after checking ``pfa`` in (0, 1) and the default against
    :data:`MAX_NULL_TRIALS`. A given number is checked by the job."""
    in_range("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True)
    if null_trials is not None:
        return null_trials
    n = math.ceil(20 / pfa)
    if n > MAX_NULL_TRIALS:
        raise ConfigError(
            "pfa", pfa, f"needs 20/P_FA = {20 / pfa:.1e} null trials by default, more than "
            f"{MAX_NULL_TRIALS:.0e}: raise it or set the number of null trials",
        )  # fmt: skip
    return n


def null_trials_warning(null_trials: int, pfa: float) -> str | None:
    """A note when ``null_trials`` are too few for the target ``pfa`` (the threshold is then the largest
    null maximum), else None."""
    if null_trials * pfa >= 1:
        return None
    return (
        f"warning: {null_trials} null trials < 1/P_FA: the threshold is the largest null maximum, "
        f"its false-alarm rate is not {pfa:g}"
    )


def threshold_for(null_max: np.ndarray, pfa: float) -> float:
    """The smallest order statistic t of ``null_max`` with #{λ* > t} ≤ ⌊pfa n⌋."""
    s = np.sort(np.asarray(null_max, dtype=float))
    n = s.size
    k = math.floor(pfa * n)  # maxima allowed above the threshold
    if k >= n:
        return -math.inf
    return float(s[n - k - 1])


@dataclass(frozen=True, eq=False)
class CalibrationJob:
    """Null distribution of λ* (records with no signature), the threshold for ``pfa`` and P_D at it, per
    (f_r, R, horizon).

    Its tasks are those of two :class:`LmpJob` arms: the null arm (``null_trials``, no signature, trial t
    drawn as trial NULL_OFFSET + t) and the signature arm (``trials``). The result does not depend on the
    engine. The chunking (fixed by the parameters) batches the filters' floating-point work, so another
    chunk size may move the thresholds' last bits; the counts are exact integers either way.

    Attributes:
        pfa: Target false-alarm probability, in (0, 1).
        null_trials: Null trials per cell, 1 … :data:`MAX_NULL_TRIALS`; None: ⌈20 / pfa⌉.
        trials: Signature trials per cell, 1 … :data:`MAX_NULL_TRIALS`.
        Others: as in :class:`LmpJob` (default f_r: 0.01 Hz).
    """

    name: ClassVar[str] = "detect --calibrate"

    cfg: LMPConfig = field(default_factory=LMPConfig)
    fr_list: tuple[float, ...] = (0.01,)
    R_list: tuple[float, ...] = (1e-1, 1e-2, 1e-3, 1e-5)
    horizons_s: tuple[float, ...] | None = None
    trials: int = 50
    null_trials: int | None = None
    pfa: float = 0.01
    seed: int = DEFAULT_SEED
    method: Method = "bank"
    vehicle: Vehicle1D = field(default_factory=Vehicle1D)
    codes: Codes = "corrected"
    chips: np.ndarray | None = None
    m_rho: int = 20
    f_c: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "null_trials", calibration_null_trials(self.pfa, self.null_trials))
        for name in ("null_trials", "trials"):
            integer(name, getattr(self, name), 1)
            if getattr(self, name) > MAX_NULL_TRIALS:
                raise ConfigError(
                    name, getattr(self, name), f"is too many: at most {MAX_NULL_TRIALS:.0e} per cell"
                )
        arm = self.arm(True)  # checks the shared fields
        for name in ("fr_list", "R_list", "horizons_s", "chips"):
            object.__setattr__(self, name, getattr(arm, name))

    def arm(self, signature: bool) -> LmpJob:
        """The signature arm (``trials``) or the null arm (``null_trials``, no signature)."""
        return LmpJob(
            self.cfg, self.fr_list, self.R_list, self.horizons_s, self.trials if signature else self.null_trials,
            self.seed, signature, self.method, self.vehicle, self.codes, self.chips, self.m_rho, self.f_c,
        )  # fmt: skip

    @property
    def warning(self) -> str | None:
        """A note when the null trials are too few for the target P_FA."""
        return null_trials_warning(self.null_trials, self.pfa)

    def tasks(self) -> list[tuple[int, float, range]]:
        """``(0 | 1, R, trials)``: 0 = null records (no signature), 1 = with it; the null tasks first."""
        null = [(0, R, r) for R, r in self.arm(False).tasks()]
        return null + [(1, R, r) for R, r in self.arm(True).tasks()]

    def task_size(self, task: tuple[int, float, range]) -> int:
        return len(task[2])

    def run_task(self, task: tuple[int, float, range]) -> TrialOutcomes:
        which, R, ids = task
        if which == 0:
            ids = range(NULL_OFFSET + ids.start, NULL_OFFSET + ids.stop)
        return self.arm(which == 1).run_task((R, ids))

    def reduce(
        self, tasks: Sequence[tuple[int, float, range]], results: Sequence[TrialOutcomes]
    ) -> Calibration:
        def joined(which: int, R: float, attr: str) -> np.ndarray:
            mine = [getattr(o, attr) for t, o in zip(tasks, results, strict=True) if t[:2] == (which, R)]
            return np.concatenate(mine, axis=1)

        null = {R: joined(0, R, "lam_max") for R in self.R_list}
        sig = {R: joined(1, R, "lam_max") for R in self.R_list}
        corr = {R: joined(1, R, "ok") for R in self.R_list}
        cells = []
        for R in self.R_list:
            for f, fr in enumerate(self.fr_list):
                for j, hs in enumerate(self.horizons_s):
                    thr = threshold_for(null[R][f, :, j], self.pfa)
                    det = sig[R][f, :, j] > thr
                    cells.append(
                        CalibrationCell(
                            fr, float(R), float(hs), self.pfa, thr, self.null_trials,
                            int(np.sum(null[R][f, :, j] > thr)), self.trials, int(det.sum()),
                            int(np.sum(det & corr[R][f, :, j])),
                        )
                    )  # fmt: skip
        return Calibration(cells, null, sig, corr, self)

    def identity(self) -> dict[str, Any]:
        return dict(
            method=self.method, cfg=repr(self.cfg), fr_list=list(self.fr_list), R_list=list(self.R_list),
            horizons_s=list(self.horizons_s), trials=self.trials, null_trials=self.null_trials, pfa=self.pfa,
            seed=self.seed, **self.arm(True)._model_identity(),
        )  # fmt: skip


@dataclass(frozen=True, eq=False)
class Calibration:
    """Cells plus the raw maxima (for ROC curves): ``null[R]``, ``signal[R]`` are (F, trials, H)."""

    cells: list[CalibrationCell]
    null: dict[float, np.ndarray]
    signal: dict[float, np.ndarray]
    correct: dict[float, np.ndarray]
    job: CalibrationJob

    def table(self) -> Table:
        job = self.job
        rows = []
        for c in self.cells:
            lin, l10, lnl = anr_db(c.R, job.vehicle.a_sig)
            rows.append(
                (c.f_r, c.R, lin, l10, lnl, SEED_ANR_LABELS.get(c.R, ""), c.horizon_s, c.pfa, c.threshold,
                 c.false_alarms / c.null_trials, c.null_trials, c.pd, c.pd_se, c.detections_correct / c.trials,
                 c.trials)
            )  # fmt: skip
        veh = job.vehicle
        model: dict[str, Any] = {}
        if replace(veh, R=DEFAULT_R) != Vehicle1D():  # the truth's settings, where one is not the default
            model = dict(K=list(veh.K), a_sig=veh.a_sig, a_r=veh.a_r, sigma_a=veh.sigma_a, f_d=veh.f_d,
                         feedback=veh.feedback)  # fmt: skip
            if veh.feedback == "estimate":
                model["onboard_estimator"] = ONBOARD_ESTIMATOR
        meta = make_meta(
            "detect --calibrate", method=job.method, pfa=job.pfa, trials=job.trials, null_trials=job.null_trials,
            fr_list=list(job.fr_list), R_list=list(job.R_list), horizons_s=list(job.horizons_s), seed=job.seed,
            **detector_meta(job.cfg, full=False), T=job.vehicle.T, m_rho=job.m_rho, f_c=job.f_c, **model,
            codes=job.codes,
            statistic="max over candidates of Lambda (eq 29); declare present when it exceeds the threshold",
            threshold_rule="order statistic of the null maxima leaving at most floor(pfa * null_trials) above it",
            trial_streams="signature trial t: SeedSequence(seed, spawn_key=(t, 0|1|2)); "
            "null trial t: spawn_key=(2^40 + t, 0|1|2), drawn with no signature",
        )  # fmt: skip
        columns = ("f_r", "R", "anr_linear", "anr_db_log10", "anr_db_paper_ln", "seed_anr_label", "horizon_s",
                   "pfa_target", "threshold", "pfa_in_sample", "null_trials", "pd", "pd_se", "pd_and_correct",
                   "trials")  # fmt: skip
        return Table(columns, rows, meta)

    def figure_data(self) -> tuple[dict[str, dict[str, tuple[np.ndarray, np.ndarray]]], float, str]:
        """(panel → {horizon → ROC curve}, P_FA, title): the arguments of
        :func:`motionsig_cli.plotting.calibration_roc_figure`."""
        job = self.job
        panels: dict[str, dict[str, tuple[np.ndarray, np.ndarray]]] = {}
        for R in job.R_list:
            for f, fr in enumerate(job.fr_list):
                name = f"ANR {anr_db(R, job.vehicle.a_sig)[2]:.1f} paper dB (R={R:g})" + (
                    f", f_r={fr:g}" if len(job.fr_list) > 1 else ""
                )
                panels[name] = {
                    f"{h:g} s": roc_curve(self.null[R][f, :, j], self.signal[R][f, :, j])
                    for j, h in enumerate(job.horizons_s)
                }
        return panels, job.pfa, f"{job.method}: {job.trials} + {job.null_trials} null trials"

    def summary(self) -> str:
        job = self.job
        return f"{len(self.cells)} cells; threshold for P_FA = {job.pfa:g} from {job.null_trials} null trials each"


def roc_curve(null_max: np.ndarray, signal_max: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Empirical (P_FA, P_D) of the test λ* > t for every t among the pooled maxima."""
    t = np.unique(np.concatenate([null_max, signal_max]))
    n0, n1 = np.sort(null_max), np.sort(signal_max)
    pfa = 1.0 - np.searchsorted(n0, t, side="right") / n0.size
    pd = 1.0 - np.searchsorted(n1, t, side="right") / n1.size
    return np.concatenate([[1.0], pfa]), np.concatenate([[1.0], pd])


# ---------------------------------------------------------------------------------------- one record
MAX_RECORD_SECONDS = 3600.0  # estimated run time limit of a detection on one record
BANK_US = {"kf": 2.0, "ukf": 5.0}  # µs per filter and time step of the banks (measured, 2 cores: 1.4-2, 4)
Threshold = float | tuple[float, ...] | None


def check_threshold(threshold: Threshold, n_horizons: int | None = None) -> None:
    """A decision threshold on max Λ: None (no decision), a number (±inf allowed, not NaN), or one number
    per horizon (``n_horizons`` of them, a calibrated threshold)."""
    values = threshold if isinstance(threshold, tuple) else (threshold,)
    if threshold is None:
        return
    if isinstance(threshold, tuple) and n_horizons is not None and len(threshold) != n_horizons:
        raise ConfigError("threshold", threshold, f"holds {len(threshold)} values for {n_horizons} horizons")
    for v in values:
        if not (isinstance(v, int | float) and v == v):
            raise ConfigError("threshold", threshold, "is not a number")


def n_grid_candidates(n_modes: int, n_rho: int, m_rho: int, tau_grid: str, n_fc: int) -> int:
    """Candidates of :func:`~motionsig_cli.detection.lmp.candidate_grid`, counted without building it."""
    return n_modes * (n_rho if tau_grid == "chips" else n_rho * m_rho) * n_fc


class RecordHorizons:
    """The horizons of a detection on one record (``record``, ``horizons`` [s]) in samples."""

    record: VehicleRecord
    horizons: tuple[float, ...]

    @property
    def horizon_samples(self) -> list[int]:
        return [round(h / self.record.vehicle.T) for h in self.horizons]

    @property
    def n_used(self) -> int:
        """Samples the detector runs over (the longest horizon)."""
        return max(self.horizon_samples)

    def missing_checked(self, what: str) -> None:
        """Refuse a missing sample within the horizons, for a detector (``what``) that cannot skip one."""
        err = self.record.missing_error(what, self.n_used)
        if err is not None:
            raise err


def check_record_detector(method: str, filter: str, cfg: LMPConfig, sigma: SigmaPointParams) -> None:
    """The 1-D detector of one record (and of its null records): ``filter`` kf or ukf, ``method`` bank or
    fft for ``cfg``; the FFT path runs no sigma-point filters, and the sigma-point bank supports center
    none and weights paper only, with α, κ that suit its 4- and 5-state filters (2 and 3 with a known
    reference).

    Raises:
        ConfigError: naming ``filter`` or ``method``.
    """
    one_of("filter", filter, ("kf", "ukf"))
    check_method(method, cfg)
    if method == "fft" and filter == "ukf":
        raise ConfigError("method", "fft", "replaces the filter bank: it runs no sigma-point filters (ukf)")
    if filter == "ukf":
        if cfg.center != "none" or cfg.weights != "paper":
            raise ConfigError(
                "filter", "ukf", "(the sigma-point bank) supports center none and weights paper only"
            )
        n = 2 if cfg.A_r == "known" else 4
        sigma.weights(n)  # the H0 filter
        sigma.weights(n + 1)  # the H1 filters


@dataclass(frozen=True, eq=False)
class RecordDetection(RecordHorizons):
    """Eq (52) on one 1-D record (Fig 3): the argmax per horizon, or every candidate's statistic.

    Attributes:
        record: The record (:func:`motionsig_cli.modesig.record_reading.read_vehicle_record`); the
            filters assume its vehicle (T, K, a_sig, R) and search its codes. A missing sample (NaN) is a
            predict-only step of the bank; the FFT path cannot skip one (an error naming its line).
        cfg: Detector settings.
        method: ``"bank"`` (2C + 1 filters) or ``"fft"`` (one steady-state filter and FFTs).
        filter: ``"kf"`` (Kalman bank) or ``"ukf"`` (the sigma-point bank on the same linear model; it
            supports center ``"none"`` and weights ``"paper"`` only, and α, κ must suit its 4- and 5-state
            filters).
        sigma: Unscented-transform parameters of ``"ukf"``.
        horizons: Horizons [s] (see :func:`~motionsig_cli.modesig.record_reading.record_horizons`);
            None: every 10 s. The bank keeps its gains up to the longest: at most :data:`MAX_BANK_GB`
            and ~:data:`MAX_RECORD_SECONDS` (estimated from :data:`BANK_US`); the FFT path at most
            :data:`MAX_BANK_GB` of arrays.
        threshold: Declare "signature present" when max Λ >= threshold: one number, or one per horizon
            (a threshold calibrated for the record); None: no decision.
        candidates: Every candidate's statistic instead of the argmax.
        threshold_meta: How a calibrated threshold was found (metadata), or None.
    """

    record: VehicleRecord
    cfg: LMPConfig
    method: Method = "bank"
    filter: Literal["kf", "ukf"] = "kf"
    sigma: SigmaPointParams = field(default_factory=SigmaPointParams)
    horizons: tuple[float, ...] | None = None
    threshold: Threshold = None
    candidates: bool = False
    threshold_meta: dict[str, Any] | None = None

    def __post_init__(self) -> None:
        check_record_detector(self.method, self.filter, self.cfg, self.sigma)
        check_model(self.record.vehicle, self.cfg, self.record.f_c)
        check_known_reference(self.record, self.cfg)
        rec, T = self.record, self.record.vehicle.T
        hs = record_horizons(self.horizons, rec.y.shape[0] * T, T)
        object.__setattr__(self, "horizons", tuple(hs))
        self._check_size()
        check_threshold(self.threshold, len(hs))

    def _check_size(self) -> None:
        """Refuse, before any work, a run over :data:`MAX_BANK_GB` or ~:data:`MAX_RECORD_SECONDS`."""
        rec, cfg = self.record, self.cfg
        n_modes, n_rho = rec.chips.shape
        C = n_grid_candidates(n_modes, n_rho, rec.m_rho, cfg.tau_grid, len(cfg.fc_grid))
        n_filters, N, H = 2 * C + 1, self.n_used, len(self.horizons)
        if self.method == "bank":
            # gains, S⁻¹, log det per filter and step (7 doubles), the replicas and the a-column (3)
            need_gb = n_filters * N * 10 * 8 / 1e9
            seconds = n_filters * N * BANK_US[self.filter] * 1e-6
            what = f"the bank of {n_filters} filters"
        else:  # folded innovations per horizon (N or the code period), and the statistic's 10 arrays
            need_gb = (4 * H * max(N, n_rho * rec.m_rho) * 16 + 10 * C * H * 8) / 1e9
            seconds = 0.0
            what = f"the FFT path over {C} candidates"
        if need_gb > MAX_BANK_GB:
            raise ConfigError(
                "horizons", max(self.horizons), f"s is too long for {what}: it would need an estimated "
                f"{need_gb:.1f} GB; the limit is {MAX_BANK_GB:g} GB: use shorter horizons, fewer codes or a "
                "coarser grid",
            )  # fmt: skip
        check_run_time(  # one record, in this process: --max-minutes raises the limit
            "horizons", max(self.horizons), seconds, MAX_RECORD_SECONDS, what=f"s is too long for {what}: it ",
            parallel=False, also="use shorter horizons, fewer codes or a coarser grid, or ",
        )  # fmt: skip

    @property
    def steps(self) -> int:
        """The time steps :meth:`detect` reports to its ``progress`` callback (0 for the FFT path)."""
        return 0 if self.method == "fft" else progress_steps(self.n_used, self.cfg, self.filter)

    @property
    def title(self) -> str:
        """The Fig 3-style panel's title."""
        return f"horizon {self.horizons[-1]:g} s, R = {self.record.vehicle.R:g}, c_r = {self.cfg.c_r:g}"

    def detect(self, progress: Progress = None) -> RecordResult:
        """Run the detector; ``progress`` is called with the time steps done, per block of steps.

        Raises:
            InputError: a missing sample within the horizons on the FFT path (or a bank that cannot skip
                one), naming its file line.
        """
        rec, cfg, hz = self.record, self.cfg, self.horizon_samples
        args = (rec.y[: self.n_used], rec.chips, rec.vehicle, rec.m_rho, cfg, hz)
        if self.method == "fft":
            self.missing_checked("the FFT path cannot skip a missing sample: use --method bank")
            try:
                res = lmp_detect_fft(*args)
            except ConfigError:
                raise
            except ValueError as exc:  # e.g. an unstable steady-state filter
                raise ConfigError("method", "fft", f"cannot run: {exc}") from None
        else:
            try:
                res = lmp_detect(*args, filter=self.filter, sigma=self.sigma, progress=progress)
            except ValueError as exc:
                if np.isnan(args[0]).any():  # a bank without predict-only steps
                    self.missing_checked(f"the filter bank cannot skip a missing sample ({exc})")
                raise
        params = dict(
            source=rec.source, **detector_meta(cfg), **known_reference_meta(rec, cfg), horizons_s=list(self.horizons),
            threshold=list(self.threshold) if isinstance(self.threshold, tuple) else self.threshold,
            filter=self.filter, method=self.method,
            **(sigma_meta(self.sigma, res.repairs) if self.filter == "ukf" else {}),
            **({"threshold_calibration": self.threshold_meta} if self.threshold_meta else {}),
            **rec.provenance, input_meta=rec.meta,
        )  # fmt: skip
        return record_result(
            res, list(self.horizons), hz, rec.truth, params, rec.chips.shape, rec.m_rho,
            candidates=self.candidates, threshold=self.threshold, notes=record_notes(rec, self.n_used),
        )  # fmt: skip


def check_known_reference(rec: VehicleRecord, cfg: LMPConfig) -> None:
    """``A_r="known"`` on a record: the reference (a_r, f_r) must come from the record's metadata or the
    options, never from a default (the filters would subtract a reference nobody stated).

    Raises:
        ConfigError: naming ``A_r``.
    """
    if cfg.A_r != "known":
        return
    sources = rec.provenance.get("model_sources", {})
    defaulted = [n for n in ("a_r", "f_r") if str(sources.get(n, "record")).startswith("default")]
    if defaulted:
        raise ConfigError(
            "A_r", "known", f"needs the vehicle's own reference, and the record does not state {' or '.join(defaulted)}: "
            "give --a-r and --f-r (the commanded reference a_r sin(2 pi f_r t), t from the first sample)",
        )  # fmt: skip


def known_reference_meta(rec: VehicleRecord, cfg: LMPConfig) -> dict[str, Any]:
    """The known reference the filters subtracted (``A_r="known"``), for the metadata."""
    if cfg.A_r != "known":
        return {}
    v = rec.vehicle
    return {"known_reference": {"a_r": v.a_r, "f_r": v.f_r, "form": "a_r sin(2 pi f_r k T), k from 0"}}


def record_notes(rec: VehicleRecord, n_used: int) -> tuple[str, ...]:
    """Remarks for the summary line: the missing samples within the horizons."""
    n = int(rec.missing[:n_used].sum())
    return (f"{n} of {n_used} samples missing (predict-only)",) if n else ()
