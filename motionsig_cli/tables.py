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
import errno
import gzip
import io
import json
import math
import os
import re
import stat
import sys
import zlib
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from motionsig_cli import __version__
from motionsig_cli.errors import InputError  # re-exported: the table readers raise it

__all__ = [
    "FORMATS",
    "InputError",
    "Table",
    "is_decimal",
    "make_meta",
    "read_regular",
    "read_table",
    "render",
]

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
        meta_lines: For tables read from a file, the 1-based line of each metadata key (for errors).
    """

    columns: tuple[str, ...]
    rows: list[tuple[Any, ...]]
    meta: dict[str, Any] = field(default_factory=dict)
    lines: tuple[int, ...] = ()
    source: str = ""
    header_line: int = 0
    meta_lines: dict[str, int] = field(default_factory=dict, compare=False)

    def meta_where(self, key: str) -> str:
        """``file:line`` of the metadata key ``key`` (``file`` where its line is unknown)."""
        line = self.meta_lines.get(key, 0)
        return f"{self.source}:{line}" if line else self.source

    def column(self, name: str) -> list[Any]:
        """The raw values of one column (raises :class:`InputError` naming the file if absent)."""
        if name not in self.columns:
            where = f"{self.source}: " if self.source else ""
            raise InputError(f"{where}missing column {name!r} (columns: {name_list(self.columns)})")
        j = self.columns.index(name)
        return [row[j] for row in self.rows]

    def numeric(self, name: str, *, integer: bool = False) -> np.ndarray:
        """One column as a float (or int) array; a non-numeric cell is reported as ``file:line``."""
        values = self.column(name)
        out = np.empty(len(values), dtype=np.int64 if integer else np.float64)
        for i, v in enumerate(values):
            try:
                if isinstance(v, str) and not is_decimal(v):
                    raise ValueError
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
                raise InputError(
                    f"{self.source}:{line}: column {name!r}: {shorten(v)} is not {kind}"
                ) from None
        return out


MAX_CELL_CHARS = 100
"""Longest number accepted in a cell (a longer digit string is refused, not converted)."""
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_NON_FINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)


def is_decimal(text: str) -> bool:
    """Whether ``text`` (blanks around it ignored) is an ASCII decimal number (``1``, ``-2.5e3``, ``.5``),
    ``nan`` or ``inf``, of at most :data:`MAX_CELL_CHARS` characters: what :func:`float` reads *beside*
    (``1_0``, Arabic-Indic or full-width digits) is not a number in a table."""
    t = text.strip()
    return len(t) <= MAX_CELL_CHARS and bool(_DECIMAL.fullmatch(t) or _NON_FINITE.fullmatch(t))


def all_decimal(cells: Sequence[Any]) -> bool:
    """Whether every cell is a number or a text :func:`is_decimal` accepts (fast for the common case:
    plain ASCII without underscores is what :func:`float` and NumPy read as the same number)."""
    texts = [c for c in cells if isinstance(c, str)]
    if not texts:
        return True
    joined = "".join(texts)
    if joined.isascii() and "_" not in joined and max(map(len, texts)) <= MAX_CELL_CHARS:
        return True
    return all(is_decimal(t) for t in texts)


def shorten(value: Any, limit: int = 60) -> str:
    """``repr(value)``, at most ``limit`` characters (a cell quoted in a message)."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 4] + "…" + text[-3:]


def name_list(names: Sequence[str], limit: int = 12) -> str:
    """Column names for a message: the first ``limit`` and how many more."""
    shown = ", ".join(shorten(n, 40) if len(n) > 40 else n for n in names[:limit])
    return shown + (f", … ({len(names) - limit} more)" if len(names) > limit else "")


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
    csv.writer(buf, lineterminator="\n").writerow(table.columns)
    buf.write(format_rows(table.rows))
    return buf.getvalue()


