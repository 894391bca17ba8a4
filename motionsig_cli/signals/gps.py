"""GPS L1 C/A codes, PRN 1–32 (IS-GPS-200 §3.3.2.3): the degree-10 Gold-code reference.

G1 = 1 + x³ + x¹⁰ and G2 = 1 + x² + x³ + x⁶ + x⁸ + x⁹ + x¹⁰ in the interface specification's
register notation (feedback from stages 3, 10 and 2, 3, 6, 8, 9, 10 into stage 1), both registers
start all ones; the C/A chip is G1 stage 10 ⊕ (G2 stage i ⊕ G2 stage j) with the PRN's
phase-selector taps (i, j) of IS-GPS-200 Table 3-Ia (``data/gps_ca.csv``).

The generator here is written from the interface specification, independently of
:mod:`~motionsig_cli.signals.gold`; the tests check that the two agree (the C/A codes are members of
the Gold family of the reciprocal polynomials, in this package's recurrence convention).
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache

import numpy as np

from motionsig_cli.config import integer
from motionsig_cli.refdata import load

CA_LENGTH = 1023
G1_FEEDBACK = (3, 10)  # stages (1-based) summed into stage 1: 1 + x^3 + x^10
G2_FEEDBACK = (2, 3, 6, 8, 9, 10)  # 1 + x^2 + x^3 + x^6 + x^8 + x^9 + x^10


@cache
def phase_selectors() -> dict[int, tuple[int, int]]:
    """PRN → G2 phase-selector taps (IS-GPS-200 Table 3-Ia)."""
    t = load("gps_ca.csv")
    prns, a, b = (
        t.numeric("prn", integer=True),
        t.numeric("g2_tap1", integer=True),
        t.numeric("g2_tap2", integer=True),
    )
    return {int(p): (int(i), int(j)) for p, i, j in zip(prns, a, b, strict=True)}


@cache
def g2_delays() -> dict[int, int]:
    """PRN → G2 code-phase delay in chips (IS-GPS-200 Table 3-Ia), equivalent to the phase selectors."""
    t = load("gps_ca.csv")
    prns, delays = t.numeric("prn", integer=True), t.numeric("g2_delay_chips", integer=True)
    return {int(p): int(d) for p, d in zip(prns, delays, strict=True)}


@cache
def _registers() -> tuple[np.ndarray, np.ndarray]:
    """G1 output (stage 10) and the full G2 register history over one period.

    A register is an ``int`` whose bit i − 1 is stage i; each clock shifts the stages up by one and feeds
    the parity of the feedback stages into stage 1.
    """
    full = (1 << 10) - 1
    mask1 = sum(1 << (s - 1) for s in G1_FEEDBACK)
    mask2 = sum(1 << (s - 1) for s in G2_FEEDBACK)
    g1 = g2 = full  # both registers start all ones
    g1_out, g2_states = [], []
    for _ in range(CA_LENGTH):
        g1_out.append(g1 >> 9)
        g2_states.append(g2)
        g1 = ((g1 << 1) | ((g1 & mask1).bit_count() & 1)) & full
        g2 = ((g2 << 1) | ((g2 & mask2).bit_count() & 1)) & full
    g2_hist = (np.array(g2_states)[:, None] >> np.arange(10)) & 1  # column i: stage i + 1
    return np.array(g1_out, dtype=np.uint8), g2_hist.astype(np.uint8)


def _prn(prn: int) -> int:
    taps = phase_selectors()
    return integer("prn", prn, min(taps), max(taps))


def ca_code(prn: int) -> np.ndarray:
    """The 1023-chip C/A code of ``prn`` (1–32) as 0/1 bits, chip 0 first (:class:`ConfigError` naming
    ``prn`` for another number).

    Examples:
        >>> from motionsig_cli import ca_code
        >>> c = ca_code(1)
        >>> c.size, oct(int("".join(map(str, c[:10])), 2))  # IS-GPS-200 Table 3-Ia: first 10 chips of PRN 1, octal 1440
        (1023, '0o1440')
    """
    i, j = phase_selectors()[_prn(prn)]
    g1_out, g2_hist = _registers()
    return g1_out ^ g2_hist[:, i - 1] ^ g2_hist[:, j - 1]


def ca_codes(prns: Sequence[int]) -> np.ndarray:
    """``(len(prns), 1023)`` array of C/A codes (every PRN checked before any code is built).

    Examples:
        >>> from motionsig_cli import ca_codes
        >>> ca_codes([1, 2, 3]).shape
        (3, 1023)
    """
    for p in prns:
        _prn(p)
    return np.stack([ca_code(p) for p in prns])


def first_chips_octal(bits: np.ndarray, n: int = 10) -> str:
    """The first ``n`` chips as an octal number, first chip most significant (IS-GPS-200 Table 3-Ia)."""
    return format(int("".join(str(int(b)) for b in bits[:n]), 2), "o")
