"""Reading a record for the LMP detector (``motionsig detect RECORD``): a ``simulate`` record, or a user's
own export, through the common reader :mod:`motionsig_cli.records`.

**Columns** (roles; ``--columns role=name`` maps them, a header unit ``[km]`` or ``--units`` converts them):

- 1-D: ``time`` (also ``t``, ``timestamp``: seconds or ISO 8601) and ``y`` (also ``position``, ``z``): the
  measured position [length].
- 2-D radar (the radar at the origin): ``time``, ``range`` [length] and ``bearing`` [angle, from the x axis
  towards y, as atan2(y, x)], or ``x``, ``y`` Cartesian positions [length] converted exactly to
  range = hypot(x, y) and bearing = atan2(y, x) (the filters keep the polar noise model, eq 60).

A column named exactly as its role wins over an alias (a ``simulate`` record holds ``y`` and the signature
``z``); a ``simulate`` record (metadata ``command: simulate``) is read from its own columns only (``t``,
``y`` or ``range``, ``bearing``). A record is 2-D when its metadata says ``example: "2d"``, when
``--columns`` maps range, bearing or x, or when it has a range or a bearing column, or x and y columns (a
1-D record that also holds the true x, as a ``simulate`` record stripped of its metadata does, needs
``--example 1d``); ``example`` (``--example``) forces it.

**The model** the filters assume: every quantity comes from the option of ``simulate``'s name for it
(:class:`ModelOptions`), else the record's metadata, else ``simulate``'s default (assumed); the output's
metadata says which (``model_sources``). The sample period T comes from the option, the metadata, or the
time column (:func:`motionsig_cli.records.uniform_grid`); a given T must fit the time column. A
``simulate`` record carries its whole model: a key missing from its metadata (and from the options) is
refused, since the record was edited.

**Missing samples.** An empty or NaN cell, and a sample absent from the time grid, is NaN in
:attr:`VehicleRecord.y` (a 2-D sample missing either coordinate is missing as a whole): the filter banks
make it a predict-only step. **Bad input** (a wrong header, text in a number column, a repeated or
decreasing time, an unknown unit, an empty file, more than :data:`MAX_RECORD` samples, a position or range
beyond ±:data:`MAX_MAGNITUDE`, a range ≤ 0, a bearing beyond ±π) is an :class:`~motionsig_cli.errors.InputError` naming the file, line and column; a bad
option value a :class:`~motionsig_cli.config.ConfigError` naming its field. Horizons are checked against
the record's length (:func:`record_horizons`, a ConfigError naming ``horizons``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of, positive
from motionsig_cli.errors import InputError
from motionsig_cli.models.vehicle import (
    DEFAULT_R,
    Vehicle1D,
    measurement_variance,
    pole_placement_gain,
)
from motionsig_cli.models.vehicle2d import Vehicle2D, anr_pair_variances, radar_noise
from motionsig_cli.records import (
    UNITS,
    Record,
    RecordSpec,
    Role,
    parse_columns,
    parse_units,
    read_record,
    uniform_grid,
)
from motionsig_cli.signals.code_spec import ModeCodes, parse_codes
from motionsig_cli.tables import Table, read_table

NEEDED_META_1D = ("T", "m_rho", "K", "R", "codes", "f_c", "a_sig")
NEEDED_META_2D = ("T", "m_rho", "K", "R_range", "R_bearing", "codes", "f_c", "a_sig", "start")
MAX_DEFAULT_HORIZONS = 1000
MAX_MAGNITUDE = 1e9
"""Largest |position| or range accepted from a record [m] (assumed, as ``maneuver``'s bound: a million km,
beyond any radar's range; the filters' squared innovations, divided by the smallest measurement variances,
stay far from float overflow, where a value such as 1e300 makes the statistic NaN)."""
HINT_1D = "produce the record with 'motionsig simulate'"
HINT_2D = "produce the record with 'motionsig simulate --example 2d'"
DEFAULT = "default (assumed)"
RECORD = "record"
OPTION = "option"

TIME = Role("time", ("t", "timestamp"), kind="time", quantity="time", help="sample time: seconds or ISO 8601")
POSITION = Role("y", ("position", "z"), quantity="length", missing=True, help="1-D: the measured position")
RANGE = Role("range", quantity="length", missing=True, help="2-D: the measured range from the radar")
BEARING = Role("bearing", quantity="angle", missing=True, help="2-D: the measured bearing, atan2(y, x)")
EAST = Role("x", quantity="length", required=True, missing=True, help="2-D: the position's x (radar at 0)")
NORTH = Role("y", quantity="length", required=True, missing=True, help="2-D: the position's y (radar at 0)")
MAX_RECORD = 1_000_000
"""Samples per record, read or simulated."""
SPEC_1D = RecordSpec((TIME, POSITION), max_rows=MAX_RECORD, hint="a 1-D record has time and y columns")
SPEC_POLAR = RecordSpec(
    (TIME, RANGE, BEARING),
    max_rows=MAX_RECORD,
    hint="a 2-D record has range and bearing (or x and y) columns",
)
SPEC_CARTESIAN = RecordSpec((TIME, EAST, NORTH), max_rows=MAX_RECORD, hint="a 2-D record has x and y columns")
SPEC_ANY = RecordSpec((TIME, POSITION, RANGE, BEARING, EAST), max_rows=MAX_RECORD)
"""Every role ``detect`` reads (for checking ``--columns`` and ``--units`` before the layout is known)."""
LAYOUTS = {"1d": SPEC_1D, "polar": SPEC_POLAR, "cartesian": SPEC_CARTESIAN}
LEGACY_COLUMNS = {
    "1d": {"time": "t", "y": "y"},
    "polar": {"time": "t", "range": "range", "bearing": "bearing"},
}
CARTESIAN_NOTE = "x, y converted to range = hypot(x, y), bearing = atan2(y, x) (radar at the origin)"
_HEADER_UNIT = re.compile(r"^(.*?)\s*[\[(]\s*([^\])]+?)\s*[\])]$")  # as motionsig_cli.records reads a header


@dataclass(frozen=True)
class VehicleRecord:
    """A record read for the detector.

    Attributes:
        times: Sample times (N,) [s]: the uniform grid t₀ + kT, absent samples included.
        y: Measurements: (N,) position (1-D) or (N, 2) [range, bearing in radians] (2-D); NaN: missing
            (a 2-D sample is missing as a whole).
        vehicle: The vehicle the filters assume.
        chips: Bipolar codes of the modes, (n_modes, n_ρ).
        m_rho: Samples per chip.
        f_c: Carrier frequency [Hz].
        truth: (0-based mode, τ) of the signature, or None (none, or not recorded).
        meta: The record's metadata.
        source: The file's name (``<stdin>`` for standard input).
        lines: (N,) the file line of each sample, 0 where the sample is absent (None: not read from a file).
        codes: The code set (:func:`motionsig_cli.signals.code_spec.parse_codes` reads it back).
        provenance: What the output's metadata records about the reading, where it is not the plain
            ``simulate`` record: the model's values and sources, columns, units, missing samples.
        first_missing: (sample index, ``file:line: column`` text) of the first missing sample, or None.
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
    lines: np.ndarray | None = None
    codes: str = "corrected"
    provenance: dict[str, Any] = field(default_factory=dict)
    first_missing: tuple[int, str] | None = None

    @property
    def missing(self) -> np.ndarray:
        """(N,) True where the sample is missing."""
        return np.isnan(self.y) if self.y.ndim == 1 else np.isnan(self.y).any(axis=1)

    def missing_error(self, reason: str, n_used: int | None = None) -> InputError | None:
        """An error naming the first missing sample among the first ``n_used`` (None when there is none)."""
        miss = np.flatnonzero(self.missing[: self.y.shape[0] if n_used is None else n_used])
        if not miss.size:
            return None
        i = int(miss[0])
        if self.first_missing is not None and self.first_missing[0] == i:
            where = self.first_missing[1]
        else:
            where = f"{self.source}: sample {i} (t = {self.times[i]:.9g} s)"
        n = int(miss.size)
        return InputError(f"{where}: missing measurement ({n} missing): {reason}")


