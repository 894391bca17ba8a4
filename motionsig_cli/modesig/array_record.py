"""The LMP mode detector on one record given as arrays: the Python entry point of ``motionsig detect
RECORD``.

The arrays become the record ``detect`` reads (:func:`~motionsig_cli.modesig.record_reading.read_vehicle_record`:
the time grid, missing samples, the model from the options or ``simulate``'s defaults) and the detector
is the command's (:class:`~motionsig_cli.modesig.lmp1d.RecordDetection` for a 1-D record,
:class:`~motionsig_cli.modesig.lmp2d.RadarRecordDetection` for a radar record): the argmax of eq (52) per
horizon, the same numbers as the command's table.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.lmp import LMPConfig, LMPResult, RadarLMPConfig
from motionsig_cli.modesig.lmp1d import RecordDetection
from motionsig_cli.modesig.lmp2d import RadarRecordDetection
from motionsig_cli.modesig.lmp_record import RecordResult
from motionsig_cli.modesig.record_reading import ModelOptions, read_vehicle_record
from motionsig_cli.tables import Table

__all__ = ["ModeDetection", "detect_mode", "detect_mode_radar"]

SOURCE = "<arrays>"
"""The record's name in messages and metadata."""


@dataclass(frozen=True)
class ModeDetection:
    """The LMP detector's decision on one record, per horizon (eq 52's argmax over the candidates).

    Attributes:
        horizon_s: (H,) horizons [s].
        mode: (H,) the estimated mode (1-based: mode i carries code i).
        tau: (H,) the estimated code phase [samples].
        tau_chips: (H,) the same in chips.
        f_c: (H,) the estimated carrier [Hz] (the carrier grid's best).
        statistic: (H,) the largest Λ (eq 52) [nats].
        margin: (H,) its margin over the runner-up candidate [nats].
        present: (H,) "signature present" (Λ ≥ the threshold), or None without a threshold.
        result: every candidate's statistics (:class:`~motionsig_cli.detection.lmp.LMPResult`).
        summary: one line, as the command prints it.

    Examples:
        >>> import numpy as np
        >>> from motionsig_cli import detect_mode
        >>> det = detect_mode(np.arange(200) * 0.05, np.zeros(200), horizons=[5.0, 10.0], threshold=1e9)
        >>> det.horizon_s.tolist(), det.present.tolist()  # the vehicle at rest carries no signature
        ([5.0, 10.0], [False, False])
    """

    horizon_s: np.ndarray
    mode: np.ndarray
    tau: np.ndarray
    tau_chips: np.ndarray
    f_c: np.ndarray
    statistic: np.ndarray
    margin: np.ndarray
    present: np.ndarray | None
    result: LMPResult
    summary: str


def _options(model: dict[str, Any]) -> ModelOptions:
    names = {f.name for f in fields(ModelOptions)}
    for key, value in model.items():
        if key not in names:
            raise ConfigError(key, value, f"is not a model quantity ({', '.join(sorted(names))})")
    return ModelOptions(**model)


def _cell(v: float) -> float | str:
    return "" if math.isnan(v) else float(v)


def _table(times: np.ndarray, columns: tuple[str, ...], values: Sequence[np.ndarray]) -> Table:
    t = np.asarray(times, float)
    cols = [np.asarray(v, float) for v in values]
    if t.ndim != 1:
        raise ConfigError("times", f"shape {t.shape}", "is not (N,) times [s]")
    for name, v in zip(columns[1:], cols, strict=True):
        if v.shape != t.shape:
            raise ConfigError(name, f"shape {v.shape}", f"is not ({t.size},), one value per time")
    rows = [(float(ti), *(_cell(float(c[i])) for c in cols)) for i, ti in enumerate(t)]
    return Table(columns=columns, rows=rows, source=SOURCE)


def _decision(out: RecordResult) -> ModeDetection:
    tab = out.table

    def col(name: str) -> np.ndarray:
        return np.asarray(tab.column(name))

    present = col("signature_present").astype(bool) if "signature_present" in tab.columns else None
    return ModeDetection(
        col("horizon_s").astype(float), col("mode_hat").astype(int), col("tau_hat").astype(int),
        col("tau_hat_chips").astype(float), col("fc_hat").astype(float), col("statistic").astype(float),
        col("margin").astype(float), present, out.res, out.summary,
    )  # fmt: skip


