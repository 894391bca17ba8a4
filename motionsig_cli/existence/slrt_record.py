"""The track-existence test of Govaers, *Evaluation of Distributed Detection Methods for Agile Targets*
(Fraunhofer FKIE, slides) on the user's own detections: the chosen fusion methods of
:data:`~motionsig_cli.detection.track_existence.FUSION_METHODS` (default CKF, FKF, LKF) score the record
scan by scan, and Wald's test decides. The files are read with :func:`motionsig_cli.records.read_record`.

**Detections file** (:data:`DETECTION_SPEC`): one row per detection, per scan and sensor.

- ``time`` (seconds, any time unit, or ISO 8601 timestamps) or ``scan`` (an integer), non-decreasing.
  With scan numbers, they are the scans; the period T is ``--T``, else the file's metadata ``T``, else
  the least-squares slope of each scan's first time against its number (so the times of one scan's
  rows may differ, as a rotating antenna stamps them), else 1 s (assumed, without times). With times
  alone, the rows of a scan share its time and the scans lie on a uniform grid of period T (``--T``,
  else the metadata ``T``, else estimated from the times); a time between grid points is refused.
  With scan numbers each scan's time is after the previous scan's, and every row's time within one period of its scan's grid point; a period (given or
  estimated) that contradicts the times — ``T: 1e-300`` beside rows 1 s apart, a time a century late — is
  refused naming both values, the file, the line and the column.
- ``sensor``: a label of the sensors table.
- ``range,bearing`` (polar, relative to the sensor; bearing counter-clockwise from the x axis,
  atan2(y − y_s, x − x_s), radians unless the header, the metadata or ``--units`` say ``deg``) or
  ``x,y`` (Cartesian, m). A file with both pairs needs ``--meas``.

The scans are those of the grid from the first row's scan to the last row's: **every sensor of the
sensors table scans at every scan**; a sensor without a row at a scan detected nothing there, and a scan
without any row is a scan in which no sensor detected anything. A row whose two measurement cells are
empty (or NaN) records a scan without detections (it places the scan on the grid and adds nothing); a
row with only one of them empty is refused. A detection outside its sensor's field of view (a range
beyond ``fov`` or negative, a bearing beyond ±2π, a Cartesian point beyond ``fov`` on either axis) is
refused, not dropped: the clutter model assumes every detection lies in the field of view, and such a
value is usually a unit error.

**Sensors table** (:data:`SENSOR_SPEC`): one row per sensor, at most :data:`MAX_SENSORS`: ``sensor``
(unique labels), position ``x,y`` (m), the noise ``sigma_r`` (m) and ``sigma_phi`` (degrees unless a unit
is given) for range–bearing or ``sigma_xy`` (m, both axes) for Cartesian detections, ``pd`` (the p_D the
filters assume), ``clutter`` (mean false alarms per scan, λ_F) or ``clutter_density`` (per m·rad for
range–bearing, per m² for Cartesian), and ``fov`` (the field-of-view range, m: the polar box
r ∈ [0, fov], φ ∈ [−π, π), or the square of half-width fov about the sensor). Sensors may differ in
every value (each filter update uses its own sensor's R, p_D and ρ_F); with equal values the scores
are those of the simulated scenario to the last bit.

**The track.** ``--init x,vx,y,vy`` (or the file's metadata ``init``) is the track's state one scan
period before the first scan (the filters predict to each scan before its update, as in the
simulation, whose track starts at t = 0 and whose first scan is at t = T), with prior standard
deviations ``--init-sd pos,vel`` (or the metadata ``init_sd``; default 200 m, 50 m/s: the simulation's).
Without either, **one tentative track starts from each detection of the first scan that has any**
(one-point initialisation: position the detection's, in x–y, velocity 0; position sd the larger of σ_r
and r·σ_φ of its sensor, or σ_xy; velocity sd 150 m/s, assumed: an air target up to about 300 m/s within
2σ; ``--init-sd`` replaces both), scored from the next scan on, at most :data:`MAX_TRACKS` tracks.

With one sensor the fusion rules coincide (CKF = FKF = FKF-FB = LKF = LDF, and DKF where it applies; the
naive score is the same frozen at its decision: the fusion differs only with several sensors); the output
says so.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from motionsig_cli.config import ConfigError, in_range, one_of, positive
from motionsig_cli.detection.existence_model import FusionSettings
from motionsig_cli.detection.sprt import CONFIRM, DELETE, first_crossing, freeze_at_decision, wald_thresholds
from motionsig_cli.detection.track_existence import (
    FUSION_METHODS,
    METHODS,
    FusionOptions,
    ScanData,
    SensorModel,
    TrackExistenceModel,
    check_methods,
    run_methods,
)
from motionsig_cli.engine import run_time_limit
from motionsig_cli.errors import InputError
from motionsig_cli.existence import slrt as exp
from motionsig_cli.models.radar import MeasurementModel, cv_model
from motionsig_cli.records import (
    GRID_TOL,
    Record,
    RecordSpec,
    Role,
    parse_columns,
    parse_units,
    read_record,
    uniform_grid,
)
from motionsig_cli.tables import Table, make_meta

__all__ = [
    "DETECTION_SPEC",
    "MAX_DETECTIONS",
    "MAX_SENSORS",
    "MAX_TRACKS",
    "SENSOR_SPEC",
    "Detections",
    "RecordResult",
    "SensorTable",
    "SlrtRecordConfig",
    "detection_table",
    "load",
    "read_sensors",
    "score",
    "sensor_table",
    "split_units",
]

MAX_DETECTIONS = 1_000_000
"""Most rows of a detections file (a longer one is refused while it is read)."""
MAX_SENSORS = 64
"""Most sensors (the filters loop over the sensors in Python; as the simulated scenario)."""
MAX_SCANS = 100_000
"""Most scans of a record (from its first scan to its last), as the simulated scenario."""
MAX_TRACKS = 200
"""Most tentative tracks of the one-point initialisation (detections of the first scan)."""
MAX_OUTPUT_ROWS = 2_000_000
"""Most rows of the per-scan table (tracks × methods × scans)."""
DEFAULT_INIT_SD = (200.0, 50.0)
"""Prior sd (position m, velocity m/s) of an --init track: the simulated scenario's."""
ONE_POINT_VEL_SD = exp.ONE_POINT_VEL_SD
"""Velocity prior sd of a track started from one detection [m/s] (assumed; the simulation's false tracks')."""
KINDS = ("range_bearing", "cartesian")

