"""Monte Carlo ROC under multiple-access noise (ATC-10 §3): plain Monte Carlo against the exact ROC,
importance sampling in the deep tail, the chip-level PSK ensemble, a negative control, reproducibility;
the configurations of ``mac-roc`` and the Monte Carlo job.

Tolerances are statistical: 4 standard errors (binomial σ̂ = √(p̂(1 − p̂)/n) for plain Monte Carlo,
the sample relative standard error of the weights for importance sampling); seeds are fixed.
"""

import json
import math

import numpy as np
import pytest

from motionsig_cli.atc10 import mac_roc as exp
from motionsig_cli.config import ConfigError
from motionsig_cli.engine import Engine, MonteCarloJob, run_job
from motionsig_cli.surveillance.amplitude import b_of_ell
from motionsig_cli.surveillance.densities import density
from motionsig_cli.surveillance.multiple_access import MANModel
from motionsig_cli.surveillance.psk_amplitude import PSKAmplitude
from motionsig_cli.surveillance.roc_bounds import roc_bounds
from motionsig_cli.surveillance.roc_exact import exact_roc
from motionsig_cli.surveillance.time_bandwidth import MSEQ31

THETA = np.array(exp.MC_THETA)  # the Monte Carlo's check grid


def _z(est, se, exact):
    return (est - exact) / np.where(se > 0, se, np.inf)


@pytest.mark.parametrize(
    ("name", "ell"),
    [
        ("uniform", 4.0),
        ("uniform", 8.0),
        ("two-point", 4.0),
        ("two-point", 8.0),
        ("triangular", 6.0),
        ("gaussian", 6.0),
        ("laplace", 8.0),
    ],
)
def test_monte_carlo_agrees_with_exact_and_lies_between_the_bounds(name, ell):
    """Level A, 4·10⁵ trials: |z| < 4 against the exact ROC for p_f and p_m, the sample power within 4 SE
    of P, and the sandwich LB − 4σ ≤ p̂ ≤ UB + 4σ."""
    m = exp.report_model(name, ell)
    mc = exp.monte_carlo(m, THETA, 400_000, seed=12)
    e = exact_roc(m, THETA)
    assert np.all(np.abs(_z(mc.pf, mc.pf_se, np.exp(e.log_pf))) < 4)
    assert np.all(np.abs(_z(mc.pm, mc.pm_se, np.exp(e.log_pm))) < 4)
    assert abs(mc.power - m.power) < 4 * mc.power_se
    rb = roc_bounds(m, THETA)
    assert np.all(exp.within_bounds(mc.pf, mc.pf_se, np.exp(rb.log_pf_lo), np.exp(rb.log_pf_up), mc.trials))
    assert np.all(exp.within_bounds(mc.pm, mc.pm_se, np.exp(rb.log_pm_lo), np.exp(rb.log_pm_up), mc.trials))


def test_negative_control_twice_the_power_fails_the_sharp_check():
    """A simulator with a 2× power error (b doubled, as when the carrier cos φ factor is dropped) must fail
    the z-test against the correct exact ROC (the bounds alone are too loose to be relied on)."""
    right = exp.report_model("uniform", 8.0)
    wrong = MANModel.common(right.N, right.tau_over_alpha, density("uniform", 2 * b_of_ell(8.0)))
    mc = exp.monte_carlo(wrong, THETA, 400_000, seed=12)
    e = exact_roc(right, THETA)
    z = np.concatenate([_z(mc.pf, mc.pf_se, np.exp(e.log_pf)), _z(mc.pm, mc.pm_se, np.exp(e.log_pm))])
    assert np.max(np.abs(z)) > 4  # detected (measured: |z| up to ~100)
    assert abs(mc.power - right.power) > 4 * mc.power_se


def test_monte_carlo_reference_t12():
    """T12: uniform, ℓ = 8, θ = 0.5: p̂_f within 4σ of 8.236968e-4 (here 10⁶ trials, σ ≈ 2.9e-5)."""
    mc = exp.monte_carlo(exp.report_model("uniform", 8.0), [0.5], 1_000_000, seed=2008)
    assert abs(mc.pf[0] - 8.236968e-4) < 4 * mc.pf_se[0]


