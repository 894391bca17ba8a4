"""Command-layer I/O: atomic files, standard output, and re-exports of the table format.

Files are written atomically: to a temporary file in the target directory, then ``os.replace``;
a failed or interrupted run never leaves a partial file behind.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

from motionsig_cli.tables import InputError, Table, make_meta, read_table, render

__all__ = ["InputError", "Table", "atomic_path", "emit", "make_meta", "read_table", "write_text"]


@contextlib.contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it onto ``path`` only if the block succeeds."""
    path = Path(path)
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.is_dir():
        raise InputError(f"--out/--plot: directory {str(directory)!r} does not exist")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=f".tmp{path.suffix}", dir=directory)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        os.replace(tmp_path, path)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def write_text(text: str, out: Path | None) -> None:
    """Write to ``out`` atomically, or to stdout when ``out`` is None."""
    if out is None:
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    with atomic_path(out) as tmp:
        tmp.write_text(text, encoding="utf-8")


def emit(table: Table, fmt: str, out: Path | None) -> None:
    """Render and write a table (stdout or atomic file)."""
    write_text(render(table, fmt), out)