DETECTION_SPEC = RecordSpec(
    (
        Role("time", ("t", "timestamp"), kind="time", required=False,
             help="scan time: seconds or ISO 8601 (non-decreasing unless there are scan numbers)"),
        Role("scan", ("scan_number",), kind="integer", required=False, order="non-decreasing",
             help="scan number (instead of, or with, the time)"),
        Role("sensor", ("sensor_id", "radar"), kind="label", help="sensor label (of the sensors table)"),
        Role("range", ("r",), quantity="length", required=False, missing=True, help="range from the sensor"),
        Role("bearing", ("phi",), quantity="angle", required=False, missing=True,
             help="bearing from the sensor, counter-clockwise from the x axis"),
        Role("x", ("east",), quantity="length", required=False, missing=True, help="Cartesian x"),
        Role("y", ("north",), quantity="length", required=False, missing=True, help="Cartesian y"),
    ),
    max_rows=MAX_DETECTIONS,
    what="detections file",
    hint="a detections file has time (or scan), sensor, and range,bearing or x,y",
)  # fmt: skip
"""The roles of a detections file."""

SENSOR_SPEC = RecordSpec(
    (
        Role("sensor", ("id", "sensor_id", "name", "radar"), kind="label", help="unique sensor label"),
        Role("x", ("east",), quantity="length", help="sensor position x"),
        Role("y", ("north",), quantity="length", help="sensor position y"),
        Role("sigma_r", (), quantity="length", required=False, help="range noise sd (range-bearing)"),
        Role("sigma_phi", (), quantity="angle", unit="deg", required=False,
             help="bearing noise sd (range-bearing; degrees unless a unit is given)"),
        Role("sigma_xy", (), quantity="length", required=False, help="noise sd per axis (Cartesian)"),
        Role("pd", ("p_d",), help="detection probability the filters assume, in (0, 1]"),
        Role("clutter", ("clutter_rate",), required=False, help="mean false alarms per scan"),
        Role("clutter_density", (), required=False,
             help="false alarms per scan per m·rad (range-bearing) or per m² (Cartesian)"),
        Role("fov", ("fov_range",), quantity="length", help="field-of-view range"),
    ),
    max_rows=MAX_SENSORS,
    what="sensors table",
    hint="a sensors table has sensor, x, y, sigma_r and sigma_phi (or sigma_xy), pd, clutter and fov",
)  # fmt: skip
"""The roles of a sensors table."""

SCAN_RULE = (
    "every sensor of the sensors table scans at every scan from the first row's to the last row's; a sensor "
    "without a row at a scan detected nothing there; a row with empty measurement cells records a scan "
    "without detections"
)
FOV_RULE = "a detection outside its sensor's field of view is refused (not dropped)"
BEARING_CONVENTION = "counter-clockwise from the x axis, atan2(y - y_s, x - x_s), relative to the sensor"
SINGLE_SENSOR = (
    "one sensor: the fusion rules coincide (CKF = FKF = FKF-FB = LKF = LDF, the naive score frozen at its "
    "decision; they differ only with several sensors)"
)
ASSUMPTIONS = (
    "assumed: synchronous scans on a uniform grid, nearly-constant-velocity motion (q), clutter uniform in "
    "each field of view (in measurement space), the track prior"
)


# ------------------------------------------------------------------------------------------ options
@dataclass(frozen=True)
class SlrtRecordConfig(FusionSettings):
    """How a record is scored; every field is checked (:class:`~motionsig_cli.config.ConfigError` naming it).

    Attributes:
        q: acceleration psd q̃ of the filters' motion model [m²/s³], in [0, 10⁶].
        T: the scan period [s] in (0, 3600], or None (from the file).
        init: the track's state [x, ẋ, y, ẏ] one scan period before the first scan, or None (the file's
            metadata ``init``, else one track per detection of the first scan).
        init_sd: prior sd (position m, velocity m/s), two numbers > 0, or None (the rule's default).
        meas: ``range_bearing`` or ``cartesian`` to choose the detections' columns, or None (the file's).
        methods: the fusion methods (as the simulation's).
        lkf_mean, gate_pg, feedback_every, ldf_prior, ldf_weights: the fusion rules' options, the fields of
            :class:`~motionsig_cli.detection.track_existence.FusionOptions` (checked there).
        alpha, beta: Wald's error probabilities, in (0, 0.5) (also the naive rule's local tests').
        stop: freeze each track's score at its decision.

    Examples:
        >>> from motionsig_cli import ConfigError, SlrtRecordConfig
        >>> log_a, log_b = SlrtRecordConfig(alpha=0.01, beta=0.1).thresholds  # Wald's bounds
        >>> round(log_a, 4), round(log_b, 4)  # log(β/(1 − α)), log((1 − β)/α)
        (-2.2925, 4.4998)
        >>> try:
        ...     SlrtRecordConfig(q=-1.0)
        ... except ConfigError as exc:
        ...     print(exc.field, exc.value)
        q -1.0
    """

    q: float = 10.0
    T: float | None = None
    init: tuple[float, ...] | None = None
    init_sd: tuple[float, ...] | None = None
    meas: str | None = None
    methods: tuple[str, ...] = METHODS
    lkf_mean: str = "lr"
    alpha: float = 1e-3
    beta: float = 0.1
    stop: bool = False
    gate_pg: float | None = None
    feedback_every: int = 1
    ldf_prior: float = 0.5
    ldf_weights: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        in_range("q", self.q, 0.0, 1e6, unit="m²/s³")
        if self.T is not None:
            in_range("T", self.T, 0.0, 3600.0, lo_open=True, unit="s")
        if self.init is not None:
            _four("init", self.init)
        if self.init_sd is not None:
            _sd("init_sd", self.init_sd)
        if self.meas is not None:
            one_of("meas", self.meas, KINDS)
        check_methods(self.methods)
        wald_thresholds(self.alpha, self.beta)
        self.options  # noqa: B018 (checks the fusion options)


def _fusion_options(cfg: SlrtRecordConfig) -> dict[str, Any]:
    """The fusion options for the metadata: those a selected rule uses, and any not at its default."""
    out: dict[str, Any] = {}
    defaults = FusionOptions()
    for name, rule in (("gate_pg", None), ("feedback_every", "fkf-feedback"), ("ldf_prior", "ldf"),
                       ("ldf_weights", "ldf")):  # fmt: skip
        if getattr(cfg, name) != getattr(defaults, name) or rule in cfg.methods:
            out[name] = getattr(cfg, name)
    return out


def _four(name: str, v: Sequence[float]) -> None:
    if len(v) != 4:
        raise ConfigError(name, list(v), "is not four numbers x,vx,y,vy (m, m/s)")
    for x in v:
        in_range(name, x)


