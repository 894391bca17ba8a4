"""The 2-D radar experiment of seed 000 §IV.B (Fig 7): one trial = draw (i, τ, θ), simulate, detect.

The random streams are those of :mod:`motionsig_cli.experiments.lmp1d` with two-column noise:
``trial_rng(seed, t, 0)`` draws i, τ, θ (the same values as the 1-D trial t), ``(seed, t, 1)`` the
(x, y) process noise and ``(seed, t, 2)`` the (range, bearing) measurement noise. ``motionsig
simulate --example 2d --seed s`` is trial 0 of ``motionsig detect --montecarlo --example 2d --seed s``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np

from motionsig_cli.detection.lmp import RadarLMPConfig, lmp_detect_radar
from motionsig_cli.engine import Engine, run_tasks, tasks_of, trials_per_task
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


@dataclass(frozen=True)
class RadarMCSpec:
    """Everything a Fig 7 Monte Carlo task needs (picklable)."""

    vehicle: Vehicle2D
    chips: np.ndarray
    m_rho: int
    f_c: float
    cfg: RadarLMPConfig
    horizons_s: tuple[float, ...]
    seed: int
    signature: bool = True


def radar_task(
    spec: RadarMCSpec, task: tuple[float, int, float, float, range]
) -> tuple[np.ndarray, np.ndarray, int]:
    """One task: trials ``task[4]`` of one (f_r, pair) → (% correct counts (H,), mode counts (H,), repairs)."""
    fr, _, R_range, R_bearing, ids = task
    veh = replace(spec.vehicle, f_r=fr, R_range=R_range, R_bearing=R_bearing)
    n = round(max(spec.horizons_s) / veh.T)
    hz = [round(h / veh.T) for h in spec.horizons_s]
    sim, draws = simulate_trials_2d(veh, spec.chips, spec.m_rho, spec.f_c, n, spec.seed, list(ids),
                                    signature=spec.signature)  # fmt: skip
    res = lmp_detect_radar(sim["y"], spec.chips, veh, spec.m_rho, spec.cfg, hz)
    best, _ = res.best()  # (B, H)
    c = res.candidates
    ok_mode = c.mode[best] == np.array([d.mode for d in draws])[:, None]
    ok = ok_mode & (c.tau[best] == np.array([d.tau for d in draws])[:, None])
    return ok.sum(0), ok_mode.sum(0), int(sum(res.repairs))


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
    chunk: int | None = None,
    on_chunk: Callable[[int], None] | None = None,
    signature: bool = True,
    engine: Engine | None = None,
    identity: dict[str, Any] | None = None,
) -> list[RadarMCCell]:
    """% correct (i, τ) vs horizon for every reference frequency and (R_κ, R_χ) pair — Fig 7.

    One record per trial (the longest horizon) serves every horizon; trial t uses the same draws in
    every pair (common random numbers), so pairs differ only by the noise level. Tasks of ≥ 0.1 s
    (a sigma-point trial costs ≈ 1.6 µs per filter-step, 2C + 1 filters) run on ``engine``.
    """
    spec = RadarMCSpec(vehicle, np.asarray(chips, float), m_rho, f_c, cfg, tuple(horizons_s), seed, signature)
    n = round(max(horizons_s) / vehicle.T)
    C = chips.shape[0] * chips.shape[1] * (m_rho if cfg.tau_grid == "samples" else 1) * len(cfg.fc_grid)
    per = chunk or min(50, trials_per_task(n * (2 * C + 1) * 1.6e-6))
    keys = [(fr, p, pr) for fr in fr_list for p, pr in enumerate(pairs, start=1)]
    tasks = [
        (float(fr), p, float(pr[0]), float(pr[1]), r) for fr, p, pr in keys for r in tasks_of(trials, per)
    ]
    results = run_tasks(
        partial(radar_task, spec),
        tasks,
        engine or Engine(),
        sizes=[len(t[4]) for t in tasks],
        progress=on_chunk,
        identity=identity,
    )
    cells: list[RadarMCCell] = []
    for fr, p, (R_range, R_bearing) in keys:
        mine = [res for t, res in zip(tasks, results, strict=True) if t[0] == fr and t[1] == p]
        ok_n = np.sum([m[0] for m in mine], axis=0)
        okm_n = np.sum([m[1] for m in mine], axis=0)
        repairs = sum(m[2] for m in mine)
        for j, hs in enumerate(horizons_s):
            cells.append(
                RadarMCCell(
                    fr, p, R_range, R_bearing, float(hs), trials, int(ok_n[j]), int(okm_n[j]), repairs
                )
            )
    return cells
