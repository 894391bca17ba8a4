"""The EBPSK radar function: the echo, the sample-level chain against its detector-output equivalent, the CRLB,
the location by weighted least squares, and the checks of the configuration.

Tolerances: detection counts within 4 binomial standard errors of the model's P_D (√(P_D(1 − P_D)/n), from the
model, so that a P_D of 1 observed 0 times is not an automatic failure); RMS range errors within 4 combined
standard errors (delta method from the sample's fourth moment, for the sample-level run and for the
calibration that the equivalent interpolates). Every check uses fixed seeds.
"""

import math
import time

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.engine import run_job
from motionsig_cli.maneuver.ebpsk_radar import (
    CAL_ENR_DB,
    EbpskRadar,
    EbpskRadarConfig,
    EbpskRadarJob,
    locate,
    rms_bandwidth,
)
from motionsig_cli.models.radar_equation import C_LIGHT, undb
from motionsig_cli.rng import trial_rng
from motionsig_cli.signals.ebpsk import modulate


@pytest.fixture(scope="module")
def radar():
    return EbpskRadar(EbpskRadarConfig())


@pytest.fixture(scope="module")
def equivalent(radar):
    return radar.equivalent(450.0)


@pytest.fixture(scope="module")
def result():
    # between and beside the calibration E/N₀, other seed: P_D from 10 % to 1, range errors near and far above
    # the detection threshold
    job = EbpskRadarJob(EbpskRadarConfig(), (16.0, 19.0, 21.0, 32.5, 45.0), 600, 99, radial_speed=450.0)
    return run_job(job)


def test_echo_is_the_modulated_pulse(radar):
    cfg = radar.cfg
    x = radar.echo(np.array([1.0]), np.array([0.0]), 0.0, 0.0, cfg.pulse_samples + 5)[0]
    np.testing.assert_allclose(x[: cfg.pulse_samples], modulate(np.array(cfg.bits), cfg.wave), atol=1e-9)
    assert np.all(x[cfg.pulse_samples :] == 0)
    # a fractional delay is the same analytic waveform sampled later
    y = radar.echo(np.array([2.0]), np.array([0.25]), 0.0, 0.0, 40)[0]
    t = (np.arange(40) - 0.25) / cfg.wave.fs
    want = 2.0 * np.sin(2 * np.pi * cfg.wave.f_if * t + np.pi * (t < 2 / cfg.wave.f_if))  # bit 1 first
    np.testing.assert_allclose(y[1:], want[1:], atol=1e-9)
    assert y[0] == 0.0


def test_pd_sample_level_equals_the_equivalent(result, equivalent):
    n = result.trials
    pd = equivalent.pd(undb(result.enr_db))
    np.testing.assert_allclose(pd, result.pd_model)
    assert 0.05 < pd[0] < 0.2 and 0.4 < pd[1] < 0.8  # the checks below are not all at P_D = 1
    se = np.sqrt(np.maximum(pd * (1 - pd), 1e-4 * (1 - 1e-4)) / n)
    assert np.all(np.abs(result.pd - pd) < 4 * se), (result.pd, pd)


def test_range_error_sample_level_equals_the_equivalent(result, equivalent):
    # from P_D ≈ 1 upwards (below, too few detections per E/N₀ for a test with power)
    enr = undb(result.enr_db)
    sig = equivalent.sigma_range(enr)
    cal = dict(zip(CAL_ENR_DB, equivalent.cal_sigma_r_se, strict=True))
    for i in (2, 3, 4):
        lo = max(g for g in CAL_ENR_DB if g <= result.enr_db[i])
        se = math.hypot(
            result.rms_r_se[i], 1.5 * cal[lo]
        )  # an interpolated value: allow its neighbours' error
        assert abs(result.rms_r[i] - sig[i]) < 4 * se, (result.enr_db[i], result.rms_r[i], sig[i], se)


def test_range_error_above_the_crlb(result, radar):
    # the estimator cannot beat the bound; the impacting filter keeps it far above (narrow band, no matched filter)
    assert np.all(result.rms_r > result.crlb_r)
    assert result.beta == pytest.approx(radar.beta)
    want = C_LIGHT / 2 / np.sqrt(8 * np.pi**2 * radar.beta**2 * undb(result.enr_db))
    np.testing.assert_allclose(result.crlb_r, want)


def test_chain_false_alarm_rate():
    # the CFAR of the chain holds its design P_FA on the filtered, integrated noise (one cell per pulse)
    cfg = EbpskRadarConfig(pfa=5e-2, bits=(1, 0, 1, 1))
    res = run_job(EbpskRadarJob(cfg, (30.0,), 2000, 5))
    n, p = res.trials[0], cfg.pfa
    assert abs(res.pfa[0] - p) < 4 * math.sqrt(p * (1 - p) / n), res.pfa


def test_rms_bandwidth_of_a_gaussian_pulse():
    # |S(f)|² of a Gaussian envelope exp(−t²/(2σ²)) is Gaussian with variance 1/(8π²σ²) about the carrier
    fs, sig = 1e9, 20e-9
    t = np.arange(-400, 401) / fs
    x = np.exp(-(t**2) / (2 * sig**2)) * np.cos(2 * np.pi * 100e6 * t)
    assert rms_bandwidth(x, fs) == pytest.approx(1 / (2 * math.sqrt(2) * math.pi * sig), rel=1e-3)
    assert rms_bandwidth(x, fs, centred=False) == pytest.approx(
        math.hypot(100e6, 1 / (2 * math.sqrt(2) * math.pi * sig)), rel=1e-3
    )


