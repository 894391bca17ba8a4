"""``motionsig mac-roc``: detection under multiple-access noise — ROC bounds, the exact and Monte Carlo
ROC, the Gaussian comparison, exponents and time–bandwidth (ATC-10, Schneider, Stiglitz & Eckberg, MIT
Lincoln Laboratory, 1972: §3, Apps E–F, Figs 3.2–3.11).

N aircraft send unit-energy signatures of duration τ once per period α; at the matched filter of one
of them the other N − 1 overlap the window with probability q = 2τ/α, each adding an amplitude from a
density C of second moment b = 1/(3ℓ²). The detector compares y = (signal 1 or 0) + n with θ ∈ (0, 1).

Each command parses its options into a configuration of :mod:`motionsig_cli.atc10.mac_roc` (which
checks every value), calls one function there and writes its outcome.
"""

from __future__ import annotations

import contextlib
import functools
import inspect
from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, Annotated, Any

import typer

from motionsig_cli.cli import common
from motionsig_cli.cli.common import DEFAULT_SEED_VALUE, Output, Parallel, SeedOpt, choices, command

if TYPE_CHECKING:
    from motionsig_cli.atc10.mac_roc import Codes, Outcome

app = typer.Typer(
    help="Detection under multiple-access noise (ATC-10 §3): ROC bounds (3.5.13)-(3.5.14), the exact and "
    "Monte Carlo ROC, the Gaussian ROC_g, the exponent Exp(Exp_g) and the time-bandwidth relation.",
    no_args_is_help=True,
)

# option defaults (the core's values: atc10.mac_roc REPORT_TAU_OVER_ALPHA and FIG32_B; a test checks)
REPORT_TAU_OVER_ALPHA = 2e-5
FIG32_B = 1.0 / 3.0
CODE_OPTIONS = {"ref": "--code", "family": "--code"}  # the psk density's codes come from --code


LowerVariant = choices(
    "LowerVariant",
    "Which lower bound: the report's (3.5.14, corrected sign) or Gallager's tighter form.",
    "report",
    "gallager",
)
Interferers = choices(
    "Interferers",
    "psk density: interferers with fresh random codes, or members of the reference code's family.",
    "random",
    "family",
)
GaussVar = choices(
    "GaussVar",
    "Variance of ROC_g: (N − 1)qb as in (3.4.13), or the report's N·q·b (Theorem 3.1).",
    n1="N-1",
    n="N",
)


# --- option parsing -------------------------------------------------------------------------------


def _number(text: str, option: str) -> float:
    """A number such as 100000 or 1e5 (the configuration checks its range)."""
    try:
        return float(text)
    except ValueError:
        raise typer.BadParameter(f"expected a number; got {text!r}", param_hint=option) from None


def _numbers(text: str, option: str) -> tuple[float, ...]:
    try:
        return tuple(common.float_list(text, what=option))
    except ValueError as exc:
        raise typer.BadParameter(str(exc), param_hint=option) from None


def _thetas(text: str) -> tuple[float, ...]:
    """``start:stop:step`` (the core builds the grid) or a comma-separated list."""
    if ":" not in text:
        return _numbers(text, "--theta")
    from motionsig_cli.atc10.mac_roc import theta_grid

    parts = text.split(":")
    if len(parts) != 3:
        raise typer.BadParameter(f"expected start:stop:step; got {text!r}", param_hint="--theta")
    a, b, s = (_number(p, "--theta") for p in parts)
    return tuple(theta_grid(a, b, s).tolist())


def _grid(text: str | None, name: str, *, log: bool) -> tuple[float, ...] | None:
    """``start:stop:count`` (n points, log-spaced when ``log``; the core builds it) or a list."""
    if text is None:
        return None
    option = "--" + name.replace("_", "-")
    if ":" not in text:
        return _numbers(text, option)
    from motionsig_cli.atc10.mac_roc import value_grid

    parts = text.split(":")
    if len(parts) != 3:
        raise typer.BadParameter(f"expected start:stop:count; got {text!r}", param_hint=option)
    a, b = (_number(p, option) for p in parts[:2])
    try:
        n = int(parts[2])
    except ValueError:
        raise typer.BadParameter(f"expected start:stop:count; got {text!r}", param_hint=option) from None
    return tuple(value_grid(name, a, b, n, log=log).tolist())


