"""The registry of track-existence fusion rules (Govaers, *Evaluation of Distributed Detection Methods for
Agile Targets*, Fraunhofer FKIE slides): every member scores every run and scan, runs independently,
reduces to the centralised filter with one sensor, falls without a target, and is refused (with the
field named) where it does not apply; the options are checked field by field."""

import math
from dataclasses import replace

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.sprt import freeze_at_decision
from motionsig_cli.detection.track_existence import (
    ALL_METHODS,
    FUSION_METHODS,
    METHODS,
    FusionOptions,
    ScanData,
    check_applicable,
    check_methods,
    run_methods,
)
from motionsig_cli.existence import slrt

LINEAR = dict(meas_model="cartesian", pd_true=1.0, pd_filter=1.0, clutter_rate=0.0)
"""Where the exact DKF applies: linear sensors, p_D = 1, no clutter."""


def scenario_for(name, **kw):
    """A scenario the rule applies to: the exact DKF needs LINEAR, every other rule takes the default."""
    return slrt.SlrtScenario(**{**(LINEAR if name == "dkf" else {}), **kw})


@pytest.fixture(scope="module")
def batches():
    """Per rule, 6 runs × 8 scans of three sensors (in clutter with misses, except for the DKF)."""
    out = {}
    for name in FUSION_METHODS:
        kw = {} if name == "dkf" else dict(pd_true=0.7, pd_filter=0.7, clutter_rate=4.0)
        sc = scenario_for(name, n_sensors=3, scans=8, **kw)
        out[name] = (sc, slrt.generate(sc, range(6), 11))
    return out


def test_the_registry_names_every_rule_and_the_default_selection():
    assert (
        ALL_METHODS == tuple(FUSION_METHODS) == ("ckf", "dkf", "fkf", "fkf-feedback", "lkf", "ldf", "naive")
    )
    assert METHODS == ("ckf", "fkf", "lkf")  # the slides' curves, the command's default
    assert [n for n, m in FUSION_METHODS.items() if m.uses_thresholds] == ["naive"]
    assert {n for n, m in FUSION_METHODS.items() if m.check is not None} == {"dkf", "ldf"}


@pytest.mark.parametrize("name", list(FUSION_METHODS))
def test_each_method_is_described(name):
    method = FUSION_METHODS[name]
    assert method.abbreviation and method.title and method.description
    assert method.help == f"{method.abbreviation} = {method.title}: {method.description}"
    assert "spec" not in method.help.lower() and "issue" not in method.help.lower()


@pytest.mark.parametrize("name", list(FUSION_METHODS))
@pytest.mark.parametrize("lkf_mean", ["lr", "log"])
def test_each_method_scores_every_run_and_scan_finitely(name, lkf_mean, batches):
    sc, gen = batches[name]
    out = FUSION_METHODS[name].score(sc.model(), gen.m0, gen.scans, FusionOptions(lkf_mean))
    assert out.shape == (6, 8) and out.dtype == np.float64
    assert np.all(np.isfinite(out))
    np.testing.assert_array_equal(
        out, run_methods(sc.model(), gen.m0, gen.scans, [name], lkf_mean=lkf_mean)[name]
    )
    np.testing.assert_array_equal(
        out, run_methods(sc.model(), gen.m0, gen.scans, [name], options=FusionOptions(lkf_mean))[name]
    )


@pytest.mark.parametrize("name", list(FUSION_METHODS))
def test_each_method_scores_runs_independently(name, batches):
    """A run's score depends on that run's data only: the first 3 of a 6-run batch equal a 3-run batch."""
    sc, gen = batches[name]
    model, options = sc.model(), FusionOptions()
    part = [ScanData(tuple(z[:3] for z in s.Z), tuple(v[:3] for v in s.valid)) for s in gen.scans]
    full = FUSION_METHODS[name].score(model, gen.m0, gen.scans, options)
    np.testing.assert_allclose(
        FUSION_METHODS[name].score(model, gen.m0[:3], part, options), full[:3], rtol=1e-12
    )


@pytest.mark.parametrize("name", list(FUSION_METHODS))
def test_each_method_equals_the_centralised_filter_with_one_sensor(name):
    """With one sensor there is nothing to fuse: every method is the centralised filter (naive: its score
    frozen at its decision, as the one local test stops there)."""
    sc = scenario_for(name, n_sensors=1, scans=10, **({} if name == "dkf" else {"clutter_rate": 3.0}))
    gen = slrt.generate(sc, range(4), 2)
    model, options = sc.model(), FusionOptions()
    ckf = FUSION_METHODS["ckf"].score(model, gen.m0, gen.scans, options)
    if name == "naive":
        ckf = freeze_at_decision(ckf, *options.thresholds)
        assert np.any(ckf != FUSION_METHODS["ckf"].score(model, gen.m0, gen.scans, options))  # it did stop
    np.testing.assert_allclose(FUSION_METHODS[name].score(model, gen.m0, gen.scans, options), ckf, rtol=1e-12)