def test_equivalent_draws_and_speed(equivalent):
    cfg = equivalent.cfg
    # 500 runs x 450 scans of a receding target, ranges across the detection threshold
    ranges = np.linspace(5e3, 2e4, 450)
    bearings = np.linspace(-3.0, 3.0, 450)
    t0 = time.perf_counter()
    out = [equivalent.draw(trial_rng(3, r), ranges, bearings) for r in range(500)]
    assert time.perf_counter() - t0 < 10.0
    det = np.stack([o[0] for o in out])
    enr = cfg.energy_snr(ranges)
    pd = equivalent.pd(enr)
    assert 0.02 < pd.min() < 0.5 and pd.max() > 0.999
    # the detections of the scans where P_D < 1 (independent draws): their total within 4 SE
    mid = pd < 0.999
    k, want = det[:, mid].sum(), 500 * pd[mid].sum()
    assert abs(k - want) < 4 * math.sqrt(500 * np.sum(pd[mid] * (1 - pd[mid]))), (k, want)
    dr = np.stack([o[1] for o in out]) - ranges
    ok = det[:, :100]  # the near ranges: P_D ≈ 1
    z = dr[:, :100][ok] / np.broadcast_to(equivalent.sigma_range(enr[:100]), ok.shape)[ok]
    assert abs(z.std() - 1) < 4 / math.sqrt(2 * z.size)
    assert np.all(np.isnan(np.stack([o[2] for o in out])[~det]))


def test_locate_one_sensor_is_the_polar_conversion():
    r, phi = np.array([[1e4], [5e4]]), np.array([[0.3], [-2.0]])
    sig = np.array([0.5, 1e-3])
    s = np.array([[100.0, -200.0]])
    xy, cov = locate(r, phi, sig, s)
    want = s + r * np.hstack([np.cos(phi), np.sin(phi)])
    np.testing.assert_allclose(xy, want, rtol=1e-12)
    J = np.array([[np.cos(0.3), -1e4 * np.sin(0.3)], [np.sin(0.3), 1e4 * np.cos(0.3)]])
    np.testing.assert_allclose(cov[0], J @ np.diag(sig**2) @ J.T, rtol=1e-10)


def test_locate_two_sensors_monte_carlo():
    # a target seen by two sensors: the WLS estimate is unbiased to first order and its spread is the covariance
    rng = np.random.default_rng(11)
    sensors = np.array([[0.0, 0.0], [3e4, 0.0]])
    p = np.array([1.5e4, 2e4])
    d = p - sensors
    r0, phi0 = np.hypot(d[:, 0], d[:, 1]), np.arctan2(d[:, 1], d[:, 0])
    sig = np.array([[20.0, 2e-3], [30.0, 4e-3]])
    n = 20_000
    r = r0 + rng.standard_normal((n, 2)) * sig[:, 0]
    phi = phi0 + rng.standard_normal((n, 2)) * sig[:, 1]
    xy, cov = locate(r, phi, sig, sensors)
    err = xy - p
    c = np.cov(err.T)
    cbar = cov.mean(axis=0)
    # sample covariance entries within 4 SE (var of a sample variance: 2σ⁴/n)
    assert np.all(np.abs(np.diag(c) - np.diag(cbar)) < 4 * np.sqrt(2 / n) * np.diag(cbar))
    assert np.all(np.abs(err.mean(axis=0)) < 4 * np.sqrt(np.diag(cbar) / n))
    # the fused covariance is smaller than either sensor's own
    _, cov1 = locate(r[:, :1], phi[:, :1], sig[:1], sensors[:1])
    assert np.all(np.linalg.eigvalsh(cov1.mean(axis=0) - cbar) > 0)
    # a sensor without a detection gets no weight; none at all gives NaN
    r2 = r[:3].copy()
    r2[0, 1] = np.nan
    r2[1, :] = np.nan
    xy2, cov2 = locate(r2, phi[:3], sig, sensors)
    np.testing.assert_allclose(xy2[0], locate(r[:1, :1], phi[:1, :1], sig[:1], sensors[:1])[0][0], rtol=1e-9)
    assert np.all(np.isnan(xy2[1])) and np.all(np.isnan(cov2[1]))
    assert np.all(np.isfinite(xy2[2]))


def test_bad_configurations():
    cfg = EbpskRadarConfig()
    with pytest.raises(ConfigError) as exc:
        cfg.energy_snr(np.array([1e5, cfg.max_range * 1.01]))
    assert exc.value.field == "range" and "unambiguous" in str(exc.value)
    assert cfg.max_range == pytest.approx(C_LIGHT * 5e-3 / 2)
    for kwargs, field in (
        ({"bits": (0, 0, 0)}, "bits"), ({"bits": ()}, "bits"), ({"bits": (1, 2)}, "bits"),
        ({"pfa": 0.0}, "pfa"), ({"n_train": 5}, "n_train"), ({"pri": 1e-7}, "pri"),
        ({"bearing": "radar"}, "bearing"), ({"beamwidth": -0.1}, "beamwidth"), ({"k_m": 0.0}, "k_m"),
    ):  # fmt: skip
        with pytest.raises(ConfigError) as exc:
            EbpskRadarConfig(**kwargs)
        assert exc.value.field == field
    with pytest.raises(ConfigError) as exc:
        EbpskRadarJob(cfg, (-50.0,), 10, 1)
    assert exc.value.field == "enr_db"
    with pytest.raises(ConfigError) as exc:
        EbpskRadarJob(cfg, (10.0,), 0, 1)
    assert exc.value.field == "trials"


def test_bearing_models():
    cfg = EbpskRadarConfig()
    e = np.array([10.0, 1000.0])
    np.testing.assert_allclose(cfg.sigma_bearing_at(e), math.radians(2) / (1.6 * np.sqrt(2 * e)))
    np.testing.assert_allclose(
        EbpskRadarConfig(bearing="fixed", sigma_bearing=2e-3).sigma_bearing_at(e), 2e-3
    )
