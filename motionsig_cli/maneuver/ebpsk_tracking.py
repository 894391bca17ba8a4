"""The trackers of Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System* ("the
paper") on the measurements of the EBPSK radar front end, along the paper's trajectory.

The paper feeds its trackers with Cartesian positions of a fixed σ (100 or 200 m per axis, §V) and says that
they come from an EBPSK joint radar–communication front end by weighted-least-squares location (§I, Fig. 1).
Here the positions are made by that front end (:mod:`motionsig_cli.maneuver.ebpsk_radar`):

* **Geometry** (assumed; the paper gives none): one radar at :data:`DEFAULT_RADAR_POSITION` = (150 km, 150 km),
  beside the track (the literal trajectory's first point is the origin; from there the range runs from 92 km to
  530 km), measuring range and bearing φ = atan2(y − y_s, x − x_s) once per scan.
* **SNR along the track**: E/N₀(k) of scan k from the radar equation at the true range r(k)
  (:class:`~motionsig_cli.models.radar_equation.RadarEquation`), the target's radial speed giving the Doppler
  shift of the sample-level echo.
* **Detection** with P_D(E/N₀) < 1 (CA-CFAR after the impacting filter): a missed scan is a NaN measurement,
  a predict-only step of every tracker. The track is initiated on scans 1 and 2, which are therefore taken as
  detected (assumed: the Monte Carlo conditions on the initiation; the trackers' two-point initialisation needs
  them).
* **Range and bearing errors**: σ_r(E/N₀) of the impact-peak range estimator and σ_φ = θ₃dB/(k_m √(2 E/N₀))
  of the monopulse model, at the true E/N₀ (assumed: the front end knows its SNR).
* **Location** (:func:`~motionsig_cli.maneuver.ebpsk_radar.locate`, one sensor): the position
  p = s + r̂ (cos φ̂, sin φ̂) and its covariance R(k) = J diag(σ_r², σ_φ²) Jᵀ at the measured (r̂, φ̂) — the
  measurement and the time-varying R(k) of every tracker (:mod:`motionsig_cli.filters.imm`,
  :mod:`motionsig_cli.detection.glr`) — plus the conversion's second-order term along the line of sight
  (cf. Lerro & Bar-Shalom, *Tracking with debiased consistent converted measurements versus EKF*, IEEE T-AES
  1993): there the error is δr + r(1 − cos δφ) ≈ δr + r δφ²/2, of mean square σ_r² + ¾ r̂² σ_φ⁴, so R gains
  ¾ r̂² σ_φ⁴ u uᵀ (u the measured line of sight; assumed: the mean r σ_φ²/2, metres against a cross-range σ of
  kilometres, is left in). At the far end of the track σ_r is ~1 m and r σ_φ²/2 several metres: without the
  term R would understate the radial error there by a factor of several.

Two levels make the same measurements: ``samples`` simulates every scan's echo at the sample level (waveform,
impacting filter, CA-CFAR, parabolic range interpolation: slow, for tests and short runs), ``detector`` draws
detections and errors from the statistics of that chain (:class:`~motionsig_cli.maneuver.ebpsk_radar.
DetectorEquivalent`: fast, for long Monte Carlos). Run r draws only from its own generator (``trial_rng(seed,
r)``), scan after scan, so its record does not depend on the other runs or on the number of workers.

**σ delivered.** The position σ of scan k is σ_pos(k) = √(tr R(k)/2), the RMS per axis, comparable to the
paper's σ per axis. E/N₀ ∝ P_t and σ_pos decreases with E/N₀ (σ_φ ∝ 1/√(E/N₀); σ_r falls to the floor of the
range estimator), so the transmit power that gives a σ is a root in log P_t (:meth:`EbpskFrontEnd.power_for`).
With ``calibrate`` the source sets P_t so that the *median* σ_pos along the track equals the σ asked for
(assumed: the median, one number along a track whose σ varies as r³ at a fixed power).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from motionsig_cli.config import ConfigError, one_of

if TYPE_CHECKING:
    from motionsig_cli.maneuver.ebpsk_radar import DetectorEquivalent, EbpskRadar, EbpskRadarConfig
    from motionsig_cli.maneuver.scenario import ManeuverScenario
    from motionsig_cli.tables import Table

__all__ = [
    "DEFAULT_RADAR_POSITION",
    "LEVELS",
    "EbpskFrontEnd",
    "EbpskPositions",
    "FrontEndScans",
    "front_end_figure_data",
    "front_end_table",
    "track_phases",
]

LEVELS = ("detector", "samples")
"""``detector``: draws from the chain's statistics; ``samples``: the sample-level chain at every scan."""
DEFAULT_RADAR_POSITION = (150e3, 150e3)
"""The radar's position [m] (assumed: beside the paper's trajectory, 92–530 km from every point of the literal
track and 212–343 km from the turn90 track)."""
POSITION_LIMIT = 1e8
"""|x|, |y| of the radar accepted [m]."""
SPEED_STEP = 500.0
"""Spacing of the radial-speed nodes of P_D [m/s] (the Doppler loss is 0.6 dB at 3 km/s, smooth in |ṙ|)."""
SAMPLES_SECONDS_PER_PULSE = 3e-3
"""Run time of one sample-level pulse on a 2-core machine [s] (measured: 1000 pulses in 3 s)."""


