"""``motionsig jam-bound``: jamming-vulnerability bounds of the satellite surveillance link (Section 2 and
Appendices A–D of ATC-10: Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972; Tables 1.1 and
2.1; Figs 2.1–2.16).

All outputs are fractions of the aircraft population N_T (the report never gives N_T). The default
``--convention corrected`` evaluates p_f with the re-derived √(P₀Bτ/(2J)) (eq D.17);
``--convention report`` uses the misprinted ½√(P₀Bτ/J) of eqs 2.8.1/2.8.3 for N̄_FL with K > 1, the
only place the report prints it (a 3.01 dB shift; no table depends on it).

Each command parses its options, builds the configurations of :mod:`motionsig_cli.atc10.jamming`
(which check every value), calls one function there and writes the table it returns. NumPy and SciPy are
imported only when a command runs, matplotlib only when a figure is asked for.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from typing import TYPE_CHECKING, Annotated, Any

import typer

from motionsig_cli.cli.common import Output, checked, choices, command, float_list

if TYPE_CHECKING:
    from motionsig_cli.atc10.jamming import JamResult

app = typer.Typer(
    help="Jamming bounds of the air-to-satellite-to-ground surveillance link (ATC-10 §2): "
    "N̄_FL / N̄_ADL curves, the jammer power that disables the system, Tables 1.1 and 2.1.\n\n"
    "Source: ATC-10 (Schneider, Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972), Section 2 and "
    "Appendices A–D.",
    no_args_is_help=True,
)

C_MPH = 299_792_458.0 / 0.44704  # surveillance.jamming.C_MPH (that module imports SciPy; a test checks)

# Configuration fields whose option is not ``--`` + the field's name.
OPTIONS = {
    "bandwidth_hz": "--B",
    "alpha_s": "--alpha",
    "beta_s": "--beta",
    "pf_form": "--convention",
    "n_alpha": "--B/--alpha",
    "n_beta": "--B/--beta",
    "n_v": "--B/--vmax-mph/--alpha/--c-mph",
    "p_d": "--pd",
    "efficiency": "--eta",
    "beamwidth_const_deg": "--bw-const",
    "antenna": "--freq-hz/--eta/--bw-const",
}


Convention = choices(
    "Convention",
    "Which p_f formula: the re-derived D.17 or the misprinted 2.8.1/2.8.3.",
    "corrected",
    "report",
)
QuantityChoice = choices("QuantityChoice", "Which bound.", "nfl", "nadl", "both")
Bound = choices("Bound", "Which bound a threshold is solved for.", "nfl", "nadl")
WhichTable = choices("WhichTable", "Which table of the report.", t21="2.1", t11="1.1")


# --- shared options -------------------------------------------------------------------------------

_SYSTEM: dict[str, tuple[Any, Any]] = {  # parameter: (annotation, default)
    "B": (Annotated[float, typer.Option("--B", help="Bandwidth B [Hz] (report: 10 MHz).")], 1.0e7),
    "alpha": (Annotated[float, typer.Option("--alpha", help="Signature period α [s] (report: 1 s).")], 1.0),
    "beta": (
        Annotated[
            float, typer.Option("--beta", help="Largest differential satellite delay β [s] (report: 24 ms).")
        ],
        0.024,
    ),
    "vmax_mph": (
        Annotated[float, typer.Option("--vmax-mph", help="Largest aircraft speed v [mph] (report: 600).")],
        600.0,
    ),
    "c_mph": (
        Annotated[
            float,
            typer.Option(
                "--c-mph",
                help="Speed of light [mph] (assumed: the exact 299 792 458 m/s; the report does not say).",
            ),
        ],
        C_MPH,
    ),
    "energy_j": (
        Annotated[float, typer.Option("--energy-j", help="Signature energy E = P₀τ [J] (report: 10 mJ).")],
        0.01,
    ),
    "airborne_frac": (
        Annotated[float, typer.Option("--airborne-frac", help="N/N_T airborne, in (0, 1) (report: 0.1).")],
        0.1,
    ),
    "convention": (
        Annotated[
            Convention,
            typer.Option(
                "--convention",
                help="corrected: p_f from √(P₀Bτ/2J) (App. D re-derived); report: the misprinted ½√(P₀Bτ/J) "
                "of eqs 2.8.1/2.8.3 for N̄_FL with K > 1.",
            ),
        ],
        Convention.corrected,
    ),
}


def system_options(fn: Callable[..., None]) -> Callable[..., None]:
    """Give a command the shared system options (--B … --convention); it receives one ``system`` (a
    :class:`~motionsig_cli.surveillance.jamming.JammingSystem`, which checks them).

    The wrapper's signature is the command's own with ``system`` replaced by the options (inserted before
    ``output``), which is what :func:`~motionsig_cli.cli.common.command` and typer read.
    """
    sig = inspect.signature(fn, eval_str=True)  # the module uses postponed annotations
    own = [p for p in sig.parameters.values() if p.name != "system"]
    added = [
        inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=default, annotation=annotation)
        for name, (annotation, default) in _SYSTEM.items()
    ]

    @functools.wraps(fn)
    def wrapper(**kwargs: Any) -> None:
        from motionsig_cli.atc10.jamming import PF_FORM
        from motionsig_cli.surveillance.jamming import JammingSystem

        v = {name: kwargs.pop(name) for name in _SYSTEM}
        system = JammingSystem(
            bandwidth_hz=v["B"],
            alpha_s=v["alpha"],
            beta_s=v["beta"],
            vmax_mph=v["vmax_mph"],
            c_mph=v["c_mph"],
            energy_j=v["energy_j"],
            airborne_frac=v["airborne_frac"],
            pf_form=PF_FORM[v["convention"].value],
        )
        return fn(system=system, **kwargs)

    at = next(i for i, p in enumerate(own) if p.name == "output")
    wrapper.__signature__ = sig.replace(parameters=[*own[:at], *added, *own[at:]])  # type: ignore[attr-defined]
    wrapper.__annotations__ = {p.name: p.annotation for p in wrapper.__signature__.parameters.values()}  # type: ignore[attr-defined]
    return wrapper


def _floats(text: str | None, option: str) -> tuple[float, ...] | None:
    """A comma-separated list of numbers, in order and without repeats (-0 read as 0); None passes."""
    if text is None:
        return None
    return tuple(dict.fromkeys(v + 0.0 for v in checked(option, float_list, text, what=option)))


def _command(
    *, plot: bool = False, system: bool = True
) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """Declare a subcommand: the output options (``--plot`` with ``plot``), the option names of
    :data:`OPTIONS` in errors and, with ``system``, the shared system options (:func:`system_options`)."""

    def decorate(fn: Callable[..., None]) -> Callable[..., None]:
        return app.command()(command(plot=plot, options=OPTIONS)(system_options(fn) if system else fn))

    return decorate


def _write(output: Output, result: JamResult) -> None:
    """The table (stdout or --out) and its summary line (stderr)."""
    output.emit(result.table)
    output.note(result.summary)


KOpt = Annotated[int, typer.Option("--K", help="Tracking length K in pulses, ≥ 1.")]
PdOpt = Annotated[
    str | None,
    typer.Option(
        "--pd", help="Pulse detection probabilities p_d in (0, 1) instead of --pdl (P_DL is computed)."
    ),
]
LevelOpt = Annotated[
    float, typer.Option("--level", help="Target N̄/N_T in (0, 1] (report: N̄_ADL = 0.01 N_T).")
]
FreqOpt = Annotated[
    float,
    typer.Option(
        "--freq-hz", help="Jammer frequency [Hz] (assumed: 1.6 GHz, L band; the report does not say)."
    ),
]
EtaOpt = Annotated[float, typer.Option("--eta", help="Dish aperture efficiency η in (0, 1] (assumed: 0.55).")]
BwOpt = Annotated[float, typer.Option("--bw-const", help="Beamwidth θ = k λ/D degrees (assumed: k = 70).")]


# --- commands -------------------------------------------------------------------------------------


@_command(plot=True)
def curves(
    figure: Annotated[
        str | None, typer.Option("--figure", help="A figure preset of the report: 2.1 to 2.16 (Fig. 2.N).")
    ] = None,
    quantity: Annotated[
        QuantityChoice | None,
        typer.Option("--quantity", help="Which bound (default: both, or the figure's)."),
    ] = None,
    K: Annotated[int | None, typer.Option("--K", help="Tracking length K in pulses (default 10).")] = None,
    pdl: Annotated[
        str | None, typer.Option("--pdl", help="Design P_DL values, comma-separated (default 0.88,0.999).")
    ] = None,
    t: Annotated[
        str | None,
        typer.Option("--t", help="Rule parameters t in [0, 1) (default 0,0.1,0.2,0.3,0.5; 0 for K = 1)."),
    ] = None,
    pd: PdOpt = None,
    x_min: Annotated[
        float | None, typer.Option("--x-min", help="Smallest 10 log10(J/P₀Bτ) [dB] (default by K).")
    ] = None,
    x_max: Annotated[float | None, typer.Option("--x-max", help="Largest 10 log10(J/P₀Bτ) [dB].")] = None,
    step: Annotated[float, typer.Option("--step", help="Grid step [dB].")] = 0.05,
    system: Any = None,
    *,
    output: Output,
) -> None:
    """N̄_FL/N_T and N̄_ADL/N_T against 10 log10(J/P₀Bτ) (eqs 2.7.3, 2.8.3, 2.8.4; Figs 2.1–2.16).

    One row per (quantity, design, x). log10_value is exact even where the value underflows a
    double (value is then empty): the bounds reach 10^-222 and below.
    """
    from motionsig_cli.atc10 import jamming as exp

    output.check()
    config = exp.CurvesConfig(
        figure=figure,
        quantity=None if quantity is None else quantity.value,
        K=K,
        pdl=_floats(pdl, "--pdl"),
        pd=_floats(pd, "--pd"),
        t=_floats(t, "--t"),
        x_min=x_min,
        x_max=x_max,
        step=step,
        system=system,
    )
    result = exp.curves_table(config)
    if output.plot is not None:
        from motionsig_cli.plotting import jamming_figure

        output.figure(jamming_figure(result.panels, title=result.title))
    _write(output, result)


@_command()
def threshold(
    quantity: Annotated[
        Bound, typer.Option("--quantity", help="Which bound reaches the level.")
    ] = Bound.nadl,
    level: LevelOpt = 0.01,
    K: KOpt = 10,
    pdl: Annotated[str | None, typer.Option("--pdl", help="Design P_DL values (default 0.88,0.999).")] = None,
    t: Annotated[str, typer.Option("--t", help="Rule parameters t in [0, 1).")] = "0",
    pd: PdOpt = None,
    system: Any = None,
    *,
    output: Output,
) -> None:
    """The jammer power at which a bound reaches a level (eqs 2.7.3, 2.8.3, 2.8.4 solved for the jammer
    power), with the supremum and conditioning.

    attainable = false when the level is at or above the bound's supremum: no jammer power reaches it
    (the report's "> 130 dBW"). ill_conditioned = true when p_f* > 0.9 p_d (K = 1000).
    """
    from motionsig_cli.atc10 import jamming as exp

    output.check()
    config = exp.ThresholdConfig(
        quantity=quantity.value,
        level=level,
        K=K,
        pdl=_floats(pdl, "--pdl"),
        pd=_floats(pd, "--pd"),
        t=_floats(t, "--t") or (0.0,),
        system=system,
    )
    _write(output, exp.threshold_table(config))


@_command()
def table(
    which: Annotated[
        WhichTable, typer.Option("--which", help="Table 2.1 (ERP vs K, P_DL) or Table 1.1 (ERP and antenna).")
    ] = WhichTable.t21,
    level: Annotated[
        float, typer.Option("--level", help="N̄_ADL target as a fraction of N_T, in (0, 1] (report 0.01).")
    ] = 0.01,
    freq_hz: FreqOpt = 1.6e9,
    eta: EtaOpt = 0.55,
    bw_const: BwOpt = 70.0,
    system: Any = None,
    *,
    output: Output,
) -> None:
    """Tables 2.1 and 1.1 recomputed, with the printed values, the deviation in dB and the report's
    internal inconsistencies flagged (t = 0 curves, N̄_ADL = 0.01 N_T)."""
    from motionsig_cli.atc10 import jamming as exp
    from motionsig_cli.surveillance.antenna import DishAntenna

    output.check()
    config = exp.TableConfig(which.value, level, DishAntenna(freq_hz, eta, bw_const), system)
    _write(output, exp.report_table(config))


@_command(system=False)
def design(
    K: KOpt = 10,
    pdl: Annotated[
        float | None, typer.Option("--pdl", help="Target P_DL in (0, 1): solve for p_d (or for t with --pd).")
    ] = None,
    pd: Annotated[
        float | None, typer.Option("--pd", help="Pulse detection probability p_d in (0, 1).")
    ] = None,
    t: Annotated[float | None, typer.Option("--t", help="Rule parameter t in [0, 1) (default 0).")] = None,
    *,
    output: Output,
) -> None:
    """The first-stage design (App. A): p_d from (K, P_DL, t), P_DL from (K, p_d, t), or t from (K, p_d, P_DL).

    Also the Chernoff parameter ν* = ln[q(1−t)/(t(1−q))] and the exponent E(t, q) = D(t‖q), q = p_d^4.
    """
    from motionsig_cli.atc10 import jamming as exp

    output.check()
    _write(output, exp.design_table(K, pdl, pd, t))


@_command(system=False)
def antenna(
    erp_dbw: Annotated[float, typer.Option("--erp-dbw", help="Jammer ERP per satellite [dBW].")] = 33.0,
    rf_dbw: Annotated[float | None, typer.Option("--rf-dbw", help="rf power [dBW] (inverse chain).")] = None,
    rf_w: Annotated[float | None, typer.Option("--rf-w", help="rf power [W] (inverse chain).")] = None,
    diameter_ft: Annotated[
        float | None, typer.Option("--diameter-ft", help="Dish diameter [ft] (forward chain).")
    ] = None,
    freq_hz: FreqOpt = 1.6e9,
    eta: EtaOpt = 0.55,
    bw_const: BwOpt = 70.0,
    *,
    output: Output,
) -> None:
    """The jammer's dish: from the ERP and one of rf power or diameter, the rest (Table 1.1 columns)."""
    from motionsig_cli.atc10 import jamming as exp
    from motionsig_cli.surveillance.antenna import DishAntenna

    output.check()
    dish = DishAntenna(freq_hz, eta, bw_const)
    _write(output, exp.antenna_table(erp_dbw, rf_dbw=rf_dbw, rf_w=rf_w, diameter_ft=diameter_ft, dish=dish))
