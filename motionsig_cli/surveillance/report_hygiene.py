"""Real-record hygiene: what a surveillance feed holds besides measurements, handled by a stated policy and
counted, before any tracker sees it.

A real feed (ADS-B, a radar's plot export, several sensors merged) is not a clean sequence of one report per
scan. :func:`clean_reports` takes the rows of one track as recorded — times, and the position values as the
file gives them (latitude/longitude, range/bearing or x/y: compared exactly, before any conversion) — and
returns the rows to track, in time order, with their segments:

1. **Order.** Rows are sorted by time (a stable sort: rows of equal time keep the file's order). With
   ``strict``, a row earlier than the one before is refused instead (its index is named).
2. **Exact duplicates** — the same time and the same position values as an earlier row (a message
   received twice, by two receivers of one network) — are dropped.
3. **Conflicting duplicates** — the same time, another position — keep the first row of that time and drop
   the others (``conflicting="first"``), or are refused (``"refuse"``). Two positions for one instant cannot
   both be measurements of one aircraft. A row without a position at the time of one with a position (a
   velocity or identity message received in the same millisecond) adds nothing and is dropped
   (``empty_duplicates``).
4. **Stale repeats** — a position identical, to every digit, to the previous kept row's, under a new time:
   ADS-B decoders and some exports repeat the last position when a report carries only velocity or
   identity. A real position measured afresh never repeats a previous one to every recorded digit while
   the target moves; taking it as new would tell the tracker the target stopped. Dropped by default
   (``stale="drop"``), or kept (``"keep"``).
5. **Rows without a position** (empty or NaN cells) are kept: the sensor reported at that time and measured
   nothing, a predict-only step for the trackers.
6. **Gaps.** A time step longer than ``max_gap`` ends the segment; the next row starts a new one, which
   the trackers initialise afresh. A coverage gap is never bridged silently. Default: the larger of
   :data:`MIN_GAP_S` and :data:`GAP_STEPS` times the median step (30 s for ADS-B at 0.5–1 s, 32 s for a
   radar at 4 s).

With ``strict`` every departure from a clean record (unsorted rows, duplicates, conflicts) is refused
instead of handled; stale repeats follow ``stale``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from motionsig_cli.config import ConfigError, in_range, one_of

__all__ = ["GAP_STEPS", "MIN_GAP_S", "Cleaned", "HygieneError", "HygienePolicy", "clean_reports"]

MIN_GAP_S = 30.0
"""Smallest default gap limit [s]."""
GAP_STEPS = 8
"""Default gap limit in median steps (a radar at 4 s: 32 s, eight missed scans)."""
MAX_GAP_RANGE = (1e-3, 1e7)


class HygieneError(ValueError):
    """A row a strict policy refuses: ``row`` is its index in the input, ``message`` why."""

    def __init__(self, row: int, message: str) -> None:
        super().__init__(message)
        self.row, self.message = row, message


@dataclass(frozen=True)
class HygienePolicy:
    """How a record's rows are cleaned (module docstring).

    Attributes:
        strict: refuse unsorted rows, duplicates and conflicts instead of handling them.
        stale: ``drop`` or ``keep`` stale repeats.
        conflicting: ``first`` (keep the first row of a time) or ``refuse``.
        max_gap: the gap limit [s]; None: the default rule.
    """

    strict: bool = False
    stale: str = "drop"
    conflicting: str = "first"
    max_gap: float | None = None

    def __post_init__(self) -> None:
        one_of("stale", self.stale, ("drop", "keep"))
        one_of("conflicting", self.conflicting, ("first", "refuse"))
        if self.max_gap is not None:
            in_range("max_gap", self.max_gap, *MAX_GAP_RANGE, unit="s")
        if not isinstance(self.strict, bool):
            raise ConfigError("strict", self.strict, "is not true or false")


@dataclass(frozen=True)
class Cleaned:
    """The rows to track.

    Attributes:
        rows: (K,) input row indices, in time order.
        segment: (K,) the segment of each row (0, 1, …: a new one after each gap).
        max_gap: the gap limit used [s].
        counts: what was done: ``reordered`` (rows that moved), ``exact_duplicates``,
            ``conflicting_duplicates``, ``stale_repeats`` (dropped or kept, as ``stale`` says), ``gaps``.
    """

    rows: np.ndarray
    segment: np.ndarray
    max_gap: float
    counts: dict[str, int] = field(default_factory=dict)


def clean_reports(t: np.ndarray, pos: np.ndarray, policy: HygienePolicy | None = None) -> Cleaned:
    """Clean one track's rows (module docstring).

    Args:
        t: (N,) times [s], finite.
        pos: (N, d) the position values as recorded (NaN: no position in that row).
        policy: the policy (default :class:`HygienePolicy`).

    Raises:
        HygieneError: what a strict policy (or ``conflicting="refuse"``) refuses, naming the row.

    Examples:
        >>> import numpy as np
        >>> from motionsig_cli.surveillance.report_hygiene import clean_reports
        >>> t = np.array([0.0, 1.0, 1.0, 2.0, 3.0, 100.0, 101.0])
        >>> pos = np.array([[0, 0], [1, 0], [1, 0], [1, 0], [3, 0], [9, 9], [10, 9]], float)
        >>> c = clean_reports(t, pos)
        >>> c.rows.tolist(), c.segment.tolist(), c.counts["stale_repeats"]
        ([0, 1, 4, 5, 6], [0, 0, 0, 1, 1], 1)
    """
    pol = policy if policy is not None else HygienePolicy()
    t = np.asarray(t, float)
    pos = np.asarray(pos, float).reshape(t.shape[0], -1)
    n = t.shape[0]
    counts = {"reordered": 0, "exact_duplicates": 0, "conflicting_duplicates": 0, "empty_duplicates": 0,
              "stale_repeats": 0, "gaps": 0}  # fmt: skip
    if n == 0:
        return Cleaned(np.zeros(0, np.int64), np.zeros(0, np.int64), pol.max_gap or MIN_GAP_S, counts)
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size and pol.strict:
        i = int(back[0]) + 1
        raise HygieneError(i, f"time {t[i]:.9g} s is earlier than the row before ({t[i - 1]:.9g} s)")
    order = np.argsort(t, kind="stable")
    counts["reordered"] = int(np.sum(order != np.arange(n)))
    ts, ps = t[order], pos[order]
    keep = np.ones(n, dtype=bool)
    has = ~np.isnan(ps).any(axis=1)
    starts = np.flatnonzero(np.concatenate([[True], np.diff(ts) != 0]))
    sizes = np.diff(np.concatenate([starts, [n]]))
    for g0, size in zip(starts[sizes > 1], sizes[sizes > 1], strict=True):  # only the repeated times
        rows = np.arange(g0, g0 + size)
        with_pos = rows[has[rows]]
        first = int(with_pos[0]) if with_pos.size else int(rows[0])
        for i in rows:
            if i == first:
                continue
            keep[i] = False
            if not has[i] and with_pos.size:
                counts["empty_duplicates"] += 1  # a row without a position at a measured time
            elif np.array_equal(ps[i], ps[first], equal_nan=True):
                if pol.strict:
                    raise HygieneError(
                        int(order[i]), f"the row repeats the time of an earlier row ({ts[i]:.9g} s)"
                    )
                counts["exact_duplicates"] += 1
            else:
                if pol.strict or pol.conflicting == "refuse":
                    raise HygieneError(
                        int(order[i]),
                        f"the row has another position at the time of an earlier row ({ts[i]:.9g} s)",
                    )
                counts["conflicting_duplicates"] += 1
    idx = np.flatnonzero(keep)
    # stale repeats: the same position values as the previous kept row with a position
    hk = has[idx]
    stale = np.zeros(idx.size, dtype=bool)
    with_pos = np.flatnonzero(hk)
    if with_pos.size > 1:
        prev, cur = ps[idx[with_pos[:-1]]], ps[idx[with_pos[1:]]]
        stale[with_pos[1:]] = np.all(prev == cur, axis=1)
    counts["stale_repeats"] = int(stale.sum())
    if pol.stale == "drop":
        idx = idx[~stale]
    tk = ts[idx]
    steps = np.diff(tk)
    if pol.max_gap is not None:
        gap = float(pol.max_gap)
    else:
        med = float(np.median(steps)) if steps.size else 0.0
        gap = max(MIN_GAP_S, GAP_STEPS * med) if math.isfinite(med) else MIN_GAP_S
    breaks = steps > gap
    counts["gaps"] = int(breaks.sum())
    segment = np.concatenate([[0], np.cumsum(breaks)]).astype(np.int64)
    return Cleaned(order[idx].astype(np.int64), segment, gap, counts)
