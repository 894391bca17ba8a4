"""The filters' model options of the 1-D LMP detector: Q read as a continuous-time density (Van Loan, checked
against quadrature, a closed form, the block-matrix exponential and the small-T limit Q·T), the reference
as a known input (checked against a direct Kalman filter with the control term B u_k, FilterPy), the FFT
path in step with it, and a carrier search that finds the offset f_d of eq (3)."""

import math

import numpy as np
import pytest
import scipy.linalg
from filterpy.kalman import KalmanFilter

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.lmp import (
    LMPConfig,
    carrier_offsets,
    continuous_generator,
    discretised_noise,
    filter_model,
    known_input_removed,
    lmp_detect,
    van_loan,
)
from motionsig_cli.detection.lmp_fft import lmp_detect_fft, lmp_detect_projection
from motionsig_cli.models.vehicle import Vehicle1D, amplitude_column, nominal_reference, transition_h0
from motionsig_cli.modesig.lmp1d import simulate_trials, table1_chips
from motionsig_cli.signals.signature import replica_bank

CHIPS = table1_chips()


# ------------------------------------------------------------------------------ continuous-time Q
@pytest.mark.parametrize("A_r", ["cv", "identity", "known"])
def test_van_loan_equals_the_quadrature_of_the_integral(A_r):
    """Q_d = ∫₀ᵀ e^{As} Q_c e^{Aᵀs} ds with e^{AT} = F (the filters' F exactly), by Gauss–Legendre quadrature."""
    veh = Vehicle1D()
    F = transition_h0(veh, A_r)
    q = [1e-3, 1e2, 1e-1, 1e1][: F.shape[0]]
    A = continuous_generator(F, veh.T)
    np.testing.assert_allclose(scipy.linalg.expm(A * veh.T), F, rtol=0, atol=1e-10)
    nodes, weights = np.polynomial.legendre.leggauss(16)  # Gauss–Legendre: exact to degree 31 in s
    s = 0.5 * veh.T * (nodes + 1)
    quad = sum(
        0.5 * veh.T * wt * scipy.linalg.expm(A * si) @ np.diag(q) @ scipy.linalg.expm(A * si).T
        for si, wt in zip(s, weights, strict=True)
    )
    Qd = discretised_noise(F, q, veh.T)
    np.testing.assert_allclose(Qd, quad, rtol=1e-8, atol=1e-12)
    assert np.all(np.linalg.eigvalsh(Qd) > 0)


def test_van_loan_block_matrix_and_the_kinematic_closed_form():
    """The block exponential expm([[−A, Q], [0, Aᵀ]] T) gives Φ = F and Q_d = Φ·(upper right); for a
    constant-velocity pair with density q on the velocity, Q_d = q [[T³/3, T²/2], [T²/2, T]]."""
    T, q = 0.2, 3.0
    A = np.array([[0.0, 1.0], [0.0, 0.0]])
    Qc = np.diag([0.0, q])
    M = np.block([[-A, Qc], [np.zeros((2, 2)), A.T]]) * T
    E = scipy.linalg.expm(M)
    Phi, Qd = van_loan(A, Qc, T)
    np.testing.assert_allclose(Phi, E[2:, 2:].T)
    np.testing.assert_allclose(Qd, E[2:, 2:].T @ E[:2, 2:])
    np.testing.assert_allclose(Qd, q * np.array([[T**3 / 3, T**2 / 2], [T**2 / 2, T]]), rtol=1e-12)
    # the filters' reference block (A_r cv) is this pair exactly: its rows of Q_d from a density on rdot
    veh = Vehicle1D(T=T, K=(0.0, 0.0))  # no feedback: the plant is a free constant-velocity pair too
    Qd4 = discretised_noise(transition_h0(veh, "cv"), [0.0, 0.0, 0.0, q], T)
    np.testing.assert_allclose(Qd4[2:, 2:], q * np.array([[T**3 / 3, T**2 / 2], [T**2 / 2, T]]), rtol=1e-9)


