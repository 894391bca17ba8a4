"""``motionsig maneuver``: tracking a maneuvering target with an IMM of three Kalman filters and with GLR / MLR
maneuver detection (Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System*),
Monte Carlo over runs or one measurement record.

Views: ``scans`` (eqs 14–15 per scan, RMS error, mean model probabilities, declaration rate), ``events``
(detection delay and onset error after each true input change), ``summary`` (one row per σ and method: RMS
error per phase, false alarms, detection of each change — the comparison table), ``measurements`` (the
simulated records, to pipe into ``maneuver FILE``) and, with a record FILE, the per-scan track of one record: a CSV or
JSON export with a time (seconds or ISO 8601) and/or scan column and the positions x, y (``--columns``,
``--units``); missed scans are predict-only steps, σ is given, in the metadata or estimated
(:mod:`motionsig_cli.maneuver.record`).

Front ends: ``gaussian`` (default: the paper's positions with σ per axis) or ``ebpsk`` (positions located by the
EBPSK radar, with their covariance per scan and missed detections,
:mod:`motionsig_cli.maneuver.ebpsk_tracking`; ``--view front-end`` tabulates what it delivers along the
track).

The command parses the options and writes the results; the configurations of
:mod:`motionsig_cli.maneuver.study` check every value, and its :class:`ManeuverJob` is the Monte Carlo.
"""

from __future__ import annotations

import contextlib
import math
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import DEFAULT_SEED_VALUE, Output, Parallel, SeedOpt, choices, command
from motionsig_cli.cli.option_groups import RecordOptions, given, options

if TYPE_CHECKING:
    from motionsig_cli.engine import Engine
    from motionsig_cli.maneuver import study as exp

CHI2_2_999 = -2.0 * math.log(1e-3)
"""The default GLR threshold, the 0.999 quantile of χ²₂ (``detection.glr.CHI2_2_999``, which needs NumPy)."""

OPTIONS = {"sigmas": "--sigma", "methods": "--method", "Pi": "--transition", "g2": "--G2",
           "sigma_u": "--mlr-sigma-u", "g_t_db": "--gain-db", "g_r_db": "--gain-db", "range": "--radar-position",
           "source": "--front-end"}  # fmt: skip
"""Configuration fields whose option is not ``--`` + the field's name."""


G2 = choices("G2", "Form of G₂ = G₃ (``models.motion.G2_FORMS``).", "paper-fixed", "standard")
Preset = choices("Preset", "Trajectory preset (``maneuver.scenario.PRESETS``).", "literal", "turn90")
View = choices(
    "View", "What the table holds.", "scans", "events", "summary", "measurements", "front-end", "network"
)
FrontEnd = choices("FrontEnd", "Where the trackers' measurements come from.", "gaussian", "ebpsk")
Level = choices("Level", "How the EBPSK front end is simulated.", "detector", "samples")
Correction = choices("Correction", "State correction on a declaration.", "exact", "paper")
Continuation = choices(
    "Continuation", "What happens to the input estimate after a declaration.", "estimate", "known"
)


def _methods(text: str, choices: tuple[str, ...]) -> tuple[str, ...]:
    """``'imm,glr'`` → ``('imm', 'glr')`` in order without repeats; ``'all'`` → every method."""
    names = tuple(dict.fromkeys(m.strip().lower() for m in text.split(",") if m.strip()))
    return choices if names == ("all",) else names


def _matrix(text: str, what: str = "transition probability") -> tuple[tuple[float, ...], ...]:
    """``'a,b,c;d,e,f;…'`` → rows."""
    rows = [r for r in text.split(";") if r.strip()]
    if not rows:
        raise ValueError(f"no rows in {text!r}")
    out = [tuple(common.float_list(r, what=what)) for r in rows]
    if len({len(r) for r in out}) != 1:
        raise ValueError(f"rows of different lengths in {text!r}")
    return tuple(out)


