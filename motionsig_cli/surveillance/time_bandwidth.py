"""Time–bandwidth of PSK signatures and the MAN power — ATC-10 §3.9 and App. F, eqs (F.5)–(F.8),
(3.9.1)–(3.9.3).

With t_j uniform over the 2τ window and E cos² = ½, the second moment of one MAN component depends
only on the two autocorrelations (F.5; ∫|R_ij|² = ∫R_ii R_jj for aperiodic correlations):

    b_ij = (1/(4τ)) ∫ R_ii(t) R_jj(t) dt,      E n² = (1/(2α)) Σ_{j≠i} ∫ R_ii R_jj        (F.5)–(F.6)

Theorem 3.3: E n² ≤ Σ_{j≠i} 1/(4α√(W_i W_j)) with the Zakai bandwidth W = [2∫R²]⁻¹ (the statement
prints √(W_j)W_j; (F.8) prints the exponents −1 and −½: both are +½), equality iff all R_jj = R_ii.
For a PSK set sharing one "good" autocorrelation (Fig. 3.11, chip τ_c):

    E n² = (N − 1)/(4αW),   W = [(4/3)τ_c(1 + 2τ_c/τ + 2(τ_c/τ)²)]⁻¹ ≈ 3/(4τ_c)      (3.9.2)–(3.9.3)

so E n² ≈ Nτ_c/(3α) and the peak signal-to-interference ratio is ≈ 3α/(Nτ_c).

For a ±1 code with rectangular chips and unit energy the autocorrelation is piecewise linear between
chip lags, R(mτ_c) = r_m/L (r_m the aperiodic autocorrelation), so ∫R_iR_j has the closed form
τ_c Σ_m (2r_m s_m + r_m s_{m+1} + r_{m+1} s_m + 2r_{m+1} s_{m+1})/(6L²). The report's correction factor
(1 + 2x + 2x²) cannot be tied to a definite R(t) (Fig. 3.11 is lost); the numerical W of a real code
is offered beside it.
"""

from __future__ import annotations

import numpy as np


def as_code(code: np.ndarray | list[int]) -> np.ndarray:
    """A ±1 code as a float array (0/1 bits are mapped 0 → +1, 1 → −1)."""
    c = np.asarray(code)
    if c.ndim != 1 or c.size < 1:
        raise ValueError("a code must be a non-empty 1-D sequence")
    if np.all(np.isin(c, (0, 1))) and not np.all(np.isin(c, (-1, 1))):
        c = 1 - 2 * c
    if not np.all(np.isin(c, (-1, 1))):
        raise ValueError("a code must consist of ±1 chips (or 0/1 bits)")
    return c.astype(float)


def aperiodic_correlation(c: np.ndarray, d: np.ndarray) -> np.ndarray:
    """C(m) = Σ_n d_n c_{n+m} for m = −L … L (out-of-range terms 0; C(±L) = 0), length 2L + 1."""
    c, d = as_code(c), as_code(d)
    if c.size != d.size:
        raise ValueError("codes must have equal length")
    full = np.correlate(c, d, mode="full")  # index m + L − 1 holds Σ_n c_{n+m} d_n, m = −(L−1) … L−1
    return np.concatenate([[0.0], full, [0.0]])


def product_integral(r: np.ndarray, s: np.ndarray, L: int) -> float:
    """∫R_a R_b dt / τ_c for piecewise-linear correlations given at the lags m = −L … L (values r/L, s/L)."""
    r0, r1, s0, s1 = r[:-1], r[1:], s[:-1], s[1:]
    return float(np.sum(2 * r0 * s0 + r0 * s1 + r1 * s0 + 2 * r1 * s1) / (6.0 * L * L))


def zakai_bandwidth(code: np.ndarray) -> float:
    """W·τ_c = 1/(2∫R²dt/τ_c) of a code's aperiodic autocorrelation (Theorem 3.3's W)."""
    c = as_code(code)
    r = aperiodic_correlation(c, c)
    return 1.0 / (2.0 * product_integral(r, r, c.size))


def zakai_bandwidth_report(tauc_over_tau: float | np.ndarray) -> np.ndarray:
    """W·τ_c = [(4/3)(1 + 2x + 2x²)]⁻¹, x = τ_c/τ (3.9.3 as printed)."""
    x = np.asarray(tauc_over_tau, dtype=float)
    return 1.0 / ((4.0 / 3.0) * (1.0 + 2.0 * x + 2.0 * x * x))


IDEAL_W_TAUC = 0.75  # W = 3/(4τ_c) for a triangular main lobe without sidelobes: ∫R² = 2τ_c/3


def b_from_autocorrelations(ref: np.ndarray, codes: np.ndarray) -> np.ndarray:
    """b_ij = (1/(4τ))∫R_ii R_jj for each row j of ``codes`` against the reference i (F.5)."""
    c = as_code(ref)
    L = c.size
    ri = aperiodic_correlation(c, c)
    rows = np.atleast_2d(codes)
    out = []
    for d in rows:
        d = as_code(d)
        out.append(product_integral(ri, aperiodic_correlation(d, d), L) / (4.0 * L))  # τ = Lτ_c
    return np.array(out)


def b_random_codes(ref: np.ndarray) -> float:
    """b for interferers with fresh random ±1 codes against a fixed code c: (1/(6L))(1 + r₁/2), r₁ the
    lag-1 aperiodic autocorrelation of c over L (the mean over codes of R_jj is the ideal triangle)."""
    c = as_code(ref)
    L = c.size
    r1 = float(np.dot(c[:-1], c[1:])) / L if L > 1 else 0.0
    return (1.0 + 0.5 * r1) / (6.0 * L)


def psk_power(N: float, alpha: float, W: float) -> float:
    """E n² = (N − 1)/(4αW) (3.9.2)."""
    if not (N >= 1 and alpha > 0 and W > 0):
        raise ValueError("need N >= 1, alpha > 0 and W > 0")
    return (N - 1.0) / (4.0 * alpha * W)


def peak_sir(N: float, alpha: float, tau_c: float) -> float:
    """Peak signal-to-interference ratio 1/E n² ≈ 3α/(Nτ_c) (Sec. 3.9, ideal W)."""
    return 3.0 * alpha / (N * tau_c)


def reference1_power(N_eff: float, B: float, alpha: float = 1.0) -> float:
    """The white-noise power of Reference [1], p = (N − 1)/(Bα) (Sec. 3.8, 3.9)."""
    return (N_eff - 1.0) / (B * alpha)


def autocorrelation_curve(code: np.ndarray, per_chip: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """(t/τ_c, R(t)) of a code's aperiodic autocorrelation, sampled ``per_chip`` points per chip."""
    c = as_code(code)
    L = c.size
    r = aperiodic_correlation(c, c) / L
    lags = np.arange(-L, L + 1, dtype=float)
    t = np.linspace(-L, L, 2 * L * per_chip + 1)
    return t, np.interp(t, lags, r)


def ideal_autocorrelation(t_over_tauc: np.ndarray) -> np.ndarray:
    """The ideal triangle R(t) = max(0, 1 − |t|/τ_c)."""
    return np.clip(1.0 - np.abs(np.asarray(t_over_tauc, dtype=float)), 0.0, None)


BARKER13 = np.array([1, 1, 1, 1, 1, -1, -1, 1, 1, -1, 1, -1, 1], dtype=float)
MSEQ31 = np.array([1 if ch == "+" else -1 for ch in "++++-+-+---+--+++-----++--+-++-"], dtype=float)
"""The length-31 m-sequence of the chip-level checks (LFSR x⁵ + x² + 1, initial state 10000, bit 0 → +1)."""
