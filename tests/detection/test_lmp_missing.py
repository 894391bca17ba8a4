"""Missing samples in the LMP banks: a NaN measurement is a predict-only step of every filter.

Oracles: FilterPy's KalmanFilter run step by step (update skipped where y is NaN) for the H0 filter and
H1 filters; a filter written here that runs on the present samples only, with the transition composed
over each gap (F_{k+g−1}⋯F_k and its accumulated process noise: exact for a linear model); and the
batch-GLS identity of the static-amplitude bank on the deleted record (eqs 35, 49).
"""

import math

import numpy as np
import pytest

from motionsig_cli.detection.lmp import LMPConfig, lmp_detect, progress_steps
from motionsig_cli.detection.lmp_fft import MissingSamples, lmp_detect_fft, lmp_detect_projection
from motionsig_cli.filters.kalman import innovation_costs, riccati
from motionsig_cli.models.vehicle import Vehicle1D, amplitude_column, transition_h0
from motionsig_cli.modesig.lmp1d import simulate_trials
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import corrected_codes
from motionsig_cli.signals.signature import replica_bank

CHIPS = to_bipolar(corrected_codes()).astype(float)
VEH = Vehicle1D(R=1e-3)
M_RHO = 20


def _gappy(y: np.ndarray, seed: int, frac: float = 0.1) -> np.ndarray:
    """y with ~frac of the samples missing, plus the first sample and a run of 7 (a long gap)."""
    y = np.array(y, dtype=float)
    rng = np.random.default_rng(seed)
    for row in np.atleast_2d(y):
        row[rng.random(row.size) < frac] = np.nan
        row[0] = np.nan
        row[100:107] = np.nan
    return y


def _models(cfg: LMPConfig, N: int):
    """H0 transition (4×4) and the H1 transitions F_k (2C, N, 5, 5) of lmp_detect, built from the model."""
    F0 = transition_h0(VEH, cfg.A_r)
    mode, tau = np.repeat(np.arange(3), 31), np.tile(np.arange(0, 31 * M_RHO, M_RHO), 3)
    zc, zs, dc, ds = replica_bank(CHIPS, mode, tau, np.full(93, 1.0), VEH.T, M_RHO, N, cfg.zdot)
    g = np.concatenate([amplitude_column(VEH, zc, dc), amplitude_column(VEH, zs, ds)])  # (2C, N)
    return F0, g


def _F1(F0: np.ndarray, gk: float) -> np.ndarray:
    F = np.zeros((5, 5))
    F[:4, :4], F[4, 4], F[1, 4] = F0, 1.0, gk
    return F


def _filterpy_costs(Fs, Q, R, P0, y):
    """FilterPy's KalmanFilter from the predicted prior (0, P0 I): update with y_k unless it is NaN (then
    predict only), predict with F_k. Returns J after every sample (N,) and the final state."""
    from filterpy.kalman import KalmanFilter

    n = Q.shape[0]
    kf = KalmanFilter(dim_x=n, dim_z=1)
    kf.x, kf.P, kf.Q, kf.R = np.zeros((n, 1)), P0 * np.eye(n), Q, np.array([[R]])
    kf.H = np.eye(1, n)
    J, out = 0.0, []
    for k, yk in enumerate(y):
        if not np.isnan(yk):
            kf.update(np.array([[yk]]))  # Joseph form
            J += 0.5 * float(kf.y[0, 0] ** 2 / kf.S[0, 0])
        out.append(J)
        if k + 1 < len(y):
            kf.predict(F=Fs(k))
    return np.array(out), kf.x[:, 0]


def test_bank_equals_filterpy_with_predict_only_steps():
    """J of the H0 filter and of H1 filters (cos and sin, three code phases) after EVERY sample equals FilterPy's
    Kalman filter that skips the update where y is NaN: to 1e-10 relative (measured ~1e-13)."""
    N, cfg = 300, LMPConfig()
    y = _gappy(simulate_trials(VEH, CHIPS, M_RHO, 1.0, N, 3, [0])[0][0], 1)
    assert 30 < np.isnan(y).sum() < 60
    res = lmp_detect(y, CHIPS, VEH, M_RHO, cfg, list(range(1, N + 1)))
    F0, g = _models(cfg, N)
    R = cfg.c_r * VEH.R
    J0, _ = _filterpy_costs(lambda k: F0, np.diag(cfg.Q0), R, cfg.P0, y)
    np.testing.assert_allclose(res.J0[0], J0, rtol=1e-10, atol=0)
    Q1 = np.diag([*cfg.Q0, cfg.Q_a])
    for c in (0, 40, 92):
        for J_res, row in ((res.J_cos, c), (res.J_sin, 93 + c)):
            J1, _ = _filterpy_costs(lambda k, row=row: _F1(F0, g[row, k]), Q1, R, cfg.P0, y)
            np.testing.assert_allclose(J_res[c, 0], J1, rtol=1e-10, atol=0)
    np.testing.assert_allclose(res.Lambda[:, 0], 2 * res.J0[0][None] - res.J_cos[:, 0] - res.J_sin[:, 0])
    assert np.all(np.diff(res.J0[0])[np.isnan(y[1:])] == 0)  # a missing sample adds nothing to J


