"""Tables: CSV with ``# key: value`` provenance lines, JSON, and a reader with file:line errors.

Every command emits a :class:`Table`. As CSV it is::

    # command: "encode gold"
    # motionsig_version: "0.1.0"
    # poly1: "45"
    code,chip,value
    gold_k0_a0,0,1
    ...

Metadata values are JSON (strings quoted), so a reader gets back exactly the types that were
written; pandas reads the file with ``pd.read_csv(path, comment="#")``. As JSON the same table is
``{"meta": {...}, "columns": [...], "data": [{column: value}, ...]}``.

Writing files (atomically) and standard streams is the command layer's job (:mod:`motionsig_cli.cli.io`).
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from motionsig_cli import __version__
from motionsig_cli.errors import InputError  # re-exported: the table readers raise it

__all__ = ["FORMATS", "InputError", "Table", "make_meta", "read_table", "render"]

FORMATS = ("csv", "json")


@dataclass(frozen=True)
class Table:
    """A rectangular result with provenance.

    Attributes:
        columns: Column names, in order.
        rows: One sequence of values per row (str, int, float or bool).
        meta: Provenance: command, every resolved parameter, convention, seed, version.
        lines: For tables read from a file, the 1-based source line of each row (for errors).
        source: For tables read from a file, its name (``<stdin>`` for ``-``).
    """

    columns: tuple[str, ...]
    rows: list[tuple[Any, ...]]
    meta: dict[str, Any] = field(default_factory=dict)
    lines: tuple[int, ...] = ()
    source: str = ""

    def column(self, name: str) -> list[Any]:
        """The raw values of one column (raises :class:`InputError` naming the file if absent)."""
        if name not in self.columns:
            where = f"{self.source}: " if self.source else ""
            raise InputError(f"{where}missing column {name!r} (columns: {', '.join(self.columns)})")
        j = self.columns.index(name)
        return [row[j] for row in self.rows]

    def numeric(self, name: str, *, integer: bool = False) -> np.ndarray:
        """One column as a float (or int) array; a non-numeric cell is reported as ``file:line``."""
        values = self.column(name)
        out = np.empty(len(values), dtype=np.int64 if integer else np.float64)
        for i, v in enumerate(values):
            try:
                x = float(v)
                if integer:
                    if not math.isfinite(x) or x != int(x):
                        raise ValueError
                    out[i] = int(x)
                else:
                    out[i] = x
            except (TypeError, ValueError, OverflowError):
                kind = "an integer" if integer else "a number"
                line = self.lines[i] if i < len(self.lines) else i + 2
                raise InputError(f"{self.source}:{line}: column {name!r}: {v!r} is not {kind}") from None
        return out


def make_meta(command: str, **params: Any) -> dict[str, Any]:
    """Provenance block: command, version, then every resolved parameter in the given order."""
    meta: dict[str, Any] = {"command": command, "motionsig_version": __version__}
    meta.update({k: _plain(v) for k, v in params.items()})
    return meta


def _plain(value: Any) -> Any:
    """JSON-friendly version of a value: tuples → lists, numpy scalars → Python, NaN/±inf → None
    (strict JSON has no non-finite numbers)."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, Path):
        return str(value)
    return value


def _cell(value: Any) -> Any:
    """Full-precision, locale-free text for a CSV cell."""
    if isinstance(value, bool | np.bool_):
        return "true" if value else "false"
    if isinstance(value, float | np.floating):
        return repr(float(value))  # shortest string that round-trips
    if isinstance(value, np.integer):
        return int(value)
    return value


def format_csv(table: Table, *, meta: bool = True) -> str:
    """Render a table as CSV, with the provenance block as leading ``# key: value`` lines."""
    buf = io.StringIO()
    if meta:
        for key, value in table.meta.items():
            buf.write(f"# {key}: {json.dumps(_plain(value), allow_nan=False)}\n")
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(table.columns)
    for row in table.rows:
        writer.writerow([_cell(v) for v in row])
    return buf.getvalue()


def format_json(table: Table) -> str:
    """Render a table as JSON: ``{"meta", "columns", "data": [records]}``."""

    conv = _plain

    doc = {
        "meta": _plain(table.meta),
        "columns": list(table.columns),
        "data": [{c: conv(v) for c, v in zip(table.columns, row, strict=True)} for row in table.rows],
    }
    return json.dumps(doc, indent=1, allow_nan=False) + "\n"


def render(table: Table, fmt: str) -> str:
    """Render ``table`` in format ``fmt`` (``csv`` or ``json``)."""
    if fmt == "csv":
        return format_csv(table)
    if fmt == "json":
        return format_json(table)
    raise ValueError(f"unknown format {fmt!r}; expected one of {', '.join(FORMATS)}")


def read_table(source: str | Path, *, required: Sequence[str] = ()) -> Table:
    """Read a table written by :func:`format_csv` (or any CSV with a header row).

    Args:
        source: A path, or ``-`` for standard input.
        required: Columns that must be present.

    Raises:
        InputError: unreadable file, no header, ragged row or missing column; the message names
            the file and, for row errors, the line.
    """
    name = "<stdin>" if str(source) == "-" else str(source)
    try:
        if str(source) == "-":
            stream = getattr(sys.stdin, "buffer", None)  # bytes, decoded strictly like a file
            raw: bytes | str = stream.read() if stream is not None else sys.stdin.read()
        else:
            raw = Path(source).read_bytes()
        text = (
            raw.decode("utf-8-sig") if isinstance(raw, bytes) else raw.removeprefix("\ufeff")
        )  # tolerate a BOM
    except OSError as exc:
        raise InputError(f"{name}: cannot read ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise InputError(f"{name}: not a UTF-8 text file") from None
    meta: dict[str, Any] = {}
    body: list[tuple[int, str]] = []
    for lineno, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            key, sep, value = stripped[1:].partition(":")
            if sep:
                value = value.strip()
                try:
                    meta[key.strip()] = json.loads(value)
                except json.JSONDecodeError:
                    meta[key.strip()] = value
            continue
        body.append((lineno, line))
    if not body:
        raise InputError(f"{name}: no header row (empty input?)")
    parsed = list(csv.reader([line for _, line in body]))
    if len(parsed) != len(body):
        raise InputError(f"{name}: a quoted field spans several lines (not supported)")
    columns = tuple(c.strip() for c in parsed[0])
    if len(set(columns)) != len(columns):
        raise InputError(f"{name}:{body[0][0]}: duplicate column names in header")
    rows: list[tuple[Any, ...]] = []
    lines: list[int] = []
    for (lineno, _), cells in zip(body[1:], parsed[1:], strict=True):
        if len(cells) != len(columns):
            raise InputError(f"{name}:{lineno}: expected {len(columns)} fields, found {len(cells)}")
        rows.append(tuple(c.strip() for c in cells))
        lines.append(lineno)
    table = Table(columns=columns, rows=rows, meta=meta, lines=tuple(lines), source=name)
    for col in required:
        table.column(col)
    return table