def _probabilities(transition: str | None, mu0: str | None) -> dict[str, Any]:
    """The IMM transition matrix (``Pi``) and initial probabilities (``mu0``) given on the command line."""
    probs: dict[str, Any] = {}
    if transition is not None:
        probs["Pi"] = common.checked("--transition", _matrix, transition)
    if mu0 is not None:
        probs["mu0"] = tuple(common.checked("--mu0", common.float_list, mu0, what="probability"))
    return probs


def _opt(name: str, help_text: str, *aliases: str) -> typer.models.OptionInfo:
    return typer.Option(name, *aliases, help=help_text)


MethodOpt = Annotated[
    str, _opt("--method", "Trackers, comma-separated: imm, glr, mlr, cv (CV Kalman filter), or all.")
]
SigmaOpt = Annotated[
    str | None,
    _opt(
        "--sigma",
        "Measurement noise σ per axis [m], 1e-3 to 1e7, comma-separated (default 100,200). With FILE: one "
        "σ, or 'estimate' (from the positions' second differences); default the record's metadata 'sigma', "
        "else estimated.",
    ),
]
PresetOpt = Annotated[Preset, _opt("--preset", "literal (as printed) or turn90 (exact 90° turns).")]
TOpt = Annotated[
    float | None,
    _opt(
        "--T",
        "Scan period [s], 1e-3 to 3600 (assumed: 1; the paper does not state it). With FILE: default the "
        "record's metadata 'T', else the period of its times, else 1; must agree with the times (0.1 %).",
    ),
]
ScansOpt = Annotated[int, _opt("--scans", "Scans per run, 3 to 100000 (paper: 450).")]
RunsOpt = Annotated[
    int,
    _opt("--runs", "Monte Carlo runs, 1 to 1e6 (paper: 500); a run over the time limit: see --max-minutes."),
]
G2Opt = Annotated[G2, _opt("--G2", "G2 = G3: paper-fixed (T²/4, T/2, 1) or standard (T²/2, T, 1).")]
TransitionOpt = Annotated[
    str | None, _opt("--transition", "IMM transition matrix, rows separated by ';' (default: the paper's).")
]
Mu0Opt = Annotated[str | None, _opt("--mu0", "Initial model probabilities (default 0.8,0.1,0.1).")]
ImmQOpt = Annotated[
    str | None,
    _opt(
        "--imm-q",
        "IMM acceleration-increment variances q1,q2,q3 [(m/s²)²] of the CV and the two CA models, each 0 to "
        "1e6 (default the paper's 0,0.001,0.0144).",
    ),
]
Q0Opt = Annotated[
    float | None,
    _opt("--q0", "GLR/MLR/CV filter acceleration psd q̃0 [m²/s³], 0 to 1e6 (paper tuning 1, aircraft 0.5)."),
]
WindowOpt = Annotated[
    int | None, _opt("--window", "GLR/MLR onset window s [scans], 1 to 200 (paper tuning 10, aircraft 20).")
]
GlrThresholdOpt = Annotated[
    float | None,
    _opt(
        "--glr-threshold",
        "GLR threshold λ on ΔJ, ≥ 0 (paper tuning: χ²₂ 0.999 quantile, 13.8; aircraft: 30).",
    ),
]
MlrThresholdOpt = Annotated[
    float | None, _opt("--mlr-threshold", "MLR threshold h on max_n J(n) (paper: 0; aircraft: 8).")
]
SigmaUOpt = Annotated[
    float | None,
    _opt("--mlr-sigma-u", "MLR prior σ_u of each input [m/s²], 1e-3 to 1e6 (paper tuning 20, aircraft 10)."),
]
CorrectionOpt = Annotated[
    Correction, _opt("--correction", "exact (updated estimate) or paper (prediction, re-update).")
]
ContinuationOpt = Annotated[
    Continuation,
    _opt(
        "--continuation",
        "estimate (input estimate keeps its covariance) or known (the paper's: an exactly known input).",
    ),
]
ResponseOpt = Annotated[
    int, _opt("--response", "Scans after a change a declaration can be attributed to it, 1 to 10000.")
]
ViewOpt = Annotated[
    View,
    _opt(
        "--view",
        "scans, events, summary, measurements, front-end (ebpsk: σ, P_D along the track) or network (ebpsk: "
        "position accuracy of several nodes ranging the target, beside the single radar).",
    ),
]
FrontEndOpt = Annotated[
    FrontEnd,
    _opt(
        "--front-end",
        "gaussian (the paper's positions, σ per axis) or ebpsk (the EBPSK radar's located positions with their "
        "covariance per scan and missed detections).",
    ),
]
LevelOpt = Annotated[
    Level | None,
    _opt(
        "--level",
        "ebpsk: detector (draws from the detector's statistics; default) or samples (the sample-level echo, "
        "impacting filter and CFAR at every scan: slow).",
    ),
]
RadarPositionOpt = Annotated[
    str | None, _opt("--radar-position", "ebpsk: the radar's x,y [m] (assumed 150000,150000).")
]
PtOpt = Annotated[
    float | None,
    _opt(
        "--p-t",
        "ebpsk: transmit power [W]. Default: set so that the median position σ along the track is each --sigma.",
    ),
]
GainOpt = Annotated[float | None, _opt("--gain-db", "ebpsk: transmit and receive antenna gain [dBi] (38).")]
RcsOpt = Annotated[float | None, _opt("--rcs", "ebpsk: target radar cross-section [m²] (1).")]
LossOpt = Annotated[float | None, _opt("--loss-db", "ebpsk: system losses [dB], 0 to 100 (6).")]
NoiseFigureOpt = Annotated[float | None, _opt("--noise-figure-db", "ebpsk: receiver noise figure [dB] (3).")]
PulsesOpt = Annotated[int | None, _opt("--n-pulses", "ebpsk: pulses integrated coherently per scan (1).")]
PfaOpt = Annotated[float | None, _opt("--pfa", "ebpsk: CA-CFAR false-alarm probability per cell (1e-6).")]
PriOpt = Annotated[
    float | None, _opt("--pri", "ebpsk: pulse repetition interval [s] (5e-3: unambiguous range 749 km).")
]
BeamwidthOpt = Annotated[float | None, _opt("--beamwidth", "ebpsk: 3-dB beamwidth [deg], 0 to 180 (2).")]
NodesOpt = Annotated[
    str | None,
    _opt(
        "--nodes",
        "ebpsk, --view network: node positions x,y;x,y;... [m] (assumed: seven nodes along the literal track).",
    ),
]
PlotCompareOpt = Annotated[
    Path | None, _opt("--plot-compare", "Also draw RMS error and declarations of every method.")
]


