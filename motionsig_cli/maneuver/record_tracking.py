"""One user's track record (:mod:`motionsig_cli.maneuver.record`) through the manoeuvre trackers of Yao, Teng &
Wu: the IMM of three Kalman filters, the GLR and MLR input-estimation trackers, and the constant-velocity
Kalman filter — every segment of the record at once (a batch), each step with its own Δt, every tracker
watching its own consistency (:mod:`motionsig_cli.filters.consistency`).

**Segments.** Each segment (the record cut at its coverage gaps) starts by two-point differencing (§IV) on
its first two measured steps a < b, with their covariances (velocity (z_b − z_a)/(t_b − t_a)), and is
tracked from the step after b. A segment with fewer than three measured steps is not tracked and is listed
in the metadata (``untracked_segments``). The segments run through the trackers as one batch, padded to the
longest (padding is a predict-only step whose output is dropped).

**Declarations.** GLR and MLR declare as in §III (the onset n̂ of eq 3). The IMM declares too, so every
method can be compared on one record: a manoeuvre is declared when the probability of the manoeuvring
models, 1 − μ_CV, rises above ``declare[0]`` (0.9), with hysteresis: the next declaration needs it to have
fallen below ``declare[1]`` (0.5) first; the onset is the last step before the declaration at which it was
below ``declare[1]`` (where the rise began).

**Output** (one row per method and step): the state, the IMM's model probabilities, ``declared`` and
``onset`` (the onset's scan), ``onset_t``, and the consistency columns ``nis`` (the normalised innovation
squared), ``gated`` (a measurement rejected as an outlier) and ``reinit`` (the reason the track restarted
at that step, empty if it did not); ``time`` and ``onset_time`` as ISO 8601 when the record's times were
timestamps; ``latitude``/``longitude`` when the record was geodetic or polar. The events table has one row
per declaration.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.glr import InputModel, input_tracker
from motionsig_cli.errors import InputError
from motionsig_cli.filters.consistency import REASONS, Consistency
from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.maneuver.record import TrackRecord, choose_sigma
from motionsig_cli.maneuver.study import TrackerConfig, _check_methods, _numerics
from motionsig_cli.models.motion import H_POS4, H_POS6, cv_input_model, cv_input_steps, two_point_restart
from motionsig_cli.tables import Table, make_meta

__all__ = ["RecordTrack", "imm_declarations", "track_record"]


@dataclass(frozen=True)
class RecordTrack:
    """One record tracked by every requested method.

    Attributes:
        table: one row per method and tracked step, with the provenance.
        events: one row per declared manoeuvre.
        note: a one-line summary.
        figure: keyword arguments of :func:`motionsig_cli.plotting.maneuver_record_figure`.
        sigma_estimated: σ was estimated because none was given or in the record (the command says so).
    """

    table: Table
    events: Table
    note: str
    figure: dict[str, Any]
    sigma_estimated: bool


def imm_declarations(p_man: np.ndarray, on: float, off: float) -> tuple[np.ndarray, np.ndarray]:
    """IMM declarations with hysteresis (module docstring) from the manoeuvre probability p (B, N).

    Returns:
        declared (B, N) and onset (B, N): the step index where the rise began (−1 where none).
    """
    B, N = p_man.shape
    idx = np.arange(N)
    code = np.where(p_man > on, 1, np.where(p_man < off, 0, -1))  # −1: keep the state before
    last = np.maximum.accumulate(np.where(code >= 0, idx, -1), axis=1)
    state = np.where(last >= 0, np.take_along_axis(code, np.maximum(last, 0), axis=1), 0)
    before = np.concatenate([np.zeros((B, 1), int), state[:, :-1]], axis=1)
    declared = (state == 1) & (before == 0)
    low = np.maximum.accumulate(np.where(p_man < off, idx, -1), axis=1)  # the last step below 'off'
    onset = np.where(declared, np.maximum(low, 0), -1)
    return declared, onset


def _batch(rec: TrackRecord, R: np.ndarray) -> dict[str, Any]:
    """The segments as a padded batch (module docstring)."""
    measured = rec.measured
    segs, starts, tracked, skipped = [], [], [], []
    for s in np.unique(rec.segment):
        steps = np.flatnonzero(rec.segment == s)
        meas = steps[measured[steps]]
        if meas.size < 3:
            skipped.append(int(s))
            continue
        a, b = int(meas[0]), int(meas[1])
        segs.append(int(s))
        starts.append((a, b))
        tracked.append(steps[steps > b])
    S = len(segs)
    L = max((t.size for t in tracked), default=0)
    z = np.full((S, L, 2), np.nan)
    Rb = np.broadcast_to(np.eye(2), (S, L, 2, 2)).copy()
    dt = np.ones((S, L))
    for i, steps in enumerate(tracked):
        n = steps.size
        z[i, :n] = rec.z[steps]
        Rb[i, :n] = R[steps]
        prev = np.concatenate([[starts[i][1]], steps[:-1]])
        if rec.grid:  # whole scans of T (exactly: the paper's case)
            dt[i, :n] = (rec.scan[steps] - rec.scan[prev]) * rec.T
        else:
            dt[i, :n] = rec.t[steps] - rec.t[prev]
    a = np.array([s[0] for s in starts], dtype=np.int64)
    b = np.array([s[1] for s in starts], dtype=np.int64)
    return {"segments": segs, "skipped": skipped, "steps": tracked, "z": z, "R": Rb, "dt": dt, "a": a, "b": b}


def _iso(origin: str | None, t: float) -> str | None:
    """ISO 8601 of t seconds after the record's first timestamp (None without one)."""
    if origin is None or not math.isfinite(t):
        return None
    text = origin.replace("Z", "+00:00")
    try:
        base = datetime.fromisoformat(text)
    except ValueError:
        return None
    out = (base + timedelta(seconds=t)).isoformat(timespec="milliseconds")
    return out.replace("+00:00", "Z")


