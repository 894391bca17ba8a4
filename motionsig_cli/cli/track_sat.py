"""``motionsig track-sat``: aircraft position by satellite multilateration with a model of the
transmitter's clock, after ATC-10 (Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972), §4 and
Apps G–H: Tables 4.1–4.3, Figs 4.1–4.3.

``--convention corrected`` (default): exact speed of light, geosynchronous orbit radius and the
frame-independent three-satellite constant 1'(UU')⁻¹1. ``--convention report``: c = 1 ft/ns,
r_sat = 9.235 Earth radii and the printed (frame-dependent) constant — this reproduces Tables 4.2/4.3.
Every output records its convention and where its constellation constants came from.

The commands parse their options into the configurations of
:mod:`motionsig_cli.experiments.satellite_tracking`, which check every field, and write what its
``*_report`` functions return.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import DEFAULT_SEED_VALUE, Output, Parallel, SeedOpt, choices, command

if TYPE_CHECKING:
    from motionsig_cli.experiments.satellite_tracking import Constellation, Orbit, Report

app = typer.Typer(
    help="Satellite multilateration with clock tracking (ATC-10 §4): constellation constants, "
    "Tables 4.2/4.3, ψ(α) (Fig 4.1), RMS error curves (Figs 4.2/4.3) and a Monte Carlo of the estimators.",
    no_args_is_help=True,
)


Example = choices("Example", "The report's two constellations (Table 4.1).", "I", "II")
Convention = choices(
    "Convention", "Which speed of light, orbit radius and three-satellite constant.", "corrected", "report"
)
Params = choices(
    "Params",
    "Source of β, tr, b: auto (report → printed Table 4.2; corrected → Table 4.1 geometry).",
    "auto",
    "table",
    "geometry",
)
TableConvention = choices(
    "TableConvention", "Which convention(s) a table shows.", "both", "corrected", "report"
)
WhichTable = choices("WhichTable", "Which table of §4.6.", t42="4.2", t43="4.3")
View = choices(
    "View",
    "Constellation output: one row per satellite subset, or one per satellite.",
    "summary",
    "satellites",
)
Gain = choices(
    "Gain",
    "Clock gain: the exact recursive γ_n, or the constant steady-state ψ(α)/β from n = 1.",
    "recursive",
    "steady",
)
Figure4 = choices("Figure4", "Figure presets: 4.2 = Example I, 4.3 = Example II.", f42="4.2", f43="4.3")


SAT_FIELDS = {
    "lat_deg": "--sats",
    "lon_deg": "--sats",
    "labels": "--sats",
    "triplet": "--outage-sats",
    "r_sat_km": "--rsat-km",
}
"""Option names of the constellation's fields."""

ExampleOpt = Annotated[
    Example, typer.Option("--example", help="Constellation of Table 4.1 (I: 7, II: 8 satellites).")
]
ConventionOpt = Annotated[
    Convention,
    typer.Option(
        "--convention",
        help="corrected: exact c, geosynchronous radius, b3 = 1'(UU')^-1 1; report: c = 1 ft/ns, "
        "9.235 Earth radii, the printed b3 (reproduces Tables 4.2/4.3).",
    ),
]
RadiusConventionOpt = Annotated[
    Convention,
    typer.Option(
        "--convention",
        help="Sets the default orbit radius: report 9.235 Earth radii, corrected geosynchronous "
        "(both b = 1'U(U'U)^-2 U'1 and the report's literal 1'(U'U)^-1 1 are always listed).",
    ),
]
ParamsOpt = Annotated[
    Params,
    typer.Option(
        "--params",
        help="Constellation constants: table = printed Table 4.2 (corrected: with the correct b3); "
        "geometry = from Table 4.1; auto = table for report, geometry for corrected.",
    ),
]
RsatReOpt = Annotated[
    float | None,
    typer.Option(
        "--rsat-re",
        help="Orbit radius in Earth radii (default by --convention: report 9.235, corrected geosynchronous 6.61).",
    ),
]
RsatKmOpt = Annotated[
    float | None, typer.Option("--rsat-km", help="Orbit radius in km (instead of --rsat-re).")
]
SimRsatReOpt = Annotated[
    float | None, typer.Option("--rsat-re", help="Orbit radius in Earth radii (default geosynchronous).")
]
SigmaOpt = Annotated[
    float,
    typer.Option("--sigma", help="Time-of-arrival (TOA) error σ per satellite [ns] (report: 50)."),
]
EpochsOpt = Annotated[int, typer.Option("--epochs", help="Last update n (updates once per second).")]
OutageStartOpt = Annotated[
    int,
    typer.Option(
        "--outage-start",
        help="N: last update with all satellites (assumed: 100; the report does not state it).",
    ),
]
OutageLenOpt = Annotated[
    int,
    typer.Option(
        "--outage-length",
        help="M: updates with the --outage-sats triplet only (assumed: 60; the report does not state it).",
    ),
]
ReinitOpt = Annotated[
    bool,
    typer.Option(
        "--reinit-after-outage",
        help="Restart by least squares after the outage (the report); default continue.",
    ),
]
GainOpt = Annotated[Gain, typer.Option("--gain", help="recursive γ_n (exact) or steady ψ/β from n = 1.")]
OutageSatsOpt = Annotated[
    str,
    typer.Option(
        "--outage-sats", help="The three satellites kept in the outage (1-based; Table 4.1: 1,2,3)."
    ),
]


