"""Users' measurement records: the one format every reading command accepts.

A record is a table (:func:`motionsig_cli.tables.read_table`): CSV with optional leading ``# key: value``
metadata lines (values JSON), or the JSON document the commands write. A command declares the *roles* it
reads (:class:`Role`: ``time``, ``x``, ``y``, ``range``, ``bearing``, ``scan``, ``sensor``, …) in a
:class:`RecordSpec`; :func:`read_record` finds each role's column, converts it, and checks it.

- **Columns.** A role is found under its own name or one of its aliases (case-insensitive; ``time`` also
  as ``t`` or ``timestamp``), or where the user maps it: ``--columns time=timestamp,x=east,y=north``
  (:func:`parse_columns`). Two columns that could both be a role are refused (map one).
- **Units.** Every physical role has an SI unit (metres, radians, seconds) into which it is converted. A
  file states another unit in the header (``range [km]``, ``bearing (deg)``), in the column's name
  (``range_nm``, ``bearing_deg``, ``altitude_ft``, ``speed_kt``: the text after the last ``_`` is a
  known unit of the role's quantity and the text before it a name or alias of the role), in the
  metadata (``# units: {"bearing": "deg"}``, or the older ``# bearing_unit: "deg"``), or the user does
  (``--units bearing=deg``, :func:`parse_units`), in that order of precedence: option, header, name
  suffix, metadata. :data:`UNITS` lists the known units (looked up case-insensitively where that is
  unambiguous: :func:`canonical_unit`). A column named with a suffix is found as its role (and
  ``--columns range=range_nm`` still reads the unit from the suffix), but a column whose name is a
  role's own name or alias is never read as another role's suffix form, and a record with both
  ``range`` and ``range_nm`` is refused as ambiguous, like any two columns that could both be a role.
- **Times** are seconds (any unit above) or ISO 8601 timestamps (``2026-05-01T12:00:00.250Z``), read
  relative to the first one (recorded as :attr:`Record.time_origin`); naive and zoned timestamps are
  not mixed. A time role is finite and increasing (or non-decreasing, where several rows share a scan).
- **Missing values.** An empty cell, ``nan``, ``NA``, ``null`` (or JSON ``null``) in a role that allows
  it becomes NaN: the commands make such a step predict-only. Where a role does not allow it the value
  is refused, naming the file, line and column.
- **Limits.** A record longer than the command's row limit is refused while it is read, before it is
  held in memory.

Every failure raises :class:`~motionsig_cli.errors.InputError` with ``file:line: column 'name': …``; a
bad ``--columns`` or ``--units`` text is a :class:`~motionsig_cli.config.ConfigError` naming the option.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from datetime import datetime
from pathlib import Path
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError, integer, one_of
from motionsig_cli.errors import InputError
from motionsig_cli.tables import (
    MAX_BYTES,
    MAX_ROWS,
    Table,
    all_decimal,
    is_decimal,
    iter_table,
    name_list,
    read_table,
    shorten,
)

__all__ = [
    "KINDS",
    "MISSING",
    "QUANTITIES",
    "UNITS",
    "Record",
    "RecordSpec",
    "Role",
    "canonical_unit",
    "fit_period",
    "grid_period",
    "parse_columns",
    "parse_units",
    "read_record",
    "read_record_in_pieces",
    "uniform_grid",
]

UNITS: dict[str, dict[str, float]] = {
    "length": {
        "m": 1.0,
        "km": 1e3,
        "cm": 1e-2,
        "mm": 1e-3,
        "ft": 0.3048,
        "kft": 304.8,
        "nmi": 1852.0,
        "NM": 1852.0,
        "nm": 1852.0,
        "mi": 1609.344,
    },
    "angle": {
        "rad": 1.0,
        "mrad": 1e-3,
        "deg": math.pi / 180.0,
        "degree": math.pi / 180.0,
        "degrees": math.pi / 180.0,
        "°": math.pi / 180.0,
    },
    "time": {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "ns": 1e-9, "min": 60.0, "h": 3600.0},
    "speed": {
        "m/s": 1.0,
        "km/h": 1 / 3.6,
        "kn": 1852.0 / 3600.0,
        "kt": 1852.0 / 3600.0,
        "kts": 1852.0 / 3600.0,
        "knot": 1852.0 / 3600.0,
        "knots": 1852.0 / 3600.0,
        "ft/s": 0.3048,
        "ft/min": 0.3048 / 60.0,
        "fpm": 0.3048 / 60.0,
    },
    "variance_length": {"m2": 1.0, "km2": 1e6},
}
"""Known units per quantity, as the factor to the SI unit (the first of each).

