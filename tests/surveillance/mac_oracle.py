"""Independent test oracle for the multiple-access-noise (MAN) ROC bounds of ATC-10 Sec. 3.

This is a second implementation of the report's Sec. 3 (and of the exact ROC and the Monte
Carlo levels beyond it), written from the equations only, and **not** from ``motionsig_cli``
(nothing is imported from the package).  It favours simple, direct formulas at high precision over
clever numerics:

* all bound / exact computations run in ``mpmath`` at ``DPS`` (60) significant digits or
  more;
* the MGF of each amplitude density is available both in closed form (used by the bounds)
  and by direct numerical quadrature (``mgf``), so the closed forms can be checked;
* every derivative of the log-MGF Lambda is taken numerically with ``mpmath.diff`` (no
  hand-written g', g'' and no w-form), and every root is found by plain bisection;
* the exact ROC conditions on K ~ Binomial(M, q) with an exact pmf and exact tails of S_K
  (Irwin-Hall alternating sum at >= 90 digits, binomial lattice tail with >= / >, erfc, and
  for Laplace a Gamma-difference: exact finite sum by default, mpmath.quad of the
  regularized gammainc on request; the two agree to > 25 digits);
* Sec. 3.8's Exp(G) is obtained by numerically maximising the two-point exponent, not from
  the closed form (3.7.24)/(3.8.16);
* PSK second moments are exact rational numbers (``fractions.Fraction``) from a direct
  enumeration; the RF-level (Level C) matched-filter output is a plain waveform
  simulation with an FFT brick-wall low-pass filter; the Zakai bandwidth is a dense
  numerical integral of the sampled autocorrelation.

Conventions: N aircraft, M = N - 1 interferers, q = 2 tau/alpha, amplitude density C with
second moment b, Lambda(rho) = M ln(1 - q + q Phi(rho)).  Density names: "two-point",
"uniform", "triangular", "gaussian", "laplace".  Floats are converted to mpf through
their shortest repr (so 2e-5 means the decimal 2/100000); mpf / int / str inputs are
used as they are.  Public functions return Python floats or dicts of floats, except the
PSK second moments, which return exact ``Fraction``s.

Public API (b = second moment, N = number of aircraft, theta in (0, 1)):

    mgf(density, b, rho)                                      -> Phi(rho) by quadrature
    chernoff(density, b, N, tau_over_alpha, theta)            -> rho_star, E_f, log_pf_up, pf_up
    chernoff_miss(density, b, N, tau_over_alpha, theta)       -> gamma_star, E_d, log_pm_up, pm_up
    lower_bound(density, b, N, tau_over_alpha, theta, variant="report"|"gallager")
                                                              -> rho1, phi1, log_pf_lo, pf_lo
    lower_bound_miss(...same...)                              -> gamma1, phi2, log_pm_lo, pm_lo
    exact(density, b, N, tau_over_alpha, theta)               -> pf, pm
    roc_g(b, N, tau_over_alpha, theta)                        -> P, pf, pm   (P = (N-1) q b)
    exp_two_point_numeric(G, N, tau_over_alpha)               -> Exp(G), exact form, brute force
    exp_approx_3816(G, N, tau_over_alpha)                     -> Exp(G), approximation (3.8.16)
    psk_b_random(code), psk_b_family(ref, codes)              -> b as Fraction
    chip_formula(ref, intf, delay_chips), chip_formula_kf(...) -> X (Level B chip formula)
    rf_mf_output(ref, intf, delay_chips, phase, cycles_per_chip=128, samples_per_cycle=16)
                                                              -> RF-level MF sample ~ cos(phase) X
    zakai_W_numeric(code)                                     -> W tau_c
    code_from_string("++-+...")                               -> numpy +-1 array

Run ``python tests/surveillance/mac_oracle.py`` for a self-check against the reference values
T1 ... T12.
"""

from __future__ import annotations

import math
import time
from fractions import Fraction

import mpmath
import numpy as np
from mpmath import mp, mpf

DPS = 60
DENSITIES = ("two-point", "uniform", "triangular", "gaussian", "laplace")


def _m(val):
    """Convert to mpf; floats go through repr so 2e-5 is the decimal 2/100000."""
    if isinstance(val, mpf):
        return +val
    if isinstance(val, (float, np.floating)):
        return mpf(repr(float(val)))
    if isinstance(val, (int, np.integer)):
        return mpf(int(val))
    if isinstance(val, Fraction):
        return mpf(val.numerator) / val.denominator
    return mpf(val)


def _f(x):
    """mpf -> Python float (inf kept)."""
    return float(x)


# ------------------------------------------------------------------------------------------
# amplitude densities
# ------------------------------------------------------------------------------------------


def _check_density(density):
    if density not in DENSITIES:
        raise ValueError(f"unknown density {density!r}; expected one of {DENSITIES}")


def _scale(density, b):
    """The natural scale parameter of the density with second moment b."""
    if density == "two-point":
        return mpmath.sqrt(b)  # A
    if density == "uniform":
        return mpmath.sqrt(3 * b)  # a
    if density == "triangular":
        return mpmath.sqrt(3 * b / 2)  # c (half-width of each of the two uniforms)
    if density == "gaussian":
        return mpmath.sqrt(b)  # sigma
    if density == "laplace":
        return mpmath.sqrt(b / 2)  # beta
    raise ValueError(density)


def _a_max(density, b):
    """Largest |x| in the support (inf for unbounded densities)."""
    s = _scale(density, b)
    if density in ("two-point", "uniform"):
        return s
    if density == "triangular":
        return 2 * s
    return mpmath.inf


