"""Command-layer side of ``motionsig detect`` on one record (1-D or 2-D radar): the ``--horizons`` option,
the threshold calibrated for the record (``--pfa``), and writing the per-record result (table, Fig 3-style
figure, summary line).

What is not input/output lives in the core: the checks of a record's contents and its reading back
(:mod:`motionsig_cli.modesig.record_reading`) and the result table
(:mod:`motionsig_cli.modesig.lmp_record`). Their functions are reachable here under their old names
(``finite_column``, ``uniform_times``, ``truth_of``, ``sigma_meta``), imported on first use.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import typer

from motionsig_cli.cli.common import Output, OutputFormat, checked, float_list, run_job
from motionsig_cli.config import ConfigError

if TYPE_CHECKING:
    from motionsig_cli.engine import Engine
    from motionsig_cli.filters.unscented import SigmaPointParams
    from motionsig_cli.modesig.lmp1d import RecordDetection
    from motionsig_cli.modesig.lmp2d import RadarRecordDetection
    from motionsig_cli.modesig.lmp_record import RecordResult, sigma_meta
    from motionsig_cli.modesig.record_reading import finite_column, truth_of, uniform_times

_MOVED = {
    "finite_column": "motionsig_cli.modesig.record_reading",
    "uniform_times": "motionsig_cli.modesig.record_reading",
    "truth_of": "motionsig_cli.modesig.record_reading",
    "sigma_meta": "motionsig_cli.modesig.lmp_record",
}

__all__ = [
    "emit_record",
    "emit_record_result",
    "finite_column",
    "parse_horizons",
    "sigma_meta",
    "truth_of",
    "uniform_times",
    "with_null_threshold",
]


def __getattr__(name: str) -> Any:
    """The core functions that used to live here, imported on first use (they need NumPy)."""
    if name in _MOVED:
        import importlib

        return getattr(importlib.import_module(_MOVED[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def parse_horizons(text: str | None, duration: float, T: float) -> list[float]:
    """--horizons in seconds (default every 10 s of the record), each within the record; a bad value is a
    usage error naming --horizons."""
    from motionsig_cli.modesig.record_reading import record_horizons

    hs = None if text is None else checked("--horizons", float_list, text, what="horizon")
    try:
        return record_horizons(hs, duration, T)
    except ConfigError as exc:
        raise typer.BadParameter(exc.detail, param_hint="--horizons") from None


RunT = TypeVar("RunT", "RecordDetection", "RadarRecordDetection")


def with_null_threshold(
    run: RunT, method: str, filter: str, sigma: SigmaPointParams, pfa: float, null_trials: int | None,
    seed: int, engine: Engine, output: Output,
) -> RunT:  # fmt: skip
    """``run`` at the threshold (one per horizon) that null records of its model exceed with probability
    ``pfa``: :class:`~motionsig_cli.modesig.record_calibration.RecordNullJob` on the engine, with a
    progress bar of its null trials (and a note when they are too few for ``pfa``)."""
    if method == "fft":
        run.missing_checked("the FFT path cannot skip a missing sample: use --method bank")
    try:
        from motionsig_cli.modesig.record_calibration import RecordNullJob
    except ImportError:  # the calibration of one record is not part of this installation
        raise typer.BadParameter(
            "needs motionsig_cli.modesig.record_calibration, which this installation lacks; use "
            "--threshold X",
            param_hint="--pfa",
        ) from None
    job = RecordNullJob(run.record, run.cfg, method, filter, sigma, run.horizons, pfa, null_trials, seed)
    cal = run_job(job, engine, "null records (no signature)", output.quiet)
    if cal.warning:
        output.note(cal.warning)
    thresholds = tuple(float(v) for v in cal.thresholds)
    return dataclasses.replace(run, threshold=thresholds, threshold_meta=cal.meta())


def emit_record(output: Output, result: RecordResult, title: str) -> None:
    """A record's table, its Fig 3-style figure (--plot) and the summary line."""
    if output.plot is not None:
        from motionsig_cli.plotting import statistic_figure

        lam, cell, tau_chips = result.statistic_grid()
        output.figure(statistic_figure([(title, lam, cell)], result.n_modes, tau_chips))
    output.emit(result.table)
    output.note(result.summary)


def emit_record_result(
    *args: Any,
    candidates: bool,
    threshold: float | None,
    output: Output | None = None,
    plot: Path | None = None,
    fmt: OutputFormat = OutputFormat.csv,
    out: Path | None = None,
    quiet: bool = False,
) -> None:
    """Write the argmax per horizon (or the whole candidate table), the Fig 3-style plot, a summary line.

    ``args``: the positional arguments of :func:`~motionsig_cli.modesig.lmp_record.record_result`
    (``res, hs, hz, truth, params, chips_shape, m_rho``), then the figure's title. ``output`` (the
    command's output options) or, for older callers, ``plot``, ``fmt``, ``out``, ``quiet``.
    """
    from motionsig_cli.modesig.lmp_record import record_result

    *fields, title = args
    result = record_result(*fields, candidates=candidates, threshold=threshold)
    emit_record(output or Output(fmt=fmt, out=out, plot=plot, quiet=quiet), result, title)
