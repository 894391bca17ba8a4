"""Brent's root finder in plain Python, step for step the one SciPy ships.

:func:`scipy.optimize.brentq` is the Brent–Dekker method (R. P. Brent, *Algorithms for Minimization
without Derivatives*, 1973, ch. 4): inverse quadratic interpolation or a secant step while they shrink
the bracket fast enough, bisection otherwise. Importing :mod:`scipy.optimize` costs about half a
second, more than a whole ``motionsig jam-bound table``; this module repeats SciPy's iteration (its
``brentq.c``, BSD-3-licensed) operation for operation in IEEE double arithmetic, so it returns the
same bits (a test compares the two on many brackets and functions).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from motionsig_cli.config import ConfigError

EPS = 2.220446049250313e-16  # numpy.finfo(float).eps
RTOL = 4 * EPS  # SciPy's smallest allowed relative tolerance


def _div(a: float, b: float) -> float:
    """a / b with IEEE semantics, as in C: ±inf for x/0, nan for 0/0 (Python raises instead)."""
    try:
        return a / b
    except ZeroDivisionError:
        if a == 0 or math.isnan(a):
            return math.nan
        return math.copysign(math.inf, a) * math.copysign(1.0, b)


class RootError(ArithmeticError):
    """The bracket holds no sign change, or the iteration did not converge."""


def brentq(
    f: Callable[[float], float],
    a: float,
    b: float,
    *,
    xtol: float = 2e-12,
    rtol: float = RTOL,
    maxiter: int = 100,
) -> float:
    """A root of ``f`` in [a, b], where f(a) and f(b) differ in sign (SciPy's ``brentq``, same arguments
    and defaults, same result).

    The iteration stops when the bracket's half-width is below (xtol + rtol·|x|)/2.
    """
    if not xtol > 0:
        raise ConfigError("xtol", xtol, "is not > 0")
    if not rtol >= RTOL:
        raise ConfigError("rtol", rtol, f"is below 4 eps = {RTOL:g}")
    if maxiter < 0:
        raise ConfigError("maxiter", maxiter, "is not >= 0")
    xtol, rtol = float(xtol), float(rtol)  # Python floats: a NumPy scalar would warn where C is silent
    xpre, xcur = float(a), float(b)
    xblk = fblk = spre = scur = 0.0
    fpre = float(f(xpre))
    fcur = float(f(xcur))
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if math.copysign(1.0, fpre) == math.copysign(1.0, fcur):
        raise RootError(f"f(a) and f(b) must have different signs (f({a:g}) = {fpre:g}, f({b:g}) = {fcur:g})")
    for _ in range(maxiter):
        if fpre != 0 and fcur != 0 and math.copysign(1.0, fpre) != math.copysign(1.0, fcur):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):  # keep xcur the best estimate
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # secant (linear interpolation)
                stry = _div(-fcur * (xcur - xpre), fcur - fpre)
            else:  # inverse quadratic interpolation
                dpre = _div(fpre - fcur, xpre - xcur)
                dblk = _div(fblk - fcur, xblk - xcur)
                stry = _div(-fcur * (fblk * dblk - fpre * dpre), dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):  # a good short step
                spre, scur = scur, stry
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = float(f(xcur))
    raise RootError(f"no convergence in {maxiter} iterations (last x = {xcur:g})")
