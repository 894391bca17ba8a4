"""The Performance page from the benchmark results (the last step of ``make bench``).

    python scripts/bench_report.py

1. Copies every ``benchmarks/results/*.csv`` to ``docs/performance/`` (committed, so the docs build
   offline without running the benchmarks); copies there that no longer exist in results are removed.
2. Draws ``docs/performance/performance.svg`` (matplotlib, Agg): µs per filter-step on a log axis for
   FilterPy's KF and UKF, our KF and UKF banks and the FFT path; wall time of the Monte Carlo engine
   with 1 worker, 2 workers and a Dask LocalCluster.
3. Rewrites the block between ``<!-- bench:begin -->`` and ``<!-- bench:end -->`` of
   ``docs/performance.md``: the figure, the machine and versions, one table per benchmark and the
   agreement of the FFT path.

Reads only the copies in ``docs/performance/`` after step 1, so ``--no-copy`` redraws the page from
the committed files.
"""

from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
from benchlib import read_results  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"
OUT = ROOT / "docs" / "performance"
PAGE = ROOT / "docs" / "performance.md"
FIGURE = "performance.svg"
BEGIN, END = "<!-- bench:begin -->", "<!-- bench:end -->"
ENV_KEYS = ("machine", "cores", "python", "numpy", "scipy", "filterpy", "dask", "distributed", "jax")
TITLES = {
    "bench_kf_bank": "Kalman filter bank (Fig 4 of the mode-signature paper)",
    "bench_ukf_bank": "Sigma-point (UKF) bank, radar (Fig 7 of the mode-signature paper)",
    "bench_ukf_history": "Sigma-point bank today against the bank as first published",
    "bench_fft": "FFT fast path of the 1-D LMP detector (Fig 4 workload, Q_a = 0)",
    "bench_imm": "IMM and GLR tracker (the Monte Carlo of Yao, Teng & Wu)",
    "bench_tracks": "IMM and GLR trackers on a real ADS-B feed (213 aircraft), against FilterPy and Stone Soup",
    "bench_feed_memory": "Peak memory of maneuver on feeds of 4.6 and 10 million rows",
    "bench_engine": "Monte Carlo engine: 1 worker, 2 workers, Dask",
    "bench_startup": "Start-up of the command line",
    "bench_slrt": "Track-existence fusion schemes (Govaers' slides)",
    "bench_radar_fast": "Linearised fast path of the radar LMP detector (Fig 7 workload)",
}
# The summary table at the top of the results: (what, file, our case, the case it is compared with).
SUMMARY = [
    ("Kalman filter bank, Fig 4 detection", "bench_kf_bank", "motionsig batched bank", "FilterPy"),
    ("Sigma-point filter bank, Fig 7 radar detection", "bench_ukf_bank", "motionsig", "FilterPy"),
    ("FFT fast path, Fig 4 detection (Q_a = 0)", "bench_fft", "motionsig FFT path", "FilterPy"),
    ("FFT fast path against our own bank", "bench_fft", "motionsig FFT path", "motionsig batched bank"),
    ("Linearised fast path, Fig 7 radar detection", "bench_radar_fast", "linearised", "sigma-point bank"),
    ("IMM, 500 Monte Carlo runs of Yao, Teng & Wu", "bench_imm", "motionsig batched IMM", "FilterPy"),
    ("IMM on a real feed of 213 aircraft, one core", "bench_tracks", "motionsig IMM filter only", "FilterPy"),
    ("IMM on a real feed, against Stone Soup", "bench_tracks", "motionsig IMM filter only", "Stone Soup"),
    ("Monte Carlo engine, 2 worker processes", "bench_engine", "2 workers", "1 worker (in process)"),
    ("Monte Carlo engine, Dask LocalCluster of 2", "bench_engine", "Dask LocalCluster, 2 workers", "1 worker (in"),
]
ORDER = [
    "bench_kf_bank",
    "bench_ukf_bank",
    "bench_ukf_history",
    "bench_fft",
    "bench_imm",
    "bench_tracks",
    "bench_feed_memory",
    "bench_engine",
    "bench_slrt",
    "bench_startup",
]

Results = dict[str, tuple[list[str], list[dict[str, str]]]]


def copy_results() -> list[str]:
    OUT.mkdir(parents=True, exist_ok=True)
    names = sorted(p.name for p in RESULTS.glob("*.csv"))
    for name in names:
        shutil.copyfile(RESULTS / name, OUT / name)
    for stale in OUT.glob("*.csv"):
        if stale.name not in names:
            stale.unlink()
    return names


def load() -> Results:
    return {p.stem: read_results(p) for p in sorted(OUT.glob("*.csv"))}


def _num(text: str | None) -> float | None:
    try:
        return float(text) if text not in (None, "") else None
    except ValueError:
        return None


def _row(res: Results, name: str, prefix: str) -> dict[str, str] | None:
    for row in res.get(name, ([], []))[1]:
        if row.get("case", "").startswith(prefix):
            return row
    return None


