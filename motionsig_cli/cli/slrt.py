"""``motionsig slrt``: the sequential likelihood-ratio test for track existence from several radars, after
Govaers, *Evaluation of Distributed Detection Methods for Agile Targets* (Fraunhofer FKIE, slides).

The chosen fusion methods (:data:`~motionsig_cli.detection.track_existence.FUSION_METHODS`: the choices,
help and options are read from there; default CKF, FKF, LKF) score the same Monte Carlo runs of target
cases at several detection probabilities, for a constant-velocity or an agile target or both, and no-target
cases (false tracks started on clutter); the output is, per scan, the mean, median and 5–95 % band of log LR,
Wald's decisions, the study's comparison (rates with standard errors against Wald's bounds, ASN), the
operating characteristics over a grid of thresholds, or the schemes at equal error rates. Every value is checked by
the experiment (:class:`~motionsig_cli.existence.slrt.SlrtStudy`), not here; the fusion options
(``--gate-pg``, ``--feedback-every``, ``--ldf-prior``, ``--ldf-weights``, ``--lkf-mean``) are the fields of
:class:`~motionsig_cli.detection.track_existence.FusionOptions`.

With ``slrt DETECTIONS --sensor-table SENSORS`` the methods score the user's own record instead
(:mod:`motionsig_cli.existence.slrt_record`: the files' format and rules); ``--view detections`` and
``--view sensors`` write run 0 of the first simulated case as such files.
"""

from __future__ import annotations

from dataclasses import dataclass
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
from motionsig_cli.cli.option_groups import RecordOptions, options
from motionsig_cli.detection.track_existence import FUSION_METHODS, METHODS

if TYPE_CHECKING:
    from motionsig_cli.existence import slrt as exp

