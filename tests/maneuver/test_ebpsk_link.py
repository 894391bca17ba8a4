"""BER Monte Carlo of the EBPSK receivers (motionsig_cli.maneuver.ebpsk_link).

Tolerances. A BER estimate from n bits has binomial SE √(p(1−p)/n); "within 4 SE" fails by chance with
probability < 10⁻⁴ per point. The coherent bound is checked two ways: an optimum correlation receiver
written here reaches it (within 4 SE: checks the noise scaling, E_b and ρ), and no receiver beats it by
more than 4 SE. The default (differential) receiver is checked against its closed form (Stein's formula),
which is itself checked against binary DPSK's ½e^{−γ}; the earlier default (``impacting-assumed``) against
the error counts that the previous version of the code printed for the same seed.
"""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.engine import Engine, run_job
from motionsig_cli.maneuver.ebpsk_link import (
    BerJob,
    closed_form_ber,
    coherent_ber,
    differential_ber,
    noise_sigma,
    optimum_threshold,
)
from motionsig_cli.rng import trial_rng
from motionsig_cli.signals.ebpsk import EBPSKConfig, Receiver, modulate, symbol_waveforms

CFG = EBPSKConfig()
EBN0 = (6.0, 10.0, 14.0, 18.0)
ASSUMED = Receiver("impacting-assumed")


@pytest.fixture(scope="module")
def assumed():
    return run_job(BerJob(CFG, EBN0, trials=20, bits_per_trial=1000, seed=11, receiver=ASSUMED))


def test_earlier_default_is_reproducible_by_name(assumed):
    """``impacting-assumed`` is the receiver that was the default before the differential one: the previous
    version of this code (commit 2e36d59, ``BerJob(CFG, EBN0, trials=20, bits_per_trial=1000, seed=11)``)
    printed these error counts of 20000 bits (BER 0.280, 0.126, 0.0173, 3.0e-4)."""
    np.testing.assert_array_equal(assumed.errors, [5603, 2525, 346, 6])
    ber, se = assumed.ber, assumed.se
    for i in range(len(EBN0) - 1):
        assert ber[i + 1] < ber[i] - 4 * math.hypot(se[i], se[i + 1])


@pytest.fixture(scope="module")
def receivers():
    """Every receiver on the same bits and noise: 100 000 bits per point."""
    out = {}
    for rx in (Receiver(), Receiver(span=1), Receiver("matched"), Receiver("impacting"), ASSUMED):
        out[(rx.name, rx.span)] = run_job(
            BerJob(
                CFG, (6.0, 10.0), trials=100, bits_per_trial=1000, seed=23, receiver=rx, calibration_bits=5000
            )
        )
    return out


def test_default_receiver_meets_its_closed_form_and_the_target(receivers):
    """The differential receiver (span 3: the default; span 1: the per-symbol noncoherent ML detector) is
    within 4 SE of Stein's formula (the record's two end symbols, with fewer tails, are 2 of 1000 bits: their
    effect is < 10⁻⁵), and at 10 dB its BER is ≤ 2·10⁻² — 0.1 dB from the bound at 10⁻² (span 1: 0.4 dB)."""
    for span in (3, 1):
        res = receivers[("differential", span)]
        p = differential_ber(CFG, np.array(res.ebn0_db), span)
        np.testing.assert_allclose(res.closed_form, p)
        sd = np.sqrt(p * (1 - p) / res.bits)
        assert np.all(np.abs(res.ber - p) < 4 * sd), (span, res.ber, p)
    default = run_job(BerJob(CFG, (10.0,), trials=100, bits_per_trial=1000, seed=23, calibration_bits=5000))
    assert default.receiver == Receiver() and default.receiver.span == 3
    assert default.ber[0] + 4 * default.se[0] <= 2e-2


def test_no_receiver_beats_the_bound_and_the_matched_filter_reaches_it(receivers):
    bound = coherent_ber(CFG, np.array([6.0, 10.0]))
    sd = np.sqrt(bound * (1 - bound) / 100_000)  # SE under the bound: the most a lucky run could dip
    for res in receivers.values():
        assert np.all(res.ber >= bound - 4 * sd), res.receiver
    assert np.all(np.abs(receivers[("matched", 3)].ber - bound) < 4 * sd)
    # the impacting-filter receivers stay far short of it (≈ 10× the differential receiver's BER at 10 dB)
    for key in (("impacting", 3), ("impacting-assumed", 3)):
        assert receivers[key].ber[1] > 5 * receivers[("differential", 3)].ber[1]
        assert np.all(np.isnan(receivers[key].closed_form))