@dataclass(frozen=True)
class TrackerOptions:
    """The trackers' settings: the IMM's G2, transition matrix, initial probabilities and noise, and the
    GLR/MLR detectors'. An option left out takes the tuning's value (``--tuning``)."""

    g2: G2Opt = G2.paper_fixed
    transition: TransitionOpt = None
    mu0: Mu0Opt = None
    imm_q: ImmQOpt = None
    q0: Q0Opt = None
    window: WindowOpt = None
    glr_threshold: GlrThresholdOpt = None
    mlr_threshold: MlrThresholdOpt = None
    mlr_sigma_u: SigmaUOpt = None
    correction: CorrectionOpt = Correction.exact
    continuation: ContinuationOpt = Continuation.estimate

    def config(self, tuning: str = "paper") -> exp.TrackerConfig:
        """The trackers' configuration: the tuning's defaults with the options given (which it checks)."""
        from motionsig_cli.maneuver import study as exp

        extra = _probabilities(self.transition, self.mu0)
        if self.imm_q is not None:
            extra["imm_q"] = tuple(common.checked("--imm-q", common.float_list, self.imm_q, what="variance"))
        for name, field_name in (("q0", "q0"), ("window", "window"), ("glr_threshold", "glr_threshold"),
                                 ("mlr_threshold", "mlr_threshold"), ("mlr_sigma_u", "sigma_u")):  # fmt: skip
            if getattr(self, name) is not None:
                extra[field_name] = getattr(self, name)
        return exp.TrackerConfig.tuned(tuning, g2=self.g2.value, correction=self.correction.value,
                                       continuation=self.continuation.value, **extra)  # fmt: skip


