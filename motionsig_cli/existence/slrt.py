"""The track-existence scenario of Govaers, *Evaluation of Distributed Detection Methods for Agile Targets*
(Fraunhofer FKIE, slides), and its Monte Carlo: S radars on a circle, a nearly-constant-velocity target, an
agile one (coordinated turns and longitudinal accelerations at stated scans, :class:`SlrtScenario`), or none,
Poisson clutter uniform in each field of view, and the track-existence scores of
:data:`~motionsig_cli.detection.track_existence.FUSION_METHODS`.

Run r draws only from ``trial_rng(seed, r)`` (truth, detections, clutter, the initial track draw), so a
result does not depend on the number of runs or on their order.

The command's experiment is a :class:`SlrtStudy` (target cases at several p_D and no-target cases, the runs,
Wald's test). A no-target case is run as a tracker runs it (:func:`false_tracks`): every detection of scan 1
starts a tentative track, one-point initialised, scored from scan 2 on the clutter that follows, so its rates
are over false tracks; :meth:`SlrtResult.oc_rows` sweeps Wald's thresholds over a grid to give the operating
characteristics (false-track confirmation against true-track confirmation and deletion), and
:meth:`SlrtResult.matched_rows` compares the schemes at equal error rates.

Its Monte Carlo, :meth:`SlrtStudy.job`, is a :class:`SlrtJob` for the engine
(:class:`motionsig_cli.engine.MonteCarloJob`): tasks are chunks of consecutive runs of one case, sized from
:func:`cost` only (never from the worker count), and joined in task order, so the scores are the same on
1 worker, N workers or Dask. :meth:`SlrtStudy.result` turns the scores into the per-scan curves or Wald's
decisions (:class:`SlrtResult`: tables, figure panels, a summary line).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of, positive
from motionsig_cli.detection.existence_model import FusionSettings
from motionsig_cli.detection.sprt import (
    Decisions,
    first_crossing,
    freeze_at_decision,
    wald_thresholds,
)
from motionsig_cli.detection.track_existence import (
    FUSION_METHODS,
    METHODS,
    FusionOptions,
    ScanData,
    TrackExistenceModel,
    check_applicable,
    check_methods,
    run_methods,
)
from motionsig_cli.engine import check_run_time, tasks_of, trials_per_task
from motionsig_cli.models.radar import MeasurementModel, cv_model, wrap_angle
from motionsig_cli.rng import DEFAULT_SEED, trial_rng
from motionsig_cli.tables import Table, make_meta

__all__ = [
    "MATCHED_RATES",
    "OC_LOG_A",
    "OC_LOG_B",
    "ONE_POINT_VEL_SD",
    "VIEWS",
    "FalseTracks",
    "SlrtJob",
    "SlrtResult",
    "SlrtScenario",
    "SlrtStudy",
    "clopper_pearson",
    "cost",
    "decisions",
    "false_tracks",
    "generate",
    "lost_after_confirmation",
    "one_point_cov",
    "run",
    "scan_picture",
    "scan_xy",
    "score_case",
    "summarise",
    "to_xy",
]

MAX_SECONDS = 240.0
"""Largest estimated run time :class:`SlrtStudy` accepts (:func:`cost`)."""
MAX_BYTES = 2 * 1024**3
"""Largest estimated memory for the generated measurements."""
DRAWS = "blocks"
"""How :func:`generate` orders a run's draws, in a checkpoint's manifest: ``blocks`` (the initial track and
per-scan noise normals, the detection uniforms, the false-alarm counts, their positions). The order of the
scan-by-scan loop before it gave other numbers from the same streams; a checkpoint written with it (no
``draws`` in its manifest) is refused instead of mixing its runs with these."""
MAX_PD_CASES = 10
"""Most target cases (distinct p_D values) of one study."""
MEAS_MODELS = ("range_bearing", "cartesian")
TARGET_MOTIONS = ("cv", "agile")
"""The target's motion: nearly constant velocity, or agile (manoeuvres at stated scans, :class:`SlrtScenario`)."""
G0 = 9.80665
"""Standard gravity [m/s²], to state accelerations in g."""
MAX_MANEUVERS = 100
"""Most turn (or acceleration) windows of one scenario."""
VIEWS = ("curves", "decisions", "study", "oc", "matched")
"""The tables of :meth:`SlrtResult.table`: per-scan statistics of log LR, Wald's decisions, the study's
comparison (rates with standard errors and confidence intervals against Wald's bounds, ASN, mean scores), the
operating characteristics over a grid of thresholds (false-track confirmation against true-track confirmation
and deletion), or the schemes compared at equal error rates."""
OC_LOG_B = tuple(0.5 * k for k in range(1, 29))
"""The confirmation thresholds log B of the operating-characteristic grid: 0.5 to 14 in steps of 0.5."""
OC_LOG_A = tuple(-0.5 * k for k in range(1, 21))
"""The deletion thresholds log A of the grid: −0.5 to −10 in steps of 0.5."""
MATCHED_RATES = ((1e-3, 0.01), (1e-2, 0.05))
"""The (false-track confirmation, true-track deletion) rates at which the ``matched`` view compares the schemes."""
OC_NOTE = (
    "operating characteristics: per threshold pair (log_A, log_B) of the grid (Wald's design alpha = (1 - A)/(B - A), "
    "beta = A(B - 1)/(B - A) beside it), the first crossing on the false tracks of the no-target case with the same "
    "filter p_D (false_confirmed, exact 95 % interval) and on the target runs (target_confirmed, target_deleted "
    "with exact intervals); asn: mean decision scan of the decided rows; rules whose score depends on the "
    "thresholds (naive) are left out; false tracks of one run share its clutter, so the binomial intervals assume "
    "their weak dependence away"
)
MATCHED_NOTE = (
    "each scheme at the threshold pair of the grid with false_confirmed <= reference_false and target_deleted <= "
    "reference_deleted that confirms the most targets within the scans, then the one deciding them soonest "
    "(target_asn); None: no pair of the grid meets both"
)


ASSUMPTIONS = (
    "assumed: measurement model, noise, field of view, scan period, sensor angles, initial track and "
    "thresholds (the slides do not give them)"
)


AGILE_NOTE = (
    "agile target: the white-noise acceleration q plus, at the stated scans, coordinated turns (exact circular "
    "arcs; rate > 0 turns left) and longitudinal accelerations along the velocity; scan k is reached from scan "
    "k-1 by one transition; g = rate x speed / 9.80665 at the window's noise-free start speed; assumed (the "
    "slides give no manoeuvre)"
)
FALSE_TRACK_NOTE = (
    "no-target cases: one tentative track per detection of scan 1 (clutter, every sensor), position the "
    "detection's, velocity 0, position sd max(sigma_r, r sigma_phi) (or sigma_xy), velocity sd 150 m/s (assumed); "
    "log LR 0 at scan 1, scored from scan 2; rates are over the false tracks (the tracks column)"
)
STUDY_NOTE = (
    "rates are fractions of the runs with binomial standard errors sqrt(p(1-p)/n); error_rate_lo95..hi95 is "
    "the exact (Clopper-Pearson) 95 % interval; lost = confirmed, then the score fell by log B - log A below its "
    "running maximum (assumed track-maintenance test); asn is the mean decision scan of the decided runs (undecided "
    "ones left out); asn_wald = (P_c log B + P_d log A) / mean_increment with the design (1-beta, beta) or "
    "(alpha, 1-alpha), overshoot neglected; mean_increment = mean log LR(K) / K before any freezing; "
    "wald_design = beta (target) or alpha (no target); wald_bound = beta/(1-alpha) or alpha/(1-beta)"
)