def format_rows(rows: Iterable[Sequence[Any]], *, plain: bool = False) -> str:
    """The CSV lines of ``rows``, as :func:`format_csv` writes them after the header (a table's rows may be
    written a piece at a time and the pieces joined). ``plain``: the caller vouches that every value is a
    ``str``, ``int``, ``float`` or None (booleans already text), which the csv module writes as is."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    if plain:
        writer.writerows(rows)
        return buf.getvalue()
    for row in rows:
        kinds = set(map(type, row))
        if kinds <= _AS_IS:  # the csv module writes these as _cell does: str(float) is repr, None is empty
            writer.writerow(row)
        elif kinds <= _AS_IS_OR_BOOL:
            writer.writerow([("true" if v else "false") if v.__class__ is bool else v for v in row])
        else:
            writer.writerow([_cell(v) for v in row])
    return buf.getvalue()


_AS_IS = frozenset({str, int, float, type(None)})
_AS_IS_OR_BOOL = _AS_IS | {bool}


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
MAX_BYTES = 1 << 30
"""Default byte limit of :func:`read_table` (1 GiB): reading stops with an error at the next byte."""
MAX_JSON_BYTES = 128 << 20
"""Largest JSON table (a JSON document is parsed whole: a larger one is refused before it is parsed;
CSV, read line by line, has :data:`MAX_BYTES`)."""
MAX_JSON_VALUES = 4_000_000
"""Most values (commas) of a JSON table: a parsed value costs ~200 bytes until the table is built, so this
keeps reading one under 1 GiB (measured: 2·10⁶ values, 510 MiB); larger tables are read as CSV."""
MAX_LINE_BYTES = 4 << 20
"""Longest line of a CSV table (a longer one is refused as it is read: ``/dev/zero`` has no line end)."""
MAX_JSON_DEPTH = 64
"""Deepest nesting of a JSON table (a table is 4 deep: document, data, record, a list in a cell)."""
_KIND = {
    stat.S_IFDIR: "a directory",
    stat.S_IFIFO: "a FIFO (named pipe)",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
    stat.S_IFLNK: "a symbolic link",
}


def _not_regular(name: str, mode: int) -> InputError:
    kind = _KIND.get(stat.S_IFMT(mode), "not a regular file")
    return InputError(f"{name}: is {kind}, not a regular file (only regular files, or - for stdin, are read)")


def open_regular(path: str | Path, *, name: str | None = None, follow: bool = True) -> io.BufferedReader:
    """``path`` opened for reading in binary, if it is a regular file; refused by name otherwise.

    The file is checked with :func:`os.stat` before it is opened (a FIFO, a device, a directory or a
    symlink loop is never opened) and again with :func:`os.fstat` once open (it cannot be swapped in
    between); it is opened with ``O_NONBLOCK``, so that even a FIFO put in its place never blocks.
    ``follow=False``: a symbolic link is refused too.

    Raises:
        InputError: ``name: …`` (default: the path): missing, unreadable, a symlink loop, not a regular file.
    """
    name = str(path) if name is None else name
    try:
        st = os.stat(path) if follow else os.lstat(path)
        if not stat.S_ISREG(st.st_mode):
            raise _not_regular(name, st.st_mode)
        flags = os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
        fd = os.open(path, flags if follow else flags | getattr(os, "O_NOFOLLOW", 0))
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            why = "a symbolic link loop (too many levels of links)" if follow else "a symbolic link"
            raise InputError(f"{name}: cannot read ({why})") from None
        raise InputError(f"{name}: cannot read ({exc.strerror or exc})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise _not_regular(name, st.st_mode)
        os.set_blocking(fd, True)
        return open(fd, "rb", closefd=True)  # the caller closes it
    except BaseException:
        os.close(fd)
        raise


def read_regular(path: str | Path, *, limit: int, what: str = "file", follow: bool = True) -> bytes:
    """The bytes of the regular file ``path`` (:func:`open_regular`), at most ``limit`` of them.

    Raises:
        InputError: as :func:`open_regular`, or a file larger than ``limit`` bytes (the ``what`` named).
    """
    data = bytearray()
    with open_regular(path, follow=follow) as fh:
        while len(data) <= limit and (chunk := fh.read(min(1 << 20, limit + 1 - len(data)))):
            data += chunk  # in chunks: read(limit) would allocate the limit at once
    if len(data) > limit:
        raise InputError(f"{path}: {what} larger than {limit} bytes")
    return bytes(data)


class _Limited(io.RawIOBase):
    """A binary stream that raises :class:`InputError` once more than ``limit`` bytes have been read."""

    def __init__(self, raw: Any, name: str, limit: int) -> None:
        self.raw, self.name_, self.limit, self.count = raw, name, limit, 0

    def readable(self) -> bool:
        return True

    def readinto(self, b: Any) -> int:
        want = min(len(b), self.limit + 1 - self.count)
        if want <= 0:
            raise InputError(f"{self.name_}: larger than {self.limit} bytes (the limit for this input)")
        data = self.raw.read1(want) if hasattr(self.raw, "read1") else self.raw.read(want)
        n = len(data)
        b[:n] = data
        self.count += n
        if self.count > self.limit:
            raise InputError(f"{self.name_}: larger than {self.limit} bytes (the limit for this input)")
        return n


def _lines(stream: io.BufferedReader, name: str) -> Any:
    """(line number, text) of each line of a UTF-8 stream (a BOM at the start dropped; ``\\r\\n``, ``\\n``
    and ``\\r`` end lines, and are kept as the CSV parser wants them). A line that is not UTF-8 is an
    :class:`InputError` naming its line; so is a line longer than :data:`MAX_LINE_BYTES`."""
    lineno = 0
    first = True
    while True:
        raw = stream.readline(MAX_LINE_BYTES + 1)
        if not raw:
            return
        if len(raw) > MAX_LINE_BYTES and not raw.endswith(b"\n"):
            raise InputError(f"{name}:{lineno + 1}: a line longer than {MAX_LINE_BYTES} bytes")
        if first:
            raw = raw.removeprefix(b"\xef\xbb\xbf")
            first = False
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise InputError(
                f"{name}:{lineno + 1}:{len(raw[: exc.start].decode('utf-8')) + 1}: not a UTF-8 text file "
                f"(byte {raw[exc.start]:#04x})"
            ) from None
        pieces = _CR_LINES.findall(text) if "\r" in text.rstrip("\r\n") else (text,)
        for piece in pieces:
            lineno += 1
            yield lineno, piece


_CR_LINES = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)|[^\r\n]+")


def read_table(
    source: str | Path,
    *,
    required: Sequence[str] = (),
    max_rows: int = MAX_ROWS,
    max_bytes: int = MAX_BYTES,
) -> Table:
    """Read a table written by :func:`format_csv` or :func:`format_json` (or any CSV with a header row).

    A gzip-compressed file (``.csv.gz``, recognised by its magic bytes, not its name) is read through its
    decompression, with the same limits on the decompressed bytes; a Parquet file (magic bytes ``PAR1``,
    the format air-traffic tools exchange) with the optional pyarrow (:func:`_read_parquet`). The format is recognised from the
    content: a document whose first non-blank character is ``{`` is
    the JSON the commands write (``{"meta": {...}, "columns": [...], "data": [{...}, ...]}``), anything
    else CSV with optional leading ``# key: value`` metadata lines (values JSON; other text is kept as
    a string). CSV is read line by line, and reading stops with an error at row ``max_rows + 1``, at byte
    ``max_bytes + 1`` or at a line longer than :data:`MAX_LINE_BYTES`, so a file far too long for the
    command is refused without being held in memory. A JSON document is refused if it is longer than
    :data:`MAX_JSON_BYTES`, nested deeper than :data:`MAX_JSON_DEPTH` or has more than ``max_rows``
    records, all before it is parsed; a number longer than :data:`MAX_CELL_CHARS` characters or a key
    repeated in an object is refused while it is parsed.

    Only a regular file (or ``-``, standard input) is read: a FIFO, a device, a directory or a symbolic
    link loop is refused by name before any read (:func:`open_regular`).

    Args:
        source: A path, or ``-`` for standard input.
        required: Columns that must be present.
        max_rows: Most data rows accepted.
        max_bytes: Most bytes read.

    Raises:
        InputError: unreadable or special file, not UTF-8, no header, ragged row, too many rows or bytes,
            repeated (also in letter case) or missing column; the message names the file and, where
            there is one, the line.
    """
    tables = list(iter_table(source, max_rows=max_rows, max_bytes=max_bytes))
    if len(tables) != 1:  # pragma: no cover - without chunk_rows a source is one table
        raise AssertionError("read_table: one table expected")
    table = tables[0]
    for col in required:
        table.column(col)
    return table


def iter_table(
    source: str | Path,
    *,
    chunk_rows: int | None = None,
    max_rows: int = MAX_ROWS,
    max_bytes: int = MAX_BYTES,
) -> Iterator[Table]:
    """:func:`read_table` in pieces of at most ``chunk_rows`` rows (None: one piece), each a :class:`Table`
    with the source's columns, metadata, header line and the file lines of its own rows, so that a large
    CSV (or gzip-compressed CSV, or Parquet, read a batch at a time) is never held whole: only one piece of
    cells is alive at a time. The limits and checks are those of :func:`read_table`, over the whole source
    (``max_rows`` counts every piece); a JSON document is parsed whole and comes as one piece. The first
    piece may be empty (a header without rows); later pieces never are.

    Raises:
        InputError: as :func:`read_table`, when the piece that holds the fault is reached (earlier pieces
            have been yielded: a caller that must be all-or-nothing keeps its output until the end).
    """
    if chunk_rows is not None and (isinstance(chunk_rows, bool) or not isinstance(chunk_rows, int) or chunk_rows < 1):
        raise ValueError(f"chunk_rows: {chunk_rows!r} is not a positive integer")
    name = "<stdin>" if str(source) == "-" else str(source)
    try:
        if str(source) == "-":
            raw = getattr(sys.stdin, "buffer", None)
            if raw is None:  # a text stream (tests): its text, as UTF-8 bytes
                raw = io.BytesIO(sys.stdin.read(max_bytes + 1).encode("utf-8"))
            stream = _gunzipped(io.BufferedReader(_Limited(raw, name, max_bytes), buffer_size=1 << 16), name,
                                max_bytes)  # fmt: skip
            yield from _read_stream(stream, name, max_rows, chunk_rows)
        else:
            with open_regular(source) as fh:
                if fh.peek(4)[:4] == b"PAR1":
                    yield from _read_parquet(fh, name, max_rows, max_bytes, chunk_rows)
                else:
                    stream = _gunzipped(io.BufferedReader(_Limited(fh, name, max_bytes), buffer_size=1 << 16),
                                        name, max_bytes)  # fmt: skip
                    yield from _read_stream(stream, name, max_rows, chunk_rows)
    except (gzip.BadGzipFile, EOFError, zlib.error) as exc:
        raise InputError(f"{name}: not a readable gzip file ({exc or 'truncated'})") from None
    except OSError as exc:
        raise InputError(f"{name}: cannot read ({exc.strerror or exc})") from None


def _read_parquet(
    fh: io.BufferedReader, name: str, max_rows: int, max_bytes: int, chunk_rows: int | None = None
) -> Iterator[Table]:
    """A Parquet file (recognised by its magic bytes ``PAR1``), read with the optional pyarrow: its columns
    as the table's, its rows numbered from 2 as a CSV's would be (row 1 the header), timestamps as ISO 8601
    text (UTC with ``Z``), nulls as empty cells. The file's size counts against ``max_bytes`` and its rows
    against ``max_rows``, both before the data are read."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise InputError(
            f"{name}: a Parquet file, which needs the optional pyarrow: pip install 'motionsig_cli[parquet]' (or give "
            "CSV)"
        ) from None
    size = os.fstat(fh.fileno()).st_size
    if size > max_bytes:
        raise InputError(f"{name}: larger than {max_bytes} bytes (the limit for this input)")
    try:
        pf = pq.ParquetFile(fh)
        n = pf.metadata.num_rows
        if n > max_rows:
            raise InputError(f"{name}: more than {max_rows} data rows (the limit for this input)")
    except (pa.ArrowException, OSError) as exc:
        raise InputError(f"{name}: not a readable Parquet file ({shorten(str(exc), 120)})") from None
    columns = tuple(str(c) for c in pf.schema_arrow.names)
    seen: dict[str, str] = {}
    for c in columns:
        if c.lower() in seen:
            raise InputError(f"{name}: columns {seen[c.lower()]!r} and {c!r} differ only in letter case")
        seen[c.lower()] = c
    meta = {k.decode(errors="replace"): v.decode(errors="replace") for k, v in (pf.schema_arrow.metadata or {}).items()
            if not k.startswith(b"pandas") and not k.startswith(b"ARROW")}  # fmt: skip
    first = 2  # the line a CSV's first row would have (row 1 the header)
    batches = pf.iter_batches(batch_size=chunk_rows or max(n, 1))
    while True:
        try:
            batch = next(batches, None)
        except (pa.ArrowException, OSError) as exc:
            raise InputError(f"{name}: not a readable Parquet file ({shorten(str(exc), 120)})") from None
        if batch is None:
            break
        rows = _parquet_rows(pa, batch)
        yield Table(columns=columns, rows=rows, meta=meta, lines=tuple(range(first, first + len(rows))),
                    source=name, header_line=1)  # fmt: skip
        first += len(rows)
    if first == 2:  # no rows: the header alone
        yield Table(columns=columns, rows=[], meta=meta, lines=(), source=name, header_line=1)


