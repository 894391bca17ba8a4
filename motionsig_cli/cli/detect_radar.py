"""``motionsig detect`` on 2-D radar records and its Fig 7 Monte Carlo (the radar example of the
mode-signature paper, 47th IEEE CDC, Cancún, 2008, §IV.B, eqs 59–62).

:func:`detect_radar` builds the detector's configuration and one run of
:mod:`motionsig_cli.modesig.lmp2d` (a record's
:class:`~motionsig_cli.modesig.lmp2d.RadarRecordDetection` or the job
:class:`~motionsig_cli.modesig.lmp2d.RadarLmpJob`) and writes its table and figure.
"""

from __future__ import annotations

from enum import StrEnum
from typing import TYPE_CHECKING, Any

import typer

from motionsig_cli.cli.common import Output, checked, int_list, progress_bar, run_job

if TYPE_CHECKING:
    from motionsig_cli.engine import Engine
    from motionsig_cli.modesig.record_reading import VehicleRecord


def detect_radar(
    output: Output, engine: Engine, rec: VehicleRecord | None, montecarlo: bool, filter_: StrEnum,
    radar: dict[str, Any], hs: tuple[float, ...] | None, threshold: float | None, candidates: bool,
    frs: tuple[float, ...] | None, anr_pairs: str, trials: int, seed: int, signature: bool,
    calibration: tuple[float, int | None, int] | None = None, *, method: str = "bank", center: str = "none",
    calibrate: bool = False, pfa: float | None = None, null_trials: int | None = None,
) -> None:  # fmt: skip
    """The 2-D example: the Fig 7 Monte Carlo (``montecarlo``), its threshold calibration (``calibrate``) or
    eq (52) on the radar record ``rec``.

    ``radar``: the :class:`~motionsig_cli.detection.lmp.RadarLMPConfig` fields the options set (without
    --fc-grid the grid is the known f_c: 1 Hz for the Monte Carlo, the record's for a record).
    ``calibration``: (pfa, null trials, seed) of a threshold calibrated on null records (--pfa), or None.
    ``method``: ``bank`` or ``linearised`` (``fft`` is refused before); ``center``: none, h0-noise or
    standardised (the linearised path only). --calibrate runs the linearised path unless --method bank was
    given on the command line.
    """
    if filter_.value == "kf":
        raise typer.BadParameter(
            "the radar example is nonlinear (range, bearing): use --filter ukf", param_hint="--filter"
        )
    if method == "linearised" and filter_.value == "ukf":
        raise typer.BadParameter(
            "the linearised path replaces the bank: drop --filter ukf", param_hint="--method"
        )
    if center != "none" and not (method == "linearised" or (calibrate and not _given("method"))):
        raise typer.BadParameter("applies to the radar with --method linearised", param_hint="--center")
    pairs = tuple(checked("--anr-pairs", int_list, anr_pairs, what="pair"))
    if calibrate:
        how = method if _given("method") else "linearised"
        _calibrate(output, engine, radar, frs, pairs, hs, trials, seed, how, center, null_trials, pfa or 0.01)
    elif montecarlo:
        _montecarlo(output, engine, radar, frs, pairs, hs, trials, seed, signature, method, center)
    else:
        assert rec is not None
        _record(output, engine, rec, radar, hs, threshold, candidates, calibration, method, center)


def _given(name: str) -> bool:
    """Whether the command line gave the option of parameter ``name`` (not its default)."""
    import click

    ctx = click.get_current_context(silent=True)
    if ctx is None:
        return False
    source = ctx.get_parameter_source(name)
    return source is not None and source.name not in ("DEFAULT", "DEFAULT_MAP")


