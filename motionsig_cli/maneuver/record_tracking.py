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
models, 1 − μ_CV, rises above ``declare[0]`` (0.8 in the aircraft tuning, 0.9 in the paper's), with hysteresis: the next declaration needs it to have
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

import hashlib
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any, ClassVar, Protocol

import numpy as np

from motionsig_cli.config import ConfigError, integer
from motionsig_cli.detection.glr import InputModel, input_tracker
from motionsig_cli.engine import Engine, run_job, run_tasks
from motionsig_cli.errors import InputError
from motionsig_cli.filters.consistency import REASONS, Consistency
from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.maneuver.record import TrackRecord, TrackSet, choose_sigma
from motionsig_cli.maneuver.study import TrackerConfig, _check_methods, _numerics
from motionsig_cli.models.motion import H_POS4, H_POS6, cv_input_model, cv_input_steps, two_point_restart
from motionsig_cli.tables import Table, format_rows, make_meta

__all__ = ["TASK_STEPS", "RecordJob", "RecordTrack", "TrackingPlan", "imm_declarations", "plan_tracking", "track_record",
           "track_records", "track_records_to_files"]


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


def _iso_many(origin: str, t: np.ndarray) -> list[str | None]:
    """:func:`_iso` of many times at once (numpy datetimes; the offset of the first timestamp kept)."""
    try:
        base = datetime.fromisoformat(origin.replace("Z", "+00:00"))
    except ValueError:
        return [None] * len(t)
    off = base.utcoffset()
    suffix = "" if off is None else ("Z" if off == timedelta(0) else base.isoformat()[-6:])
    t = np.asarray(t, float)
    ok = np.isfinite(t)
    stamp = np.datetime64(base.replace(tzinfo=None), "us") + np.round(np.where(ok, t, 0.0) * 1e6).astype(
        "timedelta64[us]"
    )
    text = np.datetime_as_string(stamp, unit="ms")
    return [f"{x}{suffix}" if k else None for x, k in zip(text.tolist(), ok.tolist(), strict=True)]


def _nullable(a: np.ndarray) -> list[float | None]:
    """Floats, NaN as None (an empty cell)."""
    return [None if v != v else v for v in a.tolist()]


@dataclass(frozen=True)
class _Segment:
    """One segment of one track: its first two measured steps a < b and the steps tracked after b."""

    track: int
    segment: int
    a: int
    b: int
    steps: np.ndarray


def _noise(rec: TrackRecord, sigma: float | str | None, cfg: TrackerConfig) -> tuple[np.ndarray, float, dict[str, Any], bool, bool]:
    """A track's measurement covariances (K, 2, 2), its σ (or median σ), the σ metadata, whether σ was
    estimated without being asked, and whether one σ serves every step."""
    if rec.R is not None and sigma is None:
        R = rec.R.copy()
        bad = np.flatnonzero(rec.measured & ~np.isfinite(R).all(axis=(1, 2)))
        if bad.size:
            i = int(bad[0])
            raise InputError(f"{rec.source}:{int(rec.line[i])}: the row has a position but no σ")
        R[~rec.measured] = np.eye(2)
        sd = np.sqrt(np.diagonal(R[rec.measured], axis1=1, axis2=2))
        s = float(np.median(sd))
        return R, s, {"sigma_source": "the record's covariances per row", "sigma_median": s}, False, False
    s, meta, implicit = choose_sigma(rec, sigma, cfg.sigma_floor)
    return np.broadcast_to(s * s * np.eye(2), (rec.z.shape[0], 2, 2)).copy(), s, meta, implicit, True


def _segments(recs: Sequence[TrackRecord]) -> tuple[list[_Segment], list[tuple[str, int]]]:
    """Every segment of every track with three measured steps, and (label, segment) of the others."""
    segs, skipped = [], []
    for ti, rec in enumerate(recs):
        measured = rec.measured
        for sg in np.unique(rec.segment):
            steps = np.flatnonzero(rec.segment == sg)
            meas = steps[measured[steps]]
            if meas.size < 3:
                skipped.append((rec.label, int(sg)))
                continue
            a, b = int(meas[0]), int(meas[1])
            segs.append(_Segment(ti, int(sg), a, b, steps[steps > b]))
    return segs, skipped


def track_records(
    tracks: TrackSet | Sequence[TrackRecord],
    methods: Sequence[str],
    cfg: TrackerConfig,
    *,
    sigma: float | str | None = None,
    consistency: Consistency | str | None = "tuned",
    bucket: int = 256,
) -> RecordTrack:
    """Track every segment of every track with every method in ``methods`` (module docstring): the segments
    of all tracks run through each tracker together, sorted by length and batched ``bucket`` at a time (the
    padding of a batch is then small), each with its own Δt, noise and checks.

    Args:
        tracks: the tracks (:func:`~motionsig_cli.maneuver.record.read_track_records`) or a sequence of
            :class:`~motionsig_cli.maneuver.record.TrackRecord`.
        methods: among :data:`~motionsig_cli.maneuver.study.METHODS`.
        cfg: the trackers' settings (:meth:`~motionsig_cli.maneuver.study.TrackerConfig.tuned`).
        sigma: σ per axis [m] (overrides the records' per-row covariances); ``"estimate"``; None: each track's
            covariances, else the metadata ``sigma``, else estimated per track.
        consistency: the checks; ``"tuned"``: those of ``cfg`` (:meth:`TrackerConfig.consistency`); None:
            unwatched, as the paper's Monte Carlo.
        bucket: most segments per batch.
    """
    plan = plan_tracking(tracks, methods, cfg, sigma=sigma, consistency=consistency, bucket=bucket)
    return run_job(RecordJob(plan))  # the tasks of the command, in this process: the command's numbers


@dataclass(frozen=True)
class TrackingPlan:
    """Every decision of a tracking run that concerns all tracks at once (each track's noise, the segments,
    the shared period and whether one σ serves every step), made before any tracker runs, so that the
    segments can be tracked in any grouping — in this process or on the engine's workers
    (:class:`RecordJob`) — with the same numbers."""

    recs: tuple[TrackRecord, ...]
    noise: tuple[tuple[np.ndarray, float, dict[str, Any], bool, bool], ...]
    segs: tuple[_Segment, ...]
    methods: tuple[str, ...]
    cfg: TrackerConfig
    consistency: Consistency | None
    fixed_T: float | None
    r_uniform: float | None
    T: float
    s_med: float
    bucket: int
    untracked: tuple[tuple[str, str], ...]
    skipped: tuple[tuple[str, int], ...]

    def track(self, which: Sequence[int]) -> dict[int, dict[str, dict[str, np.ndarray | None]]]:
        """The segments ``which``: segment → method → the tracker's arrays (batched longest first)."""
        which = list(which)
        order = sorted(which, key=lambda i: (-self.segs[i].steps.size, i))
        out: dict[int, dict[str, dict[str, np.ndarray | None]]] = {i: {} for i in which}
        Rs = [n[0] for n in self.noise]
        for idx in _buckets(order, [self.segs[i].steps.size for i in order], self.bucket):
            bt = _batch([self.segs[i] for i in idx], list(self.recs), Rs, self.fixed_T)
            for m in self.methods:
                with _numerics(self.s_med, self.T), np.errstate(all="ignore"):
                    res = _run(m, bt, self.cfg, self.consistency, self.T, self.fixed_T is not None, self.r_uniform)
                for j, i in enumerate(idx):
                    n = self.segs[i].steps.size
                    out[i][m] = {k: (None if v is None else v[j, :n]) for k, v in res.items()}
        return out

    def tables(self, done: Mapping[int, dict[str, dict[str, np.ndarray | None]]]) -> RecordTrack:
        """The output tables from every segment's arrays."""
        builder = _Builder(self)
        builder.add(done)
        return builder.finish()


def plan_tracking(
    tracks: TrackSet | Sequence[TrackRecord],
    methods: Sequence[str],
    cfg: TrackerConfig,
    *,
    sigma: float | str | None = None,
    consistency: Consistency | str | None = "tuned",
    bucket: int = 256,
) -> TrackingPlan:
    """The :class:`TrackingPlan` of :func:`track_records` (same arguments)."""
    _check_methods(methods)
    integer("bucket", bucket, 1)
    if isinstance(consistency, str):
        if consistency != "tuned":
            raise ConfigError("consistency", consistency, "is not a Consistency, None or 'tuned'")
        consistency = cfg.consistency()
    tset = tracks if isinstance(tracks, TrackSet) else None
    recs = list(tset.tracks if tset is not None else tracks)
    untracked = list(tset.untracked) if tset is not None else []
    kept, noise = [], []
    for rec in recs:
        try:
            noise.append(_noise(rec, sigma, cfg))
            kept.append(rec)
        except InputError as exc:
            if len(recs) == 1:
                raise
            untracked.append((rec.label, str(exc)))
    segs, skipped = _segments(kept)
    if not segs:
        raise InputError(f"{recs[0].source}: no segment has 3 measured steps (two initialise the trackers)")
    Ts = {rec.T for rec in kept}
    fixed_T = next(iter(Ts)) if (len(Ts) == 1 and all(r.grid for r in kept) and consistency is None) else None
    one_r = {n[1] for n in noise} if all(n[4] for n in noise) else set()
    r_uniform = next(iter(one_r)) ** 2 if len(one_r) == 1 else None
    T = fixed_T if fixed_T is not None else float(np.median([r.T for r in kept if math.isfinite(r.T)] or [1.0]))
    return TrackingPlan(tuple(kept), tuple(noise), tuple(segs), tuple(methods), cfg, consistency, fixed_T,
                        r_uniform, T, float(np.median([n[1] for n in noise])), bucket, tuple(untracked),
                        tuple(skipped))  # fmt: skip


TASK_STEPS = 200_000
"""Steps per task of a :class:`RecordJob` (whole tracks): large enough that a task's batches are wide (a task of
20,000 steps ran the quickstart collection at a third of the speed of one of 300,000: batches of a few segments
pay the per-step cost for few reports), small enough that a day's feed still spreads over many workers."""


@dataclass(frozen=True)
class RecordJob:
    """A record of many tracks on the engine (:func:`motionsig_cli.engine.run_job`): tasks of whole tracks,
    about :data:`TASK_STEPS` steps each, in the record's order of tracks (the chunking depends on the record
    only, never on the workers); each task tracks its segments with the plan's shared decisions, so the
    output is byte-identical for 1 worker, N workers and a Dask cluster, and a ``--checkpoint`` resumes it."""

    name: ClassVar[str] = "maneuver-record"
    plan: TrackingPlan
    text: bool = False
    """Each task returns its rows as CSV text (made where the task runs, so that the formatting spreads over
    the workers too) with its events and counts, instead of the trackers' arrays."""

    def identity(self) -> dict[str, Any]:
        h = hashlib.sha256()
        for rec in self.plan.recs:
            h.update(rec.label.encode() + b"\0")
            for a in (rec.z, rec.t, rec.segment):
                h.update(np.ascontiguousarray(a).tobytes())
        for n in self.plan.noise:
            h.update(np.ascontiguousarray(n[0]).tobytes())
        c = self.plan.consistency
        return {"record_sha256": h.hexdigest(), "methods": list(self.plan.methods), "config": self.plan.cfg.meta(),
                "consistency": c.meta() if c is not None else "off", "bucket": self.plan.bucket,
                **({"results": "csv text"} if self.text else {})}  # fmt: skip

    def tasks(self) -> list[tuple[int, ...]]:
        by_track: dict[int, list[int]] = {}
        for i, sg in enumerate(self.plan.segs):
            by_track.setdefault(sg.track, []).append(i)
        tasks, cur, size = [], [], 0
        for t in sorted(by_track):
            cur += by_track[t]
            size += sum(self.plan.segs[i].steps.size for i in by_track[t])
            if size >= TASK_STEPS:
                tasks.append(tuple(cur))
                cur, size = [], 0
        if cur:
            tasks.append(tuple(cur))
        return tasks

    def task_size(self, task: tuple[int, ...]) -> int:
        return int(sum(self.plan.segs[i].steps.size for i in task))

    def run_task(self, task: tuple[int, ...]) -> Any:
        done = self.plan.track(task)
        if not self.text:
            return [done[i] for i in task]
        texts = {m: _TextSink() for m in self.plan.methods}
        part = _Builder(self.plan, texts)
        part.add(done)
        return {"text": [texts[m].bytes() for m in self.plan.methods], "events": [part.erows[m] for m in self.plan.methods],
                "counts": part.counts, "tally": part.tally}  # fmt: skip

    def reduce(self, tasks: Sequence[tuple[int, ...]], results: Sequence[Any]) -> RecordTrack:
        done = {i: r for task, res in zip(tasks, results, strict=True) for i, r in zip(task, res, strict=True)}
        return self.plan.tables(done)


def track_records_to_files(
    plan: TrackingPlan,
    engine: Engine,
    directory: Path,
    *,
    progress: Callable[[int], None] | None = None,
) -> tuple[RecordTrack, list[Path]]:
    """:class:`RecordJob` of ``plan`` on ``engine`` with its rows written as they are computed: each task's
    tracks, once the tasks before it are done, become CSV text in one file per method under ``directory``,
    and their arrays are dropped. So a record of millions of rows holds its tracks and a few tasks'
    arrays, not its output. Returns the tables without their rows (the metadata and events complete) and
    the files, in method order: the output's rows are those files' text joined
    (:func:`motionsig_cli.cli.io.emit_spooled`), the bytes :func:`track_records` would give."""
    job = RecordJob(plan, text=len(plan.recs) > 1)  # one track: its arrays, for the figure
    tasks = job.tasks()
    spools = {m: _Spool(Path(directory) / f"rows-{k}-{m}.csv") for k, m in enumerate(plan.methods)}
    builder = _Builder(plan, spools)

    def consume(i: int, res: Any) -> None:
        if job.text:
            builder.merge(res)
        else:
            builder.add(dict(zip(tasks[i], res, strict=True)))

    try:
        run_tasks(job.run_task, tasks, engine, sizes=[job.task_size(t) for t in tasks], progress=progress,
                  identity={"command": job.name, **job.identity()}, consume=consume)  # fmt: skip
    finally:
        for sp in spools.values():
            sp.close()
    return builder.finish(), [spools[m].path for m in plan.methods]


STEP_COST_LANES = 64.0
"""The fixed cost of one step of a batch, in units of one segment's step within it (measured on 2 cores, IMM with
the checks: ~0.4 ms a step plus ~6 µs per segment; about the same for GLR), for :func:`_buckets`."""


def _buckets(order: list[int], lengths: list[int], size: int) -> list[list[int]]:
    """Segments sorted longest first, cut into batches of at most ``size`` so that the modelled time
    Σ_batches L_longest · (STEP_COST_LANES + |batch|) is least (a batch runs as many steps as its longest
    segment, each costing a fixed part and a part per segment, padding included): the exact optimum over cuts
    of the sorted order, by dynamic programming."""
    S = len(order)
    L = np.asarray(lengths, dtype=float)
    best = np.zeros(S + 1)  # best[j]: the least cost of the first j segments
    cut = [0] * (S + 1)
    for j in range(1, S + 1):  # the last batch is i..j-1, led by the longest, lengths[i]
        i = np.arange(max(0, j - size), j)
        c = best[i] + L[i] * (STEP_COST_LANES + (j - i))
        k = int(np.argmin(c))  # the first least: the shortest batch among equals
        best[j], cut[j] = c[k], int(i[k])
    out: list[list[int]] = []
    j = S
    while j > 0:
        out.append(order[cut[j] : j])
        j = cut[j]
    return out[::-1]


def track_record(
    rec: TrackRecord,
    methods: Sequence[str],
    cfg: TrackerConfig,
    *,
    sigma: float | str | None = None,
    consistency: Consistency | str | None = "tuned",
) -> RecordTrack:
    """Track every segment of one record (:func:`track_records` of one track)."""
    return track_records([rec], methods, cfg, sigma=sigma, consistency=consistency)


def _batch(chunk: list[_Segment], recs: list[TrackRecord], Rs: list[np.ndarray], fixed_T: float | None) -> dict[str, Any]:
    """The segments of a chunk as one padded batch (padding: predict-only steps of 1 s, dropped)."""
    S, L = len(chunk), max(sg.steps.size for sg in chunk)
    z = np.full((S, L, 2), np.nan)
    R = np.broadcast_to(np.eye(2), (S, L, 2, 2)).copy()
    dt = np.ones((S, L))
    za, zb, Ra, Rb, dt0 = (np.empty((S, 2)), np.empty((S, 2)), np.empty((S, 2, 2)), np.empty((S, 2, 2)),
                           np.empty(S))  # fmt: skip
    for i, sg in enumerate(chunk):
        rec, Rr, n = recs[sg.track], Rs[sg.track], sg.steps.size
        z[i, :n] = rec.z[sg.steps]
        R[i, :n] = Rr[sg.steps]
        prev = np.concatenate([[sg.b], sg.steps[:-1]])
        if rec.grid:  # whole scans of T (exactly: the paper's case)
            dt[i, :n] = (rec.scan[sg.steps] - rec.scan[prev]) * rec.T
            dt0[i] = (rec.scan[sg.b] - rec.scan[sg.a]) * rec.T
        else:
            dt[i, :n] = rec.t[sg.steps] - rec.t[prev]
            dt0[i] = rec.t[sg.b] - rec.t[sg.a]
        za[i], zb[i], Ra[i], Rb[i] = rec.z[sg.a], rec.z[sg.b], Rr[sg.a], Rr[sg.b]
    return {"z": z, "R": R, "dt": dt, "za": za, "zb": zb, "Ra": Ra, "Rb": Rb, "dt0": dt0}


def _run(
    m: str, bt: dict[str, Any], cfg: TrackerConfig, consistency: Consistency | None, T: float, fixed: bool,
    r_uniform: float | None,
) -> dict[str, np.ndarray | None]:  # fmt: skip
    """One method on a batch. On one scan grid without the checks, the fixed-period models and (with one σ)
    the one R: the paper's recursion, bit for bit."""
    dt = None if fixed else bt["dt"]
    R_steps = bt["R"] if r_uniform is None else None
    if m == "imm":
        x0, P0 = two_point_restart(bt["za"], bt["zb"], bt["dt0"], bt["Ra"], bt["Rb"], n=6)
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
    x0, P0 = two_point_restart(bt["za"], bt["zb"], bt["dt0"], bt["Ra"], bt["Rb"], n=4)
    it = input_tracker(bt["z"], model, x0, P0, cfg.glr("none" if m == "cv" else m), R=R_steps, dt=dt,
                       consistency=consistency)  # fmt: skip
    state = np.concatenate([it.x, it.u_cur], axis=-1)
    out: dict[str, np.ndarray | None] = {"state": state, "mu": None, "declared": None, "onset": None, "u": None,
                                         "nis": it.nis, "gated": it.gated, "reinit": it.reinit,
                                         "rejected": it.rejected}  # fmt: skip
    if m != "cv":
        out.update(declared=it.detected, onset=it.onset, u=it.u_jump)
    return out


class _RowSink(Protocol):
    """Where the output rows of one method go: a list (in memory) or a spool file (:class:`_Spool`)."""

    def extend(self, rows: Any) -> None: ...


class _Spool:
    """Rows written as CSV text (:func:`~motionsig_cli.tables.format_rows`) to a file as they come."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.fh = open(path, "w", encoding="utf-8", newline="")

    def extend(self, rows: Any) -> None:
        self.fh.write(format_rows(rows, plain=True))

    def write(self, text: str) -> None:
        self.fh.write(text)

    def close(self) -> None:
        self.fh.close()


def _flag_list(a: np.ndarray) -> list[bool]:
    return a.tolist()  # type: ignore[no-any-return]


def _flag_text(a: np.ndarray) -> list[str]:
    """Booleans as a CSV cell writes them (:func:`~motionsig_cli.tables.format_rows`)."""
    return np.where(a, "true", "false").tolist()  # type: ignore[no-any-return]


class _TextSink:
    """Rows as CSV text in memory (a task's, sent back from where it ran)."""

    def __init__(self) -> None:
        self.parts: list[str] = []

    def extend(self, rows: Any) -> None:
        self.parts.append(format_rows(rows, plain=True))

    def bytes(self) -> np.ndarray:
        """The UTF-8 text as a byte array (an array travels and checkpoints as data, not as a long string)."""
        return np.frombuffer("".join(self.parts).encode("utf-8"), dtype=np.uint8)


class _Builder:
    """The output tables of a tracking run, built a task of whole tracks at a time (:meth:`add`, in the
    record's order of tracks), the rows of each method going to that method's sink; :meth:`finish` gives
    the :class:`RecordTrack` (rows in method order, then track, then segment) with the metadata of all."""

    def __init__(self, plan: TrackingPlan, sinks: Mapping[str, _RowSink] | None = None) -> None:
        self.plan = plan
        recs = plan.recs
        rec0 = recs[0]
        self.origin = rec0.record.time_origin
        self.geo = rec0.frame is not None
        self.labelled = any(r.label for r in recs)
        self.many = len(recs) + len(plan.untracked) > 1
        lead = ["track"] if self.labelled else []
        cols = [*lead, "method", "scan", "t", "measured", "x", "vx", "y", "vy", "ax", "ay", "mu_1", "mu_2", "mu_3",
                "declared", "onset", "segment", "onset_t", "nis", "gated", "reinit"]  # fmt: skip
        ecols = [*lead, "method", "segment", "scan", "t", "onset_scan", "onset_t", "u_x", "u_y", "x", "y"]
        if self.origin is not None:
            cols += ["time", "onset_time"]
            ecols += ["time", "onset_time"]
        if self.geo:
            cols += ["latitude", "longitude"]
            ecols += ["latitude", "longitude"]
        self.cols, self.ecols = cols, ecols
        self.rows: dict[str, _RowSink] = dict(sinks) if sinks is not None else {m: [] for m in plan.methods}  # type: ignore[misc]
        self.text = sinks is not None  # rows as CSV text: the flags written "true"/"false" here, once per column
        self.erows: dict[str, list[tuple[Any, ...]]] = {m: [] for m in plan.methods}
        self.counts = {m: {name: 0 for name in REASONS[1:]} for m in plan.methods}
        self.tally = {m: {"gated": 0, "declarations": 0, "rejected": 0} for m in plan.methods}
        self.by_track: dict[int, list[int]] = {}
        for i, sg in enumerate(plan.segs):
            self.by_track.setdefault(sg.track, []).append(i)
        self.fig = recs[0] if len(recs) == 1 else None
        self.figure: dict[str, dict[str, Any]] = {"tracks": {}, "speeds": {}, "declarations": {}}
        self.mu_full: np.ndarray | None = None
        if self.fig is not None:
            K = self.fig.z.shape[0]
            for m in plan.methods:
                self.figure["tracks"][m.upper()] = np.full((K, 2), np.nan)
                self.figure["speeds"][m.upper()] = np.full(K, np.nan)
                self.figure["declarations"][m.upper()] = []
            if "imm" in plan.methods:
                self.mu_full = np.full((K, 3), np.nan)

    def merge(self, part: Mapping[str, Any]) -> None:
        """A task's rows as text, its events and counts (:meth:`RecordJob.run_task` with ``text``), the next
        tracks in the record's order."""
        for m, text, events in zip(self.plan.methods, part["text"], part["events"], strict=True):
            sink = self.rows[m]
            assert isinstance(sink, _Spool)
            sink.write(bytes(text).decode("utf-8"))
            self.erows[m].extend(tuple(e) for e in events)
            for k, v in part["counts"][m].items():
                self.counts[m][k] += v
            for k, v in part["tally"][m].items():
                self.tally[m][k] += v

    def add(self, done: Mapping[int, dict[str, dict[str, np.ndarray | None]]]) -> None:
        """The rows of the segments ``done`` (segment → method → the tracker's arrays): whole tracks, the
        next ones in the record's order."""
        tracks = sorted({self.plan.segs[i].track for i in done})
        for m in self.plan.methods:
            for ti in tracks:
                for i in self.by_track[ti]:
                    self._segment_rows(m, ti, i, done[i][m])

    def _segment_rows(self, m: str, ti: int, i: int, r: dict[str, np.ndarray | None]) -> None:
        rec, sg, origin, fig = self.plan.recs[ti], self.plan.segs[i], self.origin, self.fig
        label = [rec.label] if self.labelled else []
        steps, n = sg.steps, sg.steps.size
        st = r["state"]
        assert st is not None
        if fig is not None:
            self.figure["tracks"][m.upper()][steps] = st[:, [0, 2]]
            self.figure["speeds"][m.upper()][steps] = np.hypot(st[:, 1], st[:, 3])
            if r["mu"] is not None and self.mu_full is not None:
                self.mu_full[steps] = r["mu"]
        latlon = rec.frame.to_geodetic(st[:, 0], st[:, 2]) if self.geo else None
        mu, det, ons = r["mu"], r["declared"], r["onset"]
        nis = r["nis"] if r["nis"] is not None else np.full(n, np.nan)
        gated = r["gated"] if r["gated"] is not None else np.zeros(n, bool)
        reinit = r["reinit"] if r["reinit"] is not None else np.zeros(n, np.int8)
        tally = self.tally[m]
        tally["gated"] += int(gated.sum())
        if r["rejected"] is not None:
            tally["rejected"] += int(r["rejected"].sum())
        for code in reinit[reinit > 0]:
            self.counts[m][REASONS[int(code)]] += 1
        g = steps
        onset_scan: list[Any] = [None] * n
        onset_t: list[Any] = [None] * n
        onset_iso: list[Any] = [None] * n
        if det is not None and ons is not None:
            hit = np.flatnonzero(det & (ons >= 0))
            og = np.where(ons[hit] < n, steps[np.minimum(ons[hit], n - 1)], steps[hit])
            o_scan, o_t = rec.scan[og].tolist(), rec.t[og].tolist()
            o_iso = _iso_many(origin, rec.t[og]) if origin is not None else [None] * hit.size
            u = r["u"][hit] if r["u"] is not None else np.full((hit.size, 2), np.nan)
            t_iso = _iso_many(origin, rec.t[steps[hit]]) if origin is not None else []
            for q, j in enumerate(hit.tolist()):
                onset_scan[j], onset_t[j], onset_iso[j] = o_scan[q], o_t[q], o_iso[q]
                if fig is not None:
                    self.figure["declarations"][m.upper()].append((int(steps[j]), int(og[q])))
                ev: list[Any] = [*label, m, sg.segment, int(rec.scan[steps[j]]), float(rec.t[steps[j]]),
                                 o_scan[q], o_t[q], _f(u[q, 0]), _f(u[q, 1]), float(st[j, 0]),
                                 float(st[j, 2])]  # fmt: skip
                if origin is not None:
                    ev += [t_iso[q], o_iso[q]]
                if latlon is not None:
                    ev += [float(latlon[0][j]), float(latlon[1][j])]
                self.erows[m].append(tuple(ev))
            tally["declarations"] += hit.size
        flags = _flag_text if self.text else _flag_list
        columns: list[list[Any]] = [
            *([[rec.label] * n] if self.labelled else []),
            [m] * n,
            rec.scan[g].tolist(),
            rec.t[g].tolist(),
            flags(rec.measured[g]),
            *(st[:, c].tolist() for c in range(st.shape[1])),
            *(([None] * n,) * 3 if mu is None else (mu[:, c].tolist() for c in range(3))),
            [None] * n if det is None else flags(det),
            onset_scan,
            [sg.segment] * n,
            onset_t,
            _nullable(nis),
            flags(gated),
            [REASONS[c] or None for c in reinit.tolist()],
        ]
        if origin is not None:
            columns += [_iso_many(origin, rec.t[g]), onset_iso]
        if latlon is not None:
            columns += [latlon[0].tolist(), latlon[1].tolist()]
        self.rows[m].extend(zip(*columns, strict=True))

    def finish(self) -> RecordTrack:
        """The tables (rows in memory, or none where the rows went to spool files) and the summary."""
        plan = self.plan
        recs, methods, cfg, consistency = list(plan.recs), plan.methods, plan.cfg, plan.consistency
        segs, noise, untracked, skipped = list(plan.segs), list(plan.noise), list(plan.untracked), list(plan.skipped)
        rec0, many, fig = recs[0], self.many, self.fig
        summary: dict[str, dict[str, int]] = {}
        for m in methods:
            counts, tally = self.counts[m], self.tally[m]
            summary[m] = {"declarations": tally["declarations"], "gated": tally["gated"],
                          "rejected_declarations": tally["rejected"], "restarts": sum(counts.values()),
                          **{f"restarts_{k}": v for k, v in counts.items()}}  # fmt: skip
        steps_all = sum(r.z.shape[0] for r in recs)
        missed = sum(int((~r.measured).sum()) for r in recs)
        S = len(segs)
        if many:
            sig_meta: dict[str, Any] = {
                "sigma": float(np.median([nz[1] for nz in noise])),
                "sigma_source": "per track (see sigma_by_track)",
                "sigma_by_track": {r.label: nz[1] for r, nz in zip(recs, noise, strict=True)},
            }
            hygiene: dict[str, Any] = {"policy": rec0.hygiene.get("policy"), "max_gap_s": "per track"}
            for key in ("reordered", "exact_duplicates", "conflicting_duplicates", "empty_duplicates",
                        "stale_repeats", "gaps"):  # fmt: skip
                hygiene[key] = sum(int(r.hygiene.get(key, 0)) for r in recs)
            T_meta: dict[str, Any] = {"T": float(np.median([r.T for r in recs])), "T_source": "per track (median)"}
        else:
            sig_meta = {"sigma": noise[0][1], **noise[0][2]}
            hygiene = rec0.hygiene
            T_meta = {"T": rec0.T, "T_source": rec0.T_source}
        meta = make_meta(
            "maneuver",
            **rec0.record.provenance(),
            **T_meta,
            grid=all(r.grid for r in recs),
            position_form=rec0.form,
            conversion=rec0.conversion,
            hygiene=hygiene,
            **sig_meta,
            steps=steps_all,
            measured_steps=steps_all - missed,
            missed_scans=missed,
            segments=S + len(skipped),
            untracked_segments=[seg for _lab, seg in skipped] if not many else [list(x) for x in skipped],
            init="two-point differencing on the first two measured scans of each segment (velocity over their time "
            "difference, covariances of both): "
            + "; ".join(f"{int(recs[sg.track].scan[sg.a])} and {int(recs[sg.track].scan[sg.b])}" for sg in segs[:20]),
            methods=list(methods),
            config=cfg.meta(),
            transition=[list(row) for row in cfg.Pi],
            mu0=list(cfg.mu0),
            consistency=consistency.meta() if consistency is not None else "off",
            summary=summary,
            imm_declaration=f"1 - mu_CV above {cfg.declare[0]:g}, again only after falling below "
            f"{cfg.declare[1]:g}; onset: the last step below {cfg.declare[1]:g}",
            **({"tracks": len(recs), "untracked_tracks": [list(x) for x in untracked]} if many else {}),
        )
        rows: list[tuple[Any, ...]] = []
        for m in methods:
            if isinstance(self.rows[m], list):
                rows.extend(self.rows[m])  # type: ignore[arg-type]
        table = Table(columns=tuple(self.cols), rows=rows, meta=meta)
        events = Table(columns=tuple(self.ecols), rows=[e for m in methods for e in self.erows[m]],
                       meta={**meta, "view": "events"})  # fmt: skip
        s0 = sig_meta["sigma"]
        if fig is not None:
            figure = {"z": fig.z, "scan": fig.scan, "first": 0, "tracks": self.figure["tracks"],
                      "speeds": self.figure["speeds"], "declarations": self.figure["declarations"], "mu": self.mu_full,
                      "model_names": cfg.models(fig.T if math.isfinite(fig.T) else 1.0).names,
                      "title": f"{fig.source}: σ = {s0:.4g} m, {steps_all} steps, {missed} missed, {S} segment"
                      f"{'s' * (S != 1)}"}  # fmt: skip
        else:
            figure = {}
        parts = [f"{m} {v['declarations']} declaration{'s' * (v['declarations'] != 1)}"
                 + (f", {v['restarts']} restart{'s' * (v['restarts'] != 1)}" if v["restarts"] else "")
                 for m, v in summary.items()]  # fmt: skip
        how = str(sig_meta["sigma_source"]).split(":")[0]
        what = (f"{len(recs)} tracks ({len(untracked)} untracked)" if many else f"track {rec0.label}"
                if self.labelled else "1 track")  # fmt: skip
        note = (
            f"tracked {steps_all} steps of {rec0.source} ({what}) in {S} segment{'s' * (S != 1)} ({missed} without a "
            f"position) with {', '.join(methods)}; σ = {s0:.4g} m ({how}); " + "; ".join(parts)
        )
        return RecordTrack(table, events, note, figure, any(nz[3] for nz in noise))


def _f(v: Any) -> float | None:
    v = float(v)
    return v if math.isfinite(v) else None
