"""``motionsig detect``: the LMP mode detector of seed 000 eq (52) on a simulate record, or the
Monte Carlo study of Figs 4–6 (``--montecarlo``)."""

from __future__ import annotations

import math
from enum import StrEnum
from pathlib import Path
from typing import Annotated, Any

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
    save_figure,
)
from motionsig_cli.cli.detect_radar import detect_radar_record, montecarlo_radar, radar_config
from motionsig_cli.cli.io import InputError, Table, emit, make_meta, read_table
from motionsig_cli.cli.records import (
    emit_record_result,
    finite_column,
    parse_horizons,
    sigma_meta,
    truth_of,
    uniform_times,
)
from motionsig_cli.detection.lmp import LMPConfig, candidate_grid, lmp_detect
from motionsig_cli.detection.lmp_fft import check_fft_config, lmp_detect_fft
from motionsig_cli.engine import Engine
from motionsig_cli.experiments.lmp1d import SEED_ANR_LABELS, MCSpec, anr_db, calibrate, monte_carlo, roc_curve
from motionsig_cli.filters.unscented import SigmaPointParams
from motionsig_cli.models.vehicle import Q0_DIAG, Vehicle1D
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import table1_codes

MAX_MC_TRIALS = 100_000_000  # records of one --montecarlo run (trials x R)
MAX_NULL_TRIALS = 2_000_000  # null (and signature) trials per cell of --calibrate: 16 B each per horizon kept
NEEDED_META = ("T", "m_rho", "K", "R", "codes", "f_c", "a_sig")
R_LIST_DEFAULT = "1e-1,1e-2,1e-3,1e-5"
_TABLE_CACHE: dict[str, Table] = {}  # a record read early (to learn its example) is not read twice (stdin)


def _record_example(source: str) -> str:
    """The ``example`` metadata of a record ('1d' when absent); the table is kept for the detect run."""
    t = read_table(source, required=("t",))
    _TABLE_CACHE[source] = t
    return str(t.meta.get("example", "1d"))


Q0_DEFAULT = ",".join(f"{q:g}" for q in Q0_DIAG)
MAX_BANK_GB = 4.0


class TauGrid(StrEnum):
    """Code-phase search grid."""

    chips = "chips"
    samples = "samples"


class Weights(StrEnum):
    """cos/sin gain weighting."""

    paper = "paper"
    exact = "exact"


class Center(StrEnum):
    """H0 centring of the statistic."""

    none = "none"
    h0_noise = "h0-noise"


class Zdot(StrEnum):
    """Replica derivative in the a-column of eq 44."""

    analytic = "analytic"
    finite_difference = "finite-difference"


class FilterKind(StrEnum):
    """Filter bank."""

    auto = "auto"
    kf = "kf"
    ukf = "ukf"


class Method(StrEnum):
    """How the 1-D statistic is computed."""

    bank = "bank"
    fft = "fft"


class ExampleKind(StrEnum):
    """Example of seed 000 for --montecarlo."""

    one_d = "1d"
    two_d = "2d"


class Ar(StrEnum):
    """Reference random-walk model."""

    cv = "cv"
    identity = "identity"