def _record(
    output: Output, engine: Engine, rec: VehicleRecord, radar: dict[str, Any], hs: tuple[float, ...] | None,
    threshold: float | None, candidates: bool, calibration: tuple[float, int | None, int] | None,
    method: str = "bank", center: str = "none",
) -> None:  # fmt: skip
    """Eq (52) with the sigma-point bank (or the linearised path) on one radar record, with a progress bar of
    its time steps."""
    from motionsig_cli.cli.records import emit_record, with_null_threshold
    from motionsig_cli.detection.lmp import RadarLMPConfig
    from motionsig_cli.modesig.lmp2d import RadarRecordDetection

    cfg = RadarLMPConfig(**{"fc_grid": (rec.f_c,), **radar})
    run = RadarRecordDetection(rec, cfg, hs, threshold, candidates, method=method, center=center)
    if calibration is not None and method == "bank":
        run = with_null_threshold(run, "bank", "ukf", cfg.sigma, *calibration, engine, output)
    elif calibration is not None:  # the null records run the record's statistic: the linearised path, center
        run = _linearised_null_threshold(run, calibration, engine, output)
    what = "Sigma-point filter bank" if method == "bank" else "Linearised projection"
    with progress_bar(f"{what} (time steps)", run.steps, output.quiet) as advance:
        result = run.detect(progress=advance)
    emit_record(output, result, run.title)


def _linearised_null_threshold(
    run: Any, calibration: tuple[float, int | None, int], engine: Engine, output: Output
) -> Any:
    """``run`` (a linearised :class:`~motionsig_cli.modesig.lmp2d.RadarRecordDetection`) at the thresholds
    that null records of its model, through the same path and centring, exceed with probability P_FA."""
    import dataclasses

    from motionsig_cli.modesig.record_calibration import RecordNullJob

    pfa, null_trials, seed = calibration
    job = RecordNullJob(run.record, run.cfg, "linearised", "ukf", run.cfg.sigma, run.horizons, pfa, null_trials,
                        seed, center=run.center)  # fmt: skip
    cal = run_job(job, engine, "null records (no signature)", output.quiet)
    if cal.warning:
        output.note(cal.warning)
    thresholds = tuple(float(v) for v in cal.thresholds)
    return dataclasses.replace(run, threshold=thresholds, threshold_meta=cal.meta())


def _montecarlo(
    output: Output, engine: Engine, radar: dict[str, Any], frs: tuple[float, ...] | None,
    pairs: tuple[int, ...], hs: tuple[float, ...] | None, trials: int, seed: int, signature: bool,
    method: str = "bank", center: str = "none",
) -> None:  # fmt: skip
    """Fig 7: % correct (i, τ) vs horizon for Fig 7's (angle, range) ANR pairs."""
    from motionsig_cli.detection.lmp import RadarLMPConfig
    from motionsig_cli.modesig.lmp2d import RadarLmpJob

    cfg = RadarLMPConfig(**radar)
    if method == "bank":  # the job as before (its identity and outputs unchanged)
        job = RadarLmpJob(cfg, frs, pairs, None, hs, trials, seed, signature)
    else:
        job = RadarLmpJob(cfg, frs, pairs, None, hs, trials, seed, signature, method=method, center=center)
    mc = run_job(job, engine, "Monte Carlo trials (2-D radar)", output.quiet)
    output.result(mc, "montecarlo_figure")


def _calibrate(
    output: Output, engine: Engine, radar: dict[str, Any], frs: tuple[float, ...] | None,
    pairs: tuple[int, ...], hs: tuple[float, ...] | None, trials: int, seed: int, method: str, center: str,
    null_trials: int | None, pfa: float,
) -> None:  # fmt: skip
    """The threshold of max Λ for a false-alarm probability per Fig 7 pair and horizon, and P_D at it (ROC
    curves with --plot)."""
    from motionsig_cli.detection.lmp import RadarLMPConfig
    from motionsig_cli.modesig.lmp2d import RadarCalibrationJob

    job = RadarCalibrationJob(
        RadarLMPConfig(**radar), frs or (0.01,), pairs, hs, trials, null_trials, pfa, seed, method, center
    )
    if job.warning:
        output.note(job.warning)
    cal = run_job(job, engine, "Calibration trials (2-D radar, null + signature)", output.quiet)
    output.result(cal, "calibration_roc_figure")
