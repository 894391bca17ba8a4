"""The track-existence schemes of Govaers, *Evaluation of Distributed Detection Methods for Agile Targets*
(Fraunhofer FKIE, slides): time per run of every fusion rule of
:data:`~motionsig_cli.detection.track_existence.FUSION_METHODS`, batched over the Monte Carlo runs.

Workload: the default scenario (``SlrtScenario()``: 4 range–bearing radars on a 13 km circle, 5 false alarms
per sensor and scan, a target at p_D = 0.9, 30 scans of 1 s), RUNS runs drawn once (``generate``, timed
apart, beside the CKF that consumes it: every run draws from its own random stream in a few block draws,
the rest is vectorised across runs, scans and sensors), then each rule scores the same data: all runs at once, one vectorised filter bank per sensor (the only Python
loops are over scans and sensors). The exact DKF applies only to linear sensors with p_D = 1 and no clutter,
so it is timed on that case (``meas_model="cartesian"``, ``pd = 1``, ``clutter_rate = 0``) beside CKF on the
same data.

1. Correctness gate (the exact case: 4 Cartesian sensors with p_D = 1, no clutter, RUNS_GATE runs): DKF and
   FKF with feedback after every scan equal CKF to 1e-9 (relative, at least 1e-9 absolute), as their
   derivations say; with one sensor CKF, FKF, FKF-FB and LKF are bit-identical.
2. Timing: best of REPEATS of the generation (default and agile scenario) and of each rule on the whole
   batch (µs per run-scan: one run, one scan, all four sensors), CKF on the agile scenario's data, and CKF
   at batch sizes 1, 10, 100 and RUNS, which shows what batching the runs buys.

``BENCH_SLRT_RUNS`` sets RUNS (default 500) for a quicker check; the workload line states it.

Writes ``benchmarks/results/bench_slrt.csv`` (layout: ``benchlib.COLUMNS``) and prints a summary.
"""

from __future__ import annotations

import os

import numpy as np
from benchlib import best_of, gate, measured_row, publish

from motionsig_cli.detection.track_existence import ALL_METHODS, FUSION_METHODS, run_methods
from motionsig_cli.existence import slrt
from motionsig_cli.rng import DEFAULT_SEED

RUNS = int(os.environ.get("BENCH_SLRT_RUNS", 500))
RUNS_GATE = 50
REPEATS = 3  # best of 3 (the machine is shared; minima are the least disturbed)
BATCHES = (*(b for b in (1, 10, 100) if b < RUNS), RUNS)


def _score(sc: slrt.SlrtScenario, gen: slrt.Generated, method: str, runs: int | None = None) -> np.ndarray:
    m0, scans = gen.m0, gen.scans
    if runs is not None:  # the first ``runs`` runs of the batch (the scans' padding kept)
        m0 = m0[:runs]
        scans = [slrt.ScanData(tuple(z[:runs] for z in s.Z), tuple(v[:runs] for v in s.valid)) for s in scans]
    return run_methods(sc.model(), m0, scans, (method,))[method]


def correctness() -> tuple[bool, str]:
    exact = slrt.SlrtScenario(meas_model="cartesian", pd_true=1.0, pd_filter=1.0, clutter_rate=0.0)
    out, _ = slrt.run(exact, RUNS_GATE, DEFAULT_SEED, ("ckf", "dkf", "fkf-feedback"))
    ref = out["ckf"]
    worst = {
        m: float(np.max(np.abs(out[m] - ref) / np.maximum(np.abs(ref), 1.0))) for m in ("dkf", "fkf-feedback")
    }
    one, _ = slrt.run(
        slrt.SlrtScenario(n_sensors=1), RUNS_GATE, DEFAULT_SEED, ("ckf", "fkf", "fkf-feedback", "lkf")
    )
    same = all(np.array_equal(one["ckf"], one[m]) for m in ("fkf", "fkf-feedback", "lkf"))
    ok = max(worst.values()) <= 1e-9 and same
    summary = (
        f"correctness gate: {RUNS_GATE} runs of 4 cartesian sensors, p_D = 1, no clutter: max relative |DKF - CKF| "
        f"{worst['dkf']:.1e}, |FKF-FB - CKF| {worst['fkf-feedback']:.1e}; one sensor: CKF = FKF = FKF-FB = LKF "
        f"to the bit: {same}"
    )
    return ok, summary