def _rho_cap(density, b):
    """Upper end of the MGF domain (the Laplace pole 1/beta; inf otherwise)."""
    if density == "laplace":
        return 1 / _scale(density, b)
    return mpmath.inf


def _sinhc(x):
    if x == 0:
        return mpf(1)
    return mpmath.sinh(x) / x


def _phi_closed(density, b, r):
    """Closed-form MGF Phi(r) (mpf arithmetic)."""
    s = _scale(density, b)
    if density == "two-point":
        return mpmath.cosh(r * s)
    if density == "uniform":
        return _sinhc(r * s)
    if density == "triangular":
        return _sinhc(r * s) ** 2
    if density == "gaussian":
        return mpmath.exp(b * r * r / 2)
    if density == "laplace":
        z = 1 - (s * r) ** 2
        if z <= 0:
            return mpmath.inf
        return 1 / z
    raise ValueError(density)


def _pdf(density, b, x):
    """Density C(x) (continuous densities only)."""
    s = _scale(density, b)
    if density == "uniform":
        return 1 / (2 * s) if abs(x) <= s else mpf(0)
    if density == "triangular":
        return max(2 * s - abs(x), mpf(0)) / (4 * s * s)
    if density == "gaussian":
        return mpmath.npdf(x, 0, s)
    if density == "laplace":
        return mpmath.exp(-abs(x) / s) / (2 * s)
    raise ValueError(density)


def mgf(density, b, rho):
    """Phi(rho) = int e^{rho x} C(x) dx by direct numerical quadrature (sum of atoms for two-point)."""
    _check_density(density)
    with mp.workdps(DPS):
        b = _m(b)
        r = _m(rho)
        s = _scale(density, b)
        if density == "two-point":
            res = (mpmath.exp(r * s) + mpmath.exp(-r * s)) / 2
        elif density == "uniform":
            res = mpmath.quad(lambda x: mpmath.exp(r * x) * _pdf(density, b, x), [-s, 0, s])
        elif density == "triangular":
            res = mpmath.quad(lambda x: mpmath.exp(r * x) * _pdf(density, b, x), [-2 * s, 0, 2 * s])
        elif density == "gaussian":
            res = mpmath.quad(lambda x: mpmath.exp(r * x) * _pdf(density, b, x), [-mpmath.inf, 0, mpmath.inf])
        else:  # laplace
            if abs(r) * s >= 1:
                return math.inf
            res = mpmath.quad(lambda x: mpmath.exp(r * x) * _pdf(density, b, x), [-mpmath.inf, 0, mpmath.inf])
        return _f(res)


# ------------------------------------------------------------------------------------------
# Lambda and its numerical derivatives
# ------------------------------------------------------------------------------------------


class _Model:
    """Lambda(r) = M ln(1 - q + q Phi(r)) for a common density, all numbers mpf at DPS."""

    def __init__(self, density, b, N, tau_over_alpha, sign=1):
        _check_density(density)
        self.density = density
        self.b = _m(b)
        self.N = int(N)
        if self.N < 1:
            raise ValueError("N must be >= 1")
        self.M = mpf(self.N - 1)
        self.q = 2 * _m(tau_over_alpha)
        if not (0 < self.q < 1):
            raise ValueError("q = 2 tau/alpha must be in (0, 1)")
        if self.b <= 0:
            raise ValueError("b must be > 0")
        self.sign = sign  # +1: Lambda(r); -1: Lambda_-(g) = Lambda(-g)
        self.cap = _rho_cap(density, self.b)
        self.a_max = _a_max(density, self.b)

    def lam(self, r):
        phi = _phi_closed(self.density, self.b, self.sign * r)
        return self.M * mpmath.log(1 - self.q + self.q * phi)

    def d1(self, r):
        return mpmath.diff(self.lam, r, 1)

    def d2(self, r):
        return mpmath.diff(self.lam, r, 2)


def _bisect(fun, lo, hi, rtol=None, maxit=400):
    """Root of fun on [lo, hi] with fun(lo) < 0 < fun(hi), by plain bisection."""
    if rtol is None:
        rtol = mpf(10) ** -28
    flo = fun(lo)
    fhi = fun(hi)
    if not (flo < 0 < fhi):
        raise ValueError("root not bracketed")
    for _ in range(maxit):
        mid = (lo + hi) / 2
        fm = fun(mid)
        if fm < 0:
            lo = mid
        else:
            hi = mid
        if hi - lo <= rtol * hi:
            break
    return (lo + hi) / 2


def _upper_bracket(fun, model):
    """Find hi with fun(hi) > 0 (fun increasing from fun(0) < 0); None if none exists."""
    if model.cap == mpmath.inf:
        hi = mpf(1)
        for _ in range(200):
            if fun(hi) > 0:
                return hi
            hi *= 2
        return None
    # Laplace: approach the pole 1/beta
    for k in range(1, 200):
        hi = model.cap * (1 - mpf(2) ** -k)
        if fun(hi) > 0:
            return hi
    return None


def _chernoff_core(model, t):
    """(r_star, E) = argmax / max over r >= 0 of r t - Lambda_sign(r)."""
    if model.N == 1:
        return mpmath.inf, mpmath.inf
    if t >= model.M * model.a_max:
        return mpmath.inf, mpmath.inf  # p = 0 (the lattice point t = M A itself aside)

    def fun(r):
        return model.d1(r) - t

    hi = _upper_bracket(fun, model)
    if hi is None:
        return mpmath.inf, mpmath.inf
    r = _bisect(fun, mpf(0), hi)
    return r, r * t - model.lam(r)