def _user_sats(path: Path) -> tuple[tuple[float, ...], tuple[float, ...], tuple[str, ...]]:
    """Satellites from a CSV with latitude_deg, longitude_deg (and optionally satellite) columns. A bad
    point, or one that repeats an earlier one, is an error naming the file and line; the constellation
    checks the rest (count, labels)."""
    from motionsig_cli.cli.io import InputError, read_table
    from motionsig_cli.experiments.satellite_tracking import MAX_LON_DEG

    t = read_table(path, required=("latitude_deg", "longitude_deg"))
    lat, lon = t.numeric("latitude_deg"), t.numeric("longitude_deg")
    seen: dict[tuple[float, float], int] = {}
    for i, (a, b) in enumerate(zip(lat, lon, strict=True)):
        where = f"{t.source}:{t.lines[i]}"
        if not (math.isfinite(a) and -90.0 <= a <= 90.0):
            raise InputError(f"{where}: latitude {float(a):g} is outside [-90, 90] degrees")
        if not (math.isfinite(b) and -MAX_LON_DEG <= b <= MAX_LON_DEG):
            raise InputError(
                f"{where}: longitude {float(b):g} is not in [-{MAX_LON_DEG:g}, {MAX_LON_DEG:g}] degrees"
            )
        key = (float(a), float(b) % 360.0)
        if key in seen:
            raise InputError(f"{where}: the same sub-satellite point as line {seen[key]}")
        seen[key] = t.lines[i]
    labels = tuple(str(v) for v in t.column("satellite")) if "satellite" in t.columns else ()
    return tuple(map(float, lat)), tuple(map(float, lon)), labels


def _constellation(
    example: Example, orbit: Orbit, outage_sats: str, *, sats: Path | None = None, aircraft: str | None = None
) -> Constellation:
    """The constellation of the options (Table 4.1 or ``--sats``; the configuration checks the values)."""
    from motionsig_cli.experiments import satellite_tracking as exp

    if sats is not None:
        lat, lon, labels = _user_sats(sats)
        name = str(sats)
    else:
        lat, lon = exp.table_4_1()[example.value]
        labels, name = (), f"Example {example.value} (Table 4.1)"
    ac: tuple[float, ...] = (45.0, 120.0, 0.0)
    if aircraft is not None:
        vals = common.checked(
            "--aircraft", common.float_list, aircraft, what="latitude,longitude[,altitude km]"
        )
        ac = (*vals, 0.0) if len(vals) == 2 else tuple(vals)
    triplet = tuple(
        i - 1
        for part in outage_sats.split(",")
        for i in common.checked("--outage-sats", common.int_list, part, what="satellite number")
    )
    return exp.Constellation(lat, lon, orbit.km, ac, triplet, labels, name)  # type: ignore[arg-type]


def _observable(con: Constellation, *, sats: bool = False, aircraft: bool = False) -> list[str]:
    """Observability errors, each naming the option most likely to blame; the warnings are returned."""
    common.checked("--aircraft" if aircraft else "--rsat-km/--rsat-re", con.check_horizon)
    common.checked("--sats" if sats else "--example", con.check_all)
    common.checked("--outage-sats", con.check_triplet)
    return con.warnings()


def _warn(output: Output, warnings: list[str]) -> None:
    if warnings:
        output.note("track-sat: warning: " + "; ".join(warnings))


def _write(output: Output, report: Report, figure: str | None = None) -> None:
    """Emit the table, draw the figure (a function of :mod:`motionsig_cli.plotting`) when asked, and
    print the summary."""
    output.emit(report.table)
    if figure is not None and output.plot is not None:
        from motionsig_cli import plotting

        output.figure(getattr(plotting, figure)(**report.figure))
    output.note(report.summary)