def main() -> int:
    ok, summary = correctness()
    if not gate(summary, not ok, "FAILED: a distributed rule differs from CKF where it must equal it"):
        return 1
    sc = slrt.SlrtScenario()
    agile = slrt.SlrtScenario(target_motion="agile")
    gen = slrt.generate(sc, range(RUNS), DEFAULT_SEED)
    gen_agile = slrt.generate(agile, range(RUNS), DEFAULT_SEED)
    exact = slrt.SlrtScenario(meas_model="cartesian", pd_true=1.0, pd_filter=1.0, clutter_rate=0.0)
    gen_exact = slrt.generate(exact, range(RUNS), DEFAULT_SEED)
    run_scans = RUNS * sc.scans
    how_gen = f"; {RUNS} runs in one call, each from its own random stream (block draws), the rest vectorised"
    rows = []
    for what, case in (("default", sc), ("agile", agile)):
        t = best_of(lambda c=case: slrt.generate(c, range(RUNS), DEFAULT_SEED), REPEATS)
        rows.append(measured_row(f"generation ({what} scenario)", t, run_scans, "run-scan", None, REPEATS,
                                 how=how_gen))  # fmt: skip
    t = best_of(lambda: _score(agile, gen_agile, "ckf"), REPEATS)
    rows.append(measured_row("ckf (CKF), agile scenario", t, run_scans, "run-scan", None, REPEATS,
                             how=f"; {RUNS} runs in one batch, the data of the agile generation row"))  # fmt: skip
    for name in ALL_METHODS:
        case, data, what = (exact, gen_exact, "cartesian, p_D = 1, no clutter") if name == "dkf" else (
            sc, gen, "default scenario")  # fmt: skip
        t = best_of(lambda n=name, c=case, d=data: _score(c, d, n), REPEATS)
        rows.append(measured_row(f"{name} ({FUSION_METHODS[name].abbreviation}), {what}", t, run_scans, "run-scan",
                                 None, REPEATS, how=f"; {RUNS} runs in one batch"))  # fmt: skip
    t = best_of(lambda: _score(exact, gen_exact, "ckf"), REPEATS)
    rows.append(measured_row("ckf (CKF), cartesian, p_D = 1, no clutter", t, run_scans, "run-scan", None, REPEATS,
                             how=f"; {RUNS} runs in one batch, the data of the dkf row"))  # fmt: skip
    for batch in BATCHES[:-1]:
        reps = max(1, min(RUNS // batch, 20))
        t = best_of(lambda b=batch, r=reps: [_score(sc, gen, "ckf", b) for _ in range(r)], REPEATS) / reps
        rows.append(measured_row(f"ckf (CKF), batch of {batch} run(s)", t, batch * sc.scans, "run-scan", None,
                                 REPEATS, how=f"; mean of {reps} calls"))  # fmt: skip
    publish(
        "bench_slrt",
        [
            f"workload: {RUNS} runs x {sc.scans} scans x {sc.n_sensors} range-bearing radars, clutter "
            f"{sc.clutter_rate:g} per sensor and scan, target at p_D = {sc.pd_true:g} (dkf: cartesian, p_D = 1, "
            "no clutter, where it applies); every rule on the same generated data; generation and CKF also on the "
            "agile scenario (target_motion = agile: its default turns and deceleration)",
            summary,
        ],
        rows,
        "{case:52s} {seconds:8.3f} s  {us_per_unit:9.2f} µs/run-scan  ({how})",
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
