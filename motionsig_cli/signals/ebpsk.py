"""EBPSK: the extended binary phase shift keying waveform, the impacting filter and the amplitude
demodulator of the joint radar–communication front end of Yao, Teng & Wu, *Maneuvering Target Tracking
Based on EBPSK Modulated JRC System* (Table I: carrier 10 GHz, down-conversion to a 100 MHz IF, sampling
at 1 GHz, EBPSK K = 2, N = 7).

The modulation (Wu & Feng, "On BER performance of EBPSK-MODEM in AWGN channel", Sensors 10(4), 2010;
Chen & Wu, "A novel detection scheme for EBPSK system", Math. Probl. Eng. 2012). A symbol is N cycles of
the carrier f (here the IF f_if), T = N/f; with t measured from the start of the symbol::

    bit 0:  s0(t) = sin(2π f t),                          0 ≤ t < N/f
    bit 1:  s1(t) = sin(2π f t + θ),   0 ≤ t < K/f;   sin(2π f t),   K/f ≤ t < N/f

so a bit 1 differs from a bit 0 only by a phase jump θ (π by default) held for the first K cycles. The
carrier phase runs on across symbols: a bit-0 sequence is one unbroken sine, and the only phase jumps
are at the start of a bit-1 symbol and K cycles later. Sampled at fs: sample n of the record is
t_n = n/fs, symbol n // L with L = N·fs/f samples per symbol (an integer: checked).

The impacting filter (Feng, Wu & Gao, "From special analogous crystal filters to digital impacting
filters", Digital Signal Processing 22(4), 2012; the "special impacting filter" of Chen & Wu) is a
narrow-band IIR filter built from conjugate zero and pole pairs close to the carrier: the zeros notch
the unmodulated carrier, the poles make a narrow pass band around it, and a phase jump — a broadband
transient — rings in that pass band as a large amplitude impulse, an "impact", at the start of each
bit-1 symbol; a simple amplitude threshold then demodulates. The literature gives the structure (zeros
on the unit circle at, or very near, the carrier; poles just inside it, near the carrier), not one
coefficient set for our sampling; the placement used here is documented in :func:`impacting_filter`
and its radii and offsets are **assumed** (chosen for the impact ratio and the BER measured in
``tests/signals/test_ebpsk.py`` and ``tests/maneuver/test_ebpsk_link.py``).

Receivers (:data:`RECEIVERS`, :class:`Receiver`). The bound is the coherent matched filter on the raw samples
(:func:`matched_statistic`, eq. M1: it needs the carrier phase). The default is the differential receiver
(:func:`differential_statistic`, eqs D1–D3): the phase of the first K cycles against the unmodulated rest of
the symbol (and of its neighbours), the per-symbol noncoherent ML detector when the reference is the symbol's
own tail. The impacting-filter receivers threshold :func:`symbol_statistic` of the filter output:
``impacting`` with the filter designed from a stated Q (:func:`designed_filter`, eqs F1–F3: a reading of the
literature's structure), ``impacting-assumed`` with the placement of :class:`EBPSKConfig` (the earlier
default; the radar of :mod:`motionsig_cli.maneuver.ebpsk_radar` still uses it).

Everything is vectorised over rows: ``modulate`` takes bits ``(..., n_bits)``, ``apply_filter`` and
``demodulate`` waveforms ``(..., n_samples)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of, positive

__all__ = [
    "DEFAULT_RECEIVER",
    "DEFAULT_SPAN",
    "MAX_SAMPLES_PER_SYMBOL",
    "MAX_WAVEFORM_SAMPLES",
    "RECEIVERS",
    "EBPSKConfig",
    "Receiver",
    "Statistic",
    "apply_filter",
    "check_bits",
    "demodulate",
    "designed_filter",
    "detection_window",
    "differential_statistic",
    "filter_response",
    "filter_roots",
    "impact_ratio",
    "impacting_filter",
    "matched_statistic",
    "modulate",
    "signal_correlation",
    "symbol_statistic",
    "symbol_waveforms",
]

Statistic = Literal["peak", "energy"]
MAX_SAMPLES_PER_SYMBOL = 1_000_000  # one symbol; a larger one is refused before allocation
MAX_WAVEFORM_SAMPLES = 50_000_000  # one modulated record (400 MB of float64)


@dataclass(frozen=True, slots=True)
class EBPSKConfig:
    """The EBPSK waveform and its impacting filter.

    Checked here, once: N an integer ≥ 1; K an integer with 1 ≤ K < N; theta finite in (0, 2π); f_if
    finite and > 0; fs > 2·f_if (the IF below Nyquist) with N·fs/f_if an integer (a symbol is a whole
    number of samples) of at most :data:`MAX_SAMPLES_PER_SYMBOL`; f_carrier ≥ f_if; the filter's radii
    and offsets as stated below, with every zero and pole frequency inside (0, fs/2).

    Attributes:
        N: Carrier cycles per symbol (Yao, Teng & Wu, Table I: 7).
        K: Cycles of a bit-1 symbol whose phase is changed, 1 ≤ K < N (Table I: 2).
        theta: Modulation angle θ [rad], in (0, 2π) (π: the phase of the first K cycles is reversed).
        f_if: Carrier of the sampled waveform, the intermediate frequency [Hz] (Table I: 100 MHz).
        fs: Sampling frequency [Hz] (Table I: 1 GHz, 10 samples per IF cycle, 70 per symbol).
        f_carrier: Radio-frequency carrier [Hz] before down-conversion (Table I: 10 GHz); recorded in
            metadata (and used by a radar to convert a Doppler shift), never in the IF waveform.
        zero_radius: Radius of the zero pair, in (0, 1] (assumed 1: on the unit circle, a true notch).
        zero_offset: Relative frequency offset of the zero pair, f_zero = f_if·(1 + zero_offset)
            (assumed 0: the notch sits on the carrier, so an unmodulated carrier gives no output).
        pole_radius: Radius of the pole pairs, in (0, 1) (assumed 0.93: a ringing time constant
            1/(1 − r) ≈ 14 samples, about 1.4 IF cycles, so an impact decays by ~10⁻² within a symbol).
        pole_offset: Relative frequency offset of the two pole pairs, f_pole = f_if·(1 ± pole_offset),
            in [0, 0.5) (assumed 0.08: the pass band straddles the notch; its two peaks of |H| lie ≈ 15 % below
            and above f_if for Table I).
    """

    N: int = 7
    K: int = 2
    theta: float = math.pi
    f_if: float = 100e6
    fs: float = 1e9
    f_carrier: float = 10e9
    zero_radius: float = 1.0
    zero_offset: float = 0.0
    pole_radius: float = 0.93
    pole_offset: float = 0.08

    def __post_init__(self) -> None:
        integer("N", self.N, 1)
        k = integer("K", self.K, 1)
        if k >= self.N:
            raise ConfigError(
                "K", self.K, f"is not < N = {self.N} (a bit 1 changes the phase of K of N cycles)"
            )
        in_range("theta", self.theta, 0.0, 2 * math.pi, lo_open=True, hi_open=True, unit="rad")
        positive("f_if", self.f_if, unit="Hz")
        fs = positive("fs", self.fs, unit="Hz")
        if not fs > 2 * self.f_if:
            raise ConfigError(
                "fs", self.fs, f"Hz is not above 2·f_if = {2 * self.f_if:g} Hz (the IF must be below Nyquist)"
            )
        cycles = self.N * fs / self.f_if
        if abs(cycles - round(cycles)) > 1e-9 * max(1.0, cycles):
            raise ConfigError(
                "fs",
                self.fs,
                f"Hz gives N·fs/f_if = {cycles:g} samples per symbol, not a whole number (choose fs a multiple "
                f"of f_if/N = {self.f_if / self.N:g} Hz)",
            )
        if round(cycles) > MAX_SAMPLES_PER_SYMBOL:
            raise ConfigError(
                "fs",
                self.fs,
                f"Hz gives {round(cycles)} samples per symbol, more than {MAX_SAMPLES_PER_SYMBOL}",
            )
        in_range("f_carrier", self.f_carrier, self.f_if, unit="Hz")
        in_range("zero_radius", self.zero_radius, 0.0, 1.0, lo_open=True)
        in_range("zero_offset", self.zero_offset, -0.5, 0.5, lo_open=True, hi_open=True)
        in_range("pole_radius", self.pole_radius, 0.0, 1.0, lo_open=True, hi_open=True)
        in_range("pole_offset", self.pole_offset, 0.0, 0.5, hi_open=True)
        nyq = fs / 2
        for name, f in (
            ("zero_offset", self.f_if * (1 + self.zero_offset)),
            ("pole_offset", self.f_if * (1 + self.pole_offset)),
            ("pole_offset", self.f_if * (1 - self.pole_offset)),
        ):
            if not 0 < f < nyq:
                raise ConfigError(
                    name,
                    getattr(self, name),
                    f"puts a filter frequency at {f:g} Hz, outside (0, fs/2 = {nyq:g}) Hz",
                )

    def waveform_meta(self) -> dict[str, float]:
        """The waveform's settings as metadata: N, K, theta, f_if, fs, f_carrier."""
        return {name: getattr(self, name) for name in ("N", "K", "theta", "f_if", "fs", "f_carrier")}

    def filter_meta(self) -> dict[str, float]:
        """The impacting filter's settings as metadata: filter_zero_radius, …, filter_pole_offset."""
        names = ("zero_radius", "zero_offset", "pole_radius", "pole_offset")
        return {f"filter_{name}": getattr(self, name) for name in names}

    @property
    def samples_per_cycle(self) -> float:
        """fs / f_if (10 for Table I)."""
        return self.fs / self.f_if

    @property
    def samples_per_symbol(self) -> int:
        """L = N·fs/f_if (70 for Table I)."""
        return round(self.N * self.fs / self.f_if)

    @property
    def symbol_duration(self) -> float:
        """T = N/f_if [s] (70 ns for Table I)."""
        return self.N / self.f_if

    @property
    def bit_rate(self) -> float:
        """1/T [bit/s]."""
        return self.f_if / self.N

    @property
    def bit_energy(self) -> float:
        """E_b: the mean of the two symbols' energies Σ s² over one symbol's samples (sample energy, unit
        amplitude; N·fs/(2 f_if) = 35 for Table I)."""
        s = symbol_waveforms(self)
        return float(np.mean(np.sum(s * s, axis=1)))


