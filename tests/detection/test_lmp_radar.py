"""The LMP detector with the sigma-point bank: the bank's model against the oracle UKF, the KF = UKF
cross-check on the linear example, and Fig 7's targets at fixed seeds."""

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.lmp import LMPConfig, RadarLMPConfig, lmp_detect, lmp_detect_radar
from motionsig_cli.engine import run_job
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.models.vehicle2d import Q0_2D, Q1_2D, Vehicle2D, anr_pair_variances, prior_mean_2d
from motionsig_cli.modesig.lmp1d import simulate_trials
from motionsig_cli.modesig.lmp2d import RadarLmpJob, simulate_trials_2d
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import table1_codes
from motionsig_cli.signals.signature import replica_bank
from tests.filters import ukf_oracle as O

CHIPS = to_bipolar(table1_codes("corrected")).astype(float)


@pytest.mark.parametrize("logdet", [False, True])
def test_ukf_bank_reproduces_the_kf_bank_on_the_linear_example(logdet):
    """Target: the sigma-point bank on a linear measurement reproduces the KF bank's statistics to
    1e-8 (the UT is exact for linear maps; the paths share nothing but the model)."""
    veh = Vehicle1D(R=1e-3)
    y, _ = simulate_trials(veh, CHIPS, 20, 1.0, 400, 5, [0, 1])
    cfg = LMPConfig(include_logdet=logdet)
    kf = lmp_detect(y, CHIPS, veh, 20, cfg, [150, 400])
    ukf = lmp_detect(y, CHIPS, veh, 20, cfg, [150, 400], filter="ukf")
    for a, b in ((kf.J0, ukf.J0), (kf.J_cos, ukf.J_cos), (kf.J_sin, ukf.J_sin), (kf.Lambda, ukf.Lambda)):
        assert np.max(np.abs(a - b)) <= 1e-8 * np.max(np.abs(a))
    assert np.array_equal(kf.best()[0], ukf.best()[0])
    with pytest.raises(ValueError, match="center"):
        lmp_detect(y, CHIPS, veh, 20, LMPConfig(center="h0-noise"), [400], filter="ukf")


def test_radar_statistic_equals_the_oracle_filters():
    """J_H0 and J of two H1 candidates from lmp_detect_radar equal the oracle UKF run on matrices built
    independently from the paper's equations (8-state eq 61 and 10-state eq 62 models)."""
    veh = Vehicle2D(R_range=3e-4, R_bearing=5e-3)
    N = 120
    sim, _ = simulate_trials_2d(veh, CHIPS, 20, 1.0, N, 3, [0])
    cfg = RadarLMPConfig(c_r=3.0)
    res = lmp_detect_radar(sim["y"], CHIPS, veh, 20, cfg, [N])
    R = cfg.c_r * np.diag([veh.R_range, veh.R_bearing])
    k1, k2 = veh.K
    o0 = O.ukf_run(
        O.transition_2d(veh.T, k1, k2), np.diag(Q0_2D), O.range_bearing, R,
        prior_mean_2d(veh.start, False), np.eye(8), sim["y"][0], angular=(False, True),
    )  # fmt: skip
    assert res.J0[0, 0] == pytest.approx(o0["J"][-1], rel=1e-9)
    c = res.candidates
    for idx in (5, 70):
        zc, zs, dc, ds = replica_bank(CHIPS, c.mode[[idx]], c.tau[[idx]], c.f_c[[idx]], veh.T, 20, N)
        for z, zd, J in ((zc, dc, res.J_cos), (zs, ds, res.J_sin)):
            g = veh.T * (k1 * z[0] + k2 * zd[0])
            Fs = [O.transition_2d(veh.T, k1, k2, (g[k], g[k])) for k in range(N)]
            o = O.ukf_run(
                Fs, np.diag(Q1_2D), O.range_bearing, R, prior_mean_2d(veh.start, True), np.eye(10),
                sim["y"][0], angular=(False, True),
            )  # fmt: skip
            assert J[idx, 0, 0] == pytest.approx(o["J"][-1], rel=1e-9)
    assert res.Lambda[5, 0, 0] == pytest.approx(2 * res.J0[0, 0] - res.J_cos[5, 0, 0] - res.J_sin[5, 0, 0])


def test_fig7_best_pair_and_fall_with_anr():
    """Targets at seed 2008, 20 trials, horizon 40 s: at the best ANR pair the true (i, τ) wins in
    ≥ 90 % of trials (expected ~100 %; 18/20 leaves a binomial margin), and at the worst pair the rate is at
    least 30 points lower (measured ~0 % with c_r = 100)."""
    pairs = [anr_pair_variances(1), anr_pair_variances(4)]
    job = RadarLmpJob(
        RadarLMPConfig(), [0.01], pairs=pairs, horizons_s=[40.0], trials=20, seed=2008, chunk=10
    )
    worst, best = run_job(job).cells
    assert best.pct >= 90.0
    assert best.pct >= worst.pct + 30.0
    assert best.repairs == worst.repairs == 0


def test_monte_carlo_does_not_depend_on_chunking():
    args = dict(anr_pairs=(2,), horizons_s=(3.0, 6.0), trials=4, seed=77)
    one, four = (run_job(RadarLmpJob(**args, chunk=c)).cells for c in (1, 4))
    assert one == four
    assert [c.pair for c in one] == [1, 1] and one[0].R_range == anr_pair_variances(2)[0]


def test_radar_config_and_record_validation():
    with pytest.raises(ConfigError, match=r"Q0 = .* is not 8 variances"):
        RadarLMPConfig(Q0=(1.0,) * 4)
    with pytest.raises(ConfigError, match="c_r"):
        RadarLMPConfig(c_r=0.0)
    y = np.ones((1, 10, 2))
    y[0, 4, 0] = np.inf
    with pytest.raises(ValueError, match="contain inf"):  # NaN is a missing sample; inf is refused
        lmp_detect_radar(y, CHIPS, Vehicle2D(), 20, RadarLMPConfig(), [10])
    with pytest.raises(ValueError, match="range and bearing"):
        lmp_detect_radar(np.ones((1, 10, 3)), CHIPS, Vehicle2D(), 20, RadarLMPConfig(), [10])
