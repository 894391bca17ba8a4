"""Shared by the `make reproduce` scripts: run the CLI as a user would, and name its outputs.

Every output is made by ``python -m motionsig_cli ...`` in a subprocess, its command line echoed first
(``$ motionsig ...``), so that the log of ``make reproduce`` lists the commands that reproduce each file.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path


def _echo(args: tuple[str, ...]) -> list[str]:
    print("$ motionsig " + " ".join(args), flush=True)
    return [sys.executable, "-m", "motionsig_cli", *args]


def motionsig(*args: str) -> None:
    """Run ``motionsig ARGS -q``, its output straight through (the echo leaves out the ``-q``)."""
    subprocess.run([*_echo(args), "-q"], check=True)


def motionsig_stdout(*args: str, stdin: str | None = None) -> str:
    """Run ``motionsig ARGS`` with ``stdin`` as its input; its stdout (stderr is captured and dropped)."""
    return subprocess.run(_echo(args), input=stdin, capture_output=True, text=True, check=True).stdout


def numbered(prefix: str, number: str) -> str:
    """The file stem of a numbered figure or table: ``numbered("fig", "2.16")`` -> ``"fig2_16"``."""
    return f"{prefix}{number.replace('.', '_')}"


def to_csv(out: Path, stem: str) -> tuple[str, str]:
    """``-o OUT/STEM.csv``."""
    return "-o", str(out / f"{stem}.csv")


def plot_and_csv(out: Path, stem: str) -> tuple[str, str, str, str]:
    """``--plot OUT/STEM.png -o OUT/STEM.csv``: a figure with its CSV beside it."""
    return "--plot", str(out / f"{stem}.png"), *to_csv(out, stem)