def _sd(name: str, v: Sequence[float]) -> None:
    if len(v) != 2:
        raise ConfigError(name, list(v), "is not two numbers pos,vel (m, m/s)")
    for x in v:
        positive(name, x)


def split_units(text: str | Mapping[str, str] | None) -> tuple[dict[str, str], dict[str, str]]:
    """``--units`` for both files: (the detections' units, the sensors table's); a role of both files
    (``x``, ``y``) applies to both.

    Raises:
        ConfigError: naming ``units``: a malformed entry, or a role neither file has.
    """
    units = parse_units(text)
    det_roles = [r.name for r in DETECTION_SPEC.roles]
    sen_roles = [r.name for r in SENSOR_SPEC.roles]
    for role in units:
        if role not in det_roles and role not in sen_roles:
            names = ", ".join(dict.fromkeys([*det_roles, *sen_roles]))
            raise ConfigError("units", role, f"is not a column of the detections or sensors ({names})")
    return (
        {k: v for k, v in units.items() if k in det_roles},
        {k: v for k, v in units.items() if k in sen_roles},
    )


# ------------------------------------------------------------------------------------------ sensors
@dataclass(frozen=True)
class SensorTable:
    """A sensors table read for one kind of detections.

    Attributes:
        labels: the sensors' labels, in the table's order (the CKF's update order).
        positions: (S, 2) positions [m].
        models: each sensor's measurement model, p_D and clutter rate.
        lines: the line of each sensor's row.
        record: what was read (provenance).
    """

    labels: tuple[str, ...]
    positions: np.ndarray
    models: tuple[SensorModel, ...]
    lines: tuple[int, ...]
    record: Record

    @property
    def kind(self) -> str:
        return self.models[0].meas.kind

    @property
    def uniform(self) -> bool:
        """All sensors share noise, field of view, p_D and clutter rate."""
        a = self.models[0]
        return all(
            np.array_equal(m.meas.R, a.meas.R)
            and m.meas.fov_range == a.meas.fov_range
            and m.pd == a.pd
            and m.clutter_rate == a.clutter_rate
            for m in self.models[1:]
        )

    def where(self, s: int) -> str:
        return f"{self.record.source}:{self.lines[s]}"

    def describe(self) -> list[dict[str, Any]]:
        """The sensors' values in SI units, for metadata."""
        out = []
        for lab, pos, sm in zip(self.labels, self.positions, self.models, strict=True):
            d: dict[str, Any] = {"sensor": lab, "x_m": float(pos[0]), "y_m": float(pos[1])}
            if sm.meas.kind == "range_bearing":
                d["sigma_r_m"] = math.sqrt(sm.meas.R[0, 0])
                d["sigma_phi_deg"] = math.degrees(math.sqrt(sm.meas.R[1, 1]))
            else:
                d["sigma_xy_m"] = math.sqrt(sm.meas.R[0, 0])
            d |= {"pd": sm.pd, "clutter": sm.clutter_rate, "fov_m": sm.meas.fov_range}
            out.append(d)
        return out


def read_sensors(
    source: Any,
    kind: str,
    *,
    columns: str | Mapping[str, str] | None = None,
    units: str | Mapping[str, str] | None = None,
) -> SensorTable:
    """Read a sensors table (:data:`SENSOR_SPEC`) for detections of ``kind``.

    Raises:
        ConfigError: a bad ``columns`` (named ``sensor_columns``) or ``units`` text.
        InputError: ``file:line: column 'name': …`` for a missing column, a bad or out-of-range value or a
            repeated label.
    """
    one_of("kind", kind, KINDS)
    try:
        rec = read_record(source, SENSOR_SPEC, columns=parse_columns(columns, SENSOR_SPEC), units=units)
    except ConfigError as exc:
        if exc.field == "columns":
            raise ConfigError("sensor_columns", exc.value, exc.reason) from None
        raise
    except InputError as exc:  # this table's columns are mapped by --sensor-columns
        raise InputError(str(exc).replace("--columns ", "--sensor-columns ")) from None
    if len(rec) == 0:
        raise InputError(f"{rec.source}: no sensors (the table has a header and no rows)")
    noise = ("sigma_r", "sigma_phi") if kind == "range_bearing" else ("sigma_xy",)
    for role in noise:
        if not rec.has(role):
            raise _missing(rec, role, f"{kind.replace('_', '-')} detections need it", "--sensor-columns")
    has_rate, has_density = rec.has("clutter"), rec.has("clutter_density")
    if has_rate == has_density:
        if has_rate:
            raise rec.error(None, None, "has both 'clutter' and 'clutter_density': give one")
        raise _missing(rec, "clutter", "or 'clutter_density'", "--sensor-columns")
    labels = [str(v) for v in rec["sensor"]]
    first: dict[str, int] = {}
    for i, lab in enumerate(labels):
        if lab in first:
            raise rec.error(
                i, "sensor", f"sensor {lab!r} is listed twice (first at line {rec.lines[first[lab]]})"
            )
        first[lab] = i
    models = []
    for i in range(len(rec)):
        models.append(_sensor_model(rec, i, kind, has_rate))
    return SensorTable(
        tuple(labels),
        np.stack([rec["x"], rec["y"]], axis=-1),
        tuple(models),
        tuple(int(v) for v in rec.lines),
        rec,
    )


def _sensor_model(rec: Record, i: int, kind: str, has_rate: bool) -> SensorModel:
    """Row ``i``'s model; each value checked like the simulated scenario's."""

    def value(role: str, lo: float, hi: float, unit: str = "", *, lo_open: bool = False) -> float:
        v = float(rec[role][i])
        try:  # an angle is checked in degrees
            in_range(role, math.degrees(v) if unit == "deg" else v, lo, hi, lo_open=lo_open, unit=unit)
        except ConfigError as exc:
            raise rec.error(i, role, exc.detail) from None
        return v

    if kind == "range_bearing":
        sr = value("sigma_r", 1e-3, 1e5, "m")
        sphi = value("sigma_phi", 1e-6, 90.0, "deg")
        R = np.diag([sr**2, sphi**2])
    else:
        sxy = value("sigma_xy", 1e-3, 1e5, "m")
        R = np.diag([sxy**2, sxy**2])
    fov = value("fov", 0.0, 1e9, "m", lo_open=True)
    pd = value("pd", 0.0, 1.0, lo_open=True)
    meas = MeasurementModel(kind, R, fov)
    if has_rate:
        rate = value("clutter", 0.0, 1000.0)
    else:
        rate = value("clutter_density", 0.0, math.inf) * meas.fov_volume
        if rate > 1000.0:
            raise rec.error(
                i,
                "clutter_density",
                f"means {rate:.6g} false alarms per scan in the field of view (at most 1000)",
            )
    if pd == 1.0 and rate > 0:
        raise rec.error(
            i, "pd", "p_D = 1 is only meaningful without clutter (clutter 0), as in the simulation"
        )
    return SensorModel(meas, pd, rate)


