"""The paper's trajectory (Yao, Teng & Wu §V): the scenario that the manoeuvre studies and the EBPSK front end
share, in a module of its own so that both import it and neither imports the other."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, one_of

__all__ = ["FIRST_SCAN", "PRESETS", "SCANS_RANGE", "T_RANGE", "ManeuverScenario"]

PRESETS = ("literal", "turn90")
FIRST_SCAN = 3
"""First filtered scan (two-point initialisation at scan 2)."""
T_RANGE = (1e-3, 3600.0)
"""Scan periods accepted [s] (below 1 ms the two-point covariance 2σ²/T² leaves the range of doubles)."""
SCANS_RANGE = (3, 100_000)
"""Scans per run: two initialise the trackers; 100 000 (28 h at T = 1 s) keeps one task's arrays ~1 GB."""


@dataclass(frozen=True)
class ManeuverScenario:
    """The paper's trajectory (§V).

    Attributes:
        preset: ``literal`` (as printed: v(1) = (0, 450) m/s, u = (20, 20) m/s² on scans [200, 300),
            (3, 3) on [305, 330)) or ``turn90`` (exact 90° turns in the same windows: v(1) = (0, −450),
            u₁ = 450/(100T)·(1, 1), u₂ = −450/(25T)·(1, 1)).
        T: scan period [s], in :data:`T_RANGE` (assumed: 1 s; the paper does not state it).
        scans: N (paper: 450), in :data:`SCANS_RANGE`.
        p0: initial position [m] (assumed: the origin; the paper does not state it).
    """

    preset: str = "literal"
    T: float = 1.0
    scans: int = 450
    p0: tuple[float, float] = (0.0, 0.0)
    segments: tuple[tuple[int, int, float, float], ...] = field(init=False, repr=False)
    v0: tuple[float, float] = field(init=False)

    def __post_init__(self) -> None:
        one_of("preset", self.preset, PRESETS)
        in_range("T", self.T, *T_RANGE, unit="s")
        integer("scans", self.scans, *SCANS_RANGE)
        if len(self.p0) != 2 or not all(math.isfinite(v) for v in self.p0):
            raise ConfigError("p0", self.p0, "is not a finite position (x, y)")
        if self.preset == "literal":
            segs = ((200, 300, 20.0, 20.0), (305, 330, 3.0, 3.0))
            v0 = (0.0, 450.0)
        else:
            a1, a2 = 450.0 / (100 * self.T), -450.0 / (25 * self.T)
            segs = ((200, 300, a1, a1), (305, 330, a2, a2))
            v0 = (0.0, -450.0)
        object.__setattr__(self, "segments", segs)
        object.__setattr__(self, "v0", v0)

    def inputs(self) -> np.ndarray:
        """u(k) for k = 1..N, (N, 2): the acceleration held over interval k."""
        u = np.zeros((self.scans, 2))
        for a, b, ux, uy in self.segments:
            u[a - 1 : min(b, self.scans + 1) - 1] = (ux, uy)
        return u

    def truth(self) -> np.ndarray:
        """[x, ẋ, y, ẏ] at scans 1..N, (N, 4), noise-free, exact constant-acceleration kinematics."""
        u, T = self.inputs(), self.T
        out = np.empty((self.scans, 4))
        p, v = np.array(self.p0, float), np.array(self.v0, float)
        for i in range(self.scans):
            out[i] = (p[0], v[0], p[1], v[1])
            p = p + v * T + 0.5 * u[i] * T * T
            v = v + u[i] * T
        return out

    def events(self) -> list[tuple[int, tuple[float, float]]]:
        """Input changes (onset scan n, jump u(n) − u(n−1)) that the record can show: n in GLR convention
        (u(n) first moves the position of scan n + 1), so n < N."""
        u = self.inputs()
        du = np.diff(np.vstack([np.zeros((1, 2)), u]), axis=0)
        changes = np.flatnonzero(np.any(du != 0, axis=1))
        return [(int(i + 1), (float(du[i, 0]), float(du[i, 1]))) for i in changes if i + 1 < self.scans]

    def phases(self) -> list[tuple[str, int, int]]:
        """Scan ranges [a, b) for the summary: cruise before the turns, each turn (with its transient), after."""
        segs = self.segments
        out = [("cruise", 50, segs[0][0]), ("turn 1", segs[0][0], segs[1][0]), ("turn 2", segs[1][0], segs[1][1] + 10),
               ("after", segs[1][1] + 50, self.scans + 1)]  # fmt: skip
        return [
            (name, max(a, FIRST_SCAN), min(b, self.scans + 1))
            for name, a, b in out
            if min(b, self.scans + 1) > a
        ]
