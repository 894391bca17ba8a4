"""Wald's sequential probability-ratio test on a log likelihood ratio, as used for track existence in
Govaers, *Evaluation of Distributed Detection Methods for Agile Targets* (Fraunhofer FKIE, slides).

Thresholds from the error probabilities α = P(confirm | h0) and β = P(delete | h1):
log A = log(β/(1 − α)), log B = log((1 − β)/α). Continue while log A < log LR(k) < log B; at or below
log A delete the track (accept h0); at or above log B confirm it (accept h1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from motionsig_cli.config import in_range

__all__ = ["Decisions", "first_crossing", "freeze_at_decision", "wald_thresholds"]

CONFIRM, DELETE, UNDECIDED = 1, -1, 0


def wald_thresholds(alpha: float, beta: float) -> tuple[float, float]:
    """(log A, log B) = (log β/(1−α), log (1−β)/α) for α, β in (0, 0.5).

    Wald's bounds only need α + β < 1 (then log A < log B); an error probability of one half or more is
    no test at all, so each is checked in the open interval (0, 0.5) (:class:`~motionsig_cli.config.
    ConfigError` naming ``alpha`` or ``beta``).

    Examples:
        >>> import math
        >>> from motionsig_cli import wald_thresholds
        >>> log_a, log_b = wald_thresholds(0.01, 0.01)
        >>> round(log_a, 4), round(log_b, 4), math.isclose(log_b, math.log(0.99 / 0.01))
        (-4.5951, 4.5951, True)
    """
    in_range("alpha", alpha, 0.0, 0.5, lo_open=True, hi_open=True)
    in_range("beta", beta, 0.0, 0.5, lo_open=True, hi_open=True)
    return math.log(beta) - math.log1p(-alpha), math.log1p(-beta) - math.log(alpha)


@dataclass(frozen=True)
class Decisions:
    """First-crossing decisions per run: ``decision`` ∈ {1 confirm, −1 delete, 0 undecided} and the scan
    (1-based) at which it was taken (0 if undecided)."""

    decision: np.ndarray
    time: np.ndarray


def freeze_at_decision(loglr: np.ndarray, log_a: float, log_b: float) -> np.ndarray:
    """The score with the test stopped: after the first crossing each row keeps its value at the decision."""
    d = first_crossing(loglr, log_a, log_b)
    k = np.arange(loglr.shape[-1])
    stop = np.where(d.decision != UNDECIDED, d.time - 1, loglr.shape[-1])
    at = np.take_along_axis(loglr, np.minimum(stop, loglr.shape[-1] - 1)[..., None], axis=-1)
    return np.where(k > stop[..., None], at, loglr)


def first_crossing(loglr: np.ndarray, log_a: float, log_b: float) -> Decisions:
    """The SPRT's decision on each row of ``loglr`` (runs × scans): the first scan at which the score
    leaves (log A, log B)."""
    out = (loglr >= log_b) | (loglr <= log_a)
    hit = out.any(axis=-1)
    k = np.argmax(out, axis=-1)
    val = np.take_along_axis(loglr, k[..., None], axis=-1)[..., 0]
    decision = np.where(hit, np.where(val >= log_b, CONFIRM, DELETE), UNDECIDED)
    return Decisions(decision=decision, time=np.where(hit, k + 1, 0))