Lengths include the nautical mile as aviation writes it: ``nmi``, ``NM`` and ``nm`` are all 1852 m.
Nanometres are not a unit any position sensor read here reports, so ``nm`` is the nautical mile, not
10⁻⁹ m. Speeds include knots (``kn``, ``kt``, ``kts``, ``knot``, ``knots``) and vertical rates in
feet per minute (``ft/min``, ``fpm``). A unit is looked up exactly, else case-insensitively where that
matches exactly one factor (``Deg``, ``KT``, ``Nm``: :func:`canonical_unit`)."""
QUANTITIES = tuple(UNITS)
TIME_ZONE_LABELS = frozenset({"utc", "gmt", "z", "local", "tai", "gps"})
"""Header annotations of a time column that name its time scale or zone, not a unit (``Time (UTC)``)."""
KINDS = ("number", "integer", "time", "label")
"""How a role's cells are read: a float (SI), an integer, a time (seconds or ISO 8601), or a label."""
MISSING = frozenset({"", "nan", "na", "n/a", "null", "none", "-"})
"""Cell texts (lower case) that mean "no measurement"."""
ORDERS = (None, "increasing", "non-decreasing")
MAX_ABS_TIME_S = 1e12
"""Largest time accepted [s] (31,700 years, after unit conversion): a larger one is an absurd value, refused
as a cell error before any arithmetic on it overflows."""
_HEADER_UNIT = re.compile(r"^(.*?)\s*[\[(]\s*([^\])]+?)\s*[\])]$")


def canonical_unit(quantity: str, text: str) -> str | None:
    """The key of :data:`UNITS` [``quantity``] that ``text`` names, or None.

    An exact match first; else a case-insensitive one, where every unit that matches has one factor
    (``Deg`` → ``deg``, ``KT`` → ``kt``, ``Nm`` → ``NM``: ``NM`` and ``nm`` are both the nautical mile);
    a text that matches units of different factors, or none, is not a unit.

    Examples:
        >>> from motionsig_cli.records import canonical_unit
        >>> canonical_unit("speed", "KTS"), canonical_unit("angle", "Deg"), canonical_unit("length", "parsec")
        ('kts', 'deg', None)
    """
    known = UNITS[quantity]
    text = str(text).strip()
    if text in known:
        return text
    hits = [k for k in known if k.casefold() == text.casefold()]
    if hits and len({known[k] for k in hits}) == 1:
        return hits[0]
    return None


@dataclass(frozen=True)
class Role:
    """A quantity a command reads from a record.

    Attributes:
        name: The role's name (what ``--columns`` maps: ``time``, ``x``, ``range``…).
        aliases: Other column names that are this role (matched case-insensitively, like the name).
        kind: One of :data:`KINDS`.
        quantity: For numbers and times: one of :data:`QUANTITIES` (converted to its SI unit); None for
            a dimensionless number.
        unit: The unit assumed when the file and the user state none (the SI unit by default).
        required: The record must have it.
        missing: Missing cells are allowed (NaN; integers and labels never).
        order: For times (and integers such as scans): None, ``"increasing"`` or ``"non-decreasing"``.
        help: One line for the documentation and the error messages.

    Raises:
        ConfigError: naming the first bad field.

    Examples:
        >>> from motionsig_cli import Role
        >>> Role("y", ("position", "z"), quantity="length", missing=True).aliases
        ('position', 'z')
    """

    name: str
    aliases: tuple[str, ...] = ()
    kind: str = "number"
    quantity: str | None = None
    unit: str | None = None
    required: bool = True
    missing: bool = False
    order: str | None = None
    help: str = ""

    def __post_init__(self) -> None:
        if not re.fullmatch(r"[a-z][a-z0-9_]*", self.name):
            raise ConfigError("name", self.name, "is not a lower-case identifier")
        one_of("kind", self.kind, KINDS)
        if self.quantity is not None:
            one_of("quantity", self.quantity, QUANTITIES)
            if self.unit is not None:
                one_of("unit", self.unit, tuple(UNITS[self.quantity]))
        elif self.unit is not None:
            raise ConfigError("unit", self.unit, "is given for a role without a quantity")
        if self.kind == "time" and self.quantity not in (None, "time"):
            raise ConfigError("quantity", self.quantity, "of a time role must be 'time'")
        if self.missing and self.kind in ("integer", "label", "time"):
            raise ConfigError("missing", self.missing, f"cells cannot be missing in a {self.kind} role")
        one_of("order", self.order, ORDERS)

    @property
    def names(self) -> tuple[str, ...]:
        """The column names that are this role, lower case."""
        return tuple(dict.fromkeys(n.lower() for n in (self.name, *self.aliases)))

    @property
    def si_unit(self) -> str | None:
        q = "time" if self.kind == "time" else self.quantity
        return None if q is None else next(iter(UNITS[q]))


@dataclass(frozen=True)
class RecordSpec:
    """What a command reads: its roles, and the most rows it accepts.

    Attributes:
        roles: The roles, in the order of the documentation.
        max_rows: Row limit (a longer record is refused while it is read).
        what: What a record is, for messages (``"record"``, ``"detections"``…).
        hint: A hint appended to "missing column" errors.
        columns_option: The option that maps this record's columns (named in errors).

    Examples:
        >>> from motionsig_cli import RecordSpec, Role
        >>> spec = RecordSpec((Role("time", ("t",), kind="time"), Role("x", quantity="length")), max_rows=1000)
        >>> [r.name for r in spec.roles]
        ['time', 'x']
    """

    roles: tuple[Role, ...]
    max_rows: int = MAX_ROWS
    what: str = "record"
    hint: str = ""
    columns_option: str = "--columns"

    def __post_init__(self) -> None:
        if not self.roles:
            raise ConfigError("roles", self.roles, "holds no role")
        names = [r.name for r in self.roles]
        if len(set(names)) != len(names):
            raise ConfigError("roles", names, "repeat a name")
        integer("max_rows", self.max_rows, 1)

    def role(self, name: str) -> Role:
        for r in self.roles:
            if r.name == name:
                return r
        raise ConfigError("role", name, f"is not one of {', '.join(r.name for r in self.roles)}")


