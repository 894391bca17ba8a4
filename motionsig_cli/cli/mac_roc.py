"""``motionsig mac-roc``: detection under multiple-access noise — ROC bounds, the exact and Monte Carlo
ROC, the Gaussian comparison, exponents and time–bandwidth (ATC-10 §3, Apps E–F, Figs 3.2–3.11).

N aircraft send unit-energy signatures of duration τ once per period α; at the matched filter of one
of them the other N − 1 overlap the window with probability q = 2τ/α, each adding an amplitude from a
density C of second moment b = 1/(3ℓ²). The detector compares y = (signal 1 or 0) + n with θ ∈ (0, 1).
"""

from __future__ import annotations

import functools
import math
from enum import StrEnum
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
    engine_session,
    float_list,
    make_engine,
    note,
    progress,
    save_figure,
)
from motionsig_cli.cli.io import Table, emit, make_meta
from motionsig_cli.engine import Engine
from motionsig_cli.experiments import mac_roc as exp
from motionsig_cli.surveillance import time_bandwidth as tb
from motionsig_cli.surveillance.amplitude import DENSITY_NAMES, REPORT_IDS, b_of_ell, density, ell_of_b
from motionsig_cli.surveillance.gaussian_roc import gaussian_power, gaussian_roc
from motionsig_cli.surveillance.multiple_access import MANModel
from motionsig_cli.surveillance.psk_amplitude import PSKAmplitude
from motionsig_cli.surveillance.quasi_optimal import (
    exp_of_gaussian_exponent,
    exp_of_gaussian_exponent_exact,
)
from motionsig_cli.surveillance.roc_bounds import RocBounds, chernoff, roc_bounds, theta_for_pd
from motionsig_cli.surveillance.roc_exact import EXACT_DENSITIES, MAX_MEAN_ACTIVE, exact_roc

app = typer.Typer(
    help="Detection under multiple-access noise (ATC-10 §3): ROC bounds (3.5.13)-(3.5.14), the exact and "
    "Monte Carlo ROC, the Gaussian ROC_g, the exponent Exp(Exp_g) and the time-bandwidth relation.",
    no_args_is_help=True,
)

LN10 = math.log(10.0)
MAX_TRIALS = 10**10


class LowerVariant(StrEnum):
    """Which lower bound: the report's (3.5.14, corrected sign) or Gallager's tighter form."""

    report = "report"
    gallager = "gallager"


class Interferers(StrEnum):
    """psk density: interferers with fresh random codes, or members of the reference code's family."""

    random = "random"
    family = "family"


class GaussVar(StrEnum):
    """Variance of ROC_g: (N − 1)qb as in (3.4.13), or the report's N·q·b (Theorem 3.1)."""

    n1 = "N-1"
    n = "N"


# --- option parsing -------------------------------------------------------------------------------


def _count(text: str, option: str, *, lo: int = 1) -> int:
    """An integer count given as 100000 or 1e5."""
    try:
        v = float(text)
    except ValueError:
        raise typer.BadParameter(f"expected a number; got {text!r}", param_hint=option) from None
    if not math.isfinite(v) or v != round(v):
        raise typer.BadParameter(f"{text!r} is not an integer", param_hint=option)
    if v < lo:
        raise typer.BadParameter(f"{text} is below {lo}", param_hint=option)
    if v > 1e15:
        raise typer.BadParameter(f"{text} is too large (at most 1e15)", param_hint=option)
    return int(v)


def _tau_over_alpha(value: float) -> float:
    if math.isfinite(value) and 0.0 < value < 1e-50:
        raise typer.BadParameter(f"{value:g} is below 1e-50 (q underflows the log-MGF)")
    if not (math.isfinite(value) and 0.0 < value < 0.5):
        raise typer.BadParameter(
            f"{value:g} is not in (0, 0.5): q = 2 tau/alpha must be < 1 (the window would overlap itself)"
        )
    return value


def _thetas(text: str, option: str = "--theta") -> np.ndarray:
    """``start:stop:step`` or a comma-separated list, every value in (0, 1)."""
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise typer.BadParameter(f"expected start:stop:step; got {text!r}", param_hint=option)
        try:
            a, b, s = (float(p) for p in parts)
        except ValueError:
            raise typer.BadParameter(f"expected start:stop:step; got {text!r}", param_hint=option) from None
        return checked(option, exp.theta_grid, a, b, s)
    values = checked(option, float_list, text, what="threshold")
    for v in values:
        if not 0.0 < v < 1.0:
            raise typer.BadParameter(f"{v:g} is not in the open interval (0, 1)", param_hint=option)
    return np.array(sorted(set(values)))


def _positive_list(text: str, option: str) -> list[float]:
    values = checked(option, float_list, text, what=option)
    for v in values:
        if not v > 0.0:
            raise typer.BadParameter(f"{v:g} is not > 0", param_hint=option)
    return list(dict.fromkeys(values))


@functools.cache
def _file_codes(text: str) -> np.ndarray:
    """The codes of a ``code,chip,value`` table written by ``motionsig encode`` (``file:PATH``, ``file:-``);
    read once per run (stdin cannot be read twice)."""
    from motionsig_cli.cli.encode import _read_codes

    _, codes, _ = _read_codes(text.strip()[5:])
    return codes.astype(float)


