"""Cell-averaging CFAR (CA-CFAR) for square-law detection, vectorised over pulses and trials.

The radar function of Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System*, detects the
echoes after the EBPSK impacting filter "by an amplitude threshold with CFAR" without saying which CFAR; this is
the textbook cell-averaging detector (assumed).

Model and threshold factor. The cell under test (CUT) holds ``X = |w|²`` with w circular complex Gaussian of
unknown power μ (noise only), so X/μ ~ Exp(1); the N_t training cells (N_t/2 on each side of the CUT, beyond
n_guard guard cells) hold independent copies, their sum S ~ μ·Gamma(N_t, 1). The detector declares a target
when ``X > α·S/N_t`` (α times the training *mean*). Conditioned on S, P(X > βS | S) = exp(−βS/μ), and the
moment-generating function of the gamma law gives

    P_FA = E[exp(−β S/μ)] = (1 + β)^(−N_t),  β = α/N_t,

independent of μ (hence "CFAR"). Solving for α:

    α = N_t (P_FA^(−1/N_t) − 1).

Detection probability of a non-fluctuating target (Swerling 0) of CUT signal-to-noise ratio s (signal power
over μ): 2X/μ ~ χ'²(2, 2s), so P(X > t | S) = Q₁(√(2s), √(2t/μ)) (Marcum Q) and

    P_D(s) = E_S[Q₁(√(2s), √(2βS/μ))],

the expectation over S/μ ~ Gamma(N_t, 1) taken by generalised Gauss–Laguerre quadrature (:func:`pd_swerling0`).
For a Rayleigh-fluctuating target (Swerling 1) the same steps give P_D = (1 + β/(1 + s))^(−N_t)
(:func:`pd_swerling1`).

Correlated samples: the formulas need independent training cells. A sample stream whose noise is correlated over
several samples (a narrow-band filter's output) takes its training cells ``stride`` samples apart
(:class:`CFARConfig`), a stride at least its correlation length.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy import special

from motionsig_cli.config import ConfigError, in_range, integer

__all__ = ["CFARConfig", "ca_cfar", "ca_cfar_alpha", "pd_swerling0", "pd_swerling1"]

PFA_RANGE = (1e-12, 0.5)
"""False-alarm probabilities accepted per cell (below 1e-12 α grows past any useful threshold)."""
MAX_TRAIN = 4096
"""Most training cells (an average over more adds nothing and costs memory)."""


def ca_cfar_alpha(pfa: float, n_train: int) -> float:
    """The CA-CFAR threshold factor α = N_t (P_FA^(−1/N_t) − 1) on the training mean (module docstring).

    Raises:
        ConfigError: ``pfa`` not in :data:`PFA_RANGE` or ``n_train`` not an integer in [1, MAX_TRAIN].
    """
    p = in_range("pfa", pfa, *PFA_RANGE)
    n = integer("n_train", n_train, 1, MAX_TRAIN)
    return float(n * math.expm1(-math.log(p) / n))


@dataclass(frozen=True)
class CFARConfig:
    """A CA-CFAR detector.

    Attributes:
        n_train: training cells N_t, even (N_t/2 on each side), in [2, MAX_TRAIN] (assumed default 32).
        n_guard: guard cells on each side of the CUT (assumed default 2).
        pfa: design false-alarm probability per cell (assumed default 1e-6).
        stride: samples between successive guard/training cells (1: adjacent samples); a stride at least the
            noise correlation length keeps the training cells independent (module docstring).
    """

    n_train: int = 32
    n_guard: int = 2
    pfa: float = 1e-6
    stride: int = 1

    def __post_init__(self) -> None:
        integer("n_train", self.n_train, 2, MAX_TRAIN)
        if self.n_train % 2:
            raise ConfigError(
                "n_train", self.n_train, "is not even (half the training cells lie on each side)"
            )
        integer("n_guard", self.n_guard, 0, 100_000)
        in_range("pfa", self.pfa, *PFA_RANGE)
        integer("stride", self.stride, 1, 100_000)

    @property
    def alpha(self) -> float:
        """The threshold factor α on the training mean."""
        return ca_cfar_alpha(self.pfa, self.n_train)

    @property
    def half_width(self) -> int:
        """Samples from the CUT to the farthest training cell on one side."""
        return (self.n_guard + self.n_train // 2) * self.stride


def ca_cfar(
    power: np.ndarray, cfg: CFARConfig, *, reference: np.ndarray | None = None, scale: float = 1.0
) -> tuple[np.ndarray, np.ndarray]:
    """CA-CFAR over the last axis of ``power`` (square-law samples |y|², any leading axes: pulses, trials).

    For sample n the training cells are n ± (n_guard + j)·stride, j = 1..N_t/2. Samples whose training cells
    would leave the array get threshold +inf (never detected): no one-sided or shrunken windows.

    ``reference``: take the training cells from this array (same shape) instead of ``power``, and multiply
    their mean by ``scale``: for a CUT formed by a known linear processing of the reference samples (a coherent
    integration) whose noise power is ``scale`` times theirs, the P_FA is that of the formula as long as the
    CUT's noise is independent of the training cells' (the guard cells see to it).

    Returns:
        (detections, threshold): a boolean array ``power > threshold`` and the threshold
        α·scale·mean(training), both of the shape of ``power``.
    """
    p = np.asarray(power, dtype=float)
    if p.ndim == 0:
        raise ValueError("power must have at least one axis")
    ref = p if reference is None else np.asarray(reference, dtype=float)
    if ref.shape != p.shape:
        raise ValueError(f"reference must have the shape of power {p.shape}; got {ref.shape}")
    n = p.shape[-1]
    s, g, h = cfg.stride, cfg.n_guard, cfg.n_train // 2
    # cumulative sums along each residue class mod stride: c[m] = Σ_{k<m} p[k·s + r] (m = 0..M)
    m_len = -(-n // s)
    padded = np.zeros((*p.shape[:-1], m_len * s))
    padded[..., :n] = ref
    cls = padded.reshape(*p.shape[:-1], m_len, s)
    c = np.zeros((*p.shape[:-1], m_len + 1, s))
    np.cumsum(cls, axis=-2, out=c[..., 1:, :])
    m = np.arange(m_len)
    lo_a, lo_b = m - g - h, m - g  # left cells: class indices [m−g−h, m−g)
    hi_a, hi_b = m + g + 1, m + g + h + 1  # right cells: [m+g+1, m+g+h+1)
    ok = (lo_a >= 0) & (hi_b <= m_len)
    ia = np.clip(lo_a, 0, m_len)
    ib = np.clip(lo_b, 0, m_len)
    ja = np.clip(hi_a, 0, m_len)
    jb = np.clip(hi_b, 0, m_len)
    total = (c[..., ib, :] - c[..., ia, :]) + (c[..., jb, :] - c[..., ja, :])
    thr_cls = np.where(ok[:, None], cfg.alpha * scale * total / cfg.n_train, np.inf)
    thr = thr_cls.reshape(*p.shape[:-1], m_len * s)[..., :n]
    # the far right training cells of the last residue classes may fall in the padding: refuse them
    idx = np.arange(n)
    valid = (idx - (g + h) * s >= 0) & (idx + (g + h) * s <= n - 1)
    thr = np.where(valid, thr, np.inf)
    return p > thr, thr


@lru_cache(maxsize=16)
def _laguerre(n_train: int, nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and normalised weights for E[f(S)], S ~ Gamma(n_train, 1)."""
    x, w = special.roots_genlaguerre(nodes, n_train - 1)
    w = w / math.gamma(n_train) if n_train < 150 else w / np.exp(special.gammaln(n_train))
    return x, w / w.sum()  # renormalised: the quadrature integrates 1 exactly up to rounding


