"""Sequential likelihood ratio for track existence from several sensors, after Govaers, *Evaluation of
Distributed Detection Methods for Agile Targets* (Fraunhofer FKIE, slides): the ways of confirming a track
seen by several sensors that the slides compare — centralised, distributed, local and decision-level —
kept in the registry :data:`FUSION_METHODS`.

All scores are log likelihood ratios, accumulated scan by scan: log LR(k) = log LR(k−1) + log Λ(k).

- **CKF** (centralised Kalman filter): one filter with all data; per scan predict with (F, Q), then the
  local update (:func:`motionsig_cli.filters.pda.local_update`) of each sensor in turn;
  log Λ(k) = Σ_s log p̄ˢ.
- **DKF** (distributed Kalman filter, Govaers & Koch): local filters on the global covariance, exact
  (= CKF) for linear sensors with p_D = 1 and no clutter, refused elsewhere
  (:mod:`motionsig_cli.detection.fusion_dkf`).
- **FKF** (federated Kalman filter, the slides' distributed test for non-linear sensors): local filters
  with the relaxed evolution model Pˢ ← FPˢFᵀ + S·Q, initialised at (m₀, S·P₀), so that the product of
  the S local Gaussians is the centralised one. The fusion centre receives (xˢ, Pˢ, p̄ˢ) and computes
  log Λ(k) = log c_{k|k} − log c_{k|k−1} + Σ_s log p̄ˢ, with c = ∫ ∏_s N(x; xˢ, Pˢ) dx evaluated by the
  sequential product c = ∏_{s=1}^{S−1} N(x^{s+1}; x^{(1:s)}, P^{(1:s)} + P^{s+1}) (the slides' P^{s}
  corrected to P^{s+1}). No feedback: each local filter runs on its own data only.
- **FKF-FB** (``fkf-feedback``): FKF whose local filters are reset to the fused estimate after every
  ``FusionOptions.feedback_every``-th scan: xˢ = x_f, Pˢ = S·P_f with (x_f, P_f) the product of the
  local posteriors (so that the product of the reset locals is again N(x; x_f, P_f)). The LR formula is
  unchanged (c_{k|k−1} from the reset locals predicted). With feedback after every scan, linear sensors,
  p_D = 1 and no clutter it equals CKF (each scan then starts from the exact fused posterior).
- **LKF** (local Kalman filters): one filter per sensor with (F, Q); fused LR = (1/S) Σ_s LRˢ, i.e.
  logsumexp − log S (``lkf_mean="log"``: the mean of the log LRs).
- **LDF** (local decision fusion) and **naive** (local tracks accepted as confirmed): decision-level
  rules on the local filters' scores (:mod:`motionsig_cli.detection.decision_fusion`).

Sensors may differ (noise, field of view, p_D, clutter): :class:`SensorModel` per sensor in
``TrackExistenceModel.sensor_models``; without them every sensor shares the model's values. Every rule
takes an optional χ² validation gate (``FusionOptions.gate_pg``, derived in
:mod:`motionsig_cli.filters.pda`).

A new fusion rule is one scoring function and one entry of :data:`FUSION_METHODS`; the command's
``--methods`` choices and help, and the experiment, are read from there. What a caller needs to know of
an entry: ``default`` (in :data:`METHODS`, the default selection), ``check`` (raises
:class:`~motionsig_cli.config.ConfigError` where the rule does not apply; :func:`run_methods` calls it
for every selected rule before scoring any), ``metadata`` (one line for a result's provenance) and
``uses_thresholds`` (the score depends on ``FusionOptions.alpha, beta``: pass the study's own, as the
naive rule's local tests use them).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from motionsig_cli.config import ConfigError, one_of
from motionsig_cli.detection.decision_fusion import check_ldf, score_ldf, score_naive
from motionsig_cli.detection.existence_model import (
    LKF_MEANS,
    FusionOptions,
    ScanData,
    SensorModel,
    TrackExistenceModel,
    fuse_gaussians,
    local_scores,
    log_gauss,
    log_product_constant,
    sensor_update,
    stack_scan,
)
from motionsig_cli.detection.fusion_dkf import check_dkf, score_dkf

__all__ = [
    "ALL_METHODS",
    "FUSION_METHODS",
    "LKF_MEANS",
    "METHODS",
    "FusionMethod",
    "FusionOptions",
    "ScanData",
    "SensorModel",
    "TrackExistenceModel",
    "check_applicable",
    "check_methods",
    "local_scores",
    "log_gauss",
    "log_product_constant",
    "run_methods",
    "score_ckf",
    "score_dkf",
    "score_fkf",
    "score_fkf_feedback",
    "score_ldf",
    "score_lkf",
    "score_naive",
]


def score_ckf(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """CKF: one filter updated by every sensor in turn; log LR (R, K)."""
    R, S = m0.shape[0], model.n_sensors
    F, Q = model.F, model.Q
    out = np.zeros((R, len(scans)))
    m, P = m0.copy(), np.broadcast_to(model.m0_cov, (R, 4, 4)).copy()
    total = np.zeros(R)
    for k, scan in enumerate(scans):
        m, P = m @ F.T, F @ P @ F.T + Q
        lam = np.zeros(R)
        for s in range(S):  # sequential by construction: each sensor updates the running estimate
            m, P, lp = sensor_update(
                model, m, P, scan.Z[s], scan.valid[s], model.sensors[s], s, gate_pg=options.gate_pg
            )
            lam += lp
        total = total + lam
        out[:, k] = total
    return out


def score_lkf(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """LKF: S independent local filters (:func:`local_scores`), their LRs (or log LRs, with
    ``options.lkf_mean = "log"``) averaged; log LR (R, K)."""
    score = local_scores(model, m0, scans, options)
    if options.lkf_mean == "log":
        return score.mean(axis=0)
    top = score.max(axis=0)
    safe = np.where(np.isneginf(top), 0.0, top)
    with np.errstate(divide="ignore"):
        return safe + np.log(np.mean(np.exp(score - safe), axis=0))  # log of the mean LR


def _federated(
    model: TrackExistenceModel,
    m0: np.ndarray,
    scans: Sequence[ScanData],
    options: FusionOptions,
    feedback_every: int | None,
) -> np.ndarray:
    """The federated filter's log LR (R, K), with the locals reset to the fused estimate after every
    ``feedback_every``-th scan (None: never)."""
    R, S = m0.shape[0], model.n_sensors
    F, Q = model.F, model.Q
    out = np.zeros((R, len(scans)))
    P0b = np.broadcast_to(model.m0_cov, (R, 4, 4))
    m, P = np.tile(m0, (S, 1)), S * np.tile(P0b, (S, 1, 1))  # relaxed: ∏ N(·; m0, S·P0) ∝ N(·; m0, P0)
    sensor_rows = np.repeat(model.sensors, R, axis=0)  # (S·R, 2)
    total = np.zeros(R)
    for k, scan in enumerate(scans):
        Zs, Vs = stack_scan(scan, S, R)
        m, P = m @ F.T, F @ P @ F.T + S * Q  # relaxed evolution model
        log_c_prior = log_product_constant(list(m.reshape(S, R, 4)), list(P.reshape(S, R, 4, 4)))
        m, P, lp = sensor_update(model, m, P, Zs, Vs, sensor_rows, gate_pg=options.gate_pg)
        log_c_post, x_f, P_f = fuse_gaussians(list(m.reshape(S, R, 4)), list(P.reshape(S, R, 4, 4)))
        total = total + lp.reshape(S, R).sum(axis=0) + log_c_post - log_c_prior
        out[:, k] = total
        if feedback_every is not None and (k + 1) % feedback_every == 0:
            m, P = np.tile(x_f, (S, 1)), S * np.tile(P_f, (S, 1, 1))  # the centre's feedback
    return out


def score_fkf(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """FKF: local filters on the relaxed evolution model (S·Q, initialised at S·P₀, no feedback), fused
    through the product constants c_{k|k−1} and c_{k|k}; log LR (R, K)."""
    return _federated(model, m0, scans, options, None)


def score_fkf_feedback(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """FKF with feedback: as :func:`score_fkf`, the locals reset to (x_f, S·P_f) after every
    ``options.feedback_every``-th scan; log LR (R, K)."""
    return _federated(model, m0, scans, options, options.feedback_every)


ScoreFn = Callable[[TrackExistenceModel, np.ndarray, Sequence[ScanData], FusionOptions], np.ndarray]
"""``score(model, m0 (R, 4), scans, options)`` → log LR(k), k = 1..K, per run: (R, K)."""
CheckFn = Callable[[TrackExistenceModel, FusionOptions], None]
"""``check(model, options)``: raises :class:`~motionsig_cli.config.ConfigError` where a rule does not apply."""


@dataclass(frozen=True)
class FusionMethod:
    """One way of fusing the sensors' data into a track-existence score.

    Attributes:
        abbreviation: The short name used in the slides (``CKF``).
        title: What the abbreviation stands for (``centralised Kalman filter``).
        description: How the sensors' data reach the score, in a few words.
        score: The scoring function (:data:`ScoreFn`).
        default: In the default selection :data:`METHODS` (the slides' curves: CKF, FKF, LKF).
        check: Raises :class:`~motionsig_cli.config.ConfigError` for a model or options the rule does not
            apply to (:data:`CheckFn`), or None: it applies to every model.
        metadata: How the score is computed, one line for a result's provenance ("" for none).
        uses_thresholds: The score depends on Wald's thresholds (``FusionOptions.alpha, beta``), so a
            study must pass its own (the naive rule, whose local tests stop at their decisions).
    """

    abbreviation: str
    title: str
    description: str
    score: ScoreFn
    default: bool = False
    check: CheckFn | None = None
    metadata: str = ""
    uses_thresholds: bool = False

    @property
    def help(self) -> str:
        """``CKF = centralised Kalman filter: …``, for help texts."""
        return f"{self.abbreviation} = {self.title}: {self.description}"


FUSION_METHODS: dict[str, FusionMethod] = {
    "ckf": FusionMethod(
        "CKF", "centralised Kalman filter", "all measurements at one filter", score_ckf, default=True
    ),
    "dkf": FusionMethod(
        "DKF",
        "distributed Kalman filter",
        "local filters on the global covariance, fused at a centre; exact (= CKF) for linear (cartesian) "
        "sensors with p_D = 1 and no clutter, refused elsewhere",
        score_dkf,
        check=check_dkf,
        metadata="exact distributed Kalman filter (Govaers & Koch): locals on the global covariance S*P, "
        "information vectors kept, c by the sequential product; linear sensors, p_D = 1, no clutter",
    ),
    "fkf": FusionMethod(
        "FKF",
        "federated Kalman filter",
        "local filters on the relaxed evolution model (S·Q), fused at a centre without feedback",
        score_fkf,
        default=True,
        metadata="relaxed evolution model S*Q, locals initialised at S*P0, no feedback; c by the sequential "
        "product with P^(s+1) (slides' P^s corrected)",
    ),
    "fkf-feedback": FusionMethod(
        "FKF-FB",
        "federated Kalman filter with feedback",
        "as FKF, the local filters reset to the fused estimate after every transmission (or every few scans)",
        score_fkf_feedback,
        metadata="relaxed evolution model S*Q, locals reset to (x_fused, S*P_fused) after every feedback_every-th "
        "scan; c by the sequential product with P^(s+1)",
    ),
    "lkf": FusionMethod(
        "LKF",
        "local Kalman filters",
        "one per sensor, their likelihood ratios averaged",
        score_lkf,
        default=True,
    ),
    "ldf": FusionMethod(
        "LDF",
        "local decision fusion",
        "a weighted mean of the local existence probabilities, as a log LR against the prior odds",
        score_ldf,
        check=check_ldf,
        metadata="p_s = P0 LR_s / (P0 LR_s + 1 - P0), p = sum w_s p_s, score = log odds(p) - log odds(P0)",
    ),
    "naive": FusionMethod(
        "Naive",
        "naive confirmation",
        "local tracks accepted as confirmed: confirmed when any local test confirms, deleted when all have "
        "deleted (score: the largest local log LR, each frozen at its decision)",
        score_naive,
        metadata="each sensor's own Wald test (alpha, beta); confirmed when any confirms, deleted when all have "
        "deleted; score max_s of the local log LRs frozen at their decisions",
        uses_thresholds=True,
    ),
}
"""The fusion rules by name (the command's ``--methods`` values): centralised, distributed, local."""

ALL_METHODS = tuple(FUSION_METHODS)
"""Every rule's name."""
METHODS = tuple(name for name, method in FUSION_METHODS.items() if method.default)
"""The default selection: the slides' curves (CKF, FKF, LKF), in output order."""


def check_methods(methods: Sequence[str], field: str = "methods") -> tuple[str, ...]:
    """``methods`` as a tuple if it is a non-empty selection of :data:`FUSION_METHODS`, else
    :class:`~motionsig_cli.config.ConfigError` naming ``field``."""
    names = tuple(methods)
    if not names:
        raise ConfigError(field, names, f"is empty: choose from {', '.join(ALL_METHODS)}")
    for name in names:
        one_of(field, name, ALL_METHODS)
    return names


def check_applicable(methods: Sequence[str], model: TrackExistenceModel, options: FusionOptions) -> None:
    """Every selected rule's ``check`` on the model and options (:class:`~motionsig_cli.config.ConfigError`
    from the first that does not apply)."""
    for name in check_methods(methods):
        check = FUSION_METHODS[name].check
        if check is not None:
            check(model, options)


def run_methods(
    model: TrackExistenceModel,
    m0: np.ndarray,
    scans: Sequence[ScanData],
    methods: Sequence[str] = METHODS,
    *,
    lkf_mean: str | None = None,
    options: FusionOptions | None = None,
) -> dict[str, np.ndarray]:
    """log LR(k) for k = 1..K of each method, (R, K) per method, from initial track means m0 (R, 4).

    ``options`` default to :class:`FusionOptions`'s; ``lkf_mean``, if given, replaces theirs. Every
    method's ``check`` runs before any scoring (:func:`check_applicable`).
    """
    if options is None:
        options = FusionOptions("lr" if lkf_mean is None else lkf_mean)
    elif lkf_mean is not None:
        options = replace(options, lkf_mean=lkf_mean)
    names = check_methods(methods)
    check_applicable(names, model, options)
    return {name: FUSION_METHODS[name].score(model, m0, scans, options) for name in names}
