"""``motionsig jam-bound``: jamming-vulnerability bounds of the satellite surveillance link (ATC-10 §2,
Apps A–D; Tables 1.1 and 2.1; Figs 2.1–2.16).

All outputs are fractions of the aircraft population N_T (the report never gives N_T). The default
``--convention corrected`` evaluates p_f with the re-derived √(P₀Bτ/(2J)) (eq D.17);
``--convention report`` uses the misprinted ½√(P₀Bτ/J) of eqs 2.8.1/2.8.3 for N̄_FL with K > 1, the
only place the report prints it (a 3.01 dB shift; no table depends on it).
"""

from __future__ import annotations

import functools
import inspect
import math
from collections.abc import Callable
from enum import StrEnum
from typing import Annotated, Any

import typer

from motionsig_cli.cli.common import (
    DebugOpt,
    FormatOpt,
    OutOpt,
    OutputFormat,
    PlotOpt,
    QuietOpt,
    check_outputs,
    checked,
    float_list,
    note,
    positive,
    save_figure,
)
from motionsig_cli.cli.io import Table, emit, make_meta
from motionsig_cli.experiments import jamming as exp
from motionsig_cli.surveillance.antenna import FOOT_M, DishAntenna, jammer_antenna
from motionsig_cli.surveillance.jamming import (
    C_MPH,
    DEFAULT_SYSTEM,
    JammingDesign,
    JammingSystem,
    Quantity,
    required_jamming,
)

app = typer.Typer(
    help="Jamming bounds of the air-to-satellite-to-ground surveillance link (ATC-10 §2): "
    "N̄_FL / N̄_ADL curves, the jammer power that disables the system, Tables 1.1 and 2.1.",
    no_args_is_help=True,
)

LN10 = math.log(10.0)


class Convention(StrEnum):
    """Which p_f formula: the re-derived D.17 or the misprinted 2.8.1/2.8.3."""

    corrected = "corrected"
    report = "report"


class QuantityChoice(StrEnum):
    """Which bound."""

    nfl = "nfl"
    nadl = "nadl"
    both = "both"


class Bound(StrEnum):
    """Which bound a threshold is solved for."""

    nfl = "nfl"
    nadl = "nadl"


class WhichTable(StrEnum):
    """Which table of the report."""

    t21 = "2.1"
    t11 = "1.1"


# --- shared system options ------------------------------------------------------------------------


def _open_unit(value: float | None) -> float | None:
    """Option callback: a number in the open interval (0, 1)."""
    if value is not None and not 0.0 < value < 1.0:
        raise typer.BadParameter(f"{value:g} is not in the open interval (0, 1)")
    return value


def _half_open_unit(value: float | None) -> float | None:
    """Option callback: a number in (0, 1]."""
    if value is not None and not 0.0 < value <= 1.0:
        raise typer.BadParameter(f"{value:g} is not in (0, 1]")
    return value


_pos = {"callback": positive}
BOpt = Annotated[float, typer.Option("--B", **_pos, help="Bandwidth B [Hz] (report: 10 MHz).")]
AlphaOpt = Annotated[float, typer.Option("--alpha", **_pos, help="Signature period α [s] (report: 1 s).")]
BetaOpt = Annotated[
    float, typer.Option("--beta", **_pos, help="Largest differential satellite delay β [s] (report: 24 ms).")
]
VmaxOpt = Annotated[
    float, typer.Option("--vmax-mph", **_pos, help="Largest aircraft speed v [mph] (report: 600).")
]
COpt = Annotated[
    float, typer.Option("--c-mph", **_pos, help="Speed of light [mph] [assumption: exact 299 792 458 m/s].")
]
EnergyOpt = Annotated[
    float, typer.Option("--energy-j", **_pos, help="Signature energy E = P₀τ [J] (report: 10 mJ).")
]
AirborneOpt = Annotated[
    float,
    typer.Option(
        "--airborne-frac",
        callback=_open_unit,
        help="N/N_T airborne (report: 0.1).",
    ),
]
ConventionOpt = Annotated[
    Convention,
    typer.Option(
        "--convention",
        help="corrected: p_f from √(P₀Bτ/2J) (App. D re-derived); report: the misprinted ½√(P₀Bτ/J) of "
        "eqs 2.8.1/2.8.3 for N̄_FL with K > 1.",
    ),
]