Tuning = choices("Tuning", "Tracker defaults.", "paper", "aircraft")
Stale = choices("Stale", "What to do with stale repeats.", "drop", "keep")
Convention = choices("Convention", "Bearing convention.", "north-clockwise", "math")
OnOff = choices("OnOff", "On or off.", "on", "off")


@dataclass(frozen=True)
class RealRecordOptions:
    """How a real record (FILE) is read and watched: its frame, its hygiene, the tracker defaults and the
    consistency checks."""

    tuning: Annotated[
        Tuning | None,
        _opt(
            "--tuning",
            "Tracker defaults: aircraft (real records; the default with FILE) or paper (the paper's "
            "values; the default for the paper's scenario). Options given override them.",
        ),
    ] = None
    origin: Annotated[
        str | None,
        _opt(
            "--origin",
            "Local frame origin LAT,LON[,ALT] [deg, deg, m] for latitude/longitude or range/bearing "
            "records (default: the middle of the record's box, or the sensor).",
        ),
    ] = None
    sensor: Annotated[
        str | None,
        _opt("--sensor", "The sensor LAT,LON[,ALT] of range/bearing plots (default: the metadata 'sensor')."),
    ] = None
    bearing_convention: Annotated[
        Convention,
        _opt(
            "--bearing-convention",
            "north-clockwise (default: degrees from north, clockwise) or math (counter-clockwise from east).",
        ),
    ] = Convention.north_clockwise
    max_gap: Annotated[
        float | None,
        _opt(
            "--max-gap",
            "A gap longer than this [s] ends a segment; the trackers restart after it (default: the "
            "larger of 30 s and 8 median steps).",
        ),
    ] = None
    strict: Annotated[
        bool,
        typer.Option(
            "--strict", help="Refuse unsorted rows and duplicate times instead of sorting and dropping them."
        ),
    ] = False
    stale: Annotated[
        Stale,
        _opt("--stale", "Stale repeats (the previous position under a new time): drop (default) or keep."),
    ] = Stale.drop
    consistency: Annotated[
        OnOff,
        _opt(
            "--consistency",
            "Each tracker's own checks (NIS gate and window, speed, acceleration, covariance; a "
            "track that fails restarts and says so): on (default) or off.",
        ),
    ] = OnOff.on
    max_speed: Annotated[
        float | None, _opt("--max-speed", "Largest plausible speed [m/s] (aircraft tuning 600, paper 5000).")
    ] = None
    max_accel: Annotated[
        float | None, _opt("--max-accel", "Largest plausible acceleration [m/s²] (100).")
    ] = None

    def refuse(self) -> None:
        """Without FILE these options are usage errors (the paper's scenario has no frame or feed)."""
        for name in ("origin", "sensor", "max_gap"):
            if getattr(self, name) is not None:
                raise typer.BadParameter(
                    "describes a record; give FILE", param_hint="--" + name.replace("_", "-")
                )

    def read_options(self, record: RecordOptions, T: float | None) -> Any:
        from motionsig_cli.maneuver.record import ReadOptions
        from motionsig_cli.surveillance.report_hygiene import HygienePolicy

        def point(opt: str, text: str | None) -> tuple[float, ...] | None:
            return (
                None if text is None else tuple(common.checked(opt, common.float_list, text, what="LAT,LON"))
            )

        return ReadOptions(columns=record.columns, units=record.units, T=T,
                           origin=point("--origin", self.origin), sensor=point("--sensor", self.sensor),
                           bearing_convention=self.bearing_convention.value,
                           hygiene=HygienePolicy(strict=self.strict, stale=self.stale.value,
                                                 max_gap=self.max_gap))  # fmt: skip

    def checks(self, cfg: exp.TrackerConfig) -> Any:
        from motionsig_cli.filters.consistency import Consistency

        if self.consistency is OnOff.off:
            return None
        return Consistency(max_speed=cfg.max_speed if self.max_speed is None else self.max_speed,
                           max_accel=cfg.max_accel if self.max_accel is None else self.max_accel)  # fmt: skip


