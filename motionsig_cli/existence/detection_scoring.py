"""The sequential likelihood-ratio test of track existence (Govaers, *Evaluation of Distributed Detection
Methods for Agile Targets*) on detections given as arrays: the Python entry point of ``motionsig slrt
--input DETECTIONS --sensor-table SENSORS``.

The arrays become the two tables the command reads (:func:`~motionsig_cli.existence.slrt_record.load`:
the scan grid, every sensor scanning at every scan, the field-of-view checks, the track initialisation) and
the record is scored by the command's :func:`~motionsig_cli.existence.slrt_record.score`: every fusion
method's log likelihood ratio per scan and Wald's decision (first crossing of log A or log B) — the same
numbers as the command (and, for a simulated run, as the simulation).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from motionsig_cli.config import ConfigError, one_of
from motionsig_cli.existence.slrt_record import KINDS, SlrtRecordConfig, load, score
from motionsig_cli.tables import Table

__all__ = ["ExistenceScores", "Sensor", "score_detections"]


@dataclass(frozen=True)
class Sensor:
    """One sensor of :func:`score_detections` (a row of the command's sensors table).

    Attributes:
        label: the label its detections carry.
        x, y: its position [m].
        pd: the detection probability the filters assume, in (0, 1].
        fov: its field-of-view range [m] (range–bearing: r ∈ [0, fov]; Cartesian: the square of half-width
            fov about the sensor).
        clutter: mean false alarms per scan λ_F (or give ``clutter_density``).
        clutter_density: false alarms per scan per m·rad (range–bearing) or per m² (Cartesian).
        sigma_r: range noise sd [m] (range–bearing detections).
        sigma_phi: bearing noise sd [rad] (range–bearing detections).
        sigma_xy: noise sd per axis [m] (Cartesian detections).

    Examples:
        >>> import math
        >>> from motionsig_cli import Sensor
        >>> Sensor("radar1", 0.0, 0.0, pd=0.9, fov=20e3, clutter=1.0, sigma_r=20.0, sigma_phi=math.radians(1))
        ... # doctest: +ELLIPSIS
        Sensor(label='radar1', x=0.0, y=0.0, pd=0.9, fov=20000.0, clutter=1.0, ...)
    """

    label: str
    x: float
    y: float
    pd: float
    fov: float
    clutter: float | None = None
    clutter_density: float | None = None
    sigma_r: float | None = None
    sigma_phi: float | None = None
    sigma_xy: float | None = None


_SENSOR_COLUMNS = (
    ("sigma_r", "sigma_r [m]"),
    ("sigma_phi", "sigma_phi [rad]"),
    ("sigma_xy", "sigma_xy [m]"),
    ("clutter", "clutter"),
    ("clutter_density", "clutter_density"),
)


@dataclass(frozen=True)
class ExistenceScores:
    """The scores of the tracks of one record.

    Attributes:
        methods: the fusion methods, in order.
        times: (K,) the times of the scored scans [s].
        log_lr: method -> (R, K) log likelihood ratio of existence of each of the R tracks after each scan.
        decision: method -> (R,) Wald's decision: +1 confirmed, −1 deleted, 0 undecided.
        decision_time: method -> (R,) the time of the decision [s] (NaN: undecided).
        start: (R, 4) each track's initial state (x, ẋ, y, ẏ) [m, m/s].
        thresholds: Wald's (log A, log B).

    Examples:
        See :func:`score_detections`; the arrays are per method:

        >>> import numpy as np
        >>> from motionsig_cli import ExistenceScores
        >>> s = ExistenceScores(("ckf",), np.array([1.0]), {"ckf": np.array([[3.2]])}, {"ckf": np.array([0])},
        ...                     {"ckf": np.array([np.nan])}, np.zeros((1, 4)), (-2.3, 6.9))
        >>> s.final("ckf").tolist()
        [3.2]
    """

    methods: tuple[str, ...]
    times: np.ndarray
    log_lr: dict[str, np.ndarray]
    decision: dict[str, np.ndarray]
    decision_time: dict[str, np.ndarray]
    start: np.ndarray
    thresholds: tuple[float, float]

    def final(self, method: str) -> np.ndarray:
        """(R,) the log likelihood ratio of each track after the last scan."""
        return self.log_lr[method][:, -1]


def _sensor_table(sensors: Sequence[Sensor]) -> Table:
    if not sensors:
        raise ConfigError("sensors", [], "is empty: give at least one Sensor")
    for s in sensors:
        if not isinstance(s, Sensor):
            raise ConfigError("sensors", type(s).__name__, "holds something other than a Sensor")
    optional = []
    for name, header in _SENSOR_COLUMNS:
        given = [getattr(s, name) is not None for s in sensors]
        if any(given) and not all(given):
            missing = next(s.label for s, g in zip(sensors, given, strict=True) if not g)
            raise ConfigError(
                name, None, f"is given for some sensors, not for {missing!r}: give it for every sensor"
            )
        if all(given):
            optional.append((name, header))
    cols = ("sensor", "x [m]", "y [m]", "pd", "fov [m]", *(h for _, h in optional))
    rows = [(str(s.label), float(s.x), float(s.y), float(s.pd), float(s.fov),
             *(float(getattr(s, n)) for n, _ in optional)) for s in sensors]  # fmt: skip
    return Table(cols, rows, source="<sensors>")


def _detection_table(times: np.ndarray, sensor: Sequence[str], z: np.ndarray, kind: str) -> Table:
    t = np.asarray(times, float)
    zz = np.asarray(z, float)
    labels = [str(v) for v in sensor]
    if t.ndim != 1:
        raise ConfigError("times", f"shape {t.shape}", "is not (M,) times [s], one per detection")
    if len(labels) != t.size:
        raise ConfigError("sensor", f"{len(labels)} labels", f"is not one label per detection ({t.size})")
    if zz.shape != (t.size, 2):
        raise ConfigError("measurements", f"shape {zz.shape}", f"is not ({t.size}, 2)")
    names = ("range [m]", "bearing [rad]") if kind == "range_bearing" else ("x [m]", "y [m]")

    def cell(v: float) -> float | str:
        return "" if math.isnan(v) else float(v)  # an empty cell: a scan without detections

    rows = [(float(t[i]), labels[i], cell(zz[i, 0]), cell(zz[i, 1])) for i in range(t.size)]
    return Table(("time", "sensor", *names), rows, source="<detections>")


def score_detections(
    times: np.ndarray,
    sensor: Sequence[str],
    measurements: np.ndarray,
    sensors: Sequence[Sensor],
    *,
    kind: str = "range_bearing",
    config: SlrtRecordConfig | None = None,
) -> ExistenceScores:
    """Score the existence of a track in detections of several sensors, scan by scan (module docstring).

    Args:
        times: (M,) the scan time of each detection [s]; the scans lie on a uniform grid (a scan with no
            row is a scan in which no sensor detected anything).
        sensor: (M,) the label of the sensor of each detection (a :attr:`Sensor.label`).
        measurements: (M, 2) range [m] and bearing [rad] (counter-clockwise from the x axis, relative to the
            sensor), or x, y [m] with ``kind="cartesian"``; a NaN row records a scan without detections.
        sensors: every sensor; each scans at every scan.
        kind: ``range_bearing`` or ``cartesian``.
        config: the filters' motion model, the track's start (``init``: one track from a given state; else
            one tentative track per detection of the first scan), the fusion methods and Wald's α, β.

    Raises:
        ConfigError: a bad argument, naming it.
        InputError: a detection the command would refuse (outside its sensor's field of view, an unknown
            sensor label, times off the scan grid), naming ``<detections>`` and its row.

    Examples:
        One radar sees a target moving at 100 m/s east in every scan, no clutter:

        >>> import math
        >>> import numpy as np
        >>> from motionsig_cli import Sensor, SlrtRecordConfig, score_detections
        >>> t = np.arange(1.0, 11.0)
        >>> x, y = 5000.0 + 100.0 * t, np.full(t.size, 3000.0)
        >>> z = np.stack([np.hypot(x, y), np.arctan2(y, x)], axis=1)
        >>> radar = Sensor("r1", 0.0, 0.0, pd=0.9, fov=20e3, clutter=0.1, sigma_r=10.0, sigma_phi=0.002)
        >>> cfg = SlrtRecordConfig(init=(5000.0, 100.0, 3000.0, 0.0), methods=("ckf",))
        >>> s = score_detections(t, ["r1"] * t.size, z, [radar], config=cfg)
        >>> s.decision["ckf"].tolist(), bool(s.final("ckf")[0] > s.thresholds[1])
        ([1], True)
    """
    one_of("kind", kind, KINDS)
    cfg = config if config is not None else SlrtRecordConfig()
    if not isinstance(cfg, SlrtRecordConfig):
        raise ConfigError("config", type(cfg).__name__, "is not a SlrtRecordConfig")
    if cfg.meas is not None and cfg.meas != kind:
        raise ConfigError("kind", kind, f"disagrees with config.meas = {cfg.meas!r}")
    record = load(_detection_table(times, sensor, measurements, kind), _sensor_table(sensors), cfg)
    res = score(record, cfg)
    det = record.detections
    ks = res.scan_index
    decision, decision_time = {}, {}
    for m in res.scores:
        dec, at = res.decisions(m)
        decision[m] = dec.astype(int)
        decision_time[m] = np.where(at >= 0, det.times[ks[np.maximum(at, 0)]], np.nan)
    return ExistenceScores(
        methods=tuple(res.scores), times=np.asarray(det.times, float)[ks], log_lr=dict(res.scores),
        decision=decision, decision_time=decision_time, start=res.tracks.m0.copy(), thresholds=cfg.thresholds,
    )  # fmt: skip