def _system(
    B: float,
    alpha: float,
    beta: float,
    vmax: float,
    c: float,
    energy: float,
    airborne: float,
    convention: Convention,
) -> JammingSystem:
    if not vmax < c:
        raise typer.BadParameter(f"must be below the speed of light ({c:.6g} mph)", param_hint="--vmax-mph")
    return checked(
        "--B/--alpha/--beta/--vmax-mph",
        JammingSystem,
        bandwidth_hz=B,
        alpha_s=alpha,
        beta_s=beta,
        vmax_mph=vmax,
        c_mph=c,
        energy_j=energy,
        airborne_frac=airborne,
        pf_form="report" if convention is Convention.report else "d17",
    )


_SYSTEM_OPTIONS = [
    inspect.Parameter(name, inspect.Parameter.POSITIONAL_OR_KEYWORD, default=default, annotation=annotation)
    for name, annotation, default in (
        ("B", BOpt, 1.0e7),
        ("alpha", AlphaOpt, 1.0),
        ("beta", BetaOpt, 0.024),
        ("vmax_mph", VmaxOpt, 600.0),
        ("c_mph", COpt, C_MPH),
        ("energy_j", EnergyOpt, 0.01),
        ("airborne_frac", AirborneOpt, 0.1),
        ("convention", ConventionOpt, Convention.corrected),
    )
]


def system_options(fn: Callable[..., None]) -> Callable[..., None]:
    """Give a command the shared system options (--B … --convention); it receives one ``system``.

    The wrapper's signature is the command's own with ``system`` replaced by the options (inserted
    before --format), which is what typer reads.
    """
    sig = inspect.signature(fn, eval_str=True)  # the module uses postponed annotations
    own = [p for p in sig.parameters.values() if p.name != "system"]
    names = [p.name for p in _SYSTEM_OPTIONS]

    @functools.wraps(fn)
    def command(**kwargs: Any) -> None:
        values = {n: kwargs.pop(n) for n in names}
        return fn(system=_system(*values.values()), **kwargs)

    at = next(i for i, p in enumerate(own) if p.name == "fmt")
    command.__signature__ = sig.replace(parameters=[*own[:at], *_SYSTEM_OPTIONS, *own[at:]])  # type: ignore[attr-defined]
    command.__annotations__ = {k: v for k, v in fn.__annotations__.items() if k != "system"} | {
        p.name: p.annotation for p in _SYSTEM_OPTIONS
    }
    return command


def _system_meta(system: JammingSystem) -> dict[str, object]:
    convention = Convention.report if system.pf_form == "report" else Convention.corrected
    return {
        "convention": convention.value,
        "pf_formula": "p_f = Phi(Phi^-1(p_d) - sqrt(P0 B tau / J)) (eq D.17)"
        + (
            "; N_FL with K > 1 uses the misprinted 1/2 sqrt(P0 B tau / J) of eqs 2.8.1/2.8.3"
            if convention is Convention.report
            else ""
        ),
        "B_hz": system.bandwidth_hz,
        "alpha_s": system.alpha_s,
        "beta_s": system.beta_s,
        "vmax_mph": system.vmax_mph,
        "c_mph": system.c_mph,
        "energy_j": system.energy_j,
        "airborne_frac": system.airborne_frac,
        "n_alpha": system.n_alpha,
        "n_beta": system.n_beta,
        "n_v": system.n_v,
        "eb_dbw": system.eb_dbw,
        "units": "bounds are fractions of the population N_T; x_db = 10 log10(J/(P0 B tau)); "
        "erp_dbw = x_db + 10 log10(E B)",
    }


def _probabilities(text: str | None, option: str, *, lo_closed: bool = False) -> list[float] | None:
    if text is None:
        return None
    values = checked(option, float_list, text, what=option)
    for v in values:
        ok = (0.0 <= v < 1.0) if lo_closed else (0.0 < v < 1.0)
        if not ok:
            interval = "[0, 1)" if lo_closed else "the open interval (0, 1)"
            raise typer.BadParameter(f"{v:g} is not in {interval}", param_hint=option)
    return list(dict.fromkeys(v + 0.0 for v in values))  # + 0.0 turns -0.0 into 0.0


