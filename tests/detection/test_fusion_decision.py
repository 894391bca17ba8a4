"""Decision-level confirmation (Govaers, *Evaluation of Distributed Detection Methods for Agile Targets*,
Fraunhofer FKIE slides): the naive rule (confirmed when any local test confirms, deleted when all have
deleted) and local decision fusion (weighted mean of local existence probabilities), checked against
direct computations written here, on hand-made and random local scores and on the local filters' own."""

import math

import numpy as np
import pytest

from motionsig_cli.detection.decision_fusion import ldf_score, naive_decisions, naive_score
from motionsig_cli.detection.sprt import CONFIRM, DELETE, UNDECIDED, first_crossing
from motionsig_cli.detection.track_existence import FusionOptions, local_scores, run_methods
from motionsig_cli.existence import slrt

LOG_A, LOG_B = -2.3, 6.8


def rule_by_hand(local, log_a, log_b):
    """The naive rule scan by scan, one run at a time, with explicit per-sensor test states."""
    S, R, K = local.shape
    dec, when = np.zeros(R, int), np.zeros(R, int)
    for r in range(R):
        state = [UNDECIDED] * S
        for k in range(K):
            for s in range(S):
                if state[s] == UNDECIDED:
                    v = local[s, r, k]
                    state[s] = CONFIRM if v >= log_b else DELETE if v <= log_a else UNDECIDED
            if CONFIRM in state:
                dec[r], when[r] = CONFIRM, k + 1
                break
            if all(x == DELETE for x in state):
                dec[r], when[r] = DELETE, k + 1
                break
    return dec, when


def test_naive_rule_on_hand_made_scores():
    """Run 0: sensor 0 deletes at scan 2, sensor 1 confirms at scan 4 → confirmed at 4 (a deleted local
    test stays deleted even when its score later rises above log B). Run 1: both delete (scans 1 and 3)
    → deleted at 3. Run 2: one deletes, one never decides → undecided."""
    local = np.array(
        [
            [[0.0, -3.0, 9.0, 9.0], [-5.0, 0.0, 0.0, 0.0], [-3.0, 0.0, 7.0, 7.0]],
            [[1.0, 2.0, 3.0, 7.0], [0.0, 1.0, -2.5, 9.0], [0.0, 1.0, 2.0, 3.0]],
        ]
    )
    d = naive_decisions(local, LOG_A, LOG_B)
    np.testing.assert_array_equal(d.decision, [CONFIRM, DELETE, UNDECIDED])
    np.testing.assert_array_equal(d.time, [4, 3, 0])
    score = naive_score(local, LOG_A, LOG_B)
    np.testing.assert_array_equal(score[0], [1.0, 2.0, 3.0, 7.0])  # sensor 0 frozen at −3 from scan 2
    np.testing.assert_array_equal(score[1], [0.0, 1.0, -2.5, -2.5])  # both frozen: −5 and −2.5
    d2 = first_crossing(score, LOG_A, LOG_B)
    np.testing.assert_array_equal(d2.decision, d.decision)
    np.testing.assert_array_equal(d2.time, d.time)


def test_the_first_crossing_of_the_naive_score_is_the_rule_on_random_walks():
    """5000 runs of 4 local random walks (drift 0, steps N(0, 1.5²)), so that every combination of local
    decisions occurs: Wald's first crossing of the naive score, the vectorised rule and the rule by hand
    agree run by run."""
    rng = np.random.default_rng(17)
    local = np.cumsum(rng.normal(0.0, 1.5, (4, 5000, 20)), axis=-1)
    local[1, :50, 3] = -np.inf  # a certain deletion (p_D = 1 and an empty scan)
    d = naive_decisions(local, LOG_A, LOG_B)
    by_hand = rule_by_hand(local, LOG_A, LOG_B)
    np.testing.assert_array_equal(d.decision, by_hand[0])
    np.testing.assert_array_equal(d.time, by_hand[1])
    fc = first_crossing(naive_score(local, LOG_A, LOG_B), LOG_A, LOG_B)
    np.testing.assert_array_equal(fc.decision, d.decision)
    np.testing.assert_array_equal(fc.time, d.time)
    assert {CONFIRM, DELETE, UNDECIDED} <= set(d.decision.tolist())
    # the rule differs from a test on the unfrozen maximum: a deleted local test that rises again
    unfrozen = first_crossing(local.max(axis=0), LOG_A, LOG_B)
    assert np.any(unfrozen.decision != d.decision)