def symbol_waveforms(cfg: EBPSKConfig) -> np.ndarray:
    """The two symbols as sampled (2, L): row 0 is bit 0, row 1 is bit 1 (the definition above, t = n/fs
    from the start of the symbol; the phase is changed for the samples with t < K/f_if)."""
    n = np.arange(cfg.samples_per_symbol)
    phase = 2 * np.pi * (cfg.f_if / cfg.fs) * n
    s0 = np.sin(phase)
    # n/fs < K/f_if  ⇔  n·f_if < K·fs (exact in integers when fs/f_if is one)
    s1 = np.where(n * cfg.f_if < cfg.K * cfg.fs * (1 - 1e-12), np.sin(phase + cfg.theta), s0)
    return np.stack([s0, s1])


def check_bits(bits: object) -> np.ndarray:
    """``bits`` as an integer array of 0/1 with at least one bit on its last axis.

    Raises:
        ConfigError: naming ``bits``: empty, not integers, or a value other than 0 and 1.
    """
    arr = np.asarray(bits)
    if arr.ndim == 0 or arr.shape[-1] == 0 or arr.size == 0:
        raise ConfigError("bits", bits, "is empty: give at least one bit")
    if arr.dtype == bool:
        arr = arr.astype(np.int8)
    if not np.issubdtype(arr.dtype, np.integer):
        if not np.issubdtype(arr.dtype, np.floating) or not np.all(np.isin(arr, (0.0, 1.0))):
            raise ConfigError("bits", _short(arr), "holds values other than 0 and 1")
    bad = ~np.isin(arr, (0, 1))
    if bad.any():
        i = int(np.flatnonzero(bad.reshape(-1))[0])
        raise ConfigError("bits", _short(arr), f"holds {arr.reshape(-1)[i]!r} at bit {i}; bits are 0 or 1")
    return arr.astype(np.int8)