def _designs(
    K: int, pdl: list[float] | None, t: list[float], pd: list[float] | None
) -> list[tuple[float, JammingDesign]]:
    """(target P_DL, design) pairs from --pdl × --t, or --pd × --t (P_DL computed)."""
    if K == 1 and any(v != 0.0 for v in t):
        raise typer.BadParameter("with --K 1 the only meaningful rule is t = 0", param_hint="--t")
    if pd is not None and pdl is not None:
        raise typer.BadParameter("give --pdl or --pd, not both", param_hint="--pd")
    if pd is None:
        assert pdl is not None
        return checked("--pdl", exp.designs_for, K, pdl, t)
    out = []
    for p in pd:
        for tt in t:
            design = checked("--pd", JammingDesign, K, p, tt)
            if design.pdl <= 0.0:
                raise typer.BadParameter(
                    f"t = {tt:g} >= q = p_d^4 = {design.q:.6g} makes P_DL = 0 (the design is infeasible)",
                    param_hint="--t",
                )
            out.append((design.pdl, design))
    return out


def _value(log_value: float) -> float | None:
    """N̄/N_T as a float, or None where it underflows a double (the log10 column is exact)."""
    return math.exp(log_value) if log_value > -690.0 else None


LABEL = {"nfl": r"$\bar N_{FL}/N_T$", "nadl": r"$\bar N_{ADL}/N_T$"}


