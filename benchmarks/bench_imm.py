"""The maneuvering-target IMM (Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC
System*), batched over Monte Carlo runs, vs FilterPy's IMMEstimator.

Workload (the paper's Monte Carlo, default scenario): 500 runs × 448 filtered scans (scans 3..450, two-point
initialisation at scan 2) at σ = 100 m, ``ManeuverScenario("literal")``, T = 1 s, measurements from
``measurements(sc, 100.0, range(500), DEFAULT_SEED)`` = 224 000 run-scans. The IMM mixes three 6-state
Kalman filters (``imm_models(1.0)``: CV, CA q = 0.001, CA q = 0.0144) with ``H_POS6`` and R = σ² I.

1. Correctness gate: on run 0, FilterPy's ``IMMEstimator`` with three ``KalmanFilter(dim_x=6, dim_z=2)``
   (F = Φ_j, Q = G_j Q_j G_jᵀ, H = H_POS6, R = σ² I, x = x0, P = P0 of ``two_point_init``; ``imm.predict();
   imm.update(z)`` per scan) must give the same combined estimates X̂(k|k) as ``imm_filter`` to 1e-8
   relative (each state component scaled by its largest magnitude over the run, at least 1), and the same
   model probabilities to 1e-8 absolute. Both use the Joseph-form update, so the work is the same.
2. Timing: motionsig runs ``imm_filter`` on all 500 runs at once (best of 3; measurements and the two-point
   initialisation computed beforehand, not timed). FilterPy runs one record at a time, as it is used: a
   slice of 5 runs × 448 scans (building the three filters and the estimator included; best of 3),
   extrapolated linearly in run-scans: every run costs it the same. Both run in this process, side by side.
3. For information: the GLR tracker (``track("glr", z, 1.0, 100.0, TrackerConfig())``: input-estimation
   filter, maneuver detection, state correction; best of 3) on the same 500 runs. FilterPy has no
   equivalent, so it gets no ratio.

Writes ``benchmarks/results/bench_imm.csv`` (layout: ``benchlib.COLUMNS``) and prints a summary.
"""

from __future__ import annotations

import resource

import numpy as np
from benchlib import best_of, filterpy_row, gate, measured_row, publish

from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.maneuver.scenario import FIRST_SCAN, ManeuverScenario
from motionsig_cli.maneuver.study import TrackerConfig, measurements, track
from motionsig_cli.models.motion import H_POS6, ModelSet, imm_models, two_point_init
from motionsig_cli.rng import DEFAULT_SEED

RUNS, SIGMA, T = 500, 100.0, 1.0
REPEATS = 3  # best of 3 on both sides (the machine is shared; minima are the least disturbed)
SLICE_RUNS = 5  # FilterPy: runs timed, then extrapolated per run-scan
R_MEAS = SIGMA * SIGMA * np.eye(2)


def filterpy_imm(ms: ModelSet, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """FilterPy IMMEstimator of three KalmanFilter objects on one record z (N, 2) of scans 1..N.

    Returns the combined estimates (N−2, 6) and model probabilities (N−2, 3) of scans 3..N.
    """
    from filterpy.kalman import IMMEstimator, KalmanFilter

    x0, P0 = two_point_init(z[0], z[1], T, SIGMA)
    filters = []
    for j in range(ms.r):
        kf = KalmanFilter(dim_x=6, dim_z=2)
        kf.x, kf.P = x0.copy(), P0.copy()
        kf.F, kf.Q, kf.H, kf.R = ms.Phi[j].copy(), ms.Qd[j].copy(), H_POS6.copy(), R_MEAS.copy()
        filters.append(kf)
    imm = IMMEstimator(filters, ms.mu0.copy(), ms.Pi.copy())
    n = z.shape[0] - (FIRST_SCAN - 1)
    xs, mus = np.empty((n, 6)), np.empty((n, ms.r))
    for k, zk in enumerate(z[FIRST_SCAN - 1 :]):
        imm.predict()
        imm.update(zk)
        xs[k] = imm.x
        mus[k] = imm.mu
    return xs, mus


def main() -> int:
    sc = ManeuverScenario("literal")
    ms = imm_models(T)
    z = measurements(sc, SIGMA, range(RUNS), DEFAULT_SEED)  # (RUNS, 450, 2), not timed
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA)
    zf = np.ascontiguousarray(z[:, FIRST_SCAN - 1 :])  # scans 3..450
    n_scans = zf.shape[1]

    # 1. correctness gate: run 0, every scan
    ours1 = imm_filter(zf[:1], H_POS6, R_MEAS, ms, x0[:1], P0)
    ref_x, ref_mu = filterpy_imm(ms, z[0])
    scale = np.maximum(np.abs(ref_x).max(axis=0), 1.0)
    rel = float(np.max(np.abs(ours1.x[0] - ref_x) / scale))
    dmu = float(np.max(np.abs(ours1.mu[0] - ref_mu)))
    summary = (
        f"correctness gate: max relative difference vs FilterPy over 1 run × {n_scans} scans: "
        f"combined estimate {rel:.2e}, model probabilities {dmu:.2e} (absolute)"
    )
    if not gate(summary, rel > 1e-8 or dmu > 1e-8, "FAILED: results differ from FilterPy by more than 1e-8"):
        return 1

    # 2a. motionsig, whole workload
    t_ours = best_of(lambda: imm_filter(zf, H_POS6, R_MEAS, ms, x0, P0), REPEATS)
    run_scans = RUNS * n_scans

    # 2b. FilterPy, a slice: SLICE_RUNS runs, one at a time
    def filterpy_once() -> None:
        for b in range(SLICE_RUNS):
            filterpy_imm(ms, z[b])

    t_slice = best_of(filterpy_once, REPEATS)
    row_fp = filterpy_row("FilterPy IMMEstimator", t_slice, SLICE_RUNS * n_scans, run_scans, "run-scan",
                          f"{SLICE_RUNS} runs x {n_scans} scans", REPEATS)  # fmt: skip

    # 3. GLR tracker, for information (no FilterPy equivalent)
    cfg = TrackerConfig()
    t_glr = best_of(lambda: track("glr", z, T, SIGMA, cfg), REPEATS)
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    row_glr = measured_row("motionsig GLR tracker", t_glr, run_scans, "run-scan", None, REPEATS,
                           how="; no FilterPy equivalent")  # fmt: skip
    rows = [
        measured_row("motionsig batched IMM", t_ours, run_scans, "run-scan", row_fp["seconds"], REPEATS),
        row_fp,
        row_glr,
    ]
    publish(
        "bench_imm",
        [
            f"workload: {RUNS} runs x {n_scans} scans (scans {FIRST_SCAN}..{sc.scans}), sigma={SIGMA:g}, "
            "3-model IMM, literal scenario (the paper's Monte Carlo)",
            f"correctness: max rel diff vs FilterPy combined estimate {rel:.2e}, model probabilities {dmu:.2e} (abs); peak RSS {peak_mb:.0f} MB",
        ],
        rows,
        "{case:24s} {seconds:10.2f} s  {us_per_unit:9.4f} µs/run-scan  ({how})",
    )
    print(f"speed-up (IMM): {rows[0]['ratio_vs_filterpy']:.0f}x   peak RSS {peak_mb:.0f} MB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