@app.command()
@command(plot=False, options=SAT_FIELDS)
def constellation(
    example: ExampleOpt = Example.I,
    sats: Annotated[
        Path | None,
        typer.Option(
            "--sats", help="CSV of sub-satellite points (latitude_deg, longitude_deg[, satellite]) instead."
        ),
    ] = None,
    aircraft: Annotated[
        str | None,
        typer.Option("--aircraft", help="Aircraft latitude,longitude[,altitude km] (default 45,120,0)."),
    ] = None,
    outage_sats: OutageSatsOpt = "1,2,3",
    convention: RadiusConventionOpt = Convention.corrected,
    rsat_re: RsatReOpt = None,
    rsat_km: RsatKmOpt = None,
    view: Annotated[
        View, typer.Option("--view", help="summary (per subset) or satellites (per satellite).")
    ] = View.summary,
    *,
    output: Output,
) -> None:
    """Constellation constants (c = 1 units): β, tr{(U'U)⁻¹}, 1'U(U'U)⁻²U'1, the report's literal
    1'(U'U)⁻¹1, the geometric dilution of precision (GDOP) and zenith angles, for all satellites and for
    the outage triplet.

    \b
    Example:
      motionsig track-sat constellation --example I --convention report   # Table 4.2 from Table 4.1
      motionsig track-sat constellation --sats my_sats.csv --aircraft 40,-100,10 --view satellites
    """
    from motionsig_cli.experiments import satellite_tracking as exp

    output.check()
    conv = exp.Convention(convention)
    con = _constellation(
        example, exp.Orbit(conv, rsat_re, rsat_km), outage_sats, sats=sats, aircraft=aircraft
    )
    _warn(output, _observable(con, sats=sats is not None, aircraft=aircraft is not None))
    _write(output, exp.constellation_report(con, view=view.value, convention=conv))


@app.command()
@command(plot=False)
def table(
    which: Annotated[
        WhichTable, typer.Option("--which", help="Table 4.2 (constellation) or 4.3 (estimation).")
    ] = WhichTable.t43,
    convention: Annotated[
        TableConvention, typer.Option("--convention", help="Table 4.3: rows for both conventions, or one.")
    ] = TableConvention.both,
    params: ParamsOpt = Params.auto,
    *,
    output: Output,
) -> None:
    """Tables 4.2 and 4.3 recomputed beside the printed values, with the deviation (%), the tolerance and
    a status per value.

    \b
    Example:
      motionsig track-sat table --which 4.2    # printed, report (9.235 R_E), corrected
      motionsig track-sat table                # Table 4.3 in both conventions
    """
    from motionsig_cli.experiments import satellite_tracking as exp

    output.check()
    _write(output, exp.table_report(exp.TableConfig(which.value, convention.value, params.value)))


def _grid(text: str) -> tuple[float, float, int]:
    """``lo:hi:n`` (the configuration checks the values)."""
    parts = text.split(":")
    try:
        if len(parts) != 3:
            raise ValueError
        return float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise typer.BadParameter(f"expected lo:hi:n, got {text!r}", param_hint="--grid") from None


@app.command("psi")
@command()
def psi_cmd(
    alpha: Annotated[str | None, typer.Option("--alpha", help="Comma-separated α values (α ≥ 0).")] = None,
    grid: Annotated[
        str, typer.Option("--grid", help="Log-spaced grid lo:hi:n (α > 0) when --alpha is not given.")
    ] = "1e-6:1e2:161",
    *,
    output: Output,
) -> None:
    """Fig 4.1: ψ(α) (eq 4.5.34, exact root of the cubic) and the report's two approximations.

    \b
    Example:
      motionsig track-sat psi --alpha 1.61e-4,1.61e-2,1.61   # Table 4.3, Example I: 0.0993, 0.4020, 0.9267
      motionsig track-sat psi --plot fig4_1.png
    """
    from motionsig_cli.experiments import satellite_tracking as exp

    output.check()
    if alpha is not None:
        cfg = exp.PsiConfig(alpha=tuple(common.checked("--alpha", common.float_list, alpha, what="alpha")))
    else:
        cfg = exp.PsiConfig(grid=_grid(grid))
    _write(output, exp.psi_report(cfg), "psi_figure")


