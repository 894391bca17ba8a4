"""The trackers on irregular times (each step its own Δt) and their consistency checks.

Oracles: the regular-grid recursion itself (Δt = T at every step must give it to rounding), FilterPy's
KalmanFilter and IMMEstimator run step by step with the per-step F, Q and Π (an independent implementation),
and bounds that hold by construction (no speed above the stated limit after the checks)."""

import numpy as np
import pytest
from filterpy.kalman import IMMEstimator, KalmanFilter

from motionsig_cli.detection.glr import GLRConfig, InputModel, input_tracker
from motionsig_cli.filters.consistency import REASONS, Consistency
from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.models.motion import (
    H_POS4,
    H_POS6,
    aircraft_models,
    cv_input_model,
    cv_input_steps,
    imm_models,
    two_point_init,
)


def _turning(n: int, seed: int, irregular: bool = True, sigma: float = 10.0):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.3, 1.7, n)) if irregular else np.arange(n, dtype=float)
    w = np.deg2rad(3.0) * ((t > t[n // 3]) & (t < t[n // 2]))  # a 3°/s turn in the middle
    heading = np.concatenate([[0.0], np.cumsum(w[1:] * np.diff(t))])
    v = 200.0 * np.stack([np.cos(heading), np.sin(heading)], axis=1)
    pos = np.concatenate([[[0.0, 0.0]], np.cumsum(v[1:] * np.diff(t)[:, None], axis=0)])
    return t, pos + sigma * rng.standard_normal(pos.shape)


def _input_model(q0: float = 0.5) -> InputModel:
    F, G, Q = cv_input_model(1.0, q0)
    return InputModel(F, G, Q, H_POS4, 100.0 * np.eye(2), steps=lambda d: cv_input_steps(d, q0))


@pytest.mark.parametrize("method", ["glr", "mlr", "none"])
def test_input_tracker_with_a_constant_step_is_the_regular_recursion(method):
    _t, z = _turning(300, 1, irregular=False)
    x0, P0 = two_point_init(z[0], z[1], 1.0, 10.0, n=4)
    cfg = GLRConfig(method=method)
    reg = input_tracker(z[None, 2:], _input_model(), x0, P0, cfg)
    irr = input_tracker(z[None, 2:], _input_model(), x0, P0, cfg, dt=np.ones(298))
    np.testing.assert_allclose(irr.x, reg.x, rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(irr.detected, reg.detected)
    np.testing.assert_array_equal(irr.onset, reg.onset)


@pytest.mark.parametrize("models", [imm_models(1.0), aircraft_models()], ids=["paper", "aircraft"])
def test_imm_with_a_constant_step_is_the_regular_recursion(models):
    _t, z = _turning(300, 2, irregular=False)
    x0, P0 = two_point_init(z[0], z[1], 1.0, 10.0)
    reg = imm_filter(z[2:], H_POS6, 100.0, models, x0, P0)
    irr = imm_filter(z[2:], H_POS6, 100.0, models, x0, P0, dt=np.ones(298))
    np.testing.assert_allclose(irr.x, reg.x, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(irr.mu, reg.mu, rtol=1e-10, atol=1e-14)


def test_the_reference_filter_equals_filterpy_with_per_step_F_and_Q():
    """GLR's H0 filter (method 'none': no detection) on irregular times against FilterPy's KalmanFilter
    given F(Δt_k) and Q(Δt_k) at every predict: equal to 1e-10 (relative to the track's scale)."""
    t, z = _turning(400, 3)
    x0, P0 = two_point_init(z[0], z[1], t[1] - t[0], 10.0, n=4)
    dt = np.diff(t)[1:]
    ours = input_tracker(z[None, 2:], _input_model(0.7), x0, P0, GLRConfig(method="none"), dt=dt[None])
    kf = KalmanFilter(dim_x=4, dim_z=2)
    kf.x, kf.P, kf.H, kf.R = x0.copy(), P0.copy(), H_POS4, 100.0 * np.eye(2)
    ref = []
    for k in range(z.shape[0] - 2):
        F, _, Q = cv_input_steps(np.float64(dt[k]), 0.7)
        kf.predict(F=F, Q=Q)
        kf.update(z[k + 2])
        ref.append(kf.x.copy())
    scale = np.abs(np.array(ref)).max()
    np.testing.assert_allclose(ours.x[0], np.array(ref), rtol=0, atol=1e-10 * scale)


def test_the_imm_equals_filterpy_with_per_step_models_and_switching():
    """The IMM with the aircraft models on irregular times against FilterPy's IMMEstimator given, at every
    step, each filter's F(Δt) and Q(Δt) and the transition matrix Π(Δt): states and model probabilities equal
    to 1e-10."""
    t, z = _turning(300, 4)
    ms = aircraft_models()
    x0, P0 = two_point_init(z[0], z[1], t[1] - t[0], 10.0)
    dt = np.diff(t)[1:]
    ours = imm_filter(z[2:], H_POS6, 100.0, ms, x0, P0, dt=dt)
    filters = []
    for _ in range(3):
        f = KalmanFilter(dim_x=6, dim_z=2)
        f.x, f.P, f.H, f.R = x0.copy(), P0.copy(), H_POS6, 100.0 * np.eye(2)
        filters.append(f)
    imm = IMMEstimator(filters, np.asarray(ms.mu0), np.asarray(ms.Pi))
    xs, mus = [], []
    for k in range(z.shape[0] - 2):
        Phi, Qd, Pi = ms.steps(np.float64(dt[k]))
        for j, f in enumerate(filters):
            f.F, f.Q = Phi[j], Qd[j]
        imm.M = Pi
        imm._compute_mixing_probabilities()  # FilterPy mixes with the Π set at its last update: use Π(Δt_k)
        imm.predict()
        imm.update(z[k + 2])
        xs.append(imm.x.copy())
        mus.append(imm.mu.copy())
    scale = np.abs(np.array(xs)).max()
    np.testing.assert_allclose(ours.x, np.array(xs), rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(ours.mu, np.array(mus), rtol=0, atol=1e-10)


@pytest.mark.parametrize("which", ["imm", "glr", "mlr", "none"])
def test_stale_repeats_and_outliers_never_make_a_state_grow_without_bound(which):
    """A track with stale repeats (20 % of the positions are the previous one), 1 % outliers of 3 km and a
    5 km jump: with the checks, every output speed stays within max_speed and every acceleration within
    max_accel at the measured steps; outliers are gated, the jump restarts the track (and says why)."""
    t, z = _turning(1500, 5, sigma=5.0)
    rng = np.random.default_rng(6)
    stale = np.flatnonzero(rng.random(z.shape[0]) < 0.2)
    stale = stale[stale > 2]
    z[stale] = z[stale - 1]
    out = np.flatnonzero(rng.random(z.shape[0]) < 0.01)
    out = out[out > 2]
    z[out] += 3000.0
    z[900:] += 5000.0
    cons = Consistency()
    dt = np.diff(t)[1:]
    if which == "imm":
        x0, P0 = two_point_init(z[0], z[1], t[1] - t[0], 5.0)
        tr = imm_filter(z[2:], H_POS6, 25.0, aircraft_models(), x0, P0, dt=dt, consistency=cons)
        speed, acc = np.hypot(tr.x[:, 1], tr.x[:, 3]), np.hypot(tr.x[:, 4], tr.x[:, 5])
        gated, reinit = tr.gated, tr.reinit
    else:
        x0, P0 = two_point_init(z[0], z[1], t[1] - t[0], 5.0, n=4)
        m = _input_model()
        tr = input_tracker(z[None, 2:], m, x0, P0, GLRConfig(method=which), dt=dt[None], consistency=cons)
        speed = np.hypot(tr.x[0, :, 1], tr.x[0, :, 3])
        acc = np.hypot(tr.u_cur[0, :, 0], tr.u_cur[0, :, 1])
        gated, reinit = tr.gated[0], tr.reinit[0]
    assert np.all(speed <= cons.max_speed) and np.all(acc <= cons.max_accel)
    assert gated.sum() >= 0.5 * out.size  # most outliers are gated (some fall on a restart)
    assert np.any(reinit[895:905] > 0)  # the jump restarts the track near where it happens
    jump = {REASONS[int(c)] for c in reinit[895:905] if c}
    assert jump & {"outliers", "nis", "speed"} and "covariance" not in jump  # the jump's reason, named


def test_without_the_checks_a_consistent_filter_never_restarts_and_gates_at_its_rate():
    """On a clean constant-velocity track with the model's own noise, the gate (p = 1e-9) rejects nothing
    and the windowed NIS test (α = 1e-4 per test) restarts nothing in 2000 steps; the NIS mean is 2 ± 4 SE."""
    rng = np.random.default_rng(8)
    t = np.cumsum(rng.uniform(0.4, 0.6, 2000))
    pos = np.stack([150.0 * t, -80.0 * t], axis=1)
    z = pos + 10.0 * rng.standard_normal(pos.shape)
    x0, P0 = two_point_init(z[0], z[1], t[1] - t[0], 10.0, n=4)
    tr = input_tracker(z[None, 2:], _input_model(1e-6), x0, P0, GLRConfig(method="none"),
                       dt=np.diff(t)[1:][None], consistency=Consistency())  # fmt: skip
    nis = tr.nis[0]
    assert tr.gated.sum() == 0 and tr.reinit.sum() == 0
    se = nis.std(ddof=1) / np.sqrt(nis.size)  # correlated by the filter's start only
    assert abs(nis[50:].mean() - 2.0) < 4 * se


def test_a_bad_setting_names_its_field():
    from motionsig_cli.config import ConfigError

    for kw, field in (({"gate": 0.0}, "gate"), ({"window": 0}, "window"), ({"max_speed": -1.0}, "max_speed")):
        with pytest.raises(ConfigError) as exc:
            Consistency(**kw)
        assert exc.value.field == field