def _missing(rec: Record, role: str, why: str, option: str = "--columns") -> InputError:
    cols = ", ".join(rec.table.columns) if rec.table is not None else ""
    return rec.error(
        None, None, f"missing column {role!r} ({why}): columns are {cols}; map one with {option} {role}=NAME"
    )


# ------------------------------------------------------------------------------------------ detections
@dataclass(frozen=True)
class Detections:
    """A detections file on its scan grid.

    Attributes:
        kind: ``range_bearing`` or ``cartesian``.
        T: scan period [s]; ``T_source``: where it came from.
        times: (K,) the scans' times [s] (the file's; seconds after ``record.time_origin`` for timestamps;
            scan index × T without a time column).
        z: (N, 2) the detections (SI units), sorted by scan, then sensor, then file order.
        scan, sensor, line: (N,) each detection's scan index (0-based), sensor index and file line.
        record: what was read (provenance).
    """

    kind: str
    T: float
    T_source: str
    times: np.ndarray
    z: np.ndarray
    scan: np.ndarray
    sensor: np.ndarray
    line: np.ndarray
    record: Record

    @property
    def n_scans(self) -> int:
        return int(self.times.size)

    def counts(self, n_sensors: int) -> np.ndarray:
        """(K, S) detections per scan and sensor."""
        out = np.zeros((self.n_scans, n_sensors), dtype=np.int64)
        np.add.at(out, (self.scan, self.sensor), 1)
        return out

    def scan_data(self, n_sensors: int, n_tracks: int, first: int = 0) -> list[ScanData]:
        """Scans ``first``… as the filters read them: per sensor (n_tracks, M_s, 2) measurements, the same
        for every track (a read-only broadcast), and their validity mask."""
        counts = self.counts(n_sensors)
        start = np.r_[0, np.cumsum(counts.ravel())].reshape(-1)
        out = []
        for k in range(first, self.n_scans):
            Z, V = [], []
            for s in range(n_sensors):
                a, m = int(start[k * n_sensors + s]), int(counts[k, s])
                Z.append(np.broadcast_to(self.z[a : a + m], (n_tracks, m, 2)))
                V.append(np.ones((n_tracks, m), dtype=bool))
            out.append(ScanData(tuple(Z), tuple(V)))
        return out


def _kind(rec: Record, meas: str | None) -> tuple[str, str, str]:
    """The measurement kind and its two roles: ``--meas``, else the pair of columns the file has."""
    pairs = {"range_bearing": ("range", "bearing"), "cartesian": ("x", "y")}
    present = [k for k, (a, b) in pairs.items() if rec.has(a) or rec.has(b)]
    if meas is None:
        if len(present) == 2:
            raise rec.error(
                None,
                None,
                "has both range,bearing and x,y columns: choose with --meas range-bearing|cartesian",
            )
        if not present:
            raise _missing(rec, "range", "and 'bearing', or 'x' and 'y'")
        meas = present[0]
    a, b = pairs[meas]
    for role in (a, b):
        if not rec.has(role):
            raise _missing(rec, role, f"{meas.replace('_', '-')} detections have {a} and {b}")
    return meas, a, b


def _metadata_number(rec: Record, key: str) -> float | None:
    if key not in rec.meta:
        return None
    v = rec.meta[key]
    if isinstance(v, bool) or not isinstance(v, int | float) or not (math.isfinite(v) and 0 < v <= 3600):
        raise InputError(f"{rec.source}: metadata {key!r} = {v!r} is not a number in (0, 3600] s")
    return float(v)


def _grid(rec: Record, T_given: float | None) -> tuple[np.ndarray, float, str, np.ndarray]:
    """Each row's scan index (0-based), the period, its source, and the scans' times.

    With scan numbers, they are the scans (their times may jitter: a rotating antenna stamps each
    detection when it sees it); the times then give the period by least squares over each scan's first
    time, and each scan its time. Without them, each distinct time is a scan, on a uniform grid
    (:func:`~motionsig_cli.records.uniform_grid`)."""
    T_meta = _metadata_number(rec, "T")
    T, source = (T_given, "--T") if T_given is not None else (T_meta, "the file's metadata 'T'")
    has_time = rec.has("time")
    if rec.has("scan"):
        sc = rec["scan"]
        k = sc - sc[0]
        new = np.r_[True, np.diff(k) > 0]
        first = np.flatnonzero(new)
        if has_time:
            _check_scan_order(rec, first)
            t, kf = rec["time"][first], k[first].astype(float)
            if T is None and first.size > 1:
                dk = kf - kf.mean()
                T = float(np.dot(dk, t - t.mean()) / np.dot(dk, dk))
                source = "estimated from the times of the scan numbers (least squares)"
                if not (math.isfinite(T) and 0 < T <= 3600):
                    raise rec.error(
                        int(first[-1]), "time", f"gives a scan period of {T:.6g} s, not in (0, 3600]"
                    )
            if T is None:
                raise rec.error(0, "time", "all rows share one scan: give the scan period with --T")
            _check_scan_times(rec, k, first, T, source)
        elif T is None:
            T, source = 1.0, "assumed: 1 s (scan numbers without times; give --T)"
        times = (rec["time"][0] if has_time else 0.0) + np.arange(int(k[-1]) + 1) * T
        if has_time:
            times[k[first]] = rec["time"][first]  # the file's own times where it has them
    elif has_time:
        t = rec["time"]
        back = np.flatnonzero(np.diff(t) < 0)
        if back.size:
            i = int(back[0]) + 1
            raise rec.error(i, "time", f"time goes backwards ({t[i]:.9g} s after {t[i - 1]:.9g} s)")
        new = np.r_[True, np.diff(t) > 0]
        first = np.flatnonzero(new)
        u = t[first]
        if u.size == 1:
            if T is None:
                raise rec.error(
                    0, "time", "all rows share one time (one scan): give the scan period with --T"
                )
            k_u = np.zeros(1, dtype=np.int64)
        else:
            if T is None:
                source = "estimated from the time column"
            else:
                _check_span(rec, u, first, T, source)
            k_u, T = uniform_grid(replace(rec, lines=rec.lines[first]), u, T)
        k = k_u[np.cumsum(new) - 1]
        times = u[0] + np.arange(int(k[-1]) + 1) * T
        times[k_u] = u  # the file's own times where it has them
    else:
        raise _missing(rec, "time", "or 'scan'")
    if k[-1] + 1 > MAX_SCANS:
        raise rec.error(
            len(rec) - 1,
            "scan" if rec.has("scan") else "time",
            f"is {int(k[-1]) + 1} scans after the first row's (at most {MAX_SCANS})",
        )
    return k.astype(np.int64), float(T), source, times


