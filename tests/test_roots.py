"""The plain-Python Brent root finder against SciPy's brentq: the same bits, the same errors."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq as scipy_brentq

from motionsig_cli.config import ConfigError
from motionsig_cli.roots import RootError, brentq

FUNCTIONS = {
    "cubic": (lambda x: x**3 - 2 * x - 5, 2.0, 3.0),
    "cos-x": (lambda x: math.cos(x) - x, 0.0, 1.0),
    "exp": (lambda x: math.exp(x) - 10.0, -5.0, 5.0),
    "flat": (lambda x: (x - 1.0) ** 5, 0.0, 3.0),
    "log1p": (lambda x: math.log1p(x) - 0.3, -0.9, 10.0),
    "step-like": (lambda x: math.tanh(50 * (x - 0.123)), -1.0, 1.0),
    "expm1 tail": (lambda w: -math.expm1(w) - 1e-9, -700.0, -1e-15),
}


@pytest.mark.parametrize("name", list(FUNCTIONS))
@pytest.mark.parametrize("tols", [{}, {"xtol": 1e-15}, {"xtol": 1e-13, "rtol": 4 * np.finfo(float).eps}])
def test_same_bits_as_scipy(name, tols):
    f, a, b = FUNCTIONS[name]
    for lo, hi in ((a, b), (b, a)):
        try:
            want = scipy_brentq(f, lo, hi, **tols)
        except RuntimeError:  # no convergence in 100 iterations: ours must say so too
            with pytest.raises(RootError):
                brentq(f, lo, hi, **tols)
            continue
        assert brentq(f, lo, hi, **tols) == want


def test_same_bits_as_scipy_on_random_polynomials():
    rng = np.random.default_rng(7)
    for _ in range(300):
        roots = np.sort(rng.uniform(-3, 3, 3))
        c = float(rng.uniform(0.1, 10))

        def f(x: float, r=roots, c=c) -> float:
            return c * (x - r[0]) * (x - r[1]) * (x - r[2])

        a = float(rng.uniform(roots[0], roots[1]))
        b = float(rng.uniform(roots[1], roots[2]))
        if math.copysign(1, f(a)) == math.copysign(1, f(b)):
            continue
        assert brentq(f, a, b, xtol=1e-14) == scipy_brentq(f, a, b, xtol=1e-14)


def test_maxiter_and_the_number_of_calls_agree():
    calls = {"ours": 0, "scipy": 0}

    def counted(key):
        def f(x):
            calls[key] += 1
            return math.cos(x) - x

        return f

    brentq(counted("ours"), 0.0, 1.0, xtol=1e-15)
    scipy_brentq(counted("scipy"), 0.0, 1.0, xtol=1e-15)
    assert calls["ours"] == calls["scipy"]
    with pytest.raises(RootError):
        brentq(lambda x: math.cos(x) - x, 0.0, 1.0, xtol=1e-15, maxiter=2)
    with pytest.raises(RuntimeError):
        scipy_brentq(lambda x: math.cos(x) - x, 0.0, 1.0, xtol=1e-15, maxiter=2)


def test_endpoint_roots_and_bad_brackets():
    assert brentq(lambda x: x, 0.0, 1.0) == 0.0
    assert brentq(lambda x: x - 1.0, 0.0, 1.0) == 1.0
    with pytest.raises(RootError, match="different signs"):
        brentq(lambda x: x * x + 1, -1.0, 1.0)
    with pytest.raises(ConfigError, match="xtol"):
        brentq(lambda x: x, -1.0, 1.0, xtol=0.0)
    with pytest.raises(ConfigError, match="rtol"):
        brentq(lambda x: x, -1.0, 1.0, rtol=1e-17)


def test_division_by_zero_follows_ieee_like_scipys_c_code():
    from motionsig_cli.roots import _div

    assert _div(1.0, 0.0) == math.inf and _div(-1.0, 0.0) == -math.inf and _div(1.0, -0.0) == -math.inf
    assert math.isnan(_div(0.0, 0.0))

    # a function flat on part of the bracket makes the interpolation divide 0 by 0 (SciPy: nan, then bisect)
    def f(x: float) -> float:
        return max(x, 0.0) - 0.25

    tol = {"xtol": 1e-15, "rtol": 4 * np.finfo(float).eps}
    assert brentq(f, -3.0, 1.0, **tol) == scipy_brentq(f, -3.0, 1.0, **tol)
