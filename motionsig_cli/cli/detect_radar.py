"""``motionsig detect`` on 2-D radar records and its Fig 7 Monte Carlo (seed 000 §IV.B, eqs 59–62)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import typer

from motionsig_cli.cli.common import (
    OutputFormat,
    checked,
    engine_session,
    float_list,
    int_list,
    note,
    save_figure,
)
from motionsig_cli.cli.io import InputError, Table, emit, make_meta
from motionsig_cli.cli.records import (
    emit_record_result,
    finite_column,
    parse_horizons,
    sigma_meta,
    truth_of,
    uniform_times,
)
from motionsig_cli.detection.lmp import RadarLMPConfig, candidate_grid, lmp_detect_radar
from motionsig_cli.engine import Engine
from motionsig_cli.experiments.lmp2d import monte_carlo_2d
from motionsig_cli.filters.unscented import SigmaPointParams
from motionsig_cli.models.vehicle2d import Q0_2D, Q1_2D, SEED_ANR_PAIRS, Vehicle2D, anr_pair_variances
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import table1_codes

NEEDED_META_2D = ("T", "m_rho", "K", "R_range", "R_bearing", "codes", "f_c", "a_sig", "start")
MAX_SECONDS = 3600.0  # estimated run time limit
MAX_GB = 4.0  # estimated memory limit
BEARING_UNITS = {"rad": 1.0, "deg": math.pi / 180}


def _q_list(text: str | None, option: str, default: tuple[float, ...], what: str) -> tuple[float, ...]:
    if text is None:
        return default
    q = checked(option, float_list, text, what="variance")
    if len(q) != len(default):
        raise typer.BadParameter(
            f"expected {len(default)} variances for {what}, got {len(q)}", param_hint=option
        )
    if min(q) < 0:
        raise typer.BadParameter("process-noise variances must be >= 0 (Q must be PSD)", param_hint=option)
    return tuple(q)


def radar_config(
    c_r: float,
    Q0: str | None,
    Q1: str | None,
    P0: float,
    tau_grid: Any,
    fc_grid: str | None,
    include_logdet: bool,
    zdot: Any,
    sigma: SigmaPointParams,
) -> RadarLMPConfig:
    """The 2-D detector settings from the options (without --fc-grid the grid is the known f_c: 1 Hz
    for the Monte Carlo, the record's for a record)."""
    if not (math.isfinite(c_r) and c_r > 0):
        raise typer.BadParameter(f"must be > 0, got {c_r}", param_hint="--c-r")
    if not (math.isfinite(P0) and P0 > 0):
        raise typer.BadParameter(f"must be > 0, got {P0}", param_hint="--P0")
    fcs = (1.0,) if fc_grid is None else tuple(checked("--fc-grid", float_list, fc_grid, what="frequency"))
    if any(f < 0 for f in fcs):
        raise typer.BadParameter("frequencies must be >= 0", param_hint="--fc-grid")
    return RadarLMPConfig(
        c_r=c_r,
        Q0=_q_list(Q0, "--Q0", Q0_2D, "the H0 states [x, xdot, y, ydot, r_x, rdot_x, r_y, rdot_y] (eq 61)"),
        Q1=_q_list(Q1, "--Q1", Q1_2D, "the H1 states [..., a_x, a_y] (eq 62)"),
        P0=P0,
        tau_grid=tau_grid.value,
        fc_grid=fcs,
        include_logdet=include_logdet,
        zdot=zdot.value,
        sigma=sigma,
    )


def read_radar_record(t: Table) -> tuple[np.ndarray, np.ndarray, Vehicle2D, np.ndarray]:
    """Times, [range, bearing] in radians (N, 2), the vehicle the filters assume, and the Table I chips.

    Refuses (one line, file and line named) a range ≤ 0 (a target at the radar has no bearing), a
    non-finite value, an unknown bearing unit, and a bearing column beyond ±π labelled radians.
    """
    missing = [k for k in NEEDED_META_2D if k not in t.meta]
    absent = [c for c in ("range", "bearing") if c not in t.columns]
    if missing or absent:
        what = [f"metadata {m!r}" for m in missing] + [f"column {c!r}" for c in absent]
        raise InputError(
            f"{t.source}: missing {', '.join(what)} (produce the record with 'motionsig simulate --example 2d')"
        )
    times = uniform_times(t)
    rng_ = finite_column(t, "range")
    brg = finite_column(t, "bearing")
    bad = np.flatnonzero(rng_ <= 0)
    if bad.size:
        raise InputError(
            f"{t.source}:{t.lines[bad[0]]}: range {rng_[bad[0]]:g} <= 0: the target is at the radar (bearing undefined)"
        )
    unit = str(t.meta.get("bearing_unit", "rad"))
    if unit not in BEARING_UNITS:
        raise InputError(f"{t.source}: metadata 'bearing_unit' must be 'rad' or 'deg', got {unit!r}")
    limit = math.pi if unit == "rad" else 180.0
    over = np.flatnonzero(np.abs(brg) > limit * (1 + 1e-12))
    if over.size:
        hint = ' (degrees in a column labelled radians? set bearing_unit: "deg")' if unit == "rad" else ""
        raise InputError(
            f"{t.source}:{t.lines[over[0]]}: bearing {brg[over[0]]:g} is outside [-{limit:g}, {limit:g}] {unit}{hint}"
        )
    try:
        for key in ("start", "K"):
            v = t.meta[key]
            if not (isinstance(v, list) and len(v) == 2 and all(isinstance(e, int | float) for e in v)):
                raise ValueError(f"{key} must be a list of two numbers, got {v!r}")
        m_rho = t.meta["m_rho"]
        if isinstance(m_rho, bool) or not isinstance(m_rho, int) or m_rho < 1:
            raise ValueError(f"m_rho must be an integer >= 1, got {m_rho!r}")
        f_c = float(t.meta["f_c"])
        if not (math.isfinite(f_c) and f_c >= 0):
            raise ValueError(f"f_c must be finite and >= 0, got {t.meta['f_c']!r}")
        start = tuple(float(v) for v in t.meta["start"])
        vehicle = Vehicle2D(
            T=float(t.meta["T"]),
            K=tuple(float(k) for k in t.meta["K"]),
            a_sig=float(t.meta["a_sig"]),
            R_range=float(t.meta["R_range"]),
            R_bearing=float(t.meta["R_bearing"]),
            start=start,
        )
        chips = to_bipolar(table1_codes(str(t.meta["codes"]))).astype(float)
    except (ValueError, TypeError) as exc:
        raise InputError(f"{t.source}: bad metadata: {exc}") from None
    y = np.stack([rng_, brg * BEARING_UNITS[unit]], axis=-1)
    return times, y, vehicle, chips


def _check_size(n_filters: int, trials: int, n_samples: int, option: str, batch: int) -> None:
    """Refuse runs over ~1 h or ~4 GB before any work: ~(2 + 10/B) µs per filter-step for B records at
    once (measured), and the candidate replicas and transitions, ~6 arrays of (filters × samples) doubles."""
    seconds = float(n_filters) * trials * n_samples * (2 + 10 / batch) * 1e-6
    gb = 6.0 * n_filters * n_samples * 8 / 1e9
    if seconds > MAX_SECONDS or gb > MAX_GB:
        raise typer.BadParameter(
            f"~{seconds / 3600:.2g} h and ~{gb:.2g} GB (limits {MAX_SECONDS / 3600:g} h, {MAX_GB:g} GB): "
            "fewer trials, shorter horizons or a coarser grid",
            param_hint=option,
        )


def detect_radar_record(
    table: Table,
    cfg: RadarLMPConfig,
    fc_given: bool,
    horizons: str | None,
    threshold: float | None,
    candidates: bool,
    plot: Path | None,
    fmt: OutputFormat,
    out: Path | None,
    quiet: bool,
) -> None:
    """Eq (52) with the sigma-point bank on one radar record."""
    times, y, vehicle, chips = read_radar_record(table)
    meta = table.meta
    m_rho = int(meta["m_rho"])
    if not fc_given:
        cfg = replace(cfg, fc_grid=(float(meta["f_c"]),))
    T = vehicle.T
    hs = parse_horizons(horizons, times.size * T, T)
    hz = [round(h / T) for h in hs]
    n_used = max(hz)
    n_cand = len(candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg.as_grid))
    _check_size(2 * n_cand + 1, 1, n_used, "--horizons", 1)
    res = lmp_detect_radar(y[:n_used], chips, vehicle, m_rho, cfg, hz)
    params = dict(
        source=table.source,
        example="2d",
        filter="ukf",
        c_r=cfg.c_r,
        Q0=list(cfg.Q0),
        Q1=list(cfg.Q1),
        P0=cfg.P0,
        tau_grid=cfg.tau_grid,
        fc_grid=list(cfg.fc_grid),
        include_logdet=cfg.include_logdet,
        zdot=cfg.zdot,
        horizons_s=hs,
        threshold=threshold,
        **sigma_meta(cfg.sigma, res.repairs),
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
        f"horizon {hs[-1]:g} s, R_range = {vehicle.R_range:.3g}, R_bearing = {vehicle.R_bearing:.3g}, c_r = {cfg.c_r:g}",
        candidates=candidates,
        threshold=threshold,
        plot=plot,
        fmt=fmt,
        out=out,
        quiet=quiet,
    )


