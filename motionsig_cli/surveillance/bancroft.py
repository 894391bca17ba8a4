"""Closed-form position and clock from pseudoranges (times of arrival): the start of the least-squares fix
that needs no guess (Bancroft, "An Algebraic Solution of the GPS Equations", IEEE Trans. Aerospace and
Electronic Systems AES-21(1), 56–59, 1985), and its variant for receivers in one plane.

**Bancroft's algorithm.** With ρ_i = ‖p − S_i‖ + b, square ‖p − S_i‖ = ρ_i − b and use the Lorentz inner
product ⟨a, c⟩ = a₁c₁ + a₂c₂ + a₃c₃ − a₄c₄ on a_i = (S_i, ρ_i) and y = (p, b):

    ⟨a_i, a_i⟩ − 2⟨a_i, y⟩ + ⟨y, y⟩ = 0,   i.e.   B M y = α + Λ 1                               (1)

with the rows of B the a_i, M = diag(1, 1, 1, −1), α_i = ½⟨a_i, a_i⟩ and Λ = ½⟨y, y⟩ (Bancroft's linear system).
Given Λ, (1) is linear: My = Λu + v with u = B⁺1, v = B⁺α (B⁺ the weighted least-squares inverse
(BᵀWB)⁻¹BᵀW for K > 4 receivers), and Λ = ½⟨y, y⟩ gives the quadratic

    ⟨u, u⟩ Λ² + 2(⟨u, v⟩ − 1) Λ + ⟨v, v⟩ = 0                                                    (2)

(Bancroft's quadratic): two roots, two candidate solutions y = M(Λu + v). One of them has the transmitter where
the ranges ρ_i − b are positive; with noise both are examined (the least-squares refinement decides). The
ρ_i are taken about their mean (the clock absorbs a
constant). The positions stay about the Earth's centre (ECEF, as Bancroft's): about the receivers' centroid
the columns of B would sum to zero and the least-squares u = B⁺1 would vanish.

**Receivers in one plane** (a ground network): B is then (nearly) rank deficient and the component of p
normal to the plane is not determined by (1). In plane coordinates s_i (2-D) and the height h above the
plane, ‖p − S_i‖² = ‖q − s_i‖² + h², and the same squaring gives, linear in (q, b, L = ‖q‖² + h² − b²),

    2 s_iᵀq − 2ρ_i b − L = ‖s_i‖² − ρ_i²                                                            (3)

so h² = L − ‖q‖² + b², and the two candidates are the point q at heights ±h: the mirror images in the
plane, between which the data hardly decide (the caller keeps the side it is told). For a nearly planar
network (the Earth's curvature over 50 km is a 200 m sag) (3) is an approximation that the Gauss–Newton
refinement removes.
"""

from __future__ import annotations

import numpy as np

__all__ = ["bancroft", "planar_start"]

_M = np.array([1.0, 1.0, 1.0, -1.0])


def _lorentz(a: np.ndarray, c: np.ndarray) -> np.ndarray:
    return np.sum(a * c * _M, axis=-1)


