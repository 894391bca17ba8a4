"""Preferred pairs and Gold code families — seed 000 §II.A (ref [11]); Gold (1967), Sarwate & Pursley (1980).

For degree n with n mod 4 ≠ 0, a *preferred pair* of m-sequences (u, v) has a three-valued periodic
cross-correlation {−t(n), −1, t(n) − 2}, t(n) = 1 + 2^⌊(n+2)/2⌋ (n = 5: {−9, −1, 7}). Its Gold
family has 2ⁿ + 1 members — u, v and u ⊕ Tᵏv for k = 0 … 2ⁿ − 2 — whose off-peak auto- and
cross-correlations all lie in the same three values.

Indexing follows MATLAB ``comm.GoldSequence``: ``Index`` −2 → u, −1 → v, k ≥ 0 → u ⊕ (v advanced
by k). A member with start offset a is ``code[t] = u[(t+a) mod N] ⊕ v[(t+a+k) mod N]``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motionsig_cli.signals.correlation import gold_bound, periodic_correlation, to_bipolar
from motionsig_cli.signals.gf2 import degree, primitive_polynomials, require_primitive, to_octal
from motionsig_cli.signals.lfsr import m_sequence


def gold_values(n: int) -> tuple[int, int, int]:
    """The three Gold correlation values (−t(n), −1, t(n) − 2)."""
    t = gold_bound(n)
    return (-t, -1, t - 2)


def require_gold_degree(n: int) -> int:
    """Raise ValueError unless preferred pairs exist for degree n (n ≥ 3, n mod 4 ≠ 0)."""
    if n < 3:
        raise ValueError(f"degree {n} < 3: Gold codes need degree >= 3")
    if n % 4 == 0:
        raise ValueError(f"degree {n} is a multiple of 4: no preferred pairs of m-sequences exist")
    return n


@dataclass(frozen=True)
class PairCheck:
    """Result of a preferred-pair test."""

    poly1: int
    poly2: int
    degree: int
    values: tuple[int, ...]
    expected: tuple[int, int, int] | None
    preferred: bool


def check_pair(poly1: int, poly2: int) -> PairCheck:
    """Test whether (poly1, poly2) is a preferred pair: cross-correlation values ⊆ Gold's three.

    The value set of a periodic cross-correlation over all lags does not depend on the initial
    states, so the default states are used.
    """
    require_primitive(poly1)
    require_primitive(poly2)
    n1, n2 = degree(poly1), degree(poly2)
    if n1 != n2:
        raise ValueError(f"polynomials have different degrees ({n1} and {n2})")
    u, v = to_bipolar(m_sequence(poly1)), to_bipolar(m_sequence(poly2))
    r = periodic_correlation(np.stack([u, v]))[0, 1]
    values = tuple(int(x) for x in np.unique(r))
    expected = gold_values(n1) if n1 % 4 and n1 >= 3 else None
    preferred = expected is not None and poly1 != poly2 and set(values) == set(expected)
    return PairCheck(poly1, poly2, n1, values, expected, preferred)


def require_preferred(poly1: int, poly2: int) -> PairCheck:
    """check_pair, raising ValueError (with the values found) when the pair is not preferred."""
    n = degree(poly1)
    require_gold_degree(n)
    chk = check_pair(poly1, poly2)
    if not chk.preferred:
        raise ValueError(
            f"({to_octal(poly1)}, {to_octal(poly2)}) is not a preferred pair: cross-correlation takes "
            f"{list(chk.values)}, not {list(gold_values(n))}"
        )
    return chk


def preferred_pairs(n: int) -> list[tuple[int, int]]:
    """All unordered preferred pairs (poly1 < poly2) of degree n, by exhaustive FFT test.

    One FFT per primitive polynomial and one inverse FFT per pair (degree 11: 176 polynomials,
    15 400 pairs, well under a second).
    """
    require_gold_degree(n)
    polys = primitive_polynomials(n)
    seqs = np.stack([to_bipolar(m_sequence(p)) for p in polys]).astype(np.float64)
    spec = np.fft.rfft(seqs, axis=1)
    period = seqs.shape[1]
    allowed = np.array(gold_values(n), dtype=np.float64)
    pairs = []
    for i in range(len(polys) - 1):
        r = np.fft.irfft(np.conj(spec[i])[None, :] * spec[i + 1 :], n=period, axis=1)
        r = np.rint(r)
        ok = np.isin(r, allowed).all(axis=1)
        pairs.extend((polys[i], polys[i + 1 + j]) for j in np.flatnonzero(ok))
    return pairs


def gold_code(
    poly1: int,
    poly2: int,
    index: int,
    shift: int = 0,
    state1: str | tuple[int, ...] | None = None,
    state2: str | tuple[int, ...] | None = None,
    *,
    verify: bool = True,
) -> np.ndarray:
    """One member of the Gold family of a preferred pair (MATLAB ``comm.GoldSequence`` conventions).

    Args:
        poly1, poly2: A preferred pair.
        index: −2 → u, −1 → v, 0 … 2ⁿ − 2 → u ⊕ Tᵏv.
        shift: Start offset a of the output (applied to the whole code).
        state1, state2: Initial states of the two registers (MATLAB order, default ``0…01``).
        verify: Reject a pair that is not preferred (default). MATLAB's ``comm.GoldSequence``
            does not check; ``verify=False`` reproduces it for any two primitive polynomials of
            equal degree, but the result is then not a Gold code.

    Returns:
        ``uint8`` bits of length 2ⁿ − 1.
    """
    if verify:
        require_preferred(poly1, poly2)
    elif degree(poly1) != degree(poly2):
        raise ValueError(f"polynomials have different degrees ({degree(poly1)} and {degree(poly2)})")
    u = m_sequence(poly1, state1)
    v = m_sequence(poly2, state2)
    period = u.size
    if not -2 <= index <= period - 1:
        raise ValueError(f"index must be in -2..{period - 1} for degree {degree(poly1)}, got {index}")
    code = u if index == -2 else v if index == -1 else u ^ np.roll(v, -index)
    return np.roll(code, -shift)


def gold_family(
    poly1: int,
    poly2: int,
    state1: str | tuple[int, ...] | None = None,
    state2: str | tuple[int, ...] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """All 2ⁿ + 1 members: returns ``(indices, codes)`` with indices −2, −1, 0 … 2ⁿ − 2."""
    require_preferred(poly1, poly2)
    u = m_sequence(poly1, state1)
    v = m_sequence(poly2, state2)
    period = u.size
    k = np.arange(period)
    shifted_v = v[(np.arange(period)[None, :] + k[:, None]) % period]  # row k: v advanced by k
    codes = np.vstack([u, v, u[None, :] ^ shifted_v])
    return np.arange(-2, period), codes