@dataclass(frozen=True)
class SlrtScenario:
    """One case of the slides' scenario. The slides give the geometry (radars on a circle of about 13 km),
    the target's motion, clutter and the p_D values; every other value is our assumption, and a field.

    Attributes:
        n_sensors: radars on a circle of radius ``radius`` m at equally spaced azimuths from 0°.
        target: a target is present (h1) or only clutter (h0).
        pd_true: detection probability of the data; ``pd_filter``: the one the filters assume.
        clutter_rate: mean false alarms per sensor per scan (λ_F).
        sigma_r, sigma_phi_deg: range–bearing noise (m, degrees); Cartesian sensors use σ_r on both axes.
        meas_model: ``range_bearing`` or ``cartesian``.
        q: acceleration psd q̃ [m²/s³] of the truth (white-noise acceleration; the slides' "psd = 10"); T: scan
            period [s]; scans: number of scans.
        x0: truth initial state [x, ẋ, y, ẏ]; p0_sd: track prior standard deviations (position, velocity).
        fov_range: field-of-view radius [m].
        target_motion: ``cv`` (nearly constant velocity: the white-noise acceleration alone, the slides'
            setting) or ``agile``: the same white noise plus deterministic manoeuvres in the windows below
            (the slides' title speaks of agile targets but gives no manoeuvre; these are assumed).
        turn_scans, turn_rate_deg: coordinated turns: in window (a, b) the scans a..b (1-based; scan k is the
            truth at t = kT, reached from scan k−1 by one transition) turn at the window's rate [deg/s],
            positive to the left (counter-clockwise). Assumed default: 9°/s over scans 1–10, a 90° turn while
            the track is being confirmed (2.5 g at the initial 158 m/s; 2.4 g at 150 m/s), and −3°/s over
            scans 19–28, a 30° standard-rate turn back (0.74 g at the 138 m/s left after the deceleration).
        accel_scans, accel: longitudinal accelerations [m/s²] along the velocity in their windows. Assumed
            default: −5 m/s² (0.51 g) over scans 13–16, 158 → 138 m/s.
        filter_q: the acceleration psd the filters assume [m²/s³]; ``None``: ``q`` (the truth's, the slides'
            setting). An agile target needs a larger one (the notebook measures how much).
        filter_clutter: the clutter rate λ_F the filters assume (their clutter density λ_F/|FoV|, the density
            of a measurement under h₀); ``None``: ``clutter_rate``, the data's. With data without clutter
            (``clutter_rate = 0``) a positive value gives the log LRs their scale (with λ_F = 0 the density is
            floored at 10⁻³⁰⁰ and the scores are arbitrary up to a constant per measurement).
        false_tracks: with ``target = False``, start the tentative tracks as a tracker does: one per detection
            of scan 1 (all clutter; every sensor's), one-point initialised (:func:`one_point_cov`), scored
            from scan 2 on (:func:`false_tracks`); a track's log LR is 0 at scan 1. Needs clutter and at least
            two scans. False (the default): one track per run from N(m₀, P₀), m₀ drawn about ``x0``.

    Every field is checked (:class:`~motionsig_cli.config.ConfigError` naming it):

    - ``n_sensors`` an integer in [1, 64]; ``scans`` an integer in [1, 10⁵] (the long-run check's length);
      ``clutter_rate`` in [0, 1000]. The upper bounds are the sizes the implementation is built for (the
      filters loop over sensors and scans in Python; beyond 1000 false alarms per scan a sensor's
      measurements say nothing about the target); :class:`SlrtStudy` bounds their product by its cost.
    - ``radius`` in [0, fov_range) m: sensors at or beyond the field of view never see the target (which
      starts at the origin); with two sensors or more at least 1 m, or they all stand at one point.
    - ``pd_true``, ``pd_filter`` in (0, 1]; ``pd_filter = 1`` only without clutter (``clutter_rate = 0``).
    - ``sigma_r`` in [10⁻³, 10⁵] m and ``sigma_phi_deg`` in [10⁻⁶, 90] deg: R positive definite and well
      conditioned.
    - ``q`` and ``filter_q`` (unless None) in [0, 10⁶] m²/s³; ``T`` in (0, 3600] s; ``x0`` four finite
      numbers; ``p0_sd`` two numbers > 0; ``fov_range`` > 0 m; ``meas_model`` one of :data:`MEAS_MODELS`;
      ``target_motion`` one of :data:`TARGET_MOTIONS`.
    - With ``target_motion = "agile"``: each window a pair of integers 1 ≤ a ≤ b ≤ ``scans``, at most
      :data:`MAX_MANEUVERS` of each kind, no two windows (turn or acceleration) sharing a scan; one rate per
      turn window, in [−90, 90] deg/s, and one acceleration per window, in [−100, 100] m/s² (about 10 g);
      the noise-free speed stays above 1 m/s (a deceleration may not stop or reverse the target). The
      windows are not checked for ``cv`` (they are unused).
    """

    n_sensors: int = 4
    radius: float = 13_000.0
    target: bool = True
    pd_true: float = 0.9
    pd_filter: float = 0.9
    clutter_rate: float = 5.0
    sigma_r: float = 50.0
    sigma_phi_deg: float = 0.2
    meas_model: str = "range_bearing"
    q: float = 10.0
    T: float = 1.0
    scans: int = 30
    x0: tuple[float, float, float, float] = (0.0, 150.0, 0.0, 50.0)
    p0_sd: tuple[float, float] = (200.0, 50.0)
    fov_range: float = 26_000.0
    target_motion: str = "cv"
    turn_scans: tuple[tuple[int, int], ...] = ((1, 10), (19, 28))
    turn_rate_deg: tuple[float, ...] = (9.0, -3.0)
    accel_scans: tuple[tuple[int, int], ...] = ((13, 16),)
    accel: tuple[float, ...] = (-5.0,)
    filter_q: float | None = None
    false_tracks: bool = False
    filter_clutter: float | None = None

    def __post_init__(self) -> None:
        integer("n_sensors", self.n_sensors, 1, 64)
        positive("fov_range", self.fov_range, unit="m")
        in_range("radius", self.radius, 0.0, self.fov_range, hi_open=True, unit="m")
        if self.n_sensors > 1 and self.radius < 1.0:
            raise ConfigError("radius", self.radius, "m puts all sensors at one point: use at least 1 m")
        if not isinstance(self.target, bool | np.bool_):
            raise ConfigError("target", self.target, "is not true or false")
        in_range("pd_true", self.pd_true, 0.0, 1.0, lo_open=True)
        in_range("pd_filter", self.pd_filter, 0.0, 1.0, lo_open=True)
        in_range("clutter_rate", self.clutter_rate, 0.0, 1000.0)
        if self.pd_filter == 1.0 and self.clutter_rate > 0:
            raise ConfigError(
                "pd_filter", self.pd_filter, "for the filters is only meaningful without clutter"
            )
        in_range("sigma_r", self.sigma_r, 1e-3, 1e5, unit="m")
        in_range("sigma_phi_deg", self.sigma_phi_deg, 1e-6, 90.0, unit="deg")
        one_of("meas_model", self.meas_model, MEAS_MODELS)
        in_range("q", self.q, 0.0, 1e6, unit="m²/s³")
        if self.filter_q is not None:
            in_range("filter_q", self.filter_q, 0.0, 1e6, unit="m²/s³")
        if self.filter_clutter is not None:
            in_range("filter_clutter", self.filter_clutter, 0.0, 1000.0)
        in_range("T", self.T, 0.0, 3600.0, lo_open=True, unit="s")
        integer("scans", self.scans, 1, 100_000)
        if len(self.x0) != 4:
            raise ConfigError("x0", self.x0, "is not four numbers [x, ẋ, y, ẏ]")
        for v in self.x0:
            in_range("x0", v)
        if len(self.p0_sd) != 2:
            raise ConfigError("p0_sd", self.p0_sd, "is not two numbers (position, velocity)")
        for v in self.p0_sd:
            positive("p0_sd", v)
        one_of("target_motion", self.target_motion, TARGET_MOTIONS)
        if self.target_motion == "agile":
            self._check_maneuvers()
        if not isinstance(self.false_tracks, bool | np.bool_):
            raise ConfigError("false_tracks", self.false_tracks, "is not true or false")
        if self.false_tracks:
            if self.target:
                raise ConfigError("false_tracks", self.false_tracks, "needs target = False (clutter only)")
            if self.clutter_rate <= 0:
                raise ConfigError(
                    "clutter_rate", self.clutter_rate, "leaves no false alarm to start a false track on: "
                    "the no-target case needs clutter"
                )  # fmt: skip
            if self.scans < 2:
                raise ConfigError(
                    "scans",
                    self.scans,
                    "is too few: a false track starts on scan 1 and is scored from scan 2",
                )

    def _check_maneuvers(self) -> None:
        """The agile windows and their values (see the class docstring)."""
        used: dict[int, str] = {}
        for windows, values, name, vname, lim, unit in (
            (self.turn_scans, self.turn_rate_deg, "turn_scans", "turn_rate_deg", 90.0, "deg/s"),
            (self.accel_scans, self.accel, "accel_scans", "accel", 100.0, "m/s²"),
        ):
            if len(windows) > MAX_MANEUVERS:
                raise ConfigError(name, windows, f"is more than {MAX_MANEUVERS} windows")
            for w in windows:
                if len(w) != 2:
                    raise ConfigError(name, w, "is not a window (first scan, last scan)")
                a, b = (integer(name, v, 1) for v in w)
                if b < a:
                    raise ConfigError(name, w, "ends before it starts")
                if b > self.scans:
                    raise ConfigError(name, w, f"ends after the last scan ({self.scans})")
                for k in range(a, b + 1):
                    if k in used:
                        raise ConfigError(name, w, f"shares scan {k} with a {used[k]} window")
                    used[k] = name.split("_")[0]
            what = "rate" if name == "turn_scans" else "acceleration"
            if len(values) != len(windows):
                raise ConfigError(
                    vname,
                    values,
                    f"gives {len(values)} value(s) for {len(windows)} window(s): one {what} each",
                )
            for v in values:
                in_range(vname, v, -lim, lim, unit=unit)
        speed = math.hypot(self.x0[1], self.x0[3])  # turns keep the speed; accelerations change it by aT
        for (a, b), acc in sorted(zip(self.accel_scans, self.accel, strict=True)):
            speed += acc * self.T * (b - a + 1)
            if speed <= 1.0:
                raise ConfigError(
                    "accel",
                    self.accel,
                    f"brings the noise-free speed to {speed:.3g} m/s by scan {b}: at least 1 m/s",
                )

    def schedule(self) -> tuple[np.ndarray, np.ndarray]:
        """Per scan k = 1..K, the motion of the transition into it: (kind (K,) with 0 straight, 1 turn,
        2 longitudinal acceleration; value (K,): turn rate [rad/s] or acceleration [m/s²]). All straight for
        ``cv``."""
        kind, value = np.zeros(self.scans, dtype=int), np.zeros(self.scans)
        if self.target_motion == "agile":
            for code, windows, values, scale in (
                (1, self.turn_scans, self.turn_rate_deg, math.pi / 180.0),
                (2, self.accel_scans, self.accel, 1.0),
            ):
                for (a, b), v in zip(windows, values, strict=True):
                    kind[a - 1 : b], value[a - 1 : b] = code, v * scale
        return kind, value

    def step(self, x: np.ndarray, k: int, kind: np.ndarray, value: np.ndarray) -> np.ndarray:
        """The deterministic transition of the truth into scan k (0-based) from the states x (..., 4): constant
        velocity, a coordinated turn (exact, at the window's rate ω: the velocity rotates by ωT, the position
        follows the arc) or a longitudinal acceleration a along the velocity (speed + aT, heading kept,
        the position advanced by (|v|T + aT²/2) along the heading). Elementwise over the leading axes (runs),
        so a state's successor depends on that state only."""
        T = self.T
        px, vx, py, vy = x[..., 0], x[..., 1], x[..., 2], x[..., 3]
        if kind[k] == 1:
            w = float(value[k])
            s, c = math.sin(w * T), math.cos(w * T)
            a, b = (s / w, (1.0 - c) / w) if w != 0.0 else (T, 0.0)  # ω → 0: straight flight
            return np.stack([px + a * vx - b * vy, c * vx - s * vy,
                             py + b * vx + a * vy, s * vx + c * vy], axis=-1)  # fmt: skip
        if kind[k] == 2:
            acc = float(value[k])
            speed = np.hypot(vx, vy)
            ux, uy = vx / speed, vy / speed  # the heading, kept
            d, dv = speed * T + 0.5 * acc * T * T, acc * T  # (|v|T + aT²/2) along it; the speed + aT
            return np.stack([px + d * ux, vx + dv * ux, py + d * uy, vy + dv * uy], axis=-1)
        return np.stack([px + T * vx, vx, py + T * vy, vy], axis=-1)  # F x of the constant-velocity model

    def nominal(self) -> np.ndarray:
        """The noise-free truth (K, 4) at scans 1..K from ``x0``."""
        kind, value = self.schedule()
        x = np.asarray(self.x0, dtype=float)
        out = np.empty((self.scans, 4))
        for k in range(self.scans):
            x = self.step(x, k, kind, value)
            out[k] = x
        return out

    def nominal_speed(self) -> np.ndarray:
        """Speed [m/s] of the noise-free truth at scans 1..K."""
        nom = self.nominal()
        return np.hypot(nom[:, 1], nom[:, 3])

    def maneuvers(self) -> list[dict[str, Any]]:
        """The agile windows for the metadata, in scan order: kind, scans, the rate or acceleration, the
        noise-free speed at the window's start and the lateral or longitudinal acceleration in g."""
        if self.target_motion != "agile":
            return []
        v0 = float(math.hypot(self.x0[1], self.x0[3]))
        speed = np.concatenate([[v0], self.nominal_speed()])  # speed[k] at scan k (0: the start)
        out = []
        for (a, b), rate in zip(self.turn_scans, self.turn_rate_deg, strict=True):
            v = float(speed[a - 1])
            out.append({"kind": "turn", "scans": [a, b], "rate_deg_s": rate, "speed_m_s": round(v, 3),
                        "g": round(abs(math.radians(rate)) * v / G0, 3)})  # fmt: skip
        for (a, b), acc in zip(self.accel_scans, self.accel, strict=True):
            out.append({"kind": "longitudinal", "scans": [a, b], "accel_m_s2": acc,
                        "speed_m_s": round(float(speed[a - 1]), 3), "g": round(abs(acc) / G0, 3)})  # fmt: skip
        return sorted(out, key=lambda m: m["scans"][0])

    @property
    def sensors(self) -> np.ndarray:
        """(S, 2) sensor positions."""
        az = 2.0 * math.pi * np.arange(self.n_sensors) / self.n_sensors
        return self.radius * np.stack([np.cos(az), np.sin(az)], axis=-1)

    @property
    def q_filter(self) -> float:
        """The acceleration psd of the filters' model: ``filter_q``, else the truth's ``q``."""
        return self.q if self.filter_q is None else self.filter_q

    def measurement(self) -> MeasurementModel:
        if self.meas_model == "range_bearing":
            R = np.diag([self.sigma_r**2, math.radians(self.sigma_phi_deg) ** 2])
        else:
            R = np.diag([self.sigma_r**2, self.sigma_r**2])
        return MeasurementModel(self.meas_model, R, self.fov_range)

    def model(self) -> TrackExistenceModel:
        F, Q = cv_model(self.T, self.q_filter)
        p, v = self.p0_sd
        return TrackExistenceModel(
            F,
            Q,
            self.sensors,
            self.measurement(),
            self.pd_filter,
            self.clutter_rate if self.filter_clutter is None else self.filter_clutter,
            np.diag([p * p, v * v, p * p, v * v]),
        )