@dataclass(frozen=True)
class RadarOptions:
    """The EBPSK radar of ``--front-end ebpsk`` (None: the radar modules' defaults)."""

    level: LevelOpt = None
    radar_position: RadarPositionOpt = None
    p_t: PtOpt = None
    gain_db: GainOpt = None
    rcs: RcsOpt = None
    loss_db: LossOpt = None
    noise_figure_db: NoiseFigureOpt = None
    n_pulses: PulsesOpt = None
    pfa: PfaOpt = None
    pri: PriOpt = None
    beamwidth: BeamwidthOpt = None
    nodes: NodesOpt = None

    def refuse(self) -> None:
        """Without --front-end ebpsk, a radar option is a usage error."""
        for name in given(self):
            raise typer.BadParameter(
                "sets the EBPSK radar; give --front-end ebpsk", param_hint="--" + name.replace("_", "-")
            )


@command(parallel=True, options=OPTIONS)
@options(record=RecordOptions, tracker=TrackerOptions, radar=RadarOptions, real=RealRecordOptions)
def maneuver(
    record: RecordOptions,
    method: MethodOpt = "imm",
    sigma: SigmaOpt = None,
    preset: PresetOpt = Preset.literal,
    T: TOpt = None,
    scans: ScansOpt = 450,
    runs: RunsOpt = 500,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    tracker: TrackerOptions = TrackerOptions(),
    response: ResponseOpt = 30,
    view: ViewOpt = View.scans,
    plot_compare: PlotCompareOpt = None,
    front_end: FrontEndOpt = FrontEnd.gaussian,
    radar: RadarOptions = RadarOptions(),
    real: RealRecordOptions = RealRecordOptions(),
    *,
    output: Output,
    parallel: Parallel,
) -> None:
    """Maneuvering-target tracking: IMM of three Kalman filters, GLR and MLR maneuver detection.

    After Yao, Teng & Wu, Maneuvering Target Tracking Based on EBPSK Modulated JRC System. IMM = interacting
    multiple model filter; GLR / MLR = generalised / marginalised likelihood ratio; CV = constant velocity.

    FILE: track one record instead of simulating: CSV or JSON with time (t, timestamp: seconds or ISO 8601)
    and/or scan, and x, y [m], or latitude, longitude [deg] (altitude), or range, bearing from --sensor
    (unit suffixes such as range_nm, bearing_deg read as units); '-' for stdin. Rows are sorted, duplicates
    and stale repeats dropped, gaps end a segment; each step uses its own time (irregular reports are fine).
    Every tracker checks its consistency and restarts (and says so) rather than diverge. --view events lists
    the declared manoeuvres of every method (the IMM declares too).

    \b
    Example:
      motionsig maneuver --runs 100 --plot figs.png                  # Figs 2-4 and the IMM probabilities
      motionsig maneuver --method all --view summary --plot-compare cmp.png
      motionsig maneuver --view measurements --runs 1 --sigma 100 | motionsig maneuver - --method glr
      motionsig maneuver export.csv --columns x=East,y=North --units x=km,y=km --plot track.png
      motionsig maneuver adsb.csv --method all --view events        # latitude/longitude, ISO times
      motionsig maneuver plots.csv --sensor 51.40,-3.34,50           # range_nm, bearing_deg plots
      motionsig maneuver --runs 5000 --method all --workers 8 --checkpoint ckpt/   # resumable if interrupted
      motionsig maneuver --front-end ebpsk --method all --view summary   # on the EBPSK radar's positions
      motionsig maneuver --front-end ebpsk --view front-end --plot sigma.png
      motionsig maneuver --front-end ebpsk --view network --runs 100   # several nodes ranging the target

    --workers, --scheduler and --checkpoint apply to the Monte Carlo views (scans, events, summary) and to
    FILE (its tracks, in tasks of whole tracks); the measurements view runs no Monte Carlo and ignores them.
    """
    from motionsig_cli.maneuver import study as exp

    output.check(plot_compare=plot_compare)
    engine = parallel.engine()
    methods = _methods(method, exp.METHODS)
    if front_end is FrontEnd.gaussian:
        radar.refuse()
        if view in (View.front_end, View.network):
            raise typer.BadParameter(
                "tabulates the EBPSK front end; give --front-end ebpsk", param_hint="--view"
            )
    path = record.path
    if path is not None:
        if front_end is not FrontEnd.gaussian:
            raise typer.BadParameter(
                "with a record (FILE) the record holds the measurements", param_hint="--front-end"
            )
        _track_record(path, methods, tracker, sigma, T, record, real, view, plot_compare, output, engine)
        return
    record.refuse_without_file()
    real.refuse()
    cfg = tracker.config(real.tuning.value if real.tuning is not None else "paper")
    if sigma is not None and sigma.strip().lower() == "estimate":
        raise typer.BadParameter("'estimate' estimates σ from a record (FILE)", param_hint="--sigma")
    sigmas = (
        (100.0, 200.0) if sigma is None else common.checked("--sigma", common.float_list, sigma, what="σ")
    )
    sc = exp.ManeuverScenario(preset=preset.value, T=1.0 if T is None else T, scans=scans)
    source: Any = "gaussian"
    if front_end is FrontEnd.ebpsk:
        if radar.nodes is not None and view is not View.network:
            raise typer.BadParameter("places the nodes of --view network", param_hint="--nodes")
        fe = _front_end(sc, radar)
        if view is View.network:
            _network_view(sc, fe, sigmas, radar, runs, seed, output)
            return
        if view is View.front_end:
            _front_end_view(sc, fe, sigmas, radar.p_t is None, output)
            return
        source, sigmas = _ebpsk_source(sc, fe, sigma, radar.p_t, sigmas)
    job = exp.ManeuverJob(sc, tuple(dict.fromkeys(sigmas)), runs, seed, methods, cfg, quiet_fp=True,
                          source=source)  # fmt: skip
    _monte_carlo(job, view, response, methods, plot_compare, engine, output)


