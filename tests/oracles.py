"""Second implementations used only as test oracles (independent of the package's algorithms)."""

from __future__ import annotations

import numpy as np


def berlekamp_massey(bits: np.ndarray) -> tuple[int, int]:
    """Linear complexity L and connection polynomial C(x) (bit mask) of a GF(2) sequence.

    Textbook Berlekamp–Massey (Massey 1969). C(x) = 1 + c_1 x + … + c_L x^L satisfies
    s_t = ⊕ c_i s_{t−i}; its reciprocal is the characteristic (recurrence) polynomial.
    """
    s = [int(b) for b in bits]
    c, b = 1, 1
    length, m = 0, 1
    for n in range(len(s)):
        d = s[n]
        for i in range(1, length + 1):
            d ^= (c >> i & 1) & s[n - i]
        if d == 0:
            m += 1
        elif 2 * length <= n:
            t = c
            c ^= b << m
            length, b, m = n + 1 - length, t, 1
        else:
            c ^= b << m
            m += 1
    return length, c


def naive_periodic_correlation(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """R[l] = Σ_t x_t y_{(t+l) mod N} by the definition (O(N²))."""
    n = len(x)
    return np.array([sum(int(x[t]) * int(y[(t + lag) % n]) for t in range(n)) for lag in range(n)])


def euler_phi(m: int) -> int:
    """Euler's totient by trial division."""
    result, p, k = m, 2, m
    while p * p <= k:
        if k % p == 0:
            while k % p == 0:
                k //= p
            result -= result // p
        p += 1
    if k > 1:
        result -= result // k
    return result
