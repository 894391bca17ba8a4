"""``motionsig detect`` on 2-D radar records and its Fig 7 Monte Carlo (the radar example of the
mode-signature paper, LMP mode detection with Gold-code signatures, IEEE CDC 2008, §IV.B, eqs 59–62).

:func:`detect_radar` builds the detector's configuration and one run of
:mod:`motionsig_cli.experiments.lmp2d` (a record's
:class:`~motionsig_cli.experiments.lmp2d.RadarRecordDetection` or the job
:class:`~motionsig_cli.experiments.lmp2d.RadarLmpJob`) and writes its table and figure.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import typer

from motionsig_cli.cli.common import Output, checked, int_list, progress_bar, run_job

if TYPE_CHECKING:
    from motionsig_cli.cli.detect import FilterKind
    from motionsig_cli.engine import Engine
    from motionsig_cli.experiments.record_reading import VehicleRecord


def detect_radar(
    output: Output, engine: Engine, rec: VehicleRecord | None, montecarlo: bool, filter_: FilterKind,
    radar: dict[str, Any], hs: tuple[float, ...] | None, threshold: float | None, candidates: bool,
    frs: tuple[float, ...] | None, anr_pairs: str, trials: int, seed: int, signature: bool,
    calibration: tuple[float, int | None, int] | None = None,
) -> None:  # fmt: skip
    """The 2-D example: the Fig 7 Monte Carlo (``montecarlo``) or eq (52) on the radar record ``rec``.

    ``radar``: the :class:`~motionsig_cli.detection.lmp.RadarLMPConfig` fields the options set (without
    --fc-grid the grid is the known f_c: 1 Hz for the Monte Carlo, the record's for a record).
    ``calibration``: (pfa, null trials, seed) of a threshold calibrated on null records (--pfa), or None.
    """
    if filter_.value == "kf":
        raise typer.BadParameter(
            "the radar example is nonlinear (range, bearing): use --filter ukf", param_hint="--filter"
        )
    if montecarlo:
        pairs = tuple(checked("--anr-pairs", int_list, anr_pairs, what="pair"))
        _montecarlo(output, engine, radar, frs, pairs, hs, trials, seed, signature)
    else:
        assert rec is not None
        _record(output, engine, rec, radar, hs, threshold, candidates, calibration)


def _record(
    output: Output, engine: Engine, rec: VehicleRecord, radar: dict[str, Any], hs: tuple[float, ...] | None,
    threshold: float | None, candidates: bool, calibration: tuple[float, int | None, int] | None,
) -> None:  # fmt: skip
    """Eq (52) with the sigma-point bank on one radar record, with a progress bar of its time steps."""
    from motionsig_cli.cli.records import emit_record, with_null_threshold
    from motionsig_cli.detection.lmp import RadarLMPConfig
    from motionsig_cli.experiments.lmp2d import RadarRecordDetection

    cfg = RadarLMPConfig(**{"fc_grid": (rec.f_c,), **radar})
    run = RadarRecordDetection(rec, cfg, hs, threshold, candidates)
    if calibration is not None:
        run = with_null_threshold(run, "bank", "ukf", cfg.sigma, *calibration, engine, output)
    with progress_bar("Sigma-point filter bank (time steps)", run.steps, output.quiet) as advance:
        result = run.detect(progress=advance)
    emit_record(output, result, run.title)


def _montecarlo(
    output: Output, engine: Engine, radar: dict[str, Any], frs: tuple[float, ...] | None,
    pairs: tuple[int, ...], hs: tuple[float, ...] | None, trials: int, seed: int, signature: bool,
) -> None:  # fmt: skip
    """Fig 7: % correct (i, τ) vs horizon for Fig 7's (angle, range) ANR pairs."""
    from motionsig_cli.detection.lmp import RadarLMPConfig
    from motionsig_cli.experiments.lmp2d import RadarLmpJob

    cfg = RadarLMPConfig(**radar)
    job = RadarLmpJob(cfg, frs, pairs, None, hs, trials, seed, signature)
    mc = run_job(job, engine, "Monte Carlo trials (2-D radar)", output.quiet)
    if output.plot is not None:
        from motionsig_cli.plotting import montecarlo_figure

        output.figure(montecarlo_figure(*mc.figure_data()))
    output.emit(mc.table())
    output.note(mc.summary())
