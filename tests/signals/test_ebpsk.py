"""EBPSK waveform, impacting filter and demodulator (motionsig_cli.signals.ebpsk).

The waveform is checked against the definition written out sample by sample here (not with the module's
vectorised construction); the filter against its stated placement; the impact ratio and the noiseless
demodulation against measured values (impact ratio 17.0 for Table I's K = 2, N = 7: tested ≥ 10).
"""

import math

import numpy as np
import pytest
from scipy import signal as sp_signal

from motionsig_cli.config import ConfigError
from motionsig_cli.signals.ebpsk import (
    RECEIVERS,
    EBPSKConfig,
    Receiver,
    apply_filter,
    demodulate,
    designed_filter,
    detection_window,
    differential_statistic,
    filter_response,
    filter_roots,
    impact_ratio,
    impacting_filter,
    matched_statistic,
    modulate,
    signal_correlation,
    symbol_statistic,
)

CFG = EBPSKConfig()  # Table I: f_if 100 MHz, fs 1 GHz, K = 2, N = 7


def reference_waveform(bits, N, K, theta, f, fs, phase0=0.0):
    """The definition, one sample at a time: in symbol j, t = n/fs − j·N/f; bit 1 adds θ while t < K/f
    (``phase0``: a carrier phase added throughout, as an unknown channel phase)."""
    L = round(N * fs / f)
    out = []
    for j, b in enumerate(bits):
        for m in range(L):
            t_local = m / fs
            t = (j * L + m) / fs
            phase = theta if (b == 1 and t_local < K / f - 1e-15) else 0.0
            out.append(math.sin(2 * math.pi * f * t + phase + phase0))
    return np.array(out)


@pytest.mark.parametrize(
    "kw",
    [
        {},
        {"K": 1, "N": 3, "theta": 2.0},
        {"fs": 7e8, "f_if": 1e8, "N": 5, "K": 3},
        {"fs": 2.5e8, "N": 2, "K": 1},
    ],
)
def test_modulate_matches_definition(kw):
    cfg = EBPSKConfig(**kw)
    bits = [0, 1, 1, 0, 1, 0, 0]
    want = reference_waveform(bits, cfg.N, cfg.K, cfg.theta, cfg.f_if, cfg.fs)
    np.testing.assert_allclose(modulate(bits, cfg), want, atol=1e-9)


def test_modulate_is_batched_and_bit0_is_one_sine():
    rng = np.random.default_rng(5)
    bits = rng.integers(0, 2, (3, 11))
    x = modulate(bits, CFG)
    assert x.shape == (3, 11 * 70)
    for r in range(3):
        np.testing.assert_array_equal(x[r], modulate(bits[r], CFG))
    n = np.arange(5 * 70)
    np.testing.assert_allclose(modulate(np.zeros(5, int), CFG), np.sin(2 * np.pi * 0.1 * n), atol=1e-12)


@pytest.mark.parametrize("bits", [[], [0, 2], [0.5, 1], np.zeros((2, 0))])
def test_bad_bits(bits):
    with pytest.raises(ConfigError) as e:
        modulate(bits, CFG)
    assert e.value.field == "bits"


@pytest.mark.parametrize(
    "kw, field",
    [
        ({"K": 7}, "K"),
        ({"K": 9}, "K"),
        ({"N": 0}, "N"),
        ({"K": 0}, "K"),
        ({"theta": 0.0}, "theta"),
        ({"theta": 2 * math.pi}, "theta"),
        ({"fs": 2e8}, "fs"),  # fs must exceed 2 f_if
        ({"fs": 1.05e9}, "fs"),  # 73.5 samples per symbol
        ({"f_carrier": 5e7}, "f_carrier"),
        ({"pole_radius": 1.0}, "pole_radius"),
        ({"pole_offset": -0.1}, "pole_offset"),
        ({"f_if": 4e8, "fs": 1e9, "N": 2, "K": 1, "pole_offset": 0.3}, "pole_offset"),  # pole above fs/2
    ],
)
def test_config_errors_name_the_field(kw, field):
    with pytest.raises(ConfigError) as e:
        EBPSKConfig(**kw)
    assert e.value.field == field


