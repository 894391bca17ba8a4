"""Receivers of a multilateration system — ground stations or satellites — read from a user's table.

A receivers table is a record (:mod:`motionsig_cli.records`: CSV with optional ``# key: value`` metadata, or
the JSON the commands write; ``--columns role=name`` and ``--units role=unit`` apply). Its roles:

- ``receiver`` (aliases ``id``, ``station``, ``satellite``, ``sat``, ``name``, ``receiver_id``, ``site``):
  a label; optional for a table of one epoch (the receivers are then ``1``, ``2``, … in row order), required
  when positions change from epoch to epoch, and wherever another file names the receivers
  (``require_label``: ``track-sat solve``'s measurements name each row's receiver, and numbering the rows
  would pair them with the wrong stations);
- the position, in one of three forms:

  * ``x``, ``y``, ``z``: Earth-centred Earth-fixed (ECEF) coordinates [m unless stated];
  * ``latitude``, ``longitude`` [deg unless stated] and ``altitude`` (aliases ``alt``, ``height``, ``h``)
    [m]: geodetic coordinates on the WGS-84 ellipsoid (:mod:`motionsig_cli.geodesy`);
  * ``latitude``, ``longitude`` without an altitude, where the caller gives a sphere radius: points on a
    sphere about the Earth's centre (the report's form: sub-satellite points on one orbit radius);

  a table with both ECEF and geodetic columns is read as ECEF, and the two must agree within
  :data:`AGREE_M`;
- optionally ``epoch`` (an integer; aliases ``pulse``, ``update``, ``scan``) and/or ``time`` (seconds or
  ISO 8601) for positions that change from epoch to epoch (satellites, a moving receiver): the rows of an
  epoch are consecutive and share one time, epochs increase (:func:`epoch_groups`).

Plausibility checks (each an :class:`~motionsig_cli.errors.InputError` ``file:line: column 'name': …``):
latitudes in [−90, 90] and longitudes in [−360, 360] degrees; every ECEF position between
:data:`MIN_NORM_M` (inside the Earth: not an Earth-centred position) and :data:`MAX_NORM_M` from the
Earth's centre — a table in kilometres read as metres is caught and named ("positions look like
kilometres"); a receiver listed twice at one epoch; two receivers closer than :data:`COINCIDENT_M`
(coincident: naming both lines); fewer receivers at an epoch than the caller needs.

:func:`read_receivers` reads a table; :data:`POSITION_ROLES`, :func:`positions_from` and
:func:`check_coincident` let another record (a measurement record with the receivers' positions in its own
columns) use the same roles and checks.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from datetime import datetime
from decimal import Decimal, InvalidOperation, localcontext
from pathlib import Path
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError, integer, one_of
from motionsig_cli.errors import InputError
from motionsig_cli.geodesy import ecef_to_geodetic, geodetic_to_ecef
from motionsig_cli.records import MISSING, UNITS, Record, RecordSpec, Role, read_record
from motionsig_cli.surveillance.multilateration import ecef
from motionsig_cli.tables import MAX_ROWS, Table

__all__ = [
    "AGREE_M",
    "COINCIDENT_M",
    "FORMS",
    "ID_ROLE",
    "MAX_LON_DEG",
    "MAX_NORM_M",
    "MIN_NORM_M",
    "MULTI_EPOCH",
    "POSITION_ROLES",
    "SPEC",
    "Positions",
    "Receivers",
    "check_coincident",
    "check_unique",
    "epoch_groups",
    "exact_values",
    "positions_from",
    "read_receivers",
    "receivers_spec",
    "subset_rows",
    "time_shift",
]

MIN_NORM_M = 6.3e6
"""Smallest distance of a receiver from the Earth's centre [m]: below the lowest point of the Earth's
surface (the polar radius is 6 356 752 m; the deepest ocean floor is about 6 366 km from the centre)."""
MAX_NORM_M = 1e8
"""Largest distance of a receiver from the Earth's centre [m] (100 000 km: beyond the geosynchronous radius
of 42 164 km; assumed)."""
COINCIDENT_M = 1e-3
"""Two receivers closer than this [m] at one epoch are coincident (assumed: 1 mm)."""
AGREE_M = 1.0
"""Largest distance between a table's ECEF and geodetic columns of one receiver [m] (assumed)."""
MAX_LON_DEG = 360.0
"""Longitudes accepted: [−360, 360] degrees (both the −180..180 and the 0..360 habits)."""
FORMS = ("ecef", "geodetic", "sphere")
"""How the positions were given: ECEF x, y, z; WGS-84 latitude, longitude, altitude; latitude, longitude
on a sphere of a given radius."""
MULTI_EPOCH = ("allow", "first", "refuse")
"""What :func:`read_receivers` does with a table of several epochs: keep them, keep the first, or refuse."""

