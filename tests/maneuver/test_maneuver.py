"""The maneuvering-target scenario and Monte Carlo of Yao, Teng & Wu, *Maneuvering Target Tracking Based on
EBPSK Modulated JRC System*: reproduction targets R11–R15, the IMM-against-CV target, the checked
configurations, the measurement sources and the job protocol.

Tolerances: the paper's curves depend on unstated parameters, so the targets are ranges and orderings
(R11–R14) on 100 runs; the prototype values measured when they were set are far from every bound.
"""

import dataclasses
import math
import pickle

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.engine import MonteCarloJob, run_job
from motionsig_cli.maneuver import study as ex
from motionsig_cli.rng import trial_rng

RUNS = 100
SEED = 2008


@pytest.fixture(scope="module")
def results():
    out = {}
    for preset in ex.PRESETS:
        sc = ex.ManeuverScenario(preset)
        for sigma in (100.0, 200.0):
            out[preset, sigma] = (sc, ex.monte_carlo(sc, sigma, RUNS, SEED, ex.METHODS, ex.TrackerConfig()))
    return out


def _mean(st, a, b, values):
    sel = (st.scan >= a) & (st.scan < b)
    return values[sel]


def test_literal_preset_is_as_printed_and_turn90_turns_by_ninety_degrees():
    lit = ex.ManeuverScenario("literal")
    u = lit.inputs()
    assert np.all(u[199:299] == 20.0) and np.all(u[304:329] == 3.0)
    assert np.all(u[:199] == 0) and np.all(u[299:304] == 0) and np.all(u[329:] == 0)
    v = lit.truth()[:, [1, 3]]
    np.testing.assert_allclose(v[0], [0, 450])
    # paper §V: 20 m/s² for 100 scans, then 3 m/s² for 25 scans, on both axes, from (0, 450) m/s
    np.testing.assert_allclose(v[-1], [20 * 100 + 3 * 25, 450 + 20 * 100 + 3 * 25])
    t90 = ex.ManeuverScenario("turn90").truth()[:, [1, 3]]
    heading = np.degrees(np.arctan2(t90[:, 1], t90[:, 0]))
    assert heading[0] == pytest.approx(-90)
    assert heading[300] == pytest.approx(0, abs=1e-9)  # after turn 1: along +x
    assert heading[-1] == pytest.approx(-90, abs=1e-9)  # after turn 2: back along −y
    np.testing.assert_allclose(np.hypot(*t90[[0, 300, -1]].T), 450.0)
    # positions follow the exact constant-acceleration kinematics
    tr = lit.truth()
    T = lit.T
    np.testing.assert_allclose(tr[1:, 0], tr[:-1, 0] + tr[:-1, 1] * T + 0.5 * u[:-1, 0] * T * T, rtol=1e-12)
    assert [n for n, _ in lit.events()] == [200, 300, 305, 330]


def test_r11_filtering_gain(results):
    for preset in ex.PRESETS:
        sd = {}
        for sigma in (100.0, 200.0):
            _, r = results[preset, sigma]
            st = r["imm"].stats
            sd[sigma] = _mean(st, 50, 200, st.sd[:, 0]).mean()
            assert 0.2 * sigma <= sd[sigma] <= 0.5 * sigma
        assert 1.5 <= sd[200.0] / sd[100.0] <= 2.3


def test_r12_maneuver_signature_and_r13_first_turn_larger(results):
    for preset in ex.PRESETS:
        for sigma in (100.0, 200.0):
            st = results[preset, sigma][1]["imm"].stats
            turn = np.abs(_mean(st, 200, 250, st.mean[:, 0])).max()
            before = np.abs(_mean(st, 150, 200, st.mean[:, 0])).max()
            assert turn >= 5 * before
            if preset == "literal":  # R13, the paper's Fig 4 claim (fails for turn90 by design)
                assert _mean(st, 200, 300, st.sd[:, 0]).max() > _mean(st, 300, 340, st.sd[:, 0]).max()


