"""Preferred pairs and Gold code families — §II.A (ref [11]) of the mode-signature paper (47th IEEE CDC, Cancún, 2008); Gold (1967), Sarwate & Pursley (1980).

For degree n with n mod 4 ≠ 0, a *preferred pair* of m-sequences (u, v) has a three-valued periodic
cross-correlation {−t(n), −1, t(n) − 2}, t(n) = 1 + 2^⌊(n+2)/2⌋ (n = 5: {−9, −1, 7}). Its Gold
family has 2ⁿ + 1 members — u, v and u ⊕ Tᵏv for k = 0 … 2ⁿ − 2 — whose off-peak auto- and
cross-correlations all lie in the same three values.

Indexing follows MATLAB ``comm.GoldSequence``: ``Index`` −2 → u, −1 → v, k ≥ 0 → u ⊕ (v advanced
by k). A member with start offset a is ``code[t] = u[(t+a) mod N] ⊕ v[(t+a+k) mod N]``.

:class:`GoldConfig` is the checked entry point (polynomials as text or bit masks, the preferred-pair test,
initial states); the functions below take bit masks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motionsig_cli.config import ConfigError, integer
from motionsig_cli.signals.correlation import gold_bound, periodic_correlation, to_bipolar
from motionsig_cli.signals.gf2 import (
    degree,
    parse_polynomial,
    primitive_polynomials,
    require_primitive,
    to_octal,
)
from motionsig_cli.signals.lfsr import default_state, m_sequence, parse_state, primitive_polynomial

MAX_PAIR_SEARCH_DEGREE = 13  # the exhaustive preferred-pair search (630 polynomials, ~200 000 pairs)


def gold_values(n: int) -> tuple[int, int, int]:
    """The three Gold correlation values (−t(n), −1, t(n) − 2)."""
    t = gold_bound(n)
    return (-t, -1, t - 2)


def require_gold_degree(n: int, field: str = "degree") -> int:
    """Raise :class:`ConfigError` (naming ``field``) unless preferred pairs exist for degree n
    (n ≥ 3, n mod 4 ≠ 0)."""
    if n < 3:
        raise ConfigError(field, n, "is < 3: Gold codes need degree >= 3")
    if n % 4 == 0:
        raise ConfigError(field, n, "is a multiple of 4: no preferred pairs of m-sequences exist")
    return n


def require_search_degree(n: int, field: str = "degree") -> int:
    """:func:`require_gold_degree`, and n ≤ :data:`MAX_PAIR_SEARCH_DEGREE` (the exhaustive pair search grows
    as the square of the number of primitive polynomials)."""
    require_gold_degree(n, field)
    if n > MAX_PAIR_SEARCH_DEGREE:
        raise ConfigError(
            field, n, f"is > {MAX_PAIR_SEARCH_DEGREE}: the exhaustive pair search is limited to n <= 13"
        )
    return n


def _same_degree(poly1: int, poly2: int, field: str = "poly2") -> int:
    n1, n2 = degree(poly1), degree(poly2)
    if n1 != n2:
        raise ConfigError(field, to_octal(poly2), f"has degree {n2}, not the degree {n1} of poly1")
    return n1


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
    require_primitive(poly1, "poly1")
    require_primitive(poly2, "poly2")
    n1 = _same_degree(poly1, poly2)
    u, v = to_bipolar(m_sequence(poly1)), to_bipolar(m_sequence(poly2))
    r = periodic_correlation(np.stack([u, v]))[0, 1]
    values = tuple(int(x) for x in np.unique(r))
    expected = gold_values(n1) if n1 % 4 and n1 >= 3 else None
    preferred = expected is not None and poly1 != poly2 and set(values) == set(expected)
    return PairCheck(poly1, poly2, n1, values, expected, preferred)


def require_preferred(poly1: int, poly2: int, field: str = "poly2") -> PairCheck:
    """check_pair, raising :class:`ConfigError` (naming ``field``, with the values found) when the pair is
    not preferred."""
    n = degree(poly1)
    try:
        require_gold_degree(n)
    except ConfigError as exc:
        raise ConfigError("poly1", to_octal(poly1), f"has degree {n}, which {exc.reason}") from None
    chk = check_pair(poly1, poly2)
    if not chk.preferred:
        raise ConfigError(field, to_octal(poly2), _not_preferred(chk))
    return chk


def _not_preferred(chk: PairCheck) -> str:
    return (
        f"is not a preferred partner of {to_octal(chk.poly1)}: the cross-correlation takes {list(chk.values)}, "
        f"not {list(gold_values(chk.degree))}"
    )


def preferred_pairs(n: int) -> list[tuple[int, int]]:
    """All unordered preferred pairs (poly1 < poly2) of degree n, by exhaustive FFT test.

    One FFT per primitive polynomial and one inverse FFT per pair (degree 11: 176 polynomials,
    15 400 pairs, well under a second). The polynomials are ``int`` bit masks; ``oct`` shows them in the
    command line's octal notation.

    Examples:
        >>> from motionsig_cli import preferred_pairs
        >>> pairs = preferred_pairs(5)
        >>> len(pairs), (0o45, 0o75) in pairs  # the pair of the mode-signature paper's Table I
        (12, True)
    """
    require_search_degree(n)
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


def _polys(poly1: int | str, poly2: int | str) -> tuple[int, int]:
    """The pair as bit masks: text read as the command line reads ``--poly1``/``--poly2`` (octal ``"45"``,
    ``"0o45"``, or exponents), an ``int`` taken as the bit mask."""
    p1 = parse_polynomial(poly1, "poly1") if isinstance(poly1, str) else poly1
    p2 = parse_polynomial(poly2, "poly2") if isinstance(poly2, str) else poly2
    return p1, p2


def gold_code(
    poly1: int | str,
    poly2: int | str,
    index: int,
    shift: int = 0,
    state1: str | tuple[int, ...] | None = None,
    state2: str | tuple[int, ...] | None = None,
    *,
    verify: bool = True,
) -> np.ndarray:
    """One member of the Gold family of a preferred pair (MATLAB ``comm.GoldSequence`` conventions).

    Args:
        poly1: The first polynomial of a preferred pair. Text is read as ``--poly1`` on the command line:
            octal (``"45"``, ``"0o45"``) or exponents (``"x^5+x^2+1"``); an ``int`` is the GF(2) bit mask
            (write ``0o45`` in Python: the decimal ``45`` is another polynomial).
        poly2: The second polynomial of the pair (likewise).
        index: −2 → u, −1 → v, 0 … 2ⁿ − 2 → u ⊕ Tᵏv.
        shift: Start offset a of the output (applied to the whole code).
        state1: Initial state of the first register (MATLAB order, default ``0…01``).
        state2: Initial state of the second register (likewise).
        verify: Reject a pair that is not preferred (default). MATLAB's ``comm.GoldSequence``
            does not check; ``verify=False`` reproduces it for any two primitive polynomials of
            equal degree, but the result is then not a Gold code.

    Returns:
        ``uint8`` bits of length 2ⁿ − 1.

    Examples:
        Mode 1 of Table I of the mode-signature paper is member 9 at offset 8 of the pair 45, 75 (octal):

        >>> from motionsig_cli import gold_code
        >>> code = gold_code("45", "75", index=9, shift=8)
        >>> "".join(map(str, code))
        '1100001010111001011011000011011'
        >>> bool((code == gold_code(0o45, 0o75, 9, 8)).all())
        True
    """
    poly1, poly2 = _polys(poly1, poly2)
    if verify:
        require_preferred(poly1, poly2)
    else:
        _same_degree(poly1, poly2)
    u = m_sequence(poly1, state1)
    v = m_sequence(poly2, state2)
    return _member(u, v, index, shift)


def _member(u: np.ndarray, v: np.ndarray, index: int, shift: int) -> np.ndarray:
    period = u.size
    integer("index", index, -2, period - 1)
    code = u if index == -2 else v if index == -1 else u ^ np.roll(v, -index)
    return np.roll(code, -integer("shift", shift))


def gold_family(
    poly1: int | str,
    poly2: int | str,
    state1: str | tuple[int, ...] | None = None,
    state2: str | tuple[int, ...] | None = None,
    *,
    verify: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """All 2ⁿ + 1 members: returns ``(indices, codes)`` with indices −2, −1, 0 … 2ⁿ − 2.

    The polynomials are read as in :func:`gold_code`: text as on the command line (octal ``"45"`` or
    exponents), an ``int`` as the bit mask (``0o45``; the decimal ``45`` is another polynomial and is
    refused as not primitive or not preferred). ``verify=False`` skips the preferred-pair test.

    Examples:
        >>> from motionsig_cli import gold_family
        >>> idx, codes = gold_family("45", "75")
        >>> codes.shape, idx[:3].tolist()
        ((33, 31), [-2, -1, 0])
        >>> bool((gold_family(0o45, 0o75)[1] == codes).all())
        True
    """
    poly1, poly2 = _polys(poly1, poly2)
    if verify:
        require_preferred(poly1, poly2)
    else:
        _same_degree(poly1, poly2)
    return _family(m_sequence(poly1, state1), m_sequence(poly2, state2))


def _family(u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    period = u.size
    k = np.arange(period)
    shifted_v = v[(np.arange(period)[None, :] + k[:, None]) % period]  # row k: v advanced by k
    codes = np.vstack([u, v, u[None, :] ^ shifted_v])
    return np.arange(-2, period), codes


@dataclass(frozen=True)
class GoldConfig:
    """A Gold family: two primitive polynomials of one degree, their initial states, and whether the pair
    must be preferred (each field checked; MATLAB ``comm.GoldSequence`` conventions).

    Attributes:
        poly1, poly2: The pair (``int`` bit masks, or text: octal ``"45"`` or exponents ``"x^5+x^2+1"``;
            stored as bit masks). Degree ≤ 20, equal degrees.
        init1, init2: Initial states of the two registers (MATLAB order, default ``0…01``; stored as
            tuples of bits).
        preferred: Require a preferred pair (default). ``False`` accepts any two primitive polynomials of
            equal degree, as MATLAB does; the members are then not Gold codes.
    """

    poly1: int | str = 0o45
    poly2: int | str = 0o75
    init1: str | tuple[int, ...] | None = None
    init2: str | tuple[int, ...] | None = None
    preferred: bool = True

    def __post_init__(self) -> None:
        p1 = primitive_polynomial(self.poly1, "poly1")
        p2 = primitive_polynomial(self.poly2, "poly2")
        n = degree(p1)
        if degree(p2) != n:
            raise ConfigError("poly2", self.poly2, f"has degree {degree(p2)}, not the degree {n} of poly1")
        if self.preferred:
            try:
                require_gold_degree(n)
            except ConfigError as exc:
                raise ConfigError("poly1", self.poly1, f"has degree {n}, which {exc.reason}") from None
            chk = check_pair(p1, p2)
            if not chk.preferred:
                raise ConfigError("poly2", self.poly2, _not_preferred(chk))
        object.__setattr__(self, "poly1", p1)
        object.__setattr__(self, "poly2", p2)
        for name in ("init1", "init2"):
            value = getattr(self, name)
            object.__setattr__(self, name, default_state(n) if value is None else parse_state(value, n, name))

    @property
    def degree(self) -> int:
        """n: the codes have 2ⁿ − 1 chips."""
        return degree(int(self.poly1))

    def _sequences(self) -> tuple[np.ndarray, np.ndarray]:
        return m_sequence(int(self.poly1), self.init1), m_sequence(int(self.poly2), self.init2)

    def member(self, index: int = 0, shift: int = 0) -> np.ndarray:
        """Member ``index`` (−2 → u, −1 → v, k ≥ 0 → u ⊕ Tᵏv) with start offset ``shift``: ``uint8`` bits
        (:class:`ConfigError` naming ``index`` outside −2 … 2ⁿ − 2)."""
        return _member(*self._sequences(), index, shift)

    def family(self) -> tuple[np.ndarray, np.ndarray]:
        """All 2ⁿ + 1 members: ``(indices, codes)`` with indices −2, −1, 0 … 2ⁿ − 2."""
        return _family(*self._sequences())