_KM_LOW, _KM_HIGH = MIN_NORM_M / 1e3, MAX_NORM_M / 1e3

POSITION_ROLES: tuple[Role, ...] = (
    Role("x", ("x_m", "ecef_x", "x_ecef"), quantity="length", required=False, help="ECEF x [m]"),
    Role("y", ("y_m", "ecef_y", "y_ecef"), quantity="length", required=False, help="ECEF y [m]"),
    Role("z", ("z_m", "ecef_z", "z_ecef"), quantity="length", required=False, help="ECEF z [m]"),
    Role("latitude", ("lat", "latitude_deg", "lat_deg"), quantity="angle", unit="deg", required=False,
         help="geodetic latitude (WGS-84) [deg]"),
    Role("longitude", ("lon", "lng", "long", "longitude_deg", "lon_deg"), quantity="angle", unit="deg",
         required=False, help="longitude [deg]"),
    Role("altitude", ("alt", "height", "h", "altitude_m", "alt_m", "height_m"), quantity="length",
         required=False, help="height above the WGS-84 ellipsoid [m]"),
)  # fmt: skip
"""The position roles of a receivers table (and of a measurement record that carries the positions)."""
ID_ROLE = Role(
    "receiver",
    ("id", "station", "satellite", "sat", "name", "receiver_id", "site"),
    kind="label",
    required=False,
    help="receiver label",
)
EPOCH_ROLE = Role(
    "epoch",
    ("pulse", "update", "scan"),
    kind="integer",
    required=False,
    order="non-decreasing",
    help="epoch number (positions that change per epoch)",
)
TIME_ROLE = Role(
    "time",
    ("t", "timestamp"),
    kind="time",
    required=False,
    help="epoch time: seconds or ISO 8601 (positions that change per epoch)",
)
"""The order of the times is checked by :func:`epoch_groups` (with an epoch column, a row whose time differs
from its epoch's is named, not the row after it)."""


def receivers_spec(max_rows: int = MAX_ROWS, columns_option: str = "--columns") -> RecordSpec:
    """The record specification of a receivers table (at most ``max_rows`` rows; ``columns_option``: the
    option that maps its columns, named in messages)."""
    return RecordSpec(
        (ID_ROLE, EPOCH_ROLE, TIME_ROLE, *POSITION_ROLES),
        max_rows=max_rows,
        what="receivers table",
        hint="a receivers table has x, y, z [m] (ECEF) or latitude, longitude [deg], altitude [m] (WGS-84)",
        columns_option=columns_option,
    )


SPEC = receivers_spec()
"""What :func:`read_receivers` reads."""


@dataclass(frozen=True)
class Positions:
    """Positions read from the rows of a record.

    Attributes:
        ecef: (N, 3) ECEF positions [m].
        form: one of :data:`FORMS`.
        lat_deg, lon_deg: (N,) latitude and longitude [deg]: as read (exact digits) for the geodetic and
            sphere forms, WGS-84 geodetic for the ECEF form.
        alt_m: (N,) height above the WGS-84 ellipsoid [m] (NaN for the sphere form).
    """

    ecef: np.ndarray
    form: str
    lat_deg: np.ndarray
    lon_deg: np.ndarray
    alt_m: np.ndarray


def _degrees(rec: Record, role: str) -> np.ndarray:
    """An angle role in degrees, exactly as written when its unit is degrees (no round trip through
    radians, so that the report's sub-satellite points keep their digits)."""
    unit = rec.units.get(role, "deg")
    t = rec.table
    if t is not None and unit == "deg":
        j = t.columns.index(rec.columns[role])
        return np.asarray([float(row[j]) for row in t.rows], dtype=float)
    return rec[role] / UNITS["angle"]["deg"]