def test_r14_cv_model_probability_drops_in_the_turn(results):
    for key, (_, r) in results.items():
        mu1 = r["imm"].mu[:, 0]
        scan = r["imm"].stats.scan
        assert mu1[(scan >= 200) & (scan < 300)].mean() < mu1[(scan >= 50) & (scan < 200)].mean(), key


def test_imm_beats_cv_filter_in_the_turns_and_recovers_after(results):
    """Target: the IMM's RMS error during the turns is below the CV Kalman filter's, and after the turns
    it returns to within 20 % of the non-maneuvering level."""
    for key, (sc, r) in results.items():
        imm, cv = r["imm"].stats, r["cv"].stats
        ph = {name: (a, b) for name, a, b in sc.phases()}
        for turn in ("turn 1", "turn 2"):
            a, b = ph[turn]
            assert np.sqrt(np.mean(_mean(imm, a, b, imm.rms) ** 2)) < np.sqrt(
                np.mean(_mean(cv, a, b, cv.rms) ** 2)
            )
        cruise = np.sqrt(np.mean(_mean(imm, *ph["cruise"], imm.rms) ** 2))
        after = np.sqrt(np.mean(_mean(imm, *ph["after"], imm.rms) ** 2))
        assert after <= 1.2 * cruise, key


def test_r15_glr_false_alarms_and_detection(results):
    """R15 (provisional): GLR false alarms ≤ 2 % of non-maneuvering scans; the first maneuver
    (literal) declared in ≥ 95 % of runs. Measured delays are reported, not asserted against the target's
    '5 scans' (the mean delay is 5–8 scans at λ = 13.8)."""
    for sigma in (100.0, 200.0):
        sc, r = results["literal", sigma]
        d = ex.detection_summary(sc, r["glr"].detected, r["glr"].onset, 30)
        assert d.false_alarms_per_1000 <= 20
        first = d.events[0]
        assert first[0] == 200 and first[2] >= 0.95
        # mean onset error: 500 runs give +0.6 / +1.2 scans with an RMS of 2.1 / 2.8, so its standard error on
        # 100 runs is ≤ 0.3 and 2.5 scans is the σ = 200 mean plus 4 standard errors
        assert abs(first[5]) <= 2.5


def test_mlr_with_the_seeds_threshold_declares_far_more_often_than_glr(results):
    """Measured, not a reproduction target: with h = 0 the MLR declares on about a third of quiet scans (≈ e⁻¹ per
    newest onset), the GLR on well under 1 %."""
    sc, r = results["literal", 100.0]
    g = ex.detection_summary(sc, r["glr"].detected, r["glr"].onset, 30)
    m = ex.detection_summary(sc, r["mlr"].detected, r["mlr"].onset, 30)
    assert m.false_alarms_per_1000 > 10 * g.false_alarms_per_1000