@dataclass(frozen=True)
class ModelOptions:
    """The model quantities given on the command line (None: not given), named and meant as ``motionsig
    simulate``'s options: ``T`` (--T), ``m_rho`` (--mrho), ``K`` (--K) or pole placement at ``wn``, ``zeta``
    (--pole-wn, --pole-zeta; ignored when K is given, as in ``simulate``), ``R`` (--R) or ``anr_db``
    (--anr-db, read with ``db_convention``), ``f_c`` (--fc), ``a_sig`` (--a-sig), ``codes`` (--codes);
    2-D: ``R_range``, ``R_bearing`` (--R-range, --R-bearing) or ``anr_pair`` (--anr-pair), ``start``
    (--start). ``a_r``, ``f_r``, ``sigma_a`` (--a-r, --f-r, --sigma-a) describe the true vehicle, which
    the filters do not assume but the null records of a calibrated threshold simulate (so does
    ``feedback``, --feedback); ``f_d`` (--f-d) is the record's carrier offset (the truth's carrier
    f_c + f_d; the filters search it with their carrier grid). ``f_d`` and ``feedback`` come from the
    option, else the metadata, else 0 and ``"true"`` (not listed among the defaults of the output). Each
    value is checked where it is used (a :class:`ConfigError` naming the field)."""

    T: float | None = None
    m_rho: int | None = None
    K: tuple[float, ...] | None = None
    wn: float | None = None
    zeta: float | None = None
    R: float | None = None
    anr_db: float | None = None
    db_convention: str | None = None
    f_c: float | None = None
    a_sig: float | None = None
    codes: str | None = None
    R_range: float | None = None
    R_bearing: float | None = None
    anr_pair: int | None = None
    start: tuple[float, ...] | None = None
    a_r: float | None = None
    f_r: float | None = None
    sigma_a: float | None = None
    f_d: float | None = None
    feedback: str | None = None

    def given(self, *names: str) -> list[str]:
        """Those of ``names`` that were given."""
        return [n for n in names if getattr(self, n) is not None]


