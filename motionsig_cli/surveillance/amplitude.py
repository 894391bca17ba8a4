"""Amplitude densities C(x) of one multiple-access-noise component, given overlap — ATC-10 §3.3 (3.3.8),
§3.6 (Fig. 3.2), §3.7 (3.7.1).

An interfering aircraft j whose transmission overlaps the matched-filter window adds n_ij, drawn from
C(x), to the sample of matched filter i. Every density here is parameterised by its second moment
b = ∫x²C(x)dx so that densities of equal power can be compared (the report's ℓ = 1/√(3b)).

| id | name        | definition at second moment b                     | kurtosis |
|----|-------------|---------------------------------------------------|----------|
| C₂ | two-point   | ½δ(x − A) + ½δ(x + A), A = √b  (quasi-optimal, 3.7.1) | 1    |
| C₁ | uniform     | U(−a, a), a = √(3b)                                | 1.8      |
| C₃ | triangular  | sum of two U(−c, c), c = √(3b/2)                   | 2.4      |
| C₄ | gaussian    | N(0, b)                                            | 3        |
|    | laplace     | scale β = √(b/2); MGF finite for |ρ| < 1/β          | 6        |
|    | arcsine     | A cos φ, A = √(2b), φ uniform                      | 1.5      |
|    | psk         | chip-level PSK signatures (:mod:`.psk_amplitude`)  |          |
|    | discrete    | user-given atoms and weights                       |          |

C₂ is pinned by the report (§3.7–3.8); C₁, C₃, C₄ are not described in the text (Fig. 3.2 is lost):
uniform, triangular and Gaussian are an assumption, chosen by "peakiness" and consistent with the
report's preference order C₂ ≻ C₁ ≻ C₃ ≻ C₄.

Each density gives its cumulant-generating function g(ρ) = ln Φ(ρ) = ln ∫e^{ρx}C(x)dx with g′ and g″,
evaluated in a log form that neither overflows (Φ reaches e^{700} and beyond) nor cancels near ρ = 0,
a sampler and, where one exists, an exponentially tilted sampler C_ρ(x) ∝ e^{ρx}C(x) for importance
sampling and the tail of the sum of k draws for the exact ROC (``log_tail``).

The registry of the densities a user can name (``--density``) is
:data:`motionsig_cli.surveillance.densities.DENSITIES`: each member says what it supports — an exact ROC, importance sampling, a closed-form second
moment, its report id and figure — so that callers ask the member instead of testing types or names.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import ClassVar, Protocol, runtime_checkable

import numpy as np
from scipy.special import expit, gammaln, i0e, i1e, log_ndtr, logsumexp

from motionsig_cli.config import ConfigError, positive

LN2 = math.log(2.0)


@runtime_checkable
class AmplitudeDensity(Protocol):
    """What the MAN model needs of a component density."""

    name: str

    @property
    def b(self) -> float:
        """Second moment ∫x²C(x)dx."""
        ...

    @property
    def max_abs(self) -> float:
        """sup |x| over the support (inf when unbounded)."""
        ...

    @property
    def rho_max(self) -> float:
        """The MGF is finite for |ρ| < rho_max (inf for bounded and Gaussian densities)."""
        ...

    @property
    def symmetric(self) -> bool: ...

    def cgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(g, g′, g″) at r (any real array)."""
        ...

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray: ...

    def sample_tilted(self, rng: np.random.Generator, r: float, size: int) -> np.ndarray:
        """Draws from C_r(x) ∝ e^{rx}C(x)."""
        ...


def log_cosh(x: np.ndarray) -> np.ndarray:
    """ln cosh x without overflow at large |x| nor cancellation at small |x| (ln cosh x ≈ x²/2):
    log1p(2 sinh²(x/2)) below |x| = 20, |x| + log1p(e^{−2|x|}) − ln 2 above."""
    a = np.abs(np.asarray(x, dtype=float))
    small = a < 20.0
    s = np.sinh(0.5 * np.where(small, a, 0.0))
    return np.where(small, np.log1p(2.0 * s * s), a + np.log1p(np.exp(-2.0 * a)) - LN2)


