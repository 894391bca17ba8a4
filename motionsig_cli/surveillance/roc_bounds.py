"""Upper and lower bounds to the ROC of the matched-filter detector under multiple-access noise —
ATC-10 §3.5, eqs (3.5.7), (3.5.12)–(3.5.14).

The detector declares "present" iff y = (signal) + n ≥ θ, 0 < θ < 1, with the signal 1 or 0, so

    p_f = P(n ≥ θ),        p_m = 1 − p_d = P(−n > 1 − θ)                        (3.5.1)–(3.5.8)

Chernoff exponents (ρ*, γ* the maximisers; Λ is convex with Λ′(0) = 0, so each is the unique root
of a monotone equation):

    E_f(θ) = sup_{ρ≥0} [ρθ − Λ(ρ)],        E_d(θ) = sup_{γ≥0} [γ(1 − θ) − Λ(−γ)]

Upper bound to the ROC ("worst case", the report's solid contours, 3.5.13):

    p_f ≤ e^{−E_f(θ)},    p_m ≤ e^{−E_d(θ)}                                         (3.5.7), (3.5.12)

Lower bound ("best case", broken contours, 3.5.14) with the sign of φ corrected (the printed
φ₁ = −2ρ₁√(…) makes the "lower" bound exceed 1 at every tested point):

    p_f ≥ ½ e^{−E_f(θ) − φ₁},   φ₁ = 2ρ₁√(2Λ″(ρ₁)),   ρ₁ = the smallest root of Λ′(r) − √(2Λ″(r)) = θ
    p_m ≥ ½ e^{−E_d(θ) − φ₂}    (the same with Λ₋(g) = Λ(−g) and 1 − θ)

This is the report's variant. Gallager's tilted-Chebyshev bound, of which it is a loosening, uses
Λ(ρ₁) − ρ₁θ in place of −E_f(θ) (``variant="gallager"``, slightly tighter). Both are valid: under
the law tilted at s the mean is Λ′(s) and the variance Λ″(s); Chebyshev leaves probability ≥ ½ in
(Λ′ − √(2Λ″), Λ′ + √(2Λ″)), where the likelihood ratio is at least e^{Λ − s(Λ′ + √(2Λ″))}.

Everything is returned as natural logarithms: the lower bounds reach 10⁻⁴⁰ on the report's grid.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.optimize import brentq

from motionsig_cli.surveillance.multiple_access import MANModel

LowerVariant = Literal["report", "gallager"]
LN_HALF = math.log(0.5)
Fun = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]


def _side(model: MANModel, sign: float) -> Fun:
    """Λ_s(r) = Λ(s r) with its derivatives in r (s = +1: false alarms, −1: misses)."""

    def fun(r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        lam, d1, d2 = model.log_mgf(sign * np.asarray(r, dtype=float))
        return lam, sign * d1, d2

    return fun


def _bracket_up(fun: Fun, x: np.ndarray, start: np.ndarray, rho_max: float) -> tuple[np.ndarray, np.ndarray]:
    """[lo, hi] with Λ_s′(lo) ≤ x < Λ_s′(hi) by doubling from ``start`` (towards rho_max when finite);
    hi = inf where no r reaches x (a bounded density with x ≥ sup|n|)."""
    lo = np.zeros_like(x)
    hi = np.minimum(start, 0.5 * rho_max) if math.isfinite(rho_max) else start.copy()
    todo = np.ones(x.shape, bool)
    for _ in range(2100):
        _, d1, _ = fun(hi[todo])
        up = d1 > x[todo]
        idx = np.flatnonzero(todo)
        todo[idx[up]] = False
        if not todo.any():
            break
        moving = idx[~up]
        lo[moving] = hi[moving]
        if math.isfinite(rho_max):
            hi[moving] = rho_max - 0.5 * (rho_max - hi[moving])
            stuck = hi[moving] >= rho_max
        else:
            with np.errstate(over="ignore"):
                hi[moving] = 2.0 * hi[moving]
            stuck = ~np.isfinite(hi[moving])
        if stuck.any():
            hi[moving[stuck]] = np.inf
            todo[moving[stuck]] = False
    hi[todo] = np.inf
    return lo, hi


def _newton_bisect(
    residual: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
    lo: np.ndarray,
    hi: np.ndarray,
    *,
    newton: bool = True,
    iters: int = 200,
) -> np.ndarray:
    """Root of an increasing-through-zero residual in finite brackets [lo, hi] (vectorised), Newton
    steps kept inside the bracket, bisection otherwise; converges to ~1e-15 relative."""
    lo, hi = lo.copy(), hi.copy()
    r = 0.5 * (lo + hi)
    for _ in range(iters):
        f, df = residual(r)
        lo = np.where(f < 0.0, r, lo)
        hi = np.where(f > 0.0, r, hi)
        done = (f == 0.0) | (hi - lo <= 4e-16 * hi)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            step = r - f / df if newton else np.full_like(r, np.nan)
        inside = np.isfinite(step) & (step > lo) & (step < hi)
        r_new = np.where(done, r, np.where(inside, step, 0.5 * (lo + hi)))
        if np.all(done | (np.abs(r_new - r) <= 1e-15 * np.abs(r_new))):
            return r_new
        r = r_new
    return r


def chernoff(model: MANModel, x: np.ndarray, sign: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """(r*, E) with E = sup_{r≥0} [r x − Λ(s r)] and r* its maximiser, for levels x > 0.

    sign = +1 gives (ρ*, E_f(θ)) at x = θ; sign = −1 gives (γ*, E_d(θ)) at x = 1 − θ. Where no r
    reaches x (a bounded density with x ≥ sup|n|) r* = E = inf: the tail probability is 0.
    """
    x = np.atleast_1d(np.asarray(x, dtype=float))
    if model.trivial:
        return np.full_like(x, np.inf), np.full_like(x, np.inf)
    fun = _side(model, sign)
    P = model.power
    lo, hi = _bracket_up(fun, x, np.maximum(x / P, 1e-300), model.rho_max)
    ok = np.isfinite(hi)
    r = np.full_like(x, np.inf)
    if ok.any():
        xs = x[ok]

        def residual(rr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            _, d1, d2 = fun(rr)
            return d1 - xs, d2

        r[ok] = _newton_bisect(residual, lo[ok], hi[ok])  # Λ_s′(r*) = x
    E = np.full_like(x, np.inf)
    if ok.any():
        lam, _, _ = fun(r[ok])
        E[ok] = np.maximum(r[ok] * x[ok] - lam, 0.0)  # the sup includes r = 0: E ≥ 0
    return r, E


def _illinois(
    fun: Callable[[np.ndarray], np.ndarray], a: np.ndarray, b: np.ndarray, iters: int = 100
) -> np.ndarray:
    """Vectorised Illinois (modified regula falsi) on brackets with f(a) < 0 < f(b)."""
    fa, fb = fun(a), fun(b)
    side = np.zeros(a.shape, int)
    c = b.copy()
    for _ in range(iters):
        with np.errstate(invalid="ignore", divide="ignore"):
            c = b - fb * (b - a) / (fb - fa)
        c = np.where(np.isfinite(c) & (c > a) & (c < b), c, 0.5 * (a + b))
        fc = fun(c)
        up = fc > 0.0
        b, fb = np.where(up, c, b), np.where(up, fc, fb)
        a, fa = np.where(up, a, c), np.where(up, fa, fc)
        fa = np.where(up & (side == 1), 0.5 * fa, fa)  # the same end moved twice: halve the other
        fb = np.where(~up & (side == -1), 0.5 * fb, fb)
        side = np.where(up, 1, -1)
        if np.all((fc == 0.0) | (b - a <= 4e-16 * np.abs(b))):
            break
    return c


def gallager_root(model: MANModel, x: np.ndarray, r_star: np.ndarray, sign: float = 1.0) -> np.ndarray:
    """The smallest r > 0 with Λ_s′(r) − √(2Λ_s″(r)) = x (the lower bound's root); NaN where none exists.

    Below r* the residual is negative (Λ_s′ ≤ x there), so the scan starts at r*: a geometric grid
    (ratio 1.03 up to 10³r*, then 1.25 up to 10¹²r*; towards rho_max for a Laplace density), scanned in
    blocks of 16 points until every column has changed sign, finds the first sign change; the Illinois
    method refines it.
    """
    x = np.atleast_1d(np.asarray(x, dtype=float))
    r_star = np.atleast_1d(np.asarray(r_star, dtype=float))
    out = np.full_like(x, np.nan)
    ok = np.isfinite(r_star) & (r_star > 0)
    if not ok.any() or model.trivial:
        return out
    fun = _side(model, sign)
    xs, rs = x[ok], r_star[ok]
    rho_max = model.rho_max
    if math.isfinite(rho_max):
        frac = 1.0 - np.concatenate([0.97 ** np.arange(1, 1200), [1e-15]])
        grid = rs[None, :] + (rho_max - rs[None, :]) * frac[:, None]
    else:
        steps = np.concatenate([1.03 ** np.arange(1, 235), 1.03**234 * 1.25 ** np.arange(1, 94)])
        grid = rs[None, :] * steps[:, None]

    def h(r: np.ndarray, target: np.ndarray) -> np.ndarray:
        with np.errstate(invalid="ignore", over="ignore"):
            _, d1, d2 = fun(r)
            return d1 - np.sqrt(2.0 * np.clip(d2, 0.0, None)) - target

    lo, hi = rs.copy(), np.full_like(rs, np.nan)
    todo = np.ones(rs.shape, bool)
    for start in range(0, grid.shape[0], 16):
        cols = np.flatnonzero(todo)
        if cols.size == 0:
            break
        block = grid[start : start + 16][:, cols]
        pos = h(block, xs[cols][None, :]) > 0.0
        hit = pos.any(axis=0)
        first = np.argmax(pos, axis=0)
        c_hit = cols[hit]
        hi[c_hit] = block[first[hit], np.flatnonzero(hit)]
        prev = np.where(first[hit] > 0, block[np.maximum(first[hit] - 1, 0), np.flatnonzero(hit)], lo[c_hit])
        lo[c_hit] = prev
        lo[cols[~hit]] = block[-1, ~hit]
        todo[c_hit] = False
    found = np.flatnonzero(np.isfinite(hi))
    if found.size:
        target = xs[found]
        root = _illinois(lambda r: h(r, target), lo[found], hi[found])
        sub = np.full(xs.shape, np.nan)
        sub[found] = root
        out[ok] = sub
    return out


@dataclass(frozen=True)
class RocBounds:
    """Both bounds at each threshold θ (arrays over θ; logs are natural)."""

    theta: np.ndarray
    rho_star: np.ndarray
    E_f: np.ndarray
    rho1: np.ndarray
    phi1: np.ndarray
    log_pf_up: np.ndarray
    log_pf_lo: np.ndarray
    gamma_star: np.ndarray
    E_d: np.ndarray
    gamma1: np.ndarray
    phi2: np.ndarray
    log_pm_up: np.ndarray
    log_pm_lo: np.ndarray
    variant: LowerVariant

    @property
    def pd_lo(self) -> np.ndarray:
        """p_d ≥ 1 − e^{−E_d} (the upper ROC contour's p_d)."""
        return -np.expm1(self.log_pm_up)

    @property
    def pd_up(self) -> np.ndarray:
        """p_d ≤ 1 − ½e^{−E_d − φ₂} (the lower ROC contour's p_d)."""
        return -np.expm1(self.log_pm_lo)


def _lower(
    model: MANModel, x: np.ndarray, r_star: np.ndarray, E: np.ndarray, sign: float, variant: LowerVariant
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(r₁, φ, ln lower bound) for one side (eq 3.5.14 with the corrected sign)."""
    r1 = gallager_root(model, x, r_star, sign)
    phi = np.full_like(x, np.nan)
    log_lo = np.full_like(x, -np.inf)
    ok = np.isfinite(r1)
    if ok.any():
        lam, _, d2 = _side(model, sign)(r1[ok])
        phi[ok] = 2.0 * r1[ok] * np.sqrt(2.0 * np.clip(d2, 0.0, None))  # φ = 2r₁√(2Λ″(r₁))
        if variant == "report":
            log_lo[ok] = LN_HALF - E[ok] - phi[ok]  # ½ exp(−E(θ) − φ)
        else:
            log_lo[ok] = LN_HALF + lam - r1[ok] * x[ok] - phi[ok]  # ½ exp(Λ(r₁) − r₁x − φ)
    return r1, phi, log_lo


def roc_bounds(model: MANModel, theta: np.ndarray, variant: LowerVariant = "report") -> RocBounds:
    """Upper (3.5.13) and lower (3.5.14, corrected) bounds at thresholds θ ∈ (0, 1)."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    if np.any(~((theta > 0.0) & (theta < 1.0))):
        raise ValueError("thresholds must lie in the open interval (0, 1)")
    if variant not in ("report", "gallager"):
        raise ValueError(f"unknown lower-bound variant {variant!r}; use report or gallager")
    rho, E_f = chernoff(model, theta, +1.0)
    gam, E_d = chernoff(model, 1.0 - theta, -1.0)
    rho1, phi1, lf = _lower(model, theta, rho, E_f, +1.0, variant)
    gam1, phi2, lm = _lower(model, 1.0 - theta, gam, E_d, -1.0, variant)
    return RocBounds(theta, rho, E_f, rho1, phi1, -E_f, lf, gam, E_d, gam1, phi2, -E_d, lm, variant)


def theta_for_pd(
    model: MANModel, pd: float, log_pm: Callable[[np.ndarray], np.ndarray] | None = None
) -> float:
    """The threshold at which a miss curve ln p_m(θ) (increasing in θ) equals ln(1 − p_d).

    The default curve is the upper bound −E_d(θ) (the report's solid contour at fixed p_d).
    NaN when the curve does not reach the target in (0, 1).
    """
    if not 0.0 < pd < 1.0:
        raise ValueError(f"p_d must lie in (0, 1); got {pd!r}")
    target = math.log1p(-pd)
    if log_pm is None:

        def log_pm(t: np.ndarray) -> np.ndarray:
            return -chernoff(model, 1.0 - np.atleast_1d(t), -1.0)[1]

    def f(t: float) -> float:
        v = float(log_pm(np.array([t]))[0])
        return max(v, -1e300) - target

    lo, hi = 1e-12, 1.0 - 1e-12
    flo, fhi = f(lo), f(hi)
    if not (flo <= 0.0 <= fhi):
        return math.nan
    return float(brentq(f, lo, hi, xtol=1e-15, rtol=1e-15, maxiter=500))