def chernoff(density, b, N, tau_over_alpha, theta):
    """Chernoff p_f exponent: {rho_star, E_f, log_pf_up (= -E_f), pf_up}."""
    with mp.workdps(DPS):
        model = _Model(density, b, N, tau_over_alpha, sign=1)
        th = _m(theta)
        r, E = _chernoff_core(model, th)
        return {"rho_star": _f(r), "E_f": _f(E), "log_pf_up": _f(-E), "pf_up": _f(mpmath.exp(-E))}


def chernoff_miss(density, b, N, tau_over_alpha, theta):
    """Chernoff p_m exponent computed with Lambda(-gamma) and 1 - theta (no symmetry used).

    Returns {gamma_star, E_d, log_pm_up (= -E_d), pm_up}.
    """
    with mp.workdps(DPS):
        model = _Model(density, b, N, tau_over_alpha, sign=-1)
        t = 1 - _m(theta)
        g, E = _chernoff_core(model, t)
        return {"gamma_star": _f(g), "E_d": _f(E), "log_pm_up": _f(-E), "pm_up": _f(mpmath.exp(-E))}


def _first_root_h(model, t):
    """Smallest r > 0 with Lambda'(r) - sqrt(2 Lambda''(r)) = t (geometric scan + bisection)."""

    def h(r):
        return model.d1(r) - mpmath.sqrt(2 * max(model.d2(r), mpf(0))) - t

    grid = []
    r = mpf("1e-6")
    rmax = mpf("1e7") if model.cap == mpmath.inf else model.cap
    while r < rmax:
        grid.append(r)
        r *= mpf("1.25")
    if model.cap != mpmath.inf:  # Laplace: add points crowding towards the pole
        grid += [model.cap * (1 - mpf(10) ** -k / 10) for k in range(1, 40)]
        grid = sorted(set(grid))
    prev = mpf(0)
    for r in grid:
        if h(r) > 0:
            return _bisect(h, prev, r)
        prev = r
    return None


def _lower_core(model, t, variant):
    if variant not in ("report", "gallager"):
        raise ValueError("variant must be 'report' or 'gallager'")
    r1 = _first_root_h(model, t)
    if r1 is None:
        return None, None, -mpmath.inf
    phi1 = 2 * r1 * mpmath.sqrt(2 * model.d2(r1))
    if variant == "report":
        _, E = _chernoff_core(model, t)
        log_lo = mpmath.log(mpf(1) / 2) - E - phi1
    else:
        log_lo = mpmath.log(mpf(1) / 2) + model.lam(r1) - r1 * t - phi1
    return r1, phi1, log_lo


def lower_bound(density, b, N, tau_over_alpha, theta, variant="report"):
    """p_f lower bound (spec Sec. 4.2, phi entering with the corrected sign).

    Returns {rho1, phi1, log_pf_lo, pf_lo}; rho1 = phi1 = None and log_pf_lo = -inf if no root.
    """
    with mp.workdps(DPS):
        model = _Model(density, b, N, tau_over_alpha, sign=1)
        r1, phi1, lo = _lower_core(model, _m(theta), variant)
        return {
            "rho1": None if r1 is None else _f(r1),
            "phi1": None if phi1 is None else _f(phi1),
            "log_pf_lo": _f(lo),
            "pf_lo": _f(mpmath.exp(lo)),
        }


def lower_bound_miss(density, b, N, tau_over_alpha, theta, variant="report"):
    """p_m lower bound with Lambda_-(g) = Lambda(-g) and 1 - theta: {gamma1, phi2, log_pm_lo, pm_lo}."""
    with mp.workdps(DPS):
        model = _Model(density, b, N, tau_over_alpha, sign=-1)
        g1, phi2, lo = _lower_core(model, 1 - _m(theta), variant)
        return {
            "gamma1": None if g1 is None else _f(g1),
            "phi2": None if phi2 is None else _f(phi2),
            "log_pm_lo": _f(lo),
            "pm_lo": _f(mpmath.exp(lo)),
        }


# ------------------------------------------------------------------------------------------
# exact ROC (spec Sec. 11.1)
# ------------------------------------------------------------------------------------------


def _irwin_hall_cdf(n, u):
    """P(U_1 + ... + U_n <= u) for iid U(0,1), alternating sum; caller sets the precision."""
    if u <= 0:
        return mpf(0)
    if u >= n:
        return mpf(1)
    tot = mpf(0)
    for j in range(int(mpmath.floor(u)) + 1):
        tot += (-1) ** j * mpmath.binomial(n, j) * (u - j) ** n
    return tot / mpmath.factorial(n)


def _laplace_tail_quad(K, y):
    """P(G1 - G2 >= y) = int_0^inf P(G1 >= y + s) f_{G2}(s) ds by mpmath.quad (regularized gammainc)."""

    def integrand(t):
        upper = mpmath.gammainc(K, y + t, mpmath.inf, regularized=True)
        return upper * mpmath.exp((K - 1) * mpmath.log(t) - t - mpmath.loggamma(K))

    with mp.workdps(30):
        res = mpmath.quad(integrand, [mpf(0), mpf(max(K - 1, 1)), mpf(2 * K + 10), mpmath.inf])
    return +res


def _laplace_tail_series(K, y):
    """Same probability as a finite positive sum (integer K, y >= 0).

    With P(G1 >= z) = e^{-z} sum_{i<K} z^i/i! and a binomial expansion of (y + s)^i,
    P(G1 - G2 >= y) = e^{-y} 2^{-K} sum_{l=0}^{K-1} C(K-1+l, l) 2^{-l} e_{K-1-l}(y),
    e_n(y) = sum_{j<=n} y^j/j!.  No cancellation (all terms positive).
    """
    e = [mpf(0)] * K  # e[n] = truncated exponential series of order n
    term = mpf(1)
    acc = mpf(0)
    for j in range(K):
        if j > 0:
            term = term * y / j
        acc += term
        e[j] = acc
    tot = mpf(0)
    for ell in range(K):
        tot += mpmath.binomial(K - 1 + ell, ell) / mpf(2) ** ell * e[K - 1 - ell]
    return mpmath.exp(-y) * tot / mpf(2) ** K


