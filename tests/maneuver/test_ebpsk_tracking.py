"""The EBPSK front end along the maneuvering-target trajectory: the two levels agree, detections follow P_D,
the calibration and the table's powers do what they say, the Monte Carlo does not depend on the workers, and
bad geometry is refused naming its field.

Tolerances: 4 standard errors of the difference of two independent estimates (a fixed seed; a correct
implementation fails a single comparison with probability 6e-5).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.engine import Engine, run_job
from motionsig_cli.maneuver import ebpsk_tracking as et
from motionsig_cli.maneuver import study as ex
from motionsig_cli.rng import trial_rng


@pytest.fixture(scope="module")
def literal():
    sc = ex.ManeuverScenario("literal")
    fe = et.EbpskFrontEnd().prepared(sc.truth())
    return sc, fe.calibrated(sc.truth(), 100.0)


def _errors(fe, truth, runs, seed, level):
    """Position errors (runs, scans, 2), detections, and the radial component of the error."""
    import dataclasses

    f = dataclasses.replace(fe, level=level)
    z, R = f.measure(truth, [trial_rng(seed, r) for r in range(runs)], initiation=0)
    e = z - truth[None][..., [0, 2]]
    d = truth[:, [0, 2]] - np.asarray(fe.position)
    u = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    return e, ~np.isnan(z[..., 0]), np.einsum("bkn,kn->bk", e, u), R


def test_sample_level_and_detector_level_give_the_same_statistics(literal):
    """At three scans of the track (P_D ≈ 1, ≈ 0.6, ≈ 0.25: the far end, with its own Doppler): P_D, the
    per-axis σ of the position error and the σ of its radial (range) component agree within 4 SE."""
    sc, fe = literal
    truth = sc.truth()
    pd = fe.scans(truth).pd
    ks = [int(np.argmin(np.abs(pd - p) + (np.arange(pd.size) < 300))) for p in (0.99, 0.6, 0.25)]
    sub = truth[ks]
    e_s, det_s, rad_s, _ = _errors(fe, sub, 300, 11, "samples")
    e_d, det_d, rad_d, _ = _errors(fe, sub, 20000, 12, "detector")
    for j, k in enumerate(ks):
        p_s, p_d = det_s[:, j].mean(), det_d[:, j].mean()
        se = math.sqrt(p_s * (1 - p_s) / 300 + p_d * (1 - p_d) / 20000 + 1e-12)
        assert abs(p_s - p_d) < 4 * se + 1e-9, (k, p_s, p_d, se)
        assert abs(p_d - pd[k]) < 4 * math.sqrt(pd[k] * (1 - pd[k]) / 20000) + 1e-9
        for stat in ("pos", "radial"):
            xs = e_s[det_s[:, j], j].ravel() if stat == "pos" else rad_s[det_s[:, j], j]
            xd = e_d[det_d[:, j], j].ravel() if stat == "pos" else rad_d[det_d[:, j], j]
            s_s, s_d = np.sqrt(np.mean(xs**2)), np.sqrt(np.mean(xd**2))
            se_s = np.std(xs**2) / math.sqrt(xs.size) / (2 * s_s)  # delta method on √(mean x²)
            se_d = np.std(xd**2) / math.sqrt(xd.size) / (2 * s_d)
            assert abs(s_s - s_d) < 4 * math.hypot(se_s, se_d), (k, stat, s_s, s_d)


def test_detections_follow_pd_and_R_is_the_location_covariance(literal):
    """Missed scans occur with probability 1 − P_D (4 SE over the far end); at detected scans z − truth is
    N(0, R): the whitened errors have unit covariance (4 SE); the first two scans are the initiation."""
    sc, fe = literal
    truth = sc.truth()
    z, R = fe.measure(truth, [trial_rng(5, r) for r in range(400)])
    det = ~np.isnan(z[..., 0])
    assert det[:, :2].all() and np.isnan(R[~det]).all()
    pd = fe.scans(truth).pd
    far = slice(340, 420)
    n = det[:, far].size
    expect = pd[far].mean()
    se = math.sqrt(np.sum(pd[far] * (1 - pd[far])) * 400) / n
    assert abs(det[:, far].mean() - expect) < 4 * se
    e = (z - truth[None][..., [0, 2]])[det]
    L = np.linalg.cholesky(R[det])
    w = np.linalg.solve(L, e[..., None])[..., 0]
    cov = w.T @ w / len(w)
    np.testing.assert_allclose(cov, np.eye(2), atol=4 * math.sqrt(2 / len(w)))


def test_runs_are_reproducible_per_run_and_independent_of_the_others(literal):
    sc, fe = literal
    src = et.EbpskPositions(fe, calibrate=False)
    z, R = ex.measurements_cov(sc, 100.0, range(4), 3, src)
    z2, R2 = ex.measurements_cov(sc, 100.0, [2, 0], 3, src)
    np.testing.assert_array_equal(z2, z[[2, 0]])
    np.testing.assert_array_equal(R2, R[[2, 0]])
    assert not np.array_equal(ex.measurements_cov(sc, 100.0, range(4), 4, src)[0], z, equal_nan=True)


def test_calibration_sets_the_median_sigma_and_the_table_powers_reach_their_sigma(literal):
    sc, fe = literal
    truth = sc.truth()
    base = et.EbpskFrontEnd().prepared(truth)
    for s in (100.0, 200.0):
        f = base.calibrated(truth, s)
        assert np.median(f.scans(truth).sigma_pos) == pytest.approx(s, rel=1e-9)
    tab = et.front_end_table(sc, fe)
    cols = tab.columns
    for row in tab.rows:
        a, b = row[cols.index("first_scan")], row[cols.index("last_scan")]
        for s in (100, 200):
            p = row[cols.index(f"p_t_W_for_{s}")]
            sp = fe.with_power(p).scans(truth).sigma_pos[a - 1 : b]
            assert np.sqrt(np.mean(sp**2)) == pytest.approx(s, rel=1e-6)
        # σ_pos ∝ P_t^(-1/2) while the cross-range term dominates (σ_r ≪ r σ_φ): 4× the power for ½ the σ
        assert row[cols.index("p_t_W_for_100")] / row[cols.index("p_t_W_for_200")] == pytest.approx(
            4, rel=0.02
        )
    assert [r[0] for r in tab.rows] == ["cruise", "turn 1", "turn 2", "after", "track"]


def test_monte_carlo_does_not_depend_on_the_workers(monkeypatch):
    monkeypatch.setenv("MOTIONSIG_MIN_TASK_SECONDS", "1e-9")
    sc30 = ex.ManeuverScenario("literal", scans=40)
    src = et.EbpskPositions(et.EbpskFrontEnd().prepared(sc30.truth()), calibrate=True)
    job = ex.ManeuverJob(sc30, (100.0, 200.0), 6, 7, ("imm", "glr"), ex.TrackerConfig(), source=src, chunk=2)
    a = run_job(job, Engine(workers=1))
    b = run_job(job, Engine(workers=2))
    for s in (100.0, 200.0):
        for m in ("imm", "glr"):
            np.testing.assert_array_equal(a[s][m].stats.rms, b[s][m].stats.rms)
            np.testing.assert_array_equal(a[s][m].track0, b[s][m].track0)
        assert np.all(np.isfinite(a[s]["imm"].stats.rms))


def test_bad_geometry_is_refused_naming_the_field():
    sc = ex.ManeuverScenario("literal")
    with pytest.raises(ConfigError) as exc:
        et.EbpskFrontEnd(position=(0.0, 0.0)).check_track(sc.truth())
    assert exc.value.field == "radar_position"
    from motionsig_cli.maneuver.ebpsk_radar import EbpskRadarConfig

    with pytest.raises(ConfigError) as exc:
        et.EbpskFrontEnd(radar=EbpskRadarConfig(pri=2e-3)).check_track(sc.truth())
    assert exc.value.field == "pri" and "unambiguous" in exc.value.detail
    with pytest.raises(ConfigError) as exc:
        et.EbpskFrontEnd(level="chips")
    assert exc.value.field == "level"
    with pytest.raises(ConfigError) as exc:
        et.EbpskFrontEnd(position=(math.nan, 0.0))
    assert exc.value.field == "radar_position"
