"""The radar function of an EBPSK joint radar–communication front end: echo, impacting filter, CA-CFAR, range,
bearing and location, and its equivalent at the detector output for long tracking runs.

Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System*, name but do not specify this
part of their front end: EBPSK pulses (Table I: carrier 10 GHz, IF 100 MHz, sampling 1 GHz, K = 2, N = 7), echoes
detected after the EBPSK impacting filter by an amplitude threshold with CFAR, and a weighted-least-squares target
location that feeds the trackers. Everything below that the paper does not state is assumed, and says so.

Transmitted pulse: the payload bits (the communication message; any sequence with at least one 1 — the impacting
filter answers bit-1 symbols only) EBPSK-modulated at the IF, T_p = n_bits · N / f_if.

Echo (sample level), from a target at range r with radial speed v_r (positive: receding):

    x(t) = A sin(2π (f_if − f_D)(t − τ) + θ b(t − τ) + φ₀) on 0 ≤ t − τ < T_p,  τ = 2r/c,  f_D = 2 v_r f_c / c,

plus real white Gaussian noise of variance σ_n² = N₀ f_s/2 per sample (:mod:`motionsig_cli.models.radar_equation`).
The Doppler shift is a phase rotation 2π f_D (t − τ) across the pulse (narrow-band approximation: the stretch
of the envelope by 1 − 2v_r/c, 3·10⁻⁶ at 450 m/s, is neglected — it moves the pulse end by 10⁻¹¹ s). The echo's
carrier phase φ₀ (2π f_c τ modulo 2π: λ = 3 cm makes it random from pulse to pulse) is uniform on [0, 2π) (assumed).
The echo is sampled from this analytic form: the delay need not be a whole number of samples.

Receiver: (1) the impacting filter (:func:`motionsig_cli.signals.ebpsk.impacting_filter`); (2) I/Q: the filter
output times exp(−j2π f_if n/f_s), averaged over one IF period (L = f_s/f_if = 10 samples: a boxcar that nulls the
2 f_if image exactly when L is a whole number); (3) impact integration: the payload is known to the radar that
sent it, so the I/Q samples at the starts of the bit-1 symbols (N·L samples apart) are added coherently,
u[n] = Σ_j z[n + d_j] (assumed; with a single 1 bit, u is the plain impact); (4) square-law CA-CFAR
(:mod:`motionsig_cli.detection.cfar`): the cell under test is |u[n]|², the noise level is the mean of N_t training
cells of |z|² spaced by the noise correlation length of z (|ρ|² < 0.01) beyond guard cells that cover the whole
echo response, times the known ratio E|u|²/E|z|² of the integration (the integrated samples are correlated over
the whole pulse, the unintegrated ones over a few tens of samples, so the training cells stay independent in a
short window); the threshold factor is set for a stated P_FA per cell.

Detection and range: the target is detected when the CFAR crosses at the cell nearest its noise-free impact peak
(the cell-level P_D of CFAR analyses); its range is then read from the largest envelope sample |u| within the
half-power mainlobe about that cell, refined by a parabola through that sample and its two neighbours (assumed:
parabolic interpolation on the envelope), and converted with the delay of the noise-free reference peak.
Gross errors on sidelobes of other bit-1 impacts are thereby excluded from the range statistics (a tracker's gate
does the same).

Bearing: not measured at the sample level. ``monopulse`` (default, assumed): an amplitude-comparison monopulse
with the thermal-noise accuracy σ_φ = θ₃dB / (k_m √(2 E/N₀)) (Barton, *Radar System Analysis and Modeling*: the
single-pulse monopulse formula; θ₃dB = 2° and slope k_m = 1.6 assumed) — the paper's location by range and bearing
needs an angle, and monopulse is the standard single-pulse angle measurement of a tracking radar; ``fixed``: a
constant σ_φ.

Cramér–Rao bound of the delay: for a known pulse s(t) of energy E in white noise of one-sided density N₀ with an
unknown carrier phase, var(τ̂) ≥ 1/(8π² β² E/N₀), β² = ∫(f − f̄)²|S(f)|² df / ∫|S(f)|² df the squared RMS bandwidth
of the *received pulse* about its mean frequency f̄ (the phase is a nuisance parameter, so only the envelope's
bandwidth counts; with a known phase f̄² would add to β²). The bound refers to the received samples, not to the
impacting filter's output: a filter is processing, which cannot add information, so the bound holds for every
estimator and the filter's narrow band is what costs accuracy. β is computed numerically from the sampled pulse
(band-limited at f_s/2), :func:`rms_bandwidth`.

Equivalent at the detector output (:class:`DetectorEquivalent`): given E/N₀, a detection with
P_D = mean over nodes of P_D,CA-CFAR(g·E/N₀) (the CA-CFAR probability of a non-fluctuating target of CUT
signal-to-noise ratio s = g·E/N₀, g computed from the noise-free chain on a grid of sub-sample offsets and carrier
phases), a range error ~ N(0, σ_r²) with σ_r(E/N₀) the RMS error measured by a sample-level calibration run and
interpolated (the measured error follows no single 1/√(E/N₀) law: it is flat near the detection threshold, where
only pulses whose noise favours the peak are detected, and at high E/N₀ it meets a floor of ≈ 0.14 m for Table I,
the carrier-phase-dependent shift of the impact peak), and a bearing error ~ N(0, σ_φ²). Tests check it against the sample-level Monte Carlo.

Location (:func:`locate`): weighted least squares (Gauss–Newton) from the range and bearing of one or more sensors
to a position and its covariance (HᵀR⁻¹H)⁻¹, the measurement and R of the trackers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from typing import Any, ClassVar

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of, positive
from motionsig_cli.detection.cfar import CFARConfig, ca_cfar, pd_swerling0
from motionsig_cli.engine import tasks_of, trials_per_task
from motionsig_cli.models.radar_equation import C_LIGHT, RadarEquation, db, undb
from motionsig_cli.rng import trial_rng
from motionsig_cli.signals.ebpsk import EBPSKConfig, impacting_filter, modulate

__all__ = [
    "BEARING_MODELS",
    "DetectorEquivalent",
    "EbpskRadar",
    "EbpskRadarConfig",
    "EbpskRadarJob",
    "EbpskRadarResult",
    "locate",
    "rms_bandwidth",
]

BEARING_MODELS = ("monopulse", "fixed")
DEFAULT_BITS = (1, 0, 1, 1, 0, 1, 0, 0, 1, 1, 1, 0, 0, 0, 1, 0)
"""Default payload (assumed): 16 bits, 8 of them 1 — any message works."""
MAX_BITS = 4096
"""Longest payload per pulse."""
CAL_ENR_DB = (18.0, 20.0, 22.0, 23.5, 25.0, 26.5, 28.0, 29.5, 31.0, 35.0, 40.0, 50.0)
"""E/N₀ [dB] of the range-error calibration of :class:`DetectorEquivalent` (P_D ≥ 0.5 at the default P_FA)."""
CAL_TRIALS = 500
"""Pulses per calibration E/N₀ (σ_r to ≈ 3 % where P_D ≈ 1; ≈ 4 s for Table I on one core)."""
CAL_SEED = 20_150_624
"""Root seed of the calibration (assumed)."""
RHO2_MAX = 0.01
"""Training cells are spaced so that the squared noise correlation of u between them is below this (assumed)."""
ENR_DB_RANGE = (-30.0, 80.0)
"""E/N₀ accepted [dB]."""
FRAC_NODES = 8
"""Sub-sample offsets averaged by the equivalent model."""
PHASE_NODES = 16
"""Carrier phases averaged by the equivalent model."""


def _check_bits(bits: Sequence[int]) -> tuple[int, ...]:
    try:
        out = tuple(int(b) for b in bits)
    except (TypeError, ValueError):
        raise ConfigError("bits", bits, "is not a sequence of 0/1 bits") from None
    if not out:
        raise ConfigError("bits", out, "is empty")
    if len(out) > MAX_BITS:
        raise ConfigError("bits", out, f"has more than {MAX_BITS} bits")
    if any(b not in (0, 1) for b in out):
        raise ConfigError("bits", out, "holds values other than 0 and 1")
    if 1 not in out:
        raise ConfigError("bits", out, "has no 1 bit: the impacting filter answers bit-1 symbols only")
    return out


@dataclass(frozen=True)
class EbpskRadarConfig:
    """The EBPSK radar (module docstring); every value that the paper does not give is assumed.

    Attributes:
        wave: the EBPSK waveform (Table I by default).
        bits: the payload of one pulse (:data:`DEFAULT_BITS`).
        pfa: CA-CFAR false-alarm probability per cell (assumed 1e-6).
        n_train: CA-CFAR training cells (assumed 32); the guard cells and the stride follow from the waveform.
        pri: pulse repetition interval [s] (assumed 5 ms: c·PRI/2 = 749 km, beyond the 737 km the paper's
            trajectory reaches from the origin).
        bearing: ``monopulse`` or ``fixed`` (:data:`BEARING_MODELS`).
        beamwidth: θ₃dB [rad] (assumed 2°).
        k_m: monopulse slope (assumed 1.6).
        sigma_bearing: σ_φ [rad] of the ``fixed`` model (assumed 1 mrad).
        radar: the power budget.
    """

    wave: EBPSKConfig = field(default_factory=EBPSKConfig)
    bits: tuple[int, ...] = DEFAULT_BITS
    pfa: float = 1e-6
    n_train: int = 32
    pri: float = 5e-3
    bearing: str = "monopulse"
    beamwidth: float = math.radians(2.0)
    k_m: float = 1.6
    sigma_bearing: float = 1e-3
    radar: RadarEquation = field(default_factory=RadarEquation)

    def __post_init__(self) -> None:
        object.__setattr__(self, "bits", _check_bits(self.bits))
        CFARConfig(n_train=self.n_train, pfa=self.pfa)  # checks pfa and n_train
        positive("pri", self.pri, unit="s")
        if self.pulse_duration >= self.pri:
            raise ConfigError("pri", self.pri, f"is not longer than the pulse ({self.pulse_duration:g} s)")
        one_of("bearing", self.bearing, BEARING_MODELS)
        in_range("beamwidth", self.beamwidth, 0.0, math.pi, lo_open=True, unit="rad")
        positive("k_m", self.k_m)
        in_range("sigma_bearing", self.sigma_bearing, 0.0, math.pi, lo_open=True, unit="rad")
        ratio = self.wave.fs / self.wave.f_if
        if abs(ratio - round(ratio)) > 1e-9:
            raise ConfigError("fs", self.wave.fs, "is not a whole multiple of f_if (the I/Q boxcar needs it)")
        if self.radar.fs != self.wave.fs:
            raise ConfigError(
                "fs", self.radar.fs, f"of the radar equation differs from the waveform's {self.wave.fs:g}"
            )

    @property
    def samples_per_cycle(self) -> int:
        """L = f_s / f_if."""
        return round(self.wave.fs / self.wave.f_if)

    @property
    def samples_per_symbol(self) -> int:
        """N·L."""
        return self.wave.N * self.samples_per_cycle

    @property
    def pulse_samples(self) -> int:
        """Samples of one pulse."""
        return len(self.bits) * self.samples_per_symbol

    @property
    def pulse_duration(self) -> float:
        """T_p [s]."""
        return len(self.bits) * self.wave.N / self.wave.f_if

    @property
    def max_range(self) -> float:
        """The unambiguous range c·PRI/2 [m]."""
        return C_LIGHT * self.pri / 2.0

    def check_range(self, r: np.ndarray | float) -> np.ndarray:
        """``r`` as an array, if every range is in (0, c·PRI/2]; else :class:`ConfigError` on ``range``."""
        r = np.asarray(r, dtype=float)
        bad = ~(np.isfinite(r) & (r > 0))
        if np.any(bad):
            raise ConfigError("range", float(r[bad].flat[0]), "is not a finite number > 0 m")
        if np.any(r > self.max_range):
            raise ConfigError(
                "range",
                float(r.max()),
                f"is beyond the unambiguous range c·PRI/2 = {self.max_range:g} m (pri = {self.pri:g} s)",
            )
        return r

    def energy_snr(self, r: np.ndarray | float) -> np.ndarray:
        """E/N₀ (linear) of a target at range r from the radar equation (checked against c·PRI/2)."""
        return self.radar.energy_snr(self.check_range(r), self.pulse_duration)

    def sigma_bearing_at(self, enr: np.ndarray | float) -> np.ndarray:
        """σ_φ [rad] at E/N₀ = ``enr`` (linear): θ₃dB/(k_m √(2 E/N₀)) or the fixed value."""
        e = np.asarray(enr, dtype=float)
        if self.bearing == "fixed":
            return np.full(e.shape, self.sigma_bearing)
        return self.beamwidth / (self.k_m * np.sqrt(2.0 * e))


def rms_bandwidth(x: np.ndarray, fs: float, *, centred: bool = True, nfft: int | None = None) -> float:
    """RMS bandwidth β [Hz] of a real sampled signal x: √(Σ(f − f̄)²|X|² / Σ|X|²) over 0 ≤ f ≤ f_s/2
    (``centred=False``: about f = 0, the known-phase case)."""
    x = np.asarray(x, dtype=float)
    n = nfft or 1 << math.ceil(math.log2(8 * len(x)))
    p = np.abs(np.fft.rfft(x, n)) ** 2
    f = np.fft.rfftfreq(n, 1.0 / fs)
    fbar = float(np.sum(f * p) / np.sum(p)) if centred else 0.0
    return float(np.sqrt(np.sum((f - fbar) ** 2 * p) / np.sum(p)))


class EbpskRadar:
    """The sample-level radar chain of one :class:`EbpskRadarConfig` (module docstring).

    The derived quantities (filter, reference response, noise correlation, CFAR layout) are computed once.
    A processing window of :attr:`window` samples holds: a filter warm-up (discarded), the CFAR half-width, a
    noise-only stretch of :attr:`n_fa` cells (to count false alarms), the echo response, the CFAR half-width.
    """

    def __init__(self, cfg: EbpskRadarConfig) -> None:
        self.cfg = cfg
        self.b, self.a = (np.asarray(v, dtype=float) for v in impacting_filter(cfg.wave))
        L = cfg.samples_per_cycle
        self.L = L
        ones = np.flatnonzero(np.asarray(cfg.bits) == 1)
        self.offsets = (ones - ones[0]) * cfg.samples_per_symbol  # d_j, relative to the first bit-1 symbol
        # filter memory: samples until the impulse response's envelope falls below 1e-4 of its peak
        from scipy import signal  # here, not at import: scipy.signal costs 0.5 s to import

        imp = signal.lfilter(self.b, self.a, np.r_[1.0, np.zeros(200_000)])
        env = np.abs(imp)
        peak = env.max()
        above = np.flatnonzero(env > 1e-4 * peak)
        self.memory = int(above[-1]) + 1
        if self.memory >= 200_000:
            raise ConfigError(
                "wave", cfg.wave, "has an impacting filter whose response does not decay (unstable?)"
            )
        # noise of z and u: their responses G to white input (_noise_response), energies and correlations
        gz, gu = self._noise_response()
        self.noise_var_z = float(np.sum(np.abs(gz) ** 2))
        self.noise_var = float(np.sum(np.abs(gu) ** 2))  # E|u|² for unit-variance white input
        self.acf = self._acf(gu, self.noise_var)
        rho2 = np.abs(self._acf(gz, self.noise_var_z)) ** 2
        beyond = np.flatnonzero(rho2 >= RHO2_MAX)
        self.stride = int(beyond[-1]) + 1  # training cells of z this far apart are (nearly) independent
        # reference: the noise-free response to an echo at delay 0, φ₀ = 0, no Doppler (its mainlobe); the
        # delay of the peak is calibrated as the mean over the sub-sample offset and the carrier phase (the
        # envelope peak moves with φ₀ by about ±1 sample: the phase jumps of a real IF echo are steps of
        # 2 sin φ₀ that the filter turns into impacts of their own)
        self.ref_pre = 4 * self.stride + self.memory  # leading zeros so the reference peak is interior
        self.ref_len = self.ref_pre + cfg.pulse_samples + self.memory + 4 * self.L
        ref = self.process(
            self.echo(np.array([1.0]), np.array([float(self.ref_pre)]), 0.0, 0.0, self.ref_len)
        )
        self.ref_env = np.abs(ref[1][0])
        k = int(np.argmax(self.ref_env))
        half = self.ref_env >= self.ref_env[k] / math.sqrt(2.0)
        lo = k  # half-power mainlobe: contiguous samples about the peak above −3 dB
        while lo > 0 and half[lo - 1]:
            lo -= 1
        hi = k
        while hi < len(half) - 1 and half[hi + 1]:
            hi += 1
        self.mainlobe = max(1, min(k - lo, hi - k))
        self.peak_offset = float(k - self.ref_pre)
        start, est = self._grid_response(0.0)[:2]
        self.peak_offset = float(np.mean(est - start))
        # CFAR: |u|² against the mean of |z|² training cells (stride apart) times E|u|²/E|z|²; the guard covers
        # the whole echo response (pulse + filter memory) and the z samples that enter u at the CUT
        extent = cfg.pulse_samples + self.memory + 2 * self.L
        n_guard = -(-(extent + self.stride) // self.stride)
        self.cfar = CFARConfig(n_train=cfg.n_train, n_guard=n_guard, pfa=cfg.pfa, stride=self.stride)
        hw = self.cfar.half_width
        self.warmup = self.memory + self.L
        self.n_fa = 4 * self.stride
        self.echo_at = self.warmup + hw + self.n_fa + hw  # the echo's first sample (before its fraction)
        self.window = self.echo_at + extent + hw + 2
        self.fa_cells = (
            self.warmup + hw,
            self.warmup + hw + self.n_fa,
        )  # CUTs whose training misses the echo

    # ----------------------------------------------------------------------------------------- the chain
    def echo(
        self, amp: np.ndarray, start: np.ndarray, f_dopp: float, phase: np.ndarray | float, n: int
    ) -> np.ndarray:
        """Noise-free echoes (B, n): amplitude ``amp`` (B,), start ``start`` (B,) in samples (fractional),
        Doppler ``f_dopp`` [Hz] (a rotation across the pulse), carrier phase ``phase`` (B,) [rad]."""
        w = self.cfg.wave
        amp = np.asarray(amp, float)
        start = np.asarray(start, float)
        t = (np.arange(n)[None, :] - start[:, None]) / w.fs  # time since the echo's start [s]
        inside = (t >= 0) & (t < self.cfg.pulse_duration)
        t_sym = w.N / w.f_if
        sym = np.clip(np.floor(t / t_sym).astype(int), 0, len(self.cfg.bits) - 1)
        in_sym = t - sym * t_sym
        bits = np.asarray(self.cfg.bits)[sym]
        jump = (bits == 1) & (in_sym < w.K / w.f_if)
        ph = 2.0 * math.pi * (w.f_if - f_dopp) * t + w.theta * jump + np.asarray(phase, float).reshape(-1, 1)
        return np.where(inside, amp[:, None] * np.sin(ph), 0.0)

    def process(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(z, u) (B, n) complex: z the I/Q of the impacting filter's output (one-period boxcar), u the coherent
        sum of z over the bit-1 offsets, u[n] = Σ_j z[n + d_j] (samples whose offsets leave the window: 0)."""
        from scipy import signal

        y = signal.lfilter(self.b, self.a, x, axis=-1)
        n = x.shape[-1]
        lo = np.exp(-2j * math.pi * np.arange(n) / self.L)  # exp(−j2π f_if n/f_s)
        c = np.cumsum(y * lo, axis=-1)
        z = c.copy()
        z[..., self.L :] -= c[..., : -self.L]
        z /= self.L
        u = np.zeros_like(z)
        for d in self.offsets:  # a handful of shifts (bit-1 symbols), not a loop over trials
            u[..., : n - d] += z[..., d:]
        return z, u

    def _noise_response(self) -> tuple[np.ndarray, np.ndarray]:
        """The responses G_z, G_u of z and u to a unit impulse of x (the chain is z = (x·e^{−jωk}) * q,
        u = Σ_j z[· + d_j]: linear and time-invariant on the demodulated input, so the noise covariance of
        u is E[u[m] u*[m + l]] = σ² Σ_n G[n] G*[n + l] for white x of variance σ²)."""
        n = self.memory + int(self.offsets[-1]) + 2 * self.L
        x = np.zeros((1, 2 * n + 1))
        x[0, n] = 1.0
        z, u = self.process(x)
        return z[0], u[0]

    @staticmethod
    def _acf(g: np.ndarray, var: float) -> np.ndarray:
        """conj of the normalised autocorrelation R(l)/R(0), l = 0.. (R(l) = Σ G[n] G*[n + l])."""
        spec = np.fft.fft(g, 2 * len(g))
        r = np.fft.ifft(np.abs(spec) ** 2)[: len(g)]  # Σ_n conj(G[n]) G[n + l]
        return r / var

    @staticmethod
    def _parabola(env: np.ndarray, k: np.ndarray) -> np.ndarray:
        """Vertex of the parabola through env[k − 1], env[k], env[k + 1] (rows of env)."""
        rows = np.arange(env.shape[0])
        em, e0, ep = env[rows, k - 1], env[rows, k], env[rows, k + 1]
        den = em - 2.0 * e0 + ep
        frac = np.where(den < 0, 0.5 * (em - ep) / np.where(den < 0, den, -1.0), 0.0)
        return k + np.clip(frac, -0.5, 0.5)

    def measure(
        self, enr: np.ndarray, frac: np.ndarray, phase: np.ndarray, noise: np.ndarray, f_dopp: float = 0.0
    ) -> dict[str, np.ndarray]:
        """One pulse per row: E/N₀ ``enr`` (B,), sub-sample delay ``frac`` (B,) in [0, 1), carrier phase (B,),
        unit-variance real noise (B, window). Returns ``detected`` (B,), ``error`` (B,) range error [m] (NaN if
        not detected), ``fa`` (B,) a false alarm at the first noise-only cell (one per row, so that the counts are
        independent), ``fa_cells`` (1 per row)."""
        cfg = self.cfg
        amp = 2.0 * np.sqrt(np.asarray(enr, float) / cfg.pulse_samples)  # E/N₀ = A² n/4 for σ_n² = 1
        start = self.echo_at + np.asarray(frac, float)  # the echo's first sample time (fractional)
        x = self.echo(amp, start, f_dopp, phase, self.window) + noise
        z, u = self.process(x)
        p = np.abs(u) ** 2
        det, _ = ca_cfar(p, self.cfar, reference=np.abs(z) ** 2, scale=self.noise_var / self.noise_var_z)
        true_peak = start + self.peak_offset
        cut = np.rint(true_peak).astype(int)
        rows = np.arange(len(cut))
        detected = det[rows, cut]
        env = np.abs(u)
        m = self.mainlobe
        idx = cut[:, None] + np.arange(-m, m + 1)[None, :]
        k = cut - m + np.argmax(env[rows[:, None], idx], axis=1)
        k = np.clip(k, 1, self.window - 2)
        est = self._parabola(env, k)
        err = (est - true_peak) * C_LIGHT / (2.0 * cfg.wave.fs)
        a = self.fa_cells[0]
        return {
            "detected": detected,
            "error": np.where(detected, err, np.nan),
            "error_all": err,
            "fa": det[:, a].astype(int),  # one noise-only cell per pulse: independent counts
            "fa_cells": np.ones(len(cut), dtype=int),
        }

    # ------------------------------------------------------------------------------- model quantities
    def _grid_response(self, f_dopp: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Noise-free chain at E/N₀ = 1 on a grid of :data:`FRAC_NODES` sub-sample offsets (midpoints of [0, 1))
        × :data:`PHASE_NODES` carrier phases (midpoints of [0, 2π)): per node, the echo start [samples], the
        noise-free range estimate [samples] and the CUT SNR g (s = g·E/N₀)."""
        cfg = self.cfg
        fr = (np.arange(FRAC_NODES) + 0.5) / FRAC_NODES
        ph = 2.0 * math.pi * (np.arange(PHASE_NODES) + 0.5) / PHASE_NODES
        fr, ph = (v.reshape(-1) for v in np.meshgrid(fr, ph, indexing="ij"))
        nodes = len(fr)
        n = self.ref_len + 2
        amp = np.full(nodes, 2.0 * math.sqrt(1.0 / cfg.pulse_samples))
        start = self.ref_pre + fr
        u = self.process(self.echo(amp, start, f_dopp, ph, n))[1]
        rows = np.arange(nodes)
        cut = np.rint(start + self.peak_offset).astype(int)
        gain = np.abs(u[rows, cut]) ** 2 / self.noise_var
        env = np.abs(u)
        m = self.mainlobe
        idx = cut[:, None] + np.arange(-m, m + 1)[None, :]
        k = cut - m + np.argmax(env[rows[:, None], idx], axis=1)
        est = self._parabola(env, k)
        return start, est, gain

    @cached_property
    def crlb_factor(self) -> float:
        """c/2 · √(1/(8π² β²)) [m]: the range CRLB at E/N₀ = 1 (divide by √(E/N₀))."""
        beta = self.beta
        return C_LIGHT / 2.0 / math.sqrt(8.0 * math.pi**2 * beta**2)

    @cached_property
    def beta(self) -> float:
        """RMS bandwidth [Hz] of the transmitted pulse about its mean frequency (known-payload modulation)."""
        return rms_bandwidth(self.pulse(), self.cfg.wave.fs)

    def pulse(self) -> np.ndarray:
        """The transmitted pulse, one amplitude, from :func:`motionsig_cli.signals.ebpsk.modulate`."""
        return np.asarray(modulate(np.asarray(self.cfg.bits), self.cfg.wave), dtype=float).reshape(-1)

    def equivalent(self, radial_speed: float = 0.0, *, seed: int = CAL_SEED) -> DetectorEquivalent:
        """The detector-output equivalent of this chain for targets of ``radial_speed`` [m/s]: P_D from the
        CA-CFAR statistics at the CUT SNR of the noise-free chain, σ_r from a sample-level calibration run
        (:data:`CAL_ENR_DB`, :data:`CAL_TRIALS` pulses each, ``seed``; a few seconds, once per configuration)."""
        return _equivalent(self.cfg, float(radial_speed), int(seed))

    def noise_free_gain(self, radial_speed: float = 0.0) -> np.ndarray:
        """The CUT SNR per unit E/N₀ on the sub-sample offset × carrier phase grid."""
        return self._grid_response(2.0 * radial_speed * self.cfg.wave.f_carrier / C_LIGHT)[2]


@lru_cache(maxsize=8)
def _radar(cfg: EbpskRadarConfig) -> EbpskRadar:
    return EbpskRadar(cfg)


@lru_cache(maxsize=8)
def _equivalent(cfg: EbpskRadarConfig, radial_speed: float, seed: int) -> DetectorEquivalent:
    rad = _radar(cfg)
    job = EbpskRadarJob(cfg, CAL_ENR_DB, CAL_TRIALS, seed, radial_speed=radial_speed)
    sums = np.stack([job.run_task(t) for t in job.tasks()])
    per = np.zeros((len(CAL_ENR_DB), 7))
    for (i, _), part in zip(job.tasks(), sums, strict=True):
        per[i] += part
    rms, se = _rms(per)
    return DetectorEquivalent(
        cfg=cfg,
        gain=tuple(float(g) for g in rad.noise_free_gain(radial_speed)),
        cal_enr_db=CAL_ENR_DB,
        cal_sigma_r=tuple(float(v) for v in rms),
        cal_sigma_r_se=tuple(float(v) for v in se),
    )


def _rms(acc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """RMS range error of the detections and its standard error, from sums [n, k, Σe, Σe², Σe⁴, …]."""
    k, s2, s4 = acc[:, 1], acc[:, 3], acc[:, 4]
    with np.errstate(invalid="ignore", divide="ignore"):
        msq = s2 / k
        rms = np.sqrt(msq)
        se = np.sqrt(np.maximum(s4 / k - msq**2, 0.0) / k) / (2.0 * rms)  # delta method on √(mean e²)
    return rms, se


@dataclass(frozen=True)
class DetectorEquivalent:
    """The radar at its detector output (module docstring): detection, range and bearing errors drawn from the
    chain's statistics at E/N₀, without sampling the waveform.

    Attributes:
        cfg: the radar.
        gain: CUT SNR per unit E/N₀ at each node of the sub-sample offset × carrier phase grid.
        cal_enr_db, cal_sigma_r, cal_sigma_r_se: the measured RMS range error [m] (and its standard error) of
            the sample-level chain at these E/N₀ [dB]; σ_r is interpolated linearly in (dB, log σ_r), held at the
            last value above the grid (the error floor of the phase-dependent peak shift) and extended as
            1/√(E/N₀) below it (assumed).
    """

    cfg: EbpskRadarConfig
    gain: tuple[float, ...]
    cal_enr_db: tuple[float, ...]
    cal_sigma_r: tuple[float, ...]
    cal_sigma_r_se: tuple[float, ...]
    _grid: tuple[np.ndarray, np.ndarray] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        # P_D(s) of the CUT tabulated on a fine grid of s (0.01 dB), then averaged over the grid nodes' gains:
        # P_D(E/N₀) = mean_nodes P_D(g·E/N₀); tabulated on E/N₀ (0.01 dB) for fast draws
        s_db = np.arange(ENR_DB_RANGE[0] - 40.0, ENR_DB_RANGE[1] + 1e-9, 0.01)
        pd_s = pd_swerling0(undb(s_db), self.cfg.pfa, self.cfg.n_train)
        grid = np.arange(ENR_DB_RANGE[0], ENR_DB_RANGE[1] + 1e-9, 0.01)
        g_db = db(np.asarray(self.gain))
        pd = np.mean([np.interp(grid + g, s_db, pd_s) for g in g_db], axis=0)  # ≤ 128 nodes
        object.__setattr__(self, "_grid", (grid, pd))

    def pd(self, enr: np.ndarray | float) -> np.ndarray:
        """P_D at E/N₀ = ``enr`` (linear), averaged over the sub-sample offset."""
        grid, pd = self._grid
        return np.interp(db(np.maximum(np.asarray(enr, float), 1e-300)), grid, pd)

    def sigma_range(self, enr: np.ndarray | float) -> np.ndarray:
        """σ_r [m] at E/N₀ = ``enr`` (linear): the calibration, interpolated (class docstring)."""
        x = db(np.maximum(np.asarray(enr, float), 1e-300))
        g = np.asarray(self.cal_enr_db)
        ls = np.log10(np.asarray(self.cal_sigma_r))
        out = np.interp(x, g, ls)
        out = np.where(x < g[0], ls[0] - (x - g[0]) / 20.0, out)
        return 10.0**out

    def sigma_bearing(self, enr: np.ndarray | float) -> np.ndarray:
        """σ_φ [rad] at E/N₀ = ``enr`` (linear)."""
        return self.cfg.sigma_bearing_at(enr)

    def draw(
        self, rng: np.random.Generator, ranges: np.ndarray, bearings: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """One run's measurements of targets at true ``ranges`` and ``bearings`` (any shape, e.g. scans):
        (detected, measured range [m], measured bearing [rad, wrapped]); NaN where not detected.

        Draw order per run (reproducible from the run's generator): U(0,1) for detection, then N(0,1) for
        range, then N(0,1) for bearing, each of the shape of ``ranges``.
        """
        r = self.cfg.check_range(ranges)
        phi = np.asarray(bearings, float)
        enr = self.cfg.energy_snr(r)
        det = rng.random(r.shape) < self.pd(enr)
        dr = rng.standard_normal(r.shape) * self.sigma_range(enr)
        dphi = rng.standard_normal(r.shape) * self.sigma_bearing(enr)
        rm = np.where(det, r + dr, np.nan)
        pm = np.where(det, np.pi - np.mod(np.pi - (phi + dphi), 2.0 * np.pi), np.nan)
        return det, rm, pm

    def sigmas(self, ranges: np.ndarray) -> np.ndarray:
        """(…, 2) [σ_r, σ_φ] at true ``ranges`` (for :func:`locate`)."""
        enr = self.cfg.energy_snr(ranges)
        return np.stack([self.sigma_range(enr), self.sigma_bearing(enr)], axis=-1)


# ------------------------------------------------------------------------------------------ location
def locate(
    ranges: np.ndarray,
    bearings: np.ndarray,
    sigmas: np.ndarray,
    sensor_pos: np.ndarray,
    *,
    iterations: int = 3,
) -> tuple[np.ndarray, np.ndarray]:
    """Weighted least squares position from the ranges and bearings of S sensors, vectorised over leading axes.

    Model: z_s = h_s(p) + v_s, h_s(p) = [‖p − s‖, atan2(p_y − s_y, p_x − s_x)], v_s ~ N(0, diag(σ_r², σ_φ²)),
    independent between sensors. Start: the inverse-covariance-weighted mean of the sensors' polar-to-Cartesian
    conversions (each with covariance J diag(σ²) Jᵀ); then ``iterations`` Gauss–Newton steps on Σ ‖R⁻½(z − h(p))‖²
    (bearing residuals wrapped). Covariance: (Σ Hᵀ R⁻¹ H)⁻¹ at the solution. For one sensor the start is the
    exact solution and the covariance the linearised conversion.

    Args:
        ranges, bearings: (…, S) [m, rad]; NaN marks a sensor without a detection (it gets zero weight).
        sigmas: (…, S, 2) or broadcastable: [σ_r, σ_φ] per sensor.
        sensor_pos: (S, 2) or (…, S, 2) sensor positions [m].

    Returns:
        (xy, cov): (…, 2) and (…, 2, 2); NaN where no sensor detected.
    """
    r = np.asarray(ranges, float)
    phi = np.asarray(bearings, float)
    if r.shape != phi.shape or r.ndim < 1:
        raise ValueError(f"ranges and bearings must share a shape (…, S); got {r.shape} and {phi.shape}")
    sig = np.broadcast_to(np.asarray(sigmas, float), (*r.shape, 2))
    pos = np.broadcast_to(np.asarray(sensor_pos, float), (*r.shape, 2))
    if np.any(~(sig > 0)):
        raise ConfigError("sigmas", float(sig[~(sig > 0)].flat[0]), "is not a finite number > 0")
    seen = np.isfinite(r) & np.isfinite(phi)
    r0 = np.where(seen, r, 1.0)
    p0 = np.where(seen, phi, 0.0)
    c, s = np.cos(p0), np.sin(p0)
    pts = pos + r0[..., None] * np.stack([c, s], axis=-1)
    J = np.empty((*r.shape, 2, 2))
    J[..., 0, 0], J[..., 0, 1] = c, -r0 * s
    J[..., 1, 0], J[..., 1, 1] = s, r0 * c
    D = sig**2
    P = J * D[..., None, :] @ np.swapaxes(J, -1, -2)
    Pinv = np.linalg.inv(P) * seen[..., None, None]
    info = Pinv.sum(axis=-3)
    vec = (Pinv @ pts[..., None])[..., 0].sum(axis=-2)
    none = ~seen.any(axis=-1)
    info_safe = np.where(none[..., None, None], np.eye(2), info)
    xy = np.linalg.solve(info_safe, vec[..., None])[..., 0]
    w = seen[..., None] / D  # R⁻¹ diagonal, zero for missing sensors
    for _ in range(iterations if r.shape[-1] > 1 else 0):
        d = xy[..., None, :] - pos
        rr = np.hypot(d[..., 0], d[..., 1])
        rr = np.maximum(rr, 1e-9)
        h_r, h_p = rr, np.arctan2(d[..., 1], d[..., 0])
        res = np.stack([r0 - h_r, np.pi - np.mod(np.pi - (p0 - h_p), 2 * np.pi)], axis=-1)
        H = np.empty((*r.shape, 2, 2))
        H[..., 0, 0], H[..., 0, 1] = d[..., 0] / rr, d[..., 1] / rr
        H[..., 1, 0], H[..., 1, 1] = -d[..., 1] / rr**2, d[..., 0] / rr**2
        HtW = np.swapaxes(H, -1, -2) * w[..., None, :]
        A = (HtW @ H).sum(axis=-3)
        g = (HtW @ res[..., None])[..., 0].sum(axis=-2)
        A = np.where(none[..., None, None], np.eye(2), A)
        xy = xy + np.linalg.solve(A, g[..., None])[..., 0]
    if r.shape[-1] > 1:
        d = xy[..., None, :] - pos
        rr = np.maximum(np.hypot(d[..., 0], d[..., 1]), 1e-9)
        H = np.empty((*r.shape, 2, 2))
        H[..., 0, 0], H[..., 0, 1] = d[..., 0] / rr, d[..., 1] / rr
        H[..., 1, 0], H[..., 1, 1] = -d[..., 1] / rr**2, d[..., 0] / rr**2
        HtW = np.swapaxes(H, -1, -2) * w[..., None, :]
        info = (HtW @ H).sum(axis=-3)
        info_safe = np.where(none[..., None, None], np.eye(2), info)
    cov = np.linalg.inv(info_safe)
    cov = 0.5 * (cov + np.swapaxes(cov, -1, -2))
    xy = np.where(none[..., None], np.nan, xy)
    cov = np.where(none[..., None, None], np.nan, cov)
    return xy, cov


# ------------------------------------------------------------------------------------------ Monte Carlo
@dataclass(frozen=True)
class EbpskRadarResult:
    """P_D and range error vs E/N₀ (one row per E/N₀), with the equivalent model and the CRLB beside them.

    Attributes (arrays over E/N₀): enr_db; trials; pd, pd_se (binomial); pd_model; rms_r, rms_r_se [m] (RMS range
    error of the detections and its standard error from the sample's fourth moment); sigma_r_model [m];
    crlb_r [m] (√CRLB of the range); sigma_bearing [rad]; pfa, pfa_se (false alarms among the noise-only cells).
    """

    enr_db: np.ndarray
    trials: np.ndarray
    pd: np.ndarray
    pd_se: np.ndarray
    pd_model: np.ndarray
    rms_r: np.ndarray
    rms_r_se: np.ndarray
    sigma_r_model: np.ndarray
    crlb_r: np.ndarray
    sigma_bearing: np.ndarray
    pfa: np.ndarray
    pfa_se: np.ndarray
    beta: float


@dataclass(frozen=True)
class EbpskRadarJob:
    """The sample-level Monte Carlo of the radar chain (a :class:`~motionsig_cli.engine.MonteCarloJob`).

    Trial t at E/N₀ index i draws from ``trial_rng(seed, t, i)``: the sub-sample delay U(0, 1), the carrier
    phase U(0, 2π), then the window's noise N(0, 1).

    Attributes:
        cfg: the radar.
        enr_db: E/N₀ values [dB] in :data:`ENR_DB_RANGE` (at most 64).
        trials: pulses per E/N₀, in [1, 10⁶].
        seed: root seed ≥ 0.
        radial_speed: target radial speed [m/s] (Doppler; assumed 450 m/s, the paper's target speed).
        chunk: trials per task (None: from the cost model).
    """

    name: ClassVar[str] = "ebpsk-radar"

    cfg: EbpskRadarConfig
    enr_db: tuple[float, ...]
    trials: int
    seed: int
    radial_speed: float = 450.0
    chunk: int | None = None

    def __post_init__(self) -> None:
        if not self.enr_db or len(self.enr_db) > 64:
            raise ConfigError("enr_db", tuple(self.enr_db), "is not 1 to 64 values")
        for e in self.enr_db:
            in_range("enr_db", e, *ENR_DB_RANGE, unit="dB")
        integer("trials", self.trials, 1, 1_000_000)
        integer("seed", self.seed, 0)
        in_range("radial_speed", self.radial_speed, -1e5, 1e5, unit="m/s")
        if self.chunk is not None:
            integer("chunk", self.chunk, 1)

    @property
    def radar(self) -> EbpskRadar:
        """The chain (built once per configuration and process)."""
        return _radar(self.cfg)

    def _per_task(self) -> int:
        if self.chunk is not None:
            return self.chunk
        return trials_per_task(2e-8 * 12 * 16_384, at_most=2000)  # ≈ 12 array passes over a window (model)

    def tasks(self) -> list[tuple[int, range]]:
        """(E/N₀ index, trials), in E/N₀ order."""
        return [(i, t) for i in range(len(self.enr_db)) for t in tasks_of(self.trials, self._per_task())]

    def task_size(self, task: tuple[int, range]) -> int:
        return len(task[1])

    def identity(self) -> dict[str, Any]:
        w = self.cfg.wave
        return {
            "wave": {
                "N": w.N,
                "K": w.K,
                "theta": w.theta,
                "f_if": w.f_if,
                "fs": w.fs,
                "f_carrier": w.f_carrier,
            },
            "bits": "".join(map(str, self.cfg.bits)),
            "pfa": self.cfg.pfa,
            "n_train": self.cfg.n_train,
            "enr_db": list(self.enr_db),
            "trials": self.trials,
            "seed": self.seed,
            "radial_speed": self.radial_speed,
            "per_task": self._per_task(),
        }

    def run_task(self, task: tuple[int, range]) -> np.ndarray:
        """Sums over the task's trials: [n, detections, Σe, Σe², Σe⁴ (detections), false alarms, FA cells]."""
        i, trials = task
        rad = self.radar
        rngs = [trial_rng(self.seed, t, i) for t in trials]
        frac = np.array([g.random() for g in rngs])
        phase = np.array([2.0 * math.pi * g.random() for g in rngs])
        noise = np.stack([g.standard_normal(rad.window) for g in rngs])
        f_d = 2.0 * self.radial_speed * self.cfg.wave.f_carrier / C_LIGHT
        enr = np.full(len(rngs), float(undb(self.enr_db[i])))
        out = rad.measure(enr, frac, phase, noise, f_d)
        e = out["error"][out["detected"]]
        return np.array(
            [len(rngs), e.size, e.sum(), (e**2).sum(), (e**4).sum(), out["fa"].sum(), out["fa_cells"].sum()],
            dtype=float,
        )

    def reduce(self, tasks: Sequence[tuple[int, range]], results: Sequence[np.ndarray]) -> EbpskRadarResult:
        """Per E/N₀, the tasks' sums added in task order."""
        acc = np.zeros((len(self.enr_db), 7))
        for (i, _), part in zip(tasks, results, strict=True):
            acc[i] += part
        n, k, fa, cells = acc[:, 0], acc[:, 1], acc[:, 5], acc[:, 6]
        pd = k / n
        rms, rms_se = _rms(acc)
        pfa = fa / cells
        eq = self.radar.equivalent(self.radial_speed)
        enr = undb(np.asarray(self.enr_db))
        return EbpskRadarResult(
            enr_db=np.asarray(self.enr_db, float),
            trials=n,
            pd=pd,
            pd_se=np.sqrt(pd * (1 - pd) / n),
            pd_model=eq.pd(enr),
            rms_r=rms,
            rms_r_se=rms_se,
            sigma_r_model=eq.sigma_range(enr),
            crlb_r=self.radar.crlb_factor / np.sqrt(enr),
            sigma_bearing=self.cfg.sigma_bearing_at(enr),
            pfa=pfa,
            pfa_se=np.sqrt(np.maximum(pfa * (1 - pfa), 0) / cells),
            beta=self.radar.beta,
        )