def track_record(
    rec: TrackRecord,
    methods: Sequence[str],
    cfg: TrackerConfig,
    *,
    sigma: float | str | None = None,
    consistency: Consistency | str | None = "tuned",
) -> RecordTrack:
    """Track every segment of a record with every method in ``methods`` (module docstring).

    Args:
        rec: the record (:func:`~motionsig_cli.maneuver.record.read_track_record`).
        methods: among :data:`~motionsig_cli.maneuver.study.METHODS`.
        cfg: the trackers' settings (:meth:`~motionsig_cli.maneuver.study.TrackerConfig.tuned`).
        sigma: σ per axis [m] (overrides the record's per-row covariances); ``"estimate"``; None: the
            record's covariances, else its metadata ``sigma``, else estimated.
        consistency: the checks; ``"tuned"``: those of ``cfg`` (:meth:`TrackerConfig.consistency`); None:
            unwatched, as the paper's Monte Carlo.
    """
    _check_methods(methods)
    if isinstance(consistency, str):
        if consistency != "tuned":
            raise ConfigError("consistency", consistency, "is not a Consistency, None or 'tuned'")
        consistency = cfg.consistency()
    if rec.R is not None and sigma is None:
        R = rec.R.copy()
        bad = np.flatnonzero(rec.measured & ~np.isfinite(R).all(axis=(1, 2)))
        if bad.size:
            i = int(bad[0])
            raise InputError(f"{rec.source}:{int(rec.line[i])}: the row has a position but no σ")
        R[~rec.measured] = np.eye(2)
        sd = np.sqrt(np.diagonal(R[rec.measured], axis1=1, axis2=2))
        s = float(np.median(sd))
        sigma_meta: dict[str, Any] = {"sigma_source": "the record's covariances per row",
                                      "sigma_median": s}  # fmt: skip
        implicit = False
    else:
        s, sigma_meta, implicit = choose_sigma(rec, sigma, cfg.sigma_floor)
        R = np.broadcast_to(s * s * np.eye(2), (rec.z.shape[0], 2, 2)).copy()
    bt = _batch(rec, R)
    if not bt["segments"]:
        raise InputError(f"{rec.source}: no segment has 3 measured steps (two initialise the trackers)")
    S = len(bt["segments"])
    a, b = bt["a"], bt["b"]
    dt0 = (rec.scan[b] - rec.scan[a]) * rec.T if rec.grid else rec.t[b] - rec.t[a]
    T = rec.T if math.isfinite(rec.T) else float(np.median(bt["dt"]))
    results: dict[str, dict[str, np.ndarray | None]] = {}
    for m in methods:
        with _numerics(s, T), np.errstate(all="ignore"):
            results[m] = _run(m, bt, rec, R, dt0, cfg, consistency, T, None if rec.R is not None and sigma is None
                              else s * s)  # fmt: skip
    return _tables(rec, methods, cfg, consistency, bt, results, s, sigma_meta, implicit, S)