def _tail(density, b, K, x, strict, laplace_method="series"):
    """P(S_K >= x) (strict=False) or P(S_K > x) (strict=True), S_K = sum of K iid draws from C."""
    s = _scale(density, b)
    if density == "two-point":
        # S_K = A (2B - K), B ~ Bin(K, 1/2)
        z = (K + x / s) / 2
        j0 = int(mpmath.floor(z)) + 1 if strict else int(mpmath.ceil(z))
        j0 = max(j0, 0)
        if j0 > K:
            return mpf(0)
        num = sum(math.comb(K, j) for j in range(j0, K + 1))
        return mpf(num) / mpf(2) ** K
    if density in ("uniform", "triangular"):
        n = K if density == "uniform" else 2 * K
        # S = s (2 IH_n - n);  P(IH_n >= t) = F_n(n - t) with t = (n + x/s)/2
        with mp.workdps(max(90, 60 + 2 * n)):
            u = (n - _m(x) / s) / 2
            res = _irwin_hall_cdf(n, u)
        return +res
    if density == "gaussian":
        return mpmath.erfc(x / mpmath.sqrt(2 * K * b)) / 2
    if density == "laplace":
        # S_K = beta (G1 - G2), G1, G2 ~ Gamma(K, 1) independent; y = x / beta >= 0
        y = x / s
        if y < 0:
            raise ValueError("laplace tail implemented for x >= 0 only")
        if laplace_method == "quad":
            return _laplace_tail_quad(K, y)
        if laplace_method == "series":
            return _laplace_tail_series(K, y)
        raise ValueError("laplace_method must be 'series' or 'quad'")
    raise ValueError(density)


def exact(density, b, N, tau_over_alpha, theta, laplace_method="series"):
    """Exact ROC point {pf, pm}: sum over K ~ Bin(M, q) of P(S_K >= theta) and P(S_K > 1 - theta).

    K = 1, 2, ... until K > Mq and the binomial pmf is below 1e-45 times the smaller running
    sum.  For "laplace", ``laplace_method="quad"`` uses the mpmath.quad/gammainc integral
    (slow, ~10 s per call at Mq = 4); the default "series" uses the equivalent exact finite sum
    (see ``_laplace_tail_series``); both are cross-checked in the self-check.
    """
    _check_density(density)
    with mp.workdps(DPS):
        b = _m(b)
        N = int(N)
        M = N - 1
        q = 2 * _m(tau_over_alpha)
        th = _m(theta)
        if M == 0:
            return {"pf": 0.0, "pm": 0.0}
        pmf = (1 - q) ** M  # K = 0 (never contributes for 0 < theta < 1)
        ratio = q / (1 - q)
        pf = mpf(0)
        pm = mpf(0)
        mean = M * q
        amax = _a_max(density, b)
        need_pf = M * amax >= th
        need_pm = M * amax > 1 - th
        for K in range(1, M + 1):
            pmf = pmf * (M - K + 1) / K * ratio
            pf += pmf * _tail(density, b, K, th, False, laplace_method)
            pm += pmf * _tail(density, b, K, 1 - th, True, laplace_method)
            # stop only once every probability that can be non-zero is non-zero (bounded densities
            # give P(S_K >= x) = 0 for small K) and the pmf is negligible relative to both
            refs = [v for v, need in ((pf, need_pf), (pm, need_pm)) if need]
            if K > mean and all(v > 0 for v in refs) and all(pmf < mpf("1e-45") * v for v in refs):
                break
        return {"pf": _f(pf), "pm": _f(pm)}


# ------------------------------------------------------------------------------------------
# Gaussian ROC_g (3.8.3) and Sec. 3.8 Exp(G)
# ------------------------------------------------------------------------------------------


def roc_g(b, N, tau_over_alpha, theta):
    """ROC_g with P = (N-1) q b: {P, pf, pm}."""
    with mp.workdps(DPS):
        P = (int(N) - 1) * 2 * _m(tau_over_alpha) * _m(b)
        th = _m(theta)
        return {
            "P": _f(P),
            "pf": _f(mpmath.erfc(th / mpmath.sqrt(2 * P)) / 2),
            "pm": _f(mpmath.erfc((1 - th) / mpmath.sqrt(2 * P)) / 2),
        }


def exp_two_point_numeric(G, N, tau_over_alpha):
    """Exp(G) of spec Sec. 7.3 (exact, no approximation) by brute-force maximisation.

    theta = 0.5, p = theta^2/(2G), two-point density A = sqrt(p/(M q)); maximise
    rho theta - M ln(1 - q + q cosh(rho A)) over rho (bisection on its mpmath.diff derivative).
    """
    with mp.workdps(DPS):
        G = _m(G)
        M = mpf(int(N) - 1)
        q = 2 * _m(tau_over_alpha)
        th = mpf(1) / 2
        p = th * th / (2 * G)
        A = mpmath.sqrt(p / (M * q))
        if th >= M * A:
            return math.inf

        def obj(r):
            return r * th - M * mpmath.log(1 - q + q * mpmath.cosh(r * A))

        def neg_slope(r):
            return -mpmath.diff(obj, r)

        hi = mpf(1)
        while neg_slope(hi) <= 0:
            hi *= 2
        r = _bisect(neg_slope, mpf(0), hi)
        return _f(obj(r))


