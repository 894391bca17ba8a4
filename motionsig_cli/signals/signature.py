"""Mode perturbation signatures: the mode-signature paper (47th IEEE CDC, Cancún, 2008), §II.A, eqs (1)–(3).

Sampling t_k = kT. A chip lasts m_ρ samples (T_c = m_ρT); with code phase τ (samples) the sample k
carries chip j(k) = ⌊(k − τ)/m_ρ⌋ mod n_ρ (floor division, so negative k − τ wraps correctly)::

    p_k[τ] = b_{j(k)}                                  eq (1), chips b ∈ {ρ0, ρ1} = {−1, +1}
    z_k    = p_k[τ] cos(2π f_c t_k + 2π f_d t_k + θ)    eqs (2)–(3) (f_d = 0 in the paper)
    z_cos,k = p_k[τ] cos(2π f_c t_k),   z_sin,k = p_k[τ] sin(2π f_c t_k)   (replicas, θ removed)

With f_d = 0, z = cos θ · z_cos − sin θ · z_sin exactly. Time derivatives (used by the closed
loop, eq 54): ``"analytic"`` differentiates the carrier inside a chip (chip edges
ignored): ż = −ω p sin(ωt + θ), ż_cos = −ω_c p sin(ω_c t), ż_sin = ω_c p cos(ω_c t);
``"finite-difference"`` is the backward difference (z_k − z_{k−1})/T, which spikes by up to 2/T at
chip flips.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, positive

ZdotMethod = Literal["analytic", "finite-difference"]
MAX_SAMPLES = 5_000_000  # one signature record; larger ones are refused before allocation
MAX_TAU = 2**53  # |code phase| in samples: integers up to 2^53 are exact as floats (metadata, t = kT)


@dataclass(frozen=True, slots=True)
class SignatureConfig:
    """Sampling and carrier parameters of a mode signature.

    Checked here, once: T finite and > 0; m_rho an integer ≥ 1; f_c finite and ≥ 0; theta and f_d
    finite; tau an integer with |tau| ≤ 2^53. Any code phase is meaningful (the code repeats every
    n_ρ m_ρ samples); the bound is where integers stop being exact as floats.

    Attributes:
        T: Sample interval [s] (assumed: 0.05 s; the paper does not state it).
        m_rho: Samples per chip (assumed: 20, so that T_c = 1 s is one carrier cycle per chip; the paper
            does not state it).
        f_c: Carrier frequency [Hz] (1.0, implicit in the paper's Fig 6 discussion).
        theta: Carrier phase [rad].
        tau: Code phase in samples (any integer; the code repeats every n_ρ m_ρ samples).
        f_d: Frequency offset of eq (3) [Hz]; 0 in the paper.

    Raises:
        ConfigError: naming the first bad field.
    """

    T: float = 0.05
    m_rho: int = 20
    f_c: float = 1.0
    theta: float = 0.0
    tau: int = 0
    f_d: float = 0.0

    def __post_init__(self) -> None:
        try:
            positive("T", self.T, unit="s")
        except ConfigError:
            raise ConfigError("T", self.T, "is not a positive, finite sample interval [s]") from None
        try:
            integer("m_rho", self.m_rho, 1)
        except ConfigError:
            raise ConfigError("m_rho", self.m_rho, "is not an integer >= 1 (samples per chip)") from None
        in_range("f_c", self.f_c, 0.0, unit="Hz")
        finite("theta", self.theta)
        if not _is_int(self.tau) or abs(self.tau) > MAX_TAU:
            raise ConfigError("tau", self.tau, "is not an integer number of samples with |tau| <= 2^53")
        finite("f_d", self.f_d)


def finite(name: str, value: float) -> float:
    """``value`` if it is a finite number, else :class:`ConfigError` naming ``name``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ConfigError(name, value, "is not a number") from None
    if not math.isfinite(x):
        raise ConfigError(name, value, "is not a finite number")
    return x


def _is_int(value: object) -> bool:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        return False
    return isinstance(value, int | np.integer) or (math.isfinite(value) and int(value) == value)


@dataclass(frozen=True)
class Signature:
    """A sampled signature and its replicas (all arrays of length n)."""

    k: np.ndarray
    t: np.ndarray
    chip: np.ndarray
    p: np.ndarray
    z: np.ndarray
    z_cos: np.ndarray
    z_sin: np.ndarray
    zdot: np.ndarray
    zdot_cos: np.ndarray
    zdot_sin: np.ndarray


def chip_index(k: np.ndarray, tau: int, m_rho: int, n_rho: int) -> np.ndarray:
    """j(k) = ⌊(k − τ)/m_ρ⌋ mod n_ρ (0-based chip index of sample k, eq 1)."""
    return np.floor_divide(np.asarray(k) - tau, m_rho) % n_rho


def spreading_waveform(chips: np.ndarray, k: np.ndarray, tau: int, m_rho: int) -> np.ndarray:
    """p_k[τ]: the chip value (±1) held for m_ρ samples, code phase τ — eq (1) sampled."""
    chips = np.asarray(chips)
    return chips[chip_index(k, tau, m_rho, chips.size)]


def mode_signature(
    chips: np.ndarray,
    config: SignatureConfig,
    n_samples: int | None = None,
    zdot: ZdotMethod = "analytic",
) -> Signature:
    """Sample a mode signature, its θ-free replicas and their time derivatives — eqs (1)–(3).

    Args:
        chips: Bipolar chips (±1) of one code period, e.g. ``to_bipolar(table1_codes()[0])``.
        config: Sampling/carrier parameters.
        n_samples: Number of samples; default one code period n_ρ m_ρ.
        zdot: ``"analytic"`` (default) or ``"finite-difference"`` derivative.

    Examples:
        >>> import numpy as np
        >>> from motionsig_cli import mode_signature, parse_codes
        >>> from motionsig_cli.signals.signature import SignatureConfig
        >>> sig = mode_signature(parse_codes("corrected").chips[0], SignatureConfig())
        >>> sig.z.shape == sig.zdot.shape
        True
    """
    chips = np.asarray(chips)
    if chips.ndim != 1 or chips.size < 1 or not np.all(np.abs(chips) == 1):
        raise ValueError("chips must be a 1-D array of +1/-1 values")
    n = chips.size * config.m_rho if n_samples is None else n_samples
    if int(n) != n or n < 1:
        raise ValueError(f"n_samples must be a positive integer, got {n_samples}")
    if n > MAX_SAMPLES:
        raise ValueError(f"{n} samples > {MAX_SAMPLES}: shorten the record (or m_rho)")
    if zdot not in ("analytic", "finite-difference"):
        raise ValueError(f"zdot must be 'analytic' or 'finite-difference', got {zdot!r}")
    k = np.arange(int(n))
    with np.errstate(all="ignore"):  # overflow is reported below as a ValueError, not as warnings
        return _sample(chips, config, k, zdot)


def _sample(chips: np.ndarray, config: SignatureConfig, k: np.ndarray, zdot: ZdotMethod) -> Signature:
    t = k * config.T
    wc = 2 * np.pi * config.f_c
    w = 2 * np.pi * (config.f_c + config.f_d)
    tau = int(config.tau)
    p = spreading_waveform(chips, k, tau, config.m_rho).astype(np.float64)  # eq (1)
    z = p * np.cos(w * t + config.theta)  # eqs (2)-(3)
    z_cos = p * np.cos(wc * t)
    z_sin = p * np.sin(wc * t)
    if zdot == "analytic":
        zd = -w * p * np.sin(w * t + config.theta)
        zd_cos = -wc * p * np.sin(wc * t)
        zd_sin = wc * p * np.cos(wc * t)
    else:
        t_prev = t - config.T
        p_prev = spreading_waveform(chips, k - 1, tau, config.m_rho)
        zd = (z - p_prev * np.cos(w * t_prev + config.theta)) / config.T
        zd_cos = (z_cos - p_prev * np.cos(wc * t_prev)) / config.T
        zd_sin = (z_sin - p_prev * np.sin(wc * t_prev)) / config.T
    chip = chip_index(k, tau, config.m_rho, chips.size)
    if not all(np.all(np.isfinite(a)) for a in (t, z, z_cos, z_sin, zd, zd_cos, zd_sin)):
        raise ValueError("non-finite samples: T, f_c or f_d is too large for this record length")
    return Signature(k, t, chip, p, z, z_cos, z_sin, zd, zd_cos, zd_sin)


def replica_bank(
    chips: np.ndarray,
    modes: np.ndarray,
    taus: np.ndarray,
    fcs: np.ndarray,
    T: float,
    m_rho: int,
    n_samples: int,
    zdot: ZdotMethod = "analytic",
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """θ-free replicas of many candidates at once (the replicas z_cos, z_sin of eqs 2–3 and their
    derivatives, for the filter bank of eq 52).

    Args:
        chips: Bipolar codes of all modes, (M, n_ρ).
        modes, taus, fcs: Candidate mode index (0-based), code phase (samples), carrier (Hz), each (C,).

    Returns:
        ``z_cos, z_sin, zdot_cos, zdot_sin``, each (C, N).
    """
    chips = np.asarray(chips, dtype=float)
    k = np.arange(n_samples)
    modes, taus, fcs = (np.asarray(a) for a in (modes, taus, fcs))
    j = chip_index(k[None, :], taus[:, None], m_rho, chips.shape[1])  # (C, N)
    p = chips[modes[:, None], j]
    wt = 2 * np.pi * fcs[:, None] * (k * T)[None, :]
    z_cos, z_sin = p * np.cos(wt), p * np.sin(wt)
    if zdot == "analytic":
        w = 2 * np.pi * fcs[:, None]
        return z_cos, z_sin, -w * p * np.sin(wt), w * p * np.cos(wt)
    jp = chip_index(k[None, :] - 1, taus[:, None], m_rho, chips.shape[1])
    pp = chips[modes[:, None], jp]
    wtp = wt - 2 * np.pi * fcs[:, None] * T
    return z_cos, z_sin, (z_cos - pp * np.cos(wtp)) / T, (z_sin - pp * np.sin(wtp)) / T
