"""The track-existence experiment: the study's checks (every field, named), its Monte Carlo job (the engine's
protocol, the same scores as a direct run) and its tables (curves, decisions, provenance)."""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.sprt import wald_thresholds
from motionsig_cli.engine import MonteCarloJob, job_trials, run_job
from motionsig_cli.existence import slrt

SMALL = slrt.SlrtScenario(scans=6, clutter_rate=2.0)


@pytest.mark.parametrize(
    ("kw", "field"),
    [
        ({"pd": ()}, "pd"),
        ({"pd": (0.0,)}, "pd"),
        ({"pd": (0.9, 1.5)}, "pd"),
        ({"pd": tuple(0.05 * i for i in range(1, 12))}, "pd"),  # 11 cases
        ({"pd": (1.0,)}, "pd"),  # filters with p_D = 1 in clutter
        ({"filter_pd": 0.0}, "filter_pd"),
        ({"filter_pd": 1.0}, "filter_pd"),
        ({"runs": 0}, "runs"),
        ({"runs": 2.5}, "runs"),
        ({"runs": 10**6}, "runs"),  # over the time and memory limits
        ({"seed": -1}, "seed"),
        ({"methods": ()}, "methods"),
        ({"methods": ("ckf", "ukf")}, "methods"),
        ({"lkf_mean": "median"}, "lkf_mean"),
        ({"alpha": 0.0}, "alpha"),
        ({"alpha": 0.5}, "alpha"),
        ({"beta": 0.0}, "beta"),
        ({"beta": math.nan}, "beta"),
        ({"gate_pg": 0.0}, "gate_pg"),
        ({"gate_pg": 1.5}, "gate_pg"),
        ({"feedback_every": 0}, "feedback_every"),
        ({"ldf_prior": 1.0}, "ldf_prior"),
        ({"ldf_weights": (1.0, 2.0), "methods": ("ldf",)}, "ldf_weights"),  # two weights for four sensors
        ({"ldf_weights": (0.0,) * 4}, "ldf_weights"),
        ({"methods": ("dkf",)}, "methods"),  # range-bearing sensors in clutter: the exact DKF does not apply
        ({"motions": ("cv", "cv")}, "motions"),
    ],
)
def test_study_rejects_each_bad_field_naming_it(kw, field):
    with pytest.raises(ConfigError) as err:
        slrt.SlrtStudy(SMALL, **kw)
    assert err.value.field == field


def test_study_cases_and_the_exceptions_to_its_checks():
    st = slrt.SlrtStudy(SMALL, pd=(0.9, 0.5, 0.9), filter_pd=0.7, runs=3)
    assert [label for label, _ in st.cases] == [
        "target, p_D = 0.9",
        "target, p_D = 0.5",
        "no target, p_D = 0.7",
    ]
    assert [(sc.target, sc.pd_true, sc.pd_filter, sc.false_tracks) for _, sc in st.cases] == [
        (True, 0.9, 0.9, False),
        (True, 0.5, 0.5, False),
        (False, 0.7, 0.7, True),
    ]
    # without filter_pd, one no-target case per p_D, whose filters assume it
    per_pd = slrt.SlrtStudy(SMALL, pd=(0.9, 0.5), runs=3).cases
    assert [(label, sc.pd_filter) for label, sc in per_pd[2:]] == [("no target, p_D = 0.9", 0.9),
                                                                   ("no target, p_D = 0.5", 0.5)]  # fmt: skip
    no_clutter = slrt.SlrtScenario(clutter_rate=0.0, scans=6)
    assert slrt.SlrtStudy(no_clutter, pd=(1.0,), no_target=False).cases[0][1].pd_filter == 1.0
    with pytest.raises(ConfigError) as err:  # no clutter: nothing to start a false track on
        slrt.SlrtStudy(no_clutter, pd=(0.9,))
    assert err.value.field == "clutter_rate"
    assert st.thresholds == wald_thresholds(1e-3, 0.1)