def _parquet_rows(pa: Any, batch: Any) -> list[tuple[Any, ...]]:
    """The rows of a Parquet record batch as cells: timestamps as ISO 8601 text (UTC with ``Z``), nulls as
    empty cells."""
    cells = []
    for col in batch.columns:
        if pa.types.is_timestamp(col.type):
            unit = col.type.unit
            tz = col.type.tz
            ints = col.cast(pa.int64()).to_numpy(zero_copy_only=False)
            null = col.is_null().to_numpy(zero_copy_only=False)
            stamps = np.datetime_as_string(ints.astype(f"datetime64[{unit}]"), unit="ms")
            suffix = "Z" if tz is not None and tz.upper() in ("UTC", "Z", "+00:00") else ""
            cells.append(["" if m else f"{v}{suffix}" for v, m in zip(stamps.tolist(), null.tolist(), strict=True)])
        else:
            cells.append(["" if v is None else v for v in col.to_pylist()])
    return list(zip(*cells, strict=True)) if cells else []


def _gunzipped(stream: io.BufferedReader, name: str, max_bytes: int) -> io.BufferedReader:
    """The stream itself, or, where it starts with gzip's magic bytes, its decompressed content — limited to
    ``max_bytes`` too (a small file that inflates beyond the limit is refused while it is read)."""
    if stream.peek(2)[:2] != b"\x1f\x8b":
        return stream
    return io.BufferedReader(_Limited(gzip.GzipFile(fileobj=stream, mode="rb"), name, max_bytes),
                             buffer_size=1 << 16)  # fmt: skip


