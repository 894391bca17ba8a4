"""`make reproduce`: the search for the regime of the mode-signature paper's Figs 3–6 (*LMP mode detection
with Gold-code signatures*, IEEE CDC 2008) — every setup of
:func:`motionsig_cli.experiments.lmp_search.design` scored against the paper's claims, into
data/lmp_search.csv (one row per setup: its fields, each claim's score with its Monte Carlo standard error,
and the deterministic predictors).

Usage: ``python scripts/reproduce_lmp_search.py [--trials N] [--workers W] [--seed S] [--out PATH]``
(default 50 trials per cell, 2 workers: 9 minutes measured on 2 cores of a loaded machine; ``--checkpoint DIR`` resumes an
interrupted run). The CSV's header records the
command, seed, trials and date.
"""

from __future__ import annotations

import argparse
import datetime
import sys
import time
from pathlib import Path

from motionsig_cli.engine import Engine, run_job
from motionsig_cli.experiments.lmp_search import SearchJob, design, predictors
from motionsig_cli.rng import DEFAULT_SEED
from motionsig_cli.tables import Table, format_csv


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--trials", type=int, default=50)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED)
    ap.add_argument("--out", type=Path, default=Path("data/lmp_search.csv"))
    ap.add_argument("--checkpoint", type=Path, default=None, help="keep finished tasks here (resume a run)")
    args = ap.parse_args(argv)
    setups = design()
    job = SearchJob(tuple(setups), trials=args.trials, seed=args.seed)
    print(f"lmp search: {len(setups)} setups x {args.trials} trials, {args.workers} workers", flush=True)
    t0 = time.perf_counter()
    result = run_job(job, Engine(args.workers, checkpoint=args.checkpoint))
    predicted = {s.name: predictors(s, seed=args.seed) for s in setups}
    table = result.table(predicted)
    command = "python scripts/reproduce_lmp_search.py " + " ".join(
        f"--{k} {v}" for k, v in (("trials", args.trials), ("workers", args.workers), ("seed", args.seed))
    )
    meta = {
        "command": command,
        **{k: v for k, v in table.meta.items() if k != "command"},
        "date": datetime.date.today().isoformat(),
        "run_seconds": round(time.perf_counter() - t0, 1),
        "note": "reduced run (fewer trials than the paper's 50)" if args.trials < 50 else "full run",
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(format_csv(Table(table.columns, table.rows, meta)))
    holds = table.columns.index("claims_holding")
    best = max(table.rows, key=lambda r: r[holds])
    print(
        f"wrote {args.out} ({time.perf_counter() - t0:.0f} s); most claims holding: {best[0]} ({best[holds]} of 4)"
    )


if __name__ == "__main__":
    main(sys.argv[1:])
