"""The linearised fast path of the radar LMP detector: the exact case against the sigma-point bank (a
real oracle: a linear measurement with constant amplitudes, where the projection identity is exact), its
H0 filter against the bank's, the H0 moments against a Monte Carlo, agreement on a small radar run, and
refusals."""

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.lmp import RadarLMPConfig, _assemble, lmp_detect_radar
from motionsig_cli.detection.lmp_linearised import H_POSITION, lmp_detect_radar_linearised
from motionsig_cli.filters.kalman import MissingSamples
from motionsig_cli.filters.unscented import StructuredTransition, linear_measurement, ukf_bank_costs
from motionsig_cli.models.vehicle2d import (
    AMPLITUDE_ENTRIES_2D,
    Q0_2D,
    Q1_2D,
    Vehicle2D,
    anr_pair_variances,
    prior_mean_2d,
    transition_h0_2d,
    transition_h1_2d_base,
)
from motionsig_cli.modesig.lmp1d import table1_chips
from motionsig_cli.modesig.lmp2d import RadarRecordDetection, check_radar_method, simulate_trials_2d
from motionsig_cli.signals.signature import replica_bank

CHIPS = table1_chips()
VEH = Vehicle2D(R_range=anr_pair_variances(3)[0], R_bearing=anr_pair_variances(3)[1])
CONST = RadarLMPConfig(Q1=(*Q1_2D[:8], 0.0, 0.0))  # constant amplitudes: (★) exact on a linear measurement


def linear_bank(y, cfg, hz):
    """The sigma-point bank (ukf_bank_costs, the code of lmp_detect_radar) on the measurement y = (x, y) + v."""
    n = y.shape[1]
    meas = linear_measurement(H_POSITION, cfg.c_r * np.diag([VEH.R_range, VEH.R_bearing]))
    from motionsig_cli.detection.lmp import candidate_grid

    c = candidate_grid(3, 31, 20, cfg.as_grid)
    zc, zs, dc, ds = replica_bank(CHIPS, c.mode, c.tau, c.f_c, VEH.T, 20, n)
    g = VEH.T * (VEH.K[0] * np.concatenate([zc, zs]) + VEH.K[1] * np.concatenate([dc, ds]))
    c0 = ukf_bank_costs(StructuredTransition.constant(transition_h0_2d(VEH.T, VEH.K), n), np.diag(cfg.Q0), meas,
                        prior_mean_2d(VEH.start, False), np.eye(8), y, hz, cfg.sigma)  # fmt: skip
    tr1 = StructuredTransition(
        transition_h1_2d_base(VEH.T, VEH.K), AMPLITUDE_ENTRIES_2D, np.repeat(g[:, :, None], 2, 2)
    )
    c1 = ukf_bank_costs(
        tr1, np.diag(cfg.Q1), meas, prior_mean_2d(VEH.start, True), np.eye(10), y, hz, cfg.sigma
    )
    return _assemble(c, np.asarray(hz), c0, c1, cfg.include_logdet)


def position_records(n, trials, missing=()):
    sim, _ = simulate_trials_2d(VEH, CHIPS, 20, 1.0, n, 11, trials)
    rng = np.random.default_rng(5)
    y = sim["x"][:, :, [0, 2]] + np.sqrt([VEH.R_range, VEH.R_bearing]) * rng.standard_normal(
        (len(trials), n, 2)
    )
    for b, k in missing:
        y[b, k] = np.nan
    return y


@pytest.mark.parametrize("logdet", [False, True])
def test_projection_equals_the_bank_in_the_exact_case(logdet):
    """Oracle: with a linear measurement and Q_a = 0 the projection identity is exact, so Λ, J_cos, J_sin
    equal the bank's to rounding (measured ~2e-14; 1e-10 leaves room for BLAS differences)."""
    cfg = RadarLMPConfig(Q1=CONST.Q1, include_logdet=logdet)
    y = position_records(240, [0, 1])
    fast = lmp_detect_radar_linearised(y, CHIPS, VEH, 20, cfg, [120, 240], measurement="position")
    bank = linear_bank(y, cfg, [120, 240])
    for a, b in (
        (bank.Lambda, fast.Lambda),
        (bank.J_cos, fast.J_cos),
        (bank.J_sin, fast.J_sin),
        (bank.J0, fast.J0),
    ):
        assert np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(a))