def detect_mode(
    times: np.ndarray,
    y: np.ndarray,
    *,
    cfg: LMPConfig | None = None,
    horizons: Sequence[float] | None = None,
    threshold: float | None = None,
    method: str = "bank",
    **model: Any,
) -> ModeDetection:
    """The mode and code phase of the signature in one 1-D record (eq 52 per horizon; Fig 3).

    Args:
        times: (N,) sample times [s] on a uniform grid (a gap is a run of missing samples).
        y: (N,) measured positions [m]; NaN: a missing sample (a predict-only step of the filter bank).
        cfg: the detector's settings (default :class:`~motionsig_cli.detection.lmp.LMPConfig`).
        horizons: horizons [s]; None: every 10 s.
        threshold: declare "signature present" where max Λ ≥ threshold; None: no decision.
        method: ``bank`` (2C + 1 Kalman filters) or ``fft``.
        **model: the model the filters assume, named as ``motionsig simulate``'s options (``T``, ``m_rho``,
            ``K``, ``R``, ``f_c``, ``a_sig``, ``codes``…); each defaults to ``simulate``'s.

    Raises:
        ConfigError: a bad argument, naming it.

    Examples:
        A record simulated with mode 2 at code phase 5 chips is detected as such:

        >>> from motionsig_cli import Vehicle1D, detect_mode
        >>> from motionsig_cli.modesig.vehicle_record import RecordConfig, simulate_record
        >>> sim = simulate_record(RecordConfig(Vehicle1D(), mode=2, tau_chips=5, duration=20.0, seed=1))
        >>> det = detect_mode(sim.t, sim.y, horizons=[20.0])
        >>> int(det.mode[0]), float(det.tau_chips[0])
        (2, 5.0)
    """
    rec = read_vehicle_record(_table(times, ("time", "y"), [y]), example="1d", model=_options(model))
    run = RecordDetection(rec, cfg if cfg is not None else LMPConfig(), method=method,  # type: ignore[arg-type]
                          horizons=None if horizons is None else tuple(horizons), threshold=threshold)  # fmt: skip
    return _decision(run.detect())


def detect_mode_radar(
    times: np.ndarray,
    range_m: np.ndarray,
    bearing_rad: np.ndarray,
    *,
    cfg: RadarLMPConfig | None = None,
    horizons: Sequence[float] | None = None,
    threshold: float | None = None,
    method: str = "bank",
    **model: Any,
) -> ModeDetection:
    """The mode and code phase of the signature in one radar record (eq 52 with sigma-point filters, eqs
    59–62; Fig 7).

    Args:
        times: (N,) sample times [s] on a uniform grid.
        range_m: (N,) measured ranges from the radar at the origin [m]; NaN: a missing sample.
        bearing_rad: (N,) measured bearings atan2(y, x) [rad].
        cfg: the detector's settings (default :class:`~motionsig_cli.detection.lmp.RadarLMPConfig`).
        horizons: horizons [s]; None: every 10 s.
        threshold: declare "signature present" where max Λ ≥ threshold; None: no decision.
        method: ``bank`` or ``linearised``.
        **model: the model, named as ``motionsig simulate --example 2d``'s options (``T``, ``m_rho``,
            ``R_range``, ``R_bearing``, ``start``, ``codes``…); each defaults to ``simulate``'s.

    Raises:
        ConfigError: a bad argument, naming it.

    Examples:
        >>> from motionsig_cli import Vehicle2D, detect_mode_radar
        >>> from motionsig_cli.modesig.vehicle_record import RecordConfig, simulate_record
        >>> sim = simulate_record(RecordConfig(Vehicle2D(), mode=3, tau_chips=7, duration=20.0, seed=1))
        >>> det = detect_mode_radar(sim.t, sim.y[:, 0], sim.y[:, 1], horizons=[20.0], method="linearised")
        >>> int(det.mode[0]), float(det.tau_chips[0])
        (3, 7.0)
    """
    table = _table(times, ("time", "range", "bearing"), [range_m, bearing_rad])
    rec = read_vehicle_record(table, example="2d", model=_options(model))
    run = RadarRecordDetection(rec, cfg if cfg is not None else RadarLMPConfig(), method=method,
                               horizons=None if horizons is None else tuple(horizons), threshold=threshold)  # fmt: skip
    return _decision(run.detect())