def exp_approx_3816(G, N, tau_over_alpha):
    """The approximation (3.8.16): sqrt(4 lam G) asinh(sqrt(G/lam)) - N ln(1 - q + q sqrt(1 + G/lam))."""
    with mp.workdps(DPS):
        G = _m(G)
        ta = _m(tau_over_alpha)
        lam = int(N) * ta
        q = 2 * ta
        res = mpmath.sqrt(4 * lam * G) * mpmath.asinh(mpmath.sqrt(G / lam)) - int(N) * mpmath.log(
            1 - q + q * mpmath.sqrt(1 + G / lam)
        )
        return _f(res)


# ------------------------------------------------------------------------------------------
# PSK second moments (spec Sec. 8 / 12.1 Level B), exact rationals
# ------------------------------------------------------------------------------------------

_F_WEIGHTS = (Fraction(1, 3), Fraction(1, 6), Fraction(1, 3))  # E(1-f)^2, E f(1-f), E f^2


def _code(c):
    return [int(v) for v in np.asarray(c).ravel()]


def _ccorr(d, c, m):
    """C(m) = sum_n d_n c_{n+m}, aperiodic (out-of-range terms 0)."""
    L = len(c)
    return sum(d[n] * c[n + m] for n in range(len(d)) if 0 <= n + m < L)


def psk_b_random(code):
    """Exact b = E n_ij^2 for a fresh iid +-1 interferer code against the reference ``code``.

    X = [(1-f) C(k) + f C(k+1)]/L, k uniform on -L..L-1, f ~ U(0,1), E cos^2 = 1/2, and
    E_d[C(k) C(k')] = sum_n c_{n+k} c_{n+k'} over n in [0, L) with both indices in range.
    Returns a Fraction.
    """
    c = _code(code)
    L = len(c)

    def ed(k1, k2):
        return sum(c[n + k1] * c[n + k2] for n in range(L) if 0 <= n + k1 < L and 0 <= n + k2 < L)

    w0, w1, w2 = _F_WEIGHTS
    tot = Fraction(0)
    for k in range(-L, L):
        tot += w0 * ed(k, k) + 2 * w1 * ed(k, k + 1) + w2 * ed(k + 1, k + 1)
    ex2 = tot / (2 * L) / (L * L)
    return ex2 / 2


def psk_b_family(ref, codes):
    """Exact b when the interferer code is a uniformly drawn row of ``codes`` (no d average).

    Returns a Fraction: (1/2) E_{j,k,f} X^2.
    """
    c = _code(ref)
    L = len(c)
    rows = [_code(r) for r in np.atleast_2d(np.asarray(codes))]
    w0, w1, w2 = _F_WEIGHTS
    tot = Fraction(0)
    for d in rows:
        if len(d) != L:
            raise ValueError("all codes must have the reference length")
        cc = {m: _ccorr(d, c, m) for m in range(-L, L + 1)}
        for k in range(-L, L):
            tot += w0 * cc[k] ** 2 + 2 * w1 * cc[k] * cc[k + 1] + w2 * cc[k + 1] ** 2
    ex2 = tot / (len(rows) * 2 * L) / (L * L)
    return ex2 / 2


# ------------------------------------------------------------------------------------------
# Level C: RF waveform -> mixer -> brick-wall LPF -> matched filter (spec Sec. 12.1)
# ------------------------------------------------------------------------------------------


def chip_formula(ref, intf, delay_chips):
    """X = int S_j(x - delay) S_i(x) dx for rectangular unit-energy chips (tau_c = 1, tau = L).

    Computed by direct summation of chip-overlap lengths d_n c_m |[n+delay, n+delay+1) & [m, m+1)| / L;
    this equals the linearly interpolated aperiodic cross-correlation [(1-f)C(k) + f C(k+1)]/L.
    """
    c = _code(ref)
    d = _code(intf)
    L = len(c)
    dl = float(delay_chips)
    tot = 0.0
    for n, dn in enumerate(d):
        s0 = n + dl
        for m in range(max(0, math.floor(s0)), min(L, math.floor(s0) + 2)):
            ov = min(s0 + 1, m + 1) - max(s0, m)
            if ov > 0:
                tot += dn * c[m] * ov
    return tot / L


def chip_formula_kf(ref, intf, delay_chips):
    """[(1-f) C(k) + f C(k+1)]/L with delay = k + f (the spec's Level-B formula)."""
    c = _code(ref)
    d = _code(intf)
    L = len(c)
    k = math.floor(delay_chips)
    f = delay_chips - k
    return ((1 - f) * _ccorr(d, c, k) + f * _ccorr(d, c, k + 1)) / L


