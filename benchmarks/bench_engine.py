"""The Monte Carlo engine: one worker, 2 local workers (this process and a pool of 1) and a Dask LocalCluster.

Workload: the Fig-4 Monte Carlo (``LmpJob(..., method="bank")``: simulation and detection with
the 187-filter bank, default ``LMPConfig``), TRIALS trials × 2 R values (1e-1, 1e-3), f_r = 0.01,
horizons 10..80 s (1600 steps), the default seed. The tasks (chunks of 50 trials by the cost model of
``LmpJob.cost``) are the same whatever the engine, so the cells must be identical.

Timed (wall clock around ``engine.run_job``, best of 3 each; every process computes with one BLAS
thread, ``engine.one_blas_thread``):

* ``Engine(1)``: every task in this process.
* ``Engine(1)`` with nothing kept between tasks (``$MOTIONSIG_CACHE_MB=0``): every task computes its own
  Riccati recursion, replicas and structure (~0.07 s a task), which a process otherwise computes once
  per R (``motionsig_cli.cache``).
* ``Engine(2)``: this process and one spawned worker (its start-up and imports included: it starts
  0.3 s after this process has begun computing, the job is sent to it once, tasks one at a time).
* ``Engine(2, "local")``: this process and a Dask LocalCluster of 1 worker process, started and closed
  inside the call (start-up included; this process computes tasks all along, the cluster's worker too once
  it is up).
* Dask without start-up: a LocalCluster of 2 started beforehand, reached through its address
  (``Engine(2, scheduler=address)``); the workers stay warm across the 3 repeats.

On a 2-core machine the pool cannot beat 2x; the numbers say what the engine costs, not what a larger
machine gains.

Writes ``benchmarks/results/bench_engine.csv`` (layout: ``benchlib.COLUMNS``) and prints a summary.
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys
import time
from collections.abc import Iterator

from benchlib import cores, write_results

from motionsig_cli.cache import clear_all
from motionsig_cli.detection.lmp import LMPConfig
from motionsig_cli.engine import Engine, run_job
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.modesig.lmp1d import LmpJob, MCCell
from motionsig_cli.rng import DEFAULT_SEED
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import corrected_codes

TRIALS, RS, FR, M_RHO = 2400, (1e-1, 1e-3), 0.01, 20  # ≈ 16 s on one core (0.17 s / 50 trials, idle): ≥ 15 s
HORIZONS_S = tuple(float(h) for h in range(10, 81, 10))
REPEATS = 3
CHIPS = to_bipolar(corrected_codes()).astype(float)


def run(engine: Engine, chunk: int | None = None) -> tuple[float, list[MCCell]]:
    t0 = time.perf_counter()
    cells = run_job(job(chunk), engine).cells
    return time.perf_counter() - t0, cells


def job(chunk: int | None = None) -> LmpJob:
    return LmpJob(
        LMPConfig(), (FR,), RS, HORIZONS_S, TRIALS, DEFAULT_SEED, method="bank", vehicle=Vehicle1D(f_r=FR),
        chips=CHIPS, m_rho=M_RHO, f_c=1.0, chunk=chunk,
    )  # fmt: skip


@contextlib.contextmanager
def uncached() -> Iterator[None]:
    """Nothing kept between tasks inside the block (and nothing kept from before it)."""
    old = os.environ.get("MOTIONSIG_CACHE_MB")
    os.environ["MOTIONSIG_CACHE_MB"] = "0"
    clear_all()
    try:
        yield
    finally:
        if old is None:
            os.environ.pop("MOTIONSIG_CACHE_MB")
        else:
            os.environ["MOTIONSIG_CACHE_MB"] = old
        clear_all()


def best(engine: Engine, chunk: int | None = None) -> tuple[float, list[MCCell]]:
    times, cells = [], None
    for _ in range(REPEATS):
        t, c = run(engine, chunk)
        times.append(t)
        if cells is not None and c != cells:
            raise AssertionError(f"{engine}: cells differ between repeats")
        cells = c
    assert cells is not None
    return min(times), cells


def main() -> int:
    from distributed import LocalCluster

    n_tasks = len(job().tasks())
    filter_steps = TRIALS * len(RS) * 187 * round(max(HORIZONS_S) / Vehicle1D().T)

    t1, cells1 = best(Engine(1))
    with uncached():
        tb, cells_b = best(Engine(1))
    t2, cells2 = best(Engine(2))
    td, cells_d = best(Engine(2, "local"))
    import dask

    from motionsig_cli.engine import TRIM_KEY

    with (
        dask.config.set({TRIM_KEY: None}),
        LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=":0",
            silence_logs=logging.CRITICAL,
        ) as cluster,
    ):
        tw, cells_w = best(Engine(2, cluster.scheduler_address))
    same = cells1 == cells_b == cells2 == cells_d == cells_w
    print(f"cells identical across Engine(1) (kept and not), Engine(2), Dask (cold and warm): {same}")
    if not same:
        print("FAILED: the engines disagree", file=sys.stderr)
        return 1
    pct = {c.R: c.pct for c in cells1 if c.horizon_s == max(HORIZONS_S)}

    def row(case: str, t: float, how: str) -> dict[str, object]:
        return {
            "case": case,
            "seconds": t,
            "units": filter_steps,
            "unit": "filter-step",
            "us_per_unit": 1e6 * t / filter_steps,
            "speedup": t1 / t,
            "how": f"{how}; wall time of run_job, best of {REPEATS}; speedup: vs 1 worker",
        }

    rows = [
        row("1 worker (in process)", t1, "Engine(1)"),
        row(
            "1 worker, nothing kept between tasks",
            tb,
            "Engine(1), MOTIONSIG_CACHE_MB=0: a Riccati recursion per task (the default: per process and R)",
        ),
        row("2 workers (process pool)", t2, "Engine(2): this process + 1 spawned worker, start-up included"),
        row(
            "Dask LocalCluster, 2 workers",
            td,
            'Engine(2, "local"): this process + 1 Dask worker, start-up included',
        ),
        row(
            "Dask LocalCluster, 2 workers, warm",
            tw,
            "Engine(2, address) on a LocalCluster started beforehand (start-up excluded)",
        ),
    ]
    write_results(
        "bench_engine",
        [
            f"workload: Fig-4 Monte Carlo (simulation + 187-filter bank), {TRIALS} trials x {len(RS)} R "
            f"({', '.join(f'{r:g}' for r in RS)}) x f_r {FR:g} x 1600 steps, {n_tasks} tasks",
            f"correctness: the {len(cells1)} cells are identical for every engine; % correct at 80 s: "
            + ", ".join(f"R={r:g} {p:.1f}" for r, p in pct.items()),
            f"cores available: {cores()}",
        ],
        rows,
    )
    for r in rows:
        print(f"{r['case']:36s} {r['seconds']:7.2f} s  speed-up {r['speedup']:5.2f}x  ({r['how']})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
