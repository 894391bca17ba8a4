"""Maximal-length sequences (m-sequences) from a primitive polynomial — seed 000 §II.A, ref [11].

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

import numpy as np

from motionsig_cli.signals.gf2 import degree, require_primitive

MAX_SEQUENCE_DEGREE = 20  # 2^20 − 1 chips; longer periods are not tabulated


def parse_state(text: str | Sequence[int], n: int) -> tuple[int, ...]:
    """Parse an n-bit initial state (``"00001"`` or a sequence of 0/1) in MATLAB order.

    Raises:
        ValueError: wrong length, non-binary digit, or the all-zeros state (which is a fixed
            point of every LFSR and yields no m-sequence).
    """
    bits = list(text.replace(" ", "").replace(",", "")) if isinstance(text, str) else list(text)
    if len(bits) != n:
        raise ValueError(f"initial state must have {n} bits for a degree-{n} polynomial, got {len(bits)}")
    if any(str(b) not in ("0", "1") for b in bits):  # ASCII 0/1 only (int() would accept other digits)
        raise ValueError(f"initial state {text!r} must contain only 0 and 1")
    state = tuple(int(b) for b in bits)
    if not any(state):
        raise ValueError("initial state is all zeros: the LFSR would output zeros forever")
    return state


def default_state(n: int) -> tuple[int, ...]:
    """MATLAB's default initial state ``[0 … 0 1]``."""
    return (0,) * (n - 1) + (1,)


def m_sequence(poly: int, state: Sequence[int] | str | None = None, shift: int = 0) -> np.ndarray:
    """One period (2ⁿ − 1 chips) of the m-sequence of primitive polynomial ``poly``.

    Args:
        poly: Primitive polynomial as a GF(2) bit mask (see :mod:`~motionsig_cli.signals.gf2`).
        state: Initial state ``[s_{n−1} … s_0]`` (MATLAB order); default ``[0 … 0 1]``.
        shift: Cyclic advance of the output.

    Returns:
        ``uint8`` array of 0/1 of length 2ⁿ − 1.
    """
    require_primitive(poly)
    n = degree(poly)
    if n > MAX_SEQUENCE_DEGREE:
        raise ValueError(f"degree {n} > {MAX_SEQUENCE_DEGREE}: the period 2^{n}-1 is too long to tabulate")
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