def _code(text: str, option: str = "--code") -> np.ndarray:
    """A ±1 code: mseq31, barker13, gold:P1,P2:INDEX, mseq:POLY, file:PATH (the first code of a
    ``motionsig encode`` table), or a literal +-/01 string."""
    t = text.strip()
    low = t.lower()
    if low.startswith("file:"):
        code = _file_codes(t)[0]
        if code.size > 4095:
            raise typer.BadParameter(f"a code needs 2 … 4095 chips; got {code.size}", param_hint=option)
        return code
    if low == "mseq31":
        return tb.MSEQ31.copy()
    if low == "barker13":
        return tb.BARKER13.copy()
    if low.startswith("gold:"):
        from motionsig_cli.signals.gf2 import parse_polynomial
        from motionsig_cli.signals.gold import gold_family

        parts = t[5:].split(":")
        polys = parts[0].split(",")
        if len(parts) != 2 or len(polys) != 2:
            raise typer.BadParameter(
                f"expected gold:P1,P2:INDEX (octal polynomials); got {text!r}", param_hint=option
            )
        p1 = checked(option, parse_polynomial, polys[0])
        p2 = checked(option, parse_polynomial, polys[1])
        idx, codes = checked(option, gold_family, p1, p2)
        try:
            k = int(parts[1])
        except ValueError:
            raise typer.BadParameter(
                f"member index {parts[1]!r} is not an integer", param_hint=option
            ) from None
        if k not in set(idx.tolist()):
            raise typer.BadParameter(f"member index {k} is not in {idx[0]}…{idx[-1]}", param_hint=option)
        return 1.0 - 2.0 * codes[list(idx).index(k)].astype(float)
    if low.startswith("mseq:"):
        from motionsig_cli.signals.gf2 import parse_polynomial, require_primitive
        from motionsig_cli.signals.lfsr import m_sequence

        poly = checked(option, parse_polynomial, t[5:])
        checked(option, require_primitive, poly)
        if poly.bit_length() - 1 > 12:
            raise typer.BadParameter("at most degree 12 (4095 chips)", param_hint=option)
        return 1.0 - 2.0 * m_sequence(poly).astype(float)
    if t and set(t) <= set("+-"):
        code = np.array([1.0 if ch == "+" else -1.0 for ch in t])
    elif t and set(t) <= set("01"):
        code = 1.0 - 2.0 * np.array([float(ch) for ch in t])
    else:
        raise typer.BadParameter(
            f"expected mseq31, barker13, gold:P1,P2:INDEX, mseq:POLY or a +-/01 string; got {text!r}",
            param_hint=option,
        )
    if not 2 <= code.size <= 4095:
        raise typer.BadParameter(f"a code needs 2 … 4095 chips; got {code.size}", param_hint=option)
    return code


def _family(text: str, ref: np.ndarray) -> np.ndarray:
    """The interferers' codes for ``--interferers family``: the other members of the Gold family, or the
    other codes of a ``file:`` table."""
    if text.strip().lower().startswith("file:"):
        family = _file_codes(text)
        family = family[~np.all(family == ref[None, :], axis=1)]
        if family.shape[0] == 0:
            raise typer.BadParameter(
                "the codes file holds no code besides the reference", param_hint="--interferers"
            )
        return family
    if not text.strip().lower().startswith("gold:"):
        raise typer.BadParameter(
            "--interferers family needs a gold:P1,P2:INDEX or file:PATH --code", param_hint="--interferers"
        )
    from motionsig_cli.signals.gf2 import parse_polynomial
    from motionsig_cli.signals.gold import gold_family

    polys = text.strip()[5:].split(":")[0].split(",")
    _, codes = gold_family(parse_polynomial(polys[0]), parse_polynomial(polys[1]))
    family = 1.0 - 2.0 * codes.astype(float)
    keep = ~np.all(family == ref[None, :], axis=1)
    return family[keep]


def _models(
    name: str,
    ells: str | None,
    bs: str | None,
    N: str,
    tau_over_alpha: float,
    code: str,
    interferers: Interferers,
    *,
    exact_only: bool = False,
) -> tuple[list[tuple[float, MANModel]], dict[str, object]]:
    """(ℓ, model) per requested power, and the density description for the metadata."""
    _file_codes.cache_clear()  # a new command reads its files afresh
    key = REPORT_IDS.get(name.upper(), name.lower())
    allowed = (*DENSITY_NAMES, "psk")
    if key not in allowed:
        raise typer.BadParameter(
            f"unknown density {name!r}; use one of {', '.join(allowed)} or C1…C4", param_hint="--density"
        )
    if exact_only and key not in EXACT_DENSITIES:
        raise typer.BadParameter(
            f"no exact ROC for the {key} density ({', '.join(EXACT_DENSITIES)}); use mac-roc montecarlo",
            param_hint="--density",
        )
    N_ = _count(N, "--N")
    if N_ == 1:
        raise typer.BadParameter("N = 1 has no interferers: p_f = 0 and p_d = 1 exactly", param_hint="--N")
    info: dict[str, object] = {"density": key}
    if key == "psk":
        if ells is not None or bs is not None:
            raise typer.BadParameter(
                "the psk density's power follows from --code; drop --ell/--b", param_hint="--ell"
            )
        ref = _code(code)
        fam = _family(code, ref) if interferers is Interferers.family else None
        dens = checked(
            "--code",
            PSKAmplitude,
            tuple(int(v) for v in ref),
            None if fam is None else tuple(map(tuple, fam.astype(int))),
        )
        info.update(code=code, chips=int(ref.size), interferers=interferers.value)
        model = checked("--N/--tau-over-alpha", MANModel.common, N_, tau_over_alpha, dens)
        return [(ell_of_b(dens.b), model)], info
    if ells is not None and bs is not None:
        raise typer.BadParameter("give --ell or --b, not both", param_hint="--b")
    if bs is not None:
        b_values = _positive_list(bs, "--b")
    else:
        ell_values = _positive_list(ells, "--ell") if ells is not None else list(exp.ELL_SET)
        b_values = [b_of_ell(e) for e in ell_values]
    out = []
    for b in b_values:
        if not math.isfinite(b):
            raise typer.BadParameter("must be finite", param_hint="--b/--ell")
        d = checked("--b/--ell", density, key, b)
        out.append((ell_of_b(b), checked("--N/--tau-over-alpha", MANModel.common, N_, tau_over_alpha, d)))
    return out, info


def _figure(figure: str | None, command: str) -> str | None:
    if figure is None:
        return None
    owner = checked("--figure", exp.figure_command, figure)
    if owner != command:
        raise typer.BadParameter(
            f"Fig. {figure} is drawn by `motionsig mac-roc {owner}`", param_hint="--figure"
        )
    return figure


def _fin(x: float) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def _p(log_p: float) -> float | None:
    """A probability from its natural log (0 for −inf; None for NaN)."""
    v = float(log_p)
    return None if math.isnan(v) else math.exp(v)


def _l10(log_p: float) -> float | None:
    v = float(log_p)
    return v / LN10 if math.isfinite(v) else None