def _read_stream(
    stream: io.BufferedReader, name: str, max_rows: int, chunk_rows: int | None = None
) -> Iterator[Table]:
    """CSV (line by line, in pieces of ``chunk_rows`` rows) or JSON (one piece) from an open binary stream."""
    start = stream.peek(1 << 16)[: 1 << 16].removeprefix(b"\xef\xbb\xbf").lstrip()
    if start[:1] in (b"{", b"["):  # JSON: read whole (bounded), as one text; a one-line document may be long
        chunks: list[bytes] = []
        total = 0
        while total <= MAX_JSON_BYTES and (chunk := stream.read(1 << 20)):  # read(n) would allocate n at once
            chunks.append(chunk)
            total += len(chunk)
        data = b"".join(chunks).removeprefix(b"\xef\xbb\xbf")
        del chunks
        if total > MAX_JSON_BYTES:
            raise InputError(
                f"{name}: a JSON table larger than {MAX_JSON_BYTES} bytes (JSON is parsed whole; write "
                "larger tables as CSV, which is read line by line)"
            )
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as exc:
            at = data.count(b"\n", 0, exc.start) + 1
            raise InputError(f"{name}:{at}: not a UTF-8 text file (byte {data[exc.start]:#04x})") from None
        del data
        yield _read_json(text, name, max_rows)
        return
    lines = _lines(stream, name)
    head: list[tuple[int, str]] = []
    meta: dict[str, Any] = {}
    meta_lines: dict[str, int] = {}
    linenos: list[int] = []  # line of each non-comment line handed to the CSV parser since the last piece
    started = False  # the header has been handed over: later comments are skipped, not metadata

    def body() -> Any:
        nonlocal started
        for lineno, line in _chain(head, lines):
            stripped = line.strip()
            if not stripped:
                continue
            if stripped.startswith("#"):
                if not started:  # metadata lines before the header; later comments are skipped
                    key, sep, value = stripped[1:].partition(":")
                    if sep:
                        value = value.strip()
                        key = key.strip()
                        try:
                            meta[key] = _loads(value)
                        except json.JSONDecodeError:
                            meta[key] = value
                        except (ValueError, RecursionError) as exc:
                            raise InputError(f"{name}:{lineno}: metadata {shorten(key, 40)}: {exc}") from None
                        meta_lines[key] = lineno
                continue
            started = True
            linenos.append(lineno)
            yield line

    try:
        for table in _parse_csv(csv.reader(body(), strict=True), linenos, meta, name, max_rows, chunk_rows):
            table.meta_lines.update(meta_lines)
            yield table
    except csv.Error as exc:
        at = f"{name}:{linenos[-1]}" if linenos else name
        raise InputError(f"{at}: not readable as CSV ({exc})") from None