def _check_scan_order(rec: Record, first: np.ndarray) -> None:
    """With scan numbers, each scan's time is after the previous scan's: a time that goes backwards or
    repeats from one scan to the next contradicts the scan numbers."""
    t = rec["time"][first]
    bad = np.flatnonzero(np.diff(t) <= 0)
    if bad.size:
        j = int(bad[0]) + 1
        how = "repeats" if t[j] == t[j - 1] else "goes backwards"
        raise rec.error(
            int(first[j]),
            "time",
            f"time {how}: {t[j]:.9g} s at scan {rec['scan'][first[j]]:.0f}, after {t[j - 1]:.9g} s at scan "
            f"{rec['scan'][first[j - 1]]:.0f}",
        )


def _check_scan_times(rec: Record, k: np.ndarray, first: np.ndarray, T: float, source: str) -> None:
    """With scan numbers and times, every row's time lies within one period of its scan's point on the
    grid of period T (a rotating antenna stamps a detection anywhere in its scan; the times may jitter so,
    not contradict T): a period that contradicts the times (the
    metadata's ``T: 1e-300`` beside rows 1 s apart) or a time that jumps (a century) is refused, naming
    both values."""
    t = rec["time"]
    kf = k.astype(float)
    phase = float(np.median(t[first] - kf[first] * T))
    off = np.abs(t - phase - kf * T)
    bad = np.flatnonzero(~(off <= T))
    if not bad.size:
        return
    i = int(bad[0])
    implied = ""
    if first.size > 1:
        dk = kf[first] - kf[first].mean()
        tf = t[first]
        est = float(np.dot(dk, tf - tf.mean()) / np.dot(dk, dk))
        implied = f"; the scans' times give a period of {est:.6g} s"
    raise rec.error(
        i,
        "time",
        f"time {t[i]:.9g} s at scan {rec['scan'][i]:.0f} is {off[i] / T:.3g} periods off the grid of the "
        f"period T = {T:.6g} s ({source}){implied}: the period and the times contradict each other",
    )


def _check_span(rec: Record, u: np.ndarray, first: np.ndarray, T: float, source: str) -> None:
    """A given period under which the times would span more than :data:`MAX_SCANS` scans contradicts
    them (``T: 1e-300`` beside rows 1 s apart), and so does one longer than the shortest step."""
    steps = np.diff(u)
    i = int(np.argmin(steps)) + 1
    if steps[i - 1] < (1 - GRID_TOL) * T:
        raise rec.error(
            int(first[i]),
            "time",
            f"the period T = {T:.6g} s ({source}) contradicts the times: {u[i]:.9g} s is {steps[i - 1]:.6g} s "
            f"after {u[i - 1]:.9g} s",
        )
    span = float(u[-1] - u[0])
    if span / T + 1 > MAX_SCANS:
        step = float(np.min(steps))
        raise rec.error(
            int(first[-1]),
            "time",
            f"the period T = {T:.6g} s ({source}) contradicts the times ({step:.6g} s apart at the least): "
            f"they would span {span / T + 1:.3g} scans (at most {MAX_SCANS})",
        )


def read_detections(
    source: Any,
    sensors_of: Any,
    *,
    columns: str | Mapping[str, str] | None = None,
    units: str | Mapping[str, str] | None = None,
    meas: str | None = None,
    T: float | None = None,
) -> tuple[Detections, SensorTable]:
    """Read a detections file (:data:`DETECTION_SPEC`) and, through ``sensors_of(kind)``, its sensors table.

    Raises:
        ConfigError: a bad ``columns`` or ``units`` text.
        InputError: ``file:line: column 'name': …`` (see the module docstring for every rule).
    """
    rec = read_record(source, DETECTION_SPEC, columns=columns, units=units)
    if len(rec) == 0:
        raise InputError(f"{rec.source}: no detections (the file has a header and no rows)")
    kind, ra, rb = _kind(rec, meas)
    sensors: SensorTable = sensors_of(kind)
    index = {lab: s for s, lab in enumerate(sensors.labels)}
    labels = rec["sensor"]
    s_row = np.empty(len(rec), dtype=np.int64)
    for i, lab in enumerate(labels):
        s = index.get(lab)
        if s is None:
            raise rec.error(
                i,
                "sensor",
                f"sensor {lab!r} is not in the sensors table {sensors.record.source} ({_some(sensors.labels)})",
            )
        s_row[i] = s
    a, b = rec[ra], rec[rb]
    na, nb = np.isnan(a), np.isnan(b)
    half = np.flatnonzero(na != nb)
    if half.size:
        i = int(half[0])
        gone, there = (ra, rb) if na[i] else (rb, ra)
        raise rec.error(
            i,
            gone,
            f"missing while {there!r} has a value (a detection has both; a scan without one, neither)",
        )
    det = np.flatnonzero(~na)
    z = np.stack([a[det], b[det]], axis=-1)
    _check_fov(rec, sensors, kind, (ra, rb), det, z, s_row[det])
    k, T, T_source, times = _grid(rec, T)
    order = np.lexsort((s_row[det], k[det]))  # stable: file order within a scan and sensor
    det = det[order]
    return (
        Detections(kind, T, T_source, times, z[order], k[det], s_row[det], rec.lines[det], rec),
        sensors,
    )


def _some(labels: Sequence[str], n: int = 8) -> str:
    """The first ``n`` labels, and how many there are in all when there are more."""
    more = f", … ({len(labels)} in all)" if len(labels) > n else ""
    return ", ".join(labels[:n]) + more


def _check_fov(
    rec: Record,
    sensors: SensorTable,
    kind: str,
    roles: tuple[str, str],
    rows: np.ndarray,
    z: np.ndarray,
    s_row: np.ndarray,
) -> None:
    """Refuse the first detection outside its sensor's field of view, naming its line and column."""
    fov = np.array([m.meas.fov_range for m in sensors.models])[s_row]

    def refuse(mask: np.ndarray, c: int, what: str) -> None:
        if mask.any():
            j = int(np.flatnonzero(mask)[0])
            s = int(s_row[j])
            raise rec.error(
                int(rows[j]),
                roles[c],
                what.format(v=z[j, c], fov=fov[j])
                + f" of sensor {sensors.labels[s]!r} ({sensors.where(s)}): refused (check the unit or the fov)",
            )

    if kind == "range_bearing":
        refuse(z[:, 0] < 0, 0, "range {v:.9g} m is negative: outside the field of view")
        refuse(z[:, 0] > fov, 0, "range {v:.9g} m is beyond the field of view ({fov:.9g} m)")
        refuse(
            np.abs(z[:, 1]) > 2 * math.pi,
            1,
            "bearing {v:.9g} rad is beyond ±2π (degrees read as radians? state 'bearing [deg]' or "
            "--units bearing=deg), outside the field of view",
        )
    else:
        d = np.abs(z - sensors.positions[s_row])
        for c in (0, 1):
            refuse(
                d[:, c] > fov,
                c,
                roles[c] + " {v:.9g} m is further than the field of view ({fov:.9g} m) from the position",
            )