@dataclass(frozen=True)
class Record:
    """A record read for a command.

    Attributes:
        values: Role name → values: floats in SI units for numbers and times (NaN: missing), int64 for
            integers, str objects for labels. Only the roles the record has.
        lines: (N,) the 1-based line of each row in the file (for messages).
        columns: Role name → the column it was read from.
        units: Role name → the unit the column was read in.
        time_origin: The first timestamp (ISO 8601) when times were timestamps, else None.
        extra: Columns of the file that no role took.
        meta: The file's metadata.
        source: The file's name (``<stdin>`` for standard input).
        header_line: The line of the header (0 when unknown).
    """

    values: dict[str, np.ndarray]
    lines: np.ndarray
    columns: dict[str, str]
    units: dict[str, str]
    time_origin: str | None
    extra: tuple[str, ...]
    meta: dict[str, Any]
    source: str
    header_line: int = 0
    table: Table | None = field(default=None, repr=False, compare=False)

    def __len__(self) -> int:
        return int(self.lines.size)

    def has(self, role: str) -> bool:
        return role in self.values

    def __getitem__(self, role: str) -> np.ndarray:
        if role not in self.values:
            raise InputError(f"{self.source}: no {role!r} column")
        return self.values[role]

    def where(self, i: int | None, role: str | None = None) -> str:
        """``file:line: column 'name'`` of row ``i`` (None: the header) and role."""
        line = self.header_line if i is None else int(self.lines[i])
        at = f"{self.source}:{line}" if line else self.source
        return at + (f": column {self.columns.get(role, role)!r}" if role is not None else "")

    def error(self, i: int | None, role: str | None, message: str) -> InputError:
        """An :class:`InputError` ``file:line: column 'name': message``."""
        return InputError(f"{self.where(i, role)}: {message}")

    def provenance(self) -> dict[str, Any]:
        """What was read, for output metadata: file, columns per role, units, time origin."""
        out: dict[str, Any] = {"input": self.source, "input_columns": dict(self.columns)}
        if self.extra:
            out["input_ignored_columns"] = list(self.extra)
        if self.units:
            out["input_units"] = dict(self.units)
        if self.time_origin is not None:
            out["time_origin"] = self.time_origin
        return out


def parse_columns(text: str | Mapping[str, str] | None, spec: RecordSpec | None = None) -> dict[str, str]:
    """``"time=timestamp,x=east"`` → ``{"time": "timestamp", "x": "east"}`` (a mapping passes through).

    Raises:
        ConfigError: naming ``columns``: an entry without ``=``, an empty name, a role given twice or
            two roles mapped to one column, or (with ``spec``) a role the command does not read.
    """
    if text is None:
        return {}
    if isinstance(text, Mapping):
        items = list(text.items())
    else:
        items = []
        for entry in (e.strip() for e in str(text).split(",")):
            if not entry:
                continue
            role, sep, name = entry.partition("=")
            if not sep:
                raise ConfigError("columns", entry, "is not role=column (e.g. time=timestamp)")
            items.append((role.strip(), name.strip()))
    out: dict[str, str] = {}
    for role, name in items:
        if not role or not name:
            raise ConfigError("columns", f"{role}={name}", "has an empty role or column name")
        if role in out:
            raise ConfigError("columns", role, "is mapped twice")
        if name in out.values():
            raise ConfigError("columns", name, "is mapped to two roles")
        if spec is not None and role not in (r.name for r in spec.roles):
            raise ConfigError(
                "columns",
                role,
                f"is not a column this command reads ({', '.join(r.name for r in spec.roles)})",
            )
        out[role] = name
    return out


def parse_units(text: str | Mapping[str, str] | None, spec: RecordSpec | None = None) -> dict[str, str]:
    """``"range=km,bearing=deg"`` → a mapping role → unit.

    Raises:
        ConfigError: naming ``units``: a malformed entry, a role given twice, (with ``spec``) a role the
            command does not read or that has no unit, or a unit not known for the role's quantity.
    """
    if text is None:
        return {}
    items = list(text.items()) if isinstance(text, Mapping) else []
    if not isinstance(text, Mapping):
        for entry in (e.strip() for e in str(text).split(",")):
            if not entry:
                continue
            role, sep, unit = entry.partition("=")
            if not sep or not role.strip() or not unit.strip():
                raise ConfigError("units", entry, "is not role=unit (e.g. bearing=deg)")
            items.append((role.strip(), unit.strip()))
    out: dict[str, str] = {}
    for role, unit in items:
        if role in out:
            raise ConfigError("units", role, "is given twice")
        if spec is not None:
            r = next((x for x in spec.roles if x.name == role), None)
            if r is None:
                raise ConfigError("units", role, f"is not a column this command reads ({_names(spec)})")
            q = "time" if r.kind == "time" else r.quantity
            if q is None:
                raise ConfigError("units", role, "has no unit")
            known = canonical_unit(q, unit)
            if known is None:
                raise ConfigError("units", f"{role}={unit}", f"is not {_a(q)} unit ({', '.join(UNITS[q])})")
            unit = known
        out[role] = unit
    return out