def _lmp_config(
    c_r: float,
    Q0: str,
    Qa: float,
    P0: float,
    Ar_: Ar,
    tau_grid: TauGrid,
    fc_grid: str | None,
    default_fc: float,
    include_logdet: bool,
    weights: Weights,
    center: Center = Center.none,
    zdot: Zdot | None = None,
) -> LMPConfig:
    q0 = checked("--Q0", float_list, Q0, what="variance")
    if len(q0) != 4:
        raise typer.BadParameter(
            f"expected 4 variances for [x, xdot, r, rdot], got {len(q0)}", param_hint="--Q0"
        )
    if min(q0) < 0:
        raise typer.BadParameter("process-noise variances must be >= 0 (Q must be PSD)", param_hint="--Q0")
    if not (math.isfinite(Qa) and Qa >= 0):
        raise typer.BadParameter("must be >= 0 (Q must be PSD)", param_hint="--Qa")
    if not (math.isfinite(c_r) and c_r > 0):
        raise typer.BadParameter(f"must be > 0, got {c_r}", param_hint="--c-r")
    if not (math.isfinite(P0) and P0 > 0):
        raise typer.BadParameter(f"must be > 0, got {P0}", param_hint="--P0")
    fcs = (
        (default_fc,)
        if fc_grid is None
        else tuple(checked("--fc-grid", float_list, fc_grid, what="frequency"))
    )
    if any(f < 0 for f in fcs):
        raise typer.BadParameter("frequencies must be >= 0", param_hint="--fc-grid")
    return LMPConfig(
        c_r=c_r,
        Q0=tuple(q0),
        Q_a=Qa,
        P0=P0,
        A_r=Ar_.value,
        tau_grid=tau_grid.value,
        fc_grid=fcs,
        include_logdet=include_logdet,
        weights=weights.value,
        center=center.value,
        zdot=(zdot or Zdot.analytic).value,
    )


def _read_record(t: Table) -> tuple[np.ndarray, np.ndarray, dict[str, Any], str]:
    if "y" not in t.columns:
        raise InputError(f"{t.source}: missing column 'y' (produce the record with 'motionsig simulate')")
    missing = [k for k in NEEDED_META if k not in t.meta]
    if missing:
        raise InputError(
            f"{t.source}: missing metadata {', '.join(repr(m) for m in missing)} "
            "(produce the record with 'motionsig simulate')"
        )
    times = uniform_times(t)
    return times, finite_column(t, "y"), t.meta, t.source


