"""The amplitude density of one MAN component for PSK signatures at the chip level (the Monte Carlo's
"Level B"; ATC-10 §3.3, eq 3.3.7, with real codes).

The reference aircraft i has a ±1 code c of L rectangular chips (unit energy: S_i = c_k/√τ on chip k,
τ = Lτ_c). An overlapping interferer j arrives with a continuous delay δ ~ U(−τ, τ) relative to the
matched-filter window, written δ = (k + f)τ_c, and a carrier phase φ ~ U(0, 2π); its code is either a
fresh random ±1 code d (``family=None``, the random-code ensemble) or a member of a code family drawn
uniformly (e.g. the Gold family of c). Its contribution (3.3.7) is exactly

    n_ij = cos φ · X,    X = (1/L)[(1 − f)C(k) + f C(k + 1)],    C(m) = Σ_n d_n c_{n+m}  (aperiodic)

The density is a mixture over (code, k, f, φ). Its cumulant-generating function is a quadrature:

* random codes: given (k, f, φ) the chips d_n are iid Rademacher, E_d e^{sX} = Π_n cosh(s v_n/L) with
  v_n = (1 − f)c_{n+k} + f c_{n+k+1}. Each v_n is ±1 (equal neighbours), ±(1 − 2f) (unequal), 1 − f or
  f (one neighbour outside the code), so ln E_d e^{sX} = n_eq lc(s/L) + n_ne lc(s(1−2f)/L) +
  n_a lc(s(1−f)/L) + n_b lc(sf/L), lc = ln cosh, with per-k counts. f and |cos φ| are integrated by
  Gauss–Legendre (12 and 24 nodes), k exactly;
* a code family: E_φ e^{r cosφ X} = I₀(rX) exactly; f by Gauss–Legendre (16 nodes), k and j exactly.

At r = 0 the quadrature is exact (the integrands are polynomials of degree 2 in f), so b = g″(0)
equals (1/(6L))(1 + r₁/2) for random codes and the (F.5) value (1/(4τ))∫R_iiR_jj for a family.

Sampling is done at the chip level: the interferer's code is drawn (or picked) and C(k), C(k + 1) are
computed by correlating it with c, independent of the counting identity above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from scipy.special import i0e, i1e, logsumexp

from motionsig_cli.config import ConfigError
from motionsig_cli.surveillance.amplitude import DensityDefaults, log_cosh, log_i0
from motionsig_cli.surveillance.time_bandwidth import aperiodic_correlation, as_code

CHUNK_NODES = 2_000_000  # r-values × nodes per evaluation chunk (bounds memory)


def _lc(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ln cosh x, tanh x, sech² x without overflow or cancellation."""
    e = np.exp(-2.0 * np.abs(x))
    return log_cosh(x), np.tanh(x), 4.0 * e / (1.0 + e) ** 2


def chip_correlation(ref: np.ndarray, intf: np.ndarray, delay_chips: float) -> float:
    """X(δ) = (1/L)[(1 − f)C(k) + f C(k + 1)] at a delay δ = (k + f)τ_c ∈ (−τ, τ) (eq 3.3.7 without the
    carrier factor): the matched-filter output of reference ``ref`` for interferer ``intf``."""
    c = as_code(ref)
    L = c.size
    if not -L < delay_chips < L:
        raise ValueError(f"the delay must lie in (-{L}, {L}) chips")
    k = math.floor(delay_chips)
    f = delay_chips - k
    C = aperiodic_correlation(c, intf)  # index m + L holds C(m), m = −L … L
    return float(((1.0 - f) * C[k + L] + f * C[k + L + 1]) / L)


