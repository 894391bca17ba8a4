"""solve_epoch (one multilateration epoch from arrays): exact times recover the truth; with noise the
weighted least-squares statistics are the theory's (χ² of K − 4 degrees of freedom, the covariance of
eq 4.5.3 that of the fixes); a bad argument is a ConfigError naming it."""

from __future__ import annotations

import numpy as np
import pytest

from motionsig_cli import ConfigError, solve_epoch
from motionsig_cli.geodesy import enu_to_ecef

C = 299_792_458.0
ENU = np.array([[-1e4, -8e3, 0], [1.2e4, -1e4, 50], [9e3, 1.1e4, -30], [-7e3, 9e3, 100], [0, 1.5e4, 20],
                [1.5e4, 0, 10]], float)  # fmt: skip
S = enu_to_ecef(ENU, 45.0, 0.0, 0.0)
P = enu_to_ecef(np.array([1000.0, 2000.0, 5000.0]), 45.0, 0.0, 0.0)
TAU = 12.5  # emission time [s]


def _toa() -> np.ndarray:
    return TAU + np.linalg.norm(S - P, axis=1) / C


def test_exact_times_recover_the_transmitter() -> None:
    fix = solve_epoch(S, _toa())
    assert np.linalg.norm(fix.position - P) < 1e-3  # [m]
    assert abs(fix.emission_time - TAU) < 1e-11
    assert fix.converged and fix.n_used == 6 and fix.chi2 < 1e-6


def test_a_missing_time_drops_its_receiver() -> None:
    toa = _toa()
    toa[2] = np.nan
    fix = solve_epoch(S, toa)
    assert fix.n_used == 5 and np.isnan(fix.residuals[2]) and np.linalg.norm(fix.position - P) < 1e-3


def test_noisy_fixes_follow_the_least_squares_theory() -> None:
    rng = np.random.default_rng(7)
    sigma = 3e-9  # [s] (0.9 m)
    fixes = [solve_epoch(S, _toa() + sigma * rng.standard_normal(6), sigma=sigma) for _ in range(400)]
    chi2 = np.array([f.chi2 for f in fixes])
    assert abs(chi2.mean() - 2.0) < 0.35  # χ²_{K-4}: mean 2, standard error 2/√400 = 0.1
    err = np.array([f.position - P for f in fixes])
    emp = np.cov(err.T)
    model = fixes[0].covariance[:3, :3]
    ratio = np.trace(emp) / np.trace(model)
    assert 0.85 < ratio < 1.15  # trace of the empirical covariance (400 fixes: ±~10 %)


@pytest.mark.parametrize(
    ("args", "kwargs", "field"),
    [
        ((S[:, :2], np.zeros(6)), {}, "receivers"),
        ((S, np.zeros(5)), {}, "toa"),
        ((S, np.zeros(6)), {"sigma": -1.0}, "sigma"),
        ((S[:3], np.zeros(3)), {}, "receivers"),  # 3 receivers cannot fix position and clock
    ],
)
def test_bad_arguments_name_their_field(args, kwargs, field) -> None:
    with pytest.raises(ConfigError) as exc:
        solve_epoch(*args, **kwargs)
    assert exc.value.field == field
