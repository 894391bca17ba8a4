"""GLR / MLR maneuver detection (§II–III of Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK
Modulated JRC System*; properties P11–P12) against a brute-force oracle that re-runs Kalman filters with a
known input (tests/detection/glr_oracle.py, helper-written from the paper's equations: no
bias propagation, no closed-form statistic), exact recovery of noise-free steps, and the χ²₂ law under H0."""

import math

import numpy as np
import pytest
from scipy import integrate, stats

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.glr import CHI2_2_999, GLRConfig, InputModel, input_tracker
from motionsig_cli.models.motion import H_POS4, cv_input_model, two_point_init
from tests.detection.glr_oracle import glr_brute, mlr_brute

T, SIGMA, Q0 = 1.0, 50.0, 1.0


def _model(sigma=SIGMA, q0=Q0, T=T):
    F, G, Q = cv_input_model(T, q0)
    return InputModel(F, G, Q, H_POS4, sigma * sigma * np.eye(2))


def _truth(N, u, onset, x0=(0.0, 0.0, 0.0, 450.0), T=T, rng=None, q0=0.0):
    """CV truth with the input u from scan index ``onset`` on (u first moves the position of onset + 1)."""
    F, G, Q = cv_input_model(T, max(q0, 0.0))
    L = np.linalg.cholesky(Q + 1e-300 * np.eye(4)) if q0 > 0 else None
    x = np.array(x0, float)
    out = np.empty((N, 4))
    for k in range(N):
        out[k] = x
        x = F @ x + (G @ u if k >= onset else 0.0)
        if L is not None:
            x = x + L @ rng.standard_normal(4)
    return out