@pytest.mark.parametrize(
    ("name", "theta"), [("uniform", 0.8), ("two-point", 0.8), ("gaussian", 0.75), ("triangular", 0.85)]
)
def test_importance_sampling_reaches_1e_minus_20(name, theta):
    """Importance sampling agrees with the exact value to 1 % relative at
    p_f ≈ 1e-20 (ℓ = 20; measured relative SE ≈ 0.3 % with 10⁶ trials), and within 4 relative SE."""
    m = exp.report_model(name, 20.0)
    e = exact_roc(m, [theta])
    pf = math.exp(e.log_pf[0])
    assert 1e-24 < pf < 1e-15
    s = exp.importance_sampling(m, [theta], 1_000_000, seed=5)
    err = s.p[0] / pf - 1.0
    assert abs(err) < 0.01 and abs(err) < 4 * s.rel_se[0]
    sm = exp.importance_sampling(m, [theta], 200_000, seed=5, side="pm")
    assert abs(sm.p[0] / math.exp(e.log_pm[0]) - 1.0) < 4 * sm.rel_se[0]


def test_importance_sampling_streams_are_keyed_by_theta_and_blocks_by_seed():
    m = exp.report_model("uniform", 12.0)
    one = exp.importance_sampling(m, [0.5], 70_000, seed=3)
    two = exp.importance_sampling(m, [0.3, 0.5], 70_000, seed=3)
    assert one.log_p[0] == two.log_p[1]
    other = exp.importance_sampling(m, [0.5], 70_000, seed=4)
    assert other.log_p[0] != one.log_p[0]


def test_monte_carlo_is_a_sum_of_independent_blocks():
    """Trials run in blocks of BLOCK with their own SeedSequence child: the result is the sum of the
    blocks, whatever runs them, and the same seed gives the same counts."""
    m = exp.report_model("two-point", 6.0)
    trials = exp.BLOCK + 1000
    mc = exp.monte_carlo(m, THETA, trials, seed=9)
    parts = [exp.monte_carlo_block(m, THETA, 9, b, size) for b, size in exp.n_blocks(trials)]
    assert np.array_equal(mc.false_alarms, sum(p[0] for p in parts))
    assert np.array_equal(mc.misses, sum(p[1] for p in parts))
    again = exp.monte_carlo(m, THETA, trials, seed=9)
    assert np.array_equal(again.false_alarms, mc.false_alarms)
    assert not np.array_equal(exp.monte_carlo(m, THETA, trials, seed=10).false_alarms, mc.false_alarms)
    with pytest.raises(ValueError, match=">= 1"):
        exp.n_blocks(0)


def test_psk_chip_level_monte_carlo_reference_t11():
    """Level B with the length-31 m-sequence and random interferer codes: E n_ij² = b = 1/186 within
    4 SE; p̂_f(0.5) agrees with a reference 10⁷-trial estimate 2.390e-3 ± 1.5e-5 within 4 combined SE,
    p̂_m(0.5) with 2.410e-3; both lie inside the quadrature bounds; ROC_g (3.25e-4) is ~7× optimistic."""
    d = PSKAmplitude(tuple(int(v) for v in MSEQ31))
    x = d.sample(np.random.default_rng(1), 1_000_000)
    assert abs(np.mean(x * x) - d.b) < 4 * np.std(x * x) / math.sqrt(x.size)
    m = MANModel.common(exp.REPORT_N, exp.REPORT_TAU_OVER_ALPHA, d)
    mc = exp.monte_carlo(m, [0.5], 1_000_000, seed=31)
    for est, se, ref in ((mc.pf[0], mc.pf_se[0], 2.390e-3), (mc.pm[0], mc.pm_se[0], 2.410e-3)):
        assert abs(est - ref) < 4 * math.hypot(se, 1.5e-5)
    rb = roc_bounds(m, [0.5])
    assert math.exp(rb.log_pf_lo[0]) < mc.pf[0] < math.exp(rb.log_pf_up[0])
    from motionsig_cli.surveillance.gaussian_roc import gaussian_roc

    assert mc.pf[0] > 5 * math.exp(gaussian_roc(m.power, [0.5]).log_pf[0])