def _run(
    m: str, bt: dict[str, Any], rec: TrackRecord, R: np.ndarray, dt0: np.ndarray, cfg: TrackerConfig,
    consistency: Consistency | None, T: float, r_uniform: float | None,
) -> dict[str, np.ndarray | None]:  # fmt: skip
    """One method on the batch. On a scan grid without the checks, the fixed-period models and (with one σ)
    the one R: the paper's recursion, bit for bit."""
    a, b = bt["a"], bt["b"]
    fixed = rec.grid and consistency is None
    dt = None if fixed else bt["dt"]
    R_steps = bt["R"] if r_uniform is None else None
    z_a, z_b, R_a, R_b = rec.z[a], rec.z[b], R[a], R[b]
    if m == "imm":
        x0, P0 = two_point_restart(z_a, z_b, dt0, R_a, R_b, n=6)
        tr = imm_filter(bt["z"], H_POS6, bt["R"] if R_steps is not None else r_uniform, cfg.models(T), x0, P0,
                        dt=dt, consistency=consistency)  # fmt: skip
        mu = tr.mu
        declared, onset = imm_declarations(1.0 - mu[..., 0], *cfg.declare)
        return {"state": tr.x, "mu": mu, "declared": declared, "onset": onset, "u": None, "nis": tr.nis,
                "gated": tr.gated, "reinit": tr.reinit, "rejected": None}  # fmt: skip
    F, G, Q = cv_input_model(T, cfg.q0)
    q0 = cfg.q0
    R0 = np.eye(2) if r_uniform is None else r_uniform * np.eye(2)
    model = InputModel(F, G, Q, H_POS4, R0, steps=lambda d: cv_input_steps(d, q0))
    x0, P0 = two_point_restart(z_a, z_b, dt0, R_a, R_b, n=4)
    it = input_tracker(bt["z"], model, x0, P0, cfg.glr("none" if m == "cv" else m), R=R_steps, dt=dt,
                       consistency=consistency)  # fmt: skip
    state = np.concatenate([it.x, it.u_cur], axis=-1)
    out: dict[str, np.ndarray | None] = {"state": state, "mu": None, "declared": None, "onset": None, "u": None,
                                         "nis": it.nis, "gated": it.gated, "reinit": it.reinit,
                                         "rejected": it.rejected}  # fmt: skip
    if m != "cv":
        out.update(declared=it.detected, onset=it.onset, u=it.u_jump)
    return out