def _deleted_record_costs(Fs, Q, R, P0, y):
    """A filter on the present samples only: between two of them, k and k + g, the transition is
    Φ = F_{k+g−1}⋯F_k and the process noise Σ_i (F_{k+g−1}⋯F_{k+i+1}) Q (…)ᵀ (exact for a linear model)."""
    n = Q.shape[0]
    x, P, J, k_last = np.zeros(n), P0 * np.eye(n), 0.0, None
    for k in np.flatnonzero(~np.isnan(y)):
        if k_last is not None:  # compose the transition over samples k_last … k − 1
            Phi, Qg = np.eye(n), np.zeros((n, n))
            for j in range(k_last, k):
                Phi, Qg = Fs(j) @ Phi, Fs(j) @ Qg @ Fs(j).T + Q
            x, P = Phi @ x, Phi @ P @ Phi.T + Qg
        elif k > 0:  # the record starts with a gap
            for j in range(k):
                x, P = Fs(j) @ x, Fs(j) @ P @ Fs(j).T + Q
        S = P[0, 0] + R
        nu = y[k] - x[0]
        J += 0.5 * nu**2 / S
        K = P[:, 0] / S
        x, P = x + K * nu, P - np.outer(K, K) * S
        k_last = k
    return J


def test_missing_samples_equal_the_deleted_record_with_composed_transitions():
    """Derivation check: J on the record with NaN equals J on the record with those samples deleted, the
    model's transition composed over each gap (F² over a one-sample gap), to 1e-10 relative."""
    N, cfg = 260, LMPConfig()
    y = _gappy(simulate_trials(VEH, CHIPS, M_RHO, 1.0, N, 4, [0])[0][0], 2, frac=0.2)
    res = lmp_detect(y, CHIPS, VEH, M_RHO, cfg, [N])
    F0, g = _models(cfg, N)
    R = cfg.c_r * VEH.R
    assert math.isclose(
        res.J0[0, 0], _deleted_record_costs(lambda k: F0, np.diag(cfg.Q0), R, cfg.P0, y), rel_tol=1e-10
    )
    Q1 = np.diag([*cfg.Q0, cfg.Q_a])
    for c in (5, 77):
        J1 = _deleted_record_costs(lambda k, c=c: _F1(F0, g[c, k]), Q1, R, cfg.P0, y)
        assert math.isclose(res.J_cos[c, 0, 0], J1, rel_tol=1e-10)


def test_static_amplitude_bank_equals_batch_gls_on_the_present_samples():
    """Eqs (35), (49) with missing samples: Σ ν²/S over the present samples = y_pᵀ(R I + P0 z_p z_pᵀ)⁻¹ y_p
    (Sherman–Morrison), z_p, y_p the present samples, and Σ log S = log det(R I + P0 z_p z_pᵀ)."""
    rng = np.random.default_rng(11)
    N, R, P0 = 200, 0.3, 2.0
    z = rng.choice([-1.0, 1.0], N) * np.cos(2 * np.pi * 0.05 * np.arange(N) + 0.4)
    y = 0.7 * z + rng.normal(scale=math.sqrt(R), size=N)
    skip = rng.random(N) < 0.25
    skip[0] = skip[-1] = True
    y[skip] = np.nan

    def F_at(k):
        return np.array([[[1.0, 0.0], [z[k + 1], 0.0]]])

    prior = P0 * np.array([[1.0, z[0]], [z[0], z[0] ** 2]])
    gains = riccati(F_at, np.array([[0.0, 1.0]]), np.zeros((2, 2)), np.array([[R]]), prior, N, 1, skip=skip)
    J = innovation_costs(F_at, np.array([[0.0, 1.0]]), gains, np.zeros(2), y[None], [N])[0, 0, 0]
    full = innovation_costs(
        F_at, np.array([[0.0, 1.0]]), gains, np.zeros(2), y[None], [N], include_logdet=True
    )
    p = ~skip
    zp, yp = z[p], y[p]
    gls = yp @ yp / R - P0 * (zp @ yp) ** 2 / (R * (R + P0 * zp @ zp))
    assert math.isclose(2 * J, gls, rel_tol=1e-9)
    logdet_S = 2 * full[0, 0, 0] - 2 * J - p.sum() * math.log(2 * math.pi)
    assert math.isclose(logdet_S, p.sum() * math.log(R) + math.log1p(P0 * zp @ zp / R), rel_tol=1e-9)


