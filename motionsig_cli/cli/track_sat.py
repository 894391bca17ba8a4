"""``motionsig track-sat``: aircraft position by satellite multilateration with a model of the
transmitter's clock, after ATC-10 (Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972), §4 and
Apps G–H: Tables 4.1–4.3, Figs 4.1–4.3.

``--convention corrected`` (default): exact speed of light, geosynchronous orbit radius and the
frame-independent three-satellite constant 1'(UU')⁻¹1. ``--convention report``: c = 1 ft/ns,
r_sat = 9.235 Earth radii and the printed (frame-dependent) constant — this reproduces Tables 4.2/4.3.
Every output records its convention and where its constellation constants came from.

``--receivers FILE`` (constellation, rms, simulate) takes any receiver geometry instead of Table 4.1: ground
stations or satellites in ECEF metres or WGS-84 latitude, longitude, altitude, or sub-satellite points in
the report's form (latitude, longitude on the orbit radius of ``--rsat-km``/``--rsat-re``); positions may
change from epoch to epoch for simulate. Columns carry their unit: ``--units report`` (feet, nanoseconds,
positions in km: the default for Table 4.1 and ``--sats``) or ``--units si`` (metres, seconds: the default
with ``--receivers``).

The commands parse their options into the configurations of
:mod:`motionsig_cli.atc10.satellite_tracking`, which check every field, and write what its
``*_report`` functions return.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import DEFAULT_SEED_VALUE, Output, Parallel, SeedOpt, choices, command

if TYPE_CHECKING:
    from motionsig_cli.atc10.satellite_tracking import Constellation, Geometry, Orbit, Report

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
RECEIVER_FIELDS = {
    "positions_m": "--receivers",
    "times_s": "--receivers",
    "constellation": "--receivers",
    "triplet": "--outage-sats",
    "r_sat_km": "--rsat-km",
    "multi_epoch": "--receivers",
    "min_receivers": "--receivers",
    "sphere_radius_m": "--rsat-km",
}
"""Option names of the fields of a receiver geometry and of the receivers reader."""

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
ReceiversOpt = Annotated[
    Path | None,
    typer.Option(
        "--receivers",
        help="A receivers table (CSV or the JSON the commands write) instead of Table 4.1: receiver, and "
        "x, y, z [m] (ECEF) or latitude, longitude [deg], altitude [m] (WGS-84), or latitude, longitude "
        "alone (the report's form: sub-satellite points on the orbit radius of --rsat-km/--rsat-re); "
        "optionally epoch or time for positions that change (simulate). Outputs default to SI units.",
    ),
]
ColumnsOpt = Annotated[
    str | None,
    typer.Option(
        "--columns",
        help="The receivers table's columns: role=name,... (roles receiver, x, y, z, latitude, longitude, "
        "altitude, epoch, time).",
    ),
]
UnitsOpt = Annotated[
    str | None,
    typer.Option(
        "--units",
        help="Columns in report units (ft, ns; positions and ranges in km) or si (m, s); default report, si "
        "with --receivers. role=unit entries give the receivers table's units (e.g. si,x=km,y=km,z=km).",
    ),
]
AircraftOpt = Annotated[
    str | None,
    typer.Option(
        "--aircraft",
        help="Aircraft latitude,longitude[,altitude km] (default 45,120,0; WGS-84 geodetic with --receivers "
        "in ECEF or WGS-84 form).",
    ),
]
TableUnits = choices("TableUnits", "The columns' units: the report's (ft, ns) or SI (m, s).", "report", "si")


def _user_sats(path: Path) -> tuple[tuple[float, ...], tuple[float, ...], tuple[str, ...]]:
    """Satellites from a CSV with latitude_deg, longitude_deg (and optionally satellite) columns. A bad
    point, or one that repeats an earlier one, is an error naming the file and line; the constellation
    checks the rest (count, labels)."""
    from motionsig_cli.atc10.satellite_tracking import MAX_LON_DEG
    from motionsig_cli.cli.io import InputError, read_table

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


def _aircraft(text: str | None) -> tuple[float, ...]:
    """``--aircraft lat,lon[,alt km]`` (default 45, 120, 0; the geometry checks the values)."""
    if text is None:
        return (45.0, 120.0, 0.0)
    vals = common.checked("--aircraft", common.float_list, text, what="latitude,longitude[,altitude km]")
    return (*vals, 0.0) if len(vals) == 2 else tuple(vals)


def _triplet(text: str, labels: Sequence[str] = ()) -> tuple[int, ...]:
    """``--outage-sats``: 1-based numbers, or (with a receivers table) the receivers' labels; the geometry
    checks that they are three distinct receivers."""
    out: list[int] = []
    for part in text.split(","):
        if labels and part.strip() in labels:
            out.append(list(labels).index(part.strip()))
            continue
        what = "satellite number" if not labels else "receiver label or number"
        out.extend(i - 1 for i in common.checked("--outage-sats", common.int_list, part, what=what))
    return tuple(out)


def _units(text: str | None, receivers: Path | None) -> tuple[str, dict[str, str]]:
    """``--units``: the columns' units (report or si; default report, si with a receivers table) and the
    receivers table's own units (role=unit entries)."""
    chosen: list[str] = []
    table: dict[str, str] = {}
    for entry in (e.strip() for e in (text or "").split(",")):
        if not entry:
            continue
        role, sep, unit = entry.partition("=")
        if not sep:
            if entry.lower() not in ("report", "si"):
                raise typer.BadParameter(
                    f"{entry!r} is neither report nor si (nor a receivers column's role=unit)",
                    param_hint="--units",
                )
            chosen.append(entry.lower())
        else:
            table[role.strip()] = unit.strip()
    if len(set(chosen)) > 1:
        raise typer.BadParameter("gives both report and si", param_hint="--units")
    if table and receivers is None:
        raise typer.BadParameter(
            f"{', '.join(f'{k}={v}' for k, v in table.items())}: a receivers table's units; give --receivers",
            param_hint="--units",
        )
    return (chosen[0] if chosen else "si" if receivers is not None else "report"), table


