"""Batched IMM (eqs 7–13 of Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System*;
property P10) against an independent textbook IMM (helper-written,
loop-based, linear-domain likelihoods: tests/filters/imm_oracle.py) and FilterPy's IMMEstimator."""

import numpy as np
import pytest

from motionsig_cli.filters.imm import imm_filter, logsumexp
from motionsig_cli.maneuver.scenario import ManeuverScenario
from motionsig_cli.maneuver.study import measurements
from motionsig_cli.models.motion import H_POS6, ModelSet, imm_models, two_point_init
from tests.filters.imm_oracle import imm_oracle, kf_oracle

T, SIGMA = 1.0, 100.0
R = SIGMA**2 * np.eye(2)


def _record(n_scans=320, runs=(0,), preset="literal"):
    sc = ManeuverScenario(preset, scans=n_scans)
    return measurements(sc, SIGMA, runs, 11)


def _run(z, ms, keep_P=True):
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA)
    return imm_filter(z[:, 2:], H_POS6, R, ms, x0, P0, keep_P=keep_P)


def _oracle_models(ms: ModelSet, T: float):
    """Hand the oracle (Φ, G, Q) with G Q Gᵀ = Qd: G from the printed forms, Q = q I₂."""
    G1 = np.array([[T * T / 2, 0], [T, 0], [0, T * T / 2], [0, T], [0, 0], [0, 0]])
    G2 = np.array([[T * T / 4, 0], [T / 2, 0], [0, T * T / 4], [0, T / 2], [1, 0], [0, 1]])
    out = []
    for j, G in enumerate((G1, G2, G2)):
        q = ms.Qd[j][4, 4] if j else 0.0  # the (ẍ, ẍ) entry of q G Gᵀ is q
        out.append((ms.Phi[j], G, q * np.eye(2)))
    return out


@pytest.mark.parametrize("preset", ["literal", "turn90"])
def test_imm_equals_textbook_oracle_through_the_turns(preset):
    z = _record(preset=preset)
    ms = imm_models(T)
    tr = _run(z, ms)
    ref = imm_oracle(z[0], T, SIGMA, ms.Pi, ms.mu0, _oracle_models(ms, T))
    scale = np.abs(ref["x"]).max(axis=0)
    assert np.max(np.abs(tr.x[0] - ref["x"]) / np.maximum(scale, 1.0)) < 1e-9
    np.testing.assert_allclose(tr.mu[0], ref["mu"], atol=1e-9)
    # measured: 4e-12 (x), 4e-12 (μ), 2e-12 (P, relative to its largest entry); the oracle updates P in the
    # plain form (I − KH)P, so only rounding separates them
    np.testing.assert_allclose(tr.P[0], ref["P"], rtol=0, atol=1e-9 * np.abs(ref["P"]).max())


def test_imm_equals_filterpy_imm_estimator():
    """Second implementation: FilterPy's IMMEstimator with three KalmanFilter objects (Joseph update)."""
    from filterpy.kalman import IMMEstimator, KalmanFilter

    z = _record(260)[0]
    ms = imm_models(T)
    x0, P0 = two_point_init(z[0], z[1], T, SIGMA)
    filters = []
    for j in range(3):
        kf = KalmanFilter(dim_x=6, dim_z=2)
        kf.x, kf.P = x0.copy(), P0.copy()
        kf.F, kf.Q, kf.H, kf.R = ms.Phi[j].copy(), ms.Qd[j].copy(), H_POS6.copy(), R.copy()
        filters.append(kf)
    imm = IMMEstimator(filters, ms.mu0.copy(), ms.Pi.copy())
    xs, mus = [], []
    for zk in z[2:]:
        imm.predict()
        imm.update(zk)
        xs.append(imm.x.copy())
        mus.append(imm.mu.copy())
    tr = _run(z[None], ms, keep_P=False)
    xs = np.array(xs)
    assert np.max(np.abs(tr.x[0] - xs) / np.maximum(np.abs(xs).max(axis=0), 1.0)) < 1e-9
    np.testing.assert_allclose(tr.mu[0], np.array(mus), atol=1e-9)


def test_single_model_imm_is_a_kalman_filter():
    z = _record(300)
    ms = imm_models(T)
    one = ModelSet(ms.Phi[2:], ms.Qd[2:], np.ones((1, 1)), np.ones(1))
    tr = _run(z, one)
    G2 = np.array([[0.25, 0], [0.5, 0], [0, 0.25], [0, 0.5], [1, 0], [0, 1]])
    ref = kf_oracle(z[0], T, SIGMA, ms.Phi[2], G2, 0.0144 * np.eye(2))
    np.testing.assert_allclose(tr.x[0], ref["x"], rtol=1e-10, atol=1e-10 * np.abs(ref["x"]).max())
    assert np.all(tr.mu == 1.0)


