"""The estimate-then-correlate baseline: its filters against independent implementations (a plain Kalman
loop written here; the slow sigma-point oracle of tests/filters/ukf_oracle.py), its correlation against a
direct sum, and the correlation identity for a perfect estimate."""

from __future__ import annotations

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.estimate_correlate import (
    ECConfig,
    RadarECConfig,
    command_replicas,
    correlate,
    detrend_window,
    detrended,
    estimate_correlate_detect,
    estimate_correlate_detect_radar,
)
from motionsig_cli.detection.lmp import candidate_grid
from motionsig_cli.models.vehicle import Q0_DIAG, Vehicle1D
from motionsig_cli.models.vehicle2d import Q0_2D, Vehicle2D
from motionsig_cli.modesig.lmp1d import simulate_trials, table1_chips
from motionsig_cli.modesig.lmp2d import simulate_trials_2d
from tests.filters import ukf_oracle

CHIPS = table1_chips()


def _plain_kf_estimates(y: np.ndarray, veh: Vehicle1D, c_r: float, q_e: float, var_e: float) -> np.ndarray:
    """k1 r̂ + k2 ṙ̂ + ê after each update: a textbook Kalman filter, one record, written out here."""
    T, (k1, k2) = veh.T, veh.K
    F = np.array(
        [
            [1, T, 0, 0, 0],
            [-T * k1, 1 - T * k2, T * k1, T * k2, T],
            [0, 0, 1, T, 0],
            [0, 0, 0, 1, 0],
            [0, 0, 0, 0, 1],
        ],
        float,
    )
    Q = np.diag([*Q0_DIAG, q_e])
    x, P = np.zeros(5), np.diag([1.0, 1.0, 1.0, 1.0, var_e])
    out = []
    for yk in y:
        S = P[0, 0] + c_r * veh.R
        K = P[:, 0] / S
        x = x + K * (yk - x[0])
        P = P - np.outer(K, K) * S
        out.append(k1 * x[2] + k2 * x[3] + x[4])
        x, P = F @ x, F @ P @ F.T + Q
    return np.array(out)


def test_1d_estimate_equals_a_plain_kalman_filter() -> None:
    veh = Vehicle1D(R=1e-3)
    y, _ = simulate_trials(veh, CHIPS, 20, 1.0, 300, 3, [0, 1, 2])
    res = estimate_correlate_detect(y, CHIPS, veh, 20, ECConfig(), [100, 300])
    g = command_replicas(
        CHIPS, candidate_grid(3, 31, 20, ECConfig().as_grid), veh.K, veh.T, 20, 300, "analytic"
    )
    var_e = 0.25 * 0.5 * (np.mean(g[0] ** 2) + np.mean(g[1] ** 2))
    for b in range(3):
        ref = _plain_kf_estimates(y[b], veh, 100.0, res.q_e, var_e)
        np.testing.assert_allclose(res.estimate[b], ref, rtol=1e-8, atol=1e-8 * np.abs(ref).max())


def test_correlation_equals_the_direct_sum() -> None:
    rng = np.random.default_rng(0)
    est = rng.standard_normal((2, 50, 2))
    gc, gs = rng.standard_normal((3, 50)), rng.standard_normal((3, 50))
    hz = np.array([10, 50])
    lam = correlate(est, gc, gs, hz, 2)
    for c in range(3):
        for b in range(2):
            for j, n in enumerate(hz):
                m = n - 2
                num = sum(
                    sum(est[b, k + 2, a] * gc[c, k] for k in range(m)) ** 2
                    + sum(est[b, k + 2, a] * gs[c, k] for k in range(m)) ** 2
                    for a in range(2)
                )
                E = sum(0.5 * (gc[c, k] ** 2 + gs[c, k] ** 2) for k in range(m))
                assert lam[c, b, j] == pytest.approx(num / E, rel=1e-10)