# ------------------------------------------------------------------------------------------ the record
@dataclass(frozen=True)
class Tracks:
    """The tracks to score: initial means (R, 4) and prior covariance (4, 4) or (R, 4, 4), the first
    scored scan, the rule, and each track's start (sensor label and line, or None for --init)."""

    m0: np.ndarray
    cov: np.ndarray
    first: int
    rule: str
    sd: list[float] | str
    starts: list[tuple[str | None, int | None]]


def _prior(sd: Sequence[float]) -> np.ndarray:
    p, v = sd
    return np.diag([p * p, v * v, p * p, v * v])


def _tracks(det: Detections, sensors: SensorTable, cfg: SlrtRecordConfig) -> Tracks:
    rec = det.record
    meta_init = rec.meta.get("init")
    meta_sd = rec.meta.get("init_sd")
    sd_given: tuple[float, ...] | None = cfg.init_sd
    if sd_given is None and meta_sd is not None:
        sd_given = _meta_vector(rec, "init_sd", meta_sd, 2)
    if cfg.init is not None or meta_init is not None:
        if cfg.init is not None:
            init, rule = cfg.init, "--init: the state one scan period before the first scan"
        else:
            init = _meta_vector(rec, "init", meta_init, 4)
            rule = "the file's metadata 'init': the state one scan period before the first scan"
        sd = tuple(sd_given) if sd_given is not None else DEFAULT_INIT_SD
        return Tracks(
            np.asarray(init, dtype=float)[None, :],
            _prior(sd),
            0,
            rule,
            [float(v) for v in sd],
            [(None, None)],
        )
    if det.z.shape[0] == 0:
        raise InputError(f"{rec.source}: no detection to start a track from: give --init x,vx,y,vy")
    k0 = int(det.scan[0])
    sel = np.flatnonzero(det.scan == k0)
    if k0 + 1 >= det.n_scans:
        raise InputError(
            f"{rec.source}:{det.line[sel[0]]}: no scan after the first with detections (scan {k0 + 1}) to "
            "score a track started there: give --init x,vx,y,vy"
        )
    if sel.size > MAX_TRACKS:
        raise InputError(
            f"{rec.source}: the first scan with detections has {sel.size} (more than {MAX_TRACKS} tentative "
            "tracks): give --init x,vx,y,vy"
        )
    s_idx = det.sensor[sel]
    z = det.z[sel]
    meas = sensors.models[
        int(s_idx[0])
    ].meas  # the kind and the conversion to x-y; the noise per detection below
    xy = exp.to_xy(meas, z, sensors.positions[s_idx])
    how = "the larger of sigma_r and r*sigma_phi" if det.kind == "range_bearing" else "sigma_xy"
    m0 = np.zeros((sel.size, 4))
    m0[:, 0], m0[:, 2] = xy[:, 0], xy[:, 1]
    if sd_given is not None:
        cov, sd = _prior(sd_given), [float(v) for v in sd_given]
    else:
        cov = exp.one_point_cov(meas, z, np.stack([sensors.models[s].meas.R for s in s_idx]))
        sd = f"position: {how} of the detection's sensor; velocity: {ONE_POINT_VEL_SD:g} m/s (assumed)"
    starts = [(sensors.labels[s], int(ln)) for s, ln in zip(s_idx, det.line[sel], strict=True)]
    rule = (
        f"one tentative track per detection of scan {k0 + 1} (the first with detections): position the "
        "detection's, velocity 0; scored from the next scan"
    )
    return Tracks(m0, cov, k0 + 1, rule, sd, starts)


def _meta_vector(rec: Record, key: str, value: Any, n: int) -> tuple[float, ...]:
    ok = isinstance(value, list) and len(value) == n
    ok = ok and all(
        isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) for v in value
    )
    if ok and n == 2:
        ok = all(v > 0 for v in value)
    if not ok:
        what = "[x, vx, y, vy]" if n == 4 else "[pos, vel] (> 0)"
        raise InputError(f"{rec.source}: metadata {key!r} = {value!r} is not {n} finite numbers {what}")
    return tuple(float(v) for v in value)


@dataclass(frozen=True)
class SlrtRecord:
    """A record ready to score: its detections, its sensors and the filters' model."""

    detections: Detections
    sensors: SensorTable

    @property
    def n_sensors(self) -> int:
        return len(self.sensors.labels)


def load(
    detections: Any,
    sensors: Any,
    cfg: SlrtRecordConfig,
    *,
    columns: str | Mapping[str, str] | None = None,
    sensor_columns: str | Mapping[str, str] | None = None,
    units: str | Mapping[str, str] | None = None,
) -> SlrtRecord:
    """Read the detections file and the sensors table (``units`` for both, :func:`split_units`)."""
    det_units, sen_units = split_units(units)
    sensor_columns_map = _sensor_columns(sensor_columns)
    det, table = read_detections(
        detections,
        lambda kind: read_sensors(sensors, kind, columns=sensor_columns_map, units=sen_units),
        columns=columns,
        units=det_units,
        meas=cfg.meas,
        T=cfg.T,
    )
    return SlrtRecord(det, table)


def _sensor_columns(text: str | Mapping[str, str] | None) -> dict[str, str]:
    try:
        return parse_columns(text, SENSOR_SPEC)
    except ConfigError as exc:
        raise ConfigError("sensor_columns", exc.value, exc.reason) from None


