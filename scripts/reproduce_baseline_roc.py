"""`make reproduce`: the LMP detector against the estimate-then-correlate baseline at equal false-alarm rate
(the mode-signature paper, 47th IEEE CDC, Cancún, 2008, §I), into
results/mode_signature/baseline_roc.csv and results/mode_signature/baseline_roc.png.

Three runs of :class:`motionsig_cli.modesig.baseline_roc.BaselineRocJob` on the Monte Carlo engine:

1. 1-D, R = 1e-3, f_r = 0.01 Hz: P_D at P_FA = 0.01 (2000 null records) vs a_sig 0.01 … 2, horizons 10–80 s,
   200 signature records per amplitude;
2. the same with the LMP's amplitude state constant (Q_a = 0, the true model of the simulation, instead of
   the paper's Q_a = 1 per step);
3. 1-D with the reference at the carrier frequency (f_r = f_c = 1 Hz, the paper's Fig 6 setting), where the
   LMP's reference model leaks into its candidates: a model mismatch for both detectors;
4. radar (range/bearing, Fig 7's best ANR pair): P_D at P_FA = 0.05 (400 null records), horizons 10–40 s,
   50 records per amplitude (the LMP's sigma-point bank is the cost).

``--scale S`` multiplies every record count (a quick look: ``--scale 0.1``); ``--workers`` sets the engine's
local processes (default: all cores).
"""

from __future__ import annotations

import argparse
import math
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.lines import Line2D
from matplotlib.ticker import NullFormatter

from motionsig_cli.detection.lmp import LMPConfig
from motionsig_cli.engine import Engine, default_workers, run_job
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.modesig.baseline_roc import DETECTORS, BaselineRoc, BaselineRocJob, RocCell
from motionsig_cli.tables import Table, format_csv, make_meta

OUT = Path("results/mode_signature")


def runs(scale: float) -> list[tuple[str, BaselineRocJob]]:
    def n(k: int) -> int:
        return max(2, math.ceil(k * scale))

    return [
        ("1-D, R = 1e-3, f_r = 0.01 Hz", BaselineRocJob(trials=n(200), null_trials=n(2000), pfa=0.01)),
        (
            "1-D, the LMP with Q_a = 0 (a constant amplitude)",
            BaselineRocJob(
                a_list=(0.01, 0.02, 0.05, 0.1),
                trials=n(200),
                null_trials=n(2000),
                pfa=0.01,
                lmp=LMPConfig(Q_a=0.0),
            ),
        ),
        (
            "1-D, f_r = f_c = 1 Hz (reference at the carrier)",
            BaselineRocJob(
                a_list=(0.2, 0.5, 1.0, 2.0),
                horizons_s=(20.0, 40.0, 80.0),
                trials=n(100),
                null_trials=n(2000),
                pfa=0.01,
                vehicle=replace(Vehicle1D(R=1e-3), f_r=1.0),
            ),
        ),
        (
            "radar, Fig 7 ANR pair 4",
            BaselineRocJob(
                example="radar",
                a_list=(0.05, 0.2, 0.5, 2.0),
                horizons_s=(10.0, 20.0, 40.0),
                trials=n(50),
                null_trials=n(400),
                pfa=0.05,
            ),
        ),
    ]


def _pd_correct(c: RocCell) -> float:
    return c.detections_correct / c.trials


def figure(results: list[tuple[str, BaselineRoc]], path: Path) -> None:
    # one colour per horizon across every panel (the panels' horizons differ), one line style per detector,
    # and one legend for the figure below the panels instead of eight legends of eight entries
    horizons = sorted({h for _, res in results for h in res.job.horizons_s})
    colour = {h: f"C{j}" for j, h in enumerate(horizons)}
    fig, axes = plt.subplots(2, len(results), figsize=(5 * len(results), 8.4), squeeze=False)
    for col, (title, res) in enumerate(results):
        job = res.job
        for row, (what, value) in enumerate(
            ((f"P_D at P_FA = {job.pfa:g}", lambda c: c.pd), ("P(detected and (i, tau) right)", _pd_correct))
        ):
            ax = axes[row, col]
            for h in job.horizons_s:
                for d, style in zip(DETECTORS, ("-", "--"), strict=True):
                    cells = [res.cell(d, a, h) for a in job.a_list]
                    p = [value(c) for c in cells]
                    se = [math.sqrt(max(q * (1 - q), 0.0) / c.trials) for q, c in zip(p, cells, strict=True)]
                    ax.errorbar(job.a_list, p, yerr=se, ls=style, marker="o", color=colour[h], capsize=2)
            ax.set_xscale("log")
            ax.xaxis.set_minor_formatter(NullFormatter())
            ax.set_ylim(-0.03, 1.03)
            ax.set_xlabel("signature amplitude a_sig")
            ax.set_ylabel(what)
            ax.set_title(title, fontsize=9)
            ax.grid(alpha=0.3)
    handles = [Line2D([], [], color=colour[h], marker="o", label=f"horizon {h:g} s") for h in horizons]
    handles += [
        Line2D([], [], color="0.3", ls=st, label=d) for d, st in zip(DETECTORS, ("-", "--"), strict=True)
    ]
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=9, frameon=False)
    fig.suptitle(
        "LMP (solid) vs estimate-then-correlate (dashed), equal P_FA from the null records", fontsize=10
    )
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--workers", type=int, default=default_workers())
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    engine = Engine(workers=args.workers)
    results = []
    for title, job in runs(args.scale):
        print(f"== {title}: {job.trials} + {job.null_trials} null records", flush=True)
        results.append((title, run_job(replace(job, label=title), engine)))
    tables = [res.table() for _, res in results]
    meta = make_meta("scripts/reproduce_baseline_roc.py", scale=args.scale, runs=[t.meta for t in tables])
    out = Table(tables[0].columns, [row for t in tables for row in t.rows], meta)
    (args.out / "baseline_roc.csv").write_text(format_csv(out))
    figure(results, args.out / "baseline_roc.png")
    print(f"wrote {args.out}/baseline_roc.csv, {args.out}/baseline_roc.png")


if __name__ == "__main__":
    main()