def test_psk_gold_family_sampling_matches_its_second_moment():
    from motionsig_cli.signals.gold import gold_family

    _, codes = gold_family(0o45, 0o75)
    pm = 1 - 2 * codes.astype(int)
    d = PSKAmplitude(tuple(pm[0]), tuple(map(tuple, pm[1:])))
    x = d.sample(np.random.default_rng(2), 1_000_000)
    assert abs(np.mean(x * x) - d.b) < 4 * np.std(x * x) / math.sqrt(x.size)
    assert np.max(np.abs(x)) <= d.max_abs + 1e-12


def test_theta_grid_and_figure_routing():
    g = exp.theta_grid(0.01, 0.99, 0.01)
    assert g.size == 99 and g[0] == 0.01 and g[-1] == 0.99
    with pytest.raises(ValueError, match="empty"):
        exp.theta_grid(0.9, 0.1, 0.01)
    assert exp.figure_command("3.4") == "bounds" and exp.DENSITY_OF_FIGURE["3.4"] == "two-point"
    assert [exp.DENSITY_OF_FIGURE[f] for f in ("3.3", "3.5", "3.6")] == ["uniform", "triangular", "gaussian"]
    with pytest.raises(ValueError, match="no Fig"):
        exp.figure_command("2.1")


def test_fig_3_2_densities_have_equal_second_moment():
    for rid, name, *_ in exp.density_curves():
        assert exp.second_moment(density(name, exp.FIG32_B)) == pytest.approx(exp.FIG32_B, rel=1e-8), rid


def test_amplitudes_are_drawn_in_bounded_slices(monkeypatch):
    """With many overlapping interferers the amplitudes are drawn in slices of at most MAX_DRAWS: the
    per-trial sums are the same as one big draw (uniform draws are sequential in the stream)."""
    m = MANModel.common(10**7, 2e-5, density("two-point", b_of_ell(8.0)))  # Mq = 400
    whole = exp.noise_samples(m, np.random.default_rng(1), 3000)
    monkeypatch.setattr(exp, "MAX_DRAWS", 1000)
    sliced = exp.noise_samples(m, np.random.default_rng(1), 3000)
    assert np.allclose(sliced, whole, rtol=0, atol=1e-12)
    assert exp.expected_draws(m, 1000, 2) == pytest.approx(2 * 1000 * m.mean_active)


# --- the configurations: each rejects a bad value of every checked field, naming the field --------