def _a(quantity: str) -> str:
    """``"a length"``, ``"an angle"``."""
    words = quantity.replace("_", " ")
    return ("an " if words[0] in "aeiou" else "a ") + words


def _names(spec: RecordSpec) -> str:
    return ", ".join(r.name for r in spec.roles)


def read_record(
    source: str | Path | Table,
    spec: RecordSpec,
    *,
    columns: str | Mapping[str, str] | None = None,
    units: str | Mapping[str, str] | None = None,
) -> Record:
    """Read ``source`` (a path, ``-`` for standard input, or a table already read) for ``spec``.

    Raises:
        ConfigError: a bad ``columns`` or ``units`` text (naming that field).
        InputError: a missing or ambiguous column, a bad cell, an unknown unit, a time that repeats or
            goes backwards, too many rows: ``file:line: column 'name': …``.

    Examples:
        >>> from motionsig_cli import RecordSpec, Role, read_record
        >>> from motionsig_cli.tables import Table
        >>> spec = RecordSpec((Role("time", ("t",), kind="time"), Role("x", quantity="length")))
        >>> rec = read_record(Table(columns=("t", "x [km]"), rows=[(0.0, 1.5), (1.0, 2.0)]), spec)
        >>> rec["x"].tolist()  # converted to metres
        [1500.0, 2000.0]
    """
    colmap = parse_columns(columns, spec)
    unitmap = parse_units(units, spec)
    t = source if isinstance(source, Table) else read_table(source, max_rows=spec.max_rows)
    if len(t.rows) > spec.max_rows:
        raise InputError(f"{t.source}: more than {spec.max_rows} rows (the limit for this {spec.what})")
    found = _find_columns(t, spec, colmap)
    lines = np.asarray(t.lines if len(t.lines) == len(t.rows) else range(2, len(t.rows) + 2), dtype=np.int64)
    rec = Record({}, lines, {}, {}, None, (), dict(t.meta), t.source, t.header_line, t)
    meta_units = t.meta.get("units", {})
    if not isinstance(meta_units, dict):
        raise InputError(
            f'{t.meta_where("units")}: metadata \'units\' must be a JSON object such as {{"x": "km"}}, '
            f"got {shorten(meta_units)}"
        )
    values: dict[str, np.ndarray] = {}
    used_units: dict[str, str] = {}
    origin: str | None = None
    for role in spec.roles:
        if role.name not in found:
            continue
        col = found[role.name]
        rec.columns[role.name] = col
        j = t.columns.index(col)
        cells = [row[j] for row in t.rows]
        unit = _unit(rec, role, col, unitmap, meta_units)
        if unit is not None:
            used_units[role.name] = unit
        if role.kind == "time":
            arr, origin_r = _times(rec, role, cells, unit)
            origin = origin or origin_r
        elif role.kind == "number":
            arr = _numbers(rec, role, cells)
            if unit is not None:
                q = role.quantity
                assert q is not None
                arr = arr * UNITS[q][unit]
        elif role.kind == "integer":
            arr = _integers(rec, role, cells)
        else:
            arr = _labels(rec, role, cells)
        if role.order is not None:
            _check_order(rec, role, arr)
        values[role.name] = arr
    extra = tuple(c for c in t.columns if c not in found.values())
    return Record(
        values, lines, rec.columns, used_units, origin, extra, dict(t.meta), t.source, t.header_line, t
    )


CHUNK_ROWS = 200_000
"""Rows per piece of :func:`read_record_in_pieces` (~250 MB of cells while a piece is converted)."""