ONLY_1D = ("R", "anr_db", "f_d", "feedback")
ONLY_2D = ("R_range", "R_bearing", "anr_pair", "start")


# ------------------------------------------------------------------------------ the former checks
def finite_column(t: Table, name: str) -> np.ndarray:
    """A numeric column whose every value is finite (else an error naming file:line)."""
    arr = t.numeric(name)
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise InputError(f"{t.source}:{t.lines[bad[0]]}: column {name!r} is not finite")
    return arr


def uniform_times(t: Table) -> np.ndarray:
    """Column ``t``: at least 2 finite samples, increasing, spaced by the metadata ``T`` (no gaps)."""
    times = t.numeric("t")
    if times.size < 2:
        raise InputError(f"{t.source}: need at least 2 samples")
    times = finite_column(t, "t")
    T = _meta_T(t.meta, t.source)
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
    10 s of the record (or the whole record when shorter than 10 s); every 10 n s where 10 s is shorter
    than a sample (n s ≥ T) or would give more than :data:`MAX_DEFAULT_HORIZONS` horizons (assumed).

    Raises:
        ConfigError: naming ``horizons``: one ≤ 0, longer than the record, or shorter than one sample.
    """
    if horizons is None:
        step = 10 * max(1, math.ceil(T / 10 - 1e-9), math.ceil(duration / 10 / MAX_DEFAULT_HORIZONS - 1e-9))
        return [float(h) for h in range(step, math.floor(duration + 1e-9) + 1, step)] or [duration]
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
    """A 1-D record (:func:`read_vehicle_record` with ``example="1d"``)."""
    return read_vehicle_record(t, example="1d")


def read_record_2d(t: Table) -> VehicleRecord:
    """A 2-D radar record (:func:`read_vehicle_record` with ``example="2d"``)."""
    return read_vehicle_record(t, example="2d")


# ---------------------------------------------------------------------------------------- reading
def read_vehicle_record(
    source: str | Path | Table,
    *,
    example: str | None = None,
    columns: str | Mapping[str, str] | None = None,
    units: str | Mapping[str, str] | None = None,
    model: ModelOptions | None = None,
) -> VehicleRecord:
    """Read a record for the detector (see the module docstring).

    Args:
        source: A path, ``-`` for standard input, or a table already read.
        example: ``"1d"`` or ``"2d"`` to force the layout (None: from the metadata and the columns).
        columns: ``--columns`` (role=column,...).
        units: ``--units`` (role=unit,...).
        model: The model quantities given as options.

    Raises:
        InputError: bad input, naming the file (line and column where there is one).
        ConfigError: a bad option value, naming its field (``columns``, ``units``, ``example``, ``T``…).
    """
    opts = model or ModelOptions()
    table = source if isinstance(source, Table) else read_table(source, max_rows=MAX_RECORD)
    src, meta = table.source, table.meta
    kind = meta.get("example")
    if kind is not None and str(kind) not in ("1d", "2d"):
        raise InputError(f"{src}: unknown example {kind!r} in the metadata")
    if example is not None:
        one_of("example", example, ("1d", "2d"))
        if kind is not None and str(kind) != example:
            raise ConfigError("example", example, f"does not match the record: {src} is a {kind} record")
    simulate = meta.get("command") == "simulate"
    colmap = parse_columns(columns, SPEC_ANY)
    unitmap = parse_units(units, SPEC_ANY)
    layout = _layout(table, colmap, example or (None if kind is None else str(kind)))
    spec = LAYOUTS[layout]
    names = tuple(r.name for r in spec.roles)
    what = "1-D" if layout == "1d" else "2-D (x, y)" if layout == "cartesian" else "2-D (range, bearing)"
    for option, given in (("columns", colmap), ("units", unitmap)):
        for role in given:
            if role not in names:
                raise ConfigError(option, role, f"is not a column of a {what} record ({', '.join(names)})")
    for name in opts.given(*(ONLY_2D if layout == "1d" else ONLY_1D)):
        other = "2d" if layout == "1d" else "1d"
        why = "; --example 1d reads its y as a 1-D position" if layout == "cartesian" else ""
        raise ConfigError(
            name, getattr(opts, name), f"applies to the {other} example only ({src} is a {what} record{why})"
        )
    colmap = _pin_columns(table, spec, colmap, LEGACY_COLUMNS.get(layout) if simulate else None, layout)
    if simulate:
        _refuse_missing_meta(meta, opts, layout, src)
    rec = read_record(table, spec, columns=colmap, units=unitmap)
    t = rec["time"]
    if t.size < 2:
        raise InputError(f"{src}: need at least 2 samples, found {t.size}")
    d = np.diff(t)
    if np.any(d <= 0):
        i = int(np.flatnonzero(d <= 0)[0]) + 1
        how = "repeats the previous row's" if d[i - 1] == 0 else f"goes backwards after {t[i - 1]:.9g} s"
        raise rec.error(i, "time", f"time is not increasing ({t[i]:.9g} s {how})")
    T, k, T_source = _sample_period(rec, t, meta, opts)
    n = int(k[-1]) + 1
    if n > MAX_RECORD:
        raise rec.error(
            len(rec) - 1,
            "time",
            f"the record spans {n} samples of {T:g} s, more than {MAX_RECORD}: shorten it",
        )
    y, first_xy = _measurements(rec, layout, k, n)
    lines = np.zeros(n, dtype=np.int64)
    lines[k] = rec.lines
    times = t[0] + np.arange(n) * T
    miss = np.isnan(y) if y.ndim == 1 else np.isnan(y).any(axis=1)
    if miss.all():
        raise InputError(f"{src}: no measurement: every sample of the record is missing")
    first = _first_missing(rec, layout, k, lines, times, miss)
    m = _Model(meta, opts, layout, src)
    m.lines = dict(table.meta_lines)  # the line of each metadata key, for its errors
    vehicle, codes, m_rho, f_c = m.resolve(T, T_source, first_xy)
    truth = _truth(meta, m, codes, src)
    prov = _provenance(rec, layout, m, int(miss.sum()), n)
    return VehicleRecord(
        times, y, vehicle, codes.chips, m_rho, f_c, truth, meta, src, lines, codes.spec, prov, first
    )


def _base(column: str) -> str:
    """A header's name without its unit, lower case (``Range [km]`` → ``range``)."""
    return _HEADER_UNIT.sub(r"\1", column).strip().lower()


