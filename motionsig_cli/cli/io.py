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
from typing import TYPE_CHECKING, Any

from motionsig_cli.errors import InputError

if TYPE_CHECKING:
    from motionsig_cli.tables import Table, make_meta, read_table, render

_FROM_TABLES = ("Table", "make_meta", "read_table", "render")


def __getattr__(name: str) -> Any:
    """The table format (:mod:`motionsig_cli.tables`, which needs NumPy) is imported on first use."""
    if name in _FROM_TABLES:
        from motionsig_cli import tables

        return getattr(tables, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "InputError",
    "Table",
    "atomic_path",
    "check_output_path",
    "emit",
    "make_meta",
    "read_table",
    "render",
    "write_text",
]


def check_output_path(path: Path | None, option: str) -> None:
    """Validate an output path before any work is done (so a bad ``--out`` leaves no ``--plot`` behind)."""
    if path is None:
        return
    if str(path) == "":
        raise InputError(f"{option}: empty file name")
    target = Path(os.path.realpath(path))
    if target.is_dir():
        raise InputError(f"{option}: {str(path)!r} is a directory")
    if not target.parent.is_dir():
        raise InputError(f"{option}: directory {str(target.parent)!r} does not exist")


@contextlib.contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """Yield a path to write; publish it at ``path`` only if the block succeeds.

    Regular files are written to a temporary file beside the target and renamed onto it, so a
    failed or interrupted run never leaves a partial file. A symbolic link is followed (the file
    it points to is replaced, the link stays). An existing non-regular target (``/dev/null``, a
    FIFO) is written in place: it cannot be replaced, and must not be.
    """
    path = Path(path)
    check_output_path(path, "output")
    target = Path(os.path.realpath(path))
    if target.exists() and not target.is_file():
        yield target
        return
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=f".tmp{target.suffix}", dir=target.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp_path, 0o666 & ~umask)  # mkstemp creates 0600; give the file the usual permissions
    try:
        yield tmp_path
        os.replace(tmp_path, target)
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
    from motionsig_cli.tables import render

    write_text(render(table, fmt), out)