def _default_radar() -> EbpskRadarConfig:
    from motionsig_cli.maneuver.ebpsk_radar import EbpskRadarConfig

    return EbpskRadarConfig()


@functools.lru_cache(maxsize=4)
def _chain(cfg: EbpskRadarConfig) -> EbpskRadar:
    """The sample-level chain of ``cfg`` (built once per process)."""
    from motionsig_cli.maneuver.ebpsk_radar import EbpskRadar

    return EbpskRadar(cfg)


def _normalised(cfg: EbpskRadarConfig) -> EbpskRadarConfig:
    """``cfg`` with the default power budget: the chain and its equivalent depend on E/N₀ only, not on the
    budget that sets it, so one chain serves every transmit power."""
    from motionsig_cli.models.radar_equation import RadarEquation

    return dataclasses.replace(cfg, radar=RadarEquation(fs=cfg.radar.fs))


@dataclass(frozen=True)
class FrontEndScans:
    """What the front end delivers at each scan of the noise-free track (arrays over scans 1..N).

    Attributes:
        range, bearing: true range [m] and bearing [rad] from the radar.
        radial_speed: ṙ [m/s] (positive: receding).
        enr: E/N₀ (linear) from the radar equation.
        pd: detection probability.
        sigma_range, sigma_bearing: σ_r [m], σ_φ [rad].
        sigma_cross: r σ_φ [m], the cross-range σ.
        sigma_pos: √(tr R/2) [m], the position σ per axis (RMS of the two axes).
    """

    range: np.ndarray
    bearing: np.ndarray
    radial_speed: np.ndarray
    enr: np.ndarray
    pd: np.ndarray
    sigma_range: np.ndarray
    sigma_bearing: np.ndarray

    @property
    def sigma_cross(self) -> np.ndarray:
        return self.range * self.sigma_bearing

    @property
    def sigma_pos(self) -> np.ndarray:
        return np.sqrt(0.5 * (self.sigma_range**2 + self.sigma_cross**2))