def _short(arr: np.ndarray) -> str:
    flat = arr.reshape(-1)
    text = "".join(str(v) for v in flat[:24].tolist())
    return text + ("…" if flat.size > 24 else "")


def modulate(bits: object, cfg: EBPSKConfig) -> np.ndarray:
    """The sampled IF waveform of a bit sequence (unit amplitude): ``bits`` (..., n_bits) of 0/1 →
    (..., n_bits·L) floats, symbol j occupying samples [j·L, (j+1)·L).

    A symbol is exactly N carrier cycles (L = N·fs/f_if samples), so the carrier of the whole record,
    ``sin(2π f_if n/fs + θ·[bit 1 and t < K/f_if within its symbol])``, is the per-symbol definition of
    the module docstring: a bit-0 sequence is one unbroken sine and the phase jumps only where the
    definition puts them.

    Raises:
        ConfigError: naming ``bits`` (see :func:`check_bits`), or a record longer than
            :data:`MAX_WAVEFORM_SAMPLES`.
    """
    b = check_bits(bits)
    L = cfg.samples_per_symbol
    if b.size * L > MAX_WAVEFORM_SAMPLES:
        raise ConfigError(
            "bits", _short(b), f"would make {b.size * L} samples, more than {MAX_WAVEFORM_SAMPLES}"
        )
    n_bits = b.shape[-1]
    n = np.arange(n_bits * L)
    phase = 2 * np.pi * (cfg.f_if / cfg.fs) * n  # the carrier of the whole record
    in_first_k = (n % L) * cfg.f_if < cfg.K * cfg.fs * (1 - 1e-12)
    jump = np.repeat(b, L, axis=-1).astype(bool) & in_first_k
    return np.sin(phase + cfg.theta * jump)


