"""A user's time-of-arrival (TOA) record solved epoch by epoch for the transmitter's position and clock, and
the clock tracked across epochs with the estimator of ATC-10 (Schneider, Stiglitz & Eckberg, MIT Lincoln
Laboratory, 1972), §4.5 — the multilateration system of its §4 (an aircraft transmits, receivers on
satellites or on the ground record the pulse, the ground estimates position and the aircraft's clock).

**The record** (read with :mod:`motionsig_cli.records`; one row per receiver and epoch, the rows of an
epoch consecutive):

- ``epoch`` (an integer; aliases ``pulse``, ``update``, ``scan``) and/or ``time`` (seconds or ISO 8601;
  aliases ``t``, ``timestamp``): which pulse a row belongs to, and the epoch's nominal time t_n. Without
  either, the record is one epoch;
- ``receiver`` (aliases ``id``, ``station``, ``satellite``, ``sat``, ``name``, ``receiver_id``, ``site``):
  the receiver's label (required with a receivers file, and so is the receivers file's own receiver
  column — rows numbered by position could be paired with the wrong stations; otherwise the receivers of
  an epoch are ``1``, ``2``, … in row order);
- the receiver's position in the record's own columns (ECEF ``x, y, z`` or WGS-84 ``latitude, longitude,
  altitude``: :mod:`motionsig_cli.atc10.receivers`), or in a receivers file (``--receivers``;
  static, or per epoch by ``epoch`` or ``time``);
- the measurement: ``toa`` [s] (aliases ``arrival``, ``time_of_arrival``, ``toa_s``) — the arrival time, in the time
  frame of the ``time`` column (seconds after its first timestamp when the times are timestamps), or
  measured from the epoch's own time with ``toa_origin="epoch"`` (and always without a time column) —
  or ``tdoa`` [s] (aliases ``time_difference``, ``tdoa_s``): the arrival minus the arrival at the epoch's
  reference receiver, which has its own row with 0 (the same fixes as the TOAs),
  or ``pseudorange`` [m] (aliases ``pr``, ``rho``, ``pseudorange_m``) = c(T − t_n);
- optionally ``sigma`` (aliases ``sd``, ``std``, ``sigma_toa``, ``sigma_pr``): the measurement's standard
  deviation, in the unit of the measurement (s for a TOA or TDOA, m for a pseudorange, unless stated).

An empty or NaN measurement is a receiver that missed the pulse: it drops out of that epoch. The rows of
an epoch share its time; the row that differs from the others is named.

**Exact reading.** Times, TOAs and pseudoranges are read as decimals from the cells' text (with their unit
factors, exactly) and differenced before anything is rounded to float64: absolute TOAs as Unix seconds with
12 decimals or as integer nanoseconds (1777629600000009523 ns), where float64 resolves only 0.24 µs (70 m
of range), keep every digit. The offsets τ − t_n (TOA minus its epoch's time) are exact decimals, then
floats; the epochs' times are compared as exact differences from the first epoch's whole second, and the
output metadata (``reading``) states that first time. A JSON number with a fraction is already float64
when the JSON is parsed: give such times as strings or integers in JSON.

**Clock offset** (defined precisely): b_n/c = τ_n − t_n, the emission time of epoch n's pulse in the
receivers' common time frame minus the epoch's nominal time t_n (the ``time`` value; 0 for TOAs measured
from their epoch and for pseudoranges). A transmitter that sends when its own clock reads t_n has a clock
error (its reading minus true time) of −b_n/c. The speed of light is exact, c = 299 792 458 m/s, and the
propagation is a straight line at c (no atmosphere: ionosphere, troposphere, satellite clocks and
ephemerides are the user's corrections; the Earth's rotation during the flight only with
``earth_rotation``).

**Snapshot fixes** (:func:`~motionsig_cli.surveillance.toa_fix.solve_snapshot`): weighted least squares
for (p, b) at every epoch on its own, from the closed-form solution (Bancroft 1985, both roots refined;
for receivers nearly in one plane the planar closed form above them:
:mod:`~motionsig_cli.surveillance.bancroft`) or a given point, Gauss–Newton with a line search (Newton's
steps where it crawls), an epoch that does not converge restarted from the nearest converged epoch's fix.
Receivers come and go: a receiver without a row (or with an empty measurement) at an epoch is left out of
it. An epoch with fewer than four receivers, a singular geometry or no convergence has no fix, and its row
says why (``status``); the run goes on. For a ground network (receivers nearly in one plane) the fix's
mirror image in the plane fits about as well; the start's side is kept (default: above the receivers),
and a warning says when the other side fits much better over the record. The covariance is (HᵀWH)⁻¹ with
W = 1/σ² when σ is known (a ``sigma`` column or ``sigma``), else scaled by each epoch's a-posteriori
variance factor (``covariance="epoch"``; ``"pooled"`` pools it over the record), as the output's metadata
states.

**Faults** (σ known, ``fde=True``: :mod:`~motionsig_cli.surveillance.fault_exclusion`): each epoch's
r'Wr is tested against the χ²(K − 4) quantile at the false-alarm probability ``p_fa``; a failing epoch
loses the receiver with the largest standardised residual and is solved again, while five or more
receivers remain. **Plausibility**: fixes whose median lies more than :data:`MAX_DEPTH_M` below the
ellipsoid mean measurements that do not fit the receivers (a km/m mix-up): the record is refused.
**Earth rotation** (``earth_rotation=True``): the anchors are rotated by ω_E·range/c about z
(:mod:`~motionsig_cli.surveillance.earth_rotation`), for satellite positions given at the transmission.

**Clock tracking** (``clock="track"``: :func:`track_clock`; without the measurements the fault test
excluded): the report's estimator (eqs 4.5.3–4.5.5,
4.5.16–4.5.28, :class:`~motionsig_cli.surveillance.clock_tracking.ReportClock`) with the clock model of
§4.3 (σ1 = σ2 = σ0, ρ = 1: x_n = Σ w_i + n a_0, eq 4.3.1) per step of the epoch grid (the epoch numbers, or
the uniform grid of the times), the measurement rows whitened by 1/σ_i. It starts with the first epoch's
least-squares fix (at least four receivers), then at each epoch linearises at the previous estimate,
updates the clock from the pseudo-measurement y = 1̃ᵀ(I − P̃)z̃/β̃ (four or more receivers) and solves the
position given the clock (eq 4.5.17); with three receivers the clock is predicted and the position follows
from the prediction (eq 4.5.28, the report's outage case); with fewer, and at missing steps, the clock is
predicted only (eq 4.5.27). Its clock variance is the recursion of
:func:`~motionsig_cli.surveillance.clock_tracking.clock_error_recursion`, and the position covariance
(ŨᵀŨ)⁻¹ + V vvᵀ (eq 4.5.35, corrected).

Every failure is one line: a bad record an :class:`~motionsig_cli.errors.InputError` ``file:line: column
'name': …``, a bad parameter a :class:`~motionsig_cli.config.ConfigError` naming its field.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from decimal import ROUND_FLOOR, Decimal, localcontext
from pathlib import Path
from typing import Any

import numpy as np

from motionsig_cli.atc10.receivers import (
    DECIMAL_DIGITS,
    ID_ROLE,
    POSITION_ROLES,
    Receivers,
    check_coincident,
    check_unique,
    decimal_seconds,
    epoch_groups,
    exact_values,
    positions_from,
    read_receivers,
    subset_rows,
    time_shift,
)
from motionsig_cli.config import ConfigError, in_range, integer, one_of
from motionsig_cli.errors import InputError
from motionsig_cli.geodesy import ecef_to_geodetic, geodetic_to_ecef
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
from motionsig_cli.surveillance.clock import psi
from motionsig_cli.surveillance.clock_tracking import ReportClock
from motionsig_cli.surveillance.earth_rotation import rotate_for_flight
from motionsig_cli.surveillance.fault_exclusion import P_FA, FaultExclusion, FdeResult, exclude_faults
from motionsig_cli.surveillance.multilateration import COND_LIMIT, FOOT_M, GeometryError
from motionsig_cli.surveillance.toa_fix import (
    C_M_PER_S,
    MIN_RECEIVERS,
    NO_FIX,
    START_ALT_M,
    EpochError,
    SnapshotFix,
    position_covariance,
    scale_covariance,
    solve_snapshot,
    weighted_position_update,
    weighted_pseudo_measurement,
)
from motionsig_cli.tables import Table, make_meta, read_table

__all__ = [
    "CLOCKS",
    "COVARIANCES",
    "GAINS",
    "KINDS",
    "MAX_MEASUREMENTS",
    "MAX_RECEIVERS",
    "MAX_TOA_OFFSET_S",
    "TOA_ORIGINS",
    "UNIT_SYSTEMS",
    "VIEWS",
    "ClockTrack",
    "Measurements",
    "SolveConfig",
    "SolveReport",
    "SolveResult",
    "TrackError",
    "measurement_spec",
    "read_measurements",
    "solve",
    "solve_report",
    "track_clock",
]

MAX_MEASUREMENTS = 1_000_000
"""Most rows of a measurement record (a day of one pulse a second at eleven receivers)."""
MAX_RECEIVERS = 1000
"""Most distinct receivers in one record."""
MAX_SLOTS = 20_000_000
"""Most epochs × receivers (the arrays the solver holds)."""
MAX_TOA_OFFSET_S = 60.0
"""Largest |arrival time − the epoch's time| accepted [s] (assumed: a TOA further from its epoch's time is
in another time frame, e.g. seconds of the day against epochs counted from zero)."""
OTHER_SIDE_CHI2 = 25.0
"""Mirror-image fixes whose χ², summed over the epochs, is lower by more than this (a likelihood ratio of
e^12.5: assumed) are reported: the transmitter may be on the other side of the receivers' plane from the
starting point."""
MAX_DEPTH_M = 100e3
"""Fixes whose median over a record lies more than this below the ellipsoid [m] (assumed: no transmitter or
receiver is 100 km underground) mean measurements that do not fit the receivers' positions, such as
pseudoranges in kilometres read as metres: the record is refused."""
EXCESS_FRACTION = 0.01
"""Measurement differences beyond the receivers' separation by more than this fraction of it (plus 10 σ)
break the triangle inequality (assumed margin for positions and refraction)."""
CHECK_EPOCHS = 2000
"""Most epochs the triangle-inequality check looks at (evenly spaced)."""
CHECK_PAIRS = 1_000_000
"""Most receiver pairs (over the epochs) that check holds in memory at once."""
TIME_MATCH_S = 1e-6
"""Largest difference between a record's epoch time and a receivers file's time taken as the same [s]."""
MAX_NS = 1e9
"""Largest σ and σ0 accepted [ns] (one second)."""
RECEIVER_ROLES = ("receiver", "epoch", "time", "x", "y", "z", "latitude", "longitude", "altitude")
"""The roles of a receivers file (``--units`` entries for them apply to it)."""
SIGMA0_NS = 50.0
"""Default clock scale σ0 [ns] (that of ``track-sat simulate``; the report's Table 4.3 uses 5, 50 and 500)."""
CLOCKS = ("snapshot", "track")
VIEWS = ("epochs", "residuals")
UNIT_SYSTEMS = ("si", "report")
"""Output units: SI (metres, seconds) or the report's tables (feet, nanoseconds)."""
TOA_ORIGINS = ("time", "epoch")
"""Where a TOA is measured from: the time column's origin (absolute), or its own epoch's time."""
COVARIANCES = ("auto", "known", "epoch", "pooled")
"""The fix covariance: auto (known when σ is given, else pooled), (HᵀWH)⁻¹ with the known σ, or scaled by
each epoch's or the pooled a-posteriori variance factor."""
GAINS = ("recursive", "steady")
KINDS = ("toa", "tdoa", "pseudorange")
"""What a record measures: times of arrival, time differences of arrival against a reference receiver, or
pseudoranges."""
TDOA_ALIASES = ("time_difference", "tdoa_s")
MODES = ("init", "update", "outage", "predict")
"""What the tracker did at an epoch: start (least squares), update the clock, predict the clock and solve
the position (three receivers), predict the clock only (fewer)."""


def measurement_spec(kind: str, max_rows: int = MAX_MEASUREMENTS) -> RecordSpec:
    """The roles of a TOA record (``kind="toa"``), a TDOA record (``"tdoa"``) or a pseudorange record
    (``"pseudorange"``)."""
    one_of("kind", kind, KINDS)
    q = "length" if kind == "pseudorange" else "time"
    if kind == "toa":
        meas = Role("toa", ("arrival", "time_of_arrival", "toa_s"), quantity="time", missing=True,
                    help="time of arrival [s] (empty: the receiver missed the pulse)")  # fmt: skip
    elif kind == "tdoa":
        meas = Role("tdoa", TDOA_ALIASES, quantity="time", missing=True,
                    help="time difference of arrival against the epoch's reference receiver [s] (its own row: 0)")  # fmt: skip
    else:
        meas = Role("pseudorange", ("pr", "rho", "pseudorange_m"), quantity="length", missing=True,
                    help="pseudorange c(T - t) [m] (empty: the receiver missed the pulse)")  # fmt: skip
    return RecordSpec(
        (
            Role("epoch", ("pulse", "update", "scan"), kind="integer", required=False, order="non-decreasing",
                 help="epoch (pulse) number"),
            Role("time", ("t", "timestamp"), kind="time", required=False,
                 help="the epoch's nominal time: seconds or ISO 8601 (order checked by epoch_groups)"),
            ID_ROLE,
            meas,
            Role("sigma", ("sd", "std", "sigma_toa", "sigma_pr"), quantity=q, required=False, missing=True,
                 help=f"standard deviation of the measurement [{'s' if q == 'time' else 'm'}]"),
            *POSITION_ROLES,
        ),
        max_rows=max_rows,
        what="TOA record",
        hint="a TOA record has an epoch and/or time column, a receiver, and toa [s] or pseudorange [m]",
    )  # fmt: skip


def parse_sigma(value: str | float) -> tuple[float, str | None]:
    """``--sigma``: (value, unit) from a number (unit None: the measurement's own, s for TOAs and TDOAs, m
    for pseudoranges) or a text with a time or length unit, ``"10ns"``, ``"3 m"``, ``"0.5us"``.

    Raises:
        ConfigError: (field ``sigma``) not a number with an optional known unit, or not > 0.
    """
    unit: str | None = None
    if isinstance(value, str):
        m = re.fullmatch(r"\s*([-+0-9.eE]+)\s*([A-Za-zµ]*)\s*", value)
        try:
            v = float(m.group(1)) if m else math.nan
        except ValueError:
            v = math.nan
        if not m or not math.isfinite(v):
            raise ConfigError("sigma", value, "is not a number with an optional unit (e.g. 10ns, 3m, 1e-8)")
        unit = m.group(2) or None
        if unit is not None and unit not in UNITS["time"] and unit not in UNITS["length"]:
            known = ", ".join([*UNITS["time"], *UNITS["length"]])
            raise ConfigError("sigma", value, f"has unit {unit!r}: not a time or length unit ({known})")
    else:
        v = float(value)
    if not (v > 0 and math.isfinite(v)):
        raise ConfigError("sigma", value, "is not > 0")
    return v, unit


def sigma_metres(value: str | float, kind: str) -> float:
    """σ [m] of a ``--sigma`` value for a record of measurements ``kind`` (a time times c).

    Raises:
        ConfigError: (field ``sigma``) bad, or more than one second (c × 1 s).
    """
    v, unit = parse_sigma(value)
    if unit is None:
        unit = "m" if kind == "pseudorange" else "s"
    metres = v * UNITS["length"][unit] if unit in UNITS["length"] else C_M_PER_S * v * UNITS["time"][unit]
    if metres > C_M_PER_S * MAX_NS * 1e-9:
        hint = (
            f" (a number without a unit is in the measurement's unit, {unit} here: 10 ns is 10ns)"
            if isinstance(value, float | int) or re.fullmatch(r"\s*[-+0-9.eE]+\s*", str(value))
            else ""
        )
        raise ConfigError("sigma", value, f"is more than one second of light time{hint}")
    return metres


@dataclass(frozen=True)
class SolveConfig:
    """What ``track-sat solve`` computes and writes.

    Attributes:
        clock: ``snapshot`` (a least-squares fix per epoch) or ``track`` (also the report's clock tracker).
        sigma: the error σ of every measurement (overrides a ``sigma`` column): a number in the unit of the
            measurement (seconds for TOAs and TDOAs, metres for pseudoranges) or a text with a unit
            (``"10ns"``, ``"3 m"``: :func:`parse_sigma`), at most one second (c × 1 s as a length);
            None: the record's ``sigma`` column, else unknown (unit weights).
        sigma_ns: the same σ in nanoseconds (the older spelling; not with ``sigma``).
        sigma0_ns: the clock model's scale σ0 [ns] per epoch step (σ1 = σ2 = σ0, ρ = 1), in [0, MAX_NS];
            None: :data:`SIGMA0_NS` (the default of ``track-sat simulate``).
        gain: ``recursive`` (the exact γ_n) or ``steady`` (the constant ψ(α) from the first epoch's geometry).
        reinit_after_outage: restart the tracker by least squares at the first epoch with four or more
            receivers after an epoch with fewer or a missing step (the report's choice); default continue.
        relinearise: extra linearisations per epoch at the new estimate, 0 to 10.
        units: ``si`` (m, s) or ``report`` (ft, ns) for the output.
        toa_origin: one of :data:`TOA_ORIGINS`.
        covariance: one of :data:`COVARIANCES`.
        start: (latitude [deg], longitude [deg], altitude [m]) of the Gauss–Newton starting point, or None
            (the receivers' centroid 10 km above the ellipsoid).
        max_iter: Gauss–Newton steps per epoch, 1 to 1000.
        view: ``epochs`` (one row per epoch) or ``residuals`` (one row per measurement).
        full_covariance: add the covariance of (x, y, z, clock offset) as columns.
        fde: fault detection and exclusion (:mod:`~motionsig_cli.surveillance.fault_exclusion`; needs σ).
        p_fa: the fault test's false-alarm probability per epoch, in (0, 0.5].
        earth_rotation: rotate the anchors by the Earth's rotation during the signal's flight
            (:mod:`~motionsig_cli.surveillance.earth_rotation`; for satellite positions given at the
            transmission time).
    """

    clock: str = "snapshot"
    sigma: str | float | None = None
    sigma_ns: float | None = None
    sigma0_ns: float | None = None
    gain: str = "recursive"
    reinit_after_outage: bool = False
    relinearise: int = 2
    units: str = "si"
    toa_origin: str = "time"
    covariance: str = "auto"
    start: tuple[float, float, float] | None = None
    max_iter: int = 20
    view: str = "epochs"
    full_covariance: bool = False
    fde: bool = True
    p_fa: float = P_FA
    earth_rotation: bool = False

    def __post_init__(self) -> None:
        one_of("clock", self.clock, CLOCKS)
        if self.sigma_ns is not None:
            in_range("sigma_ns", self.sigma_ns, 0.0, MAX_NS, lo_open=True, unit="ns")
            if self.sigma is not None:
                raise ConfigError("sigma_ns", self.sigma_ns, "and sigma both given: give one")
        if self.sigma is not None:
            parse_sigma(self.sigma)
        FaultExclusion(self.p_fa, self.fde)
        if self.earth_rotation and self.clock == "track":
            raise ConfigError("earth_rotation", True, "applies to the snapshot fixes: not with --clock track")
        if self.sigma0_ns is not None:
            in_range("sigma0_ns", self.sigma0_ns, 0.0, MAX_NS, unit="ns")
        one_of("gain", self.gain, GAINS)
        integer("relinearise", self.relinearise, 0, 10)
        one_of("units", self.units, UNIT_SYSTEMS)
        one_of("toa_origin", self.toa_origin, TOA_ORIGINS)
        one_of("covariance", self.covariance, COVARIANCES)
        integer("max_iter", self.max_iter, 1, 1000)
        one_of("view", self.view, VIEWS)
        if self.start is not None:
            if len(self.start) != 3:
                raise ConfigError("start", tuple(self.start), "is not latitude,longitude,altitude")
            in_range("start", self.start[0], -90.0, 90.0, unit="degrees (latitude)")
            in_range("start", self.start[1], -360.0, 360.0, unit="degrees (longitude)")
            in_range("start", self.start[2], -1e4, 1e8, unit="m (altitude)")
        if self.clock != "track":
            for name, value, default in (("gain", self.gain, "recursive"), ("relinearise", self.relinearise, 2),
                                         ("reinit_after_outage", self.reinit_after_outage, False),
                                         ("sigma0_ns", self.sigma0_ns, None)):  # fmt: skip
                if value != default:
                    raise ConfigError(name, value, "applies to the clock tracker: add --clock track")

    @property
    def sigma0(self) -> float:
        """σ0 [ns] (given, or :data:`SIGMA0_NS`)."""
        return SIGMA0_NS if self.sigma0_ns is None else float(self.sigma0_ns)

    @property
    def sigma0_m(self) -> float:
        """σ0 as a length [m] (c σ0)."""
        return C_M_PER_S * self.sigma0 * 1e-9


# --- reading -----------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Measurements:
    """A TOA record on its epochs (E) and receiver slots (K).

    Attributes:
        kind: ``toa`` or ``pseudorange`` (what the record held).
        rho: (E, K) pseudoranges c(T − t_n) [m]; NaN: no measurement.
        sigma: (E, K) σ of each pseudorange [m], or None (unknown: unit weights).
        sigma_source: where σ came from (for the metadata).
        receivers: (E, K, 3) ECEF positions [m] (NaN: the receiver has no row at that epoch).
        row: (E, K) the record row of each slot (−1: none).
        labels: (K,) receiver labels.
        epoch: (E,) the epoch numbers (the ``epoch`` column, else 0, 1, …).
        time: (E,) the epochs' times [s] (relative to the record's ``time_origin`` for timestamps), or None.
        t_ref: (E,) the nominal time each TOA was measured from [s] (the offsets are τ − t_ref).
        first_row: (E,) the first record row of each epoch.
        record: the record read.
        receivers_file: the receivers table, or None (positions in the record).
        first_time: the first epoch's time as an exact decimal text [s] (seconds after the first timestamp
            for timestamps), or None without a time column: what the TOAs' and times' differences were
            taken from (:func:`read_measurements`).
    """

    kind: str
    rho: np.ndarray
    sigma: np.ndarray | None
    sigma_source: str
    receivers: np.ndarray
    row: np.ndarray
    labels: tuple[str, ...]
    epoch: np.ndarray
    time: np.ndarray | None
    t_ref: np.ndarray
    first_row: np.ndarray
    record: Record
    receivers_file: Receivers | None = None
    first_time: str | None = None

    @property
    def E(self) -> int:
        return int(self.rho.shape[0])

    @property
    def K(self) -> int:
        return int(self.rho.shape[1])

    @property
    def used(self) -> np.ndarray:
        """(E, K) slots with a measurement."""
        return np.isfinite(self.rho)

    @property
    def n_used(self) -> np.ndarray:
        return self.used.sum(axis=1)

    def where(self, e: int, role: str | None = None) -> str:
        """``file:line`` of epoch ``e``'s first row (and the column of ``role``)."""
        return self.record.where(int(self.first_row[e]), role)

    def epoch_name(self, e: int) -> str:
        return f"epoch {int(self.epoch[e])}"


def _kind(table: Table, colmap: dict[str, str]) -> str:
    """``toa``, ``tdoa`` or ``pseudorange``: which measurement column the record has."""
    probe = RecordSpec(
        (
            Role(
                "toa", ("arrival", "time_of_arrival", "toa_s"), quantity="time", required=False, missing=True
            ),
            Role("tdoa", TDOA_ALIASES, quantity="time", required=False, missing=True),
            Role(
                "pseudorange", ("pr", "rho", "pseudorange_m"), quantity="length", required=False, missing=True
            ),
        ),
        max_rows=max(len(table.rows), 1),
    )
    sub_c = {k: v for k, v in colmap.items() if k in KINDS}
    found = read_record(Table(table.columns, [], table.meta, (), table.source, table.header_line), probe,
                        columns=sub_c)  # fmt: skip
    where = f"{table.source}:{table.header_line}" if table.header_line else table.source
    have = [k for k in KINDS if found.has(k)]
    if len(have) > 1:
        cols = " and ".join(repr(found.columns[k]) for k in have)
        raise InputError(
            f"{where}: columns {cols}: a record holds times of arrival, time differences or pseudoranges, not "
            "several; map one with --columns toa=NAME, tdoa=NAME or pseudorange=NAME"
        )
    if not have:
        toa, tdoa, pr = (", ".join(repr(a) for a in r.aliases) for r in probe.roles)
        raise InputError(
            f"{where}: missing column 'toa' (or {toa}) [s], 'tdoa' (or {tdoa}) [s] or 'pseudorange' (or {pr}) "
            f"[m]: columns are {', '.join(table.columns)}; map one with --columns toa=NAME"
        )
    return have[0]


def _filter_units(unitmap: dict[str, str], spec: RecordSpec) -> dict[str, str]:
    names = {r.name for r in spec.roles}
    return {k: v for k, v in unitmap.items() if k in names}


def read_measurements(
    source: str | Path | Table,
    *,
    columns: str | Mapping[str, str] | None = None,
    units: str | Mapping[str, str] | None = None,
    receivers: str | Path | Receivers | None = None,
    receivers_columns: str | Mapping[str, str] | None = None,
    toa_origin: str = "time",
    sigma_ns: float | None = None,
    sigma: str | float | None = None,
) -> Measurements:
    """Read a TOA record (and a receivers file) into epochs and receiver slots (module docstring).

    Args:
        source: the record (a path, ``-`` for standard input, or a table already read).
        columns: ``--columns`` of the record.
        units: ``--units`` role=unit entries (applied to the record and to the receivers file, each for
            the roles it reads).
        receivers: a receivers file (path or :class:`Receivers` already read), or None (positions in the
            record).
        receivers_columns: ``--columns`` of the receivers file.
        toa_origin: one of :data:`TOA_ORIGINS`.
        sigma_ns: a σ [ns] for every measurement (overrides a ``sigma`` column).
        sigma: a σ for every measurement in its own unit or with a unit (:func:`parse_sigma`; overrides a
            ``sigma`` column; not with ``sigma_ns``).

    Raises:
        ConfigError: a bad ``columns``/``units`` text or option.
        InputError: a bad record or receivers file (``file:line: column 'name': …``).
    """
    one_of("toa_origin", toa_origin, TOA_ORIGINS)
    unitmap = parse_units(units)
    table = source if isinstance(source, Table) else read_table(source, max_rows=MAX_MEASUREMENTS)
    if len(table.rows) > MAX_MEASUREMENTS:
        raise InputError(f"{table.source}: more than {MAX_MEASUREMENTS} rows (the limit for a TOA record)")
    colmap = parse_columns(columns)
    kind = _kind(table, colmap)
    spec = measurement_spec(kind)
    known = {r.name for r in spec.roles} | set(RECEIVER_ROLES)
    for role in unitmap:
        if role not in known:
            raise ConfigError(
                "units", role, f"is not a column this command reads ({', '.join(sorted(known))})"
            )
    rec = read_record(table, spec, columns=parse_columns(colmap, spec), units=_filter_units(unitmap, spec))
    if not len(rec):
        raise InputError(f"{rec.source}: no measurements (the record has a header but no rows)")
    # times as exact decimals: compared and differenced from the first epoch's whole second, not as floats
    t_dec: list[Decimal] | None = decimal_seconds(rec) if rec.has("time") else None
    t_rel: np.ndarray | None = None
    if t_dec is not None:
        with localcontext() as ctx:
            ctx.prec = DECIMAL_DIGITS
            t0 = t_dec[0].to_integral_value(rounding=ROUND_FLOOR)
            t_rel = np.array([float(d - t0) for d in t_dec])
    group, start, epochs, _ = epoch_groups(rec, t_rel)
    times = None if t_dec is None else np.array([float(t_dec[i]) for i in start.tolist()])
    E = len(start)
    has_pos = any(rec.has(r.name) for r in POSITION_ROLES)
    rx: Receivers | None = None
    if receivers is not None:
        if has_pos:
            cols = ", ".join(rec.columns[r.name] for r in POSITION_ROLES if rec.has(r.name))
            raise ConfigError(
                "receivers",
                str(receivers.source if isinstance(receivers, Receivers) else receivers),
                f"is given, but the record has receiver positions of its own ({cols}): use one or the other",
            )
        if isinstance(receivers, Receivers):
            rx = receivers
        else:
            try:
                rx = read_receivers(
                    receivers,
                    columns=receivers_columns,
                    units={k: v for k, v in unitmap.items() if k in RECEIVER_ROLES},
                    require_label=True,
                    columns_option="--receivers-columns",
                )
            except ConfigError as exc:  # name the option of the receivers file
                if exc.field != "columns":
                    raise
                raise ConfigError("receivers_columns", exc.value, exc.reason) from None
        if not rx.record.has("receiver"):  # a table read without require_label: its rows are numbered
            raise rx.record.error(
                None,
                None,
                "no receiver column: map one with --receivers-columns receiver=NAME (columns: "
                f"{', '.join(rx.record.columns.values())}): the measurements name their receivers",
            )
        if not rec.has("receiver"):
            raise rec.error(
                None,
                None,
                f"missing column 'receiver' (or {', '.join(repr(a) for a in ID_ROLE.aliases)}): the positions "
                f"are in {rx.source}, so each row must name its receiver; map it with --columns receiver=NAME",
            )
    elif receivers_columns is not None:
        raise ConfigError(
            "receivers_columns", str(receivers_columns), "describes a --receivers file: give one"
        )
    elif not has_pos:
        raise rec.error(
            None,
            None,
            "no receiver positions: give x, y, z [m] (ECEF) or latitude, longitude, altitude (WGS-84) columns, "
            "or a receivers file (--receivers FILE) and a receiver column",
        )
    # labels and slots
    if rec.has("receiver"):
        labels_row = rec["receiver"]
    else:  # 1, 2, … in row order within each epoch
        labels_row = (np.arange(len(rec)) - start[group] + 1).astype(str).astype(object)
    codes = check_unique(rec, group, labels_row)
    if rx is not None:
        index = rx.index()
        unknown = [i for i, v in enumerate(labels_row) if v not in index]
        if unknown:
            i = unknown[0]
            shown = ", ".join(rx.ids[:8]) + (f" and {rx.K - 8} more" if rx.K > 8 else "")
            raise rec.error(i, "receiver", f"unknown receiver {labels_row[i]!r} ({rx.source} lists {shown})")
        codes = np.fromiter((index[v] for v in labels_row), dtype=np.int64, count=len(rec))
        labels = rx.ids
    else:
        labels = tuple(dict.fromkeys(labels_row.tolist()))
    K = len(labels)
    if K > MAX_RECEIVERS:
        raise InputError(f"{rec.source}: {K} receivers; at most {MAX_RECEIVERS}")
    if E * K > MAX_SLOTS:
        raise InputError(f"{rec.source}: {E} epochs x {K} receivers exceeds {MAX_SLOTS:,} (split the record)")
    # positions of every row
    if rx is None:
        pos = positions_from(rec).ecef
        check_coincident(rec, pos, group, labels_row)
    else:
        pos = _receiver_positions(rec, rx, group, codes, epochs, times)
    # the measurement as a pseudorange [m]: decimal differences of the cells' text, then float64
    t_epoch = times if times is not None else np.zeros(E)
    from_time = toa_origin == "time" and t_dec is not None
    t_ref = t_epoch if from_time else np.zeros(E)
    if kind == "toa":
        toa_dec = exact_values(rec, "toa", "time")
        with localcontext() as ctx:
            ctx.prec = DECIMAL_DIGITS
            if from_time:
                assert t_dec is not None
                ref_dec = [t_dec[i] for i in start.tolist()]
                offset = np.array(
                    [
                        math.nan if a is None else float(a - ref_dec[g])
                        for a, g in zip(toa_dec, group.tolist(), strict=True)
                    ]
                )
            else:
                offset = np.array([math.nan if a is None else float(a) for a in toa_dec])
        rho_row = C_M_PER_S * offset
        far = np.flatnonzero(np.abs(offset) > MAX_TOA_OFFSET_S)  # NaN compares False
        if far.size:
            i = int(far[0])
            frame = (
                "the time column's"
                if toa_origin == "time" and times is not None
                else "its epoch's own (no time column)"
            )
            raise rec.error(
                i,
                "toa",
                f"arrival {rec['toa'][i]:.12g} s is {offset[i]:.6g} s from the epoch's time {t_ref[group[i]]:.12g} s "
                f"(TOAs are read in {frame} time frame; more than {MAX_TOA_OFFSET_S:g} s apart is another frame: "
                + (
                    "measure the TOAs from each epoch's time with --toa-origin epoch, or add a time column"
                    if toa_origin == "time"
                    else "use --toa-origin time with a time column in the TOAs' frame"
                )
                + ")",
            )
    elif kind == "tdoa":
        rho_row = C_M_PER_S * np.array(
            [math.nan if a is None else float(a) for a in exact_values(rec, "tdoa", "time")]
        )
        _check_tdoa(rec, rho_row, group, len(start))
    else:
        rho_row = np.array(
            [math.nan if a is None else float(a) for a in exact_values(rec, "pseudorange", "length")]
        )
        far = np.flatnonzero(np.abs(rho_row) > C_M_PER_S * MAX_TOA_OFFSET_S)
        if far.size:
            i = int(far[0])
            raise rec.error(
                i,
                "pseudorange",
                f"|pseudorange| {abs(rho_row[i]):.6g} m is more than c x {MAX_TOA_OFFSET_S:g} s",
            )
    measured = np.isfinite(rho_row)
    # σ [m]
    sigma_row: np.ndarray | None
    if sigma is not None:
        if sigma_ns is not None:
            raise ConfigError("sigma_ns", sigma_ns, "and sigma both given: give one")
        sm = sigma_metres(sigma, kind)
        sigma_row = np.full(len(rec), sm)
        v, u = parse_sigma(sigma)
        source_s = f"--sigma {v:g} {u or ('m' if kind == 'pseudorange' else 's')} ({sm:.6g} m of range)" + (
            " (over the record's sigma column)" if rec.has("sigma") else ""
        )
    elif sigma_ns is not None:
        in_range("sigma_ns", sigma_ns, 0.0, MAX_NS, lo_open=True, unit="ns")
        sigma_row = np.full(len(rec), C_M_PER_S * sigma_ns * 1e-9)
        source_s = f"--sigma {sigma_ns:g} ns" + (
            " (over the record's sigma column)" if rec.has("sigma") else ""
        )
    elif rec.has("sigma"):
        s = rec["sigma"] * (1.0 if kind == "pseudorange" else C_M_PER_S)
        bad = np.flatnonzero(measured & ~(s > 0))
        if bad.size:
            i = int(bad[0])
            v = rec["sigma"][i]
            what = "missing" if math.isnan(v) else f"{v:g} is not > 0"
            raise rec.error(
                i, "sigma", f"sigma {what} for a measurement (every measurement needs a sigma > 0)"
            )
        sigma_row = s
        source_s = f"the record's column {rec.columns['sigma']!r} [{rec.units.get('sigma', '')}]"
    else:
        sigma_row = None
        source_s = "unknown: unit weights, covariance scaled by the a-posteriori variance factor"
    rho = np.full((E, K), np.nan)
    S = np.full((E, K, 3), np.nan)
    row = np.full((E, K), -1, dtype=np.int64)
    rho[group, codes] = rho_row
    S[group, codes] = pos
    row[group, codes] = np.arange(len(rec))
    sig = None
    if sigma_row is not None:
        sig = np.full((E, K), np.nan)
        sig[group, codes] = sigma_row
    ep = epochs if epochs is not None else np.arange(E, dtype=np.int64)
    first = None if t_dec is None else format(t_dec[0].normalize(), "f")
    return Measurements(kind, rho, sig, source_s, S, row, labels, ep, times, t_ref, start, rec, rx, first)


def _check_tdoa(rec: Record, rho_row: np.ndarray, group: np.ndarray, E: int) -> None:
    """Every epoch of a TDOA record has its reference receiver's row (tdoa 0), and no TDOA is further than
    :data:`MAX_TOA_OFFSET_S` (another frame, or times in the wrong unit)."""
    far = np.flatnonzero(np.abs(rho_row) > C_M_PER_S * MAX_TOA_OFFSET_S)
    if far.size:
        i = int(far[0])
        raise rec.error(
            i, "tdoa", f"|tdoa| {abs(rho_row[i]) / C_M_PER_S:.6g} s is more than {MAX_TOA_OFFSET_S:g} s"
        )
    has_ref = np.zeros(E, dtype=bool)
    has_ref[group[rho_row == 0.0]] = True
    missing = np.flatnonzero(~has_ref)
    if missing.size:
        e = int(missing[0])
        i = int(np.flatnonzero(group == e)[0])
        raise rec.error(
            i,
            "tdoa",
            "this epoch has no reference row: a TDOA record lists each epoch's reference receiver with tdoa 0 "
            "(the time differences are taken against it)",
        )


def _receiver_positions(
    rec: Record,
    rx: Receivers,
    group: np.ndarray,
    codes: np.ndarray,
    epochs: np.ndarray | None,
    times: np.ndarray | None,
) -> np.ndarray:
    """(N, 3) the position of each row's receiver at its epoch from the receivers file."""
    if rx.static:
        return rx.ecef[0, codes]
    if rx.epochs is not None:
        if epochs is None:
            raise rec.error(
                None,
                None,
                f"missing column 'epoch': {rx.source} gives positions by epoch; the record needs the epochs",
            )
        key_rec, key_rx, what = epochs.astype(float), rx.epochs.astype(float), "epoch"
        tol = 0.0
    else:
        assert rx.times is not None
        if times is None:
            raise rec.error(
                None,
                None,
                f"missing column 'time': {rx.source} gives positions by time; the record needs the times",
            )
        try:
            shift = time_shift(rx.time_origin, rec.time_origin)
        except ValueError as exc:
            raise InputError(f"{rec.source}: {exc} ({rx.source})") from None
        if (rx.time_origin is None) != (rec.time_origin is None):
            raise InputError(
                f"{rec.source}: its times are {'timestamps' if rec.time_origin else 'seconds'} and those of "
                f"{rx.source} are {'timestamps' if rx.time_origin else 'seconds'}: give both in one form"
            )
        key_rec, key_rx, what = times, rx.times + shift, "time"
        tol = TIME_MATCH_S
    j = np.clip(np.searchsorted(key_rx, key_rec - tol), 0, len(key_rx) - 1)
    hit = np.abs(key_rx[j] - key_rec) <= tol
    miss = np.flatnonzero(~hit[group])
    if miss.size:
        i = int(miss[0])
        v = int(epochs[group[i]]) if what == "epoch" and epochs is not None else f"{key_rec[group[i]]:.9g} s"
        raise rec.error(i, what, f"{what} {v} is not in {rx.source} (it has positions for {rx.E} epochs)")
    out = rx.ecef[j[group], codes]
    absent = np.flatnonzero(~np.all(np.isfinite(out), axis=-1))
    if absent.size:
        i = int(absent[0])
        raise rec.error(
            i,
            "receiver",
            f"receiver {rx.ids[codes[i]]!r} has no position in {rx.source} at this row's {what}",
        )
    return out


# --- the clock tracker ---------------------------------------------------------------------------------


class TrackError(EpochError):
    """An epoch the clock tracker cannot process (``epoch``: its index)."""


@dataclass(frozen=True)
class ClockTrack:
    """The report's tracker over E epochs, vectorised over R runs (R = 1 for a record).

    Attributes:
        bias: (R, E) clock estimate b̂_n = c(τ̂_n − t_n) [m] after epoch n.
        var: (R, E) its variance V_n [m²] (the recursion of eqs 4.5.18–4.5.27).
        gain: (R, E) the gain g_n (1 at a start, 0 without a clock update).
        position: (R, E, 3) ECEF position [m] (NaN where the tracker predicts only).
        position_cov: (R, E, 3, 3) its covariance [m²].
        mode: (E,) one of :data:`MODES` per epoch.
        steps: (E,) the epoch's step on the clock model's grid.
        beta: (R, E) β̃ of the epoch at the tracker's linearisation point [1/m²] (0 without clock
            information).
    """

    bias: np.ndarray
    var: np.ndarray
    gain: np.ndarray
    position: np.ndarray
    position_cov: np.ndarray
    mode: tuple[str, ...]
    steps: np.ndarray
    beta: np.ndarray


def _advance(tracker: ReportClock, m: int) -> None:
    """m clock steps without a measurement in closed form (eq 4.5.27 in recursive form, m times):
    V += 2mσ0² + 2mχ + m(m − 1)σ0², χ += mσ0²; τ̂ unchanged."""
    if m <= 0:
        return
    s02 = tracker.s02
    tracker.V = tracker.V + 2.0 * m * s02 + 2.0 * m * tracker.chi + m * (m - 1) * s02
    tracker.chi = tracker.chi + m * s02


def track_clock(
    rho: np.ndarray,
    receivers: np.ndarray,
    weight: np.ndarray,
    steps: np.ndarray,
    start: np.ndarray,
    *,
    sigma0_m: float,
    steady_gain: bool = False,
    reinit_after_outage: bool = False,
    relinearise: int = 2,
) -> ClockTrack:
    """The report's clock tracker (module docstring), vectorised over runs.

    Args:
        rho: (R, E, K) pseudoranges [m] (any value where ``weight`` is 0).
        receivers: (E, K, 3) ECEF positions [m].
        weight: (E, K) 1/σ [1/m] of each measurement, 0 where absent (the same for every run).
        steps: (E,) increasing step of each epoch on the clock model's grid (gaps: predicted steps).
        start: (R, E, 3) least-squares fixes, used where the tracker starts (NaN: none, or one that did not
            converge: the tracker neither starts nor restarts there).
        sigma0_m: the clock model's σ0 [m] per step.
        steady_gain: the constant gain ψ(α), α = (8/27)σ0²β̃ at the first epoch (eq 4.5.32), instead of γ_n.
        reinit_after_outage: restart by least squares after epochs with fewer than four receivers or a gap.
        relinearise: extra linearisations per epoch.

    Raises:
        TrackError: the first epoch has fewer than four receivers (the track starts with a snapshot fix),
            or the directions of an epoch's receivers are singular.
    """
    rho = np.asarray(rho, float)
    R, E = rho.shape[:2]
    weight = np.asarray(weight, float)
    n_used = np.sum(weight > 0, axis=1)
    steps = np.asarray(steps, np.int64)
    tracker = ReportClock(1.0, sigma0_m)  # whitened rows: σ = 1 (eq 4.5.20 with R_n = 1/β̃_n)
    bias, var, gain, beta_out = (np.full((R, E), np.nan) for _ in range(4))
    pos = np.full((R, E, 3), np.nan)
    pcov = np.full((R, E, 3, 3), np.nan)
    modes: list[str] = []
    p_prev = np.full((R, 3), np.nan)
    last = "init"
    for e in range(E):
        n = int(n_used[e])
        S, wt, r = receivers[e], weight[e], rho[:, e]
        gap = int(steps[e] - steps[e - 1]) - 1 if e else 0
        if e:
            _advance(tracker, gap)
        restart = e == 0 or (
            reinit_after_outage
            and n >= MIN_RECEIVERS
            and (last in ("outage", "predict") or gap > 0)
            and bool(np.all(np.isfinite(start[:, e])))  # no restart from a fix that did not converge
        )
        if restart:
            if n < MIN_RECEIVERS:
                raise TrackError(
                    e,
                    f"{n} receiver(s): the clock track starts with a snapshot fix (at least {MIN_RECEIVERS})",
                )
            if not np.all(np.isfinite(start[:, e])):
                raise TrackError(
                    e,
                    "its snapshot fix did not converge, and the clock track starts from it: give a starting "
                    "point (--start) or more Gauss-Newton steps (--max-iter)",
                )
            p_ls = start[:, e]
            pm = weighted_pseudo_measurement(r, S, wt, p_ls)
            _check_directions(e, pm.R)
            if steady_gain and e == 0:
                tracker.steady_gain = np.asarray(psi((8.0 / 27.0) * tracker.s02 * pm.beta))  # (4.5.32), σ = 1
            tracker.reinit(pm.y, pm.beta)  # (4.5.3), (4.5.5)
            p = weighted_position_update(pm, p_ls, pm.y)
            mode, g = "init", np.ones(R)
        elif n >= 3:
            clock = n >= MIN_RECEIVERS
            p = p_prev
            for _ in range(1 + relinearise):
                pm = weighted_pseudo_measurement(r, S, wt, p)
                _check_directions(e, pm.R)
                p = weighted_position_update(pm, p, tracker.estimate(pm.y, pm.beta if clock else None))
            vm = tracker.prior()[1]
            g = tracker.gain(vm, pm.beta) if clock else np.zeros(R)
            tracker.commit(pm.y, pm.beta if clock else None)  # (4.5.16) / (4.5.27)
            mode = "update" if clock else "outage"
        else:
            tracker.commit(np.full(R, np.nan), None)
            p, mode, g, pm = np.full((R, 3), np.nan), "predict", np.zeros(R), None
        bias[:, e], var[:, e], gain[:, e] = tracker.tau, tracker.V, g
        if pm is not None:
            pos[:, e] = p
            pcov[:, e] = position_covariance(pm, tracker.V)
            beta_out[:, e] = pm.beta
            p_prev = p
        else:
            beta_out[:, e] = 0.0
        modes.append(mode)
        last = mode
    return ClockTrack(bias, var, gain, pos, pcov, tuple(modes), steps, beta_out)


def _check_directions(e: int, R: np.ndarray) -> None:
    """The whitened directions (R of their QR, (R, 3, 3)) span space: the position given the clock is
    observable (not so when the transmitter lies in the plane of three receivers, or the receivers are on
    a line)."""
    sv = np.linalg.svd(R, compute_uv=False)
    with np.errstate(divide="ignore", invalid="ignore"):
        cond = np.where(sv[..., -1] > 0, sv[..., 0] / sv[..., -1], np.inf)
    if np.any(~(cond <= COND_LIMIT)):
        raise TrackError(
            e,
            f"the receivers' directions are singular (condition number {float(np.max(cond)):.3g} > "
            f"{COND_LIMIT:g}): the position is not observable from them",
        )


# --- the command's computation ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SolveResult:
    """What :func:`solve` computed: the snapshot fixes (None in an epoch without one) and the track."""

    meas: Measurements
    fix_epochs: np.ndarray
    fix: SnapshotFix | None
    track: ClockTrack | None
    steps: np.ndarray | None
    period: float | None
    covariance: str
    notes: tuple[str, ...] = field(default=())
    fde: FdeResult | None = None


def _covariance_mode(cfg: SolveConfig, meas: Measurements) -> str:
    if cfg.covariance == "auto":
        return "known" if meas.sigma is not None else "epoch"
    if cfg.covariance == "known" and meas.sigma is None:
        raise ConfigError(
            "covariance", "known", "needs σ: give --sigma or a sigma column (or use --covariance pooled)"
        )
    return cfg.covariance


def _steps(meas: Measurements) -> tuple[np.ndarray, float | None]:
    """The epochs' steps on the clock model's grid: the epoch numbers, or the uniform grid of the times."""
    rec = meas.record
    if rec.has("epoch"):
        steps = meas.epoch - meas.epoch[0]
        if meas.time is not None and meas.E > 1:
            _check_epoch_times(meas, steps)
        return steps, None
    if meas.time is None or meas.E == 1:
        return np.arange(meas.E, dtype=np.int64), None
    first = np.zeros(len(rec), dtype=bool)
    first[meas.first_row] = True
    sub = subset_rows(rec, first)
    try:
        k, T = uniform_grid(sub, meas.time)
    except InputError as exc:
        raise InputError(
            f"{exc}; the clock model steps once per epoch: --clock track needs the epochs on a uniform grid "
            "(or an epoch column)"
        ) from None
    same = np.flatnonzero(np.diff(k) == 0)
    if same.size:
        i = int(same[0]) + 1
        raise sub.error(i, "time", "two epochs on one step of the time grid (give an epoch column)")
    return k, T


def _check_epoch_times(meas: Measurements, steps: np.ndarray) -> None:
    """The clock model steps once per epoch number, whatever the times (uneven times are fine): but a time
    more than one period from its epoch number's point on the grid of the median step (a time a century
    late beside epochs 1 s apart) contradicts the epoch numbers, and is refused naming both."""
    assert meas.time is not None
    k = steps.astype(float)
    t = meas.time - meas.time[0]
    with np.errstate(all="ignore"):
        T = float(np.median(np.diff(t) / np.diff(k)))  # robust: one absurd time does not move it
        off = np.abs(t - float(np.median(t - k * T)) - k * T)
    limit = T if math.isfinite(T) and T > 0 else -1.0
    bad = np.flatnonzero(~(off <= limit))
    if bad.size:
        e = int(bad[0])
        raise meas.record.error(
            int(meas.first_row[e]),
            "time",
            f"epoch {int(meas.epoch[e])} at {meas.time[e]:.9g} s is {off[e]:.6g} s off the grid the epoch numbers "
            f"and times give (period {T:.6g} s, the median step): the epoch numbers and the times contradict "
            "each other (--clock track steps once per epoch number)",
        )


def _snapshot(
    rho: np.ndarray, S: np.ndarray, sigma: np.ndarray | None, p0: np.ndarray | None, cfg: SolveConfig
) -> SnapshotFix:
    """Unscaled fixes of some epochs, every epoch decided on its own (``on_failure="flag"``); with
    ``earth_rotation`` solved again with the anchors rotated for the flight time at the fix (twice)."""
    fix = solve_snapshot(rho, S, sigma=sigma, p0=p0, max_iter=cfg.max_iter, on_failure="flag")
    if cfg.earth_rotation:
        for _ in range(2):
            ok = fix.ok
            Sr = np.where(
                ok[:, None, None], rotate_for_flight(S, np.where(ok[:, None], fix.position, 0.0)), S
            )
            fix = solve_snapshot(rho, Sr, sigma=sigma, p0=p0, max_iter=cfg.max_iter, on_failure="flag")
    return fix


def _refuse_unsolvable(meas: Measurements, fix: SnapshotFix, role: str) -> None:
    """A record none of whose epochs can be solved for want of receivers or geometry is refused (one line,
    naming the first epoch): there is nothing to write. With --clock track three receivers are enough."""
    st = fix.status
    if st is None or fix.ok.any() or not np.all((st == "too few receivers") | (st == "singular geometry")):
        return
    e = 0
    if st[e] == "too few receivers":
        raise InputError(
            f"{meas.where(e, role)}: {meas.epoch_name(e)} has {int(meas.n_used[e])} receiver(s) with a measurement: "
            f"a snapshot fix needs at least {MIN_RECEIVERS} (and no epoch of the record has a fix)"
        )
    raise InputError(
        f"{meas.where(e, 'receiver' if meas.record.has('receiver') else None)}: {meas.epoch_name(e)}: the geometry "
        "is singular: position and clock cannot be separated (e.g. all receivers on a line, or in a plane with the "
        "transmitter), and no epoch of the record has a fix"
    )


def _check_differences(meas: Measurements, role: str) -> None:
    """The measurements' differences against the receivers' separations: for any transmitter position,
    |ρ_i − ρ_j| = |‖p − S_i‖ − ‖p − S_j‖| ≤ ‖S_i − S_j‖ (the triangle inequality). A record where most epochs
    break it by more than :data:`EXCESS_FRACTION` of the separation plus 10 σ (e.g. TOAs in milliseconds read
    as seconds) does not fit the geometry and is refused; a fault at a few epochs is left to the fault test.
    At most :data:`CHECK_EPOCHS` epochs (evenly spaced) and 50 receivers per epoch are looked at."""
    E, K = meas.rho.shape
    if K < 2:
        return
    nk = min(K, 50)
    ep = np.unique(np.linspace(0, E - 1, max(1, min(E, CHECK_EPOCHS, CHECK_PAIRS // (nk * nk)))).astype(int))
    k = slice(0, nk)
    rho, S = meas.rho[ep, k], meas.receivers[ep, k]
    sig = np.zeros(rho.shape) if meas.sigma is None else np.nan_to_num(meas.sigma[ep, k])
    with np.errstate(invalid="ignore"):
        diff = np.abs(rho[:, :, None] - rho[:, None, :])
        base = np.linalg.norm(S[:, :, None, :] - S[:, None, :, :], axis=-1)
        excess = diff - base * (1.0 + EXCESS_FRACTION) - 10.0 * (sig[:, :, None] + sig[:, None, :])
        bad = np.nan_to_num(excess, nan=-1.0) > 0
    n_pairs = np.sum(np.isfinite(diff) & (base > 0), axis=(1, 2))
    checked = n_pairs > 0
    broken = bad.any(axis=(1, 2))
    if not checked.any() or broken.sum() <= 0.5 * checked.sum():
        return
    i = int(np.flatnonzero(broken)[0])
    e = int(ep[i])
    a, b = np.unravel_index(int(np.nanargmax(np.where(bad[i], diff[i] / np.where(base[i] > 0, base[i], np.inf), -1.0))),
                            bad[i].shape)  # fmt: skip
    ratio = diff[i, a, b] / base[i, a, b]
    what = "times" if meas.kind != "pseudorange" else "pseudoranges"
    raise InputError(
        f"{meas.where(e, role)}: the {meas.kind} values do not fit the receivers' positions: at {int(broken.sum())} of "
        f"{int(checked.sum())} epoch(s) two receivers' {what} differ by more than light covers between them (e.g. "
        f"{meas.epoch_name(e)}: {meas.labels[a]!r} and {meas.labels[b]!r} are {base[i, a, b]:.6g} m apart, their "
        f"{what} differ by {diff[i, a, b]:.6g} m of range, {ratio:.3g} times as much): a unit mix-up? (label "
        f"the unit, e.g. '{meas.record.columns[role]} [ms]' in the header, or --units {role}=ms)"
    )


def _plausible(meas: Measurements, fix: SnapshotFix, cfg: SolveConfig, role: str) -> None:
    """A record whose fixes lie deep inside the Earth (median over the epochs with a fix more than
    :data:`MAX_DEPTH_M` below the ellipsoid) does not fit its receivers' positions: refused, with the unit
    that would fit (a kilometre/metre mix-up) when one of ×1000 or ÷1000 does."""
    ok = np.flatnonzero(fix.ok)
    if not ok.size:
        return
    alt = ecef_to_geodetic(fix.position[ok], strict=False)[2]
    med = float(np.median(alt))
    if med >= -MAX_DEPTH_M:
        return
    hint = ""
    sub = ok[: min(ok.size, 5)]
    sig = None if meas.sigma is None else meas.sigma[sub]
    for factor, what in ((1e3, "kilometres" if meas.kind == "pseudorange" else "milliseconds"),
                         (1e-3, "millimetres" if meas.kind == "pseudorange" else "microseconds")):  # fmt: skip
        trial = solve_snapshot(meas.rho[sub] * factor, meas.receivers[sub], sigma=sig, on_failure="flag")
        if (
            trial.ok.any()
            and np.median(ecef_to_geodetic(trial.position[trial.ok], strict=False)[2]) > -MAX_DEPTH_M
        ):
            col = meas.record.columns[role]
            unit = {"kilometres": "km", "milliseconds": "ms", "millimetres": "mm", "microseconds": "us"}[what]
            hint = f"; they fit as {what}: label the unit ('{col} [{unit}]' in the header, or --units {role}={unit})"
            break
    raise InputError(
        f"{meas.where(int(ok[0]), role)}: the {meas.kind} values do not fit the receivers' positions: the fixes lie "
        f"{-med / 1e3:.6g} km below the WGS-84 ellipsoid (median over {ok.size} epoch(s)){hint}"
    )


def solve(meas: Measurements, cfg: SolveConfig) -> SolveResult:
    """Snapshot fixes (every epoch on its own: one that cannot be solved gets a status), faults excluded
    (with σ known), and with ``cfg.clock == "track"`` the clock track (module docstring).

    Raises:
        InputError: the fixes lie deep inside the Earth (a unit mix-up), or the clock track cannot start.
        ConfigError: ``covariance="known"`` without σ, or ``clock="track"`` without σ.
    """
    cov_mode = _covariance_mode(cfg, meas)
    scale = {"known": "none", "epoch": "epoch", "pooled": "pooled"}[cov_mode]
    role = {"toa": "toa", "tdoa": "tdoa"}.get(meas.kind, "pseudorange")
    if cfg.clock == "track" and meas.sigma is None:
        raise ConfigError(
            "sigma_ns",
            None,
            "is needed by --clock track: the gain weighs the clock model against the measurements; give --sigma "
            "or a sigma column",
        )
    fix_epochs = np.arange(meas.E)
    notes: list[str] = []
    p0 = None if cfg.start is None else geodetic_to_ecef(*cfg.start)
    sig_all = meas.sigma

    def run(rho: np.ndarray, idx: np.ndarray) -> SnapshotFix:
        return _snapshot(rho, meas.receivers[idx], None if sig_all is None else sig_all[idx], p0, cfg)

    fde_cfg = FaultExclusion(cfg.p_fa, enabled=cfg.fde and sig_all is not None)
    fde = exclude_faults(meas.rho, meas.receivers, np.ones(meas.rho.shape) if sig_all is None else sig_all,
                         run, fde_cfg)  # fmt: skip
    if sig_all is None:  # unit weights: r'Wr is no chi-square, there is nothing to test
        nan = np.full(meas.E, np.nan)
        fde = replace(fde, statistic=nan, threshold=nan, first_statistic=nan, first_threshold=nan,
                      alarm=np.zeros(meas.E, dtype=bool))  # fmt: skip
    fix = scale_covariance(fde.fix, scale)
    _refuse_unsolvable(meas, fix, role)
    _check_differences(meas, role)
    _plausible(meas, fix, cfg, role)
    if cfg.fde and sig_all is None:
        notes.append(
            "fault detection and exclusion is off: it needs the measurements' sigma (--sigma or a sigma column)"
        )
    status = fix.status if fix.status is not None else np.where(fix.converged, "", "no convergence")
    for reason in NO_FIX:
        bad = np.flatnonzero(status == reason)
        if bad.size:
            names = ", ".join(meas.epoch_name(int(i)) for i in bad[:5])
            notes.append(
                f"{bad.size} epoch(s) without a fix ({reason}: {names}{' ...' if bad.size > 5 else ''})"
            )
    if np.any(status == "no convergence"):
        notes.append(f"no convergence in {cfg.max_iter} Gauss-Newton steps: try --start or --max-iter")
    if fde.alarm.any():
        al = np.flatnonzero(fde.alarm)
        names = ", ".join(meas.epoch_name(int(i)) for i in al[:5])
        why = "with no receiver left to exclude" if fde_cfg.enabled else "(--no-fde: nothing excluded)"
        notes.append(
            f"{al.size} epoch(s) fail the fault test {why} ({names}"
            f"{' ...' if al.size > 5 else ''}): their fixes are flagged (integrity = false)"
        )
    both = fix.ok & np.isfinite(fix.other_chi2)
    gain = float(np.sum((fix.chi2 - fix.other_chi2)[both]))
    if gain > OTHER_SIDE_CHI2:
        notes.append(
            f"the mirror images of the fixes in the receivers' plane fit better (chi-square lower by {gain:.3g} "
            f"over {int(both.sum())} epoch(s)): is the transmitter on the other side of the receivers from the "
            "starting point? (--start)"
        )
    track = steps = period = None
    if cfg.clock == "track":
        steps, period = _steps(meas)
        assert meas.sigma is not None
        kept = meas.used & ~fde.excluded  # the tracker leaves out what the fault test excluded
        weight = np.where(kept, 1.0 / np.where(kept, meas.sigma, 1.0), 0.0)
        start = np.full((1, meas.E, 3), np.nan)
        start[0] = np.where(fix.ok[:, None], fix.position, np.nan)
        try:
            track = track_clock(
                np.where(meas.used, meas.rho, 0.0)[None],
                np.where(np.isfinite(meas.receivers), meas.receivers, 0.0),
                weight,
                steps,
                start,
                sigma0_m=cfg.sigma0_m,
                steady_gain=cfg.gain == "steady",
                reinit_after_outage=cfg.reinit_after_outage,
                relinearise=cfg.relinearise,
            )
        except (TrackError, GeometryError) as exc:
            e = int(getattr(exc, "epoch", 0))
            reason = getattr(exc, "reason", str(exc))
            raise InputError(f"{meas.where(e, role)}: {meas.epoch_name(e)}: {reason}") from None
    return SolveResult(meas, fix_epochs, fix, track, steps, period, cov_mode, tuple(notes), fde)


# --- the table ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SolveReport:
    """The table ``track-sat solve`` writes, its one-line summary and its warnings."""

    table: Table
    summary: str
    warnings: tuple[str, ...] = ()


def _cells(a: np.ndarray) -> list[Any]:
    """Python values of an array, None for NaN."""
    return [None if isinstance(v, float) and v != v else v for v in np.asarray(a).tolist()]


def _units(cfg: SolveConfig) -> tuple[float, str, float, str]:
    """(length factor, length suffix, time factor, time suffix) of the output."""
    if cfg.units == "report":
        return 1.0 / FOOT_M, "ft", 1e9, "ns"
    return 1.0, "m", 1.0, "s"


def solve_report(meas: Measurements, cfg: SolveConfig, result: SolveResult | None = None) -> SolveReport:
    """The per-epoch table (``view="epochs"``) or the per-measurement residuals (``"residuals"``)."""
    res = solve(meas, cfg) if result is None else result
    L, lu, Tf, tu = _units(cfg)
    E = meas.E
    fe = res.fix_epochs
    fix = res.fix

    def full(values: np.ndarray, shape: tuple[int, ...] = (), *, all_fixes: bool = False) -> np.ndarray:
        """Per-epoch values of the fixes (NaN without a fix, or where it did not converge)."""
        out = np.full((E, *shape), np.nan)
        if fix is not None:
            keep = np.ones(len(fe), dtype=bool) if all_fixes else fix.ok
            out[fe[keep]] = np.asarray(values)[keep]
        return out

    residual_unit = lu if meas.kind == "pseudorange" else tu
    to_res = (
        L if meas.kind == "pseudorange" else (Tf / C_M_PER_S)
    )  # metres of pseudorange → the residual's unit
    cols: dict[str, list[Any]] = {"epoch": meas.epoch.tolist()}
    if meas.time is not None:
        cols["time_s"] = _cells(meas.time)
    if cfg.view == "residuals":
        table = _residual_table(meas, cfg, res, cols, residual_unit, to_res)
    else:
        table = _epoch_table(meas, cfg, res, cols, full, residual_unit, to_res, L, lu, Tf, tu)
    summary = _summary(meas, res, residual_unit, to_res, Tf, tu)
    return SolveReport(table, summary, res.notes)


def _status_text(reason: str, n: int) -> str:
    """The status column of an epoch without a fix."""
    if reason == "too few receivers":
        return f"no fix: {n} receiver(s), a fix needs {MIN_RECEIVERS}"
    return f"no fix: {reason}"


def _epoch_table(
    meas: Measurements, cfg: SolveConfig, res: SolveResult, cols: dict[str, list[Any]], full: Any,
    residual_unit: str, to_res: float, L: float, lu: str, Tf: float, tu: str,
) -> Table:  # fmt: skip
    fix = res.fix
    cols["n_receivers"] = meas.n_used.tolist()
    pos = full(fix.position if fix else None, (3,))
    lat, lon, alt = ecef_to_geodetic(pos, strict=False)
    for j, a in enumerate("xyz"):
        cols[f"{a}_{lu}"] = _cells(pos[:, j] * L)
    cols["latitude_deg"], cols["longitude_deg"], cols[f"altitude_{lu}"] = (
        _cells(lat),
        _cells(lon),
        _cells(alt * L),
    )
    bias = full(fix.bias if fix else None)
    cols[f"clock_offset_{tu}"] = _cells(bias / C_M_PER_S * Tf)
    sd = full(fix.sd if fix else None, (4,))
    sd_enu = full(fix.sd_enu() if fix else None, (3,))
    for j, a in enumerate("xyz"):
        cols[f"sd_{a}_{lu}"] = _cells(sd[:, j] * L)
    for j, a in enumerate(("east", "north", "up")):
        cols[f"sd_{a}_{lu}"] = _cells(sd_enu[:, j] * L)
    cols[f"sd_clock_offset_{tu}"] = _cells(sd[:, 3] / C_M_PER_S * Tf)
    for d in ("gdop", "pdop", "hdop", "vdop", "tdop"):
        cols[d] = _cells(full(getattr(fix, d) if fix else None))
    cols[f"rms_residual_{residual_unit}"] = _cells(full(fix.rms_residual if fix else None) * to_res)
    it = full(fix.iterations.astype(float) if fix else None, all_fixes=True)
    cols["iterations"] = [None if v != v else int(v) for v in it.tolist()]
    cols["converged"] = [bool(c) for c in fix.ok] if fix is not None else [None] * meas.E
    cols["status"] = ["fix" if not st else _status_text(st, int(n)) for st, n in zip(fix.status, meas.n_used, strict=True)] \
        if fix is not None and fix.status is not None else ["fix"] * meas.E  # fmt: skip
    fde = res.fde
    if fde is not None:
        cols["excluded"] = [
            " ".join(meas.labels[k] for k in np.flatnonzero(row)) or None for row in fde.excluded
        ]
        cols["test_statistic"] = _cells(fde.statistic)
        cols["test_threshold"] = _cells(fde.threshold)
        cols["integrity"] = [None if not (t == t) or not (s == s) else bool(not a)
                             for t, s, a in zip(fde.threshold.tolist(), fde.statistic.tolist(), fde.alarm.tolist(), strict=True)]  # fmt: skip
    if cfg.full_covariance:
        P = full(fix.covariance if fix else None, (4, 4))
        names = ("x", "y", "z", "clock")
        scale = (L, L, L, Tf / C_M_PER_S)
        unit = (lu, lu, lu, tu)
        for i in range(4):
            for j in range(i, 4):
                u = f"{unit[i]}2" if unit[i] == unit[j] else f"{unit[i]}_{unit[j]}"
                cols[f"cov_{names[i]}_{names[j]}_{u}"] = _cells(P[:, i, j] * scale[i] * scale[j])
    tr = res.track
    if tr is not None:
        cols["track_mode"] = list(tr.mode)
        cols[f"track_clock_offset_{tu}"] = _cells(tr.bias[0] / C_M_PER_S * Tf)
        cols[f"track_sd_clock_offset_{tu}"] = _cells(np.sqrt(tr.var[0]) / C_M_PER_S * Tf)
        cols["track_gain"] = _cells(tr.gain[0])
        tp = tr.position[0]
        tlat, tlon, talt = ecef_to_geodetic(tp, strict=False)
        for j, a in enumerate("xyz"):
            cols[f"track_{a}_{lu}"] = _cells(tp[:, j] * L)
        cols["track_latitude_deg"], cols["track_longitude_deg"] = _cells(tlat), _cells(tlon)
        cols[f"track_altitude_{lu}"] = _cells(talt * L)
        tsd = np.sqrt(np.maximum(np.diagonal(tr.position_cov[0], axis1=-2, axis2=-1), 0.0))
        for j, a in enumerate("xyz"):
            cols[f"track_sd_{a}_{lu}"] = _cells(tsd[:, j] * L)
    names = tuple(cols)
    rows = list(zip(*(cols[c] for c in names), strict=True))
    return Table(columns=names, rows=rows, meta=_meta(meas, cfg, res, lu, tu, residual_unit))


def _residual_table(
    meas: Measurements, cfg: SolveConfig, res: SolveResult, epoch_cols: dict[str, list[Any]],
    residual_unit: str, to_res: float,
) -> Table:  # fmt: skip
    rec = meas.record
    order = np.argsort(meas.row, axis=None, kind="stable")
    flat = meas.row.ravel()[order]
    keep = order[flat >= 0]
    e_idx, k_idx = np.unravel_index(keep, meas.row.shape)
    rows_rec = meas.row[e_idx, k_idx]
    resid = np.full(meas.row.shape, np.nan)
    norm = np.full(meas.row.shape, np.nan)
    if res.fix is not None:
        ok = res.fix_epochs[res.fix.ok]
        resid[ok] = res.fix.residuals[res.fix.ok]
        norm[ok] = res.fix.normalised[res.fix.ok]
        if res.fde is not None and res.fde.excluded.any():  # an excluded measurement against the final fix
            S = meas.receivers
            if cfg.earth_rotation:
                S = rotate_for_flight(S, np.where(np.isfinite(res.fix.position), res.fix.position, 0.0))
            rng = np.linalg.norm(res.fix.position[:, None, :] - S, axis=-1)
            ex = res.fde.excluded & res.fix.ok[:, None]
            resid[ex] = (meas.rho - rng - res.fix.bias[:, None])[ex]
            if meas.sigma is not None:
                norm[ex] = resid[ex] / meas.sigma[ex]
    cols: dict[str, list[Any]] = {"line": rec.lines[rows_rec].tolist()}
    cols["epoch"] = [epoch_cols["epoch"][e] for e in e_idx]
    if "time_s" in epoch_cols:
        cols["time_s"] = [epoch_cols["time_s"][e] for e in e_idx]
    cols["receiver"] = [meas.labels[k] for k in k_idx]
    cols["measured"] = meas.used[e_idx, k_idx].tolist()
    if res.fde is not None:
        cols["excluded"] = res.fde.excluded[e_idx, k_idx].tolist()
    cols[f"residual_{residual_unit}"] = _cells(resid[e_idx, k_idx] * to_res)
    if meas.sigma is not None:
        cols[f"sigma_{residual_unit}"] = _cells(meas.sigma[e_idx, k_idx] * to_res)
        cols["normalised_residual"] = _cells(norm[e_idx, k_idx])
    if res.track is not None:
        tr = res.track
        p = tr.position[0][e_idx]
        rng = np.linalg.norm(p - meas.receivers[e_idx, k_idx], axis=-1)
        tres = meas.rho[e_idx, k_idx] - rng - tr.bias[0][e_idx]
        cols[f"track_residual_{residual_unit}"] = _cells(tres * to_res)
    names = tuple(cols)
    rows = list(zip(*(cols[c] for c in names), strict=True))
    return Table(columns=names, rows=rows, meta=_meta(meas, cfg, res, *_units(cfg)[1::2], residual_unit))


def _meta(
    meas: Measurements, cfg: SolveConfig, res: SolveResult, lu: str, tu: str, residual_unit: str
) -> dict[str, Any]:
    rec = meas.record
    extra: dict[str, Any] = {}
    if meas.receivers_file is not None:
        extra.update(meas.receivers_file.provenance())
    track: dict[str, Any] | None = None
    if res.track is not None:
        modes = res.track.mode
        track = {
            "estimator": "ATC-10 section 4.5 (eqs 4.5.3-4.5.5, 4.5.16-4.5.28), rows whitened by 1/sigma",
            "clock_model": "sigma1 = sigma2 = sigma0, rho = 1 (eq 4.3.1), one step per epoch of the grid",
            "sigma0_ns": cfg.sigma0,
            "gain": cfg.gain,
            "after_outage": "reinit" if cfg.reinit_after_outage else "continue",
            "linearisations_per_epoch": cfg.relinearise + 1,
            "steps": "epoch numbers" if rec.has("epoch") else "uniform grid of the times",
            "period_s": res.period,
            "missing_steps": int(np.sum(np.diff(res.steps) - 1))
            if res.steps is not None and len(res.steps) > 1
            else 0,
            "modes": {m: modes.count(m) for m in MODES if modes.count(m)},
        }
    return make_meta(
        "track-sat solve",
        **rec.provenance(),
        **extra,
        measurement=meas.kind,
        toa_origin=(cfg.toa_origin if meas.kind == "toa" else None),
        reading=_reading(meas, cfg),
        clock_offset=f"tau - t: the emission time minus the epoch's nominal time t ({_tref_text(meas, cfg)}); "
        "the transmitter's clock error is its negative",
        speed_of_light_m_s=C_M_PER_S,
        units={"length": lu, "time": tu, "residual": residual_unit, "system": cfg.units},
        sigma=meas.sigma_source,
        covariance={
            "known": "(H'WH)^-1 with W = 1/sigma^2 (sigma known), not scaled",
            "epoch": "(H'WH)^-1 scaled by each epoch's a-posteriori variance factor r'Wr/(K - 4) (an epoch with 4 "
            "receivers: the pooled factor of the others)",
            "pooled": "(H'WH)^-1 scaled by the pooled a-posteriori variance factor sum r'Wr / sum (K - 4)",
        }[res.covariance],
        variance_factor=(
            float(res.fix.variance_factor[0]) if res.fix is not None and res.covariance == "pooled" else None
        ),
        solver="weighted least squares, Gauss-Newton by thin QR, step < 1e-6 m, each epoch on its own; an epoch "
        "that does not converge is restarted from the nearest converged epoch's fix",
        start=(
            list(cfg.start)
            if cfg.start is not None
            else "closed form (Bancroft 1985, both roots refined, the lower chi-square kept; for receivers nearly "
            f"in one plane the planar closed form above the plane); where it fails the receivers' centroid "
            f"{START_ALT_M:g} m above the WGS-84 ellipsoid"
        ),
        earth_rotation=(
            "the anchors rotated about z by omega_E * range / c (the Earth's rotation during the signal's flight; "
            "positions given at the transmission)"
            if cfg.earth_rotation
            else "not corrected (anchor positions taken in the frame of the reception)"
        ),
        propagation="straight line at c: ionosphere, troposphere, satellite clocks and ephemerides are the "
        "user's corrections, applied before",
        fault_exclusion=_fde_meta(res, cfg),
        max_iter=cfg.max_iter,
        fixes=(
            None
            if res.fix is None
            else {
                "epochs": len(res.fix_epochs),
                "with_a_fix": int(np.sum(res.fix.ok)),
                "no_fix": {
                    r: int(np.sum(res.fix.status == r)) for r in NO_FIX if np.any(res.fix.status == r)
                },
                "not_converged": int(np.sum(res.fix.status == "no convergence")),
                "restarted_from_a_neighbour": int(np.sum(res.fix.retried)),
                "mirror_image_taken": int(np.sum(res.fix.mirrored)),
                "side": "the starting point's side of the receivers' plane (for a nearly planar network the "
                "fix's mirror image in the plane is tried too)",
            }
        ),
        dop="unweighted: GDOP = sqrt(tr G), G = (H'H)^-1, H = [u' 1]; HDOP, VDOP in the local ENU frame; the "
        "report's GDOP k (eq 4.1.2) is the PDOP",
        earth="WGS-84 (latitude, longitude, altitude above the ellipsoid)",
        epochs=meas.E,
        receivers_seen=meas.K,
        clock=cfg.clock,
        track=track,
        view=cfg.view,
    )


def _fde_meta(res: SolveResult, cfg: SolveConfig) -> dict[str, Any] | str:
    fde = res.fde
    if fde is None or res.meas.sigma is None:
        return "off: the chi-square test needs the measurements' sigma"
    if not cfg.fde:
        return "off (--no-fde): the test statistic and threshold are reported, nothing is excluded"
    ex = fde.excluded
    counts = {res.meas.labels[k]: int(ex[:, k].sum()) for k in np.flatnonzero(ex.any(axis=0))}
    return {
        "test": "chi-square of the weighted residuals r'Wr against its (1 - p_fa) quantile with K - 4 degrees of "
        "freedom (Parkinson & Axelrad 1988; Brown 1992); epochs with 4 receivers are not tested",
        "exclusion": "the receiver with the largest standardised residual |r|/(sigma sqrt(1 - h)), then solved "
        "again, while at least 5 receivers remain",
        "p_fa": fde.p_fa,
        "epochs_tested": int(np.isfinite(fde.first_threshold).sum()),
        "epochs_alarmed": int(np.sum(fde.first_statistic > fde.first_threshold)),
        "epochs_with_exclusions": int(ex.any(axis=1).sum()),
        "receivers_excluded": int(ex.sum()),
        "excluded_by_receiver": counts,
        "epochs_failing_after_exclusion": int(fde.alarm.sum()),
    }


def _reading(meas: Measurements, cfg: SolveConfig) -> dict[str, Any]:
    """How the measurements were converted (metadata): exact decimal differences, then float64."""
    rec = meas.record
    out: dict[str, Any] = {
        "arithmetic": "exact decimals from the cells' text (times, TOAs, pseudoranges, with their units); only "
        "differences are rounded to float64",
    }
    if meas.first_time is not None:
        out["first_epoch_time_s"] = meas.first_time + (
            " after the first timestamp" if rec.time_origin is not None else ""
        )
    if meas.kind == "toa":
        out["toa_minus"] = (
            "its epoch's time (column "
            f"{rec.columns['time']!r}): the offsets tau - t are exact before rounding"
            if meas.time is not None and cfg.toa_origin == "time"
            else "nothing: each TOA is measured from its epoch's time"
        )
    return out


def _tref_text(meas: Measurements, cfg: SolveConfig) -> str:
    if meas.kind == "tdoa":
        return "the arrival at the epoch's reference receiver (tdoa 0): the offset is minus the reference's range / c"
    if meas.kind == "pseudorange":
        return "the pseudoranges' own reference: rho = c(T - t)"
    if meas.time is not None and cfg.toa_origin == "time":
        return "the record's time column; the TOAs share its time frame"
    return "0: each TOA is measured from its epoch's time"


def _summary(
    meas: Measurements, res: SolveResult, residual_unit: str, to_res: float, Tf: float, tu: str
) -> str:
    parts = [f"track-sat solve: {meas.E} epoch(s), {meas.K} receiver(s)"]
    fix = res.fix
    if fix is not None:
        ok = fix.ok
        n_ok, n_all = int(ok.sum()), len(res.fix_epochs)
        if n_ok:
            parts.append(
                f"{n_ok} snapshot fix(es): median PDOP {float(np.median(fix.pdop[ok])):.3g}, median RMS "
                f"residual {float(np.median(fix.rms_residual[ok])) * to_res:.4g} {residual_unit}"
            )
        elif fix.status is not None and np.all(fix.status == "no convergence"):
            parts.append(f"no snapshot fix: none of {n_all} epoch(s) converged")
        if n_ok < n_all:
            parts.append(f"{n_all - n_ok} epoch(s) without a fix (status column)")
        if res.fde is not None and res.fde.excluded.any():
            ex = res.fde.excluded
            parts.append(
                f"{int(ex.sum())} measurement(s) excluded as faulty in {int(ex.any(axis=1).sum())} epoch(s)"
            )
    tr = res.track
    if tr is not None:
        sd = np.sqrt(tr.var[0, -1]) / C_M_PER_S * Tf
        counts = ", ".join(f"{tr.mode.count(m)} {m}" for m in MODES if tr.mode.count(m))
        parts.append(f"clock track: last sd {sd:.4g} {tu} ({counts})")
    return "; ".join(parts)