def _layout(table: Table, colmap: dict[str, str], example: str | None) -> str:
    """``"1d"``, ``"polar"`` or ``"cartesian"`` (see the module docstring)."""
    bases = {_base(c) for c in table.columns}

    def has(role: Role) -> bool:
        return role.name in colmap or any(n in bases for n in role.names)

    if example is None:
        two_d = bool(set(colmap) & {"range", "bearing", "x"}) or has(RANGE) or has(BEARING)
        two_d = two_d or (has(EAST) and has(NORTH) and not ("y" in colmap and "x" not in colmap))
        if not two_d:
            return "1d"
    elif example == "1d":
        return "1d"
    if set(colmap) & {"range", "bearing"}:
        return "polar"
    if set(colmap) & {"x", "y"}:
        return "cartesian"
    if has(RANGE) or has(BEARING) or not (has(EAST) or has(NORTH)):
        return "polar"
    return "cartesian"


def _pin_columns(
    table: Table, spec: RecordSpec, colmap: dict[str, str], legacy: dict[str, str] | None, layout: str
) -> dict[str, str]:
    """The column of each role: the user's mapping, then (a ``simulate`` record) its own columns, or a
    column named exactly as the role (which wins over an alias)."""
    out = dict(colmap)
    where = f"{table.source}:{table.header_line}" if table.header_line else table.source
    for role in spec.roles:
        if role.name in out:
            continue
        if legacy is not None:
            col = legacy[role.name]
            if col not in table.columns:
                hint = HINT_1D if layout == "1d" else HINT_2D
                raise InputError(f"{where}: missing column {col!r} ({hint}, or map one with --columns)")
            out[role.name] = col
            continue
        hits = [c for c in table.columns if _base(c) == role.name and c not in out.values()]
        if len(hits) == 1:
            out[role.name] = hits[0]
    return out