def _monte_carlo(
    job: exp.ManeuverJob, view: View, response: int, methods: tuple[str, ...], plot_compare: Path | None,
    engine: Engine, output: Output,
) -> None:  # fmt: skip
    """The Monte Carlo views (scans, events, summary) and the measurements view of ``job``."""
    from motionsig_cli.maneuver import study as exp

    if view is View.measurements:
        for name, path in (("--plot", output.plot), ("--plot-compare", plot_compare)):
            if path is not None:
                raise typer.BadParameter("the measurements view draws no figure", param_hint=name)
        output.emit(exp.measurement_table(job))
        return
    if plot_compare is not None and len(methods) < 2:
        raise typer.BadParameter(
            "needs at least two methods (e.g. --method all)", param_hint="--plot-compare"
        )
    study = exp.ManeuverStudy(job, view.value, response)
    report = exp.report(study, common.run_job(job, engine, "maneuver", output.quiet))
    if output.plot is not None or plot_compare is not None:
        from motionsig_cli.plotting import maneuver_comparison_figure, maneuver_figure

        if output.plot is not None:
            output.figure(maneuver_figure(**report.track_figure))
        if plot_compare is not None:
            output.figure(maneuver_comparison_figure(**report.compare_figure), plot_compare)
    output.emit(report.table)  # after the figures: all or nothing
    output.note(f"maneuver: {report.note}")