def score(record: SlrtRecord, cfg: SlrtRecordConfig) -> RecordResult:
    """Every method's log LR per scan for each track, on the record's data.

    Raises:
        InputError: a record whose scoring would take more than :data:`~motionsig_cli.existence.slrt.
            MAX_SECONDS` (the simulation's cost model), or whose per-scan table would be too long.
    """
    det, sensors = record.detections, record.sensors
    S, K = record.n_sensors, det.n_scans
    tracks = _tracks(det, sensors, cfg)
    R = tracks.m0.shape[0]
    scored = K - tracks.first
    counts = det.counts(S)
    mean_m = float(counts[tracks.first :].mean()) if scored else 0.0
    stand_in = replace(
        exp.SlrtScenario(), n_sensors=S, scans=max(scored, 1), clutter_rate=min(mean_m, 1000.0)
    )
    seconds, limit = exp.cost(stand_in, R)[0], run_time_limit(exp.MAX_SECONDS)
    if seconds > limit:
        raise InputError(
            f"{det.record.source}: {scored} scans x {S} sensors x {R} track(s) would take about {seconds:.0f} s "
            f"(the limit is {limit:.0f} s): split the file, give --init for one track or raise the limit "
            "(--max-minutes)"
        )
    F, Q = cv_model(det.T, cfg.q)
    first = sensors.models[0]
    model = TrackExistenceModel(
        F,
        Q,
        sensors.positions,
        first.meas,
        first.pd,
        first.clutter_rate,
        tracks.cov,
        () if sensors.uniform else sensors.models,
    )
    scans = det.scan_data(S, R, tracks.first)
    scores = run_methods(model, tracks.m0, scans, cfg.methods, options=cfg.options)
    for m, v in scores.items():
        if np.any(np.isnan(v) | (v == np.inf)):
            raise RuntimeError(f"NaN or +inf log LR ({m})")
        if cfg.stop:
            scores[m] = freeze_at_decision(v, *cfg.thresholds)
    return RecordResult(record, cfg, tracks, scores, counts)


RECORD_SCAN_COLUMNS = ("track", "method", "scan", "time", "detections", "log_lr", "decision")
RECORD_DECISION_COLUMNS = (
    "track",
    "method",
    "decision",
    "decision_scan",
    "decision_time",
    "decision_log_lr",
    "last_scan",
    "last_log_lr",
    "start_sensor",
    "start_line",
    "start_x",
    "start_y",
)
DECISION_WORDS = {CONFIRM: "confirmed", DELETE: "deleted", 0: "undecided"}


@dataclass(frozen=True)
class RecordResult:
    """The scores of a record: per method, log LR (tracks × scored scans)."""

    record: SlrtRecord
    config: SlrtRecordConfig
    tracks: Tracks
    scores: dict[str, np.ndarray]
    counts: np.ndarray

    @property
    def scan_index(self) -> np.ndarray:
        """0-based indices of the scored scans."""
        return np.arange(self.tracks.first, self.record.detections.n_scans)

    def decisions(self, method: str) -> tuple[np.ndarray, np.ndarray]:
        """Wald's first-crossing decision per track and the index (into the scored scans) it was taken
        at (−1: undecided)."""
        d = first_crossing(self.scores[method], *self.config.thresholds)
        return d.decision, np.where(d.decision != 0, d.time - 1, -1)

    def table(self, view: str) -> Table:
        """``curves``: per track, method and scan, log LR and the test's state; ``decisions``: per track
        and method, Wald's decision."""
        one_of("view", view, ("curves", "decisions"))
        if view == "curves":
            rows = self.scan_rows()
            return Table(RECORD_SCAN_COLUMNS, rows, self.meta(view))
        return Table(RECORD_DECISION_COLUMNS, self.decision_rows(), self.meta(view))

    def scan_rows(self) -> list[tuple[Any, ...]]:
        det = self.record.detections
        ks = self.scan_index
        n = self.tracks.m0.shape[0] * len(self.scores) * ks.size
        if n > MAX_OUTPUT_ROWS:
            raise InputError(
                f"{det.record.source}: the per-scan table would have {n} rows (more than {MAX_OUTPUT_ROWS}): "
                "use --view decisions, fewer --methods, or --init for one track"
            )
        per_scan = self.counts.sum(axis=1)
        rows: list[tuple[Any, ...]] = []
        decided = {m: self.decisions(m) for m in self.scores}
        for r in range(self.tracks.m0.shape[0]):
            for m, v in self.scores.items():
                dec, at = decided[m]
                for j, k in enumerate(ks):
                    state = DECISION_WORDS[int(dec[r])] if 0 <= at[r] <= j else "undecided"
                    rows.append(
                        (r + 1, m, int(k) + 1, float(det.times[k]), int(per_scan[k]), float(v[r, j]), state)
                    )
        return rows

    def decision_rows(self) -> list[tuple[Any, ...]]:
        det = self.record.detections
        ks = self.scan_index
        rows: list[tuple[Any, ...]] = []
        decided = {m: self.decisions(m) for m in self.scores}
        for r, (sensor, line) in enumerate(self.tracks.starts):
            x, y = float(self.tracks.m0[r, 0]), float(self.tracks.m0[r, 2])
            for m, v in self.scores.items():
                dec, at = decided[m]
                j = int(at[r])
                k = int(ks[j]) if j >= 0 else None
                rows.append((
                    r + 1, m, DECISION_WORDS[int(dec[r])], None if k is None else k + 1,
                    None if k is None else float(det.times[k]), None if j < 0 else float(v[r, j]),
                    int(ks[-1]) + 1, float(v[r, -1]), sensor, line, x, y,
                ))  # fmt: skip
        return rows

    def meta(self, view: str) -> dict[str, Any]:
        det, sensors, cfg, tr = self.record.detections, self.record.sensors, self.config, self.tracks
        log_a, log_b = cfg.thresholds
        S = self.record.n_sensors
        silent = [lab for s, lab in enumerate(sensors.labels) if self.counts[:, s].sum() == 0]
        sen_prov = sensors.record.provenance()
        return make_meta(
            "slrt",
            view=view,
            detections=det.record.provenance(),
            sensor_table={"input": sen_prov["input"], "input_columns": sen_prov["input_columns"],
                          "input_units": sen_prov.get("input_units", {})},
            measurement=det.kind,
            bearing=BEARING_CONVENTION if det.kind == "range_bearing" else None,
            scans=det.n_scans,
            scored_scans=int(self.scan_index.size),
            T=det.T,
            T_source=det.T_source,
            scan_rule=SCAN_RULE,
            fov_rule=FOV_RULE,
            sensors=sensors.describe(),
            per_sensor_values=not sensors.uniform,
            silent_sensors=silent or None,
            single_sensor=SINGLE_SENSOR if S == 1 else None,
            q=cfg.q,
            motion_model="nearly constant velocity, state [x, vx, y, vy]",
            init={"rule": tr.rule, "sd": tr.sd, "tracks": int(tr.m0.shape[0]),
                  "state": [float(v) for v in tr.m0[0]] if tr.starts[0][0] is None else None},
            methods=list(cfg.methods),
            lkf_mean=cfg.lkf_mean,
            **{m: FUSION_METHODS[m].metadata for m in cfg.methods if FUSION_METHODS[m].metadata},
            **_fusion_options(cfg),
            sprt={"alpha": cfg.alpha, "beta": cfg.beta, "log_A": log_a, "log_B": log_b, "rule": "first crossing"},
            stop=cfg.stop,
            minus_inf="a log LR of -inf means a sensor with p_D = 1 saw nothing: the track is impossible",
            assumptions=ASSUMPTIONS,
        )  # fmt: skip

    def notes(self) -> list[str]:
        """Lines for stderr: the single-sensor coincidence, sensors that never detected, the summary."""
        out = []
        if self.record.n_sensors == 1:
            out.append(f"slrt: {SINGLE_SENSOR}")
        sensors = self.record.sensors
        silent = [lab for s, lab in enumerate(sensors.labels) if self.counts[:, s].sum() == 0]
        if silent:
            out.append(
                f"slrt: sensor(s) {', '.join(silent)} reported nothing in the whole file: they count as scanning "
                "and missing every scan (remove them from the sensors table if they were off)"
            )
        out.append(self.summary())
        return out

    def summary(self) -> str:
        det = self.record.detections
        R = self.tracks.m0.shape[0]
        parts = []
        for m in self.scores:
            dec, at = self.decisions(m)
            if R == 1:
                j = int(at[0])
                word = DECISION_WORDS[int(dec[0])]
                parts.append(f"{m} {word}" + (f" at scan {int(self.scan_index[j]) + 1}" if j >= 0 else ""))
            else:
                conf = [str(r + 1) for r in np.flatnonzero(dec == CONFIRM)]
                parts.append(
                    f"{m}: {len(conf)} confirmed" + (f" (track {', '.join(conf[:10])})" if conf else "")
                    + f", {int((dec == DELETE).sum())} deleted, {int((dec == 0).sum())} undecided"
                )  # fmt: skip
        return (
            f"slrt: {det.record.source}: {self.record.n_sensors} sensor(s), {det.n_scans} scans, "
            f"{det.z.shape[0]} detections, {R} track(s): " + "; ".join(parts)
        )

    def panels(self, limit: int = 4) -> list[tuple[str, np.ndarray, dict[str, tuple[np.ndarray, ...]]]]:
        """Up to ``limit`` tracks for the figure (confirmed ones first, then by the last score of the
        first method): (title, scans, {method: (log LR, log LR, log LR)})."""
        m1 = next(iter(self.scores))
        dec, _ = self.decisions(m1)
        last = self.scores[m1][:, -1]
        order = sorted(range(len(dec)), key=lambda r: (dec[r] != CONFIRM, -last[r], r))[:limit]
        k = self.scan_index + 1
        out = []
        for r in order:
            sensor, line = self.tracks.starts[r]
            title = f"track {r + 1}" + (
                f" (from {sensor}, line {line})" if sensor is not None else " (--init)"
            )
            out.append((title, k, {m: (v[r], v[r], v[r]) for m, v in self.scores.items()}))
        return out


