"""The radar sigma-point bank today against the bank as first published with these benchmarks (commit 281efaf).

Workload: that of ``bench_ukf_bank.py`` (Fig 7 of the mode-signature paper): ``lmp_detect_radar`` on 50
trials x 4 ANR pairs (187 filters x 1600 steps each), records simulated beforehand and not timed. Each run
is a fresh process with one BLAS thread on one tree: this checkout, or the first published tree taken out
of the git history (``git archive``) into a temporary folder. The two alternate, ROUNDS times, so that a
change of the machine's load falls on both; the wall time of the best run of each is reported (and its
process CPU time), and the statistics of the two must agree (max |ΔΛ| ≤ 1e-12 of max |Λ|, every argmax equal).

Needs git and the repository's history (a shallow clone without 281efaf skips this benchmark).
Writes ``benchmarks/results/bench_ukf_history.csv`` (layout: ``benchlib.COLUMNS``) and prints a summary.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from benchlib import write_results

FIRST = "281efaf"  # the commit that published bench_ukf_bank.py
ROUNDS = 2
ROOT = Path(__file__).resolve().parents[1]
FILTER_STEPS = 50 * 4 * 187 * 1600

RUN = """
import sys, time
sys.path.insert(0, sys.argv[1])
from dataclasses import replace
import numpy as np
import motionsig_cli
assert motionsig_cli.__file__.startswith(sys.argv[1]), motionsig_cli.__file__
from motionsig_cli.detection.lmp import RadarLMPConfig, lmp_detect_radar
from motionsig_cli.modesig.lmp2d import simulate_trials_2d
from motionsig_cli.models.vehicle2d import Vehicle2D, anr_pair_variances
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import corrected_codes
chips = to_bipolar(corrected_codes()).astype(float)
cfg, hz = RadarLMPConfig(), [200 * j for j in range(1, 9)]
veh = {p: replace(Vehicle2D(), R_range=anr_pair_variances(p)[0], R_bearing=anr_pair_variances(p)[1])
       for p in (1, 2, 3, 4)}
rec = {p: simulate_trials_2d(veh[p], chips, 20, 1.0, 1600, 7, range(50))[0]["y"] for p in veh}
t0, c0 = time.perf_counter(), time.process_time()
lam = [lmp_detect_radar(rec[p], chips, veh[p], 20, cfg, hz).Lambda for p in veh]
print(time.process_time() - c0, time.perf_counter() - t0)
np.save(sys.argv[2], np.stack(lam))
"""


def run(tree: Path, out: Path) -> tuple[float, float]:
    """(CPU, wall) seconds of one whole workload on ``tree``, its statistics saved to ``out``."""
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, "-c", RUN, str(tree), str(out)], env=env, check=True,
                          capture_output=True, text=True, cwd=tree)  # fmt: skip
    cpu, wall = map(float, done.stdout.split()[-2:])
    return cpu, wall


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        old = Path(tmp) / "first"
        old.mkdir()
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", FIRST], capture_output=True)
        if archive.returncode:
            print(
                f"skipped: commit {FIRST} is not in this checkout's history ({archive.stderr.decode().strip()})"
            )
            return 0
        subprocess.run(["tar", "-x", "-C", str(old)], input=archive.stdout, check=True)
        times: dict[str, list[tuple[float, float]]] = {"first": [], "today": []}
        for r in range(ROUNDS):
            for name, tree in (("first", old), ("today", ROOT)):
                times[name].append(run(tree, Path(tmp) / f"{name}.npy"))
                print(
                    f"round {r + 1}: {name:5s} {times[name][-1][0]:.2f} s CPU, {times[name][-1][1]:.2f} s wall"
                )
        lam_old, lam_new = np.load(Path(tmp) / "first.npy"), np.load(Path(tmp) / "today.npy")
    diff = float(np.max(np.abs(lam_new - lam_old)) / np.max(np.abs(lam_old)))
    same_argmax = bool(np.all(lam_new.argmax(axis=1) == lam_old.argmax(axis=1)))
    summary = f"statistics today vs first published: max |dLambda| {diff:.2e} of max |Lambda|, argmax equal: {same_argmax}"
    print(summary)
    if diff > 1e-12 or not same_argmax:
        print("FAILED: the two banks disagree", file=sys.stderr)
        return 1
    best = {k: min(v, key=lambda t: t[1]) for k, v in times.items()}  # by wall time
    ratio = best["first"][1] / best["today"][1]
    rows = []
    for name, label in (("first", f"bank as first published ({FIRST})"), ("today", "bank today")):
        cpu, wall = best[name]
        rows.append({"case": label, "seconds": wall, "units": FILTER_STEPS, "unit": "filter-step",
                     "us_per_unit": 1e6 * wall / FILTER_STEPS, "speedup": best["first"][1] / wall,
                     "how": f"measured, whole workload, best of {ROUNDS} alternating fresh processes (process CPU "
                            f"time {cpu:.2f} s); speedup: vs the first published bank"})  # fmt: skip
    write_results(
        "bench_ukf_history",
        [
            "workload: lmp_detect_radar, 50 trials x 4 ANR pairs x 187 filters x 1600 steps (Fig 7 of the mode-signature paper)",
            summary,
            "each run a fresh process with one BLAS thread; the two trees alternate",
        ],
        rows,
    )
    print(f"speed-up of the bank since it was first published: {ratio:.2f}x   target: >= 2x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
