"""`make reproduce`: the search for the regime of the mode-signature paper's Figs 3–6 (47th IEEE CDC, Cancún, 2008) — every setup of
:func:`motionsig_cli.modesig.lmp_search.design` scored against the paper's claims, into
data/lmp_search.csv (one row per setup: its fields, each claim's score with its Monte Carlo standard error,
and the deterministic predictors); and the radar example's Fig 7 (claim 5): every setup of
:func:`motionsig_cli.modesig.lmp_search.design_radar` into data/lmp_search_radar.csv.

Usage: ``python scripts/reproduce_lmp_search.py [--part 1d|radar|both] [--trials N] [--workers W] [--seed S]
[--out PATH] [--radar-out PATH]`` (default both parts, 50 trials per cell, 2 workers: about 40 minutes for
the 1-D part, three quarters of it the sample-grid setups, and about 10 for the radar part, measured on 2
cores of a loaded machine; ``--checkpoint DIR`` resumes
an interrupted run). The CSVs' headers record the command, seed, trials and date.
"""

from __future__ import annotations

import argparse
import datetime
import sys
import time
from pathlib import Path

from motionsig_cli.engine import Engine, run_job
from motionsig_cli.modesig.lmp_search import RadarSearchJob, SearchJob, design, design_radar, predictors
from motionsig_cli.rng import DEFAULT_SEED
from motionsig_cli.tables import Table, format_csv


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--trials", type=int, default=50)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED)
    ap.add_argument("--out", type=Path, default=Path("data/lmp_search.csv"))
    ap.add_argument("--radar-out", type=Path, default=Path("data/lmp_search_radar.csv"))
    ap.add_argument("--part", choices=("1d", "radar", "both"), default="both")
    ap.add_argument("--checkpoint", type=Path, default=None, help="keep finished tasks here (resume a run)")
    args = ap.parse_args(argv)
    if args.part in ("1d", "both"):
        search_1d(args)
    if args.part in ("radar", "both"):
        search_radar(args)


def _write(table: Table, out: Path, args: argparse.Namespace, t0: float, part: str) -> None:
    command = f"python scripts/reproduce_lmp_search.py --part {part} " + " ".join(
        f"--{k} {v}" for k, v in (("trials", args.trials), ("workers", args.workers), ("seed", args.seed))
    )
    meta = {
        "command": command,
        **{k: v for k, v in table.meta.items() if k != "command"},
        "date": datetime.date.today().isoformat(),
        "run_seconds": round(time.perf_counter() - t0, 1),
        "note": "reduced run (fewer trials than the paper's 50)" if args.trials < 50 else "full run",
    }
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(format_csv(Table(table.columns, table.rows, meta)))


def search_radar(args: argparse.Namespace) -> None:
    setups = design_radar()
    job = RadarSearchJob(tuple(setups), trials=args.trials, seed=args.seed)
    print(
        f"lmp search radar: {len(setups)} setups x {args.trials} trials, {args.workers} workers", flush=True
    )
    t0 = time.perf_counter()
    table = run_job(job, Engine(args.workers, checkpoint=args.checkpoint)).table()
    _write(table, args.radar_out, args, t0, "radar")
    holds = table.columns.index("claim5_holds")
    good = [r[0] for r in table.rows if r[holds]]
    print(
        f"wrote {args.radar_out} ({time.perf_counter() - t0:.0f} s); claim 5 holds for: {', '.join(good) or 'none'}"
    )


def search_1d(args: argparse.Namespace) -> None:
    setups = design()
    job = SearchJob(tuple(setups), trials=args.trials, seed=args.seed)
    print(f"lmp search: {len(setups)} setups x {args.trials} trials, {args.workers} workers", flush=True)
    t0 = time.perf_counter()
    result = run_job(job, Engine(args.workers, checkpoint=args.checkpoint))
    predicted = {s.name: predictors(s, seed=args.seed) for s in setups}
    table = result.table(predicted)
    _write(table, args.out, args, t0, "1d")
    holds = table.columns.index("claims_holding")
    best = max(table.rows, key=lambda r: r[holds])
    print(
        f"wrote {args.out} ({time.perf_counter() - t0:.0f} s); most claims holding: {best[0]} ({best[holds]} of 4)"
    )


if __name__ == "__main__":
    main(sys.argv[1:])
