"""Shared by the ``make bench`` scripts: the machine and versions, and one CSV layout for every result.

Every ``benchmarks/results/*.csv`` starts with ``# ...`` comment lines (workload, correctness) and then
has the columns of :data:`COLUMNS`: one row per timed case, the machine and package versions repeated
on every row so that a row read alone still says where it was measured. ``scripts/bench_report.py``
copies the files to ``docs/performance/`` and draws the Performance page from them.
"""

from __future__ import annotations

import csv
import importlib.metadata
import os
import platform
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

RESULTS = Path(__file__).resolve().parent / "results"

# unit: what one "unit" of work is (filter-step = one filter, one time step; run-scan; ...);
# us_per_unit: wall seconds / units · 1e6 (for the FFT path: per filter-step of the equivalent bank);
# ratio_vs_filterpy: FilterPy's (extrapolated) time / this case's time; speedup: case-specific
# reference (see ``how``) / this case's time; agreement_pct: bench_fft only.
COLUMNS = [
    "benchmark",
    "case",
    "seconds",
    "units",
    "unit",
    "us_per_unit",
    "ratio_vs_filterpy",
    "speedup",
    "agreement_pct",
    "how",
    "machine",
    "cores",
    "python",
    "numpy",
    "scipy",
    "filterpy",
    "dask",
    "distributed",
    "jax",
]


def _version(dist: str) -> str:
    try:
        return importlib.metadata.version(dist)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


def _cpu_name() -> str:
    """The CPU model (from /proc/cpuinfo on Linux), else platform.processor()."""
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.lower().startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def cores() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def environment() -> dict[str, str]:
    """Machine and versions, the columns after ``how``."""
    return {
        "machine": f"{platform.system()} {platform.machine()} {_cpu_name()}",
        "cores": str(cores()),
        "python": platform.python_version(),
        "numpy": _version("numpy"),
        "scipy": _version("scipy"),
        "filterpy": _version("filterpy"),
        "dask": _version("dask"),
        "distributed": _version("distributed"),
        "jax": _version("jax"),  # the optional bench-jax extra (bench_kf_bank's one-core comparison)
    }


def environment_line() -> str:
    env = environment()
    return f"# machine: {env['machine']} cores={env['cores']} " + " ".join(
        f"{k}={env[k]}" for k in ("python", "numpy", "scipy", "filterpy", "dask", "distributed", "jax")
    )


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def write_results(name: str, comments: Sequence[str], rows: Sequence[Mapping[str, Any]]) -> Path:
    """Write ``benchmarks/results/<name>.csv``: the comment lines, the environment line, the rows."""
    RESULTS.mkdir(exist_ok=True)
    path = RESULTS / f"{name}.csv"
    env = environment()
    with open(path, "w", newline="") as fh:
        for c in comments:
            fh.write(f"# {c}\n")
        fh.write(environment_line() + "\n")
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(COLUMNS)
        for row in rows:
            unknown = set(row) - set(COLUMNS)
            if unknown:
                raise ValueError(f"unknown columns {sorted(unknown)}")
            full = {"benchmark": name, **env, **row}
            w.writerow([_cell(full.get(c)) for c in COLUMNS])
    return path


def read_results(path: Path) -> tuple[list[str], list[dict[str, str]]]:
    """(comment lines without '# ', rows as dicts) of a file written by :func:`write_results`."""
    comments, body = [], []
    with open(path, newline="") as fh:
        for line in fh:
            if line.startswith("#"):
                comments.append(line[1:].strip())
            else:
                body.append(line)
    return comments, list(csv.DictReader(body))


def best_of(fn: Callable[[], object], repeats: int, clock: Callable[[], float] = time.perf_counter) -> float:
    """Minimum time of ``repeats`` calls on ``clock``: wall time by default, or ``time.process_time`` for the
    process's CPU time (the machine is shared; minima are the least disturbed)."""
    times = []
    for _ in range(repeats):
        t0 = clock()
        fn()
        times.append(clock() - t0)
    return min(times)


def gate(summary: str, failed: bool, failure: str) -> bool:
    """Print a correctness gate's summary and, if it ``failed``, ``failure`` to stderr; True if it passed."""
    print(summary)
    if failed:
        print(failure, file=sys.stderr)
    return not failed


def measured_row(
    case: str, seconds: float, units: int, unit: str, t_filterpy: float | None, repeats: int, **extra: Any
) -> dict[str, Any]:
    """A row timed on the whole workload (best of ``repeats``); ``how`` goes on with ``extra['how']``."""
    how = f"measured, whole workload, best of {repeats}{extra.pop('how', '')}"
    ratio = None if t_filterpy is None else t_filterpy / seconds
    return {"case": case, "seconds": seconds, "units": units, "unit": unit, "us_per_unit": 1e6 * seconds / units,
            "ratio_vs_filterpy": ratio, "how": how, **extra}  # fmt: skip


def filterpy_row(
    case: str, t_slice: float, slice_units: int, units: int, unit: str, slice_what: str, repeats: int
) -> dict[str, Any]:
    """FilterPy timed on a slice of ``slice_units`` (``slice_what``), extrapolated linearly to ``units``."""
    per_unit = t_slice / slice_units
    return {"case": case, "seconds": per_unit * units, "units": units, "unit": unit, "us_per_unit": 1e6 * per_unit,
            "ratio_vs_filterpy": 1.0,
            "how": f"extrapolated from {slice_what} ({t_slice:.2f} s, best of {repeats})"}  # fmt: skip


def publish(name: str, comments: Sequence[str], rows: Sequence[Mapping[str, Any]], line: str) -> Path:
    """:func:`write_results`, then one summary line per row: ``line.format(**row)``."""
    path = write_results(name, comments, rows)
    for r in rows:
        print(line.format(**r))
    return path