# ------------------------------------------------------------------------------------------ writing a run
def _first_case(study: exp.SlrtStudy) -> tuple[str, exp.SlrtScenario, exp.Generated]:
    label, sc = study.cases[0]
    return label, sc, exp.generate(sc, range(1), study.seed)


def sensor_label(s: int) -> str:
    """The label of simulated sensor ``s`` (0-based)."""
    return f"radar{s + 1}"


def detection_table(study: exp.SlrtStudy) -> Table:
    """Run 0 of the study's first case as a detections file: one row per detection (the target's first in
    each sensor's list, then the false alarms; ``origin`` says which, ``truth_x``, ``truth_y`` where the
    target is), a row with empty measurement cells for a sensor and scan without detections, full-precision
    floats; the metadata carries the scan period
    ``T`` and the run's initial track (``init``, ``init_sd``), so that ``--input`` scores the same run."""
    label, sc, gen = _first_case(study)
    polar = sc.meas_model == "range_bearing"
    cols = (
        "scan",
        "time",
        "sensor",
        *(("range [m]", "bearing [rad]") if polar else ("x [m]", "y [m]")),
        "origin",
        "truth_x [m]",
        "truth_y [m]",
    )
    rows: list[tuple[Any, ...]] = []
    for k in range(sc.scans):
        t = (k + 1) * sc.T
        truth = (float(gen.truth[0, k, 0]), float(gen.truth[0, k, 2]))
        for s in range(sc.n_sensors):
            z = gen.scans[k].Z[s][0][gen.scans[k].valid[s][0]]
            n_t = len(z) - int(gen.clutter_counts[0, k, s])
            if len(z) == 0:
                rows.append((k + 1, t, sensor_label(s), None, None, "", *truth))
            for j, (a, b) in enumerate(z):
                origin = "target" if j < n_t else "clutter"
                rows.append((k + 1, t, sensor_label(s), float(a), float(b), origin, *truth))
    meta = make_meta(
        "slrt",
        view="detections",
        case=label,
        run=0,
        seed=study.seed,
        T=sc.T,
        init=[float(v) for v in gen.m0[0]],
        init_sd=list(sc.p0_sd),
        init_note="init: the run's initial track mean one scan period before scan 1 (drawn around x0)",
        scenario={"n_sensors": sc.n_sensors, "radius": sc.radius, "target": sc.target, "pd_true": sc.pd_true,
                  "clutter_rate": sc.clutter_rate, "q": sc.q, "T": sc.T, "scans": sc.scans, "x0": list(sc.x0),
                  "meas_model": sc.meas_model},
        read_back="motionsig slrt --input THIS --sensor-table SENSORS (with the same --q, --methods, --lkf-mean)",
        scan_rule=SCAN_RULE,
    )  # fmt: skip
    return Table(cols, rows, meta)


def sensor_table(study: exp.SlrtStudy) -> Table:
    """The study's sensors as a sensors table, with the p_D the first case's filters assume."""
    label, sc = study.cases[0]
    polar = sc.meas_model == "range_bearing"
    noise = ("sigma_r [m]", "sigma_phi [deg]") if polar else ("sigma_xy [m]",)
    cols = ("sensor", "x [m]", "y [m]", *noise, "pd", "clutter", "fov [m]")
    rows = []
    for s, (x, y) in enumerate(sc.sensors):
        sig = (sc.sigma_r, sc.sigma_phi_deg) if polar else (sc.sigma_r,)
        rows.append((sensor_label(s), float(x), float(y), *sig, sc.pd_filter, sc.clutter_rate, sc.fov_range))
    meta = make_meta("slrt", view="sensors", case=label, note="pd: the p_D the filters of this case assume")
    return Table(cols, rows, meta)
