"""Missing samples in the sigma-point bank: a NaN [range, bearing] row is a predict-only step, per record.

Oracle: FilterPy's UnscentedKalmanFilter (MerweScaledSigmaPoints, the bearing averaged about the central
point and wrapped, as the bank does), run step by step, the update skipped where the row is NaN. FilterPy
keeps the predicted sigma points for the update; the bank draws new ones from the predicted (x, P) (the
filter of the module docstring), so the oracle redraws them before each update.
"""

import math

import numpy as np
import pytest

from motionsig_cli.detection.lmp import RadarLMPConfig, lmp_detect_radar, radar_measurement
from motionsig_cli.filters import unscented as U
from motionsig_cli.filters.kalman import MissingSamples
from motionsig_cli.models.vehicle2d import (
    AMPLITUDE_ENTRIES_2D,
    Q0_2D,
    Q1_2D,
    Vehicle2D,
    prior_mean_2d,
    transition_h0_2d,
    transition_h1_2d_base,
)
from motionsig_cli.modesig.lmp1d import table1_chips
from motionsig_cli.modesig.lmp2d import simulate_trials_2d

VEH = Vehicle2D(R_range=3e-4, R_bearing=5e-4)
C_R = 1.0


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def _records(B: int, N: int, seed: int) -> np.ndarray:
    sim, _ = simulate_trials_2d(VEH, table1_chips(), 20, 1.0, N, seed, list(range(B)))
    return sim["y"]


def _gaps(y: np.ndarray, seed: int, frac: float = 0.15) -> np.ndarray:
    y = np.array(y)
    rng = np.random.default_rng(seed)
    y[rng.random(y.shape[0]) < frac] = np.nan
    y[0] = y[50:56] = np.nan
    return y


def _filterpy(Fs, Q, x0, P0, R, y, params):
    """FilterPy's UKF from the predicted prior: per sample, redraw the sigma points, update unless the row is
    NaN (J += ½ νᵀS⁻¹ν), predict with F_k. Returns J after every sample and the final (x, P)."""
    from filterpy.kalman import MerweScaledSigmaPoints, UnscentedKalmanFilter

    n = x0.size

    def hx(s):
        return np.array([math.hypot(s[0], s[2]), math.atan2(s[2], s[0])])

    def z_mean(sigmas, Wm):
        d = sigmas - sigmas[0]
        d[:, 1] = _wrap(d[:, 1])
        m = sigmas[0] + Wm @ d
        m[1] = _wrap(m[1])
        return m

    def residual_z(a, b):
        d = np.asarray(a, float) - b
        d[1] = _wrap(d[1])
        return d

    pts = MerweScaledSigmaPoints(n, params.alpha, params.beta, params.kappa)
    ukf = UnscentedKalmanFilter(
        dim_x=n,
        dim_z=2,
        dt=VEH.T,
        hx=hx,
        fx=lambda x, dt: x,
        points=pts,
        z_mean_fn=z_mean,
        residual_z=residual_z,
    )
    ukf.x, ukf.P, ukf.Q, ukf.R = x0.copy(), P0.copy(), Q, R
    J, out = 0.0, []
    for k, yk in enumerate(y):
        if not np.isnan(yk).any():
            ukf.sigmas_f = pts.sigma_points(ukf.x, ukf.P)
            ukf.update(yk)
            J += 0.5 * float(ukf.y @ ukf.SI @ ukf.y)
        out.append(J)
        if k + 1 < len(y):
            Fk = Fs(k)
            ukf.predict(fx=lambda x, dt, F=Fk: F @ x)
    return np.array(out), ukf.x, ukf.P