def _receivers(
    path: Path,
    orbit: Orbit,
    *,
    columns: str | None,
    units: dict[str, str],
    aircraft: str | None,
    outage_sats: str,
    radius_given: bool,
    one_epoch: bool,
) -> Geometry:
    """The geometry of a receivers table: the report's form (latitude, longitude without an altitude, on the
    orbit radius) as a :class:`Constellation`, exactly as ``--sats``; ECEF or WGS-84 positions as a
    :class:`ReceiverGeometry`. ``one_epoch``: refuse a table of several epochs (constellation, rms). A
    table of three receivers fixes no position without the clock: it is refused where the command needs
    a snapshot fix."""
    import numpy as np

    from motionsig_cli.atc10 import satellite_tracking as exp
    from motionsig_cli.atc10.receivers import read_receivers
    from motionsig_cli.errors import InputError

    rx = read_receivers(
        path,
        columns=columns,
        units=units or None,
        multi_epoch="refuse" if one_epoch else "allow",
        min_receivers=3,
        sphere_radius_m=orbit.km * 1e3,
    )
    triplet = _triplet(outage_sats, rx.ids)
    if rx.form != "sphere" and radius_given:
        raise typer.BadParameter(
            f"applies to sub-satellite points (latitude, longitude without an altitude); {rx.source} gives "
            "ECEF or WGS-84 positions",
            param_hint="--rsat-km/--rsat-re",
        )
    if rx.K == 3 and rx.static:
        raise InputError(
            f"{rx.source}: 3 receivers fix a position only when the transmitter's clock is known "
            "(the report's outage case): a snapshot fix and the clock tracker's start need at least 4"
        )
    if rx.form == "sphere":
        if not rx.static:
            second = int(rx.lines[1][rx.lines[1] > 0][0])
            raise InputError(
                f"{rx.source}:{second}: the report's form (sub-satellite points on one orbit radius) is one "
                "geometry; give ECEF x, y, z or WGS-84 latitude, longitude, altitude for receivers that move"
            )
        return exp.Constellation(
            tuple(map(float, rx.lat_deg[0])),
            tuple(map(float, rx.lon_deg[0])),
            orbit.km,
            _aircraft(aircraft),  # type: ignore[arg-type]
            triplet,  # type: ignore[arg-type]
            rx.ids,
            rx.source,
            rx.provenance(),
        )
    if rx.times is not None:
        times = rx.times - rx.times[0]
    elif rx.epochs is not None:
        times = (rx.epochs - rx.epochs[0]).astype(float)  # epoch e at (e - e_0) tau_bar, tau_bar = 1 s
    else:
        times = np.zeros(1)
    return exp.ReceiverGeometry(
        rx.ecef,
        times,
        _aircraft(aircraft),  # type: ignore[arg-type]
        triplet,  # type: ignore[arg-type]
        rx.ids,
        rx.source,
        rx.lines,
        rx.provenance(),
        np.stack([rx.lat_deg, rx.lon_deg, rx.alt_m], axis=-1),
    )


