"""Maximal-length sequences (m-sequences) from a primitive polynomial — §II.A (ref [11]) of the mode-signature
paper (47th IEEE CDC, Cancún, 2008).

Convention (MATLAB ``comm.PNSequence`` / ``comm.GoldSequence`` compatible, checked against the
MATLAB vectors quoted in the ``mhostetter/sdr`` tests; see ``tests/signals/test_lfsr.py``):

* For p(x) = xⁿ + c_{n−1}xⁿ⁻¹ + … + c_1 x + 1 the output satisfies the linear recurrence
  s_{t+n} = ⊕_{i<n, c_i=1} s_{t+i}  (e.g. x⁵+x²+1: s_{t+5} = s_{t+2} ⊕ s_t).
* The initial-state vector ``[s_{n−1} … s_1 s_0]`` is given in MATLAB's ``InitialConditions``
  order: the first n output chips are the vector reversed. The default is ``[0 … 0 1]``.
* ``shift`` advances the output: ``out[t] = s[(t + shift) mod (2ⁿ − 1)]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from motionsig_cli.config import ConfigError, integer
from motionsig_cli.signals.gf2 import degree, is_primitive, not_primitive, parse_polynomial, require_primitive

MAX_SEQUENCE_DEGREE = 20  # 2^20 − 1 chips; longer periods are not tabulated


def primitive_polynomial(value: int | str, field: str = "poly", max_degree: int = MAX_SEQUENCE_DEGREE) -> int:
    """Parse (octal or exponents, see :func:`~motionsig_cli.signals.gf2.parse_polynomial`) and check a
    primitive polynomial of degree ≤ ``max_degree``.

    Raises:
        ConfigError: naming ``field``, with the value as given.
    """
    poly = parse_polynomial(value, field)
    n = degree(poly)
    if n > max_degree:
        raise ConfigError(
            field,
            value,
            f"has degree {n} > {max_degree}: sequences of period 2^n-1 are tabulated up to n = {max_degree}",
        )
    if not is_primitive(poly):
        raise ConfigError(field, value, not_primitive(poly))
    return poly


def parse_state(text: str | Sequence[int], n: int, field: str = "init") -> tuple[int, ...]:
    """Parse an n-bit initial state (``"00001"`` or a sequence of 0/1) in MATLAB order.

    Raises:
        ConfigError: (naming ``field``) wrong length, non-binary digit, or the all-zeros state (which is
            a fixed point of every LFSR and yields no m-sequence).
    """
    bits = list(text.replace(" ", "").replace(",", "")) if isinstance(text, str) else list(text)
    shown = text if isinstance(text, str) else "".join(map(str, bits))
    if len(bits) != n:
        raise ConfigError(field, shown, f"has {len(bits)} bits; a degree-{n} register needs {n} bits")
    if any(str(b) not in ("0", "1") for b in bits):  # ASCII 0/1 only (int() would accept other digits)
        raise ConfigError(field, shown, "may contain only 0 and 1")
    state = tuple(int(b) for b in bits)
    if not any(state):
        raise ConfigError(field, shown, "is all zeros: the LFSR would output zeros forever")
    return state


def default_state(n: int) -> tuple[int, ...]:
    """MATLAB's default initial state ``[0 … 0 1]``."""
    return (0,) * (n - 1) + (1,)


def m_sequence(poly: int | str, state: Sequence[int] | str | None = None, shift: int = 0) -> np.ndarray:
    """One period (2ⁿ − 1 chips) of the m-sequence of primitive polynomial ``poly``.

    Args:
        poly: Primitive polynomial. Text is read as the command line reads ``--poly``: octal (``"45"``,
            ``"0o45"``) or exponents (``"x^5+x^2+1"``). An ``int`` is the GF(2) bit mask itself (bit i is
            the coefficient of xⁱ, see :mod:`~motionsig_cli.signals.gf2`): write ``0o45`` in Python, since
            ``45`` is the decimal 45 = 0b101101 = x⁵ + x³ + x² + 1, another polynomial.
        state: Initial state ``[s_{n−1} … s_0]`` (MATLAB order); default ``[0 … 0 1]``.
        shift: Cyclic advance of the output.

    Returns:
        ``uint8`` array of 0/1 of length 2ⁿ − 1.

    Examples:
        >>> from motionsig_cli import m_sequence
        >>> m_sequence("45")[:10].tolist()  # x^5 + x^2 + 1, state 00001
        [1, 0, 0, 0, 0, 1, 0, 0, 1, 0]
        >>> bool((m_sequence("45") == m_sequence(0o45)).all() and (m_sequence("x^5+x^2+1") == m_sequence(0o45)).all())
        True
    """
    if isinstance(poly, str):
        poly = parse_polynomial(poly, "poly")
    require_primitive(poly)
    n = degree(poly)
    if n > MAX_SEQUENCE_DEGREE:
        raise ConfigError(
            "poly", format(poly, "o"), f"has degree {n} > {MAX_SEQUENCE_DEGREE}: too long to tabulate"
        )
    bits = parse_state(state, n) if state is not None else default_state(n)
    period = (1 << n) - 1
    taps = poly & ((1 << n) - 1)  # c_0 … c_{n−1}
    # reg holds s_t … s_{t+n−1} in bits 0 … n−1; first outputs are the state vector reversed.
    reg = 0
    for i, b in enumerate(reversed(bits)):
        reg |= b << i
    out = np.empty(period, dtype=np.uint8)
    top = n - 1
    for t in range(period):
        out[t] = reg & 1
        fb = (reg & taps).bit_count() & 1  # s_{t+n} = ⊕ c_i s_{t+i}
        reg = (reg >> 1) | (fb << top)
    return np.roll(out, -shift) if shift else out


@dataclass(frozen=True)
class MSequenceConfig:
    """One period of an m-sequence: the polynomial, the initial state and a cyclic advance, each checked.

    Attributes:
        poly: Primitive polynomial of degree ≤ :data:`MAX_SEQUENCE_DEGREE` (an ``int`` bit mask, or text in
            octal ``"45"`` or exponents ``"x^5+x^2+1"``; stored as the bit mask).
        init: Initial state ``[s_{n−1} … s_0]`` (MATLAB order, ``"00001"``); default ``0…01``; stored as a
            tuple of bits.
        shift: Cyclic advance of the output (any integer).
    """

    poly: int | str = 0o45
    init: str | tuple[int, ...] | None = None
    shift: int = 0

    def __post_init__(self) -> None:
        poly = primitive_polynomial(self.poly, "poly")
        n = degree(poly)
        object.__setattr__(self, "poly", poly)
        object.__setattr__(self, "init", default_state(n) if self.init is None else parse_state(self.init, n))
        object.__setattr__(self, "shift", integer("shift", self.shift))

    @property
    def degree(self) -> int:
        """n: the period is 2ⁿ − 1."""
        return degree(int(self.poly))

    def sequence(self) -> np.ndarray:
        """The ``uint8`` bits, length 2ⁿ − 1."""
        return m_sequence(int(self.poly), self.init, self.shift)