def test_result_does_not_depend_on_chunking_or_run_subset():
    sc = ex.ManeuverScenario("turn90", scans=230)
    a = ex.monte_carlo(sc, 100.0, 13, 5, ("imm", "glr"), ex.TrackerConfig(), chunk=4)
    b = ex.monte_carlo(sc, 100.0, 13, 5, ("imm", "glr"), ex.TrackerConfig(), chunk=250)
    for m in ("imm", "glr"):
        np.testing.assert_allclose(a[m].stats.mean, b[m].stats.mean, rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(a[m].stats.sd, b[m].stats.sd, rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(a["glr"].detected, b["glr"].detected)
    # run r's measurements depend on (seed, r) only
    z_all = ex.measurements(sc, 100.0, range(13), 5)
    z_one = ex.measurements(sc, 100.0, [7], 5)
    np.testing.assert_array_equal(z_all[7], z_one[0])


def test_error_statistics_are_eqs_14_and_15():
    sc = ex.ManeuverScenario(scans=10)
    truth = sc.truth()[2:, [0, 2]]
    rng = np.random.default_rng(0)
    est = truth[None] + rng.normal(size=(7, 8, 2))
    st = ex.error_stats(sc, est)
    e = truth[None] - est
    np.testing.assert_allclose(st.mean, e.mean(0))
    np.testing.assert_allclose(st.sd, e.std(0), rtol=1e-12)  # 1/M normalisation (eq 15) = numpy's ddof=0
    np.testing.assert_allclose(st.rms, np.sqrt((e**2).sum(-1).mean(0)))
    assert st.scan[0] == 3 and not np.isnan(st.sd).any()


def test_declarations_are_attributed_by_estimated_onset():
    """Hand-made declarations on the literal scenario (changes at 200, 300, 305, 330): a declaration at scan
    307 with n̂ = 300 belongs to the end of turn 1, one at 312 with n̂ = 306 to the start of turn 2; one at
    scan 100 is a false alarm; one at 260 (inside the turn, beyond the window) is 'other'."""
    sc = ex.ManeuverScenario("literal")
    n_scan = sc.scans - ex.FIRST_SCAN + 1
    det = np.zeros((2, n_scan), dtype=bool)
    on = np.full((2, n_scan), -1)
    for run, k, n in ((0, 307, 300), (0, 312, 306), (0, 100, 95), (0, 260, 255), (1, 205, 200)):
        det[run, k - ex.FIRST_SCAN], on[run, k - ex.FIRST_SCAN] = True, n
    d = ex.detection_summary(sc, det, on, 30)
    by = {e[0]: e for e in d.events}
    assert by[200][2] == 0.5 and by[200][3] == 5.0 and by[200][5] == 0.0
    assert by[300][2] == 0.5 and by[300][3] == 7.0 and by[300][5] == 0.0
    assert by[305][2] == 0.5 and by[305][3] == 7.0 and by[305][5] == 1.0
    assert by[330][2] == 0.0 and math.isnan(by[330][3])
    # scans 3..200 (u(200) first moves scan 201) and 361..450 (30 scans after the last change at 330)
    assert d.quiet_scans == (201 - 3) + (451 - 361)
    assert d.false_alarms_per_1000 == pytest.approx(1000 * 1 / (2 * d.quiet_scans))
    assert d.other == 0.5


# ------------------------------------------------------------------ checked configurations
def _job(**kw):
    args = {"sc": ex.ManeuverScenario(scans=20), "sigmas": (100.0,), "runs": 2, "seed": 1, "methods": ("imm",),
            "cfg": ex.TrackerConfig()} | kw  # fmt: skip
    return ex.ManeuverJob(**args)


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda: ex.ManeuverScenario(preset="spiral"), "preset"),
        (lambda: ex.ManeuverScenario(T=0.0), "T"),
        (lambda: ex.ManeuverScenario(T=math.nan), "T"),
        (lambda: ex.ManeuverScenario(T=3601.0), "T"),
        (lambda: ex.ManeuverScenario(scans=2), "scans"),
        (lambda: ex.ManeuverScenario(scans=100_001), "scans"),
        (lambda: ex.ManeuverScenario(scans=30.5), "scans"),
        (lambda: ex.ManeuverScenario(p0=(0.0, math.inf)), "p0"),
        (lambda: ex.TrackerConfig(g2="printed"), "g2"),
        (lambda: ex.TrackerConfig(Pi=((0.5, 0.5), (0.5, 0.5))), "Pi"),
        (lambda: ex.TrackerConfig(Pi=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.5, 0.4))), "Pi"),
        (lambda: ex.TrackerConfig(Pi=((1.1, -0.1, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))), "Pi"),
        (lambda: ex.TrackerConfig(mu0=(0.5, 0.5)), "mu0"),
        (lambda: ex.TrackerConfig(mu0=(0.8, 0.1, 0.2)), "mu0"),
        (lambda: ex.TrackerConfig(q0=-1.0), "q0"),
        (lambda: ex.TrackerConfig(q0=2e6), "q0"),
        (lambda: ex.TrackerConfig(window=0), "window"),
        (lambda: ex.TrackerConfig(window=201), "window"),
        (lambda: ex.TrackerConfig(glr_threshold=-1.0), "glr_threshold"),
        (lambda: ex.TrackerConfig(glr_threshold=math.inf), "glr_threshold"),
        (lambda: ex.TrackerConfig(mlr_threshold=math.nan), "mlr_threshold"),
        (lambda: ex.TrackerConfig(mlr_threshold=-math.inf), "mlr_threshold"),
        (lambda: ex.TrackerConfig(sigma_u=1e-4), "sigma_u"),
        (lambda: ex.TrackerConfig(sigma_u=1e7), "sigma_u"),
        (lambda: ex.TrackerConfig(correction="late"), "correction"),
        (lambda: ex.TrackerConfig(continuation="forget"), "continuation"),
        (lambda: _job(sigmas=()), "sigmas"),
        (lambda: _job(sigmas=(100.0, 0.0)), "sigmas"),
        (lambda: _job(sigmas=(2e7,)), "sigmas"),
        (lambda: _job(sigmas=tuple(range(1, 12))), "sigmas"),
        (lambda: _job(runs=0), "runs"),
        (lambda: _job(runs=1_000_001), "runs"),
        (lambda: _job(seed=-1), "seed"),
        (lambda: _job(methods=()), "methods"),
        (lambda: _job(methods=("imm", "ckf")), "methods"),
        (lambda: _job(source="waveform"), "source"),
        (lambda: _job(chunk=0), "chunk"),
        (lambda: ex.ManeuverStudy(_job(), view="measurements"), "view"),
        (lambda: ex.ManeuverStudy(_job(), view="events"), "view"),  # the IMM declares nothing
        (lambda: ex.ManeuverStudy(_job(), response=0), "response"),
        (lambda: ex.ManeuverStudy(_job(), response=10_001), "response"),
        (lambda: ex.ManeuverStudy(_job(sc=ex.ManeuverScenario(), runs=1_000_000)), "runs"),  # run time
        (lambda: ex.measurement_table(_job(sc=ex.ManeuverScenario(), runs=3000)), "runs"),  # rows
        (lambda: ex.measurements(ex.ManeuverScenario(scans=20), 0.0, [0], 1), "sigma"),
        (
            lambda: ex.detection_summary(ex.ManeuverScenario(scans=20), np.zeros((1, 18), bool), None, 0),
            "response",
        ),
    ],
)
def test_every_checked_field_is_refused_by_name(make, field):
    with pytest.raises(ConfigError) as info:
        make()
    assert info.value.field == field