def rf_mf_output(
    ref, intf, delay_chips, phase, cycles_per_chip=128, samples_per_cycle=16, include_signal=False
):
    """RF-level MF sample of one interferer (spec Sec. 12.1 Level C); tau_c = 1, tau = L.

    Received interferer: S_j(t - delay) cos(2 pi f0 t + phase), i.e. envelope delayed by
    ``delay_chips`` relative to the MF window [0, L) and carrier time offset chosen so that
    cos(2 pi f0 (t_i - t_j)) = cos(phase) (t_i = 0).  The sub-carrier-cycle part of t_j is
    treated as independent of the envelope delay, which is the f0 -> inf idealisation of the
    report.  Steps: mix with 2 cos(2 pi f0 t), brick-wall LPF (keep |f| <= f0) by FFT on a grid
    zero-padded by 4L chips on each side, correlate with S_i over [0, L).  Envelopes are
    cell-averaged over each sample so fractional chip edges are represented exactly.
    With include_signal=True the wanted signal S_i(t) cos(2 pi f0 t) is added (output ~ 1 + ...).
    Expected: cos(phase) * chip_formula(ref, intf, delay_chips) (+ 1).
    """
    c = np.asarray(_code(ref), dtype=float)
    d = np.asarray(_code(intf), dtype=float)
    L = len(c)
    f0 = float(cycles_per_chip)
    fs = int(cycles_per_chip) * int(samples_per_cycle)  # samples per chip
    dt = 1.0 / fs
    pad = 4 * L
    t0 = -L - pad
    nchips = 3 * L + 2 * pad
    ns = nchips * fs
    edges = t0 + np.arange(ns + 1) * dt
    tmid = t0 + (np.arange(ns) + 0.5) * dt

    def cell_avg(code, shift):
        cum = np.concatenate([[0.0], np.cumsum(code)])
        u = np.clip(edges - shift, 0.0, len(code))
        m = np.minimum(np.floor(u).astype(int), len(code) - 1)
        E = cum[m] + code[m] * (u - m)
        return np.diff(E) / dt / math.sqrt(L)

    rx = cell_avg(d, float(delay_chips)) * np.cos(2 * np.pi * f0 * tmid + phase)
    if include_signal:
        rx = rx + cell_avg(c, 0.0) * np.cos(2 * np.pi * f0 * tmid)
    mixed = rx * 2.0 * np.cos(2 * np.pi * f0 * tmid)
    spec = np.fft.rfft(mixed)
    freqs = np.fft.rfftfreq(ns, dt)
    spec[freqs > f0] = 0.0
    lp = np.fft.irfft(spec, n=ns)
    idx = np.floor(tmid).astype(int)
    inwin = (idx >= 0) & (idx < L)
    si = np.zeros(ns)
    si[inwin] = c[idx[inwin]] / math.sqrt(L)
    return float(np.sum(lp * si) * dt)


# ------------------------------------------------------------------------------------------
# Zakai bandwidth (Theorem 3.3), numerically
# ------------------------------------------------------------------------------------------


def zakai_W_numeric(code, samples_per_chip=2000):
    """W tau_c = 1 / (2 int R^2(t) dt), R the aperiodic autocorrelation (rectangular unit-energy chips).

    The code waveform is sampled at ``samples_per_chip`` (even) cells per chip; the discrete
    correlation (via FFT) then equals the continuous R at lags j/samples_per_chip exactly, and
    R^2 (piecewise quadratic between chip lags) is integrated by composite Simpson over
    [-L, L], which is exact up to rounding.
    """
    from scipy.integrate import simpson
    from scipy.signal import fftconvolve

    s = int(samples_per_chip)
    if s % 2:
        raise ValueError("samples_per_chip must be even")
    c = np.asarray(_code(code), dtype=float)
    L = len(c)
    wave = np.repeat(c, s) / math.sqrt(L)
    R = fftconvolve(wave, wave[::-1]) / s  # lags -(Ls-1)..(Ls-1) in units 1/s
    R = np.concatenate([[0.0], R, [0.0]])  # R(-L) = R(L) = 0
    lags = np.arange(-L * s, L * s + 1) / s
    integral = simpson(R * R, x=lags)
    return float(1.0 / (2.0 * integral))


# ------------------------------------------------------------------------------------------
# self-check against spec Sec. 13
# ------------------------------------------------------------------------------------------

MSEQ31 = "++++-+-+---+--+++-----++--+-++-"
BARKER13 = "+++++--++-+-+"


def code_from_string(s):
    return np.array([1 if ch == "+" else -1 for ch in s], dtype=int)


def _rel(a, b):
    return abs(a - b) / abs(b) if b else abs(a)


def _row(label, ours, ref, tol, kind="spec"):
    ok = _rel(ours, ref) <= tol
    print(
        f"  {label:<36s} ours={ours:<16.9g} {kind}={ref:<14.7g} rel={_rel(ours, ref):.1e} {'OK' if ok else 'FAIL'}"
    )
    return ok