@pytest.mark.parametrize("correction", ["exact", "paper"])
@pytest.mark.parametrize(
    ("u", "onset", "window"), [((20.0, -10.0), 30, 10), ((3.0, 3.0), 41, 20), ((-50.0, 0.0), 17, 10)]
)
def test_noise_free_step_is_recovered_exactly(u, onset, window, correction):
    """P11: noise-free truth, step input u from onset n: the first declaration has n̂ = n and û = u exactly,
    and the corrected state equals the truth. (The small 3 m/s² step needs 11 scans to cross λ, so its
    window is 20: with s = 10 the true onset has left the window when ΔJ crosses, and n̂ = n + 1.)"""
    N = onset + 25
    tr = _truth(N, np.array(u), onset)
    z = tr[None][..., [0, 2]]
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    cfg = GLRConfig(correction=correction, window=window)
    out = input_tracker(z[:, 2:], _model(), x0, P0, cfg, keep_P=True)
    k = np.flatnonzero(out.detected[0])
    assert k.size >= 1
    k0 = k[0]
    assert out.onset[0, k0] + 2 == onset  # local index 0 is the third scan
    np.testing.assert_allclose(out.u_jump[0, k0], u, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(out.x[0, k0], tr[k0 + 2], rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(out.u_cur[0, -1], u, rtol=1e-6, atol=1e-6)
    assert np.all(out.stat[0, : onset - 2] < 1e-12)  # no evidence before the onset
    assert k.size == 1  # and nothing after it


def _oracle_prior(x0, P0, model):
    """The oracle's prior is the *predicted* one at the first processed scan."""
    return model.F @ x0, model.F @ P0 @ model.F.T + model.Q


def test_glr_and_mlr_statistics_equal_brute_force_kalman_reruns():
    """ΔJ(n), û(n) and J_MLR(n) for every onset of the window equal the oracle's values from Kalman filters
    re-run with the input (ΔJ = 2 max_u ℓ(u); J_MLR by 2-D quadrature of exp ℓ(u) N(u; 0, σ_u² I))."""
    rng = np.random.default_rng(7)
    N = 40
    tr = _truth(N, np.array([6.0, -4.0]), 25)
    z = tr[None][..., [0, 2]] + SIGMA * rng.standard_normal((1, N, 2))
    model = _model()
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    glr = input_tracker(z[:, 2:], model, x0, P0, GLRConfig(threshold=math.inf))
    mlr = input_tracker(z[:, 2:], model, x0, P0, GLRConfig(method="mlr", threshold=math.inf, sigma_u=8.0))
    xp, Pp = _oracle_prior(x0[0], P0, model)
    zz = z[0, 2:]
    k = 30
    for d in range(10):
        n = k - 1 - d
        dJ, u_hat = glr_brute(zz, T, SIGMA, Q0, xp, Pp, k, n)
        assert glr.dJ[0, k, d] == pytest.approx(dJ, rel=1e-10, abs=1e-10)  # measured ≤ 4e-14
        if d in (0, 4, 9):  # ~3 s per quadrature
            J = mlr_brute(zz, T, SIGMA, Q0, xp, Pp, k, n, 8.0)
            assert mlr.score[0, k, d] == pytest.approx(J, abs=1e-10)  # measured ≤ 1e-13
    # the declared û equals the oracle's maximiser at the declared onset (runs agree up to the declaration)
    run = input_tracker(z[:, 2:], model, x0, P0, GLRConfig(threshold=glr.stat[0, k] - 1e-9))
    first = int(np.flatnonzero(run.detected[0])[0])
    assert first <= k
    best = int(np.nanargmax(glr.dJ[0, first]))
    assert run.onset[0, first] == first - 1 - best
    _, u_hat = glr_brute(zz, T, SIGMA, Q0, xp, Pp, first, first - 1 - best)
    np.testing.assert_allclose(run.u_jump[0, first], u_hat, rtol=1e-8)


def test_delta_j_under_h0_is_chi_square_two():
    """Under H0 with the model exact (truth driven by the filter's own process noise), ΔJ at a fixed onset is
    χ²₂. 3000 runs, fixed seed: Kolmogorov–Smirnov p-value > 1e-3 and mean within 4 standard errors of 2.
    Negative control: the same runs filtered with σ assumed half the truth's must be rejected."""
    rng = np.random.default_rng(2024)
    B, N = 3000, 30
    F, _, Q = cv_input_model(T, Q0)
    L = np.linalg.cholesky(Q)
    x = np.tile([0.0, 10.0, 0.0, 450.0], (B, 1))
    pos = np.empty((B, N, 2))
    for k in range(N):
        pos[:, k] = x[:, [0, 2]]
        x = x @ F.T + rng.standard_normal((B, 4)) @ L.T
    z = pos + SIGMA * rng.standard_normal((B, N, 2))
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    out = input_tracker(z[:, 2:], _model(), x0, P0, GLRConfig(threshold=math.inf))
    sample = out.dJ[:, 25, 9]  # onset n = 15, 10 innovations
    assert np.all(np.isfinite(sample))
    assert stats.kstest(sample, stats.chi2(2).cdf).pvalue > 1e-3
    assert abs(sample.mean() - 2.0) < 4 * 2.0 / math.sqrt(B)  # sd of χ²₂ is 2
    wrong = input_tracker(z[:, 2:], _model(sigma=SIGMA / 2), x0, P0, GLRConfig(threshold=math.inf))
    assert stats.kstest(wrong.dJ[:, 25, 9], stats.chi2(2).cdf).pvalue < 1e-6


def test_mlr_closed_form_by_quadrature_and_flat_prior_limit():
    """P12. (a) As σ_u → ∞, J_MLR(n) + ½ log det Σ_u → ½ΔJ(n) + ½ log det Σ(n) (rel 1e-3 at σ_u = 10⁴), with
    Σ(n)⁻¹ the Hessian of the brute-force log ratio ℓ(u) (oracle). (b) The scalar closed form
    J = ½ e²/(1/s + 1/σ_u²) − ½ log(1 + σ_u²/s) equals log ∫ exp(eu − ½u²/s) N(u; 0, σ_u²) du by quadrature."""
    from tests.detection.glr_oracle import _llr_function, _maximise_quadratic

    rng = np.random.default_rng(3)
    N = 30
    z = _truth(N, np.zeros(2), 0)[None][..., [0, 2]] + SIGMA * rng.standard_normal((1, N, 2))
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    model = _model()
    k, d = 20, 4
    g = input_tracker(z[:, 2:], model, x0, P0, GLRConfig(threshold=math.inf))
    m = input_tracker(z[:, 2:], model, x0, P0, GLRConfig(method="mlr", threshold=math.inf, sigma_u=1e4))
    xp, Pp = _oracle_prior(x0[0], P0, model)
    _, A = _maximise_quadratic(_llr_function(z[0, 2:], T, SIGMA, Q0, xp, Pp, k, k - 1 - d), h=10.0)
    limit = 0.5 * g.dJ[0, k, d] - 0.5 * np.linalg.slogdet(A)[1]  # ½ΔJ + ½ log det Σ, Σ = A⁻¹
    assert m.score[0, k, d] + math.log(1e4**2) == pytest.approx(limit, rel=1e-3)
    # scalar toy: J(e, s, σ_u) = ½ e²/(1/s + 1/σ_u²) − ½ log(1 + σ_u²/s) equals the quadrature
    for e, s, su in ((1.3, 0.7, 2.0), (-4.0, 0.05, 20.0), (0.2, 3.0, 0.5)):
        closed = 0.5 * e * e / (1 / s + 1 / su**2) - 0.5 * math.log(1 + su**2 / s)
        f = lambda u, e=e, s=s, su=su: math.exp(e * u - 0.5 * u * u / s) * stats.norm.pdf(u, 0, su)  # noqa: E731
        v = 1 / (1 / s + 1 / su**2)  # the integrand is a Gaussian bump at v e of variance v
        quad, _ = integrate.quad(
            f, v * e - 40 * math.sqrt(v), v * e + 40 * math.sqrt(v), epsabs=0, epsrel=1e-12
        )
        assert closed == pytest.approx(math.log(quad), abs=1e-9)


def test_continuation_known_uses_the_estimate_as_a_known_input():
    """continuation='known': after the first declaration the input estimate is û exactly and carries no
    covariance; 'estimate' keeps refining it (its later value moves toward the truth)."""
    rng = np.random.default_rng(9)
    N = 80
    u = np.array([15.0, -8.0])
    z = _truth(N, u, 40)[None][..., [0, 2]] + SIGMA * rng.standard_normal((1, N, 2))
    x0, P0 = two_point_init(z[:, 0], z[:, 1], T, SIGMA, n=4)
    known = input_tracker(z[:, 2:], _model(), x0, P0, GLRConfig(continuation="known"), keep_P=True)
    est = input_tracker(z[:, 2:], _model(), x0, P0, GLRConfig(continuation="estimate"))
    k = int(np.flatnonzero(known.detected[0])[0])
    np.testing.assert_allclose(known.u_cur[0, k], known.u_jump[0, k], rtol=1e-12)
    if not known.detected[0, k + 1 :].any():
        np.testing.assert_allclose(known.u_cur[0, -1], known.u_jump[0, k], rtol=1e-12)
    assert np.linalg.norm(est.u_cur[0, -1] - u) < np.linalg.norm(est.u_jump[0, k] - u) + 1e-9


@pytest.mark.parametrize(
    ("kw", "field"),
    [
        ({"method": "x"}, "method"),
        ({"window": 0}, "window"),
        ({"window": 201}, "window"),
        ({"window": 2.5}, "window"),
        ({"threshold": math.nan}, "threshold"),
        ({"threshold": -math.inf, "method": "mlr"}, "threshold"),
        ({"threshold": -1.0}, "threshold"),  # ΔJ is never negative
        ({"sigma_u": 0.0}, "sigma_u"),
        ({"sigma_u": 1e7}, "sigma_u"),
        ({"correction": "x"}, "correction"),
        ({"continuation": "x"}, "continuation"),
    ],
)
def test_bad_configuration_is_refused_by_field(kw, field):
    with pytest.raises(ConfigError) as info:
        GLRConfig(**kw)
    assert info.value.field == field


def test_thresholds_of_each_method():
    """The MLR statistic is a log-likelihood ratio (h may be negative); inf never declares."""
    assert GLRConfig(method="mlr", threshold=-3.0).threshold == -3.0
    assert GLRConfig(threshold=math.inf).threshold == math.inf
    assert GLRConfig(method="none", threshold=math.inf).method == "none"
    assert CHI2_2_999 == pytest.approx(stats.chi2(2).ppf(0.999), rel=1e-12)


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"F": np.eye(3)}, "G"),
        ({"G": np.zeros((3, 2))}, "G"),
        ({"Q": np.eye(3)}, "Q"),
        ({"H": np.eye(2, 3)}, "H"),
        ({"R": np.eye(3)}, "R"),
        ({"F": np.full((4, 4), np.nan)}, "F"),
        ({"Q": np.full((4, 4), np.inf)}, "Q"),
        ({"R": np.diag([1.0, 0.0])}, "R"),
    ],
)
def test_bad_input_model_is_refused_by_field(change, field):
    F, G, Q = cv_input_model(T, Q0)
    kw = {"F": F, "G": G, "Q": Q, "H": H_POS4, "R": np.eye(2)} | change
    with pytest.raises(ConfigError) as info:
        InputModel(**kw)
    assert info.value.field == field