def _parse_csv(
    reader: Any, linenos: list[int], meta: dict[str, Any], name: str, max_rows: int, chunk_rows: int | None = None
) -> Iterator[Table]:
    """The header and rows of a CSV reader fed by ``_read_stream`` (which appends to ``linenos`` the line of
    each CSV line it hands over; emptied here after the header and after each piece), in pieces of at most
    ``chunk_rows`` rows (None: one)."""
    header = next(reader, None)
    if header is None:
        raise InputError(f"{name}: no header row (empty input?)")
    if len(linenos) != 1:
        raise InputError(f"{name}:{linenos[0]}: a quoted field is not closed on its line (not supported)")
    header_line = linenos[0]
    columns = tuple(c.strip() for c in header)
    if len(columns) == 1 and ";" in columns[0]:
        raise InputError(
            f"{name}:{header_line}: the header {shorten(columns[0])} is one column: the file looks separated by "
            "';' (fields must be separated by commas)"
        )
    _check_columns(columns, f"{name}:{header_line}")
    n = len(columns)
    del linenos[:]
    rows: list[tuple[Any, ...]] = []
    total = 0
    pieces = 0
    for cells in reader:
        if len(linenos) != len(rows) + 1:
            raise InputError(
                f"{name}:{linenos[len(rows)]}: a quoted field is not closed on its line (not supported)"
            )
        if len(cells) != n:
            raise InputError(f"{name}:{linenos[-1]}: expected {n} fields, found {len(cells)}")
        if total >= max_rows:
            raise InputError(
                f"{name}:{linenos[-1]}: more than {max_rows} data rows (the limit for this input)"
            )
        rows.append(tuple(map(str.strip, cells)))
        total += 1
        if chunk_rows is not None and len(rows) >= chunk_rows:
            yield Table(columns=columns, rows=rows, meta=meta, lines=tuple(linenos), source=name,
                        header_line=header_line)  # fmt: skip
            pieces += 1
            rows = []
            del linenos[:]
    if rows or not pieces:
        yield Table(columns=columns, rows=rows, meta=meta, lines=tuple(linenos[: len(rows)]), source=name,
                    header_line=header_line)  # fmt: skip