def detect(
    source: Annotated[
        str, typer.Argument(help="simulate CSV, or - for stdin (ignored with --montecarlo).")
    ] = "-",
    c_r: Annotated[
        float, typer.Option("--c-r", help="KF measurement covariance R_KF = c_r R (seed: 1 or 100).")
    ] = 100.0,
    Q0: Annotated[
        str | None,
        typer.Option("--Q0", help="Per-step H0 Q: 1d [x, xdot, r, rdot] (eq 56); 2d 8 values (eq 61)."),
    ] = None,
    Qa: Annotated[
        float | None,
        typer.Option(
            "--Qa",
            help="1d: per-step Q of the amplitude state (eq 57: 10^0; --method fft: 0, which it needs).",
        ),
    ] = None,
    method: Annotated[
        Method,
        typer.Option(
            "--method",
            help="1d: bank (2C+1 Kalman filters, eq 52) or fft (one steady-state filter and FFT "
            "cross-correlations: exact identity for Qa = 0, and a steady-state approximation whose relative "
            "error falls like 1/horizon, ~5 % of Lambda at 10 s and 0.7 % at 80 s with the defaults).",
        ),
    ] = Method.bank,
    Q1: Annotated[str | None, typer.Option("--Q1", help="2d: per-step H1 Q, 10 values (eq 62).")] = None,
    filter_: Annotated[
        FilterKind,
        typer.Option(
            "--filter", help="auto: kf for 1d records, ukf for 2d; ukf on 1d runs the sigma-point bank."
        ),
    ] = FilterKind.auto,
    alpha: Annotated[float, typer.Option("--alpha", help="Unscented transform: spread alpha.")] = 1.0,
    beta: Annotated[float, typer.Option("--beta", help="Unscented transform: beta (2: Gaussian).")] = 2.0,
    kappa: Annotated[float, typer.Option("--kappa", help="Unscented transform: kappa.")] = 0.0,
    example: Annotated[
        ExampleKind | None,
        typer.Option("--example", help="--montecarlo: 1d (Figs 4-6) or 2d (Fig 7); records carry their own."),
    ] = None,
    anr_pairs: Annotated[
        str, typer.Option("--anr-pairs", help="2d --montecarlo: Fig 7 (angle, range) ANR pairs 1-4.")
    ] = "1,2,3,4",
    P0: Annotated[float, typer.Option("--P0", help="Prior covariance P0 = P0 * I (assumption).")] = 1.0,
    Ar_: Annotated[
        Ar, typer.Option("--Ar", help="Reference random walk: cv or identity (assumption).")
    ] = Ar.cv,
    tau_grid: Annotated[
        TauGrid, typer.Option("--tau-grid", help="chips (31 phases) or samples (all n_rho*m_rho).")
    ] = TauGrid.chips,
    fc_grid: Annotated[
        str | None,
        typer.Option("--fc-grid", help="Candidate carrier frequencies [Hz]; default the known f_c."),
    ] = None,
    include_logdet: Annotated[
        bool,
        typer.Option("--include-logdet", help="Use the full -log-likelihood (add 1/2 sum log det 2 pi S)."),
    ] = False,
    weights: Annotated[
        Weights, typer.Option("--weights", help="paper: eq 42 (weights dropped); exact: eqs 38/40.")
    ] = Weights.paper,
    zdot: Annotated[
        Zdot,
        typer.Option(
            "--zdot", help="Replica derivative: analytic (chip edges ignored) or finite-difference."
        ),
    ] = Zdot.analytic,
    center: Annotated[
        Center,
        typer.Option(
            "--center",
            help="none: the seed's eq 52; h0-noise: subtract E[Lambda] under white noise (reduces the H0 bias).",
        ),
    ] = Center.none,
    horizons: Annotated[
        str | None, typer.Option("--horizons", help="Horizons [s], e.g. 10,20,40; default every 10 s.")
    ] = None,
    threshold: Annotated[
        float | None, typer.Option("--threshold", help="Declare 'signature present' when max Lambda >= this.")
    ] = None,
    candidates: Annotated[
        bool, typer.Option("--candidates", help="Output the full candidate table instead of the argmax.")
    ] = False,
    montecarlo: Annotated[
        bool, typer.Option("--montecarlo", help="Monte Carlo % correct vs horizon and ANR (Figs 4-6).")
    ] = False,
    trials: Annotated[
        int, typer.Option("--trials", min=1, help="Monte Carlo trials per (f_r, R) cell.")
    ] = 50,
    fr_list: Annotated[
        str | None,
        typer.Option(
            "--fr-list", help="Monte Carlo reference frequencies [Hz] (1d: 0.01,0.1,1.0; 2d: 0.01)."
        ),
    ] = None,
    R_list: Annotated[
        str, typer.Option("--R-list", help="Monte Carlo measurement variances.")
    ] = R_LIST_DEFAULT,
    no_signature: Annotated[
        bool, typer.Option("--no-signature", help="Monte Carlo under H0 (argmax should be uniform).")
    ] = False,
    calibrate_: Annotated[
        bool,
        typer.Option(
            "--calibrate",
            help="1d: the null distribution of max Lambda (no signature), the threshold for --pfa and "
            "P_D at it vs horizon and ANR; --plot draws ROC curves. Use --method fft: the bank costs "
            "~0.05 s per trial, and the default 20/pfa null trials per cell add up.",
        ),
    ] = False,
    pfa: Annotated[float, typer.Option("--pfa", help="--calibrate: target false-alarm probability.")] = 0.01,
    null_trials: Annotated[
        int | None,
        typer.Option("--null-trials", min=1, help="--calibrate: null trials per cell (default 20 / pfa)."),
    ] = None,
    workers: WorkersOpt = None,
    scheduler: SchedulerOpt = None,
    checkpoint: CheckpointOpt = None,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    plot: PlotOpt = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """LMP mode detector: Lambda(i,tau,f_c) = 2 J_H0 - J_H1,cos - J_H1,sin from a filter bank (eq 52).

    1-D records run a Kalman bank; 2-D radar records (simulate --example 2d) a sigma-point bank.
    --montecarlo gives Figs 4-6 (1d) or Fig 7 (--example 2d).

    \b
    Example:
      motionsig simulate --mode 2 --tau-chips 5 | motionsig detect
      motionsig simulate --R 1e-3 | motionsig detect --candidates --horizons 62 --plot fig3.png
      motionsig detect --montecarlo --trials 50 --fr-list 0.01 --plot fig4.png -o fig4.csv
      motionsig simulate --example 2d | motionsig detect
      motionsig detect --montecarlo --example 2d --trials 50 --plot fig7.png
    """
    check_outputs(out, plot)
    engine = make_engine(workers, scheduler, checkpoint)
    sigma = checked("--alpha/--kappa", SigmaPointParams, alpha=alpha, beta=beta, kappa=kappa)
    if example is ExampleKind.two_d or (not (montecarlo or calibrate_) and _record_example(source) == "2d"):
        for opt, given in (
            ("--Qa", Qa is not None),
            ("--method", method is not Method.bank),
            ("--calibrate", calibrate_),
            ("--Ar", Ar_ is not Ar.cv),
            ("--weights", weights is not Weights.paper),
            ("--center", center is not Center.none),
            ("--R-list", R_list != R_LIST_DEFAULT),
        ):
            if given:
                raise typer.BadParameter("applies to the 1d example only", param_hint=opt)
        checked("--alpha/--kappa", sigma.weights, 8)  # n + λ = α²(n + κ) > 0 for the 8-state H0 filter
    else:
        if anr_pairs != "1,2,3,4" or Q1 is not None:
            raise typer.BadParameter("applies to the 2d example only", param_hint="--anr-pairs/--Q1")
        if filter_ is FilterKind.ukf:
            checked("--alpha/--kappa", sigma.weights, 4)  # the 4-state H0 filter
    if method is Method.fft and filter_ is FilterKind.ukf:
        raise typer.BadParameter(
            "the FFT path replaces the filter bank: drop --filter ukf", param_hint="--method"
        )
    if Qa is None:
        Qa = 0.0 if method is Method.fft else 1.0
    if calibrate_:
        if not 0 < pfa < 1:
            raise typer.BadParameter(f"must lie in (0, 1), got {pfa:g}", param_hint="--pfa")
        if null_trials is None and math.ceil(20 / pfa) > MAX_NULL_TRIALS:
            raise typer.BadParameter(
                f"P_FA = {pfa:g} needs 20/P_FA = {20 / pfa:.1e} null trials by default, more than "
                f"{MAX_NULL_TRIALS:.0e}: raise --pfa or set --null-trials",
                param_hint="--pfa",
            )
        if null_trials is not None and null_trials > MAX_NULL_TRIALS:
            raise typer.BadParameter(f"at most {MAX_NULL_TRIALS:.0e}", param_hint="--null-trials")
        if trials > MAX_NULL_TRIALS:
            raise typer.BadParameter(f"at most {MAX_NULL_TRIALS:.0e} with --calibrate", param_hint="--trials")
        if null_trials is not None and null_trials * pfa < 1:
            note(
                f"warning: {null_trials} null trials < 1/P_FA: the threshold is the largest null maximum, "
                f"its false-alarm rate is not {pfa:g}",
                quiet,
            )
        _calibrate(
            c_r, Q0, Qa, P0, Ar_, tau_grid, fc_grid, include_logdet, weights, center, zdot, horizons, trials,
            null_trials or math.ceil(20 / pfa), pfa, fr_list or "0.01", R_list, seed, method, engine, plot, fmt,
            out, quiet,
        )  # fmt: skip
        return
    if montecarlo and example is ExampleKind.two_d:
        if filter_ is FilterKind.kf:
            raise typer.BadParameter(
                "the radar example is nonlinear: use --filter ukf", param_hint="--filter"
            )
        montecarlo_radar(
            radar_config(c_r, Q0, Q1, P0, tau_grid, fc_grid, include_logdet, zdot, sigma),
            horizons, trials, fr_list or "0.01", anr_pairs, no_signature, seed, plot, fmt, out, quiet, engine,
        )  # fmt: skip
        return
    if montecarlo:
        if filter_ is FilterKind.ukf:
            raise typer.BadParameter(
                "the 1d Monte Carlo runs the Kalman bank (the sigma-point bank gives the same numbers "
                "at ~20x the cost); use it on single records",
                param_hint="--filter",
            )
        _montecarlo(
            c_r,
            Q0,
            Qa,
            P0,
            Ar_,
            tau_grid,
            fc_grid,
            include_logdet,
            weights,
            center,
            zdot,
            horizons,
            trials,
            fr_list or "0.01,0.1,1.0",
            R_list,
            no_signature,
            seed,
            plot,
            fmt,
            out,
            quiet,
            method,
            engine,
        )
        return
    table_in = _TABLE_CACHE.pop(source, None) or read_table(source, required=("t",))
    rec_example = str(table_in.meta.get("example", "1d"))
    if example is not None and example.value != rec_example:
        raise typer.BadParameter(
            f"the record is a {rec_example} record ({table_in.source})", param_hint="--example"
        )
    if rec_example == "2d":
        if filter_ is FilterKind.kf:
            raise typer.BadParameter(
                "the radar record is nonlinear (range, bearing): use --filter ukf", param_hint="--filter"
            )
        detect_radar_record(
            table_in,
            radar_config(c_r, Q0, Q1, P0, tau_grid, fc_grid, include_logdet, zdot, sigma),
            fc_grid is not None,
            horizons, threshold, candidates, plot, fmt, out, quiet,
        )  # fmt: skip
        return
    if rec_example != "1d":
        raise InputError(f"{table_in.source}: unknown example {rec_example!r} in the metadata")
    if Q1 is not None:
        raise typer.BadParameter("applies to 2d records only", param_hint="--Q1")
    times, y, meta, src = _read_record(table_in)
    T = float(meta["T"])  # validated by _read_record
    try:
        f_c = float(meta["f_c"])
        m_rho = int(meta["m_rho"])
        if m_rho < 1:
            raise ValueError(f"m_rho must be >= 1, got {m_rho}")
        vehicle = Vehicle1D(T=T, K=tuple(meta["K"]), a_sig=float(meta["a_sig"]), R=float(meta["R"]))
        chips = to_bipolar(table1_codes(str(meta["codes"]))).astype(float)
    except (ValueError, TypeError) as exc:
        raise InputError(f"{src}: bad metadata: {exc}") from None
    cfg = _lmp_config(
        c_r, Q0 or Q0_DEFAULT, Qa, P0, Ar_, tau_grid, fc_grid, f_c, include_logdet, weights, center, zdot
    )
    if method is Method.fft:
        checked("--method", check_fft_config, cfg)
    hs = parse_horizons(horizons, times.size * T, T)
    hz = [round(h / T) for h in hs]
    n_used = max(hz)  # the bank runs only as far as the longest horizon
    n_cand = len(candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg))
    need_gb = (2 * n_cand + 1) * n_used * 7 * 8 / 1e9  # gains, S⁻¹, log det per filter and step
    if need_gb > MAX_BANK_GB and method is Method.bank:
        raise typer.BadParameter(
            f"the bank of {2 * n_cand + 1} filters over {n_used} samples needs ~{need_gb:.1f} GB "
            f"(limit {MAX_BANK_GB} GB): use shorter --horizons or a coarser grid",
            param_hint="--horizons",
        )
    kind = "ukf" if filter_ is FilterKind.ukf else "kf"
    if kind == "ukf" and (center is not Center.none or weights is not Weights.paper):
        raise typer.BadParameter(
            "the sigma-point bank supports --center none and --weights paper only", param_hint="--filter"
        )
    res = (
        checked("--method", lmp_detect_fft, y[:n_used], chips, vehicle, m_rho, cfg, hz)
        if method is Method.fft
        else lmp_detect(y[:n_used], chips, vehicle, m_rho, cfg, hz, filter=kind, sigma=sigma)
    )
    params = dict(
        source=src,
        c_r=cfg.c_r,
        Q0=list(cfg.Q0),
        Q_a=cfg.Q_a,
        P0=cfg.P0,
        A_r=cfg.A_r,
        tau_grid=cfg.tau_grid,
        fc_grid=list(cfg.fc_grid),
        include_logdet=cfg.include_logdet,
        weights=cfg.weights,
        center=cfg.center,
        zdot=cfg.zdot,
        horizons_s=hs,
        threshold=threshold,
        filter=kind,
        method=method.value,
        **(sigma_meta(sigma, res.repairs) if kind == "ukf" else {}),
        input_meta=meta,
    )
    emit_record_result(
        res,
        hs,
        hz,
        truth_of(meta),
        params,
        chips.shape,
        m_rho,
        f"horizon {hs[-1]:g} s, R = {vehicle.R:g}, c_r = {cfg.c_r:g}",
        candidates=candidates,
        threshold=threshold,
        plot=plot,
        fmt=fmt,
        out=out,
        quiet=quiet,
    )


