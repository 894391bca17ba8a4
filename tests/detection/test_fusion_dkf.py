"""The exact distributed Kalman filter (Govaers & Koch) and the federated filter with feedback, against an
independent joint Kalman filter written here (all sensors' measurements stacked into one vector, one
update per scan, scipy's Gaussian density): with linear sensors of *different* noise, p_D = 1 and no
clutter, theory says DKF = CKF = the joint filter exactly, and the federated filter without feedback
is only an approximation (its relaxed evolution model mixes unequal local covariances)."""

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from motionsig_cli.detection.track_existence import (
    FusionOptions,
    ScanData,
    SensorModel,
    TrackExistenceModel,
    run_methods,
)
from motionsig_cli.models.radar import MeasurementModel, cv_model

NOISE_SD = [(20.0, 80.0), (50.0, 50.0), (120.0, 30.0), (300.0, 300.0)]  # m, per axis: unequal sensors
SENSORS = np.array([[13_000.0, 0.0], [0.0, 13_000.0], [-13_000.0, 0.0], [0.0, -13_000.0]])
H = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])


def linear_model(m0_cov=None):
    F, Q = cv_model(1.0, 10.0)
    P0 = np.diag([200.0**2, 50.0**2, 200.0**2, 50.0**2]) if m0_cov is None else m0_cov
    sms = tuple(
        SensorModel(MeasurementModel("cartesian", np.diag([a * a, b * b])), 1.0, 0.0) for a, b in NOISE_SD
    )
    return TrackExistenceModel(F, Q, SENSORS, sms[0].meas, 1.0, 0.0, P0, sms)


def draw(runs, scans, seed):
    """Truth from (0, 150, 0, 50) with the model's process noise, one position measurement per sensor and
    scan with its own noise, and initial track means drawn around the truth: plain numpy."""
    rng = np.random.default_rng(seed)
    F, Q = cv_model(1.0, 10.0)
    LQ = np.linalg.cholesky(Q + 1e-12 * np.eye(4))
    x = np.tile([0.0, 150.0, 0.0, 50.0], (runs, 1))
    m0 = x + rng.normal(size=(runs, 4)) * [200.0, 50.0, 200.0, 50.0]
    out = []
    for _ in range(scans):
        x = x @ F.T + rng.normal(size=(runs, 4)) @ LQ.T
        Z = tuple((x[:, [0, 2]] + rng.normal(size=(runs, 2)) * sd)[:, None, :] for sd in NOISE_SD)
        out.append(ScanData(Z, tuple(np.ones((runs, 1), bool) for _ in NOISE_SD)))
    return m0, out


def joint_filter(model, m0, scans):
    """log LR (R, K) of one Kalman filter with every sensor's measurement in one stacked vector:
    log Λ(k) = log N(z̃; H̃x, H̃PH̃ᵀ + R̃) − Σ_s log ρ_s (p_D = 1, one measurement per sensor)."""
    S = model.n_sensors
    Ht = np.vstack([H] * S)
    Rt = np.zeros((2 * S, 2 * S))
    for s in range(S):
        Rt[2 * s : 2 * s + 2, 2 * s : 2 * s + 2] = model.sensor(s)[0].R
    log_rho = sum(model.sensor(s)[2] for s in range(S))
    R, K = m0.shape[0], len(scans)
    out = np.zeros((R, K))
    for r in range(R):
        m = m0[r]
        P = model.m0_cov if model.m0_cov.ndim == 2 else model.m0_cov[r]
        total = 0.0
        for k, scan in enumerate(scans):
            m, P = model.F @ m, model.F @ P @ model.F.T + model.Q
            z = np.concatenate([scan.Z[s][r, 0] for s in range(S)])
            St = Ht @ P @ Ht.T + Rt
            total += multivariate_normal(Ht @ m, St).logpdf(z) - log_rho
            G = P @ Ht.T @ np.linalg.inv(St)
            m, P = m + G @ (z - Ht @ m), P - G @ St @ G.T
            out[r, k] = total
    return out


def increments(x):
    return np.diff(x, axis=1, prepend=0.0)