def _front_end(sc: exp.ManeuverScenario, radar: RadarOptions) -> Any:
    """The EBPSK front end of the options (defaults: those of the radar modules), checked against the track."""
    from motionsig_cli.config import in_range
    from motionsig_cli.maneuver import ebpsk_radar as er
    from motionsig_cli.maneuver import ebpsk_tracking as et
    from motionsig_cli.models.radar_equation import RadarEquation

    values = given(radar)
    eq_args = {k: values[k] for k in ("p_t", "rcs", "loss_db", "noise_figure_db", "n_pulses") if k in values}
    if radar.gain_db is not None:
        eq_args |= {"g_t_db": radar.gain_db, "g_r_db": radar.gain_db}
    radar_args: dict[str, Any] = {k: values[k] for k in ("pfa", "pri") if k in values}
    if (beamwidth := radar.beamwidth) is not None:
        radar_args["beamwidth"] = math.radians(in_range("beamwidth", beamwidth, 0.0, 180.0, lo_open=True,
                                                        hi_open=True, unit="°"))  # fmt: skip
    position = et.DEFAULT_RADAR_POSITION
    if (radar_position := radar.radar_position) is not None:
        vals = common.checked("--radar-position", common.float_list, radar_position, what="coordinate")
        if len(vals) != 2:
            raise typer.BadParameter(f"give x,y [m]; got {radar_position!r}", param_hint="--radar-position")
        position = (vals[0], vals[1])
    config = er.EbpskRadarConfig(radar=RadarEquation(**eq_args), **radar_args)
    level = "detector" if radar.level is None else radar.level.value
    fe = et.EbpskFrontEnd(radar=config, position=position, level=level)
    fe.check_track(sc.truth())
    return fe.prepared(sc.truth())


def _ebpsk_source(
    sc: exp.ManeuverScenario, fe: Any, sigma: str | None, p_t: float | None, sigmas: Any
) -> tuple[Any, tuple[float, ...]]:
    """The ebpsk source: P_t calibrated to each --sigma (the median position σ along the track), or the radar
    as given by --p-t (its median σ is then the table's σ)."""
    from motionsig_cli.maneuver import ebpsk_tracking as et

    if p_t is None:
        for s in sigmas:
            fe.calibrated(sc.truth(), s)  # a σ no power reaches: an error naming --sigma, before any run
        return et.EbpskPositions(fe, calibrate=True), tuple(sigmas)
    if sigma is not None:
        raise typer.BadParameter(
            "sets the EBPSK transmit power (median position σ along the track); with --p-t leave it out",
            param_hint="--sigma",
        )
    import numpy as np

    med = float(np.median(fe.scans(sc.truth()).sigma_pos))
    return et.EbpskPositions(fe, calibrate=False), (med,)


def _front_end_view(sc: exp.ManeuverScenario, fe: Any, sigmas: Any, calibrate: bool, output: Output) -> None:
    """``--view front-end``: per phase, what the front end delivers (at --p-t, else at the power that makes
    the median position σ the first --sigma) and the power that would give each σ."""
    import numpy as np

    from motionsig_cli.maneuver import ebpsk_tracking as et

    if calibrate:
        fe = fe.calibrated(sc.truth(), sigmas[0])
    table = et.front_end_table(sc, fe, sigmas)
    table.meta["front_end"]["p_t_W"] = fe.p_t
    table.meta["p_t"] = (
        f"set so that the median position σ along the track is {sigmas[0]:g} m" if calibrate else "--p-t"
    )
    if output.plot is not None:
        from motionsig_cli.plotting import ebpsk_front_end_figure

        output.figure(ebpsk_front_end_figure(**et.front_end_figure_data(sc, fe, sigmas)))
    output.emit(table)
    r = table.rows[-1]
    med = float(np.median(fe.scans(sc.truth()).sigma_pos))
    output.note(
        f"maneuver: front end at P_t = {fe.p_t:.3g} W: median position σ {med:.0f} m, mean P_D {r[6]:.3f}"
    )