def _code_files(specs: list[str]) -> tuple[tuple[str, Codes], ...]:
    """The codes of each ``file:PATH`` (or ``file:-``) code: a ``code,chip,value`` table written by
    ``motionsig encode``, read once (stdin cannot be read twice)."""
    from motionsig_cli.signals.code_sets import load_codes

    out: dict[str, Codes] = {}
    for spec in specs:
        key = spec.strip()
        if key.lower().startswith("file:") and key not in out:
            out[key] = tuple(tuple(int(v) for v in row) for row in load_codes(key[5:]).codes)
    return tuple(out.items())


def _contours(
    density: str | None,
    ell: str | None,
    b: str | None,
    N: str,
    tau_over_alpha: float,
    theta: str | None,
    code: str = "mseq31",
    interferers: Interferers = Interferers.random,
) -> dict[str, Any]:
    """The fields of :class:`~motionsig_cli.atc10.mac_roc.Contours` (``theta`` None: no grid)."""
    from motionsig_cli.surveillance.densities import density_kind

    chip_level = density is not None and density_kind(density).chip_level
    fields: dict[str, Any] = dict(
        density=density,
        ell=None if ell is None else _numbers(ell, "--ell"),
        b=None if b is None else _numbers(b, "--b"),
        N=_number(N, "--N"),
        tau_over_alpha=tau_over_alpha,
        code=code,
        interferers=interferers.value,
        code_files=_code_files([code]) if chip_level else (),
    )
    if theta is not None:
        fields["theta"] = _thetas(theta)
    return fields


def _write(output: Output, result: Outcome) -> None:
    """Warnings, the figure (with --plot), the table and the summary line."""
    for line in result.warnings:
        output.note(line)
    if output.plot is not None and result.plot is not None:
        from motionsig_cli import plotting

        name, kwargs = result.plot
        output.figure(getattr(plotting, name)(**kwargs))
    output.emit(result.table)
    output.note(result.summary)


DensityOpt = Annotated[
    str,
    typer.Option(
        "--density",
        help="Amplitude density C: two-point (C2), uniform (C1), triangular (C3), gaussian (C4) [C1, C3, C4 "
        "assumed], laplace, arcsine, psk (chip level, --code).",
    ),
]
EllOpt = Annotated[
    str | None,
    typer.Option("--ell", help="Contour labels ℓ = 1/√(3b), comma-separated (default 4,6,8,10,12)."),
]
BOpt = Annotated[str | None, typer.Option("--b", help="Second moments b instead of --ell.")]
NOpt = Annotated[str, typer.Option("--N", help="Number of aircraft N (integer >= 2; 1e5 allowed).")]
TauOpt = Annotated[
    float, typer.Option("--tau-over-alpha", help="Signature duty τ/α in (0, 0.5) (report 2e-5).")
]
ThetaOpt = Annotated[str, typer.Option("--theta", help="Thresholds: start:stop:step or a list, in (0, 1).")]
CodeOpt = Annotated[
    str,
    typer.Option(
        "--code",
        help="psk reference code: mseq31, barker13, gold:45,75:3, mseq:45, a +-/01 string, or file:PATH "
        "(a `motionsig encode` table: the first code is the reference, the others the family).",
    ),
]
InterferersOpt = Annotated[
    Interferers,
    typer.Option("--interferers", help="psk interferer codes: random ±1 codes or the Gold family."),
]
VariantOpt = Annotated[
    LowerVariant,
    typer.Option(
        "--lower-variant", help="Lower bound: report (3.5.14, sign corrected) or gallager (tighter)."
    ),
]
BoundsDensityOpt = Annotated[
    str | None,
    typer.Option("--density", help="Amplitude density (as for the other subcommands; default two-point)."),
]


