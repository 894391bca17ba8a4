"""Reading a ``motionsig simulate`` record back: the checks of its contents (columns, times, metadata) and
what it says: the measurements, the vehicle the detector's filters assume, the Table I chips, the truth.

A record that fails a check raises :class:`~motionsig_cli.errors.InputError` naming the file (and the line,
for a bad cell); the command line prints it as one line with exit code 2. Horizons are checked against
the record's length (:func:`record_horizons`, a :class:`~motionsig_cli.config.ConfigError` naming
``horizons``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer
from motionsig_cli.errors import InputError
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.models.vehicle2d import Vehicle2D
from motionsig_cli.tables import Table

NEEDED_META_1D = ("T", "m_rho", "K", "R", "codes", "f_c", "a_sig")
NEEDED_META_2D = ("T", "m_rho", "K", "R_range", "R_bearing", "codes", "f_c", "a_sig", "start")
BEARING_UNITS = {"rad": 1.0, "deg": math.pi / 180}
HINT_1D = "produce the record with 'motionsig simulate'"
HINT_2D = "produce the record with 'motionsig simulate --example 2d'"


@dataclass(frozen=True)
class VehicleRecord:
    """A record read back.

    Attributes:
        times: Sample times (N,), uniform at the vehicle's T.
        y: Measurements: (N,) position (1-D) or (N, 2) [range, bearing in radians] (2-D).
        vehicle: The vehicle the filters assume (from the metadata).
        chips: Bipolar Table I codes of the record's variant, (3, n_ρ).
        m_rho: Samples per chip.
        f_c: Carrier frequency [Hz].
        truth: (0-based mode, τ) of the signature, or None (none, or not recorded).
        meta: The record's metadata.
        source: The file's name (``<stdin>`` for standard input).
    """

    times: np.ndarray
    y: np.ndarray
    vehicle: Vehicle1D | Vehicle2D
    chips: np.ndarray
    m_rho: int
    f_c: float
    truth: tuple[int, int] | None
    meta: dict[str, Any]
    source: str


def finite_column(t: Table, name: str) -> np.ndarray:
    """A numeric column whose every value is finite (else an error naming file:line)."""
    arr = t.numeric(name)
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise InputError(f"{t.source}:{t.lines[bad[0]]}: column {name!r} is not finite")
    return arr


def uniform_times(t: Table) -> np.ndarray:
    """Column ``t``: at least 2 finite samples, increasing, spaced by the metadata ``T``."""
    times = t.numeric("t")
    if times.size < 2:
        raise InputError(f"{t.source}: need at least 2 samples")
    times = finite_column(t, "t")
    try:
        T = float(t.meta["T"])
        if not (math.isfinite(T) and T > 0):
            raise ValueError
    except (TypeError, ValueError):
        raise InputError(f"{t.source}: metadata 'T' must be a positive number, got {t.meta['T']!r}") from None
    dt = np.diff(times)
    if np.any(dt <= 0):
        i = int(np.flatnonzero(dt <= 0)[0]) + 1
        raise InputError(f"{t.source}:{t.lines[i]}: time is not increasing")
    if np.max(np.abs(dt - T)) > 1e-6 * max(T, 1.0):
        i = int(np.argmax(np.abs(dt - T))) + 1
        raise InputError(
            f"{t.source}:{t.lines[i]}: time step {dt[i - 1]:g} differs from the metadata T = {T:g} (non-uniform time)"
        )
    return times


def truth_of(meta: dict[str, Any]) -> tuple[int, int] | None:
    """(0-based mode, τ) recorded by ``simulate``, or None (no signature, or not recorded)."""
    if "mode" in meta and "tau" in meta and meta.get("signature", True):
        return int(meta["mode"]) - 1, int(meta["tau"])
    return None


def record_horizons(horizons: Sequence[float] | None, duration: float, T: float) -> list[float]:
    """Detection horizons [s] within a record of ``duration`` seconds sampled every ``T``: by default every
    10 s of the record (or the whole record when shorter than 10 s).

    Raises:
        ConfigError: naming ``horizons``: one ≤ 0, longer than the record, or shorter than one sample.
    """
    if horizons is None:
        return [float(h) for h in range(10, math.floor(duration + 1e-9) + 1, 10)] or [duration]
    hs = list(horizons)
    if not hs:
        raise ConfigError("horizons", hs, "holds no horizon")
    if min(hs) <= 0:
        raise ConfigError("horizons", min(hs), "s is not > 0: horizons must be > 0 seconds")
    if max(hs) > duration + 1e-9:
        raise ConfigError("horizons", max(hs), f"s is longer than the record ({duration:g} s)")
    if round(min(hs) / T) < 1:
        raise ConfigError("horizons", min(hs), f"s is shorter than one sample (T = {T:g} s)")
    return hs


def read_record_1d(t: Table) -> VehicleRecord:
    """A 1-D record: times, positions and the vehicle of its metadata (missing or bad metadata, a bad
    time column or a non-finite measurement is an :class:`InputError` naming the file)."""
    if "y" not in t.columns:
        raise InputError(f"{t.source}: missing column 'y' ({HINT_1D})")
    missing = [k for k in NEEDED_META_1D if k not in t.meta]
    if missing:
        raise InputError(f"{t.source}: missing metadata {', '.join(repr(m) for m in missing)} ({HINT_1D})")
    times = uniform_times(t)
    y = finite_column(t, "y")
    meta = t.meta
    try:
        f_c = in_range("f_c", meta["f_c"], 0.0)
        m_rho = integer("m_rho", meta["m_rho"], 1)
        vehicle = Vehicle1D(
            T=float(meta["T"]), K=tuple(meta["K"]), a_sig=float(meta["a_sig"]), R=float(meta["R"])
        )
        chips = _chips(meta)
    except (ValueError, TypeError) as exc:
        raise InputError(f"{t.source}: bad metadata: {exc}") from None
    return VehicleRecord(times, y, vehicle, chips, m_rho, f_c, truth_of(meta), meta, t.source)


def read_record_2d(t: Table) -> VehicleRecord:
    """A 2-D radar record: times, [range, bearing] in radians (N, 2), the vehicle the filters assume.

    Refuses (one line, file and line named) a range ≤ 0 (a target at the radar has no bearing), a
    non-finite value, an unknown bearing unit, and a bearing column beyond ±π labelled radians.
    """
    missing = [k for k in NEEDED_META_2D if k not in t.meta]
    absent = [c for c in ("range", "bearing") if c not in t.columns]
    if missing or absent:
        what = [f"metadata {m!r}" for m in missing] + [f"column {c!r}" for c in absent]
        raise InputError(f"{t.source}: missing {', '.join(what)} ({HINT_2D})")
    times = uniform_times(t)
    rng = finite_column(t, "range")
    brg = finite_column(t, "bearing")
    bad = np.flatnonzero(rng <= 0)
    if bad.size:
        raise InputError(
            f"{t.source}:{t.lines[bad[0]]}: range {rng[bad[0]]:g} <= 0: the target is at the radar (bearing undefined)"
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
    meta = t.meta
    try:
        for key in ("start", "K"):
            v = meta[key]
            if not (isinstance(v, list) and len(v) == 2 and all(isinstance(e, int | float) for e in v)):
                raise ValueError(f"{key} must be a list of two numbers, got {v!r}")
        m_rho = meta["m_rho"]
        if isinstance(m_rho, bool) or not isinstance(m_rho, int) or m_rho < 1:
            raise ValueError(f"m_rho must be an integer >= 1, got {m_rho!r}")
        f_c = float(meta["f_c"])
        if not (math.isfinite(f_c) and f_c >= 0):
            raise ValueError(f"f_c must be finite and >= 0, got {meta['f_c']!r}")
        vehicle = Vehicle2D(
            T=float(meta["T"]),
            K=tuple(float(k) for k in meta["K"]),
            a_sig=float(meta["a_sig"]),
            R_range=float(meta["R_range"]),
            R_bearing=float(meta["R_bearing"]),
            start=tuple(float(v) for v in meta["start"]),
        )
        chips = _chips(meta)
    except (ValueError, TypeError) as exc:
        raise InputError(f"{t.source}: bad metadata: {exc}") from None
    y = np.stack([rng, brg * BEARING_UNITS[unit]], axis=-1)
    return VehicleRecord(times, y, vehicle, chips, m_rho, f_c, truth_of(meta), meta, t.source)


def _chips(meta: dict[str, Any]) -> np.ndarray:
    from motionsig_cli.signals.correlation import to_bipolar
    from motionsig_cli.signals.modes import table1_codes

    return to_bipolar(table1_codes(str(meta["codes"]))).astype(float)