def _tables(
    rec: TrackRecord, methods: Sequence[str], cfg: TrackerConfig, consistency: Consistency | None,
    bt: dict[str, Any], results: dict[str, dict[str, np.ndarray | None]], s: float, sigma_meta: dict[str, Any],
    implicit: bool, S: int,
) -> RecordTrack:  # fmt: skip
    origin = rec.record.time_origin
    geo = rec.frame is not None
    K = rec.z.shape[0]
    cols = ["method", "scan", "t", "measured", "x", "vx", "y", "vy", "ax", "ay", "mu_1", "mu_2", "mu_3",
            "declared", "onset", "segment", "onset_t", "nis", "gated", "reinit"]  # fmt: skip
    if origin is not None:
        cols += ["time", "onset_time"]
    if geo:
        cols += ["latitude", "longitude"]
    ecols = ["method", "segment", "scan", "t", "onset_scan", "onset_t", "u_x", "u_y", "x", "y"]
    if origin is not None:
        ecols += ["time", "onset_time"]
    if geo:
        ecols += ["latitude", "longitude"]
    rows: list[tuple[Any, ...]] = []
    erows: list[tuple[Any, ...]] = []
    summary: dict[str, dict[str, int]] = {}
    figure_tracks, figure_speeds, figure_decl = {}, {}, {}
    mu_full = None
    measured = rec.measured
    for m in methods:
        r = results[m]
        state = r["state"]
        assert state is not None
        pos_full = np.full((K, 2), np.nan)
        spd_full = np.full(K, np.nan)
        decl: list[tuple[int, int]] = []
        counts = {name: 0 for name in REASONS[1:]}
        n_gated = n_decl = n_rej = 0
        if r["mu"] is not None:
            mu_full = np.full((K, 3), np.nan)
        latlon = None
        for i, steps in enumerate(bt["steps"]):
            n = steps.size
            st = state[i, :n]
            pos_full[steps] = st[:, [0, 2]]
            spd_full[steps] = np.hypot(st[:, 1], st[:, 3])
            if geo:
                latlon = rec.frame.to_geodetic(st[:, 0], st[:, 2])
            mu = r["mu"][i, :n] if r["mu"] is not None else None
            if mu is not None and mu_full is not None:
                mu_full[steps] = mu
            det = r["declared"][i, :n] if r["declared"] is not None else None
            ons = r["onset"][i, :n] if r["onset"] is not None else None
            nis = r["nis"][i, :n] if r["nis"] is not None else np.full(n, np.nan)
            gated = r["gated"][i, :n] if r["gated"] is not None else np.zeros(n, bool)
            reinit = r["reinit"][i, :n] if r["reinit"] is not None else np.zeros(n, np.int8)
            n_gated += int(gated.sum())
            if r["rejected"] is not None:
                n_rej += int(r["rejected"][i, :n].sum())
            for code in reinit[reinit > 0]:
                counts[REASONS[int(code)]] += 1
            for j in range(n):
                g = int(steps[j])
                onset = None
                onset_t = None
                if det is not None and ons is not None and det[j] and ons[j] >= 0:
                    og = int(steps[int(ons[j])]) if ons[j] < n else g
                    onset, onset_t = int(rec.scan[og]), float(rec.t[og])
                    decl.append((g, og))
                    n_decl += 1
                    u = r["u"][i, j] if r["u"] is not None else (math.nan, math.nan)
                    ev: list[Any] = [m, int(rec.segment[g]), int(rec.scan[g]), float(rec.t[g]), onset, onset_t,
                                     _f(u[0]), _f(u[1]), float(st[j, 0]), float(st[j, 2])]  # fmt: skip
                    if origin is not None:
                        ev += [_iso(origin, float(rec.t[g])), _iso(origin, onset_t)]
                    if geo and latlon is not None:
                        ev += [float(latlon[0][j]), float(latlon[1][j])]
                    erows.append(tuple(ev))
                row: list[Any] = [m, int(rec.scan[g]), float(rec.t[g]), bool(measured[g]),
                                  *(float(v) for v in st[j]),
                                  *((None, None, None) if mu is None else (float(v) for v in mu[j])),
                                  None if det is None else bool(det[j]), onset, int(rec.segment[g]), onset_t,
                                  _f(nis[j]), bool(gated[j]), REASONS[int(reinit[j])] or None]  # fmt: skip
                if origin is not None:
                    row += [
                        _iso(origin, float(rec.t[g])),
                        _iso(origin, onset_t) if onset_t is not None else None,
                    ]
                if geo and latlon is not None:
                    row += [float(latlon[0][j]), float(latlon[1][j])]
                rows.append(tuple(row))
        figure_tracks[m.upper()] = pos_full
        figure_speeds[m.upper()] = spd_full
        figure_decl[m.upper()] = decl
        summary[m] = {"declarations": n_decl, "gated": n_gated, "rejected_declarations": n_rej,
                      "restarts": sum(counts.values()), **{f"restarts_{k}": v for k, v in counts.items()}}  # fmt: skip
    missed = int(K - measured.sum())
    meta = make_meta(
        "maneuver",
        **rec.record.provenance(),
        T=rec.T,
        T_source=rec.T_source,
        grid=rec.grid,
        position_form=rec.form,
        conversion=rec.conversion,
        hygiene=rec.hygiene,
        sigma=s,
        **sigma_meta,
        steps=K,
        measured_steps=int(measured.sum()),
        missed_scans=missed,
        segments=S + len(bt["skipped"]),
        untracked_segments=bt["skipped"],
        init="two-point differencing on the first two measured scans of each segment (velocity over their time "
        "difference, covariances of both): "
        + "; ".join(
            f"{int(rec.scan[a_])} and {int(rec.scan[b_])}" for a_, b_ in zip(bt["a"], bt["b"], strict=True)
        ),
        methods=list(methods),
        config=cfg.meta(),
        transition=[list(row) for row in cfg.Pi],
        mu0=list(cfg.mu0),
        consistency=consistency.meta() if consistency is not None else "off",
        summary=summary,
        imm_declaration=f"1 - mu_CV above {cfg.declare[0]:g}, again only after falling below "
        f"{cfg.declare[1]:g}; onset: the last step below {cfg.declare[1]:g}",
    )
    table = Table(columns=tuple(cols), rows=rows, meta=meta)
    events = Table(columns=tuple(ecols), rows=erows, meta={**meta, "view": "events"})
    figure = {
        "z": rec.z,
        "scan": rec.scan,
        "first": 0,
        "tracks": figure_tracks,
        "speeds": figure_speeds,
        "declarations": figure_decl,
        "mu": mu_full,
        "model_names": cfg.models(rec.T if math.isfinite(rec.T) else 1.0).names,
        "title": f"{rec.source}: σ = {s:.4g} m, {K} steps, {missed} missed, {S} segment{'s' * (S != 1)}",
    }
    parts = [f"{m} {v['declarations']} declaration{'s' * (v['declarations'] != 1)}"
             + (f", {v['restarts']} restart{'s' * (v['restarts'] != 1)}" if v["restarts"] else "")
             for m, v in summary.items()]  # fmt: skip
    how = sigma_meta["sigma_source"].split(":")[0]
    note = (
        f"tracked {K} steps of {rec.source} in {S} segment{'s' * (S != 1)} ({missed} without a position) with "
        f"{', '.join(methods)}; σ = {s:.4g} m ({how}); " + "; ".join(parts)
    )
    return RecordTrack(table, events, note, figure, implicit)


def _f(v: Any) -> float | None:
    v = float(v)
    return v if math.isfinite(v) else None