def test_small_T_limit_is_Q_times_T():
    """Q_d / T → Q_c as T → 0, the error falling like T (first order): ×10 smaller T, ~×10 smaller error.
    Its first-order term is (A Q_c + Q_c Aᵀ) T / 2: the velocity entry's relative error is k2 T."""
    q = [1e-3, 1e2, 1e-1, 1e1]
    errs = []
    for T in (1e-3, 1e-4):
        veh = Vehicle1D(T=T, K=(100.0, 17.0))  # a fixed continuous-time gain
        Qd = discretised_noise(transition_h0(veh, "cv"), q, T)
        errs.append(np.max(np.abs(Qd / T - np.diag(q))) / max(q))
    assert errs[1] < 1.2 * 17.0 * 1e-4 and 7 < errs[0] / errs[1] < 13


def test_filter_model_reads_Q_as_configured():
    veh = Vehicle1D()
    per = filter_model(veh, LMPConfig())
    np.testing.assert_array_equal(per.Q0, np.diag([1e-3, 1e2, 1e-1, 1e1]))
    assert per.Q_a == 1.0 and per.Q1.shape == (5, 5) and per.Q1[4, 4] == 1.0
    cont = filter_model(veh, LMPConfig(q_model="continuous", Q_a=2.0))
    assert cont.Q_a == pytest.approx(2.0 * veh.T)  # the amplitude's own transition is 1: Q_a T exactly
    np.testing.assert_allclose(cont.Q0, discretised_noise(per.F0, [1e-3, 1e2, 1e-1, 1e1], veh.T))
    known = filter_model(veh, LMPConfig(A_r="known", Q0=(1.0, 2.0, 3.0, 4.0)))
    np.testing.assert_array_equal(known.Q0, np.diag([1.0, 2.0]))  # the reference's entries are unused


def test_continuous_q_refuses_a_transition_without_a_real_logarithm():
    """A gain that puts an eigenvalue of F on the negative real axis has no real generator."""
    veh = Vehicle1D(K=(0.0, 50.0))  # 1 − T k2 = −1.5: a real negative eigenvalue
    with pytest.raises(ConfigError) as exc:
        filter_model(veh, LMPConfig(q_model="continuous"))
    assert exc.value.field == "q_model"
    filter_model(veh, LMPConfig())  # per step: any F


@pytest.mark.parametrize(
    ("kwargs", "field"), [({"q_model": "density"}, "q_model"), ({"A_r": "given"}, "A_r")]
)
def test_config_refusals_name_the_field(kwargs, field):
    with pytest.raises(ConfigError) as exc:
        LMPConfig(**kwargs)
    assert exc.value.field == field


def test_continuous_q_runs_the_bank_and_the_fft_path_alike():
    """q_model continuous with Q_a = 0: the projection identity (★) equals the bank (the same Q)."""
    veh = Vehicle1D(R=1e-3)
    y, _ = simulate_trials(veh, CHIPS, 20, 1.0, 300, 5, range(2))
    cfg = LMPConfig(q_model="continuous", Q_a=0.0)
    bank = lmp_detect(y, CHIPS[:1], veh, 20, cfg, [150, 300])
    proj = lmp_detect_projection(y, CHIPS[:1], veh, 20, cfg, [150, 300])
    np.testing.assert_allclose(proj.Lambda, bank.Lambda, rtol=1e-7, atol=1e-9)
    assert not np.allclose(
        bank.Lambda, lmp_detect(y, CHIPS[:1], veh, 20, LMPConfig(Q_a=0.0), [150, 300]).Lambda
    )


