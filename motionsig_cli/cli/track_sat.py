"""``motionsig track-sat``: aircraft position by satellite multilateration with a model of the
transmitter's clock (ATC-10 §4, Apps G–H; Tables 4.1–4.3, Figs 4.1–4.3).

``--convention corrected`` (default): exact speed of light, geosynchronous orbit radius and the
frame-independent three-satellite constant 1'(UU')⁻¹1. ``--convention report``: c = 1 ft/ns,
r_sat = 9.235 Earth radii and the printed (frame-dependent) constant — this reproduces Tables 4.2/4.3.
Every output records its convention and where its constellation constants came from.
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
    float_list,
    int_list,
    make_engine,
    note,
    positive,
    run_monte_carlo,
    save_figure,
)
from motionsig_cli.cli.io import InputError, Table, emit, make_meta, read_table
from motionsig_cli.experiments import satellite_tracking as exp
from motionsig_cli.experiments.satellite_tracking import Convention, ParamSource
from motionsig_cli.surveillance.clock import psi, psi_large, psi_small
from motionsig_cli.surveillance.multilateration import R_EARTH_KM

app = typer.Typer(
    help="Satellite multilateration with clock tracking (ATC-10 §4): constellation constants, "
    "Tables 4.2/4.3, ψ(α) (Fig 4.1), RMS error curves (Figs 4.2/4.3) and a Monte Carlo of the estimators.",
    no_args_is_help=True,
)


class Example(StrEnum):
    """The report's two constellations (Table 4.1)."""

    I = "I"  # noqa: E741
    II = "II"


class Params(StrEnum):
    """Source of β, tr, b: auto (report → printed Table 4.2; corrected → Table 4.1 geometry)."""

    auto = "auto"
    table = "table"
    geometry = "geometry"


class TableConvention(StrEnum):
    """Which convention(s) a table shows."""

    both = "both"
    corrected = "corrected"
    report = "report"


class WhichTable(StrEnum):
    """Which table of §4.6."""

    t42 = "4.2"
    t43 = "4.3"


class View(StrEnum):
    """Constellation output: one row per satellite subset, or one per satellite."""

    summary = "summary"
    satellites = "satellites"


class Gain(StrEnum):
    """Clock gain: the exact recursive γ_n, or the constant steady-state ψ(α)/β from n = 1."""

    recursive = "recursive"
    steady = "steady"


class Figure4(StrEnum):
    """Figure presets: 4.2 = Example I, 4.3 = Example II."""

    f42 = "4.2"
    f43 = "4.3"


MAX_NS = 1e9
"""Largest σ, σ0 accepted [ns]: one second per update."""
MAX_RSAT_KM = 1e6
MAX_SATS = 1000


def _ns_scale(value: float) -> float:
    """Option callback: a time scale in (0, 1e9] ns."""
    if not (math.isfinite(value) and 0 < value <= MAX_NS):
        raise typer.BadParameter(f"{value:g} is not in (0, {MAX_NS:g}] ns")
    return value


