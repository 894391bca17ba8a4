"""The 1-D vehicle's carrier offset f_d (eq 3) and its feedback on the state estimate (eq 5): the controller
sees only the onboard estimate, which is a Kalman filter of the vehicle's own sensor (checked against
FilterPy, an independent implementation), and the configuration checks name their field."""

import math

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter

from motionsig_cli.config import ConfigError
from motionsig_cli.models.vehicle import Vehicle1D, reference_response, simulate_1d, transition_h0

N = 120


def _draws(seed: int, B: int = 2) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    return tuple(rng.standard_normal((B, N)) for _ in range(5))


def test_estimate_feedback_controller_sees_only_the_estimate():
    """u_k = K(−x̂_k + r_k + a[z_k, ż_k]) at every step, with x̂ ≠ x: the loop feeds back the estimate."""
    cfg = Vehicle1D(R=1e-2, sigma_a=0.5, f_r=0.1, feedback="estimate")
    z, zd, w, v, v_own = _draws(1)
    sim = simulate_1d(cfg, z, zd, w, v, v_own)
    k1, k2 = cfg.K
    r, xh, x = sim["r"], sim["xhat"], sim["x"]
    u = k1 * (-xh[..., 0] + r[:, 0] + cfg.a_sig * z) + k2 * (-xh[..., 1] + r[:, 1] + cfg.a_sig * zd)
    np.testing.assert_allclose(sim["u"], u, rtol=0, atol=1e-9)
    u_true = k1 * (-x[..., 0] + r[:, 0] + cfg.a_sig * z) + k2 * (-x[..., 1] + r[:, 1] + cfg.a_sig * zd)
    assert np.max(np.abs(sim["u"] - u_true)) > 1.0  # the estimate's error moves the control input
    # the observer's measurement is the truth plus its own noise, not the onboard sensor's
    np.testing.assert_allclose(sim["y"], x[..., 0] + math.sqrt(cfg.R) * v)


def test_onboard_estimator_is_the_kalman_filter_of_the_own_sensor():
    """x̂_{k|k} equals FilterPy's KalmanFilter on y_own = x + √R v_own with the known input B u_k."""
    cfg = Vehicle1D(R=1e-2, sigma_a=0.3, f_r=0.1, feedback="estimate")
    z, zd, w, v, v_own = _draws(2, B=1)
    sim = simulate_1d(cfg, z, zd, w, v, v_own)
    T = cfg.T
    kf = KalmanFilter(dim_x=2, dim_z=1, dim_u=1)
    kf.F = np.array([[1.0, T], [0.0, 1.0]])
    kf.B = np.array([[0.0], [T]])
    kf.H = np.array([[1.0, 0.0]])
    kf.R = np.array([[cfg.R]])
    G = np.array([[T**2 / 2], [T]])
    kf.Q = cfg.sigma_a**2 * G @ G.T
    kf.x = np.zeros((2, 1))
    kf.P = np.zeros((2, 2))  # the initial state is known exactly
    y_own = sim["x"][0, :, 0] + math.sqrt(cfg.R) * v_own[0]
    for k in range(N):
        kf.update(np.array([[y_own[k]]]))
        np.testing.assert_allclose(kf.x[:, 0], sim["xhat"][0, k], rtol=1e-9, atol=1e-12)
        kf.predict(u=np.array([[sim["u"][0, k]]]))


def test_estimate_feedback_needs_the_own_sensor_and_true_feedback_ignores_it():
    z, zd, w, v, v_own = _draws(3)
    with pytest.raises(ValueError, match="v_own"):
        simulate_1d(Vehicle1D(feedback="estimate"), z, zd, w, v)
    a = simulate_1d(Vehicle1D(), z, zd, w, v)
    b = simulate_1d(Vehicle1D(), z, zd, w, v, v_own)
    assert "xhat" not in a and np.array_equal(a["y"], b["y"])


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [({"feedback": "observer"}, "feedback"), ({"f_d": math.nan}, "f_d"), ({"f_d": math.inf}, "f_d")],
)
def test_bad_options_name_their_field(kwargs, field):
    with pytest.raises(ConfigError) as exc:
        Vehicle1D(**kwargs)
    assert exc.value.field == field


def test_negative_offset_is_a_vehicle_value():
    """f_d < 0 is legitimate (a receiver clock fast or slow); f_c + f_d >= 0 is checked where f_c is known."""
    assert Vehicle1D(f_d=-0.05).f_d == -0.05


def test_reference_response_is_the_plant_response_to_the_known_input():
    """H m_k of m_{k+1} = (A − BK) m_k + B K r_k, against a direct state-space loop."""
    cfg = Vehicle1D(f_r=0.3, a_r=2.0)
    rng = np.random.default_rng(4)
    ref = rng.standard_normal((3, 50, 2))
    F = transition_h0(cfg, "known")
    Bu = np.array([0.0, cfg.T])
    k = np.array(cfg.K)
    for b in range(3):
        m = np.zeros(2)
        out = []
        for j in range(50):
            out.append(m[0])
            m = F @ m + Bu * (k @ ref[b, j])
        np.testing.assert_allclose(reference_response(cfg, ref)[b], out, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(reference_response(cfg, ref[1]), reference_response(cfg, ref)[1])