# ------------------------------------------------------------------------------ the known reference
def _direct_costs(y, veh, cfg, z, zd, ref):
    """J = ½ Σ ν²/S of a FilterPy Kalman filter on [x, ẋ] (H0) or [x, ẋ, a] (H1, replica z, ż), the known
    reference entering as the control term B u_k with u_k = k1 r_k + k2 ṙ_k (an independent implementation
    of the known-input model: no subtraction)."""
    T, (k1, k2) = veh.T, veh.K
    n = 2 if z is None else 3
    kf = KalmanFilter(dim_x=n, dim_z=1, dim_u=1)
    F = np.eye(n)
    F[:2, :2] = transition_h0(veh, "known")
    kf.B = np.zeros((n, 1))
    kf.B[1, 0] = T
    kf.H = np.zeros((1, n))
    kf.H[0, 0] = 1.0
    kf.R = np.array([[cfg.c_r * veh.R]])
    kf.Q = np.diag([*cfg.Q0[:2], cfg.Q_a][:n])
    kf.x = np.zeros((n, 1))
    kf.P = cfg.P0 * np.eye(n)
    J = 0.0
    for k in range(y.size):
        kf.update(np.array([[y[k]]]))
        J += 0.5 * float(kf.y[0, 0] ** 2 / kf.S[0, 0])
        if z is not None:
            F[1, 2] = amplitude_column(veh, z[k], zd[k])
        kf.F = F.copy()
        kf.predict(u=np.array([[k1 * ref[k, 0] + k2 * ref[k, 1]]]))
    return J


def test_known_reference_equals_the_direct_control_input_implementation():
    """A_r known: the bank (the known input's response subtracted from y) gives J0, J_cos, J_sin of the
    Kalman filters that carry the reference as B u_k."""
    veh = Vehicle1D(R=1e-3, f_r=0.1)
    N = 160
    y, _ = simulate_trials(veh, CHIPS, 20, 1.0, N, 7, range(1))
    cfg = LMPConfig(A_r="known", Q0=(1e-4, 1e-1, 0.0, 0.0), Q_a=0.1)
    res = lmp_detect(y, CHIPS[:1], veh, 20, cfg, [N])
    ref = nominal_reference(veh, np.arange(N) * veh.T)
    assert _direct_costs(y[0], veh, cfg, None, None, ref) == pytest.approx(res.J0[0, 0], rel=1e-9)
    c = res.candidates
    zc, zs, dc, ds = replica_bank(CHIPS[:1], c.mode, c.tau, c.f_c, veh.T, 20, N)
    for j in (0, 7):
        assert _direct_costs(y[0], veh, cfg, zc[j], dc[j], ref) == pytest.approx(res.J_cos[j, 0, 0], rel=1e-9)
        assert _direct_costs(y[0], veh, cfg, zs[j], ds[j], ref) == pytest.approx(res.J_sin[j, 0, 0], rel=1e-9)


def test_known_reference_is_the_vehicles_or_the_one_given():
    veh = Vehicle1D(R=1e-3, f_r=0.1)
    y, _ = simulate_trials(veh, CHIPS, 20, 1.0, 200, 3, range(2))
    cfg = LMPConfig(A_r="known")
    ref = nominal_reference(veh, np.arange(200) * veh.T)
    a = lmp_detect(y, CHIPS[:1], veh, 20, cfg, [200])
    b = lmp_detect(y, CHIPS[:1], veh, 20, cfg, [200], reference=np.stack([ref, ref]))
    np.testing.assert_array_equal(a.Lambda, b.Lambda)
    other = lmp_detect(y, CHIPS[:1], veh, 20, cfg, [200], reference=0 * ref)
    assert not np.allclose(a.J0, other.J0)
    with pytest.raises(ValueError, match="A_r='known' only"):
        known_input_removed(y, veh, LMPConfig(), ref)
    with pytest.raises(ValueError, match=r"\(200, 2\)"):
        known_input_removed(y, veh, cfg, ref[:10])