@pytest.mark.parametrize("params", [U.SigmaPointParams(), U.SigmaPointParams(0.5, 2.0, 1.0)])
def test_h0_and_h1_filters_equal_filterpy_with_predict_only_rows(params):
    """The radar H0 filter (8 states) and two H1 filters (10 states, time-varying amplitude entries) of the
    bank on a record with NaN rows: J after every sample and the final state and covariance equal FilterPy's
    UKF, to 1e-9 relative (measured ~1e-14; FilterPy predicts through the UT, the bank in closed form)."""
    N = 160
    y = _gaps(_records(1, N, 3)[0], 1)
    assert 20 < np.isnan(y[:, 0]).sum() < 50
    meas = radar_measurement(VEH, C_R)
    R = C_R * np.diag([VEH.R_range, VEH.R_bearing])
    cases = []
    F0 = transition_h0_2d(VEH.T, VEH.K)
    x0 = prior_mean_2d(VEH.start, False)
    cases.append((U.StructuredTransition.constant(F0, N), np.diag(Q0_2D), x0, [lambda k: F0]))
    g = 0.4 * np.random.default_rng(2).normal(size=(2, N, 2))
    tr1 = U.StructuredTransition(transition_h1_2d_base(VEH.T, VEH.K), AMPLITUDE_ENTRIES_2D, g)
    x1 = prior_mean_2d(VEH.start, True)
    cases.append((tr1, np.diag(Q1_2D), x1, [lambda k, c=c: tr1.dense(k)[c] for c in range(2)]))
    for trans, Q, xp, Fs in cases:
        n = xp.size
        res = U.ukf_bank_costs(trans, Q, meas, xp, np.eye(n), y[None], list(range(1, N + 1)), params)
        assert res.repairs_P == res.repairs_S == 0
        for c, F_of in enumerate(Fs):
            J, x, P = _filterpy(F_of, Q, xp, np.eye(n), R, y, params)
            np.testing.assert_allclose(res.J[c, 0], J, rtol=1e-9, atol=0)
            np.testing.assert_allclose(res.x[c, 0], x, rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(res.P[c, 0], P, rtol=0, atol=1e-9 * np.abs(P).max())
            assert np.all(np.diff(res.J[c, 0])[np.isnan(y[1:, 0])] == 0)


def test_per_record_mask_equals_each_record_alone():
    """Records with different gaps in one bank (the mask is per record and step): each equals the record run
    alone to 1e-12; a record with every sample present is unchanged by the others' gaps."""
    N = 120
    y = _records(3, N, 4)
    y[0] = _gaps(y[0], 2)
    y[1] = _gaps(y[1], 3, frac=0.4)
    cfg = RadarLMPConfig(c_r=C_R)
    both = lmp_detect_radar(y, table1_chips(), VEH, 20, cfg, [60, N])
    for b in range(3):
        one = lmp_detect_radar(y[b], table1_chips(), VEH, 20, cfg, [60, N])
        np.testing.assert_allclose(both.Lambda[:, b], one.Lambda[:, 0], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(both.J0[b], one.J0[0], rtol=1e-12)
    assert not np.allclose(both.J0[0], both.J0[2], rtol=0.1)


def test_a_record_with_every_row_missing_only_predicts():
    """No update at all: J = 0 and the final state is the prior propagated by F0 (P by F0 P F0ᵀ + Q)."""
    N = 30
    F0 = transition_h0_2d(VEH.T, VEH.K)
    x0 = prior_mean_2d(VEH.start, False)
    y = np.full((1, N, 2), np.nan)
    res = U.ukf_bank_costs(
        U.StructuredTransition.constant(F0, N), np.diag(Q0_2D), radar_measurement(VEH, C_R), x0, np.eye(8), y,
        [N], U.SigmaPointParams(),
    )  # fmt: skip
    x, P = x0.copy(), np.eye(8)
    for _ in range(N - 1):
        x, P = F0 @ x, F0 @ P @ F0.T + np.diag(Q0_2D)
    assert np.all(res.J == 0) and np.all(res.half_logdet == 0)
    np.testing.assert_allclose(
        res.x[0, 0], x, rtol=1e-12, atol=1e-12 * np.abs(x).max()
    )  # closed form vs matmul
    np.testing.assert_allclose(res.P[0, 0], P, rtol=1e-12, atol=1e-12 * np.abs(P).max())


def test_a_row_with_one_component_missing_is_refused_naming_it():
    y = _records(2, 40, 5)
    y[1, 17, 1] = np.nan  # bearing missing, range present
    with pytest.raises(MissingSamples, match="another component of the sample is missing") as err:
        lmp_detect_radar(y, table1_chips(), VEH, 20, RadarLMPConfig(), [40])
    assert (err.value.index, err.value.trial, err.value.column) == (17, 1, 0)