def _sigma0_one(value: float) -> float:
    """Option callback: σ0 in [0, 1e9] ns."""
    if not (math.isfinite(value) and 0 <= value <= MAX_NS):
        raise typer.BadParameter(f"{value:g} is not in [0, {MAX_NS:g}] ns")
    return value


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
        callback=positive,
        help="Orbit radius in Earth radii (default by --convention: report 9.235, corrected geosynchronous 6.61).",
    ),
]
RsatKmOpt = Annotated[
    float | None,
    typer.Option("--rsat-km", callback=positive, help="Orbit radius in km (instead of --rsat-re)."),
]
SimRsatReOpt = Annotated[
    float | None,
    typer.Option(
        "--rsat-re", callback=positive, help="Orbit radius in Earth radii (default geosynchronous)."
    ),
]
SigmaOpt = Annotated[
    float, typer.Option("--sigma", callback=_ns_scale, help="TOA error σ per satellite [ns] (report: 50).")
]
EpochsOpt = Annotated[
    int, typer.Option("--epochs", min=0, max=100_000, help="Last update n (updates once per second).")
]
OutageStartOpt = Annotated[
    int, typer.Option("--outage-start", min=0, help="N: last update with all satellites [assumption 100].")
]
OutageLenOpt = Annotated[
    int,
    typer.Option(
        "--outage-length", min=0, help="M: updates with the --outage-sats triplet only [assumption 60]."
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


def _rsat_km(convention: Convention, rsat_re: float | None, rsat_km: float | None) -> float:
    if rsat_re is not None and rsat_km is not None:
        raise typer.BadParameter("give --rsat-re or --rsat-km, not both", param_hint="--rsat-km")
    option, r = ("--rsat-re", rsat_re * R_EARTH_KM) if rsat_re is not None else ("--rsat-km", rsat_km)
    if r is None:
        return exp.default_rsat_km(convention)
    lo = R_EARTH_KM + exp.MAX_ALT_KM
    if not lo < r <= MAX_RSAT_KM:
        raise typer.BadParameter(
            f"orbit radius {r:.6g} km is not in ({lo:g}, {MAX_RSAT_KM:g}] km", param_hint=option
        )
    return r


def _triplet(text: str, K: int) -> tuple[int, int, int]:
    idx = checked("--outage-sats", int_list, text, what="satellite number")
    if len(idx) != 3 or len(text.split(",")) != 3 or not all(1 <= i <= K for i in idx):
        raise typer.BadParameter(
            f"expected three distinct satellite numbers in 1..{K}; got {text!r}", param_hint="--outage-sats"
        )
    return (idx[0] - 1, idx[1] - 1, idx[2] - 1)


def _aircraft(text: str) -> tuple[float, float, float]:
    vals = checked("--aircraft", float_list, text, what="latitude,longitude[,altitude km]")
    if len(vals) not in (2, 3):
        raise typer.BadParameter("expected latitude,longitude[,altitude_km]", param_hint="--aircraft")
    if not -90.0 <= vals[0] <= 90.0:
        raise typer.BadParameter(
            f"latitude {vals[0]:g} is outside [-90, 90] degrees", param_hint="--aircraft"
        )
    if not -360.0 <= vals[1] <= 360.0:
        raise typer.BadParameter(
            f"longitude {vals[1]:g} is outside [-360, 360] degrees", param_hint="--aircraft"
        )
    alt = vals[2] if len(vals) == 3 else 0.0
    if not exp.MIN_ALT_KM <= alt <= exp.MAX_ALT_KM:
        raise typer.BadParameter(
            f"altitude {alt:g} km is outside [{exp.MIN_ALT_KM:g}, {exp.MAX_ALT_KM:g}] km",
            param_hint="--aircraft",
        )
    return (vals[0], vals[1], alt)


def _user_sats(path: Path) -> tuple[tuple[float, ...], tuple[float, ...], tuple[str, ...]]:
    """Satellites from a CSV with latitude_deg, longitude_deg (and optionally satellite) columns."""
    t = read_table(path, required=("latitude_deg", "longitude_deg"))
    lat, lon = t.numeric("latitude_deg"), t.numeric("longitude_deg")
    seen: dict[tuple[float, float], int] = {}
    for i, (a, b) in enumerate(zip(lat, lon, strict=True)):
        if not (math.isfinite(a) and -90.0 <= a <= 90.0):
            raise InputError(f"{t.source}:{t.lines[i]}: latitude {float(a):g} is outside [-90, 90] degrees")
        if not (math.isfinite(b) and -360.0 <= b <= 360.0):
            raise InputError(f"{t.source}:{t.lines[i]}: longitude {float(b):g} is not in [-360, 360] degrees")
        key = (float(a), float(b) % 360.0)
        if key in seen:
            raise InputError(f"{t.source}:{t.lines[i]}: the same sub-satellite point as line {seen[key]}")
        seen[key] = t.lines[i]
    if len(lat) < 3:
        raise InputError(f"{t.source}: {len(lat)} satellite(s); at least three are needed to fix a position")
    if len(lat) > MAX_SATS:
        raise InputError(f"{t.source}: {len(lat)} satellites; at most {MAX_SATS}")
    labels: tuple[str, ...] = ()
    if "satellite" in t.columns:
        labels = tuple(str(v) for v in t.column("satellite"))
        dup = [v for v in labels if not v or labels.count(v) > 1]
        if dup:
            raise InputError(f"{t.source}: satellite labels must be non-empty and distinct (got {dup[0]!r})")
    return tuple(map(float, lat)), tuple(map(float, lon)), labels


def _constellation(
    example: Example,
    sats: Path | None,
    aircraft: str | None,
    r_sat_km: float,
    outage_sats: str,
) -> exp.Constellation:
    if sats is not None:
        lat, lon, labels = _user_sats(sats)
        name = str(sats)
    else:
        lat, lon = exp.table_4_1()[example.value]
        labels, name = (), f"Example {example.value} (Table 4.1)"
    ac = _aircraft(aircraft) if aircraft is not None else (45.0, 120.0, 0.0)
    triplet = _triplet(outage_sats, len(lat))
    return checked(
        "--sats" if sats else "--example", exp.Constellation, lat, lon, r_sat_km, ac, triplet, labels, name
    )


def _check(con: exp.Constellation, *, sats: bool, aircraft: bool, quiet: bool) -> None:
    """Observability checks, each error naming the option that caused it; warnings on one line."""
    checked("--aircraft" if aircraft else "--rsat-km/--rsat-re", con.check_horizon)
    checked("--sats" if sats else "--example", con.check_all)
    checked("--outage-sats", con.check_triplet)
    w = con.warnings()
    if w:
        note("track-sat: warning: " + "; ".join(w), quiet)


def _timeline(epochs: int, start: int, length: int, reinit: bool) -> exp.Timeline:
    return checked("--outage-length", exp.Timeline, epochs, start, length, reinit)


def _source(convention: Convention, params: Params) -> ParamSource:
    if params is Params.auto:
        return ParamSource.table if convention is Convention.report else ParamSource.geometry
    return ParamSource(params.value)


@app.command()
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
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Constellation constants (c = 1 units): β, tr{(U'U)⁻¹}, 1'U(U'U)⁻²U'1, the report's literal
    1'(U'U)⁻¹1, GDOP and zenith angles, for all satellites and for the outage triplet.

    \b
    Example:
      motionsig track-sat constellation --example I --convention report   # Table 4.2 from Table 4.1
      motionsig track-sat constellation --sats my_sats.csv --aircraft 40,-100,10 --view satellites
    """
    check_outputs(out)
    rs = _rsat_km(convention, rsat_re, rsat_km)
    con = _constellation(example, sats, aircraft, rs, outage_sats)
    _check(con, sats=sats is not None, aircraft=aircraft is not None, quiet=quiet)
    z = con.zenith_deg()
    meta = make_meta(
        "track-sat constellation",
        constellation=con.name,
        r_sat_km=rs,
        r_sat_earth_radii=rs / R_EARTH_KM,
        aircraft=list(con.aircraft),
        earth="sphere, R_E = 6378.137 km",
        convention=convention.value,
        units="c = 1 (unit direction vectors); GDOP k = sqrt(tr + b/beta)",
    )
    if view is View.satellites:
        rng_km = np.linalg.norm(con.sats_km() - con.aircraft_km(), axis=-1)
        rows = [
            (
                con.labels[i],
                con.lat_deg[i],
                con.lon_deg[i],
                float(z[i]),
                bool(z[i] <= exp.CONE_DEG),
                i in con.triplet,
                float(rng_km[i]),
            )
            for i in range(con.K)
        ]
        cols = (
            "satellite",
            "latitude_deg",
            "longitude_deg",
            "zenith_deg",
            "in_45deg_cone",
            "outage_triplet",
            "range_km",
        )
    else:
        from motionsig_cli.surveillance.multilateration import metrics

        rows = []
        for label, subset in (("all", None), (",".join(con.labels[i] for i in con.triplet), con.triplet)):
            m = metrics(con.directions(subset))
            rows.append(
                (label, m.K, float(m.beta), float(m.tr), float(m.b), float(m.b_literal),
                 float(m.gdop) if m.K > 3 else None, float(m.cond))
            )  # fmt: skip
        cols = ("subset", "K", "beta", "tr", "b", "b_literal", "gdop", "cond")
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(f"track-sat constellation: {con.name}, r_sat = {rs:.6g} km, {con.K} satellites", quiet)


@app.command()
def table(
    which: Annotated[
        WhichTable, typer.Option("--which", help="Table 4.2 (constellation) or 4.3 (estimation).")
    ] = WhichTable.t43,
    convention: Annotated[
        TableConvention, typer.Option("--convention", help="Table 4.3: rows for both conventions, or one.")
    ] = TableConvention.both,
    params: ParamsOpt = Params.auto,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Tables 4.2 and 4.3 recomputed beside the printed values, with the deviation (%), the tolerance and
    a status per value.

    \b
    Example:
      motionsig track-sat table --which 4.2    # printed, report (9.235 R_E), corrected
      motionsig track-sat table                # Table 4.3 in both conventions
    """
    check_outputs(out)
    if which is WhichTable.t42:
        if convention is not TableConvention.both or params is not Params.auto:
            raise typer.BadParameter(
                "Table 4.2 always shows the printed, report and corrected values; --convention and "
                "--params apply to Table 4.3",
                param_hint="--which",
            )
        rows, cols, meta, msg = _table_4_2()
    else:
        convs = (
            [Convention.report, Convention.corrected]
            if convention is TableConvention.both
            else [Convention(convention.value)]
        )
        rows, cols, meta, msg = _table_4_3(convs, params)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(msg, quiet)


TOL_42 = dict.fromkeys(exp.TABLE_4_2_KEYS, 0.5)
"""Table 4.2 tolerance [%] in the report convention (issue 8: 0.5 %)."""


def _table_4_2() -> tuple[list[tuple[object, ...]], tuple[str, ...], dict[str, object], str]:
    printed = exp.table_4_2_printed()
    r_rep = exp.default_rsat_km(Convention.report)
    rows = []
    for ex in exp.EXAMPLES:
        rep = exp.geometry_params(exp.example(ex, r_sat_km=r_rep))
        geo = exp.geometry_params(exp.example(ex, r_sat_km=exp.default_rsat_km(Convention.corrected)))
        for key in exp.TABLE_4_2_KEYS:
            k_rep = "b_123_literal" if key == "b_123" else key
            k_cor = "b_123_correct" if key == "b_123" else key
            dev = 100.0 * (rep[k_rep] / printed[ex][key] - 1.0)
            rows.append(
                (ex, key, printed[ex][key], rep[k_rep], dev, TOL_42[key],
                 "agrees" if abs(dev) <= TOL_42[key] else "differs",
                 rep[k_cor], geo[k_cor], 100.0 * (geo[k_cor] / printed[ex][key] - 1.0))
            )  # fmt: skip
    cols = (
        "example", "quantity", "printed", "report", "deviation_report_pct", "tolerance_pct", "status",
        "corrected_at_report_radius", "corrected", "deviation_corrected_pct",
    )  # fmt: skip
    meta = make_meta(
        "track-sat table",
        which="4.2",
        source="ATC-10 (1972) Table 4.2",
        report=f"Table 4.1 geometry at 9.235 Earth radii ({r_rep:.6g} km), aircraft (45, 120, 0), "
        "b_123 = literal 1'(U'U)^-1 1 in ECEF",
        corrected=f"geosynchronous radius ({exp.default_rsat_km(Convention.corrected):.6g} km), b_123 = 1'(UU')^-1 1",
        corrected_at_report_radius="9.235 Earth radii, b_123 = 1'(UU')^-1 1 (isolates the b3 correction)",
        fitted_radius_earth_radii=round(exp.fit_orbit_radius(), 4),
    )
    agree = sum(r[6] == "agrees" for r in rows)
    return rows, cols, meta, f"Table 4.2: {agree}/{len(rows)} values agree in the report convention"


def _table_4_3(
    convs: list[Convention], params: Params
) -> tuple[list[tuple[object, ...]], tuple[str, ...], dict[str, object], str]:
    from motionsig_cli.surveillance.clock_tracking import table_4_3_values

    rows = []
    sources = {}
    for conv in convs:
        c_ft = exp.c_ft_per_ns(conv)
        for ex in exp.EXAMPLES:
            p = exp.constellation_params(ex, conv, _source(conv, params))
            sources[f"{conv.value} {ex}"] = p.source
            for pr in (r for r in exp.table_4_3_printed() if r["example"] == ex):
                v = table_4_3_values(
                    float(pr["sigma_ns"]), float(pr["sigma0_ns"]), p.beta, p.tr, p.b, p.tr3, p.b3, c_ft
                )
                devs = [100.0 * (float(v[k]) / float(pr[f"{k}_ft"]) - 1.0) for k in ("e0", "eN", "eN1")]
                tol = 2.0 if conv is Convention.report else None  # the target: report convention within 2 %
                if tol is None:
                    status = "corrected (no target; see the errata page)"
                else:
                    status = "agrees" if all(abs(d) <= tol for d in devs) else "differs"
                rows.append(
                    (conv.value, ex, pr["sigma_ns"], pr["sigma0_ns"], float(v["alpha"]), pr["alpha"], float(v["psi"]), pr["psi"],
                     float(v["e0"]), pr["e0_ft"], devs[0], float(v["eN"]), pr["eN_ft"], devs[1],
                     float(v["eN1"]), pr["eN1_ft"], devs[2], tol, status)
                )  # fmt: skip
    cols = (
        "convention", "example", "sigma_ns", "sigma0_ns", "alpha", "printed_alpha", "psi", "printed_psi",
        "e0_ft", "printed_e0_ft", "deviation_e0_pct", "eN_ft", "printed_eN_ft", "deviation_eN_pct",
        "eN1_ft", "printed_eN1_ft", "deviation_eN1_pct", "tolerance_pct", "status",
    )  # fmt: skip
    meta = make_meta(
        "track-sat table",
        which="4.3",
        source="ATC-10 (1972) Table 4.3",
        params=params.value,
        constants=sources,
        speed_of_light={"report": "1 ft/ns", "corrected": "0.299792458 m/ns = 0.983571 ft/ns"},
        formulas="e0 = c sigma sqrt(tr + b/beta); eN = c sigma sqrt(tr + psi b/beta); "
        "eN1 = c sigma sqrt(tr3 + [psi/beta + (sigma0/sigma)^2 (2 - psi)/psi + (sigma0/sigma)^2] b3)",
        psi="exact root of psi^3 + (27 alpha/4)(psi - 1) = 0 (the report read it off Fig 4.1)",
    )
    msg = "; ".join(
        f"{c.value}: {sum(r[-1] == 'agrees' for r in rows if r[0] == c.value)}/6 rows within 2 %"
        for c in convs
    )
    return rows, cols, meta, f"Table 4.3: {msg}"


@app.command("psi")
def psi_cmd(
    alpha: Annotated[str | None, typer.Option("--alpha", help="Comma-separated α values (α ≥ 0).")] = None,
    grid: Annotated[
        str, typer.Option("--grid", help="Log-spaced grid lo:hi:n (α > 0) when --alpha is not given.")
    ] = "1e-6:1e2:161",
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Fig 4.1: ψ(α) (eq 4.5.34, exact root of the cubic) and the report's two approximations.

    \b
    Example:
      motionsig track-sat psi --alpha 1.61e-4,1.61e-2,1.61   # Table 4.3, Example I: 0.0993, 0.4020, 0.9267
      motionsig track-sat psi --plot fig4_1.png
    """
    check_outputs(out, plot)
    if alpha is not None:
        a = np.array(checked("--alpha", float_list, alpha, what="alpha"))
        if np.any(a < 0):
            raise typer.BadParameter("alpha must be >= 0", param_hint="--alpha")
    else:
        a = _grid(grid)
    p = psi(a)
    with np.errstate(all="ignore"):
        lg, sm = psi_large(a), psi_small(a)
        rel_l = np.where(p > 0, lg / p - 1.0, np.nan)
        rel_s = np.where(p > 0, sm / p - 1.0, np.nan)
    rows = [tuple(float(x) for x in r) for r in zip(a, p, lg, sm, rel_l, rel_s, strict=True)]
    cols = ("alpha", "psi", "psi_large_alpha", "psi_small_alpha", "rel_error_large", "rel_error_small")
    meta = make_meta(
        "track-sat psi",
        figure="4.1",
        exact="real root in [0, 1) of psi^3 + (27 alpha/4)(psi - 1) = 0 (eq 4.5.34)",
        large_alpha="1 - 4/(27 alpha), labelled alpha >= 1",
        small_alpha="(3/2) 2^(1/3) [alpha^(1/3) - (alpha/2)^(2/3)], labelled alpha <= 0.3",
    )
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    if plot is not None:
        from motionsig_cli.plotting import psi_figure

        marks = [
            (float(r["alpha"]), float(r["psi"]), f"{r['example']}, σ0={r['sigma0_ns']:g}")
            for r in exp.table_4_3_printed()
        ]
        ag = a if alpha is None else np.geomspace(1e-6, 1e2, 161)
        save_figure(psi_figure(ag, psi(ag), psi_large(ag), psi_small(ag), marks), plot)
    note(f"track-sat psi: {len(rows)} values", quiet)


def _grid(text: str) -> np.ndarray:
    parts = text.split(":")
    try:
        lo, hi, n = float(parts[0]), float(parts[1]), int(parts[2])
        if len(parts) != 3:
            raise ValueError
    except (ValueError, IndexError):
        raise typer.BadParameter(f"expected lo:hi:n, got {text!r}", param_hint="--grid") from None
    if not (0 < lo < hi and math.isfinite(hi) and 2 <= n <= 100_000):
        raise typer.BadParameter("need 0 < lo < hi (finite) and 2 <= n <= 100000", param_hint="--grid")
    return np.geomspace(lo, hi, n)


def _sigma0_list(text: str) -> list[float]:
    vals = checked("--sigma0", float_list, text, what="sigma0 [ns]")
    if any(not 0 <= v <= MAX_NS for v in vals):
        raise typer.BadParameter(f"sigma0 must be in [0, {MAX_NS:g}] ns", param_hint="--sigma0")
    if len(vals) > 20:
        raise typer.BadParameter("at most 20 values", param_hint="--sigma0")
    return vals


@app.command()
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
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Figs 4.2/4.3: RMS position error against update n — least squares, tracking with all satellites,
    then the three-satellite outage — by the exact error recursion.

    \b
    Example:
      motionsig track-sat rms --figure 4.3 --convention report --plot fig4_3.png   # as printed
      motionsig track-sat rms --example I --sigma0 5 --outage-length 300 --epochs 400
    """
    check_outputs(out, plot)
    ex = Example.I if figure is Figure4.f42 else Example.II if figure is Figure4.f43 else example
    s0 = _sigma0_list(sigma0)
    tl = _timeline(epochs, outage_start, outage_length, reinit_after_outage)
    src = _source(convention, params)
    rs = _rsat_km(convention, rsat_re, rsat_km)
    if src is ParamSource.table and (rsat_re is not None or rsat_km is not None):
        raise typer.BadParameter(
            "the printed Table 4.2 constants carry no orbit radius; add --params geometry",
            param_hint="--rsat-re" if rsat_re is not None else "--rsat-km",
        )
    if src is ParamSource.geometry:
        _check(exp.example(ex.value, r_sat_km=rs), sats=False, aircraft=False, quiet=quiet)
    p = checked("--params", exp.constellation_params, ex.value, convention, src, r_sat_km=rs)
    c_ft = exp.c_ft_per_ns(convention)
    curves = exp.rms_curves(p, sigma, s0, tl, c_ft, steady_gain=gain is Gain.steady)
    k_all = len(exp.table_4_1()[ex.value][0])
    rows = []
    for i, s in enumerate(curves.sigma0):
        for j, n in enumerate(curves.n):
            ls = float(curves.rms_ls[i, j])
            rows.append(
                (int(n), 3 if curves.outage[j] else k_all, float(s), float(curves.rms_tracking[i, j]),
                 None if math.isnan(ls) else ls, float(curves.gain[i, j]), math.sqrt(float(curves.clock_var[i, j])))
            )  # fmt: skip
    cols = ("n", "K", "sigma0_ns", "rms_ft", "rms_no_tracking_ft", "gain", "clock_sd_ns")
    meta = make_meta(
        "track-sat rms",
        figure={Example.I: "4.2", Example.II: "4.3"}[ex],
        example=ex.value,
        convention=convention.value,
        constants={"beta": p.beta, "tr": p.tr, "b": p.b, "tr3": p.tr3, "b3": p.b3, "source": p.source},
        r_sat_km=rs if src is ParamSource.geometry else None,
        sigma_ns=sigma,
        outage={
            "N": tl.outage_start,
            "M": tl.outage_length,
            "satellites": "1,2,3",
            "after": "reinit" if reinit_after_outage else "continue",
        },
        gain=gain.value,
        c_ft_per_ns=c_ft,
        rms="sqrt(sigma^2 tr_n + V_n b_n) in c = 1 units times c (eq 4.5.35, corrected); V_n by the exact recursion",
    )
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    if plot is not None:
        from motionsig_cli.plotting import rms_error_figure

        series = []
        for i, s in enumerate(curves.sigma0):
            series.append((f"tracking, σ0 = {s:g} ns", curves.rms_tracking[i], {"color": f"C{i}", "lw": 1.4}))
        series.append(("least squares (no tracking)", curves.rms_ls[0], {"color": "k", "ls": "--", "lw": 1}))
        fig = rms_error_figure(
            curves.n, series, outage=(tl.outage_start, tl.outage_start + tl.outage_length),
            title=f"Fig 4.{2 if ex is Example.I else 3}: RMS error, Example {ex.value} (σ = {sigma:g} ns, {convention.value} convention)",
        )  # fmt: skip
        save_figure(fig, plot)
    note(
        f"track-sat rms: Example {ex.value}, {convention.value}; e0 = {curves.rms_tracking[0, 0]:.0f} ft; "
        + ", ".join(
            f"σ0={s:g}: eN = {curves.rms_tracking[i, min(tl.outage_start, tl.epochs)]:.0f} ft"
            for i, s in enumerate(curves.sigma0)
        ),
        quiet,
    )


@app.command()
def simulate(
    example: ExampleOpt = Example.I,
    sigma0: Annotated[
        float, typer.Option("--sigma0", callback=_sigma0_one, help="Clock scale σ0 [ns] (σ1 = σ2 = σ0).")
    ] = 50.0,
    sigma: SigmaOpt = 50.0,
    rho: Annotated[
        float,
        typer.Option("--rho", help="True clock's flicker exponent ρ in (1/2, 1] (1: the report's model)."),
    ] = 1.0,
    runs: Annotated[int, typer.Option("--runs", min=1, max=exp.MAX_RUNS, help="Monte Carlo runs.")] = 2000,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    estimators: Annotated[
        str, typer.Option("--estimators", help="Comma-separated: none (LS each update), report, kf2.")
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
    workers: WorkersOpt = None,
    scheduler: SchedulerOpt = None,
    checkpoint: CheckpointOpt = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Monte Carlo of the estimators on nonlinear time-of-arrival measurements (exact c, Gaussian noise),
    with the analytic recursion beside it: RMS error and its standard error per update.

    \b
    Example:
      motionsig track-sat simulate --example I --sigma0 50 --rsat-re 9.235 --plot mc.png
      motionsig track-sat simulate --example II --rho 0.9 --estimators report,kf2 --outage-length 0 --epochs 300
      motionsig track-sat simulate --runs 20000 --workers 8 --checkpoint ckpt/   # resumable, same result
    """
    check_outputs(out, plot)
    engine = make_engine(workers, scheduler, checkpoint)
    if not 0.5 < rho <= 1.0:
        raise typer.BadParameter(f"{rho:g} is outside (1/2, 1]", param_hint="--rho")
    names = tuple(dict.fromkeys(e.strip() for e in estimators.split(",") if e.strip()))
    bad = [e for e in names if e not in exp.ESTIMATORS]
    if bad or not names:
        raise typer.BadParameter(
            f"unknown estimator(s) {', '.join(bad) or '(none)'}; choose from none, report, kf2",
            param_hint="--estimators",
        )
    vel = checked("--velocity-enu", float_list, velocity_enu, what="velocity component [m/s]")
    if len(vel) != 3:
        raise typer.BadParameter("expected three components east,north,up", param_hint="--velocity-enu")
    if math.hypot(*vel) > exp.MAX_SPEED_MPS:
        raise typer.BadParameter(
            f"speed must be at most {exp.MAX_SPEED_MPS:g} m/s", param_hint="--velocity-enu"
        )
    rs = _rsat_km(Convention.corrected, rsat_re, rsat_km)
    if runs * (epochs + 1) > exp.MAX_WORK:
        raise typer.BadParameter(
            f"runs x (epochs + 1) = {runs * (epochs + 1):,} exceeds {exp.MAX_WORK:,} (about 4 minutes of work)",
            param_hint="--runs",
        )
    con = _constellation(example, None, None, rs, outage_sats)
    tl = _timeline(epochs, outage_start, outage_length, reinit_after_outage)
    cfg = checked(
        "--rho", exp.SimulationConfig, con, sigma, sigma0, rho, tl, names, (vel[0], vel[1], vel[2]),
        steady_gain=gain is Gain.steady,
    )  # fmt: skip
    checked("--velocity-enu", exp.check_track, cfg)
    _check(con, sats=False, aircraft=False, quiet=quiet)
    tasks = checked("--velocity-enu", exp.simulation_tasks, cfg, runs)
    identity = {
        "command": "track-sat simulate",
        "example": example.value,
        "r_sat_km": rs,
        "sigma_ns": sigma,
        "sigma0_ns": sigma0,
        "rho": rho,
        "runs": runs,
        "seed": seed,
        "estimators": list(names),
        "epochs": epochs,
        "outage_start": outage_start,
        "outage_length": outage_length,
        "outage_sats": list(con.triplet),
        "reinit_after_outage": reinit_after_outage,
        "gain": gain.value,
        "velocity_enu_mps": list(vel),
        "runs_per_task": len(tasks[0]),
    }
    parts = checked(
        "--velocity-enu",
        run_monte_carlo,
        exp.task_function(cfg, seed),
        tasks,
        engine,
        sizes=[len(t) for t in tasks],
        identity=identity,
        label="track-sat simulate",
        quiet=quiet,
    )
    res = exp.combine_runs(cfg, parts)
    rows = []
    for j, n in enumerate(res.n):
        row: list[object] = [int(n), int(res.K[j]), float(res.analytic_report[j])]
        ls = float(res.analytic_ls[j])
        row.append(None if math.isnan(ls) else ls)
        for e in names:
            r, s = float(res.rms[e][j]), float(res.se[e][j])
            row += [None if math.isnan(r) else r, None if math.isnan(s) else s]
        rows.append(tuple(row))
    per_estimator = tuple(c for e in names for c in (f"rms_{e}_ft", f"se_{e}_ft"))
    cols = ("n", "K", "analytic_report_ft", "analytic_no_tracking_ft", *per_estimator)
    z = None
    if "report" in names and rho == 1.0 and runs > 1 and not any(vel):
        with np.errstate(all="ignore"):
            zz = np.abs((res.rms["report"] - res.analytic_report) / res.se["report"])
        z = float(np.max(zz[np.isfinite(zz)])) if np.isfinite(zz).any() else None
    meta = make_meta(
        "track-sat simulate",
        example=example.value,
        r_sat_km=rs,
        convention="corrected (physical simulation: exact c, b3 from the geometry)",
        sigma_ns=sigma,
        sigma0_ns=sigma0,
        rho=rho,
        runs=runs,
        seed=seed,
        seeding="run r draws from SeedSequence(seed).spawn(...)[r]: tau_0, clock path, TOA noise, initial guess",
        estimators=list(names),
        outage={
            "N": tl.outage_start,
            "M": tl.outage_length,
            "satellites": outage_sats,
            "after": "reinit" if reinit_after_outage else "continue",
        },
        gain=gain.value,
        velocity_enu_mps=vel,
        relinearisations_per_update=cfg.relinearise + 1,
        initial_guess="truth + N(0, (50 km)^2) per axis; Gauss-Newton least squares",
        tau0="uniform +-1 ms, unknown to the estimators",
        se="standard error of the RMS by the delta method: sd(e^2)/(2 RMS sqrt(runs))",
        max_abs_z_report_vs_analytic=z,
        analytic="the recursion for a rho = 1 clock at the initial (static) geometry: a reference, not a "
        "prediction, when --rho < 1 or the aircraft moves",
    )
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    if plot is not None:
        from motionsig_cli.plotting import rms_error_figure

        styles = {
            "none": ("least squares each update", "k"),
            "report": ("report's tracker", "C0"),
            "kf2": ("kf2 (phase + rate KF)", "C3"),
        }
        series: list[tuple[str, np.ndarray, dict[str, object]]] = [
            (
                "analytic recursion (report's tracker)",
                res.analytic_report,
                {"color": "0.3", "ls": "--", "lw": 1},
            )
        ]
        bands = []
        for e in names:
            label, color = styles[e]
            series.append((f"Monte Carlo: {label}", res.rms[e], {"color": color, "lw": 1.2}))
            bands.append((res.rms[e] - 2 * res.se[e], res.rms[e] + 2 * res.se[e], color))
        fig = rms_error_figure(
            res.n, series, outage=(tl.outage_start, tl.outage_start + tl.outage_length), bands=bands,
            title=f"Example {example.value}: σ0 = {sigma0:g} ns, ρ = {rho:g}, {runs} runs (bands ±2 SE)",
        )  # fmt: skip
        save_figure(fig, plot)
    note(
        f"track-sat simulate: {runs} runs"
        + (
            f"; report tracker vs analytic recursion: max |z| = {z:.2f} over {len(res.n)} updates"
            if z is not None
            else ""
        ),
        quiet,
    )