def test_known_reference_fft_path_in_step_with_the_bank():
    """Q_a = 0 with a known reference: (★) with the time-varying filter equals the bank; the FFT path
    (steady state) agrees to its approximation and picks the same argmax."""
    veh = Vehicle1D(R=1e-3, f_r=1.0)
    y, _ = simulate_trials(veh, CHIPS, 20, 1.0, 800, 11, range(3))
    cfg = LMPConfig(A_r="known", Q_a=0.0)
    bank = lmp_detect(y, CHIPS, veh, 20, cfg, [400, 800])
    proj = lmp_detect_projection(y, CHIPS, veh, 20, cfg, [400, 800])
    fft = lmp_detect_fft(y, CHIPS, veh, 20, cfg, [400, 800])
    np.testing.assert_allclose(proj.Lambda, bank.Lambda, rtol=1e-7, atol=1e-9)
    # the steady-state approximation: a few % of Λ at 20 s (the relative error falls like 1/horizon)
    assert np.max(np.abs(fft.Lambda - bank.Lambda)) < 0.05 * np.max(np.abs(bank.Lambda))
    np.testing.assert_array_equal(fft.best()[0], bank.best()[0])


# ------------------------------------------------------------------------------ the carrier offset
def test_matched_carrier_grid_finds_the_offset():
    """f_d = ±0.02, −0.04 Hz: with the filters' model matched to the truth (known reference, small Q,
    Q_a = 0, c_r = 1) the carrier grid's argmax is the true carrier f_c + f_d in every trial, with mode and
    code phase right; the same records on the f_c grid alone score far lower."""
    grid = tuple(1.0 + d for d in carrier_offsets(-0.06, 0.06, 7))
    cfg = LMPConfig(fc_grid=grid, A_r="known", Q_a=0.0, Q0=(1e-6, 1e-4, 0.0, 0.0), c_r=1.0)
    for f_d in (0.02, -0.02, -0.04):
        veh = Vehicle1D(R=1e-3, f_d=f_d)
        y, draws = simulate_trials(veh, CHIPS, 20, 1.0, 1600, 3, range(3))
        res = lmp_detect_fft(y, CHIPS, veh, 20, cfg, [1600])
        best = res.best()[0][:, 0]
        c = res.candidates
        np.testing.assert_allclose(c.f_c[best], 1.0 + f_d, atol=1e-12)
        assert [(int(c.mode[b]), int(c.tau[b])) for b in best] == [(d.mode, d.tau) for d in draws]
        only_fc = lmp_detect_fft(y, CHIPS, veh, 20, LMPConfig(**{**_fields(cfg), "fc_grid": (1.0,)}), [1600])
        assert np.all(only_fc.best()[1] < 0.2 * res.best()[1])


def _fields(cfg: LMPConfig) -> dict:
    return {name: getattr(cfg, name) for name in cfg.__slots__}


def test_carrier_offsets_grid():
    assert carrier_offsets(-0.1, 0.1, 3) == (-0.1, 0.0, 0.1) and carrier_offsets(0.5, 0.5, 1) == (0.5,)
    for args in ((0.1, -0.1, 3), (0, 1, 0), (0, 1, 2.5), (0, math.inf, 3)):
        with pytest.raises(ValueError):
            carrier_offsets(*args)


@pytest.mark.parametrize("cfg", [LMPConfig(A_r="known"), LMPConfig(q_model="continuous")])
def test_sigma_point_bank_follows_the_model_options(cfg):
    """The sigma-point bank is exact on this linear model: it reproduces the Kalman bank with a known
    reference (2- and 3-state filters) and with a continuous-time Q (full Q matrices)."""
    veh = Vehicle1D(R=1e-3)
    y, _ = simulate_trials(veh, CHIPS, 20, 1.0, 200, 1, range(2))
    kf = lmp_detect(y, CHIPS[:1], veh, 20, cfg, [100, 200])
    ukf = lmp_detect(y, CHIPS[:1], veh, 20, cfg, [100, 200], filter="ukf")
    np.testing.assert_allclose(ukf.Lambda, kf.Lambda, rtol=1e-9, atol=1e-10)