def _geometry(
    receivers: Path | None, example: Example, orbit: Orbit, outage_sats: str, *, columns: str | None,
    units: dict[str, str], aircraft: str | None, one_epoch: bool, sats: Path | None = None,
) -> Geometry:  # fmt: skip
    """The geometry of a --receivers table, else the constellation of Table 4.1 (or --sats)."""
    if receivers is not None:
        return _receivers(receivers, orbit, columns=columns, units=units, aircraft=aircraft,
                          outage_sats=outage_sats, radius_given=orbit.given, one_epoch=one_epoch)  # fmt: skip
    _no_receivers(columns=columns)
    return _constellation(example, orbit, outage_sats, sats=sats, aircraft=aircraft)


def _constellation(
    example: Example, orbit: Orbit, outage_sats: str, *, sats: Path | None = None, aircraft: str | None = None
) -> Constellation:
    """The constellation of the options (Table 4.1 or ``--sats``; the configuration checks the values)."""
    from motionsig_cli.atc10 import satellite_tracking as exp

    if sats is not None:
        lat, lon, labels = _user_sats(sats)
        name = str(sats)
    else:
        lat, lon = exp.table_4_1()[example.value]
        labels, name = (), f"Example {example.value} (Table 4.1)"
    return exp.Constellation(lat, lon, orbit.km, _aircraft(aircraft), _triplet(outage_sats), labels, name)  # type: ignore[arg-type]


def _exclusive(receivers: Path | None, **others: bool) -> None:
    """``--receivers`` replaces the report's constellations: refuse it beside an option that names one."""
    if receivers is None:
        return
    for option, given in others.items():
        if given:
            raise typer.BadParameter(
                f"cannot be given with {option}: both name the constellation", param_hint="--receivers"
            )


def _observable(
    con: Geometry, *, sats: bool = False, aircraft: bool = False, receivers: bool = False
) -> list[str]:
    """Observability errors, each naming the option most likely to blame; the warnings are returned."""
    whole = "--receivers" if receivers else "--sats" if sats else "--example"
    common.checked("--aircraft" if aircraft or receivers else "--rsat-km/--rsat-re", con.check_horizon)
    common.checked(whole, con.check_all)
    common.checked("--outage-sats", con.check_triplet)
    return con.warnings()


def _warn(output: Output, warnings: list[str]) -> None:
    if warnings:
        output.note("track-sat: warning: " + "; ".join(warnings))


def _write(output: Output, report: Report, figure: str | None = None) -> None:
    """Emit the table, draw the figure (a function of :mod:`motionsig_cli.plotting`) when asked, and
    print the summary."""
    if figure is not None and output.plot is not None:  # the figure first: a failed one leaves no table
        from motionsig_cli import plotting

        output.figure(getattr(plotting, figure)(**report.figure))
    output.emit(report.table)
    output.note(report.summary)


def _given(name: str) -> bool:
    """Whether the option of parameter ``name`` was given on the command line (not its default)."""
    from typer._click.core import ParameterSource
    from typer._click.globals import get_current_context

    ctx = get_current_context(silent=True)
    source = ctx.get_parameter_source(name) if ctx is not None else None
    return source is not None and source not in (ParameterSource.DEFAULT, ParameterSource.DEFAULT_MAP)


@app.command()
@command(plot=False, options={**SAT_FIELDS, **RECEIVER_FIELDS})
def constellation(
    example: ExampleOpt = Example.I,
    sats: Annotated[
        Path | None,
        typer.Option(
            "--sats", help="CSV of sub-satellite points (latitude_deg, longitude_deg[, satellite]) instead."
        ),
    ] = None,
    receivers: ReceiversOpt = None,
    columns: ColumnsOpt = None,
    aircraft: AircraftOpt = None,
    outage_sats: OutageSatsOpt = "1,2,3",
    convention: RadiusConventionOpt = Convention.corrected,
    rsat_re: RsatReOpt = None,
    rsat_km: RsatKmOpt = None,
    view: Annotated[
        View, typer.Option("--view", help="summary (per subset) or satellites (per satellite).")
    ] = View.summary,
    units: UnitsOpt = None,
    *,
    output: Output,
) -> None:
    """Constellation constants (c = 1 units): β, tr{(U'U)⁻¹}, 1'U(U'U)⁻²U'1, the report's literal
    1'(U'U)⁻¹1, the geometric dilution of precision (GDOP) and zenith angles, for all satellites and for
    the outage triplet — of Table 4.1, or of any receivers (--receivers: one epoch, at least 4 receivers).

    \b
    Example:
      motionsig track-sat constellation --example I --convention report   # Table 4.2 from Table 4.1
      motionsig track-sat constellation --sats my_sats.csv --aircraft 40,-100,10 --view satellites
      motionsig track-sat constellation --receivers stations.csv --aircraft 48.35,11.79,3 --view satellites
    """
    from motionsig_cli.atc10 import satellite_tracking as exp

    output.check()
    _exclusive(receivers, **{"--sats": sats is not None, "--example": _given("example")})
    col_units, file_units = _units(units, receivers)
    conv = exp.Convention(convention)
    orbit = exp.Orbit(conv, rsat_re, rsat_km)
    con = _geometry(receivers, example, orbit, outage_sats, columns=columns, units=file_units, aircraft=aircraft,
                    one_epoch=True, sats=sats)  # fmt: skip
    warnings = _observable(
        con, sats=sats is not None, aircraft=aircraft is not None, receivers=receivers is not None
    )
    _warn(output, warnings)
    _write(output, exp.constellation_report(con, view=view.value, convention=conv, units=col_units))


