"""Periodic auto- and cross-correlation of bipolar codes (§II.A of the mode-signature paper, 47th IEEE CDC, Cancún, 2008; Sarwate & Pursley 1980).

R_xy[ℓ] = Σ_t x_t y_{(t+ℓ) mod N},  ℓ = 0 … N−1,  x, y ∈ {−1, +1}ᴺ.

Computed for a whole set at once with one FFT per code; the values of ±1 codes are integers and
are rounded exactly (the FFT error for N ≤ 2²⁰ is < 10⁻⁶, asserted).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np


def to_bipolar(bits: np.ndarray) -> np.ndarray:
    """BPSK chips of the mode-signature paper (eq 3 text): bit 0 → ρ0 = −1, bit 1 → ρ1 = +1."""
    bits = np.asarray(bits)
    return (2 * bits.astype(np.int8) - 1).astype(np.int8)


def periodic_correlation(codes: np.ndarray) -> np.ndarray:
    """All periodic correlations of a set of bipolar codes.

    Args:
        codes: ``(M, N)`` array of ±1 chips.

    Returns:
        ``(M, M, N)`` integer array, ``R[i, j, ℓ] = Σ_t codes[i, t] codes[j, (t+ℓ) mod N]``.

    Examples:
        Two bipolar m-sequences of a preferred pair: peak 31, off-peak values among Gold's −9, −1, 7:

        >>> import numpy as np
        >>> from motionsig_cli import m_sequence, periodic_correlation
        >>> codes = 1 - 2 * np.stack([m_sequence("45"), m_sequence("75")]).astype(int)
        >>> R = periodic_correlation(codes)
        >>> int(R[0, 0, 0]), sorted(set(R[0, 1].tolist()))
        (31, [-9, -1, 7])
    """
    x = np.asarray(codes, dtype=np.float64)
    if x.ndim != 2:
        raise ValueError(f"codes must be a 2-D (M, N) array, got shape {x.shape}")
    spec = np.fft.rfft(x, axis=1)
    n = x.shape[1]
    r = np.fft.irfft(np.conj(spec)[:, None, :] * spec[None, :, :], n=n, axis=2)
    rounded = np.rint(r)
    err = np.max(np.abs(r - rounded), initial=0.0)
    if err > 1e-6:  # pragma: no cover - would mean non-±1 input or an FFT precision problem
        raise ValueError(f"correlations are not integers (max deviation {err:.3g}); are the codes ±1?")
    return rounded.astype(np.int64)


def correlation_rows(codes: np.ndarray) -> Iterator[tuple[int, np.ndarray]]:
    """Stream the correlations of code ``a`` with codes ``a, a+1, …, M−1``, one ``a`` at a time.

    Yields ``(a, R)`` with ``R[j, ℓ] = R_{a, a+j}[ℓ]``. Memory is O(M N) instead of the O(M² N) of
    :func:`periodic_correlation` (a degree-10 family of 1025 codes would need ~8 GB at once).
    """
    x = np.asarray(codes, dtype=np.float64)
    if x.ndim != 2:
        raise ValueError(f"codes must be a 2-D (M, N) array, got shape {x.shape}")
    n = x.shape[1]
    spec = np.fft.rfft(x, axis=1)
    for a in range(x.shape[0]):
        r = np.fft.irfft(np.conj(spec[a])[None, :] * spec[a:], n=n, axis=1)
        rounded = np.rint(r)
        if np.max(np.abs(r - rounded), initial=0.0) > 1e-6:  # pragma: no cover
            raise ValueError("correlations are not integers; are the codes ±1?")
        yield a, rounded.astype(np.int64)


def gold_bound(n: int) -> int:
    """t(n) = 1 + 2^⌊(n+2)/2⌋: the Gold-family peak off-peak correlation magnitude."""
    return 1 + 2 ** ((n + 2) // 2)


def degree_of_period(period: int) -> int | None:
    """n such that period = 2ⁿ − 1, else None."""
    n = (period + 1).bit_length() - 1
    return n if (1 << n) - 1 == period and n >= 2 else None


@dataclass(frozen=True)
class PairSummary:
    """Correlation summary of one (a, b) pair; for a = b the peak at lag 0 is excluded."""

    a: int
    b: int
    values: tuple[int, ...]
    max_offpeak: int


def summarize(codes: np.ndarray) -> list[PairSummary]:
    """Distinct values and max off-peak magnitude for every unordered pair (a ≤ b), streamed."""
    out = []
    for a, rows in correlation_rows(codes):
        for j, r in enumerate(rows):
            vals = r[1:] if j == 0 else r
            out.append(
                PairSummary(a, a + j, tuple(int(v) for v in np.unique(vals)), int(np.max(np.abs(vals))))
            )
    return out


def offpeak_counts(codes: np.ndarray) -> tuple[dict[int, int], dict[int, int]]:
    """Histogram of off-peak values: ``(auto_counts, cross_counts)``, value → number of lags.

    Values of ±1 codes lie in [−N, N], so each block is counted with one ``bincount``.
    """
    n = np.asarray(codes).shape[1]
    auto = np.zeros(2 * n + 1, dtype=np.int64)
    cross = np.zeros(2 * n + 1, dtype=np.int64)
    for _, rows in correlation_rows(codes):
        auto += np.bincount(rows[0, 1:] + n, minlength=2 * n + 1)
        if rows.shape[0] > 1:
            cross += np.bincount(rows[1:].ravel() + n, minlength=2 * n + 1)
    return _histogram_dict(auto, n), _histogram_dict(cross, n)


def _histogram_dict(counts: np.ndarray, n: int) -> dict[int, int]:
    """bincount over value + n → {value: count} for the non-empty bins."""
    return {int(v) - n: int(c) for v, c in enumerate(counts) if c}
