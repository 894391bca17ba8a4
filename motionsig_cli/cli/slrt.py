"""``motionsig slrt``: the sequential likelihood-ratio test for track existence from several radars, after
Govaers, *Evaluation of Distributed Detection Methods for Agile Targets* (Fraunhofer FKIE, slides).

The fusion methods (CKF, DKF, LKF: :data:`~motionsig_cli.detection.track_existence.FUSION_METHODS`) score
the same Monte Carlo runs of target cases at several detection probabilities and a no-target case; the
output is, per scan, the mean, median and 5–95 % band of log LR, or Wald's decisions. Every value is
checked by the experiment (:class:`~motionsig_cli.experiments.slrt.SlrtStudy`), not here.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import DEFAULT_SEED_VALUE, Output, Parallel, SeedOpt, choices, command
from motionsig_cli.detection.track_existence import FUSION_METHODS, METHODS

View = choices(
    "View", "Output: per-scan statistics of log LR, or the SPRT decision table.", "curves", "decisions"
)
Meas = choices("Meas", "Sensor measurement model.", "range-bearing", "cartesian")
LkfMean = choices(
    "LkfMean", "LKF fusion: the arithmetic mean of the local LRs (slides) or of the log LRs.", "lr", "log"
)


METHODS_HELP = (
    "Comma-separated, any of: " + "; ".join(f"{n} ({m.help})" for n, m in FUSION_METHODS.items()) + "."
)


@command(
    parallel=True,
    options={"n_sensors": "--sensors", "clutter_rate": "--clutter", "meas_model": "--meas"},
)
def slrt(
    output: Output,
    parallel: Parallel,
    pd: Annotated[
        str, typer.Option("--pd", help="Detection probabilities of the target cases (data and filters).")
    ] = "0.9,0.5,0.2",
    no_target: Annotated[
        bool, typer.Option("--no-target/--target-only", help="Also run the no-target (clutter only) case.")
    ] = True,
    filter_pd: Annotated[
        float, typer.Option("--filter-pd", help="p_D the filters assume in the no-target case.")
    ] = 0.9,
    sensors: Annotated[int, typer.Option("--sensors", help="Radars on the circle.")] = 4,
    radius: Annotated[
        float, typer.Option("--radius", help="Sensor circle radius [m] (slides: about 13 km).")
    ] = 13_000.0,
    clutter: Annotated[float, typer.Option("--clutter", help="Mean false alarms per sensor and scan.")] = 5.0,
    sigma_r: Annotated[float, typer.Option("--sigma-r", help="Range noise σ_r [m].")] = 50.0,
    sigma_phi_deg: Annotated[float, typer.Option("--sigma-phi-deg", help="Bearing noise σ_φ [deg].")] = 0.2,
    meas: Annotated[
        Meas, typer.Option("--meas", help="range-bearing (EKF) or cartesian (linear).")
    ] = Meas.range_bearing,
    q: Annotated[float, typer.Option("--q", help="Acceleration psd q̃ [m²/s³].")] = 10.0,
    T: Annotated[float, typer.Option("--T", help="Scan period [s].")] = 1.0,
    scans: Annotated[int, typer.Option("--scans", help="Scans per run.")] = 30,
    runs: Annotated[int, typer.Option("--runs", help="Monte Carlo runs per case.")] = 50,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    alpha: Annotated[float, typer.Option("--alpha", help="SPRT α = P(confirm | no target).")] = 1e-3,
    beta: Annotated[float, typer.Option("--beta", help="SPRT β = P(delete | target).")] = 0.1,
    methods: Annotated[str, typer.Option("--methods", help=METHODS_HELP)] = ",".join(METHODS),
    lkf_mean: Annotated[
        LkfMean, typer.Option("--lkf-mean", help="LKF: mean of the likelihood ratios (slides) or of log LRs.")
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
) -> None:
    """Sequential likelihood ratio for track existence from several radars: centralised (CKF), local (LKF)
    and distributed (DKF) Kalman filter scores.

    CKF: all measurements at one filter; DKF: here the federated relaxed-evolution approximation; LKF: one
    filter per radar, their likelihood ratios averaged. After Govaers, Evaluation of Distributed Detection
    Methods for Agile Targets (Fraunhofer FKIE, slides).

    \b
    Example:
      motionsig slrt --plot slrt.png                          # the slides' four panels, 50 runs
      motionsig slrt --view decisions --runs 200              # confirm / delete / undecided, mean decision time
      motionsig slrt --runs 2000 --workers 8 --checkpoint ckpt/  # parallel; rerun to resume if interrupted
    """
    from motionsig_cli.experiments import slrt as exp

    output.check(plot_scan=plot_scan)
    scenario = exp.SlrtScenario(
        n_sensors=sensors, radius=radius, clutter_rate=clutter, sigma_r=sigma_r, sigma_phi_deg=sigma_phi_deg,
        meas_model=meas.value.replace("-", "_"), q=q, T=T, scans=scans,
    )  # fmt: skip
    study = exp.SlrtStudy(
        scenario, pd=tuple(common.checked("--pd", common.float_list, pd, what="p_D")), no_target=no_target,
        filter_pd=filter_pd, runs=runs, seed=seed, alpha=alpha, beta=beta, lkf_mean=lkf_mean.value,
        methods=tuple(dict.fromkeys(m.strip() for m in methods.split(",") if m.strip())), stop=stop,
    )  # fmt: skip
    if meas is Meas.cartesian:
        output.note("slrt: --meas cartesian: --sigma-r applies to both axes, --sigma-phi-deg is unused")
    result = study.result(common.run_job(study.job(), parallel.engine(), "slrt", output.quiet))
    output.emit(result.table(view.value))
    if output.plot is not None or plot_scan is not None:
        from motionsig_cli.plotting import slrt_figure, slrt_scan_figure

        if output.plot is not None:
            output.figure(slrt_figure(result.panels(), study.thresholds))
        if plot_scan is not None:
            output.figure(slrt_scan_figure(*exp.scan_picture(study)), plot_scan)
    output.note(result.summary())
