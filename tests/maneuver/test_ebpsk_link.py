"""BER Monte Carlo of the EBPSK amplitude demodulator (motionsig_cli.maneuver.ebpsk_link).

Tolerances. A BER estimate from n bits has binomial SE √(p(1−p)/n); "within 4 SE" fails by chance with
probability < 10⁻⁴ per point. The coherent bound is checked two ways: an optimum correlation receiver
written here reaches it (within 4 SE: checks the noise scaling, E_b and ρ), and the impacting-filter
detector never beats it by more than 4 SE.
"""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.engine import Engine, run_job
from motionsig_cli.maneuver.ebpsk_link import BerJob, coherent_ber, noise_sigma, optimum_threshold
from motionsig_cli.rng import trial_rng
from motionsig_cli.signals.ebpsk import EBPSKConfig, modulate, symbol_waveforms

CFG = EBPSKConfig()
EBN0 = (6.0, 10.0, 14.0, 18.0)


@pytest.fixture(scope="module")
def result():
    return run_job(BerJob(CFG, EBN0, trials=20, bits_per_trial=1000, seed=11))


def test_ber_decreases_and_is_small_at_high_snr(result):
    ber, se = result.ber, result.se
    for i in range(len(EBN0) - 1):
        assert ber[i + 1] < ber[i] - 4 * math.hypot(se[i], se[i + 1])
    # measured (this seed, 20000 bits per point): 0.280, 0.126, 0.0173, 3.0e-4
    assert 0.2 < ber[0] < 0.4
    assert ber[-1] < 2e-3


def test_detector_never_beats_the_coherent_bound(result):
    bound = coherent_ber(CFG, np.array(EBN0))
    se = np.sqrt(bound * (1 - bound) / result.bits)  # SE under the bound: the most a lucky run could dip
    assert np.all(result.ber >= bound - 4 * se)
    # and it stays well short of it: ≈ 8 dB at a BER of 10⁻² (the simple detector is not optimal)
    assert result.ber[2] > 10 * bound[2]


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
    for chunk in (1, 4, 6):
        job = BerJob(**kw, chunk=chunk)
        assert len(job.tasks()) == math.ceil(6 / chunk)
        np.testing.assert_array_equal(run_job(job, Engine(1)).errors, base.errors)


def test_trial_streams_and_fixed_threshold():
    job = BerJob(CFG, (10.0,), trials=3, bits_per_trial=50, threshold=0.9, seed=2)
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
        ({"statistic": "mean"}, "statistic"),
        ({"threshold": -1.0}, "threshold"),
        ({"trials": 10**7, "bits_per_trial": 1000}, "trials"),
    ],
)
def test_job_config_errors(kw, field):
    with pytest.raises(ConfigError) as e:
        BerJob(**{"calibration_bits": 100, **kw})
    assert e.value.field == field