def test_maneuver_models_switched_off_gives_the_cv_filter():
    """Π = I, μ0 = (1, 0, 0): models 2 and 3 are unreachable (c̄ = 0, log μ = −inf) — the IMM equals the CV
    Kalman filter (model 1) to 1e-10, with no NaN from 0/0."""
    z = _record(300)
    ms = imm_models(T, Pi=np.eye(3), mu0=np.array([1.0, 0.0, 0.0]))
    tr = _run(z, ms)
    single = _run(z, ModelSet(ms.Phi[:1], ms.Qd[:1], np.ones((1, 1)), np.ones(1)))
    assert np.all(np.isfinite(tr.x)) and np.all(np.isfinite(tr.P))
    np.testing.assert_allclose(tr.x, single.x, rtol=1e-10, atol=1e-10 * np.abs(single.x).max())
    np.testing.assert_array_equal(tr.mu[..., 0], 1.0)
    assert np.all(tr.log_mu[..., 1:] == -np.inf)


def test_identical_models_propagate_probabilities_by_the_chain():
    """Three identical models: every likelihood is equal, so μ(k) = Πᵀ μ(k−1) (→ 1/3 each) and the output is
    the single filter's."""
    z = _record(120)
    ms = imm_models(T)
    same = ModelSet(np.repeat(ms.Phi[1:2], 3, 0), np.repeat(ms.Qd[1:2], 3, 0), ms.Pi, ms.mu0)
    tr = _run(z, same)
    mu = ms.mu0.copy()
    for k in range(tr.mu.shape[1]):
        mu = ms.Pi.T @ mu
        np.testing.assert_allclose(tr.mu[0, k], mu, atol=1e-13)
    # the second eigenvalue of Π is 0.925: after 118 scans μ is within 0.47 · 0.925¹¹⁸ ≈ 5e-5 of uniform
    np.testing.assert_allclose(tr.mu[0, -1], [1 / 3] * 3, atol=1e-4)
    single = _run(z, ModelSet(ms.Phi[1:2], ms.Qd[1:2], np.ones((1, 1)), np.ones(1)))
    np.testing.assert_allclose(tr.x, single.x, rtol=1e-10, atol=1e-9)


def test_probabilities_stay_finite_and_normalised_for_ten_thousand_scans_with_an_outlier():
    """P10 and the robustness target: 10⁴ scans, and a 10⁶ m outlier whose likelihood exp(−5·10⁷) underflows a
    double for every model (a linear-domain IMM divides 0 by 0 there). Combined P stays symmetric PSD."""
    rng = np.random.default_rng(5)
    N = 10_000
    truth = np.stack([np.zeros(N), 450.0 * np.arange(N)], axis=-1)
    z = (truth + SIGMA * rng.standard_normal((N, 2)))[None]
    z[0, 5000] += 1e6
    tr = _run(z, imm_models(T))
    assert np.all(np.isfinite(tr.log_mu)) and np.all(np.isfinite(tr.x)) and np.all(np.isfinite(tr.P))
    np.testing.assert_allclose(tr.mu.sum(axis=-1), 1.0, atol=1e-12)
    assert np.all(tr.mu >= 0)
    assert np.all(tr.loglik[0, 4998] < -1e6)  # the outlier scan's log-likelihoods are far below log(1e-308)
    P = tr.P[0]
    np.testing.assert_allclose(P, np.swapaxes(P, 1, 2), atol=1e-9 * np.abs(P).max())
    assert np.linalg.eigvalsh(P).min() > -1e-8 * np.abs(P).max()
    # the track recovers: the last 1000 scans have the same error level as the first 4000 after start-up
    err = np.linalg.norm(tr.x[0, :, [0, 2]].T - truth[2:], axis=-1)
    assert err[-1000:].mean() < 1.2 * err[500:4500].mean()


def test_mixing_weights_sum_to_one():
    """Σ_i μ_{i|j} = 1 for every j (P10), seen through the mixing of constant vectors: an IMM whose models
    all start from X and have Φ = I, Q = 0 keeps X exactly only if the weights sum to 1."""
    ms = imm_models(T)
    eye = ModelSet(np.repeat(np.eye(6)[None], 3, 0), np.zeros((3, 6, 6)), ms.Pi, ms.mu0)
    x0 = np.array([[5.0, 1.0, -3.0, 2.0, 0.5, 0.25]])
    P0 = np.eye(6)
    z = np.tile(x0[:, None, [0, 2]], (1, 50, 1))
    tr = imm_filter(z, H_POS6, R, eye, x0, P0)
    np.testing.assert_allclose(tr.x[0], np.repeat(x0, 50, 0), rtol=1e-14)


def test_logsumexp_all_minus_inf_is_minus_inf():
    a = np.array([[-np.inf, -np.inf], [0.0, -np.inf], [1000.0, 1000.0]])
    out = logsumexp(a, axis=1)
    assert out[0] == -np.inf and out[1] == 0.0 and out[2] == pytest.approx(1000 + np.log(2))
