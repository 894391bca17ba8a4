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

import numpy as np

from motionsig_cli.detection.lmp import LMPConfig, lmp_detect
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
    chunk: int = 50,
    on_chunk: Callable[[int], None] | None = None,
    signature: bool = True,
) -> list[MCCell]:
    """% correct (i, τ) vs horizon for every (f_r, R) — Figs 4–6.

    One record per trial (the longest horizon) serves every horizon. Trial t of every cell uses the
    same draws (common random numbers across f_r and R), so cells differ only by f_r and R. One
    Riccati recursion per R serves all f_r and trials (the filters do not know f_r).
    """
    n = round(max(horizons_s) / vehicle.T)
    hz = [round(h / vehicle.T) for h in horizons_s]
    cells: list[MCCell] = []
    for R in R_list:
        counts = {(fr, h): [0, 0] for fr in fr_list for h in hz}
        for start in range(0, trials, chunk):
            ids = list(range(start, min(trials, start + chunk)))
            ys, truths = [], []
            for fr in fr_list:
                veh = replace(vehicle, R=R, f_r=fr)
                y, draws = simulate_trials(veh, chips, m_rho, f_c, n, seed, ids, signature=signature)
                ys.append(y)
                truths.extend(draws)
            res = lmp_detect(np.concatenate(ys), chips, replace(vehicle, R=R), m_rho, cfg, hz)
            best, _ = res.best()  # (B, H)
            c = res.candidates
            true_mode = np.array([d.mode for d in truths])[:, None]
            true_tau = np.array([d.tau for d in truths])[:, None]
            ok_mode = c.mode[best] == true_mode  # (B, H), records ordered f_r-major
            ok = ok_mode & (c.tau[best] == true_tau)
            per_fr = len(ids)
            for f, fr in enumerate(fr_list):
                rows = slice(f * per_fr, (f + 1) * per_fr)
                for j, h in enumerate(hz):
                    counts[(fr, h)][0] += int(ok[rows, j].sum())
                    counts[(fr, h)][1] += int(ok_mode[rows, j].sum())
            if on_chunk:
                on_chunk(len(ids))
        for fr in fr_list:
            for h, hs in zip(hz, horizons_s, strict=True):
                k, km = counts[(fr, h)]
                cells.append(MCCell(fr, R, float(hs), trials, k, km))
    return cells