@dataclass(frozen=True)
class Generated:
    """Truth, initial track means and the measurements of every scan for a batch of runs (:func:`generate`:
    each scan and sensor's (R, M, 2) array is a contiguous view of one zero-padded buffer; per run, the
    target's measurement, if any, comes first, then the false alarms)."""

    truth: np.ndarray  # (R, K, 4)
    m0: np.ndarray  # (R, 4)
    scans: list[ScanData]
    clutter_counts: np.ndarray  # (R, K, S)


def generate(sc: SlrtScenario, runs: Sequence[int], seed: int) -> Generated:
    """Draw the scenario for the given run indices (the truth's motion with the truth's ``q``).

    Run r draws only from ``trial_rng(seed, r)``, in blocks (:func:`_draws`): the standard normals of the
    initial track (4), then per scan the process noise (4) and each sensor's measurement noise (2); the
    detection uniforms (scan × sensor); the false-alarm counts (scan × sensor, Poisson with mean
    ``clutter_rate``); the false alarms' uniforms (2 each, in scan, sensor order). Every run draws all of
    them, with or without a target, whatever its motion, and whether or not it is detected. Everything
    after the draws is elementwise over runs, scans and sensors, so a run's data are the same, to the bit,
    alone or in any batch (only the padding of the measurement arrays, to the batch's most measurements of
    a sensor in a scan, depends on the batch).
    """
    runs = list(runs)
    R, K, S = len(runs), sc.scans, sc.n_sensors
    kind, value = sc.schedule()
    meas = sc.measurement()
    sensors = sc.sensors
    _, Q = cv_model(sc.T, sc.q)
    LQ = np.linalg.cholesky(Q + 1e-12 * np.eye(4))  # process noise w = L_Q n, n ~ N(0, I)
    LR = np.linalg.cholesky(meas.R)  # measurement noise v = L_R n
    normals, detect_u, n_fa, clutter_u = _draws(sc, runs, seed)
    x0 = np.asarray(sc.x0, dtype=float)
    p, v = sc.p0_sd
    m0 = x0 + np.array([p, v, p, v]) * normals[:, :4]  # m0 = x0 + L0 n, L0 = diag(p, v, p, v)
    per_scan = normals[:, 4:].reshape(R, K, 4 + 2 * S)
    w = _lower_times(LQ, per_scan[..., :4])  # (R, K, 4)
    truth = _truth(sc, x0, w, kind, value)  # (R, K, 4): scan k at t = (k + 1) T
    noise = _lower_times(LR, per_scan[..., 4:].reshape(R, K, S, 2))  # (R, K, S, 2)
    zt = meas.h(truth[:, :, None, :], sensors) + noise  # z = h(x, sensor) + v
    if meas.angular is not None:
        zt[..., 1] = wrap_angle(zt[..., 1])
    seen = (detect_u < sc.pd_true) & meas.in_fov(zt, sensors)  # detected (u < p_D) and inside the FoV
    seen &= bool(sc.target)
    n_t = seen.astype(np.int64)  # the target's measurement (0 or 1), first in its sensor's list
    total = n_t + n_fa  # (R, K, S) measurements per run, scan and sensor
    M = total.max(axis=0, initial=0)  # (K, S): the batch's padded width per scan and sensor
    # one zero-padded buffer of measurement entries: scan k and sensor s own R M_ks consecutive entries, run r's
    # list starting at base_ks + r M_ks, so their (R, M_ks, 2) array is a contiguous view of it
    size = R * M
    base = np.cumsum(size.ravel()).reshape(K, S) - size
    Z = np.zeros((int(size.sum()), 2))
    valid = np.zeros(len(Z), dtype=bool)
    Z1, zt1 = Z.view(np.complex128).ravel(), zt.view(np.complex128).ravel()  # an entry's 2 floats as one
    head = (base + np.arange(R)[:, None, None] * M).ravel()  # run-major cells (r, k, s): a list's first entry
    hit = np.flatnonzero(seen)  # the target's measurements: first in their lists
    Z1[head[hit]], valid[head[hit]] = zt1[hit], True
    n_c = int(n_fa.sum())
    if n_c:
        counts = n_fa.ravel()  # per run-major cell: the order of the draws
        first = np.cumsum(counts) - counts  # index of a cell's first false alarm among all
        # false alarm i of cell c goes to entry head_c + n_t,c + (i − first_c): after the target's, if any
        entry = np.repeat(head + n_t.ravel() - first, counts) + np.arange(n_c)
        sensor = np.repeat(np.tile(np.arange(S), R * K), counts)
        Z1[entry] = meas.place_uniform(clutter_u.reshape(n_c, 2), sensors[sensor]).view(np.complex128).ravel()
        valid[entry] = True
    scans = [
        ScanData(
            tuple(Z[base[k, s] : base[k, s] + size[k, s]].reshape(R, M[k, s], 2) for s in range(S)),
            tuple(valid[base[k, s] : base[k, s] + size[k, s]].reshape(R, M[k, s]) for s in range(S)),
        )
        for k in range(K)
    ]
    return Generated(truth, m0, scans, n_fa)