def _no_receivers(**options: str | None) -> None:
    """Options that only apply to a receivers table."""
    for name, value in options.items():
        if value is not None:
            raise typer.BadParameter(
                "applies to a --receivers table", param_hint="--" + name.replace("_", "-")
            )


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
    units: Annotated[
        TableUnits,
        typer.Option(
            "--units", help="Table 4.3 in the report's ft and ns, or in m and s (Table 4.2 has no unit)."
        ),
    ] = TableUnits.report,
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
    from motionsig_cli.atc10 import satellite_tracking as exp

    output.check()
    _write(
        output,
        exp.table_report(exp.TableConfig(which.value, convention.value, params.value), units=units.value),
    )


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
    units: Annotated[
        TableUnits, typer.Option("--units", help="Accepted for uniformity: α and ψ have no unit.")
    ] = TableUnits.report,
    *,
    output: Output,
) -> None:
    """Fig 4.1: ψ(α) (eq 4.5.34, exact root of the cubic) and the report's two approximations.

    \b
    Example:
      motionsig track-sat psi --alpha 1.61e-4,1.61e-2,1.61   # Table 4.3, Example I: 0.0993, 0.4020, 0.9267
      motionsig track-sat psi --plot fig4_1.png
    """
    from motionsig_cli.atc10 import satellite_tracking as exp

    output.check()
    if alpha is not None:
        cfg = exp.PsiConfig(alpha=tuple(common.checked("--alpha", common.float_list, alpha, what="alpha")))
    else:
        cfg = exp.PsiConfig(grid=_grid(grid))
    _write(output, exp.psi_report(cfg), "psi_figure")


