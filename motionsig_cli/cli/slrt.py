"""``motionsig slrt``: the distributed sequential likelihood-ratio test for track existence (seed 001).

Three scores on the same Monte Carlo runs — centralised (CKF), the mean of local scores (LKF) and the
distributed fusion of local estimates (DKF) — for target cases at several detection probabilities and a
no-target case; per scan the mean, median and 5–95 % band of log LR, or Wald's decisions.
"""

from __future__ import annotations

import math
from enum import StrEnum
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from motionsig_cli.cli.common import (
    DEFAULT_SEED_VALUE,
    CheckpointOpt,
    DebugOpt,
    FormatOpt,
    OutOpt,
    OutputFormat,
    PlotOpt,
    QuietOpt,
    SchedulerOpt,
    SeedOpt,
    WorkersOpt,
    check_outputs,
    checked,
    engine_session,
    float_list,
    make_engine,
    note,
    positive,
    save_figure,
)
from motionsig_cli.cli.io import Table, emit, make_meta
from motionsig_cli.detection.sprt import freeze_at_decision, wald_thresholds
from motionsig_cli.detection.track_existence import METHODS
from motionsig_cli.experiments import slrt as exp


class View(StrEnum):
    """Output: per-scan statistics of log LR, or the SPRT decision table."""

    curves = "curves"
    decisions = "decisions"


class Meas(StrEnum):
    """Sensor measurement model."""

    range_bearing = "range-bearing"
    cartesian = "cartesian"


class LkfMean(StrEnum):
    """LKF fusion: the arithmetic mean of the local LRs (slides) or of the log LRs."""

    lr = "lr"
    log = "log"


def _unit_interval(value: float) -> float:
    if not 0.0 < value < 0.5:
        raise typer.BadParameter(f"{value:g} is outside (0, 0.5)")
    return value


def _check_ranges(
    sensors: int, radius: float, sigma_r: float, sigma_phi_deg: float, q: float, T: float
) -> None:
    """Scenario values checked one option at a time, so each error names its own option."""
    fov = exp.SlrtScenario().fov_range
    if not (math.isfinite(radius) and radius < fov):
        raise typer.BadParameter(
            f"{radius:g} m: sensors at or beyond the {fov:g} m field of view never see the target",
            param_hint="--radius",
        )
    if sensors > 1 and radius < 1.0:
        raise typer.BadParameter(
            "all sensors at one point: use a radius of at least 1 m", param_hint="--radius"
        )
    if not 1e-3 <= sigma_r <= 1e5:
        raise typer.BadParameter(f"{sigma_r:g} is not in [1e-3, 1e5] m", param_hint="--sigma-r")
    if not 1e-6 <= sigma_phi_deg <= 90.0:
        raise typer.BadParameter(f"{sigma_phi_deg:g} is not in [1e-6, 90] deg", param_hint="--sigma-phi-deg")
    if not (math.isfinite(q) and q <= 1e6):
        raise typer.BadParameter(f"{q:g} is not in [0, 1e6]", param_hint="--q")
    if not T <= 3600.0:
        raise typer.BadParameter(f"{T:g} is not in (0, 3600] s", param_hint="--T")