def pd_swerling0(snr: np.ndarray | float, pfa: float, n_train: int, *, nodes: int = 64) -> np.ndarray:
    """P_D of CA-CFAR for a non-fluctuating target of CUT signal-to-noise ratio ``snr`` (linear, power
    ratio), P_D = E_S[Q₁(√(2s), √(2βS))] over S ~ Gamma(N_t, 1) (module docstring), vectorised over ``snr``.
    """
    beta = ca_cfar_alpha(pfa, n_train) / n_train
    s = np.asarray(snr, dtype=float)
    if np.any(s < 0) or not np.all(np.isfinite(s)):
        raise ConfigError("snr", float(np.min(s)), "is not a finite number >= 0")
    x, w = _laguerre(int(n_train), nodes)
    # 2X ~ ncx2(2, 2s): P(X > βS) = ncx2.sf(2βS, 2, 2s); nc = 0 is the central χ²(2)
    t = 2.0 * beta * x
    sf = np.where(
        s[..., None] > 0,
        _ncx2_sf(t, 2, np.maximum(2.0 * s[..., None], 1e-300)),
        np.exp(-t / 2.0),
    )
    return np.clip(sf @ w, 0.0, 1.0)


def pd_swerling1(snr: np.ndarray | float, pfa: float, n_train: int) -> np.ndarray:
    """P_D of CA-CFAR for a Rayleigh-fluctuating target (Swerling 1) of mean CUT SNR ``snr``:
    (1 + β/(1 + s))^(−N_t), β = α/N_t."""
    beta = ca_cfar_alpha(pfa, n_train) / n_train
    s = np.asarray(snr, dtype=float)
    return (1.0 + beta / (1.0 + s)) ** (-float(n_train))


def _ncx2_sf(x: np.ndarray, df: int, nc: np.ndarray) -> np.ndarray:
    """scipy.stats.ncx2.sf, imported where it is used (scipy.stats costs 0.6 s to import, and the commands
    that only read this module's names need none of it)."""
    from scipy import stats

    return stats.ncx2.sf(x, df, nc)