INJECTED: Mapping[str, Any] = MappingProxyType({})  # the default of ``contour``: contour_options sets it


def contour_options(
    *, theta: str = "0.01:0.99:0.01", density: tuple[Any, str | None] = (DensityOpt, "uniform")
) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """Give a command the contour options --density, --ell, --b, --N, --tau-over-alpha and --theta (with
    these ``theta`` and ``density`` (annotation, default)); it receives them as one dict ``contour`` of the
    raw values, keyed as the parameters of :func:`_contours`.

    The wrapper's signature is the command's own with ``contour`` replaced by the six options (in its
    place), which is what :func:`~motionsig_cli.cli.common.command` and typer read.
    """
    options: dict[str, tuple[Any, Any]] = {
        "density": density,
        "ell": (EllOpt, None),
        "b": (BOpt, None),
        "N": (NOpt, "100000"),
        "tau_over_alpha": (TauOpt, REPORT_TAU_OVER_ALPHA),
        "theta": (ThetaOpt, theta),
    }

    def decorate(fn: Callable[..., None]) -> Callable[..., None]:
        sig = inspect.signature(fn, eval_str=True)  # the module uses postponed annotations
        own = list(sig.parameters.values())
        at = next(i for i, p in enumerate(own) if p.name == "contour")
        added = [
            inspect.Parameter(
                "density_name" if name == "density" else name,
                inspect.Parameter.POSITIONAL_OR_KEYWORD,
                default=default,
                annotation=annotation,
            )
            for name, (annotation, default) in options.items()
        ]

        @functools.wraps(fn)
        def wrapper(**kwargs: Any) -> None:
            contour = {name: kwargs.pop("density_name" if name == "density" else name) for name in options}
            return fn(contour=contour, **kwargs)

        wrapper.__signature__ = sig.replace(parameters=[*own[:at], *added, *own[at + 1 :]])  # type: ignore[attr-defined]
        wrapper.__annotations__ = {p.name: p.annotation for p in wrapper.__signature__.parameters.values()}  # type: ignore[attr-defined]
        return wrapper

    return decorate


@app.command()
@command(parallel=True, options=CODE_OPTIONS)
@contour_options(density=(BoundsDensityOpt, None))
def bounds(
    figure: Annotated[str | None, typer.Option("--figure", help="Fig. 3.3 (C1) … 3.6 (C4) settings.")] = None,
    contour: Mapping[str, Any] = INJECTED,
    at_pd: Annotated[
        str | None,
        typer.Option(
            "--at-pd", help="Instead of a θ grid: p_f of each contour at these p_d (e.g. 0.9,0.99,0.999)."
        ),
    ] = None,
    lower_variant: VariantOpt = LowerVariant.report,
    with_exact: Annotated[bool, typer.Option("--exact", help="Add the exact ROC beside the bounds.")] = False,
    mc_trials: Annotated[
        str | None,
        typer.Option(
            "--montecarlo", help="Add a Monte Carlo ROC with this many trials (e.g. 1e6) per contour."
        ),
    ] = None,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    code: CodeOpt = "mseq31",
    interferers: InterferersOpt = Interferers.random,
    *,
    output: Output,
    parallel: Parallel,
) -> None:
    """Upper (3.5.13) and lower (3.5.14) ROC bounds per contour label ℓ (Figs 3.3–3.6).

    One row per (ℓ, θ): the Chernoff optima ρ*, γ*, exponents E_f, E_d, Gallager roots ρ₁, γ₁, and the
    bounds on p_f and p_m = 1 − p_d (log10 columns stay exact where a probability underflows).
    --workers/--scheduler/--checkpoint run the --montecarlo overlay.
    """
    output.check()
    engine = parallel.engine()
    if mc_trials is None and (parallel.scheduler is not None or parallel.checkpoint is not None):
        raise typer.BadParameter(
            "runs only the --montecarlo overlay; add --montecarlo N",
            param_hint="--scheduler" if parallel.scheduler is not None else "--checkpoint",
        )
    from motionsig_cli.atc10 import mac_roc as exp

    cfg = exp.BoundsConfig(
        figure=figure,
        at_pd=None if at_pd is None else _numbers(at_pd, "--at-pd"),
        lower_variant=lower_variant.value,
        exact=with_exact,
        montecarlo=None if mc_trials is None else _number(mc_trials, "--montecarlo"),
        seed=seed,
        **_contours(
            **{**contour, "theta": contour["theta"] if at_pd is None else None},
            code=code,
            interferers=interferers,
        ),
    )
    with contextlib.ExitStack() as bar:
        advance = bar.enter_context(common.progress_bar("bounds", len(cfg.models), output.quiet))

        def run(job: exp.MacRocJob) -> list[Any]:
            bar.close()  # the bounds are done: their bar goes before the Monte Carlo's
            return common.run_job(job, engine, "montecarlo", output.quiet)

        result = exp.bounds(cfg, advance, run)
    _write(output, result)