def test_valid_configurations_pass_and_are_normalised():
    cfg = ex.TrackerConfig(Pi=[[1, 0, 0], [0, 1, 0], [0, 0, 1]], mu0=[1, 0, 0], glr_threshold=0.0)
    assert cfg.Pi == ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)) and cfg.mu0 == (1.0, 0.0, 0.0)
    assert ex.TrackerConfig(q0=0.0, window=200, sigma_u=1e6, mlr_threshold=-5.0).window == 200
    study = ex.ManeuverStudy(_job(methods=("glr",)), view="events", response=10_000)
    assert study.view == "events"


def test_a_singular_covariance_is_a_config_error_on_sigma_and_survives_pickling():
    exc = ex.SingularCovariance(1e-3, 3600.0)
    back = pickle.loads(pickle.dumps(exc))
    assert isinstance(back, ConfigError) and isinstance(back, np.linalg.LinAlgError)
    assert back.field == "sigma" and (back.sigma, back.T) == (1e-3, 3600.0) and str(back) == str(exc)
    job = _job(sc=ex.ManeuverScenario(T=3600.0, scans=240), sigmas=(1e-3,), methods=("imm",))
    with pytest.raises(ex.SingularCovariance):
        job.run_task(job.tasks()[0])


# ------------------------------------------------------------------ measurement sources
@pytest.mark.parametrize("name", sorted(ex.SOURCES))
def test_every_measurement_source_is_reproducible_per_run(name):
    """Every registered source: (B, N, 2) finite records; run r's record depends on (seed, r) only; the
    registry's key is the source's name; a Monte Carlo runs on it."""
    src = ex.SOURCES[name]
    assert src.name == name and ex.measurement_source(name) is src and isinstance(src.seeding, str)
    sc = ex.ManeuverScenario("turn90", scans=40)
    z = ex.measurements(sc, 50.0, range(5), 3, source=name)
    assert z.shape == (5, 40, 2) and np.all(np.isfinite(z))
    np.testing.assert_array_equal(ex.measurements(sc, 50.0, [3, 1], 3, source=name), z[[3, 1]])
    assert not np.array_equal(ex.measurements(sc, 50.0, range(5), 4, source=name), z)
    assert ex.measurements(sc, 50.0, [], 3, source=name).shape == (0, 40, 2)
    res = ex.monte_carlo(
        ex.ManeuverScenario(scans=30), 100.0, 2, 1, ("imm", "glr"), ex.TrackerConfig(), source=name
    )
    assert np.all(np.isfinite(res["imm"].stats.rms))