def positions_from(
    rec: Record,
    *,
    sphere_radius_m: float | None = None,
    norm_range_m: tuple[float, float] = (MIN_NORM_M, MAX_NORM_M),
) -> Positions:
    """The positions of every row of ``rec`` (read with :data:`POSITION_ROLES`), checked.

    Args:
        rec: a record read with a specification holding :data:`POSITION_ROLES`.
        sphere_radius_m: the radius of the sphere form (latitude, longitude without an altitude); None:
            an altitude is required.
        norm_range_m: the distances from the Earth's centre accepted [m] (the sphere form is not checked:
            its radius is the caller's).

    Raises:
        InputError: a missing or incomplete set of position columns, a latitude or longitude out of range,
            a position too close to or too far from the Earth's centre (kilometres read as metres are
            named), or ECEF and geodetic columns that disagree.
    """
    has_xyz = [rec.has(r) for r in ("x", "y", "z")]
    has_geo = [rec.has(r) for r in ("latitude", "longitude")]
    cols = ", ".join(rec.table.columns) if rec.table is not None else ""
    if any(has_xyz) and not all(has_xyz):
        miss = next(r for r, h in zip(("x", "y", "z"), has_xyz, strict=True) if not h)
        raise rec.error(
            None, None, f"missing column {miss!r}: ECEF positions need x, y and z (columns: {cols})"
        )
    if any(has_geo) and not all(has_geo):
        miss = "longitude" if has_geo[0] else "latitude"
        raise rec.error(
            None,
            None,
            f"missing column {miss!r}: geodetic positions need latitude and longitude (columns: {cols})",
        )
    if not any(has_xyz) and not any(has_geo):
        raise rec.error(
            None,
            None,
            "no receiver positions: give x, y, z [m] (ECEF) or latitude, longitude [deg] and altitude [m] "
            f"(WGS-84) (columns: {cols}); map them with --columns x=NAME,... or --columns latitude=NAME,...",
        )
    geo = all(has_geo)
    lat = lon = alt = None
    if geo:
        lat, lon = _degrees(rec, "latitude"), _degrees(rec, "longitude")
        for role, v, lim in (("latitude", lat, 90.0), ("longitude", lon, MAX_LON_DEG)):
            bad = np.flatnonzero(np.abs(v) > lim)
            if bad.size:
                i = int(bad[0])
                raise rec.error(i, role, f"{role} {v[i]:g} deg is outside [{-lim:g}, {lim:g}] degrees")
    if all(has_xyz):
        xyz = np.stack([rec["x"], rec["y"], rec["z"]], axis=-1)
        _check_norms(rec, xyz, norm_range_m, "x", "positions")
        glat, glon, galt = _geodetic(xyz)
        if geo:
            if not rec.has("altitude"):
                raise rec.error(None, None, "missing column 'altitude' beside latitude and longitude")
            diff = np.linalg.norm(geodetic_to_ecef(lat, lon, rec["altitude"]) - xyz, axis=-1)
            bad = np.flatnonzero(diff > AGREE_M)
            if bad.size:
                i = int(bad[0])
                raise rec.error(
                    i,
                    "latitude",
                    f"the geodetic position is {diff[i]:.4g} m from the ECEF x, y, z of the same row "
                    f"(more than {AGREE_M:g} m): check the units, or give one form only",
                )
        return Positions(xyz, "ecef", glat, glon, galt)
    assert lat is not None and lon is not None
    if rec.has("altitude"):
        alt = rec["altitude"]
        xyz = geodetic_to_ecef(lat, lon, alt).reshape(-1, 3)
        _check_norms(rec, xyz, norm_range_m, "altitude", "altitudes")
        return Positions(xyz, "geodetic", lat, lon, alt)
    if sphere_radius_m is None:
        raise rec.error(
            None,
            None,
            f"missing column 'altitude' (or 'alt', 'height', 'h') [m] beside latitude and longitude (columns: "
            f"{cols}); map it with --columns altitude=NAME",
        )
    xyz = ecef(lat, lon, float(sphere_radius_m)).reshape(-1, 3)  # the report's spherical Earth
    return Positions(xyz, "sphere", lat, lon, np.full(len(lat), np.nan))