PSK = {"density": "psk"}
BAD = [
    (exp.Contours, {"density": "cauchy"}, "density"),
    (exp.Contours, {"ell": (-1.0,)}, "ell"),
    (exp.Contours, {"ell": ()}, "ell"),
    (exp.Contours, {"b": (0.0,)}, "b"),
    (exp.Contours, {"b": (math.inf,)}, "b"),
    (exp.Contours, {"ell": (8.0,), "b": (0.1,)}, "b"),
    (exp.Contours, {"N": 1}, "N"),
    (exp.Contours, {"N": 0}, "N"),
    (exp.Contours, {"N": 2.5}, "N"),
    (exp.Contours, {"N": math.nan}, "N"),
    (exp.Contours, {"N": 10**16}, "N"),
    (exp.Contours, {"tau_over_alpha": 0.5}, "tau_over_alpha"),
    (exp.Contours, {"tau_over_alpha": 1e-60}, "tau_over_alpha"),
    (exp.Contours, {"tau_over_alpha": -1.0}, "tau_over_alpha"),
    (exp.Contours, {"theta": (0.0, 0.5)}, "theta"),
    (exp.Contours, {"theta": (1.5,)}, "theta"),
    (exp.Contours, {"theta": ()}, "theta"),
    (exp.Contours, {"interferers": "some"}, "interferers"),
    (exp.Contours, {**PSK, "code": "xyz"}, "code"),
    (exp.Contours, {**PSK, "code": "gold:45,75:99"}, "code"),
    (exp.Contours, {**PSK, "code": "mseq:45,3"}, "code"),
    (exp.Contours, {**PSK, "code": "+"}, "code"),
    (exp.Contours, {**PSK, "code": "file:x.csv"}, "code"),
    (exp.Contours, {**PSK, "ell": (8.0,)}, "ell"),
    (exp.Contours, {**PSK, "interferers": "family"}, "interferers"),
    (exp.BoundsConfig, {"figure": "3.9"}, "figure"),
    (exp.BoundsConfig, {"figure": "4.2"}, "figure"),
    (exp.BoundsConfig, {"figure": "3.3", "density": "C2"}, "density"),
    (exp.BoundsConfig, {"at_pd": (1.0,)}, "at_pd"),
    (exp.BoundsConfig, {"lower_variant": "tight"}, "lower_variant"),
    (exp.BoundsConfig, {**PSK, "exact": True}, "exact"),
    (exp.BoundsConfig, {"montecarlo": 0}, "montecarlo"),
    (exp.BoundsConfig, {"montecarlo": 10**11}, "montecarlo"),
    (exp.BoundsConfig, {"montecarlo": 1000, "at_pd": (0.9,)}, "montecarlo"),
    (exp.BoundsConfig, {"montecarlo": 10**6, "N": 10**12}, "montecarlo"),
    (exp.BoundsConfig, {"seed": -1}, "seed"),
    (exp.ExactConfig, {"density": "psk"}, "density"),
    (exp.ExactConfig, {"density": "arcsine"}, "density"),
    (exp.ExactConfig, {"lower_variant": "x"}, "lower_variant"),
    (exp.MonteCarloConfig, {"trials": 0}, "trials"),
    (exp.MonteCarloConfig, {"trials": 1.5}, "trials"),
    (exp.MonteCarloConfig, {"trials": 10**6, "N": 10**12}, "trials"),
    (exp.MonteCarloConfig, {"importance": True, "density": "arcsine"}, "importance"),
    (exp.MonteCarloConfig, {"importance": True, **PSK}, "importance"),
    (exp.MonteCarloConfig, {"seed": -3}, "seed"),
    (exp.MonteCarloConfig, {"lower_variant": "x"}, "lower_variant"),
    (exp.GaussianConfig, {"figure": "3.3"}, "figure"),
    (exp.GaussianConfig, {"gauss_variance": "M"}, "gauss_variance"),
    (exp.ExponentConfig, {"figure": "3.8"}, "figure"),
    (exp.ExponentConfig, {"expg": (-1.0,)}, "expg"),
    (exp.ExponentConfig, {"expg": (math.inf,)}, "expg"),
    (exp.ExponentConfig, {"N": (1.0,)}, "N"),
    (exp.ExponentConfig, {"tau_over_alpha": (0.5,)}, "tau_over_alpha"),
    (exp.ExponentConfig, {"expg": tuple(range(2000)), "N": tuple(range(2, 1000))}, "expg"),
    (exp.DensitiesConfig, {"figure": "3.3"}, "figure"),
    (exp.DensitiesConfig, {"b": 0.0}, "b"),
    (exp.DensitiesConfig, {"b": math.nan}, "b"),
    (exp.BandwidthConfig, {"alpha": 0.0}, "alpha"),
    (exp.BandwidthConfig, {"tau_c": -1e-7}, "tau_c"),
    (exp.BandwidthConfig, {"N": 0}, "N"),
    (exp.BandwidthConfig, {"code": ()}, "code"),
    (exp.BandwidthConfig, {"code": ("+2-",)}, "code"),
    (exp.BandwidthConfig, {"code": ("mseq:77777",)}, "code"),
]


@pytest.mark.parametrize(
    ("cls", "kwargs", "name"), BAD, ids=[f"{c.__name__}-{n}-{i}" for i, (c, _, n) in enumerate(BAD)]
)
def test_a_configuration_rejects_a_bad_value_naming_the_field(cls, kwargs, name):
    with pytest.raises(ConfigError) as info:
        cls(**kwargs)
    assert info.value.field == name
    assert name in str(info.value)


