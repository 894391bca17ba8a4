"""``motionsig slrt``: the sequential likelihood-ratio test for track existence from several radars, after
Govaers, *Evaluation of Distributed Detection Methods for Agile Targets* (Fraunhofer FKIE, slides).

The fusion methods (CKF, DKF, LKF: :data:`~motionsig_cli.detection.track_existence.FUSION_METHODS`) score
the same Monte Carlo runs of target cases at several detection probabilities and a no-target case; the
output is, per scan, the mean, median and 5–95 % band of log LR, or Wald's decisions. Every value is
checked by the experiment (:class:`~motionsig_cli.experiments.slrt.SlrtStudy`), not here.

With ``--input DETECTIONS --sensor-table SENSORS`` the methods score the user's own record instead
(:mod:`motionsig_cli.experiments.slrt_record`: the files' format and rules); ``--view detections`` and
``--view sensors`` write run 0 of the first simulated case as such files.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import (
    DEFAULT_SEED_VALUE,
    Output,
    Parallel,
    SeedOpt,
    choices,
    command,
)
from motionsig_cli.detection.track_existence import FUSION_METHODS, METHODS

if TYPE_CHECKING:
    from motionsig_cli.experiments import slrt as exp

View = choices(
    "View",
    "Output: per-scan log LR (statistics over runs), the SPRT decision table, or one simulated run's "
    "detections or sensors as input files.",
    "curves",
    "decisions",
    "detections",
    "sensors",
)
Meas = choices("Meas", "Sensor measurement model.", "range-bearing", "cartesian")
LkfMean = choices(
    "LkfMean", "LKF fusion: the arithmetic mean of the local LRs (slides) or of the log LRs.", "lr", "log"
)


METHODS_HELP = (
    "Comma-separated, any of: " + "; ".join(f"{n} ({m.help})" for n, m in FUSION_METHODS.items()) + "."
)


# the scenario options an --input record replaces (option name → parameter, and what replaces it)
SIMULATION_ONLY = {
    "--pd": ("pd", "the sensors table's pd"),
    "--no-target/--target-only": ("no_target", "the record"),
    "--filter-pd": ("filter_pd", "the sensors table's pd"),
    "--sensors": ("sensors", "the sensors table"),
    "--radius": ("radius", "the sensors table's x, y"),
    "--clutter": ("clutter", "the sensors table's clutter"),
    "--sigma-r": ("sigma_r", "the sensors table's sigma_r"),
    "--sigma-phi-deg": ("sigma_phi_deg", "the sensors table's sigma_phi"),
    "--scans": ("scans", "the record's scans"),
    "--runs": ("runs", "the record (one run)"),
    "--seed": ("seed", "the record (nothing is drawn)"),
}
INPUT_ONLY = {
    "--sensor-table": "sensor_table",
    "--columns": "columns",
    "--sensor-columns": "sensor_columns",
    "--units": "units",
    "--init": "init",
    "--init-sd": "init_sd",
}


def _given(name: str) -> bool:
    """Whether the option of parameter ``name`` was given on the command line (not its default)."""
    from typer._click.core import ParameterSource
    from typer._click.globals import get_current_context

    ctx = get_current_context(silent=True)
    source = ctx.get_parameter_source(name) if ctx is not None else None
    return source is not None and source not in (ParameterSource.DEFAULT, ParameterSource.DEFAULT_MAP)


@command(
    parallel=True,
    options={
        "n_sensors": "--sensors",
        "clutter_rate": "--clutter",
        "meas_model": "--meas",
        "sensor_columns": "--sensor-columns",
    },
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
    T: Annotated[
        float | None,
        typer.Option(
            "--T", help="Scan period [s] (default 1; with --input: the file's metadata T or time grid)."
        ),
    ] = None,
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
        View,
        typer.Option(
            "--view",
            help="curves (per scan) or decisions (SPRT table); detections or sensors: run 0 of the first case "
            "as the files --input and --sensor-table read.",
        ),
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
    input_file: Annotated[
        str | None,
        typer.Option(
            "--input",
            "-i",
            help="Score this detections file (CSV or JSON; '-' for stdin) instead of simulating: one row per "
            "detection, with time (s or ISO 8601) or scan, sensor, and range,bearing or x,y.",
        ),
    ] = None,
    sensor_table: Annotated[
        Path | None,
        typer.Option(
            "--sensor-table",
            help="With --input: the sensors (sensor, x, y, sigma_r, sigma_phi [deg] or sigma_xy, pd, clutter "
            "or clutter_density, fov).",
        ),
    ] = None,
    columns: Annotated[
        str | None,
        typer.Option(
            "--columns", help="With --input: the detections' columns, role=name,... (e.g. time=ts)."
        ),
    ] = None,
    sensor_columns: Annotated[
        str | None,
        typer.Option("--sensor-columns", help="With --input: the sensors table's columns, role=name,..."),
    ] = None,
    units: Annotated[
        str | None,
        typer.Option(
            "--units",
            help="With --input: units of either file, role=unit,... (e.g. bearing=deg,range=km; x, y: both "
            "files); over the header's 'name [unit]' and the metadata.",
        ),
    ] = None,
    init: Annotated[
        str | None,
        typer.Option(
            "--init",
            help="With --input: the track x,vx,y,vy [m, m/s] one scan period before the first scan (default: "
            "the file's metadata init, else one track per detection of the first scan).",
        ),
    ] = None,
    init_sd: Annotated[
        str | None,
        typer.Option(
            "--init-sd",
            help="With --input: the track prior sd pos,vel [m, m/s] (default 200,50 with --init; from a "
            "detection: its sensor's accuracy and 150 m/s).",
        ),
    ] = None,
) -> None:
    """Sequential likelihood ratio for track existence from several radars: centralised (CKF), local (LKF)
    and distributed (DKF) Kalman filter scores.

    CKF: all measurements at one filter; DKF: here the federated relaxed-evolution approximation; LKF: one
    filter per radar, their likelihood ratios averaged. After Govaers, Evaluation of Distributed Detection
    Methods for Agile Targets (Fraunhofer FKIE, slides).

    With --input DETECTIONS --sensor-table SENSORS the methods score your own record: per track and scan,
    log LR and Wald's decision. Every sensor of the table scans at every scan; a sensor without a row at a
    scan detected nothing there. A detection outside its sensor's field of view is refused.

    \b
    Example:
      motionsig slrt --plot slrt.png                          # the slides' four panels, 50 runs
      motionsig slrt --view decisions --runs 200              # confirm / delete / undecided, mean decision time
      motionsig slrt --runs 2000 --workers 8 --checkpoint ckpt/  # parallel; rerun to resume if interrupted
      motionsig slrt --view detections -o dets.csv; motionsig slrt --view sensors -o sensors.csv
      motionsig slrt --input dets.csv --sensor-table sensors.csv   # the same run's scores, from the files
    """
    from motionsig_cli.experiments import slrt as exp

    output.check(plot_scan=plot_scan)
    if input_file is not None:
        for option, value in (
            ("--workers", parallel.workers),
            ("--scheduler", parallel.scheduler),
            ("--checkpoint", parallel.checkpoint),
        ):
            if value is not None:
                raise typer.BadParameter("does not apply with --input (no Monte Carlo)", param_hint=option)
        _score_record(
            output, input_file, sensor_table, view, meas, columns=columns, sensor_columns=sensor_columns,
            units=units, init=init, init_sd=init_sd, q=q, T=T, alpha=alpha, beta=beta, methods=methods,
            lkf_mean=lkf_mean.value, stop=stop, plot_scan=plot_scan,
        )  # fmt: skip
        return
    for option, name in INPUT_ONLY.items():
        if _given(name):
            raise typer.BadParameter("applies only with --input DETECTIONS", param_hint=option)
    writes_run = view in (View.detections, View.sensors)
    if writes_run:
        if _given("runs") and runs != 1:
            raise typer.BadParameter(
                f"--view {view.value} writes one run (run 0 of the first case): use --runs 1",
                param_hint="--runs",
            )
        runs = 1
    scenario = exp.SlrtScenario(
        n_sensors=sensors, radius=radius, clutter_rate=clutter, sigma_r=sigma_r, sigma_phi_deg=sigma_phi_deg,
        meas_model=meas.value.replace("-", "_"), q=q, T=1.0 if T is None else T, scans=scans,
    )  # fmt: skip
    study = exp.SlrtStudy(
        scenario, pd=tuple(common.checked("--pd", common.float_list, pd, what="p_D")), no_target=no_target,
        filter_pd=filter_pd, runs=runs, seed=seed, alpha=alpha, beta=beta, lkf_mean=lkf_mean.value,
        methods=tuple(dict.fromkeys(m.strip() for m in methods.split(",") if m.strip())), stop=stop,
    )  # fmt: skip
    if meas is Meas.cartesian:
        output.note("slrt: --meas cartesian: --sigma-r applies to both axes, --sigma-phi-deg is unused")
    if writes_run:
        _write_run(output, study, view, plot_scan)
        return
    result = study.result(common.run_job(study.job(), parallel.engine(), "slrt", output.quiet))
    output.emit(result.table(view.value))
    if output.plot is not None or plot_scan is not None:
        from motionsig_cli.plotting import slrt_figure, slrt_scan_figure

        if output.plot is not None:
            output.figure(slrt_figure(result.panels(), study.thresholds))
        if plot_scan is not None:
            output.figure(slrt_scan_figure(*exp.scan_picture(study)), plot_scan)
    output.note(result.summary())


def _write_run(output: Output, study: exp.SlrtStudy, view: View, plot_scan: Path | None) -> None:
    """``--view detections|sensors``: run 0 of the first case as an input file."""
    from motionsig_cli.experiments import slrt_record

    for name, path in (("--plot", output.plot), ("--plot-scan", plot_scan)):
        if path is not None:
            raise typer.BadParameter(f"--view {view.value} draws no figure", param_hint=name)
    label = study.cases[0][0]
    if view is View.detections:
        output.emit(slrt_record.detection_table(study))
    else:
        output.emit(slrt_record.sensor_table(study))
    output.note(f"slrt: wrote the {view.value} of run 0 of '{label}' (seed {study.seed})")


def _score_record(
    output: Output, path: str, sensors: Path | None, view: View, meas: Meas, *, columns: str | None,
    sensor_columns: str | None, units: str | None, init: str | None, init_sd: str | None, q: float,
    T: float | None, alpha: float, beta: float, methods: str, lkf_mean: str, stop: bool, plot_scan: Path | None,
) -> None:  # fmt: skip
    """``--input``: score the user's detections with every method."""
    from motionsig_cli.experiments import slrt_record as rec

    for option, (name, instead) in SIMULATION_ONLY.items():
        if _given(name):
            raise typer.BadParameter(f"does not apply with --input (given by {instead})", param_hint=option)
    if plot_scan is not None:
        raise typer.BadParameter("draws a simulated scan; not with --input", param_hint="--plot-scan")
    if view not in (View.curves, View.decisions):
        raise typer.BadParameter(
            f"{view.value} writes a simulated run; with --input choose curves or decisions",
            param_hint="--view",
        )
    if sensors is None:
        raise typer.BadParameter(
            "is needed with --input (the sensors of the detections)", param_hint="--sensor-table"
        )
    if output.out is not None:
        for option, p in (("--input", None if path == "-" else Path(path)), ("--sensor-table", sensors)):
            if p is not None and p.resolve() == output.out.resolve():
                raise typer.BadParameter(f"is the {option} file", param_hint="--out")
    cfg = rec.SlrtRecordConfig(
        q=q, T=T, meas=meas.value.replace("-", "_") if _given("meas") else None,
        init=None if init is None else tuple(common.checked("--init", common.float_list, init, what="x,vx,y,vy")),
        init_sd=None if init_sd is None else tuple(
            common.checked("--init-sd", common.float_list, init_sd, what="pos,vel")),
        methods=tuple(dict.fromkeys(m.strip() for m in methods.split(",") if m.strip())), lkf_mean=lkf_mean,
        alpha=alpha, beta=beta, stop=stop,
    )  # fmt: skip
    record = rec.load(path, sensors, cfg, columns=columns, sensor_columns=sensor_columns, units=units)
    result = rec.score(record, cfg)
    table = result.table(view.value)
    if output.plot is not None:
        from motionsig_cli.plotting import slrt_figure

        output.figure(slrt_figure(result.panels(), cfg.thresholds))
    output.emit(table)
    for line in result.notes():
        output.note(line)
