"""The EBPSK link in AWGN: bit error rate of the registered receivers against E_b/N_0, beside the coherent
bound (the front end of Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System*; the
modulation and the impacting-filter demodulator of Wu & Feng, "On BER performance of EBPSK-MODEM in AWGN
channel", Sensors 10(4), 2010).

Noise. Real white Gaussian noise of variance σ² per sample is added to the unit-amplitude IF waveform;
with the bit energy E_b = Σ s² over one symbol's samples (:attr:`EBPSKConfig.bit_energy`, 35 for Table I)
and N_0/2 = σ² (two-sided density, the sample interval as the unit of time), E_b/N_0 = E_b/(2σ²).

Bound. Bit 0 and bit 1 are two known signals s0, s1 of equal energy E_b and correlation ρ
(:func:`~motionsig_cli.signals.ebpsk.signal_correlation`); each bit's signal lies in its own symbol, so
with equiprobable independent bits the optimum (coherent, matched-filter) receiver errs with
P_b = Q(‖s1 − s0‖/(2σ)) = Q(√((1 − ρ) E_b/N_0)) and no receiver does better. The symbols differ only in the
first K cycles: ‖s1 − s0‖² = (1 − cos θ)·K·M (M samples per cycle) against 2E_b = N·M, so
1 − ρ = (K/N)(1 − cos θ) — 4/7 for K = 2, N = 7, θ = π: BPSK on the modulated segment alone, whose energy
is 2/7 of E_b (5.4 dB short of BPSK's 1 − ρ = 2).

Receivers (:data:`~motionsig_cli.signals.ebpsk.RECEIVERS`, :class:`~motionsig_cli.signals.ebpsk.Receiver`):
``differential`` (the default; noncoherent, eqs D1–D3 of
:func:`~motionsig_cli.signals.ebpsk.differential_statistic`, error probability :func:`differential_ber`),
``matched`` (the coherent reference, which reaches the bound), ``impacting`` (the impacting filter designed
from a stated Q, :func:`~motionsig_cli.signals.ebpsk.designed_filter`, and an amplitude threshold) and
``impacting-assumed`` (the earlier default: the filter placement of the configuration, assumed).

Threshold. The differential and matched receivers decide bit 1 where their statistic is > 0 (no threshold
to set). For the impacting receivers ``threshold=None`` (the default) sets, at each E_b/N_0, the threshold
that minimises the errors on an independent calibration sequence of ``calibration_bits`` bits (the best fixed
threshold of a receiver that knows its SNR; its random streams are disjoint from the trials'); a number
fixes it for every E_b/N_0 (in the units of the statistic, see
:func:`~motionsig_cli.signals.ebpsk.symbol_statistic`).

Random streams: trial t draws its bits from ``trial_rng(seed, t, 0)`` and its standard-normal noise from
``trial_rng(seed, t, 1)``; the same noise, scaled, serves every E_b/N_0 (common random numbers: the curve
is smooth and monotone where the detector is) and every receiver. Calibration at E_b/N_0 number i draws from
``trial_rng(seed, i, 2)``. A trial is one record of ``bits_per_trial`` data bits after a lead-in bit 0
that is not counted (the filter starts from rest). Counts are sums over trials, so the result does not
depend on the chunking or on the engine.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from scipy.special import erfc, i0e

from motionsig_cli.config import ConfigError, in_range, integer
from motionsig_cli.engine import tasks_of, trials_per_task
from motionsig_cli.rng import trial_rng
from motionsig_cli.signals.ebpsk import (
    EBPSKConfig,
    Receiver,
    apply_filter,
    detection_window,
    impact_ratio,
    impacting_filter,
    modulate,
    signal_correlation,
)
from motionsig_cli.tables import Table, make_meta

__all__ = [
    "DEFAULT_EBN0_DB",
    "BerJob",
    "BerResult",
    "calibrate_thresholds",
    "closed_form_ber",
    "coherent_ber",
    "differential_ber",
    "noise_sigma",
    "optimum_threshold",
    "waveform_table",
]

DEFAULT_EBN0_DB = tuple(float(e) for e in range(0, 21, 2))
LEAD_IN = 1  # bit-0 symbols before the data of a record (not counted)
MAX_BITS = 2_000_000_000  # data bits of one run (trials × bits per trial)
MAX_BITS_PER_TRIAL = 100_000
SECONDS_PER_SAMPLE = 4e-8  # cost model: filter, statistic and noise per sample and E_b/N_0 (measured ≈ 3e-8)


def noise_sigma(cfg: EBPSKConfig, ebn0_db: float | np.ndarray) -> np.ndarray:
    """σ per sample for E_b/N_0 [dB]: σ² = E_b / (2·10^(E_b/N_0 / 10))."""
    return np.sqrt(cfg.bit_energy / (2 * 10 ** (np.asarray(ebn0_db, dtype=float) / 10)))


def coherent_ber(cfg: EBPSKConfig, ebn0_db: float | np.ndarray) -> np.ndarray:
    """The coherent bound P_b = Q(√((1 − ρ) E_b/N_0)) of the module docstring."""
    rho = signal_correlation(cfg)
    snr = (1 - rho) * 10 ** (np.asarray(ebn0_db, dtype=float) / 10)
    return 0.5 * erfc(np.sqrt(snr) / math.sqrt(2))


def differential_ber(cfg: EBPSKConfig, ebn0_db: float | np.ndarray, span: int = 1) -> np.ndarray:
    """Error probability of the differential receiver (eq. D3 of
    :func:`~motionsig_cli.signals.ebpsk.differential_statistic`) for θ = π, a symbol with ``span`` tails in
    its reference (the interior of a record).

    With γ_a = (K/N) E_b/N_0 and γ_b = span·((N − K)/N) E_b/N_0 the SNRs |E a|²/var a and |E b|²/var b of
    eq. D1 (independent, circular), the sign of Re(a b*) errs with (Stein's formula for the difference of two
    Rician envelopes; Proakis, *Digital Communications*, 4th ed., App. B)

        P = Q₁(α, β) − ½ exp(−(α² + β²)/2) I₀(αβ),  α = |√γ_b − √γ_a|/√2,  β = (√γ_b + √γ_a)/√2

    (γ_a = γ_b = γ gives binary DPSK's ½ e^{−γ}). Q₁ is Marcum's Q function, from the noncentral χ² with
    2 degrees of freedom.

    Raises:
        ConfigError: naming ``theta`` where θ ≠ π (the formula is the antipodal case).
    """
    if abs(cfg.theta - math.pi) > 1e-12:
        raise ConfigError("theta", cfg.theta, "is not π: the closed form covers the antipodal case only")
    from scipy.stats import ncx2  # here: scipy.stats costs 0.3 s to import

    e = 10 ** (np.asarray(ebn0_db, dtype=float) / 10)
    ga, gb = cfg.K / cfg.N * e, span * (cfg.N - cfg.K) / cfg.N * e
    alpha = np.abs(np.sqrt(gb) - np.sqrt(ga)) / math.sqrt(2)
    beta = (np.sqrt(gb) + np.sqrt(ga)) / math.sqrt(2)
    # e^{-(α²+β²)/2} I₀(αβ) = e^{-(β-α)²/2} i0e(αβ)
    return ncx2.sf(beta**2, 2, alpha**2) - 0.5 * np.exp(-((beta - alpha) ** 2) / 2) * i0e(alpha * beta)


def closed_form_ber(cfg: EBPSKConfig, receiver: Receiver, ebn0_db: float | np.ndarray) -> np.ndarray:
    """The receiver's BER in closed form where there is one: ``matched`` the bound, ``differential`` (θ = π)
    :func:`differential_ber`; NaN otherwise (the impacting receivers: Monte Carlo only)."""
    e = np.asarray(ebn0_db, dtype=float)
    if receiver.name == "matched":
        return coherent_ber(cfg, e)
    if receiver.name == "differential" and abs(cfg.theta - math.pi) <= 1e-12:
        return differential_ber(cfg, e, receiver.span)
    return np.full(e.shape, np.nan)


def optimum_threshold(stat: np.ndarray, bits: np.ndarray) -> float:
    """The threshold t minimising #(bit 1 with stat ≤ t) + #(bit 0 with stat > t), as the midpoint between
    neighbouring sorted statistics (the lowest such t where several tie)."""
    order = np.argsort(stat, kind="stable")
    s, b = stat[order], bits[order].astype(bool)
    # errors if the threshold sits just above sorted element j: ones at or below j, zeros above j
    ones_below = np.cumsum(b)
    zeros_above = np.count_nonzero(~b) - np.cumsum(~b)
    errors = np.concatenate([[np.count_nonzero(~b)], ones_below + zeros_above])
    j = int(np.argmin(errors))  # j = 0: below everything
    if j == 0:
        return float(s[0] / 2) if s[0] > 0 else float(np.nextafter(0.0, 1.0))
    upper = s[j] if j < len(s) else s[-1] * 2 + 1e-12
    return float((s[j - 1] + upper) / 2)


def _records(cfg: EBPSKConfig, bits: np.ndarray) -> np.ndarray:
    """Modulated records (..., (LEAD_IN + n_bits)·L) of data bits (..., n_bits) after the lead-in."""
    lead = np.zeros((*bits.shape[:-1], LEAD_IN), dtype=np.int8)
    return modulate(np.concatenate([lead, bits], axis=-1), cfg)


def calibrate_thresholds(
    cfg: EBPSKConfig, ebn0_db: Sequence[float], receiver: Receiver, seed: int, n_bits: int
) -> tuple[float, ...]:
    """The minimum-error threshold (:func:`optimum_threshold`) of an impacting ``receiver`` at each E_b/N_0,
    each from its own calibration record of ``n_bits`` bits (streams ``trial_rng(seed, i, 2)``)."""
    out = []
    for i, eb in enumerate(ebn0_db):
        g = trial_rng(seed, i, 2)
        bits = g.integers(0, 2, n_bits, dtype=np.int8)
        x = _records(cfg, bits)
        stat = receiver.statistic_of(x + noise_sigma(cfg, eb) * g.standard_normal(x.shape), cfg)
        out.append(optimum_threshold(stat[LEAD_IN:], bits))
    return tuple(out)


@dataclass(frozen=True)
class BerResult:
    """Errors per E_b/N_0 of a BER Monte Carlo, with the thresholds used and the bound."""

    cfg: EBPSKConfig
    ebn0_db: tuple[float, ...]
    errors: np.ndarray  # (n_ebn0,) int
    bits: int  # data bits per E_b/N_0
    thresholds: tuple[float, ...]
    receiver: Receiver
    threshold_rule: str
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def ber(self) -> np.ndarray:
        return self.errors / self.bits

    @property
    def se(self) -> np.ndarray:
        """Binomial standard error √(p(1 − p)/n) of each BER."""
        p = self.ber
        return np.sqrt(p * (1 - p) / self.bits)

    @property
    def bound(self) -> np.ndarray:
        return coherent_ber(self.cfg, np.array(self.ebn0_db))

    @property
    def closed_form(self) -> np.ndarray:
        """The receiver's BER in closed form (:func:`closed_form_ber`; NaN where there is none)."""
        return closed_form_ber(self.cfg, self.receiver, np.array(self.ebn0_db))

    def table(self) -> Table:
        rows = [
            (float(e), int(self.bits), int(n), float(p), float(s), float(b), float(c), float(t))
            for e, n, p, s, b, c, t in zip(
                self.ebn0_db,
                self.errors,
                self.ber,
                self.se,
                self.bound,
                self.closed_form,
                self.thresholds,
                strict=True,
            )
        ]
        cols = ("ebn0_db", "bits", "errors", "ber", "se", "coherent_bound", "closed_form", "threshold")
        return Table(cols, rows, self.meta)

    def summary(self) -> str:
        i = len(self.ebn0_db) - 1
        return (
            f"EBPSK(K={self.cfg.K}, N={self.cfg.N}) {self.receiver.name} receiver: BER {self.ber[i]:.3g} "
            f"± {self.se[i]:.2g} at {self.ebn0_db[i]:g} dB (coherent bound {self.bound[i]:.3g}); "
            f"{self.bits} bits per point"
        )


@dataclass(frozen=True, eq=False)
class BerJob:
    """BER vs E_b/N_0 of one receiver (a :class:`~motionsig_cli.engine.MonteCarloJob`).

    Attributes:
        cfg: Waveform and filter.
        ebn0_db: E_b/N_0 values [dB], each finite in [−20, 40] (default 0, 2, …, 20).
        trials: Records per E_b/N_0, ≥ 1.
        bits_per_trial: Data bits per record, 1 … :data:`MAX_BITS_PER_TRIAL` (trials × bits at most
            :data:`MAX_BITS`).
        receiver: The receiver and its settings (default: ``differential``).
        threshold: Impacting receivers only. None: the calibrated minimum-error threshold at each E_b/N_0
            (module docstring); a number > 0: that threshold everywhere.
        calibration_bits: Bits of each calibration record (≥ 100).
        seed: Root seed.
        chunk: Trials per task (None: from the cost model); never changes the result.
    """

    name: ClassVar[str] = "encode ebpsk --ber"

    cfg: EBPSKConfig = field(default_factory=EBPSKConfig)
    ebn0_db: tuple[float, ...] = DEFAULT_EBN0_DB
    trials: int = 100
    bits_per_trial: int = 1000
    receiver: Receiver = field(default_factory=Receiver)
    threshold: float | None = None
    calibration_bits: int = 20_000
    seed: int = 2008
    chunk: int | None = None
    thresholds: tuple[float, ...] = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "ebn0_db", tuple(float(e) for e in self.ebn0_db))
        if not self.ebn0_db:
            raise ConfigError("ebn0_db", self.ebn0_db, "holds no value")
        for e in self.ebn0_db:
            in_range("ebn0_db", e, -20.0, 40.0, unit="dB")
        integer("trials", self.trials, 1)
        integer("bits_per_trial", self.bits_per_trial, 1, MAX_BITS_PER_TRIAL)
        if self.trials * self.bits_per_trial > MAX_BITS:
            raise ConfigError(
                "trials", self.trials, f"× {self.bits_per_trial} bits is more than {MAX_BITS} bits per point"
            )
        if not isinstance(self.receiver, Receiver):
            raise ConfigError("receiver", self.receiver, "is not a Receiver")
        if self.threshold is not None:
            if not self.receiver.filtered:
                raise ConfigError(
                    "threshold",
                    self.threshold,
                    f"applies to the impacting receivers, not {self.receiver.name}",
                )
            in_range("threshold", self.threshold, 0.0, lo_open=True)
        integer("calibration_bits", self.calibration_bits, 100, MAX_BITS_PER_TRIAL * 10)
        integer("seed", self.seed, 0)
        if self.chunk is not None:
            integer("chunk", self.chunk, 1)
        if not self.receiver.filtered:
            th = (0.0,) * len(self.ebn0_db)
        elif self.threshold is None:
            th = calibrate_thresholds(self.cfg, self.ebn0_db, self.receiver, self.seed, self.calibration_bits)
        else:
            th = (float(self.threshold),) * len(self.ebn0_db)
        object.__setattr__(self, "thresholds", th)

    @property
    def threshold_rule(self) -> str:
        if not self.receiver.filtered:
            return "sign of the statistic (bit 1 where > 0)"
        if self.threshold is None:
            return f"minimum-error threshold per Eb/N0 from {self.calibration_bits} calibration bits"
        return "fixed"

    def tasks(self) -> list[range]:
        samples = (self.bits_per_trial + LEAD_IN) * self.cfg.samples_per_symbol * len(self.ebn0_db)
        per = self.chunk or trials_per_task(
            samples * SECONDS_PER_SAMPLE, at_most=max(1, 4_000_000 // samples)
        )
        return tasks_of(self.trials, per)

    def task_size(self, task: range) -> int:
        return len(task)

    def run_task(self, task: range) -> np.ndarray:
        """Errors per E_b/N_0 over the task's trials, (n_ebn0,) int64."""
        bits = np.stack(
            [trial_rng(self.seed, t, 0).integers(0, 2, self.bits_per_trial, dtype=np.int8) for t in task]
        )
        x = _records(self.cfg, bits)  # (B, n)
        w = np.stack([trial_rng(self.seed, t, 1).standard_normal(x.shape[-1]) for t in task])
        sig = noise_sigma(self.cfg, np.array(self.ebn0_db))
        y = x[:, None, :] + sig[None, :, None] * w[:, None, :]  # (B, E, n)
        stat = self.receiver.statistic_of(y, self.cfg)[..., LEAD_IN:]
        decided = stat > np.array(self.thresholds)[None, :, None]
        return np.count_nonzero(decided != bits[:, None, :].astype(bool), axis=(0, 2)).astype(np.int64)

    def reduce(self, tasks: Sequence[range], results: Sequence[np.ndarray]) -> BerResult:
        errors = np.sum(np.stack(list(results)), axis=0) if results else np.zeros(len(self.ebn0_db), int)
        return BerResult(
            self.cfg,
            self.ebn0_db,
            errors,
            self.trials * self.bits_per_trial,
            self.thresholds,
            self.receiver,
            self.threshold_rule,
            self.meta(),
        )

    def identity(self) -> dict[str, Any]:
        return self.meta()

    def meta(self) -> dict[str, Any]:
        c, rx = self.cfg, self.receiver
        filtered = rx.filtered
        return make_meta(
            "encode ebpsk --ber",
            **c.waveform_meta(),
            **(rx.filter_config(c).filter_meta() if filtered else {}),
            receiver=rx.name,
            receiver_description=rx.describe(),
            span=rx.span if rx.name == "differential" else None,
            statistic=rx.statistic if filtered else None,
            filter_q=(math.pi * c.K if rx.q is None else rx.q) if rx.name == "impacting" else None,
            ebn0_db=list(self.ebn0_db),
            trials=self.trials,
            bits_per_trial=self.bits_per_trial,
            threshold_rule=self.threshold_rule,
            calibration_bits=self.calibration_bits if filtered and self.threshold is None else None,
            seed=self.seed,
            noise="real AWGN, Eb/N0 = Eb/(2 sigma^2), Eb = sum of s^2 over one symbol's samples",
            bound="coherent detection of two signals of correlation rho: Q(sqrt((1-rho) Eb/N0))",
            rho=signal_correlation(c),
            source="Yao, Teng & Wu, Maneuvering Target Tracking Based on EBPSK Modulated JRC System (Table I); "
            "Wu & Feng, On BER performance of EBPSK-MODEM in AWGN channel (Sensors 2010)",
            filter_design=_FILTER_DESIGN.get(rx.name),
            closed_form=_CLOSED_FORM.get(rx.name),
        )


_FILTER_DESIGN = {
    "impacting": "zero pair on the carrier; two resonators of Q (default pi K) at f_if(1 +- 1/(2Q)), "
    "radius exp(-pi f_if/(Q fs)): designed from these stated specifications",
    "impacting-assumed": "zero pair on the carrier, two pole pairs at f_if(1 +- offset): assumed",
}
_CLOSED_FORM = {
    "matched": "the coherent bound",
    "differential": "Stein's formula for the sign of Re(a b*), interior symbols (theta = pi only)",
}


def waveform_table(cfg: EBPSKConfig, bits: np.ndarray, source: str) -> tuple[Table, np.ndarray, np.ndarray]:
    """The noiseless record of ``bits`` as a table ``sample, t, bit, symbol, x, y`` (x: the IF waveform,
    y: the impacting filter's output, from rest), with (x, y) for a figure. ``source`` says where the bits
    came from (``--bits`` or the code set), for the metadata."""
    x = modulate(bits, cfg)
    y = apply_filter(x, cfg)
    L = cfg.samples_per_symbol
    n = np.arange(x.size)
    sym = n // L
    t = n / cfg.fs
    b = np.asarray(bits, dtype=np.int64)[sym]
    rows = list(zip(n.tolist(), t.tolist(), b.tolist(), sym.tolist(), x.tolist(), y.tolist(), strict=True))
    start, stop = detection_window(cfg)
    meta = make_meta(
        "encode ebpsk",
        **cfg.waveform_meta(),
        samples_per_symbol=L,
        bits=source,
        n_bits=len(bits),
        filter_b=impacting_filter(cfg)[0].tolist(),
        filter_a=impacting_filter(cfg)[1].tolist(),
        filter_design="zero pair on the carrier, two pole pairs at f_if(1 +- offset), peak gain 1: assumed",
        **cfg.filter_meta(),
        detection_window=[start, stop],
        impact_ratio=impact_ratio(cfg),
        convention="x = sin(2 pi f_if t + theta [bit 1, first K cycles of its symbol]); y from rest",
        source="Yao, Teng & Wu, Maneuvering Target Tracking Based on EBPSK Modulated JRC System (Table I)",
    )
    return Table(("sample", "t", "bit", "symbol", "x", "y"), rows, meta), x, y