def slrt(
    pd: Annotated[
        str, typer.Option("--pd", help="Detection probabilities of the target cases (data and filters).")
    ] = "0.9,0.5,0.2",
    no_target: Annotated[
        bool, typer.Option("--no-target/--target-only", help="Also run the no-target (clutter only) case.")
    ] = True,
    filter_pd: Annotated[
        float, typer.Option("--filter-pd", help="p_D the filters assume in the no-target case.")
    ] = 0.9,
    sensors: Annotated[int, typer.Option("--sensors", min=1, max=64, help="Radars on the circle.")] = 4,
    radius: Annotated[
        float, typer.Option("--radius", min=0.0, help="Sensor circle radius [m] (slides: about 13 km).")
    ] = 13_000.0,
    clutter: Annotated[
        float, typer.Option("--clutter", min=0.0, max=1000.0, help="Mean false alarms per sensor and scan.")
    ] = 5.0,
    sigma_r: Annotated[
        float, typer.Option("--sigma-r", callback=positive, help="Range noise σ_r [m].")
    ] = 50.0,
    sigma_phi_deg: Annotated[
        float, typer.Option("--sigma-phi-deg", callback=positive, help="Bearing noise σ_φ [deg].")
    ] = 0.2,
    meas: Annotated[
        Meas, typer.Option("--meas", help="range-bearing (EKF) or cartesian (linear).")
    ] = Meas.range_bearing,
    q: Annotated[float, typer.Option("--q", min=0.0, help="Acceleration psd q̃ [m²/s³].")] = 10.0,
    T: Annotated[float, typer.Option("--T", callback=positive, help="Scan period [s].")] = 1.0,
    scans: Annotated[int, typer.Option("--scans", min=1, max=100_000, help="Scans per run.")] = 30,
    runs: Annotated[int, typer.Option("--runs", min=1, max=100_000, help="Monte Carlo runs per case.")] = 50,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    alpha: Annotated[
        float, typer.Option("--alpha", callback=_unit_interval, help="SPRT α = P(confirm | no target).")
    ] = 1e-3,
    beta: Annotated[
        float, typer.Option("--beta", callback=_unit_interval, help="SPRT β = P(delete | target).")
    ] = 0.1,
    methods: Annotated[
        str, typer.Option("--methods", help="Comma-separated: ckf, dkf, lkf.")
    ] = "ckf,dkf,lkf",
    lkf_mean: Annotated[
        LkfMean, typer.Option("--lkf-mean", help="LKF: mean of LRs (slides) or of log LRs.")
    ] = LkfMean.lr,
    view: Annotated[
        View, typer.Option("--view", help="curves (per scan) or decisions (SPRT table).")
    ] = View.curves,
    stop: Annotated[
        bool,
        typer.Option(
            "--stop/--no-stop", help="Freeze each run's score at its decision (default: keep accumulating)."
        ),
    ] = False,
    plot_scan: Annotated[
        Path | None,
        typer.Option("--plot-scan", help="Also draw one scan (radars, clutter, target) of run 0."),
    ] = None,
    workers: WorkersOpt = None,
    scheduler: SchedulerOpt = None,
    checkpoint: CheckpointOpt = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Sequential likelihood ratio for track existence from several radars: CKF, LKF and DKF (seed 001).

    \b
    Example:
      motionsig slrt --plot slrt.png                          # the slides' four panels, 50 runs
      motionsig slrt --view decisions --runs 200              # confirm / delete / undecided, mean decision time
      motionsig slrt --runs 2000 --workers 8 --checkpoint ckpt/  # parallel; rerun to resume if interrupted
    """
    check_outputs(out, plot, extra={"--plot-scan": plot_scan})
    engine = make_engine(workers, scheduler, checkpoint)
    pds = list(dict.fromkeys(checked("--pd", float_list, pd, what="p_D")))
    if any(not 0.0 < v <= 1.0 for v in pds) or len(pds) > 10:
        raise typer.BadParameter("each p_D must be in (0, 1] (at most 10 values)", param_hint="--pd")
    _check_ranges(sensors, radius, sigma_r, sigma_phi_deg, q, T)
    if not 0.0 < filter_pd <= 1.0:
        raise typer.BadParameter(f"{filter_pd:g} is outside (0, 1]", param_hint="--filter-pd")
    names = tuple(dict.fromkeys(m.strip() for m in methods.split(",") if m.strip()))
    if not names or any(m not in METHODS for m in names):
        raise typer.BadParameter(f"choose from {', '.join(METHODS)}; got {methods!r}", param_hint="--methods")
    if meas is Meas.cartesian:
        note("slrt: --meas cartesian: --sigma-r applies to both axes, --sigma-phi-deg is unused", quiet)
    cases: list[tuple[str, exp.SlrtScenario]] = []
    common = dict(n_sensors=sensors, radius=radius, clutter_rate=clutter, sigma_r=sigma_r, sigma_phi_deg=sigma_phi_deg,
                  meas_model=meas.value.replace("-", "_"), q=q, T=T, scans=scans)  # fmt: skip
    for v in pds:
        cases.append(
            (
                f"target, p_D = {v:g}",
                checked("--pd", exp.SlrtScenario, target=True, pd_true=v, pd_filter=v, **common),
            )
        )
    if no_target:
        cases.append(("no target", checked("--filter-pd", exp.SlrtScenario,
                                           target=False, pd_true=filter_pd, pd_filter=filter_pd, **common)))  # fmt: skip
    seconds, nbytes = exp.cost(cases[0][1], runs, len(cases))
    if seconds > exp.MAX_SECONDS or nbytes > exp.MAX_BYTES:
        raise typer.BadParameter(
            f"estimated {seconds:.0f} s and {nbytes / 1e9:.2g} GB for {len(cases)} case(s) of {runs} runs x {scans} "
            f"scans x {sensors} sensors; the limits are {exp.MAX_SECONDS:.0f} s and 2 GB",
            param_hint="--runs",
        )
    log_a, log_b = wald_thresholds(alpha, beta)
    job = exp.SlrtJob(tuple(sc for _, sc in cases), runs, seed, names, lkf_mean.value)
    with engine_session(engine, runs * len(cases), "slrt", quiet) as advance:
        scored = exp.monte_carlo(job, engine, progress=advance)
    results = [(label, sc, scores) for (label, sc), scores in zip(cases, scored, strict=True)]
    for label, _, scores in results:
        for m, v in scores.items():
            if np.any(np.isnan(v) | (v == np.inf)):
                raise RuntimeError(f"NaN or +inf log LR in {label}, {m}")
            if stop:
                scores[m] = freeze_at_decision(v, log_a, log_b)
    k = np.arange(1, scans + 1)
    if view is View.curves:
        rows = []
        for label, sc, scores in results:
            for m in names:
                st = exp.summarise(scores[m])
                for j in range(scans):
                    rows.append((label, sc.target, sc.pd_filter, m, int(k[j]), float(st["mean"][j]), float(st["median"][j]),
                                 float(st["q05"][j]), float(st["q95"][j])))  # fmt: skip
        cols = (
            "case",
            "target",
            "pd",
            "method",
            "scan",
            "mean_loglr",
            "median_loglr",
            "q05_loglr",
            "q95_loglr",
        )
    else:
        rows = []
        for label, sc, scores in results:
            for m in names:
                d = exp.decisions(scores[m], alpha, beta)
                conf, dele = d.decision == 1, d.decision == -1
                decided = d.decision != 0
                wrong = dele if sc.target else conf
                bound = beta / (1 - alpha) if sc.target else alpha / (1 - beta)
                rows.append((label, sc.target, sc.pd_filter, m, runs, float(conf.mean()), float(dele.mean()),
                             float(1 - decided.mean()), float(d.time[decided].mean()) if decided.any() else None,
                             int(d.time.max()) if decided.any() else None, float(wrong.mean()), bound,
                             float(math.sqrt(max(wrong.mean() * (1 - wrong.mean()), 1 / runs) / runs))))  # fmt: skip
        cols = ("case", "target", "pd", "method", "runs", "confirmed", "deleted", "undecided", "mean_decision_scan",
                "max_decision_scan", "error_rate", "wald_bound", "error_rate_se")  # fmt: skip
    meta = make_meta(
        "slrt",
        view=view.value,
        methods=list(names),
        lkf_mean=lkf_mean.value,
        runs=runs,
        seed=seed,
        seeding="run r draws from SeedSequence(seed).spawn(...)[r]: truth, detections, clutter, initial track",
        scenario={
            **common,
            "x0": list(exp.SlrtScenario().x0),
            "p0_sd": list(exp.SlrtScenario().p0_sd),
            "fov_range_m": exp.SlrtScenario().fov_range,
            "sensor_azimuths": "equally spaced from 0 deg",
        },
        no_target_filter_pd=filter_pd if no_target else None,
        sprt={"alpha": alpha, "beta": beta, "log_A": log_a, "log_B": log_b, "rule": "first crossing"},
        dkf="relaxed evolution model S*Q, locals initialised at S*P0, no feedback; c by the sequential product "
        "with P^(s+1) (slides' P^s corrected)"
        if "dkf" in names
        else None,
        stop=stop,
        clutter_floor="with --clutter 0 the clutter density is floored at 1e-300 per field of view: absolute scores "
        "are arbitrary, only differences between methods mean something"
        if clutter == 0
        else None,
        minus_inf="a log LR of -inf means the filters' p_D = 1 and a sensor saw nothing: the target hypothesis is "
        "impossible (certain deletion)",
        assumptions="measurement model, noise, FoV, scan period, sensor angles, initial track and thresholds are "
        "not given by the slides (spec §2.5 defaults)",
    )
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    if plot is not None:
        from motionsig_cli.plotting import slrt_figure

        panels = []
        for label, _, scores in results:
            curves = {}
            for m in names:
                st = exp.summarise(scores[m])
                curves[m] = (st["mean"], st["q05"], st["q95"])
            panels.append((label, k, curves))
        save_figure(slrt_figure(panels, (log_a, log_b)), plot)
    if plot_scan is not None:
        _scan_picture(cases[0], seed, plot_scan)
    last = "; ".join(
        f"{label}: " + ", ".join(f"{m} {scores[m][:, -1].mean():.1f}" for m in names)
        for label, _, scores in results
    )
    note(f"slrt: mean log LR at scan {scans}: {last}", quiet)


def _scan_picture(case: tuple[str, exp.SlrtScenario], seed: int, path: Path) -> None:
    """Run 0, last scan, measurements mapped to Cartesian coordinates (run 0 drawn again: it depends on
    (seed, 0) only, so it is the run 0 of the Monte Carlo)."""
    from motionsig_cli.plotting import slrt_scan_figure

    label, sc = case
    gen = exp.generate(sc, range(1), seed)
    k = sc.scans - 1
    clutter_xy, target_xy = exp.scan_xy(sc, gen, 0, k)
    sensors = sc.sensors
    fig = slrt_scan_figure(
        sensors, clutter_xy, target_xy, gen.truth[0, : k + 1], title=f"{label}: run 0, scan {k + 1}"
    )
    save_figure(fig, path)
