"""A tracker's watch over its own consistency: nothing diverges silently.

Every tracker fed by a real sensor meets what its model does not describe: a position that is wrong by a
kilometre, a stale report, a manoeuvre harder than its process noise, a gap. A filter that goes on as if
nothing happened can drift without bound and still print numbers. :class:`Consistency` states the checks
a tracker runs at every step, batched over tracks; :class:`Monitor` carries their state through the scan
loop of :func:`motionsig_cli.filters.imm.imm_filter` and :func:`motionsig_cli.detection.glr.input_tracker`.

1. **Validation gate.** A measurement is an outlier when it is both statistically and physically out of
   reach: its normalised innovation squared ε_k = ν_kᵀ S_k⁻¹ ν_k exceeds the χ²_m quantile at 1 − ``gate``
   (under the model ε_k ~ χ²_m: a fraction ``gate`` of a consistent filter's measurements, 10⁻⁹ by default,
   6.4 σ in two dimensions), *and* the innovation is longer than a manoeuvre at ``max_accel`` could make it
   since the last accepted measurement, |ν_k| > ½ a_max τ² + √(g tr S_k) (τ: the time since; g: the gate's
   quantile). The second condition keeps a hard manoeuvre, which a filter's model does not describe but
   a detector must see, from being gated. An outlier's step is predict-only (the measurement is not used)
   and the row says so (``gated``).                                                                  (C1)
2. **Lost track.** ``max_gated`` gated measurements in a row mean the target is no longer where the filter
   looks: the track is re-initialised (reason ``outliers``).                                          (C2)
3. **Windowed NIS.** Over the last ``window`` accepted measurements, Σ ε_k ~ χ²_{m·window} for a consistent
   filter (the innovations are white: Bar-Shalom, Li & Kirubarajan 2001, §5.4.2); a sum beyond its quantile
   at 1 − ``alpha`` re-initialises the track (reason ``nis``). The test runs once the window is full.   (C3)
4. **Plausibility.** A speed above ``max_speed`` or an acceleration above ``max_accel`` (the estimate's, or a
   GLR/MLR input estimate's) is not an aircraft's: the track is re-initialised (reasons ``speed``,
   ``acceleration``); a GLR/MLR declaration whose corrected input would exceed ``max_accel`` is rejected
   (no correction is applied).                                                                       (C4)
5. **Covariance health.** A covariance with a non-finite entry, or a position standard deviation above
   ``max_position_sd``, re-initialises the track (reason ``covariance``).                             (C5)

A re-initialisation is the two-point start of the trackers (§IV of Yao, Teng & Wu) on the last accepted
measurement and the current one, with their covariances (:meth:`Consistency.restart`; where that
difference is itself faster than ``max_speed``, the track starts at rest with a velocity standard
deviation of ``max_speed``; at a step without a measurement, the track keeps its position and forgets its
velocity: :meth:`Consistency.coast`); the row carries the reason, and the command's
summary counts them. With ``consistency=None`` the trackers run unwatched (the paper's Monte Carlo, whose
numbers stay bit for bit those of the paper's recursion).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import gammainccinv

from motionsig_cli.config import ConfigError, in_range, integer

__all__ = ["REASONS", "Consistency", "Monitor"]

REASONS = ("", "outliers", "nis", "speed", "acceleration", "covariance")
"""Reason codes of a re-initialisation (index 0: none), in the order the checks are tried."""


@dataclass(frozen=True)
class Consistency:
    """The checks (module docstring, C1–C5) and their thresholds.

    Attributes:
        gate: false-alarm probability of the validation gate per measurement (C1), in (0, 0.5].
        max_gated: gated measurements in a row that re-initialise the track (C2), ≥ 1.
        window: accepted measurements in the windowed NIS test (C3), in [1, 1000].
        alpha: false-alarm probability of the windowed NIS test (C3), in (0, 0.5].
        max_speed: largest plausible speed [m/s] (C4); 600 m/s is Mach 1.8 at altitude.
        max_accel: largest plausible acceleration [m/s²] (C4); 100 m/s² is 10 g.
        max_position_sd: largest position standard deviation per axis [m] (C5).

    Examples:
        >>> from motionsig_cli.filters.consistency import Consistency
        >>> c = Consistency()
        >>> round(c.gate_bound(2), 2), round(c.nis_bound(2), 1)  # χ²₂ at 1 − 1e-9; χ²₄₀ at 1 − 1e-4
        (41.45, 82.1)
    """

    gate: float = 1e-9
    max_gated: int = 3
    window: int = 20
    alpha: float = 1e-4
    max_speed: float = 600.0
    max_accel: float = 100.0
    max_position_sd: float = 1e5

    def __post_init__(self) -> None:
        for name in ("gate", "alpha"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and 0 < v <= 0.5):
                raise ConfigError(name, v, "is not a probability in (0, 0.5]")
        integer("max_gated", self.max_gated, 1, 1000)
        integer("window", self.window, 1, 1000)
        in_range("max_speed", self.max_speed, 1e-3, 3e8, unit="m/s")
        in_range("max_accel", self.max_accel, 1e-3, 1e6, unit="m/s²")
        in_range("max_position_sd", self.max_position_sd, 1e-3, 1e9, unit="m")

    def gate_bound(self, m: int) -> float:
        """χ²_m quantile at 1 − gate (C1): the χ²_k upper quantile is 2 Q⁻¹(k/2, p) (Q: the regularised upper
        incomplete gamma function; scipy.special, not scipy.stats, whose import costs 0.75 s)."""
        return float(2.0 * gammainccinv(m / 2.0, self.gate))

    def nis_bound(self, m: int) -> float:
        """χ²_{m·window} quantile at 1 − alpha (C3)."""
        return float(2.0 * gammainccinv(m * self.window / 2.0, self.alpha))

    def restart(self, x: np.ndarray, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A two-point start x (B, n), P (B, n, n) (state [x, ẋ, y, ẏ, …]) made plausible: where its speed
        exceeds ``max_speed``, the velocity is 0 with variance max_speed² per axis, uncorrelated."""
        wild = ~(np.hypot(x[:, 1], x[:, 3]) <= self.max_speed)
        if wild.any():
            x, P = x.copy(), P.copy()
            vel = [1, 3]
            x[np.ix_(wild, vel)] = 0.0
            Pw = P[wild]
            Pw[:, vel, :] = 0.0
            Pw[:, :, vel] = 0.0
            Pw[:, 1, 1] = Pw[:, 3, 3] = self.max_speed**2
            P[wild] = Pw
        return x, P

    def coast(self, x: np.ndarray, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A track that fails a check at a step without a measurement (nothing to restart from): its position
        and position covariance are kept, its velocity (and acceleration) set to 0 with a velocity variance
        of max_speed² per axis — the target is where it was, its motion unknown (x (B, n), P (B, n, n),
        state [x, ẋ, y, ẏ, …])."""
        x, P = x.copy(), P.copy()
        rest = [i for i in range(x.shape[-1]) if i not in (0, 2)]
        x[:, rest] = 0.0
        P[:, rest, :] = 0.0
        P[:, :, rest] = 0.0
        P[:, 1, 1] = P[:, 3, 3] = self.max_speed**2
        return x, P

    def meta(self) -> dict[str, float | int]:
        """The settings, for a table's provenance."""
        return {"gate": self.gate, "max_gated": self.max_gated, "nis_window": self.window,
                "nis_alpha": self.alpha, "max_speed": self.max_speed, "max_accel": self.max_accel,
                "max_position_sd": self.max_position_sd}  # fmt: skip


class Monitor:
    """The checks' state for B tracks through a scan loop (one call per step, all tracks at once).

    Attributes:
        gated, reason, nis: (B, N) per step: the measurement was gated (C1); the re-initialisation's reason
            code (:data:`REASONS`; 0: none); ε_k (NaN where no measurement).
    """

    def __init__(self, cfg: Consistency, B: int, N: int, m: int) -> None:
        self.cfg = cfg
        self.gate = cfg.gate_bound(m)
        self.bound = cfg.nis_bound(m)
        self.ring = np.zeros((B, cfg.window))
        self.count = np.zeros(B, dtype=np.int64)
        self.run = np.zeros(B, dtype=np.int64)
        self.gated = np.zeros((B, N), dtype=bool)
        self.reason = np.zeros((B, N), dtype=np.int8)
        self.nis = np.full((B, N), math.nan)

    def screen(
        self, k: int, seen: np.ndarray, nis: np.ndarray, nu: np.ndarray, S: np.ndarray, tau: np.ndarray
    ) -> np.ndarray:
        """Record ε_k of the measured tracks ``seen`` (B,) and return which of them to accept (C1), from the
        innovations ν (B, m), their covariances S (B, m, m) and the time τ (B,) since the last accepted
        measurement."""
        self.nis[:, k] = np.where(seen, nis, math.nan)
        trace = np.trace(S, axis1=-2, axis2=-1)
        reach = 0.5 * self.cfg.max_accel * tau**2 + np.sqrt(self.gate * np.maximum(trace, 0.0))
        far = ~(np.linalg.norm(nu, axis=-1) <= reach)
        gated = seen & ~(nis <= self.gate) & far  # NaN ε (a singular S) is gated too
        self.gated[:, k] = gated
        ok = seen & ~gated
        self.run = np.where(gated, self.run + 1, np.where(ok, 0, self.run))
        slot = self.count % self.cfg.window
        rows = np.flatnonzero(ok)
        self.ring[rows, slot[rows]] = nis[rows]
        self.count = self.count + ok
        return ok

    def verdict(
        self, k: int, speed: np.ndarray, accel: np.ndarray, pos_var: np.ndarray, finite: np.ndarray
    ) -> np.ndarray:
        """Which tracks to re-initialise at step k (B,), after the update (C2–C5); records the reason."""
        c = self.cfg
        reason = np.zeros(speed.shape, dtype=np.int8)
        full = self.count >= c.window
        checks = (
            self.run >= c.max_gated,  # C2
            full & (self.ring.sum(axis=1) > self.bound),  # C3
            ~(speed <= c.max_speed),  # C4 (NaN fails)
            ~(accel <= c.max_accel),
            ~finite | ~(pos_var <= c.max_position_sd**2),  # C5
        )
        for code, bad in enumerate(checks, start=1):
            reason = np.where((reason == 0) & bad, code, reason).astype(np.int8)
        self.reason[:, k] = reason
        return reason > 0

    def reset(self, mask: np.ndarray) -> None:
        """Start the checks afresh for the re-initialised tracks."""
        self.ring[mask] = 0.0
        self.count[mask] = 0
        self.run[mask] = 0