def _warn_realisable(models: list[tuple[float, MANModel]], quiet: bool) -> bool:
    ok = all(m.realisable() for _, m in models)
    if not ok:
        note(
            "mac-roc: warning: the density's support exceeds ±1, which |n_ij| <= 1 forbids (not realisable)",
            quiet,
        )
    return ok


def _require_nonempty(curves: list[np.ndarray], what: str) -> None:
    if all(np.all(c == -np.inf) for c in curves):
        raise typer.BadParameter(
            f"every threshold gives {what} = 0 (the noise never reaches them): the ROC is empty",
            param_hint="--theta",
        )


N_HELP = "Number of aircraft N (integer >= 1; 1e5 allowed)."
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
NOpt = Annotated[str, typer.Option("--N", help=N_HELP)]
TauOpt = Annotated[
    float,
    typer.Option(
        "--tau-over-alpha", callback=_tau_over_alpha, help="Signature duty τ/α in (0, 0.5) (report 2e-5)."
    ),
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


def _model_meta(ell: float, model: MANModel) -> dict[str, object]:
    return {
        "N": model.N,
        "tau_over_alpha": model.tau_over_alpha,
        "q": model.q,
        "mean_active": model.mean_active,
    }


def _bounds_rows(figure: str | None, name: str, ell: float, model: MANModel, rb: RocBounds) -> list[tuple]:
    rows = []
    b = model.power / model.mean_active
    for i, th in enumerate(rb.theta):
        rows.append(
            (
                figure or "",
                name,
                ell,
                b,
                model.power,
                float(th),
                _fin(rb.rho_star[i]),
                _fin(rb.E_f[i]),
                _fin(rb.rho1[i]),
                _fin(rb.phi1[i]),
                _p(rb.log_pf_up[i]),
                _p(rb.log_pf_lo[i]),
                _fin(rb.gamma_star[i]),
                _fin(rb.E_d[i]),
                _fin(rb.gamma1[i]),
                _fin(rb.phi2[i]),
                _p(rb.log_pm_up[i]),
                _p(rb.log_pm_lo[i]),
                float(rb.pd_lo[i]),
                float(rb.pd_up[i]),
                _l10(rb.log_pf_up[i]),
                _l10(rb.log_pf_lo[i]),
                _l10(rb.log_pm_up[i]),
                _l10(rb.log_pm_lo[i]),
            )
        )
    return rows


BOUND_COLS = (
    "figure",
    "density",
    "ell",
    "b",
    "P",
    "theta",
    "rho_star",
    "E_f",
    "rho1",
    "phi1",
    "pf_up",
    "pf_lo",
    "gamma_star",
    "E_d",
    "gamma1",
    "phi2",
    "pm_up",
    "pm_lo",
    "pd_lo",
    "pd_up",
    "log10_pf_up",
    "log10_pf_lo",
    "log10_pm_up",
    "log10_pm_lo",
)

BOUNDS_NOTE = (
    "upper bound (3.5.13): pf <= exp(-E_f), pm <= exp(-E_d); lower bound (3.5.14) with the sign of phi "
    "corrected (the printed sign exceeds 1): pf >= 1/2 exp(-E_f - phi1), phi1 = 2 rho1 sqrt(2 Lambda''(rho1))"
)
ASSUMPTIONS = (
    "C1, C3, C4 = uniform, triangular, gaussian (not described in the report); contour labels ell and the "
    "theta grid are not stated in the report"
)


def _curves_for_plot(ell: float, rb: RocBounds) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    return {
        "upper": (rb.log_pm_up / LN10, rb.log_pf_up / LN10),
        "lower": (rb.log_pm_lo / LN10, rb.log_pf_lo / LN10),
    }


@app.command()
def bounds(
    figure: Annotated[str | None, typer.Option("--figure", help="Fig. 3.3 (C1) … 3.6 (C4) settings.")] = None,
    density_name: Annotated[
        str | None,
        typer.Option(
            "--density", help="Amplitude density (as for the other subcommands; default two-point)."
        ),
    ] = None,
    ell: EllOpt = None,
    b: BOpt = None,
    N: NOpt = "100000",
    tau_over_alpha: TauOpt = exp.REPORT_TAU_OVER_ALPHA,
    theta: ThetaOpt = "0.01:0.99:0.01",
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
    workers: WorkersOpt = None,
    scheduler: SchedulerOpt = None,
    checkpoint: CheckpointOpt = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Upper (3.5.13) and lower (3.5.14) ROC bounds per contour label ℓ (Figs 3.3–3.6).

    One row per (ℓ, θ): the Chernoff optima ρ*, γ*, exponents E_f, E_d, Gallager roots ρ₁, γ₁, and the
    bounds on p_f and p_m = 1 − p_d (log10 columns stay exact where a probability underflows).
    --workers/--scheduler/--checkpoint run the --montecarlo overlay.
    """
    check_outputs(out, plot)
    engine = make_engine(workers, scheduler, checkpoint)
    fig = _figure(figure, "bounds")
    if fig is not None:
        wanted = exp.DENSITY_OF_FIGURE[fig]
        given = None if density_name is None else REPORT_IDS.get(density_name.upper(), density_name.lower())
        if given is not None and given != wanted:
            raise typer.BadParameter(f"Fig. {fig} is drawn for the {wanted} density", param_hint="--density")
        density_name = wanted
    density_name = density_name or "two-point"
    models, info = _models(density_name, ell, b, N, tau_over_alpha, code, interferers)
    realisable = _warn_realisable(models, quiet)
    variant = lower_variant.value
    exact_ok = info["density"] in EXACT_DENSITIES
    if with_exact and not exact_ok:
        raise typer.BadParameter(f"no exact ROC for the {info['density']} density", param_hint="--exact")
    n_mc = _count(mc_trials, "--montecarlo") if mc_trials is not None else None
    if n_mc is not None and sum(exp.expected_draws(m, n_mc) for _, m in models) > exp.MAX_TOTAL_DRAWS:
        raise typer.BadParameter(
            f"too many amplitude draws (trials x overlapping interferers > {exp.MAX_TOTAL_DRAWS:.0e})",
            param_hint="--montecarlo",
        )
    if n_mc is not None and at_pd is not None:
        raise typer.BadParameter(
            "the Monte Carlo overlay needs a theta grid, not --at-pd", param_hint="--montecarlo"
        )
    if n_mc is None and (scheduler is not None or checkpoint is not None):
        raise typer.BadParameter(
            "runs only the --montecarlo overlay; add --montecarlo N",
            param_hint="--scheduler" if scheduler is not None else "--checkpoint",
        )
    base_meta = dict(
        figure=fig,
        **info,
        **_model_meta(*models[0]),
        lower_variant=variant,
        bounds=BOUNDS_NOTE,
        realisable=realisable,
        assumptions=ASSUMPTIONS,
    )
    if at_pd is not None:
        pds = [float(v) for v in checked("--at-pd", float_list, at_pd, what="p_d")]
        for v in pds:
            if not 0.0 < v < 1.0:
                raise typer.BadParameter(f"{v:g} is not in (0, 1)", param_hint="--at-pd")
        rows = []
        grid = np.round(np.arange(1, 1000) * 1e-3, 12)  # the exact ROC is interpolated on this θ grid
        ex_grid = {e: checked("--N", exact_roc, model, grid) for e, model in models} if with_exact else {}
        for e, model in models:
            for pd in pds:
                th_u = theta_for_pd(model, pd)
                pf_u = math.exp(-float(chernoff(model, [th_u])[1][0])) if math.isfinite(th_u) else None
                rows_exact: tuple[float | None, float | None] = (None, None)
                if with_exact:
                    th_e, pf_e = exp.pf_at_pm(grid, ex_grid[e].log_pf, ex_grid[e].log_pm, 1.0 - pd)
                    rows_exact = (_fin(th_e), _fin(pf_e))
                P = model.power
                th_g = theta_for_pd(model, pd, lambda t, P=P: gaussian_roc(P, t).log_pm)
                pf_g = _p(gaussian_roc(P, [th_g]).log_pf[0]) if math.isfinite(th_g) else None
                rows.append(
                    (info["density"], e, model.power, pd, _fin(th_u), pf_u, *rows_exact, _fin(th_g), pf_g)
                )
        cols = (
            "density",
            "ell",
            "P",
            "pd",
            "theta_up",
            "pf_up",
            "theta_exact",
            "pf_exact",
            "theta_gauss",
            "pf_gauss",
        )
        meta = make_meta(
            "mac-roc bounds",
            view="at-pd",
            pd=pds,
            contour="theta_up solves E_d(theta) = -ln(1 - pd) (upper contour); theta_gauss solves the ROC_g "
            "miss equation; theta_exact is interpolated in ln pm on a theta grid of step 0.001 (on a lattice: "
            "the corner of the step)",
            **base_meta,
        )
        emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
        note(f"mac-roc bounds: {len(rows)} contour points", quiet)
        return
    th = _thetas(theta)
    per_model = []
    all_up = []
    with progress(quiet) as bar:
        task = bar.add_task("bounds", total=len(models))
        for e, model in models:
            rb = checked("--theta", roc_bounds, model, th, variant)
            all_up.append(rb.log_pf_up)
            r = _bounds_rows(fig, str(info["density"]), e, model, rb)
            curves = _curves_for_plot(e, rb)
            if with_exact:
                ex = checked("--N", exact_roc, model, th)
                r = [
                    (*row, _p(ex.log_pf[i]), _p(ex.log_pm[i]), _l10(ex.log_pf[i]), _l10(ex.log_pm[i]))
                    for i, row in enumerate(r)
                ]
                curves["exact"] = (ex.log_pm / LN10, ex.log_pf / LN10)
            per_model.append((e, r, curves))
            bar.advance(task)
    _require_nonempty(all_up, "p_f")
    if n_mc is not None:
        specs = [exp.PlainRun(m, tuple(float(t) for t in th), n_mc, seed) for _, m in models]
        identity = {
            "command": "mac-roc bounds --montecarlo",
            "figure": fig,
            "lower_variant": variant,
            "exact": with_exact,
            **_mc_identity(info, models, th, n_mc, seed),
        }
        mcs = _run_specs(specs, engine, identity, "montecarlo", quiet)
        for (_, r, curves), mc in zip(per_model, mcs, strict=True):
            r[:] = [
                (*row, float(mc.pf[i]), float(mc.pf_se[i]), float(mc.pm[i]), float(mc.pm_se[i]))
                for i, row in enumerate(r)
            ]
            with np.errstate(divide="ignore"):
                curves["montecarlo"] = (np.log10(mc.pm), np.log10(mc.pf))
    rows = [row for _, r, _ in per_model for row in r]
    panels = [(e, curves) for e, _, curves in per_model]
    cols = (
        BOUND_COLS
        + (("pf_exact", "pm_exact", "log10_pf_exact", "log10_pm_exact") if with_exact else ())
        + (("pf_mc", "pf_mc_se", "pm_mc", "pm_mc_se") if n_mc is not None else ())
    )
    mc_meta = {"montecarlo_trials": n_mc, "seed": seed} if n_mc is not None else {}
    meta = make_meta(
        "mac-roc bounds", theta=[float(th[0]), float(th[-1]), int(th.size)], **base_meta, **mc_meta
    )
    if plot is not None:
        from motionsig_cli.plotting import mac_roc_figure

        title = f"Fig. {fig}: " if fig else ""
        save_figure(
            mac_roc_figure(panels, title=f"{title}{info['density']} density, N = {models[0][1].N:g}"), plot
        )
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(f"mac-roc bounds: {len(models)} contour(s) × {th.size} thresholds ({variant} lower bound)", quiet)


@app.command()
def exact(
    density_name: DensityOpt = "uniform",
    ell: EllOpt = None,
    b: BOpt = None,
    N: NOpt = "100000",
    tau_over_alpha: TauOpt = exp.REPORT_TAU_OVER_ALPHA,
    theta: ThetaOpt = "0.01:0.99:0.01",
    lower_variant: VariantOpt = LowerVariant.report,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """The exact ROC (sum over the number of overlapping interferers; beyond the report) beside the bounds.

    inside = true when LB <= exact <= UB for both p_f and p_m (to 1e-9 relative).
    """
    check_outputs(out, plot)
    models, info = _models(
        density_name, ell, b, N, tau_over_alpha, "mseq31", Interferers.random, exact_only=True
    )
    realisable = _warn_realisable(models, quiet)
    th = _thetas(theta)
    rows = []
    panels = []
    all_pf = []
    for e, model in models:
        ex = checked("--N", exact_roc, model, th)
        rb = roc_bounds(model, th, lower_variant.value)
        all_pf.append(ex.log_pf)
        tol = 1e-9
        inside = (
            (ex.log_pf <= rb.log_pf_up + tol)
            & (ex.log_pf >= rb.log_pf_lo - tol)
            & (ex.log_pm <= rb.log_pm_up + tol)
            & (ex.log_pm >= rb.log_pm_lo - tol)
        )
        for i, t in enumerate(th):
            rows.append(
                (
                    info["density"],
                    e,
                    model.power / model.mean_active,
                    model.power,
                    float(t),
                    _p(ex.log_pf[i]),
                    _p(ex.log_pm[i]),
                    float(ex.pd[i]),
                    _l10(ex.log_pf[i]),
                    _l10(ex.log_pm[i]),
                    _p(rb.log_pf_up[i]),
                    _p(rb.log_pf_lo[i]),
                    _p(rb.log_pm_up[i]),
                    _p(rb.log_pm_lo[i]),
                    bool(inside[i]),
                )
            )
        curves = _curves_for_plot(e, rb)
        curves["exact"] = (ex.log_pm / LN10, ex.log_pf / LN10)
        panels.append((e, curves))
    _require_nonempty(all_pf, "p_f")
    cols = (
        "density",
        "ell",
        "b",
        "P",
        "theta",
        "pf",
        "pm",
        "pd",
        "log10_pf",
        "log10_pm",
        "pf_up",
        "pf_lo",
        "pm_up",
        "pm_lo",
        "inside",
    )
    meta = make_meta(
        "mac-roc exact",
        **info,
        **_model_meta(*models[0]),
        lower_variant=lower_variant.value,
        method="sum over K ~ Binomial(N-1, 2 tau/alpha) of P(S_K >= theta); Irwin-Hall tails by B-splines",
        realisable=realisable,
        assumptions=ASSUMPTIONS,
    )
    if plot is not None:
        from motionsig_cli.plotting import mac_roc_figure

        save_figure(mac_roc_figure(panels, title=f"exact ROC, {info['density']} density"), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    bad = sum(1 for r in rows if not r[-1])
    note(f"mac-roc exact: {len(rows)} points, {bad} outside the bounds", quiet)


def _mc_identity(
    info: dict[str, object], models: list[tuple[float, MANModel]], th: np.ndarray, trials: int, seed: int
) -> dict[str, object]:
    """The parameters that determine a Monte Carlo's tasks (for a checkpoint's manifest)."""
    return {
        **info,
        "N": models[0][1].N,
        "tau_over_alpha": models[0][1].tau_over_alpha,
        "b": [m.power / m.mean_active if m.mean_active else None for _, m in models],
        "ell": [e for e, _ in models],
        "theta": [float(t) for t in th],
        "trials": trials,
        "seed": seed,
    }


def _run_specs(specs: list, engine: Engine, identity: dict[str, object], label: str, quiet: bool) -> list:
    """Run Monte Carlo specs as one list of tasks on the engine, with a progress bar in trials."""
    with engine_session(engine, sum(spec.trials for spec in specs), label, quiet) as advance:
        return exp.run_specs(specs, engine, advance, identity)


@app.command()
def montecarlo(
    density_name: DensityOpt = "uniform",
    ell: EllOpt = None,
    b: BOpt = None,
    N: NOpt = "100000",
    tau_over_alpha: TauOpt = exp.REPORT_TAU_OVER_ALPHA,
    theta: ThetaOpt = "0.2,0.35,0.5,0.65,0.8",
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
    workers: WorkersOpt = None,
    scheduler: SchedulerOpt = None,
    checkpoint: CheckpointOpt = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """The Monte Carlo ROC (Level A; chip level with --density psk) beside the exact ROC and the bounds.

    z_pf, z_pm = (estimate − exact)/SE where the exact ROC exists; inside = the estimate lies within
    [LB − 4 SE, UB + 4 SE] for both p_f and p_m. The trials run in blocks of 65 536 on --workers local
    processes or a Dask --scheduler; the result is the same bit for bit, and --checkpoint DIR resumes
    an interrupted run.
    """
    check_outputs(out, plot)
    engine = make_engine(workers, scheduler, checkpoint)
    n_trials = _count(trials, "--trials")
    if n_trials > MAX_TRIALS:
        raise typer.BadParameter(f"at most {MAX_TRIALS:.0e} trials", param_hint="--trials")
    models, info = _models(density_name, ell, b, N, tau_over_alpha, code, interferers)
    if importance and info["density"] in ("arcsine", "psk"):
        raise typer.BadParameter(
            f"importance sampling is not available for the {info['density']} density",
            param_hint="--importance",
        )
    realisable = _warn_realisable(models, quiet)
    th = _thetas(theta)
    runs = 2 * th.size if importance else 1
    draws = sum(exp.expected_draws(m, n_trials, runs) for _, m in models)
    if draws > exp.MAX_TOTAL_DRAWS:
        raise typer.BadParameter(
            f"{draws:.3g} amplitude draws expected (trials x {models[0][1].mean_active:.4g} overlapping interferers"
            f"{' x 2 x thresholds' if importance else ''}); at most {exp.MAX_TOTAL_DRAWS:.0e}",
            param_hint="--trials",
        )
    identity = {
        "command": "mac-roc montecarlo",
        "importance": importance,
        "lower_variant": lower_variant.value,
        **_mc_identity(info, models, th, n_trials, seed),
    }
    references = []  # the bounds and the exact ROC first: a bad setting fails before the Monte Carlo
    for _, model in models:
        rb = roc_bounds(model, th, lower_variant.value)
        has_exact = info["density"] in EXACT_DENSITIES and model.mean_active <= MAX_MEAN_ACTIVE
        references.append((rb, exact_roc(model, th) if has_exact else None))
    results: list = []
    if importance:  # every (model, side, θ) is a spec; all of them run as one list of tasks
        sides = [
            (
                *exp.importance_runs(m, th, n_trials, seed, "pf"),
                *exp.importance_runs(m, th, n_trials, seed, "pm"),
            )
            for _, m in models
        ]
        specs = [r for f_runs, _, m_runs, _ in sides for r in (*f_runs, *m_runs) if r is not None]
        done = iter(_run_specs(specs, engine, identity, "trials", quiet))

        def estimate(runs: list, tilt: np.ndarray) -> exp.ImportanceEstimate:
            return exp.importance_estimate(
                th, n_trials, tilt, [None if r is None else next(done) for r in runs]
            )

        results = [
            (estimate(f_runs, f_tilt), estimate(m_runs, m_tilt)) for f_runs, f_tilt, m_runs, m_tilt in sides
        ]
    else:
        specs = [exp.PlainRun(model, tuple(float(t) for t in th), n_trials, seed) for _, model in models]
        results = _run_specs(specs, engine, identity, "trials", quiet)
    rows = []
    panels = []
    power_checks = []
    for (e, model), (rb, ex), result in zip(models, references, results, strict=True):
        if importance:
            f, m = result
            pf, pm = f.p, m.p
            pf_se, pm_se = f.p * f.rel_se, m.p * m.rel_se
        else:
            mc = result
            pf, pm, pf_se, pm_se = mc.pf, mc.pm, mc.pf_se, mc.pm_se
            power_checks.append(
                {"ell": e, "P": model.power, "mean_n2": mc.power, "se": mc.power_se,
                 "z": (mc.power - model.power) / mc.power_se if mc.power_se > 0 else None}
            )  # fmt: skip
        up_f, lo_f = np.exp(rb.log_pf_up), np.exp(rb.log_pf_lo)
        up_m, lo_m = np.exp(rb.log_pm_up), np.exp(rb.log_pm_lo)
        inside = exp.within_bounds(pf, pf_se, lo_f, up_f, n_trials) & exp.within_bounds(
            pm, pm_se, lo_m, up_m, n_trials
        )
        for i, t in enumerate(th):
            ef = math.exp(ex.log_pf[i]) if ex is not None else None
            em = math.exp(ex.log_pm[i]) if ex is not None else None
            zf = (pf[i] - ef) / pf_se[i] if ef is not None and pf_se[i] > 0 else None
            zm = (pm[i] - em) / pm_se[i] if em is not None and pm_se[i] > 0 else None
            rows.append(
                (
                    info["density"],
                    e,
                    model.power,
                    float(t),
                    "importance" if importance else "plain",
                    n_trials,
                    float(pf[i]),
                    float(pf_se[i]),
                    float(pm[i]),
                    float(pm_se[i]),
                    ef,
                    zf,
                    em,
                    zm,
                    float(up_f[i]),
                    float(lo_f[i]),
                    float(up_m[i]),
                    float(lo_m[i]),
                    bool(inside[i]),
                )
            )
        curves = _curves_for_plot(e, rb)
        if ex is not None:
            curves["exact"] = (ex.log_pm / LN10, ex.log_pf / LN10)
        with np.errstate(divide="ignore"):
            curves["montecarlo"] = (np.log10(pm), np.log10(pf))
        panels.append((e, curves))
    cols = (
        "density",
        "ell",
        "P",
        "theta",
        "method",
        "trials",
        "pf",
        "pf_se",
        "pm",
        "pm_se",
        "pf_exact",
        "z_pf",
        "pm_exact",
        "z_pm",
        "pf_up",
        "pf_lo",
        "pm_up",
        "pm_lo",
        "inside",
    )
    meta = make_meta(
        "mac-roc montecarlo",
        **info,
        **_model_meta(*models[0]),
        trials=n_trials,
        seed=seed,
        method="importance sampling: K ~ Bin(M, w(r)), amplitudes tilted at r, weight exp(-r n + Lambda(r))"
        if importance
        else "plain: K ~ Bin(N-1, 2 tau/alpha) interferers, amplitudes summed"
        + (" (chip level: codes, delays, phases)" if info["density"] == "psk" else ""),
        block=exp.BLOCK,
        streams="block t draws from SeedSequence(seed, spawn_key=(t, ...))",
        power_check=power_checks or None,
        realisable=realisable,
    )
    if plot is not None:
        from motionsig_cli.plotting import mac_roc_figure

        save_figure(mac_roc_figure(panels, title=f"Monte Carlo ROC, {info['density']} density"), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    zs = [abs(r[11]) for r in rows if r[11] is not None] + [abs(r[13]) for r in rows if r[13] is not None]
    msg = f"mac-roc montecarlo: {len(rows)} points, {sum(1 for r in rows if not r[-1])} outside the bounds ± 4 SE"
    if zs:
        msg += f", max |z| against the exact ROC {max(zs):.2f}"
    note(msg, quiet)


@app.command()
def gaussian(
    figure: Annotated[str | None, typer.Option("--figure", help="Fig. 3.8 settings.")] = None,
    density_name: DensityOpt = "uniform",
    ell: EllOpt = None,
    b: BOpt = None,
    N: NOpt = "100000",
    tau_over_alpha: TauOpt = exp.REPORT_TAU_OVER_ALPHA,
    theta: ThetaOpt = "0.01:0.99:0.01",
    gauss_variance: Annotated[
        GaussVar,
        typer.Option("--gauss-variance", help="ROC_g variance: (N-1)qb as (3.4.13), or the report's N q b."),
    ] = GaussVar.n1,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """ROC_g, the ROC of a Gaussian MAN of equal power (3.8.1)–(3.8.3), and its Chernoff bound (3.8.8).

    The power depends only on b (ℓ), not on the density's shape.
    """
    check_outputs(out, plot)
    fig = _figure(figure, "gaussian")
    models, _ = _models(density_name, ell, b, N, tau_over_alpha, "mseq31", Interferers.random)
    th = _thetas(theta)
    rows = []
    panels = []
    for e, model in models:
        P = gaussian_power(model, gauss_variance.value)
        g = gaussian_roc(P, th)
        for i, t in enumerate(th):
            rows.append(
                (
                    fig or "",
                    e,
                    P,
                    float(t),
                    _p(g.log_pf[i]),
                    float(-np.expm1(g.log_pm[i])),
                    _p(g.log_pm[i]),
                    _l10(g.log_pf[i]),
                    _l10(g.log_pm[i]),
                    g.d_prime,
                    float(g.exp_f[i]),
                    float(g.exp_d[i]),
                    math.exp(-g.exp_f[i]),
                    math.exp(-g.exp_d[i]),
                )
            )
        panels.append((e, {"gaussian": (g.log_pm / LN10, g.log_pf / LN10)}))
    cols = (
        "figure",
        "ell",
        "P",
        "theta",
        "pf",
        "pd",
        "pm",
        "log10_pf",
        "log10_pm",
        "d_prime",
        "expfg",
        "expdg",
        "pf_chernoff",
        "pm_chernoff",
    )
    meta = make_meta(
        "mac-roc gaussian",
        figure=fig,
        **_model_meta(*models[0]),
        gauss_variance=gauss_variance.value,
        formula="pf = 1/2 erfc(theta/sqrt(2P)), pm = 1/2 erfc((1-theta)/sqrt(2P)) (3.8.1)-(3.8.3); "
        "Chernoff exp(-theta^2/(2P)) (3.8.8)",
    )
    if plot is not None:
        from motionsig_cli.plotting import mac_roc_figure

        save_figure(mac_roc_figure(panels, title=f"{'Fig. ' + fig + ': ' if fig else ''}ROC$_g$"), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(f"mac-roc gaussian: {len(models)} curve(s) × {th.size} thresholds", quiet)


def _range_or_list(text: str, option: str, *, log: bool) -> np.ndarray:
    """``a:b:n`` (n points, log-spaced when ``log``) or a comma-separated list."""
    if ":" in text:
        parts = text.split(":")
        try:
            a, b_, n = float(parts[0]), float(parts[1]), int(parts[2])
        except (ValueError, IndexError):
            raise typer.BadParameter(f"expected start:stop:count; got {text!r}", param_hint=option) from None
        if (
            len(parts) != 3
            or not (1 <= n <= 100_000)
            or not (math.isfinite(a) and math.isfinite(b_))
            or b_ < a
        ):
            raise typer.BadParameter(
                f"expected start:stop:count with start <= stop; got {text!r}", param_hint=option
            )
        if log:
            if a <= 0:
                raise typer.BadParameter("a log range needs start > 0", param_hint=option)
            return np.geomspace(a, b_, n)
        return np.linspace(a, b_, n)
    return np.array(checked(option, float_list, text, what=option))


@app.command()
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
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Exp(Exp_g; N, τ/α): the quasi-optimal two-point exponent against the Gaussian one (3.8.16, Figs 3.9–3.10).

    Exp is the report's form (3.8.16); Exp_exact the closed form (3.7.24) without approximation.
    """
    check_outputs(out, plot)
    fig = _figure(figure, "exponent") or ("3.10" if expg is not None and N is not None else "3.9")
    if fig == "3.9":
        G = _range_or_list(expg, "--expg", log=False) if expg is not None else np.array([exp.FIG39_G])
        Ns = _range_or_list(N, "--N", log=True) if N is not None else np.geomspace(*exp.FIG39_N_RANGE, 61)
        tas = (
            _positive_list(tau_over_alpha, "--tau-over-alpha")
            if tau_over_alpha
            else list(exp.FIG39_TAU_OVER_ALPHA)
        )
    else:
        G = (
            _range_or_list(expg, "--expg", log=False)
            if expg is not None
            else np.linspace(*exp.FIG310_G_RANGE, 81)
        )
        Ns = _range_or_list(N, "--N", log=True) if N is not None else np.array(exp.FIG310_N)
        tas = (
            _positive_list(tau_over_alpha, "--tau-over-alpha")
            if tau_over_alpha
            else [exp.FIG310_TAU_OVER_ALPHA]
        )
    if np.any(~(G >= 0.0)) or not np.all(np.isfinite(G)):
        raise typer.BadParameter("Exp_g must be finite and >= 0", param_hint="--expg")
    if np.any(~(Ns > 1.0)) or not np.all(np.isfinite(Ns)):
        raise typer.BadParameter("N must be finite and > 1", param_hint="--N")
    for t in tas:
        _tau_over_alpha(t)
    if G.size * Ns.size * len(tas) > 1_000_000:
        raise typer.BadParameter("more than 1e6 rows requested", param_hint="--expg")
    rows = []
    lines = []
    for t in tas:
        for n in Ns:
            approx = exp_of_gaussian_exponent(G, n, t)
            exact_ = exp_of_gaussian_exponent_exact(G, n, t)
            for gi, a, x in zip(G, approx, exact_, strict=True):
                rows.append(
                    (fig, t, float(n), float(gi), float(a), _fin(x), float(gi / a) if a > 0 else None)
                )
        if fig == "3.9":
            for gi in G:
                ys = exp_of_gaussian_exponent(gi, Ns, t)
                lines.append((f"τ/α = {t:g}" + (f", Exp_g = {gi:g}" if G.size > 1 else ""), Ns, ys))
        else:
            for n in Ns:
                lines.append(
                    (
                        f"N = {n:g}" + (f", τ/α = {t:g}" if len(tas) > 1 else ""),
                        G,
                        exp_of_gaussian_exponent(G, n, t),
                    )
                )
    cols = ("figure", "tau_over_alpha", "N", "Exp_g", "Exp", "Exp_exact", "ratio")
    meta = make_meta(
        "mac-roc exponent",
        figure=fig,
        formula="Exp = sqrt(4 lambda G) asinh(sqrt(G/lambda)) - N ln[1 - q + q sqrt(1 + G/lambda)], "
        "lambda = N tau/alpha, q = 2 tau/alpha (3.8.16; alpha restored)",
        assumptions="tau/alpha set of Fig 3.9, N set of Fig 3.10 and the axis ranges are not stated in the report",
    )
    if plot is not None:
        from motionsig_cli.plotting import exponent_figure

        save_figure(exponent_figure(lines, vs_n=fig == "3.9", title=f"Fig. {fig}"), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(f"mac-roc exponent: Fig. {fig}, {len(rows)} rows", quiet)


@app.command()
def densities(
    figure: Annotated[
        str, typer.Option("--figure", help="Fig. 3.2 (the densities) or 3.7 (the C* component).")
    ] = "3.2",
    b: Annotated[
        float, typer.Option("--b", help="Second moment (Fig. 3.2 default 1/3: C1 = U(-1, 1)).")
    ] = exp.FIG32_B,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Fig. 3.2: C₁ … C₄ at equal second moment (impulses as weights); Fig. 3.7: n_ij(t) for C*."""
    check_outputs(out, plot)
    fig = _figure(figure, "densities")
    if not (math.isfinite(b) and b > 0):
        raise typer.BadParameter(f"{b:g} is not a finite number > 0", param_hint="--b")
    if fig == "3.2":
        curves = exp.density_curves(b, x_lim=2.0 * math.sqrt(3.0 * b))
        rows = []
        for rid, name, x, pdf, w in curves:
            for i in range(x.size):
                rows.append(
                    (
                        rid,
                        name,
                        float(x[i]),
                        None if w is not None else float(pdf[i]),
                        None if w is None else float(w[i]),
                    )
                )
        checks = {name: exp.second_moment(density(name, b)) for _, name, *_ in curves}
        cols = ("id", "density", "x", "pdf", "weight")
        meta = make_meta(
            "mac-roc densities", figure=fig, b=b, second_moment_check=checks, assumptions=ASSUMPTIONS
        )
        if plot is not None:
            from motionsig_cli.plotting import density_figure

            save_figure(density_figure(curves, b), plot)
    else:
        A = math.sqrt(b)
        t, n = exp.schematic_component(A)
        rows = [(float(ti), float(v), float(-v)) for ti, v in zip(t, n, strict=True)]
        cols = ("t_over_tau", "n_ij_plus", "n_ij_minus")
        meta = make_meta(
            "mac-roc densities", figure=fig, b=b, A=A, note="n_ij = +A or -A for t_j < t < t_j + 2 tau"
        )
        if plot is not None:
            from motionsig_cli.plotting import schematic_figure

            save_figure(schematic_figure(t, n), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(f"mac-roc densities: Fig. {fig}", quiet)


@app.command()
def bandwidth(
    code: Annotated[
        str,
        typer.Option("--code", help="Codes, ';'-separated: mseq31, barker13, gold:45,75:3, mseq:45, +-/01."),
    ] = "barker13;mseq31",
    curves: Annotated[
        bool, typer.Option("--curves", help="Fig. 3.11: the autocorrelations R(t) instead of the table.")
    ] = False,
    N: NOpt = "100000",
    alpha: Annotated[float, typer.Option("--alpha", help="Signature period α [s].")] = 1.0,
    tau_c: Annotated[float, typer.Option("--tau-c", help="Chip duration τ_c [s].")] = 1e-7,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Sec. 3.9 / App. F: Zakai bandwidth W of each code (numerical, the report's (3.9.3), ideal 3/(4τ_c)),
    b for random-code interferers, E n² = (N−1)/(4αW) and the peak signal-to-interference ratio."""
    check_outputs(out, plot)
    for name, v in (("--alpha", alpha), ("--tau-c", tau_c)):
        if not (math.isfinite(v) and v > 0):
            raise typer.BadParameter(f"{v:g} is not a finite number > 0", param_hint=name)
    N_ = _count(N, "--N")
    specs = [s for s in code.split(";") if s.strip()]
    if not specs:
        raise typer.BadParameter("no code given", param_hint="--code")
    codes = [(s.strip(), _code(s)) for s in specs]
    if curves:
        rows = []
        lines = []
        for s, c in codes:
            t, R = tb.autocorrelation_curve(c)
            rows.extend((s, float(a), float(r)) for a, r in zip(t, R, strict=True))
            lines.append((s, t, R))
        cols = ("code", "t_over_tauc", "R")
        meta = make_meta("mac-roc bandwidth", figure="3.11", view="curves", ideal="R = max(0, 1 - |t|/tau_c)")
    else:
        rows = []
        for s, c in codes:
            L = c.size
            W = tb.zakai_bandwidth(c)
            Wr = float(tb.zakai_bandwidth_report(1.0 / L))
            b_r = tb.b_random_codes(c)
            power = tb.psk_power(N_, alpha, W / tau_c)
            rows.append(
                (
                    s,
                    L,
                    W,
                    Wr,
                    tb.IDEAL_W_TAUC,
                    b_r,
                    ell_of_b(b_r),
                    power,
                    1.0 / power,
                    tb.peak_sir(N_, alpha, tau_c),
                )
            )
        cols = (
            "code",
            "chips",
            "W_tauc",
            "W_tauc_report",
            "W_tauc_ideal",
            "b_random",
            "ell",
            "En2",
            "sir",
            "sir_ideal",
        )
        meta = make_meta(
            "mac-roc bandwidth",
            N=N_,
            alpha=alpha,
            tau_c=tau_c,
            formulas="W = 1/(2 int R^2) (Theorem 3.3); W_report = [(4/3) tau_c (1 + 2x + 2x^2)]^-1, x = 1/L "
            "(3.9.3); E n^2 = (N-1)/(4 alpha W) (3.9.2); sir_ideal = 3 alpha/(N tau_c)",
        )
        lines = [(s, *tb.autocorrelation_curve(c)) for s, c in codes]
    if plot is not None:
        from motionsig_cli.plotting import autocorrelation_figure

        save_figure(autocorrelation_figure(lines), plot)
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(f"mac-roc bandwidth: {len(codes)} code(s)", quiet)


@app.command()
def report(
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """The numbers printed in ATC-10 §3 beside ours, with the deviation and the reason for each difference."""
    check_outputs(out)
    rows = [
        (r.quantity, r.source, r.printed, r.ours, r.deviation, r.status, r.note)
        for r in exp.printed_comparison()
    ]
    cols = ("quantity", "source", "printed", "ours", "deviation", "status", "note")
    meta = make_meta("mac-roc report", source="ATC-10 (1972) Sec. 3; data/atc10_sec3_printed.csv")
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)
    note(f"mac-roc report: {len(rows)} printed values compared", quiet)