def draw(res: Results) -> None:
    """The two-panel figure; a bar whose result file is missing is left out."""
    plt.rcParams.update({"svg.hashsalt": "motionsig-bench", "font.size": 12})
    bars = [  # (label, file, case prefix, FilterPy?)
        ("FilterPy UKF", "bench_ukf_bank", "FilterPy", True),
        ("motionsig UKF bank", "bench_ukf_bank", "motionsig", False),
        ("FilterPy KF", "bench_kf_bank", "FilterPy", True),
        ("motionsig KF bank", "bench_kf_bank", "motionsig", False),
        ("FilterPy KF, Q_a = 0 (FFT run)", "bench_fft", "FilterPy", True),
        ("motionsig KF bank, Q_a = 0 (FFT run)", "bench_fft", "motionsig batched bank", False),
        ("motionsig FFT path (bank equiv.)", "bench_fft", "motionsig FFT path", False),
    ]
    engine = [
        ("1 worker", "1 worker (in process)"),
        ("1 worker,\n1 task per R", "1 worker, one task per R"),
        ("2 workers\n(process pool)", "2 workers (process pool)"),
        ("Dask, 2 workers\n(start-up incl.)", "Dask LocalCluster, 2 workers"),
        ("Dask, 2 workers\n(warm)", "Dask LocalCluster, 2 workers, warm"),
    ]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.8), gridspec_kw={"width_ratios": [1.5, 1]})
    labels, values, colors, notes = [], [], [], []
    for label, name, prefix, is_fp in bars:
        row = _row(res, name, prefix)
        us = _num(row.get("us_per_unit")) if row else None
        if us is None or row is None:
            continue
        labels.append(label)
        values.append(us)
        colors.append("#9e9e9e" if is_fp else "#3f51b5")
        ratio = _num(row.get("ratio_vs_filterpy"))
        notes.append(f"{us:.3g} µs" + ("" if is_fp or ratio is None else f"  ({ratio:,.0f}× FilterPy)"))
    y = range(len(labels))
    ax1.barh(list(y), values, color=colors)
    ax1.set_xscale("log")
    ax1.set_yticks(list(y), labels)
    ax1.invert_yaxis()
    ax1.set_xlabel("µs per filter-step (log scale; lower is faster)")
    ax1.set_title("Time per filter-step, same workload")
    if values:
        ax1.set_xlim(min(values) / 3, max(values) * 80)
    for i, (v, note) in enumerate(zip(values, notes, strict=True)):
        ax1.text(v * 1.15, i, note, va="center", fontsize=11)
    ax1.grid(axis="x", which="major", alpha=0.3)

    e_labels, e_vals, e_notes = [], [], []
    for label, case in engine:
        row = next((r for r in res.get("bench_engine", ([], []))[1] if r.get("case") == case), None)
        sec = _num(row.get("seconds")) if row else None
        if sec is None or row is None:
            continue
        e_labels.append(label)
        e_vals.append(sec)
        sp = _num(row.get("speedup"))
        e_notes.append(f"{sec:.1f} s" + ("" if sp is None else f"\n{sp:.2f}×"))
    x = range(len(e_labels))
    ax2.bar(list(x), e_vals, color=["#3f51b5", "#9fa8da", "#5c6bc0", "#ef6c00", "#ffa726"][: len(e_vals)])
    ax2.set_xticks(list(x), e_labels, fontsize=10, rotation=25, ha="right")
    ax2.set_ylabel("wall time [s] (speed-up vs 1 worker)")
    ax2.set_title("Monte Carlo engine (Fig 4, bank)")
    if e_vals:
        ax2.set_ylim(0, max(e_vals) * 1.3)
    for i, (v, note) in enumerate(zip(e_vals, e_notes, strict=True)):
        ax2.text(i, v, note, ha="center", va="bottom", fontsize=11)
    ax2.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(OUT / FIGURE, format="svg", metadata={"Date": None})
    plt.close(fig)


def _fmt(text: str | None, kind: str = "g") -> str:
    v = _num(text)
    if v is None:
        return text or ""
    if kind == "s":
        return f"{v:,.3f}" if v < 10 else f"{v:,.1f}"
    if kind == "us":
        return f"{v:.4g}"
    if kind == "x":
        return f"{v:,.0f}×" if v >= 10 else f"{v:.2f}×"
    if kind == "pct":
        return f"{v:.2f} %"
    return f"{v:g}"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def table(rows: list[dict[str, str]]) -> list[str]:
    cols = [  # (header, key, format)
        ("Case", "case", "t"),
        ("Wall time [s]", "seconds", "s"),
        ("µs per unit", "us_per_unit", "us"),
        ("Unit", "unit", "t"),
        ("× FilterPy", "ratio_vs_filterpy", "x"),
        ("Speed-up", "speedup", "x"),
        ("Agreement", "agreement_pct", "pct"),
        ("How", "how", "t"),
    ]
    used = [c for c in cols if any(r.get(c[1]) for r in rows)]
    out = ["| " + " | ".join(h for h, _, _ in used) + " |", "|" + "---|" * len(used)]
    for r in rows:
        cells = [_cell(r.get(k, "") if f == "t" else _fmt(r.get(k), f)) for _, k, f in used]
        out.append("| " + " | ".join(cells) + " |")
    return out