def test_filter_placement_and_response():
    zeros, poles = filter_roots(CFG)
    w_if = 2 * np.pi * CFG.f_if / CFG.fs
    np.testing.assert_allclose(np.abs(zeros), 1.0)
    np.testing.assert_allclose(np.sort(np.abs(np.angle(zeros))), [w_if, w_if])
    assert np.all(np.abs(poles) < 1)
    b, a = impacting_filter(CFG)
    np.testing.assert_allclose(np.sort_complex(np.roots(b)), np.sort_complex(zeros), atol=1e-9)
    np.testing.assert_allclose(np.sort_complex(np.roots(a)), np.sort_complex(poles), atol=1e-9)
    # notch on the carrier, peak gain 1
    _, h_if = sp_signal.freqz(b, a, worN=[CFG.f_if], fs=CFG.fs)
    assert abs(h_if[0]) < 1e-9
    f, h = filter_response(CFG, 1 << 16)
    mag = np.abs(h)
    assert abs(mag.max() - 1) < 1e-3
    # the pass band: two peaks straddling the carrier, within ±20 % of it, centred on it within 2 %
    peaks, _ = sp_signal.find_peaks(mag)
    assert len(peaks) == 2
    lo, hi = f[peaks]
    assert 0.8 * CFG.f_if < lo < CFG.f_if < hi < 1.2 * CFG.f_if
    assert abs((lo + hi) / 2 - CFG.f_if) < 0.02 * CFG.f_if  # measured 0.6 %
    # a band pass: down at half the carrier (measured 0.55) and at twice it (measured 0.16)
    assert mag[np.argmin(np.abs(f - 0.5 * CFG.f_if))] < 0.6
    assert mag[np.argmin(np.abs(f - 2 * CFG.f_if))] < 0.2


def test_apply_filter_is_lfilter_per_row():
    rng = np.random.default_rng(1)
    x = rng.standard_normal((2, 3, 140))
    b, a = impacting_filter(CFG)
    y = apply_filter(x, CFG)
    for i in range(2):
        for j in range(3):
            np.testing.assert_allclose(y[i, j], sp_signal.lfilter(b, a, x[i, j]), rtol=1e-12, atol=1e-14)


def test_impacts_dominate_bit0_response():
    # measured: 17.0 (peak), 982 (energy); a filter without the notch (zeros off the carrier) gives ~1.7
    assert impact_ratio(CFG) > 10
    assert impact_ratio(CFG, "energy") > 100
    assert impact_ratio(EBPSKConfig(zero_offset=0.05)) < 3
    y = apply_filter(modulate([0, 0, 1, 0, 0], CFG), CFG)
    stat = symbol_statistic(y, CFG)
    assert 1.1 < stat[2] < 1.5  # the impact (measured 1.27)
    assert stat[4] < 0.01  # two symbols later the ringing is gone (r_p^140 ≈ 4e-5)


def test_detection_window():
    assert detection_window(CFG) == (0, 30)
    assert detection_window(EBPSKConfig(N=3, K=2)) == (0, 30)
    assert detection_window(EBPSKConfig(N=2, K=1, fs=2.5e8)) == (0, 5)


def test_noiseless_demodulation_recovers_bits():
    rng = np.random.default_rng(7)
    bits = np.concatenate([[0], rng.integers(0, 2, 400)])
    x = modulate(bits, CFG)
    for statistic, th in (("peak", 0.7), ("energy", 3.0)):
        got = demodulate(x, CFG, th, statistic=statistic)
        np.testing.assert_array_equal(got[1:], bits[1:])


@pytest.mark.parametrize("K, N, theta", [(2, 7, math.pi), (1, 4, 1.0), (3, 5, 2.5), (6, 7, 0.3)])
def test_signal_correlation_closed_form(K, N, theta):
    cfg = EBPSKConfig(K=K, N=N, theta=theta)
    assert signal_correlation(cfg) == pytest.approx(1 - K / N * (1 - math.cos(theta)), abs=1e-12)
    assert cfg.bit_energy == pytest.approx(N * 10 / 2)