@pytest.mark.parametrize("name", list(FUSION_METHODS))
def test_each_method_falls_without_a_target(name):
    """Without a target the mean score falls scan by scan (naive: until every run's local tests have
    deleted, then it stays); where the DKF applies (p_D = 1, no clutter) an empty scan is certain deletion."""
    sc = scenario_for(name, target=False, scans=10)
    gen = slrt.generate(sc, range(20), 4)
    out = FUSION_METHODS[name].score(sc.model(), gen.m0, gen.scans, FusionOptions())
    mean = out.mean(axis=0)
    if name == "dkf":
        assert np.all(out == -np.inf)
    elif name == "naive":
        log_a = FusionOptions().thresholds[0]
        assert np.all(np.diff(mean) <= 0) and mean[-1] <= log_a and np.all(out[:, -1] <= log_a)
    else:
        assert np.all(np.diff(mean) < 0)


@pytest.mark.parametrize(
    ("kw", "why"),
    [
        ({}, "range-bearing sensors"),
        ({"meas_model": "cartesian"}, "here: p_D < 1 ("),
        ({"meas_model": "cartesian", "clutter_rate": 0.0}, "here: p_D < 1"),
        (
            {**LINEAR, "clutter_rate": 1.0, "pd_filter": 0.9},
            "here: p_D < 1 (",
        ),  # the filters' clutter density is no reason
    ],
)
def test_dkf_is_refused_where_it_is_not_exact_before_any_scoring(kw, why, monkeypatch):
    sc = slrt.SlrtScenario(scans=2, **kw)
    gen = slrt.generate(sc, range(1), 0)
    scored = []
    monkeypatch.setitem(
        FUSION_METHODS, "ckf", replace(FUSION_METHODS["ckf"], score=lambda *a: scored.append(1))
    )
    with pytest.raises(ConfigError) as err:
        run_methods(sc.model(), gen.m0, gen.scans, ("ckf", "dkf"))
    assert err.value.field == "methods" and err.value.value == "dkf" and why in err.value.reason
    assert "fkf" in err.value.reason and scored == []  # refused before the first rule ran


def test_dkf_is_refused_with_a_gate_and_accepts_a_gate_of_one():
    sc = slrt.SlrtScenario(scans=3, **LINEAR)
    gen = slrt.generate(sc, range(2), 0)
    with pytest.raises(ConfigError, match="a gate"):
        check_applicable(["dkf"], sc.model(), FusionOptions(gate_pg=0.99))
    a = run_methods(sc.model(), gen.m0, gen.scans, ["dkf"], options=FusionOptions(gate_pg=1.0))["dkf"]
    np.testing.assert_array_equal(a, run_methods(sc.model(), gen.m0, gen.scans, ["dkf"])["dkf"])


def test_dkf_refuses_two_measurements_of_one_sensor_in_a_scan():
    """Without clutter a sensor reports at most the target; a second measurement makes the local update a
    mixture, where the DKF is not exact: refused, naming the scan."""
    sc = slrt.SlrtScenario(scans=3, **LINEAR)
    gen = slrt.generate(sc, range(2), 0)
    z, v = gen.scans[1].Z[0], gen.scans[1].valid[0]
    scans = list(gen.scans)
    Z0 = np.concatenate([z, z + 10.0], axis=1)
    scans[1] = ScanData((Z0, *gen.scans[1].Z[1:]), (np.concatenate([v, v], axis=1), *gen.scans[1].valid[1:]))
    with pytest.raises(ConfigError, match="scan 2 has 2"):
        run_methods(sc.model(), gen.m0, scans, ["dkf"])


def test_ldf_weights_must_match_the_sensors():
    sc = slrt.SlrtScenario(scans=2)
    gen = slrt.generate(sc, range(1), 0)
    with pytest.raises(ConfigError) as err:
        run_methods(sc.model(), gen.m0, gen.scans, ["ldf"], options=FusionOptions(ldf_weights=(1.0, 1.0)))
    assert err.value.field == "ldf_weights" and "2 weights for 4 sensors" in err.value.reason


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("lkf_mean", "median"),
        ("gate_pg", 0.0),
        ("gate_pg", 1.01),
        ("gate_pg", math.nan),
        ("feedback_every", 0),
        ("feedback_every", 1.5),
        ("feedback_every", 100_001),
        ("ldf_prior", 0.0),
        ("ldf_prior", 1.0),
        ("ldf_weights", ()),
        ("ldf_weights", (1.0, -0.5)),
        ("ldf_weights", (0.0, 0.0)),
        ("ldf_weights", (1.0, math.inf)),
        ("alpha", 0.0),
        ("alpha", 0.5),
        ("beta", 0.0),
        ("beta", 0.6),
    ],
)
def test_fusion_options_reject_each_bad_field_naming_it(field, value):
    with pytest.raises(ConfigError) as err:
        FusionOptions(**{field: value})
    assert err.value.field == field


def test_fusion_options_accept_the_edges_and_give_the_local_thresholds():
    o = FusionOptions(gate_pg=1.0, feedback_every=100_000, ldf_prior=1e-9, ldf_weights=(0.0, 2.0), alpha=0.01)
    assert o.thresholds == pytest.approx((math.log(0.1 / 0.99), math.log(0.9 / 0.01)))
    assert FusionOptions().thresholds == pytest.approx((-2.302, 6.802), abs=1e-3)


def test_method_names_are_checked_against_every_rule():
    assert check_methods(["naive", "fkf-feedback"]) == ("naive", "fkf-feedback")
    for bad in ((), ("ckf", "ukf"), ("DKF",)):
        with pytest.raises(ConfigError) as err:
            check_methods(bad)
        assert err.value.field == "methods"
    with pytest.raises(ConfigError, match="ckf, dkf, fkf, fkf-feedback, lkf, ldf, naive"):
        check_methods(["ukf"])