def _refuse_missing_meta(meta: dict[str, Any], opts: ModelOptions, layout: str, src: str) -> None:
    """A ``simulate`` record carries its whole model: a key missing from its metadata and the options is an
    edited record."""
    covered = {
        "T": opts.T, "m_rho": opts.m_rho, "K": opts.K or opts.wn or opts.zeta, "R": opts.R or opts.anr_db,
        "codes": opts.codes, "f_c": opts.f_c, "a_sig": opts.a_sig, "R_range": opts.R_range or opts.anr_pair,
        "R_bearing": opts.R_bearing or opts.anr_pair, "start": opts.start,
    }  # fmt: skip
    needed = NEEDED_META_1D if layout == "1d" else NEEDED_META_2D
    missing = [k for k in needed if k not in meta and covered[k] is None]
    if missing:
        hint = HINT_1D if layout == "1d" else HINT_2D
        raise InputError(f"{src}: missing metadata {', '.join(repr(m) for m in missing)} ({hint})")


def _meta_T(meta: dict[str, Any], src: str) -> float:
    try:
        T = float(meta["T"])
        if not (math.isfinite(T) and T > 0):
            raise ValueError
    except (TypeError, ValueError):
        raise InputError(f"{src}: metadata 'T' must be a positive number, got {meta['T']!r}") from None
    return T


def _snap(T: float) -> float:
    """An estimated period within 1e-9 of a number of 9 significant digits is that number (assumed: the
    estimate of exact multiples of 0.05 s reads 0.05 s, not 0.05000000000000001 s)."""
    short = float(f"{T:.9g}")
    return short if abs(short - T) <= 1e-9 * T else T


def _sample_period(
    rec: Record, t: np.ndarray, meta: dict[str, Any], opts: ModelOptions
) -> tuple[float, np.ndarray, str]:
    """(T, the step of each row on the grid, where T came from)."""
    T_meta = _meta_T(meta, rec.source) if "T" in meta else None
    if opts.T is not None:
        T = positive("T", opts.T, unit="s")
        try:
            k, _ = uniform_grid(rec, t, T)
        except InputError as exc:
            try:
                hint = f"the times give T = {_snap(uniform_grid(rec, t)[1]):.6g} s"
            except InputError:
                hint = "the times are not uniform either"
            raise ConfigError("T", opts.T, f"s does not fit the record's times ({hint}): {exc}") from None
        said = (
            ""
            if T_meta is None
            else f" (the record says {T_meta:g} s)"
            if T_meta != T
            else " (as the record)"
        )
        return T, k, OPTION + said
    if T_meta is not None:
        try:
            k, _ = uniform_grid(rec, t, T_meta)
        except InputError as exc:
            raise InputError(f"{exc} (T = {T_meta:g} s from the metadata)") from None
        return T_meta, k, RECORD
    k, T = uniform_grid(rec, t)
    return _snap(T), k, "record (estimated from the time column)"


def _measurements(
    rec: Record, layout: str, k: np.ndarray, n: int
) -> tuple[np.ndarray, tuple[float, float] | None]:
    """The measurements on the grid (NaN: missing) and, 2-D, the first measured position (x, y)."""
    for role in LAYOUTS[layout].roles:
        if role.quantity == "length":
            _refuse_huge(rec, role.name)
    if layout == "1d":
        y = np.full(n, np.nan)
        y[k] = rec["y"]
        return y, None
    if layout == "polar":
        rng, brg = rec["range"], rec["bearing"]
        present = ~(np.isnan(rng) | np.isnan(brg))
        bad = np.flatnonzero(present & (rng <= 0))
        if bad.size:
            i = int(bad[0])
            reason = (
                "range 0 <= 0: the target is at the radar (bearing undefined)"
                if rng[i] == 0
                else f"range {_in_unit(rec, 'range', rng[i])} is not > 0"
            )
            raise rec.error(i, "range", reason)
        over = np.flatnonzero(present & (np.abs(brg) > math.pi * (1 + 1e-12)))
        if over.size:
            i, unit = int(over[0]), rec.units["bearing"]
            f = UNITS["angle"][unit]
            hint = (
                " (degrees in a column labelled radians? say so with --units bearing=deg, a header "
                '"bearing [deg]" or the metadata # bearing_unit: "deg")'
                if unit == "rad"
                else ""
            )
            raise rec.error(
                i,
                "bearing",
                f"bearing {brg[i] / f:g} is outside [-{math.pi / f:g}, {math.pi / f:g}] {unit}{hint}",
            )
    else:
        x, yy = rec["x"], rec["y"]
        present = ~(np.isnan(x) | np.isnan(yy))
        rng, brg = np.hypot(x, yy), np.arctan2(yy, x)
        bad = np.flatnonzero(present & (rng == 0))
        if bad.size:
            raise rec.error(int(bad[0]), "x", "x = y = 0: the target is at the radar (bearing undefined)")
    y = np.full((n, 2), np.nan)
    y[k[present]] = np.stack([rng[present], brg[present]], axis=-1)
    first = int(np.flatnonzero(present)[0]) if present.any() else None
    xy = (
        None
        if first is None
        else (float(rng[first] * math.cos(brg[first])), float(rng[first] * math.sin(brg[first])))
    )
    return y, xy