def _check_columns(columns: Sequence[str], where: str) -> None:
    """Refuse a header whose names repeat. Names that differ in letter case only (``A_r`` and ``a_r``) are
    two columns of a table; a record reader that matches names to roles case-insensitively refuses them
    where both could be one role (:mod:`motionsig_cli.records`)."""
    seen: set[str] = set()
    for c in columns:
        if c in seen:
            raise InputError(f"{where}: duplicate column {shorten(c, 40)} in the header")
        seen.add(c)


def _chain(head: list[tuple[int, str]], rest: Any) -> Any:
    yield from head
    yield from rest


def _unique(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out = dict(pairs)
    if len(out) != len(pairs):
        seen: set[str] = set()
        key = next(k for k, _ in pairs if k in seen or seen.add(k))  # type: ignore[func-returns-value]
        raise ValueError(f"key {shorten(key, 40)} repeats in an object")
    return out


_LONG_DIGITS = re.compile(rf"[0-9]{{{MAX_CELL_CHARS + 1},}}")
_JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')


def _long_number(text: str) -> int:
    """The offset of the first number longer than :data:`MAX_CELL_CHARS` digits outside a string, or −1 (a
    C-speed search; the strings are looked at only where it finds a long run of digits)."""
    strings = _JSON_STRING.finditer(text)
    s = None
    for m in _LONG_DIGITS.finditer(text):
        while s is None or s.end() <= m.start():  # the strings are scanned once, as far as the digits
            if (s := next(strings, None)) is None:
                return m.start()
        if s.start() > m.start():
            return m.start()
    return -1


def _loads(text: str) -> Any:
    """JSON with limits: no repeated key, no number longer than :data:`MAX_CELL_CHARS` digits, no nesting
    deeper than :data:`MAX_JSON_DEPTH` (``ValueError``; a syntax error is ``JSONDecodeError``)."""
    if len(text) > 64 and _depth(text, 1 << 30)[0] > MAX_JSON_DEPTH:
        raise ValueError(f"nested deeper than {MAX_JSON_DEPTH} levels")
    if _long_number(text) >= 0:
        raise ValueError(f"a number of more than {MAX_CELL_CHARS} digits")
    return json.loads(text, object_pairs_hook=_unique)


_JSON_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[{}\[\]\n]')


def _depth(text: str, max_records: int) -> tuple[int, list[int]]:
    """(deepest nesting, the 1-based line of each object that is an element of an array at depth ≤ 2, the
    records of ``data``), scanning tokens; it stops at a nesting deeper than :data:`MAX_JSON_DEPTH` or
    at record ``max_records + 1``."""
    lines: list[int] = []
    depth = deepest = 0
    stack: list[str] = []
    line = 1
    for m in _JSON_TOKEN.finditer(text):
        tok = m.group()
        if tok == "\n":
            line += 1
        elif tok in "{[":
            if tok == "{" and stack and stack[-1] == "[" and len(stack) <= 2:
                lines.append(line)
                if len(lines) > max_records:
                    break
            stack.append(tok)
            depth += 1
            if depth > deepest:
                deepest = depth
                if deepest > MAX_JSON_DEPTH:
                    break
        elif tok in "}]":
            if stack:
                stack.pop()
                depth -= 1
        else:
            line += tok.count("\n")
    return deepest, lines


def _json_error(name: str, text: str, exc: Exception) -> InputError:
    if isinstance(exc, json.JSONDecodeError):
        return InputError(f"{name}:{exc.lineno}:{exc.colno}: not valid JSON ({exc.msg})")
    return InputError(f"{name}: not a valid table ({exc})")


def _read_json(text: str, name: str, max_rows: int) -> Table:
    """The JSON document of :func:`format_json`; each record's line is found for error messages."""
    deepest, record_lines = _depth(text, max_rows)
    if deepest > MAX_JSON_DEPTH:
        raise InputError(f"{name}: JSON nested deeper than {MAX_JSON_DEPTH} levels")
    if len(record_lines) > max_rows:
        raise InputError(
            f"{name}:{record_lines[-1]}: more than {max_rows} data records (the limit for this input)"
        )
    if text.count(",") >= MAX_JSON_VALUES:
        raise InputError(
            f"{name}: a JSON table of more than {MAX_JSON_VALUES} values (JSON is parsed whole; write larger "
            "tables as CSV, which is read line by line)"
        )
    if (at := _long_number(text)) >= 0:
        raise InputError(
            f"{name}:{text.count(chr(10), 0, at) + 1}: a number of more than {MAX_CELL_CHARS} digits"
        )
    try:
        raw = json.loads(text, object_pairs_hook=_unique)
    except (ValueError, RecursionError) as exc:
        raise _json_error(name, text, exc) from None
    doc = {"data": raw} if isinstance(raw, list) else raw  # a bare list of records (pandas: orient="records")
    if not isinstance(doc, dict) or not isinstance(doc.get("data"), list):
        raise InputError(
            f'{name}: a JSON table is {{"meta": {{...}}, "columns": [...], "data": [{{...}}, ...]}} (as the commands '
            'write it) or a list of records [{"column": value, ...}, ...]'
        )
    data = doc["data"]  # its numbers become text, like CSV cells (repr: the same float back)
    meta = doc.get("meta", {})
    if not isinstance(meta, dict):
        raise InputError(f'{name}: "meta" must be an object')
    if len(data) > max_rows:
        raise InputError(f"{name}: more than {max_rows} data records (the limit for this input)")
    if len(record_lines) != len(data):
        record_lines = [1] * len(data)  # objects nested oddly: no line numbers
    columns = doc.get("columns")
    if columns is None:
        columns = list(dict.fromkeys(k for rec in data if isinstance(rec, dict) for k in rec))
    if not isinstance(columns, list) or not all(isinstance(c, str) for c in columns):
        raise InputError(f'{name}: "columns" must be a list of names')
    _check_columns(columns, name)
    known = set(columns)
    rows: list[tuple[Any, ...]] = []
    for rec, ln in zip(data, record_lines, strict=True):
        if not isinstance(rec, dict):
            raise InputError(f"{name}:{ln}: a record is not an object")
        if not known.issuperset(rec):
            extra = sorted(set(rec) - known)
            raise InputError(f"{name}:{ln}: field {shorten(extra[0], 40)} is not one of the columns")
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
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)  # the shortest text of the same float
    if isinstance(value, str):
        return value
    return json.dumps(value)