@pytest.fixture(scope="module")
def scored():
    model = linear_model()
    m0, scans = draw(6, 25, 2012)
    out = run_methods(model, m0, scans, ("ckf", "dkf", "fkf", "fkf-feedback"))
    every3 = run_methods(model, m0, scans, ["fkf-feedback"], options=FusionOptions(feedback_every=3))
    return model, m0, scans, out, every3["fkf-feedback"]


def test_dkf_equals_the_joint_filter_and_the_ckf(scored):
    """Scores are large (the clutter density floor adds ≈ 711 per sensor and scan), so the per-scan log Λ are
    compared too: DKF's equal the joint filter's to 1e-7 absolute (rounding of sums of order 10⁴)."""
    model, m0, scans, out, _ = scored
    joint = joint_filter(model, m0, scans)
    for name in ("ckf", "dkf"):
        np.testing.assert_allclose(out[name], joint, rtol=1e-9)
        np.testing.assert_allclose(increments(out[name]), increments(joint), rtol=0, atol=1e-7)


def test_the_federated_filter_without_feedback_is_not_exact_here(scored):
    """The contrast that makes the previous test able to fail: FKF's per-scan log Λ differ from the joint
    filter's by more than 0.01 at some scan (unequal local covariances), DKF's by less than 1e-7."""
    out = scored[3]
    gap = np.abs(increments(out["fkf"]) - increments(out["ckf"])).max()
    assert gap > 1e-2
    assert np.abs(increments(out["dkf"]) - increments(out["ckf"])).max() < 1e-7


def test_feedback_after_every_scan_is_exact_and_rarer_feedback_is_not(scored):
    """With the locals reset to (x_f, S·P_f) after every scan each scan starts from the fused posterior,
    which for linear sensors is the centralised one: FKF-FB = CKF. Every third scan: in between, the
    relaxed model acts again and the scores differ (less than without feedback)."""
    _, _, _, out, every3 = scored
    np.testing.assert_allclose(increments(out["fkf-feedback"]), increments(out["ckf"]), rtol=0, atol=1e-7)
    gap3 = np.abs(every3 - out["ckf"])[:, -1]
    gap_none = np.abs(out["fkf"] - out["ckf"])[:, -1]
    assert np.all(gap3 > 1e-4) and gap3.mean() < gap_none.mean()
    inc = np.abs(increments(every3) - increments(out["ckf"]))
    np.testing.assert_allclose(inc[:, 0], 0.0, atol=1e-7)  # the first scan is exact (consistent start)
    assert inc[:, 1].max() > 1e-6  # the second is not: no feedback after the first scan


def test_feedback_later_than_the_last_scan_is_the_federated_filter_to_the_bit(scored):
    model, m0, scans, out, _ = scored
    late = run_methods(model, m0, scans, ["fkf-feedback"], options=FusionOptions(feedback_every=26))
    np.testing.assert_array_equal(late["fkf-feedback"], out["fkf"])


def test_dkf_with_a_prior_covariance_per_run_and_one_sensor():
    """Tracks started with different prior covariances (one per run): still the joint filter. With one
    sensor the DKF is the single filter (S·P = P, c ≡ 1)."""
    rng = np.random.default_rng(5)
    A = rng.normal(size=(4, 4, 4)) * [200.0, 50.0, 200.0, 50.0]
    covs = A @ np.swapaxes(A, -1, -2) + np.diag([100.0**2, 20.0**2, 100.0**2, 20.0**2])
    model = linear_model(covs)
    m0, scans = draw(4, 12, 9)
    out = run_methods(model, m0, scans, ("ckf", "dkf"))
    joint = joint_filter(model, m0, scans)
    np.testing.assert_allclose(increments(out["dkf"]), increments(joint), rtol=0, atol=1e-7)
    one = TrackExistenceModel(
        model.F, model.Q, SENSORS[:1], model.meas, 1.0, 0.0, covs, model.sensor_models[:1]
    )
    single = [ScanData(s.Z[:1], s.valid[:1]) for s in scans]
    out1 = run_methods(one, m0, single, ("ckf", "dkf"))
    np.testing.assert_allclose(out1["dkf"], out1["ckf"], rtol=1e-12)