@pytest.mark.parametrize(
    ("method", "kw"),
    [
        ("fkf-feedback", {"feedback_every": 3}),
        ("ldf", {"ldf_prior": 0.2}),
        ("ldf", {"ldf_weights": (4.0, 1.0, 1.0, 1.0)}),
        ("ckf", {"gate_pg": 0.99}),
        ("naive", {"alpha": 0.01, "beta": 0.2}),
        ("lkf", {"lkf_mean": "log"}),
    ],
)
def test_the_studys_fusion_options_reach_the_rules(method, kw):
    from motionsig_cli.detection.track_existence import FusionOptions, run_methods

    st = slrt.SlrtStudy(SMALL, pd=(0.5,), no_target=False, runs=5, seed=2, methods=(method,), **kw)
    assert st.options == FusionOptions(**kw) and st.job().options == st.options
    got = run_job(st.job())[0][method]
    sc = st.cases[0][1]
    gen = slrt.generate(sc, range(5), 2)
    want = run_methods(sc.model(), gen.m0, gen.scans, (method,), options=FusionOptions(**kw))[method]
    default = run_methods(sc.model(), gen.m0, gen.scans, (method,))[method]
    np.testing.assert_array_equal(got, want)
    assert not np.array_equal(got, default)  # the option changes the score: it was not dropped on the way


def test_filter_pd_is_checked_only_with_the_no_target_case():
    with pytest.raises(ConfigError):
        slrt.SlrtStudy(SMALL, filter_pd=5.0)
    assert len(slrt.SlrtStudy(SMALL, no_target=False, filter_pd=5.0).cases) == 3


@pytest.mark.parametrize(
    ("kw", "field"),
    [
        ({"cases": ()}, "cases"),
        ({"runs": 0}, "runs"),
        ({"seed": -2}, "seed"),
        ({"methods": ("ukf",)}, "methods"),
        ({"options": {"lkf_mean": "log"}}, "options"),
        (
            {"methods": ("dkf",)},
            "methods",
        ),  # the exact DKF does not apply to range-bearing sensors in clutter
    ],
)
def test_job_rejects_each_bad_field_naming_it(kw, field):
    args = {"cases": (SMALL,), "runs": 2, "seed": 1, **kw}
    with pytest.raises(ConfigError) as err:
        slrt.SlrtJob(**args)
    assert err.value.field == field


@pytest.fixture(scope="module")
def study_scores():
    st = slrt.SlrtStudy(SMALL, pd=(0.9, 0.3), filter_pd=0.9, runs=7, seed=5, methods=("fkf", "ckf"))
    return st, run_job(st.job())


def test_the_job_follows_the_engine_protocol_and_equals_a_direct_run(study_scores, many_tasks):
    st, scores = study_scores
    job = st.job()
    assert isinstance(job, MonteCarloJob) and job.name == "slrt"
    assert job_trials(job) == 3 * 7 and len(job.tasks()) == 3 * 7  # many_tasks: one run per task
    assert job.identity()["methods"] == ["fkf", "ckf"] and job.identity()["runs"] == 7
    assert [list(s) for s in scores] == [["fkf", "ckf"]] * 3
    for (_, sc), got in zip(st.cases, scores, strict=True):
        direct, _ = slrt.run(sc, 7, 5, ("fkf", "ckf"))
        for m in got:
            np.testing.assert_allclose(got[m], direct[m], rtol=1e-12, atol=1e-12)
    chunked = run_job(job)  # under many_tasks: one run per task, joined in task order
    for a, b in zip(chunked, scores, strict=True):
        for m in a:
            np.testing.assert_array_equal(a[m], b[m])  # chunking never changes a bit


