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
import re
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
        header_line: For tables read from a file, the 1-based line of the header (0: unknown).
    """

    columns: tuple[str, ...]
    rows: list[tuple[Any, ...]]
    meta: dict[str, Any] = field(default_factory=dict)
    lines: tuple[int, ...] = ()
    source: str = ""
    header_line: int = 0

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


MAX_ROWS = 10_000_000
"""Default row limit of :func:`read_table`: a longer input is refused before it is held in memory."""


def read_table(source: str | Path, *, required: Sequence[str] = (), max_rows: int = MAX_ROWS) -> Table:
    """Read a table written by :func:`format_csv` or :func:`format_json` (or any CSV with a header row).

    The format is recognised from the content: a document whose first non-blank character is ``{`` is
    the JSON the commands write (``{"meta": {...}, "columns": [...], "data": [{...}, ...]}``), anything
    else CSV with optional leading ``# key: value`` metadata lines (values JSON; other text is kept as
    a string). CSV is read line by line, and reading stops with an error at row ``max_rows + 1``, so a
    file far too long for the command is refused without being held in memory.

    Args:
        source: A path, or ``-`` for standard input.
        required: Columns that must be present.
        max_rows: Most data rows accepted.

    Raises:
        InputError: unreadable file, no header, ragged row, too many rows or missing column; the
            message names the file and, for row errors, the line.
    """
    name = "<stdin>" if str(source) == "-" else str(source)
    try:
        if str(source) == "-":
            buffer = getattr(sys.stdin, "buffer", None)  # bytes, decoded strictly like a file
            stream: Any = (
                io.TextIOWrapper(buffer, encoding="utf-8-sig", errors="strict", newline="")
                if buffer is not None
                else sys.stdin
            )
            table = _read_stream(stream, name, max_rows)
        else:
            with open(source, encoding="utf-8-sig", errors="strict", newline="") as stream:
                table = _read_stream(stream, name, max_rows)
    except OSError as exc:
        raise InputError(f"{name}: cannot read ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise InputError(f"{name}: not a UTF-8 text file") from None
    for col in required:
        table.column(col)
    return table


def _read_stream(stream: Any, name: str, max_rows: int) -> Table:
    """CSV (line by line) or JSON from an open text stream."""
    first = ""
    head: list[str] = []
    for line in stream:
        head.append(line)
        if line.strip():
            first = line.lstrip().removeprefix("\ufeff")[:1]
            break
    if first in "{[" and first:
        return _read_json("".join(head) + stream.read(), name, max_rows)
    meta: dict[str, Any] = {}
    linenos: list[int] = []  # line of each non-comment line handed to the CSV parser

    def body() -> Any:
        for lineno, line in enumerate(_chain(head, stream), start=1):
            stripped = line.strip()
            if not stripped:
                continue
            if stripped.startswith("#"):
                if not linenos:  # metadata lines before the header; later comments are skipped
                    key, sep, value = stripped[1:].partition(":")
                    if sep:
                        value = value.strip()
                        try:
                            meta[key.strip()] = json.loads(value)
                        except json.JSONDecodeError:
                            meta[key.strip()] = value
                continue
            linenos.append(lineno)
            yield line

    try:
        return _parse_csv(csv.reader(body(), strict=True), linenos, meta, name, max_rows)
    except csv.Error as exc:
        at = f"{name}:{linenos[-1]}" if linenos else name
        raise InputError(f"{at}: not readable as CSV ({exc})") from None


def _parse_csv(reader: Any, linenos: list[int], meta: dict[str, Any], name: str, max_rows: int) -> Table:
    """The header and rows of a CSV reader fed by ``_read_stream`` (which fills ``linenos``)."""
    header = next(reader, None)
    if header is None:
        raise InputError(f"{name}: no header row (empty input?)")
    if len(linenos) != 1:
        raise InputError(f"{name}:{linenos[0]}: a quoted field is not closed on its line (not supported)")
    columns = tuple(c.strip() for c in header)
    if len(columns) == 1 and ";" in columns[0]:
        raise InputError(
            f"{name}:{linenos[0]}: the header {columns[0]!r} is one column: the file looks separated by ';' "
            "(fields must be separated by commas)"
        )
    if len(set(columns)) != len(columns):
        raise InputError(f"{name}:{linenos[0]}: duplicate column names in header")
    n = len(columns)
    rows: list[tuple[Any, ...]] = []
    for cells in reader:
        if len(linenos) != len(rows) + 2:
            raise InputError(
                f"{name}:{linenos[len(rows) + 1]}: a quoted field is not closed on its line (not supported)"
            )
        if len(cells) != n:
            raise InputError(f"{name}:{linenos[-1]}: expected {n} fields, found {len(cells)}")
        if len(rows) >= max_rows:
            raise InputError(
                f"{name}:{linenos[-1]}: more than {max_rows} data rows (the limit for this input)"
            )
        rows.append(tuple(c.strip() for c in cells))
    return Table(
        columns=columns, rows=rows, meta=meta, lines=tuple(linenos[1:]), source=name, header_line=linenos[0]
    )


def _chain(head: list[str], stream: Any) -> Any:
    yield from head
    yield from stream


_JSON_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[{}\[\]\n]')


def _json_record_lines(text: str) -> list[int]:
    """1-based line of each object that is an element of a top-level array (the records of ``data``)."""
    lines: list[int] = []
    stack: list[str] = []
    line = 1
    for m in _JSON_TOKEN.finditer(text):
        tok = m.group()
        if tok == "\n":
            line += 1
        elif tok in "{[":
            if tok == "{" and stack == ["{", "["]:
                lines.append(line)
            stack.append(tok)
        elif tok in "}]":
            if stack:
                stack.pop()
        else:
            line += tok.count("\n")
    return lines


def _read_json(text: str, name: str, max_rows: int) -> Table:
    """The JSON document of :func:`format_json`; each record's line is found for error messages."""
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{name}:{exc.lineno}:{exc.colno}: not valid JSON ({exc.msg})") from None
    if isinstance(doc, list):  # a bare list of records (pandas: to_json(orient="records"))
        doc = {"data": doc}
    # the data's numbers as their text, like CSV cells: a reader can then convert them exactly
    raw = json.loads(text, parse_float=str, parse_int=str)
    raw_data = raw if isinstance(raw, list) else raw.get("data") if isinstance(raw, dict) else None
    if not isinstance(doc, dict) or not isinstance(doc.get("data"), list):
        raise InputError(
            f'{name}: a JSON table is {{"meta": {{...}}, "columns": [...], "data": [{{...}}, ...]}} (as the commands '
            'write it) or a list of records [{"column": value, ...}, ...]'
        )
    data = raw_data if isinstance(raw_data, list) and len(raw_data) == len(doc["data"]) else doc["data"]
    meta = doc.get("meta", {})
    if not isinstance(meta, dict):
        raise InputError(f'{name}: "meta" must be an object')
    if len(data) > max_rows:
        raise InputError(f"{name}: more than {max_rows} data records (the limit for this input)")
    record_lines = _json_record_lines(text) if "\n" in text else []
    if len(record_lines) != len(data):
        record_lines = [1] * len(data)  # records on one line, or objects nested oddly: no line numbers
    columns = doc.get("columns")
    if columns is None:
        columns = list(dict.fromkeys(k for rec in data if isinstance(rec, dict) for k in rec))
    if not isinstance(columns, list) or not all(isinstance(c, str) for c in columns):
        raise InputError(f'{name}: "columns" must be a list of names')
    if len(set(columns)) != len(columns):
        raise InputError(f"{name}: duplicate column names")
    rows: list[tuple[Any, ...]] = []
    for rec, ln in zip(data, record_lines, strict=True):
        if not isinstance(rec, dict):
            raise InputError(f"{name}:{ln}: a record is not an object")
        extra = set(rec) - set(columns)
        if extra:
            raise InputError(f"{name}:{ln}: field {sorted(extra)[0]!r} is not one of the columns")
        rows.append(tuple(_json_cell(rec.get(c)) for c in columns))
    return Table(
        columns=tuple(columns), rows=rows, meta=meta, lines=tuple(record_lines), source=name, header_line=1
    )


def _json_cell(value: Any) -> Any:
    """A JSON value as the CSV reader would give it: null → empty cell, booleans as words."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return value
    if isinstance(value, str):
        return value
    return json.dumps(value)