def test_missing_samples_are_predict_only_steps_as_in_the_bank():
    """A NaN row skips the update in both; the exact case still agrees to rounding."""
    y = position_records(200, [0, 1], missing=[(0, 30), (0, 31), (1, 150)])
    fast = lmp_detect_radar_linearised(y, CHIPS, VEH, 20, CONST, [100, 200], measurement="position")
    bank = linear_bank(y, CONST, [100, 200])
    assert np.max(np.abs(bank.Lambda - fast.Lambda)) <= 1e-10 * np.max(np.abs(bank.Lambda))
    y[1, 10, 0] = np.nan  # half a sample: refused like the bank
    with pytest.raises(MissingSamples):
        lmp_detect_radar_linearised(y, CHIPS, VEH, 20, CONST, [200], measurement="position")


def test_h0_filter_is_the_banks_on_radar_records():
    """The H0 sigma-point filter of the fast path is the bank's (the same transform): J_H0 to 1e-10."""
    sim, _ = simulate_trials_2d(VEH, CHIPS, 20, 1.0, 150, 3, [0, 1])
    cfg = RadarLMPConfig()
    fast = lmp_detect_radar_linearised(sim["y"], CHIPS, VEH, 20, cfg, [150])
    bank = lmp_detect_radar(sim["y"], CHIPS, VEH, 20, cfg, [150])
    assert np.max(np.abs(fast.J0 - bank.J0)) <= 1e-10 * np.max(np.abs(bank.J0))


def test_argmax_agrees_with_the_bank_on_a_small_radar_run():
    """Seed 2008, ANR pair 2, 6 trials, horizons 10 and 20 s: where the bank is right, the fast path's argmax
    equals the bank's. Tolerance: at most 1 of the bank's right pairs may differ (the Fig 7 benchmark measured
    281 of 283 equal, 0.7 % different: 1 of ~10 pairs is the expected count's upper range)."""
    veh = Vehicle2D(R_range=anr_pair_variances(2)[0], R_bearing=anr_pair_variances(2)[1])
    sim, draws = simulate_trials_2d(veh, CHIPS, 20, 1.0, 400, 2008, range(6))
    cfg = RadarLMPConfig()
    bank = lmp_detect_radar(sim["y"], CHIPS, veh, 20, cfg, [200, 400])
    fast = lmp_detect_radar_linearised(sim["y"], CHIPS, veh, 20, cfg, [200, 400])
    c, bb, bf = bank.candidates, bank.best()[0], fast.best()[0]
    right = (c.mode[bb] == np.array([d.mode for d in draws])[:, None]) & (
        c.tau[bb] == np.array([d.tau for d in draws])[:, None]
    )
    assert right.sum() >= 6
    assert int((bb != bf)[right].sum()) <= 1


def test_h0_mean_of_the_statistic_matches_a_monte_carlo():
    """Oracle: E[G(c) | H0] of the derivation (white measurement noise of the true variance, no process
    noise) against the mean over 300 noise-only records of the exact (linear) case. The noise-free H0 truth
    that starts at the prior mean stays there (F0 x0 = x0), so a record is (70, -20) + noise. With Q^H1[:8] =
    Q^H0 the base filter is the H0 filter and Λ = G_cos + G_sin. Tolerance 4 SE of the sample mean, for the
    candidates 0, 40 and 92; the predicted mean is the same for every record (a linear model's gains)."""
    n, B = 120, 300
    rng = np.random.default_rng(9)
    y = np.array(VEH.start) + np.sqrt([VEH.R_range, VEH.R_bearing]) * rng.standard_normal((B, n, 2))
    cfg = RadarLMPConfig(Q1=(*Q0_2D, 0.0, 0.0))
    plain = lmp_detect_radar_linearised(y, CHIPS, VEH, 20, cfg, [n], measurement="position")
    cent = lmp_detect_radar_linearised(y, CHIPS, VEH, 20, cfg, [n], measurement="position", center="h0-noise")
    std = lmp_detect_radar_linearised(
        y, CHIPS, VEH, 20, cfg, [n], measurement="position", center="standardised"
    )
    mean_pred = plain.Lambda - cent.Lambda  # E[G_cos + G_sin], (C, B, 1)
    for c in (0, 40, 92):
        g = plain.Lambda[c, :, 0]
        assert abs(g.mean() - mean_pred[c, 0, 0]) <= 4 * g.std(ddof=1) / np.sqrt(B)
        assert np.ptp(mean_pred[c, :, 0]) <= 1e-9 * abs(mean_pred[c, 0, 0])
        z = std.Lambda[c, :, 0]  # the z-score: mean 0, variance 1 (a chi-square-like law: 4 SE of its mean)
        assert abs(z.mean()) <= 4 / np.sqrt(B)
        assert 0.75 <= z.std(ddof=1) <= 1.3  # SE of a sample sd of a skewed law at B = 300: ~0.08


