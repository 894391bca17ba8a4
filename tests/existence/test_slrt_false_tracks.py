"""The no-target case as a tracker runs it: false tracks started on every detection of scan 1 (clutter),
scored from scan 2 (``SlrtScenario.false_tracks``), the operating characteristics over a grid of thresholds
(the ``oc`` view) and the schemes compared at equal error rates (the ``matched`` view); the DKF = CKF check
with a proper clutter density (``filter_clutter``)."""

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.stats import binomtest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.sprt import first_crossing, wald_thresholds
from motionsig_cli.detection.track_existence import FusionOptions, ScanData, run_methods
from motionsig_cli.engine import run_job
from motionsig_cli.existence import slrt

NT = slrt.SlrtScenario(target=False, false_tracks=True, scans=5, clutter_rate=3.0, pd_true=0.5, pd_filter=0.5)


def test_false_tracks_start_on_every_detection_of_scan_one_second_implementation():
    """Oracle: the tracks built by a loop over runs, sensors and detections (position from range and bearing
    by cos/sin, the one-point sd written out), each scored alone on its own run's scans 2..K."""
    gen = slrt.generate(NT, range(6), 3)
    ft = slrt.false_tracks(NT, gen)
    assert ft.m0.shape[0] == int(gen.clutter_counts[:, 0, :].sum()) > 6  # every false alarm of scan 1
    sigma_r, sigma_phi = NT.sigma_r, math.radians(NT.sigma_phi_deg)
    i = 0
    for r in range(6):
        for s in range(NT.n_sensors):
            first = gen.scans[0]
            for z in first.Z[s][r][first.valid[s][r]]:
                x, y = NT.sensors[s] + z[0] * np.array([math.cos(z[1]), math.sin(z[1])])
                assert (ft.run[i], ft.sensor[i]) == (r, s)
                np.testing.assert_allclose(ft.m0[i], [x, 0.0, y, 0.0], rtol=1e-12, atol=1e-9)
                pos = max(sigma_r, z[0] * sigma_phi)
                np.testing.assert_allclose(
                    np.diag(ft.cov[i]), [pos**2, 150.0**2, pos**2, 150.0**2], rtol=1e-12
                )
                assert np.count_nonzero(ft.cov[i] - np.diag(np.diag(ft.cov[i]))) == 0
                i += 1
    assert i == ft.m0.shape[0]
    scores, _ = slrt.run(NT, 6, 3, ("ckf", "fkf", "lkf"))
    model = NT.model()
    for t in (0, ft.m0.shape[0] // 2, ft.m0.shape[0] - 1):
        r = ft.run[t]
        own = [
            ScanData(tuple(z[r : r + 1] for z in sc.Z), tuple(v[r : r + 1] for v in sc.valid))
            for sc in gen.scans[1:]
        ]
        alone = run_methods(replace(model, m0_cov=ft.cov[t]), ft.m0[t : t + 1], own, ("ckf", "fkf", "lkf"))
        for m, v in alone.items():
            assert scores[m][t, 0] == 0.0  # log LR 0 where the track starts
            np.testing.assert_allclose(scores[m][t, 1:], v[0], rtol=1e-10, atol=1e-9)


def test_false_tracks_are_checked_naming_the_field():
    for kw, field in (
        ({"target": True, "false_tracks": True}, "false_tracks"),
        ({"target": False, "false_tracks": True, "clutter_rate": 0.0}, "clutter_rate"),
        ({"target": False, "false_tracks": True, "scans": 1}, "scans"),
        ({"false_tracks": "yes"}, "false_tracks"),
        ({"filter_clutter": -1.0}, "filter_clutter"),
    ):
        with pytest.raises(ConfigError) as err:
            slrt.SlrtScenario(**kw)
        assert err.value.field == field


def test_a_run_draws_the_same_false_tracks_alone_or_in_a_batch():
    batch, _ = slrt.run(NT, 5, 9, ("ckf",))
    gen = slrt.generate(NT, range(5), 9)
    ft = slrt.false_tracks(NT, gen)
    alone = slrt.score_case(NT, slrt.generate(NT, [3], 9), ("ckf",), FusionOptions())["ckf"]
    np.testing.assert_array_equal(alone, batch["ckf"][ft.run == 3])


def test_no_false_alarm_in_scan_one_is_refused_naming_runs():
    st = slrt.SlrtStudy(slrt.SlrtScenario(scans=3, clutter_rate=1e-3), pd=(0.9,), runs=2, methods=("ckf",))
    with pytest.raises(ConfigError) as err:
        st.result(run_job(st.job()))
    assert err.value.field == "runs" and "no false alarm" in err.value.reason


# ------------------------------------------------------------------ Wald's bound on the false tracks
def test_ckf_and_lkf_false_track_confirmation_obeys_villes_bound():
    """Under h0 with the filters' clutter density equal to the data's, every sensor's factor of the CKF has
    E[Λ | past] = 1 − p_D + p_D ∫_FoV N(z; ẑ, S) dz ≤ 1 (Campbell's theorem for Poisson clutter, whatever the
    filter's Gaussian), so LR(k) is a non-negative supermartingale and P(max_k LR(k) ≥ B) ≤ 1/B (Ville); the
    same holds for LKF, a mean of such LRs. The false tracks never exceed it, and the SPRT's confirmations
    (Wald's bound α/(1−β)) neither: measured at p_D = 0.5 (1500 runs of 5 scans, ~18,000 false tracks); the
    exact 95 % interval of the rate must reach below the bound."""
    sc = slrt.SlrtScenario(target=False, false_tracks=True, scans=5, pd_true=0.5, pd_filter=0.5)
    scores, _ = slrt.run(sc, 1500, 2008, ("ckf", "lkf"))
    for m, v in scores.items():
        top = v.max(axis=1)
        for log_b in (1.0, 2.0, 4.0):
            k = int((top >= log_b).sum())
            assert binomtest(k, top.size).proportion_ci(method="exact").low <= math.exp(-log_b), (m, log_b)
        d = first_crossing(v, *wald_thresholds(0.05, 0.1))
        k = int((d.decision == 1).sum())
        assert binomtest(k, top.size).proportion_ci(method="exact").low <= 0.05 / 0.9, m


# ------------------------------------------------------------------ the oc and matched views
@pytest.fixture(scope="module")
def small_study():
    st = slrt.SlrtStudy(slrt.SlrtScenario(scans=8, clutter_rate=3.0), pd=(0.9, 0.3), runs=30, seed=4,
                        methods=("ckf", "lkf", "naive"))  # fmt: skip
    return st, st.result(run_job(st.job()))


def test_oc_grid_equals_wald_first_crossing_at_every_threshold_pair(small_study):
    st, res = small_study
    t = res.table("oc")
    assert t.columns == slrt.OC_COLUMNS and "naive" not in t.column("method")  # its score uses the thresholds
    assert len(t.rows) == 2 * 2 * len(slrt.OC_LOG_A) * len(slrt.OC_LOG_B)
    scores = {label: s for (label, _), s in zip(st.cases, res.scores, strict=True)}
    col = {c: i for i, c in enumerate(t.columns)}
    for row in t.rows[::37]:  # a spread of pairs: Wald's first crossing, recomputed
        log_a, log_b = row[col["log_A"]], row[col["log_B"]]
        A, B = math.exp(log_a), math.exp(log_b)
        a, b = row[col["wald_alpha"]], row[col["wald_beta"]]
        assert math.log(b / (1 - a)) == pytest.approx(log_a) and math.log((1 - b) / a) == pytest.approx(log_b)
        assert 0 < a < 1 and 0 < b < 1 and A < 1 < B
        for case, prefix, kinds in (
            (row[1], "false", ("confirmed",)),
            (row[0], "target", ("confirmed", "deleted")),
        ):
            v = scores[case][row[col["method"]]]
            d = first_crossing(v, log_a, log_b)
            for kind in kinds:
                k = int((d.decision == (1 if kind == "confirmed" else -1)).sum())
                ci = binomtest(k, v.shape[0]).proportion_ci(method="exact")
                assert row[col[f"{prefix}_{kind}"]] == k / v.shape[0]
                assert row[col[f"{prefix}_{kind}_lo95"]] == pytest.approx(ci.low, abs=1e-12)
                assert row[col[f"{prefix}_{kind}_hi95"]] == pytest.approx(ci.high, abs=1e-12)
            when = d.time[d.decision != 0]
            asn = row[col[f"{prefix}_asn"]]
            assert (asn is None and when.size == 0) or asn == pytest.approx(when.mean())
        assert row[col["false_tracks"]] == scores[row[1]]["ckf"].shape[0] and row[col["runs"]] == 30


def test_matched_picks_the_best_pair_meeting_both_rates(small_study):
    _, res = small_study
    oc, t = res.table("oc"), res.table("matched")
    assert t.columns == slrt.MATCHED_COLUMNS
    assert len(t.rows) == 2 * len(slrt.MATCHED_RATES) * 2  # pairs of cases x reference rates x (ckf, lkf)
    col = {c: i for i, c in enumerate(t.columns)}
    ocol = {c: i for i, c in enumerate(oc.columns)}
    for row in t.rows:
        sweep = [r for r in oc.rows if r[0] == row[0] and r[3] == row[col["method"]]]
        ok = [r for r in sweep if r[ocol["false_confirmed"]] <= row[col["reference_false"]]
              and r[ocol["target_deleted"]] <= row[col["reference_deleted"]]]  # fmt: skip
        if not ok:
            assert row[col["log_A"]] is None
            continue
        best = max(r[ocol["target_confirmed"]] for r in ok)
        assert row[col["target_confirmed"]] == best
        fastest = min(r[ocol["target_asn"]] for r in ok if r[ocol["target_confirmed"]] == best)
        assert row[col["target_asn"]] == fastest
        assert row[col["false_confirmed"]] <= row[col["reference_false"]]


# ------------------------------------------------------------------ DKF = CKF with a proper clutter density
def test_dkf_equals_ckf_with_a_proper_clutter_density_and_the_floor_only_shifts_the_scores():
    """With p_D = 1 every sensor reports exactly one measurement per scan, and the filters' clutter density
    ρ enters the log LR only as −log ρ per measurement: the scores with λ_F = 5 and with the floor (λ_F = 0,
    ρ = 10⁻³⁰⁰/|FoV|) differ by exactly S·k·(log ρ_5 − log ρ_floor) at scan k."""
    base = dict(meas_model="cartesian", pd_true=1.0, pd_filter=1.0, clutter_rate=0.0, scans=6, n_sensors=3)
    proper, floored = slrt.SlrtScenario(**base, filter_clutter=5.0), slrt.SlrtScenario(**base)
    a, _ = slrt.run(proper, 8, 1, ("ckf", "dkf"))
    b, _ = slrt.run(floored, 8, 1, ("ckf",))
    np.testing.assert_allclose(a["dkf"], a["ckf"], rtol=1e-9)
    shift = proper.model().log_rho - floored.model().log_rho  # log(5) - log(1e-300)
    k = np.arange(1, 7)
    np.testing.assert_allclose(b["ckf"] - a["ckf"], 3 * k * shift * np.ones((8, 1)), rtol=1e-9)
    assert np.all(np.abs(a["ckf"][:, 0]) < 200) and np.all(b["ckf"][:, 0] > 1e3)  # the scale users read