def filter_roots(cfg: EBPSKConfig) -> tuple[np.ndarray, np.ndarray]:
    """(zeros, poles) of the impacting filter in the z-plane (see :func:`impacting_filter`)."""
    wz = 2 * np.pi * cfg.f_if * (1 + cfg.zero_offset) / cfg.fs
    zeros = cfg.zero_radius * np.exp(np.array([1j, -1j]) * wz)
    wp = 2 * np.pi * cfg.f_if * np.array([1 + cfg.pole_offset, 1 - cfg.pole_offset]) / cfg.fs
    poles = cfg.pole_radius * np.exp(np.concatenate([1j * wp, -1j * wp]))
    return zeros, poles


def impacting_filter(cfg: EBPSKConfig) -> tuple[np.ndarray, np.ndarray]:
    """The impacting filter's coefficients (b, a) for :func:`scipy.signal.lfilter`.

    H(z) = g · (1 − 2 r_z cos ω_z z⁻¹ + r_z² z⁻²) / Π_± (1 − 2 r_p cos ω_± z⁻¹ + r_p² z⁻²), with

    - one conjugate zero pair r_z e^{±jω_z}, ω_z = 2π f_if (1 + zero_offset)/fs: on the unit circle at the
      carrier by default (r_z = 1, offset 0, assumed), so the steady, unmodulated carrier is notched out
      and a bit-0 symbol gives (after the start-up transient) no output at all;
    - two conjugate pole pairs r_p e^{±jω_±}, ω_± = 2π f_if (1 ± pole_offset)/fs, just inside the unit
      circle on either side of the notch (r_p = 0.93, offset 0.08: assumed), a narrow pass band around
      the carrier (the notch-in-a-peak shape of the impacting filters of Feng, Wu & Gao; the
      literature's filters have one zero pair and one or two pole pairs near the carrier);
    - g: the gain that makes max_f |H(e^{j2πf/fs})| = 1 (assumed normalisation; the demodulator's
      threshold scales with it, the BER does not).

    A phase jump of the input is a broadband transient: it rings in the pass band as an impulse of
    amplitude ≈ 1.27 (Table I, θ = π; the steady carrier gives 0), decaying as r_p^n. The filter is stable
    (r_p < 1) and real (conjugate pairs).
    """
    zeros, poles = filter_roots(cfg)
    b = np.real(np.poly(zeros))
    a = np.real(np.poly(poles))
    from scipy import signal as sp_signal  # here: scipy.signal costs 0.5 s to import

    _, h = sp_signal.freqz(b, a, worN=_grid(cfg), fs=cfg.fs)
    return b / float(np.max(np.abs(h))), a