def montecarlo_radar(
    cfg: RadarLMPConfig,
    horizons: str | None,
    trials: int,
    fr_list: str,
    anr_pairs: str,
    no_signature: bool,
    seed: int,
    plot: Path | None,
    fmt: OutputFormat,
    out: Path | None,
    quiet: bool,
    engine: Engine | None = None,
) -> None:
    """Fig 7: % correct (i, τ) vs horizon for Fig 7's (angle, range) ANR pairs."""
    frs = checked("--fr-list", float_list, fr_list, what="frequency")
    if min(frs) < 0:
        raise typer.BadParameter("frequencies must be >= 0", param_hint="--fr-list")
    pair_ids = checked("--anr-pairs", int_list, anr_pairs, what="pair")
    if any(p not in (1, 2, 3, 4) for p in pair_ids):
        raise typer.BadParameter(f"Fig 7 has pairs 1-4, got {anr_pairs!r}", param_hint="--anr-pairs")
    vehicle = Vehicle2D()
    f_c, m_rho = 1.0, 20
    hs = (
        parse_horizons(horizons, 80.0, vehicle.T)
        if horizons is None
        else checked("--horizons", float_list, horizons, what="horizon")
    )
    if min(hs) <= 0 or max(hs) > 1e6 or round(min(hs) / vehicle.T) < 1:
        raise typer.BadParameter(
            f"horizons must lie in [{vehicle.T:g}, 1e6] seconds", param_hint="--horizons"
        )
    if max(frs) > 1e6:
        raise typer.BadParameter("frequencies must be <= 1e6 Hz", param_hint="--fr-list")
    chips = to_bipolar(table1_codes("corrected")).astype(float)
    n_cand = len(candidate_grid(chips.shape[0], chips.shape[1], m_rho, cfg.as_grid))
    n = round(max(hs) / vehicle.T)
    _check_size(2 * n_cand + 1, trials * len(frs) * len(pair_ids), n, "--trials", min(trials, 25))
    pairs = [anr_pair_variances(p, vehicle.a_sig) for p in pair_ids]
    engine = engine or Engine()
    identity = dict(
        command="detect --montecarlo --example 2d", cfg=repr(cfg), fr_list=frs, pairs=pairs, horizons_s=hs,
        trials=trials, seed=seed, signature=not no_signature,
    )  # fmt: skip
    total = trials * len(pairs) * len(frs)
    with engine_session(engine, total, "Monte Carlo trials (2-D radar)", quiet) as advance:
        cells = monte_carlo_2d(
            vehicle,
            chips,
            m_rho,
            f_c,
            cfg,
            frs,
            pairs,
            hs,
            trials,
            seed,
            on_chunk=advance,
            signature=not no_signature,
            engine=engine,
            identity=identity,
        )
    rows = []
    for cell in cells:
        pid = pair_ids[cell.pair - 1]
        a_ang, a_rng = vehicle.a_sig**2 / (2 * cell.R_bearing), vehicle.a_sig**2 / (2 * cell.R_range)
        rows.append(
            (
                cell.f_r,
                pid,
                cell.R_range,
                cell.R_bearing,
                10 * math.log(a_ang),
                10 * math.log(a_rng),
                SEED_ANR_PAIRS[pid - 1][0],
                SEED_ANR_PAIRS[pid - 1][1],
                cell.horizon_s,
                cell.pct,
                cell.se_pct,
                cell.pct_mode,
                cell.correct,
                cell.trials,
                cell.repairs,
            )
        )
    meta = make_meta(
        "detect --montecarlo --example 2d",
        trials=trials,
        fr_list=frs,
        anr_pairs=pair_ids,
        horizons_s=hs,
        seed=seed,
        signature=not no_signature,
        filter="ukf",
        c_r=cfg.c_r,
        Q0=list(cfg.Q0),
        Q1=list(cfg.Q1),
        P0=cfg.P0,
        tau_grid=cfg.tau_grid,
        fc_grid=list(cfg.fc_grid),
        include_logdet=cfg.include_logdet,
        zdot=cfg.zdot,
        ut_alpha=cfg.sigma.alpha,
        ut_beta=cfg.sigma.beta,
        ut_kappa=cfg.sigma.kappa,
        T=vehicle.T,
        m_rho=m_rho,
        f_c=f_c,
        K=list(vehicle.K),
        a_sig=vehicle.a_sig,
        a_r=vehicle.a_r,
        sigma_a=vehicle.sigma_a,
        start=list(vehicle.start),
        sig_axes=vehicle.sig_axes,
        codes="corrected",
        n_candidates=n_cand,
        chance_pct=100.0 / n_cand,
        correct="mode_hat == mode and tau_hat == tau on the grid",
        anr="seed's 10*ln dB, a_sig^2 / (2 R) per channel; R_range inverted from the printed range label",
        trial_streams="trial t: SeedSequence(seed, spawn_key=(t, 0|1|2)) for (i,tau,theta) | (x,y) process | (range,bearing) noise",
    )
    table = Table(
        (
            "f_r",
            "anr_pair",
            "R_range",
            "R_bearing",
            "anr_angle_db_paper_ln",
            "anr_range_db_paper_ln",
            "seed_angle_label",
            "seed_range_label",
            "horizon_s",
            "pct_correct",
            "se_pct",
            "pct_mode_correct",
            "correct",
            "trials",
            "covariance_repairs",
        ),
        rows,
        meta,
    )
    if plot is not None:
        from motionsig_cli.plotting import montecarlo_figure

        curves: dict[float, dict[str, tuple[np.ndarray, np.ndarray]]] = {}
        for fr in frs:
            curves[fr] = {}
            for k, pid in enumerate(pair_ids, start=1):
                sel = [c for c in cells if c.f_r == fr and c.pair == k]
                ang, rg = SEED_ANR_PAIRS[pid - 1]
                curves[fr][f"({ang:g}, {rg:g})"] = (
                    np.array([c.pct for c in sel]),
                    np.array([c.se_pct for c in sel]),
                )
        save_figure(
            montecarlo_figure(
                np.array(hs), curves, f"2-D radar, UKF bank: {trials} trials per cell, c_r = {cfg.c_r:g}"
            ),
            plot,
        )
    emit(table, fmt.value, out)
    reps = sum(c.repairs for c in cells) // max(1, len(hs))
    note(
        f"{len(cells)} cells x {trials} trials; chance level {100.0 / n_cand:.2f} %; "
        f"{reps} covariance repairs",
        quiet,
    )