def test_naive_scores_use_the_options_thresholds():
    sc = slrt.SlrtScenario(n_sensors=3, scans=15, pd_true=0.5, pd_filter=0.5)
    gen = slrt.generate(sc, range(30), 8)
    model = sc.model()
    local = local_scores(model, gen.m0, gen.scans, FusionOptions())
    for alpha, beta in ((1e-3, 0.1), (0.05, 0.05)):
        opts = FusionOptions(alpha=alpha, beta=beta)
        score = run_methods(model, gen.m0, gen.scans, ["naive"], options=opts)["naive"]
        d = naive_decisions(local, *opts.thresholds)
        fc = first_crossing(score, *opts.thresholds)
        np.testing.assert_array_equal(fc.decision, d.decision)
        np.testing.assert_array_equal(fc.time, d.time)


def ldf_direct(local, prior, weights):
    """LDF in plain floating point (moderate scores only): pˢ = P₀LRˢ/(P₀LRˢ + 1 − P₀), p = Σ wₛpˢ."""
    lr = np.exp(local)
    p_s = prior * lr / (prior * lr + 1.0 - prior)
    p = np.tensordot(weights / weights.sum(), p_s, axes=1)
    return np.log(p / (1.0 - p)) - math.log(prior / (1.0 - prior))


@pytest.mark.parametrize("prior", [0.5, 0.1, 0.97])
def test_ldf_equals_the_direct_formula(prior):
    rng = np.random.default_rng(3)
    local = rng.normal(0.0, 4.0, (3, 50, 6))
    for w in (np.ones(3), np.array([0.2, 0.0, 3.0])):
        np.testing.assert_allclose(
            ldf_score(local, prior, w / w.sum()), ldf_direct(local, prior, w), rtol=1e-10, atol=1e-12
        )


def test_ldf_limits():
    """One sensor, or identical local scores, or one weight: the local log LR itself. Far apart scores
    (+800 and −800, beyond float range as LRs): p = w₁, so the score is log(w₁/(1 − w₁)) − log O₀ —
    finite, the rule's saturation."""
    rng = np.random.default_rng(4)
    one = rng.normal(0.0, 30.0, (1, 10, 5))
    np.testing.assert_allclose(ldf_score(one, 0.3, np.ones(1)), one[0], rtol=1e-12, atol=1e-12)
    same = np.repeat(one, 4, axis=0)
    np.testing.assert_allclose(ldf_score(same, 0.3, np.full(4, 0.25)), one[0], rtol=1e-12, atol=1e-11)
    scaled = same * np.array([1.0, 0.0, 2.0, 3.0])[:, None, None]
    np.testing.assert_allclose(
        ldf_score(scaled, 0.3, np.array([0, 0, 1.0, 0])), 2 * one[0], rtol=1e-12, atol=1e-11
    )
    apart = np.array([[[800.0]], [[-800.0]]])
    w = np.array([0.25, 0.75])
    assert ldf_score(apart, 0.5, w)[0, 0] == pytest.approx(math.log(0.25 / 0.75), rel=1e-12)
    assert ldf_score(np.full((2, 1, 1), -np.inf), 0.5, w)[0, 0] == -np.inf


def test_ldf_and_naive_scores_of_the_filters():
    """On the filters' own local scores the registry's LDF is ldf_score with equal weights and the prior
    of the options, and with weights given, those."""
    sc = slrt.SlrtScenario(n_sensors=3, scans=10, pd_true=0.6, pd_filter=0.6)
    gen = slrt.generate(sc, range(8), 1)
    model = sc.model()
    local = local_scores(model, gen.m0, gen.scans, FusionOptions())
    out = run_methods(model, gen.m0, gen.scans, ["ldf"], options=FusionOptions(ldf_prior=0.2))["ldf"]
    np.testing.assert_array_equal(out, ldf_score(local, 0.2, np.full(3, 1 / 3)))
    w = (1.0, 2.0, 5.0)
    out = run_methods(model, gen.m0, gen.scans, ["ldf"], options=FusionOptions(ldf_weights=w))["ldf"]
    np.testing.assert_array_equal(out, ldf_score(local, 0.5, np.array(w) / 8.0))