def _grid(cfg: EBPSKConfig) -> np.ndarray:
    """A frequency grid [Hz] on (0, fs/2) dense enough near the carrier for the narrow pass band."""
    return np.linspace(0.0, cfg.fs / 2, 1 << 16)


def filter_response(cfg: EBPSKConfig, n: int = 1 << 14) -> tuple[np.ndarray, np.ndarray]:
    """(f [Hz], H) of the impacting filter on ``n`` frequencies from 0 to fs/2 (inclusive)."""
    integer("n", n, 2)
    b, a = impacting_filter(cfg)
    f = np.linspace(0.0, cfg.fs / 2, n)
    from scipy import signal as sp_signal  # here: scipy.signal costs 0.5 s to import

    _, h = sp_signal.freqz(b, a, worN=f, fs=cfg.fs)
    return f, h


def apply_filter(x: np.ndarray, cfg: EBPSKConfig) -> np.ndarray:
    """The impacting filter's output for each row of ``x`` (..., n_samples), from rest (zero state)."""
    b, a = impacting_filter(cfg)
    from scipy import signal as sp_signal  # here: scipy.signal costs 0.5 s to import

    return sp_signal.lfilter(b, a, np.asarray(x, dtype=float), axis=-1)


def detection_window(cfg: EBPSKConfig) -> tuple[int, int]:
    """Samples [start, stop) of each symbol that the demodulator looks at: the first K + 1 carrier cycles
    (assumed), which hold both impacts of a bit 1 — the phase jump at the start of the symbol and the
    jump back K cycles later — and their first cycle of ringing; the rest of the symbol is left out, as
    it holds only decaying ringing and noise (0..30 of 70 samples for Table I)."""
    stop = min(cfg.samples_per_symbol, math.ceil((cfg.K + 1) * cfg.samples_per_cycle - 1e-9))
    return 0, max(1, stop)