def test_decisions_table(study_scores):
    st, scores = study_scores
    t = st.result(scores).table("decisions")
    assert t.columns == slrt.DECISION_COLUMNS and len(t.rows) == 3 * 2
    rows = [dict(zip(t.columns, r, strict=True)) for r in t.rows]
    alpha, beta = st.alpha, st.beta
    for r in rows:
        assert r["confirmed"] + r["deleted"] + r["undecided"] == pytest.approx(1.0)
        assert r["runs"] == 7 and (
            r["tracks"] == 7 if r["target"] else r["tracks"] > 7
        )  # a run's false tracks
        if r["target"]:
            assert r["error_rate"] == r["deleted"] and r["wald_bound"] == beta / (1 - alpha)
        else:
            assert r["error_rate"] == r["confirmed"] and r["wald_bound"] == alpha / (1 - beta)
        p = r["error_rate"]
        n = r["tracks"]  # the binomial count: the runs, or the false tracks
        assert r["error_rate_se"] == pytest.approx(math.sqrt(max(p * (1 - p), 1 / n) / n))
        assert (r["mean_decision_scan"] is None) == (r["undecided"] == 1.0)
    assert [r["method"] for r in rows] == ["fkf", "ckf"] * 3
    assert t.meta["view"] == "decisions" and t.meta["sprt"]["log_B"] == pytest.approx(math.log(0.9 / 1e-3))


def test_curves_table_panels_and_summary(study_scores):
    st, scores = study_scores
    res = st.result(scores)
    t = res.table("curves")
    assert t.columns == slrt.CURVE_COLUMNS and len(t.rows) == 3 * 2 * 6
    first = [r for r in t.rows if r[0] == "target, p_D = 0.3" and r[3] == "ckf"]
    assert [r[4] for r in first] == list(range(1, 7))
    np.testing.assert_allclose([r[5] for r in first], scores[1]["ckf"].mean(axis=0), rtol=1e-15)
    assert all(r[7] <= r[6] <= r[8] for r in t.rows)  # q05 <= median <= q95
    assert t.meta["scenario"]["clutter_rate"] == 2.0 and t.meta["no_target_filter_pd"] == 0.9
    assert "the slides do not give them" in t.meta["assumptions"] and "spec" not in t.meta["assumptions"]
    panels = res.panels()
    assert [p[0] for p in panels] == [label for label, _ in st.cases]
    np.testing.assert_array_equal(panels[0][1], np.arange(1, 7))
    assert res.summary().startswith("slrt: mean log LR at scan 6: target, p_D = 0.9: fkf ")
    with pytest.raises(ConfigError) as err:
        res.table("histogram")
    assert err.value.field == "view"


def test_stop_freezes_and_a_nan_score_is_refused(study_scores):
    st, scores = study_scores
    stopped = slrt.SlrtStudy(
        SMALL, pd=(0.9, 0.3), filter_pd=0.9, runs=7, seed=5, methods=("fkf", "ckf"), stop=True
    )
    frozen = stopped.result(scores)
    decided = 0
    for case, orig in zip(frozen.scores, scores, strict=True):
        for m, v in case.items():
            d = slrt.decisions(orig[m], st.alpha, st.beta)
            for r in range(v.shape[0]):
                if d.decision[r] != 0:
                    decided += int(d.time[r] < 6)
                    assert np.all(v[r, d.time[r] - 1 :] == orig[m][r, d.time[r] - 1])
                    np.testing.assert_array_equal(v[r, : d.time[r]], orig[m][r, : d.time[r]])
                else:
                    np.testing.assert_array_equal(v[r], orig[m][r])
    assert decided > 10  # most runs decide before the last scan: the freeze is exercised
    bad = [dict(s) for s in scores]
    bad[0]["ckf"] = bad[0]["ckf"].copy()
    bad[0]["ckf"][0, 0] = np.nan
    with pytest.raises(RuntimeError, match="NaN"):
        st.result(bad)


def test_scan_picture_is_run_zero_of_the_first_case():
    st = slrt.SlrtStudy(SMALL, pd=(0.5,), runs=2, seed=3)
    sensors, clutter_xy, target_xy, truth, title = slrt.scan_picture(st)
    assert sensors.shape == (4, 2) and len(clutter_xy) == len(target_xy) == 4
    assert truth.shape == (6, 4) and title == "target, p_D = 0.5: run 0, scan 6"
    np.testing.assert_array_equal(truth, slrt.generate(st.cases[0][1], range(2), 3).truth[0])