def test_refusals():
    with pytest.raises(ConfigError, match="center"):
        check_radar_method("bank", "h0-noise")
    with pytest.raises(ConfigError, match="method"):
        check_radar_method("fft", "none")
    with pytest.raises(ConfigError, match="center"):
        lmp_detect_radar_linearised(np.ones((1, 10, 2)), CHIPS, VEH, 20, CONST, [10], center="bias")
    with pytest.raises(ValueError, match="range and bearing"):
        lmp_detect_radar_linearised(np.ones((1, 10, 3)), CHIPS, VEH, 20, CONST, [10])
    with pytest.raises(ValueError, match="noise"):
        lmp_detect_radar_linearised(np.ones((2, 10, 2)), CHIPS, VEH, 20, CONST, [10], noise=np.ones((1, 2)))
    assert RadarRecordDetection.__dataclass_fields__["method"].default == "bank"


@pytest.mark.parametrize(
    ("tau_grid", "zdot", "n"),
    [("chips", "analytic", 1600), ("chips", "finite-difference", 300), ("samples", "analytic", 130)],
)
def test_replica_basis_reproduces_the_replicas(tau_grid, zdot, n):
    """The basis of unit-chip replicas (a linear decomposition of replica_bank's output in the chip values)
    gives back every candidate's a-column g = T(k1 z + k2 ż): exactly for the analytic ż (one ±1 term per
    sample), to rounding for the finite difference (two terms). On the chip grid there are 31 basis replicas
    per carrier (1600 samples reach every chip slot, 300 samples 15 slots)."""
    from motionsig_cli.detection.lmp import candidate_grid
    from motionsig_cli.detection.lmp_linearised import replica_basis

    cfg = RadarLMPConfig(tau_grid=tau_grid, zdot=zdot)
    c = candidate_grid(3, 31, 20, cfg.as_grid)
    basis = replica_basis(CHIPS, c, VEH.T, VEH.K, 20, n, zdot)
    zc, zs, dc, ds = replica_bank(CHIPS, c.mode, c.tau, c.f_c, VEH.T, 20, n, zdot)
    for z, d, b in ((zc, dc, basis.cos), (zs, ds, basis.sin)):
        g = VEH.T * (VEH.K[0] * z + VEH.K[1] * d)
        err = np.max(np.abs(basis.S @ b - g)) / np.max(np.abs(g))
        assert err == 0.0 if zdot == "analytic" else err < 1e-14
    if tau_grid == "chips":  # the finite difference also reads the slot of sample -1 (the last chip)
        reached = -(-n // 20) + (zdot == "finite-difference")
        assert basis.S.shape == (93, 31 if n >= 620 else reached)
    assert basis.S.shape[1] < len(c.tau)  # fewer columns than candidates (a third on these grids)


def test_fig7_grid_agrees_with_the_bank_on_one_trial_per_pair():
    """The Fig 7 configuration (every ANR pair in one call, per-record noise): the projection's Λ on radar
    records tracks the bank's (not equal: the linearisation of the module docstring), and J_H0 is the bank's
    H0 filter to 1e-10 on each pair's record (several noise levels in one call must not mix)."""
    pairs = [anr_pair_variances(p) for p in (1, 2, 3, 4)]
    ys, j0 = [], []
    for a, b in pairs:
        veh = Vehicle2D(R_range=a, R_bearing=b)
        sim, _ = simulate_trials_2d(veh, CHIPS, 20, 1.0, 120, 4, [0])
        ys.append(sim["y"])
        j0.append(lmp_detect_radar(sim["y"], CHIPS, veh, 20, RadarLMPConfig(), [120]).J0)
    fast = lmp_detect_radar_linearised(
        np.concatenate(ys), CHIPS, VEH, 20, RadarLMPConfig(), [120], noise=np.asarray(pairs)
    )
    bank_j0 = np.concatenate(j0)
    assert np.max(np.abs(fast.J0 - bank_j0)) <= 1e-10 * np.max(np.abs(bank_j0))
