"""Decision-level track confirmation from several sensors (Govaers, *Evaluation of Distributed Detection
Methods for Agile Targets*, Fraunhofer FKIE, slides: "Naïve: local tracks are accepted as confirmed";
"Local Decision Fusion: weighted mean of local existence probability").

Both rules read only the local filters' own scores, log LRˢ(k) of sensor s
(:func:`~motionsig_cli.detection.existence_model.local_scores`: one single-sensor filter per sensor with
the true model (F, Q), as LKF's); nothing but a decision or a probability leaves a sensor.

**Naive** (:func:`score_naive`, :func:`naive_decisions`). Every sensor runs its own Wald test on log LRˢ
with the thresholds (log A, log B) of ``FusionOptions.alpha, beta``; a local test stops at its first
crossing. Rule (ours, the slides give none beyond "local tracks are accepted as confirmed"): the track
is **confirmed as soon as any local test confirms** it and **deleted once every local test has deleted
it**; otherwise undecided. The score for the curves is

    score(k) = max_s  log LRˢ(min(k, kˢ))      (kˢ: the scan of local test s's decision, or ∞)

— the largest local log LR, each frozen at its own decision. Wald's first crossing of this score with the
same (log A, log B) *is* the rule: at scan k a frozen local score is ≥ log B iff that test has confirmed
by k, ≤ log A iff it has deleted by k, and inside (log A, log B) otherwise; so the maximum reaches
log B iff some local test has confirmed, and falls to log A iff all have deleted (a test that deleted
never confirms, so at most one of the two happens). A study that decides with other thresholds than the
options' gets a different rule: pass them in. With one sensor the score is the centralised filter's,
frozen at its decision. Its false-confirmation probability is at most S·α (any of S tests), not α.

**LDF** (:func:`score_ldf`). With the prior existence probability P₀ (``FusionOptions.ldf_prior``) and
prior odds O₀ = P₀/(1 − P₀), sensor s's posterior odds are Oˢ = O₀·LRˢ (Bayes), so its existence
probability is

    pˢ = Oˢ/(1 + Oˢ) = P₀ LRˢ / (P₀ LRˢ + 1 − P₀).

The fused probability is the weighted mean p = Σ_s w_s pˢ (weights ``ldf_weights`` divided by their sum;
default 1/S), and the score is its log odds relative to the prior odds,

    score = log(p/(1 − p)) − log O₀,

the LR that would turn the prior into p: with one sensor (or identical local scores) it is log LRˢ, so it
is comparable with the other rules' log LR and Wald's thresholds apply to it. In the log domain
(nothing overflows): with ℓˢ = log LRˢ, a = log P₀, b = log(1 − P₀), Lˢ = logaddexp(a + ℓˢ, b),
log pˢ = a + ℓˢ − Lˢ, log(1 − pˢ) = b − Lˢ, log p = logsumexp_s(log w_s + log pˢ),
log(1 − p) = logsumexp_s(log w_s + log(1 − pˢ)) (as Σ w_s = 1). p is bounded by the largest weighted
agreement: one confident sensor alone moves p to at most its weight.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.existence_model import (
    FusionOptions,
    ScanData,
    TrackExistenceModel,
    local_scores,
)
from motionsig_cli.detection.sprt import (
    CONFIRM,
    DELETE,
    UNDECIDED,
    Decisions,
    first_crossing,
    freeze_at_decision,
)

__all__ = [
    "check_ldf",
    "ldf_score",
    "naive_decisions",
    "naive_score",
    "score_ldf",
    "score_naive",
]


def naive_score(local: np.ndarray, log_a: float, log_b: float) -> np.ndarray:
    """The naive rule's score from local scores (S, R, K): the largest local log LR, each frozen at its
    own first crossing of (log A, log B); (R, K)."""
    S, R, K = local.shape
    frozen = freeze_at_decision(local.reshape(S * R, K), log_a, log_b).reshape(S, R, K)
    return frozen.max(axis=0)


def naive_decisions(local: np.ndarray, log_a: float, log_b: float) -> Decisions:
    """The naive rule on local scores (S, R, K), applied directly: confirmed at the first local
    confirmation, deleted at the last local deletion when every local test deleted, else undecided (the
    time 0). Equal to Wald's first crossing of :func:`naive_score` (module docstring)."""
    S, R, K = local.shape
    d = first_crossing(local.reshape(S * R, K), log_a, log_b)
    dec, time = d.decision.reshape(S, R), d.time.reshape(S, R)
    confirmed = dec == CONFIRM
    any_confirmed = confirmed.any(axis=0)
    all_deleted = (dec == DELETE).all(axis=0)
    t_confirm = np.where(confirmed, time, K + 1).min(axis=0)
    decision = np.where(any_confirmed, CONFIRM, np.where(all_deleted, DELETE, UNDECIDED))
    when = np.where(any_confirmed, t_confirm, np.where(all_deleted, time.max(axis=0), 0))
    return Decisions(decision=decision, time=when)


def score_naive(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """Naive: every sensor's own test, confirmed when any confirms, deleted when all have deleted; the score
    whose first crossing is that rule (:func:`naive_score`, thresholds from ``options``); (R, K)."""
    return naive_score(local_scores(model, m0, scans, options), *options.thresholds)


def _weights(options: FusionOptions, n_sensors: int) -> np.ndarray:
    if options.ldf_weights is None:
        return np.full(n_sensors, 1.0 / n_sensors)
    w = np.asarray(options.ldf_weights, dtype=float)
    return w / w.sum()


def check_ldf(model: TrackExistenceModel, options: FusionOptions) -> None:
    """LDF's weights, if given, are one per sensor (:class:`~motionsig_cli.config.ConfigError` naming
    ``ldf_weights``)."""
    if options.ldf_weights is not None and len(options.ldf_weights) != model.n_sensors:
        raise ConfigError(
            "ldf_weights",
            options.ldf_weights,
            f"are {len(options.ldf_weights)} weights for {model.n_sensors} sensors",
        )


def _logsumexp0(x: np.ndarray) -> np.ndarray:
    """log Σ exp over axis 0, −inf where every term is −inf."""
    top = x.max(axis=0)
    safe = np.where(np.isneginf(top), 0.0, top)
    with np.errstate(divide="ignore"):
        return safe + np.log(np.sum(np.exp(x - safe), axis=0))


def ldf_score(local: np.ndarray, prior: float, weights: np.ndarray) -> np.ndarray:
    """LDF's score from local scores (S, R, K), the prior P₀ and weights (S,) summing to 1: the log odds
    of p = Σ w_s pˢ minus the prior log odds (module docstring); (R, K)."""
    a, b = math.log(prior), math.log1p(-prior)
    with np.errstate(divide="ignore"):
        log_w = np.log(weights)[:, None, None]
    L = np.logaddexp(a + local, b)
    log_p = _logsumexp0(log_w + (a + local - L))
    log_q = _logsumexp0(log_w + (b - L))
    return (log_p - log_q) - (a - b)


def score_ldf(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """LDF: the weighted mean of the local existence probabilities, as a log LR relative to the prior
    odds (:func:`ldf_score`); (R, K)."""
    check_ldf(model, options)
    local = local_scores(model, m0, scans, options)
    return ldf_score(local, options.ldf_prior, _weights(options, model.n_sensors))