def test_gaussian_positions_are_truth_plus_sigma_times_the_runs_normal_draws():
    sc = ex.ManeuverScenario(scans=25)
    z = ex.measurements(sc, 80.0, [0, 4], 9)
    for i, r in enumerate((0, 4)):
        w = trial_rng(9, r).standard_normal((25, 2))
        np.testing.assert_array_equal(z[i], sc.truth()[:, [0, 2]] + 80.0 * w)


# ------------------------------------------------------------------ the job protocol
def test_the_job_is_an_engine_job_and_matches_the_library_function():
    job = _job(
        sc=ex.ManeuverScenario(scans=215), sigmas=(100.0, 150.0), runs=3, methods=("imm", "glr"), chunk=2
    )
    assert job.name == "maneuver" and isinstance(job, MonteCarloJob)
    tasks = job.tasks()
    assert [(i, list(r)) for i, r in tasks] == [(0, [0, 1]), (0, [2]), (1, [0, 1]), (1, [2])]
    assert [job.task_size(t) for t in tasks] == [2, 1, 2, 1]
    ident = job.identity()
    assert ident["source"] == "gaussian" and ident["runs_per_task"] == 2 and ident["sigmas"] == [100.0, 150.0]
    res = run_job(job)
    # the same runs in one task per sigma (another chunking): equal up to the order of the error sums
    whole = run_job(dataclasses.replace(job, chunk=3))
    assert len(dataclasses.replace(job, chunk=3).tasks()) == 2
    for s in (100.0, 150.0):
        for m in ("imm", "glr"):
            np.testing.assert_allclose(
                res[s][m].stats.sd, whole[s][m].stats.sd, rtol=1e-14
            )  # summation order only
            np.testing.assert_array_equal(res[s][m].track0, whole[s][m].track0)  # run 0: same task
        np.testing.assert_array_equal(res[s]["glr"].detected, whole[s]["glr"].detected)


def test_report_tables_of_every_view():
    job = _job(sc=ex.ManeuverScenario(scans=340), sigmas=(100.0,), runs=3, methods=("imm", "glr"))
    res = run_job(job)
    scans = ex.report(ex.ManeuverStudy(job, "scans"), res)
    assert len(scans.table.rows) == 2 * 338 and scans.table.meta["view"] == "scans"
    assert scans.note.startswith("σ=100 imm RMS ")
    assert scans.track_figure["method"] == "IMM" and scans.track_figure["model_names"][0] == "CV"
    assert set(scans.compare_figure["rate"]) == {(100.0, "glr")}
    events = ex.report(ex.ManeuverStudy(job, "events", response=20), res).table
    assert [r[2] for r in events.rows] == [200, 300, 305, 330] and events.meta["response_window"] == 20
    summary = ex.report(ex.ManeuverStudy(job, "summary"), res).table
    assert [r[1] for r in summary.rows] == ["imm", "glr"]
    assert summary.rows[0][summary.columns.index("false_alarms_per_1000")] is None
