"""The Gaussian approximation to the ROC and its Chernoff bound — ATC-10 §3.8, eqs (3.8.1)–(3.8.8).

Theorem 3.1 (App. E): for a common density and fixed τ/α the MAN is asymptotically Gaussian with
variance P. A Gaussian MAN of the same power gives ROC_g (Fig. 3.8):

    p_f = ½ erfc(θ/√(2P)),     p_m = ½ erfc((1 − θ)/√(2P))                    (3.8.1)–(3.8.3)

i.e. Q⁻¹(p_f) + Q⁻¹(p_m) = d′ = 1/√P. The sentence after Fig. 3.8 prints erf(θ/√(2p)) for p_d; it is
(1 − θ)/√(2p) as in (3.8.4). Its Chernoff bound, from E e^{μn} = e^{μ²P/2} (printed e^{μ²/2}, 3.8.6):

    p_f ≤ exp(−θ²/(2P)),   p_m ≤ exp(−(1 − θ)²/(2P))                           (3.8.5)–(3.8.8)

The report writes the variance as N·q·b (Theorem 3.1); the bounds use (N − 1)·q·b (3.4.13). Both are
offered (``variance="N-1"`` is the default; the relative difference is 1/N).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.special import log_ndtr

from motionsig_cli.surveillance.multiple_access import MANModel

GaussVariance = Literal["N", "N-1"]


def gaussian_power(model: MANModel, variance: GaussVariance = "N-1") -> float:
    """P = (N − 1)qb (3.4.13, default) or the report's N·q·b (Theorem 3.1) for a common density."""
    if variance == "N-1":
        return model.power
    if variance == "N":
        return model.power * model.N / model.M if model.M > 0 else 0.0
    raise ValueError(f"unknown variance convention {variance!r}; use N or N-1")


@dataclass(frozen=True)
class GaussianRoc:
    """ROC_g (3.8.3) and its Chernoff bound (3.8.8) at thresholds θ (natural logs)."""

    theta: np.ndarray
    P: float
    log_pf: np.ndarray
    log_pm: np.ndarray
    exp_f: np.ndarray  # Expfg = θ²/(2P)
    exp_d: np.ndarray  # Expdg = (1 − θ)²/(2P)

    @property
    def d_prime(self) -> float:
        """d′ = 1/√P = Q⁻¹(p_f) + Q⁻¹(p_m)."""
        return 1.0 / math.sqrt(self.P) if self.P > 0 else math.inf


def gaussian_roc(P: float, theta: np.ndarray) -> GaussianRoc:
    """ROC_g for a Gaussian MAN of power P (3.8.1)–(3.8.3) and its Chernoff exponents (3.8.8)."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    if not (math.isfinite(P) and P > 0.0):
        raise ValueError(f"the MAN power P must be a finite number > 0; got {P!r}")
    if np.any(~((theta > 0.0) & (theta < 1.0))):
        raise ValueError("thresholds must lie in the open interval (0, 1)")
    s = math.sqrt(P)
    return GaussianRoc(
        theta,
        P,
        log_ndtr(-theta / s),  # ½ erfc(θ/√(2P))            (3.8.1)
        log_ndtr(-(1.0 - theta) / s),  # ½ erfc((1 − θ)/√(2P))   (3.8.3)
        theta**2 / (2.0 * P),  # (3.8.8)
        (1.0 - theta) ** 2 / (2.0 * P),
    )
