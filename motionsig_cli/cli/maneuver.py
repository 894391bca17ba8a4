"""``motionsig maneuver``: tracking a maneuvering target with an IMM of three Kalman filters and with GLR / MLR
maneuver detection (seed 002), Monte Carlo over runs or one measurement record.

Views: ``scans`` (eqs 14–15 per scan, RMS error, mean model probabilities, declaration rate), ``events``
(detection delay and onset error after each true input change), ``summary`` (one row per σ and method: RMS
error per phase, false alarms, detection of each change — the comparison table), ``measurements`` (the
simulated records, to pipe into ``--input``) and, with ``--input``, the per-scan track of one record.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from enum import StrEnum
from functools import partial
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
    float_list,
    make_engine,
    note,
    run_monte_carlo,
    save_figure,
)
from motionsig_cli.cli.io import InputError, Table, emit, make_meta, read_table
from motionsig_cli.cli.records import finite_column
from motionsig_cli.detection.glr import CHI2_2_999
from motionsig_cli.experiments import maneuver as exp
from motionsig_cli.models.motion import G2_FORMS, MU0_PAPER, PI_PAPER, ModelSet, imm_models

MAX_COORD = 1e9
"""Largest |measurement| accepted from a record [m] (a million km; squares stay far from overflow)."""


class G2(StrEnum):
    """Form of G₂ = G₃ (spec §3.4)."""

    paper_fixed = "paper-fixed"
    standard = "standard"


assert tuple(g.value for g in G2) == G2_FORMS


class Preset(StrEnum):
    """Trajectory preset (spec §3.5)."""

    literal = "literal"
    turn90 = "turn90"


class View(StrEnum):
    """What the table holds."""

    scans = "scans"
    events = "events"
    summary = "summary"
    measurements = "measurements"


class Correction(StrEnum):
    """State correction on a declaration."""

    exact = "exact"
    paper = "paper"


class Continuation(StrEnum):
    """What happens to the input estimate after a declaration."""

    estimate = "estimate"
    known = "known"


def _period(value: float | None) -> float | None:
    if value is not None and not (math.isfinite(value) and exp.T_RANGE[0] <= value <= exp.T_RANGE[1]):
        raise typer.BadParameter(f"{value:g} is not in [{exp.T_RANGE[0]:g}, {exp.T_RANGE[1]:g}] s")
    return value


def _finite(value: float) -> float:
    if not math.isfinite(value):
        raise typer.BadParameter(f"{value:g} is not a finite number")
    return value


def _psd(value: float) -> float:
    if not (math.isfinite(value) and 0 <= value <= 1e6):
        raise typer.BadParameter(f"{value:g} is not in [0, 1e6] m²/s³")
    return value


def _prior_width(value: float) -> float:
    if not (math.isfinite(value) and 1e-3 <= value <= 1e6):
        raise typer.BadParameter(f"{value:g} is not in [1e-3, 1e6] m/s²")
    return value


def _glr_threshold(value: float) -> float:
    if not (math.isfinite(value) and value >= 0):
        raise typer.BadParameter(f"{value:g} is not a finite number >= 0 (ΔJ is never negative)")
    return value


def _methods(text: str) -> tuple[str, ...]:
    names = tuple(dict.fromkeys(m.strip().lower() for m in text.split(",") if m.strip()))
    if names == ("all",):
        return exp.METHODS
    if not names or any(m not in exp.METHODS for m in names):
        raise typer.BadParameter(
            f"choose from {', '.join(exp.METHODS)} (comma-separated) or all; got {text!r}",
            param_hint="--method",
        )
    return names


def _matrix(text: str) -> np.ndarray:
    """``'a,b,c;d,e,f;…'`` → rows."""
    rows = [r for r in text.split(";") if r.strip()]
    if not rows:
        raise ValueError(f"no rows in {text!r}")
    out = [float_list(r, what="transition probability") for r in rows]
    if len({len(r) for r in out}) != 1:
        raise ValueError(f"rows of different lengths in {text!r}")
    return np.array(out)


def _model_set(transition: str | None, mu0: str | None, T: float, g2: str) -> ModelSet:
    Pi = np.array(PI_PAPER) if transition is None else checked("--transition", _matrix, transition)
    mu = (
        np.array(MU0_PAPER)
        if mu0 is None
        else np.array(checked("--mu0", float_list, mu0, what="probability"))
    )
    if Pi.shape != (3, 3):
        raise typer.BadParameter(f"needs 3 rows of 3 probabilities (one per model); got {Pi.shape}",
                                 param_hint="--transition")  # fmt: skip
    if mu.shape != (3,):
        raise typer.BadParameter(f"needs 3 probabilities (one per model); got {mu.size}", param_hint="--mu0")
    try:  # ModelSet checks the values: rows of Π and μ₀ non-negative, summing to 1
        return imm_models(T, g2=g2, Pi=Pi, mu0=mu)
    except ValueError as exc:
        option = "--mu0" if "initial model probabilities" in str(exc) else "--transition"
        raise typer.BadParameter(str(exc), param_hint=option) from None


def _read_record(path: str) -> tuple[np.ndarray, np.ndarray, dict[str, Any], Table]:
    """Columns scan, z_x, z_y: consecutive integer scans (no gaps), finite values, at least 3 scans."""
    t = read_table(path, required=("scan", "z_x", "z_y"))
    for col in ("run", "sigma"):
        if col in t.columns and len(set(t.column(col))) > 1:
            raise InputError(f"{t.source}: several values of {col!r} in one file; track one record at a time")
    if len(t.rows) < 3:
        raise InputError(
            f"{t.source}: need at least 3 scans (two initialise the trackers), found {len(t.rows)}"
        )
    scans = t.numeric("scan", integer=True)
    steps = np.diff(scans)
    if np.any(steps != 1):
        i = int(np.flatnonzero(steps != 1)[0]) + 1
        what = "missing scan(s)" if steps[i - 1] > 1 else "scans out of order or repeated"
        raise InputError(f"{t.source}:{t.lines[i]}: {what}: scan {scans[i]} after {scans[i - 1]}")
    z = np.stack([finite_column(t, "z_x"), finite_column(t, "z_y")], axis=-1)
    big = np.flatnonzero(np.any(np.abs(z) > MAX_COORD, axis=1))
    if big.size:
        raise InputError(f"{t.source}:{t.lines[big[0]]}: |measurement| exceeds {MAX_COORD:g} m")
    return scans, z, t.meta, t


def _meta_number(meta: dict[str, Any], key: str, source: str) -> float | None:
    if key not in meta:
        return None
    if isinstance(meta[key], bool):
        raise InputError(f"{source}: metadata {key!r} must be a number, got {meta[key]!r}")
    try:
        v = float(meta[key])
    except (TypeError, ValueError):
        raise InputError(f"{source}: metadata {key!r} must be a number, got {meta[key]!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{source}: metadata {key!r} must be a finite number > 0, got {v:g}")
    return v


def maneuver(
    method: Annotated[
        str,
        typer.Option(
            "--method", help="Trackers, comma-separated: imm, glr, mlr, cv (CV Kalman filter), or all."
        ),
    ] = "imm",
    sigma: Annotated[
        str | None,
        typer.Option("--sigma", help="Measurement noise σ per axis [m], comma-separated (default 100,200)."),
    ] = None,
    preset: Annotated[
        Preset, typer.Option("--preset", help="literal (as printed) or turn90 (exact 90° turns).")
    ] = Preset.literal,
    T: Annotated[
        float | None,
        typer.Option(
            "--T", callback=_period, help="Scan period [s], 1e-3 to 3600 (default 1; not in the seed)."
        ),
    ] = None,
    scans: Annotated[
        int, typer.Option("--scans", min=3, max=100_000, help="Scans per run (seed: 450).")
    ] = 450,
    runs: Annotated[
        int, typer.Option("--runs", min=1, max=1_000_000, help="Monte Carlo runs (seed: 500).")
    ] = 500,
    seed: SeedOpt = DEFAULT_SEED_VALUE,
    g2: Annotated[
        G2,
        typer.Option("--G2", help="G2 = G3: paper-fixed (T²/4, T/2, 1) or standard (T²/2, T, 1)."),
    ] = G2.paper_fixed,
    transition: Annotated[
        str | None,
        typer.Option(
            "--transition", help="IMM transition matrix, rows separated by ';' (default: the seed's)."
        ),
    ] = None,
    mu0: Annotated[
        str | None, typer.Option("--mu0", help="Initial model probabilities (default 0.8,0.1,0.1).")
    ] = None,
    q0: Annotated[
        float,
        typer.Option("--q0", callback=_psd, help="GLR/MLR/CV filter acceleration psd q̃0 [m²/s³]."),
    ] = 1.0,
    window: Annotated[
        int, typer.Option("--window", min=1, max=200, help="GLR/MLR onset window s [scans].")
    ] = 10,
    glr_threshold: Annotated[
        float,
        typer.Option(
            "--glr-threshold",
            callback=_glr_threshold,
            help="GLR threshold λ on ΔJ (default: χ²₂ 0.999 quantile).",
        ),
    ] = CHI2_2_999,
    mlr_threshold: Annotated[
        float,
        typer.Option("--mlr-threshold", callback=_finite, help="MLR threshold h on max_n J(n) (seed: 0)."),
    ] = 0.0,
    mlr_sigma_u: Annotated[
        float,
        typer.Option("--mlr-sigma-u", callback=_prior_width, help="MLR prior σ_u of each input [m/s²]."),
    ] = 20.0,
    correction: Annotated[
        Correction,
        typer.Option("--correction", help="exact (updated estimate) or paper (prediction, re-update)."),
    ] = Correction.exact,
    continuation: Annotated[
        Continuation,
        typer.Option(
            "--continuation", help="estimate (input estimate keeps its covariance) or known (spec §3.2)."
        ),
    ] = Continuation.estimate,
    response: Annotated[
        int,
        typer.Option(
            "--response",
            min=1,
            max=10_000,
            help="Scans after a change a declaration can be attributed to it.",
        ),
    ] = 30,
    view: Annotated[
        View, typer.Option("--view", help="scans, events, summary or measurements.")
    ] = View.scans,
    input_file: Annotated[
        str | None,
        typer.Option("--input", "-i", help="Track one record (CSV: scan, z_x, z_y; '-' for stdin) instead."),
    ] = None,
    plot_compare: Annotated[
        Path | None,
        typer.Option("--plot-compare", help="Also draw RMS error and declarations of every method."),
    ] = None,
    workers: WorkersOpt = None,
    scheduler: SchedulerOpt = None,
    checkpoint: CheckpointOpt = None,
    fmt: FormatOpt = OutputFormat.csv,
    out: OutOpt = None,
    plot: PlotOpt = None,
    quiet: QuietOpt = False,
    debug: DebugOpt = False,
) -> None:
    """Maneuvering-target tracking: IMM of three Kalman filters, GLR and MLR maneuver detection (seed 002).

    \b
    Example:
      motionsig maneuver --runs 100 --plot figs.png                  # Figs 2-4 and the IMM probabilities
      motionsig maneuver --method all --view summary --plot-compare cmp.png
      motionsig maneuver --view measurements --runs 1 --sigma 100 | motionsig maneuver --input - --method glr
      motionsig maneuver --runs 5000 --method all --workers 8 --checkpoint ckpt/   # resumable if interrupted

    --workers, --scheduler and --checkpoint apply to the Monte Carlo views (scans, events, summary); the
    measurements view and --input run no Monte Carlo and ignore them.
    """
    check_outputs(out, plot, extra={"--plot-compare": plot_compare})
    engine = make_engine(workers, scheduler, checkpoint)
    methods = _methods(method)
    cfg_kw: dict[str, Any] = dict(q0=q0, window=window, glr_threshold=glr_threshold, mlr_threshold=mlr_threshold,
                                  sigma_u=mlr_sigma_u, correction=correction.value, continuation=continuation.value,
                                  g2=g2.value)  # fmt: skip
    if input_file is not None:
        _track_record(input_file, methods, sigma, T, transition, mu0, cfg_kw, fmt, out, plot, plot_compare, view,
                      quiet)  # fmt: skip
        return
    sigmas = [100.0, 200.0] if sigma is None else checked("--sigma", float_list, sigma, what="σ")
    sigmas = list(dict.fromkeys(sigmas))
    if any(not (1e-3 <= v <= 1e7) for v in sigmas) or len(sigmas) > 10:
        raise typer.BadParameter(
            "each σ must be in [1e-3, 1e7] m (at most 10 values; σ² must stay a normal double)",
            param_hint="--sigma",
        )
    T_ = 1.0 if T is None else T
    sc = checked("--scans", exp.ManeuverScenario, preset=preset.value, T=T_, scans=scans)
    ms = _model_set(transition, mu0, T_, g2.value)
    cfg = exp.TrackerConfig(Pi=tuple(map(tuple, ms.Pi.tolist())), mu0=tuple(ms.mu0.tolist()), **cfg_kw)
    if view is View.measurements:
        for name, path in (("--plot", plot), ("--plot-compare", plot_compare)):
            if path is not None:
                raise typer.BadParameter("the measurements view draws no figure", param_hint=name)
        _emit_measurements(sc, sigmas, runs, seed, fmt, out)
        return
    if plot_compare is not None and len(methods) < 2:
        raise typer.BadParameter(
            "needs at least two methods (e.g. --method all)", param_hint="--plot-compare"
        )
    if view in (View.events,) and not set(methods) & {"glr", "mlr"}:
        raise typer.BadParameter("the events view needs glr or mlr among the methods", param_hint="--view")
    seconds = exp.cost(scans, runs, methods, len(sigmas))
    if seconds > exp.MAX_SECONDS:
        raise typer.BadParameter(
            f"estimated {seconds:.0f} s for {runs} runs x {scans} scans x {len(sigmas)} σ x {len(methods)} methods; "
            f"the limit is {exp.MAX_SECONDS:.0f} s",
            param_hint="--runs",
        )
    resp = response
    job = exp.MCJob(sc, tuple(sigmas), runs, seed, methods, cfg, quiet_fp=True)
    tasks = job.tasks()
    try:
        partials = run_monte_carlo(
            partial(exp.mc_task, job),
            tasks,
            engine,
            sizes=[len(r) for _, r in tasks],
            identity={"command": "maneuver", **job.identity()},
            label="maneuver",
            quiet=quiet,
        )
    except exp.SingularCovariance as exc:
        raise _singular(exc.sigma, T_) from None
    with np.errstate(all="ignore"):
        results = exp.mc_reduce(job, tasks, partials)
    table = _table(view, sc, results, methods, resp)
    meta = make_meta(
        "maneuver",
        view=view.value,
        methods=list(methods),
        sigma=sigmas,
        runs=runs,
        seed=seed,
        seeding="run r draws w_r ~ N(0, I) (scans x 2) from SeedSequence(seed).spawn(...)[r]; z = truth + σ w_r "
        "(the same w_r for every σ and method)",
        scenario={
            "preset": sc.preset,
            "T": sc.T,
            "scans": sc.scans,
            "p0": list(sc.p0),
            "v0": list(sc.v0),
            "segments [from, to) scans, u_x, u_y": [list(x) for x in sc.segments],
            "kinematics": "exact constant acceleration over each interval; noise-free truth",
        },
        imm={
            "G2": g2.value,
            "transition": ms.Pi.tolist(),
            "mu0": ms.mu0.tolist(),
            "Q": [0.0, 0.001, 0.0144],
            "models": list(ms.names),
            "init": "two-point differencing at scan 2",
        },
        glr={
            "q0": q0,
            "window": window,
            "threshold": glr_threshold,
            "correction": correction.value,
            "continuation": continuation.value,
        },
        mlr={"sigma_u": mlr_sigma_u, "threshold": mlr_threshold},
        response_window=resp,
        first_scan=exp.FIRST_SCAN,
        error_sign="truth - estimate (eq 14); sd with 1/M (eq 15)",
        radar="EBPSK parameters of the seed's Table I (f_c 10 GHz, 100 MHz IF, f_s 1 GHz, K = 2, N = 7) do not "
        "enter the trackers",
    )
    scan = np.arange(exp.FIRST_SCAN, scans + 1)
    events = tuple(n for n, _ in sc.events())
    if plot is not None:
        from motionsig_cli.plotting import maneuver_figure

        first = methods[0]
        per = [
            (s, r[first].track0, r[first].stats.mean, r[first].stats.sd, r[first].mu)
            for s, r in results.items()
        ]
        names = ms.names if first == "imm" else ()
        save_figure(maneuver_figure(sc.truth(), scan, per, method=first.upper(), model_names=names, events=events),
                    plot)  # fmt: skip
    if plot_compare is not None:
        from motionsig_cli.plotting import maneuver_comparison_figure

        rms = {(s, m): r[m].stats.rms for s, r in results.items() for m in methods}
        rate = {(s, m): r[m].detected.mean(axis=0) for s, r in results.items() for m in methods
                if r[m].detected is not None}  # fmt: skip
        save_figure(maneuver_comparison_figure(scan, rms, rate, events=events), plot_compare)
    emit(
        Table(columns=table[0], rows=table[1], meta=meta), fmt.value, out
    )  # after the figures: all or nothing
    parts = []
    for s, r in results.items():
        for m in methods:
            st = r[m].stats
            parts.append(f"σ={s:g} {m} RMS {np.sqrt(np.mean(st.rms**2)):.0f} m")
    note("maneuver: " + "; ".join(parts), quiet)


@contextlib.contextmanager
def _numerics(sigma: float, T: float) -> Iterator[None]:
    """A covariance that stops being positive definite in floating point is a bad σ/T combination, not a bug."""
    try:
        with np.errstate(all="ignore"):
            yield
    except np.linalg.LinAlgError:
        raise _singular(sigma, T) from None


def _singular(sigma: float, T: float) -> typer.BadParameter:
    return typer.BadParameter(
        f"σ = {sigma:g} m is too small for the motion over T = {T:g} s: the innovation covariance is "
        "numerically singular (increase --sigma or decrease --T)",
        param_hint="--sigma",
    )


def _cell(v: float) -> float | None:
    """An undefined statistic (no detection, one run) is an empty cell, not 'nan'."""
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else v


def _phase_rms(sc: exp.ManeuverScenario, st: exp.ErrorStats) -> list[float]:
    out = []
    for _, a, b in sc.phases():
        sel = (st.scan >= a) & (st.scan < b)
        out.append(float(np.sqrt(np.mean(st.rms[sel] ** 2))) if sel.any() else math.nan)
    return out


def _table(
    view: View, sc: exp.ManeuverScenario, results: dict[float, dict[str, exp.MCResult]], methods: tuple[str, ...],
    resp: int,
) -> tuple[tuple[str, ...], list[tuple[Any, ...]]]:  # fmt: skip
    rows: list[tuple[Any, ...]] = []
    if view is View.scans:
        cols = ("sigma", "method", "scan", "ebar_x", "ebar_y", "sd_x", "sd_y", "rms_pos", "mu_1", "mu_2", "mu_3",
                "declared")  # fmt: skip
        for s, r in results.items():
            for m in methods:
                st, mu, det = r[m].stats, r[m].mu, r[m].detected
                rate = det.mean(axis=0) if det is not None else None
                for i, k in enumerate(st.scan):
                    rows.append((s, m, int(k), float(st.mean[i, 0]), float(st.mean[i, 1]), float(st.sd[i, 0]),
                                 float(st.sd[i, 1]), float(st.rms[i]),
                                 *((float(v) for v in mu[i]) if mu is not None else (None, None, None)),
                                 float(rate[i]) if rate is not None else None))  # fmt: skip
        return cols, rows
    if view is View.events:
        cols = ("sigma", "method", "onset_scan", "du_x", "du_y", "runs", "detected", "mean_delay", "median_delay",
                "mean_onset_error", "rms_onset_error")  # fmt: skip
        for s, r in results.items():
            for m in methods:
                if r[m].detected is None:
                    continue
                d = exp.detection_summary(sc, r[m].detected, r[m].onset, resp)
                n_runs = r[m].detected.shape[0]
                for n, du, frac, md, med, oe, roe in d.events:
                    rows.append((s, m, n, du[0], du[1], n_runs, frac, *map(_cell, (md, med, oe, roe))))
        return cols, rows
    names = [p for p, _, _ in sc.phases()]
    ev = sc.events()
    cols = ("sigma", "method", *(f"rms_{p.replace(' ', '')}" for p in names), "false_alarms_per_1000",
            "false_alarms_se", "quiet_scans", "other_per_run",
            *(f"detected_{n}" for n, _ in ev), *(f"delay_{n}" for n, _ in ev))  # fmt: skip
    for s, r in results.items():
        for m in methods:
            ph = _phase_rms(sc, r[m].stats)
            if r[m].detected is None:
                rows.append((s, m, *ph, None, None, None, None, *(None for _ in ev), *(None for _ in ev)))
                continue
            d = exp.detection_summary(sc, r[m].detected, r[m].onset, resp)
            rows.append((s, m, *map(_cell, ph), _cell(d.false_alarms_per_1000), _cell(d.false_alarms_se),
                         d.quiet_scans, d.other, *(e[2] for e in d.events), *(_cell(e[3]) for e in d.events)))  # fmt: skip
    return cols, rows


def _emit_measurements(
    sc: exp.ManeuverScenario, sigmas: list[float], runs: int, seed: int, fmt: OutputFormat, out: Path | None
) -> None:
    if runs * sc.scans * len(sigmas) > 1_000_000:
        raise typer.BadParameter("more than 1e6 measurement rows requested", param_hint="--runs")
    truth = sc.truth()
    rows = []
    for s in sigmas:
        z = exp.measurements(sc, s, range(runs), seed)
        for r in range(runs):
            for i in range(sc.scans):
                rows.append((s, r, i + 1, i * sc.T, float(z[r, i, 0]), float(z[r, i, 1]), float(truth[i, 0]),
                             float(truth[i, 2])))  # fmt: skip
    meta = make_meta("maneuver", view="measurements", sigma=sigmas[0] if len(sigmas) == 1 else sigmas,
                     T=sc.T, preset=sc.preset, runs=runs, seed=seed, scans=sc.scans)  # fmt: skip
    cols = ("sigma", "run", "scan", "t", "z_x", "z_y", "x_true", "y_true")
    emit(Table(columns=cols, rows=rows, meta=meta), fmt.value, out)


def _track_record(
    path: str, methods: tuple[str, ...], sigma: str | None, T: float | None, transition: str | None,
    mu0: str | None, cfg_kw: dict[str, Any], fmt: OutputFormat, out: Path | None, plot: Path | None,
    plot_compare: Path | None, view: View, quiet: bool,
) -> None:  # fmt: skip
    """Track one measurement record with every requested method."""
    if view is not View.scans:
        raise typer.BadParameter(
            "with --input the output is the per-scan track; leave --view out", param_hint="--view"
        )
    if plot is not None or plot_compare is not None:
        raise typer.BadParameter("figures are drawn from Monte Carlo runs, not from one record",
                                 param_hint="--plot" if plot is not None else "--plot-compare")  # fmt: skip
    if out is not None and path != "-" and Path(path).resolve() == out.resolve():
        raise typer.BadParameter("is the --input file", param_hint="--out")
    scans, z, meta, t = _read_record(path)
    if sigma is None:
        s = _meta_number(meta, "sigma", t.source)
        if s is None:
            raise typer.BadParameter("the record's metadata has no 'sigma'; give it", param_hint="--sigma")
        if not 1e-3 <= s <= 1e7:
            raise InputError(f"{t.source}: metadata 'sigma' = {s:g} is outside [1e-3, 1e7] m")
    else:
        vals = checked("--sigma", float_list, sigma, what="σ")
        if len(vals) != 1 or not 1e-3 <= vals[0] <= 1e7:
            raise typer.BadParameter("give one σ in [1e-3, 1e7] m with --input", param_hint="--sigma")
        s = vals[0]
    T_ = T if T is not None else (_meta_number(meta, "T", t.source) or 1.0)
    if not exp.T_RANGE[0] <= T_ <= exp.T_RANGE[1]:
        raise InputError(
            f"{t.source}: metadata 'T' = {T_:g} is outside [{exp.T_RANGE[0]:g}, {exp.T_RANGE[1]:g}] s"
        )
    ms = _model_set(transition, mu0, T_, cfg_kw["g2"])
    cfg = exp.TrackerConfig(Pi=tuple(map(tuple, ms.Pi.tolist())), mu0=tuple(ms.mu0.tolist()), **cfg_kw)
    rows = []
    for m in methods:
        with _numerics(s, T_):
            tr = exp.track(m, z[None], T_, s, cfg)
        for i in range(tr.state.shape[1]):
            st = tr.state[0, i]
            mu = tr.mu[0, i] if tr.mu is not None else (None, None, None)
            det = bool(tr.detected[0, i]) if tr.detected is not None else None
            onset = (
                int(scans[0] - 1 + tr.onset[0, i]) if (tr.onset is not None and tr.onset[0, i] >= 0) else None
            )
            rows.append((m, int(scans[i + 2]), *(float(v) for v in st), *(None if v is None else float(v) for v in mu),
                         det, onset))  # fmt: skip
    cols = ("method", "scan", "x", "vx", "y", "vy", "ax", "ay", "mu_1", "mu_2", "mu_3", "declared", "onset")
    meta_out = make_meta("maneuver", input=t.source, sigma=s, T=T_, methods=list(methods),
                         config={k: v for k, v in cfg_kw.items()}, transition=ms.Pi.tolist(),
                         mu0=ms.mu0.tolist())  # fmt: skip
    emit(Table(columns=cols, rows=rows, meta=meta_out), fmt.value, out)
    note(f"maneuver: tracked {len(scans)} scans of {t.source} with {', '.join(methods)}", quiet)