def _draws(
    sc: SlrtScenario, runs: Sequence[int], seed: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Every random number of the runs, each run from its own ``trial_rng(seed, r)`` in four block draws:
    (normals (R, 4 + K(4 + 2S)): the initial track's 4, then per scan 4 of process noise and 2 per sensor
    of measurement noise; detection uniforms (R, K, S); false-alarm counts (R, K, S), Poisson with mean
    ``clutter_rate``; the false alarms' uniforms, 2 each, run after run in scan, sensor order (flat)).

    The loop over runs is the seeding, which a run's own stream needs: a generator per run and its four
    draws, a fixed number of calls whatever the scans, sensors and clutter."""
    R, K, S = len(runs), sc.scans, sc.n_sensors
    normals = np.empty((R, 4 + K * (4 + 2 * S)))
    detect_u = np.empty((R, K, S))
    n_fa = np.empty((R, K, S), dtype=np.int64)
    clutter_u: list[np.ndarray] = []
    for i, r in enumerate(runs):
        g = trial_rng(seed, r)
        g.standard_normal(out=normals[i])
        g.random(out=detect_u[i])
        n_fa[i] = g.poisson(sc.clutter_rate, (K, S))
        clutter_u.append(g.random(2 * int(n_fa[i].sum())))
    return normals, detect_u, n_fa, np.concatenate(clutter_u) if clutter_u else np.empty(0)


def _lower_times(L: np.ndarray, n: np.ndarray) -> np.ndarray:
    """L n over the last axis of n (..., d) for a (d, d) matrix L: the sum over j of L[:, j] n_j, in the
    order j = 0..d−1, elementwise (no BLAS: a vector's product does not depend on the batch around it)."""
    out = n[..., 0:1] * L[:, 0]
    for j in range(1, L.shape[1]):
        out = out + n[..., j : j + 1] * L[:, j]
    return out


def _truth(
    sc: SlrtScenario, x0: np.ndarray, w: np.ndarray, kind: np.ndarray, value: np.ndarray
) -> np.ndarray:
    """The truth (R, K, 4) at scans 1..K: x_k = f_k(x_{k−1}) + w_k from x0, with the process noise w (R, K, 4).

    Constant velocity throughout (no manoeuvre in the schedule): the closed form of x_k = F x_{k−1} + w_k per
    axis, v_k = v_0 + Σ_{j≤k} w^v_j and p_k = p_0 + T Σ_{j<k} v_j + Σ_{j≤k} w^p_j (cumulative sums over the
    scans). With manoeuvres, the recursion of :meth:`SlrtScenario.step`, one step per scan for all runs at
    once."""
    R, K = w.shape[:2]
    if not kind.any():
        pos, vel = x0[[0, 2]], x0[[1, 3]]
        wp, wv = w[..., [0, 2]], w[..., [1, 3]]  # (R, K, 2): x and y axes
        v = vel + np.cumsum(wv, axis=1)  # v_k, k = 1..K
        v_prev = np.concatenate([np.broadcast_to(vel, (R, 1, 2)), v[:, :-1]], axis=1)  # v_{k-1}
        p = pos + sc.T * np.cumsum(v_prev, axis=1) + np.cumsum(wp, axis=1)
        return np.stack([p[..., 0], v[..., 0], p[..., 1], v[..., 1]], axis=-1)
    truth = np.empty((R, K, 4))
    x = np.broadcast_to(x0, (R, 4))
    for k in range(K):
        x = sc.step(x, k, kind, value) + w[:, k]
        truth[:, k] = x
    return truth


ONE_POINT_VEL_SD = 150.0
"""Velocity standard deviation [m/s] of a track started on one detection (assumed: an air target up to about
300 m/s within 2σ)."""


def one_point_cov(meas: MeasurementModel, z: np.ndarray, noise: np.ndarray | None = None) -> np.ndarray:
    """Prior covariances (N, 4, 4) of tracks started on detections z (N, 2), velocity 0: position sd the larger
    of σ_r and r·σ_φ (range–bearing) or σ_x (Cartesian), velocity sd :data:`ONE_POINT_VEL_SD`, the same on both
    axes. ``noise``: each detection's sensor noise R (N, 2, 2); None: ``meas.R`` for all."""
    R = np.broadcast_to(meas.R, (len(z), 2, 2)) if noise is None else noise
    if meas.kind == "range_bearing":
        pos = np.maximum(np.sqrt(R[:, 0, 0]), z[:, 0] * np.sqrt(R[:, 1, 1]))
    else:
        pos = np.sqrt(R[:, 0, 0])
    sd = np.stack(
        [pos, np.full_like(pos, ONE_POINT_VEL_SD), pos, np.full_like(pos, ONE_POINT_VEL_SD)], axis=-1
    )
    return sd[:, :, None] * np.eye(4) * sd[:, None, :]


def to_xy(meas: MeasurementModel, z: np.ndarray, sensor: np.ndarray) -> np.ndarray:
    """Detections z (..., 2) of sensors at ``sensor`` (..., 2) in Cartesian x–y."""
    if meas.kind == "cartesian":
        return np.array(z, dtype=float)
    return sensor + z[..., :1] * np.stack([np.cos(z[..., 1]), np.sin(z[..., 1])], axis=-1)


@dataclass(frozen=True)
class FalseTracks:
    """Tentative tracks started on the detections of scan 1 (:func:`false_tracks`): initial means (N, 4) and
    covariances (N, 4, 4), each track's run (index into the batch) and sensor (N,), and scans 2..K with each
    track's row holding its run's measurements."""

    m0: np.ndarray
    cov: np.ndarray
    run: np.ndarray
    sensor: np.ndarray
    scans: list[ScanData]


def false_tracks(sc: SlrtScenario, gen: Generated) -> FalseTracks:
    """One tentative track per detection of scan 1 of every run and sensor (with no target: every one is
    clutter), as a tracker starts them: position the detection's in x–y, velocity 0, covariance
    :func:`one_point_cov`; run-major (a run's tracks by sensor, then in list order). Each track is scored on
    its own run's scans 2..K: the scan data are gathered per track (a track's row is its run's row)."""
    meas, first = sc.measurement(), gen.scans[0]
    r_idx, s_idx, j_idx = [], [], []
    for s in range(sc.n_sensors):
        r, j = np.nonzero(first.valid[s])
        r_idx.append(r)
        s_idx.append(np.full(r.size, s))
        j_idx.append(j)
    r, s, j = (np.concatenate(a) for a in (r_idx, s_idx, j_idx))
    order = np.lexsort((j, s, r))
    r, s, j = r[order], s[order], j[order]
    z = np.zeros((r.size, 2))
    for k in range(sc.n_sensors):  # the S sensors' detections, each from its own (R, M, 2) array
        z[s == k] = first.Z[k][r[s == k], j[s == k]]
    m0 = np.zeros((r.size, 4))
    xy = to_xy(meas, z, sc.sensors[s])
    m0[:, 0], m0[:, 2] = xy[:, 0], xy[:, 1]
    scans = [ScanData(tuple(Z[r] for Z in scan.Z), tuple(V[r] for V in scan.valid)) for scan in gen.scans[1:]]
    return FalseTracks(m0, one_point_cov(meas, z), r, s, scans)


def score_case(
    sc: SlrtScenario, gen: Generated, methods: Sequence[str], options: FusionOptions
) -> dict[str, np.ndarray]:
    """log LR (rows × scans) per method of one case's generated runs: a row per run, or with
    ``sc.false_tracks`` a row per false track (:func:`false_tracks`), whose log LR is 0 at scan 1."""
    model = sc.model()
    if not sc.false_tracks:
        return run_methods(model, gen.m0, gen.scans, methods, options=options)
    ft = false_tracks(sc, gen)
    if ft.m0.shape[0] == 0:
        return {m: np.zeros((0, sc.scans)) for m in methods}
    scores = run_methods(replace(model, m0_cov=ft.cov), ft.m0, ft.scans, methods, options=options)
    start = np.zeros((ft.m0.shape[0], 1))
    return {m: np.concatenate([start, v], axis=1) for m, v in scores.items()}


FALSE_TRACK_COST = 0.25
"""A false track's share of a run's per-row filter cost (measured: 50 runs of the default scenario, six rules,
the three no-target cases' ~990 tracks each took 1.5e-5 s per track, sensor and scan per three rules, against
the 6e-5 the cost model charges a run; most false tracks see a padded but nearly empty gate)."""


def tracks_per_run(sc: SlrtScenario) -> float:
    """Mean scored tracks per run: 1, or with false tracks the mean detections of scan 1 (S·λ_F)."""
    return sc.n_sensors * sc.clutter_rate if sc.false_tracks else 1.0


def run(
    sc: SlrtScenario,
    runs: int,
    seed: int,
    methods: Sequence[str] = METHODS,
    *,
    lkf_mean: str | None = None,
    options: FusionOptions | None = None,
) -> tuple[dict[str, np.ndarray], Generated]:
    """log LR (runs × scans, or false tracks × scans: :func:`score_case`) per method, and the generated data
    (in this process; no time limit).
    ``options``: the fusion rules' (:class:`~motionsig_cli.detection.track_existence.FusionOptions`);
    ``lkf_mean``, if given, replaces theirs."""
    integer("runs", runs, 1)
    nbytes = cost(sc, runs)[1]
    if nbytes > MAX_BYTES:
        raise ConfigError(
            "runs", runs, f"would need about {nbytes / 1e9:.1f} GB of measurements; the limit is 2 GB"
        )
    gen = generate(sc, range(runs), seed)
    if options is None:
        options = FusionOptions("lr" if lkf_mean is None else lkf_mean)
    elif lkf_mean is not None:
        options = replace(options, lkf_mean=lkf_mean)
    return score_case(sc, gen, methods, options), gen


Task = tuple[int, range]
"""A task of :class:`SlrtJob`: (case index, runs)."""


@dataclass(frozen=True)
class SlrtJob:
    """The Monte Carlo of a study: runs 0..runs−1 of every case, scored by ``methods`` (an engine
    :class:`~motionsig_cli.engine.MonteCarloJob`; its result is, per case, log LR (runs × scans) per method).

    A task is ``(case index, range of runs)``; :meth:`tasks` chunks each case's runs into tasks of
    :meth:`runs_per_task` runs (from the cost model, so the chunking — and with it every floating-point
    result — depends on the parameters only, never on the number of workers).

    ``options`` are the fusion rules' (:class:`~motionsig_cli.detection.track_existence.FusionOptions`:
    LKF's mean, the gate, the feedback period, LDF's prior and weights, the naive rule's α and β). Every
    method must apply to every case's model (the exact DKF only to linear sensors with p_D = 1 and no
    clutter): checked here, before any run.
    """

    name: ClassVar[str] = "slrt"

    cases: tuple[SlrtScenario, ...]
    runs: int
    seed: int
    methods: tuple[str, ...] = METHODS
    options: FusionOptions = field(default_factory=FusionOptions)

    def __post_init__(self) -> None:
        if not self.cases:
            raise ConfigError("cases", self.cases, "is empty: at least one case")
        integer("runs", self.runs, 1)
        integer("seed", self.seed, 0)
        check_methods(self.methods)
        if not isinstance(self.options, FusionOptions):
            raise ConfigError("options", self.options, "is not FusionOptions")
        for sc in self.cases:
            check_applicable(self.methods, sc.model(), self.options)

    def runs_per_task(self) -> int:
        """Runs per task: worth at least the engine's minimum task time *and* 4× the per-batch overhead of
        the cost model (the filters' Python loop over scans and sensors), so that chunking costs ≤ 25 %
        extra. Both scale with ``$MOTIONSIG_MIN_TASK_SECONDS`` (tests set it tiny: one run per task)."""
        n = len(self.methods)
        fixed = max(cost(sc, 0, methods=n)[0] for sc in self.cases)
        per_run = max(cost(sc, 1, methods=n)[0] - cost(sc, 0, methods=n)[0] for sc in self.cases)
        return trials_per_task(per_run, fixed_seconds=fixed)

    def tasks(self) -> list[Task]:
        """(case, runs) in case order, runs in increasing order within a case."""
        per_task = self.runs_per_task()
        return [(c, r) for c in range(len(self.cases)) for r in tasks_of(self.runs, per_task)]

    def task_size(self, task: Task) -> int:
        """Runs in the task."""
        return len(task[1])

    def run_task(self, task: Task) -> dict[str, np.ndarray]:
        """One task: log LR (runs in the task × scans) per method of one case."""
        case, runs = task
        sc = self.cases[case]
        return score_case(sc, generate(sc, runs, self.seed), self.methods, self.options)

    def reduce(
        self, tasks: Sequence[Task], results: Sequence[dict[str, np.ndarray]]
    ) -> list[dict[str, np.ndarray]]:
        """Per case, the log LR (runs × scans) per method: the tasks' results joined in task order."""
        parts: list[list[dict[str, np.ndarray]]] = [[] for _ in self.cases]
        for (case, _), res in zip(tasks, results, strict=True):
            parts[case].append(res)
        return [{m: np.concatenate([p[m] for p in ps]) for m in self.methods} for ps in parts]

    def identity(self) -> dict[str, Any]:
        """Everything the task results depend on (JSON values), for a checkpoint's manifest."""
        return {
            "cases": [asdict(sc) for sc in self.cases],
            "runs": self.runs,
            "seed": self.seed,
            "methods": list(self.methods),
            "options": asdict(self.options),
            "runs_per_task": self.runs_per_task(),
            "draws": DRAWS,
        }


def _case(
    base: SlrtScenario, field_name: str, pd: float, *, target: bool, motion: str | None = None
) -> SlrtScenario:
    """``base`` with a target (or none: then false tracks started on clutter), p_D = ``pd`` for data and
    filters and (unless None) the target's motion; a bad p_D names ``field_name``."""
    in_range(field_name, pd, 0.0, 1.0, lo_open=True)
    try:
        return replace(
            base, target=target, pd_true=pd, pd_filter=pd, target_motion=motion or base.target_motion,
            false_tracks=not target,
        )  # fmt: skip
    except ConfigError as exc:
        if exc.field in ("pd_true", "pd_filter"):
            raise ConfigError(field_name, pd, exc.reason) from None
        raise


@dataclass(frozen=True)
class SlrtStudy(FusionSettings):
    """The command's experiment: target cases at several p_D (for one or both target motions) and a
    no-target case of one scenario, every case scored by the chosen fusion methods on runs 0..runs−1, and
    Wald's test on the scores.

    Attributes:
        scenario: what the cases share (its ``target``, ``pd_true``, ``pd_filter`` and, with ``motions``,
            ``target_motion`` are set per case).
        pd: p_D of the target cases (data and filters alike): 1 to :data:`MAX_PD_CASES` values in (0, 1];
            a repeated value gives one case.
        motions: the target motions of the target cases (:data:`TARGET_MOTIONS`, each once): every p_D is a
            case for each motion, in this order (labels ``target, p_D = …`` and ``agile target, p_D = …``).
            ``None``: the scenario's own ``target_motion``.
        no_target: also run the no-target (clutter only) cases: false tracks started as a tracker starts
            them, on every detection of scan 1 (``SlrtScenario.false_tracks``), one case per p_D of ``pd``
            (the filters assume that p_D; labels ``no target, p_D = …``), or with ``filter_pd`` (in (0, 1]) one
            case at that p_D.
        runs: Monte Carlo runs per case, ≥ 1, with an estimated run time ≤ :data:`MAX_SECONDS` and memory
            ≤ :data:`MAX_BYTES` for all cases (:func:`cost`).
        seed: root seed (run r draws from ``trial_rng(seed, r)``).
        methods: names in :data:`~motionsig_cli.detection.track_existence.FUSION_METHODS`, each applicable
            to every case (the exact ``dkf`` only to linear sensors with p_D = 1 and no clutter).
        lkf_mean, gate_pg, feedback_every, ldf_prior, ldf_weights: the fusion rules' options, as the fields
            of :class:`~motionsig_cli.detection.track_existence.FusionOptions` (LKF's mean, the validation
            gate's probability or None, the feedback period of ``fkf-feedback``, LDF's prior existence
            probability and sensor weights); checked there.
        alpha, beta: Wald's error probabilities P(confirm | no target) and P(delete | target), in (0, 0.5);
            also the local tests' of the naive rule.
        stop: freeze each run's score at its decision (default: keep accumulating).
    """

    scenario: SlrtScenario = field(default_factory=SlrtScenario)
    pd: tuple[float, ...] = (0.9, 0.5, 0.2)
    no_target: bool = True
    filter_pd: float | None = None
    runs: int = 50
    seed: int = DEFAULT_SEED
    methods: tuple[str, ...] = METHODS
    lkf_mean: str = "lr"
    alpha: float = 1e-3
    beta: float = 0.1
    stop: bool = False
    motions: tuple[str, ...] | None = None
    gate_pg: float | None = None
    feedback_every: int = 1
    ldf_prior: float = 0.5
    ldf_weights: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        if self.motions is not None:
            if not self.motions or len(set(self.motions)) != len(self.motions):
                raise ConfigError("motions", self.motions, "is not one or more distinct target motions")
            for m in self.motions:
                one_of("motions", m, TARGET_MOTIONS)
        cases = self.cases
        self.job()
        wald_thresholds(self.alpha, self.beta)
        seconds = sum(cost(c, self.runs, 1, len(self.methods))[0] for _, c in cases)
        job, sc = self.job(), self.scenario
        per_task = max(job.task_size(t) for t in job.tasks())
        per_worker = max(cost(c, per_task)[1] for _, c in cases)  # a worker holds one task's data at a time
        if per_worker > MAX_BYTES:
            raise ConfigError(
                "runs", self.runs, f"needs an estimated {per_worker / 1e9:.2g} GB of measurements per worker "
                f"(one task's runs of {sc.scans} scans x {sc.n_sensors} sensors); the limit is 2 GB per worker",
            )  # fmt: skip
        what = f"is too many runs for {len(cases)} case(s) x {sc.scans} scans x {sc.n_sensors} sensors: it "
        check_run_time("runs", self.runs, seconds, MAX_SECONDS, what=what)

    @cached_property
    def cases(self) -> list[tuple[str, SlrtScenario]]:
        """(label, scenario) of each case: the target cases in the order of ``pd``, then the no-target one."""
        values = tuple(dict.fromkeys(self.pd))
        if not values:
            raise ConfigError("pd", self.pd, "is empty: give at least one p_D")
        if len(values) > MAX_PD_CASES:
            raise ConfigError("pd", self.pd, f"is more than {MAX_PD_CASES} values")
        out = [
            (f"{'agile ' if motion == 'agile' else ''}target, p_D = {v:g}",
             _case(self.scenario, "pd", v, target=True, motion=motion))
            for motion in self.target_motions
            for v in values
        ]  # fmt: skip
        if self.no_target:
            no_target = values if self.filter_pd is None else (self.filter_pd,)
            out += [(f"no target, p_D = {v:g}", _case(self.scenario, "pd" if self.filter_pd is None else
                     "filter_pd", v, target=False)) for v in no_target]  # fmt: skip
        return out

    @property
    def target_motions(self) -> tuple[str, ...]:
        """The motions of the target cases: ``motions``, else the scenario's."""
        return self.motions if self.motions is not None else (self.scenario.target_motion,)

    def job(self) -> SlrtJob:
        """The Monte Carlo of every case (run it with :func:`motionsig_cli.engine.run_job`)."""
        return SlrtJob(
            tuple(sc for _, sc in self.cases), self.runs, self.seed, tuple(self.methods), self.options
        )

    def result(self, scores: Sequence[dict[str, np.ndarray]]) -> SlrtResult:
        """The job's scores checked (no NaN, no +inf) and, with ``stop``, frozen at each run's decision."""
        log_a, log_b = self.thresholds
        out = []
        for (label, _), case in zip(self.cases, scores, strict=True):
            case = dict(case)
            if not any(v.shape[0] for v in case.values()):
                raise ConfigError(
                    "runs", self.runs, f"gave no false alarm in scan 1 to start a false track on ({label}): more "
                    "runs or more clutter, or no no-target case"
                )  # fmt: skip
            for m, v in case.items():
                if np.any(np.isnan(v) | (v == np.inf)):
                    raise RuntimeError(f"NaN or +inf log LR in {label}, {m}")
                if self.stop:
                    case[m] = freeze_at_decision(v, log_a, log_b)
            out.append(case)
        return SlrtResult(self, out, [dict(c) for c in scores] if self.stop else None)


CURVE_COLUMNS = (
    "case",
    "target",
    "pd",
    "method",
    "scan",
    "mean_loglr",
    "median_loglr",
    "q05_loglr",
    "q95_loglr",
)
STUDY_COLUMNS = (
    "case",
    "target",
    "motion",
    "pd",
    "method",
    "runs",
    "tracks",
    "confirmed",
    "confirmed_se",
    "deleted",
    "deleted_se",
    "undecided",
    "asn",
    "asn_se",
    "asn_wald",
    "error_rate",
    "error_rate_se",
    "error_rate_lo95",
    "error_rate_hi95",
    "wald_design",
    "wald_bound",
    "versus_bound",
    "lost",
    "lost_se",
    "mean_increment",
    "mean_loglr_last",
)
"""The columns of the ``study`` view (:meth:`SlrtResult.study_rows`)."""
OC_COLUMNS = (
    "case",
    "false_case",
    "pd",
    "method",
    "log_A",
    "log_B",
    "wald_alpha",
    "wald_beta",
    "false_tracks",
    "false_confirmed",
    "false_confirmed_lo95",
    "false_confirmed_hi95",
    "false_asn",
    "runs",
    "target_confirmed",
    "target_confirmed_lo95",
    "target_confirmed_hi95",
    "target_deleted",
    "target_deleted_lo95",
    "target_deleted_hi95",
    "target_asn",
)
"""The columns of the ``oc`` view (:meth:`SlrtResult.oc_rows`)."""
MATCHED_COLUMNS = (*OC_COLUMNS[:3], "reference_false", "reference_deleted", *OC_COLUMNS[3:])
"""The columns of the ``matched`` view (:meth:`SlrtResult.matched_rows`)."""
DECISION_COLUMNS = (
    "case",
    "target",
    "pd",
    "method",
    "runs",
    "tracks",
    "confirmed",
    "deleted",
    "undecided",
    "mean_decision_scan",
    "max_decision_scan",
    "error_rate",
    "wald_bound",
    "error_rate_se",
)


@dataclass(frozen=True)
class SlrtResult:
    """A study's scores: per case, log LR (runs × scans) per method (frozen at the decision with ``stop``),
    and ``raw``, the same before any freezing (``None``: ``scores`` are not frozen)."""

    study: SlrtStudy
    scores: list[dict[str, np.ndarray]]
    raw: list[dict[str, np.ndarray]] | None = None

    def table(self, view: str) -> Table:
        """The ``curves``, ``decisions`` or ``study`` table (:data:`VIEWS`) with the study's provenance."""
        one_of("view", view, VIEWS)
        columns, rows = {
            "curves": (CURVE_COLUMNS, self.curves),
            "decisions": (DECISION_COLUMNS, self.decisions),
            "study": (STUDY_COLUMNS, self.study_rows),
            "oc": (OC_COLUMNS, self.oc_rows),
            "matched": (MATCHED_COLUMNS, self.matched_rows),
        }[view]
        return Table(columns=columns, rows=rows(), meta=self.meta(view))

    def _rows(self) -> list[tuple[str, SlrtScenario, str, np.ndarray]]:
        return [
            (label, sc, m, scores[m])
            for (label, sc), scores in zip(self.study.cases, self.scores, strict=True)
            for m in self.study.methods
        ]

    def curves(self) -> list[tuple[Any, ...]]:
        """Per case, method and scan: mean, median, 5 % and 95 % quantiles of log LR over the runs."""
        rows = []
        for label, sc, m, loglr in self._rows():
            st = summarise(loglr)
            for j in range(sc.scans):
                rows.append((label, sc.target, sc.pd_filter, m, j + 1, float(st["mean"][j]), float(st["median"][j]),
                             float(st["q05"][j]), float(st["q95"][j])))  # fmt: skip
        return rows

    def decisions(self) -> list[tuple[Any, ...]]:
        """Per case and method: Wald's decisions (fractions confirmed, deleted, undecided), the mean and
        latest decision scan, the error rate (deleted with a target, confirmed without), Wald's bound on it
        (β/(1−α), α/(1−β)) and its binomial standard error (at least that of one error in ``runs``)."""
        alpha, beta, runs = self.study.alpha, self.study.beta, self.study.runs
        rows = []
        for label, sc, m, loglr in self._rows():
            n = loglr.shape[0]  # the runs, or the false tracks
            d = decisions(loglr, alpha, beta)
            conf, dele = d.decision == 1, d.decision == -1
            decided = d.decision != 0
            wrong = dele if sc.target else conf
            bound = beta / (1 - alpha) if sc.target else alpha / (1 - beta)
            rows.append((label, sc.target, sc.pd_filter, m, runs, n, float(conf.mean()), float(dele.mean()),
                         float(1 - decided.mean()), float(d.time[decided].mean()) if decided.any() else None,
                         int(d.time.max()) if decided.any() else None, float(wrong.mean()), bound,
                         float(math.sqrt(max(wrong.mean() * (1 - wrong.mean()), 1 / n) / n))))  # fmt: skip
        return rows

    def study_rows(self) -> list[tuple[Any, ...]]:
        """Per case and method, the study's comparison (:data:`STUDY_COLUMNS`):

        - ``confirmed``, ``deleted``, ``undecided``: fractions of the runs (first crossing within the
          scans), with the binomial standard errors √(p(1−p)/n) of the first two;
        - ``asn``: the average sample number, the mean decision scan of the decided runs (undecided runs
          are censored at the last scan and left out: see ``undecided``), and its standard error s/√n_decided
          (``None`` with fewer than two decided runs);
        - ``asn_wald``: Wald's approximation E[N] ≈ (P_c log B + P_d log A) / E[Δ] with the design
          probabilities (P_c, P_d) = (1−β, β) with a target and (α, 1−α) without, and E[Δ] the measured
          mean increment ``mean_increment`` (log LR(K)/K over the runs): it neglects the overshoot of the
          thresholds, and the increments are neither independent nor identically distributed here (the
          filters converge), so it is an order of magnitude; ``None`` when E[Δ] has the wrong sign, and for
          a rule whose score stops at its local tests' decisions (``naive``: no drift to divide by);
        - ``error_rate``: deleted with a target, confirmed without; its binomial standard error, and the
          exact (Clopper–Pearson) 95 % interval ``error_rate_lo95``..``error_rate_hi95``, which stays
          informative with no error at all (then the upper end is 1 − 0.025^(1/n));
        - ``wald_design``: β with a target, α without (Wald's approximation of the error probability,
          overshoot neglected); ``wald_bound``: Wald's bounds β/(1−α) and α/(1−β);
        - ``versus_bound``: ``below`` (error rate ≤ bound), ``above, within sampling error`` (the 95 %
          interval reaches the bound) or ``above`` (the interval lies above it);
        - ``lost``: the fraction of runs confirmed and later lost (:func:`lost_after_confirmation`, on the
          scores before any freezing), with its binomial standard error: how often a true track is dropped
          during track maintenance, e.g. when an agile target outruns the filters' model;
        - ``mean_loglr_last``: the mean log LR at the last scan (frozen at the decision with ``stop``).
        """
        st = self.study
        alpha, beta, runs = st.alpha, st.beta, st.runs
        log_a, log_b = st.thresholds
        raw = {label: case for (label, _), case in zip(st.cases, self.raw or self.scores, strict=True)}
        rows = []
        for label, sc, m, loglr in self._rows():
            n = loglr.shape[0]  # the runs, or the false tracks
            unfrozen = raw[label][m]
            inc = float(unfrozen[:, -1].mean() / (unfrozen.shape[1] - sc.false_tracks))  # scans scored
            lost = float(lost_after_confirmation(unfrozen, log_a, log_b).mean())
            d = decisions(loglr, alpha, beta)
            conf, dele = float((d.decision == 1).mean()), float((d.decision == -1).mean())
            decided = d.decision != 0
            times = d.time[decided].astype(float)
            asn = float(times.mean()) if times.size else None
            asn_se = float(times.std(ddof=1) / math.sqrt(times.size)) if times.size > 1 else None
            p_c, p_d = (1 - beta, beta) if sc.target else (alpha, 1 - alpha)
            num = p_c * log_b + p_d * log_a
            stops = FUSION_METHODS[m].uses_thresholds  # a score frozen at local decisions has no drift
            asn_wald = num / inc if not stops and math.isfinite(inc) and inc != 0 and num / inc > 0 else None
            n_err = int(((d.decision == -1) if sc.target else (d.decision == 1)).sum())
            err = n_err / n
            lo, hi = clopper_pearson(n_err, n)
            design = beta if sc.target else alpha
            bound = beta / (1 - alpha) if sc.target else alpha / (1 - beta)
            verdict = "below" if err <= bound else "above, within sampling error" if lo <= bound else "above"
            rows.append((label, sc.target, sc.target_motion if sc.target else None, sc.pd_filter, m, runs, n,
                         conf, _binomial_se(conf, n), dele, _binomial_se(dele, n), float(1 - decided.mean()),
                         asn, asn_se, asn_wald, err, _binomial_se(err, n), lo, hi, design, bound, verdict, lost,
                         _binomial_se(lost, n), inc, float(loglr[:, -1].mean())))  # fmt: skip
        return rows

    def _pairs(self) -> list[tuple[str, str, SlrtScenario]]:
        """(target case, no-target case with the same filter p_D, the target case's scenario)."""
        false = {sc.pd_filter: label for label, sc in self.study.cases if not sc.target}
        return [(label, false[sc.pd_filter], sc) for label, sc in self.study.cases
                if sc.target and sc.pd_filter in false]  # fmt: skip

    def oc_rows(self) -> list[tuple[Any, ...]]:
        """The operating characteristics (:data:`OC_COLUMNS`): per target case paired with the no-target case
        of the same filter p_D, per scheme (not those whose score uses the thresholds) and per threshold pair
        of the grid :data:`OC_LOG_A` × :data:`OC_LOG_B`, the first-crossing rates on the unfrozen scores."""
        st = self.study
        raw = {label: case for (label, _), case in zip(st.cases, self.raw or self.scores, strict=True)}
        rows = []
        for target, false, sc in self._pairs():
            for m in st.methods:
                if not FUSION_METHODS[m].uses_thresholds:
                    rows += [
                        (target, false, sc.pd_filter, m, *p) for p in _oc_grid(raw[target][m], raw[false][m])
                    ]
        return rows

    def matched_rows(self) -> list[tuple[Any, ...]]:
        """The schemes at equal error rates (:data:`MATCHED_COLUMNS`): per pair of cases, reference rates of
        :data:`MATCHED_RATES` and scheme, the :meth:`oc_rows` row meeting both rates (false-track confirmation,
        true-track deletion) that confirms the most targets, then decides them soonest (None where none does)."""
        col = {c: i for i, c in enumerate(OC_COLUMNS)}
        oc = self.oc_rows()
        rows = []
        for target, false, sc in self._pairs():
            for r_false, r_del in MATCHED_RATES:
                for m in self.study.methods:
                    sweep = [r for r in oc if r[0] == target and r[3] == m]
                    if not sweep:
                        continue
                    ok = [
                        r
                        for r in sweep
                        if r[col["false_confirmed"]] <= r_false and r[col["target_deleted"]] <= r_del
                    ]
                    best = min(ok, key=lambda r: (-r[col["target_confirmed"]], r[col["target_asn"]] or math.inf),
                               default=None)  # fmt: skip
                    rows.append((target, false, sc.pd_filter, r_false, r_del, m,
                                 *(best[4:] if best else (None,) * (len(OC_COLUMNS) - 4))))  # fmt: skip
        return rows

    def meta(self, view: str) -> dict[str, Any]:
        """Provenance: the view, every parameter of the study and scenario, and how to read the scores."""
        st, sc = self.study, self.study.scenario
        log_a, log_b = st.thresholds
        shared = (
            "n_sensors",
            "radius",
            "clutter_rate",
            "sigma_r",
            "sigma_phi_deg",
            "meas_model",
            "q",
            "T",
            "scans",
        )
        motion: dict[str, Any] = {}  # only where the study is not the slides' (default outputs unchanged)
        if "agile" in st.target_motions:
            agile = next(c for _, c in st.cases if c.target and c.target_motion == "agile")
            motion["target_motions"] = list(st.target_motions)
            motion["maneuvers"] = agile.maneuvers()
            motion["agile"] = AGILE_NOTE
        if view == "study":
            motion["study"] = STUDY_NOTE
        if view in ("oc", "matched"):
            motion["oc"] = OC_NOTE
            motion["oc_grid"] = {"log_A": list(OC_LOG_A), "log_B": list(OC_LOG_B)}
        if view == "matched":
            motion["matched"] = MATCHED_NOTE
        fusion: dict[str, Any] = {}  # the rules' options where they are not the defaults
        defaults = FusionOptions()
        for name in ("gate_pg", "feedback_every", "ldf_prior", "ldf_weights"):
            uses = {"feedback_every": "fkf-feedback", "ldf_prior": "ldf", "ldf_weights": "ldf"}.get(name)
            if getattr(st, name) != getattr(defaults, name) or (uses in st.methods):
                fusion[name] = getattr(st, name)
        return make_meta(
            "slrt",
            view=view,
            methods=list(st.methods),
            lkf_mean=st.lkf_mean,
            runs=st.runs,
            seed=st.seed,
            seeding="run r draws from SeedSequence(seed).spawn(...)[r]: truth, detections, clutter, initial track",
            scenario={
                **{k: getattr(sc, k) for k in shared},
                "x0": list(sc.x0),
                "p0_sd": list(sc.p0_sd),
                "fov_range_m": sc.fov_range,
                "sensor_azimuths": "equally spaced from 0 deg",
                **({} if sc.filter_q is None else {"filter_q": sc.filter_q}),
            },
            no_target_filter_pd=st.filter_pd if st.no_target else None,
            false_tracks=FALSE_TRACK_NOTE if st.no_target else None,
            **motion,
            sprt={
                "alpha": st.alpha,
                "beta": st.beta,
                "log_A": log_a,
                "log_B": log_b,
                "rule": "first crossing",
            },
            **{m: FUSION_METHODS[m].metadata for m in st.methods if FUSION_METHODS[m].metadata},
            **fusion,
            stop=st.stop,
            filter_clutter=sc.filter_clutter,
            clutter_floor="the filters' clutter rate is 0: their clutter density is floored at 1e-300 per field of "
            "view, so absolute scores are arbitrary and only differences between methods mean something (give "
            "--filter-clutter)"
            if sc.model().clutter_rate == 0
            else None,
            minus_inf="a log LR of -inf means the filters' p_D = 1 and a sensor saw nothing: the target hypothesis "
            "is impossible (certain deletion)",
            assumptions=ASSUMPTIONS,
        )

    def panels(self) -> list[tuple[str, np.ndarray, dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]]]:
        """Per case (label, scans 1..K, {method: (mean, q05, q95)}) for the figure."""
        k = np.arange(1, self.study.scenario.scans + 1)
        out = []
        for (label, _), scores in zip(self.study.cases, self.scores, strict=True):
            curves = {}
            for m in self.study.methods:
                st = summarise(scores[m])
                curves[m] = (st["mean"], st["q05"], st["q95"])
            out.append((label, k, curves))
        return out

    def summary(self) -> str:
        """One line: the mean log LR at the last scan of each case and method."""
        last = "; ".join(
            f"{label}: " + ", ".join(f"{m} {scores[m][:, -1].mean():.1f}" for m in self.study.methods)
            for (label, _), scores in zip(self.study.cases, self.scores, strict=True)
        )
        return f"slrt: mean log LR at scan {self.study.scenario.scans}: {last}"


def scan_picture(
    study: SlrtStudy,
) -> tuple[np.ndarray, list[np.ndarray], list[np.ndarray], np.ndarray, str]:
    """The last scan of run 0 of the first case, for a figure: (sensors, false alarms and target detections
    per sensor in x–y, the true track up to that scan, a title). Run 0 is drawn again: it depends on
    (seed, 0) only, so it is the run 0 of the Monte Carlo."""
    label, sc = study.cases[0]
    gen = generate(sc, range(1), study.seed)
    k = sc.scans - 1
    clutter_xy, target_xy = scan_xy(sc, gen, 0, k)
    return sc.sensors, clutter_xy, target_xy, gen.truth[0, : k + 1], f"{label}: run 0, scan {k + 1}"


def scan_xy(
    sc: SlrtScenario, gen: Generated, run: int, scan: int
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """One scan of one run in Cartesian x–y, per sensor: (false alarms, target detections). The generator puts
    the target detection (if any) first in each sensor's list."""
    clutter_xy, target_xy = [], []
    for s in range(sc.n_sensors):
        Z = gen.scans[scan].Z[s][run][gen.scans[scan].valid[s][run]]
        if sc.meas_model == "cartesian":
            xy = Z
        else:
            xy = sc.sensors[s] + Z[:, :1] * np.stack([np.cos(Z[:, 1]), np.sin(Z[:, 1])], axis=-1)
        n_t = len(xy) - int(gen.clutter_counts[run, scan, s])
        target_xy.append(xy[:n_t])
        clutter_xy.append(xy[n_t:])
    return clutter_xy, target_xy


def cost(sc: SlrtScenario, runs: int, cases: int = 1, methods: int = 3) -> tuple[float, float]:
    """Rough (seconds, bytes) of ``cases`` Monte Carlo cases scored by ``methods`` fusion rules: a fixed cost
    per sensor-scan (≈ 0.9 ms of Python for three rules) plus a per-row cost that grows with the clutter (a row:
    a run, or with ``false_tracks`` each of its S·λ_F false tracks on average, whose data are gathered per track);
    the filters' part scales with the number of rules (``make bench``'s bench_slrt measures each rule)."""
    rows = runs * tracks_per_run(sc)  # filter rows: a run, or its false tracks
    weight = rows * (FALSE_TRACK_COST if sc.false_tracks else 1.0)
    filters = (0.9e-3 + 3e-5 * weight * (1.0 + sc.clutter_rate / 5.0)) * (methods / 3.0)
    per_sensor_scan = filters + 2e-5 * runs  # filters + generation
    seconds = cases * sc.scans * sc.n_sensors * per_sensor_scan
    nbytes = (
        sc.scans
        * sc.n_sensors
        * (runs + rows)
        * (sc.clutter_rate + 4.0 * math.sqrt(sc.clutter_rate + 1.0) + 2.0)
        * 17.0
    )
    return seconds, nbytes


def summarise(loglr: np.ndarray) -> dict[str, np.ndarray]:
    """Mean, median and the 5 / 95 % quantiles over runs, per scan (quantiles without interpolation, so a
    score of −inf — p_D = 1 and a missed target — stays −inf instead of becoming NaN)."""
    return {
        "mean": loglr.mean(axis=0),
        "median": np.quantile(loglr, 0.5, axis=0, method="inverted_cdf"),
        "q05": np.quantile(loglr, 0.05, axis=0, method="inverted_cdf"),
        "q95": np.quantile(loglr, 0.95, axis=0, method="inverted_cdf"),
    }


def lost_after_confirmation(loglr: np.ndarray, log_a: float, log_b: float) -> np.ndarray:
    """Per run, whether the test confirmed the track and its score later fell by log B − log A (the test's
    width) below its running maximum since the confirmation: a continued test on the confirmed track (a
    CUSUM-type deletion: assumed, the slides do not say how a confirmed track is maintained) would then
    delete it. A −inf score after a confirmation counts as lost."""
    d = first_crossing(loglr, log_a, log_b)
    k = np.arange(loglr.shape[-1])
    after = (d.decision == 1)[:, None] & (k[None, :] >= (d.time - 1)[:, None])
    masked = np.where(after, loglr, -np.inf)
    running = np.maximum.accumulate(masked, axis=-1)
    with np.errstate(invalid="ignore"):
        fall = np.where(after, running - loglr, 0.0)
    return np.any(after & ((fall >= log_b - log_a) | np.isneginf(loglr)), axis=-1)


def clopper_pearson(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """The exact (Clopper–Pearson) interval of a binomial proportion, k successes of n: the ``(1−level)/2``
    and ``(1+level)/2`` quantiles of Beta(k, n−k+1) and Beta(k+1, n−k); 0 (1) at k = 0 (n)."""
    from scipy.special import betaincinv

    a = (1.0 - level) / 2.0
    lo = 0.0 if k == 0 else float(betaincinv(k, n - k + 1, a))
    hi = 1.0 if k == n else float(betaincinv(k + 1, n - k, 1.0 - a))
    return lo, hi


def _first_times(scores: np.ndarray, levels: Sequence[float], up: bool) -> np.ndarray:
    """(L, n): per level, the 0-based scan at which each row's score first reaches it (≥ a level ``up``, ≤ it
    otherwise), or the number of scans K where it never does."""
    run = np.maximum.accumulate(scores, axis=-1) if up else -np.minimum.accumulate(scores, axis=-1)
    lv = np.asarray(levels, dtype=float)[:, None, None] * (1.0 if up else -1.0)
    return (run[None] < lv).sum(axis=-1)  # the running extreme is monotone: scans before the first hit


def _oc_grid(target: np.ndarray, false: np.ndarray) -> list[tuple[Any, ...]]:
    """The operating characteristic over the threshold grid :data:`OC_LOG_A` × :data:`OC_LOG_B` (the columns of
    :data:`OC_COLUMNS` from ``log_A``): per pair Wald's design (α, β) of the thresholds, and the first-crossing
    rates (exact 95 % intervals) and mean decision scans on the false tracks and the target runs. The first
    crossing of (a, b) is the earlier of the first scans at which the score reaches b and a (each computed once
    per threshold from the running maximum and minimum)."""
    times = {}
    for name, scores in (("false", false), ("target", target)):
        times[name] = (_first_times(scores, OC_LOG_A, up=False), _first_times(scores, OC_LOG_B, up=True))
    rows = []
    for i, log_a in enumerate(OC_LOG_A):
        for j, log_b in enumerate(OC_LOG_B):
            A, B = math.exp(log_a), math.exp(log_b)
            out: list[Any] = [log_a, log_b, (1 - A) / (B - A), A * (B - 1) / (B - A)]
            for name, kinds in (("false", (1,)), ("target", (1, -1))):
                down, up = times[name][0][i], times[name][1][j]
                n = down.size
                out.append(n)
                for kind in kinds:
                    k = int((up < down).sum() if kind == 1 else (down < up).sum())
                    out += [k / n, *clopper_pearson(k, n)]
                first = np.minimum(down, up)
                decided = first[first < (false if name == "false" else target).shape[-1]]
                out.append(float(decided.mean() + 1) if decided.size else None)
            rows.append(tuple(out))
    return rows


def _binomial_se(p: float, n: int) -> float:
    """The binomial standard error √(p(1−p)/n) of a fraction p of n runs."""
    return math.sqrt(p * (1.0 - p) / n)


def decisions(loglr: np.ndarray, alpha: float, beta: float) -> Decisions:
    """Wald's first-crossing decisions on each run."""
    log_a, log_b = wald_thresholds(alpha, beta)
    return first_crossing(loglr, log_a, log_b)
