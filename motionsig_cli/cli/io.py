"""Command-layer I/O: atomic files, standard output, and re-exports of the table format.

Files are written atomically: to a temporary file in the target directory, then ``os.replace``;
a failed or interrupted run never leaves a partial file behind.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import sys
import tempfile
from collections.abc import Callable, Iterator, Sequence
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
    """Validate an output path before any work is done (so a bad ``--out`` leaves no ``--plot`` behind):
    refuse an empty name, a symlink loop, a directory, a missing directory, a special file that cannot be
    written, and a directory where no file can be created (read-only, ``/sys``, ``/proc``: probed by
    creating and removing a temporary file, as the atomic write will)."""
    if path is None:
        return
    if str(path) == "":
        raise InputError(f"{option}: empty file name")
    try:
        os.stat(path)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise InputError(f"{option}: {str(path)!r} is a symbolic link loop") from None
    target = Path(os.path.realpath(path))
    if target.is_dir():
        raise InputError(f"{option}: {str(path)!r} is a directory")
    if not target.parent.is_dir():
        raise InputError(f"{option}: directory {str(target.parent)!r} does not exist")
    if target.exists() and not target.is_file():  # a device or a FIFO: written in place
        if not os.access(target, os.W_OK):
            raise InputError(f"{option}: {str(path)!r} is not writable")
        return
    try:
        fd, probe = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".probe", dir=target.parent)
    except OSError as exc:
        raise InputError(
            f"{option}: cannot write in directory {str(target.parent)!r} ({exc.strerror or exc})"
        ) from None
    os.close(fd)
    os.unlink(probe)


def _open_special(target: Path) -> int:
    """A descriptor to write a special file in place; a FIFO that no process reads is refused (opening it
    would wait for a reader forever)."""
    flags = os.O_WRONLY
    if stat.S_ISFIFO(os.stat(target).st_mode):
        try:
            fd = os.open(target, flags | os.O_NONBLOCK)
        except OSError as exc:
            if exc.errno == errno.ENXIO:
                raise InputError(f"{target}: a FIFO that no process reads") from None
            raise
        os.set_blocking(fd, True)
        return fd
    return os.open(target, flags)


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
    """Write to ``out`` atomically, or to stdout when ``out`` is None; a failed write (a full device, a
    vanished directory) is an :class:`InputError` naming the file, and leaves no partial file."""
    write_with(lambda fh: fh.write(text), out)


def write_with(write: Callable[[Any], Any], out: Path | None) -> None:
    """``write(fh)`` on a text stream: ``out``'s, atomically (:func:`atomic_path`), or stdout's when ``out`` is
    None; a failed write is an :class:`InputError` naming the file, and leaves no partial file."""
    if out is None:
        try:
            write(sys.stdout)
            sys.stdout.flush()
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise InputError(f"standard output: cannot write ({exc.strerror or exc})") from None
        return
    try:
        with atomic_path(out) as tmp:
            if tmp.exists() and not tmp.is_file():
                with os.fdopen(_open_special(tmp), "w", encoding="utf-8") as fh:
                    write(fh)
            else:
                with open(tmp, "w", encoding="utf-8", newline="") as fh:
                    write(fh)
    except OSError as exc:
        raise InputError(f"{out}: cannot write ({exc.strerror or exc})") from None


def emit_spooled(table: Table, bodies: Sequence[Path], out: Path | None) -> None:
    """Write ``table`` as CSV whose rows are the text of the files ``bodies`` (rows written as they were
    computed: :func:`~motionsig_cli.tables.format_rows`), joined after its metadata and header: the bytes
    of :func:`emit` of the same rows, without holding them. To ``out`` atomically, or to stdout."""
    import shutil

    from motionsig_cli.tables import Table, format_csv

    head = format_csv(Table(columns=table.columns, rows=[], meta=table.meta))

    def copy(fh: Any) -> None:
        fh.write(head)
        for body in bodies:
            with open(body, encoding="utf-8", newline="") as src:
                shutil.copyfileobj(src, fh, 1 << 20)

    write_with(copy, out)


def emit(table: Table, fmt: str, out: Path | None) -> None:
    """Render and write a table (stdout or atomic file)."""
    from motionsig_cli.tables import render

    write_text(render(table, fmt), out)
