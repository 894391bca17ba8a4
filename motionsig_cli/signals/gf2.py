"""Polynomials over GF(2): parsing, primitivity, reciprocals.

A polynomial is a Python ``int`` whose bit *i* is the coefficient of xⁱ, so octal ``45`` =
0b100101 = x⁵ + x² + 1 (the usual octal notation of Peterson's tables and of MATLAB's
``comm.GoldSequence`` documentation).

A degree-n polynomial p with p(0) = 1 is *primitive* when x has multiplicative order exactly
2ⁿ − 1 modulo p; then p is irreducible and its LFSR has maximal period (an m-sequence).
"""

from __future__ import annotations

import re
from functools import cache

from motionsig_cli.config import ConfigError, integer

MAX_DEGREE = 32

_TERM = re.compile(r"^(?:1|x|x\^(\d+)|x\*\*(\d+))$")


def degree(poly: int) -> int:
    """Degree of ``poly`` (−1 for the zero polynomial)."""
    return poly.bit_length() - 1


def parse_polynomial(text: str | int, field: str = "poly") -> int:
    """Parse a polynomial written in octal (``"45"``, ``"0o45"``) or exponent form.

    Exponent form is a ``+``-separated sum of ``1``, ``x``, ``x^k`` or ``x**k`` terms, in any
    order: ``"x^5+x^2+1"``, ``"1 + x^3 + x^10"``.

    Raises:
        ConfigError: (naming ``field``) malformed text, a repeated term, or a polynomial of degree < 1
            or > :data:`MAX_DEGREE`.
    """
    if isinstance(text, int):
        poly = text
    else:
        s = text.strip().replace(" ", "").lower()
        if not s:
            raise ConfigError(field, text, "is empty: write octal like 45 or exponents like x^5+x^2+1")
        if re.fullmatch(r"(0o)?[0-7]+", s):
            poly = int(s.removeprefix("0o"), 8)
        else:
            poly = 0
            for term in s.split("+"):
                m = _TERM.match(term)
                if m is None:
                    raise ConfigError(
                        field,
                        text,
                        f"is malformed: term {term!r} is not 1, x or x^k "
                        "(write octal like 45 or exponents like x^5+x^2+1)",
                    )
                k = 0 if term == "1" else 1 if term == "x" else int(m.group(1) or m.group(2))
                if poly >> k & 1:
                    raise ConfigError(field, text, f"is malformed: term x^{k} appears twice")
                poly |= 1 << k
    if poly < 0 or degree(poly) < 1:
        raise ConfigError(field, text, "has degree < 1")
    if degree(poly) > MAX_DEGREE:
        raise ConfigError(field, text, f"has degree {degree(poly)} > {MAX_DEGREE}")
    return poly


def to_octal(poly: int) -> str:
    """Octal notation (``0o45`` → ``"45"``)."""
    return format(poly, "o")


def to_exponents(poly: int) -> str:
    """Exponent notation, highest power first: ``"x^5+x^2+1"``."""
    terms = []
    for k in range(degree(poly), -1, -1):
        if poly >> k & 1:
            terms.append("1" if k == 0 else "x" if k == 1 else f"x^{k}")
    return "+".join(terms)


def reciprocal(poly: int) -> int:
    """The reciprocal xⁿ p(1/x): bit order reversed (generates the time-reversed m-sequence)."""
    n = degree(poly)
    return int(format(poly, f"0{n + 1}b")[::-1], 2)


def mulmod(a: int, b: int, mod: int) -> int:
    """a·b mod ``mod`` over GF(2) (shift-and-add)."""
    n = degree(mod)
    result = 0
    while b:
        if b & 1:
            result ^= a
        b >>= 1
        a <<= 1
        if a >> n & 1:
            a ^= mod
    return result


def powmod_x(exponent: int, mod: int) -> int:
    """x^exponent mod ``mod`` over GF(2) (square and multiply)."""
    result, base = 1, 2 % mod if degree(mod) > 1 else 2 ^ mod
    while exponent:
        if exponent & 1:
            result = mulmod(result, base, mod)
        base = mulmod(base, base, mod)
        exponent >>= 1
    return result


@cache
def _prime_factors(m: int) -> tuple[int, ...]:
    factors, d = [], 2
    while d * d <= m:
        if m % d == 0:
            factors.append(d)
            while m % d == 0:
                m //= d
        d += 1
    if m > 1:
        factors.append(m)
    return tuple(factors)


def is_primitive(poly: int) -> bool:
    """True when ``poly`` is primitive: the order of x modulo ``poly`` is 2ⁿ − 1."""
    n = degree(poly)
    if n < 1 or not poly & 1:
        return False
    if n == 1:
        return poly == 0b11
    period = (1 << n) - 1
    if powmod_x(period, poly) != 1:
        return False
    return all(powmod_x(period // r, poly) != 1 for r in _prime_factors(period))


def not_primitive(poly: int) -> str:
    """Why ``poly`` cannot be used (the reason of a :class:`ConfigError`; ``poly`` is not primitive)."""
    return (
        f"is not primitive ({to_exponents(poly)} = octal {to_octal(poly)}), so its LFSR does not produce "
        "an m-sequence"
    )


def require_primitive(poly: int, field: str = "poly") -> int:
    """Return ``poly`` if primitive, else raise :class:`ConfigError` naming ``field`` and the polynomial."""
    if not is_primitive(poly):
        raise ConfigError(field, to_octal(poly), not_primitive(poly))
    return poly


@cache
def primitive_polynomials(n: int) -> tuple[int, ...]:
    """All primitive polynomials of degree ``n``, ascending (there are φ(2ⁿ−1)/n of them)."""
    integer("n", n, 1, 20)
    top = 1 << n
    # p(0) = 1 and an odd number of terms (p(1) = 1) are necessary for irreducibility (n > 1).
    cands = range(top | 1, top << 1, 2)
    return tuple(p for p in cands if (n == 1 or p.bit_count() % 2 == 1) and is_primitive(p))