View = choices(
    "View",
    "Output: per-scan log LR (statistics over runs), the SPRT decision table, the study's comparison "
    "(rates with errors against Wald's bounds, ASN), the operating characteristics (false-track against "
    "true-track rates over a grid of thresholds), the schemes at equal error rates, or one simulated run's "
    "detections or sensors as input files.",
    "curves",
    "decisions",
    "study",
    "oc",
    "matched",
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


# the scenario options a detections file replaces (option name → parameter, and what replaces it)
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
    "--target-motion": ("target_motion", "the record"),
    "--turn-rate-deg": ("turn_rate_deg", "the record"),
    "--turn-scans": ("turn_scans", "the record"),
    "--accel": ("accel", "the record"),
    "--accel-scans": ("accel_scans", "the record"),
    "--filter-q": ("filter_q", "--q, the filters' psd"),
    "--filter-clutter": ("filter_clutter", "the sensors table's clutter"),
}
# the agile scenario's options (option → parameter): only with --target-motion agile (or cv,agile)
AGILE_ONLY = {
    "--turn-rate-deg": "turn_rate_deg",
    "--turn-scans": "turn_scans",
    "--accel": "accel",
    "--accel-scans": "accel_scans",
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


AlphaOpt = Annotated[float, typer.Option("--alpha", help="SPRT α = P(confirm | no target).")]
BetaOpt = Annotated[float, typer.Option("--beta", help="SPRT β = P(delete | target).")]
DEFAULT_METHODS = ",".join(METHODS)
MethodsOpt = Annotated[str, typer.Option("--methods", help=METHODS_HELP)]
ViewOpt = Annotated[
    View,
    typer.Option(
        "--view",
        help="curves (per scan), decisions (SPRT table) or study (rates with standard errors and exact "
        "intervals against Wald's bounds, ASN, tracks lost); oc (false-track and true-track confirmation and "
        "deletion over a grid of thresholds log A, log B); matched (each scheme at the thresholds meeting "
        "false-track confirmation <= 0.1 % and true-track deletion <= 1 %, and 1 % / 5 %); detections or "
        "sensors: run 0 of the first case as the files FILE and --sensor-table read.",
    ),
]
StopOpt = Annotated[
    bool,
    typer.Option(
        "--stop/--no-stop", help="Freeze each run's score at its decision (default: keep accumulating)."
    ),
]
PlotScanOpt = Annotated[
    Path | None, typer.Option("--plot-scan", help="Also draw one scan (radars, clutter, target) of run 0.")
]


@dataclass(frozen=True)
class Scenario:
    """The simulated scenario: target cases, sensors, the target's motion, scans and runs (a FILE replaces
    them: :data:`SIMULATION_ONLY`)."""

    pd: Annotated[
        str, typer.Option("--pd", help="Detection probabilities of the target cases (data and filters).")
    ] = "0.9,0.5,0.2"
    no_target: Annotated[
        bool,
        typer.Option(
            "--no-target/--target-only",
            help="Also run the no-target (clutter only) cases: one tentative track per detection of scan 1, "
            "as a tracker starts them, scored from scan 2; one case per --pd.",
        ),
    ] = True
    filter_pd: Annotated[
        float | None,
        typer.Option(
            "--filter-pd", help="One no-target case whose filters assume this p_D (default: one per --pd)."
        ),
    ] = None
    sensors: Annotated[int, typer.Option("--sensors", help="Radars on the circle.")] = 4
    radius: Annotated[
        float, typer.Option("--radius", help="Sensor circle radius [m] (slides: about 13 km).")
    ] = 13_000.0
    clutter: Annotated[float, typer.Option("--clutter", help="Mean false alarms per sensor and scan.")] = 5.0
    filter_clutter: Annotated[
        float | None,
        typer.Option(
            "--filter-clutter",
            help="Mean false alarms per sensor and scan the filters assume (default: --clutter); with --clutter "
            "0 it gives the log LRs their scale.",
        ),
    ] = None
    sigma_r: Annotated[float, typer.Option("--sigma-r", help="Range noise σ_r [m].")] = 50.0
    sigma_phi_deg: Annotated[float, typer.Option("--sigma-phi-deg", help="Bearing noise σ_φ [deg].")] = 0.2
    meas: Annotated[Meas, typer.Option("--meas", help="range-bearing (EKF) or cartesian (linear).")] = (
        Meas.range_bearing
    )
    q: Annotated[
        float,
        typer.Option(
            "--q", help="Acceleration psd q̃ [m²/s³] of the target (and of the filters, unless --filter-q)."
        ),
    ] = 10.0
    filter_q: Annotated[
        float | None,
        typer.Option(
            "--filter-q",
            help="Acceleration psd the filters assume [m²/s³] (default: --q; an agile target needs more).",
        ),
    ] = None
    target_motion: Annotated[
        str,
        typer.Option(
            "--target-motion",
            help="cv (constant velocity + white-noise acceleration, the slides), agile (manoeuvres at "
            "stated scans as well), or cv,agile: each p_D for both.",
        ),
    ] = "cv"
    turn_rate_deg: Annotated[
        str | None,
        typer.Option(
            "--turn-rate-deg",
            help="Agile: coordinated-turn rate of each turn window [deg/s], > 0 left (default 9,-3: 2.5 g, "
            "then 0.74 g).",
        ),
    ] = None
    turn_scans: Annotated[
        str | None,
        typer.Option("--turn-scans", help="Agile: the turn windows, first-last scan (default 1-10,19-28)."),
    ] = None
    accel: Annotated[
        str | None,
        typer.Option(
            "--accel",
            help="Agile: longitudinal acceleration of each window [m/s²] along the velocity (default -5).",
        ),
    ] = None
    accel_scans: Annotated[
        str | None,
        typer.Option(
            "--accel-scans", help="Agile: the acceleration windows, first-last scan (default 13-16; none)."
        ),
    ] = None
    T: Annotated[
        float | None,
        typer.Option(
            "--T", help="Scan period [s] (default 1; with a detections FILE: its metadata T or time grid)."
        ),
    ] = None
    scans: Annotated[int, typer.Option("--scans", help="Scans per run.")] = 30
    runs: Annotated[
        int, typer.Option("--runs", help="Monte Carlo runs per case (over the time limit: --max-minutes).")
    ] = 50


@dataclass(frozen=True)
class Fusion:
    """The fusion options, the fields of :class:`~motionsig_cli.detection.track_existence.FusionOptions`."""

    lkf_mean: Annotated[
        LkfMean, typer.Option("--lkf-mean", help="LKF: mean of the likelihood ratios (slides) or of log LRs.")
    ] = LkfMean.lr
    gate_pg: Annotated[
        float | None,
        typer.Option(
            "--gate-pg",
            help="χ² validation gate probability P_G in (0, 1] for every local update (default: no gate).",
        ),
    ] = None
    feedback_every: Annotated[
        int,
        typer.Option(
            "--feedback-every",
            help="fkf-feedback: reset the local filters to the fused estimate after every N-th scan.",
        ),
    ] = 1
    ldf_prior: Annotated[
        float,
        typer.Option("--ldf-prior", help="ldf: prior existence probability P0 in (0, 1) (assumed 0.5)."),
    ] = 0.5
    ldf_weights: Annotated[
        str | None,
        typer.Option("--ldf-weights", help="ldf: the sensors' weights, comma-separated (default: equal)."),
    ] = None

    def values(self, methods: tuple[str, ...]) -> dict[str, object]:
        """The fusion fields; an option of a method not in ``methods`` is a usage error."""
        for option, name, rule in (("--feedback-every", "feedback_every", "fkf-feedback"),
                                   ("--ldf-prior", "ldf_prior", "ldf"), ("--ldf-weights", "ldf_weights", "ldf")):  # fmt: skip
            if _given(name) and rule not in methods:
                raise typer.BadParameter(f"applies only with --methods including {rule}", param_hint=option)
        weights = None if self.ldf_weights is None else _values("--ldf-weights", self.ldf_weights)
        return {"lkf_mean": self.lkf_mean.value, "gate_pg": self.gate_pg, "feedback_every": self.feedback_every,
                "ldf_prior": self.ldf_prior, "ldf_weights": weights}  # fmt: skip


@dataclass(frozen=True)
class RecordInput:
    """With FILE (the detections): the sensors table and the tracks' start."""

    sensor_table: Annotated[
        Path | None,
        typer.Option(
            "--sensor-table",
            help="With FILE: the sensors (sensor, x, y, sigma_r, sigma_phi [deg] or sigma_xy, pd, clutter "
            "or clutter_density, fov).",
        ),
    ] = None
    sensor_columns: Annotated[
        str | None,
        typer.Option("--sensor-columns", help="With FILE: the sensors table's columns, role=name,..."),
    ] = None
    init: Annotated[
        str | None,
        typer.Option(
            "--init",
            help="With FILE: the track x,vx,y,vy [m, m/s] one scan period before the first scan (default: "
            "the file's metadata init, else one track per detection of the first scan).",
        ),
    ] = None
    init_sd: Annotated[
        str | None,
        typer.Option(
            "--init-sd",
            help="With FILE: the track prior sd pos,vel [m, m/s] (default 200,50 with --init; from a "
            "detection: its sensor's accuracy and 150 m/s).",
        ),
    ] = None


@command(
    parallel=True,
    options={
        "n_sensors": "--sensors",
        "clutter_rate": "--clutter",
        "meas_model": "--meas",
        "sensor_columns": "--sensor-columns",
        "motions": "--target-motion",
    },
)
@options(record=RecordOptions, scenario=Scenario, fusion=Fusion, given_input=RecordInput)
def slrt(
    output: Output,
    parallel: Parallel,
    record: RecordOptions,
    scenario: Scenario,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    alpha: AlphaOpt = 1e-3,
    beta: BetaOpt = 0.1,
    methods: MethodsOpt = DEFAULT_METHODS,
    fusion: Fusion = Fusion(),
    view: ViewOpt = View.curves,
    stop: StopOpt = False,
    plot_scan: PlotScanOpt = None,
    given_input: RecordInput = RecordInput(),
) -> None:
    """Sequential likelihood ratio for track existence from several radars: the confirmation schemes of
    Govaers, Evaluation of Distributed Detection Methods for Agile Targets (Fraunhofer FKIE, slides).

    Centralised (ckf: all measurements at one filter), distributed (fkf: the federated relaxed-evolution
    filter the slides derive for non-linear sensors; fkf-feedback: with the fusion centre's feedback; dkf:
    the exact distributed Kalman filter, linear sensors with p_D = 1 and no clutter only), local (lkf: one
    filter per radar, their likelihood ratios averaged) and decision-level (ldf: local decision fusion;
    naive: local tracks accepted as confirmed). Default: ckf, fkf, lkf (the slides' curves).

    The target flies at nearly constant velocity (the slides), or with --target-motion agile also turns and
    accelerates at stated scans (assumed defaults: 9 deg/s over scans 1-10, 2.5 g; -5 m/s² over 13-16;
    -3 deg/s over 19-28); --filter-q sets the filters' psd apart from the target's --q.

    With FILE (detections, CSV or JSON, '-' for stdin: one row per detection, with time (s or ISO 8601) or
    scan, sensor, and range,bearing or x,y) and --sensor-table SENSORS the methods score your own record
    instead of simulating (--input FILE, the old spelling, still works): per track and scan,
    log LR and Wald's decision. Every sensor of the table scans at every scan; a sensor without a row at a
    scan detected nothing there. A detection outside its sensor's field of view is refused.

    \b
    Example:
      motionsig slrt --plot slrt.png                          # the slides' four panels, 50 runs
      motionsig slrt --view decisions --runs 200              # confirm / delete / undecided, mean decision time
      motionsig slrt --view study --runs 1000 --target-motion cv,agile --methods ckf,fkf,fkf-feedback,lkf,ldf,naive
      motionsig slrt --view matched --runs 1000 --methods ckf,fkf,fkf-feedback,lkf,ldf   # at equal error rates
      motionsig slrt --runs 2000 --workers 8 --checkpoint ckpt/  # parallel; rerun to resume if interrupted
      motionsig slrt --view detections -o dets.csv; motionsig slrt --view sensors -o sensors.csv
      motionsig slrt dets.csv --sensor-table sensors.csv           # the same run's scores, from the files
    """
    output.check(plot_scan=plot_scan)
    method_names = tuple(dict.fromkeys(m.strip() for m in methods.split(",") if m.strip()))
    fused = fusion.values(method_names)
    path = record.path
    if path is not None:
        for option, value in (("--workers", parallel.workers), ("--scheduler", parallel.scheduler),
                              ("--checkpoint", parallel.checkpoint)):  # fmt: skip
            if value is not None:
                raise typer.BadParameter("does not apply with a detections FILE (no Monte Carlo)", param_hint=option)
        _score_record(
            output, path, given_input, record, view, scenario.meas, q=scenario.q, T=scenario.T, alpha=alpha,
            beta=beta, methods=method_names, stop=stop, plot_scan=plot_scan, fusion=fused,
        )  # fmt: skip
        return
    for option, name in INPUT_ONLY.items():
        if _given(name):
            raise typer.BadParameter("applies only with a detections FILE", param_hint=option)
    study = _study(scenario, view, seed, alpha, beta, method_names, stop, fused)
    if scenario.meas is Meas.cartesian:
        output.note("slrt: --meas cartesian: --sigma-r applies to both axes, --sigma-phi-deg is unused")
    if view in (View.detections, View.sensors):
        _write_run(output, study, view, plot_scan)
        return
    _simulate(output, parallel, study, view, plot_scan)


def _study(
    scenario: Scenario, view: View, seed: int, alpha: float, beta: float, methods: tuple[str, ...], stop: bool,
    fusion: dict[str, object],
) -> exp.SlrtStudy:  # fmt: skip
    """The simulated study of the options (one run with --view detections or sensors)."""
    from motionsig_cli.existence import slrt as exp

    sc = scenario
    runs = sc.runs
    if view in (View.detections, View.sensors):
        if _given("runs") and runs != 1:
            raise typer.BadParameter(
                f"--view {view.value} writes one run (run 0 of the first case): use --runs 1",
                param_hint="--runs",
            )
        runs = 1
    motions = tuple(m.strip() for m in sc.target_motion.split(","))
    agile: dict[str, object] = {}
    for option, name in AGILE_ONLY.items():
        text = getattr(sc, name)
        if text is None:
            continue
        if "agile" not in motions:
            raise typer.BadParameter(
                "applies only with --target-motion agile (or cv,agile)", param_hint=option
            )
        agile[name] = _windows(option, text) if name.endswith("_scans") else _values(option, text)
    scen = exp.SlrtScenario(
        n_sensors=sc.sensors, radius=sc.radius, clutter_rate=sc.clutter, sigma_r=sc.sigma_r,
        sigma_phi_deg=sc.sigma_phi_deg, meas_model=sc.meas.value.replace("-", "_"), q=sc.q,
        T=1.0 if sc.T is None else sc.T, scans=sc.scans, filter_q=sc.filter_q, filter_clutter=sc.filter_clutter, **agile,  # type: ignore[arg-type]
    )  # fmt: skip
    return exp.SlrtStudy(
        scen, pd=tuple(common.checked("--pd", common.float_list, sc.pd, what="p_D")),
        no_target=sc.no_target and view not in (View.detections, View.sensors),  # they write the first case
        filter_pd=sc.filter_pd, runs=runs, seed=seed, alpha=alpha, beta=beta, methods=methods, stop=stop,
        motions=None if motions == ("cv",) else motions, **fusion,  # type: ignore[arg-type]
    )  # fmt: skip


def _simulate(
    output: Output, parallel: Parallel, study: exp.SlrtStudy, view: View, plot_scan: Path | None
) -> None:
    """The Monte Carlo of ``study``: its table (--view curves, decisions, study) and figures."""
    from motionsig_cli.existence import slrt as exp

    result = study.result(common.run_job(study.job(), parallel.engine(), "slrt", output.quiet))
    output.emit(result.table(view.value))
    if output.plot is not None or plot_scan is not None:
        from motionsig_cli.plotting import slrt_figure, slrt_scan_figure

        if output.plot is not None:
            output.figure(slrt_figure(result.panels(), study.thresholds))
        if plot_scan is not None:
            output.figure(slrt_scan_figure(*exp.scan_picture(study)), plot_scan)
    output.note(result.summary())


def _windows(option: str, text: str) -> tuple[tuple[int, int], ...]:
    """``6-12,21-27`` (or one scan ``9``; ``none`` for no window) as ((first, last), ...)."""
    if text.strip().lower() in ("", "none"):
        return ()
    out = []
    for part in text.split(","):
        lo, sep, hi = part.strip().partition("-")
        if not (lo.isascii() and lo.isdigit()) or (sep and not (hi.isascii() and hi.isdigit())):
            raise typer.BadParameter(
                f"expected windows first-last like 6-12,21-27 (or none); got {text!r}", param_hint=option
            )
        out.append((int(lo), int(hi) if sep else int(lo)))
    return tuple(out)


def _values(option: str, text: str) -> tuple[float, ...]:
    """``3,-9`` (``none`` for no window) as floats."""
    if text.strip().lower() in ("", "none"):
        return ()
    return tuple(common.checked(option, common.float_list, text, what=option.lstrip("-")))


def _write_run(output: Output, study: exp.SlrtStudy, view: View, plot_scan: Path | None) -> None:
    """``--view detections|sensors``: run 0 of the first case as an input file."""
    from motionsig_cli.existence import slrt_record

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
    output: Output, path: str, given_input: RecordInput, record: RecordOptions, view: View, meas: Meas, *,
    q: float, T: float | None, alpha: float, beta: float, methods: tuple[str, ...], stop: bool,
    plot_scan: Path | None, fusion: dict[str, object],
) -> None:  # fmt: skip
    """A detections FILE: score the user's detections with every method."""
    from motionsig_cli.existence import slrt_record as rec

    for option, (name, instead) in SIMULATION_ONLY.items():
        if _given(name):
            raise typer.BadParameter(f"does not apply with a detections FILE (given by {instead})", param_hint=option)
    if plot_scan is not None:
        raise typer.BadParameter("draws a simulated scan; not with a detections FILE", param_hint="--plot-scan")
    if view not in (View.curves, View.decisions):
        raise typer.BadParameter(
            f"{view.value} is for the simulation; with a detections FILE choose curves or decisions",
            param_hint="--view",
        )
    sensors, init, init_sd = given_input.sensor_table, given_input.init, given_input.init_sd
    if sensors is None:
        raise typer.BadParameter(
            "is needed with a detections FILE (the sensors of the detections)", param_hint="--sensor-table"
        )
    output.refuse_input(path, "the input file")
    output.refuse_input(sensors, "the --sensor-table file")
    cfg = rec.SlrtRecordConfig(
        q=q, T=T, meas=meas.value.replace("-", "_") if _given("meas") else None,
        init=None if init is None else tuple(common.checked("--init", common.float_list, init, what="x,vx,y,vy")),
        init_sd=None if init_sd is None else tuple(
            common.checked("--init-sd", common.float_list, init_sd, what="pos,vel")),
        methods=methods, **fusion,  # type: ignore[arg-type]
        alpha=alpha, beta=beta, stop=stop,
    )  # fmt: skip
    loaded = rec.load(path, sensors, cfg, columns=record.columns, sensor_columns=given_input.sensor_columns,
                      units=record.units)  # fmt: skip
    result = rec.score(loaded, cfg)
    table = result.table(view.value)
    if output.plot is not None:
        from motionsig_cli.plotting import slrt_figure

        output.figure(slrt_figure(result.panels(), cfg.thresholds))
    output.emit(table)
    for line in result.notes():
        output.note(line)