def test_records_with_different_gaps_in_one_batch_equal_each_record_alone():
    """The bank groups records by missing pattern (one Riccati recursion each): a batch of four records
    (two share a pattern, one has none missing) gives each record's statistics run alone (1e-12), and the
    progress steps still add up to progress_steps."""
    N, cfg = 200, LMPConfig()
    y = simulate_trials(VEH, CHIPS, M_RHO, 1.0, N, 6, [0, 1, 2, 3])[0]
    y[0] = _gappy(y[0], 3)
    y[1] = _gappy(y[1], 4)
    y[3, np.isnan(y[0])] = np.nan  # record 3 misses what record 0 misses
    steps: list[int] = []
    res = lmp_detect(y, CHIPS, VEH, M_RHO, cfg, [50, N], progress=steps.append)
    assert sum(steps) == progress_steps(N, cfg)
    for b in range(4):
        one = lmp_detect(y[b], CHIPS, VEH, M_RHO, cfg, [50, N])
        for a, o in (
            (res.J0[b], one.J0[0]),
            (res.J_cos[:, b], one.J_cos[:, 0]),
            (res.Lambda[:, b], one.Lambda[:, 0]),
        ):
            np.testing.assert_allclose(a, o, rtol=1e-12, atol=1e-12 * np.abs(o).max())
    full = lmp_detect(simulate_trials(VEH, CHIPS, M_RHO, 1.0, N, 6, [2])[0], CHIPS, VEH, M_RHO, cfg, [50, N])
    np.testing.assert_allclose(res.Lambda[:, 2], full.Lambda[:, 0], rtol=1e-12, atol=1e-9)  # none missing


def test_centring_with_missing_samples_is_unbiased_under_white_noise():
    """center="h0-noise" subtracts E[J] under white noise of variance R, the missing samples skipped in the
    Lyapunov recursion too: on 3000 white-noise records with the record's gaps the centred J0 and J_cos
    average 0 within 4 standard errors (the sample SE of the mean of the 3000 values)."""
    chips, m_rho, N = CHIPS[:2, :5], 4, 80
    cfg = LMPConfig(center="h0-noise")
    rng = np.random.default_rng(21)
    y = rng.normal(scale=math.sqrt(VEH.R), size=(3000, N))
    y[:, _gappy(np.zeros(N), 5, frac=0.2) != 0] = np.nan  # NaN != 0
    res = lmp_detect(y, chips, VEH, m_rho, cfg, [N])
    assert np.isnan(y[0]).sum() > 10
    for J in (res.J0[:, 0], res.J_cos[0, :, 0], res.J_cos[7, :, 0], res.J_sin[3, :, 0]):
        assert abs(J.mean()) < 4 * J.std(ddof=1) / math.sqrt(J.size)
    raw = lmp_detect(y, chips, VEH, m_rho, LMPConfig(), [N])
    assert raw.J0.mean() > 10 * abs(res.J0.mean())  # the uncentred J0 is far from 0: the test can fail


def test_exact_weights_sum_over_the_present_samples():
    """weights="exact": c = Σ z_k² / (c_r R) over the samples that are present (eqs 36, 38, 40)."""
    N, cfg = 160, LMPConfig(weights="exact")
    y = _gappy(simulate_trials(VEH, CHIPS, M_RHO, 1.0, N, 8, [0])[0][0], 6, frac=0.3)
    res = lmp_detect(y, CHIPS, VEH, M_RHO, cfg, [N])
    mode, tau = np.repeat(np.arange(3), 31), np.tile(np.arange(0, 31 * M_RHO, M_RHO), 3)
    zc, zs, _, _ = replica_bank(CHIPS, mode, tau, np.full(93, 1.0), VEH.T, M_RHO, N, cfg.zdot)
    p = ~np.isnan(y)
    c_cos, c_sin = (np.sum(z[:, p] ** 2, axis=1) / (cfg.c_r * VEH.R) for z in (zc, zs))
    want = c_cos * (res.J0[0, 0] - res.J_cos[:, 0, 0]) + c_sin * (res.J0[0, 0] - res.J_sin[:, 0, 0])
    np.testing.assert_allclose(res.Lambda[:, 0, 0], want, rtol=1e-12)
    c_all = np.sum(zc**2, axis=1) / (cfg.c_r * VEH.R)
    assert np.all(c_all > c_cos) and not np.allclose(c_all, c_cos, rtol=0.05)  # the mask matters