@app.command()
@command()
def rms(
    figure: Annotated[
        Figure4 | None,
        typer.Option("--figure", help="Preset: 4.2 (Example I) or 4.3 (Example II); overrides --example."),
    ] = None,
    example: ExampleOpt = Example.I,
    sigma0: Annotated[
        str, typer.Option("--sigma0", help="Clock scales σ0 [ns], comma-separated.")
    ] = "5,50,500",
    sigma: SigmaOpt = 50.0,
    epochs: EpochsOpt = 160,
    outage_start: OutageStartOpt = 100,
    outage_length: OutageLenOpt = 60,
    reinit_after_outage: ReinitOpt = False,
    gain: GainOpt = Gain.recursive,
    convention: ConventionOpt = Convention.corrected,
    params: ParamsOpt = Params.auto,
    rsat_re: RsatReOpt = None,
    rsat_km: RsatKmOpt = None,
    *,
    output: Output,
) -> None:
    """Figs 4.2/4.3: root-mean-square (RMS) position error against update n — least squares, tracking
    with all satellites, then the three-satellite outage — by the exact error recursion.

    \b
    Example:
      motionsig track-sat rms --figure 4.3 --convention report --plot fig4_3.png   # as printed
      motionsig track-sat rms --example I --sigma0 5 --outage-length 300 --epochs 400
    """
    from motionsig_cli.experiments import satellite_tracking as exp

    output.check()
    ex = Example.I if figure is Figure4.f42 else Example.II if figure is Figure4.f43 else example
    cfg = exp.RmsConfig(
        example=ex.value,
        sigma0=tuple(common.checked("--sigma0", common.float_list, sigma0, what="sigma0 [ns]")),
        sigma=sigma,
        timeline=exp.Timeline(epochs, outage_start, outage_length, reinit_after_outage),
        steady_gain=gain is Gain.steady,
        convention=exp.Convention(convention),
        params=params.value,
        rsat_re=rsat_re,
        rsat_km=rsat_km,
    )
    con = cfg.geometry()
    if con is not None:
        _warn(output, _observable(con))
    _write(output, exp.rms_report(cfg), "rms_error_figure")


@app.command()
@command(parallel=True, options=SAT_FIELDS)
def simulate(
    example: ExampleOpt = Example.I,
    sigma0: Annotated[float, typer.Option("--sigma0", help="Clock scale σ0 [ns] (σ1 = σ2 = σ0).")] = 50.0,
    sigma: SigmaOpt = 50.0,
    rho: Annotated[
        float,
        typer.Option("--rho", help="True clock's flicker exponent ρ in (1/2, 1] (1: the report's model)."),
    ] = 1.0,
    runs: Annotated[int, typer.Option("--runs", help="Monte Carlo runs.")] = 2000,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    estimators: Annotated[
        str,
        typer.Option(
            "--estimators",
            help="Comma-separated: none (least squares each update), report (the report's tracker), "
            "kf2 (a Kalman filter of clock phase and rate).",
        ),
    ] = "none,report,kf2",
    epochs: EpochsOpt = 160,
    outage_start: OutageStartOpt = 100,
    outage_length: OutageLenOpt = 60,
    reinit_after_outage: Annotated[
        bool,
        typer.Option(
            "--reinit-after-outage",
            help="Restart the report's tracker by least squares after the outage (kf2 continues).",
        ),
    ] = False,
    gain: GainOpt = Gain.recursive,
    velocity_enu: Annotated[
        str, typer.Option("--velocity-enu", help="Aircraft velocity east,north,up [m/s] (default static).")
    ] = "0,0,0",
    outage_sats: OutageSatsOpt = "1,2,3",
    rsat_re: SimRsatReOpt = None,
    rsat_km: RsatKmOpt = None,
    *,
    output: Output,
    parallel: Parallel,
) -> None:
    """Monte Carlo of the estimators on nonlinear time-of-arrival measurements (exact c, Gaussian noise),
    with the analytic recursion beside it: RMS error and its standard error per update.

    \b
    Example:
      motionsig track-sat simulate --example I --sigma0 50 --rsat-re 9.235 --plot mc.png
      motionsig track-sat simulate --example II --rho 0.9 --estimators report,kf2 --outage-length 0 --epochs 300
      motionsig track-sat simulate --runs 20000 --workers 8 --checkpoint ckpt/   # resumable, same result
    """
    from motionsig_cli.experiments import satellite_tracking as exp

    output.check()
    engine = parallel.engine()
    con = _constellation(example, exp.Orbit(exp.Convention.corrected, rsat_re, rsat_km), outage_sats)
    warnings = _observable(con)
    job = exp.TrackSatJob(
        con,
        sigma=sigma,
        sigma0=sigma0,
        rho=rho,
        timeline=exp.Timeline(epochs, outage_start, outage_length, reinit_after_outage),
        estimators=tuple(dict.fromkeys(e.strip() for e in estimators.split(",") if e.strip())),
        velocity_enu=tuple(
            common.checked("--velocity-enu", common.float_list, velocity_enu, what="velocity component [m/s]")
        ),  # type: ignore[arg-type]
        runs=runs,
        seed=seed,
        steady_gain=gain is Gain.steady,
    )
    _warn(output, warnings)
    result = common.run_job(job, engine, "track-sat simulate", output.quiet)
    _write(output, exp.simulation_report(job, result, example=example.value), "rms_error_figure")