@dataclass(frozen=True)
class EbpskFrontEnd:
    """The EBPSK radar at a position, measuring a track (module docstring).

    Attributes:
        radar: the radar (:class:`~motionsig_cli.maneuver.ebpsk_radar.EbpskRadarConfig`; None: its defaults,
            Table I's waveform and the assumed budget). Only the ``monopulse`` bearing model scales with SNR,
            as :meth:`power_for` needs: ``fixed`` is refused.
        position: the radar's (x, y) [m] (assumed :data:`DEFAULT_RADAR_POSITION`), each within ±1e8 m.
        level: one of :data:`LEVELS`.
        radial_speed: |ṙ| [m/s] of the range-error calibration of the detector-level statistics; None: the
            median |ṙ| along the track (assumed: σ_r depends little on the Doppler; P_D, which does, is taken at
            every scan's own |ṙ|, interpolated between nodes :data:`SPEED_STEP` apart).
        eq: the detector-output statistics, once built (:meth:`prepared`; they take seconds to calibrate, and a
            prepared front end carries them to the workers).
        pd_nodes: ((|ṙ|, statistics), …) the detection statistics at the speed nodes (:meth:`prepared`).
    """

    radar: EbpskRadarConfig | None = None
    position: tuple[float, float] = DEFAULT_RADAR_POSITION
    level: str = "detector"
    radial_speed: float | None = None
    eq: DetectorEquivalent | None = field(default=None, compare=False, repr=False)
    pd_nodes: tuple[tuple[float, DetectorEquivalent], ...] = field(default=(), compare=False, repr=False)

    def __post_init__(self) -> None:
        if self.radar is None:
            object.__setattr__(self, "radar", _default_radar())
        one_of("level", self.level, LEVELS)
        try:
            pos = tuple(float(v) for v in self.position)
        except (TypeError, ValueError):
            raise ConfigError("radar_position", self.position, "is not a position x,y [m]") from None
        if len(pos) != 2 or not all(math.isfinite(v) and abs(v) <= POSITION_LIMIT for v in pos):
            raise ConfigError("radar_position", self.position, "is not a finite position x,y within ±1e8 m")
        object.__setattr__(self, "position", pos)
        if self.cfg.bearing != "monopulse":
            raise ConfigError("bearing", self.cfg.bearing, "is not 'monopulse' (σ_φ must scale with SNR)")
        if self.radial_speed is not None and not (
            math.isfinite(self.radial_speed) and 0 <= self.radial_speed <= 1e5
        ):
            raise ConfigError("radial_speed", self.radial_speed, "is not a speed in [0, 1e5] m/s")

    @property
    def cfg(self) -> EbpskRadarConfig:
        assert self.radar is not None
        return self.radar

    @property
    def p_t(self) -> float:
        """Transmit power [W]."""
        return float(self.cfg.radar.p_t)

    def with_power(self, p_t: float) -> EbpskFrontEnd:
        """The same front end with transmit power ``p_t`` [W] (the statistics do not depend on it)."""
        radar = dataclasses.replace(self.cfg, radar=dataclasses.replace(self.cfg.radar, p_t=float(p_t)))
        return dataclasses.replace(self, radar=radar)

    def speed_for(self, truth: np.ndarray) -> float:
        """|ṙ| of the detector-level statistics: ``radial_speed``, else the median along ``truth``."""
        if self.radial_speed is not None:
            return self.radial_speed
        return float(np.median(np.abs(self.geometry(truth)[2])))

    def prepared(self, truth: np.ndarray) -> EbpskFrontEnd:
        """This front end with its radial speed fixed and its detector-output statistics built (also the
        detection statistics at the speed nodes that cover the track's |ṙ|)."""
        speed = self.speed_for(truth)
        eq = self.eq if self.eq is not None and self.radial_speed == speed else None
        eq = eq or self.chain().equivalent(speed)
        top = float(np.max(np.abs(self.geometry(truth)[2])))
        nodes = tuple(SPEED_STEP * i for i in range(math.ceil(top / SPEED_STEP) + 1))
        have = dict(self.pd_nodes)
        pd_nodes = tuple((v, have.get(v) or self._at_speed(eq, v)) for v in nodes)
        return dataclasses.replace(self, radial_speed=speed, eq=eq, pd_nodes=pd_nodes)

    def _at_speed(self, eq: DetectorEquivalent, speed: float) -> DetectorEquivalent:
        """``eq`` with the CUT gains of targets at radial speed ``speed`` (their Doppler loss)."""
        gain = tuple(float(g) for g in self.chain().noise_free_gain(speed))
        return dataclasses.replace(eq, gain=gain)

    def _pd(self, enr: np.ndarray, rdot: np.ndarray, eq: DetectorEquivalent) -> np.ndarray:
        """P_D of every scan at its E/N₀ and |ṙ|: linear in |ṙ| between the nodes (``eq``'s without nodes)."""
        if not self.pd_nodes:
            return eq.pd(enr)
        v = np.array([n for n, _ in self.pd_nodes])
        table = np.stack([e.pd(enr) for _, e in self.pd_nodes])  # (nodes, N)
        s = np.clip(np.abs(rdot), v[0], v[-1])
        i = np.clip(np.searchsorted(v, s, side="right") - 1, 0, max(len(v) - 2, 0))
        if len(v) == 1:
            return table[0]
        w = (s - v[i]) / (v[i + 1] - v[i])
        cols = np.arange(enr.size)
        return (1 - w) * table[i, cols] + w * table[i + 1, cols]

    def equivalent(self, truth: np.ndarray) -> DetectorEquivalent:
        """The detector-output statistics of the chain at :meth:`speed_for` (cached per process)."""
        if self.eq is not None:
            return self.eq
        return self.chain().equivalent(self.speed_for(truth))

    def chain(self) -> EbpskRadar:
        """The sample-level chain (cached per process)."""
        return _chain(_normalised(self.cfg))

    def check_track(self, truth: np.ndarray) -> None:
        """Every scan's target must be beyond the blind range c·T_p/2 (the echo overlaps the pulse) and within
        the unambiguous range c·PRI/2; :class:`ConfigError` on ``radar_position`` / ``pri`` otherwise."""
        from motionsig_cli.models.radar_equation import C_LIGHT

        d = truth[:, [0, 2]] - np.asarray(self.position)
        r = np.hypot(d[:, 0], d[:, 1])
        blind = C_LIGHT * self.cfg.pulse_duration / 2.0
        if np.any(r <= blind):
            k = int(np.argmin(r))
            raise ConfigError(
                "radar_position", self.position,
                f"puts the target {r[k]:.0f} m from the radar at scan {k + 1}, inside the blind range c·T_p/2 = "
                f"{blind:.0f} m (the echo overlaps the pulse)",
            )  # fmt: skip
        if np.any(r > self.cfg.max_range):
            k = int(np.argmax(r))
            raise ConfigError(
                "pri", self.cfg.pri,
                f"s gives the unambiguous range c·PRI/2 = {self.cfg.max_range / 1e3:.1f} km, but the target is "
                f"{r[k] / 1e3:.1f} km from the radar at scan {k + 1} (shorten the track, move the radar or "
                "lengthen the PRI)",
            )  # fmt: skip

    def geometry(self, truth: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Range r [m], bearing φ [rad] and radial speed ṙ [m/s] of every scan of ``truth`` (N, 4)."""
        d = truth[:, [0, 2]] - np.asarray(self.position)
        r = np.hypot(d[:, 0], d[:, 1])
        phi = np.arctan2(d[:, 1], d[:, 0])
        rdot = (d[:, 0] * truth[:, 1] + d[:, 1] * truth[:, 3]) / r
        return r, phi, rdot

    def scans(self, truth: np.ndarray, gain: float = 1.0) -> FrontEndScans:
        """The front end's statistics at every scan of ``truth`` (N, 4) [x, ẋ, y, ẏ] (:class:`FrontEndScans`),
        with the transmit power times ``gain``."""
        self.check_track(truth)
        r, phi, rdot = self.geometry(truth)
        enr = self.cfg.energy_snr(r) * gain
        eq = self.equivalent(truth)
        pd = self._pd(enr, rdot, eq)
        return FrontEndScans(r, phi, rdot, enr, pd, eq.sigma_range(enr), eq.sigma_bearing(enr))

    def power_for(
        self, truth: np.ndarray, sigma: float, scans: slice = slice(None), stat: str = "rms"
    ) -> float:
        """The transmit power [W] at which the ``stat`` (``rms`` or ``median``) of σ_pos over ``scans`` of
        ``truth`` is ``sigma`` [m] (σ_pos decreases with P_t: a root in log P_t); inf if no power reaches it
        (the range error's floor)."""
        from scipy.optimize import brentq

        def f(log_gain: float) -> float:
            v = self.scans(truth, 10.0**log_gain).sigma_pos[scans]
            agg = float(np.sqrt(np.mean(v**2))) if stat == "rms" else float(np.median(v))
            return math.log(agg / sigma)

        lo, hi = -30.0, 30.0
        if f(hi) > 0:
            return math.inf
        if f(lo) < 0:
            return 0.0
        return self.p_t * 10.0 ** brentq(f, lo, hi, xtol=1e-12, rtol=1e-12)

    def calibrated(self, truth: np.ndarray, sigma: float) -> EbpskFrontEnd:
        """This front end with the transmit power at which the median σ_pos along ``truth`` is ``sigma``."""
        p = self.power_for(truth, sigma, stat="median")
        if p == math.inf:
            raise ConfigError(
                "sigmas", sigma, "m is below what any transmit power gives (the range error's floor)"
            )
        if not 0 < p <= 1e15:
            raise ConfigError(
                "sigmas", sigma, f"m needs a transmit power of {p:.3g} W (the front end reaches (0, 1e15] W)"
            )
        return self.with_power(p)

    # --------------------------------------------------------------------------------------- measurements
    def measure(
        self, truth: np.ndarray, rngs: Sequence[np.random.Generator], *, initiation: int = 2
    ) -> tuple[np.ndarray, np.ndarray]:
        """Positions z (B, N, 2) and covariances R (B, N, 2, 2) of B runs (NaN at missed scans).

        Run r draws from ``rngs[r]``: ``detector``: U(0, 1) (N,) for detection, N(0, 1) (N,) for range, then
        N(0, 1) (N,) for bearing; ``samples``: per scan, the sub-sample delay U(0, 1), the carrier phase
        U(0, 2π) and the window's noise N(0, 1), then N(0, 1) (N,) for bearing. The first ``initiation`` scans
        are taken as detected (module docstring).
        """
        st = self.scans(truth)
        B, N = len(rngs), truth.shape[0]
        if self.level == "detector":
            det = np.empty((B, N), dtype=bool)
            dr = np.empty((B, N))
            dphi = np.empty((B, N))
            for b, g in enumerate(rngs):  # one generator per run: the draws are the run's own
                det[b] = g.random(N) < st.pd
                dr[b] = g.standard_normal(N)
                dphi[b] = g.standard_normal(N)
            dr *= st.sigma_range
        else:
            det, dr = self._samples(st, rngs)
            dphi = np.stack([g.standard_normal(N) for g in rngs]) if B else np.zeros((0, N))
        det[:, :initiation] = True  # the initiation (module docstring)
        r_m = st.range + dr
        phi_m = st.bearing + dphi * st.sigma_bearing
        phi_m = np.pi - np.mod(np.pi - phi_m, 2.0 * np.pi)  # wrapped to (−π, π]
        return self._locate(np.where(det, r_m, np.nan), np.where(det, phi_m, np.nan), st)

    def _samples(
        self, st: FrontEndScans, rngs: Sequence[np.random.Generator]
    ) -> tuple[np.ndarray, np.ndarray]:
        """The sample-level chain at every scan: (detected (B, N), range error [m] (B, N)). At the
        initiation scans the error is the estimate's whether the CFAR crossed or not."""
        from motionsig_cli.models.radar_equation import C_LIGHT

        chain = self.chain()
        B, N = len(rngs), st.range.size
        det = np.zeros((B, N), dtype=bool)
        err = np.zeros((B, N))
        if B == 0:
            return det, err
        f_c = self.cfg.wave.f_carrier
        for k in range(N):  # the Doppler differs per scan; each scan is one batch over the runs
            u = np.empty((B, 2))
            noise = np.empty((B, chain.window))
            for b, g in enumerate(rngs):
                u[b] = g.random(2)
                noise[b] = g.standard_normal(chain.window)
            out = chain.measure(np.full(B, st.enr[k]), u[:, 0], 2.0 * math.pi * u[:, 1], noise,
                                2.0 * st.radial_speed[k] * f_c / C_LIGHT)  # fmt: skip
            det[:, k] = out["detected"]
            err[:, k] = out["error_all"]
        return det, err

    def _locate(self, r: np.ndarray, phi: np.ndarray, st: FrontEndScans) -> tuple[np.ndarray, np.ndarray]:
        from motionsig_cli.maneuver.ebpsk_radar import locate

        sig = np.stack([st.sigma_range, st.sigma_bearing], axis=-1)  # (N, 2)
        xy, cov = locate(r[..., None], phi[..., None], np.broadcast_to(sig[:, None, :], (*r.shape, 1, 2)),
                         np.asarray(self.position)[None])  # fmt: skip
        # second order of the polar conversion: along the measured line of sight the error is
        # δr + r(1 − cos δφ) ≈ δr + r δφ²/2, of mean square σ_r² + ¾ r² σ_φ⁴ (J diag Jᵀ has σ_r² only)
        u = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
        s2 = st.sigma_bearing**2
        cov = cov + (0.75 * r * r * s2 * s2)[..., None, None] * (u[..., :, None] * u[..., None, :])
        return xy, cov

    def meta(self) -> dict[str, Any]:
        """The front end as a table's provenance names it."""
        c, q = self.cfg, self.cfg.radar
        return {
            "level": self.level,
            "radar_position_m": list(self.position),
            "p_t_W": q.p_t,
            "gain_dBi": [q.g_t_db, q.g_r_db],
            "f_c_Hz": q.f_c,
            "rcs_m2": q.rcs,
            "loss_dB": q.loss_db,
            "noise_figure_dB": q.noise_figure_db,
            "n_pulses": q.n_pulses,
            "pfa": c.pfa,
            "radial_speed_m_s": self.radial_speed,
            "n_train": c.n_train,
            "pri_s": c.pri,
            "bits": "".join(map(str, c.bits)),
            "waveform": {
                "N": c.wave.N,
                "K": c.wave.K,
                "theta": c.wave.theta,
                "f_if": c.wave.f_if,
                "fs": c.wave.fs,
            },
            "bearing": f"monopulse σ_φ = θ3dB/(k_m √(2 E/N0)), θ3dB = {math.degrees(c.beamwidth):g}°, "
            f"k_m = {c.k_m:g}",
            "location": "one radar: p = s + r(cos φ, sin φ), R = J diag(σ_r², σ_φ²) Jᵀ + ¾ r² σ_φ⁴ u uᵀ at the "
            "measured (r, φ) (u the line of sight: the conversion's second-order mean square error)",
            "initiation": "scans 1 and 2 taken as detected (the track's initiation)",
        }


@dataclass(frozen=True)
class EbpskPositions:
    """The measurement source ``ebpsk`` of :mod:`motionsig_cli.maneuver.study`: positions located by the
    EBPSK front end, with their covariance R(k) and missed scans (module docstring).

    Attributes:
        front_end: the radar, its position and the level.
        calibrate: scale the transmit power so that the median σ_pos along the track is the job's σ; False:
            the radar as given (σ is then a label only: the job's σ should be the delivered median).
    """

    name: ClassVar[str] = "ebpsk"
    seeding: ClassVar[str] = (
        "run r draws from SeedSequence(seed).spawn(...)[r]: detector level U(0,1) x scans (detection), "
        "N(0,1) x scans (range), N(0,1) x scans (bearing); samples level per scan U(0,1) delay, U(0,1) "
        "phase, N(0,1) x window noise, then N(0,1) x scans (bearing)"
    )

    front_end: EbpskFrontEnd = field(default_factory=EbpskFrontEnd)
    calibrate: bool = True

    def front_end_for(self, truth: np.ndarray, sigma: float) -> EbpskFrontEnd:
        """The front end that measures at σ (calibrated, or as given)."""
        return self.front_end.calibrated(truth, sigma) if self.calibrate else self.front_end

    def measure(self, truth: np.ndarray, sigma: float, rngs: Sequence[np.random.Generator]) -> np.ndarray:
        """Positions z (B, N, 2), NaN at missed scans (:meth:`measure_cov` without R)."""
        return self.measure_cov(truth, sigma, rngs)[0]

    def measure_cov(
        self, truth: np.ndarray, sigma: float, rngs: Sequence[np.random.Generator]
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """Positions z (B, N, 2) and covariances R (B, N, 2, 2), NaN at missed scans."""
        return self.front_end_for(truth, sigma).measure(truth, rngs)

    def seconds_per_run(self, scans: int) -> float:
        """Rough cost of one run's measurements [s] (the samples level simulates a pulse per scan)."""
        return scans * (SAMPLES_SECONDS_PER_PULSE if self.front_end.level == "samples" else 2e-6)

    def identity(self) -> dict[str, Any]:
        """Everything the measurements depend on (JSON values)."""
        return {"name": self.name, "calibrate": self.calibrate, **self.front_end.meta()}

    def meta(self, truth: np.ndarray, sigmas: Sequence[float]) -> dict[str, Any]:
        """Provenance: the front end and, per σ, the transmit power used."""
        fes = [self.front_end_for(truth, s) for s in sigmas]
        out = self.front_end.meta()
        out["p_t_W"] = [fe.p_t for fe in fes] if len(fes) > 1 else fes[0].p_t
        out["calibration"] = (
            "P_t set so that the median position σ (per axis) along the track is σ"
            if self.calibrate
            else "none"
        )
        return out


# ------------------------------------------------------------------------------------------ the table
def track_phases(sc: ManeuverScenario) -> list[tuple[str, int, int]]:
    """Contiguous phases [a, b) covering scans 1..N: cruise, turn 1, turn 2, after."""
    (a1, _, _, _), (a2, b2, _, _) = sc.segments[0], sc.segments[1]
    out = [("cruise", 1, a1), ("turn 1", a1, a2), ("turn 2", a2, b2), ("after", b2, sc.scans + 1)]
    return [(n, a, min(b, sc.scans + 1)) for n, a, b in out if min(b, sc.scans + 1) > a]


def front_end_table(
    sc: ManeuverScenario, fe: EbpskFrontEnd, sigmas: Sequence[float] = (100.0, 200.0)
) -> Table:
    """Per phase of the track (and the whole track): range, E/N₀, P_D, σ_r, σ_φ, the cross-range and position
    σ the front end delivers at its transmit power, beside the paper's σ values, with the transmit power, E/N₀
    and P_D at which the phase's RMS position σ would equal each of them."""
    from motionsig_cli.tables import Table, make_meta

    truth = sc.truth()
    st = fe.scans(truth)
    cols = ["phase", "first_scan", "last_scan", "range_min_km", "range_max_km", "enr_db", "pd", "sigma_range_m",
            "sigma_bearing_mrad", "sigma_cross_m", "sigma_pos_m"]  # fmt: skip
    for s in sigmas:
        cols += [f"p_t_W_for_{s:g}", f"enr_db_for_{s:g}", f"pd_for_{s:g}"]
    rows = []
    for name, a, b in [*track_phases(sc), ("track", 1, sc.scans + 1)]:
        sel = slice(a - 1, b - 1)

        def rms(v: np.ndarray, sel: slice = sel) -> float:
            return float(np.sqrt(np.mean(v[sel] ** 2)))

        enr_db = 10.0 * np.log10(st.enr[sel])
        row: list[Any] = [name, a, b - 1, float(st.range[sel].min() / 1e3), float(st.range[sel].max() / 1e3),
                          float(enr_db.mean()), float(st.pd[sel].mean()), rms(st.sigma_range),
                          1e3 * rms(st.sigma_bearing), rms(st.sigma_cross), rms(st.sigma_pos)]  # fmt: skip
        for s in sigmas:
            p = fe.power_for(truth, s, sel)
            ok = 0 < p < math.inf
            gain = p / fe.p_t if ok else math.nan
            row += [
                p if ok else None,
                float(enr_db.mean() + 10.0 * math.log10(gain)) if ok else None,
                float(fe.scans(truth, gain).pd[sel].mean()) if ok else None,
            ]
        rows.append(tuple(row))
    meta = make_meta(
        "maneuver",
        view="front-end",
        preset=sc.preset,
        T=sc.T,
        scans=sc.scans,
        front_end=fe.meta(),
        sigma_paper=list(sigmas),
        columns_note="per phase: range min/max, mean E/N0 [dB], mean P_D, RMS of σ_r, σ_φ, r σ_φ and "
        "σ_pos = √(tr R/2) over the phase's scans at P_t; p_t_W_for_σ: the P_t at which the phase's RMS σ_pos "
        "is σ, with the E/N0 and P_D it gives (empty: no power reaches σ)",
        sources="trajectory and σ = 100, 200 m: Yao, Teng & Wu, Maneuvering Target Tracking Based on EBPSK "
        "Modulated JRC System (§V, Table I); radar position and power budget assumed",
    )
    return Table(columns=tuple(cols), rows=rows, meta=meta)


def front_end_figure_data(sc: ManeuverScenario, fe: EbpskFrontEnd, sigmas: Sequence[float]) -> dict[str, Any]:
    """Keyword arguments of :func:`motionsig_cli.plotting.ebpsk_front_end_figure`: per scan the range, E/N₀,
    P_D, σ_r, cross-range σ and position σ, beside the paper's σ values."""
    st = fe.scans(sc.truth())
    return {
        "scan": np.arange(1, sc.scans + 1),
        "range_km": st.range / 1e3,
        "enr_db": 10.0 * np.log10(st.enr),
        "pd": st.pd,
        "sigma_range": st.sigma_range,
        "sigma_cross": st.sigma_cross,
        "sigma_pos": st.sigma_pos,
        "sigma_paper": tuple(sigmas),
        "title": f"EBPSK front end at P_t = {fe.p_t:.3g} W, radar at ({fe.position[0] / 1e3:g}, "
        f"{fe.position[1] / 1e3:g}) km",
    }
