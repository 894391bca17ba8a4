"""The 2-D radar experiment of seed 000 §IV.B (Fig 7): one trial = draw (i, τ, θ), simulate, detect.

The random streams are those of :mod:`motionsig_cli.experiments.lmp1d` with two-column noise:
``trial_rng(seed, t, 0)`` draws i, τ, θ (the same values as the 1-D trial t), ``(seed, t, 1)`` the
(x, y) process noise and ``(seed, t, 2)`` the (range, bearing) measurement noise. ``motionsig
simulate --example 2d --seed s`` is trial 0 of ``motionsig detect --montecarlo --example 2d --seed s``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from motionsig_cli.detection.lmp import RadarLMPConfig, lmp_detect_radar
from motionsig_cli.experiments.lmp1d import CorrectRates, TrialDraw, draw_trial, signature_batch
from motionsig_cli.models.vehicle2d import Vehicle2D, simulate_2d


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
    draws = [draw_trial(seed, t, n_samples, chips.shape[0], chips.shape[1], m_rho, dims=2) for t in trials]
    modes = np.array([d.mode for d in draws])
    taus = np.array([d.tau for d in draws])
    thetas = np.array([d.theta for d in draws])
    z, zd = signature_batch(chips, modes, taus, thetas, f_c, vehicle.T, m_rho, n_samples)
    if not signature:
        z, zd = np.zeros_like(z), np.zeros_like(zd)
    sim = simulate_2d(vehicle, z, zd, np.stack([d.w for d in draws]), np.stack([d.v for d in draws]))
    return sim, draws


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


def monte_carlo_2d(
    vehicle: Vehicle2D,
    chips: np.ndarray,
    m_rho: int,
    f_c: float,
    cfg: RadarLMPConfig,
    fr_list: Sequence[float],
    pairs: Sequence[tuple[float, float]],
    horizons_s: Sequence[float],
    trials: int,
    seed: int,
    *,
    chunk: int = 50,
    on_chunk: Callable[[int], None] | None = None,
    signature: bool = True,
) -> list[RadarMCCell]:
    """% correct (i, τ) vs horizon for every reference frequency and (R_κ, R_χ) pair — Fig 7.

    One record per trial (the longest horizon) serves every horizon; trial t uses the same draws in
    every pair (common random numbers), so pairs differ only by the noise level.
    """
    n = round(max(horizons_s) / vehicle.T)
    hz = [round(h / vehicle.T) for h in horizons_s]
    cells: list[RadarMCCell] = []
    for fr, p, (R_range, R_bearing) in ((fr, p, pr) for fr in fr_list for p, pr in enumerate(pairs, start=1)):
        veh = replace(vehicle, f_r=fr, R_range=R_range, R_bearing=R_bearing)
        ok_n = np.zeros(len(hz), int)
        okm_n = np.zeros(len(hz), int)
        repairs = 0
        for start in range(0, trials, chunk):
            ids = list(range(start, min(trials, start + chunk)))
            sim, draws = simulate_trials_2d(veh, chips, m_rho, f_c, n, seed, ids, signature=signature)
            res = lmp_detect_radar(sim["y"], chips, veh, m_rho, cfg, hz)
            best, _ = res.best()  # (B, H)
            c = res.candidates
            ok_mode = c.mode[best] == np.array([d.mode for d in draws])[:, None]
            ok = ok_mode & (c.tau[best] == np.array([d.tau for d in draws])[:, None])
            ok_n += ok.sum(0)
            okm_n += ok_mode.sum(0)
            repairs += sum(res.repairs)
            if on_chunk:
                on_chunk(len(ids))
        for j, hs in enumerate(horizons_s):
            cells.append(
                RadarMCCell(
                    fr, p, R_range, R_bearing, float(hs), trials, int(ok_n[j]), int(okm_n[j]), repairs
                )
            )
    return cells
