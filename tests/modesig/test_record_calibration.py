"""A threshold on max Λ calibrated for ONE record (RecordNullJob): its false-alarm rate on independent
no-signature records, its independence of the chunking, and its checks.

The independent H0 records are simulated here, from the paper's equations (eqs 53–55: the closed loop
driven by the nominal reference, no signature) with numpy only, not by the package's simulator.

Tolerance of the false-alarm test: the threshold leaves k = ⌊pfa n⌋ of n null maxima above it, so a new
record exceeds it with probability U ~ Beta(k + 1, n − k) (mean (k+1)/(n+1) ≈ pfa, variance ≈ pfa(1−pfa)/n);
the fraction over M independent records adds binomial variance pfa(1−pfa)/M. The test allows 4 standard
errors of the sum, √(pfa(1−pfa)(1/n + 1/M)) (a false failure ~6e-5 per check).
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.lmp import LMPConfig, RadarLMPConfig, lmp_detect
from motionsig_cli.detection.lmp_fft import lmp_detect_fft
from motionsig_cli.engine import Budget, Engine, budget, run_job
from motionsig_cli.filters.unscented import SigmaPointParams
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.models.vehicle2d import Vehicle2D
from motionsig_cli.modesig.lmp1d import simulate_trials
from motionsig_cli.modesig.record_calibration import HOW, RecordNullJob, RecordThreshold
from motionsig_cli.modesig.record_reading import VehicleRecord

CHIPS = np.where(np.random.default_rng(0).random((3, 7)) < 0.5, -1.0, 1.0)  # 3 modes of 7 chips (assumed)
M_RHO, N = 4, 120  # 21 candidates; records of 6 s at T = 0.05 s
VEH = Vehicle1D(R=1e-2)
HORIZONS = (3.0, 6.0)


def _record(y: np.ndarray, vehicle=VEH) -> VehicleRecord:
    return VehicleRecord(
        times=np.arange(y.shape[0]) * vehicle.T, y=y, vehicle=vehicle, chips=CHIPS, m_rho=M_RHO, f_c=1.0,
        truth=None, meta={}, source="rec.csv",
    )  # fmt: skip


def _h0_records(veh: Vehicle1D, B: int, n: int, seed: int) -> np.ndarray:
    """Eqs (53)–(55) without a signature: x_{k+1} = A x + b u + [T²/2, T] σ_a w, u = K(r − x), y = x + √R v."""
    rng = np.random.default_rng(seed)
    T, (k1, k2) = veh.T, veh.K
    w, v = rng.standard_normal((B, n)), rng.standard_normal((B, n))
    t = np.arange(n) * T
    om = 2 * math.pi * veh.f_r
    r_pos, r_vel = veh.a_r * np.sin(om * t), om * veh.a_r * np.cos(om * t)
    pos, vel, out = np.zeros(B), np.zeros(B), np.empty((B, n))
    for k in range(n):
        out[:, k] = pos
        u = k1 * (r_pos[k] - pos) + k2 * (r_vel[k] - vel)
        acc = veh.sigma_a * w[:, k]
        pos, vel = pos + T * vel + 0.5 * T**2 * acc, vel + T * u + T * acc
    return out + math.sqrt(veh.R) * v


def _gaps(n: int, seed: int, frac: float = 0.1) -> np.ndarray:
    miss = np.random.default_rng(seed).random(n) < frac
    miss[40:45] = True
    return miss


def _check_rate(thr: RecordThreshold, lam_max: np.ndarray) -> None:
    M = lam_max.shape[0]
    se = math.sqrt(thr.pfa * (1 - thr.pfa) * (1 / thr.null_trials + 1 / M))
    rate = np.mean(lam_max > thr.thresholds[None, :], axis=0)
    assert np.all(np.abs(rate - thr.pfa) < 4 * se), (rate, thr.pfa, se)


def test_fft_threshold_holds_its_false_alarm_rate_on_independent_h0_records():
    """FFT path, no missing sample: P_FA = 0.05 from 2000 null records; 4000 independent H0 records."""
    cfg = LMPConfig(Q_a=0.0)
    rec = _record(_h0_records(VEH, 1, N, 1)[0])
    thr = run_job(RecordNullJob(rec, cfg, "fft", horizons=HORIZONS, pfa=0.05, null_trials=2000, seed=3))
    assert thr.null_trials == 2000 and thr.thresholds.shape == (2,) and np.all(np.diff(thr.thresholds) > 0)
    assert np.all(thr.false_alarms <= math.floor(0.05 * 2000))
    lam = lmp_detect_fft(_h0_records(VEH, 4000, N, 2), CHIPS, VEH, M_RHO, cfg, [60, 120]).best()[1]
    _check_rate(thr, lam)
    # the check can fail: H0 records of another model (R 1.5 times the record's) exceed it ~22 % of the time
    other = lmp_detect_fft(_h0_records(replace(VEH, R=1.5e-2), 4000, N, 2), CHIPS, VEH, M_RHO, cfg, [60, 120])
    with pytest.raises(AssertionError):
        _check_rate(thr, other.best()[1])


def test_bank_threshold_with_missing_samples_holds_its_false_alarm_rate():
    """Kalman bank, 10 % of the samples missing (and a gap of 5): the null records carry the record's gaps;
    P_FA = 0.1 from 1000 null records, 3000 independent H0 records with the same gaps."""
    cfg = LMPConfig()
    miss = _gaps(N, 4)
    y = _h0_records(VEH, 1, N, 5)[0]
    y[miss] = np.nan
    job = RecordNullJob(_record(y), cfg, "bank", horizons=HORIZONS, pfa=0.1, null_trials=1000, seed=6)
    assert np.array_equal(np.isnan(job.simulate(range(3))), np.broadcast_to(miss, (3, N)))
    thr = run_job(job)
    h0 = _h0_records(VEH, 3000, N, 7)
    h0[:, miss] = np.nan
    _check_rate(thr, lmp_detect(h0, CHIPS, VEH, M_RHO, cfg, [60, 120]).best()[1])


def test_a_record_with_a_strong_signature_exceeds_its_threshold():
    """Power: a record with the signature at ANR a²/(2R) = 125 (21 dB; R = 1e-3, a_sig = 0.5) is declared
    present, far above its threshold."""
    veh = Vehicle1D(R=1e-3)
    y, _ = simulate_trials(veh, CHIPS, M_RHO, 1.0, N, 11, [0], signature=True)
    rec = _record(y[0], veh)
    thr = run_job(RecordNullJob(rec, LMPConfig(), horizons=(6.0,), pfa=0.05, null_trials=200, seed=1))
    lam = lmp_detect(y, CHIPS, veh, M_RHO, LMPConfig(), [120]).best()[1][0]
    assert thr.decide(lam)[0] and lam[0] > 3 * thr.thresholds[0]


def test_thresholds_do_not_depend_on_chunking_or_workers(many_tasks):
    """Bit-identical null maxima for several chunkings and for 2 worker processes (blocks fix the batches)."""
    y = _h0_records(VEH, 1, N, 8)[0]
    y[_gaps(N, 9)] = np.nan
    ukf = dict(filter="ukf", sigma=SigmaPointParams(), horizons=HORIZONS, pfa=0.2, null_trials=40, seed=4)
    a, b, c = (run_job(RecordNullJob(_record(y), LMPConfig(), chunk=k, **ukf)) for k in (None, 16, 40))
    assert len(RecordNullJob(_record(y), LMPConfig(), chunk=16, **ukf).tasks()) == 3
    for other in (b, c):
        assert np.array_equal(a.null_max, other.null_max) and np.array_equal(a.thresholds, other.thresholds)
    kf = dict(horizons=HORIZONS, pfa=0.2, null_trials=600, seed=4)
    d, e = (run_job(RecordNullJob(_record(y), LMPConfig(), chunk=k, **kf)) for k in (256, 600))
    assert np.array_equal(d.null_max, e.null_max)
    job = RecordNullJob(
        _record(np.zeros(60)), LMPConfig(Q_a=0.0), "fft", horizons=(3.0,), pfa=0.2, null_trials=600
    )
    one, two = run_job(job), run_job(job, Engine(workers=2))
    assert len(job.tasks()) == 3 and np.array_equal(one.null_max, two.null_max)


def test_radar_record_with_missing_rows():
    """A radar record: the sigma-point bank, NaN rows kept in the null records, finite thresholds."""
    veh = Vehicle2D()
    y = np.ones((60, 2))
    y[[0, 13, 14, 40]] = np.nan
    job = RecordNullJob(_record(y, veh), RadarLMPConfig(), horizons=(3.0,), pfa=0.2, null_trials=20, seed=2)
    sim = job.simulate(range(2))
    assert sim.shape == (2, 60, 2) and np.array_equal(np.isnan(sim[..., 0]), np.isnan(sim[..., 1]))
    assert np.array_equal(np.flatnonzero(np.isnan(sim[0, :, 0])), [0, 13, 14, 40])
    thr = run_job(job)
    assert thr.filter == "ukf" and np.isfinite(thr.thresholds).all() and thr.null_max.shape == (20, 1)


def test_meta_and_warning():
    y = _h0_records(VEH, 1, N, 1)[0]
    thr = run_job(
        RecordNullJob(_record(y), LMPConfig(Q_a=0.0), "fft", horizons=HORIZONS, pfa=0.01, null_trials=50)
    )
    meta = thr.meta()
    assert (
        meta["how"]
        == HOW
        == "null records simulated from the record's model, same length and missing samples"
    )
    assert meta["pfa"] == 0.01 and meta["null_trials"] == 50 and meta["method"] == "fft"
    assert meta["thresholds"] == [float(t) for t in thr.thresholds] and meta["horizons_s"] == list(HORIZONS)
    assert thr.warning is not None and "1/P_FA" in thr.warning  # 50 < 100 = 1/pfa
    assert RecordNullJob(_record(y), LMPConfig(), pfa=0.01).null_trials == 2000  # ⌈20 / pfa⌉
    again = run_job(
        RecordNullJob(_record(y), LMPConfig(Q_a=0.0), "fft", horizons=HORIZONS, pfa=0.01, null_trials=50)
    )
    assert np.array_equal(again.null_max, thr.null_max)  # deterministic


def _job(**kw):
    y = kw.pop("y", np.zeros(N))
    veh = kw.pop("vehicle", VEH)
    return RecordNullJob(_record(y, veh), kw.pop("cfg", LMPConfig()), **kw)


GAPPY = np.where(np.arange(N) == 7, np.nan, 0.0)


@pytest.mark.parametrize(
    ("kw", "field", "words"),
    [
        (dict(pfa=0.0), "pfa", "not in"),
        (dict(pfa=1.0), "pfa", "not in"),
        (dict(pfa=1e-7), "pfa", "null records by default"),
        (dict(null_trials=0), "null_trials", "not in"),
        (dict(null_trials=2_000_000, y=np.zeros(4000)), "null_trials", "on one core; the limit is 10 min"),
        (dict(seed=-1), "seed", "not in"),
        (dict(chunk=0), "chunk", "not in"),
        (dict(filter="pf"), "filter", "not one of"),
        (dict(method="grid"), "method", "not one of"),
        (dict(method="fft"), "method", "Q_a = 0"),
        (
            dict(method="fft", cfg=LMPConfig(Q_a=0.0), y=GAPPY),
            "method",
            "cannot skip a missing sample (sample 7",
        ),
        (dict(method="fft", cfg=LMPConfig(Q_a=0.0), filter="ukf"), "method", "sigma-point"),
        (dict(filter="ukf", cfg=LMPConfig(center="h0-noise")), "filter", "center none"),
        (dict(filter="ukf", sigma=SigmaPointParams(kappa=-4.5)), "kappa", "<= 0"),
        (dict(horizons=(7.0,)), "horizons", "longer than the record"),
        (dict(cfg=RadarLMPConfig()), "cfg", "not an LMPConfig"),
        (dict(vehicle=Vehicle2D(), y=np.zeros((N, 2))), "cfg", "not a RadarLMPConfig"),
        (
            dict(vehicle=Vehicle2D(), y=np.zeros((N, 2)), cfg=RadarLMPConfig(), method="fft"),
            "method",
            "one of",
        ),
        (dict(y=np.zeros((N, 2))), "record", "array of measurements"),
        (
            dict(vehicle=Vehicle2D(), y=np.zeros((N, 2)), cfg=RadarLMPConfig(), pfa=1e-4),
            "null_trials",
            "on one core; the limit is 10 min",
        ),
    ],
)
def test_fields_are_checked_naming_the_field(kw, field, words):
    with pytest.raises(ConfigError) as err:
        _job(**kw)
    assert err.value.field == field and words in str(err.value), str(err.value)


def test_cost_refusal_states_the_estimate():
    refused = r"would take an estimated [\d.]+ (min|h) on one core; the limit is 10 min"
    with pytest.raises(ConfigError, match=refused):
        _job(null_trials=2_000_000, y=np.zeros(4000))  # ~1.9 h: 4000 samples x 43 filters x 2e-8 s x 2e6
    with budget(Budget(max_minutes=600.0)):  # --max-minutes raises the limit
        _job(null_trials=2_000_000, y=np.zeros(4000))
    with budget(Budget(checkpoint=True)):  # with a checkpoint there is no time limit
        _job(null_trials=2_000_000, y=np.zeros(4000))
    with budget(Budget(workers=4)), pytest.raises(ConfigError, match=r"on one core, \d+ min on 4 workers"):
        _job(null_trials=2_000_000, y=np.zeros(4000))  # ≥ 29 min on 4 workers: still over 10 min
    job = _job(pfa=0.01)
    assert 0 < job.estimate_seconds() < 60