def _pc(text: str) -> str:
    v = _num(text)
    return text if v is None else f"{v:.2f}"


def agreement_table(rows: list[dict[str, str]]) -> list[str]:
    out = [
        "| R | trial × horizon pairs | Q_a = 0 bank right | FFT argmax = that bank's | "
        "default bank (Q_a = 1) right | FFT argmax = that bank's | % correct: FFT / bank Q_a = 0 / bank Q_a = 1 |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        out.append(
            f"| {r['R']} | {r['pairs']} | {r['bank_qa0_right']} | {r['agree_qa0']} ({_fmt(r['agree_qa0_pct'], 'pct')}) "
            f"| {r['bank_qa1_right']} | {r['agree_qa1']} ({_fmt(r['agree_qa1_pct'], 'pct')}) "
            f"| {_pc(r['fft_correct_pct'])} / {_pc(r['bank_qa0_correct_pct'])} / {_pc(r['bank_qa1_correct_pct'])} |"
        )
    return out


def summary_table(res: Results) -> list[str]:
    """The short table of the results: each comparison of SUMMARY whose two rows exist, as both times
    and their ratio (of the time per unit, so an extrapolated reference counts the same work)."""
    out = ["| What | motionsig | compared with | time [s] | motionsig is |", "|---|---|---|---|---|"]
    for what, name, ours, ref in SUMMARY:
        a, b = _row(res, name, ours), _row(res, name, ref)
        if a is None or b is None:
            continue
        ua, ub = _num(a.get("us_per_unit")), _num(b.get("us_per_unit"))
        sa, sb = _num(a.get("seconds")), _num(b.get("seconds"))
        ratio = ub / ua if ua and ub else (sb / sa if sa and sb else None)
        if ratio is None:
            continue
        times = f"{_fmt(a.get('seconds'), 's')} / {_fmt(b.get('seconds'), 's')}"
        faster = f"{_fmt(str(ratio), 'x')} faster" if ratio >= 1 else f"{_fmt(str(1 / ratio), 'x')} slower"
        out.append(f"| {what} | {_cell(a['case'])} | {_cell(b['case'])} | {times} | {faster} |")
    return out


def markdown(res: Results) -> str:
    lines = [
        BEGIN,
        "<!-- generated by scripts/bench_report.py from docs/performance/*.csv; edits here are overwritten -->",
        "",
        *summary_table(res),
        "",
        f"![µs per filter-step of every implementation (log scale) and Monte Carlo engine wall times]"
        f"(performance/{FIGURE})",
        "",
        '??? note "Machine and versions of the committed run"',
        "",
    ]
    envs: dict[tuple[str, ...], list[str]] = {}
    for name in res:
        rows = res[name][1]
        if rows and all(k in rows[0] for k in ENV_KEYS):
            envs.setdefault(tuple(rows[0][k] for k in ENV_KEYS), []).append(name)
    lines += ["    | Results | " + " | ".join(ENV_KEYS) + " |", "    |---|" + "---|" * len(ENV_KEYS)]
    for env, names in envs.items():
        lines.append("    | " + ", ".join(f"`{n}`" for n in names) + " | " + " | ".join(map(_cell, env)) + " |")
    lines += ["", "### Every benchmark", ""]
    for name in [*ORDER, *sorted(set(res) - set(ORDER))]:
        if name not in res or name == "bench_fft_agreement":
            continue
        comments, rows = res[name]
        body = [f"- {_cell(c)}" for c in comments if not c.startswith("machine:")]
        body += [f"- Data: [{name}.csv](performance/{name}.csv)", "", *table(rows), ""]
        if name == "bench_fft" and "bench_fft_agreement" in res:
            body += [
                "Argmax agreement of the FFT path, per R, over trials × horizons "
                "([bench_fft_agreement.csv](performance/bench_fft_agreement.csv)):",
                "",
                *agreement_table(res["bench_fft_agreement"][1]),
                "",
            ]
        # each benchmark folded under its title (pymdownx.details): the page leads with the summary
        lines += [f'??? info "{TITLES.get(name, name)}"', "", *(f"    {b}" if b else "" for b in body)]
    lines.append(END)
    return "\n".join(lines)


def write_page(block: str) -> None:
    text = PAGE.read_text()
    if BEGIN not in text or END not in text:
        raise SystemExit(f"{PAGE}: the markers {BEGIN} and {END} are missing")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    PAGE.write_text(head + block + tail)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-copy", action="store_true", help="use the CSVs already in docs/performance/")
    args = ap.parse_args()
    if not args.no_copy:
        names = copy_results()
        print(f"copied {len(names)} result files to {OUT.relative_to(ROOT)}/")
    res = load()
    if not res:
        print("no results: run `make bench` first", file=sys.stderr)
        return 1
    draw(res)
    write_page(markdown(res))
    print(f"wrote {(OUT / FIGURE).relative_to(ROOT)} and the results block of {PAGE.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