@app.command()
@command(options=RECEIVER_FIELDS)
def rms(
    figure: Annotated[
        Figure4 | None,
        typer.Option("--figure", help="Preset: 4.2 (Example I) or 4.3 (Example II); overrides --example."),
    ] = None,
    example: ExampleOpt = Example.I,
    receivers: ReceiversOpt = None,
    columns: ColumnsOpt = None,
    aircraft: AircraftOpt = None,
    outage_sats: Annotated[
        str | None,
        typer.Option(
            "--outage-sats",
            help="The three satellites (receivers) kept in the outage: 1-based numbers or receiver labels "
            "(default 1,2,3; with --example only with --params geometry).",
        ),
    ] = None,
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
    units: UnitsOpt = None,
    *,
    output: Output,
) -> None:
    """Figs 4.2/4.3: root-mean-square (RMS) position error against update n — least squares, tracking
    with all satellites, then the three-satellite outage — by the exact error recursion; of Table 4.1, or
    of any receivers (--receivers: one epoch, at least 4 receivers; constants from the geometry).

    \b
    Example:
      motionsig track-sat rms --figure 4.3 --convention report --plot fig4_3.png   # as printed
      motionsig track-sat rms --example I --sigma0 5 --outage-length 300 --epochs 400
      motionsig track-sat rms --receivers stations.csv --aircraft 48.35,11.79,3 --sigma 10 --units si
    """
    from motionsig_cli.atc10 import satellite_tracking as exp

    output.check()
    _exclusive(receivers, **{"--figure": figure is not None, "--example": _given("example")})
    col_units, file_units = _units(units, receivers)
    ex = Example.I if figure is Figure4.f42 else Example.II if figure is Figure4.f43 else example
    conv = exp.Convention(convention)
    given: Geometry | None = None
    if receivers is not None:
        orbit = exp.Orbit(conv, rsat_re, rsat_km)
        given = _receivers(
            receivers, orbit, columns=columns, units=file_units, aircraft=aircraft,
            outage_sats=outage_sats or "1,2,3", radius_given=orbit.given, one_epoch=True,
        )  # fmt: skip
        rsat_re = rsat_km = None  # the geometry holds the radius
    else:
        _no_receivers(columns=columns)
        if aircraft is not None or outage_sats is not None:
            option = "--aircraft" if aircraft is not None else "--outage-sats"
            if exp.param_source(conv, params.value) is exp.ParamSource.table:
                raise typer.BadParameter(
                    "the printed Table 4.2 holds the constants of satellites 1,2,3 and the aircraft at 45,120,0: "
                    "add --params geometry",
                    param_hint=option,
                )
            given = _constellation(
                ex, exp.Orbit(conv, rsat_re, rsat_km), outage_sats or "1,2,3", aircraft=aircraft
            )
    cfg = exp.RmsConfig(
        example=ex.value,
        sigma0=tuple(common.checked("--sigma0", common.float_list, sigma0, what="sigma0 [ns]")),
        sigma=sigma,
        timeline=exp.Timeline(epochs, outage_start, outage_length, reinit_after_outage),
        steady_gain=gain is Gain.steady,
        convention=conv,
        params=params.value,
        rsat_re=rsat_re,
        rsat_km=rsat_km,
        constellation=given,
        units=exp.Units(col_units),
    )
    con = cfg.geometry()
    if con is not None:
        _warn(output, _observable(con, aircraft=aircraft is not None, receivers=receivers is not None))
    _write(output, exp.rms_report(cfg), "rms_error_figure")


@app.command()
@command(parallel=True, options={**SAT_FIELDS, **RECEIVER_FIELDS})
def simulate(
    example: ExampleOpt = Example.I,
    receivers: Annotated[
        Path | None,
        typer.Option(
            "--receivers",
            help="A receivers table instead of Table 4.1 (as for constellation), here with optional epoch "
            "(update n) or time [s] columns: positions that change are interpolated linearly to each update, "
            "and a receiver is used where it is listed (three receivers: no clock measurement, as in the "
            "outage). Outputs default to SI units.",
        ),
    ] = None,
    columns: ColumnsOpt = None,
    aircraft: AircraftOpt = None,
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
    units: UnitsOpt = None,
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
      motionsig track-sat simulate --receivers stations.csv --aircraft 48.35,11.79,3 --sigma 10 --sigma0 5
    """
    from motionsig_cli.atc10 import satellite_tracking as exp

    output.check()
    engine = parallel.engine()
    _exclusive(receivers, **{"--example": _given("example")})
    col_units, file_units = _units(units, receivers)
    orbit = exp.Orbit(exp.Convention.corrected, rsat_re, rsat_km)
    con = _geometry(receivers, example, orbit, outage_sats, columns=columns, units=file_units, aircraft=aircraft,
                    one_epoch=False)  # fmt: skip
    if isinstance(con, exp.ReceiverGeometry) and con.moving:
        common.checked("--aircraft", con.check_horizon)  # the first epoch; the job checks every update
        warnings: list[str] = []
    else:
        warnings = _observable(con, aircraft=aircraft is not None, receivers=receivers is not None)
    velocity = common.checked(
        "--velocity-enu", common.float_list, velocity_enu, what="velocity component [m/s]"
    )
    job = exp.TrackSatJob(
        con, sigma=sigma, sigma0=sigma0, rho=rho,
        timeline=exp.Timeline(epochs, outage_start, outage_length, reinit_after_outage),
        estimators=tuple(dict.fromkeys(e.strip() for e in estimators.split(",") if e.strip())),
        velocity_enu=tuple(velocity), runs=runs, seed=seed, steady_gain=gain is Gain.steady,  # type: ignore[arg-type]
    )  # fmt: skip
    _warn(output, warnings)
    result = common.run_job(job, engine, "track-sat simulate", output.quiet)
    report = exp.simulation_report(
        job, result, example=None if receivers is not None else example.value, units=col_units
    )
    _write(output, report, "rms_error_figure")


# ``track-sat solve`` lives in its own module, which imports only typer and the command layer; the core
# (motionsig_cli.atc10.toa_solve) is imported when the command runs.
from motionsig_cli.cli.track_sat_solve import solve as _solve  # noqa: E402

app.command("solve")(_solve)