def test_sigma_point_bank_equals_the_kalman_bank_with_missing_samples():
    """The 1-D sigma-point bank (a per-record, per-step mask) reproduces the Kalman bank (one Riccati recursion
    per pattern) with gaps: 1e-8 relative, as without gaps; records of different patterns in one batch."""
    N, cfg = 240, LMPConfig(include_logdet=True)
    y = simulate_trials(VEH, CHIPS, M_RHO, 1.0, N, 9, [0, 1])[0]
    y[0] = _gappy(y[0], 7)
    kf = lmp_detect(y, CHIPS, VEH, M_RHO, cfg, [90, N])
    ukf = lmp_detect(y, CHIPS, VEH, M_RHO, cfg, [90, N], filter="ukf")
    for a, b in ((kf.J0, ukf.J0), (kf.J_cos, ukf.J_cos), (kf.J_sin, ukf.J_sin), (kf.Lambda, ukf.Lambda)):
        assert np.max(np.abs(a - b)) <= 1e-8 * np.max(np.abs(a))


def test_a_record_with_every_sample_missing_has_no_evidence():
    res = lmp_detect(np.full(50, np.nan), CHIPS, VEH, M_RHO, LMPConfig(), [10, 50])
    assert np.all(res.J0 == 0) and np.all(res.Lambda == 0)


def test_blocks_make_a_record_independent_of_its_batch():
    """block=b: a record's statistic depends only on its block of b records, to the last bit."""
    y = _gappy(simulate_trials(VEH, CHIPS, M_RHO, 1.0, 120, 10, range(12))[0], 8)
    y[:] = np.where(np.isnan(y[0]), np.nan, y)  # one pattern
    steps: list[int] = []
    a = lmp_detect(y[0:8], CHIPS, VEH, M_RHO, LMPConfig(), [60, 120], block=3, progress=steps.append).Lambda
    assert sum(steps) == progress_steps(120, LMPConfig())  # three blocks share the progress
    a = lmp_detect(y[0:8], CHIPS, VEH, M_RHO, LMPConfig(), [60, 120], block=4).Lambda
    b = lmp_detect(y[4:12], CHIPS, VEH, M_RHO, LMPConfig(), [60, 120], block=4).Lambda
    assert np.array_equal(a[:, 4:8], b[:, 0:4])
    whole = lmp_detect(y[0:8], CHIPS, VEH, M_RHO, LMPConfig(), [60, 120]).Lambda
    np.testing.assert_allclose(a, whole, rtol=1e-12, atol=1e-9)


def test_fft_and_projection_paths_refuse_a_missing_sample_naming_it():
    y = simulate_trials(VEH, CHIPS, M_RHO, 1.0, 200, 11, [0, 1])[0]
    y[1, 37] = y[1, 90] = np.nan
    for f in (lmp_detect_fft, lmp_detect_projection):
        with pytest.raises(MissingSamples, match="cannot skip a missing sample") as err:
            f(y, CHIPS, VEH, M_RHO, LMPConfig(Q_a=0.0), [200])
        assert (err.value.index, err.value.trial, err.value.column) == (37, 1, None)
        assert isinstance(err.value, ValueError)


def test_inf_and_inconsistent_gains_are_refused():
    y = simulate_trials(VEH, CHIPS, M_RHO, 1.0, 50, 12, [0])[0]
    y[0, 5] = np.inf
    with pytest.raises(ValueError, match="inf"):
        lmp_detect(y, CHIPS, VEH, M_RHO, LMPConfig(), [50])
    F0, H, Q, R = transition_h0(VEH), np.eye(1, 4), np.diag(LMPConfig().Q0), np.array([[0.1]])
    skip = np.zeros(50, bool)
    skip[3] = True
    g_skip = riccati(lambda k: F0, H, Q, R, np.eye(4), 50, 1, skip=skip)
    g_all = riccati(lambda k: F0, H, Q, R, np.eye(4), 50, 1)
    y[0, 5] = 1.0
    with pytest.raises(ValueError, match="not the steps the gains skip"):
        innovation_costs(lambda k: F0, H, g_skip, np.zeros(4), y, [50])  # y has no NaN at 3
    y[0, 3] = np.nan
    with pytest.raises(MissingSamples, match="NaN") as err:
        innovation_costs(lambda k: F0, H, g_all, np.zeros(4), y, [50])
    assert err.value.index == 3
    assert np.isfinite(innovation_costs(lambda k: F0, H, g_skip, np.zeros(4), y, [50])).all()