def test_configurations_resolve_names_and_defaults():
    """Report ids name the registry member; a figure sets the density; ℓ and b are kept without repeats
    in their order, θ sorted; N may be given as a whole float (1e5)."""
    c = exp.Contours(density="C1", ell=(8.0, 4.0, 8.0), N=1e5, theta=(0.5, 0.2, 0.5))
    assert c.density == "uniform" and c.ell == (8.0, 4.0) and c.N == 100_000 and isinstance(c.N, int)
    assert c.theta == (0.2, 0.5) and [e for e, _ in c.models] == pytest.approx([8.0, 4.0])
    assert exp.BoundsConfig(figure="3.5").density == "triangular"
    assert exp.BoundsConfig().density == "two-point" and exp.BoundsConfig(at_pd=(0.9,)).theta is None
    assert exp.ExponentConfig(expg=(1.0,), N=(1e5,)).figure == "3.10" and exp.ExponentConfig().figure == "3.9"
    psk = exp.Contours(density="psk", code="gold:45,75:3", interferers="family")
    assert psk.info == {"density": "psk", "code": "gold:45,75:3", "chips": 31, "interferers": "family"}
    files = (("file:f.csv", ((1, -1, 1), (1, 1, -1), (-1, 1, 1))),)
    fam = exp.Contours(density="psk", code="file:f.csv", interferers="family", code_files=files)
    assert fam.models[0][1].common_density.family == ((1, 1, -1), (-1, 1, 1))


# --- the Monte Carlo job ---------------------------------------------------------------------------


def test_the_job_implements_the_engine_protocol_and_names_its_checkpoint():
    m = exp.report_model("uniform", 8.0)
    plain = exp.MacRocJob((m,), (0.5,), 1000, 3)
    tilted = exp.MacRocJob.importance((m,), (0.5,), 1000, 3)
    overlay = exp.MacRocBoundsJob((m,), (0.5,), 1000, 3)
    for job in (plain, tilted, overlay):
        assert isinstance(job, MonteCarloJob)
        assert sum(job.task_size(t) for t in job.tasks()) == 1000 * (1 if job.tilted is None else 2)
        json.dumps(job.identity())  # JSON values (the checkpoint's manifest)
    assert plain.name == "mac-roc montecarlo" and overlay.name == "mac-roc bounds --montecarlo"
    assert plain.identity()["importance"] is None and tilted.identity()["importance"] == ["pf", "pm"]
    assert plain.identity()["models"][0]["components"][0][0] == {"a": 0.125, "name": "uniform"}
    assert plain.identity() != exp.MacRocJob((m,), (0.5,), 1000, 4).identity()
    for bad, name in (({"trials": 0}, "trials"), ({"seed": -1}, "seed"), ({"sides": ("pd",)}, "sides")):
        with pytest.raises(ConfigError) as info:
            exp.MacRocJob(**{"models": (m,), "theta": (0.5,), "trials": 10, **bad})
        assert info.value.field == name


def test_the_job_result_does_not_depend_on_the_chunking(monkeypatch):
    """The same numbers with one block per task (many tasks) as with the cost model's chunking, plain
    and importance sampling: the reduction joins blocks in block order."""
    models = (exp.report_model("two-point", 6.0), exp.report_model("uniform", 10.0))
    trials = 3 * exp.BLOCK + 17
    plain = exp.MacRocJob(models, (0.3, 0.6), trials, 11)
    tilted = exp.MacRocJob.importance(models[:1], (0.5, 0.9), exp.BLOCK + 5, 11)
    whole = [run_job(plain, Engine()), run_job(tilted, Engine())]
    monkeypatch.setattr(exp, "blocks_per_task", lambda seconds: 1)
    assert len(plain.tasks()) == 2 * 4
    split = [run_job(plain, Engine()), run_job(tilted, Engine())]
    for a, b in zip(whole[0], split[0], strict=True):
        assert (
            np.array_equal(a.false_alarms, b.false_alarms) and a.sum_n2 == b.sum_n2 and a.sum_n4 == b.sum_n4
        )
    for side in ("pf", "pm"):
        assert np.array_equal(whole[1][0][side].log_p, split[1][0][side].log_p)
    single = exp.monte_carlo(models[1], np.array([0.3, 0.6]), trials, 11)
    assert np.array_equal(single.misses, whole[0][1].misses)  # a model's streams do not depend on the others