def symbol_statistic(y: np.ndarray, cfg: EBPSKConfig, statistic: Statistic = "peak") -> np.ndarray:
    """The demodulator's statistic of every symbol of the filter output ``y`` (..., n_bits·L) →
    (..., n_bits), over the :func:`detection_window` of each symbol:

    - ``peak``: max |y| in the window — the amplitude of the impact, the simple amplitude threshold
      detector of the EBPSK literature (Wu & Feng 2010);
    - ``energy``: Σ y² over the window (assumed alternative: it averages the noise over the window
      instead of taking its largest sample, and gains ≈ 2 dB at a BER of 10⁻²).
    """
    one_of("statistic", statistic, ("peak", "energy"))
    y = np.asarray(y, dtype=float)
    L = cfg.samples_per_symbol
    if y.shape[-1] % L:
        raise ConfigError("y", f"{y.shape[-1]} samples", f"is not a whole number of {L}-sample symbols")
    start, stop = detection_window(cfg)
    win = y.reshape(*y.shape[:-1], y.shape[-1] // L, L)[..., start:stop]
    if statistic == "peak":
        return np.max(np.abs(win), axis=-1)
    return np.sum(win * win, axis=-1)


def demodulate(
    x: np.ndarray, cfg: EBPSKConfig, threshold: float, *, statistic: Statistic = "peak"
) -> np.ndarray:
    """Bits of the received IF waveform ``x`` (..., n_bits·L): filter (:func:`apply_filter`, from rest),
    take each symbol's :func:`symbol_statistic` and decide 1 where it exceeds ``threshold`` (in the
    units of the statistic: the filter output of a unit-amplitude carrier, squared for ``energy``).
    Returns int8 (..., n_bits).

    The filter starts from rest, so the first symbol sees the carrier switch on (an impact of its own):
    a record should begin with a bit 0 that is not data (:func:`impact_ratio` and the BER Monte Carlo
    prepend one).
    """
    in_range("threshold", threshold, 0.0, lo_open=True)
    return (symbol_statistic(apply_filter(x, cfg), cfg, statistic) > threshold).astype(np.int8)


# A noiseless test sequence for the impact ratio: every transition (0→0, 0→1, 1→0, 1→1) occurs, after
# two lead-in zeros that let the switch-on transient decay.
_RATIO_BITS = np.array([0, 0, 0, 1, 0, 0, 1, 1, 0, 1, 0, 0, 0, 1, 1, 1, 0], dtype=np.int8)
_RATIO_LEAD = 2


def impact_ratio(cfg: EBPSKConfig, statistic: Statistic = "peak") -> float:
    """Noiseless separation of the two symbols: the smallest statistic of a bit-1 symbol divided by the
    largest of a bit-0 symbol, over a sequence with every bit transition (after a two-symbol lead-in,
    not counted). ``inf`` where every bit-0 symbol's statistic is exactly 0."""
    stat = symbol_statistic(apply_filter(modulate(_RATIO_BITS, cfg), cfg), cfg, statistic)
    bits = _RATIO_BITS[_RATIO_LEAD:]
    s = stat[_RATIO_LEAD:]
    s1, s0 = float(np.min(s[bits == 1])), float(np.max(s[bits == 0]))
    return math.inf if s0 == 0 else s1 / s0


def signal_correlation(cfg: EBPSKConfig) -> float:
    """ρ = ⟨s0, s1⟩ / √(E0 E1) of the two sampled symbols.

    From the definition, 1 − ρ = (K/N)(1 − cos θ) exactly when fs/f_if is an integer ≥ 3 (a whole cycle
    of sin(φ)·sin(φ + θ) sums to (M/2)cos θ over M ≥ 3 equally spaced samples); 4/7 for Table I.
    """
    s = symbol_waveforms(cfg)
    e = np.sum(s * s, axis=1)
    return float(np.dot(s[0], s[1]) / math.sqrt(e[0] * e[1]))


# ------------------------------------------------------------------------------------------ receivers
RECEIVERS = ("differential", "impacting", "impacting-assumed", "matched")
"""The registered receivers (:class:`Receiver`): ``differential`` (default: noncoherent, derived below),
``impacting`` (impacting filter designed from a stated Q, :func:`designed_filter`, and an amplitude threshold),
``impacting-assumed`` (the earlier default: the filter placement of :class:`EBPSKConfig`, assumed) and
``matched`` (coherent matched filter: needs the carrier phase; the reference that reaches the bound)."""
DEFAULT_RECEIVER = "differential"
DEFAULT_SPAN = 3
"""Symbol tails averaged into the differential receiver's phase reference (assumed: the carrier phase is
constant over three symbols, 210 ns for Table I)."""


@dataclass(frozen=True, slots=True)
class Receiver:
    """One of the :data:`RECEIVERS` and its settings, checked here once.

    Attributes:
        name: One of :data:`RECEIVERS`.
        span: ``differential``: symbol tails in the phase reference, an odd integer 1 … 99 (1: the symbol's own
            tail only — the per-symbol noncoherent ML detector, eq. D3 of :func:`differential_statistic`).
        statistic: ``impacting*``: ``peak`` or ``energy`` (:func:`symbol_statistic`).
        q: ``impacting``: quality factor Q > 1 of the filter's resonators (None: πK, :func:`designed_filter`).
    """

    name: str = DEFAULT_RECEIVER
    span: int = DEFAULT_SPAN
    statistic: str = "peak"
    q: float | None = None

    def __post_init__(self) -> None:
        one_of("receiver", self.name, RECEIVERS)
        span = integer("span", self.span, 1, 99)
        if span % 2 == 0:
            raise ConfigError(
                "span", self.span, "is even: the reference is centred on the symbol (1, 3, 5, …)"
            )
        one_of("statistic", self.statistic, ("peak", "energy"))
        if self.q is not None:
            in_range("q", self.q, 1.0, 1e6, lo_open=True)

    @property
    def filtered(self) -> bool:
        """Whether the receiver thresholds the impacting filter's output (a threshold to calibrate)."""
        return self.name.startswith("impacting")

    def filter_config(self, cfg: EBPSKConfig) -> EBPSKConfig:
        """The waveform with this receiver's impacting filter: designed for ``impacting``, as given otherwise."""
        return designed_filter(cfg, self.q) if self.name == "impacting" else cfg

    def statistic_of(self, x: np.ndarray, cfg: EBPSKConfig) -> np.ndarray:
        """The receiver's statistic of every symbol of the received record ``x`` (..., n_bits·L) →
        (..., n_bits). ``differential`` and ``matched`` decide bit 1 where it is > 0; the impacting receivers
        where it exceeds a threshold (in the units of :func:`symbol_statistic`)."""
        if self.name == "differential":
            return differential_statistic(x, cfg, self.span)
        if self.name == "matched":
            return matched_statistic(x, cfg)
        f = self.filter_config(cfg)
        return symbol_statistic(apply_filter(x, f), f, self.statistic)  # type: ignore[arg-type]

    def describe(self) -> str:
        """One line for metadata and summaries."""
        if self.name == "differential":
            return f"differential (noncoherent), phase reference from {self.span} symbol tail(s)"
        if self.name == "matched":
            return "coherent matched filter (knows the carrier phase)"
        if self.name == "impacting":
            q = "πK" if self.q is None else f"{self.q:g}"
            return f"impacting filter designed for Q = {q}, {self.statistic} threshold"
        return f"impacting filter of assumed placement, {self.statistic} threshold"


def designed_filter(cfg: EBPSKConfig, q: float | None = None) -> EBPSKConfig:
    """``cfg`` with the impacting filter designed from stated specifications (a reading of the literature's
    structure — one zero pair on the carrier, pole pairs beside it — with every number derived from Q):

    - zeros: r_z = 1 at f_if (a true notch: the unmodulated carrier gives no output);
    - poles: two resonators of quality factor Q, 3-dB bandwidth B = f_if/Q each, so of radius
      r_p = exp(−π B/f_s) = exp(−π f_if/(Q f_s))                                        (F1)
      (the ring-down time constant 1/(π B) = Q/(π f_if));
    - pole frequencies f_if (1 ± 1/(2Q)): half a bandwidth either side of the notch, so that the two
      resonances meet at the carrier and the notch sits between two peaks                          (F2)
    - Q = πK by default: the ring-down time constant equals the modulated segment, Q/(π f_if) = K/f_if   (F3)
      (the impact rings for as long as the phase jump lasts; Q = 2π, r_p = 0.951, offset 0.080 for Table I).

    Raises:
        ConfigError: naming ``q`` (not > 1), or ``pole_offset`` when a pole would leave (0, fs/2).
    """
    qq = math.pi * cfg.K if q is None else in_range("q", q, 1.0, 1e6, lo_open=True)
    radius = math.exp(-math.pi * cfg.f_if / (qq * cfg.fs))
    return replace(cfg, zero_radius=1.0, zero_offset=0.0, pole_radius=radius, pole_offset=1 / (2 * qq))


def _segments(x: np.ndarray, cfg: EBPSKConfig) -> tuple[np.ndarray, np.ndarray]:
    """(a, b) per symbol: the complex-baseband sums of the first K cycles and of the other N − K (eq. D1)."""
    x = np.asarray(x, dtype=float)
    L = cfg.samples_per_symbol
    if x.shape[-1] % L:
        raise ConfigError("x", f"{x.shape[-1]} samples", f"is not a whole number of {L}-sample symbols")
    n = np.arange(L)
    # the carrier's phase runs on across symbols and a symbol is N whole cycles: the same phasor every symbol
    z = x.reshape(*x.shape[:-1], x.shape[-1] // L, L) * np.exp(-2j * np.pi * (cfg.f_if / cfg.fs) * n)
    first = n * cfg.f_if < cfg.K * cfg.fs * (1 - 1e-12)
    return z[..., first].sum(axis=-1), z[..., ~first].sum(axis=-1)


def differential_statistic(x: np.ndarray, cfg: EBPSKConfig, span: int = DEFAULT_SPAN) -> np.ndarray:
    """The noncoherent (differential) EBPSK detector on the raw IF samples ``x`` (..., n_bits·L) →
    (..., n_bits); decide bit 1 where the statistic is > 0.

    Derivation. Per symbol, with ω = 2π f_if/f_s and the sums over the samples of the first K cycles (a)
    and of the other N − K (b),

        a = Σ x_n e^{−jωn},  b = Σ x_n e^{−jωn}                                                 (D1)

    A sine of phase φ gives (M/2)e^{j(φ−π/2)} per cycle of M samples (the 2ω image sums to zero over a whole
    cycle, M ≥ 3) and white noise of variance σ² a circular complex term of variance Mσ² per cycle. So
    a = (KM/2)e^{j(φ+θb)}u + n_a and b = ((N−K)M/2)e^{jφ}u + n_b (u = e^{−jπ/2}, b the bit, n_a, n_b
    independent). With φ unknown and uniform, the ML choice between the two symbols' complex templates is
    the larger envelope |⟨x, s̃_b⟩| = |a e^{−jθb} + b|, and

        |a e^{−jθ} + b|² − |a + b|² = 4 sin(θ/2) Im(a b* e^{−jθ/2})                            (D2)

    so the per-symbol noncoherent ML detector decides 1 where Im(a b* e^{−jθ/2}) > 0 (for θ = π: where
    Re(a b*) < 0 — the phase of the modulated segment against the symbol's own tail, a differential
    detector that needs no carrier phase). ``span`` > 1 replaces b by the sum of the tails of the ``span``
    symbols centred on this one (fewer at the record's ends): the carrier phase runs on across symbols and
    the tails are never modulated, so the reference gains energy whatever the neighbours' bits (assumed:
    the phase is constant over ``span`` symbols). Error probability (Stein's formula for the sign of
    Re(a b*) with independent Gaussian a, b;
    :func:`motionsig_cli.maneuver.ebpsk_link.differential_ber`)                               (D3)
    """
    s = integer("span", span, 1, 99)
    a, b = _segments(x, cfg)
    if s > 1:
        h = s // 2
        pad = [(0, 0)] * (b.ndim - 1) + [(h, h)]
        c = np.cumsum(np.pad(b, pad), axis=-1)
        c = np.concatenate([np.zeros_like(c[..., :1]), c], axis=-1)
        b = c[..., s:] - c[..., :-s]
    return np.imag(a * np.conj(b) * np.exp(-0.5j * cfg.theta))


def matched_statistic(x: np.ndarray, cfg: EBPSKConfig) -> np.ndarray:
    """The coherent matched-filter (ML) detector of two known symbols s0, s1 in white Gaussian noise, on the
    raw IF samples ``x`` (..., n_bits·L) → (..., n_bits): ⟨x, s1 − s0⟩ − (E1 − E0)/2, bit 1 where > 0 (M1).

    The symbols differ only in the first K cycles, so only those samples count; its error probability is
    Q(‖s1 − s0‖/(2σ)) = Q(√((1 − ρ) E_b/N_0)) with 1 − ρ = (K/N)(1 − cos θ) (:func:`signal_correlation`),
    the bound no receiver beats. It needs the carrier phase (0 in the link's model)."""
    x = np.asarray(x, dtype=float)
    L = cfg.samples_per_symbol
    if x.shape[-1] % L:
        raise ConfigError("x", f"{x.shape[-1]} samples", f"is not a whole number of {L}-sample symbols")
    s = symbol_waveforms(cfg)
    d = s[1] - s[0]
    bias = 0.5 * float(s[1] @ s[1] - s[0] @ s[0])
    return x.reshape(*x.shape[:-1], x.shape[-1] // L, L) @ d - bias