def _in_unit(rec: Record, role: str, value: float, fmt: str = "g") -> str:
    """A length [m] in the unit of its column (``-5 m``, ``-0.005 km``)."""
    unit = rec.units[role]
    return f"{value / UNITS['length'][unit] + 0.0:{fmt}} {unit}"  # + 0.0: -0 reads 0


def _refuse_huge(rec: Record, role: str) -> None:
    """Refuse a length whose magnitude exceeds :data:`MAX_MAGNITUDE` (NaN, a missing sample, passes)."""
    values = rec[role]
    big = np.flatnonzero(np.abs(values) > MAX_MAGNITUDE)  # NaN compares False; inf is caught
    if big.size:
        i = int(big[0])
        unit = rec.units[role]
        si = "" if unit == "m" else f" = {abs(values[i]):.9g} m"
        raise rec.error(
            i,
            role,
            f"|{role}| {_in_unit(rec, role, abs(values[i]), '.9g')}{si} exceeds {MAX_MAGNITUDE:g} m "
            "(an implausible measurement: a unit error or a fill value?)",
        )


def _first_missing(
    rec: Record, layout: str, k: np.ndarray, lines: np.ndarray, times: np.ndarray, miss: np.ndarray
) -> tuple[int, str] | None:
    """(index, ``file:line: column`` text) of the first missing sample."""
    idx = np.flatnonzero(miss)
    if not idx.size:
        return None
    i = int(idx[0])
    if lines[i] > 0:
        row = int(np.searchsorted(k, i))
        roles = [r.name for r in LAYOUTS[layout].roles if r.name != "time"]
        role = next(r for r in roles if np.isnan(rec[r][row]))
        return i, rec.where(row, role)
    after = int(np.searchsorted(k, i))  # the first row after the absent sample
    return (
        i,
        f"{rec.where(after, 'time')}: no row for t = {times[i]:.9g} s (absent before this line)",
    )


def _truth(meta: dict[str, Any], m: _Model, codes: ModeCodes, src: str) -> tuple[int, int] | None:
    """The recorded truth, where the record's codes and m_ρ are those the detector searches."""
    try:
        truth = truth_of(meta)
    except (TypeError, ValueError):
        raise InputError(f"{src}: bad metadata: mode {meta.get('mode')!r}, tau {meta.get('tau')!r}") from None
    if truth is None or not (m.from_record("codes") and m.from_record("m_rho")):
        return None
    chips = meta.get("tau_chips")
    m_rho = m.values["m_rho"]
    if chips is not None and (
        not isinstance(chips, int | float) or abs(chips * m_rho - truth[1]) > 1e-9 * m_rho
    ):
        raise InputError(
            f"{src}: metadata contradicts itself: tau {truth[1]} samples, but tau_chips {chips!r} x m_rho "
            f"{m_rho} = {chips * m_rho if isinstance(chips, int | float) else '?'} samples"
        )
    if not 0 <= truth[0] < codes.n_modes:
        raise InputError(f"{src}: bad metadata: mode {truth[0] + 1} is not one of the {codes.n_modes} modes")
    return truth


def _provenance(rec: Record, layout: str, m: _Model, n_missing: int, n: int) -> dict[str, Any]:
    """The output metadata of the reading, only where it differs from a plain ``simulate`` record."""
    out: dict[str, Any] = {}
    if any(s != RECORD for s in m.sources.values()):
        out["model"] = dict(m.values)
        out["model_sources"] = dict(m.sources)
    if rec.columns != LEGACY_COLUMNS.get(layout):
        out["input_columns"] = dict(rec.columns)
    si = {"time": "s", "y": "m", "range": "m", "bearing": "rad", "x": "m"}
    if any(si[role] != unit for role, unit in rec.units.items()):
        out["input_units"] = dict(rec.units)
    if rec.time_origin is not None:
        out["time_origin"] = rec.time_origin
    if layout == "cartesian":
        out["measurement"] = CARTESIAN_NOTE
    if n_missing:
        out["missing_samples"] = n_missing
        out["missing_rule"] = (
            f"{n_missing} of {n} samples missing (empty or NaN cells, or absent from the time grid): "
            "predict-only steps of the filters (no update, no cost)"
        )
    return out