def _geodetic(xyz: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """WGS-84 latitude, longitude, altitude of ECEF positions (NaN near the Earth's centre, where they are
    not unique)."""
    return ecef_to_geodetic(xyz, strict=False) if len(xyz) else (np.zeros(0), np.zeros(0), np.zeros(0))


def _check_norms(
    rec: Record, xyz: np.ndarray, norm_range_m: tuple[float, float], role: str, what: str
) -> None:
    """Every position between the accepted distances from the Earth's centre; kilometres are named."""
    lo, hi = norm_range_m
    r = np.linalg.norm(xyz, axis=-1)
    bad = np.flatnonzero((r < lo) | (r > hi))
    if not bad.size:
        return
    i = int(bad[0])
    unit = rec.units.get(role, "m")
    where = "x, y, z" if role == "x" else "altitude"
    if _KM_LOW <= r[i] <= _KM_HIGH and unit == "m":
        fix = (
            "x [km] in the header, or --units x=km,y=km,z=km"
            if role == "x"
            else "altitude [km], or --units altitude=km"
        )
        raise rec.error(
            i,
            role,
            f"positions look like kilometres: |r| = {r[i]:.6g} m from the Earth's centre, but an Earth-centred "
            f"position is {lo:g} to {hi:g} m from it; state the unit of {where} ({fix})",
        )
    side = "inside the Earth" if r[i] < lo else f"beyond {hi:g} m"
    raise rec.error(
        i,
        role,
        f"|r| = {r[i]:.6g} m from the Earth's centre is {side}: {what} must be Earth-centred (ECEF x, y, z) or "
        f"WGS-84 (latitude, longitude, altitude), {lo:g} to {hi:g} m from the centre",
    )


def check_coincident(
    rec: Record, ecef: np.ndarray, group: np.ndarray, ids: np.ndarray, *, tol: float = COINCIDENT_M
) -> None:
    """No two rows of the same group (epoch) closer than ``tol`` [m].

    Raises:
        InputError: ``file:line: …`` of the later row, naming both receivers and both lines.
    """
    if len(ecef) < 2:
        return
    from scipy.spatial import cKDTree

    g = np.asarray(group, dtype=np.int64)
    pts = np.column_stack([g.astype(float) * 1e10, ecef])  # groups 1e10 m apart: never neighbours
    pairs = cKDTree(pts).query_pairs(r=tol, output_type="ndarray")
    if not len(pairs):
        return
    pairs = np.sort(pairs, axis=1)
    i, j = (int(v) for v in pairs[np.lexsort((pairs[:, 0], pairs[:, 1]))[0]])
    d = float(np.linalg.norm(ecef[i] - ecef[j]))
    role = "x" if rec.has("x") else "latitude"
    raise rec.error(
        j,
        role,
        f"receivers {ids[i]!r} (line {int(rec.lines[i])}) and {ids[j]!r} (line {int(rec.lines[j])}) coincide "
        f"({d:.3g} m apart, less than {tol:g} m): a position cannot be fixed from one place twice",
    )


@dataclass(frozen=True)
class Receivers:
    """A receivers table, by epoch (one epoch for a static table).

    Attributes:
        ids: (K,) the receivers' labels, in order of first appearance.
        ecef: (E, K, 3) ECEF positions [m]; NaN where a receiver has no position at an epoch.
        lines: (E, K) the line of each position in the file (0: none).
        epochs: (E,) the epoch numbers (the ``epoch`` column), or None.
        times: (E,) the epoch times [s] (the ``time`` column; relative to ``time_origin`` for
            timestamps), or None.
        time_origin: the first timestamp (ISO 8601) when the times were timestamps, else None.
        form: one of :data:`FORMS`.
        lat_deg, lon_deg, alt_m: (E, K) as :class:`Positions` (NaN where absent).
        record: the record read (provenance, metadata, lines).
    """

    ids: tuple[str, ...]
    ecef: np.ndarray
    lines: np.ndarray
    epochs: np.ndarray | None
    times: np.ndarray | None
    time_origin: str | None
    form: str
    lat_deg: np.ndarray
    lon_deg: np.ndarray
    alt_m: np.ndarray
    record: Record

    @property
    def K(self) -> int:
        """Number of receivers."""
        return len(self.ids)

    @property
    def E(self) -> int:
        """Number of epochs."""
        return int(self.ecef.shape[0])

    @property
    def static(self) -> bool:
        """True for a table without epochs (one set of positions for all epochs)."""
        return self.epochs is None and self.times is None

    @property
    def present(self) -> np.ndarray:
        """(E, K) whether each receiver has a position at each epoch."""
        return self.lines > 0

    @property
    def source(self) -> str:
        return self.record.source

    def index(self) -> dict[str, int]:
        """Label → column of :attr:`ecef`."""
        return {r: k for k, r in enumerate(self.ids)}

    def first(self) -> Receivers:
        """The first epoch only (the receivers present at it)."""
        keep = self.present[0]
        return Receivers(
            tuple(r for r, k in zip(self.ids, keep, strict=True) if k),
            self.ecef[:1, keep],
            self.lines[:1, keep],
            None if self.epochs is None else self.epochs[:1],
            None if self.times is None else self.times[:1],
            self.time_origin,
            self.form,
            self.lat_deg[:1, keep],
            self.lon_deg[:1, keep],
            self.alt_m[:1, keep],
            self.record,
        )

    def provenance(self) -> dict[str, Any]:
        """What was read, for output metadata."""
        out: dict[str, Any] = {
            "receivers": self.source,
            "receivers_columns": dict(self.record.columns),
            "receivers_form": {
                "ecef": "ECEF x, y, z",
                "geodetic": "WGS-84 latitude, longitude, altitude",
                "sphere": "latitude, longitude on a sphere",
            }[self.form],
            "receivers_count": self.K,
        }
        if self.record.units:
            out["receivers_units"] = dict(self.record.units)
        if not self.static:
            out["receivers_epochs"] = self.E
        if self.time_origin is not None:
            out["receivers_time_origin"] = self.time_origin
        return out


DECIMAL_DIGITS = 60
"""Precision of the decimal arithmetic of :func:`exact_values` and its callers (a cell of 30 digits times a
unit factor, minus another: exact)."""


def _cells(rec: Record, role: str) -> list[Any] | None:
    """The raw cells of a role's column (the record's table), or None when the record has no table."""
    t = rec.table
    if t is None or role not in rec.columns or rec.columns[role] not in t.columns or len(t.rows) != len(rec):
        return None
    j = t.columns.index(rec.columns[role])
    return [row[j] for row in t.rows]


def _decimal(v: Any) -> Decimal | None:
    """A cell as an exact decimal (None: missing): a text as written, an integer exactly, a float (a JSON
    number with a fraction, already float64 when parsed) by its shortest representation."""
    if isinstance(v, str):
        try:
            d = Decimal(v)  # surrounding blanks allowed, as float() allows them
        except InvalidOperation:
            text = v.strip()
            if text.lower() in MISSING:
                return None
            return Decimal(
                repr(float(text))
            )  # a form float() reads and Decimal does not (the record read it)
        return None if d.is_nan() else d
    if v is None:
        return None
    if isinstance(v, bool):
        return Decimal(int(v))
    if isinstance(v, int):
        return Decimal(v)
    return None if v != v else Decimal(repr(float(v)))


def exact_values(rec: Record, role: str, quantity: str) -> list[Decimal | None]:
    """A role's cells as exact decimals in SI units (None: missing), from the text of the record's table.

    Float64 keeps 15–17 significant digits: an absolute time of arrival such as Unix seconds with 12
    decimals (1777629600.000009523) or integer nanoseconds (1777629600000009523) loses 0.24 µs (70 m of
    range) when parsed as a float. Differences of these decimals (:func:`decimal_seconds`) are exact, and
    only they are converted to float. The unit factors of :data:`motionsig_cli.records.UNITS` are decimal
    numbers (1e-9, 0.3048, …), taken exactly. A record without its table (built in code) gives its float
    values' shortest representations.
    """
    unit = rec.units.get(role)
    factor = Decimal(repr(UNITS[quantity][unit])) if unit is not None else Decimal(1)
    cells = _cells(rec, role)
    with localcontext() as ctx:
        ctx.prec = DECIMAL_DIGITS
        if cells is None:
            return [None if v != v else Decimal(repr(float(v))) for v in rec[role].tolist()]
        out = list(map(_decimal, cells))
        if factor != 1:
            out = [None if d is None else d * factor for d in out]
    return out


def decimal_seconds(rec: Record) -> list[Decimal]:
    """The ``time`` column as exact decimal seconds: numbers from their text (:func:`exact_values`), ISO 8601
    timestamps as the record's whole microseconds after its first timestamp (exact in the record's floats
    up to 10⁹ s)."""
    if rec.time_origin is None:
        out = exact_values(rec, "time", "time")
        assert all(d is not None for d in out)  # the record refuses missing times
        return out  # type: ignore[return-value]
    return [Decimal(round(v * 1e6)).scaleb(-6) for v in rec["time"].tolist()]


def _text(rec: Record, role: str, i: int) -> str:
    """Row ``i``'s cell of a role as written, with the column's unit (for messages)."""
    cells = _cells(rec, role)
    v = cells[i] if cells is not None else None
    if v is None:
        return f"{float(rec[role][i]):.15g} s"
    text = str(v).strip()
    if role == "time" and rec.time_origin is not None:
        return text
    return f"{text} {rec.units.get(role, 's')}"


def epoch_groups(
    rec: Record, time: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
    """Epochs of a record's rows (consecutive rows with the same ``epoch``, else the same ``time``; one epoch
    without either): the epoch index (N,) of each row, the first row of each epoch, and the epochs' numbers
    and times (None without that column).

    ``time``: (N,) the rows' times to compare (default the record's ``time`` values), e.g. exact differences
    from a reference where the absolute values exceed float64's resolution. Without an epoch column the
    times do not decrease; with one, an epoch has one time — the row that differs from its epoch's common
    time (the most frequent; on a tie, its first row's) is named — and the times increase from epoch to
    epoch (:class:`InputError` otherwise, ``file:line: column 'time': …``).
    """
    n = len(rec)
    has_e, has_t = rec.has("epoch"), rec.has("time")
    if not (has_e or has_t):
        return np.zeros(n, dtype=np.int64), np.zeros(min(n, 1), dtype=np.int64), None, None
    t = (rec["time"] if time is None else np.asarray(time, float)) if has_t else None
    if t is not None and not has_e:
        back = np.flatnonzero(np.diff(t) < 0)
        if back.size:
            i = int(back[0]) + 1
            raise rec.error(
                i, "time", f"time goes backwards ({_text(rec, 'time', i)} after {_text(rec, 'time', i - 1)})"
            )
    key = rec["epoch"] if has_e else t
    assert key is not None
    start = np.flatnonzero(np.concatenate([[True], key[1:] != key[:-1]])) if n else np.zeros(0, np.int64)
    group = np.cumsum(np.concatenate([[False], key[1:] != key[:-1]])) if n else np.zeros(0, np.int64)
    times = None
    if t is not None:
        if has_e:  # one time per epoch, increasing from epoch to epoch
            bad = np.flatnonzero(t != t[start][group])
            if bad.size:
                e = int(group[bad[0]])
                rows = np.arange(int(start[e]), int(start[e + 1]) if e + 1 < len(start) else n)
                values, first, counts = np.unique(t[rows], return_index=True, return_counts=True)
                common = values[np.lexsort((first, -counts))[0]]  # most frequent, then earliest
                i = int(rows[np.flatnonzero(t[rows] != common)[0]])
                same = rows[t[rows] == common]
                c = int(same[0])
                raise rec.error(
                    i,
                    "time",
                    f"epoch {int(rec['epoch'][i])} has two times: {_text(rec, 'time', i)} here, "
                    f"{_text(rec, 'time', c)} at line {int(rec.lines[c])}"
                    + (f" and {same.size - 1} more of its rows" if same.size > 1 else "")
                    + "; the rows of an epoch share its time",
                )
            d = np.diff(t[start])
            bad = np.flatnonzero(d <= 0)
            if bad.size:
                i = int(start[bad[0] + 1])
                raise rec.error(
                    i, "time", f"epoch {int(rec['epoch'][i])} does not come later than the epoch before it"
                )
        times = t[start]
    return group.astype(np.int64), start.astype(np.int64), rec["epoch"][start] if has_e else None, times


def _labels(rec: Record, group: np.ndarray, multi: bool, option: str, require: bool) -> np.ndarray:
    if rec.has("receiver"):
        return rec["receiver"]
    if require:
        cols = ", ".join(rec.table.columns) if rec.table is not None else ", ".join(rec.columns.values())
        raise rec.error(
            None,
            None,
            f"no receiver column: map one with {option} receiver=NAME (columns: {cols}; a receiver column is "
            f"named {', '.join(ID_ROLE.names)}): the measurements name their receivers, and rows numbered "
            "1, 2, ... could pair them with the wrong positions",
        )
    if multi:
        raise rec.error(
            None,
            None,
            f"missing column 'receiver' (or {', '.join(repr(a) for a in ID_ROLE.aliases)}): positions that "
            f"change from epoch to epoch need a receiver label; map one with {option} receiver=NAME",
        )
    return np.array([str(i + 1) for i in range(len(group))], dtype=object)


def check_unique(rec: Record, group: np.ndarray, labels: np.ndarray, what: str = "receiver") -> np.ndarray:
    """Integer codes of ``labels`` (in order of first appearance); a label twice in one group (epoch) is an
    :class:`InputError` naming both lines."""
    code_of: dict[str, int] = {}
    codes = np.fromiter(
        (code_of.setdefault(v, len(code_of)) for v in labels), dtype=np.int64, count=len(labels)
    )
    key = group * max(len(code_of), 1) + codes
    order = np.argsort(key, kind="stable")
    dup = np.flatnonzero(key[order][1:] == key[order][:-1])
    if dup.size:
        pairs = np.stack([order[dup], order[dup + 1]], axis=1)
        a, b = (int(v) for v in pairs[np.argmin(pairs[:, 1])])
        role = "receiver" if rec.has("receiver") else None
        at = "" if not (rec.has("epoch") or rec.has("time")) else " at one epoch"
        raise rec.error(
            b,
            role,
            f"{what} {labels[b]!r} appears twice{at} (lines {int(rec.lines[a])} and {int(rec.lines[b])})",
        )
    return codes


def read_receivers(
    source: str | Path | Table,
    *,
    columns: str | Mapping[str, str] | None = None,
    units: str | Mapping[str, str] | None = None,
    multi_epoch: str = "allow",
    min_receivers: int = 1,
    sphere_radius_m: float | None = None,
    norm_range_m: tuple[float, float] = (MIN_NORM_M, MAX_NORM_M),
    max_rows: int = MAX_ROWS,
    require_label: bool = False,
    columns_option: str = "--columns",
) -> Receivers:
    """Read and check a receivers table (module docstring).

    Args:
        source: a path (``-``: standard input) or a table already read.
        columns, units: ``--columns`` and ``--units`` texts or mappings (roles of :data:`SPEC`).
        multi_epoch: one of :data:`MULTI_EPOCH`: keep every epoch, keep the first, or refuse a table of
            several epochs (naming the first row of the second).
        min_receivers: fewest receivers at an epoch (e.g. 3 for a position given the clock, 4 for a snapshot
            fix); fewer is an :class:`InputError` naming the epoch.
        sphere_radius_m: radius [m] of the sphere form (latitude, longitude without an altitude); None: an
            altitude is required.
        norm_range_m: accepted distances from the Earth's centre [m] (default :data:`MIN_NORM_M` to
            :data:`MAX_NORM_M`).
        max_rows: row limit.
        require_label: the table must have a receiver column (another file names the receivers: rows
            numbered 1, 2, … would be paired by position, silently, with the wrong stations).
        columns_option: the option that maps the table's columns, named in messages (``--columns``, or
            ``--receivers-columns`` where a command reads another record too).

    Raises:
        ConfigError: a bad ``columns``/``units`` text, ``multi_epoch`` or ``min_receivers``.
        InputError: a bad table (``file:line: column 'name': …``).
    """
    one_of("multi_epoch", multi_epoch, MULTI_EPOCH)
    integer("min_receivers", min_receivers, 1)
    if sphere_radius_m is not None and not (math.isfinite(sphere_radius_m) and sphere_radius_m > 0):
        raise ConfigError("sphere_radius_m", sphere_radius_m, "is not a finite number > 0")
    rec = read_record(source, receivers_spec(max_rows, columns_option), columns=columns, units=units)
    if not len(rec):
        raise InputError(f"{rec.source}: no receivers (the table has a header but no rows)")
    group, start, epochs, times = epoch_groups(rec)
    if len(start) > 1 and multi_epoch != "allow":
        if multi_epoch == "refuse":
            role = "epoch" if rec.has("epoch") else "time"
            raise rec.error(
                int(start[1]),
                role,
                f"a second epoch: this command takes one geometry, and the table has {len(start)} epochs; give "
                "the receivers of one epoch",
            )
        keep = group == 0
        rec = subset_rows(rec, keep)
        group, start = group[keep], start[:1]
        epochs = None if epochs is None else epochs[:1]
        times = None if times is None else times[:1]
    pos = positions_from(rec, sphere_radius_m=sphere_radius_m, norm_range_m=norm_range_m)
    labels = _labels(rec, group, len(start) > 1, columns_option, require_label)
    codes = check_unique(rec, group, labels)
    check_coincident(rec, pos.ecef, group, labels)
    E = len(start)
    ids = tuple(dict.fromkeys(labels.tolist()))
    K = len(ids)
    counts = np.bincount(group, minlength=E)
    few = np.flatnonzero(counts < min_receivers)
    if few.size:
        e = int(few[0])
        if E == 1:
            raise InputError(
                f"{rec.source}: {int(counts[e])} receiver(s): at least {min_receivers} are needed"
            )
        raise rec.error(
            int(start[e]),
            "epoch" if rec.has("epoch") else "time",
            f"{int(counts[e])} receiver(s) at epoch {_epoch_name(epochs, times, e)}: at least {min_receivers} "
            "are needed",
        )
    ecef = np.full((E, K, 3), np.nan)
    lines = np.zeros((E, K), dtype=np.int64)
    lat, lon, alt = (np.full((E, K), np.nan) for _ in range(3))
    ecef[group, codes] = pos.ecef
    lines[group, codes] = rec.lines
    lat[group, codes], lon[group, codes], alt[group, codes] = pos.lat_deg, pos.lon_deg, pos.alt_m
    return Receivers(ids, ecef, lines, epochs, times, rec.time_origin, pos.form, lat, lon, alt, rec)


def _epoch_name(epochs: np.ndarray | None, times: np.ndarray | None, e: int) -> str:
    if epochs is not None:
        return str(int(epochs[e]))
    assert times is not None
    return f"t = {float(times[e]):.9g} s"


def subset_rows(rec: Record, keep: np.ndarray) -> Record:
    """The rows ``keep`` (a boolean mask) of a record, with their lines and table rows."""
    values = {k: v[keep] for k, v in rec.values.items()}
    table = rec.table
    if table is not None:
        idx = np.flatnonzero(keep)
        table = Table(table.columns, [table.rows[i] for i in idx], table.meta,
                      tuple(table.lines[i] for i in idx) if len(table.lines) == len(table.rows) else (),
                      table.source, table.header_line)  # fmt: skip
    return Record(values, rec.lines[keep], rec.columns, rec.units, rec.time_origin, rec.extra, rec.meta,
                  rec.source, rec.header_line, table)  # fmt: skip


def time_shift(origin_from: str | None, origin_to: str | None) -> float:
    """Seconds to add to times relative to ``origin_from`` to make them relative to ``origin_to`` (two
    ISO 8601 timestamps; 0 when either is None: times in seconds share their origin).

    Raises:
        ValueError: one timestamp with and one without a time zone.
    """
    if origin_from is None or origin_to is None:
        return 0.0
    a, b = datetime.fromisoformat(origin_from), datetime.fromisoformat(origin_to)
    if (a.tzinfo is None) != (b.tzinfo is None):
        raise ValueError("one file's timestamps have a time zone and the other's do not")
    return (a - b).total_seconds()