@app.command()
@command()
@contour_options()
def exact(
    contour: Mapping[str, Any] = INJECTED,
    lower_variant: VariantOpt = LowerVariant.report,
    *,
    output: Output,
) -> None:
    """The exact ROC (sum over the number of overlapping interferers; beyond the report) beside the bounds.

    inside = true when LB <= exact <= UB for both p_f and p_m (to 1e-9 relative).
    """
    output.check()
    from motionsig_cli.atc10 import mac_roc as exp

    cfg = exp.ExactConfig(lower_variant=lower_variant.value, **_contours(**contour))
    _write(output, exp.exact(cfg))


@app.command()
@command(parallel=True, options=CODE_OPTIONS)
@contour_options(theta="0.2,0.35,0.5,0.65,0.8")
def montecarlo(
    contour: Mapping[str, Any] = INJECTED,
    trials: Annotated[str, typer.Option("--trials", help="Trials (>= 1; 1e6 allowed).")] = "1000000",
    importance: Annotated[
        bool,
        typer.Option(
            "--importance", help="Importance sampling (tilted at the Chernoff optimum) for deep tails."
        ),
    ] = False,
    code: CodeOpt = "mseq31",
    interferers: InterferersOpt = Interferers.random,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    lower_variant: VariantOpt = LowerVariant.report,
    *,
    output: Output,
    parallel: Parallel,
) -> None:
    """The Monte Carlo ROC (Level A; chip level with --density psk) beside the exact ROC and the bounds.

    z_pf, z_pm = (estimate − exact)/SE where the exact ROC exists; inside = the estimate lies within
    [LB − 4 SE, UB + 4 SE] for both p_f and p_m. The trials run in blocks of 65 536 on --workers local
    processes or a Dask --scheduler; the result is the same bit for bit, and --checkpoint DIR resumes
    an interrupted run.
    """
    output.check()
    engine = parallel.engine()
    from motionsig_cli.atc10 import mac_roc as exp

    cfg = exp.MonteCarloConfig(
        trials=_number(trials, "--trials"),
        importance=importance,
        seed=seed,
        lower_variant=lower_variant.value,
        **_contours(**contour, code=code, interferers=interferers),
    )
    _write(output, exp.montecarlo(cfg, lambda job: common.run_job(job, engine, "trials", output.quiet)))


@app.command()
@command(options=CODE_OPTIONS)
@contour_options()
def gaussian(
    figure: Annotated[str | None, typer.Option("--figure", help="Fig. 3.8 settings.")] = None,
    contour: Mapping[str, Any] = INJECTED,
    gauss_variance: Annotated[
        GaussVar,
        typer.Option("--gauss-variance", help="ROC_g variance: (N-1)qb as (3.4.13), or the report's N q b."),
    ] = GaussVar.n1,
    *,
    output: Output,
) -> None:
    """ROC_g, the ROC of a Gaussian MAN of equal power (3.8.1)–(3.8.3), and its Chernoff bound (3.8.8).

    The power depends only on b (ℓ), not on the density's shape.
    """
    output.check()
    from motionsig_cli.atc10 import mac_roc as exp

    cfg = exp.GaussianConfig(
        figure=figure,
        gauss_variance=gauss_variance.value,
        **_contours(**contour),
    )
    _write(output, exp.gaussian(cfg))


