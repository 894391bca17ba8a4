"""The seed-002 scenario and its Monte Carlo: a target that turns twice, Cartesian position measurements, and
four trackers on the same runs — the IMM of three Kalman filters, the GLR and MLR input-estimation trackers,
and the constant-velocity Kalman filter they start from (spec §3.1–§3.6).

Scans are numbered k = 1..N as in the seed. Interval k covers (t_k, t_{k+1}]; the input u(k) is held over it:
p(k+1) = p(k) + v(k)T + ½u(k)T², v(k+1) = v(k) + u(k)T (exact constant-acceleration kinematics). Every
tracker initialises by two-point differencing at scan 2, so estimates start at scan 3.

Run r draws only from ``trial_rng(seed, r)``: the standard-normal measurement errors w_r (N, 2), scaled by σ.
Every σ and every method therefore sees the same w_r (common random numbers), and a result does not depend on
the number of runs, their order or how they are chunked.

The Monte Carlo (:class:`MCJob`) runs on the engine (:mod:`motionsig_cli.engine`): a task is a chunk of
consecutive runs at one σ (:func:`mc_task` returns the chunk's error sums and declarations), chunks are sized
from :func:`cost` only, and :func:`mc_reduce` adds the partial sums in task order — so a result is
byte-identical on 1 worker, N workers or a Dask cluster.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from functools import partial
from typing import Any

import numpy as np

from motionsig_cli.detection.glr import CHI2_2_999, GLRConfig, InputModel, input_tracker
from motionsig_cli.engine import Engine, run_tasks, tasks_of, trials_per_task
from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.models.motion import (
    H_POS4,
    H_POS6,
    MU0_PAPER,
    PI_PAPER,
    cv_input_model,
    imm_models,
    two_point_init,
)
from motionsig_cli.rng import trial_rng

__all__ = [
    "METHODS",
    "PRESETS",
    "DetectionSummary",
    "ErrorStats",
    "MCJob",
    "MCPartial",
    "MCResult",
    "ManeuverScenario",
    "SingularCovariance",
    "TrackerConfig",
    "Tracks",
    "detection_summary",
    "error_stats",
    "mc_reduce",
    "mc_task",
    "measurements",
    "monte_carlo",
    "run_trackers",
    "track",
]

METHODS = ("imm", "glr", "mlr", "cv")
"""Trackers: IMM (§IV), GLR and MLR input estimation (§II–III), and the constant-velocity KF (no detection)."""
PRESETS = ("literal", "turn90")
FIRST_SCAN = 3
"""First filtered scan (two-point initialisation at scan 2)."""
T_RANGE = (1e-3, 3600.0)
"""Scan periods accepted [s] (below 1 ms the two-point covariance 2σ²/T² leaves the range of doubles)."""
MAX_SECONDS = 600.0
"""Largest estimated run time accepted by the command layer."""


@dataclass(frozen=True)
class ManeuverScenario:
    """Trajectory of spec §3.5.

    Attributes:
        preset: ``literal`` (as printed: v(1) = (0, 450) m/s, u = (20, 20) m/s² on scans [200, 300),
            (3, 3) on [305, 330)) or ``turn90`` (exact 90° turns in the same windows: v(1) = (0, −450),
            u₁ = 450/(100T)·(1, 1), u₂ = −450/(25T)·(1, 1)).
        T: scan period [s] (not given by the seed: 1 s).
        scans: N (seed: 450).
        p0: initial position [m] (assumption: the origin).
    """

    preset: str = "literal"
    T: float = 1.0
    scans: int = 450
    p0: tuple[float, float] = (0.0, 0.0)
    segments: tuple[tuple[int, int, float, float], ...] = field(init=False, repr=False)
    v0: tuple[float, float] = field(init=False)

    def __post_init__(self) -> None:
        if self.preset not in PRESETS:
            raise ValueError(f"preset {self.preset!r} is not one of {', '.join(PRESETS)}")
        if not (math.isfinite(self.T) and T_RANGE[0] <= self.T <= T_RANGE[1]):
            raise ValueError(f"scan period T = {self.T:g} must be in [{T_RANGE[0]:g}, {T_RANGE[1]:g}] s")
        if not 3 <= self.scans <= 1_000_000:
            raise ValueError(f"scans = {self.scans} must be in [3, 1e6] (two scans initialise the trackers)")
        if not all(math.isfinite(v) for v in self.p0):
            raise ValueError("the initial position must be finite")
        if self.preset == "literal":
            segs = ((200, 300, 20.0, 20.0), (305, 330, 3.0, 3.0))
            v0 = (0.0, 450.0)
        else:
            a1, a2 = 450.0 / (100 * self.T), -450.0 / (25 * self.T)
            segs = ((200, 300, a1, a1), (305, 330, a2, a2))
            v0 = (0.0, -450.0)
        object.__setattr__(self, "segments", segs)
        object.__setattr__(self, "v0", v0)

    def inputs(self) -> np.ndarray:
        """u(k) for k = 1..N, (N, 2): the acceleration held over interval k."""
        u = np.zeros((self.scans, 2))
        for a, b, ux, uy in self.segments:
            u[a - 1 : min(b, self.scans + 1) - 1] = (ux, uy)
        return u

    def truth(self) -> np.ndarray:
        """[x, ẋ, y, ẏ] at scans 1..N, (N, 4), noise-free, exact constant-acceleration kinematics."""
        u, T = self.inputs(), self.T
        out = np.empty((self.scans, 4))
        p, v = np.array(self.p0, float), np.array(self.v0, float)
        for i in range(self.scans):
            out[i] = (p[0], v[0], p[1], v[1])
            p = p + v * T + 0.5 * u[i] * T * T
            v = v + u[i] * T
        return out

    def events(self) -> list[tuple[int, tuple[float, float]]]:
        """Input changes (onset scan n, jump u(n) − u(n−1)) that the record can show: n in GLR convention
        (u(n) first moves the position of scan n + 1), so n < N."""
        u = self.inputs()
        du = np.diff(np.vstack([np.zeros((1, 2)), u]), axis=0)
        changes = np.flatnonzero(np.any(du != 0, axis=1))
        return [(int(i + 1), (float(du[i, 0]), float(du[i, 1]))) for i in changes if i + 1 < self.scans]

    def phases(self) -> list[tuple[str, int, int]]:
        """Scan ranges [a, b) for the summary: cruise before the turns, each turn (with its transient), after."""
        segs = self.segments
        out = [("cruise", 50, segs[0][0]), ("turn 1", segs[0][0], segs[1][0]), ("turn 2", segs[1][0], segs[1][1] + 10),
               ("after", segs[1][1] + 50, self.scans + 1)]  # fmt: skip
        return [
            (name, max(a, FIRST_SCAN), min(b, self.scans + 1))
            for name, a, b in out
            if min(b, self.scans + 1) > a
        ]


@dataclass(frozen=True)
class TrackerConfig:
    """Tracker settings (spec §3.2–§3.4 defaults; the [ASSUMPTION]s are options)."""

    g2: str = "paper-fixed"
    Pi: tuple[tuple[float, ...], ...] = PI_PAPER
    mu0: tuple[float, ...] = MU0_PAPER
    q0: float = 1.0
    window: int = 10
    glr_threshold: float = CHI2_2_999
    mlr_threshold: float = 0.0
    sigma_u: float = 20.0
    correction: str = "exact"
    continuation: str = "estimate"

    def glr(self, method: str) -> GLRConfig:
        thr = {"glr": self.glr_threshold, "mlr": self.mlr_threshold, "none": math.inf}[method]
        return GLRConfig(method=method, window=self.window, threshold=thr, sigma_u=self.sigma_u,
                         correction=self.correction, continuation=self.continuation)  # fmt: skip


def measurements(sc: ManeuverScenario, sigma: float, runs: Sequence[int], seed: int) -> np.ndarray:
    """z (B, N, 2) = truth position + σ w_r, w_r from ``trial_rng(seed, r)`` (spec §3.1)."""
    if not (math.isfinite(sigma) and sigma > 0):
        raise ValueError(f"sigma = {sigma:g} must be a finite number > 0")
    pos = sc.truth()[:, [0, 2]]
    w = np.stack([trial_rng(seed, int(r)).standard_normal((sc.scans, 2)) for r in runs]) if len(runs) else (
        np.zeros((0, sc.scans, 2)))  # fmt: skip
    return pos[None] + sigma * w


@dataclass(frozen=True)
class Tracks:
    """One tracker's output on B runs for scans 3..N.

    Attributes:
        state: (B, N−2, 6) estimates [x, ẋ, y, ẏ, a_x, a_y] (the acceleration is the IMM's combined estimate
            or the GLR/MLR tracker's current input estimate; 0 for the CV filter).
        mu: (B, N−2, r) IMM model probabilities (None for the other trackers).
        detected, onset, u_jump: GLR/MLR declarations (onset as an absolute scan number, −1 if none).
        stat: (B, N−2) the maximum detection statistic of each scan (GLR/MLR).
    """

    state: np.ndarray
    mu: np.ndarray | None = None
    detected: np.ndarray | None = None
    onset: np.ndarray | None = None
    u_jump: np.ndarray | None = None
    stat: np.ndarray | None = None

    @property
    def pos(self) -> np.ndarray:
        """(B, N−2, 2) estimated positions."""
        return self.state[..., [0, 2]]


def track(method: str, z: np.ndarray, T: float, sigma: float, cfg: TrackerConfig) -> Tracks:
    """Run one tracker on measurement records z (B, N, 2) of scans 1..N."""
    if method not in METHODS:
        raise ValueError(f"method {method!r} is not one of {', '.join(METHODS)}")
    z = np.asarray(z, float)
    if z.ndim != 3 or z.shape[1] < 3 or z.shape[2] != 2:
        raise ValueError(f"z must be (runs, scans >= 3, 2); got shape {z.shape}")
    R = sigma * sigma * np.eye(2)
    if method == "imm":
        ms = imm_models(T, g2=cfg.g2, Pi=np.asarray(cfg.Pi), mu0=np.asarray(cfg.mu0))
        x0, P0 = two_point_init(z[:, 0], z[:, 1], T, sigma, n=6)
        tr = imm_filter(z[:, 2:], H_POS6, R, ms, x0, P0)
        return Tracks(tr.x, mu=tr.mu)
    F, G, Q = cv_input_model(T, cfg.q0)
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, sigma, n=4)
    it = input_tracker(
        z[:, 2:], InputModel(F, G, Q, H_POS4, R), x0, P0, cfg.glr("none" if method == "cv" else method)
    )
    state = np.concatenate([it.x, it.u_cur], axis=-1)
    if method == "cv":
        return Tracks(state)
    onset = np.where(it.onset >= 0, it.onset + FIRST_SCAN, -1)  # local index 0 is scan 3
    return Tracks(state, detected=it.detected, onset=onset, u_jump=it.u_jump, stat=it.stat)


def run_trackers(
    sc: ManeuverScenario,
    sigma: float,
    runs: Sequence[int],
    seed: int,
    methods: Sequence[str],
    cfg: TrackerConfig,
) -> dict[str, Tracks]:
    """All requested trackers on the same runs."""
    z = measurements(sc, sigma, runs, seed)
    return {m: track(m, z, sc.T, sigma, cfg) for m in methods}


@dataclass(frozen=True)
class MCResult:
    """One tracker's Monte Carlo result at one σ.

    Attributes:
        stats: eqs (14)–(15) and the RMS error per scan.
        track0: (N−2, 2) the estimated track of run 0 (Fig 2).
        mu: (N−2, r) mean IMM model probabilities, or None.
        detected, onset: (M, N−2) GLR/MLR declarations and onset estimates, or None.
    """

    stats: ErrorStats
    track0: np.ndarray
    mu: np.ndarray | None
    detected: np.ndarray | None
    onset: np.ndarray | None


class SingularCovariance(np.linalg.LinAlgError):
    """A covariance stopped being positive definite in floating point at this σ (a bad σ/T combination).
    Picklable (``args == (sigma,)``), so it crosses process boundaries intact."""

    def __init__(self, sigma: float) -> None:
        super().__init__(sigma)
        self.sigma = sigma

    def __str__(self) -> str:
        return f"numerically singular covariance at sigma = {self.sigma:g}"


@dataclass(frozen=True)
class MCJob:
    """A Monte Carlo: runs 0..runs−1 of every σ, tracked by ``methods``.

    A task is ``(σ index, range of runs)``; :meth:`tasks` chunks the runs into tasks of :meth:`runs_per_task`
    runs (``chunk``, or from the cost model), never from the number of workers, so the floating-point sums —
    added in task order by :func:`mc_reduce` — are the same however the tasks are spread.

    Attributes:
        chunk: runs per task (None: from :func:`cost`).
        quiet_fp: run the trackers under ``np.errstate(all="ignore")`` (in the worker, where it matters).
    """

    sc: ManeuverScenario
    sigmas: tuple[float, ...]
    runs: int
    seed: int
    methods: tuple[str, ...]
    cfg: TrackerConfig
    chunk: int | None = None
    quiet_fp: bool = False

    def __post_init__(self) -> None:
        if self.runs < 1:
            raise ValueError("at least one run")
        if not self.sigmas:
            raise ValueError("at least one sigma")
        if not self.methods or any(m not in METHODS for m in self.methods):
            raise ValueError(f"methods must be among {', '.join(METHODS)}; got {self.methods!r}")
        if self.chunk is not None and self.chunk < 1:
            raise ValueError("chunk must be >= 1")

    def runs_per_task(self) -> int:
        """``chunk``, or runs per task worth at least the engine's minimum task time *and* 4× the per-batch
        overhead of :func:`cost` (the trackers' Python loop over scans), so that chunking costs ≤ 25 % extra;
        at most 250 runs (bounded memory). Scales with ``$MOTIONSIG_MIN_TASK_SECONDS`` (tests: 1 run)."""
        if self.chunk is not None:
            return self.chunk
        fixed = cost(self.sc.scans, 0, self.methods, 1)
        per_run = cost(self.sc.scans, 1, self.methods, 1) - fixed
        return trials_per_task(per_run, fixed_seconds=fixed, at_most=250)

    def tasks(self) -> list[tuple[int, range]]:
        """(σ index, runs) in σ order, runs in increasing order within a σ."""
        per_task = self.runs_per_task()
        return [(i, r) for i in range(len(self.sigmas)) for r in tasks_of(self.runs, per_task)]

    def identity(self) -> dict[str, Any]:
        """Everything the task results depend on (JSON values), for a checkpoint's manifest."""
        return {
            "scenario": {
                "preset": self.sc.preset,
                "T": self.sc.T,
                "scans": self.sc.scans,
                "p0": list(self.sc.p0),
            },
            "sigmas": list(self.sigmas),
            "runs": self.runs,
            "seed": self.seed,
            "methods": list(self.methods),
            "tracker": asdict(self.cfg),
            "runs_per_task": self.runs_per_task(),
        }


@dataclass(frozen=True)
class MCPartial:
    """One tracker's sums over the runs of one task (error = truth − estimate, scans 3..N).

    Attributes:
        s1, s2: (N−2, 2) Σ e and Σ e² over the task's runs.
        mu: (N−2, r) Σ IMM model probabilities, or None.
        track0: (N−2, 2) run 0's estimated track if the task holds run 0, else None.
        detected, onset: (runs, N−2) GLR/MLR declarations, or None.
    """

    s1: np.ndarray
    s2: np.ndarray
    mu: np.ndarray | None
    track0: np.ndarray | None
    detected: np.ndarray | None
    onset: np.ndarray | None


def mc_task(job: MCJob, task: tuple[int, range]) -> dict[str, MCPartial]:
    """One task (module level: picklable): every tracker on the task's runs at σ = ``job.sigmas[i]``."""
    i, runs = task
    sigma = job.sigmas[i]
    truth = job.sc.truth()[FIRST_SCAN - 1 :, [0, 2]]
    try:
        with np.errstate(all="ignore") if job.quiet_fp else contextlib.nullcontext():
            tracks = run_trackers(job.sc, sigma, runs, job.seed, job.methods, job.cfg)
            out = {}
            for m, tr in tracks.items():
                err = truth[None] - tr.pos
                out[m] = MCPartial(
                    err.sum(axis=0),
                    (err * err).sum(axis=0),
                    None if tr.mu is None else tr.mu.sum(axis=0),
                    tr.pos[0] if runs.start == 0 and len(runs) else None,
                    tr.detected,
                    tr.onset,
                )
    except np.linalg.LinAlgError:
        raise SingularCovariance(sigma) from None
    return out


def mc_reduce(
    job: MCJob, tasks: Sequence[tuple[int, range]], partials: Sequence[dict[str, MCPartial]]
) -> dict[float, dict[str, MCResult]]:
    """Per σ and tracker, the Monte Carlo result: the tasks' sums added in task order (eqs 14–15)."""
    per_sigma: list[list[dict[str, MCPartial]]] = [[] for _ in job.sigmas]
    for (i, _), part in zip(tasks, partials, strict=True):
        per_sigma[i].append(part)
    n = job.runs
    n_scan = job.sc.scans - FIRST_SCAN + 1
    out: dict[float, dict[str, MCResult]] = {}
    for sigma, parts in zip(job.sigmas, per_sigma, strict=True):
        res = {}
        for m in job.methods:
            s1, s2 = np.zeros((n_scan, 2)), np.zeros((n_scan, 2))
            mu = track0 = None
            det, on = [], []
            for p in (part[m] for part in parts):
                s1 += p.s1
                s2 += p.s2
                if p.mu is not None:
                    mu = p.mu if mu is None else mu + p.mu
                if track0 is None:
                    track0 = p.track0
                if p.detected is not None:
                    det.append(p.detected)
                    on.append(p.onset)
            mean = s1 / n  # eq (14)
            msq = s2 / n
            sd = np.sqrt(np.maximum(msq - mean * mean, 0.0))  # eq (15)
            stats = ErrorStats(np.arange(FIRST_SCAN, job.sc.scans + 1), mean, sd, np.sqrt(msq.sum(axis=1)))
            res[m] = MCResult(stats, track0, None if mu is None else mu / n,
                              np.concatenate(det) if det else None, np.concatenate(on) if on else None)  # fmt: skip
        out[sigma] = res
    return out


def monte_carlo(
    sc: ManeuverScenario,
    sigma: float,
    n_runs: int,
    seed: int,
    methods: Sequence[str],
    cfg: TrackerConfig,
    *,
    chunk: int = 250,
    on_chunk: Callable[[int], None] | None = None,
    engine: Engine | None = None,
) -> dict[str, MCResult]:
    """Runs 0..n_runs−1 in chunks of ``chunk`` runs (memory stays bounded) on ``engine`` (default: in this
    process); sums of errors are accumulated in chunk order, so the result does not depend on the engine, and
    on the chunk size only through floating-point summation order. ``on_chunk`` gets each finished chunk's
    number of runs."""
    if n_runs < 1:
        raise ValueError("at least one run")
    job = MCJob(sc, (sigma,), n_runs, seed, tuple(methods), cfg, chunk=chunk)
    tasks = job.tasks()
    partials = run_tasks(
        partial(mc_task, job),
        tasks,
        Engine() if engine is None else engine,
        sizes=[len(r) for _, r in tasks],
        progress=on_chunk,
        identity={"command": "maneuver", **job.identity()},
    )
    return mc_reduce(job, tasks, partials)[sigma]


def cost(scans: int, runs: int, methods: Sequence[str], n_sigma: int) -> float:
    """Rough run time [s] on a 2-core machine: a per-scan loop overhead of ~0.25 ms per method plus ~15 µs per
    run-scan for the IMM, GLR and MLR and ~6 µs for the CV filter (measured: ``make bench``)."""
    per_run = sum(6e-6 if m == "cv" else 15e-6 for m in methods)
    return n_sigma * scans * (0.25e-3 * len(methods) + per_run * runs)


@dataclass(frozen=True)
class ErrorStats:
    """Per-scan error statistics over M runs (truth − estimate), scans 3..N.

    Attributes:
        scan: (N−2,) scan numbers.
        mean: (N−2, 2) ē_x, ē_y, eq (14).
        sd: (N−2, 2) σ_x̂, σ_ŷ, eq (15) (1/M normalisation as printed).
        rms: (N−2,) RMS position error √(mean over runs of e_x² + e_y²).
    """

    scan: np.ndarray
    mean: np.ndarray
    sd: np.ndarray
    rms: np.ndarray


def error_stats(sc: ManeuverScenario, pos: np.ndarray) -> ErrorStats:
    """Eqs (14)–(15) and the RMS position error of estimates pos (M, N−2, 2)."""
    truth = sc.truth()[FIRST_SCAN - 1 :, [0, 2]]
    err = truth[None] - pos  # truth − estimate (eq 14 sign)
    mean = err.mean(axis=0)  # ē(k), eq (14)
    msq = (err * err).mean(axis=0)
    sd = np.sqrt(np.maximum(msq - mean * mean, 0.0))  # σ(k), eq (15)
    rms = np.sqrt(msq.sum(axis=1))
    return ErrorStats(np.arange(FIRST_SCAN, sc.scans + 1), mean, sd, rms)


@dataclass(frozen=True)
class DetectionSummary:
    """Detection performance of a GLR/MLR tracker over M runs.

    Attributes:
        events: one row per true input change: (onset scan, jump (u_x, u_y), fraction of runs detected,
            mean and median delay [scans after the onset], mean and RMS onset-estimate error [scans]).
        false_alarms_per_1000: declarations per 1000 non-maneuvering scans (scans whose last ``response``
            intervals had zero input), with its binomial-style standard error.
        quiet_scans: number of such scans per run.
        other: declarations neither attributed to a change nor in a non-maneuvering scan, per run.
        response: W, a declaration at scan k can be attributed to a change n with n < k ≤ n + W.
    """

    events: list[tuple[int, tuple[float, float], float, float, float, float, float]]
    false_alarms_per_1000: float
    false_alarms_se: float
    quiet_scans: int
    other: float
    response: int


def detection_summary(
    sc: ManeuverScenario, detected: np.ndarray, onset: np.ndarray, response: int
) -> DetectionSummary:
    """Attribute each declaration (``detected``, ``onset``: (M, N−2) for scans 3..N) to a true input change
    or count it as a false alarm.

    A declaration at scan k with onset estimate n̂ is attributed, among the changes n with n < k ≤ n + W, to the
    one nearest to n̂ (ties to the later change): two changes a few scans apart (the end of turn 1 at 300 and
    the start of turn 2 at 305) are then told apart by the estimated onset, not by the declaration scan.
    """
    if response < 1:
        raise ValueError("the response window must be at least 1 scan")
    M = detected.shape[0]
    scans = np.arange(FIRST_SCAN, sc.scans + 1)
    ev = sc.events()
    owner = np.full(detected.shape, -1)  # change attributed to each declaration (−1: none)
    best = np.full(detected.shape, np.inf)
    near_event = np.zeros(scans.size, dtype=bool)
    for i, (n, _) in enumerate(ev):
        eligible = (scans > n) & (scans <= n + response)
        near_event |= eligible
        dist = np.where(detected & eligible[None], np.abs(onset - n), np.inf)
        take = np.isfinite(dist) & (dist <= best)
        owner[take], best[take] = i, dist[take]
    u = sc.inputs()
    moving = np.array([np.any(u[max(k - 1 - response, 0) : k - 1] != 0) for k in scans])
    quiet = ~near_event & ~moving
    rows = []
    for i, (n, du) in enumerate(ev):
        mine = owner == i
        hit = mine.any(axis=1)
        first = np.argmax(mine, axis=1)
        delay = scans[first[hit]] - n
        onset_err = onset[np.flatnonzero(hit), first[hit]] - n
        rows.append((n, du, float(hit.mean()),
                     float(delay.mean()) if hit.any() else math.nan,
                     float(np.median(delay)) if hit.any() else math.nan,
                     float(onset_err.mean()) if hit.any() else math.nan,
                     float(np.sqrt(np.mean(onset_err**2.0))) if hit.any() else math.nan))  # fmt: skip
    n_quiet = int(quiet.sum())
    fa = detected[:, quiet]
    rate = float(fa.mean()) if n_quiet else math.nan
    per_run = fa.sum(axis=1) if n_quiet else np.zeros(M)
    se = float(per_run.std(ddof=1) / math.sqrt(M) / n_quiet) if (n_quiet and M > 1) else math.nan
    other = float((detected & (owner < 0) & ~quiet[None]).sum() / M)
    return DetectionSummary(rows, 1000 * rate, 1000 * se, n_quiet, other, response)