# ------------------------------------------------------------------------------------------ receivers
@pytest.mark.parametrize("theta", [math.pi, math.pi / 2, 4.0])
@pytest.mark.parametrize("span", [1, 3])
def test_differential_needs_no_carrier_phase(theta, span):
    """The differential statistic (eq. D2) decides every noiseless bit right whatever the carrier phase and
    amplitude of the record: it compares the modulated segment's phase with the tail's, never with a
    reference phase. The record is written out here from the definition with a phase offset φ₀."""
    cfg = EBPSKConfig(theta=theta)
    rng = np.random.default_rng(4)
    bits = rng.integers(0, 2, 40)
    for phi0, amp in ((0.0, 1.0), (1.3, 0.2), (-2.9, 7.0)):
        x = amp * reference_waveform(bits, 7, 2, theta, 100e6, 1e9, phase0=phi0)
        stat = differential_statistic(x, cfg, span)
        np.testing.assert_array_equal(stat > 0, bits == 1)
        # and its magnitude is that of D2: |Im(a b* e^{-jθ/2})| = (KM/2)((N−K)M/2)·(tails)·sin(θ/2)·amp²
        tails = np.full(40, span)
        if span == 3:
            tails[[0, -1]] = 2
        expect = (2 * 10 / 2) * (5 * 10 / 2) * tails * math.sin(theta / 2) * amp**2
        np.testing.assert_allclose(np.abs(stat), expect, rtol=1e-9)


def test_matched_statistic_is_the_correlation_with_the_difference():
    """M1 written out: ⟨x, s1 − s0⟩ over the first K cycles only (the symbols agree elsewhere), bias 0 for
    equal energies; noiseless decisions are right and the statistic is ±‖s1 − s0‖²/2 = ±(1 − cos θ)KM/2."""
    bits = np.array([0, 1, 1, 0, 1])
    x = modulate(bits, CFG)
    stat = matched_statistic(x, CFG)
    np.testing.assert_allclose(stat, np.where(bits == 1, 1, -1) * 2 * 2 * 10 / 2, atol=1e-9)


def test_designed_filter_meets_its_specifications():
    """F1–F3 checked on the designed filter's roots and response, not on its formulas: each pole pair's
    impulse response decays with time constant Q/(π f_if) (Q = πK = 2π: 20 samples, two IF cycles), the
    poles sit at f_if(1 ± 1/(2Q)), the zeros on the unit circle at f_if; |H(f_if)| = 0."""
    d = designed_filter(CFG)
    zeros, poles = filter_roots(d)
    q = 2 * math.pi
    np.testing.assert_allclose(np.abs(zeros), 1.0)
    np.testing.assert_allclose(np.abs(np.angle(zeros)), 2 * math.pi * 0.1)
    freqs = np.sort(np.abs(np.angle(poles[:2]))) / (2 * math.pi) * 1e9
    np.testing.assert_allclose(freqs, 100e6 * np.array([1 - 1 / (2 * q), 1 + 1 / (2 * q)]))
    # time constant: |p|^n falls by e over Q fs/(π f_if) samples
    tau = q * 10 / math.pi
    assert np.abs(poles[0]) ** tau == pytest.approx(math.exp(-1))
    f, h = filter_response(d, 1 << 15)
    assert np.abs(h[np.argmin(np.abs(f - 100e6))]) < 1e-3
    assert d.pole_radius == pytest.approx(0.9512, abs=1e-4) and d.pole_offset == pytest.approx(
        0.0796, abs=1e-4
    )
    # a stated Q other than the default
    assert designed_filter(CFG, 10.0).pole_offset == pytest.approx(0.05)


@pytest.mark.parametrize(
    "kw, field",
    [
        ({"name": "coherent"}, "receiver"),
        ({"span": 2}, "span"),
        ({"span": 0}, "span"),
        ({"statistic": "mean"}, "statistic"),
        ({"q": 1.0}, "q"),
        ({"q": float("nan")}, "q"),
    ],
)
def test_receiver_errors_name_the_field(kw, field):
    with pytest.raises(ConfigError) as e:
        Receiver(**kw)
    assert e.value.field == field


def test_receiver_registry_dispatch():
    """Every registered receiver decides noiseless bits right (after the lead-in symbol of the filtered ones)
    and only the impacting ones need a threshold."""
    bits = np.array([0, 0, 1, 0, 1, 1, 0, 1])
    x = modulate(bits, CFG)
    for name in RECEIVERS:
        rx = Receiver(name)
        stat = rx.statistic_of(x, CFG)
        assert rx.filtered == name.startswith("impacting")
        if rx.filtered:
            s = stat[2:]
            assert s[bits[2:] == 1].min() > s[bits[2:] == 0].max()
        else:
            np.testing.assert_array_equal(stat > 0, bits == 1)