def _track_record(
    path: str, methods: tuple[str, ...], tracker: TrackerOptions, sigma: str | None, T: float | None,
    record: RecordOptions, real: RealRecordOptions, view: View, plot_compare: Path | None, output: Output,
    engine: Engine,
) -> None:  # fmt: skip
    """Track one measurement record with every requested method (and draw it with --plot). The default
    tuning is ``aircraft``, or ``paper`` for the paper's own simulated records (``--view measurements``)."""
    from motionsig_cli.maneuver import record as mr
    from motionsig_cli.maneuver import record_tracking as rt

    if view not in (View.scans, View.events):
        raise typer.BadParameter(
            "with a record (FILE) the output is the per-step track (scans) or its declarations (events)",
            param_hint="--view",
        )
    if plot_compare is not None:
        raise typer.BadParameter(
            "compares Monte Carlo runs; with a record (FILE), --plot draws the record's tracks",
            param_hint="--plot-compare",
        )
    output.refuse_input(path, "the input file")
    s: float | str | None = None
    if sigma is not None and sigma.strip().lower() == "estimate":
        s = "estimate"
    elif sigma is not None:
        vals = common.checked("--sigma", common.float_list, sigma, what="σ")
        if len(vals) != 1:
            raise typer.BadParameter("give one σ with a record (FILE) (or 'estimate')", param_hint="--sigma")
        s = vals[0]
    tracks = mr.read_track_records(path, real.read_options(record, T))
    meta = tracks.record.meta
    own = meta.get("command") == "maneuver" and meta.get("view") == "measurements"
    cfg = tracker.config(real.tuning.value if real.tuning is not None else ("paper" if own else "aircraft"))
    if output.plot is not None and len(tracks.tracks) > 1:
        raise typer.BadParameter(
            f"draws one track; the record holds {len(tracks.tracks)}", param_hint="--plot"
        )
    plan = rt.plan_tracking(tracks, methods, cfg, sigma=s, consistency=real.checks(cfg))
    del tracks  # the plan holds the tracks
    spool = view is View.scans and output.fmt.value == "csv"
    with contextlib.ExitStack() as stack:
        if spool:  # rows to files as tasks finish, then joined into --out: a feed's output is never held whole
            from motionsig_cli.cli.io import emit_spooled
            from motionsig_cli.engine import job_trials

            where = stack.enter_context(tempfile.TemporaryDirectory(prefix="motionsig-maneuver-"))
            with common.engine_session(engine, job_trials(rt.RecordJob(plan)), "maneuver", output.quiet) as advance:
                result, bodies = rt.track_records_to_files(plan, engine, Path(where), progress=advance)
        else:
            result = common.run_job(rt.RecordJob(plan), engine, "maneuver", output.quiet)
        if output.plot is not None:
            from motionsig_cli.plotting import maneuver_record_figure

            output.figure(maneuver_record_figure(**result.figure))
        if spool:  # after the figure: all or nothing
            emit_spooled(result.table, bodies, output.out)
        else:
            output.emit(result.events if view is View.events else result.table)
    if result.sigma_estimated:
        output.note(
            f"maneuver: no σ given (--sigma) or in the record's metadata: estimated σ = "
            f"{result.table.meta['sigma']:.4g} m from the positions (deviations of measured triples)"
        )
    output.note(f"maneuver: {result.note}")


def _network_view(
    sc: exp.ManeuverScenario, fe: Any, sigmas: Any, radar: RadarOptions, runs: int, seed: int, output: Output
) -> None:
    """``--view network``: several nodes ranging the target, each the radar of ``fe`` (at --p-t, else at the
    power that makes the single radar's median position σ the first --sigma), beside the single radar."""
    from motionsig_cli.maneuver import ebpsk_network as en

    if output.plot is not None:
        raise typer.BadParameter("the network view draws no figure", param_hint="--plot")
    nodes = en.DEFAULT_NODES
    if radar.nodes is not None:
        nodes = common.checked("--nodes", _matrix, radar.nodes, what="coordinate")
    calibrate = radar.p_t is None
    if calibrate:
        fe = fe.calibrated(sc.truth(), sigmas[0])
    net = en.NodeNetwork(fe, nodes)
    for node in net.node_front_ends():
        node.check_track(sc.truth())
    table = en.network_table(sc, net, runs, seed)
    table.meta["p_t"] = (
        f"set so that the single radar's median position σ along the track is {sigmas[0]:g} m"
        if calibrate
        else "--p-t"
    )
    output.emit(table)
    r = table.rows[-1]
    c = table.columns
    output.note(
        f"maneuver: {len(net.nodes)} nodes at P_t = {fe.p_t:.3g} W each: RMS position error "
        f"{r[c.index('rms_pos_m')]:.3g} ± {r[c.index('rms_pos_se_m')]:.1g} m per axis on "
        f"{r[c.index('fix_rate')]:.0%} of the scans; the single radar's median σ {r[-1]:.0f} m"
    )