def _grid_options(
    fr_list: str, R_list: str, horizons: str | None, T: float
) -> tuple[list[float], list[float], list[float]]:
    """--fr-list, --R-list and --horizons of the 1-D Monte Carlo views, checked (horizons: every 10 s
    to 80 s by default, each at least one sample)."""
    frs = checked("--fr-list", float_list, fr_list, what="frequency")
    Rs = checked("--R-list", float_list, R_list, what="variance")
    if min(Rs) <= 0:
        raise typer.BadParameter("measurement variances must be > 0", param_hint="--R-list")
    if min(frs) < 0:
        raise typer.BadParameter("frequencies must be >= 0", param_hint="--fr-list")
    hs = (
        parse_horizons(None, 80.0, T)
        if horizons is None
        else checked("--horizons", float_list, horizons, what="horizon")
    )
    if min(hs) <= 0 or round(min(hs) / T) < 1:
        raise typer.BadParameter(f"horizons must be >= {T:g} seconds (one sample)", param_hint="--horizons")
    return frs, Rs, hs


def _montecarlo(
    c_r: float,
    Q0: str,
    Qa: float,
    P0: float,
    Ar_: Ar,
    tau_grid: TauGrid,
    fc_grid: str | None,
    include_logdet: bool,
    weights: Weights,
    center: Center,
    zdot: Zdot,
    horizons: str | None,
    trials: int,
    fr_list: str,
    R_list: str,
    no_signature: bool,
    seed: int,
    plot: Path | None,
    fmt: OutputFormat,
    out: Path | None,
    quiet: bool,
    method: Method = Method.bank,
    engine: Engine | None = None,
) -> None:
    vehicle = Vehicle1D()
    f_c, m_rho = 1.0, 20
    frs, Rs, hs = _grid_options(fr_list, R_list, horizons, vehicle.T)
    cfg = _lmp_config(
        c_r, Q0 or Q0_DEFAULT, Qa, P0, Ar_, tau_grid, fc_grid, f_c, include_logdet, weights, center, zdot
    )
    if trials * len(Rs) > MAX_MC_TRIALS:
        raise typer.BadParameter(
            f"{trials} trials x {len(Rs)} R: at most {MAX_MC_TRIALS:.0e} records per run",
            param_hint="--trials",
        )
    if method is Method.fft:
        checked("--method", check_fft_config, cfg)
    chips = to_bipolar(table1_codes("corrected")).astype(float)
    engine = engine or Engine()
    identity = dict(
        command="detect --montecarlo", method=method.value, cfg=repr(cfg), fr_list=frs, R_list=Rs, horizons_s=hs,
        trials=trials, seed=seed, signature=not no_signature,
    )  # fmt: skip
    with engine_session(engine, trials * len(Rs), "Monte Carlo trials", quiet) as advance:
        cells = monte_carlo(
            vehicle,
            chips,
            m_rho,
            f_c,
            cfg,
            frs,
            Rs,
            hs,
            trials,
            seed,
            on_chunk=advance,
            signature=not no_signature,
            method=method.value,
            engine=engine,
            identity=identity,
        )
    rows = []
    for cell in cells:
        lin, l10, lnl = anr_db(cell.R, vehicle.a_sig)
        rows.append(
            (
                cell.f_r,
                cell.R,
                lin,
                l10,
                lnl,
                SEED_ANR_LABELS.get(cell.R, ""),
                cell.horizon_s,
                cell.pct,
                cell.se_pct,
                cell.pct_mode,
                cell.correct,
                cell.trials,
            )
        )
    n_cand = len(candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg))
    meta = make_meta(
        "detect --montecarlo",
        method=method.value,
        trials=trials,
        fr_list=frs,
        R_list=Rs,
        horizons_s=hs,
        seed=seed,
        signature=not no_signature,
        c_r=cfg.c_r,
        Q0=list(cfg.Q0),
        Q_a=cfg.Q_a,
        P0=cfg.P0,
        A_r=cfg.A_r,
        tau_grid=cfg.tau_grid,
        fc_grid=list(cfg.fc_grid),
        include_logdet=cfg.include_logdet,
        weights=cfg.weights,
        center=cfg.center,
        zdot=cfg.zdot,
        T=vehicle.T,
        m_rho=m_rho,
        f_c=f_c,
        K=list(vehicle.K),
        a_sig=vehicle.a_sig,
        a_r=vehicle.a_r,
        sigma_a=vehicle.sigma_a,
        codes="corrected",
        n_candidates=n_cand,
        chance_pct=100.0 / n_cand,
        correct="mode_hat == mode and tau_hat == tau on the grid",
        trial_streams="trial t: SeedSequence(seed, spawn_key=(t, 0|1|2)) for (i,tau,theta) | process | measurement noise",
    )
    table = Table(
        (
            "f_r",
            "R",
            "anr_linear",
            "anr_db_log10",
            "anr_db_paper_ln",
            "seed_anr_label",
            "horizon_s",
            "pct_correct",
            "se_pct",
            "pct_mode_correct",
            "correct",
            "trials",
        ),
        rows,
        meta,
    )
    if plot is not None:
        from motionsig_cli.plotting import montecarlo_figure

        curves: dict[float, dict[str, tuple[np.ndarray, np.ndarray]]] = {}
        for fr in frs:
            curves[fr] = {}
            for Rv in Rs:
                sel = [c for c in cells if c.f_r == fr and c.R == Rv]
                label = f"{anr_db(Rv, vehicle.a_sig)[2]:.1f} (R={Rv:g})"
                curves[fr][label] = (np.array([c.pct for c in sel]), np.array([c.se_pct for c in sel]))
        save_figure(
            montecarlo_figure(np.array(hs), curves, f"{trials} trials per cell, c_r = {cfg.c_r:g}"), plot
        )
    emit(table, fmt.value, out)
    note(f"{len(cells)} cells x {trials} trials; chance level {100.0 / n_cand:.2f} %", quiet)


