"""The multiple-access noise (MAN) at one matched filter — ATC-10 §3.3–3.4 and App. E.

N aircraft send unit-energy signatures of duration τ once per period α, uncoordinated. At the matched
filter of aircraft i each of the M = N − 1 others overlaps the 2τ window with probability q = 2τ/α and
then adds an amplitude drawn from its density C_j (3.3.8); the components are independent:

    E e^{jvn} = Π_j [(1 − q) + q ∫C_j(x)e^{jvx}dx]                       (3.4.5)–(3.4.6)
    E n = 0,   E n² = P = q Σ_j b_j   (= (N−1) q b for a common C)         (3.4.12)–(3.4.13)

Every bound uses the real log-MGF (3.5.6) Λ(ρ) = Σ_j ln[(1 − q) + qΦ_j(ρ)] and its derivatives in the
cancellation-free "w-form": with w_j = qΦ_j/(1 − q + qΦ_j), the tilted probability that
interferer j is active,

    Λ′ = Σ_j w_j g_j′,    Λ″ = Σ_j [w_j g_j″ + w_j(1 − w_j) g_j′²].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import expit

from motionsig_cli.config import ConfigError, integer, positive
from motionsig_cli.surveillance.amplitude import AmplitudeDensity

LOG_SWITCH = 30.0  # g above which ln(1 − q + qΦ) is formed by logaddexp instead of log1p(q expm1 g)


@dataclass(frozen=True)
class MANModel:
    """N aircraft, signature duty τ/α, and the interferers' amplitude densities.

    ``components`` is a tuple of (density, multiplicity) whose multiplicities sum to N − 1; a common
    density (the report's Secs 3.6–3.8) is ``MANModel.common(N, tau_over_alpha, C)``. N ≥ 1 (N = 1 is
    the trivial model without interferers) and 0 < τ/α < ½: q = 2τ/α < 1, or a window would overlap
    itself.
    """

    N: int
    tau_over_alpha: float
    components: tuple[tuple[AmplitudeDensity, int], ...]

    def __post_init__(self) -> None:
        if isinstance(self.N, bool) or not isinstance(self.N, int | np.integer):
            raise ConfigError("N", self.N, "is not an integer")
        integer("N", int(self.N), 1)
        t = self.tau_over_alpha
        positive("tau_over_alpha", t)
        if not 2.0 * t < 1.0:
            raise ConfigError(
                "tau_over_alpha",
                t,
                f"gives q = 2 tau/alpha = {2 * t:g}, which must be < 1 (a window would overlap itself)",
            )
        if any(m < 0 for _, m in self.components):
            raise ConfigError("components", [m for _, m in self.components], "has negative multiplicities")
        if sum(m for _, m in self.components) != self.N - 1:
            raise ConfigError(
                "components", [m for _, m in self.components], "has multiplicities that do not sum to N - 1"
            )

    @classmethod
    def common(cls, N: int, tau_over_alpha: float, density: AmplitudeDensity) -> MANModel:
        """Every interferer has the same density (the report's common C)."""
        return cls(int(N), float(tau_over_alpha), ((density, int(N) - 1),) if N > 1 else ())

    @property
    def M(self) -> int:
        """Number of interferers N − 1."""
        return self.N - 1

    @property
    def q(self) -> float:
        """Probability that one interferer overlaps the 2τ window, 2τ/α."""
        return 2.0 * self.tau_over_alpha

    @property
    def power(self) -> float:
        """P = E n² = q Σ_j b_j (3.4.13)."""
        return self.q * sum(m * d.b for d, m in self.components)

    @property
    def mean_active(self) -> float:
        """Mean number of overlapping interferers Mq (≈ 2λ, λ = Nτ/α)."""
        return self.M * self.q

    @property
    def max_abs(self) -> float:
        """sup |n|: Σ_j m_j max|x| (inf if any component is unbounded)."""
        return float(sum(m * d.max_abs for d, m in self.components if m > 0))

    @property
    def rho_max(self) -> float:
        """Λ is finite for |ρ| < rho_max."""
        return min((d.rho_max for d, m in self.components if m > 0), default=math.inf)

    @property
    def symmetric(self) -> bool:
        return all(d.symmetric for d, _ in self.components)

    @property
    def common_density(self) -> AmplitudeDensity | None:
        """The density shared by all interferers, or None when there are several."""
        live = [d for d, m in self.components if m > 0]
        return live[0] if len(live) == 1 else None

    @property
    def trivial(self) -> bool:
        """No MAN at all (N = 1): p_f = 0 and p_d = 1 exactly."""
        return self.M == 0 or self.power == 0.0

    def realisable(self) -> bool:
        """|n_ij| ≤ 1 by Cauchy–Schwarz; a density whose support exceeds ±1 is not realisable."""
        return all(d.max_abs <= 1.0 for d, m in self.components if m > 0)

    def log_mgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(Λ, Λ′, Λ″) at r (eq 3.5.6, w-form derivatives)."""
        r = np.asarray(r, dtype=float)
        lam = np.zeros_like(r)
        d1 = np.zeros_like(r)
        d2 = np.zeros_like(r)
        q = self.q
        lq, l1q = math.log(q), math.log1p(-q)
        for dens, m in self.components:
            if m == 0:
                continue
            g, g1, g2 = dens.cgf(r)
            with np.errstate(over="ignore", invalid="ignore"):
                small = g < LOG_SWITCH
                h = np.where(
                    small,
                    np.log1p(q * np.expm1(np.where(small, g, 0.0))),  # ln(1 − q + qΦ)
                    np.logaddexp(l1q, lq + g),
                )
                w = expit(lq + g - l1q)  # qΦ/(1 − q + qΦ)
                lam += m * h
                d1 += m * w * g1
                d2 += m * (w * g2 + w * (1.0 - w) * g1 * g1)
        return lam, d1, d2
