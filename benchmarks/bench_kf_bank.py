"""`make bench`: motionsig's batched LMP filter bank vs FilterPy running the identical bank.

Workload (Fig 4 of the mode-signature paper, *LMP mode detection with Gold-code signatures*, IEEE CDC
2008): 50 trials × 4 R values × 187 filters (1 H0 + 93 candidates ×
{cos, sin}) × 1600 steps (T = 0.05 s, 80 s) = 59.84 M filter-steps.

1. Correctness gate: for a handful of filters and one record, FilterPy's cumulative
   ½ Σ ν²/S (from ``kf.y``, ``kf.S`` after each update) must equal ours to 1e-8 relative.
2. Timing (best of 3 on both sides): motionsig runs the whole workload. FilterPy runs a slice (filters × steps of one record)
   and is extrapolated linearly in filter-steps: it has no way to share the Riccati recursion
   across trials, so every trial costs it the same. Both run in this process, side by side.

Writes ``benchmarks/results/bench_kf_bank.csv`` (layout: ``benchlib.COLUMNS``) and prints a summary.
"""

from __future__ import annotations

import resource
from collections.abc import Callable

import numpy as np
from benchlib import best_of, filterpy_row, gate, measured_row, publish

from motionsig_cli.detection.lmp import LMPConfig, candidate_grid, lmp_detect
from motionsig_cli.experiments.lmp1d import simulate_trials
from motionsig_cli.filters.kalman import innovation_costs, riccati
from motionsig_cli.models.vehicle import Vehicle1D, amplitude_column, transition_h0
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import corrected_codes
from motionsig_cli.signals.signature import replica_bank

TRIALS, RS, N, M_RHO = 50, (1e-1, 1e-2, 1e-3, 1e-5), 1600, 20
REPEATS = 3  # best of 3 on both sides (the machine is shared; minima are the least disturbed)
CHIPS = to_bipolar(corrected_codes()).astype(float)


def h1_bank(veh: Vehicle1D, cfg: LMPConfig) -> tuple[Callable[[int], np.ndarray], np.ndarray]:
    cands = candidate_grid(3, 31, M_RHO, cfg)
    zc, zs, dc, ds = replica_bank(CHIPS, cands.mode, cands.tau, cands.f_c, veh.T, M_RHO, N)
    g = np.concatenate([amplitude_column(veh, zc, dc), amplitude_column(veh, zs, ds)])
    F = np.zeros((g.shape[0], 5, 5))
    F[:, :4, :4] = transition_h0(veh)
    F[:, 4, 4] = 1.0

    def F_at(k: int) -> np.ndarray:
        F[:, 1, 4] = g[:, k]
        return F

    return F_at, g


def filterpy_costs(
    veh: Vehicle1D, cfg: LMPConfig, g_rows: np.ndarray, y: np.ndarray, n_steps: int
) -> np.ndarray:
    """FilterPy KalmanFilter, one object per filter, same model: cumulative ½ Σ ν²/S per filter."""
    from filterpy.kalman import KalmanFilter

    base = np.zeros((5, 5))
    base[:4, :4] = transition_h0(veh)
    base[4, 4] = 1.0
    out = np.empty(len(g_rows))
    for i, g in enumerate(g_rows):
        kf = KalmanFilter(dim_x=5, dim_z=1)
        kf.x = np.zeros((5, 1))
        kf.P = cfg.P0 * np.eye(5)
        kf.H = np.array([[1.0, 0, 0, 0, 0]])
        kf.R = np.array([[cfg.c_r * veh.R]])
        kf.Q = np.diag([*cfg.Q0, cfg.Q_a])
        J = 0.0
        for k in range(n_steps):
            kf.update(y[k])
            J += 0.5 * float(kf.y[0, 0] ** 2 / kf.S[0, 0])
            F = base.copy()
            F[1, 4] = g[k]
            kf.F = F
            kf.predict()
        out[i] = J
    return out


def main() -> int:
    cfg = LMPConfig()
    veh = Vehicle1D(R=1e-3)
    y1, _ = simulate_trials(veh, CHIPS, M_RHO, 1.0, N, 1, [0])

    # 1. correctness gate
    F_at, g = h1_bank(veh, cfg)
    Q1, R_kf = np.diag([*cfg.Q0, cfg.Q_a]), np.array([[cfg.c_r * veh.R]])
    gains = riccati(F_at, np.array([[1.0, 0, 0, 0, 0]]), Q1, R_kf, cfg.P0 * np.eye(5), N, g.shape[0])
    ours = innovation_costs(F_at, np.array([[1.0, 0, 0, 0, 0]]), gains, np.zeros(5), y1, [N])[:, 0, 0]
    pick = np.array([0, 1, 57, 92, 93, 150, 185])
    ref = filterpy_costs(veh, cfg, g[pick], y1[0], N)
    rel = np.max(np.abs(ours[pick] - ref) / np.abs(ref))
    summary = f"correctness gate: max relative difference vs FilterPy over {pick.size} filters × {N} steps = {rel:.2e}"
    if not gate(summary, rel > 1e-8, "FAILED: results differ from FilterPy by more than 1e-8 relative"):
        return 1

    # 2a. motionsig, whole workload (records simulated beforehand, not timed)
    records = {R: simulate_trials(Vehicle1D(R=R), CHIPS, M_RHO, 1.0, N, 7, range(TRIALS))[0] for R in RS}

    def ours_once() -> None:
        for R in RS:
            lmp_detect(records[R], CHIPS, Vehicle1D(R=R), M_RHO, cfg, [200 * j for j in range(1, 9)])

    t_ours = best_of(ours_once, REPEATS)
    filter_steps = TRIALS * len(RS) * 187 * N
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    # 2b. FilterPy, a slice: 24 filters × 1600 steps of one record
    slice_rows = g[:24]
    t_slice = best_of(lambda: filterpy_costs(veh, cfg, slice_rows, y1[0], N), REPEATS)
    row_fp = filterpy_row("FilterPy KalmanFilter", t_slice, slice_rows.shape[0] * N, filter_steps, "filter-step",
                          f"{slice_rows.shape[0]} filters x {N} steps", REPEATS)  # fmt: skip
    row_ours = measured_row(
        "motionsig batched bank", t_ours, filter_steps, "filter-step", row_fp["seconds"], REPEATS
    )
    publish(
        "bench_kf_bank",
        [
            f"workload: {TRIALS} trials x {len(RS)} R x 187 filters x {N} steps (Fig 4 of the mode-signature paper)",
            f"correctness: max rel diff vs FilterPy {rel:.2e}; peak RSS {peak_mb:.0f} MB",
        ],
        [row_ours, row_fp],
        "{case:26s} {seconds:10.2f} s  {us_per_unit:8.4f} µs/filter-step  ({how})",
    )
    print(
        f"speed-up: {row_ours['ratio_vs_filterpy']:.0f}x   peak RSS {peak_mb:.0f} MB   target: >= 500x and < 10 s"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