@app.command()
@system_options
def curves(
    figure: Annotated[
        str | None,
        typer.Option("--figure", help=f"A figure preset of the report: {', '.join(exp.FIGURES)}."),
    ] = None,
    quantity: Annotated[
        QuantityChoice | None,
        typer.Option("--quantity", help="Which bound (default: both, or the figure's)."),
    ] = None,
    K: Annotated[
        int | None, typer.Option("--K", min=1, help="Tracking length K in pulses (default 10).")
    ] = None,
    pdl: Annotated[
        str | None, typer.Option("--pdl", help="Design P_DL values, comma-separated (default 0.88,0.999).")
    ] = None,
    t: Annotated[
        str | None,
        typer.Option("--t", help="Rule parameters t in [0, 1) (default 0,0.1,0.2,0.3,0.5; 0 for K = 1)."),
    ] = None,
    pd: Annotated[
        str | None,
        typer.Option("--pd", help="Pulse detection probabilities p_d instead of --pdl (P_DL is computed)."),
    ] = None,
    x_min: Annotated[
        float | None, typer.Option("--x-min", help="Smallest 10 log10(J/P₀Bτ) [dB] (default by K).")
    ] = None,
    x_max: Annotated[float | None, typer.Option("--x-max", help="Largest 10 log10(J/P₀Bτ) [dB].")] = None,
    step: Annotated[float, typer.Option("--step", callback=positive, help="Grid step [dB].")] = 0.05,
    system: JammingSystem = DEFAULT_SYSTEM,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """N̄_FL/N_T and N̄_ADL/N_T against 10 log10(J/P₀Bτ) (eqs 2.7.3, 2.8.3, 2.8.4; Figs 2.1–2.16).

    One row per (quantity, design, x). log10_value is exact even where the value underflows a
    double (value is then empty): the bounds reach 10^-222 and below.
    """
    check_outputs(out, plot)
    preset = checked("--figure", exp.parse_figure, figure) if figure is not None else None
    if preset is not None and K is not None and K != preset.K:
        raise typer.BadParameter(
            f"Fig. {preset.figure} is drawn for K = {preset.K}; drop --K or --figure", param_hint="--K"
        )
    if preset is not None and quantity is not None and quantity.value != preset.quantity:
        raise typer.BadParameter(
            f"Fig. {preset.figure} shows {preset.quantity}; drop --quantity or --figure",
            param_hint="--quantity",
        )
    K_ = K if K is not None else preset.K if preset else 10
    pdl_ = _probabilities(pdl, "--pdl")
    pd_ = _probabilities(pd, "--pd")
    t_ = _probabilities(t, "--t", lo_closed=True)
    if pdl_ is None and pd_ is None:
        pdl_ = list(preset.pdl) if preset else [0.88, 0.999] if K_ > 1 else list(exp.PDL_SET_K1)
    if t_ is None:
        t_ = list(preset.t) if preset else [0.0] if K_ == 1 else list(exp.T_SET)
    quantities: list[Quantity]
    if quantity is None:
        quantities = [preset.quantity] if preset else ["nfl", "nadl"]
    else:
        quantities = ["nfl", "nadl"] if quantity is QuantityChoice.both else [Bound(quantity.value).value]
    lo, hi = preset.x_range if preset else exp.default_x_range(K_)
    lo, hi = lo if x_min is None else x_min, hi if x_max is None else x_max
    for name, v in (("--x-min", lo), ("--x-max", hi)):
        if not (math.isfinite(v) and abs(v) <= exp.X_LIMIT_DB):
            raise typer.BadParameter(f"{v:g} is not within ±{exp.X_LIMIT_DB:g} dB", param_hint=name)
    if lo > hi:
        raise typer.BadParameter(f"{hi:g} is below --x-min {lo:g}", param_hint="--x-max")
    designs = _designs(K_, pdl_, t_, pd_)
    per_curve = exp.MAX_ROWS // (len(designs) * len(quantities))
    x = checked("--step", exp.x_grid, lo, hi, step, max_points=per_curve)
    rows = []
    panels = []
    for q in quantities:
        lines = []
        for c in exp.curves(q, designs, x, system):
            log10_pf = c.log_pf / LN10
            log10_v = c.log_value / LN10
            for xi, lp, lv, v in zip(c.x_db, log10_pf, log10_v, c.log_value, strict=True):
                rows.append(
                    (
                        preset.figure if preset else "",
                        q,
                        K_,
                        c.pdl,
                        c.design.t,
                        c.design.p_d,
                        float(xi),
                        float(xi) + system.eb_dbw,
                        float(lp),
                        float(lv),
                        _value(float(v)),
                    )
                )
            lines.append((f"P_DL={c.pdl:g}, t={c.design.t:g} (p_d={c.design.p_d:.4f})", c.x_db, log10_v))
        levels = (
            [(1 - system.airborne_frac, "supremum $N_T - N$")]
            if q == "nfl"
            else [(exp.LEVEL_NADL, "$0.01\\,N_T$")]
        )
        panels.append((LABEL[q], lines, levels))
    meta = make_meta(
        "jam-bound curves",
        figure=preset.figure if preset else None,
        quantities=quantities,
        K=K_,
        pdl=pdl_,
        pd=pd_,
        t=t_,
        x_min=float(x[0]),
        x_max=float(x[-1]),
        step=step,
        **_system_meta(system),
        assumptions="figure presets: P_DL set of Figs 2.1/2.2, the t set of the (p_d, t) legends and the x "
        "ranges are assumptions (the report's figures carry no readable data)",
    )
    cols = (
        "figure",
        "quantity",
        "K",
        "P_DL",
        "t",
        "p_d",
        "x_db",
        "erp_dbw",
        "log10_pf",
        "log10_value",
        "value",
    )
    if plot is not None:
        from motionsig_cli.plotting import jamming_figure

        title = f"Fig. {preset.figure}" if preset else ""
        save_figure(jamming_figure(panels, title=f"{title} K = {K_}".strip()), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(f"jam-bound curves: {len(designs)} design(s) × {len(quantities)} bound(s) × {len(x)} points", quiet)


@app.command()
@system_options
def threshold(
    quantity: Annotated[
        Bound, typer.Option("--quantity", help="Which bound reaches the level.")
    ] = Bound.nadl,
    level: Annotated[
        float,
        typer.Option(
            "--level", callback=_half_open_unit, help="Target N̄/N_T in (0, 1] (report: N̄_ADL = 0.01 N_T)."
        ),
    ] = 0.01,
    K: Annotated[int, typer.Option("--K", min=1, help="Tracking length K.")] = 10,
    pdl: Annotated[str | None, typer.Option("--pdl", help="Design P_DL values (default 0.88,0.999).")] = None,
    t: Annotated[str, typer.Option("--t", help="Rule parameters t in [0, 1).")] = "0",
    pd: Annotated[
        str | None, typer.Option("--pd", help="Pulse detection probabilities instead of --pdl.")
    ] = None,
    system: JammingSystem = DEFAULT_SYSTEM,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """The jammer power at which a bound reaches a level (spec §7.3), with the supremum and conditioning.

    attainable = false when the level is at or above the bound's supremum: no jammer power reaches it
    (the report's "> 130 dBW"). ill_conditioned = true when p_f* > 0.9 p_d (K = 1000).
    """
    check_outputs(out)
    pdl_ = _probabilities(pdl, "--pdl")
    pd_ = _probabilities(pd, "--pd")
    t_ = _probabilities(t, "--t", lo_closed=True) or [0.0]
    if pdl_ is None and pd_ is None:
        pdl_ = [0.88, 0.999]
    rows = []
    for target, design in _designs(K, pdl_, t_, pd_):
        th = checked("--level", required_jamming, quantity.value, level, design, system)
        j = th.x_db if th.attainable else None
        rows.append(
            (
                quantity.value,
                level,
                K,
                target,
                design.t,
                design.p_d,
                th.attainable,
                j,
                th.erp_dbw if th.attainable else None,
                th.log_pf / LN10 if th.attainable else None,
                th.d if th.attainable else None,
                th.log_sup / LN10,
                math.exp(th.log_sup),
                th.pf_over_pd if th.attainable else None,
                th.dlog_per_db if th.attainable else None,
                th.ill_conditioned,
            )
        )
    cols = (
        "quantity",
        "level",
        "K",
        "P_DL",
        "t",
        "p_d",
        "attainable",
        "x_db",
        "erp_dbw",
        "log10_pf",
        "d",
        "log10_sup",
        "sup",
        "pf_over_pd",
        "dlog_per_db",
        "ill_conditioned",
    )
    meta = make_meta(
        "jam-bound threshold",
        quantity=quantity.value,
        level=level,
        K=K,
        pdl=pdl_,
        pd=pd_,
        t=t_,
        **_system_meta(system),
    )
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    bad = sum(1 for r in rows if not r[6])
    note(f"jam-bound threshold: {len(rows)} design(s), {bad} unattainable", quiet)


@app.command()
@system_options
def table(
    which: Annotated[
        WhichTable, typer.Option("--which", help="Table 2.1 (ERP vs K, P_DL) or Table 1.1 (ERP and antenna).")
    ] = WhichTable.t21,
    level: Annotated[
        float,
        typer.Option(
            "--level", callback=_half_open_unit, help="N̄_ADL target as a fraction of N_T (report 0.01)."
        ),
    ] = 0.01,
    freq_hz: Annotated[
        float, typer.Option("--freq-hz", **_pos, help="Jammer frequency [assumption: 1.6 GHz, L band].")
    ] = 1.6e9,
    eta: Annotated[
        float,
        typer.Option("--eta", callback=_half_open_unit, help="Dish efficiency [assumption 0.55]."),
    ] = 0.55,
    bw_const: Annotated[
        float, typer.Option("--bw-const", **_pos, help="Beamwidth θ = k λ/D degrees [assumption k = 70].")
    ] = 70.0,
    system: JammingSystem = DEFAULT_SYSTEM,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Tables 2.1 and 1.1 recomputed, with the printed values, the deviation in dB and the report's
    internal inconsistencies flagged (t = 0 curves, N̄_ADL = 0.01 N_T)."""
    check_outputs(out)
    antenna = checked("--freq-hz", DishAntenna, freq_hz, eta, bw_const)
    base = {"level": level, **_system_meta(system)}
    if which is WhichTable.t21:
        rows21 = exp.table_2_1(system, level)
        rows = []
        for r in rows21:
            th = r.threshold
            rows.append(
                (
                    r.K,
                    r.pdl,
                    r.design.t,
                    r.design.p_d,
                    math.exp(th.log_pf) if th.attainable else None,
                    th.x_db if th.attainable else None,
                    th.erp_dbw if th.attainable else None,
                    ("> " if r.relation == ">" else "") + f"{r.printed_dbw:g}",
                    r.deviation_db,
                    r.tolerance_db,
                    r.status,
                    math.exp(th.log_sup),
                    th.pf_over_pd if th.attainable else None,
                )
            )
        cols = (
            "K",
            "P_DL",
            "t",
            "p_d",
            "p_f",
            "x_db",
            "erp_dbw",
            "printed_erp_dbw",
            "deviation_db",
            "tolerance_db",
            "status",
            "sup_nadl",
            "pf_over_pd",
        )
        meta = make_meta("jam-bound table", which="2.1", source="ATC-10 (1972) Table 2.1", **base)
        agree = sum(r.status in ("agrees", "unattainable-as-printed") for r in rows21)
        msg = f"Table 2.1: {agree}/{len(rows21)} rows agree with the printed values within tolerance"
    else:
        rows11 = checked("--freq-hz/--eta/--bw-const", exp.table_1_1, system, antenna, level)
        printed21 = {(r.K, r.pdl): r for r in exp.table_2_1(system, level)}
        rows = []
        for r in rows11:
            flags = r.flags()
            in21 = {p: v for (k, p), v in printed21.items() if k == r.K and v.relation == "="}
            if in21 and not any(v.printed_dbw == r.printed["erp_dbw"] for v in in21.values()):
                flags.append(
                    "Table 2.1 prints "
                    + ", ".join(f"{v.printed_dbw:g} dBW for P_DL {p:g}" for p, v in in21.items())
                    + f", not {r.printed['erp_dbw']:g}"
                )
            cap = r.erp_by_pdl.get(r.caption_pdl)
            rows.append(
                (
                    r.K,
                    *[r.erp_by_pdl[p] for p in exp.TABLE_1_1_PDL],
                    r.printed["erp_dbw"],
                    None if cap is None else cap - r.printed["erp_dbw"],
                    ";".join(f"{p:g}" for p in r.matches),
                    r.printed["rf_dbw"],
                    r.inverse["gain_dbi"],
                    r.inverse["diameter_ft"],
                    r.printed["diameter_ft"],
                    r.inverse["beamwidth_deg"],
                    r.printed["beamwidth_deg"],
                    r.forward["rf_dbw"],
                    r.forward["beamwidth_deg"],
                    "; ".join(flags),
                )
            )
        cols = (
            "K",
            *[f"erp_dbw_pdl_{p:g}" for p in exp.TABLE_1_1_PDL],
            "printed_erp_dbw",
            "deviation_caption_db",
            "matching_pdl",
            "printed_rf_dbw",
            "gain_dbi",
            "diameter_ft",
            "printed_diameter_ft",
            "beamwidth_deg",
            "printed_beamwidth_deg",
            "rf_dbw_from_diameter",
            "beamwidth_deg_from_diameter",
            "flags",
        )
        anchor = exp.text_anchor_k1(antenna)
        meta = make_meta(
            "jam-bound table",
            which="1.1",
            source="ATC-10 (1972) Table 1.1",
            caption_pdl=rows11[0].caption_pdl,
            antenna={
                "freq_hz": freq_hz,
                "eta": eta,
                "bw_const": bw_const,
                "model": "G = eta (pi D / lambda)^2, theta = k lambda / D",
            },
            text_anchor_k1=anchor,
            chains="diameter_ft, beamwidth_deg: inverse chain from the printed ERP and rf power; "
            "*_from_diameter: forward chain from the printed ERP and diameter",
            **base,
        )
        msg = (
            f"Table 1.1: {sum(1 for r in rows if r[-1])} of {len(rows)} rows carry a flagged inconsistency; "
            f"text anchor (33 dBW, 30 W) gives {anchor['beamwidth_deg']:.1f} deg vs printed 20"
        )
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(msg, quiet)


@app.command()
def design(
    K: Annotated[int, typer.Option("--K", min=1, help="Tracking length K.")] = 10,
    pdl: Annotated[
        float | None, typer.Option("--pdl", help="Target P_DL in (0, 1): solve for p_d (or for t with --pd).")
    ] = None,
    pd: Annotated[
        float | None, typer.Option("--pd", help="Pulse detection probability p_d in (0, 1).")
    ] = None,
    t: Annotated[float | None, typer.Option("--t", help="Rule parameter t in [0, 1) (default 0).")] = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """The first-stage design (App. A): p_d from (K, P_DL, t), P_DL from (K, p_d, t), or t from (K, p_d, P_DL).

    Also the Chernoff parameter ν* = ln[q(1−t)/(t(1−q))] and the exponent E(t, q) = D(t‖q), q = p_d^4.
    """
    check_outputs(out)
    for name, v in (("--pdl", pdl), ("--pd", pd)):
        if v is not None and not 0.0 < v < 1.0:
            raise typer.BadParameter(f"{v:g} is not in the open interval (0, 1)", param_hint=name)
    if t is not None and not 0.0 <= t < 1.0:
        raise typer.BadParameter(f"{t:g} is not in [0, 1)", param_hint="--t")
    if K == 1 and t not in (None, 0.0):
        raise typer.BadParameter("with --K 1 the only meaningful rule is t = 0", param_hint="--t")
    if pd is not None and pdl is not None:
        if t is not None:
            raise typer.BadParameter(
                "give two of --pd, --pdl, --t; t is solved from --pd and --pdl", param_hint="--t"
            )
        from motionsig_cli.surveillance.jamming import t_for

        d = JammingDesign(K, pd, checked("--pdl", t_for, K, pd, pdl))
        solved = "t"
    elif pd is not None:
        d = checked("--t", JammingDesign, K, pd, t or 0.0)
        solved = "P_DL"
    elif pdl is not None:
        d = checked("--pdl", JammingDesign.from_pdl, K, pdl, t or 0.0)
        solved = "p_d"
    else:
        raise typer.BadParameter(
            "give --pdl (solve p_d), --pd (compute P_DL) or both (solve t)", param_hint="--pdl"
        )
    row = (K, d.t, d.p_d, d.q, d.pdl, d.nu, d.exponent, solved)
    meta = make_meta(
        "jam-bound design",
        K=K,
        pdl=pdl,
        pd=pd,
        t=t,
        rule="declare present iff more than K t of the K lists are non-empty (A.11)",
    )
    emit(
        Table(columns=("K", "t", "p_d", "q", "P_DL", "nu", "exponent", "solved"), rows=[row], meta=meta),
        fmt.value,
        out,
    )
    note(f"jam-bound design: solved {solved}; P_DL = {d.pdl:.10g}", quiet)


@app.command()
def antenna(
    erp_dbw: Annotated[float, typer.Option("--erp-dbw", help="Jammer ERP per satellite [dBW].")] = 33.0,
    rf_dbw: Annotated[float | None, typer.Option("--rf-dbw", help="rf power [dBW] (inverse chain).")] = None,
    rf_w: Annotated[
        float | None, typer.Option("--rf-w", callback=positive, help="rf power [W] (inverse chain).")
    ] = None,
    diameter_ft: Annotated[
        float | None,
        typer.Option("--diameter-ft", callback=positive, help="Dish diameter [ft] (forward chain)."),
    ] = None,
    freq_hz: Annotated[
        float, typer.Option("--freq-hz", **_pos, help="Frequency [Hz] [assumption 1.6 GHz].")
    ] = 1.6e9,
    eta: Annotated[
        float,
        typer.Option("--eta", callback=_half_open_unit, help="Dish efficiency [assumption 0.55]."),
    ] = 0.55,
    bw_const: Annotated[
        float, typer.Option("--bw-const", **_pos, help="θ = k λ/D degrees [assumption k = 70].")
    ] = 70.0,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """The jammer's dish: from the ERP and one of rf power or diameter, the rest (Table 1.1 columns)."""
    check_outputs(out)
    given = [
        n
        for n, v in (("--rf-dbw", rf_dbw), ("--rf-w", rf_w), ("--diameter-ft", diameter_ft))
        if v is not None
    ]
    if len(given) != 1:
        raise typer.BadParameter(
            "give exactly one of --rf-dbw, --rf-w, --diameter-ft",
            param_hint=given[1] if len(given) > 1 else "--rf-dbw",
        )
    if not math.isfinite(erp_dbw):
        raise typer.BadParameter("must be finite", param_hint="--erp-dbw")
    if rf_dbw is not None and not math.isfinite(rf_dbw):
        raise typer.BadParameter("must be finite", param_hint="--rf-dbw")
    dish = checked("--freq-hz", DishAntenna, freq_hz, eta, bw_const)
    rf = rf_dbw if rf_dbw is not None else 10 * math.log10(rf_w) if rf_w is not None else None
    tx = checked(
        given[0],
        jammer_antenna,
        erp_dbw,
        rf_dbw=rf,
        diameter_m=None if diameter_ft is None else diameter_ft * FOOT_M,
        antenna=dish,
    )
    cols = ("erp_dbw", "rf_dbw", "rf_w", "gain_dbi", "diameter_ft", "diameter_m", "beamwidth_deg")
    row = (tx.erp_dbw, tx.rf_dbw, tx.rf_w, tx.gain_dbi, tx.diameter_ft, tx.diameter_m, tx.beamwidth_deg)
    meta = make_meta(
        "jam-bound antenna",
        freq_hz=freq_hz,
        eta=eta,
        bw_const=bw_const,
        given=given[0],
        model="ERP = P_rf + G, G = eta (pi D / lambda)^2, theta = k lambda / D",
    )
    emit(Table(columns=cols, rows=[row], meta=meta), fmt.value, out)
    note(
        f"jam-bound antenna: G = {tx.gain_dbi:.2f} dBi, D = {tx.diameter_ft:.2f} ft, θ = {tx.beamwidth_deg:.1f}°",
        quiet,
    )