def _wls(A: np.ndarray, w: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Weighted least squares of A x = rhs per epoch (A (E, K, n), w (E, K) = 1/σ, rhs (E, K, m)):
    (E, n, m) by a batched SVD, NaN where the system is rank deficient (fewer than n receivers, a
    degenerate geometry)."""
    Aw = A * w[..., None]
    u, sv, vt = np.linalg.svd(Aw, full_matrices=False)
    tol = sv[:, :1] * max(A.shape[1], A.shape[2]) * np.finfo(float).eps
    full = np.all(sv > tol, axis=1)
    inv = np.where(sv > tol, 1.0 / np.where(sv > tol, sv, 1.0), 0.0)
    sol = np.einsum("eji,ej,ekj,ekm->eim", vt, inv, u, rhs * w[..., None])
    return np.where(full[:, None, None], sol, np.nan)


def bancroft(receivers: np.ndarray, rho: np.ndarray, weight: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Both closed-form solutions (eqs 1–2 of the module docstring) of each epoch.

    Args:
        receivers: (E, K, 3) ECEF positions [m] (any finite value where ``weight`` is 0).
        rho: (E, K) pseudoranges [m] (any finite value where ``weight`` is 0).
        weight: (E, K) 1/σ of each pseudorange, 0 for a receiver absent at the epoch.

    Returns:
        positions (E, 2, 3) [m] and clock offsets b (E, 2) [m] of the two roots; NaN for a root that is
        not real or an epoch whose B is singular (fewer than four receivers, a degenerate geometry).
    """
    S = np.asarray(receivers, float)
    r = np.asarray(rho, float)
    w = np.asarray(weight, float)
    used = w > 0
    n = np.maximum(used.sum(axis=1), 1)
    r0 = np.sum(np.where(used, r, 0.0), axis=1) / n
    a = np.concatenate([S, (r - r0[:, None])[..., None]], axis=-1)
    a = np.where(used[..., None], a, 0.0)
    alpha = 0.5 * _lorentz(a, a)
    sol = _wls(a, w, np.stack([np.ones_like(alpha), alpha], axis=-1))
    u, v = sol[..., 0], sol[..., 1]
    A, B, C = _lorentz(u, u), _lorentz(u, v) - 1.0, _lorentz(v, v)
    with np.errstate(invalid="ignore", divide="ignore"):
        disc = B * B - A * C
        sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
        small = np.abs(A * C) < 1e-12 * B * B  # the quadratic degenerates to a linear equation
        lam = np.stack(
            [np.where(small, -C / (2 * B), (-B + sq) / A), np.where(small, np.nan, (-B - sq) / A)], axis=1
        )
    y = (lam[..., None] * u[:, None, :] + v[:, None, :]) * _M  # (E, 2, 4)
    return y[..., :3], y[..., 3] + r0[:, None]


def planar_start(
    receivers: np.ndarray, rho: np.ndarray, weight: np.ndarray, centre: np.ndarray, normal: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The closed-form solution for receivers in one plane (eq 3 of the module docstring).

    Args:
        receivers, rho, weight: as :func:`bancroft`.
        centre: (E, 3) a point of each epoch's plane (the receivers' centroid).
        normal: (E, 3) its unit normal; the first candidate is on the side it points to.

    Returns:
        positions (E, 2, 3) and clock offsets (E, 2) [m]: the solution at height +h and its mirror image
        at −h (h = 0 when h² < 0: a transmitter near the plane); NaN where (3) is singular.
    """
    S = np.asarray(receivers, float)
    r = np.asarray(rho, float)
    w = np.asarray(weight, float)
    used = w > 0
    nrm = normal / np.linalg.norm(normal, axis=-1, keepdims=True)
    # an in-plane basis: e1 ⟂ n, e2 = n × e1
    ref = np.where(np.abs(nrm[:, :1]) < 0.9, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    e1 = ref - np.sum(ref * nrm, axis=-1, keepdims=True) * nrm
    e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
    e2 = np.cross(nrm, e1)
    d = S - centre[:, None, :]
    s = np.stack([np.einsum("ekj,ej->ek", d, e1), np.einsum("ekj,ej->ek", d, e2)], axis=-1)
    n = np.maximum(used.sum(axis=1), 1)
    r0 = np.sum(np.where(used, r, 0.0), axis=1) / n
    rc = np.where(used, r - r0[:, None], 0.0)
    s = np.where(used[..., None], s, 0.0)
    A = np.concatenate([2.0 * s, -2.0 * rc[..., None], -np.ones((*rc.shape, 1))], axis=-1)
    rhs = (np.sum(s * s, axis=-1) - rc * rc)[..., None]
    x = _wls(A, w, rhs)[..., 0]  # (E, 4): q1, q2, b, L
    q, b, L = x[:, :2], x[:, 2], x[:, 3]
    h = np.sqrt(np.maximum(L - np.sum(q * q, axis=-1) + b * b, 0.0))
    base = centre + q[:, :1] * e1 + q[:, 1:] * e2
    pos = np.stack([base + h[:, None] * nrm, base - h[:, None] * nrm], axis=1)
    return pos, np.stack([b + r0, b + r0], axis=1)
