"""Reference data shipped with the package (``data/`` in the source tree), each file with provenance.

In a source checkout the files are read from ``<repo>/data``; an installed wheel carries them as
``motionsig_cli/data`` (hatch ``force-include``).
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from motionsig_cli.tables import Table, read_table


def data_dir() -> Path:
    """The directory holding the reference data files."""
    packaged = Path(__file__).resolve().parent / "data"
    return packaged if packaged.is_dir() else Path(__file__).resolve().parent.parent / "data"


@cache
def load(name: str) -> Table:
    """Load one reference table (e.g. ``"table1.csv"``) with its provenance in ``Table.meta``."""
    return read_table(data_dir() / name)