def test_a_perfect_estimate_picks_the_true_candidate() -> None:
    """With ê = e exactly (e = a (cos θ g_cos − sin θ g_sin), eqs 2–3 through eq 54) the true candidate
    maximises Λ_b, at ≈ a² E_c (the quadratures' cross term and energy difference are small over whole
    code periods)."""
    veh = Vehicle1D()
    N, lag, a = 31 * 20 * 2, 1, 0.5
    cands = candidate_grid(3, 31, 20, ECConfig().as_grid)
    gc, gs = command_replicas(CHIPS, cands, veh.K, veh.T, 20, N + lag, "analytic")
    rng = np.random.default_rng(1)
    for c_true in rng.choice(len(cands), 6, replace=False):
        th = rng.uniform(0, 2 * np.pi)
        e = a * (np.cos(th) * gc[c_true] - np.sin(th) * gs[c_true])
        est = np.concatenate([np.zeros(lag), e[:N]])[None]  # ê_{k+lag} = e_k
        lam = correlate(est, gc[:, :N], gs[:, :N], np.array([N]), lag)[:, 0, 0]
        assert np.argmax(lam) == c_true
        E = 0.5 * np.sum(gc[c_true, : N - lag] ** 2 + gs[c_true, : N - lag] ** 2)
        assert lam[c_true] == pytest.approx(a**2 * E, rel=0.1)


def test_radar_filter_equals_the_sigma_point_oracle() -> None:
    veh = Vehicle2D()
    N = 24
    sim, _ = simulate_trials_2d(veh, CHIPS, 20, 1.0, N, 5, [0, 1])
    cfg = RadarECConfig()
    res = estimate_correlate_detect_radar(sim["y"], CHIPS, veh, 20, cfg, [N])
    T, (k1, k2) = veh.T, veh.K
    F = ukf_oracle.transition_2d(T, k1, k2, g=(T, T))  # a_x, a_y: the perturbations, T e in the ẋ, ẏ rows
    g = command_replicas(CHIPS, candidate_grid(3, 31, 20, cfg.as_grid), veh.K, T, 20, N, "analytic")
    var_e = 0.25 * 0.5 * (np.mean(g[0] ** 2) + np.mean(g[1] ** 2))
    Q = np.diag([*Q0_2D, res.q_e, res.q_e])
    P0 = np.diag([1.0] * 8 + [var_e, var_e])
    x0 = np.array([70.0, 0, -20, 0, 70, 0, -20, 0, 0, 0])
    R = 100.0 * np.diag([veh.R_range, veh.R_bearing])
    for b in range(2):
        for n in (1, 7, N):
            out = ukf_oracle.ukf_run(
                F, Q, ukf_oracle.range_bearing, R, x0, P0, sim["y"][b, :n], angular=(False, True)
            )
            x = out["x"]
            ref = np.array([k1 * x[4] + k2 * x[5] + x[8], k1 * x[6] + k2 * x[7] + x[9]])
            np.testing.assert_allclose(res.estimate[b, n - 1], ref, rtol=1e-7, atol=1e-7 * np.abs(ref).max())


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [({"lag": -1}, "lag"), ({"estimate": "x"}, "estimate"), ({"q_e": -1.0}, "q_e"), ({"c_r": 0.0}, "c_r"),
     ({"a_nom": 0.0}, "a_nom"), ({"Q0": (1.0, 1.0)}, "Q0"), ({"detrend": -1}, "detrend")],
)  # fmt: skip
def test_config_errors_name_the_field(kwargs: dict, field: str) -> None:
    with pytest.raises(ConfigError) as err:
        ECConfig(**kwargs)
    assert err.value.field == field


def test_detrending_removes_a_constant_and_defaults_to_one_carrier_period() -> None:
    rng = np.random.default_rng(2)
    est = rng.standard_normal((2, 60))
    np.testing.assert_allclose(detrended(est + 5.0, 20), detrended(est, 20), atol=1e-12)
    assert detrend_window(ECConfig(), 0.05) == 20  # 1 / (1 Hz · 0.05 s)
    assert detrend_window(ECConfig(fc_grid=(0.0, 0.5, 2.0)), 0.05) == 40  # the lowest positive carrier
    assert detrend_window(ECConfig(fc_grid=(0.0,)), 0.05) == 0
    assert detrend_window(ECConfig(detrend=0), 0.05) == 0
    assert detrended(est, 0) is est


def test_missing_samples_are_refused() -> None:
    y = np.zeros((1, 50))
    y[0, 10] = np.nan
    with pytest.raises(ValueError, match="missing"):
        estimate_correlate_detect(y, CHIPS, Vehicle1D(), 20, ECConfig(), [50])