@app.command()
@command()
def exponent(
    figure: Annotated[
        str | None, typer.Option("--figure", help="Fig. 3.9 (Exp vs N) or 3.10 (Exp vs Exp_g).")
    ] = None,
    expg: Annotated[
        str | None, typer.Option("--expg", help="Gaussian exponents Exp_g: list or start:stop:count.")
    ] = None,
    N: Annotated[
        str | None, typer.Option("--N", help="Numbers of aircraft: list or start:stop:count (log).")
    ] = None,
    tau_over_alpha: Annotated[
        str | None, typer.Option("--tau-over-alpha", help="τ/α values, comma-separated.")
    ] = None,
    *,
    output: Output,
) -> None:
    """Exp(Exp_g; N, τ/α): the quasi-optimal two-point exponent against the Gaussian one (3.8.16, Figs 3.9–3.10).

    Exp is the report's form (3.8.16); Exp_exact the closed form (3.7.24) without approximation.
    """
    output.check()
    from motionsig_cli.atc10 import mac_roc as exp

    cfg = exp.ExponentConfig(
        figure=figure,
        expg=_grid(expg, "expg", log=False),
        N=_grid(N, "N", log=True),
        tau_over_alpha=_numbers(tau_over_alpha, "--tau-over-alpha") if tau_over_alpha else None,
    )
    _write(output, exp.exponent(cfg))


@app.command()
@command()
def densities(
    figure: Annotated[
        str, typer.Option("--figure", help="Fig. 3.2 (the densities) or 3.7 (the C* component).")
    ] = "3.2",
    b: Annotated[
        float, typer.Option("--b", help="Second moment (Fig. 3.2 default 1/3: C1 = U(-1, 1)).")
    ] = FIG32_B,
    *,
    output: Output,
) -> None:
    """Fig. 3.2: C₁ … C₄ at equal second moment (impulses as weights); Fig. 3.7: n_ij(t) for C*."""
    output.check()
    from motionsig_cli.atc10 import mac_roc as exp

    _write(output, exp.densities(exp.DensitiesConfig(figure=figure, b=b)))


@app.command()
@command()
def bandwidth(
    code: Annotated[
        str,
        typer.Option("--code", help="Codes, ';'-separated: mseq31, barker13, gold:45,75:3, mseq:45, +-/01."),
    ] = "barker13;mseq31",
    curves: Annotated[
        bool, typer.Option("--curves", help="Fig. 3.11: the autocorrelations R(t) instead of the table.")
    ] = False,
    N: Annotated[
        str, typer.Option("--N", help="Number of aircraft N (integer >= 1; 1e5 allowed).")
    ] = "100000",
    alpha: Annotated[float, typer.Option("--alpha", help="Signature period α [s].")] = 1.0,
    tau_c: Annotated[float, typer.Option("--tau-c", help="Chip duration τ_c [s].")] = 1e-7,
    *,
    output: Output,
) -> None:
    """Sec. 3.9 / App. F: Zakai bandwidth W of each code (numerical, the report's (3.9.3), ideal 3/(4τ_c)),
    b for random-code interferers, E n² = (N−1)/(4αW) and the peak signal-to-interference ratio."""
    output.check()
    from motionsig_cli.atc10 import mac_roc as exp

    specs = code.split(";")
    cfg = exp.BandwidthConfig(
        code=tuple(specs),
        curves=curves,
        N=_number(N, "--N"),
        alpha=alpha,
        tau_c=tau_c,
        code_files=_code_files(specs),
    )
    _write(output, exp.bandwidth(cfg))


@app.command()
@command(plot=False)
def report(*, output: Output) -> None:
    """The numbers printed in ATC-10 §3 beside ours, with the deviation and the reason for each difference."""
    output.check()
    from motionsig_cli.atc10 import mac_roc as exp

    _write(output, exp.report())