def _calibrate(
    c_r: float,
    Q0: str | None,
    Qa: float,
    P0: float,
    Ar_: Ar,
    tau_grid: TauGrid,
    fc_grid: str | None,
    include_logdet: bool,
    weights: Weights,
    center: Center,
    zdot: Zdot,
    horizons: str | None,
    trials: int,
    null_trials: int,
    pfa: float,
    fr_list: str,
    R_list: str,
    seed: int,
    method: Method,
    engine: Engine,
    plot: Path | None,
    fmt: OutputFormat,
    out: Path | None,
    quiet: bool,
) -> None:
    """``detect --calibrate``: threshold of max Λ for a false-alarm probability, and P_D at it."""
    vehicle = Vehicle1D()
    f_c, m_rho = 1.0, 20
    frs, Rs, hs = _grid_options(fr_list, R_list, horizons, vehicle.T)
    cfg = _lmp_config(
        c_r, Q0 or Q0_DEFAULT, Qa, P0, Ar_, tau_grid, fc_grid, f_c, include_logdet, weights, center, zdot
    )
    if method is Method.fft:
        checked("--method", check_fft_config, cfg)
    chips = to_bipolar(table1_codes("corrected")).astype(float)
    spec = MCSpec(vehicle, chips, m_rho, f_c, cfg, tuple(frs), tuple(hs), seed, True, method.value)
    identity = dict(
        command="detect --calibrate", method=method.value, cfg=repr(cfg), fr_list=frs, R_list=Rs, horizons_s=hs,
        trials=trials, null_trials=null_trials, pfa=pfa, seed=seed,
    )  # fmt: skip
    total = (trials + null_trials) * len(Rs)
    with engine_session(engine, total, "Calibration trials (null + signature)", quiet) as advance:
        cal = checked(
            "--pfa",
            calibrate,
            spec,
            Rs,
            trials,
            null_trials,
            pfa,
            engine=engine,
            on_chunk=advance,
            identity=identity,
        )
    rows = []
    for c in cal.cells:
        lin, l10, lnl = anr_db(c.R, vehicle.a_sig)
        rows.append(
            (c.f_r, c.R, lin, l10, lnl, SEED_ANR_LABELS.get(c.R, ""), c.horizon_s, c.pfa, c.threshold,
             c.false_alarms / c.null_trials, c.null_trials, c.pd, c.pd_se, c.detections_correct / c.trials,
             c.trials)
        )  # fmt: skip
    meta = make_meta(
        "detect --calibrate",
        method=method.value,
        pfa=pfa,
        trials=trials,
        null_trials=null_trials,
        fr_list=frs,
        R_list=Rs,
        horizons_s=hs,
        seed=seed,
        c_r=cfg.c_r,
        Q0=list(cfg.Q0),
        Q_a=cfg.Q_a,
        P0=cfg.P0,
        A_r=cfg.A_r,
        tau_grid=cfg.tau_grid,
        fc_grid=list(cfg.fc_grid),
        include_logdet=cfg.include_logdet,
        T=vehicle.T,
        m_rho=m_rho,
        f_c=f_c,
        codes="corrected",
        statistic="max over candidates of Lambda (eq 29); declare present when it exceeds the threshold",
        threshold_rule="order statistic of the null maxima leaving at most floor(pfa * null_trials) above it",
        trial_streams="signature trial t: SeedSequence(seed, spawn_key=(t, 0|1|2)); "
        "null trial t: spawn_key=(2^40 + t, 0|1|2), drawn with no signature",
    )
    table = Table(
        ("f_r", "R", "anr_linear", "anr_db_log10", "anr_db_paper_ln", "seed_anr_label", "horizon_s", "pfa_target",
         "threshold", "pfa_in_sample", "null_trials", "pd", "pd_se", "pd_and_correct", "trials"),
        rows,
        meta,
    )  # fmt: skip
    if plot is not None:
        from motionsig_cli.plotting import calibration_roc_figure

        panels: dict[str, dict[str, tuple[np.ndarray, np.ndarray]]] = {}
        for R in Rs:
            for f, fr in enumerate(frs):
                name = f"ANR {anr_db(R, vehicle.a_sig)[2]:.1f} seed dB (R={R:g})" + (
                    f", f_r={fr:g}" if len(frs) > 1 else ""
                )
                panels[name] = {
                    f"{h:g} s": roc_curve(cal.null[R][f, :, j], cal.signal[R][f, :, j])
                    for j, h in enumerate(hs)
                }
        save_figure(
            calibration_roc_figure(panels, pfa, f"{method.value}: {trials} + {null_trials} null trials"), plot
        )
    emit(table, fmt.value, out)
    note(f"{len(cal.cells)} cells; threshold for P_FA = {pfa:g} from {null_trials} null trials each", quiet)