class _Model:
    """The model quantities of a record: option, else metadata, else default (assumed), with sources.

    A value is checked where it is used: a bad one from the metadata is an :class:`InputError` ("bad
    metadata"), a bad option value a :class:`ConfigError` naming its field (the command line maps it to
    the option)."""

    def __init__(self, meta: dict[str, Any], opts: ModelOptions, layout: str, src: str) -> None:
        self.meta, self.opts, self.layout, self.src = meta, opts, layout, src
        self.lines: dict[str, int] = {}
        self.values: dict[str, Any] = {}
        self.sources: dict[str, str] = {}

    def at(self, name: str) -> str:
        """``file:line`` of the metadata key ``name`` (``file`` where its line is unknown)."""
        line = self.lines.get(name, 0)
        return f"{self.src}:{line}" if line else self.src

    def from_record(self, name: str) -> bool:
        return self.sources.get(name, RECORD) in (RECORD, f"{OPTION} (as the record)")

    def pick(self, name: str, option: Any, default: Any, note: str = "") -> Any:
        """The option, else the metadata's value, else the default (raw); recorded with its source."""
        if option is not None:
            value, source = option, OPTION + note
            if name in self.meta:
                same = _same(self.meta[name], option)
                source += " (as the record)" if same else f" (the record says {_text(self.meta[name])})"
        elif name in self.meta:
            value, source = self.meta[name], RECORD
        else:
            value, source = default, DEFAULT + note
        self.sources[name] = source
        return value

    def check(self, name: str, raw: Any, fn: Callable[[Any], Any]) -> Any:
        """``fn(raw)``, its errors blamed on the metadata or the option the value came from."""
        try:
            return fn(raw)
        except ConfigError as exc:
            if self.sources.get(name) == RECORD:
                raise InputError(f"{self.at(name)}: bad metadata: {exc}") from None
            raise
        except (TypeError, ValueError) as exc:  # a value of the wrong type or shape
            if self.sources.get(name) == RECORD:
                raise InputError(f"{self.at(name)}: bad metadata: {name} = {raw!r} {exc}") from None
            raise ConfigError(name, raw, str(exc)) from None

    def resolve(
        self, T: float, T_source: str, first_xy: tuple[float, float] | None
    ) -> tuple[Vehicle1D | Vehicle2D, ModeCodes, int, float]:
        o = self.opts
        self.values["T"], self.sources["T"] = T, T_source
        raw = self.pick("m_rho", o.m_rho, 20)
        m_rho = self.check("m_rho", raw, lambda v: integer("m_rho", v, 1))
        raw = self.pick("f_c", o.f_c, 1.0)
        f_c = self.check("f_c", raw, lambda v: in_range("f_c", v, 0.0))
        raw = self.pick("a_sig", o.a_sig, 0.5)
        a_sig = self.check("a_sig", raw, lambda v: in_range("a_sig", _number(v), 0.0))
        raw = self.pick("codes", o.codes, "corrected")
        # a code table file only from the command line: the record's metadata is data, never a path
        files = self.sources.get("codes") != RECORD
        codes = self.check("codes", raw, lambda v: parse_codes(str(v), files=files))
        K = self._gain(T)
        fields: dict[str, Any] = dict(T=T, K=K, a_sig=a_sig)
        for name, default in (("a_r", 10.0), ("f_r", 0.01), ("sigma_a", 0.01)):  # simulate's defaults
            raw = self.pick(name, getattr(o, name), default)
            fields[name] = self.check(name, raw, lambda v, n=name: in_range(n, _number(v), 0.0))
        if self.layout == "1d":
            fields["R"] = self._variance(a_sig)
            fields.update(self._truth_loop())
        else:
            fields["R_range"], fields["R_bearing"] = self._radar_noise(a_sig)
            raw = self.pick("start", o.start, first_xy)
            if o.start is None and "start" not in self.meta:
                self.sources["start"] = "record (the first measured position, assumed)"
            fields["start"] = self.check("start", raw, _pair)
        self.values.update(m_rho=m_rho, f_c=f_c, codes=codes.spec, **fields)
        self.values = {k: list(v) if isinstance(v, tuple) else v for k, v in self.values.items()}
        cls = Vehicle1D if self.layout == "1d" else Vehicle2D
        try:
            vehicle = cls(**fields)
        except ConfigError as exc:
            if self.sources.get(exc.field) == RECORD:
                raise InputError(f"{self.src}: bad metadata: {exc}") from None
            raise
        return vehicle, codes, m_rho, f_c

    def _truth_loop(self) -> dict[str, Any]:
        """1-D: the carrier offset f_d and the feedback (simulate writes ``feedback: "true state"`` or
        ``"estimate"``), from the option or the metadata; absent from both: the defaults, unrecorded (an
        older record, or a user's export, reads as before)."""
        o, out = self.opts, {}
        if o.f_d is not None or "f_d" in self.meta:
            raw = self.pick("f_d", o.f_d, 0.0)
            out["f_d"] = self.check("f_d", raw, lambda v: in_range("f_d", _number(v)))
        if o.feedback is not None or "feedback" in self.meta:
            raw = self.pick("feedback", o.feedback, "true")
            names = {"true state": "true", "true": "true", "estimate": "estimate"}
            out["feedback"] = self.check(
                "feedback", raw, lambda v: names[one_of("feedback", str(v), tuple(names))]
            )
        for name, default in (("f_d", 0.0), ("feedback", "true")):  # a default from the record: unlisted
            if name in out and out[name] == default and getattr(o, name) is None:
                del self.sources[name]
            elif name in out:
                self.values[name] = out[name]
        return out

    def _gain(self, T: float) -> tuple[float, float]:
        o = self.opts
        if o.K is not None:
            ignored = " (--pole-wn/--pole-zeta ignored, as in simulate)" if o.given("wn", "zeta") else ""
            raw = self.pick("K", tuple(o.K), None, ignored)
        elif o.given("wn", "zeta"):
            wn = 4 * math.pi if o.wn is None else o.wn
            zeta = 0.7 if o.zeta is None else o.zeta
            raw = self.pick(
                "K", pole_placement_gain(T, wn, zeta), None, f": pole placement wn = {wn:g}, zeta = {zeta:g}"
            )
        elif "K" in self.meta:
            raw = self.pick("K", None, None)
        else:
            raw = self.pick(
                "K", None, pole_placement_gain(T), ": pole placement wn = 4 pi rad/s, zeta = 0.7 at T"
            )
        return self.check("K", raw, _pair)

    def _variance(self, a_sig: float) -> float:
        o = self.opts
        if o.anr_db is not None:
            conv = o.db_convention or "log10"
            R = measurement_variance(o.R, o.anr_db, conv, a_sig)
            return float(self.pick("R", R, None, f" (--anr-db {o.anr_db:g}, {conv})"))
        raw = self.pick("R", o.R, DEFAULT_R)
        return self.check("R", raw, _number)

    def _radar_noise(self, a_sig: float) -> tuple[float, float]:
        o = self.opts
        if o.anr_pair is not None:
            rr, rb, _ = radar_noise(o.anr_pair, o.R_range, o.R_bearing, a_sig)
            note = f" (--anr-pair {o.anr_pair})"
            return float(self.pick("R_range", rr, None, note)), float(self.pick("R_bearing", rb, None, note))
        out = []
        for i, name in enumerate(("R_range", "R_bearing")):
            option = getattr(o, name)
            if option is None and name not in self.meta:
                # simulate's default: Fig 7's pair 4 (its variances scale with a_sig²)
                default = self.check("a_sig", a_sig, lambda a, i=i: anr_pair_variances(4, a)[i])
                raw = self.pick(name, None, default, " (Fig 7 ANR pair 4)")
            else:
                raw = self.pick(name, option, None)
            out.append(self.check(name, raw, _number))
        return out[0], out[1]


def _same(meta_value: Any, option: Any) -> bool:
    """Whether an option repeats the record's value."""
    if isinstance(option, tuple | list):
        return isinstance(meta_value, list | tuple) and list(meta_value) == list(option)
    if isinstance(option, str):
        return str(meta_value) == option
    return isinstance(meta_value, int | float) and not isinstance(meta_value, bool) and meta_value == option


def _text(value: Any) -> str:
    return f"{value:g}" if isinstance(value, float) else repr(value)


def _number(value: Any) -> float:
    """A metadata number (float() of a JSON number or numeric text)."""
    try:
        if isinstance(value, bool) or not isinstance(value, int | float | str):
            raise ValueError
        return float(value)
    except ValueError:
        raise ValueError("is not a number") from None


def _pair(v: Any) -> tuple[float, float]:
    """A value that is two numbers (``K``, ``start``: a metadata list, or an option's tuple)."""
    ok = isinstance(v, list | tuple) and len(v) == 2
    ok = ok and all(isinstance(e, int | float) and not isinstance(e, bool) for e in v)
    if not ok:
        raise ValueError("is not a list of two numbers")
    return float(v[0]), float(v[1])
