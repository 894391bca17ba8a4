"""Ground truth of turns from a recording's own track angle, and the scoring of maneuver declarations.

A tracker's maneuver detector (IMM mode probability, GLR, MLR) declares onsets; on a real flight the
truth is what the aircraft itself reported. :func:`turn_intervals` reads the recorded track angle
(ADS-B ``track``: irregular times, duplicate rows, stale repeats, values quantised to 0.1–1°) and
returns the turns (|track rate| > 1°/s for at least 10 s) and the straight flight (|rate| < 0.3°/s)
over which false alarms are counted. :func:`score_declarations` matches declared onsets to turns.

The choices, each a field of :class:`TurnTruthConfig`:

- **Track rate by a local linear fit**, not by differences of consecutive samples: at 0.5 s a 1°
  quantum makes a difference of 2°/s. The rate at a sample is the least-squares slope of the unwrapped
  track angle against time over the samples within ``smoothing_s / 2`` of it (default 10 s in all),
  widened to its two neighbours where they lie further out (a sparse recording), and never across a gap.
  A step of the rate from 0 to ω at t0 gives, with the window centred at t0 - z h (h = smoothing_s / 2),
  the slope ω (1/2 - 3z/4 + z³/4): ω/2 at the step, ω a half-window after. A detected onset therefore
  lies within h (plus one sample interval) of the true one, within 0.23 h for ω = 1.5 and 3°/s.
- **Duplicates and stale repeats** are kept in the fit, with rows at one timestamp merged into one sample
  (their circular mean). A stale repeat (the previous value under a new timestamp) turns a ramp into a
  staircase; over a window several updates long the least-squares slope of a staircase is the ramp's
  slope (delayed by at most the stale hold), so stale rows bias no rate there, and dropping them would
  need a guess at which rows are fresh (a constant track in straight flight repeats legitimately).
- **Spikes**: a sample more than ``spike_deg`` (default 20°) away from both neighbours, out and back
  (the two steps of opposite directions), while the neighbours lie within ``spike_deg`` of each other, is
  dropped before the fit: an aircraft cannot swing its track 20° out and back within two reporting
  intervals (at 3°/s a reversal alone takes seconds of rolling), and resampled feeds hold such single
  stray values (a 50–200° outlier in a straight leg). A 3-sample fit cannot tell an outlier at its edge
  from a turn, so this is done on the sequence, not in the fit.
- **Gaps**: consecutive samples more than ``max_gap_s`` apart (default 15 s: three 5 s resampled
  reports) split the recording into segments; no rate is estimated across a segment boundary, and a
  sample whose window holds fewer than 3 samples has no rate (NaN): it is neither turn nor straight.
- **Turns**: maximal runs of consecutive samples of one segment with |rate| > ``rate_threshold_deg_s``
  and one sign; runs of the same sign less than ``merge_s`` apart (default 5 s: one dip below the
  threshold of a noisy estimate) are one turn; a turn lasts at least ``min_duration_s`` from its first to
  its last sample. A reversal (an S-turn) is two turns. Its mean rate is the track angle turned from
  the first to the last sample over that time (the recorded angles, the short way round each step),
  not the mean of the smoothed estimates, whose ramps at both ends (1.2 half-windows each) pull it low.
- **Straight flight**: the time between consecutive samples of one segment that both have |rate| <
  ``straight_threshold_deg_s`` (default 0.3°/s). The band between 0.3 and 1°/s, and time without an
  estimate, count neither way. 0.3°/s is a tenth of a standard-rate turn (3°/s) and three times what a
  1° quantisation error at the ends of a 10 s window can make (≈ 0.1°/s); wind drift and autopilot
  heading holds stay well below it.
- **Slow samples**: with ``speed_mps`` given, samples slower than ``min_speed_mps`` are dropped before
  anything else (a track angle means nothing for a parked aircraft); they leave gaps like missing rows.
- **Implausible rates**: with ``speed_mps`` given, a rate above what a coordinated turn at
  ``max_bank_deg`` (default 60°, a 2 g turn, twice the 30° that airliners and calibration flights
  keep to) allows at the sample's speed, g tan(bank) / v, is set to NaN. Recordings hold such rates
  where a feed interpolated the track the long way round the 0/360° wrap (352° → 2° through 180° in
  25 s: 15°/s at 180 m/s, where 60° of bank gives 5.4°/s); they are no turn of the aircraft. Ground
  speed stands in for airspeed (a tailwind of a sixth of the speed tightens the bound by a sixth).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from motionsig_cli.config import ConfigError, in_range, positive

_G = 9.80665  # standard gravity, m/s^2

__all__ = [
    "Turn",
    "TurnScore",
    "TurnTruth",
    "TurnTruthConfig",
    "score_declarations",
    "turn_intervals",
]


@dataclass(frozen=True)
class TurnTruthConfig:
    """The parameters of :func:`turn_intervals` (see the module's docstring for each choice).

    Examples:
        >>> TurnTruthConfig().straight_threshold_deg_s
        0.3
        >>> TurnTruthConfig(straight_threshold_deg_s=2.0)
        Traceback (most recent call last):
        ...
        motionsig_cli.config.ConfigError: straight_threshold_deg_s = 2 is not in (0, 1) deg/s
    """

    rate_threshold_deg_s: float = 1.0
    min_duration_s: float = 10.0
    smoothing_s: float = 10.0
    straight_threshold_deg_s: float = 0.3
    max_gap_s: float = 15.0
    merge_s: float = 5.0
    min_speed_mps: float = 0.0
    max_bank_deg: float = 60.0
    spike_deg: float = 20.0

    def __post_init__(self) -> None:
        positive("rate_threshold_deg_s", self.rate_threshold_deg_s, unit="deg/s")
        in_range("min_duration_s", self.min_duration_s, 0.0)
        positive("smoothing_s", self.smoothing_s, unit="s")
        in_range(
            "straight_threshold_deg_s",
            self.straight_threshold_deg_s,
            0.0,
            self.rate_threshold_deg_s,
            lo_open=True,
            hi_open=True,
            unit="deg/s",
        )
        positive("max_gap_s", self.max_gap_s, unit="s")
        in_range("merge_s", self.merge_s, 0.0)
        in_range("min_speed_mps", self.min_speed_mps, 0.0)
        in_range("max_bank_deg", self.max_bank_deg, 0.0, 90.0, lo_open=True, hi_open=True, unit="deg")
        in_range("spike_deg", self.spike_deg, 0.0, 180.0, lo_open=True, unit="deg")


@dataclass(frozen=True)
class Turn:
    """One turn: from ``start_s`` to ``end_s`` (the first and last sample above the threshold, in the
    recording's seconds) at a mean track rate ``mean_rate_deg_s`` (> 0 to the right, clockwise)."""

    start_s: float
    end_s: float
    mean_rate_deg_s: float

    def __post_init__(self) -> None:
        in_range("start_s", self.start_s)
        in_range("end_s", self.end_s, self.start_s)
        in_range("mean_rate_deg_s", self.mean_rate_deg_s)

    @property
    def duration_s(self) -> float:
        """``end_s - start_s``."""
        return self.end_s - self.start_s


def _intervals(name: str, value: Sequence[tuple[float, float]]) -> tuple[tuple[float, float], ...]:
    out = []
    for pair in value:
        a, b = (float(x) for x in pair)
        if not (math.isfinite(a) and math.isfinite(b) and b >= a):
            raise ConfigError(name, pair, "is not a finite interval (start <= end)")
        out.append((a, b))
    return tuple(sorted(out))


@dataclass(frozen=True, eq=False)
class TurnTruth:
    """What :func:`turn_intervals` found (read-only arrays; compared by identity, as it holds arrays).

    Attributes:
        turns: The turns, in time order.
        straight: The straight-flight intervals ``(start_s, end_s)``, in time order, disjoint.
        t_s: The sample times the rate was evaluated at (rows merged, slow rows dropped).
        rate_deg_s: The track rate at ``t_s`` (NaN where not estimated).
        config: The parameters used.
    """

    turns: tuple[Turn, ...]
    straight: tuple[tuple[float, float], ...]
    t_s: np.ndarray = field(repr=False)
    rate_deg_s: np.ndarray = field(repr=False)
    config: TurnTruthConfig = TurnTruthConfig()

    def __post_init__(self) -> None:
        if not all(isinstance(x, Turn) for x in self.turns):
            raise ConfigError("turns", self.turns, "is not a sequence of Turn")
        object.__setattr__(self, "straight", _intervals("straight", self.straight))
        if np.shape(self.t_s) != np.shape(self.rate_deg_s) or np.ndim(self.t_s) != 1:
            raise ConfigError("rate_deg_s", np.shape(self.rate_deg_s), "is not one value per sample of t_s")
        for name in ("t_s", "rate_deg_s"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    @property
    def straight_s(self) -> float:
        """The total time of straight flight in seconds."""
        return float(sum(b - a for a, b in self.straight))

    def in_straight(self, t_s: np.ndarray | float) -> np.ndarray:
        """Whether each time lies in a straight-flight interval (ends included)."""
        return _inside(np.asarray(t_s, float), self.straight)


def _inside(t: np.ndarray, intervals: Sequence[tuple[float, float]]) -> np.ndarray:
    if not intervals:
        return np.zeros(t.shape, bool)
    a = np.array([x[0] for x in intervals])
    b = np.array([x[1] for x in intervals])
    k = np.searchsorted(a, t, side="right") - 1
    return (k >= 0) & (t <= b[np.clip(k, 0, None)])


def _merge_rows(t: np.ndarray, ang: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One sample per timestamp: the circular mean of the track angles recorded at it."""
    tu, inv = np.unique(t, return_inverse=True)
    if tu.size == t.size:
        return t, ang
    rad = np.radians(ang)
    s = np.bincount(inv, np.sin(rad), tu.size)
    c = np.bincount(inv, np.cos(rad), tu.size)
    return tu, np.degrees(np.arctan2(s, c))


def _spikes(t: np.ndarray, ang: np.ndarray, cfg: TurnTruthConfig) -> np.ndarray:
    """Samples that step out by more than ``spike_deg`` and straight back (neighbours in one segment).

    Both steps exceed ``spike_deg`` and their sum (the neighbours' difference) does not: the steps have
    opposite directions (a 180° outlier included, whose steps both read -180°)."""
    out = np.zeros(t.size, bool)
    if t.size < 3:
        return out
    d = np.mod(np.diff(ang) + 180.0, 360.0) - 180.0  # the short way round
    near = np.diff(t) <= cfg.max_gap_s
    a, b = d[:-1], d[1:]
    across = np.abs(np.mod(a + b + 180.0, 360.0) - 180.0)
    out[1:-1] = (
        (np.abs(a) > cfg.spike_deg)
        & (np.abs(b) > cfg.spike_deg)
        & (across <= cfg.spike_deg)
        & near[:-1]
        & near[1:]
    )
    return out


def _rates(t: np.ndarray, ang: np.ndarray, cfg: TurnTruthConfig) -> np.ndarray:
    """The local least-squares slope at every sample (NaN where fewer than 3 samples)."""
    rate = np.full(t.size, np.nan)
    if t.size == 0:
        return rate
    cuts = np.flatnonzero(np.diff(t) > cfg.max_gap_s) + 1
    h = cfg.smoothing_s / 2.0
    for lo, hi in zip(np.r_[0, cuts], np.r_[cuts, t.size], strict=True):
        ts = t[lo:hi]
        a = np.unwrap(ang[lo:hi], period=360.0)
        n = ts.size
        for i in range(n):
            half = h
            if i > 0:
                half = max(half, ts[i] - ts[i - 1])
            if i < n - 1:
                half = max(half, ts[i + 1] - ts[i])
            j0 = np.searchsorted(ts, ts[i] - half, side="left")
            j1 = np.searchsorted(ts, ts[i] + half, side="right")
            if j1 - j0 < 3:
                continue
            x = ts[j0:j1] - ts[i]
            y = a[j0:j1]
            xc = x - x.mean()
            sxx = float(xc @ xc)
            if sxx > 0.0:
                rate[lo + i] = float(xc @ (y - y.mean())) / sxx
    return rate


def turn_intervals(
    t_s: np.ndarray,
    track_deg: np.ndarray,
    *,
    rate_threshold_deg_s: float = 1.0,
    min_duration_s: float = 10.0,
    smoothing_s: float = 10.0,
    straight_threshold_deg_s: float = 0.3,
    max_gap_s: float = 15.0,
    merge_s: float = 5.0,
    speed_mps: np.ndarray | None = None,
    min_speed_mps: float = 0.0,
    max_bank_deg: float = 60.0,
    spike_deg: float = 20.0,
) -> TurnTruth:
    """The turns and the straight flight of a recording, from its own track angle.

    Args:
        t_s: Times in seconds, nondecreasing (the recording's order; rows at one time are merged).
        track_deg: Track angle in degrees clockwise from north; NaN rows (a message without a
            velocity) are skipped.
        rate_threshold_deg_s: A turn is faster than this (|rate|).
        min_duration_s: ... and lasts at least this long.
        smoothing_s: The width of the local linear fit.
        straight_threshold_deg_s: Straight flight is slower than this (|rate|).
        max_gap_s: No rate across consecutive samples further apart than this.
        merge_s: Runs of one sign closer than this are one turn.
        speed_mps: Ground speed per row (optional); rows slower than ``min_speed_mps`` are skipped.
        min_speed_mps: See ``speed_mps``.
        max_bank_deg: With ``speed_mps``, rates beyond a coordinated turn at this bank are NaN.
        spike_deg: Single out-and-back values further than this from both neighbours are dropped.

    Returns:
        A :class:`TurnTruth`. The module's docstring states each choice.

    Examples:
        >>> t = np.arange(0.0, 120.0, 1.0)
        >>> track = 90.0 + 3.0 * np.clip(t - 40.0, 0.0, 30.0)  # a 3 deg/s turn from 40 s to 70 s
        >>> # found from 1 s early to 1 s late (the smoothing window), so 90 deg in 32 s
        >>> truth = turn_intervals(t, track)
        >>> [(round(x.start_s), round(x.end_s), round(x.mean_rate_deg_s, 1)) for x in truth.turns]
        [(39, 71, 2.8)]
    """
    cfg = TurnTruthConfig(
        rate_threshold_deg_s=rate_threshold_deg_s,
        min_duration_s=min_duration_s,
        smoothing_s=smoothing_s,
        straight_threshold_deg_s=straight_threshold_deg_s,
        max_gap_s=max_gap_s,
        merge_s=merge_s,
        min_speed_mps=min_speed_mps,
        max_bank_deg=max_bank_deg,
        spike_deg=spike_deg,
    )
    t = np.asarray(t_s, float)
    ang = np.asarray(track_deg, float)
    if t.ndim != 1 or ang.shape != t.shape:
        raise ConfigError("track_deg", ang.shape, f"is not one value per time (t_s has shape {t.shape})")
    keep = np.isfinite(ang) & np.isfinite(t)
    v = None
    if speed_mps is not None:
        v = np.asarray(speed_mps, float)
        if v.shape != t.shape:
            raise ConfigError("speed_mps", v.shape, f"is not one value per time (t_s has shape {t.shape})")
        keep &= v >= cfg.min_speed_mps  # NaN speed: dropped
        v = v[keep]
    t, ang = t[keep], ang[keep]
    if np.any(np.diff(t) < 0):
        raise ConfigError("t_s", "decreasing", "is not nondecreasing: times go back")
    tu, ang = _merge_rows(t, ang)
    v_max = None
    if v is not None and tu.size:
        v_max = np.maximum.reduceat(v, np.r_[0, np.flatnonzero(np.diff(t) > 0) + 1])  # per merged sample
    spike = _spikes(tu, ang, cfg)
    tu, ang = tu[~spike], ang[~spike]
    rate = _rates(tu, ang, cfg)
    if v_max is not None and tu.size:
        v_max = v_max[~spike]
        limit = np.degrees(_G * math.tan(math.radians(cfg.max_bank_deg)) / np.maximum(v_max, 1e-9))
        rate[np.abs(rate) > limit] = np.nan
    t = tu
    seg = np.r_[0, np.cumsum(np.diff(t) > cfg.max_gap_s)] if t.size else np.zeros(0, int)

    # turns: runs of one sign above the threshold, merged across short dips, within a segment
    sign = np.where(np.abs(rate) > cfg.rate_threshold_deg_s, np.sign(rate), 0.0)
    runs: list[list[int]] = []  # [first index, last index]
    for i in np.flatnonzero(sign != 0):
        if runs:
            j0, j1 = runs[-1]
            same = sign[j1] == sign[i] and seg[j1] == seg[i]
            contiguous = i == j1 + 1
            close = t[i] - t[j1] < cfg.merge_s and not np.any(sign[j1 + 1 : i] == -sign[i])
            if same and (contiguous or close):
                runs[-1][1] = i
                continue
        runs.append([i, i])
    turns = []
    for j0, j1 in runs:
        if t[j1] - t[j0] >= cfg.min_duration_s:
            turned = float(np.sum(np.mod(np.diff(ang[j0 : j1 + 1]) + 180.0, 360.0) - 180.0))
            turns.append(Turn(float(t[j0]), float(t[j1]), turned / float(t[j1] - t[j0])))

    # straight flight: between consecutive straight samples of one segment
    calm = np.abs(rate) < cfg.straight_threshold_deg_s  # NaN compares False
    pair = calm[:-1] & calm[1:] & (seg[:-1] == seg[1:])
    straight: list[tuple[float, float]] = []
    for i in np.flatnonzero(pair):
        a, b = float(t[i]), float(t[i + 1])
        if straight and straight[-1][1] == a:
            straight[-1] = (straight[-1][0], b)
        else:
            straight.append((a, b))
    return TurnTruth(tuple(turns), tuple(straight), t, rate, cfg)


@dataclass(frozen=True)
class TurnScore:
    """The score of a detector's declarations against the turns.

    Attributes:
        hits: Turns with a matching declaration.
        misses: Turns without one.
        false_alarms: Unmatched declarations in straight flight.
        ignored: Unmatched declarations elsewhere (in a turn, in the 0.3–1°/s band, without an
            estimate): neither hit nor false alarm.
        straight_hours: Hours of straight flight.
        false_alarms_per_hour: ``false_alarms / straight_hours`` (NaN without straight flight).
        delays_s: Per hit, the declaration's time minus the turn's start, in turn order.
        hit_turns: Per hit, the index of the turn.
    """

    hits: int
    misses: int
    false_alarms: int
    ignored: int
    straight_hours: float
    false_alarms_per_hour: float
    delays_s: tuple[float, ...] = ()
    hit_turns: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        for name in ("hits", "misses", "false_alarms", "ignored"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ConfigError(name, value, "is not an integer >= 0")
        in_range("straight_hours", self.straight_hours, 0.0)
        if len(self.delays_s) != self.hits or len(self.hit_turns) != self.hits:
            raise ConfigError("delays_s", self.delays_s, "does not hold one delay per hit")

    @property
    def p_detect(self) -> float:
        """``hits / (hits + misses)`` (NaN without turns)."""
        n = self.hits + self.misses
        return self.hits / n if n else math.nan


def score_declarations(
    declared_t: np.ndarray | Sequence[float],
    turns: Sequence[Turn] | TurnTruth,
    straight: Sequence[tuple[float, float]] | None = None,
    *,
    early_s: float = 5.0,
    late_s: float = 15.0,
) -> TurnScore:
    """Match declared maneuver onsets to turns; count misses and false alarms.

    A turn is hit when a declaration lies in ``[start - early_s, start + late_s]``. One declaration
    matches at most one turn and one turn at most one declaration: the turns are taken in time order and
    each takes the earliest unmatched declaration in its window (all windows have one length, so this
    greedy choice matches as many turns as any other). A declaration left unmatched is a false alarm
    when it lies in straight flight (ends included), else it is ignored: a second declaration in a turn,
    one in the band between the straight and the turn thresholds, or one where no rate was estimated
    counts neither way.

    Args:
        declared_t: Declared onsets, in the recording's seconds (any order).
        turns: The turns, or a :class:`TurnTruth` (then ``straight`` defaults to its own).
        straight: The straight-flight intervals ``(start_s, end_s)``.
        early_s: How early a declaration may come (>= 0).
        late_s: How late (>= 0).

    Examples:
        >>> turns = [Turn(100.0, 130.0, 3.0)]
        >>> s = score_declarations([50.0, 104.0, 110.0], turns, [(0.0, 95.0), (140.0, 3600.0)])
        >>> s.hits, s.misses, s.false_alarms, s.ignored, s.delays_s
        (1, 0, 1, 1, (4.0,))
    """
    if isinstance(turns, TurnTruth):
        if straight is None:
            straight = turns.straight
        turns = turns.turns
    if straight is None:
        raise ConfigError("straight", None, "is not given (pass the intervals or a TurnTruth)")
    in_range("early_s", early_s, 0.0)
    in_range("late_s", late_s, 0.0)
    if not all(isinstance(x, Turn) for x in turns):
        raise ConfigError("turns", turns, "is not a sequence of Turn")
    calm = _intervals("straight", straight)
    d = np.sort(np.asarray(declared_t, float).ravel())
    if not np.all(np.isfinite(d)):
        raise ConfigError("declared_t", "non-finite", "holds a time that is not finite")
    used = np.zeros(d.size, bool)
    delays, hit_turns = [], []
    order = sorted(range(len(turns)), key=lambda k: turns[k].start_s)
    for k in order:
        start = turns[k].start_s
        lo = np.searchsorted(d, start - early_s, side="left")
        hi = np.searchsorted(d, start + late_s, side="right")
        free = np.flatnonzero(~used[lo:hi])
        if free.size:
            j = lo + free[0]
            used[j] = True
            delays.append(float(d[j] - start))
            hit_turns.append(k)
    rest = d[~used]
    fa = int(np.count_nonzero(_inside(rest, calm)))
    hours = float(sum(b - a for a, b in calm)) / 3600.0
    return TurnScore(
        hits=len(hit_turns),
        misses=len(turns) - len(hit_turns),
        false_alarms=fa,
        ignored=int(rest.size - fa),
        straight_hours=hours,
        false_alarms_per_hour=fa / hours if hours > 0 else math.nan,
        delays_s=tuple(delays),
        hit_turns=tuple(hit_turns),
    )