def log_i0(x: np.ndarray) -> np.ndarray:
    """ln I₀(x) for x ≥ 0: log1p of the power series I₀ − 1 = Σ_{k≥1} (x²/4)^k/(k!)² below x = 1 (no
    cancellation: ln I₀ ≈ x²/4), ln i0e(x) + x above."""
    x = np.asarray(x, dtype=float)
    small = x < 1.0
    y = 0.25 * np.where(small, x, 0.0) ** 2
    term = np.ones_like(y)
    acc = np.zeros_like(y)
    for k in range(1, 12):  # (1/4)^k/(k!)² < 1e-17 relative beyond k = 11 for x < 1
        term = term * y / (k * k)
        acc = acc + term
    return np.where(small, np.log1p(acc), np.log(i0e(np.where(small, 1.0, x))) + np.where(small, 0.0, x))


def _even(r: np.ndarray, g: np.ndarray, g1: np.ndarray, g2: np.ndarray) -> tuple[np.ndarray, ...]:
    """Extend (g, g′, g″) computed at |r| to r for an even g."""
    return g, np.sign(r) * g1, g2


def _log_sinhc(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ln(sinh x / x) and its first two derivatives in x, for x ≥ 0, without overflow or cancellation."""
    x = np.asarray(x, dtype=float)
    small = x < 0.05
    xs = np.where(small, 1.0, x)  # placeholder where the series is used
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        e = np.exp(-2.0 * xs)
        g_big = xs + np.log1p(-e) - np.log(2.0 * xs)
        coth = (1.0 + e) / (1.0 - e)
        d1_big = coth - 1.0 / xs
        d2_big = 1.0 / xs**2 - 4.0 * e / (1.0 - e) ** 2  # 1/x² − 1/sinh²x
    y = np.where(small, x, 0.0)  # series argument (x < 0.05)
    x2 = y * y
    g_s = x2 / 6.0 - x2 * x2 / 180.0 + x2**3 / 2835.0
    d1_s = y / 3.0 - y * x2 / 45.0 + 2.0 * y * x2 * x2 / 945.0 - y * x2**3 / 4725.0
    d2_s = 1.0 / 3.0 - x2 / 15.0 + 2.0 * x2 * x2 / 189.0 - x2**3 / 675.0
    return np.where(small, g_s, g_big), np.where(small, d1_s, d1_big), np.where(small, d2_s, d2_big)


def irwin_hall_tail(k: int, t: np.ndarray) -> np.ndarray:
    """P(IH_k ≥ t) for an Irwin–Hall sum of k U(0, 1) (array t), as F_k(k − t) = Σ_j N_{k+1}(k − t − j).

    F_k(u) = Σ_{j≥0} N_{k+1}(u − j) with N_m the cardinal B-spline of order m (d/du N_{k+1}(u) =
    N_k(u) − N_k(u − 1) telescopes); N_m is evaluated by the Cox–de Boor recursion, a convex combination
    at every step, so the tail has no cancellation.
    """
    t = np.asarray(t, dtype=float)
    u = np.clip(k - t, 0.0, float(k))  # P(IH ≥ t) = P(IH ≤ k − t)
    out = np.zeros_like(u)
    live = (u > 0.0) & (u < k)
    out[u >= k] = 1.0
    if not live.any():
        return out
    uu = u[live]
    n_shift = int(np.floor(uu.max())) + k + 2
    i = np.arange(n_shift)[:, None]
    y = uu[None, :] - i  # arguments u − i
    T = ((y >= 0.0) & (y < 1.0)).astype(float)  # N₁(u − i)
    for m in range(2, k + 2):  # Cox–de Boor: N_m(y) = [y N_{m−1}(y) + (m − y) N_{m−1}(y − 1)]/(m − 1)
        shifted = np.vstack([T[1:], np.zeros((1, T.shape[1]))])  # N_{m−1}(y − 1) = row i + 1
        T = (y * T + (m - y) * shifted) / (m - 1)
    valid = y >= 0.0  # terms j = 0 … ⌊u⌋
    out[live] = np.where(valid, T, 0.0).sum(axis=0)
    return out


def _tilted_uniform(rng: np.random.Generator, a: float, r: float, size: int) -> np.ndarray:
    """Inverse-CDF draws from e^{rx} on [−a, a] (the tilt of U(−a, a)): x = a + ln(u + (1−u)e^{−2ra})/r."""
    u = rng.random(size)
    if r == 0.0:
        return a * (2.0 * u - 1.0)
    s = abs(r)
    x = a + np.log(u + (1.0 - u) * np.exp(-2.0 * s * a)) / s
    return np.clip(x, -a, a) * (1.0 if r > 0 else -1.0)


def _check_scale(name: str, value: float) -> float:
    """A scale parameter: a finite number > 0 (:class:`ConfigError` naming the field otherwise)."""
    return positive(name, value)


class DensityDefaults:
    """What most densities share, each overridden where a density differs: an MGF finite for every ρ
    (``rho_max`` = ∞), a symmetric law, and no exponentially tilted sampler (importance sampling is
    refused, naming the density)."""

    name: str

    @property
    def rho_max(self) -> float:
        return math.inf

    @property
    def symmetric(self) -> bool:
        return True

    def sample_tilted(self, rng: np.random.Generator, r: float, size: int) -> np.ndarray:
        raise ConfigError(
            "importance", True, f"is not available for the {self.name} density (no tilted sampler)"
        )


class ScaleDensity(DensityDefaults):
    """A density of one scale parameter, its only constructor field: checked to be a finite number > 0,
    and bounding the support, sup |x| = ``reach`` × the parameter (``reach`` = ∞: unbounded)."""

    reach: ClassVar[float] = math.inf

    @property
    def scale_name(self) -> str:
        """The name of the parameter (the field a :class:`ConfigError` names)."""
        (name,) = (f.name for f in fields(self) if f.init)  # type: ignore[arg-type]
        return name

    @property
    def scale(self) -> float:
        return getattr(self, self.scale_name)

    def __post_init__(self) -> None:
        _check_scale(self.scale_name, self.scale)

    @property
    def max_abs(self) -> float:
        return self.reach * self.scale


@dataclass(frozen=True)
class TwoPoint(ScaleDensity):
    """C₂ = ½δ(x − A) + ½δ(x + A) (3.7.1): the quasi-optimal density; b = A²."""

    A: float
    name: str = field(default="two-point", init=False)
    reach: ClassVar[float] = 1.0

    @property
    def b(self) -> float:
        return self.A**2

    def cgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = np.asarray(r, dtype=float)
        x = np.abs(r) * self.A
        e = np.exp(-2.0 * x)
        g = log_cosh(x)  # ln Φ = ln cosh(ρA)
        g1 = self.A * np.tanh(x)
        g2 = self.A**2 * 4.0 * e / (1.0 + e) ** 2  # A² sech² x
        return _even(r, g, g1, g2)

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        return np.where(rng.random(size) < 0.5, self.A, -self.A)

    def sample_tilted(self, rng: np.random.Generator, r: float, size: int) -> np.ndarray:
        p_plus = expit(2.0 * r * self.A)  # P(+A) = 1/(1 + e^{−2rA})
        return np.where(rng.random(size) < p_plus, self.A, -self.A)

    def atoms(self) -> tuple[np.ndarray, np.ndarray]:
        return np.array([-self.A, self.A]), np.array([0.5, 0.5])

    def log_tail(self, k: int, x: np.ndarray, strict: bool) -> np.ndarray:
        """ln P(S_k ≥ x) (> x when ``strict``) of S_k = A(2B − k), B ~ Bin(k, ½): a lattice."""
        from scipy.stats import binom

        tt = 0.5 * (k + x / self.A)  # S_k ≥ x ⇔ B ≥ tt
        near = np.round(tt)
        on_lattice = np.abs(tt - near) <= 1e-9 * np.maximum(1.0, tt)
        j0 = np.where(on_lattice, near + (1 if strict else 0), np.ceil(tt))
        return binom.logsf(j0 - 1, k, 0.5)


@dataclass(frozen=True)
class Uniform(ScaleDensity):
    """C₁ (assumed) = U(−a, a); b = a²/3, so the report's ℓ = 1/√(3b) = 1/a."""

    a: float
    name: str = field(default="uniform", init=False)
    reach: ClassVar[float] = 1.0

    @property
    def b(self) -> float:
        return self.a**2 / 3.0

    def cgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = np.asarray(r, dtype=float)
        g, d1, d2 = _log_sinhc(np.abs(r) * self.a)  # Φ = sinh(ρa)/(ρa)
        return _even(r, g, self.a * d1, self.a**2 * d2)

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        return self.a * (2.0 * rng.random(size) - 1.0)

    def sample_tilted(self, rng: np.random.Generator, r: float, size: int) -> np.ndarray:
        return _tilted_uniform(rng, self.a, r, size)

    def pdf(self, x: np.ndarray) -> np.ndarray:
        return np.where(np.abs(x) <= self.a, 0.5 / self.a, 0.0)

    def log_tail(self, k: int, x: np.ndarray, strict: bool) -> np.ndarray:
        """ln P(S_k ≥ x) of S_k = a(2·IH_k − k), IH_k Irwin–Hall (continuous: ``strict`` is moot)."""
        return np.log(irwin_hall_tail(k, 0.5 * (k + x / self.a)))


@dataclass(frozen=True)
class Triangular(ScaleDensity):
    """C₃ (assumed) = the sum of two independent U(−c, c); support ±2c, b = 2c²/3."""

    c: float
    name: str = field(default="triangular", init=False)
    reach: ClassVar[float] = 2.0

    @property
    def b(self) -> float:
        return 2.0 * self.c**2 / 3.0

    def cgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = np.asarray(r, dtype=float)
        g, d1, d2 = _log_sinhc(np.abs(r) * self.c)  # Φ = (sinh(ρc)/(ρc))²
        return _even(r, 2.0 * g, 2.0 * self.c * d1, 2.0 * self.c**2 * d2)

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        u = rng.random((2, size))
        return self.c * (2.0 * u[0] - 1.0) + self.c * (2.0 * u[1] - 1.0)

    def sample_tilted(self, rng: np.random.Generator, r: float, size: int) -> np.ndarray:
        # the tilt of a sum of independent terms is the sum of the tilted terms
        return _tilted_uniform(rng, self.c, r, size) + _tilted_uniform(rng, self.c, r, size)

    def pdf(self, x: np.ndarray) -> np.ndarray:
        w = 2.0 * self.c
        return np.clip(w - np.abs(x), 0.0, None) / w**2

    def log_tail(self, k: int, x: np.ndarray, strict: bool) -> np.ndarray:
        """ln P(S_k ≥ x): the Irwin–Hall tail of 2k uniforms of half-width c."""
        return np.log(irwin_hall_tail(2 * k, 0.5 * (2 * k + x / self.c)))


@dataclass(frozen=True)
class Gaussian(ScaleDensity):
    """C₄ (assumed) = N(0, b): unbounded, so never physically realisable (|n_ij| ≤ 1)."""

    var: float
    name: str = field(default="gaussian", init=False)

    @property
    def b(self) -> float:
        return self.var

    def cgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = np.asarray(r, dtype=float)
        return 0.5 * self.var * r * r, self.var * r, np.full_like(r, self.var)

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        return rng.normal(0.0, math.sqrt(self.var), size)

    def sample_tilted(self, rng: np.random.Generator, r: float, size: int) -> np.ndarray:
        return rng.normal(self.var * r, math.sqrt(self.var), size)

    def pdf(self, x: np.ndarray) -> np.ndarray:
        return np.exp(-0.5 * np.asarray(x) ** 2 / self.var) / math.sqrt(2.0 * math.pi * self.var)

    def log_tail(self, k: int, x: np.ndarray, strict: bool) -> np.ndarray:
        """ln P(S_k ≥ x) = ln Q(x/√(kb)) (log_ndtr)."""
        return log_ndtr(-x / math.sqrt(k * self.var))


@dataclass(frozen=True)
class Laplace(ScaleDensity):
    """Laplace(0, β) (extra): b = 2β², MGF 1/(1 − β²ρ²) for |ρ| < 1/β."""

    beta: float
    name: str = field(default="laplace", init=False)

    @property
    def b(self) -> float:
        return 2.0 * self.beta**2

    @property
    def rho_max(self) -> float:
        return 1.0 / self.beta

    def cgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = np.asarray(r, dtype=float)
        t = (self.beta * r) ** 2
        inside = t < 1.0
        ts = np.where(inside, t, 0.0)
        one = 1.0 - ts
        g = np.where(inside, -np.log1p(-ts), np.inf)
        g1 = np.where(inside, 2.0 * self.beta**2 * r / one, np.copysign(np.inf, r))
        g2 = np.where(inside, 2.0 * self.beta**2 * (1.0 + ts) / one**2, np.inf)
        return g, g1, g2

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        return rng.laplace(0.0, self.beta, size)

    def sample_tilted(self, rng: np.random.Generator, r: float, size: int) -> np.ndarray:
        if not abs(r) * self.beta < 1.0:
            raise ValueError(f"tilt r = {r:g} is outside the Laplace MGF's domain |rho| < {1 / self.beta:g}")
        e = rng.exponential(1.0, (2, size))  # x = β(E₁ − E₂); the tilt rescales each exponential
        return self.beta * (e[0] / (1.0 - self.beta * r) - e[1] / (1.0 + self.beta * r))

    def pdf(self, x: np.ndarray) -> np.ndarray:
        return np.exp(-np.abs(x) / self.beta) / (2.0 * self.beta)

    def log_tail(self, k: int, x: np.ndarray, strict: bool) -> np.ndarray:
        """ln P(S_k ≥ x) of S_k = β(G₁ − G₂), G ~ Gamma(k, 1), y = x/β > 0:
        P(G₁ − G₂ ≥ y) = e^{−y} Σ_{i<k} Σ_{l≤i} y^{i−l}/(i−l)! · Γ(k+l)/(Γ(k) l! 2^{k+l})."""
        y = x / self.beta
        i = np.arange(k)[:, None]
        l_ = np.arange(k)[None, :]
        ok = l_ <= i
        c = gammaln(k + l_) - gammaln(k) - gammaln(l_ + 1) - (k + l_) * math.log(2.0) - gammaln(i - l_ + 1)
        c = np.where(ok, c, -np.inf)
        ly = np.log(np.maximum(y, 1e-300))[:, None, None]
        pw = np.where(ok, i - l_, 0)[None]
        terms = c[None] + np.where(pw > 0, pw * ly, 0.0)
        return -y + logsumexp(terms.reshape(len(y), -1), axis=1)


@dataclass(frozen=True)
class Arcsine(ScaleDensity):
    """A·cos φ with φ uniform (extra): one constant-envelope interferer; b = A²/2, MGF I₀(ρA)."""

    A: float
    name: str = field(default="arcsine", init=False)
    reach: ClassVar[float] = 1.0

    @property
    def b(self) -> float:
        return 0.5 * self.A**2

    def cgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = np.asarray(r, dtype=float)
        x = np.abs(r) * self.A
        i0, i1 = i0e(x), i1e(x)
        ratio = i1 / i0  # I₁/I₀
        with np.errstate(divide="ignore", invalid="ignore"):
            over_x = np.where(x > 1e-8, ratio / np.where(x > 1e-8, x, 1.0), 0.5)
        g = log_i0(x)  # ln Φ = ln I₀(ρA)
        g2 = self.A**2 * np.clip(1.0 - over_x - ratio**2, 0.0, None)  # I₀″ = I₀ − I₁/x
        return _even(r, g, self.A * ratio, g2)

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        return self.A * np.cos(2.0 * math.pi * rng.random(size))

    def pdf(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        inside = np.abs(x) < self.A
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(inside, 1.0 / (math.pi * np.sqrt(np.where(inside, self.A**2 - x**2, 1.0))), 0.0)


@dataclass(frozen=True)
class Discrete(DensityDefaults):
    """A user-given discrete density: atoms x_i with weights w_i (Σw = 1, zero mean)."""

    x: tuple[float, ...]
    w: tuple[float, ...]
    name: str = field(default="discrete", init=False)

    def __post_init__(self) -> None:
        x, w = np.asarray(self.x, float), np.asarray(self.w, float)
        if x.ndim != 1 or x.shape != w.shape or x.size == 0:
            raise ConfigError("w", self.w, "must be non-empty and as long as the atoms x")
        if not np.all(np.isfinite(x)):
            raise ConfigError("x", self.x, "must be finite")
        if not (np.all(np.isfinite(w)) and np.all(w >= 0.0)):
            raise ConfigError("w", self.w, "must be finite and >= 0")
        if abs(w.sum() - 1.0) > 1e-9:
            raise ConfigError("w", self.w, f"must sum to 1; they sum to {w.sum():.12g}")
        if abs(np.dot(w, x)) > 1e-9 * max(1.0, np.abs(x).max()):
            raise ConfigError("x", self.x, "must have zero mean (the density has mean 0, ATC-10 3.4.12)")
        if np.dot(w, x * x) <= 0.0:
            raise ConfigError("x", self.x, "must give the density a positive second moment")

    @property
    def b(self) -> float:
        return float(np.dot(self.w, np.square(self.x)))

    @property
    def max_abs(self) -> float:
        return float(np.max(np.abs(np.asarray(self.x)[np.asarray(self.w) > 0])))

    @property
    def symmetric(self) -> bool:
        x, w = np.asarray(self.x), np.asarray(self.w)
        order, mirror = np.argsort(x), np.argsort(-x)
        return bool(np.allclose(x[order], -x[mirror]) and np.allclose(w[order], w[mirror]))

    def cgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = np.asarray(r, dtype=float)
        x, w = np.asarray(self.x), np.asarray(self.w)
        with np.errstate(divide="ignore"):
            logits = r[..., None] * x + np.log(w)
        g = logsumexp(logits, axis=-1)
        p = np.exp(logits - g[..., None])  # tilted weights
        m1 = p @ x
        return g, m1, np.clip(p @ (x * x) - m1 * m1, 0.0, None)

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        return rng.choice(np.asarray(self.x), size=size, p=np.asarray(self.w))

    def sample_tilted(self, rng: np.random.Generator, r: float, size: int) -> np.ndarray:
        x, w = np.asarray(self.x), np.asarray(self.w)
        with np.errstate(divide="ignore"):
            logits = r * x + np.log(w)
        p = np.exp(logits - logsumexp(logits))
        return rng.choice(x, size=size, p=p / p.sum())

    def atoms(self) -> tuple[np.ndarray, np.ndarray]:
        return np.asarray(self.x), np.asarray(self.w)


def b_of_ell(ell: float) -> float:
    """The report's contour label ℓ = 1/√(3b) (Figs 3.3–3.6, 3.8) → b = 1/(3ℓ²)."""
    _check_scale("ell", ell)
    return 1.0 / (3.0 * ell * ell)


def ell_of_b(b: float) -> float:
    """ℓ = 1/√(3b)."""
    return 1.0 / math.sqrt(3.0 * _check_scale("b", b))
