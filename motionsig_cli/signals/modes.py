"""Table I of the mode-signature paper (47th IEEE CDC, Cancún, 2008): the
three mode signatures (n_ρ = 31), printed and corrected.

The printed strings are copied verbatim in ``data/table1.csv``. Mode 1 is exactly a member of the
Gold family of the preferred pair octal 45/75 (x⁵+x²+1, x⁵+x⁴+x³+x²+1; MATLAB's default pair);
modes 2 and 3 are not Gold codes as printed (their correlations are not three-valued) but lie
within edit distance 1 and 2 of family members. The corrected codes are those members.
:func:`nearest_members` re-derives them from the printed strings by exhaustive search over the
33 × 31 (index, offset) members; :func:`corrected_codes` generates them from the stored
(index, offset).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from motionsig_cli.config import ConfigError, one_of
from motionsig_cli.refdata import load
from motionsig_cli.signals.gold import gold_code, gold_family

TABLE1_PAIR = (0o45, 0o75)
TABLE1_STATES = ("00001", "00001")
Variant = Literal["corrected", "printed"]
VARIANTS = ("corrected", "printed")


def _bits(s: str) -> np.ndarray:
    return np.frombuffer(s.encode(), dtype=np.uint8) - ord("0")


def bit_string(bits: np.ndarray) -> str:
    """0/1 array → ``"0101…"``."""
    return "".join("1" if b else "0" for b in np.asarray(bits))


def modes() -> list[tuple[int, str]]:
    """(mode number, behaviour letter) of Table I."""
    t = load("table1.csv")
    return [(int(m), str(b)) for m, b in zip(t.column("mode"), t.column("behavior"), strict=True)]


def printed_codes() -> np.ndarray:
    """The three signatures exactly as printed in Table I, ``(3, 31)`` bits."""
    return np.stack([_bits(s) for s in load("table1.csv").column("printed")])


def corrected_members() -> list[tuple[int, int]]:
    """(family index k, start offset a) of each corrected mode code (``data/table1.csv``)."""
    t = load("table1.csv")
    ks, shifts = t.numeric("corrected_index", integer=True), t.numeric("corrected_shift", integer=True)
    return [(int(k), int(a)) for k, a in zip(ks, shifts, strict=True)]


def corrected_codes() -> np.ndarray:
    """The corrected signatures: members (k, a) of the 45/75 Gold family, ``(3, 31)`` bits."""
    return np.stack([gold_code(*TABLE1_PAIR, k, a, *TABLE1_STATES) for k, a in corrected_members()])


def table1_codes(variant: Variant = "corrected") -> np.ndarray:
    """Table I codes, ``variant`` ``"corrected"`` (default) or ``"printed"`` (:class:`ConfigError` naming
    ``codes`` otherwise)."""
    one_of("codes", variant, VARIANTS)
    return corrected_codes() if variant == "corrected" else printed_codes()


def table1_code(mode: int, variant: Variant = "corrected") -> np.ndarray:
    """The code of one Table I mode (1, 2 or 3; :class:`ConfigError` naming ``mode`` otherwise)."""
    numbers = [m for m, _ in modes()]
    if isinstance(mode, bool) or mode not in numbers:
        raise ConfigError("mode", mode, f"is not a Table I mode ({', '.join(map(str, numbers))})")
    return table1_codes(variant)[numbers.index(mode)]


def family_members() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every cyclic shift of every member of the 45/75 family: ``(index, shift, codes)``, 1023 rows."""
    idx, fam = gold_family(*TABLE1_PAIR, *TABLE1_STATES)
    n = fam.shape[1]
    shifts = np.arange(n)
    rolled = fam[:, (np.arange(n)[None, :] + shifts[:, None]) % n]  # (33, 31 shifts, 31 chips)
    return np.repeat(idx, n), np.tile(shifts, idx.size), rolled.reshape(-1, n)


def edit_distances(s: np.ndarray, candidates: np.ndarray) -> np.ndarray:
    """Levenshtein distance from string ``s`` to every row of ``candidates`` (vectorised DP)."""
    s = np.asarray(s)
    cand = np.asarray(candidates)
    m, n = s.size, cand.shape[1]
    prev = np.broadcast_to(np.arange(n + 1), (cand.shape[0], n + 1)).copy()
    for i in range(1, m + 1):
        cur = np.empty_like(prev)
        cur[:, 0] = i
        sub = prev[:, :-1] + (cand != s[i - 1])
        dele = prev[:, 1:] + 1
        best = np.minimum(sub, dele)
        for j in range(1, n + 1):  # insertions depend on the left neighbour
            cur[:, j] = np.minimum(best[:, j - 1], cur[:, j - 1] + 1)
        prev = cur
    return prev[:, n]


def alignment(printed: np.ndarray, gold: np.ndarray) -> list[str]:
    """A minimal edit script turning ``gold`` into ``printed`` (0-based chip positions)."""
    a, b = np.asarray(gold), np.asarray(printed)
    m, n = a.size, b.size
    d = np.zeros((m + 1, n + 1), dtype=int)
    d[:, 0] = np.arange(m + 1)
    d[0, :] = np.arange(n + 1)
    for i in range(1, m + 1):
        for j in range(1, n + 1):
            d[i, j] = min(d[i - 1, j - 1] + (a[i - 1] != b[j - 1]), d[i - 1, j] + 1, d[i, j - 1] + 1)
    ops: list[str] = []
    i, j = m, n
    while i > 0 or j > 0:
        if i > 0 and j > 0 and d[i, j] == d[i - 1, j - 1] + (a[i - 1] != b[j - 1]):
            if a[i - 1] != b[j - 1]:
                ops.append(f"chip {i - 1}: Gold {a[i - 1]}, printed {b[j - 1]}")
            i, j = i - 1, j - 1
        elif i > 0 and d[i, j] == d[i - 1, j] + 1:
            ops.append(f"Gold chip {i - 1} ({a[i - 1]}) missing from the print")
            i -= 1
        else:
            ops.append(f"printed chip {j - 1} ({b[j - 1]}) inserted")
            j -= 1
    return ops[::-1]


@dataclass(frozen=True)
class NearestMember:
    """The family member closest to a printed code."""

    index: int
    shift: int
    code: np.ndarray
    edit_distance: int
    hamming: int
    ties: int


def nearest_members(codes: np.ndarray) -> list[NearestMember]:
    """For each code, the 45/75 family member (any index, any cyclic offset) at least edit distance.

    Ties on edit distance are broken by Hamming distance; ``ties`` counts members that remain tied.
    """
    idx, shifts, members = family_members()
    out = []
    for code in np.asarray(codes):
        ed = edit_distances(code, members)
        ham = np.count_nonzero(members != code, axis=1)
        best = np.flatnonzero(ed == ed.min())
        best = best[ham[best] == ham[best].min()]
        b = int(best[0])
        out.append(
            NearestMember(int(idx[b]), int(shifts[b]), members[b], int(ed[b]), int(ham[b]), int(best.size))
        )
    return out