@dataclass(frozen=True)
class PSKAmplitude(DensityDefaults):
    """PSK MAN component for a reference code; interferers use random codes or a code family."""

    ref: tuple[int, ...]
    family: tuple[tuple[int, ...], ...] | None = None
    n_f: int = 12
    n_phi: int = 24
    name: str = field(default="psk", init=False)

    def __post_init__(self) -> None:
        try:
            c = as_code(np.asarray(self.ref))
        except ValueError as exc:
            raise ConfigError("ref", self.ref, str(exc).replace("a code must", "must")) from None
        if c.size < 2:
            raise ConfigError("ref", self.ref, "needs at least 2 chips")
        if self.family is not None:
            fam = np.atleast_2d(np.asarray(self.family))
            if fam.ndim != 2 or fam.shape[1] != c.size or fam.shape[0] < 1:
                raise ConfigError("family", self.family, "must hold codes of the reference code's length")
            for row in fam:
                try:
                    as_code(row)
                except ValueError as exc:
                    raise ConfigError(
                        "family", self.family, str(exc).replace("a code must", "must")
                    ) from None

    @cached_property
    def code(self) -> np.ndarray:
        return as_code(np.asarray(self.ref))

    @property
    def L(self) -> int:
        return int(self.code.size)

    @property
    def draw_chips(self) -> int:
        """Chips correlated per draw: L with random interferer codes, 0 for a family (its correlations
        are tabulated once) — the Monte Carlo's cost model."""
        return self.L if self.family is None else 0

    @cached_property
    def family_codes(self) -> np.ndarray | None:
        if self.family is None:
            return None
        return np.array([as_code(r) for r in np.atleast_2d(np.asarray(self.family))])

    @cached_property
    def cross(self) -> np.ndarray:
        """C_j(m) for m = −L … L (rows: family members); empty for random codes."""
        fam = self.family_codes
        if fam is None:
            return np.zeros((0, 2 * self.L + 1))
        return np.array([aperiodic_correlation(self.code, d) for d in fam])

    @cached_property
    def _counts(self) -> np.ndarray:
        """Per k = −L … L−1: (n_eq, n_ne, n_a, n_b) of the pairs (c_{n+k}, c_{n+k+1}), n = 0 … L−1."""
        L, c = self.L, self.code
        pad = np.concatenate([np.zeros(L + 1), c, np.zeros(L + 1)])
        n = np.arange(L)
        out = []
        for k in range(-L, L):
            a = pad[n + k + L + 1]
            b = pad[n + k + L + 2]
            both = (a != 0) & (b != 0)
            out.append(
                (
                    np.sum(both & (a == b)),
                    np.sum(both & (a != b)),
                    np.sum((a != 0) & (b == 0)),
                    np.sum((a == 0) & (b != 0)),
                )
            )
        return np.array(out, dtype=float)

    @cached_property
    def _nodes(self) -> tuple[np.ndarray, ...]:
        """Quadrature nodes and log-weights.

        Random codes: the counts (2L, 4) per k, the scales |v|/L (4, n_f·n_φ) and |cos φ| per (f, φ)
        node, and the log-weights (2L, n_f·n_φ). A code family: X (flattened) and its log-weights.
        """
        L = self.L
        if self.family is None:
            xf, wf = np.polynomial.legendre.leggauss(self.n_f)
            f = 0.5 * (xf + 1.0)
            xp, wp = np.polynomial.legendre.leggauss(self.n_phi)
            phi = 0.25 * math.pi * (xp + 1.0)  # |cos φ| over [0, π/2]
            F, P = np.meshgrid(f, phi, indexing="ij")
            WF, WP = np.meshgrid(0.5 * wf, 0.5 * wp, indexing="ij")
            fv = F.ravel()
            scales = np.stack([np.ones_like(fv), 1.0 - 2.0 * fv, 1.0 - fv, fv]) / L  # |v_n|/L by pair type
            logw = np.log(WF * WP).ravel()[None, :] - math.log(2 * L) + np.zeros((2 * L, 1))
            return self._counts, scales, np.cos(P).ravel(), logw
        xf, wf = np.polynomial.legendre.leggauss(16)
        f = 0.5 * (xf + 1.0)
        C = self.cross  # (J, 2L+1): m = −L … L
        J = C.shape[0]
        Ck, Ck1 = C[:, :-1], C[:, 1:]  # k = −L … L−1
        X = ((1.0 - f)[None, None, :] * Ck[..., None] + f[None, None, :] * Ck1[..., None]) / L
        logw = np.broadcast_to(np.log(0.5 * wf) - math.log(2 * L * J), X.shape)
        return (X.ravel(), logw.ravel())

    @property
    def b(self) -> float:
        return float(self.cgf(np.array([0.0]))[2][0])

    @property
    def max_abs(self) -> float:
        if self.family is None:
            return 1.0
        return float(np.max(np.abs(self.cross))) / self.L

    def _cgf_chunk(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if self.family is None:
            cnt, scales, cphi, logw = self._nodes  # (2L, 4), (4, n), (n,), (2L, n)
            v = scales[None, :, :] * cphi[None, None, :]  # d s·v/dr per pair type and (f, φ) node
            lc, th, sech2 = _lc(r[:, None, None] * v)  # (R, 4, n): independent of k
            G = np.einsum("kt,rtn->rkn", cnt, lc).reshape(r.size, -1)  # ln E_d e^{rX} per (k, f, φ)
            G1 = np.einsum("kt,rtn->rkn", cnt, v * th).reshape(r.size, -1)
            G2 = np.einsum("kt,rtn->rkn", cnt, v * v * sech2).reshape(r.size, -1)
            logw = logw.ravel()
        else:
            X, logw = self._nodes
            z = np.abs(r[:, None] * X[None, :])
            i0, i1 = i0e(z), i1e(z)
            G = log_i0(z)  # ln I₀(rX)
            ratio = i1 / i0
            with np.errstate(divide="ignore", invalid="ignore"):
                over = np.where(z > 1e-8, ratio / np.where(z > 1e-8, z, 1.0), 0.5)
            sgn = np.sign(r[:, None] * X[None, :])
            G1 = X[None, :] * ratio * sgn
            G2 = X[None, :] ** 2 * np.clip(
                1.0 - over - ratio**2, 0.0, None
            )  # (ln I₀)″ = 1 − I₁/(zI₀) − (I₁/I₀)²
        lw = logw[None, :] + G
        g = logsumexp(lw, axis=1)
        p = np.exp(lw - g[:, None])  # tilted node weights
        g1 = np.sum(p * G1, axis=1)
        g2 = np.sum(p * (G2 + G1 * G1), axis=1) - g1 * g1
        return g, g1, np.clip(g2, 0.0, None)

    def cgf(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = np.asarray(r, dtype=float)
        flat = np.abs(r.ravel())
        n_nodes = self._nodes[-1].size
        step = max(1, CHUNK_NODES // n_nodes)
        parts = [self._cgf_chunk(flat[i : i + step]) for i in range(0, flat.size, step)]
        if not parts:
            e = np.zeros(0)
            return e.reshape(r.shape), e.reshape(r.shape), e.reshape(r.shape)
        g, g1, g2 = (np.concatenate(p) for p in zip(*parts, strict=True))
        return g.reshape(r.shape), (np.sign(r).ravel() * g1).reshape(r.shape), g2.reshape(r.shape)

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        """Chip-level draws: a code, a delay (k + f)τ_c uniform on (−τ, τ), a phase φ uniform."""
        L, c = self.L, self.code
        out = np.empty(size)
        block = max(1, 4_000_000 // L)
        pad = np.concatenate([np.zeros(L + 1), c, np.zeros(L + 1)])
        for s0 in range(0, size, block):
            n = min(block, size - s0)
            k = rng.integers(-L, L, size=n)
            f = rng.random(n)
            phi = 2.0 * math.pi * rng.random(n)
            if self.family is None:
                d = 1.0 - 2.0 * rng.integers(0, 2, size=(n, L), dtype=np.int8)
                idx = np.arange(L)[None, :] + k[:, None] + L + 1
                Ck = np.einsum("ij,ij->i", d, pad[idx])  # C(k) = Σ_n d_n c_{n+k}
                Ck1 = np.einsum("ij,ij->i", d, pad[idx + 1])  # C(k + 1)
            else:
                j = rng.integers(0, self.cross.shape[0], size=n)
                Ck = self.cross[j, k + L]
                Ck1 = self.cross[j, k + L + 1]
            out[s0 : s0 + n] = np.cos(phi) * ((1.0 - f) * Ck + f * Ck1) / L  # n_ij = cos φ · X (3.3.7)
        return out