def _selfcheck():
    t_start = time.time()
    N, ta = 100000, mpf("2e-5")
    allok = True
    print("== mgf: quadrature vs closed form (b = 1/192, rho = 7.3)")
    for dens in DENSITIES:
        with mp.workdps(DPS):
            closed = _f(_phi_closed(dens, mpf(1) / 192, mpf("7.3")))
        allok &= _row(dens, mgf(dens, mpf(1) / 192, "7.3"), closed, 1e-12, "closed")

    print("== T1")
    with mp.workdps(DPS):
        allok &= _row("Mq", _f((N - 1) * 2 * ta), 3.99996, 1e-12)
        for ell, P in ((8, 0.020833125), (4, 0.0833325), (12, 0.0092591667)):
            allok &= _row(f"P(ell={ell})", _f((N - 1) * 2 * ta / (3 * ell * ell)), P, 1e-7)

    print("== T2: ell = 8, theta = 0.5, N = 1e5, tau/alpha = 2e-5")
    t2 = {
        "two-point": (18.248904, 5.124272, 25.141066, 5.950548e-3, 3.654699e-11, 1.158783e-10, 9.837969e-4),
        "uniform": (16.241929, 4.747922, 22.284389, 8.669689e-3, 1.323891e-11, 4.390116e-11, 8.236968e-4),
        "triangular": (15.168993, 4.533229, 20.770026, 1.074593e-2, 6.601871e-12, 2.253817e-11, 1.007757e-3),
        "gaussian": (14.198236, 4.337526, 19.368331, 1.306882e-2, 1.574048e-12, 5.649889e-12, 1.201290e-3),
    }
    b8 = mpf(1) / 192
    for dens, (rs, ef, r1, ub, lbr, lbg, ex) in t2.items():
        print(f" {dens}")
        ch = chernoff(dens, b8, N, ta, 0.5)
        lr = lower_bound(dens, b8, N, ta, 0.5, "report")
        lg = lower_bound(dens, b8, N, ta, 0.5, "gallager")
        e = exact(dens, b8, N, ta, 0.5)
        cm = chernoff_miss(dens, b8, N, ta, 0.5)
        lm = lower_bound_miss(dens, b8, N, ta, 0.5, "report")
        allok &= _row("rho*", ch["rho_star"], rs, 1e-6)
        allok &= _row("E_f", ch["E_f"], ef, 1e-6)
        allok &= _row("rho1", lr["rho1"], r1, 1e-6)
        allok &= _row("pf UB", ch["pf_up"], ub, 1e-5)
        allok &= _row("pf LB report", lr["pf_lo"], lbr, 1e-5)
        allok &= _row("pf LB gallager", lg["pf_lo"], lbg, 1e-5)
        allok &= _row("pf exact", e["pf"], ex, 1e-5)
        allok &= _row("pm UB (= pf UB at 0.5)", cm["pm_up"], ub, 1e-5)
        allok &= _row("pm LB report (= pf LB)", lm["pm_lo"], lbr, 1e-5)
        allok &= _row("pm exact (= pf exact)", e["pm"], ex, 1e-5)

    print("== symmetry: chernoff_miss(theta) vs chernoff(1 - theta); lower_bound_miss vs lower_bound")
    for dens in DENSITIES:
        cm = chernoff_miss(dens, b8, N, ta, 0.3)
        cf = chernoff(dens, b8, N, ta, 0.7)
        allok &= _row(f"{dens} E_d(0.3) vs E_f(0.7)", cm["E_d"], cf["E_f"], 1e-20, "E_f")
        lm = lower_bound_miss(dens, b8, N, ta, 0.3, "gallager")
        lf = lower_bound(dens, b8, N, ta, 0.7, "gallager")
        allok &= _row(f"{dens} gamma1(0.3) vs rho1(0.7)", lm["gamma1"], lf["rho1"], 1e-20, "rho1")

    print("== laplace exact: quadrature vs finite series, P(G1 - G2 >= y) per K")
    with mp.workdps(DPS):
        y = mpf("0.5") / mpmath.sqrt(b8 / 2)
        for K in (1, 2, 5, 20, 60):
            allok &= _row(
                f"K={K}", _f(_laplace_tail_quad(K, y)), _f(_laplace_tail_series(K, y)), 1e-25, "series"
            )

    print("== T3")
    b4 = mpf(1) / 48
    b12 = mpf(1) / 432
    ch = chernoff("uniform", b4, N, ta, 0.3)
    lr = lower_bound("uniform", b4, N, ta, 0.3)
    e = exact("uniform", b4, N, ta, 0.3)
    cm = chernoff_miss("uniform", b4, N, ta, 0.3)
    print(" ell=4, theta=0.3, uniform")
    allok &= _row("pf UB", ch["pf_up"], 5.940872e-1, 1e-5)
    allok &= _row("pf LB", lr["pf_lo"], 1.404374e-5, 1e-5)
    allok &= _row("pf exact", e["pf"], 1.409319e-1, 1e-5)
    allok &= _row("pm UB", cm["pm_up"], 7.870605e-2, 1e-5)
    allok &= _row("pm exact", e["pm"], 1.008608e-2, 1e-5)
    print(" ell=4, theta=0.5, two-point")
    allok &= _row("pf UB", chernoff("two-point", b4, N, ta, 0.5)["pf_up"], 2.411600e-1, 1e-5)
    allok &= _row("pf LB", lower_bound("two-point", b4, N, ta, 0.5)["pf_lo"], 1.100145e-6, 1e-5)
    allok &= _row("pf exact", exact("two-point", b4, N, ta, 0.5)["pf"], 3.899660e-2, 1e-5)
    print(" ell=12, theta=0.5, uniform")
    allok &= _row("pf UB", chernoff("uniform", b12, N, ta, 0.5)["pf_up"], 8.959011e-5, 1e-5)
    allok &= _row("pf LB", lower_bound("uniform", b12, N, ta, 0.5)["pf_lo"], 3.557724e-16, 1e-5)
    allok &= _row("pf exact", exact("uniform", b12, N, ta, 0.5)["pf"], 5.975173e-6, 1e-5)
    print(" ell=12, theta=0.7, gaussian")
    allok &= _row("pf UB", chernoff("gaussian", b12, N, ta, 0.7)["pf_up"], 1.107309e-6, 1e-5)
    allok &= _row("pf exact", exact("gaussian", b12, N, ta, 0.7)["pf"], 5.453566e-8, 1e-5)

    print("== T4 (ROC_g)")
    g = roc_g(b8, N, ta, 0.5)
    allok &= _row("ell=8 th=0.5 pf", g["pf"], 2.659856e-4, 1e-5)
    allok &= _row("ell=4 th=0.5 pf", roc_g(b4, N, ta, 0.5)["pf"], 4.163149e-2, 1e-5)
    g = roc_g(b8, N, ta, 0.3)
    allok &= _row("ell=8 th=0.3 pf", g["pf"], 1.883298e-2, 1e-5)
    allok &= _row("ell=8 th=0.3 pm", g["pm"], 6.180344e-7, 1e-5)

    print("== T9 (Exp); ours = brute-force exact form, also (3.8.16) approximation")
    for G, NN, tt, spec in (
        (4, 100000, "1e-5", 3.302437),
        (12.5, 200000, "1e-5", 9.702096),
        (12.5, 100000, "1e-5", 8.620122),
        (6.25, 200000, "1e-5", 5.313610),
    ):
        ex_ = exp_two_point_numeric(G, NN, tt)
        ap = exp_approx_3816(G, NN, tt)
        ok = abs(ex_ - spec) <= 1e-4
        print(
            f"  Exp(G={G}, N={NN}, t/a={tt}): exact={ex_:.7f} approx(3.8.16)={ap:.7f} spec={spec} "
            f"|exact-spec|={abs(ex_ - spec):.1e} {'OK' if ok else 'FAIL'}"
        )
        allok &= ok
    print("== T9 grids (Fig. 3.9 G=4; Fig. 3.10 t/a=1e-5): rounded tables = approximation (3.8.16), +-1e-3")
    fig39 = {
        "1e-6": (0.200, 0.488, 1.095, 2.137, 3.302, 3.880, 3.987),
        "1e-5": (0.488, 1.095, 2.137, 3.302, 3.880, 3.987, 3.999),
        "1e-4": (1.096, 2.138, 3.303, 3.880, 3.987, 3.999, 4.000),
        "1e-3": (2.143, 3.305, 3.881, 3.987, 3.999, 4.000, 4.000),
    }
    fig310 = {
        10**4: (0.718, 1.254, 2.137, 3.565, 4.908, 5.840, 6.822),
        10**5: (0.934, 1.778, 3.302, 5.972, 8.620, 10.512, 12.542),
        2 * 10**5: (0.963, 1.869, 3.556, 6.605, 9.702, 11.943, 14.369),
        10**6: (0.992, 1.969, 3.880, 7.562, 11.520, 14.488, 17.779),
        10**7: (0.999, 1.997, 3.987, 7.948, 12.374, 15.796, 19.685),
    }
    cases = []
    for tt, vals in fig39.items():
        cases += [("Fig3.9", 4, 10 ** (k + 2), tt, v) for k, v in enumerate(vals)]
    for NN, vals in fig310.items():
        cases += [
            ("Fig3.10", G, NN, "1e-5", v) for G, v in zip((1, 2, 4, 8, 12.5, 16, 20), vals, strict=True)
        ]
    worst_ap = worst_ex = (0.0, "")
    for fig, G, NN, tt, v in cases:
        ex_ = exp_two_point_numeric(G, NN, tt)
        ap = exp_approx_3816(G, NN, tt)
        tag = f"{fig} G={G} N={NN:.0e} t/a={tt}: exact={ex_:.5f} approx={ap:.5f} table={v}"
        if abs(ap - v) > worst_ap[0]:
            worst_ap = (abs(ap - v), tag)
        if abs(ex_ - v) > worst_ex[0]:
            worst_ex = (abs(ex_ - v), tag)
        if abs(ap - v) > 1e-3:
            print(f"  {tag} FAIL")
            allok = False
    print(f"  {len(cases)} table cells; worst |approx - table| = {worst_ap[0]:.1e} ({worst_ap[1]})")
    print(f"  info: worst |exact - table| = {worst_ex[0]:.1e} ({worst_ex[1]})")

    print("== T7 (closed form vs numerical sup; via exp_two_point_numeric with G = theta^2/(2p))")
    for NN, tt, p, spec in ((100000, "1e-5", 0.02, 4.851041), (50, "1e-2", 0.05, 2.020122)):
        G = 0.25 / (2 * p)
        allok &= _row(f"Expf(N={NN}, t/a={tt}, p={p})", exp_two_point_numeric(G, NN, tt), spec, 3e-7)

    print("== T11 / Sec. 8 (PSK)")
    mseq = code_from_string(MSEQ31)
    b_psk = psk_b_random(mseq)
    allok &= _row("b (m-seq 31, random codes)", float(b_psk), 5.376344e-3, 1e-6)
    print(f"  b exact = {b_psk} (1/186 = {Fraction(1, 186)})")
    allok &= _row("ell = 1/sqrt(3b)", 1 / math.sqrt(3 * float(b_psk)), 7.8740, 1e-4)
    allok &= _row("P = M q b", (N - 1) * 4e-5 * float(b_psk), 0.02150516, 1e-6)
    rng = np.random.default_rng(1)
    fam = rng.choice([-1, 1], size=(4000, 31))
    print(f"  psk_b_family(m-seq, 4000 random rows) = {float(psk_b_family(mseq, fam)):.6e} (~ b above)")

    print("== Zakai W (Sec. 8)")
    allok &= _row("W tau_c Barker-13", zakai_W_numeric(code_from_string(BARKER13)), 0.70028, 1e-5)
    allok &= _row("W tau_c m-seq 31", zakai_W_numeric(mseq), 0.54151, 1e-5)

    print("== Level C (RF MF output vs chip formula)")
    rng = np.random.default_rng(7)
    intf = rng.choice([-1, 1], size=13)
    bk = code_from_string(BARKER13)
    for delay, ph in ((3.37, 0.9), (-7.81, 2.2), (0.5, 0.0)):
        x1 = chip_formula(bk, intf, delay)
        x2 = chip_formula_kf(bk, intf, delay)
        rf = rf_mf_output(bk, intf, delay, ph)
        err = abs(rf - math.cos(ph) * x1)
        ok = err < 1e-3 and abs(x1 - x2) < 1e-12
        print(
            f"  delay={delay:+.2f} phase={ph:.1f}: rf={rf:+.8f} cos*X={math.cos(ph) * x1:+.8f} "
            f"X(overlap)={x1:+.8f} X(k,f)={x2:+.8f} |rf-cos*X|={err:.1e} {'OK' if ok else 'FAIL'}"
        )
        allok &= ok
    print(f"\nALL OK: {bool(allok)}   ({time.time() - t_start:.1f} s)")
    return allok


if __name__ == "__main__":
    _selfcheck()