def test_differential_closed_form_is_dpsk_when_the_segments_match():
    """Stein's formula with equal SNRs on both segments (K = N − K, span 1) is binary DPSK's ½ e^{−γ}
    (Proakis, eq. 5.2-69), γ = (K/N) E_b/N_0; with an infinitely long reference it tends to the bound."""
    cfg = EBPSKConfig(N=4, K=2)
    e = np.array([0.0, 4.0, 8.0, 12.0])
    np.testing.assert_allclose(differential_ber(cfg, e, 1), 0.5 * np.exp(-0.5 * 10 ** (e / 10)), rtol=1e-9)
    np.testing.assert_allclose(differential_ber(CFG, 10.0, 99), coherent_ber(CFG, 10.0), rtol=0.05)
    with pytest.raises(ConfigError) as err:
        differential_ber(EBPSKConfig(theta=2.0), 10.0)
    assert err.value.field == "theta"
    assert np.isnan(closed_form_ber(EBPSKConfig(theta=2.0), Receiver(), 10.0))


def test_optimum_correlation_receiver_reaches_the_bound():
    """An independent check of σ(E_b/N_0), E_b and ρ: the correlation receiver on the raw waveform (the
    optimum for two known equal-energy signals) has BER Q(√((1 − ρ)E_b/N_0)) within 4 SE."""
    s = symbol_waveforms(CFG)
    d = s[1] - s[0]
    rng = np.random.default_rng(3)
    n = 100_000
    bits = rng.integers(0, 2, n)
    x = modulate(bits, CFG).reshape(n, -1)
    for eb in (2.0, 6.0, 8.0):
        y = x + noise_sigma(CFG, eb) * rng.standard_normal(x.shape)
        stat = y @ d - (s[1] @ s[1] - s[0] @ s[0]) / 2
        ber = np.mean((stat > 0) != (bits == 1))
        p = float(coherent_ber(CFG, eb))
        assert abs(ber - p) < 4 * math.sqrt(p * (1 - p) / n), (eb, ber, p)


def test_result_is_independent_of_chunking():
    kw = dict(cfg=CFG, ebn0_db=(8.0, 12.0), trials=6, bits_per_trial=300, seed=5, calibration_bits=2000)
    base = run_job(BerJob(**kw))
    assert run_job(BerJob(**kw, chunk=2), Engine(1)).errors.tolist() == base.errors.tolist()
    kw["receiver"] = ASSUMED
    base = run_job(BerJob(**kw))
    for chunk in (1, 4, 6):
        job = BerJob(**kw, chunk=chunk)
        assert len(job.tasks()) == math.ceil(6 / chunk)
        np.testing.assert_array_equal(run_job(job, Engine(1)).errors, base.errors)


def test_trial_streams_and_fixed_threshold():
    job = BerJob(CFG, (10.0,), trials=3, bits_per_trial=50, threshold=0.9, seed=2, receiver=ASSUMED)
    assert job.thresholds == (0.9,)
    # the task recomputes the bits of trial t from trial_rng(seed, t, 0)
    errors = job.run_task(range(0, 3))
    assert errors.shape == (1,) and 0 <= errors[0] <= 150
    again = sum(job.run_task(range(t, t + 1)) for t in range(3))
    np.testing.assert_array_equal(errors, again)
    assert trial_rng(2, 0, 0).integers(0, 2, 50, dtype=np.int8).shape == (50,)


def test_optimum_threshold():
    stat = np.array([0.1, 0.2, 0.3, 0.9, 1.0, 0.25])
    bits = np.array([0, 0, 0, 1, 1, 1])
    t = optimum_threshold(stat, bits)
    assert np.sum((stat > t) != (bits == 1)) == 1  # the best any threshold does here
    assert optimum_threshold(np.array([0.1, 0.2, 0.8, 0.9]), np.array([0, 0, 1, 1])) == pytest.approx(0.5)


@pytest.mark.parametrize(
    "kw, field",
    [
        ({"ebn0_db": ()}, "ebn0_db"),
        ({"ebn0_db": (float("nan"),)}, "ebn0_db"),
        ({"trials": 0}, "trials"),
        ({"bits_per_trial": 0}, "bits_per_trial"),
        ({"receiver": "differential"}, "receiver"),
        ({"threshold": 0.5}, "threshold"),
        ({"threshold": -1.0, "receiver": ASSUMED}, "threshold"),
        ({"trials": 10**7, "bits_per_trial": 1000}, "trials"),
    ],
)
def test_job_config_errors(kw, field):
    with pytest.raises(ConfigError) as e:
        BerJob(**{"calibration_bits": 100, **kw})
    assert e.value.field == field