def read_record_in_pieces(
    source: str | Path,
    spec: RecordSpec,
    *,
    columns: str | Mapping[str, str] | None = None,
    units: str | Mapping[str, str] | None = None,
    chunk_rows: int = CHUNK_ROWS,
    max_rows: int | None = None,
    max_bytes: int = MAX_BYTES,
    each: Callable[[Table], None] | None = None,
) -> Record:
    """:func:`read_record` of a file read ``chunk_rows`` rows at a time (:func:`~motionsig_cli.tables.iter_table`):
    each piece's cells are converted to arrays and dropped before the next piece is read, so a record of
    millions of rows costs its arrays (8 bytes a number, a shared string a label), not its text. The values
    are those :func:`read_record` gives for the whole file, to the bit: timestamps are counted from the
    file's first one (exact microseconds, as there), and a label's repeats share one string.

    Args:
        each: called with every piece's table before it is converted (checks that need the cells).
        max_rows: most rows of the whole file (default: ``spec.max_rows``).

    Raises:
        As :func:`read_record`, naming the file's line wherever the fault is.
    """
    colmap = parse_columns(columns, spec)
    unitmap = parse_units(units, spec)
    limit = spec.max_rows if max_rows is None else max_rows
    pieces: list[Record] = []
    t0: datetime | None = None
    shared: dict[str, str] = {}
    for t in iter_table(source, chunk_rows=chunk_rows, max_rows=limit, max_bytes=max_bytes):
        if each is not None:
            each(t)
        piece = read_record(t, replace(spec, max_rows=max(spec.max_rows, len(t.rows))), columns=colmap, units=unitmap)
        t.rows.clear()  # the cells are no longer needed (the arrays hold the values)
        if piece.time_origin is not None and len(piece):
            here = datetime.fromisoformat(piece.time_origin)
            if t0 is None:
                t0 = here
            elif (here.tzinfo is None) != (t0.tzinfo is None):
                raise piece.error(0, "time", "mixes timestamps with and without a time zone")
            elif here != t0:  # seconds from the file's first timestamp, exactly as read whole
                us = np.rint(piece.values["time"] * 1e6) + float((here - t0) // _MICROSECOND)
                piece.values["time"] = us / 1e6
        for name, arr in piece.values.items():
            if arr.dtype == object:
                piece.values[name] = np.array([shared.setdefault(v, v) for v in arr.tolist()], dtype=object)
        pieces.append(piece)
    first = pieces[0]
    values = {k: np.concatenate([p.values[k] for p in pieces]) for k in first.values}
    lines = np.concatenate([p.lines for p in pieces])
    table = first.table
    shell = None if table is None else Table(columns=table.columns, rows=[], meta=table.meta, lines=(),
                                             source=table.source, header_line=table.header_line,
                                             meta_lines=table.meta_lines)  # fmt: skip
    origin = None if t0 is None else t0.isoformat()
    rec = Record(values, lines, first.columns, first.units, origin, first.extra, first.meta, first.source,
                 first.header_line, shell)  # fmt: skip
    for role in spec.roles:
        if role.order is not None and role.name in values and len(pieces) > 1:
            _check_order(rec, role, values[role.name])  # across the pieces' seams too
    return rec


def _find_columns(t: Table, spec: RecordSpec, colmap: dict[str, str]) -> dict[str, str]:
    """Role → column of the table: the user's mapping first, then the names and aliases."""
    base = {c: _HEADER_UNIT.sub(r"\1", c).strip().lower() for c in t.columns}
    where = f"{t.source}:{t.header_line}" if t.header_line else t.source
    found: dict[str, str] = {}
    for role in spec.roles:
        if role.name in colmap:
            want = colmap[role.name]
            hits = [c for c in t.columns if c == want] or [c for c in t.columns if base[c] == want.lower()]
            if len(hits) > 1:
                raise InputError(
                    f"{where}: columns {shorten(hits[0], 40)} and {shorten(hits[1], 40)} could both be "
                    f"{spec.columns_option} {role.name}={want[:60]} (names differ only in letter case or "
                    "unit); name the column exactly"
                )
            if not hits:
                raise InputError(
                    f"{where}: no column {shorten(want)} for {spec.columns_option} {role.name}={want[:60]} "
                    f"(columns: {name_list(t.columns)})"
                )
            found[role.name] = hits[0]
    taken = set(found.values())
    role_names = {n for r in spec.roles for n in r.names}
    for role in spec.roles:
        if role.name in found:
            continue
        hits = [
            c
            for c in t.columns
            if c not in taken
            and (base[c] in role.names or (base[c] not in role_names and _suffix_unit(c, role) is not None))
            and not (role.kind == "label" and _HEADER_UNIT.match(c))  # a label has no unit: `track [deg]`
        ]
        if len(hits) > 1:
            raise InputError(
                f"{where}: columns {hits[0]!r} and {hits[1]!r} could both be the {role.name}; "
                f"say which with {spec.columns_option} {role.name}=NAME"
            )
        if hits:
            found[role.name] = hits[0]
            taken.add(hits[0])
        elif role.required:
            also = f" (or {', '.join(repr(a) for a in role.aliases)})" if role.aliases else ""
            hint = f"; {spec.hint}" if spec.hint else ""
            raise InputError(
                f"{where}: missing column {role.name!r}{also}: columns are {name_list(t.columns)}; "
                f"map one with {spec.columns_option} {role.name}=NAME{hint}"
            )
    return found


def _suffix_unit(col: str, role: Role) -> str | None:
    """The unit a column's name ends in, where the name is ``NAME_UNIT`` with NAME a name or alias of
    ``role`` and UNIT a unit of its quantity (``range_nm`` → ``nm``; a header ``[unit]`` is set aside);
    else None."""
    q = "time" if role.kind == "time" else role.quantity
    if q is None:
        return None
    name = _HEADER_UNIT.sub(r"\1", col).strip()
    stem, sep, suffix = name.rpartition("_")
    if not sep or not suffix or stem.lower() not in role.names or name.lower() in role.names:
        return None
    return canonical_unit(q, suffix)


def _unit(
    rec: Record, role: Role, col: str, unitmap: dict[str, str], meta_units: dict[str, Any]
) -> str | None:
    """The unit of a role's column: --units, the header's ``[unit]``, the name's suffix (``range_nm``),
    the metadata, the role's default."""
    q = "time" if role.kind == "time" else role.quantity
    if q is None:
        return None
    known = UNITS[q]
    m = _HEADER_UNIT.match(col)
    header = m.group(2) if m else None
    if header is not None and q == "time" and header.lower() in TIME_ZONE_LABELS:
        header = None  # "Time (UTC)": a time scale, not a unit (ISO stamps carry their zone)
    candidates = [
        (unitmap.get(role.name), "--units"),
        (header, "header"),
        (_suffix_unit(col, role), "column name"),
        (meta_units.get(col, meta_units.get(role.name)), "metadata 'units'"),
        (rec.meta.get(f"{role.name}_unit"), f"metadata '{role.name}_unit'"),
    ]
    for unit, origin in candidates:
        if unit is None:
            continue
        canonical = canonical_unit(q, str(unit))
        if canonical is None:
            where = rec.where(None, role.name) if origin == "header" else rec.source
            if origin.startswith("metadata") and rec.table is not None:
                where = rec.table.meta_where("units" if origin == "metadata 'units'" else f"{role.name}_unit")
            raise InputError(
                f"{where}: unknown {q.replace('_', ' ')} unit {shorten(unit)} in the {origin} "
                f"(known: {', '.join(known)})"
            )
        return canonical
    return role.unit or next(iter(known))


def _numbers(rec: Record, role: Role, cells: Sequence[Any]) -> np.ndarray:
    """Floats; missing texts → NaN where allowed; everything else must be a finite ASCII decimal number
    (``1_0`` and non-ASCII digits, which :func:`float` reads, are not numbers here)."""
    if all_decimal(cells):
        try:
            arr = np.asarray(cells, dtype=np.float64)  # fast path: every cell a number
            if np.all(np.isfinite(arr)):
                return arr
        except (TypeError, ValueError):
            pass
    out = np.empty(len(cells))
    for i, v in enumerate(cells):
        if isinstance(v, str) and v.strip().lower() in MISSING:
            if not role.missing:
                raise rec.error(i, role.name, f"missing value ({role.name} cannot be skipped here)")
            out[i] = math.nan
            continue
        try:
            if isinstance(v, str) and not is_decimal(v):
                raise ValueError
            x = float(v)
        except (TypeError, ValueError):
            raise rec.error(i, role.name, f"{shorten(v)} is not a number") from None
        if not math.isfinite(x):
            raise rec.error(i, role.name, f"{shorten(v)} is not finite")
        out[i] = x
    return out


def _check_magnitude(rec: Record, role: Role, cells: Sequence[Any], arr: np.ndarray, limit: float) -> None:
    """Refuse the first time beyond ±``limit`` seconds as a cell error."""
    with np.errstate(invalid="ignore"):
        big = np.flatnonzero(np.abs(arr) > limit)
    if big.size:
        i = int(big[0])
        what = "time" if role.kind == "time" else "value"
        raise rec.error(
            i, role.name, f"{what} {shorten(cells[i])} is beyond ±{limit:g} (SI), not a measurement"
        )


def _integers(rec: Record, role: Role, cells: Sequence[Any]) -> np.ndarray:
    out = np.empty(len(cells), dtype=np.int64)
    for i, v in enumerate(cells):
        try:
            if isinstance(v, str) and not is_decimal(v):
                raise ValueError
            x = float(v)
            if not math.isfinite(x) or x != int(x) or abs(x) > 2**53:
                raise ValueError
        except (TypeError, ValueError):
            what = "missing value" if isinstance(v, str) and v.strip().lower() in MISSING else shorten(v)
            raise rec.error(i, role.name, f"{what} is not an integer") from None
        out[i] = int(x)
    return out


def _labels(rec: Record, role: Role, cells: Sequence[Any]) -> np.ndarray:
    out = np.empty(len(cells), dtype=object)
    for i, v in enumerate(cells):
        text = str(v).strip()
        if text.lower() in MISSING:
            raise rec.error(i, role.name, "missing value")
        out[i] = text
    return out


def _times(rec: Record, role: Role, cells: Sequence[Any], unit: str | None) -> tuple[np.ndarray, str | None]:
    """Seconds: numbers (times the unit) or ISO 8601 timestamps relative to the first."""
    numeric = all_decimal(cells)
    try:
        arr = np.asarray(cells, dtype=np.float64) if numeric else np.empty(0)
    except (TypeError, ValueError):
        numeric = False
    if numeric:
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise rec.error(int(bad[0]), role.name, f"time {shorten(cells[bad[0]])} is not finite")
        seconds = arr * UNITS["time"][unit or "s"]
        _check_magnitude(rec, role, cells, seconds, MAX_ABS_TIME_S)
        return seconds, None
    texts = [str(v).strip() for v in cells]
    blank = [i for i, x in enumerate(texts) if x.lower() in MISSING]
    if blank:
        raise rec.error(blank[0], role.name, "missing time (a time cannot be skipped; leave the row out)")
    stamps: list[datetime] = []
    for i, v in enumerate(cells):
        text = str(v).strip()
        if is_decimal(text):
            raise rec.error(
                i, role.name, f"{shorten(text)} is a number among ISO 8601 timestamps (one form per column)"
            )
        if text.lower() in MISSING:
            raise rec.error(i, role.name, "missing time")
        try:
            stamps.append(datetime.fromisoformat(text))
        except ValueError:
            raise rec.error(
                i,
                role.name,
                f"{shorten(text)} is neither seconds nor an ISO 8601 time (e.g. 2026-05-01T12:00:00.5Z)",
            ) from None
        if (stamps[-1].tzinfo is None) != (stamps[0].tzinfo is None):
            raise rec.error(i, role.name, "mixes timestamps with and without a time zone")
    t0 = stamps[0]
    # exact differences in microseconds (timedelta is exact), then seconds
    us = np.array([(s - t0) // _MICROSECOND for s in stamps], dtype=np.float64)
    return us / 1e6, t0.isoformat()  # correctly rounded seconds


_MICROSECOND = datetime(2000, 1, 1, 0, 0, 0, 1) - datetime(2000, 1, 1)


def _check_order(rec: Record, role: Role, arr: np.ndarray) -> None:
    d = np.diff(arr)
    bad = d < 0 if role.order == "non-decreasing" else d <= 0
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0]) + 1
        what = "time" if role.kind == "time" else role.name
        if d[i - 1] == 0:
            raise rec.error(i, role.name, f"{what} repeats the previous row's ({_fmt(rec, role, arr[i])})")
        raise rec.error(
            i,
            role.name,
            f"{what} goes backwards ({_fmt(rec, role, arr[i])} after {_fmt(rec, role, arr[i - 1])})",
        )


def _fmt(rec: Record, role: Role, v: float) -> str:
    if role.kind == "time":
        return f"{v:.9g} s" + (" after the first timestamp" if rec.time_origin else "")
    return f"{v:g}"


GRID_TOL = 0.05
"""Default jitter tolerance of :func:`uniform_grid`: a time within 5 % of the period from its grid point
is read as on the grid (assumed; millisecond time stamps at 20 Hz are 2 % of the period)."""


def fit_period(times: np.ndarray, k: np.ndarray) -> tuple[float, float]:
    """Least-squares line ``times ≈ a + k T`` through rows at grid steps ``k``: (a, T).

    The intercept is fitted too, so the period is not pulled by the jitter of the first time stamp.
    """
    k = np.asarray(k, float)
    times = np.asarray(times, float)
    kc = k - k.mean()
    tc = times - times[0]
    T = float(np.dot(kc, tc - tc.mean()) / np.dot(kc, kc))
    return float(times[0] + tc.mean() - T * k.mean()), T


def grid_period(times: np.ndarray, rel_tol: float = GRID_TOL) -> float:
    """The period of increasing times with jitter and gaps: the coarsest grid that holds every row.

    Each spacing of consecutive rows is a whole number of periods m_i T plus jitter. From a first guess,
    m_i = round(Δ_i / T) and T = Σ m_i Δ_i / Σ m_i² (over the spacings within 2 ``rel_tol`` of m_i T) are
    iterated to a fixed point; every m_i is decided locally, so no error accumulates along a long
    record. The rows are then placed on that grid (k_i = Σ_{j<i} m_j) and a straight line
    t ≈ a + k T is fitted by least squares (:func:`fit_period`, intercept included, so the jitter of the
    first stamp does not bias T), twice, re-placing the rows on the fitted line. The first guesses are
    the median spacing δ and δ/2, δ/3, δ/4 (the median is a gap where most spacings are) and the
    spacings near the smallest one (where it is at least δ/4: a stray row between two scans must not
    make the grid fine). When only a few rows (at most 2, or 5 %) are off the median's grid, they are
    stray rows, not evidence of a finer grid: the median's estimate is returned and
    :func:`uniform_grid` refuses the first of them. Else, of the estimates that put every row within
    ``rel_tol`` of its own grid point the largest is taken (the coarsest grid: the fewest missed
    samples); where none does, the median's estimate is returned, and :func:`uniform_grid` refuses the
    row off its grid.
    """
    times = np.asarray(times, float)
    d = np.diff(times)
    delta = float(np.median(d))
    guesses = [delta / j for j in (1, 2, 3, 4)]
    small = float(np.median(d[d < 1.5 * np.min(d)]))
    if small >= delta / 4:
        guesses.append(small)
    found: list[float] = []
    estimates: list[float] = []
    for j, T in enumerate(guesses):
        for _ in range(100):
            m = np.rint(d / T)
            m[np.abs(d - m * T) > 2 * rel_tol * T] = 0.0  # a spacing off the grid does not pull the fit
            if not np.any(m > 0):
                break
            T_new = float(np.dot(m, d) / np.dot(m, m))
            if T_new == T:
                break
            T = T_new
        T = _segment_period(times, np.rint(d / T), T)  # the period within runs of consecutive samples
        k = np.concatenate([[0.0], np.cumsum(np.rint(d / T))])  # gaps counted with it
        a, T = fit_period(times, k) if np.ptp(k) > 0 else (times[0], T)
        for _ in range(2):  # re-placed on the fitted line, refitted on the rows that are on it
            k = np.rint((times - a) / T)
            on = np.abs(times - a - k * T) <= rel_tol * T
            if np.count_nonzero(on) >= 2 and np.ptp(k[on]) > 0:
                a, T = fit_period(times[on], k[on])
        k = np.rint((times - a) / T)
        estimates.append(T)
        off = np.abs(times - a - k * T) > rel_tol * T
        if j == 0 and 0 < np.count_nonzero(off) <= max(2, 0.05 * times.size):
            return T  # a few rows off the median's grid are stray rows, not a finer grid: uniform_grid refuses them
        if np.all(np.diff(k) > 0) and not np.any(off):
            found.append(T)
    return max(found) if found else estimates[0]


def uniform_grid(
    rec: Record, times: np.ndarray, T: float | None = None, *, role: str = "time", rel_tol: float = GRID_TOL
) -> tuple[np.ndarray, float]:
    """Steps of a uniform grid under increasing ``times``: (k, T) with ``times ≈ times[0] + k T``.

    T is given, or estimated by :func:`grid_period` (timestamps with jitter and records with gaps, where
    k jumps by more than one, are both read). A time further than ``rel_tol`` · T from its grid point is
    refused (non-uniform sampling), naming its line; so is T ≤ 0, and two times on one grid point.

    Returns:
        (k, T): int64 step indices starting at 0, and the period [s].
    """
    times = np.asarray(times, float)
    if times.size < 2:
        raise rec.error(None, None, f"need at least 2 times, found {times.size}")
    dt = times - times[0]
    estimated = T is None
    if T is None:
        T = grid_period(times, rel_tol)
    if not (math.isfinite(T) and T > 0):
        raise rec.error(None, role, f"sample period {T!r} is not > 0")
    k = np.rint(dt / T)
    phase = float(np.median(dt - k * T))  # the grid's offset from the first (jittered) stamp
    k = np.rint((dt - phase) / T)
    k -= k[0]
    off = np.abs(dt - phase - k * T)
    bad = np.flatnonzero(off > rel_tol * T)
    if bad.size:
        i = int(bad[0])
        raise rec.error(
            i,
            role,
            f"time {times[i]:.9g} s is {off[i] / T:.3g} periods off the {T:.6g} s grid (non-uniform sampling "
            "is not supported here: resample, or give the period)",
        )
    if estimated:
        _check_gap_counts(rec, times, k, T, role)
    same = np.flatnonzero(np.diff(k) == 0)
    if same.size:
        i = int(same[0]) + 1
        raise rec.error(
            i, role, f"time {times[i]:.9g} s falls on the same {T:.6g} s grid point as the row before"
        )
    return k.astype(np.int64), T


def _segments(times: np.ndarray, m: np.ndarray) -> tuple[float, float, int]:
    """Pooled least squares of the period over runs of consecutive samples (spacings of one period):
    (S_xy, S_xx, residual degrees of freedom) of t against the sample index within each run."""
    sxy = sxx = 0.0
    dof = 0
    start = 0
    for end in [*np.flatnonzero(m != 1).tolist(), m.size]:
        seg = times[start : end + 1]
        if seg.size >= 2:
            kc = np.arange(seg.size) - (seg.size - 1) / 2
            sxy += float(np.dot(kc, seg - seg.mean()))
            sxx += float(np.dot(kc, kc))
            dof += seg.size - 2
        start = end + 1
    return sxy, sxx, dof


def _segment_period(times: np.ndarray, m: np.ndarray, T: float) -> float:
    """The period from the runs of consecutive samples only (gaps do not pull it); T when there are none."""
    sxy, sxx, _ = _segments(times, m)
    return sxy / sxx if sxx > 0 else T


def _check_gap_counts(rec: Record, times: np.ndarray, k: np.ndarray, T: float, role: str) -> None:
    """Refuse a gap whose number of periods the times do not determine.

    The period is estimated within the runs of consecutive samples (:func:`_segments`), with standard
    error σ_T = σ_j / √S_xx (σ_j the jitter, from the residuals). A gap of duration d spans d/T periods
    known to ± d σ_T / T²; where that exceeds 1/8 of a period (a 4σ error could round to the next count)
    the count is ambiguous and the period must be given.
    """
    d, m = np.diff(times), np.diff(k)
    _, sxx, dof = _segments(times, m)
    if sxx <= 0 or dof < 1 or not np.any(m > 1):
        return
    a, T_fit = fit_period(times, k)
    sigma_j = float(np.sqrt(np.sum((times - a - k * T_fit) ** 2) / max(times.size - 2, 1)))
    sd = sigma_j / math.sqrt(sxx)
    bad = np.flatnonzero((m > 1) & (d * sd / T**2 > 0.125))
    if bad.size:
        i = int(bad[0])
        raise rec.error(
            i + 1,
            role,
            f"the {d[i]:.9g} s gap before this row is {int(m[i])} periods of {T:.9g} s, but the times give the "
            f"period only to ±{sd:.2g} s, so the gap could be {int(m[i]) - 1} or {int(m[i]) + 1} periods: give "
            "the period",
        )
