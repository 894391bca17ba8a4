"""Fault detection and exclusion against injected faults: false-alarm and detection rates at their stated
values (Monte Carlo with fixed seeds, within 4 standard errors), the faulty receiver identified, and the
exclusion only while a testable set remains. The geometry: the seven GPS satellites of the real record's
first epoch (tests/data/gnss) seen from its ground-truth position, with their σ."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from motionsig_cli.config import ConfigError
from motionsig_cli.geodesy import geodetic_to_ecef
from motionsig_cli.surveillance.fault_exclusion import (
    FaultExclusion,
    chi2_threshold,
    exclude_faults,
    standardised_residuals,
)
from motionsig_cli.surveillance.toa_fix import solve_snapshot

DATA = Path(__file__).resolve().parents[1] / "data" / "gnss" / "gsdc2022_mtv.csv"
N = 4000


@pytest.fixture(scope="module")
def geometry():
    rows = [r for r in csv.DictReader(open(DATA, newline="")) if r["epoch"] == "0"]
    S = np.array([[float(r[a]) for a in "xyz"] for r in rows])
    sig = np.array([float(r["sigma"]) for r in rows])
    p = geodetic_to_ecef(37.3958171, -122.102916, -4.488)
    return S, sig, p


def _run(geometry, seed, fault=None, p_fa=0.01):
    S, sig, p = geometry
    K = len(sig)
    rng = np.random.default_rng(seed)
    SS = np.broadcast_to(S, (N, K, 3))
    sg = np.broadcast_to(sig, (N, K))
    rho = np.linalg.norm(p - S, axis=-1) + 1234.5 + sig * rng.standard_normal((N, K))
    if fault is not None:
        k, f = fault
        rho[:, k] += f

    def solve(r, idx):
        return solve_snapshot(r, SS[idx], sigma=sg[idx], on_failure="flag")

    out = exclude_faults(rho, SS, sg, solve, FaultExclusion(p_fa=p_fa))
    _run.last_rho = rho
    return out


def _leverage(geometry):
    S, sig, p = geometry
    fix = solve_snapshot((np.linalg.norm(p - S, axis=-1))[None], S, sigma=sig)
    d = fix.position[0] - S
    U = d / np.linalg.norm(d, axis=1)[:, None]
    A = np.c_[U, np.ones(len(S))] / sig[:, None]
    return np.diag(A @ np.linalg.solve(A.T @ A, A.T))


def _within_4se(rate, p, n=N):
    return abs(rate - p) <= 4 * np.sqrt(p * (1 - p) / n)


@pytest.mark.parametrize("p_fa", [0.01, 0.05])
def test_the_false_alarm_rate_is_the_stated_one(geometry, p_fa):
    r = _run(geometry, 1 + int(100 * p_fa), p_fa=p_fa)
    alarms = np.mean(r.first_statistic > r.first_threshold)
    assert _within_4se(alarms, p_fa), alarms  # measured 0.0090 (p_fa 0.01), 0.0488 (0.05)
    assert np.mean(r.excluded.any(axis=1)) == pytest.approx(alarms)  # every alarm excludes one
    np.testing.assert_allclose(r.first_threshold, stats.chi2.isf(p_fa, 3))


def test_the_detection_rate_is_the_noncentral_chi_square_one(geometry):
    """A bias f on satellite k: P_D = P(χ²(3, λ) > T), λ = (f/σ_k)² (1 − h_kk)."""
    _, sig, _ = geometry
    h = _leverage(geometry)
    k, p_fa = 2, 0.01
    thr = float(chi2_threshold(np.array([3]), p_fa)[0])
    for target in (0.5, 0.9):
        # the fault that gives the target detection rate
        lam = _solve_lambda(thr, target)
        f = sig[k] * np.sqrt(lam / (1 - h[k]))
        r = _run(geometry, 7 + int(10 * target), fault=(k, f), p_fa=p_fa)
        pd = np.mean(r.first_statistic > r.first_threshold)
        expected = stats.ncx2.sf(thr, 3, lam)
        assert _within_4se(pd, expected), (
            target,
            pd,
            expected,
        )  # measured 0.497 (f = 28.6 m), 0.899 (41.2 m)


def _solve_lambda(thr, target):
    from scipy.optimize import brentq

    return brentq(lambda lam: stats.ncx2.sf(thr, 3, lam) - target, 1e-6, 1e4)


def test_a_large_fault_is_excluded_and_named_and_the_fix_recovers(geometry):
    S, sig, _ = geometry
    h = _leverage(geometry)
    for k in range(len(sig)):
        f = 12 * sig[k] / np.sqrt(1 - h[k])  # λ = 144: detected with certainty
        r = _run(geometry, 100 + k, fault=(k, f), p_fa=1e-3)
        assert np.mean(r.first_statistic > r.first_threshold) > 0.999
        right = np.mean(r.excluded[:, k] & (r.excluded.sum(axis=1) == 1))
        assert right > 0.95, (k, right)  # measured 0.970 to 1.000 over the seven satellites
        # where it is excluded, the fix is the least-squares fix of the other six
        sel = np.flatnonzero(r.excluded[:, k] & (r.excluded.sum(axis=1) == 1))
        rho6 = _run.last_rho[sel].copy()
        rho6[:, k] = np.nan
        ref = solve_snapshot(rho6, S, sigma=sig)
        assert np.max(np.linalg.norm(r.fix.position[sel] - ref.position, axis=1)) < 1e-6


def test_exclusion_stops_when_no_testable_set_remains(geometry):
    """Five receivers: a fault is detected but not excluded (four cannot confirm it): the fix is flagged."""
    S, sig, p = geometry
    S5, s5 = S[:5], sig[:5]
    rng = np.random.default_rng(5)
    rho = np.linalg.norm(p - S5, axis=-1)[None] + s5 * rng.standard_normal((50, 5))
    rho[:, 1] += 3000.0
    SS, sg = np.broadcast_to(S5, (50, 5, 3)), np.broadcast_to(s5, (50, 5))
    r = exclude_faults(rho, SS, sg, lambda x, i: solve_snapshot(x, SS[i], sigma=sg[i], on_failure="flag"),
                       FaultExclusion())  # fmt: skip
    assert not r.excluded.any() and r.alarm.all()
    z = standardised_residuals(r.fix, SS, sg)
    assert z.shape == (50, 5) and np.all(np.isfinite(z))


def test_the_parameters_are_checked():
    with pytest.raises(ConfigError, match=r"p_fa = 0 is not in"):
        FaultExclusion(p_fa=0.0)
    with pytest.raises(ConfigError, match=r"p_fa = 0.7"):
        FaultExclusion(p_fa=0.7)
